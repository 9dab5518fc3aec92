"""The ``pds-mesh`` command: certified triangle meshes of CAD sections and 2D drawings.

``pds-mesh demo`` runs the whole product on a built-in part; ``pds-mesh remesh IN -o
OUT`` re-triangulates every planar face of a mesh file, the solid kept; ``pds-mesh batch MANIFEST
-o DIR`` meshes many parts and planes, locally or on Dask; ``pds-mesh mesh INPUT -o
OUT`` (or just ``pds-mesh INPUT -o OUT``) meshes one or several sections of a mesh file
(STL, OBJ, PLY, OFF, 3MF, GLB), or an SVG or DXF drawing, and writes the meshes (binary PLY with
face quality = aspect ratio, or OBJ), optionally a JSON report of every certificate and a
picture per mesh. Run ``pds-mesh --help`` for the options.

- :mod:`.arguments`: the parser, one subcommand per command;
- :mod:`.mesh`, :mod:`.demo` and :mod:`.batch`: the commands;
- :mod:`.output`: messages, summaries and the JSON report.

Exit status: 0 on success (also when a certificate fails: that is reported as a
warning and in the report), 1 for a bad input (one line ``pds-mesh: error: ...`` on
stderr), 2 for a usage error, 130 when interrupted. Only bad input
(:class:`~pds_plugin.errors.PdsError`) and file errors (``OSError``) are reported in one
line; anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

import signal
import sys
import threading

from ..errors import PdsError
from . import batch, demo, mesh, remesh
from .arguments import COMMANDS, PROG, glue_negative_values, parser
from .output import say

__all__ = ["main", "console"]

_RUN = {"mesh": mesh.run, "demo": demo.run, "batch": batch.run, "remesh": remesh.run}


def main(argv=None) -> int:
    """Run ``pds-mesh`` with ``argv`` (default ``sys.argv[1:]``); return the exit status.

    A first argument that is not a command (``mesh``, ``demo``, ``batch``) nor ``-h``/``--help``
    means ``mesh``: ``pds-mesh part.stl ...`` is ``pds-mesh mesh part.stl ...``, and a
    file named ``demo`` is meshed with ``pds-mesh mesh demo ...``.

    Parameters
    ----------
    argv : list of str, optional

    Returns
    -------
    int
        0 success, 1 bad input, 2 usage error, 130 interrupted.

    Examples
    --------
    >>> main(["tiny.stl", "-o", "out.ply", "--alpha", "-1"])
    2
    """
    argv = sys.argv[1:] if argv is None else [str(a) for a in argv]
    if not argv or argv[0] not in (*COMMANDS, "-h", "--help", "--version"):
        argv = ["mesh", *argv]
    main_thread = threading.current_thread() is threading.main_thread()
    if main_thread:                       # SIGTERM ends a run as Ctrl-C does
        terminate = signal.signal(signal.SIGTERM, _interrupt)
    try:
        args = parser().parse_args(glue_negative_values(argv))
        return _RUN[args.command](args)
    except SystemExit as stop:             # --help, and usage errors from argparse
        return stop.code if isinstance(stop.code, int) else 1
    except (PdsError, OSError) as error:
        say("error", error)
        return 1
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, terminate)


def console() -> None:
    """The ``pds-mesh`` process: exit with :func:`main`'s status.

    After an interrupt the run is over, so a further Ctrl-C (pressed twice quickly)
    must not cut the exit short: it would end the process by the signal instead of
    status 130, in the middle of the interpreter's shutdown.
    """
    status = main()
    if status == 130:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    sys.exit(status)


def _interrupt(signum, frame):
    raise KeyboardInterrupt
