"""The command line of ``pds-mesh``: argument types and the parsers of its commands."""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path

from .._checks import check_alpha, check_grading, check_positive_int, check_seed
from .._version import __version__
from ..batch.jobs import AXES
from ..batch.jobs import wants_graded as graded_by_rule
from ..errors import ArgumentError
from ..region import check_tolerance
from ..sources.solids import MAX_SECTIONS

__all__ = ["PROG", "AXES", "COMMANDS", "MAX_SECTIONS", "parser", "wants_graded",
           "glue_negative_values"]

PROG = "pds-mesh"
COMMANDS = ("mesh", "demo", "batch", "remesh")
_NUMBER_OPTIONS = ("--at", "--plane-origin", "--plane-normal")

_DESCRIPTION = """\
Certified triangle meshes of planar sections: cut a mesh or STEP file with
planes (or read an SVG or DXF drawing), sample each section with a maximal Poisson disc
sampling of radius alpha, mesh it with the solid alpha-complex, and write
it with its quality certificate.

commands:
  pds-mesh [mesh] INPUT -o OUT [--alpha A|auto] ... mesh sections of INPUT ('mesh' may be
                                                    omitted; 'pds-mesh mesh demo' meshes a
                                                    file named demo)
  pds-mesh demo [-o DIR]                            see every output on a built-in part
  pds-mesh batch MANIFEST -o DIR [--scheduler ADDRESS | --workers N]
                                                    many parts and planes, locally or on
                                                    a Dask cluster; resumable
  pds-mesh remesh IN -o OUT [--alpha A|auto] [--uniform]
                                                    remesh every planar face of a mesh
                                                    file, the solid kept

Run 'pds-mesh demo' first, and 'pds-mesh mesh --help' for the options."""

_EPILOG = """\
examples:
  pds-mesh demo                                   mesh a built-in CAD part, see every output
  pds-mesh part.stl -o cut.ply --axis z --at 0.5 --alpha 0.05
  pds-mesh part.stl -o cut.ply --plane-origin 0,0,1 --plane-normal 0,1,1 --alpha auto
  pds-mesh part.stl -o slice.ply --axis z --slices 20 --alpha auto --jobs 2 --report r.json
  pds-mesh part.step -o cut.ply --axis z --alpha auto   (STEP, IGES, BREP: pds_plugin[step])
  pds-mesh drawing.svg -o drawing.ply                  (alpha auto: a graded mesh)
  pds-mesh drawing.svg -o drawing.obj --alpha 2.5 --plot drawing.png --discs
  pds-mesh bracket.dxf -o bracket.ply --alpha auto --layer OUTLINE --layer HOLES

planes (mesh files only; an SVG or DXF drawing is already planar):
  The normal is --axis or --plane-normal. The plane then passes through --plane-origin
  (default: the world origin) moved by --at along the unit normal; with neither --at nor
  --plane-origin it is the middle of the solid. --slices N cuts N planes, one in the
  middle of each of N equal slabs of the solid along the normal.

several sections (--slices, or --at with several offsets):
  OUT.ply becomes OUT_000.ply, OUT_001.ply, ... in the order of the planes (zero-padded
  to 3 digits, more when there are more sections), and so does the --plot picture; the
  --report file holds one entry per section.

alpha:
  The disc radius, in the input's units: the samples are >= alpha apart and cover the
  section within alpha, and every triangle has aspect ratio L^2/A <= 4*sqrt(3)
  (Theorem 1). 'auto' (the default) makes a graded mesh: a radius that follows the section (small at
  thin walls, holes and sharp corners, growing by at most L per unit of distance, up to
  the section's own size), so every feature is kept with the fewest well-shaped
  triangles (angles >= 23.6 degrees at the default L = 0.2). 'auto --uniform' uses one
  alpha for the whole section: it starts from half the local feature size of the
  section's boundary and refines alpha until the mesh has the section's holes and
  components (Theorem 2).

exit status: 0 success (a failed certificate is a warning), 1 bad input, 2 usage error.
"""


