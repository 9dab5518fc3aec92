"""``pds-mesh batch MANIFEST -o DIR``: many parts and planes, locally or on a Dask cluster.

Exit status: 0 when every job succeeded (or was done before), 1 when any job failed (the
others are still done), 2 for a usage error (bad arguments, a manifest that cannot be
read, a scheduler that cannot be reached), 130 when interrupted.
"""

from __future__ import annotations

import sys
from contextlib import contextmanager

from ..batch import RESULTS, mesh_batch, read_manifest
from ..errors import PdsError
from .output import say

__all__ = ["run"]

USAGE_ERROR = 2


def run(args) -> int:
    """Run ``pds-mesh batch`` with parsed arguments; return the exit status.

    Parameters
    ----------
    args : argparse.Namespace
        ``manifest``, ``output`` (the folder), ``scheduler`` or ``workers``, ``quiet``.

    Returns
    -------
    int
        0 every job ok or skipped, 1 some job failed, 2 usage error.
    """
    try:
        jobs = read_manifest(args.manifest)
    except (PdsError, OSError) as error:
        say("error", error)
        return USAGE_ERROR
    with _executor(args.scheduler) as executor:
        if executor is None and args.scheduler is not None:
            return USAGE_ERROR
        rows = mesh_batch(jobs, args.output, executor=executor, workers=args.workers,
                          base_dir=args.manifest.parent,
                          progress=not args.quiet and sys.stderr.isatty())
    failed = [row for row in rows if row["status"] == "error"]
    for row in failed:
        say("error", f"job {row['job']} ({row['input']}): {row['error']}")
    if not args.quiet:
        print(_summary(rows, args.output / RESULTS))
    return 1 if failed else 0


def _summary(rows: list[dict], results) -> str:
    """One line: how many jobs did what, and where the rows are.

    Examples
    --------
    >>> _summary([{"status": "ok", "certificate_ok": False},
    ...           {"status": "skipped", "certificate_ok": True}], "out/results.jsonl")
    '2 jobs: 1 ok, 1 skipped (done before), 0 failed, 1 with a failed certificate; results: out/results.jsonl'
    """
    count = {status: sum(row["status"] == status for row in rows)
             for status in ("ok", "skipped", "error")}
    uncertified = sum(row["certificate_ok"] is False for row in rows)
    return (f"{len(rows)} jobs: {count['ok']} ok, {count['skipped']} skipped (done before), "
            f"{count['error']} failed"
            f"{f', {uncertified} with a failed certificate' if uncertified else ''}; "
            f"results: {results}")


@contextmanager
def _executor(address):
    """A Dask executor on the cluster at ``address`` (closed afterwards); None without an
    address, or (after saying why) when the cluster cannot be used."""
    if address is None:
        yield None
        return
    try:
        from distributed import Client
    except ImportError:
        say("error", '--scheduler needs Dask: pip install "pds_plugin[dask]"')
        yield None
        return
    try:
        client = Client(address, timeout="10s")
    except (OSError, ValueError, TypeError) as error:
        say("error", f"cannot reach the Dask scheduler at {address}: {error}")
        yield None
        return
    try:
        yield client.get_executor()
    finally:
        client.close()
