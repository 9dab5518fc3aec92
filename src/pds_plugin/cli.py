"""The ``pds-mesh`` command: certified triangle meshes of CAD sections and SVG drawings.

``pds-mesh demo`` runs the whole product on a built-in part; ``pds-mesh INPUT -o OUT``
meshes one or several sections of a mesh file (STL, OBJ, PLY, OFF, 3MF, GLB), or an SVG
drawing, and writes the meshes (binary PLY with face quality = aspect ratio, or OBJ),
optionally a JSON report of every certificate and a picture per mesh. Run
``pds-mesh --help`` for the options.

Exit status: 0 on success (also when a certificate fails: that is reported as a
warning and in the report), 1 for a bad input (one line ``pds-mesh: error: ...`` on
stderr), 2 for a usage error, 130 when interrupted.
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["main"]

PROG = "pds-mesh"
_NUMBER_OPTIONS = ("--at", "--plane-origin", "--plane-normal")
_AXES = {"x": (1.0, 0.0, 0.0), "y": (0.0, 1.0, 0.0), "z": (0.0, 0.0, 1.0)}
# What a user's input can raise; anything else is a bug and keeps its traceback.
_INPUT_ERRORS = (ValueError, TypeError, FileNotFoundError, ImportError, OSError)

_EPILOG = """\
examples:
  pds-mesh demo                                   mesh a built-in CAD part, see every output
  pds-mesh part.stl -o cut.ply --axis z --at 0.5 --alpha 0.05
  pds-mesh part.stl -o cut.ply --plane-origin 0,0,1 --plane-normal 0,1,1 --alpha auto
  pds-mesh part.stl -o slice.ply --axis z --slices 20 --alpha auto --jobs 2 --report r.json
  pds-mesh drawing.svg -o drawing.obj --alpha 2.5 --plot drawing.png --discs

planes (mesh files only; an SVG drawing is already planar):
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
  (Theorem 1). 'auto' starts from half the local feature size of the section's boundary
  and refines alpha until the mesh has the section's holes and components (Theorem 2).