_BATCH_EPILOG = """\
manifest (JSON Lines, one job per line; or CSV with these column names):
  {"input": "bracket.stl", "axis": "z", "slices": 10, "alpha": "auto"}
  {"input": "bracket.stl", "plane_origin": [0, 0, 5], "plane_normal": [0, 1, 1], "alpha": 0.2}
  {"input": "logo.svg", "alpha": 2.5, "output": "logos/logo.obj"}
  The options of 'pds-mesh mesh' with _ for -: input, output, axis, plane_normal,
  plane_origin, at, slices, layer, alpha, graded, seed, max_samples. As there, alpha
  defaults to auto, a graded mesh ("graded": false for one alpha). Relative inputs are read
  from the manifest's folder, relative outputs written to DIR; without output the name
  comes from the input and the plane (bracket_z0.5.ply).

results:
  DIR/results.jsonl, one line per job in manifest order: status (ok, error, skipped,
  cancelled), output, seconds, certificate_ok, error. Each output has a record
  OUTPUT.json (input SHA-256, options, section reports); a rerun skips the jobs whose
  record still matches and leaves their files untouched. Ctrl-C lets the running jobs
  finish (again: stops them) and cancels the rest.

examples:
  pds-mesh batch parts.jsonl -o meshes/                             local processes
  pds-mesh batch parts.csv -o /shared/meshes --scheduler tcp://head:8786

exit status: 0 every job ok or skipped, 1 some job failed, 2 usage error.
"""


class _Parser(argparse.ArgumentParser):
    """argparse that reports a usage error in one line (and exits with status 2)."""

    def error(self, message):
        self.exit(2, f"{PROG}: error: {message} (see {self.prog} --help)\n")


def parser() -> argparse.ArgumentParser:
    """The parser of ``pds-mesh``, one subcommand per command.

    Returns
    -------
    argparse.ArgumentParser
        Its namespace has ``command`` ("mesh" or "demo") and that command's options.

    Examples
    --------
    >>> args = parser().parse_args(["mesh", "part.stl", "-o", "cut.ply", "--alpha", "0.5"])
    >>> args.command, args.input, args.alpha
    ('mesh', 'part.stl', 0.5)
    >>> parser().parse_args(["mesh", "part.stl", "-o", "cut.ply"]).alpha   # graded, wants_graded
    'auto'
    """
    top = _Parser(prog=PROG, formatter_class=argparse.RawDescriptionHelpFormatter,
                  description=_DESCRIPTION, epilog=_EPILOG)
    top.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    commands = top.add_subparsers(dest="command", metavar="COMMAND", required=True,
                                  parser_class=_Parser)
    _mesh_arguments(commands.add_parser(
        "mesh", help="mesh sections of a mesh file, or a drawing (the default)",
        formatter_class=argparse.RawDescriptionHelpFormatter, epilog=_EPILOG,
        description=_DESCRIPTION.split("\n\n")[0]))
    _demo_arguments(commands.add_parser(
        "demo", help="mesh a built-in CAD part and see every output",
        description="Mesh the section of a built-in CAD part (a plate with two holes, a "
                    "slot and a sharp notch, made with manifold3d) with the automatic "
                    "alpha, write the solid, the mesh, its report and its picture, and "
                    "print a summary."))
    _batch_arguments(commands.add_parser(
        "batch", help="mesh every job of a manifest, locally or on a Dask cluster",
        formatter_class=argparse.RawDescriptionHelpFormatter, epilog=_BATCH_EPILOG,
        description="Mesh every job of a manifest (many parts, many planes) in parallel "
                    "processes or on a Dask cluster; resumable: a rerun only does what "
                    "is missing."))
    _remesh_arguments(commands.add_parser(
        "remesh", help="re-triangulate every planar face of a mesh file, the solid kept",
        description="Re-triangulate every planar face (patch of coplanar triangles) of a "
                    "mesh file with certified triangles, graded towards each patch's small "
                    "features (angles >= 23.6 degrees but at sharp input corners; "
                    "--uniform: alpha everywhere but graded around the input's pieces "
                    "shorter than alpha, the same bound): each patch boundary is "
                    "sampled once for both "
                    "patches, so the result is the same closed solid. Faces of curved "
                    "surfaces narrower than alpha are kept, split where samples fall on "
                    "their edges (docs/remesh.md)."))
    return top


