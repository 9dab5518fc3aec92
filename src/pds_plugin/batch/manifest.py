"""Batch manifests: JSON Lines (one job object per line) or CSV with the same column names."""

from __future__ import annotations

import csv
import json
from pathlib import Path

from ..errors import ArgumentError

__all__ = ["read_manifest"]


def read_manifest(path) -> list[dict]:
    """The job mappings of a manifest, in file order.

    ``.csv`` files are CSV with a header row of option names (empty cells are absent
    options); anything else is JSON Lines, one JSON object per line (blank lines and
    lines starting with ``#`` are skipped). The values are checked per job later, by
    :func:`~pds_plugin.batch.jobs.parse_job`, so one bad job does not stop the others.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    list of dict

    Raises
    ------
    ArgumentError
        If the file is not valid JSON Lines / CSV (the message gives the line), or holds
        no job.
    FileNotFoundError
        If it does not exist.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> manifest = pathlib.Path(tempfile.mkdtemp()) / "jobs.csv"
    >>> _ = manifest.write_text("input,axis,at,alpha\\npart.stl,z,0.5,auto\\nmil.svg,,,0.2\\n")
    >>> read_manifest(manifest)[1]
    {'input': 'mil.svg', 'axis': '', 'at': '', 'alpha': '0.2'}
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no such manifest: {path}")
    text = path.read_text(encoding="utf-8-sig")
    jobs = _csv(text, path) if path.suffix.lower() == ".csv" else _json_lines(text, path)
    if not jobs:
        raise ArgumentError(f"{path} holds no job: write one job per line")
    return jobs


def _json_lines(text: str, path: Path) -> list[dict]:
    jobs = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            job = json.loads(line)
        except json.JSONDecodeError as error:
            raise ArgumentError(f"{path}, line {number}: not JSON ({error.msg}); a JSON Lines "
                             f"manifest has one job object per line, e.g. "
                             f'{{"input": "part.stl", "axis": "z", "alpha": "auto"}}') from None
        if not isinstance(job, dict):
            raise ArgumentError(f"{path}, line {number}: a job is a JSON object {{...}}, got "
                             f"{type(job).__name__}")
        jobs.append(job)
    return jobs


def _csv(text: str, path: Path) -> list[dict]:
    reader = csv.DictReader(text.splitlines())
    if not reader.fieldnames or "input" not in [n.strip() for n in reader.fieldnames]:
        raise ArgumentError(f"{path}: a CSV manifest starts with a header row of option "
                         f"names, with at least 'input'")
    jobs = []
    for row in reader:
        if None in row:
            raise ArgumentError(f"{path}, line {reader.line_num}: more cells than header "
                             f"columns")
        if any(value.strip() for value in row.values() if value is not None):
            jobs.append({name.strip(): value for name, value in row.items()})
    return jobs
