"""Run one peer on one region in a fresh Python process, under a time limit.

A fresh process per run makes the peak memory (``ru_maxrss``) that run's own, C
libraries included (tracemalloc sees only Python's allocations), and keeps a crash,
a hang or a leak of one peer out of the others' numbers. The child first runs the
peer once on a tiny square (imports, JIT caches, library start-up: not timed), then
on the job's region (the fastest of up to ``REPEATS`` runs when a run is shorter than
``REPEAT_BELOW`` seconds), and writes the mesh to ``result.npz`` and the rest to
``result.json``. The parent kills the child's whole process group at the time limit.

    python bench/_isolate.py JOB.pkl      # the child side; JOB.pkl from run_isolated
"""

from __future__ import annotations

import json
import os
import pickle
import signal
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

REPEATS = 3          # runs shorter than REPEAT_BELOW seconds are repeated up to this
REPEAT_BELOW = 1.0   # many times, and the fastest is kept


@dataclass
class Outcome:
    """A run's status ("ok", "timeout", "failed", "skipped") and, when ok, its data."""

    status: str
    message: str = ""
    vertices: np.ndarray | None = None
    faces: np.ndarray | None = None
    samples: np.ndarray | None = None
    alpha: float = float("nan")
    times: dict = field(default_factory=dict)
    peak_mb: float = float("nan")
    info: dict = field(default_factory=dict)


def run_isolated(peer_key: str, region, alpha: float, target: int, options,
                 timeout: float, env: dict | None = None) -> Outcome:
    """Run ``PEERS[peer_key]`` on ``region`` in a child process (with ``env`` added to
    its environment); never raises for the peer's own failures, which come back as the
    outcome's status and message."""
    with tempfile.TemporaryDirectory(prefix="pds_bench_") as folder:
        folder = Path(folder)
        with open(folder / "job.pkl", "wb") as file:
            pickle.dump({"peer": peer_key, "region": region, "alpha": alpha, "target": target,
                         "options": options}, file)
        with open(folder / "stderr.txt", "wb") as stderr:
            child = subprocess.Popen([sys.executable, __file__, str(folder / "job.pkl")],
                                     stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                     stderr=stderr, start_new_session=True,
                                     env={**os.environ, **(env or {})})
            try:
                code = child.wait(timeout=timeout)
            except BaseException as stop:        # the time limit, or Ctrl-C: no orphans
                os.killpg(child.pid, signal.SIGKILL)
                child.wait()
                if not isinstance(stop, subprocess.TimeoutExpired):
                    raise
                return Outcome("timeout", f"over the {timeout:g} s limit")
        if code != 0:
            stderr = (folder / "stderr.txt").read_text(errors="replace")
            return Outcome("failed", _failure(code, stderr))
        arrays = np.load(folder / "result.npz")
        meta = json.loads((folder / "result.json").read_text())
        return Outcome("ok", vertices=arrays["vertices"], faces=arrays["faces"],
                       samples=arrays["samples"] if "samples" in arrays else None, **meta)


def _failure(code: int, stderr: str) -> str:
    """The child's last error line, or the signal that killed it."""
    if code < 0:
        return f"killed by {signal.Signals(-code).name}"
    lines = [line for line in stderr.splitlines() if line.strip()]
    return lines[-1].strip()[:200] if lines else f"exit status {code}"


def _child(job_path: Path) -> None:
    from shapely.geometry import box

    from _runners import PEERS, Options
    from pds_plugin import Region

    with open(job_path, "rb") as file:
        job = pickle.load(file)
    run = PEERS[job["peer"]].run
    run(Region.from_shapely(box(0, 0, 1, 1)), 0.06, 200, Options())       # warm-up
    result = run(job["region"], job["alpha"], job["target"], job["options"])
    for _ in range(REPEATS - 1):     # short runs: the fastest of a few, as timeit does
        if result.times["total"] >= REPEAT_BELOW:
            break
        again = run(job["region"], job["alpha"], job["target"], job["options"])
        if again.times["total"] < result.times["total"]:
            result = again
    arrays = {"vertices": result.vertices, "faces": result.faces}
    if result.samples is not None:
        arrays["samples"] = result.samples
    np.savez(job_path.with_name("result.npz"), **arrays)
    job_path.with_name("result.json").write_text(json.dumps({
        "alpha": result.alpha, "times": result.times, "peak_mb": result.peak_mb,
        "info": result.info}, default=float))


if __name__ == "__main__":
    _child(Path(sys.argv[1]))
