"""What conformity costs the meshing (issue 9 item 6: at most 15 % of ``mesh_region``'s
time on the 1M square and the benchmark's CAD regions), region by region.

``mesh_region(..., conforming=False)`` (the paper's construction) and
``mesh_region(..., conforming=True)`` (the default) are run interleaved, ``--repeats``
times each after one warm-up run of each, the first of the pair alternating, so both see
the same machine load. The table gives the median and the minimum of wall time and of
CPU time (``time.process_time``: all threads) and the ratios conforming / pure of the
medians and of the minimums. On a busy machine the wall times swing; the CPU ratios much
less, but they do not see a step that loses a thread (compare the CPU / wall column,
about the threads in use).

    python bench/conforming_overhead.py                       # 1M square + CAD regions, 5 repeats
    python bench/conforming_overhead.py --repeats 2 --square-sizes 1e5
    python bench/conforming_overhead.py --stages              # + sampling and complex apart

``--stages`` also times ``poisson_disc`` and ``solid_alpha_complex`` apart (once each,
same seed): where a step of the conforming path runs on fewer threads, its CPU / wall
falls towards 1.

Regions (those of bench/certificate_time.py): unit squares (``--square-sizes``), the
perforated plate (``plate``, not by default) and bench/_regions.py's others at
``--region-size`` samples (the shared CAD parts' sections when ../shared/data is present).
"""

from __future__ import annotations

import argparse
import os
import statistics
import warnings

import pds_plugin as pds
from pds_plugin import _parallel
from _environment import machine
from _regions import FIXED
from certificate_time import _timed, regions

SEED = 0


def interleaved(region, alpha, repeats):
    """{conforming: [(wall, cpu), ...]} of ``repeats`` runs each, pure and conforming
    alternating (the first of each pair alternating too), after a warm-up of each; and
    the sample counts."""
    samples = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for conforming in (False, True):
            samples[conforming] = len(pds.mesh_region(region, alpha, seed=SEED,
                                                      conforming=conforming).vertices)
        times = {False: [], True: []}
        for r in range(repeats):
            for conforming in ((False, True) if r % 2 == 0 else (True, False)):
                times[conforming].append(_timed(lambda: pds.mesh_region(
                    region, alpha, seed=SEED, conforming=conforming)))
    return times, samples


def stages(region, alpha):
    """Wall and CPU seconds of the sampling and the complex, pure and conforming."""
    found = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for conforming in (False, True):
            holder = {}
            found[(conforming, "poisson_disc")] = _timed(lambda: holder.setdefault(
                "samples", pds.poisson_disc(region, alpha, seed=SEED, conforming=conforming)))
            samples = holder["samples"]
            found[(conforming, "solid_alpha_complex")] = _timed(lambda: pds.solid_alpha_complex(
                samples.points, alpha, boundary=samples.rings))
    return found


def row(name, times, samples) -> str:
    """One line of the table: medians and minimums, and their ratios."""
    (pure_wall, pure_cpu), (conf_wall, conf_cpu) = (list(zip(*times[c])) for c in (False, True))
    med = [statistics.median(v) for v in (pure_wall, conf_wall, pure_cpu, conf_cpu)]
    low = [min(v) for v in (pure_wall, conf_wall, pure_cpu, conf_cpu)]
    return (f"| {name} | {samples[False]:,} / {samples[True]:,} | "
            f"{med[0]:.3f} / {low[0]:.3f} | {med[1]:.3f} / {low[1]:.3f} | "
            f"**{med[1] / med[0]:.2f}** / {low[1] / low[0]:.2f} | "
            f"{med[2]:.3f} / {low[2]:.3f} | {med[3]:.3f} / {low[3]:.3f} | "
            f"{med[3] / med[2]:.2f} / {low[3] / low[2]:.2f} | "
            f"{med[2] / med[0]:.2f} / {med[3] / med[1]:.2f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--regions", default="square," + ",".join(FIXED))
    parser.add_argument("--square-sizes", type=float, nargs="*", default=[1e6])
    parser.add_argument("--region-size", type=float, default=5e4)
    parser.add_argument("--plate-size", type=float, default=1e5,
                        help="samples of the perforated plate (region 'plate')")
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--stages", action="store_true")
    args = parser.parse_args()
    about = machine()
    print(f"commit {about['commit']}, {about['cpu']}, {about['cores']} cores, "
          f"{_parallel.get_threads()} threads, load {os.getloadavg()[0]:.1f} at the start, "
          f"{args.repeats} repeats each, seed {SEED}\n")
    print("| region | samples pure / conforming | pure wall s, median / min | "
          "conforming wall s, median / min | wall ratio, median / min | "
          "pure CPU s, median / min | conforming CPU s, median / min | "
          "CPU ratio, median / min | CPU / wall, pure / conforming |")
    print("|---|---|---|---|---|---|---|---|---|")
    found = regions(args)
    for name, region, alpha in found:
        print(row(name, *interleaved(region, alpha, args.repeats)), flush=True)
    print(f"\nload {os.getloadavg()[0]:.1f} at the end")
    if args.stages:
        print("\n| region | step | pure wall s | pure CPU / wall | conforming wall s | "
              "conforming CPU / wall | wall ratio |")
        print("|---|---|---|---|---|---|---|")
        for name, region, alpha in found:
            times = stages(region, alpha)
            for step in ("poisson_disc", "solid_alpha_complex"):
                (pw, pc), (cw, cc) = times[(False, step)], times[(True, step)]
                print(f"| {name} | {step} | {pw:.3f} | {pc / pw:.2f} | {cw:.3f} | "
                      f"{cc / cw:.2f} | {cw / pw:.2f} |", flush=True)


if __name__ == "__main__":
    main()