def _remesh_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("input", metavar="IN", help="a mesh file (STL, OBJ, PLY, OFF...)")
    parser.add_argument("-o", "--output", metavar="OUT", type=_mesh_file, required=True,
                        help="the remeshed mesh (format by suffix: "
                             f"{', '.join(MESH_SUFFIXES)})")
    parser.add_argument("--alpha", type=_alpha, default="auto",
                        help="disc radius in the input's units, or 'auto' (default): the "
                             "bounding box's diagonal / 100")
    parser.add_argument("--uniform", action="store_true",
                        help="alpha everywhere, graded only around the input's pieces "
                             "shorter than alpha, instead of graded patches")
    parser.add_argument("--seed", type=_seed, default=0, help="random seed (default 0)")
    parser.add_argument("--report", metavar="JSON", type=Path,
                        help="write every patch certificate and the solid's checks here")


def _mesh_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("input", metavar="INPUT",
                        help="a mesh file (STL, OBJ, PLY, OFF, 3MF, GLB), a B-rep solid "
                             "(STEP, IGES, BREP; the [step] extra), or an SVG or DXF drawing")
    parser.add_argument("-o", "--output", metavar="OUT", required=True, type=Path,
                        help="the mesh file to write: .ply (binary, face quality = aspect "
                             "ratio, vertex quality = 1 on the boundary) or .obj")
    parser.add_argument("--alpha", type=_alpha, default="auto", metavar="A|auto",
                        help="disc radius in the input's units, or 'auto' (the default: a "
                             "graded mesh, see below)")
    plane = parser.add_argument_group("plane (mesh files)")
    normal = plane.add_mutually_exclusive_group()
    normal.add_argument("--axis", choices=sorted(AXES), help="normal along this axis")
    normal.add_argument("--plane-normal", type=_direction, metavar="X,Y,Z",
                        help="normal of the plane (any non-zero length)")
    plane.add_argument("--plane-origin", type=_point, metavar="X,Y,Z",
                       help="a point of the plane (default: the world origin)")
    where = plane.add_mutually_exclusive_group()
    where.add_argument("--at", type=_offsets, metavar="H[,H...]",
                       help="offset(s) of the plane along the unit normal from the origin; "
                            "several give several sections")
    plane.add_argument("--on-face", choices=("above", "below"),
                       help="a plane given by --at or --plane-origin that lies on faces of "
                            "the solid is cut just above or below them (refused otherwise); "
                            "the automatic planes (the middle, --slices) move off faces "
                            "by themselves, with a warning")
    where.add_argument("--slices", type=_section_count, metavar="N",
                       help=f"N evenly spaced sections across the solid (at most "
                            f"{MAX_SECTIONS:,})")
    parser.add_argument("--tolerance", type=_tolerance, metavar="T",
                        help="how far the region's boundary may move from the input's: for "
                             "a mesh file, to absorb its float noise and tessellation "
                             "zigzags (default: estimated from the mesh; 0 keeps every "
                             "vertex of the cut); for a drawing, the chord tolerance of its "
                             "curves (default 1e-4 of its diagonal)")
    parser.add_argument("--layer", action="append", metavar="NAME",
                        help="DXF drawings: read this layer (repeat for several; default: "
                             "every layer with outline curves or hatches)")
    parser.add_argument("--layout", metavar="NAME",
                        help="DXF drawings: read this layout, 'Model' or a paper-space sheet "
                             "(default: the model space, or the first sheet with an outline "
                             "when the model space has none; the sheet's border and title "
                             "block are left out)")
    parser.add_argument("--seed", type=_seed, default=0,
                        help="random seed, an integer >= 0; the same seed gives the same "
                             "mesh (default 0)")
    parser.add_argument("--no-conforming", dest="conforming", action="store_false",
                        help="the paper's pure solid alpha-complex: boundary edges are not "
                             "kept and notches or gaps narrower than alpha may be bridged "
                             "(default: conforming, constrained to the section)")
    parser.add_argument("--graded", action="store_true",
                        help="sizes that follow the section: a radius field <= alpha from its "
                             "walls, holes and corners; angles >= arcsin((1 - L)/2), 23.6 "
                             "degrees at the default L (docs/graded.md). The default with "
                             "--alpha auto, where the field is capped only by the section's "
                             "own size")
    parser.add_argument("--grading", type=_grading, metavar="L",
                        help="the Lipschitz constant of the graded radius field, in (0, 1) "
                             "(default 0.2); implies --graded")
    parser.add_argument("--uniform", action="store_true",
                        help="with --alpha auto, one alpha for the whole section (the "
                             "narrowest feature's), as before graded meshes were the default")
    parser.add_argument("--max-samples", type=_positive_int, metavar="N",
                        help="refuse sections that would need more samples (default "
                             "5,000,000); with --jobs the processes share it")
    parser.add_argument("--report", type=Path, metavar="REPORT.json",
                        help="write the quality statistics and certificate of every "
                             "section as JSON")
    parser.add_argument("--plot", type=Path, metavar="PICTURE.png",
                        help="draw the samples, the mesh coloured by aspect ratio and the "
                             "aspect-ratio histogram (needs matplotlib: pip install "
                             "\"pds_plugin[plot]\")")
    parser.add_argument("--discs", action="store_true",
                        help="with --plot, also draw each sample's disc of radius alpha")
    parser.add_argument("-j", "--jobs", type=_positive_int, default=1, metavar="N",
                        help="mesh sections in N parallel processes, at most one per core "
                             "(same results as 1 unless a section needs the whole "
                             "--max-samples, which the processes share)")
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="print nothing but warnings and errors")


