"""Where pds.section's time goes on the bench's STEP parts cut by OCCT's Section, stage
by stage, against its Booleans alone (bench/step_vs_stl.py's "its Booleans"), and a hash
of each section's rings (to check that a change leaves the geometry bit for bit).

    python bench/step_stages.py              # CPU ms, ratios, ring hashes
    python bench/step_stages.py --profile plate_with_holes   # cProfile of 200 sections
    python bench/step_stages.py --stages main plate_with_holes bolt   # stage by stage,
                                             # a revision's reader (main) beside this one
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


STAGES = ["the Section", "its edges chained into loops", "the face labels",
          "the edges read and flattened", "junctions on both curves",
          "the area, the arcs' and B-splines' refinement",
          "the rings, their nesting, the polygons", "region.curves",
          "Region.from_shapely", "the rest", "in all"]


def stages(ref, names, count=150):
    """Each stage's CPU time inside sections (median of ``count``, each section run after
    the Booleans alone, as the bench orders them), for the reader of revision ``ref``
    (``bench/step_before_after.py`` loads it beside this one) and this tree's: a markdown
    table. The stages are the functions of ``sources/step.py`` (and
    ``Region.from_shapely``) timed by wrappers (about 1 µs each)."""
    import functools

    import step_before_after as before_after
    import step_vs_stl as bench_module
    from pds_plugin import region as region_now
    from pds_plugin.sources.planes import checked_on_face, checked_plane

    spent = {}

    def timed(owner, name, label):
        function = getattr(owner, name)

        @functools.wraps(function)
        def wrapper(*args, **kwargs):
            start = time.process_time()
            try:
                return function(*args, **kwargs)
            finally:
                spent[label] = spent.get(label, 0.0) + time.process_time() - start
        setattr(owner, name, wrapper)

    old = before_after.old_reader(ref)
    readers = [(ref, old, sys.modules["pds_plugin._region_before"]), ("now", step, region_now)]
    for _, module, region in readers:
        for name, label in [("_boolean", STAGES[0]), ("_ancestor_labels", STAGES[2]),
                            ("_flattened", STAGES[3]), ("_junctions_refined", STAGES[4]),
                            ("_boundary_curves", STAGES[7])]:
            timed(module, name, label)
        timed(module.StepSolid, "_section_loops", "loops")
        timed(module.StepSolid, "_refined", STAGES[5])
        timed(module.StepSolid, "_polygons", STAGES[6])
        timed(region.Region, "from_shapely", STAGES[8])
    rows = {}
    with tempfile.TemporaryDirectory() as folder:
        for name, shape, origin, normal in cases(folder):
            if name not in names:
                continue
            own = bench_module.own_booleans(shape, origin, normal)
            for label, module, _ in readers:
                def section():
                    o, n = checked_plane(origin, normal)
                    return module.StepSolid(shape).cut(o, n, checked_on_face(None))
                section()
                samples = {}
                for _ in range(count):
                    own()
                    spent.clear()
                    start = time.process_time()
                    section()
                    spent["in all"] = time.process_time() - start
                    spent[STAGES[1]] = spent.pop("loops") - spent[STAGES[0]]
                    spent["the rest"] = spent["in all"] - sum(
                        spent.get(k, 0.0) for k in STAGES[:-2])
                    for key in STAGES:
                        samples.setdefault(key, []).append(spent.get(key, 0.0))
                rows[f"{name}, {label}"] = {k: float(np.median(v)) for k, v in samples.items()}
    print(f"| stage (CPU ms, median of {count}) | " + " | ".join(rows) + " |")
    print("|---" * (len(rows) + 1) + "|")
    for key in STAGES:
        print(f"| {key} | " + " | ".join(f"{1e3 * row[key]:.3f}" for row in rows.values())
              + " |")
    print("| **after the Section** | " + " | ".join(
        f"**{1e3 * (row['in all'] - row[STAGES[0]]):.3f}**" for row in rows.values()) + " |")


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--stages":
        return stages(sys.argv[2], sys.argv[3:])
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