exit status: 0 success (a failed certificate is a warning), 1 bad input, 2 usage error.
"""


class _Parser(argparse.ArgumentParser):
    """argparse that reports a usage error in one line (and exits with status 2)."""

    def error(self, message):
        self.exit(2, f"{PROG}: error: {message} (see {self.prog} --help)\n")


def main(argv=None) -> int:
    """Run ``pds-mesh`` with ``argv`` (default ``sys.argv[1:]``); return the exit status.

    Examples
    --------
    >>> main(["tiny.stl", "-o", "out.ply", "--alpha", "-1"])
    2
    """
    argv = sys.argv[1:] if argv is None else [str(a) for a in argv]
    try:
        if argv[:1] == ["demo"]:
            return _demo(_demo_parser().parse_args(argv[1:]))
        return _mesh(_parser().parse_args(_glue_negative_values(argv)))
    except SystemExit as stop:             # --help, and usage errors from argparse
        return stop.code if isinstance(stop.code, int) else 1
    except _INPUT_ERRORS as error:
        _say("error", error)
        return 1
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130


# --- arguments ---------------------------------------------------------------------

def _alpha(text: str):
    if text == "auto":
        return text
    try:
        alpha = float(text)
    except ValueError:
        alpha = math.nan
    if not (math.isfinite(alpha) and alpha > 0):
        raise argparse.ArgumentTypeError(f"alpha must be a positive number or 'auto', "
                                         f"got {text!r}")
    return alpha


def _numbers(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = [math.nan]
    if not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}")
    return values


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


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return value


def _glue_negative_values(argv: list[str]) -> list[str]:
    """``--at -1,2`` as ``--at=-1,2``: argparse takes ``-1,2`` for an option otherwise."""
    glued = []
    for arg in argv:
        if glued and glued[-1] in _NUMBER_OPTIONS and re.fullmatch(r"-[\d.][\d.,eE+-]*", arg):
            glued[-1] = f"{glued[-1]}={arg}"
        else:
            glued.append(arg)
    return glued


def _parser() -> _Parser:
    parser = _Parser(
        prog=PROG, formatter_class=argparse.RawDescriptionHelpFormatter, epilog=_EPILOG,
        description="Certified triangle meshes of planar sections: cut a mesh file with planes\n"
                    "(or read an SVG drawing), sample each section with a maximal Poisson disc\n"
                    "sampling of radius alpha, mesh it with the solid alpha-complex, and write\n"
                    "it with its quality certificate.\n\n"
                    "Run 'pds-mesh demo' first to see every output on a built-in part.")
    parser.add_argument("input", metavar="INPUT",
                        help="a mesh file (STL, OBJ, PLY, OFF, 3MF, GLB) or an SVG drawing")
    parser.add_argument("-o", "--output", metavar="OUT", required=True, type=Path,
                        help="the mesh file to write: .ply (binary, face quality = aspect "
                             "ratio, vertex quality = 1 on the boundary) or .obj")
    parser.add_argument("--alpha", required=True, type=_alpha, metavar="A|auto",
                        help="disc radius in the input's units, or 'auto' (see below)")
    plane = parser.add_argument_group("plane (mesh files)")
    normal = plane.add_mutually_exclusive_group()
    normal.add_argument("--axis", choices=sorted(_AXES), help="normal along this axis")
    normal.add_argument("--plane-normal", type=_direction, metavar="X,Y,Z",
                        help="normal of the plane (any non-zero length)")
    plane.add_argument("--plane-origin", type=_point, metavar="X,Y,Z",
                       help="a point of the plane (default: the world origin)")
    where = plane.add_mutually_exclusive_group()
    where.add_argument("--at", type=_numbers, metavar="H[,H...]",
                       help="offset(s) of the plane along the unit normal from the origin; "
                            "several give several sections")
    where.add_argument("--slices", type=_positive_int, metavar="N",
                       help="N evenly spaced sections across the solid")
    parser.add_argument("--seed", type=int, default=0,
                        help="random seed; the same seed gives the same mesh (default 0)")
    parser.add_argument("--max-samples", type=_positive_int, metavar="N",
                        help="refuse sections that would need more samples (default "
                             "5,000,000)")
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
                        help="mesh sections in N parallel processes (same results as 1)")
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="print nothing but warnings and errors")
    return parser


def _demo_parser() -> _Parser:
    parser = _Parser(
        prog=f"{PROG} demo",
        description="Mesh the section of a built-in CAD part (a plate with two holes, a "
                    "slot and a sharp notch, made with manifold3d) with the automatic "
                    "alpha, write the solid, the mesh, its report and its picture, and "
                    "print a summary.")
    parser.add_argument("-o", "--output", metavar="DIR", type=Path, default=Path("pds-demo"),
                        help="directory for the files (created; default ./pds-demo)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    return parser


# --- one section -------------------------------------------------------------------

@dataclass(frozen=True)
class _Task:
    """Everything needed to mesh one section, sent whole to a worker process."""

    region: object                 # pds_plugin.Region
    alpha: object                  # float or "auto"
    seed: int
    max_samples: int | None
    output: Path
    plot: Path | None
    discs: bool


def _mesh_section(task: _Task) -> dict:
    """Mesh, certify and write one section; return its report entry (JSON-ready)."""
    from .feature import auto_mesh, feature_size
    from .mesh import mesh_region

    budget = {} if task.max_samples is None else {"max_samples": task.max_samples}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            if task.alpha == "auto":
                mesh = auto_mesh(task.region, seed=task.seed, **budget)
            else:
                mesh = mesh_region(task.region, task.alpha, seed=task.seed, **budget)
            mesh.export(task.output)
            if task.plot is not None:
                from .plot import plot_report
                plot_report(mesh, task.plot, discs=task.discs)
        except ValueError as error:         # say which of several sections failed
            raise ValueError(f"{task.output}: {error}") from error
        certificate = mesh.certificate()
    region, frame = task.region, task.region.frame
    feature = feature_size(region)
    return {
        "output": str(task.output),
        "plot": None if task.plot is None else str(task.plot),
        "plane": {"origin": frame[:3, 3].tolist(), "normal": frame[:3, 2].tolist()},
        "frame": frame.tolist(),
        "region": {"area": region.area, "perimeter": region.perimeter,
                   "bounds": list(region.bounds), "betti": list(region.betti)},
        "feature_size": {"value": feature.value, "kind": feature.kind, "where": str(feature)},
        "alpha": mesh.alpha,
        "alpha_mode": "auto" if task.alpha == "auto" else "given",
        "seed": task.seed,
        "samples": len(mesh.vertices),
        "triangles": len(mesh.faces),
        "quality": mesh.quality().stats(),
        "certificate": certificate.as_dict(),
        "warnings": [str(w.message) for w in caught],
    }


def _results(tasks: list[_Task], jobs: int):
    """Report entries of ``tasks`` in order, meshed in ``jobs`` processes.

    Workers are spawned, not forked: a child forked after the parallel kernels started
    GNU OpenMP is terminated by it. Each worker runs its kernels in one thread.
    """
    if jobs == 1 or len(tasks) == 1:
        yield from map(_mesh_section, tasks)
        return
    from concurrent.futures import ProcessPoolExecutor
    from multiprocessing import get_context

    from ._parallel import set_threads

    with ProcessPoolExecutor(max_workers=min(jobs, len(tasks)),
                             mp_context=get_context("spawn"),
                             initializer=set_threads, initargs=(1,)) as pool:
        futures = [pool.submit(_mesh_section, task) for task in tasks]
        try:
            for future in futures:
                yield future.result()
        finally:
            for future in futures:
                future.cancel()


# --- the commands ------------------------------------------------------------------

def _mesh(args) -> int:
    from .export import writers

    if args.output.suffix.lower() not in writers():
        raise ValueError(f"cannot write {args.output}: the output suffix must be one of "
                         f"{', '.join(writers())}")
    for path in (args.output, args.report, args.plot):
        _check_directory(path)
    if args.plot is not None:
        _check_picture(args.plot)
    regions = _regions(args)
    outputs = _numbered(args.output, len(regions))
    if any(path.resolve() == Path(args.input).resolve() for path in outputs):
        raise ValueError(f"the output {args.output} would overwrite the input; choose "
                         f"another name")
    plots = _numbered(args.plot, len(regions)) if args.plot else [None] * len(regions)
    tasks = [_Task(region, args.alpha, args.seed, args.max_samples, output, plot, args.discs)
             for region, output, plot in zip(regions, outputs, plots)]
    entries = _run(tasks, args.jobs, progress=len(tasks) > 1 and not args.quiet)
    for entry in entries:
        _warn_about(entry)
        if not args.quiet:
            print(_summary(entry))
    if args.report is not None:
        _write_report(args.report, args.input, entries)
        if not args.quiet:
            print(f"report: {args.report}")
    return 0


def _run(tasks: list[_Task], jobs: int, progress: bool) -> list[dict]:
    from tqdm import tqdm

    with tqdm(total=len(tasks), desc=PROG, unit="section", file=sys.stderr,
              disable=not (progress and sys.stderr.isatty())) as bar:
        entries = []
        for entry in _results(tasks, jobs):
            entries.append(entry)
            bar.update()
    return entries


def _regions(args) -> list:
    """The sections (Regions) the arguments ask for, checked against the input's kind."""
    from .sources import load_svg, sections

    path = Path(args.input)
    if not path.exists():
        raise FileNotFoundError(f"no such file: {path}")
    if path.is_dir():
        raise IsADirectoryError(f"{path} is a directory, not a mesh file or an SVG drawing")
    normal = _AXES.get(args.axis, args.plane_normal)
    if path.suffix.lower() == ".svg":
        given = [name for name in ("axis", "plane_normal", "plane_origin", "at", "slices")
                 if getattr(args, name) is not None]
        if given:
            raise ValueError(f"{path} is an SVG drawing, which is already planar: drop "
                             f"--{given[0].replace('_', '-')}")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            region = load_svg(path)
        for warning in caught:
            _say("warning", warning.message)
        return [region]
    if normal is None:
        raise ValueError(f"{path} is a solid: say where to cut it with --axis or "
                         f"--plane-normal (and --at, --plane-origin or --slices)")
    if args.slices is not None:
        if args.plane_origin is not None:
            raise ValueError("--slices spreads the planes across the whole solid: drop "
                             "--plane-origin, or give --at offsets from it instead")
        return sections(path, normal, count=args.slices)
    if args.at is None and args.plane_origin is None:
        return sections(path, normal, count=1)          # the middle of the solid
    return sections(path, normal, offsets=args.at or [0.0], plane_origin=args.plane_origin)