def _demo_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", metavar="DIR", type=Path, default=Path("pds-demo"),
                        help="directory for the files (created; default ./pds-demo)")
    parser.add_argument("--seed", type=_seed, default=0, help="random seed (default 0)")


def _batch_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("manifest", metavar="MANIFEST", type=Path,
                        help="the jobs: JSON Lines (.jsonl, one job object per line) or CSV "
                             "(.csv, a header row of option names)")
    parser.add_argument("-o", "--output", metavar="DIR", type=Path, required=True,
                        help="folder for the meshes and results.jsonl (created)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on this Dask cluster, e.g. tcp://head:8786 (needs "
                            "pip install \"pds_plugin[dask]\")")
    where.add_argument("-w", "--workers", type=_positive_int, metavar="N",
                       help="local processes (default: one per core)")
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="print nothing but the failed jobs")


def wants_graded(args) -> bool:
    """Whether ``pds-mesh mesh`` makes graded meshes: with ``--graded`` or ``--grading``,
    and by default with ``--alpha auto`` (``--uniform`` and ``--no-conforming`` turn the
    default off: graded meshes are always conforming). Batch jobs follow the same rule
    (:func:`pds_plugin.batch.jobs.wants_graded`).

    Parameters
    ----------
    args : argparse.Namespace
        From :func:`parser`.

    Returns
    -------
    bool

    Raises
    ------
    ArgumentError
        If ``--uniform`` comes with ``--graded`` or ``--grading``.

    Examples
    --------
    >>> def graded(*options):
    ...     return wants_graded(parser().parse_args(["mesh", "p.stl", "-o", "c.ply", *options]))
    >>> graded("--alpha", "auto"), graded("--alpha", "auto", "--uniform"), graded("--alpha", "2")
    (True, False, False)
    >>> graded("--alpha", "2", "--grading", "0.3"), graded("--alpha", "auto", "--no-conforming")
    (True, False)
    """
    asked = args.graded or args.grading is not None
    if args.uniform and asked:
        raise ArgumentError("--uniform and --graded/--grading ask for different meshes; "
                            "give one of them")
    return graded_by_rule(args.alpha, True if asked else False if args.uniform else None,
                          args.conforming)


