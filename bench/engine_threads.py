"""Is the default thread count ever slower than one thread? ``mesh_region`` on unit
squares of several sizes, one thread against the default, alternating in one process
(so both see the same machine load), with and without a CPU-bound competitor process.

    python bench/engine_threads.py                     # sizes 1e3 .. 1e6
    python bench/engine_threads.py --sizes 1e4 --repeat 9

Prints the median time of each and the ratio default / one thread (below 1: the
threads help).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

import numpy as np
from shapely.geometry import box

import pds_plugin as pds
from pds_plugin import _parallel


def _median_times(region, alpha, repeat, settings):
    times = {threads: [] for threads in settings}
    pds.mesh_region(region, alpha)                         # warm
    for _ in range(repeat):
        for threads in settings:
            _parallel.set_threads(threads)
            start = time.perf_counter()
            pds.mesh_region(region, alpha)
            times[threads].append(time.perf_counter() - start)
    _parallel.set_threads(None)
    return {threads: statistics.median(values) for threads, values in times.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="*", default=[1e3, 3e3, 1e4, 3e4, 1e5, 1e6])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    default = _parallel.get_threads()
    print(f"default threads {default}, OpenMP {_parallel.openmp}, "
          f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY')}, load {os.getloadavg()[0]:.1f}\n")
    print("| machine | samples | 1 thread s | default s | default / 1 thread |\n|---|---|---|---|---|")
    square = pds.Region.from_shapely(box(0, 0, 1, 1))
    for busy in (False, True):
        competitor = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if busy else None
        try:
            for n in args.sizes:
                repeat = args.repeat if n < 1e6 else max(1, args.repeat // 3)
                t = _median_times(square, float(np.sqrt(0.7 / n)), repeat, (1, default))
                print(f"| {'+1 busy process' if busy else 'as found'} | {n:.0e} | {t[1]:.4f} | "
                      f"{t[default]:.4f} | {t[default] / t[1]:.2f} |", flush=True)
        finally:
            if competitor:
                competitor.kill()


if __name__ == "__main__":
    main()
