"""Where one call of the small default paths goes: stage by stage and kernels against
the rest (issue 21, item 1; docs/engine.md "Issue 21, third pass").

    python bench/small_paths_profile.py                  # every case (~1 min)
    python bench/small_paths_profile.py --only uniform   # one case
    python bench/small_paths_profile.py --write          # into docs/benchmarks.md
    PDS_THREADS=1 python bench/small_paths_profile.py    # one thread

Cases: uniform ``"auto"`` on the angle_block.STL z-mid section (``uniform``), graded
``"auto"`` on the 60 sections of each shared STL part (``featuretype.STL``, ...), the
373-hole drawing of bench/speed_targets.py (``drawing``), the uniform unit square of
100,000 vertices (``square``). Times are CPU time of the
process (``time.process_time``: the shared machine's load disturbs it far less than
wall time) per call, warm, averaged over ``--repeat`` calls of every region. Stages are
timed by wrapping the pipeline's calls (nested stages are indented and included in
their parent); kernels by wrapping every public function of the kernel modules (a
kernel called from another counts once). "rest" is the call's time outside the
kernels: Python, numpy, shapely and scipy between them.
"""

from __future__ import annotations

import argparse
import importlib
import sys
import warnings
from collections import Counter
from pathlib import Path
from time import process_time

from shapely.geometry import box

sys.path.insert(0, str(Path(__file__).parent))

import pds_plugin as pds                                   # noqa: E402
import pds_plugin.analysis.topology as topology            # noqa: E402,F401 (loaded before wrapping)
import pds_plugin.graded_sampling as graded_sampling       # noqa: E402
import pds_plugin.pipeline as pipeline                     # noqa: E402
import pds_plugin.sampling as sampling                     # noqa: E402

from _environment import machine                           # noqa: E402
from _regions import DATA, stl_section                     # noqa: E402
from _sections import write_section                        # noqa: E402
from speed_targets import (PARTS, drawing_region, graded, part_sections,  # noqa: E402
                           square_alpha, uniform_auto)

KERNEL_MODULES = tuple(sorted(path.name.split(".")[0] for path in
                              Path(pds.__file__).parent.glob("_*_kernels.pyx")))
STAGE_TIME: Counter = Counter()
STAGE_CALLS: Counter = Counter()
KERNEL_TIME: Counter = Counter()
KERNEL_CALLS: Counter = Counter()
_inside_kernel = [False]

STAGES = [  # (owner, attribute, label): the label's indent is its nesting
    (pipeline, "feature_size", "feature size (alpha)"),
    (pipeline, "radius_field", "radius field"),
    (pipeline, "poisson_disc", "uniform sampling"),
    (sampling._Sampler, "__init__", "  grid, cell status"),
    (sampling._Sampler, "add_conforming_boundary", "  boundary samples, chords"),
    (sampling._Sampler, "add_interior", "  interior: darts, refinement"),
    (pipeline, "graded_poisson_disc", "graded sampling"),
    (graded_sampling._GradedSampler, "add_boundary", "  boundary samples"),
    (graded_sampling, "_tau_rings", "    dense rings, τ"),
    (graded_sampling, "_unhidden", "    chord ends onto reflex vertices"),
    (graded_sampling._GradedSampler, "_place_boundary", "    chords, bins, guards"),
    (graded_sampling._GradedSampler, "add_interior", "  interior: leaves, darts, refinement"),
    (graded_sampling._GradedSampler, "_leaves", "    quadtree leaves"),
    (graded_sampling._GradedSampler, "_open", "    coverage tests of the passes"),
    (graded_sampling._GradedSampler, "_throw", "    darts (refusal, r, insertion)"),
    (pipeline, "solid_alpha_complex", "complex"),
    (pipeline, "graded_alpha_complex", "complex"),
    (pipeline, "topology_report", "topology check"),
]


def _stage(function, label):
    def wrapper(*args, **kwargs):
        start = process_time()
        try:
            return function(*args, **kwargs)
        finally:
            STAGE_TIME[label] += process_time() - start
            STAGE_CALLS[label] += 1
    return wrapper


def _kernel(function, label):
    def wrapper(*args, **kwargs):
        if _inside_kernel[0]:
            return function(*args, **kwargs)
        _inside_kernel[0] = True
        start = process_time()
        try:
            return function(*args, **kwargs)
        finally:
            KERNEL_TIME[label] += process_time() - start
            KERNEL_CALLS[label] += 1
            _inside_kernel[0] = False
    return wrapper


