"""Where pds.section's time goes on the bench's STEP parts cut by OCCT's Section, stage
by stage, against its Booleans alone (bench/step_vs_stl.py's "its Booleans"), and a hash
of each section's rings (to check that a change leaves the geometry bit for bit).

    python bench/step_stages.py              # per-stage CPU ms, ratios, ring hashes
    python bench/step_stages.py --profile plate_with_holes   # cProfile of 200 sections
"""

from __future__ import annotations

import cProfile
import hashlib
import pstats
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import pds_plugin as pds
from pds_plugin.sources import step

sys.path.insert(0, str(Path(__file__).resolve().parent))
import step_vs_stl as bench  # noqa: E402


def cases(folder):
    """The bench's parts (step_vs_stl.cases), loaded: (name, shape, origin, normal)."""
    for name, path, _, _, origin, normal in bench.cases(Path(folder)):
        yield name, step.load(path), origin, normal


def ring_hash(region) -> str:
    digest = hashlib.sha256()
    for ring in region.rings:
        digest.update(np.ascontiguousarray(ring, dtype=float).tobytes())
        digest.update(b"|")
    return digest.hexdigest()[:16]


def best(call, rounds=30, budget=3.0):
    times, spent = [], 0.0
    while len(times) < rounds and spent < budget:
        start = time.process_time()
        call()
        t = time.process_time() - start
        times.append(t)
        spent += t
    return min(times)


def interleaved(*calls, rounds=50, budget=10.0):
    """The best CPU time of each call, the calls taking turns (as bench/step_vs_stl.py
    times them: each runs after another's OCCT work, not after its own)."""
    times = [[] for _ in calls]
    while len(times[0]) < rounds and sum(map(sum, times)) < budget:
        for call, spent in zip(calls, times):
            start = time.process_time()
            call()
            spent.append(time.process_time() - start)
    return [min(spent) for spent in times]


def main():
    profile = sys.argv[2] if len(sys.argv) > 2 and sys.argv[1] == "--profile" else None
    with tempfile.TemporaryDirectory() as folder:
        for name, shape, origin, normal in cases(folder):
            if profile is not None and name != profile:
                continue
            region = pds.section(shape, origin, normal)
            if profile is not None:
                profiler = cProfile.Profile()
                profiler.enable()
                for _ in range(200):
                    pds.section(shape, origin, normal)
                profiler.disable()
                pstats.Stats(profiler).sort_stats("tottime").print_stats(45)
                pstats.Stats(profiler).sort_stats("cumtime").print_stats(45)
                return
            own = bench.own_booleans(shape, origin, normal)
            ours = lambda: pds.section(shape, origin, normal)  # noqa: E731
            b, s = interleaved(own, ours)
            print(f"{name:32s} booleans {1e3 * b:7.2f} ms  section {1e3 * s:7.2f} ms  "
                  f"ratio {s / b:5.2f}  after {1e3 * (s - b):6.2f} ms  "
                  f"rings {ring_hash(region)}  area {region.area:.12g}", flush=True)


if __name__ == "__main__":
    main()
