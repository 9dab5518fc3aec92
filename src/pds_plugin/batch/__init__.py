"""Batches: many parts and planes meshed on any ``concurrent.futures`` executor.

:func:`mesh_batch` checks every job in the driver, sends each checked job (paths,
numbers and strings only) to the executor, and writes ``results.jsonl`` in job order.
The work itself (:func:`~pds_plugin.batch.worker.run_job`) is idempotent and atomic, so
a batch can be interrupted, a worker killed, a task run twice, and a rerun does only what
is missing.

- :mod:`.jobs`: a job mapping checked and named (:func:`~.jobs.parse_job`);
- :mod:`.worker`: one job run where it lands, skipped when its record proves it done;
- :mod:`.manifest`: JSON Lines and CSV manifests.
"""

from __future__ import annotations

import json
import os
import signal
import sys
import uuid
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import replace
from pathlib import Path

from .._atomic import atomic_path, leftovers
from .._parallel import set_threads
from ..errors import PdsError
from .jobs import Job, parse_job
from .manifest import read_manifest
from .worker import result_row, run_job

__all__ = ["mesh_batch", "read_manifest", "local_executor", "RESULTS"]

#: The file, in ``out_dir``, that holds one result row per job, in job order.
RESULTS = "results.jsonl"


def mesh_batch(jobs, out_dir, *, executor=None, progress=True, workers=None,
               base_dir=".") -> list[dict]:
    """Mesh many parts and planes; return one result row per job, in job order.

    Every job is checked first; a job that cannot run (a bad option, an output shared
    with another job) becomes an ``error`` row without stopping the others, and so does
    a job that fails on its worker (unreadable file, plane missing the part, alpha too
    large). Outputs are written under a temporary name and renamed into place. A job
    whose output and record (``OUTPUT.json``: input SHA-256, options, file SHA-256s,
    section reports) match is ``skipped`` and its files are left untouched, so a rerun
    only does what is missing. On Ctrl-C the queued jobs are cancelled, the running ones
    finish (a second Ctrl-C kills the local workers; their temporary files are removed),
    ``results.jsonl`` is written with the jobs not done as ``cancelled``, and
    ``KeyboardInterrupt`` is raised again. On a cluster the running tasks cannot be
    stopped: they finish on their own, atomically, and a rerun skips them.

    Parameters
    ----------
    jobs : iterable of mapping
        Each with the CLI's options (``_`` for ``-``): ``input`` (mesh file, SVG or DXF drawing);
        a plane by ``axis`` or ``plane_normal``, with ``at`` (offsets), ``plane_origin``
        or ``slices``; ``alpha`` (number or ``"auto"``), ``graded``, ``conforming``
        (default true; false for the paper's pure complex, ``--no-conforming``), ``seed``,
        ``max_samples``; ``output`` (optional: derived from the input name and the plane,
        ``part_z0.5.ply``). See :func:`~pds_plugin.batch.jobs.parse_job`.
    out_dir : str or os.PathLike
        Where relative outputs and ``results.jsonl`` go (created).
    executor : concurrent.futures.Executor, optional
        Runs the jobs, e.g. ``dask.distributed.Client(address).get_executor()``, or a
        Ray-backed executor (see the README). On a cluster, inputs and ``out_dir`` must be
        on storage every worker sees under the same path. Default: a local pool of
        spawned processes, one per core, each with one kernel thread
        (:func:`local_executor`), shut down at the end.
    progress : bool
        Show a progress bar on stderr.
    workers : int, optional
        The number of processes of the default pool (default: one per core).
    base_dir : str or os.PathLike
        Relative inputs are read from there (the CLI passes the manifest's folder).

    Returns
    -------
    list of dict
        One row per job (see :func:`~pds_plugin.batch.worker.result_row`): ``status``
        ``ok``, ``error``, ``skipped`` or ``cancelled``, ``output``, ``seconds``,
        ``certificate_ok``, ``error``; also written to ``out_dir/results.jsonl``.

    Raises
    ------
    OSError
        If ``out_dir`` cannot be created or ``results.jsonl`` written.
    KeyboardInterrupt
        Again, after Ctrl-C, once ``results.jsonl`` is written.

    Examples
    --------
    >>> import tempfile, trimesh
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> folder = tempfile.mkdtemp()
    >>> _ = trimesh.creation.box(extents=(2, 2, 2)).export(f"{folder}/box.stl")
    >>> jobs = [{"input": f"{folder}/box.stl", "axis": "z", "at": at, "alpha": 0.5}
    ...         for at in (-0.5, 0.5)] + [{"input": f"{folder}/box.stl", "alpha": 0.5}]
    >>> with ThreadPoolExecutor(2) as pool:
    ...     rows = mesh_batch(jobs, f"{folder}/out", executor=pool, progress=False)
    >>> [(row["status"], row["certificate_ok"]) for row in rows]
    [('ok', True), ('ok', True), ('error', None)]
    >>> Path(rows[0]["output"]).name
    'box_z-0.5.ply'
    >>> rows[2]["error"]
    'box.stl is a solid: say where to cut it with axis or plane_normal (and at, plane_origin or slices)'
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    checked = _check(list(jobs), out_dir, base_dir, run=uuid.uuid4().hex)
    runnable = [job for job in checked if isinstance(job, Job)]
    rows = [None if isinstance(job, Job) else job for job in checked]
    own = executor is None and bool(runnable)
    if own:
        executor = local_executor(min(workers or os.cpu_count() or 1, len(runnable)))
    futures, interrupted = {}, False
    try:
        for job in runnable:
            futures[executor.submit(run_job, job)] = job
        with _progress_bar(len(checked), progress) as bar:
            bar.update(len(checked) - len(runnable))
            for future in as_completed(futures):
                rows[futures[future].index] = _row(future, futures[future])
                bar.update()
    except KeyboardInterrupt:
        interrupted = True
        for future in futures:
            future.cancel()
        raise
    finally:
        if own:
            _stop(executor, interrupted)
        for future, job in futures.items():       # whatever finished meanwhile counts
            if (rows[job.index] is None and future.done() and not future.cancelled()
                    and not (interrupted and future.exception() is not None)):
                rows[job.index] = _row(future, job)
        rows = [row or result_row(job, "cancelled")
                for row, job in zip(rows, checked)]
        if own or not interrupted:           # else a cluster may still be writing
            _sweep(runnable)
        _write_results(out_dir / RESULTS, rows)
    return rows


def local_executor(workers: int) -> ProcessPoolExecutor:
    """A pool of ``workers`` spawned processes, each meshing with one kernel thread.

    Spawned, not forked: a child forked after the parallel kernels started GNU OpenMP
    is terminated by it. One kernel thread per process: the processes already
    share the cores. Its processes ignore Ctrl-C: :func:`mesh_batch` decides.

    Parameters
    ----------
    workers : int

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor

    Examples
    --------
    >>> with local_executor(1) as pool:
    ...     pool.submit(os.getpid).result() != os.getpid()
    True
    """
    from multiprocessing import get_context

    return ProcessPoolExecutor(max_workers=workers, mp_context=get_context("spawn"),
                               initializer=_start_local_worker)


def _check(mappings: list, out_dir: Path, base_dir, run: str) -> list:
    """Each job checked (a :class:`Job` of this ``run``) or its error row; an output two
    jobs would write is an error for the later job."""
    checked, owner = [], {}
    for index, mapping in enumerate(mappings):
        try:
            job = replace(parse_job(mapping, index, out_dir, base_dir), run=run)
        except PdsError as error:
            checked.append(_unchecked_row(index, mapping, str(error)))
            continue
        clash = next((owner[path] for path in (*job.outputs, str(job.record))
                      if path in owner), None)
        if clash is not None:
            checked.append(result_row(job, "error", error=(
                f"{Path(job.output).name} is also written by job {clash}; give this job "
                f"another output")))
            continue
        owner.update(dict.fromkeys((*job.outputs, str(job.record)), index))
        checked.append(job)
    return checked


def _unchecked_row(index: int, mapping, error: str) -> dict:
    source = mapping.get("input") if hasattr(mapping, "get") else None
    return {"job": index, "input": source, "status": "error", "output": None,
            "seconds": None, "certificate_ok": None, "error": error}


def _row(future, job: Job) -> dict:
    """The row a finished future gives; a lost worker or task is an error row too."""
    try:
        return future.result()
    except Exception as error:
        return result_row(job, "error", error=f"the worker running this job failed "
                                             f"({type(error).__name__}: {error}); run the "
                                             f"batch again to retry it")


def _start_local_worker() -> None:
    """Pool initializer: one kernel thread, and deaf to Ctrl-C (the driver decides)."""
    set_threads(1)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _stop(pool: ProcessPoolExecutor, interrupted: bool) -> None:
    """Shut our own pool down. After Ctrl-C the running jobs finish (a job is never
    cut inside a library); a second Ctrl-C kills the processes, whose temporary files
    :func:`_sweep` then removes."""
    if interrupted:
        print("pds-mesh batch: interrupted; finishing the running jobs (Ctrl-C again to "
              "stop them now)", file=sys.stderr)
    try:
        pool.shutdown(wait=True, cancel_futures=True)
    except KeyboardInterrupt:
        for process in list((getattr(pool, "_processes", None) or {}).values()):
            process.kill()                   # pid -> Process, private but stable
            process.join()
        pool.shutdown(wait=False, cancel_futures=True)


def _sweep(jobs: list[Job]) -> None:
    """Remove the temporary files that workers killed outright (SIGKILL) left mid-write
    for this batch's files (one listing per output folder)."""
    ours = {Path(name) for job in jobs for name in (*job.outputs, job.record)}
    for folder in {path.parent for path in ours}:
        for partial, final in leftovers(folder).items():
            if final in ours:
                partial.unlink(missing_ok=True)


def _write_results(path: Path, rows: list[dict]) -> None:
    with atomic_path(path) as partial:
        partial.write_text("".join(json.dumps(row) + "\n" for row in rows), encoding="utf-8")


def _progress_bar(total: int, show: bool):
    from tqdm import tqdm

    return tqdm(total=total, desc="pds-mesh batch", unit="job", file=sys.stderr,
                disable=not show)