def instrument():
    """Wrap the stages and every kernel function (kernel modules are called through
    their module attribute, so replacing the attribute reaches every caller)."""
    for owner, name, label in STAGES:
        setattr(owner, name, _stage(getattr(owner, name), label))
    for module_name in KERNEL_MODULES:
        module = importlib.import_module(f"pds_plugin.{module_name}")
        for name in dir(module):
            function = getattr(module, name)
            if (not name.startswith("_") and callable(function)
                    and not isinstance(function, type)):
                setattr(module, name, _kernel(function, f"{module_name[1:]}.{name}"))


def cases(only):
    found = {}
    if (DATA / "angle_block.STL").exists():
        found["uniform"] = ([stl_section("angle_block.STL")()], uniform_auto)
    for part in PARTS:
        regions = part_sections(part)
        if regions:
            found[part] = (regions, graded)
    found["drawing"] = (None, graded)          # built on demand: ezdxf, ~1 s
    alpha = square_alpha(100_000)
    found["square"] = ([pds.Region.from_shapely(box(0, 0, 1, 1))],
                       lambda region: pds.mesh_region(region, alpha))
    return {k: v for k, v in found.items() if not only or k in only}


def profile(name, regions, mesher, repeat) -> list[str]:
    """The lines (markdown) of one case's profile: the call's time, its stages, its
    heaviest kernels."""
    if regions is None:
        regions = [drawing_region()]
        repeat = 1
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        meshes = [mesher(region) for region in regions]
        for counter in (STAGE_TIME, STAGE_CALLS, KERNEL_TIME, KERNEL_CALLS):
            counter.clear()
        start = process_time()
        for _ in range(repeat):
            for region in regions:
                mesher(region)
        total = process_time() - start
    n = repeat * len(regions)
    vertices = sum(len(mesh.vertices) for mesh in meshes) / len(meshes)
    kernels = sum(KERNEL_TIME.values())
    lines = [f"**{name}**: {len(regions)} region(s), {vertices:,.0f} vertices, "
             f"{1e3 * total / n:.2f} ms CPU per call ({1e6 * total / n / vertices:.1f} µs "
             f"per vertex); kernels {1e3 * kernels / n:.2f} ms in "
             f"{sum(KERNEL_CALLS.values()) / n:.0f} calls, rest {1e3 * (total - kernels) / n:.2f} ms",
             "", "| stage | ms per call | share | calls |", "|---|---|---|---|"]
    for label in dict.fromkeys(label for _, _, label in STAGES):
        if STAGE_CALLS[label]:
            lines.append(f"| {label.replace('  ', '· ')} | {1e3 * STAGE_TIME[label] / n:.3f} | "
                         f"{100 * STAGE_TIME[label] / total:.0f} % | "
                         f"{STAGE_CALLS[label] / n:.1f} |")
    lines += ["", "| kernel | ms per call | calls |", "|---|---|---|"]
    for label, seconds in KERNEL_TIME.most_common(8):
        lines.append(f"| {label} | {1e3 * seconds / n:.3f} | {KERNEL_CALLS[label] / n:.1f} |")
    return lines + [""]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--only", action="append", help="this case only (repeatable)")
    parser.add_argument("--repeat", type=int, default=3, help="timed calls of every region")
    parser.add_argument("--write", action="store_true",
                        help="write the section 'small paths profile' of docs/benchmarks.md")
    args = parser.parse_args(argv)
    start = machine()
    head = (f"{start['cpu']}, {start['cores']} cores, load {start['load'][0]:.1f}, "
            f"commit {start['commit']}")
    print(head)
    found = cases(args.only)
    instrument()
    lines = []
    for name, (regions, mesher) in found.items():
        repeat = args.repeat * (10 if name == "uniform" else 1)
        case = profile(name, regions, mesher, repeat)
        print("\n" + "\n".join(case), flush=True)
        lines += case
    if args.write:
        write_section("small paths profile", "Where the small paths' time goes "
                      "(bench/small_paths_profile.py, issue 21)",
                      f"on {start['date']} ({head}). CPU time per call, warm; stages nest "
                      "(indented ones are part of the stage above); kernels are the compiled "
                      "calls, \"rest\" is Python, numpy, shapely and scipy between them. It "
                      "explains the time misses of the speed targets: docs/engine.md, "
                      "\"Issue 21: the misses\".", lines)
        print("wrote the section 'small paths profile' of docs/benchmarks.md")


if __name__ == "__main__":
    main()
