"""Where the time of ``mesh_region`` + ``certificate()`` goes, kernel by kernel.

Every public function of the kernel modules is wrapped in a timer; the rest of each
stage (numpy glue, Python loops) is what remains of the stage's wall time. Run it warm (the script meshes each case once before timing):

    python bench/engine_profile.py                 # 10k, 100k, 1M squares and auto
    python bench/engine_profile.py --sizes 1e4     # just one size

Prints one table per case: seconds and share of the wall time.
"""

from __future__ import annotations

import argparse
import importlib
import time
from collections import defaultdict
from pathlib import Path

import numpy as np
from shapely.geometry import box

import pds_plugin as pds
from pds_plugin import complex, sampling
from _swap import KERNELS, replace_everywhere

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
TOTALS: dict[str, float] = defaultdict(float)


def _timed(name, function):
    def wrapper(*args, **kwargs):
        start = time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            TOTALS[name] += time.perf_counter() - start
    return wrapper


def _instrument():
    """Wrap every kernel function (the visibility kernels' too) and the two stages in
    timers, wherever pds_plugin calls them."""
    square = pds.Region.from_shapely(box(0, 0, 1, 1))
    pds.mesh_region(square, "auto", max_alpha=0.2).certificate()     # load every module
    for module in (importlib.import_module(f"pds_plugin.{name}")
                   for name in KERNELS + ("_visibility_kernels",)):
        for name in dir(module):
            function = getattr(module, name)
            if name.startswith("_") or not callable(function) or isinstance(function, type):
                continue
            replace_everywhere(function, _timed(f"{module.__name__.split('.')[-1]}.{name}",
                                                function))
    replace_everywhere(sampling.poisson_disc,
                       _timed("poisson_disc (total)", sampling.poisson_disc))
    replace_everywhere(complex.solid_alpha_complex,
                       _timed("solid_alpha_complex (total)", complex.solid_alpha_complex))


def _square_alpha(n):
    return float(np.sqrt(0.7 / n))


def profile(label, run, repeat):
    run()                                   # warm: compile or load kernels, fill caches
    best = None
    for _ in range(repeat):
        TOTALS.clear()
        start = time.perf_counter()
        mesh = run()
        mesh_time = time.perf_counter() - start
        TOTALS["mesh_region (total)"] = mesh_time
        start = time.perf_counter()
        mesh.certificate()
        TOTALS["certificate (total)"] = time.perf_counter() - start
        if best is None or mesh_time < best[0]:
            best = mesh_time, dict(TOTALS), len(mesh.vertices)
    mesh_time, totals, n = best
    print(f"\n## {label}: {n} vertices, mesh_region {mesh_time:.3f} s (best of {repeat})\n")
    print("| part | s | % of mesh_region |\n|---|---|---|")
    for name, seconds in sorted(totals.items(), key=lambda item: -item[1]):
        print(f"| {name} | {seconds:.4f} | {100 * seconds / mesh_time:.0f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="*", default=[1e4, 1e5, 1e6])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-auto", action="store_true")
    args = parser.parse_args()
    _instrument()
    square = pds.Region.from_shapely(box(0, 0, 1, 1))
    for n in args.sizes:
        profile(f"unit square {n:.0e}", lambda n=n: pds.mesh_region(square, _square_alpha(n)),
                args.repeat if n < 1e6 else 1)
    stl = DATA / "featuretype.STL"
    if not args.no_auto and stl.exists():
        import trimesh
        lo, hi = trimesh.load_mesh(stl).bounds
        region = pds.section(stl, plane_origin=(lo + hi) / 2, plane_normal=(0.0, 0.0, 1.0))
        profile(f"featuretype.STL mid section, {sum(len(r) for r in region.rings)} boundary "
                "vertices, alpha='auto'", lambda: pds.mesh_region(region, "auto"), 5)


if __name__ == "__main__":
    main()
