"""``pds-mesh batch MANIFEST -o DIR``: many parts and planes, locally or on a Dask cluster.

Exit status: 0 when every job succeeded (or was already done), 1 when any job failed
(the others are still done), 2 for a usage error (bad arguments, a manifest that cannot
be read, a scheduler that cannot be reached), 130 when interrupted.
"""

from __future__ import annotations

import argparse
import sys
from contextlib import contextmanager
from pathlib import Path

__all__ = ["batch_parser", "run_batch"]

_EPILOG = """\
manifest (JSON Lines, one job per line; or CSV with these column names):
  {"input": "bracket.stl", "axis": "z", "slices": 10, "alpha": "auto"}
  {"input": "bracket.stl", "plane_origin": [0, 0, 5], "plane_normal": [0, 1, 1], "alpha": 0.2}
  {"input": "logo.svg", "alpha": 2.5, "output": "logos/logo.obj"}
  Options as for 'pds-mesh INPUT' with _ for -: input, output, axis, plane_normal,
  plane_origin, at, slices, alpha, graded, seed, max_samples. Relative inputs are read
  from the manifest's folder, relative outputs written to DIR; without output the name
  comes from the input and the plane (bracket_z0.5.ply).

results:
  DIR/results.jsonl, one line per job in manifest order: status (ok, error, skipped,
  cancelled), output, seconds, certificate_ok, error. Each output has a record
  OUTPUT.json (input SHA-256, options, section reports); a rerun skips the jobs whose
  record still matches and leaves their files untouched.

examples:
  pds-mesh batch parts.jsonl -o meshes/                            local processes
  pds-mesh batch parts.csv -o /shared/meshes --scheduler tcp://head:8786

exit status: 0 every job ok or skipped, 1 some job failed, 2 usage error.
"""


def batch_parser(parser_class, prog: str) -> argparse.ArgumentParser:
    """The arguments of ``pds-mesh batch``."""
    parser = parser_class(
        prog=f"{prog} batch", formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=_EPILOG,
        description="Mesh every job of a manifest (many parts, many planes) in parallel "
                    "processes or on a Dask cluster; resumable: a rerun only does what "
                    "is missing.")
    parser.add_argument("manifest", metavar="MANIFEST", type=Path,
                        help="the jobs: JSON Lines (.jsonl) or CSV (.csv)")
    parser.add_argument("-o", "--output", metavar="DIR", type=Path, required=True,
                        help="folder for the meshes and results.jsonl (created)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on this Dask cluster, e.g. tcp://head:8786 (needs "
                            "pip install \"pds_plugin[dask]\")")
    where.add_argument("-w", "--workers", type=int, metavar="N",
                       help="local processes (default: one per core)")
    parser.add_argument("-q", "--quiet", action="store_true",
                        help="print nothing but the failed jobs")
    return parser


def run_batch(args, usage_error, say) -> int:
    """Run the parsed ``pds-mesh batch`` arguments; ``usage_error(message)`` exits with
    status 2, ``say(kind, message)`` prints one line on stderr."""
    from .batch import RESULTS, mesh_batch, read_manifest

    if args.workers is not None and args.workers < 1:
        usage_error(f"--workers must be a positive integer, got {args.workers}")
    try:
        jobs = read_manifest(args.manifest)
    except (OSError, ValueError) as error:
        usage_error(str(error))
    with _executor(args.scheduler, usage_error) as executor:
        rows = mesh_batch(jobs, args.output, executor=executor, workers=args.workers,
                          base_dir=args.manifest.parent,
                          progress=not args.quiet and sys.stderr.isatty())
    failed = [row for row in rows if row["status"] == "error"]
    for row in failed:
        say("error", f"job {row['job']} ({row['input']}): {row['error']}")
    if not args.quiet:
        counts = {status: sum(row["status"] == status for row in rows)
                  for status in ("ok", "skipped", "error")}
        uncertified = sum(row["certificate_ok"] is False for row in rows)
        print(f"{len(rows)} jobs: {counts['ok']} ok, {counts['skipped']} skipped (done "
              f"before), {counts['error']} failed"
              f"{f', {uncertified} with a failed certificate' if uncertified else ''}; "
              f"results: {args.output / RESULTS}")
    return 1 if failed else 0


@contextmanager
def _executor(address, usage_error):
    """A Dask executor on the cluster at ``address`` (closed afterwards), or None."""
    if address is None:
        yield None
        return
    try:
        from distributed import Client
    except ImportError:
        usage_error('--scheduler needs Dask: pip install "pds_plugin[dask]"')
    try:
        client = Client(address, timeout="10s")
    except (OSError, ValueError, TypeError) as error:
        usage_error(f"cannot reach the Dask scheduler at {address}: {error}")
    try:
        yield client.get_executor()
    finally:
        client.close()
