"""Where one call of the small default paths goes: stage by stage and kernels against
the rest (issue 21, item 1; docs/engine.md "Issue 21, third pass").

    python bench/small_paths_profile.py                  # every case (~1 min)
    python bench/small_paths_profile.py --only uniform   # one case
    PDS_THREADS=1 python bench/small_paths_profile.py    # one thread

Cases: uniform ``"auto"`` on the angle_block.STL z-mid section (``uniform``), graded
``"auto"`` on the 60 sections of each shared STL part (``featuretype.STL``, ...), the
373-hole drawing of bench/speed_targets.py (``drawing``). Times are CPU time of the
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

sys.path.insert(0, str(Path(__file__).parent))

import pds_plugin as pds                                   # noqa: E402
import pds_plugin.analysis.topology as topology            # noqa: E402,F401 (loaded before wrapping)
import pds_plugin.graded_sampling as graded_sampling       # noqa: E402
import pds_plugin.pipeline as pipeline                     # noqa: E402
import pds_plugin.sampling as sampling                     # noqa: E402

from _environment import machine                           # noqa: E402
from _regions import DATA, stl_section                     # noqa: E402
from speed_targets import PARTS, drawing_region, graded, part_sections, uniform_auto  # noqa: E402

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
    return {k: v for k, v in found.items() if not only or k in only}


def profile(name, regions, mesher, repeat):
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
    print(f"\n{name}: {len(regions)} region(s), {vertices:,.0f} vertices, "
          f"{1e3 * total / n:.2f} ms CPU per call; kernels {1e3 * kernels / n:.2f} ms in "
          f"{sum(KERNEL_CALLS.values()) / n:.0f} calls, rest {1e3 * (total - kernels) / n:.2f} ms\n")
    print("| stage | ms per call | share | calls |\n|---|---|---|---|")
    for label in dict.fromkeys(label for _, _, label in STAGES):
        if STAGE_CALLS[label]:
            print(f"| {label.replace('  ', '· ')} | {1e3 * STAGE_TIME[label] / n:.3f} | "
                  f"{100 * STAGE_TIME[label] / total:.0f} % | {STAGE_CALLS[label] / n:.1f} |")
    print("\n| kernel | ms per call | calls |\n|---|---|---|")
    for label, seconds in KERNEL_TIME.most_common(8):
        print(f"| {label} | {1e3 * seconds / n:.3f} | {KERNEL_CALLS[label] / n:.1f} |")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--only", action="append", help="this case only (repeatable)")
    parser.add_argument("--repeat", type=int, default=3, help="timed calls of every region")
    args = parser.parse_args(argv)
    start = machine()
    print(f"{start['cpu']}, {start['cores']} cores, load {start['load'][0]:.1f}, "
          f"commit {start['commit']}")
    found = cases(args.only)
    instrument()
    for name, (regions, mesher) in found.items():
        repeat = args.repeat * (10 if name == "uniform" else 1)
        profile(name, regions, mesher, repeat)


if __name__ == "__main__":
    main()
