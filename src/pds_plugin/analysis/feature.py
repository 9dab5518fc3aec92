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
between two components, across a hole). The paper's solid alpha-complex bridges a gap
narrower than about alpha, so with ``conforming=False`` both count. A conforming mesh
joins only samples that see each other through the region: it keeps every gap open at any
alpha, and only material thinner than alpha limits alpha. With ``conforming=True`` (the
default, like :func:`pds_plugin.mesh_region`) ``d`` is therefore the thinnest wall.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely

from ..region import Region, require_region, turning_angles

__all__ = ["ADJACENT_TURNING", "BoundaryFeature", "FeatureSize", "feature_size"]

ADJACENT_TURNING = 5 * np.pi / 6
"""Total turning (radians, 150°) below which two segments of a ring are one feature."""

_COLLINEAR = 1e-7   # |turning angle| (radians) below which a vertex is a straight-line split
_CHUNK = 16         # consecutive segments per spatial-index entry
_BATCH = 16         # pairs of runs first expanded when looking for walls (then 4x more each time)


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
    polygons (segment-to-segment distances) and is found through a spatial index over runs
    of consecutive segments: about 10 ms for a CAD section of 800 segments, 0.15 s for
    6,500.

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
        self.local = np.arange(self.start[-1]) - self.start[self.ring_of]
        self.size = sizes[self.ring_of]
        turning = np.abs(np.concatenate([turning_angles(r) for r in rings]))
        self.cumulative = np.concatenate([[0.0], np.cumsum(turning)])
        self.total = (self.cumulative[self.start[1:]] - self.cumulative[self.start[:-1]])[self.ring_of]
        self.p0 = np.concatenate(rings)
        self.p1 = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
        self.geometry = region.geometry

    def forward_adjacent(self, i, j):
        """For segments i <= j of one ring: the path i -> j turns less than the threshold."""
        turning = self.cumulative[j + 1] - self.cumulative[i + 1]     # at vertices i+1..j
        return (turning < ADJACENT_TURNING) | (j - i <= 1)

    def backward_adjacent(self, i, j):
        """For segments i <= j of one ring: the path j -> i (through the ring's start) does."""
        turning = self.total[i] - (self.cumulative[j + 1] - self.cumulative[i + 1])
        wrap = (self.local[i] == 0) & (self.local[j] == self.size[j] - 1)
        return (turning < ADJACENT_TURNING) | wrap

    def adjacent(self, i, j):
        """Adjacency of segment pairs i <= j (flat indices, possibly on different rings)."""
        same = self.ring_of[i] == self.ring_of[j]
        return same & (self.forward_adjacent(i, j) | self.backward_adjacent(i, j))

    def closest_nonadjacent(self, walls_only: bool = False):
        """``(distance, (i, j), (p, q))`` over non-adjacent segment pairs, or None; with
        ``walls_only`` over the pairs whose closest points are joined through the region.

        Runs of segments whose bounding boxes come within ``radius`` of each other are
        paired through an STRtree; ``radius`` grows until a non-adjacent pair is found
        within it, which makes the minimum exact. Each growth examines only the run
        pairs it adds (the best so far is kept on ties).
        """
        best_of = self._best_wall if walls_only else self._best_of_chunk_pairs
        chunks, first, last = self._chunks()
        tree = shapely.STRtree(chunks)
        boxes = shapely.bounds(chunks)
        x0, y0, x1, y1 = boxes.T
        span = max(x1.max() - x0.min(), y1.max() - y0.min())
        radius = 4 * np.median(np.linalg.norm(self.p1 - self.p0, axis=1))
        best, seen = None, np.empty(0, np.int64)
        while best is None or best[0] > radius:
            if best is not None:
                radius = best[0]
            a, b = tree.query(shapely.box(x0 - radius, y0 - radius, x1 + radius, y1 + radius))
            keep = a <= b
            a, b = a[keep], b[keep]
            pairs = a * len(chunks) + b
            new = ~np.isin(pairs, seen)
            seen = pairs                       # the pairs within a radius hold the smaller's
            found = best_of(chunks, boxes, first, last, a[new], b[new]) if new.any() else None
            if found is not None and (best is None or found[0] < best[0]):
                best = found
            if best is None:
                if radius > 2 * span:
                    return None
                radius *= 4
        return best

    def _chunks(self):
        """Runs of at most _CHUNK consecutive segments of one ring, as LineStrings."""
        first = np.concatenate([np.arange(s, e, _CHUNK)
                                for s, e in zip(self.start[:-1], self.start[1:])])
        ring_end = self.start[1:][self.ring_of[first]]
        last = np.minimum(first + _CHUNK, ring_end) - 1
        points = last - first + 2                 # a chunk's segment starts, then its end
        chunk = np.repeat(np.arange(len(first)), points)
        position = np.arange(points.sum()) - np.repeat(np.cumsum(points) - points, points)
        segment = first[chunk] + np.minimum(position, points[chunk] - 2)
        end = (position == points[chunk] - 1)[:, None]
        xy = np.where(end, self.p1[segment], self.p0[segment])
        return shapely.linestrings(xy, indices=chunk), first, last

    def _best_of_chunk_pairs(self, chunks, boxes, first, last, a, b):
        same_ring = self.ring_of[first[a]] == self.ring_of[first[b]]
        a0, a1, b0, b1 = first[a], last[a], first[b], last[b]
        # along each direction turning grows with the index distance, so the farthest
        # pair decides whether all pairs are adjacent, and the nearest whether none is
        distinct = same_ring & (a != b)
        all_adjacent = distinct & (self.forward_adjacent(a0, b1) | self.backward_adjacent(a1, b0))
        none_adjacent = ~same_ring | (distinct & ~self.forward_adjacent(a1, b0)
                                      & ~self.backward_adjacent(a0, b1))
        # prune by bounding boxes: their gap bounds a pair's distance from below, and the
        # distance between the first vertices of two non-adjacent runs from above
        lower = np.hypot(*np.maximum(0, np.maximum(boxes[a, :2] - boxes[b, 2:],
                                                   boxes[b, :2] - boxes[a, 2:])).T)
        upper = np.linalg.norm(self.p0[a0] - self.p0[b0], axis=1)[none_adjacent]
        near = lower <= (upper.min() if len(upper) else np.inf)
        candidates = []
        whole = none_adjacent & near
        if whole.any():
            d = shapely.distance(chunks[a[whole]], chunks[b[whole]])
            k = np.argmin(d)
            candidates.append((d[k], a[whole][k], b[whole][k]))
        mixed = ~all_adjacent & ~none_adjacent & near
        if mixed.any():
            i, j = _expand(first[a[mixed]], last[a[mixed]], first[b[mixed]], last[b[mixed]])
            keep = (i < j) & ~self.adjacent(np.minimum(i, j), np.maximum(i, j))
            if keep.any():
                i, j = i[keep], j[keep]
                d, _, _ = _segment_distance(self.p0[i], self.p1[i], self.p0[j], self.p1[j])
                k = np.argmin(d)
                owner = np.searchsorted(first, [i[k], j[k]], side="right") - 1
                candidates.append((d[k], owner[0], owner[1]))
        if not candidates:
            return None
        _, ca, cb = min(candidates)
        i, j = _expand(first[[ca]], last[[ca]], first[[cb]], last[[cb]])
        keep = (i != j) & ~self.adjacent(np.minimum(i, j), np.maximum(i, j))
        i, j = i[keep], j[keep]
        d, p, q = _segment_distance(self.p0[i], self.p1[i], self.p0[j], self.p1[j])
        k = np.argmin(d)
        return float(d[k]), (int(i[k]), int(j[k])), (p[k], q[k])

    def _best_wall(self, chunks, boxes, first, last, a, b):
        """The closest non-adjacent pair through the region among the runs ``a``, ``b``:
        run pairs in order of their distance (a lower bound of their segment pairs'),
        expanded in batches growing fourfold until the next batch cannot beat the best
        wall (the nearest run pairs usually hold it)."""
        a, b = self._not_all_adjacent(first, last, a, b)
        lower = shapely.distance(chunks[a], chunks[b])
        order = np.argsort(lower, kind="stable")
        best = None
        start, size = 0, _BATCH
        while start < len(order):
            batch = order[start:start + size]
            start, size = start + size, 4 * size
            if best is not None and lower[batch[0]] >= best[0]:
                break
            i, j = _expand(first[a[batch]], last[a[batch]], first[b[batch]], last[b[batch]])
            keep = (i < j) & ~self.adjacent(i, np.maximum(i, j))
            i, j = i[keep], j[keep]
            d, p, q = _segment_distance(self.p0[i], self.p1[i], self.p0[j], self.p1[j])
            k = self._closest_wall(d, p, q, below=np.inf if best is None else best[0])
            if k is not None:
                best = (float(d[k]), (int(i[k]), int(j[k])), (p[k], q[k]))
        return best

    def _not_all_adjacent(self, first, last, a, b):
        """The run pairs ``a``, ``b`` (a <= b) holding at least one non-adjacent segment
        pair. Along each direction the turning grows with the index distance, so the
        farthest pair of two runs of one ring decides whether all their pairs are
        adjacent: on a finely tessellated arc most run pairs are, and expanding them cost
        time quadratic in its vertices (a 10,000-vertex circle took 15 s)."""
        a0, a1, b0, b1 = first[a], last[a], first[b], last[b]
        same_ring = self.ring_of[a0] == self.ring_of[b0]
        all_adjacent = same_ring & (a != b) & (self.forward_adjacent(a0, b1)
                                               | self.backward_adjacent(a1, b0))
        return a[~all_adjacent], b[~all_adjacent]

    def _closest_wall(self, d, p, q, below):
        """Index of the closest pair nearer than ``below`` whose segment runs through the
        region, or None; pairs are tested nearest first, in blocks growing fourfold."""
        order = np.argsort(d, kind="stable")
        order = order[d[order] < below]
        start, size = 0, 16
        while start < len(order):
            block = order[start:start + size]
            wall = self._through_region(p[block], q[block])
            if wall.any():
                return int(block[np.argmax(wall)])
            start, size = start + size, 4 * size
        return None

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

    def smallest_altitude(self):
        """Ruppert's vertex-to-segment feature: a vertex and a segment not incident to it."""
        v, s = np.meshgrid(np.arange(len(self.p0)), np.arange(len(self.p0)), indexing="ij")
        same = self.ring_of[v] == self.ring_of[s]
        incident = (self.local[v] == self.local[s]) | \
                   (self.local[v] == (self.local[s] + 1) % self.size[s])
        v, s = v[~(same & incident)], s[~(same & incident)]
        d, p, q = _segment_distance(self.p0[v], self.p0[v], self.p0[s], self.p1[s])
        k = np.argmin(d)
        return float(d[k]), (int(v[k]), int(s[k])), (p[k], q[k])

    def describe(self, flat: int, point: np.ndarray, owners) -> BoundaryFeature:
        """Name the original segment (or vertex) of the ring that holds ``point``."""
        ring = int(self.ring_of[flat])
        original = self.original[ring]
        n = len(original)
        start = self.kept[ring][self.local[flat]]
        stop = self.kept[ring][(self.local[flat] + 1) % len(self.kept[ring])]
        segments = np.arange(start, stop if stop > start else stop + n) % n
        d, _, _ = _segment_distance(np.broadcast_to(point, (len(segments), 2)),
                                    np.broadcast_to(point, (len(segments), 2)),
                                    original[segments], original[(segments + 1) % n])
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


