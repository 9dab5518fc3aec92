"""The targets of issues 2, 5 and 13, checked against the rows of one run.

Speed targets are ratios on the largest unit-square case of the run (1M samples in the
full run); a peer that timed out counts as taking at least the time limit, which
gives a lower bound on the ratio. Issue 13's are checked on every size and region of
the run, against Triangle pq30 at the same vertex count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from _rows import Row, sampling_rate

ASPECT_TOL = 1e-9


@dataclass(frozen=True)
class Target:
    name: str
    goal: str
    measured: str
    holds: bool | None        # None: could not be measured in this run


def evaluate(rows: list[Row], startup: dict | None, timeout: float,
             auto: dict | None = None) -> list[Target]:
    """Every target, in the order of the issues; ``auto`` is ``_auto.auto_path()``'s
    measurement."""
    by = {(row.case.name, row.peer.key): row for row in rows}
    squares = [row.case for row in rows if row.case.key == "square"]
    big = max(squares, key=lambda case: case.expected, default=None)
    targets = []
    if big is not None:
        pds = by.get((big.name, "pds"))
        at = f"on the {big.name}"
        for key, factor, goal in (
                ("triangle-pq30", 1, "end to end no slower than Triangle pq30"),
                ("meshlab", 10, "≥ 10× faster than the MeshLab pipeline"),
                ("scipy", 300, "≥ 300× faster than scipy's PoissonDisk pipeline")):
            target = _speed(goal, at, pds, by.get((big.name, key)), factor, timeout)
            single = by.get((big.name, "pds-1thread"))
            if target.holds is not None and single is not None and single.ok:
                other = by[(big.name, key)]
                ratio = (timeout if other.status == "timeout" else other.time) / single.time
                target = replace(target, measured=f"{target.measured}; with 1 thread "
                                 f"{'≥ ' if other.status == 'timeout' else ''}{ratio:.3g}×")
            targets.append(target)
        throughput_cases = {row.case.name for row in rows if row.case.key in ("square", "mil-svg")}
        targets.append(_throughput([row for row in rows if row.peer.key == "pds" and row.ok
                                    and row.case.name in throughput_cases], by, 300))
        targets.append(_memory(pds, at))
    targets.append(_certificate([row for row in rows if row.peer.key == "pds" and row.ok],
                                "certificate() no slower than the meshing it certifies", 1))
    if startup:
        seconds = startup["import_median"]
        targets.append(Target("import", "`import pds_plugin` ≤ 0.3 s (fresh process)",
                              f"{seconds:.3f} s median, {startup['import_max']:.3f} s max",
                              seconds <= 0.3))
    targets.extend(_quality([row for row in rows if row.peer.key == "pds"]))
    targets.append(_coverage(rows))
    targets.extend(_engine(rows, startup, auto))
    return targets


def _speed(goal, at, pds, peer, factor, timeout) -> Target:
    name = goal.split(" than ")[-1]
    if pds is None or not pds.ok or peer is None or peer.status == "skipped":
        return Target(name, goal, "not measured in this run", None)
    if peer.status == "timeout":
        bound = timeout / pds.time
        return Target(name, goal, f"≥ {bound:.3g}× ({peer.peer.label} over the {timeout:g} s "
                      f"limit, pds {pds.time:.3g} s) {at}", True if bound >= factor else None)
    if not peer.ok:
        return Target(name, goal, f"{peer.peer.label} failed: {peer.message}", None)
    ratio = peer.time / pds.time
    # an extrapolated time is already for pds_plugin's vertex count
    count = peer.measured_points * peer.scale if peer.scale != 1 else peer.metric("vertices")
    per_vertex = ratio * pds.metric("vertices") / count
    note = " (extrapolated)" if peer.scale != 1 else ""
    return Target(name, goal, f"{ratio:.3g}×{note}: {peer.time:.3g} s vs pds {pds.time:.3g} s "
                  f"{at}; per vertex {per_vertex:.3g}×", ratio >= factor)


def _memory(pds, at) -> Target:
    goal = "peak memory ≤ 1 GB for 1M samples"
    if pds is None or not pds.ok:
        return Target("peak memory", goal, "not measured in this run", None)
    with_certificate = pds.info.get("peak_mb_with_certificate", math.nan)
    return Target("peak memory", goal,
                  f"{pds.peak_mb:.0f} MiB meshing, {with_certificate:.0f} MiB with the certificate "
                  f"(whole process) {at}", pds.peak_mb <= 1024)


def _extremes(name, goal, ratios, limit, *, higher_is_better=False, label="", unit=""):
    """A target on per-case ratios ``(value, case name)``: the worst and the best given,
    holding when the worst is within ``limit``."""
    if not ratios:
        return Target(name, goal, "not measured in this run", None)
    ordered = sorted(ratios, reverse=higher_is_better)
    (best, best_at), (worst, worst_at) = ordered[0], ordered[-1]
    holds = worst >= limit if higher_is_better else worst <= limit
    return Target(name, goal, f"{label}worst {worst:.3g}{unit} ({worst_at}), best "
                  f"{best:.3g}{unit} ({best_at})", holds)


def _throughput(pds_rows, by, factor) -> Target:
    ratios = [(sampling_rate(row) / sampling_rate(scipy), row.case.name) for row in pds_rows
              if (scipy := by.get((row.case.name, "scipy"))) is not None and scipy.ok]
    return _extremes("sampling throughput", f"`poisson_disc` throughput ≥ {factor}× scipy "
                     "PoissonDisk", ratios, factor, higher_is_better=True, unit="×")


def _certificate(pds_rows, goal, limit) -> Target:
    ratios = [(row.times["certificate"] / row.time, row.case.name) for row in pds_rows]
    return _extremes("certificate", goal, ratios, limit,
                     label="certificate / mesh_region time: ")


def _quality(pds_rows) -> list[Target]:
    ok = [row for row in pds_rows if row.ok and row.metrics]
    if not ok:
        return []
    above = sum(row.metric("above_bound") * row.metric("triangles") for row in ok)
    worst = min(ok, key=lambda row: row.metric("min_angle"))
    return [Target("aspect ratio", "pds_plugin: zero triangles above 4√3 on every region",
                   f"{above:.0f} triangles above 4√3 on {len(ok)} regions", above == 0),
            Target("min angle", "pds_plugin: min angle ≥ 30° on every region",
                   f"smallest {worst.metric('min_angle'):.3f}° ({worst.case.name})",
                   worst.metric("min_angle") >= 30 * (1 - ASPECT_TOL))]


def _coverage(rows) -> Target:
    goal = "pds_plugin coverage gap ≤ 1 where the other samplers' is > 1"
    samplers = [row for row in rows if row.ok and not math.isnan(row.metric("coverage_gap"))]
    pds = [row for row in samplers if row.peer.ours]
    others = [row for row in samplers if not row.peer.ours]
    if not pds:
        return Target("coverage", goal, "not measured in this run", None)
    pds_worst = max(row.metric("coverage_gap") for row in pds)
    others_best = min((row.metric("coverage_gap") for row in others), default=math.nan)
    return Target("coverage", goal, f"pds worst {pds_worst:.4f}; other samplers best "
                  f"{others_best:.3f}", pds_worst <= 1 + 1e-9 and not others_best <= 1)


# ----------------------------------------------------------------------------- issue 13

MB = 1e6 / 2**20            # one MB (10^6 bytes) in MiB: the issue counts in MB


def _engine(rows, startup, auto) -> list[Target]:
    """Issue 13: speed against Triangle at every size, throughput, certificate, memory,
    threads, cold start and the ``auto`` path."""
    by = {(row.case.name, row.peer.key): row for row in rows}
    pds_rows = [row for row in rows if row.peer.key == "pds" and row.ok]
    squares = sorted((row for row in pds_rows if row.case.key == "square"),
                     key=lambda row: row.case.expected)
    targets = []
    for row in squares:
        factor = 0.5 if row.case.expected >= 5e5 else 1.0
        targets.append(_against_triangle(f"{row.case.name}: `mesh_region` ≤ {factor:g}× "
                                         "Triangle pq30", [row], by, factor))
    regions = [row for row in pds_rows if row.case.key != "square"]
    if regions:
        targets.append(_against_triangle("every other region of the run: `mesh_region` "
                                         "≤ 1.0× Triangle pq30", regions, by, 1.0))
    targets.append(_throughput(pds_rows, by, 1000))
    targets.append(_certificate(pds_rows, "`certificate()` ≤ 0.5× the meshing time", 0.5))
    big = squares[-1] if squares and squares[-1].case.expected >= 5e5 else None
    if big is not None:
        peak = big.info.get("peak_mb_with_certificate", math.nan)
        targets.append(Target("1M memory", "peak memory at 1M samples ≤ 500 MB, with the "
                              "certificate", f"{peak:.0f} MiB = {peak / MB:.0f} MB (whole "
                              f"process) on the {big.case.name}", peak <= 500 * MB))
    targets.append(_threads(pds_rows, by))
    if startup:
        seconds = startup["import_median"] + startup["first_use"] + startup["cold_first_call"]
        targets.append(Target("cold start", "cold start: a fresh process meshes a 10k square "
                              "(and certifies it) in ≤ 5 s, imports included",
                              f"{seconds:.2f} s (import {startup['import_median']:.3f} s, "
                              f"reaching mesh_region {startup['first_use']:.3f} s, first call "
                              f"{startup['cold_first_call']:.2f} s)", seconds <= 5))
    targets.append(_auto_target(auto))
    targets.append(Target("busy machine", "with one other CPU-bound process, no timing "
                          "> 1.5× worse", "measured by `python bench/engine_threads.py` "
                          "(docs/engine.md), not by this run", None))
    return targets


def _against_triangle(goal, pds_rows, by, factor) -> Target:
    ratios = []
    for row in pds_rows:
        triangle = by.get((row.case.name, "triangle-pq30"))
        if triangle is not None and triangle.ok:
            ratios.append((row.time / triangle.time, row.case.name, row.time, triangle.time))
    if not ratios:
        return Target("against Triangle", goal, "not measured in this run", None)
    worst = max(ratios)
    listed = ", ".join(f"{ratio:.3g}× ({ours:.3g} s vs {theirs:.3g} s"
                       + (f", {name})" if len(ratios) > 1 else ")")
                       for ratio, name, ours, theirs in sorted(ratios, reverse=True))
    return Target("against Triangle", goal, listed, worst[0] <= factor)


def _threads(pds_rows, by) -> Target:
    ratios = [(row.time / single.time, row.case.name) for row in pds_rows
              if (single := by.get((row.case.name, "pds-1thread"))) is not None and single.ok]
    return _extremes("threads", "default threads never slower than one thread", ratios, 1,
                     label="default / one thread: ")


def _auto_target(auto) -> Target:
    goal = '`alpha="auto"` on a ~1k-vertex CAD section ≤ 5× Triangle pq30 (warm)'
    if not auto:
        return Target("auto", goal, "not measured (needs triangle and the shared "
                      "featuretype.STL)", None)
    ratio = auto["pds"] / auto["triangle"]
    return Target("auto", goal, f"{ratio:.3g}×: {auto['pds']:.3g} s vs {auto['triangle']:.3g} s "
                  f"on the {auto['region']} ({auto['boundary_vertices']:,} boundary vertices; "
                  f"{auto['vertices']:,} vertices against Triangle's "
                  f"{auto['triangle_vertices']:,})", ratio <= 5)
