"""The targets of issues 2 and 5, checked against the rows of one run.

Speed targets are ratios on the largest unit-square case of the run (1M samples in the
full run); a peer that timed out counts as taking at least the time limit, which
gives a lower bound on the ratio.
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


def evaluate(rows: list[Row], startup: dict | None, timeout: float) -> list[Target]:
    """Every target, in the order of the issues."""
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
        throughput_cases = _throughput_cases(rows)
        targets.append(_throughput([by.get((case.name, "pds")) for case in throughput_cases],
                                   [by.get((case.name, "scipy")) for case in throughput_cases]))
        targets.append(_memory(pds, at))
    targets.append(_certificate([row for row in rows if row.peer.key == "pds"]))
    if startup:
        seconds = startup["import_median"]
        targets.append(Target("import", "`import pds_plugin` ≤ 0.3 s (fresh process)",
                              f"{seconds:.3f} s median, {startup['import_max']:.3f} s max",
                              seconds <= 0.3))
    targets.extend(_quality([row for row in rows if row.peer.key == "pds"]))
    targets.append(_coverage(rows))
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


def _throughput_cases(rows):
    """Square cases and the many-holes drawing, as in issue 2."""
    cases = {row.case.name: row.case for row in rows if row.case.key in ("square", "mil-svg")}
    return list(cases.values())


def _throughput(pds_rows, scipy_rows) -> Target:
    goal = "sampling throughput ≥ 300× scipy PoissonDisk"
    ratios = [(sampling_rate(p) / sampling_rate(s), p.case.name)
              for p, s in zip(pds_rows, scipy_rows) if p is not None and s is not None
              and p.ok and s.ok]
    if not ratios:
        return Target("sampling throughput", goal, "not measured in this run", None)
    worst = min(ratios)
    listed = ", ".join(f"{r:.3g}× ({name})" for r, name in ratios)
    return Target("sampling throughput", goal, listed, worst[0] >= 300)


def _memory(pds, at) -> Target:
    goal = "peak memory ≤ 1 GB for 1M samples"
    if pds is None or not pds.ok:
        return Target("peak memory", goal, "not measured in this run", None)
    with_certificate = pds.info.get("peak_mb_with_certificate", math.nan)
    return Target("peak memory", goal,
                  f"{pds.peak_mb:.0f} MiB meshing, {with_certificate:.0f} MiB with the certificate "
                  f"(whole process) {at}", pds.peak_mb <= 1024)


def _certificate(pds_rows) -> Target:
    goal = "certificate() no slower than the meshing it certifies"
    ratios = [(row.times["certificate"] / row.time, row.case.name) for row in pds_rows if row.ok]
    if not ratios:
        return Target("certificate", goal, "not measured in this run", None)
    worst, where = max(ratios)
    return Target("certificate", goal, f"certificate / mesh_region time: worst {worst:.3g} "
                  f"({where}), best {min(ratios)[0]:.3g}", worst <= 1)


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
