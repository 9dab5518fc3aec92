"""Benchmark pds_plugin against the meshers users pick today, in one command.

    python bench/peers.py                 # full run: squares of 10k, 100k, 1M; ~35 min
    python bench/peers.py --quick         # small sizes only, a smoke run (~10 min)

Runs pds_plugin, scipy's PoissonDisk pipeline, MeshLab (pymeshlab), Shewchuk's Triangle
and gmsh on the same regions in one run, each peer in a fresh process under a time
limit, measures every mesh the same way, checks the targets of issues 2, 5 and 13, and writes
docs/benchmarks.md with docs/bench_time_vs_vertices.png and docs/bench_aspect_ratio.png.
Peers that are not installed get a row saying so (``pip install -e ".[bench]"``).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import shlex
import sys
from pathlib import Path

from _auto import auto_path
from _environment import machine, startup, versions
from _isolate import Outcome, run_isolated
from _plots import aspect_tails, time_vs_vertices
from _regions import KEYS, cases
from _report import write
from _rows import collect
from _runners import PEERS, Options
from _targets import evaluate

ROOT = Path(__file__).resolve().parents[1]
FULL = {"sizes": [10_000, 100_000, 1_000_000], "region_size": 50_000, "scipy_points": 10_000}
QUICK = {"sizes": [2_000, 10_000], "region_size": 5_000, "scipy_points": 2_000}


def parse(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help=f"small sizes only (squares {QUICK['sizes']}, other regions "
                             f"{QUICK['region_size']} samples): a smoke run")
    parser.add_argument("--sizes", type=_counts, help="sample counts of the unit squares, "
                        f"comma-separated (default {','.join(map(str, FULL['sizes']))})")
    parser.add_argument("--region-size", type=int,
                        help="samples aimed at on the other regions "
                             f"(default {FULL['region_size']})")
    parser.add_argument("--regions", type=_names(KEYS), default=list(KEYS),
                        help=f"comma-separated subset of {','.join(KEYS)}")
    parser.add_argument("--peers", type=_names(PEERS), default=list(PEERS),
                        help=f"comma-separated subset of {','.join(PEERS)} (pds always runs)")
    parser.add_argument("--timeout", type=float, default=120.0,
                        help="seconds allowed to each peer on each region (default 120)")
    parser.add_argument("--scipy-points", type=int,
                        help="above this many samples scipy's PoissonDisk is measured at a "
                             f"coarser alpha and extrapolated (default {FULL['scipy_points']})")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-startup", action="store_true",
                        help="skip the import, first-call and alpha='auto' measurements")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "benchmarks.md",
                        help="the report to write; the figures go next to it "
                             "(default docs/benchmarks.md)")
    args = parser.parse_args(argv)
    defaults = QUICK if args.quick else FULL
    for name, value in defaults.items():
        if getattr(args, name) is None:
            setattr(args, name, value)
    if args.timeout <= 0:
        parser.error("--timeout must be positive")
    args.peers = ["pds", *(key for key in args.peers if key != "pds")]
    return args


def main(argv=None) -> Path:
    """Run the benchmark and write the report; returns the report's path."""
    args = parse(argv)
    command = shlex.join(["python", "bench/peers.py", *(sys.argv[1:] if argv is None else argv)])
    start = machine()
    print(f"{start['cpu']}, {start['cores']} cores, load {start['load']}", flush=True)
    measured_startup = None if args.no_startup else startup()
    auto = None if args.no_startup else auto_path()
    options = Options(seed=args.seed, scipy_points=args.scipy_points)
    found, missing = cases(args.sizes, args.region_size, args.regions)
    rows, loads = [], []
    for case in found:
        target = round(case.expected)
        for key in args.peers:
            outcome = _run(key, case, target, options, args.timeout)
            if key == "pds" and outcome.status == "ok":
                target = len(outcome.vertices)
            row = collect(case, PEERS[key], outcome, target)
            rows.append(row)
            loads.append(os.getloadavg()[0])
            print(f"{case.name:55s} {PEERS[key].label:48s} {row.status:8s} "
                  f"{row.time:9.3f} s {row.message}", flush=True)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    figures = [figure for figure in (
        time_vs_vertices(rows, args.out.with_name("bench_time_vs_vertices.png")),
        aspect_tails(rows, _aspect_cases(found), args.out.with_name("bench_aspect_ratio.png")))
        if figure is not None]
    report = write(args.out, command=command, machine=start, load_end=os.getloadavg(),
                   load_peak=max(loads, default=float("nan")),
                   versions=versions(), startup=measured_startup,
                   targets=evaluate(rows, measured_startup, args.timeout, auto), rows=rows,
                   missing=missing, figures=figures, timeout=args.timeout)
    print(f"wrote {report}", flush=True)
    return report


def _run(key, case, target, options, timeout) -> Outcome:
    peer = PEERS[key]
    absent = [name for name in peer.needs if importlib.util.find_spec(name) is None]
    if absent:
        return Outcome("skipped", f"{', '.join(absent)} not installed ({peer.install})")
    # pds_plugin's child meshes, certifies, then samples and meshes again (its parts)
    limit = 3 * timeout if peer.ours else timeout
    return run_isolated(key, case.region, case.alpha, target, options, limit, peer.env)


def _aspect_cases(found) -> list[str]:
    """The aspect-ratio figure's panels: the middle unit square and the CAD section."""
    squares = [case.name for case in found if case.key == "square"]
    chosen = squares[len(squares) // 2:][:1]
    return chosen + [case.name for case in found if case.key == "cad-plate"]


def _counts(text: str) -> list[int]:
    try:
        counts = [int(float(part)) for part in text.split(",") if part]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated counts, got {text!r}") from None
    if not counts or min(counts) < 10:
        raise argparse.ArgumentTypeError(f"every size must be at least 10, got {text!r}")
    return counts


def _names(choices):
    def parse_names(text: str) -> list[str]:
        names = [part for part in text.split(",") if part]
        unknown = [name for name in names if name not in choices]
        if unknown:
            raise argparse.ArgumentTypeError(f"unknown {unknown}; choose from {','.join(choices)}")
        return names
    return parse_names


if __name__ == "__main__":
    main()
