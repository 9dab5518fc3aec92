"""``pds-mesh mesh``: mesh one or several sections of a mesh file, or a 2D drawing."""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
import warnings
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path

from .._atomic import atomic_path
from .._checks import check_output_directory, import_optional
from ..batch.jobs import numbered, plane_sections
from ..errors import ArgumentError, PdsError
from ..pipeline import mesh_region, section_report
from ..region import Region
from ..sampling import DEFAULT_MAX_SAMPLES
from ..sinks.files import writers
from ..sinks.plot import plot_report
from ..sources.drawing import READERS, is_drawing, load_drawing
from .arguments import AXES, PROG, wants_graded
from .output import say, summary, warn_about, write_report

__all__ = ["Task", "mesh_section", "mesh_and_report", "run"]


@dataclass(frozen=True)
class Task:
    """Everything needed to mesh one section, sent whole to a worker process.

    Attributes
    ----------
    region : Region
        The section.
    alpha : float or "auto"
    seed : int
    max_samples : int or None
        The sample budget, None for the default.
    output : Path
        The mesh file to write.
    plot : Path or None
        The picture to draw, if any.
    discs : bool
        Draw each sample's disc in the picture.
    write_output, write_plot : Path or None
        Where to write the mesh and the picture now, if not under their names: the
        temporary names a run of several sections renames into place when all succeeded.
    conforming : bool
        Conforming and constrained (the default), or the paper's pure construction.
    graded : bool
        A graded mesh (docs/graded.md).
    grading : float or None
        Its Lipschitz constant L, None for the default.
    """

    region: Region
    alpha: float | str
    seed: int
    max_samples: int | None
    output: Path
    plot: Path | None
    discs: bool
    write_output: Path | None = None
    write_plot: Path | None = None
    conforming: bool = True
    graded: bool = False
    grading: float | None = None


def mesh_section(task: Task) -> dict:
    """Mesh, certify and write one section; return its report entry (JSON-ready).

    Parameters
    ----------
    task : Task

    Returns
    -------
    dict
        As :func:`pds_plugin.section_report`, with the warnings raised on the way.

    Raises
    ------
    PdsError
        Of the same class as the pipeline's or the sinks', the message prefixed with the
        output file so that the failing section of several is named.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from shapely.geometry import box
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "square.ply"
    >>> task = Task(Region.from_shapely(box(0, 0, 1, 1)), 0.25, 0, None, out, None, False)
    >>> entry = mesh_section(task)
    >>> entry["certificate"]["ok"], out.read_bytes()[:3]
    (True, b'ply')
    """
    return mesh_and_report(task)[1]


def mesh_and_report(task: Task):
    """:func:`mesh_section`, returning the mesh too: (PlanarMesh, report entry)."""
    budget = {} if task.max_samples is None else {"max_samples": task.max_samples}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            mesh = mesh_region(task.region, task.alpha, seed=task.seed,
                               conforming=task.conforming, graded=task.graded,
                               grading=task.grading, **budget)
            mesh.export(task.write_output or task.output)
            if task.plot is not None:
                plot_report(mesh, task.write_plot or task.plot, discs=task.discs)
        except PdsError as error:         # say which of several sections failed
            raise type(error)(f"{task.output}: {error}") from error
        mesh.certificate()
    return mesh, section_report(mesh, seed=task.seed,
                                alpha_mode="auto" if task.alpha == "auto" else "given",
                                output=task.output, plot=task.plot,
                                warnings=[str(w.message) for w in caught])


