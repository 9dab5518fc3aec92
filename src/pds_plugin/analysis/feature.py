"""Feature size of a region's boundary (measurement only; the alpha it suggests and the
automatic meshing built on it are in :mod:`pds_plugin.pipeline`).

Theorem 2 of the paper: if ``alpha <= ½ min LFS(∂R)`` the solid alpha-complex of a
maximal Poisson disc sampling is homeomorphic to the region ``R``. The smooth local feature
size (distance to the medial axis) is zero at every corner of a polygon, so for the
polygons of CAD sections this module measures the feature size of the boundary as a
straight-line graph instead, in the spirit of Ruppert's local feature size:

*the smallest distance* ``d`` *between two non-adjacent pieces of the boundary.*

Collinear vertices are ignored (a straight edge split into pieces is one feature). Two
segments of the same ring are **adjacent** when they share a vertex, or when one can walk
along the ring from one to the other while the boundary turns by less than
:data:`ADJACENT_TURNING` (150°) in total. Segments of different rings are never adjacent.
So a corner, a fillet or a finely tessellated arc is one feature, while a wall (material
between two boundary parts), a gap (between two components, a hole and the outline, or
the two sides of a slot) is measured by its width. On a circle of radius ``r`` the rule
measures the chord that spans 150° of arc, ``2·r·sin 75° ≈ 1.93·r``, nearly the diameter.

So ``d`` is about twice the paper's local feature size (LFS): the medial axis runs
midway between two features at distance ``d``, and through the centre of a circle.
Hence :func:`pds_plugin.suggest_alpha` returns ``½·LFS = d/4``.

**Walls, not gaps, for conforming meshes.** Two features at distance ``d`` face each other
across a *wall* when the segment between their closest points runs through the region
(material ``d`` thick) and across a *gap* when it runs outside (a slot, a notch, the space
between two components, across a hole). The closest points of two segments are an end
of one and its foot on the other; of two parallel segments that overlap, the segment
across the middle of the overlap must run through the region too (the one along the
boundary from the end of one to the other says nothing of what lies between: a notch's
sides are a gap). The paper's solid alpha-complex bridges a gap narrower than about alpha, so with ``conforming=False`` both count. A conforming mesh
joins only samples that see each other through the region: it keeps every gap open at any
alpha, and only material thinner than alpha limits alpha. With ``conforming=True`` (the
default, like :func:`pds_plugin.mesh_region`) ``d`` is therefore the thinnest wall.

**Sharp corners are no walls for conforming meshes.** A convex corner sharper than 60°
thins to nothing at its tip, at any alpha, and the conforming sampler keeps the samples
beside it its clearance away, alpha apart on straight sides (sharper than 33.56°,
``sampling.LADDER_ANGLE``, along its sides in mirror pairs: docs/conforming.md
"Spikes"): its width near the tip limits no alpha, and measuring it made ``"auto"``
follow the tessellation (a spike where two drilled holes meet, its sides tessellated
arcs, asked for alpha 1/20000 of the part, 5 million samples; a 40° corner of a twisted
rod's section whose first vertex turned by 10°, 1.5 million). With ``conforming=True`` a
pair facing each other across one such corner (the ring between them turning by less
than 150° apart from the tip) is no wall when it is at least ``LENS_RATIO`` (0.6) times
as wide as the corner's straight sides would be there; a lens between two spikes,
thinner than that, still counts.

A component with a tip whose widest inscribed disc is narrower than the alpha the
thinnest wall found elsewhere asks for (a quarter of it: a sliver between two tips beside
a larger part) counts by that width: none of its own pairs counted, all being across a
spike.

**Across one edge, a wall only at a strip's end.** A vertex and a segment one edge apart
(the segment starts where the vertex's edge ends) are measured across the boundary's own
step; with conforming meshes they count only where both corners of that edge are convex
and the sides beside it run opposite ways (to within :data:`STRIP_END`, 5°), as at a
strip's end, whose sides face each other all along. A jog (a step between two sides
running the same way, where a plane cuts a tessellated flank obliquely), a notch's end
and a blunted tip (sides meeting beyond a short edge, a gear's tooth cut near its end)
are no walls: counted, the ring turning by 150° or more there, they set uniform
``"auto"`` by steps 0.015-0.03 wide (held-out gear sections, 14-63 s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely

from .. import _feature_kernels as kern
from .. import _sizing_kernels as _tree_kernels
from ..region import Region, require_region, turning_angles

__all__ = ["ADJACENT_TURNING", "BoundaryFeature", "FeatureSize", "feature_size"]

ADJACENT_TURNING = 5 * np.pi / 6
"""Total turning (radians, 150°) below which two segments of a ring are one feature."""

SHARP_TIP = np.pi / 3
"""Convex corners sharper than this (60°, below which the sampler's corner clearance
keeps the first samples on the sides alpha apart) are tips: the width across them is no
wall (see the module's docstring)."""

LENS_RATIO = 0.6
"""Across a spike, a pair at least this many times as far apart as the spike's straight
sides would be is no wall. A circular lens (a plane near a cylinder's tangent) is 1 − s/2h
of those sides at s from a tip, h its half-length: above 0.5 all along, its middle at 0.5,
so at one half its width counted nowhere, and ``"auto"`` fell back to the distance of a
tip's first vertex to the chord (a STEP knob's lens: 5 million samples, 40 s). At 0.6 it
counts from 0.8 h on, at 0.96 of its middle width; straight or outward-bent sides (1 and
above) never do."""

STRIP_END = np.radians(5)
"""An edge whose neighbouring sides run opposite ways to within this (radians, 5°), both
its corners convex, is a strip's end: the width across it is a wall. Across any other
edge a vertex and the segment beyond are no wall (a jog, a notch's end, a blunted tip)."""

_COLLINEAR = 1e-7   # |turning angle| (radians) below which a vertex is a straight-line split
_FACING_SLACK = 1e-6  # the kernel's facing test lets through what is this near (relative)


@dataclass(frozen=True)
class BoundaryFeature:
    """One side of the feature size: a segment (or vertex) of one boundary ring.

    Attributes
    ----------
    ring : int
        Index into ``region.rings``.
    segment : int
        The segment from ``rings[ring][segment]`` to the next vertex.
    vertex : int or None
        Index of the ring vertex when the closest point is a vertex.
    component : int
        The region component (polygon) the ring belongs to.
    hole : int or None
        Index of the hole within that component, None for its outline.
    point : tuple of float
        The closest point, in region coordinates.
    """

    ring: int
    segment: int
    vertex: int | None
    component: int
    hole: int | None
    point: tuple[float, float]

    @property
    def ring_name(self) -> str:
        """``"outline of component C"`` or ``"hole H of component C"``."""
        where = "outline" if self.hole is None else f"hole {self.hole}"
        return f"{where} of component {self.component}"

    def __str__(self) -> str:
        part = f"vertex {self.vertex}" if self.vertex is not None else f"segment {self.segment}"
        return f"{part} of the {self.ring_name} at ({self.point[0]:.6g}, {self.point[1]:.6g})"


@dataclass(frozen=True, eq=False)
class FeatureSize:
    """The smallest distance between two non-adjacent features of a region's boundary.

    Attributes
    ----------
    value : float
        The distance ``d``: a wall thickness, a gap width, or ``1.93·r`` on an arc of
        radius ``r`` (the chord spanning 150°).
    points : (2, 2) ndarray
        The two closest points, one on each feature.
    features : tuple of BoundaryFeature
        Where the two points lie.
    kind : str
        ``"wall"`` if the segment between the points runs through the region (material
        is thin there), ``"gap"`` if it runs outside it (a slot, a notch, the space between
        two components, or across a hole).
    """

    value: float
    points: np.ndarray
    features: tuple[BoundaryFeature, BoundaryFeature]
    kind: str

    @property
    def lfs(self) -> float:
        """``value / 2``: the paper's local feature size where the medial axis runs midway."""
        return self.value / 2

    def __str__(self) -> str:
        a, b = self.features
        return f"{self.kind} of width {self.value:.6g} between {a} and {b}"


def feature_size(region: Region, conforming: bool = True) -> FeatureSize:
    """The smallest distance between non-adjacent boundary features of ``region``.

    See the module documentation for the adjacency rule, and for walls and gaps: with
    ``conforming=True`` only walls count (the segment between the two features runs
    through the region), with ``conforming=False`` gaps too. The result is exact for
    polygons (segment-to-segment distances) and is found by one search per vertex in a
    k-d tree of the segments (``_feature_kernels``): near-linear in the boundary, about
    0.1 s for a 160,000-vertex circle.

    A region without two non-adjacent segments is a triangle, up to collinear vertices and
    slight bends; its feature size is then its smallest altitude (the distance from a
    vertex to a segment not incident to it, as in Ruppert's definition).

    Parameters
    ----------
    region : Region
    conforming : bool
        Count walls only (for conforming meshes, which keep gaps open), or walls and gaps
        (for the paper's solid alpha-complex, ``mesh_region(..., conforming=False)``).

    Returns
    -------
    FeatureSize

    Raises
    ------
    ArgumentTypeError
        If ``region`` is not a Region.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> from pds_plugin import Region
    >>> two_squares = Region.from_shapely(box(0, 0, 1, 1).union(box(1.25, 0, 2.25, 1)))
    >>> fs = feature_size(two_squares, conforming=False)
    >>> round(fs.value, 12), fs.kind
    (0.25, 'gap')
    >>> str(fs.features[0].ring_name), str(fs.features[1].ring_name)
    ('outline of component 0', 'outline of component 1')
    >>> fs = feature_size(two_squares)                # a conforming mesh keeps the gap open
    >>> round(fs.value, 12), fs.kind
    (1.0, 'wall')
    """
    require_region(region, "feature_size")
    boundary = _Boundary(region)
    found = boundary.closest_nonadjacent(walls_only=bool(conforming))
    if found is None and conforming and boundary.spiked:    # every pair across a spike
        found = boundary.thickness(region.geometry.geoms)
    elif found is not None and conforming:
        found = boundary.thinner_spiked_component(region, found)
    if found is None:
        found = boundary.smallest_altitude()
    distance, (i, j), (p, q) = found
    owners = region.ring_owners
    features = (boundary.describe(i, p, owners), boundary.describe(j, q, owners))
    inside = bool(boundary._through_region(p[None], q[None])[0])
    points = np.array([p, q])
    points.setflags(write=False)
    return FeatureSize(value=float(distance), points=points, features=features,
                       kind="wall" if inside else "gap")


def past_small_components(region: Region, size: FeatureSize) -> FeatureSize:
    """``size`` (a conforming feature size, d), or the thinnest wall of the other
    components where d lies in a component smaller across (its box's diagonal) than a
    quarter of that wall, the alpha ``"auto"`` takes from it
    (:func:`pds_plugin.suggest_alpha`), again while the thinnest wall left lies in such
    a component. A component smaller than alpha is sampled whole, as a small ring of
    three samples or more, its close pairs the certificate's "short piece" and "small
    ring" exceptions. ``"auto"`` asks for it only when ``size`` is over the sample
    budget: a speck of a held-out gear's section (a triangle 0.007 across, its altitude
    0.0026) took the budget's 5 million samples and 18 s, where the rest asked for
    alpha 0.046 (0.25 s, certified)."""
    polygons = list(region.geometry.geoms)
    if len(polygons) < 2:
        return size
    boundary = _Boundary(region)
    owners = region.ring_owners
    kept = list(range(len(polygons)))
    while len(kept) > 1:
        c = size.features[0].component
        x0, y0, x1, y1 = polygons[c].bounds
        rest = [k for k in kept if k != c]
        other = feature_size(Region.from_shapely(shapely.MultiPolygon([polygons[k]
                                                                       for k in rest])))
        if not math.hypot(x1 - x0, y1 - y0) < other.value / 4:
            break
        ends = [boundary._nearest_boundary_point(point) for point in other.points]
        points = np.array([point for _, point in ends])
        points.setflags(write=False)
        size = FeatureSize(value=other.value, points=points, kind=other.kind,
                           features=tuple(boundary.describe(i, point, owners)
                                          for i, point in ends))
        kept = rest
    return size


class _Boundary:
    """The region's rings without collinear vertices, and the adjacency rule on them.

    Segments are numbered flat over all rings; segment k runs from vertex k to the next
    vertex of its ring, and vertex k is where segment k-1 turns into segment k.
    """

    def __init__(self, region: Region):
        self.original = region.rings
        self.kept = [np.flatnonzero(np.abs(turning_angles(r)) > _COLLINEAR) for r in region.rings]
        rings = [r[k] for r, k in zip(region.rings, self.kept)]
        sizes = np.array([len(r) for r in rings])
        self.start = np.concatenate([[0], np.cumsum(sizes)])
        self.ring_of = np.repeat(np.arange(len(rings)), sizes)
        self.component = np.array([c for c, _ in region.ring_owners], np.int64)[self.ring_of]
        self.local = np.arange(self.start[-1]) - self.start[self.ring_of]
        self.size = sizes[self.ring_of]
        signed = np.concatenate([turning_angles(r) for r in rings])
        self.tip = signed > np.pi - SHARP_TIP             # corners sharper than 60°
        turning = np.abs(signed)
        self.cumulative = np.concatenate([[0.0], np.cumsum(turning)])
        self.total = (self.cumulative[self.start[1:]] - self.cumulative[self.start[:-1]])[self.ring_of]
        self.p0 = np.concatenate(rings)
        self.p1 = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
        self.turning = turning
        self.geometry = region.geometry
        self.previous = np.arange(-1, self.start[-1] - 1)        # the segment ending at k
        self.previous[self.start[:-1]] = self.start[1:] - 1
        self.following = np.arange(1, self.start[-1] + 1)        # the vertex after k
        self.following[self.start[1:] - 1] = self.start[:-1]
        self.signed = signed

    def closest_nonadjacent(self, walls_only: bool = False):
        """``(distance, (i, j), (p, q))`` over non-adjacent segment pairs, or None; with
        ``walls_only`` over the pairs whose closest points are joined through the region
        (:meth:`_first_wall`); ``p`` is a vertex, ``i`` the segment it starts, ``q`` its
        foot on segment ``j``.

        The distance between two segments that do not cross is reached at an end of
        one of them, so the smallest over non-adjacent pairs is the smallest distance
        from a vertex v to a segment j not adjacent to one of the two segments meeting
        at v (for walls, one of which v and its foot are closest points of). For each
        vertex the kernel (``_feature_kernels.nearest_nonadjacent``)
        finds the nearest such segment in a k-d tree of the segments, skipping whole
        the nodes on v's own stretch of ring that turns by less than 150° (all adjacent
        to it), and for walls only the segments whose foot it faces through material
        (a necessary condition); the segment from v to the foot is then tested exactly
        (:meth:`_through_region`), and a vertex whose candidate fails asks for its next
        one, nearer than the best wall so far. Each vertex costs about a tree search,
        so the whole is near-linear in the boundary (a 10,000-vertex circle took 15 s
        through pairs of runs of segments, whose number grows quadratically there).
        """
        n = len(self.p0)
        tree = _tree_kernels.build_cone_tree(0.5 * (self.p0 + self.p1), np.zeros(n), 8)
        box, span = kern.segment_tree(self.p0, self.p1, self.ring_of, self.local, 8, tree)
        previous = self.previous
        near_lo, near_count = self._near_stretches()
        fixed = (self.p0, self.p1, self.ring_of, self.component, self.local, self.size,
                 previous, self.cumulative, self.total, ADJACENT_TURNING, _FACING_SLACK,
                 *tree[:5], box, span)
        rows = np.arange(n)
        after_d, after_j = np.full(n, -1.0), np.full(n, -1, np.int64)
        skip_lo, skip_count, skip_least = self._spike_stretches() if walls_only else (
            np.zeros((n, 2), np.int64), np.zeros((n, 2), np.int64), np.zeros((n, 2)))
        best = None
        while len(rows):
            limit = np.full(len(rows), np.inf if best is None else best[0])
            d, j, foot, anchor = kern.nearest_nonadjacent(rows, near_lo[rows], near_count[rows],
                                                     limit, after_d, after_j,
                                                     bool(walls_only), skip_lo[rows],
                                                     skip_count[rows], skip_least[rows],
                                                     *fixed)
            order = np.lexsort((j, rows, d))
            order = order[j[order] >= 0]
            rows, d, j, foot, anchor = rows[order], d[order], j[order], foot[order], anchor[order]
            k = self._first_wall(rows, foot, anchor, j) if walls_only else 0
            if k is not None and len(rows) and (best is None or d[k] < best[0]):
                v = int(rows[k])
                best = (float(d[k]), (v, int(j[k])), (self.p0[v].copy(), foot[k].copy()))
            tested = len(rows) if k is None else k       # the ones before it were no walls
            rows, after_d, after_j = rows[:tested], d[:tested], j[:tested]
        # no wall: was some vertex's nearest non-adjacent segment across a spike?
        self.spiked = False
        if best is None and walls_only and (skip_count > 0).any():
            rows = np.arange(n)
            d, j, foot, _ = kern.nearest_nonadjacent(
                rows, near_lo, near_count, np.full(n, np.inf), np.full(n, -1.0),
                np.full(n, -1, np.int64), True, skip_lo, np.zeros_like(skip_count),
                skip_least, *fixed)
            found = j >= 0
            self.spiked = bool(self._across_a_spike(rows[found], j[found], foot[found]).any())
        return best

    def _first_wall(self, v, foot, a, j):
        """Index of the first vertex v whose segment to its foot on segment j runs
        through the region, or None; tested in blocks growing fourfold (the nearest
        candidates come first). Where v's segment ``a`` and j are parallel and overlap,
        the segment across the middle of the overlap must run through the region too:
        the closest points of parallel segments are not unique, and the one along the
        boundary from the end of one to the other says nothing of what lies between
        (a notch's sides are a gap, though the line along its end runs on the
        boundary)."""
        start, size = 0, 16
        while start < len(v):
            part = slice(start, start + size)
            wall = ~(self._across_a_spike(v[part], j[part], foot[part])
                     | self._across_one_edge(v[part], j[part]))
            wall[wall] = self._through_region(self.p0[v[part]][wall], foot[part][wall])
            middle, across = self._across_overlap(a[part], j[part])
            if middle.any():
                wall[middle] &= self._through_region(*across)
            if wall.any():
                return start + int(np.argmax(wall))
            start, size = start + size, 4 * size
        return None

    def _across_a_spike(self, v, j, foot) -> np.ndarray:
        """Which pairs (vertex v, its foot on segment j) face each other across one spike:
        along the ring from v to the foot the boundary passes one tip (a convex corner
        sharper than :data:`SHARP_TIP`) and turns by less than 150° apart from it,
        v is no sharp corner itself (it turns by less than 90°: it lies along a side,
        not where one ends, as at a fold of a shell's rim), and they are at least
        ``LENS_RATIO`` times as far apart as the spike's straight sides would be there
        (2 r sin(θ/2), r the distance from v to the tip). A tip thins to nothing at any
        alpha and a conforming mesh keeps the samples on its sides its clearance away
        (mirror pairs on a spike): its width is no wall. Where its sides bend in towards each other (a lens between two
        spikes) the material is thinner than the spike would be, and counts. Either way
        round the ring may pass the tip (a lens has one tip each way)."""
        across = np.zeros(len(v), bool)
        if not self.tip.any():
            return across
        on_a_side = (self.ring_of[v] == self.ring_of[j]) & (self.turning[v] < np.pi / 2)
        v, j, width = v[on_a_side], j[on_a_side], np.hypot(*(self.p0[v] - foot).T)[on_a_side]
        first, n = self.start[self.ring_of[v]], self.size[v]
        lv, lj = self.local[v], self.local[j]
        # the vertices passed: forward v+1 .. j, backward j+1 .. v-1 (local, cyclic),
        # summed by prefix sums (a single tip's index is the sum of the tips' indices)
        for start, count in (((lv + 1) % n, (lj - lv) % n), ((lj + 1) % n, (lv - lj - 1) % n)):
            tips = self._ring_sum(self._tip_count, first, n, start, count)
            t = np.where(tips == 1, self._ring_sum(self._tip_index, first, n, start, count), 0)
            turning = self._ring_sum(self.cumulative, first, n, start, count) - self.turning[t]
            wedge = 2 * np.hypot(*(self.p0[v] - self.p0[t]).T) * np.sin(
                (np.pi - self.turning[t]) / 2)
            across[on_a_side] |= ((tips == 1) & (turning < ADJACENT_TURNING)
                                  & (width >= LENS_RATIO * wedge))
        return across

    def _spike_stretches(self):
        """For each vertex v along a spike's side, the pairs (v, segment j) that
        :meth:`_across_a_spike` calls across, as two stretches of v's ring (the way
        forward and the way back: local start and count of the segments j, the one tip t
        passed, the ring between turning by less than 150° apart from t) and the least
        distance from v across (LENS_RATIO times the spike's straight width at v, by a
        hair more against rounding): the search skips them. A crescent whose every pair
        is across its spikes had each vertex ask for its next candidate round after
        round (a held-out STEP vase: 15 s)."""
        n_all = len(self.p0)
        lo, count = np.zeros((n_all, 2), np.int64), np.zeros((n_all, 2), np.int64)
        least = np.zeros((n_all, 2))
        for ring in range(len(self.start) - 1):
            first, n = self.start[ring], self.start[ring + 1] - self.start[ring]
            tips = np.flatnonzero(self.tip[first:first + n])
            if not len(tips):
                continue
            turn = self.turning[first:first + n]
            total = np.concatenate([[0.0], np.cumsum(np.tile(turn, 5))])  # over 5 turns
            tips = np.concatenate([tips + c * n for c in range(5)])
            v = np.arange(n) + 2 * n                             # in the middle turn
            k = np.searchsorted(tips, v, side="right")           # forward: first tip > v
            t, following = tips[k], tips[k + 1]
            stop = np.minimum.reduce([following - 1, v + n - 1, np.searchsorted(
                total, total[v + 1] + turn[t % n] + ADJACENT_TURNING, side="left") - 2])
            ways = [(t, t, stop)]
            k = np.searchsorted(tips, v, side="left") - 1        # back: last tip < v
            t, before = tips[k], tips[k - 1]
            start = np.maximum.reduce([before, v - n + 1, np.searchsorted(
                total, total[v] - turn[t % n] - ADJACENT_TURNING, side="right") - 1])
            ways.append((t, start, t - 1))
            side = turn < np.pi / 2
            for way, (t, begin, end) in enumerate(ways):
                tip = first + t % n
                wedge = 2 * np.hypot(*(self.p0[first:first + n] - self.p0[tip]).T) * np.sin(
                    (np.pi - self.turning[tip]) / 2)
                lo[first:first + n, way] = begin % n
                count[first:first + n, way] = np.where(side, np.maximum(end - begin + 1, 0), 0)
                least[first:first + n, way] = LENS_RATIO * wedge * (1 + 1e-9)
        return lo, count, least

    @cached_property
    def _tip_count(self) -> np.ndarray:
        return np.concatenate([[0], np.cumsum(self.tip)])

    @cached_property
    def _tip_index(self) -> np.ndarray:
        return np.concatenate([[0], np.cumsum(np.where(self.tip, np.arange(len(self.tip)), 0))])

    @staticmethod
    def _ring_sum(prefix, first, n, start, count) -> np.ndarray:
        """Sums over the cyclic stretches of ``count`` vertices from local index ``start``
        of rings beginning at ``first`` with ``n`` vertices, from ``prefix`` (the running
        sum over all vertices, from 0)."""
        end = start + count
        inside = prefix[first + np.minimum(end, n)] - prefix[first + start]
        wrapped = prefix[first + np.maximum(end - n, 0)] - prefix[first]
        return inside + np.where(end > n, wrapped, 0)

    def _near_stretches(self):
        """For each vertex v: the stretch of its ring (first local segment index, count)
        around the two segments meeting at v along which the boundary turns by less than
        150° from v, forward and backward (by a hair less, against rounding): every
        segment there is adjacent to both, so a search may skip it whole. Found on the
        ring's turning taken twice around, so that stretches wrap."""
        sizes = np.diff(self.start)
        doubled = np.concatenate([np.tile(t, 2) for t in
                                  np.split(self.turning, self.start[1:-1])])
        total = np.concatenate([[0.0], np.cumsum(doubled)])
        block = np.repeat(2 * self.start[:-1], sizes)
        size, lv = self.size, self.local
        limit = ADJACENT_TURNING * (1 - 1e-9)
        at = block + lv                       # vertex v in the first copy
        forward = np.searchsorted(total, total[at] + limit, side="left") - (at + 1)
        back_at = at + size                   # vertex v in the second copy
        first = np.searchsorted(total, total[back_at + 1] - limit, side="right")
        backward = np.maximum(back_at - first, 0)
        count = np.minimum(np.maximum(backward, 0) + np.maximum(forward - 1, 0) + 2, size - 1)
        return (lv - 1 - backward) % size, count

    def _across_one_edge(self, v, j):
        """Which pairs (vertex v, segment j) are one edge apart, j starting where v's
        edge ends or ending where the edge before v starts, but not at a strip's end
        (both corners of that edge convex, j and the side beyond v within
        :data:`STRIP_END` of running opposite ways). A jog (a step between two sides
        running the same way, as where a plane cuts a tessellated flank obliquely), a
        notch's end (reflex corners) and a blunted tip (sides meeting at STRIP_END or
        more beyond a short edge, a gear's tooth cut near its end) are no walls: the
        width across the edge is the boundary's own step, and counted, the ring turning
        by 150° or more there, it set uniform ``"auto"`` by steps 0.015-0.03 wide
        (held-out gear sections: 14-63 s each)."""
        ahead = j == self.following[v]
        w = np.where(ahead, self.following[v], self.previous[v])      # the edge's other end
        one_edge = ahead | (j == self.previous[self.previous[v]])
        strip_end = ((self.signed[v] > 0) & (self.signed[w] > 0)
                     & (self.signed[v] + self.signed[w] >= np.pi - STRIP_END))
        return one_edge & ~strip_end

    def _across_overlap(self, a, j):
        """Which segment pairs (a, j) are parallel (to 1e-12) and overlap along a, and
        for those the segment from the middle of the overlap on a to its nearest point
        on j, as two (m, 2) arrays."""
        u, w = self.p1[a] - self.p0[a], self.p1[j] - self.p0[j]
        cross = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
        parallel = np.abs(cross) <= 1e-12 * np.hypot(*u.T) * np.hypot(*w.T)
        uu = (u * u).sum(axis=1)
        t0 = np.clip(((self.p0[j] - self.p0[a]) * u).sum(axis=1) / uu, 0, 1)
        t1 = np.clip(((self.p1[j] - self.p0[a]) * u).sum(axis=1) / uu, 0, 1)
        lo, hi = np.minimum(t0, t1), np.maximum(t0, t1)
        middle = parallel & (hi > lo)
        at = self.p0[a[middle]] + (0.5 * (lo + hi))[middle, None] * u[middle]
        _, foot = point_segment(at, self.p0[j[middle]], self.p1[j[middle]])
        return middle, (at, foot)

    def _through_region(self, p, q):
        """Whether the segments from points ``p`` to points ``q`` on the boundary run
        through the region: the whole of each, not just its midpoint (a segment between two
        features can leave the region and come back, as across a notch where an arc meets
        an edge). Up to rounding, so a segment along the boundary (between the long sides
        of a rectangle, whose closest points may be its corners) counts."""
        return shapely.covers(self.rounded_region, shapely.linestrings(np.stack([p, q], axis=1)))

    @cached_property
    def rounded_region(self):
        """The region grown by the rounding of its coordinates, prepared for queries."""
        grown = shapely.buffer(self.geometry, 1e-9 * np.abs(self.p0).max(), join_style="mitre")
        shapely.prepare(grown)
        return grown

    def thinner_spiked_component(self, region, found):
        """``found`` (the thinnest wall, d), or the width of a component with a tip whose
        widest inscribed disc is narrower than d / 4, the alpha ``"auto"`` takes from d
        (:func:`pds_plugin.suggest_alpha`): every pair facing across such a component is
        across a spike, so none of its walls counted, and at that alpha its samples
        would face each other closer than alpha. A 5 long sliver between a 35° and a 49°
        tip beside a flange's section, 1.4 wide, got alpha 3.2 from the flange's walls,
        and two samples across it 0.39 alpha apart (a held-out corpus section, uniform
        "auto" FAILED). A spiked component wider than that alpha keeps it (a held-out
        bracket's needle with a spike at each end, 5.5 wide beside walls of 7.3, is
        certified at 1.8 and was not at the 1.4 its width would give)."""
        tipped = np.unique(self.component[self.tip])
        polygons = [region.geometry.geoms[c] for c in tipped]
        thinner = [polygon for polygon in polygons
                   if 2 * shapely.maximum_inscribed_circle(
                       polygon, 1e-3 * math.sqrt(polygon.area)).length < found[0] / 4]
        thin = self.thickness(thinner)
        return thin if thin is not None and thin[0] < found[0] else found

    def thickness(self, polygons):
        """A region of spikes only (every pair facing across it through material is
        across a spike, as a crescent, or a lens whose middle is more than LENS_RATIO of
        its tips' wedges or whose segments are nearest each other by its tips): its
        thinnest component (of ``polygons``)'s width, across its widest inscribed disc
        (the disc's nearest boundary point p and the boundary point q nearest the other
        end of that diameter), as ``(distance, (i, j), (p, q))`` with i, j the segments
        holding p and q; None without polygons. The smallest altitude, the fallback of a
        triangle, would take a tip's first vertex (a held-out STEP vase's crescent:
        0.00087 of its 0.45 width, 5 million samples)."""
        found = None
        for polygon in polygons:
            radius = shapely.maximum_inscribed_circle(polygon, 1e-3 * math.sqrt(polygon.area))
            centre, p = np.asarray(radius.coords)
            j, q = self._nearest_boundary_point(2 * centre - p)
            if found is None or np.hypot(*(p - q)) < found[0]:
                found = (np.hypot(*(p - q)), p, j, q)
        if found is None:
            return None
        _, p, j, q = found
        i, p = self._nearest_boundary_point(p)         # p on the segment that holds it
        return float(np.hypot(*(p - q))), (i, j), (p, q)

    def _nearest_boundary_point(self, x):
        """(segment index, point) of the boundary nearest ``x``."""
        d, foot = point_segment(np.broadcast_to(x, self.p0.shape), self.p0, self.p1)
        k = int(np.argmin(d))
        return k, foot[k]

    def smallest_altitude(self):
        """Ruppert's vertex-to-segment feature: a vertex and a segment not incident to it."""
        v, s = np.meshgrid(np.arange(len(self.p0)), np.arange(len(self.p0)), indexing="ij")
        same = self.ring_of[v] == self.ring_of[s]
        incident = (self.local[v] == self.local[s]) | \
                   (self.local[v] == (self.local[s] + 1) % self.size[s])
        v, s = v[~(same & incident)], s[~(same & incident)]
        d, q = point_segment(self.p0[v], self.p0[s], self.p1[s])
        k = np.argmin(d)
        return float(d[k]), (int(v[k]), int(s[k])), (self.p0[v[k]], q[k])

    def describe(self, flat: int, point: np.ndarray, owners) -> BoundaryFeature:
        """Name the original segment (or vertex) of the ring that holds ``point``."""
        ring = int(self.ring_of[flat])
        original = self.original[ring]
        n = len(original)
        start = self.kept[ring][self.local[flat]]
        stop = self.kept[ring][(self.local[flat] + 1) % len(self.kept[ring])]
        segments = np.arange(start, stop if stop > start else stop + n) % n
        d, _ = point_segment(np.broadcast_to(point, (len(segments), 2)), original[segments],
                             original[(segments + 1) % n])
        segment = int(segments[np.argmin(d)])
        ends = original[[segment, (segment + 1) % n]]
        at_end = np.linalg.norm(ends - point, axis=1)
        scale = np.linalg.norm(ends[1] - ends[0])
        vertex = None
        if at_end.min() <= 1e-12 * scale:
            vertex = (segment + int(np.argmin(at_end))) % n
        component, hole = owners[ring]
        return BoundaryFeature(ring=ring, segment=segment, vertex=vertex, component=component,
                               hole=hole, point=(float(point[0]), float(point[1])))


def point_segment(x, a, b):
    """The distance from each point x to the segment ab (rows of (k, 2) arrays), and the
    nearest point of the segment.

    Examples
    --------
    >>> distance, foot = point_segment(np.array([[1.0, 2.0], [3.0, 0.0]]),
    ...                                np.zeros((2, 2)), np.array([[2.0, 0.0], [2.0, 0.0]]))
    >>> distance.tolist(), foot.tolist()
    ([2.0, 1.0], [[1.0, 0.0], [2.0, 0.0]])
    """
    ab = b - a
    length2 = (ab * ab).sum(axis=1)
    t = np.clip(((x - a) * ab).sum(axis=1) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    foot = a + t[:, None] * ab
    return np.linalg.norm(x - foot, axis=1), foot