def _numbered(path: Path, count: int) -> list[Path]:
    """``path`` itself for one section, else ``stem_000.suffix``, ``stem_001.suffix``..."""
    if count == 1:
        return [path]
    width = max(3, len(str(count - 1)))
    return [path.with_name(f"{path.stem}_{i:0{width}d}{path.suffix}") for i in range(count)]


def _check_directory(path) -> None:
    if path is not None and not path.parent.is_dir():
        raise FileNotFoundError(f"cannot write {path}: directory {path.parent} does not "
                                f"exist; create it first")


def _check_picture(path: Path) -> None:
    """Fail before any meshing if --plot cannot be written."""
    try:
        from matplotlib.backend_bases import FigureCanvasBase
    except ImportError as error:
        raise ImportError('--plot needs matplotlib: pip install "pds_plugin[plot]"') from error
    kinds = FigureCanvasBase.get_supported_filetypes()
    if path.suffix.lower().lstrip(".") not in kinds:
        raise ValueError(f"cannot draw {path}: the picture suffix must be one of "
                         f"{', '.join('.' + k for k in sorted(kinds))}")


def _write_report(path: Path, source, entries: list[dict]) -> None:
    from . import __version__

    report = {"pds_plugin": __version__, "input": str(source), "sections": entries}
    path.write_text(json.dumps(report, indent=2) + "\n", encoding="utf-8")


