"""The graded sampler alone, on the inputs the default paths give it (docs/engine.md,
"Eighth pass"): CPU time per call, darts thrown, boxes tested and split per interior
sample, and a digest of the samples (to compare builds and thread counts bit for bit).

    python bench/graded_darts.py                  # drawing + every 3rd section of 3 parts
    python bench/graded_darts.py --repeat 5 --only drawing
    python bench/graded_darts.py --seeds 10     # sample counts over 10 seeds per call
"""

from __future__ import annotations

import argparse
import hashlib
import sys
import warnings
from pathlib import Path
from time import process_time

sys.path.insert(0, str(Path(__file__).parent))

import pds_plugin.graded_sampling as gs                    # noqa: E402
import pds_plugin.pipeline as pipeline                     # noqa: E402

from speed_targets import PARTS, drawing_region, graded, part_sections  # noqa: E402

CAPTURED = []


def capture(regions):
    """The (region, field, seed, kwargs) of each graded sampling the pipeline makes."""
    real = pipeline.graded_poisson_disc

    def spy(region, field, seed=0, **kw):
        CAPTURED.append((region, field, seed, kw))
        return real(region, field, seed, **kw)
    pipeline.graded_poisson_disc = spy
    try:
        for region in regions:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                graded(region)
    finally:
        pipeline.graded_poisson_disc = real
    out = list(CAPTURED)
    CAPTURED.clear()
    return out


COUNT = {"darts": 0, "tests": 0, "on": False}


def counted():
    real_throw, real_open = gs._GradedSampler._throw, gs._GradedSampler._open

    def throw(self, boxes, rng, *args, **kw):
        COUNT["darts"] += COUNT["on"] * len(boxes[0])
        return real_throw(self, boxes, rng, *args, **kw)

    def open_(self, boxes, since=0):
        COUNT["tests"] += COUNT["on"] * len(boxes[0])
        return real_open(self, boxes, since)
    gs._GradedSampler._throw, gs._GradedSampler._open = throw, open_


def run(cases, repeat):
    digest = hashlib.sha256()
    cpu, interior, samples = 0.0, 0, 0
    for region, field, seed, kw in cases:               # warm
        gs.graded_poisson_disc(region, field, seed, **kw)
    for _ in range(repeat):
        t = process_time()
        for region, field, seed, kw in cases:
            gs.graded_poisson_disc(region, field, seed, **kw)
        cpu += process_time() - t
    COUNT["on"] = True
    COUNT.update(darts=0, tests=0)
    for region, field, seed, kw in cases:
        s = gs.graded_poisson_disc(region, field, seed, **kw)
        digest.update(s.points.tobytes())
        interior += int((~s.on_boundary).sum())
        samples += len(s.points)
    COUNT["on"] = False
    return cpu / repeat / len(cases), interior, samples, digest.hexdigest()[:16]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--only", default=None)
    parser.add_argument("--every", type=int, default=3)
    parser.add_argument("--seeds", type=int, default=0,
                        help="instead: the samples summed over this many seeds per call")
    args = parser.parse_args()
    counted()
    groups = {"drawing": [drawing_region()]}
    for part in PARTS:
        groups[part] = part_sections(part)[::args.every]
    for name, regions in groups.items():
        if args.only and args.only != name:
            continue
        cases = capture(regions)
        if args.seeds:
            total = sum(len(gs.graded_poisson_disc(region, field, seed, **kw).points)
                        for region, field, _, kw in cases for seed in range(args.seeds))
            print(f"{name:18s} calls {len(cases):3d} seeds {args.seeds}: samples {total}",
                  flush=True)
            continue
        cpu, interior, samples, digest = run(cases, args.repeat)
        print(f"{name:18s} calls {len(cases):3d} cpu/call {1e3 * cpu:8.2f} ms  samples "
              f"{samples:7d} interior {interior:7d}  darts/int "
              f"{COUNT['darts'] / max(interior, 1):5.2f}  pass tests/int "
              f"{COUNT['tests'] / max(interior, 1):5.2f}  digest {digest}", flush=True)


if __name__ == "__main__":
    main()
