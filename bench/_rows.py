"""One row of the table: a peer's outcome on a case, measured."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from _isolate import Outcome
from _metrics import measure
from _regions import Case
from _runners import Peer


@dataclass
class Row:
    case: Case
    peer: Peer
    status: str                    # "ok", "timeout", "failed", "skipped"
    message: str = ""
    time: float = math.nan         # end-to-end seconds; extrapolated when scale != 1
    scale: float = 1.0             # time = measured time * scale (scipy above its cap)
    measured_points: int = 0       # sample count the time was measured at, when scaled
    times: dict = field(default_factory=dict)    # measured parts, seconds
    peak_mb: float = math.nan
    alpha: float = math.nan        # the radius the gap and distance are relative to
    metrics: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def metric(self, name: str, default=math.nan):
        return self.metrics.get(name, default)


def collect(case: Case, peer: Peer, outcome: Outcome, target: int) -> Row:
    """The row of ``outcome``: its metrics on the case's region, and for a run made at
    a coarser alpha than the case's (scipy's PoissonDisk above its cap) the time scaled
    linearly in the sample count to ``target`` samples."""
    if outcome.status != "ok":
        return Row(case, peer, outcome.status, outcome.message)
    row = Row(case, peer, "ok", time=outcome.times["total"], times=outcome.times,
              peak_mb=outcome.peak_mb, alpha=outcome.alpha, info=outcome.info)
    if outcome.alpha > case.alpha * (1 + 1e-9) and len(outcome.vertices):
        row.measured_points = len(outcome.vertices)
        row.scale = target / row.measured_points
        row.time *= row.scale
    try:
        row.metrics = measure(case.region, outcome.vertices, outcome.faces, outcome.alpha,
                              outcome.samples)
    except Exception as error:           # one bad mesh must not stop the table
        row.message = f"metrics failed: {type(error).__name__}: {error}"
    return row


def sampling_rate(row: Row) -> float:
    """Samples made per second of sampling: pds_plugin's samples, scipy's points in the
    whole bounding box (before clipping: the work it did)."""
    if not row.ok or "sampling" not in row.times:
        return math.nan
    made = row.info.get("bridson_points", row.metric("vertices"))
    return made / row.times["sampling"] if row.times["sampling"] > 0 else math.nan