def _warn_about(entry: dict) -> None:
    for message in entry["warnings"]:
        _say("warning", f"{entry['output']}: {message}")
    certificate = entry["certificate"]
    if not certificate["ok"]:
        failed = [name.replace("_ok", "") for name in ("sampling_ok", "quality_ok",
                                                        "topology_ok") if not certificate[name]]
        _say("warning", f"{entry['output']}: certificate FAILED ({', '.join(failed) or 'mesh'})")
        for problem in certificate["topology"]["problems"]:
            _say("warning", f"{entry['output']}: {problem}")


def _summary(entry: dict) -> str:
    c = entry["certificate"]
    return (f"{entry['output']}: {_plane_label(entry)}, {entry['samples']} samples, "
            f"{entry['triangles']} triangles, alpha {entry['alpha']:.6g}"
            f"{' (auto)' if entry['alpha_mode'] == 'auto' else ''}, max aspect ratio "
            f"{c['max_aspect_ratio']:.4f} (bound 4√3 = {c['aspect_bound']:.4f}), "
            f"(b0, b1) = {tuple(c['betti_mesh'])}, certificate {'ok' if c['ok'] else 'FAILED'}")


def _plane_label(entry: dict) -> str:
    origin, normal = np.array(entry["plane"]["origin"]), np.array(entry["plane"]["normal"])
    for name, axis in _AXES.items():
        if np.array_equal(normal, axis):
            return f"{name} = {origin @ normal:.6g}"
    return (f"plane through ({', '.join(f'{v:.6g}' for v in origin)}) normal "
            f"({', '.join(f'{v:.4g}' for v in normal)})")


def _say(kind: str, message) -> None:
    text = " ".join(str(message).split())          # one line, whatever the message
    print(f"{PROG}: {kind}: {text}", file=sys.stderr)


def _demo(args) -> int:
    from .demo import demo_part
    from .quality import ASPECT_BOUND
    from .sources import section

    out = args.output
    out.mkdir(parents=True, exist_ok=True)
    part = demo_part()
    solid = out / "part.stl"
    _write_stl(part, solid)
    region = section(part, plane_origin=(0.0, 0.0, 0.0), plane_normal=(0.0, 0.0, 1.0))
    task = _Task(region, "auto", args.seed, None, out / "section.ply", out / "section.png",
                 discs=True)
    entry = _mesh_section(task)
    _warn_about(entry)
    report = out / "report.json"
    _write_report(report, "pds_plugin.demo.demo_part()", [entry])
    c = entry["certificate"]

    def verdict(ok):
        return "ok" if ok else "FAILED"
    print("\n".join([
        "pds-mesh demo: a 4 x 2 x 0.5 plate with two holes, a slot and a sharp notch "
        "(manifold3d),",
        "cut at mid-thickness (z = 0) and meshed with the automatic alpha.",
        "",
        f"  section      {region.betti[0]} component(s), {region.betti[1]} hole(s), area "
        f"{region.area:.6g}",
        f"  alpha        {entry['alpha']:.6g}, from the narrowest feature: "
        f"{entry['feature_size']['where']}",
        f"  mesh         {entry['samples']} samples, {entry['triangles']} triangles",
        f"  certificate  {verdict(c['ok'])}",
        f"    sampling   {verdict(c['sampling_ok'])}: samples >= {c['min_separation']:.6f} "
        f"alpha apart, every point within {c['coverage_gap']:.6f} alpha of one",
        f"    quality    {verdict(c['quality_ok'])}: max aspect ratio "
        f"{c['max_aspect_ratio']:.4f} <= 4√3 = {ASPECT_BOUND:.4f}, angles "
        f"{c['min_angle']:.2f}° to {c['max_angle']:.2f}°",
        f"    topology   {verdict(c['topology_ok'])}: mesh (b0, b1) = "
        f"{tuple(c['betti_mesh'])}, section {tuple(c['betti_region'])}",
        "",
        f"  {solid}  the solid (try the command on it)",
        f"  {task.output}  the mesh: binary PLY, face quality = aspect ratio",
        f"  {report}  quality statistics and certificate",
        f"  {task.plot}  samples with discs, mesh by aspect ratio, histogram",
        "",
        "next, a finer mesh, and one too coarse (its certificate says which holes it lost):",
        f"  pds-mesh {solid} -o {out / 'fine.ply'} --axis z --alpha 0.03",
        f"  pds-mesh {solid} -o {out / 'coarse.ply'} --axis z --alpha 0.3",
    ]))
    return 0


def _write_stl(part, path: Path) -> None:
    import trimesh

    mesh = part.to_mesh64()
    trimesh.Trimesh(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts),
                    process=False).export(path)


if __name__ == "__main__":
    sys.exit(main())