def run(args) -> int:
    """Run ``pds-mesh mesh`` with parsed arguments; return the exit status.

    Parameters
    ----------
    args : argparse.Namespace
        From :func:`pds_plugin.cli.arguments.parser`.

    Returns
    -------
    int
        0: every section was meshed and written (a failed certificate is a warning).

    Raises
    ------
    PdsError, OSError
        For bad input, before any meshing when it can be seen from the arguments.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from pds_plugin.cli.arguments import parser
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "square.svg").write_text(
    ...     '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><rect width="10" '
    ...     'height="10"/></svg>')
    >>> run(parser().parse_args(["mesh", str(folder / "square.svg"), "-o",
    ...                          str(folder / "square.ply"), "--alpha", "2", "-q"]))
    0
    """
    if args.output.suffix.lower() not in writers():
        raise ArgumentError(f"cannot write {args.output}: " + (
            f"it is a directory; give a file name, e.g. {args.output / 'section.ply'}"
            if args.output.is_dir() else
            f"the output suffix must be one of {', '.join(writers())}"))
    _check_outputs([args.output, args.report, args.plot], args.input)
    graded = wants_graded(args)
    if args.plot is not None:
        _check_picture(args.plot)
    regions = _regions(args)
    outputs = numbered(args.output, len(regions))
    plots = numbered(args.plot, len(regions)) if args.plot else [None] * len(regions)
    _check_outputs([*outputs, *plots], args.input)
    workers = _workers(args.jobs, len(regions))
    budget = args.max_samples or DEFAULT_MAX_SAMPLES
    if workers > 1:                       # the processes share the memory of one budget
        budget = max(1, budget // workers)
    with ExitStack() as files:            # every file renamed into place, or none
        staged = [[files.enter_context(atomic_path(p)) if p else None for p in pair]
                  for pair in zip(outputs, plots)]
        tasks = [Task(region, args.alpha, args.seed, budget, output, plot, args.discs,
                      write_output, write_plot, args.conforming, graded, args.grading)
                 for region, output, plot, (write_output, write_plot)
                 in zip(regions, outputs, plots, staged)]
        entries = _run(tasks, workers, progress=len(tasks) > 1 and not args.quiet)
        if args.report is not None:
            write_report(args.report, args.input, entries)
    for entry in entries:
        warn_about(entry)
        if not args.quiet:
            print(summary(entry))
    if args.report is not None and not args.quiet:
        print(f"report: {args.report}")
    return 0


def _check_outputs(paths, source) -> None:
    """Fail before any work if a file to write cannot be written or is the input."""
    for path in paths:
        if path is None:
            continue
        check_output_directory(path)
        if path.resolve() == Path(source).resolve():
            raise ArgumentError(f"the output {path} would overwrite the input; choose "
                                f"another name")


def _workers(jobs: int, sections: int) -> int:
    """Processes to use: at most one per section and one per core of this machine."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return max(1, min(jobs, sections, cores or 1))


def _results(tasks: list[Task], jobs: int):
    """Report entries of ``tasks`` in order, meshed in ``jobs`` processes.

    Workers are spawned, not forked: a child forked after the parallel kernels started
    GNU OpenMP is terminated by it. Each worker runs its kernels in one thread. When a
    section fails or the run is interrupted the workers are terminated at once (no
    queued section is meshed or written), and a worker whose parent dies (even by
    SIGKILL) ends too.
    """
    if jobs == 1 or len(tasks) == 1:
        yield from map(mesh_section, tasks)
        return
    from multiprocessing import get_context

    stops = {signal.SIGINT, signal.SIGTERM}
    signal.pthread_sigmask(signal.SIG_BLOCK, stops)    # a stop now would orphan workers
    try:
        pool = get_context("spawn").Pool(jobs, initializer=_start_worker,
                                          initargs=(os.getpid(),))
    finally:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, stops)   # a pending stop lands below
    try:
        yield from pool.imap(mesh_section, tasks)
        pool.close()
    except BaseException:
        pool.terminate()
        raise
    finally:
        pool.join()


def _start_worker(parent: int) -> None:
    """In a worker: run the kernels in one thread, and exit when the process that
    started it dies, however it died."""
    from .._parallel import set_threads

    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, signal.SIGTERM})  # inherited
    set_threads(1)
    if sys.platform.startswith("linux"):
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGTERM)                      # PR_SET_PDEATHSIG
    if os.getppid() != parent:                             # it died before we could ask
        os._exit(1)

    def watch():
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(1)
    threading.Thread(target=watch, daemon=True).start()


def _run(tasks: list[Task], jobs: int, progress: bool) -> list[dict]:
    from tqdm import tqdm

    with tqdm(total=len(tasks), desc=PROG, unit="section", file=sys.stderr,
              disable=not (progress and sys.stderr.isatty())) as bar:
        entries = []
        for entry in _results(tasks, jobs):
            entries.append(entry)
            bar.update()
    return entries


def _regions(args) -> list[Region]:
    """The sections the arguments ask for, checked against the input's kind; what the
    sources warn about (open strokes, automatic planes moved off faces) is said."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        regions = _read_regions(args)
    for warning in caught:
        say("warning", warning.message)
    return regions


def _read_regions(args) -> list[Region]:
    path = Path(args.input)
    if not path.exists():
        raise FileNotFoundError(f"no such file: {path}")
    if path.is_dir():
        raise IsADirectoryError(f"{path} is a directory, not a mesh file or a drawing")
    normal = AXES.get(args.axis, args.plane_normal)
    kind = path.suffix.lower()
    if args.layer and kind != ".dxf":
        raise ArgumentError(f"--layer selects layers of a DXF drawing; {path} is not one")
    if args.layout is not None and kind != ".dxf":
        raise ArgumentError(f"--layout selects a layout of a DXF drawing; {path} is not one")
    if is_drawing(path):
        given = [name for name in ("axis", "plane_normal", "plane_origin", "at", "slices",
                                   "on_face") if getattr(args, name) is not None]
        if given:
            raise ArgumentError(f"{path} is a {kind[1:].upper()} drawing, which is already "
                                f"planar: drop --{given[0].replace('_', '-')}")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            region = load_drawing(path, **_drawing_options(args))
        for warning in caught:
            say("warning", warning.message)
        return [region]
    if normal is None:
        raise ArgumentError(f"{path} is not a drawing ({', '.join(READERS)}), so it is cut "
                            f"as a solid (a mesh or STEP file): say where with --axis or "
                            f"--plane-normal (and --at, --plane-origin or --slices)")
    if args.slices is not None and args.plane_origin is not None:
        raise ArgumentError("--slices spreads the planes across the whole solid: drop "
                            "--plane-origin, or give --at offsets from it instead")
    return plane_sections(path, normal, plane_origin=args.plane_origin, at=args.at,
                          slices=args.slices, on_face=args.on_face, tolerance=args.tolerance)


def _drawing_options(args) -> dict:
    """The keywords of the drawing readers that --tolerance, --layer and --layout give."""
    options = {"tolerance": args.tolerance, "layers": args.layer, "layout": args.layout}
    return {key: value for key, value in options.items() if value is not None}


def _check_picture(path: Path) -> None:
    """Fail before any meshing if --plot cannot be written."""
    backends = import_optional("matplotlib.backend_bases", "plot", "--plot")
    kinds = backends.FigureCanvasBase.get_supported_filetypes()
    if path.suffix.lower().lstrip(".") not in kinds:
        raise ArgumentError(f"cannot draw {path}: the picture suffix must be one of "
                            f"{', '.join('.' + k for k in sorted(kinds))}")
