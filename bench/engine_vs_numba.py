"""One-off timing of the compiled kernels against the numba kernels they replaced, and
against Triangle ``pq30`` at an equal vertex count, taken in turns in one process so all
three see the same machine load.

The numba kernels are read from git (``--numba-commit``) and swapped in for the compiled
ones between runs; needs numba and triangle installed (``pip install numba triangle``).

    python bench/engine_vs_numba.py                 # squares 1e4, 1e5, 1e6 and auto
    python bench/engine_vs_numba.py --sizes 1e4 --repeat 9
    python bench/engine_vs_numba.py --no-numba      # compiled kernels and Triangle only

Prints median wall and CPU times of ``mesh_region`` (and the wall time of
``certificate()``) for each engine with one thread and with the default count, and the
ratios to Triangle. On a loaded machine the CPU time of a one-thread run is the better
estimate of its quiet-machine wall time (the CPU time of a threaded run adds up its
threads).
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from shapely.geometry import box

import pds_plugin as pds
from pds_plugin import _parallel

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
from _regions import DATA, stl_section  # noqa: E402
from _runners import _area_for_vertices, _pslg  # noqa: E402
from _swap import KERNELS, use_kernels  # noqa: E402


def _load(folder: Path) -> dict:
    modules = {}
    for name in KERNELS:
        spec = importlib.util.spec_from_file_location(f"numba_{name}", folder / f"{name}.py")
        modules[name] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(modules[name])
    return modules


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="*", default=[1e4, 1e5, 1e6])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--numba-commit", default="16c20ab")
    parser.add_argument("--no-numba", action="store_true",
                        help="time the compiled kernels and Triangle only (numba not needed)")
    args = parser.parse_args()
    import triangle

    pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), "auto", max_alpha=0.2).certificate()
    compiled = {name: importlib.import_module(f"pds_plugin.{name}") for name in KERNELS}
    current = compiled
    with tempfile.TemporaryDirectory(prefix="pds_numba_") as folder:
        if not args.no_numba:
            for name in KERNELS:
                (Path(folder) / f"{name}.py").write_text(subprocess.run(
                    ["git", "show", f"{args.numba_commit}:src/pds_plugin/{name}.py"], cwd=ROOT,
                    check=True, capture_output=True, text=True).stdout)
            numba_kernels = _load(Path(folder))
        cores = _parallel.get_threads()

        def engine(kernels, threads, set_threads):
            def run(region, alpha):
                nonlocal current
                use_kernels(current, kernels)
                current = kernels
                set_threads(threads)
                start, cpu = time.perf_counter(), time.process_time()
                mesh = pds.mesh_region(region, alpha)
                meshed, cpu = time.perf_counter(), time.process_time() - cpu
                mesh.certificate()
                return meshed - start, cpu, time.perf_counter() - meshed, len(mesh.vertices)
            return run

        engines = {"compiled, 1 thread": engine(compiled, 1, _parallel.set_threads),
                   f"compiled, {cores} threads": engine(compiled, cores, _parallel.set_threads)}
        if not args.no_numba:
            import numba
            engines = {"numba, 1 thread": engine(numba_kernels, 1, numba.set_num_threads),
                       f"numba, {cores} threads": engine(numba_kernels, cores,
                                                         numba.set_num_threads), **engines}
        square = pds.Region.from_shapely(box(0, 0, 1, 1))
        cases = [(f"unit square {n:.0e}", square, float(np.sqrt(0.7 / n))) for n in args.sizes]
        if (DATA / "featuretype.STL").exists():
            cases.append(("featuretype.STL z-mid, alpha='auto'", stl_section("featuretype.STL")(),
                          "auto"))
        print(f"load average {' '.join(f'{v:.1f}' for v in os.getloadavg())}\n")
        print("| case | engine | mesh_region wall s | CPU s | certificate wall s | "
              "wall / Triangle | CPU / Triangle |\n|---|---|---|---|---|---|---|")
        for label, region, alpha in cases:
            for run in engines.values():
                run(region, alpha)                       # warm: numba compiles here
            target = engines["compiled, 1 thread"](region, alpha)[3]
            pslg = _pslg(region)
            area = _area_for_vertices(pslg, "pq30", target, region.area)
            times = {name: [] for name in [*engines, "Triangle pq30"]}
            repeat = args.repeat if "1e+06" not in label else max(1, args.repeat // 2)
            for _ in range(repeat):
                for name, run in engines.items():
                    times[name].append(run(region, alpha)[:3])
                start, cpu = time.perf_counter(), time.process_time()
                triangle.triangulate(pslg, f"pq30a{area:.20f}Q")
                times["Triangle pq30"].append((time.perf_counter() - start,
                                               time.process_time() - cpu, 0.0))
            wall0, cpu0 = (statistics.median(t[k] for t in times["Triangle pq30"]) for k in (0, 1))
            for name, values in times.items():
                wall, cpu, cert = (statistics.median(t[k] for t in values) for k in range(3))
                print(f"| {label} ({target} vertices) | {name} | {wall:.4f} | {cpu:.4f} | "
                      f"{cert:.4f} | {wall / wall0:.2f} | {cpu / cpu0:.2f} |", flush=True)
        use_kernels(current, compiled)
        _parallel.set_threads(None)


if __name__ == "__main__":
    main()
