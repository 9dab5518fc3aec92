"""What ``pds-mesh`` prints and writes besides the meshes: messages, summaries, the report."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from .._atomic import atomic_path
from .._version import __version__
from ..region import plane_label
from .arguments import PROG

__all__ = ["say", "warn_about", "summary", "write_report"]


def say(kind: str, message) -> None:
    """Print ``pds-mesh: KIND: MESSAGE`` on one line of stderr, whatever the message.

    Parameters
    ----------
    kind : str
        "error" or "warning".
    message : object

    Examples
    --------
    >>> import contextlib, io
    >>> with contextlib.redirect_stderr(io.StringIO()) as err:
    ...     say("warning", "two\\nlines")
    >>> err.getvalue()
    'pds-mesh: warning: two lines\\n'
    """
    text = " ".join(str(message).split())
    print(f"{PROG}: {kind}: {text}", file=sys.stderr)


def warn_about(entry: dict) -> None:
    """Say the warnings of one section's report entry, and its failed certificate if so.

    Parameters
    ----------
    entry : dict
        As :func:`pds_plugin.section_report` makes it.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.25)
    >>> entry = pds.section_report(mesh, seed=0, output="square.ply", warnings=["careful"])
    >>> import contextlib, io
    >>> with contextlib.redirect_stderr(io.StringIO()) as err:
    ...     warn_about(entry)
    >>> err.getvalue()
    'pds-mesh: warning: square.ply: careful\\n'
    """
    for message in entry["warnings"]:
        say("warning", f"{entry['output']}: {message}")
    certificate = entry["certificate"]
    if certificate["ok_with_exceptions"] and not certificate["ok"]:
        exceptions = certificate["exceptions"]
        say("warning", f"{entry['output']}: {len(exceptions)} triangles below Theorem 1 at "
                       "small features, each within its proven bound; the first: "
                       f"{_exception(exceptions[0]) if exceptions else 'none'}")
    elif not certificate["ok"]:
        unconforming = certificate["claims_conforming"] and not certificate["boundary_ok"]
        failed = [name.replace("_ok", "") for name in ("sampling_ok", "quality_ok",
                                                        "topology_ok") if not certificate[name]]
        failed += ["boundary"] if unconforming else []
        say("warning", f"{entry['output']}: certificate FAILED ({', '.join(failed) or 'mesh'})")
        problems = [*certificate["topology"]["problems"], *certificate["unexplained"],
                    *(certificate["boundary_problems"] if unconforming else [])]
        for problem in problems:
            say("warning", f"{entry['output']}: {problem}")
        if unconforming and "grading" not in certificate:
            say("warning", f"{entry['output']}: a uniform mesh usually breaks there at parts "
                           "of the section thinner than alpha (spikes, thin walls), which it "
                           "leaves out; a graded mesh (--alpha auto) or a smaller alpha keeps "
                           "them")


def _exception(exception: dict) -> str:
    """'sharp corner at (x, y), min angle 20° >= 17.5° proven' for one listed exception."""
    x, y = exception["place"]
    return (f"{exception['cause']} at ({x:.4g}, {y:.4g}), min angle "
            f"{exception['min_angle']:.3g}° >= {exception['proven_angle']:.3g}° proven")


def summary(entry: dict) -> str:
    """One line about one section: plane, samples, triangles, alpha, quality, verdict.

    Parameters
    ----------
    entry : dict
        As :func:`pds_plugin.section_report` makes it.

    Returns
    -------
    str

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.25)
    >>> print(summary(pds.section_report(mesh, seed=0, output="square.ply")))
    ... # doctest: +ELLIPSIS
    square.ply: z=0, ... samples, ... triangles, alpha 0.25, max aspect ratio ..., certificate ok
    """
    c = entry["certificate"]
    return (f"{entry['output']}: {plane_label(entry['frame'])}, {entry['samples']} samples, "
            f"{entry['triangles']} triangles, alpha {entry['alpha']:.6g}"
            f"{' (auto)' if entry['alpha_mode'] == 'auto' else ''}{_grading(c)}, max aspect ratio "
            f"{c['max_aspect_ratio']:.4f} (bound {c['aspect_bound']:.4f}), "
            f"(b0, b1) = {tuple(c['betti_mesh'])}, certificate {_verdict(c)}")


def _verdict(certificate: dict) -> str:
    """'ok', 'ok with N exceptions' (small features, each within its proven bound) or
    'FAILED'."""
    if certificate["ok"]:
        return "ok"
    if certificate["ok_with_exceptions"]:
        return f"ok with {len(certificate['exceptions'])} exceptions"
    return "FAILED"


def _grading(certificate: dict) -> str:
    """', graded L=...' for the certificate of a graded mesh, else ''."""
    return f", graded L={certificate['grading']:g}" if "grading" in certificate else ""


def write_report(path: Path, source, entries: list[dict]) -> None:
    """Write the JSON report of a run: the version, the input and one entry per section.

    Parameters
    ----------
    path : Path
    source : str or Path
        What was meshed.
    entries : list of dict
        As :func:`pds_plugin.section_report` makes them.

    Examples
    --------
    >>> import json, pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "report.json"
    >>> write_report(path, "part.stl", [])
    >>> json.loads(path.read_text())["sections"]
    []
    """
    report = {"pds_plugin": __version__, "input": str(source), "sections": entries}
    with atomic_path(path) as partial:
        partial.write_text(json.dumps(report, indent=2) + "\n", encoding="utf-8")
