"""Batches on Dask: throughput with 1 and 2 workers and the batch's overhead per job.

    python bench/batch.py                      # 100 sections of the shared parts (~3 min)
    python bench/batch.py --sections 10 --out /tmp/batch.md      # a smoke run

The jobs are single-plane sections of ``../shared/data`` featuretype.STL and
angle_block.STL, spread across each part's height. They run

1. in this process, one after the other (:func:`pds_plugin.batch.worker.run_job`, one
   kernel thread), after the same warm-up: the work itself, no batch machinery;
2. with :func:`pds_plugin.mesh_batch` on a Dask ``LocalCluster`` of 1, then 2 worker
   processes (one thread, one kernel thread each), after each worker has run one job of
   each part elsewhere (its start-up and imports, timed apart);
3. again on 2 workers into the same folder: every job is skipped (the cost of a rerun).

Throughput ratio = wall(1 worker) / wall(2 workers) (target >= 1.7). Overhead per job
(target <= 50 ms) = (wall(1 worker) - the jobs' own seconds on the worker) / jobs: what
scheduling, shipping the job and its result, and results.jsonl cost on top of the work.
Also shown: wall(1 worker) - wall(in process), which adds any difference between the
worker process and this one (on a loaded machine, mostly the share of the cores each
got). Every run's outputs are compared byte for byte (through their records' SHA-256).
The table is printed and written as a section of docs/benchmarks.md (which peers.py
keeps).
"""

from __future__ import annotations

import os

os.environ.setdefault("PDS_THREADS", "1")          # the in-process run: one kernel thread

import argparse                                                     # noqa: E402
import json                                                         # noqa: E402
import shlex                                                        # noqa: E402
import sys                                                          # noqa: E402
import tempfile                                                     # noqa: E402
import time                                                         # noqa: E402
from pathlib import Path                                            # noqa: E402

from _environment import machine                                    # noqa: E402
from _sections import put_section                                   # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"
# part: (alpha, z range strictly inside the part); alphas give ~0.2-0.4 s jobs
PARTS = {"featuretype.STL": (0.05, (0.0, 1.375)), "angle_block.STL": (0.015, (-1.352, 0.0))}
TARGET_RATIO, TARGET_OVERHEAD = 1.7, 0.050


def jobs(count: int) -> list[dict]:
    """``count`` single-plane jobs, alternating parts, planes spread over each part's
    height (offset from the slab middles so that no plane lies on a CAD face)."""
    per_part = {name: (count + i) // len(PARTS) for i, name in enumerate(reversed(PARTS))}
    result = []
    for name, (alpha, (low, high)) in PARTS.items():
        n = per_part[name]
        result += [{"input": name, "axis": "z", "alpha": alpha,
                    "at": round(low + (i + 0.37) * (high - low) / n, 9)} for i in range(n)]
    return sorted(result, key=lambda job: (job["at"], job["input"]))


def warm_up(batch: list[dict]) -> float:
    """Run one job of each part into a folder of its own, untimed by the batch: every
    library imported and every kernel loaded; seconds taken."""
    from pds_plugin.batch.jobs import parse_job
    from pds_plugin.batch.worker import run_job

    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as scratch:
        firsts = {job["input"]: job for job in reversed(batch)}
        for index, job in enumerate(firsts.values()):
            row = run_job(parse_job(job, index, scratch, DATA))
            assert row["status"] == "ok", row
    return time.perf_counter() - start


def in_process(batch: list[dict], out: Path) -> tuple[float, list[dict]]:
    from pds_plugin.batch.jobs import parse_job
    from pds_plugin.batch.worker import run_job

    warm_up(batch)
    start = time.perf_counter()
    rows = [run_job(parse_job(job, i, out, DATA)) for i, job in enumerate(batch)]
    return time.perf_counter() - start, rows


def on_dask(batch: list[dict], workers: int, out: Path, rerun: bool = False) -> dict:
    from distributed import Client, LocalCluster

    import pds_plugin as pds

    start = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=":0", env={"PDS_THREADS": "1"},
                      silence_logs=50) as cluster, Client(cluster) as client:
        started = time.perf_counter() - start
        warm = client.run(warm_up, batch)                  # once on every worker
        result = {"start": started, "warm_up": max(warm.values())}
        for run in ("first", "rerun") if rerun else ("first",):
            begin = time.perf_counter()
            rows = pds.mesh_batch(batch, out, executor=client.get_executor(),
                                  progress=False, base_dir=DATA)
            result[run] = (time.perf_counter() - begin, rows)
    return result


def _own(rows: list[dict]) -> float:
    """Mean seconds a job took where it ran, in ms."""
    return 1000 * sum(row["seconds"] for row in rows) / len(rows)


