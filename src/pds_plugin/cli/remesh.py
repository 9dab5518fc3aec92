"""``pds-mesh remesh IN -o OUT``: every planar face of a mesh file re-triangulated with
certified triangles, the solid kept (:func:`pds_plugin.remesh`)."""

from __future__ import annotations

import json

from .._version import __version__
from .._atomic import atomic_path
from ..remeshing import remesh
from .output import say

__all__ = ["run"]


def run(args) -> int:
    """Run ``pds-mesh remesh`` with parsed arguments; return the exit status.

    Parameters
    ----------
    args : argparse.Namespace
        ``input``, ``output``, ``alpha``, ``uniform``, ``seed`` and ``report`` (a path
        or None).

    Returns
    -------
    int
        0 (a failed check is a warning and in the report).

    Examples
    --------
    >>> import pathlib, tempfile, trimesh
    >>> from pds_plugin.cli.arguments import parser
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = trimesh.creation.box((2, 1, 1)).export(folder / "box.stl")
    >>> args = parser().parse_args(["remesh", str(folder / "box.stl"), "-o",
    ...                             str(folder / "out.ply"), "--alpha", "0.25"])
    >>> run(args)     # doctest: +ELLIPSIS
    pds-mesh remesh: ... -> ...out.ply
    remesh ok: ...
    0
    """
    result = remesh(args.input, args.alpha, graded=not args.uniform, seed=args.seed)
    with atomic_path(args.output) as partial:
        result.mesh.export(partial)
    print(f"pds-mesh remesh: {args.input} -> {args.output}")
    print(result)
    if not result.ok_with_exceptions:
        say("warning", "the remeshed solid is not certified: see the lines above"
            + (" and the report" if args.report else ""))
    if args.report:
        with atomic_path(args.report) as partial:
            partial.write_text(json.dumps({"pds_plugin": __version__, "input": str(args.input),
                                           "output": str(args.output), **result.as_dict()},
                                          indent=2, default=_plain) + "\n", encoding="utf-8")
    return 0


def _plain(value):
    """numpy scalars and tuples as JSON values."""
    return value.item() if hasattr(value, "item") else list(value)
