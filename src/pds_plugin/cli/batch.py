"""``pds-mesh batch MANIFEST -o DIR``: many parts and planes, locally or on a Dask cluster.

Exit status: 0 when every job succeeded (or was done before), 1 when any job failed (the
others are still done), 2 for a usage error (bad arguments, a manifest that cannot be
read, a scheduler that cannot be reached), 130 when interrupted.
"""

from __future__ import annotations

import sys

from .._checks import import_optional
from ..batch import RESULTS, mesh_batch, read_manifest
from ..errors import ArgumentError, PdsError
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
        client = _client(args.scheduler)
    except (PdsError, OSError) as error:
        say("error", error)
        return USAGE_ERROR
    try:
        rows = mesh_batch(jobs, args.output, workers=args.workers,
                          executor=None if client is None else client.get_executor(),
                          base_dir=args.manifest.parent,
                          progress=not args.quiet and sys.stderr.isatty())
    finally:
        if client is not None:
            client.close()
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


def _client(address):
    """A Dask client of the cluster at ``address``, or None without an address."""
    if address is None:
        return None
    distributed = import_optional("distributed", "dask", "pds-mesh batch --scheduler")
    try:
        return distributed.Client(address, timeout="10s")
    except (OSError, ValueError) as error:      # refused, timed out, not an address
        raise ArgumentError(f"cannot reach the Dask scheduler at {address}: {error}; "
                            f"start one with 'dask scheduler' (see pds-mesh batch "
                            f"--help)") from error