def digests(out: Path) -> dict:
    """Output name -> SHA-256, from the records."""
    found = {}
    for record in out.glob("*.ply.json"):
        found.update({Path(k).name: v for k, v in json.loads(record.read_text())["outputs"].items()})
    return found


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sections", type=int, default=100, help="jobs (default 100)")
    parser.add_argument("--repeat", type=int, default=2,
                        help="runs of each configuration, alternated, the fastest kept "
                             "(default 2): a busy machine's load drifts between runs")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks.md",
                        help="the report whose 'bench/batch.py' section is (re)written")
    args = parser.parse_args(argv)
    missing = [name for name in PARTS if not (DATA / name).exists()]
    if missing:
        sys.exit(f"bench/batch.py needs {', '.join(missing)} in {DATA}")
    command = shlex.join(["python", "bench/batch.py", *(sys.argv[1:] if argv is None else argv)])
    start = machine()
    batch = jobs(args.sections)
    runs = {"serial": [], 1: [], 2: []}
    with tempfile.TemporaryDirectory() as scratch:
        scratch = Path(scratch)
        for repeat in range(args.repeat):
            last = repeat == args.repeat - 1
            runs["serial"].append(in_process(batch, scratch / f"serial{repeat}"))
            runs[1].append(on_dask(batch, 1, scratch / f"one{repeat}"))
            runs[2].append(on_dask(batch, 2, scratch / f"two{repeat}", rerun=last))
            print(f"run {repeat + 1}: in process {runs['serial'][-1][0]:.2f} s, 1 worker "
                  f"{runs[1][-1]['first'][0]:.2f} s, 2 workers {runs[2][-1]['first'][0]:.2f} s",
                  flush=True)
        outputs = [digests(folder) for folder in sorted(scratch.iterdir())]
        same = all(found == outputs[0] for found in outputs)
    end_load = os.getloadavg()
    serial, serial_rows = min(runs["serial"], key=lambda run: run[0])
    one = min(runs[1], key=lambda run: run["first"][0])
    two = min(runs[2], key=lambda run: run["first"][0])
    two["rerun"] = runs[2][-1]["rerun"]
    rows = [serial_rows, one["first"][1], two["first"][1]]
    failed = sum(row["status"] != "ok" for run in rows for row in run)
    walls = {"in process": [run[0] for run in runs["serial"]],
             "1 worker": [run["first"][0] for run in runs[1]],
             "2 workers": [run["first"][0] for run in runs[2]]}
    every = "; ".join(f"{name} {', '.join(f'{t:.1f}' for t in times)} s"
                      for name, times in walls.items())
    skipped = sum(row["status"] == "skipped" for row in two["rerun"][1])
    n = len(batch)
    ratio = one["first"][0] / two["first"][0]
    work = sum(row["seconds"] for row in one["first"][1]) / n
    overhead = one["first"][0] / n - work
    versus_serial = (one["first"][0] - serial) / n
    verdict = {True: "**holds**", False: "**misses**"}
    table = "\n".join([
        "## Batches on Dask (bench/batch.py)\n",
        f"Written by `{command}` on {start['date']} (commit `{start['commit']}`); "
        f"{start['cores']} cores; load average (1, 5, 15 min) "
        f"{' '.join(f'{v:.2f}' for v in start['load'])} at the start, "
        f"{' '.join(f'{v:.2f}' for v in end_load)} at the end. {n} single-plane sections of "
        f"featuretype.STL (alpha {PARTS['featuretype.STL'][0]}) and angle_block.STL (alpha "
        f"{PARTS['angle_block.STL'][0]}); one thread and one kernel thread per worker. "
        f"Each configuration ran {args.repeat} time(s), alternated, the fastest kept "
        f"(every run: {every}).\n",
        "| run | wall (s) | jobs/s | wall per job (ms) | a job's own time (ms) | × 1 worker |",
        "|---|---|---|---|---|---|",
        f"| in process, one after the other | {serial:.2f} | {n / serial:.2f} | "
        f"{1000 * serial / n:.0f} | {_own(serial_rows):.0f} | — |",
        *(f"| Dask LocalCluster, {w} worker{'s' if w > 1 else ''} | {r['first'][0]:.2f} | "
          f"{n / r['first'][0]:.2f} | {1000 * r['first'][0] / n:.0f} | "
          f"{_own(r['first'][1]):.0f} | {one['first'][0] / r['first'][0]:.2f} |"
          for w, r in ((1, one), (2, two))),
        f"| rerun on 2 workers (all skipped) | {two['rerun'][0]:.2f} | {n / two['rerun'][0]:.1f} | "
        f"{1000 * two['rerun'][0] / n:.0f} | {_own(two['rerun'][1]):.0f} | — |",
        "",
        "A job's own time is its mean `seconds` on the worker. With 2 workers it stays "
        "that of 1 worker only when a second core is free; on a loaded machine it grows "
        "and the throughput ratio with it falls.",
        "",
        "| target | measured | verdict |",
        "|---|---|---|",
        f"| 2 workers ≥ {TARGET_RATIO}× the throughput of 1 | {ratio:.2f}× | "
        f"{verdict[ratio >= TARGET_RATIO]} |",
        f"| overhead ≤ {1000 * TARGET_OVERHEAD:.0f} ms per job | {1000 * overhead:.1f} ms "
        f"(1 worker's wall time per job {1000 * one['first'][0] / n:.0f} ms − the job's own "
        f"{1000 * work:.0f} ms on the worker); against the same jobs in process "
        f"{1000 * versus_serial:.0f} ms | {verdict[overhead <= TARGET_OVERHEAD]} |",
        "",
        f"Worker start-up, apart: cluster start {one['start']:.2f} s (1 worker), "
        f"{two['start']:.2f} s (2 workers); a fresh worker's first two jobs (one per part: "
        f"imports) {one['warm_up']:.2f} s / {two['warm_up']:.2f} s. "
        f"Failed jobs: {failed}. Rerun: {skipped} of {n} skipped. Outputs of the three runs "
        f"identical byte for byte: {'yes' if same else 'NO'}.",
    ])
    print(table)
    put_section(args.out, "bench/batch.py", table)
    print(f"written to {args.out}")


if __name__ == "__main__":
    main()