def _expand(a0, a1, b0, b1):
    """All (i, j) with a0 <= i <= a1 and b0 <= j <= b1, for each row, flattened."""
    offsets = np.arange(_CHUNK)
    i = a0[:, None, None] + offsets[None, :, None]
    j = b0[:, None, None] + offsets[None, None, :]
    valid = (i <= a1[:, None, None]) & (j <= b1[:, None, None])
    i, j = np.broadcast_arrays(i, j)
    return i[valid], j[valid]


def _segment_distance(p0, p1, q0, q1):
    """Distance between segments p0p1 and q0q1 that do not cross, with closest points.

    The minimum is reached at an endpoint of one of them.
    """
    found = [_point_segment(p0, q0, q1), _point_segment(p1, q0, q1),
             _point_segment(q0, p0, p1), _point_segment(q1, p0, p1)]
    distance = np.stack([d for d, _ in found])
    foot = np.stack([f for _, f in found])
    end = np.stack(np.broadcast_arrays(p0, p1, q0, q1))
    k = np.argmin(distance, axis=0)
    rows = np.arange(distance.shape[1])
    from_p = (k < 2)[:, None]
    p = np.where(from_p, end[k, rows], foot[k, rows])
    q = np.where(from_p, foot[k, rows], end[k, rows])
    return distance[k, rows], p, q


def _point_segment(x, a, b):
    ab = b - a
    length2 = (ab * ab).sum(axis=1)
    t = np.clip(((x - a) * ab).sum(axis=1) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    foot = a + t[:, None] * ab
    return np.linalg.norm(x - foot, axis=1), foot
