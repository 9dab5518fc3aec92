"""What runs on a worker: one job, idempotent, written atomically, skipped when done.

A job's proof of completion is its **record**, ``OUTPUT.json`` beside the output: the
SHA-256 of the input, the options, the pds_plugin version, the SHA-256 of every file
written and the report of every section. Every file is written under a temporary name
(see :mod:`pds_plugin._atomic`) and renamed into place only when all are complete, so
a mesh under its final name is always a finished one, proven by its record. A job whose record matches its input, options and files is skipped and its
files are left untouched; any other job first removes a stale record, then writes.
Running a job twice (Dask may) writes the same bytes twice: same inputs, same seed,
same meshes.
"""

from __future__ import annotations

import hashlib
import json
import time
import warnings
from contextlib import ExitStack
from pathlib import Path

from .._atomic import atomic_path
from .._version import __version__
from ..errors import PdsError
from ..pipeline import mesh_region, section_report

__all__ = ["run_job", "result_row", "file_digest"]

# What a job's own input can raise; anything else is a bug, reported as such.
_INPUT_ERRORS = (PdsError, OSError)


def run_job(job) -> dict:
    """Run one :class:`~pds_plugin.batch.jobs.Job`; return its result row (never raises
    for a bad input: a failure is an ``error`` row).

    Parameters
    ----------
    job : Job

    Returns
    -------
    dict
        See :func:`result_row`.

    Examples
    --------
    >>> import tempfile, trimesh
    >>> from pds_plugin.batch.jobs import parse_job
    >>> folder = tempfile.mkdtemp()
    >>> _ = trimesh.creation.box(extents=(2, 2, 2)).export(f"{folder}/box.stl")
    >>> job = parse_job({"input": "box.stl", "axis": "z", "alpha": 0.5}, 0, folder, folder)
    >>> run_job(job)["status"], run_job(job)["status"]
    ('ok', 'skipped')
    """
    started = time.perf_counter()
    try:
        digest = file_digest(job.input)
        record = _matching_record(job, digest)
        if record is not None:
            return result_row(job, "skipped", started, record["certificate_ok"])
        job.record.unlink(missing_ok=True)
        Path(job.output).parent.mkdir(parents=True, exist_ok=True)
        # every file under a temporary name until all are written; then the record is
        # renamed into place first, the meshes after it (ExitStack: last in, first out),
        # so a final-name mesh always has its record, and an interrupted job leaves at
        # most a record whose meshes are missing, which no rerun takes for done
        with ExitStack() as files, warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            partials = [files.enter_context(atomic_path(output)) for output in job.outputs]
            sections = [_mesh_section(job, region, output, partial) for region, output, partial
                        in zip(job.regions(), job.outputs, partials)]
            certificate_ok = all(section["certificate"]["ok"] for section in sections)
            record = {"pds_plugin": __version__, "input": job.input, "input_sha256": digest,
                      "options": job.settings,
                      "outputs": dict(zip(job.outputs, map(file_digest, partials))),
                      "certificate_ok": certificate_ok,
                      "warnings": [str(w.message) for w in caught], "sections": sections}
            with atomic_path(job.record) as partial:
                partial.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
        return result_row(job, "ok", started, certificate_ok)
    except _INPUT_ERRORS as error:
        return result_row(job, "error", started, error=" ".join(str(error).split()))
    except Exception as error:         # a bug: say so, the batch goes on
        return result_row(job, "error", started,
                          error=f"internal error {type(error).__name__}: {error} (a bug in "
                                f"pds_plugin; please report it with this job)")


def result_row(job, status: str, started: float | None = None, certificate_ok=None,
               error: str | None = None) -> dict:
    """One line of ``results.jsonl``.

    Parameters
    ----------
    job : Job
    status : {"ok", "error", "skipped", "cancelled"}
    started : float, optional
        ``time.perf_counter()`` when the job started; None if it never ran.
    certificate_ok : bool, optional
    error : str, optional

    Returns
    -------
    dict
        ``job`` (position in the batch), ``input``, ``status`` (``cancelled`` when the
        batch was interrupted first), ``output`` (the file, or the list of files of a
        job with several sections), ``seconds`` (on the worker), ``certificate_ok``
        (every section certified; ``None`` without a mesh), ``error`` (the message, or
        ``None``).

    Examples
    --------
    >>> from pds_plugin.batch.jobs import parse_job
    >>> job = parse_job({"input": "a.svg", "alpha": 1}, 4, "/out", "/in")
    >>> result_row(job, "cancelled")["output"]
    '/out/a.ply'
    """
    outputs = list(job.outputs)
    return {"job": job.index, "input": job.input, "status": status,
            "output": outputs[0] if len(outputs) == 1 else outputs,
            "seconds": None if started is None else round(time.perf_counter() - started, 6),
            "certificate_ok": certificate_ok, "error": error}


def file_digest(path) -> str:
    """SHA-256 of a file's bytes, in hex.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    str

    Raises
    ------
    FileNotFoundError, IsADirectoryError
        If ``path`` is not a file.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "empty"
    >>> _ = path.write_bytes(b"")
    >>> file_digest(path)[:16]
    'e3b0c44298fc1c14'
    """
    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"no such file: {path}")
    if not path.is_file():
        raise IsADirectoryError(f"{path} is a directory, not a mesh file or a drawing")
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _mesh_section(job, region, output: str, partial) -> dict:
    """Mesh one section, write it to ``partial``, and return its report."""
    o = job.settings
    budget = {} if o["max_samples"] is None else {"max_samples": o["max_samples"]}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            mesh = mesh_region(region, o["alpha"], seed=o["seed"], conforming=o["conforming"],
                               graded=o["graded"], **budget)
            mesh.export(partial)
        except PdsError as error:            # say which of several sections failed
            raise type(error)(f"{Path(output).name}: {error}") from error
        mesh.certificate()
    return section_report(mesh, seed=o["seed"],
                          alpha_mode="auto" if o["alpha"] == "auto" else "given",
                          output=output, warnings=[str(w.message) for w in caught])


def _matching_record(job, digest: str) -> dict | None:
    """The job's record if it proves this very job done (same input, options, version,
    files unchanged), else None."""
    try:
        record = json.loads(job.record.read_text(encoding="utf-8"))
        matches = (record["input_sha256"] == digest and record["options"] == job.settings
                   and record["pds_plugin"] == __version__
                   and record["outputs"] == {name: file_digest(name) for name in job.outputs})
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return record if matches else None