def glue_negative_values(argv: list[str]) -> list[str]:
    """``--at -1,2`` as ``--at=-1,2``: argparse takes ``-1,2`` for an option otherwise.

    Parameters
    ----------
    argv : list of str

    Returns
    -------
    list of str

    Examples
    --------
    >>> glue_negative_values(["--at", "-1,2", "-o", "x.ply"])
    ['--at=-1,2', '-o', 'x.ply']
    """
    glued = []
    for arg in argv:
        if glued and glued[-1] in _NUMBER_OPTIONS and re.fullmatch(r"-[\d.][\d.,eE+-]*", arg):
            glued[-1] = f"{glued[-1]}={arg}"
        else:
            glued.append(arg)
    return glued


# --- argument types: a bad value is a usage error (exit status 2) ------------------------

def _alpha(text: str):
    if text == "auto":
        return text
    try:
        return check_alpha(text)
    except ValueError:                    # not a number, or not a positive finite one
        raise argparse.ArgumentTypeError(f"alpha must be a positive number or 'auto', "
                                         f"got {text!r}") from None


def _numbers(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = [math.nan]
    if not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}")
    return values


def _offsets(text: str) -> list[float]:
    values = _numbers(text)
    if len(values) > MAX_SECTIONS:
        raise argparse.ArgumentTypeError(f"at most {MAX_SECTIONS:,} offsets per run, got "
                                         f"{len(values):,}; split the run")
    return values


def _grading(text: str) -> float:
    try:
        return check_grading(text)
    except ValueError:                    # not a number, or not in (0, 1)
        raise argparse.ArgumentTypeError(f"grading must be a number in (0, 1), got "
                                         f"{text!r}") from None


MESH_SUFFIXES = (".stl", ".ply", ".obj", ".off", ".glb", ".gltf", ".3mf")
"""The formats ``pds-mesh remesh`` writes (trimesh's exporters of triangle meshes)."""


def _mesh_file(text: str) -> Path:
    path = Path(text)
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise argparse.ArgumentTypeError(f"cannot write a mesh to {text!r}: give a file "
                                         f"ending in {', '.join(MESH_SUFFIXES)}")
    return path


def _seed(text: str) -> int:
    try:
        return check_seed(int(text))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer >= 0, got {text!r}") from None


def _section_count(text: str) -> int:
    count = _positive_int(text)
    if count > MAX_SECTIONS:
        raise argparse.ArgumentTypeError(f"at most {MAX_SECTIONS:,} slices per run, got "
                                         f"{text}; split the run with --at offsets")
    return count


def _point(text: str) -> tuple[float, float, float]:
    values = _numbers(text)
    if len(values) != 3:
        raise argparse.ArgumentTypeError(f"expected three comma-separated numbers X,Y,Z, "
                                         f"got {text!r}")
    return tuple(values)


def _direction(text: str) -> tuple[float, float, float]:
    vector = _point(text)
    if not any(vector):
        raise argparse.ArgumentTypeError(f"the normal {text!r} is the zero vector; give the "
                                         f"direction the plane faces, e.g. 0,0,1")
    return vector


def _tolerance(text: str) -> float:
    try:
        return check_tolerance(float(text))
    except ValueError:                    # float() refused the text, or the check the number
        raise argparse.ArgumentTypeError(f"expected a number >= 0, got {text!r}") from None


def _positive_int(text: str) -> int:
    try:
        return check_positive_int(int(text), "the value")
    except ValueError:                    # int() refused the text, or the check the number
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
