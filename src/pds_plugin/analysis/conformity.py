"""How a mesh's outline follows its region's boundary.

The boundary samples of a mesh lie on the region's rings. Taken in order along a ring
(the region on the left), two consecutive samples ``a -> b`` span a **chord**; the part of
the ring from ``a`` to ``b`` is the chord's **arc**, and the polygon whose rings are the
chords is the **sampled boundary polygon** Q. On a polygonal boundary whose corners are
samples every arc is straight and Q is the region; on curved input Q differs from it only
by the chords' sagitta: a *sliver* between a chord and an arc bulging away from Q (region
that Q misses), or a *bulge* where the arc bends into Q (Q reaches outside the region).

A mesh **conforms** when every chord is a mesh edge and no edge of the mesh's boundary
touches an interior sample. Its outline **is the sampled boundary** when, moreover, its
boundary edges are exactly the chords, in their direction, and its triangles, all
counter-clockwise, add up to the area of Q: the triangles then tile Q (a 2-chain of the
plane is fixed by its boundary), checked combinatorially, with no tolerance but the area
sum's rounding.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from .._certificate_kernels import segment_distances, signed_areas
from ..boundary_sampling import star_shaped_from
from .feature import point_segment

__all__ = ["BoundaryReport", "SampledBoundary", "boundary_report", "PROBES_PER_ALPHA"]

PROBES_PER_ALPHA = 50
"""Probes per length alpha along the curves whose distance is not exact: the boundary
deviation is then measured to alpha / 100 (the distance is 1-Lipschitz)."""

ON_BOUNDARY_TOL = 1e-9    # relative to alpha: how far a boundary sample may lie off its ring
ON_BOUNDARY_ROUNDING = 4  # float64 spacings at the region's coordinates: at least that far
_CUTS_PER_CHORD = 8       # a piece beyond a chord may be cut every 1/8 of the chord at least
AREA_TOL = 1e-9           # relative to the region's area: rounding of area sums
_MAX_NAMED = 3            # located examples per kind of problem
FACE_BLOCK = 65536        # triangles per block of per-triangle transients (peak memory)


@dataclass(frozen=True)
class BoundaryReport:
    """How the outline of a mesh follows the region's boundary.

    Attributes
    ----------
    conforming : bool
        Every pair of consecutive boundary samples is a mesh edge, and no edge of the
        mesh's boundary touches an interior sample.
    sampled_outline : bool
        The union of the triangles is exactly the sampled boundary polygon Q (see the
        module documentation): the mesh deviates from the region by the chords' sagitta
        and nothing else.
    boundary_deviation : float
        Hausdorff distance between the mesh's boundary and the region's, / alpha: exact
        (0) along chords on straight boundary, elsewhere measured every alpha / 50.
    outside_area_ratio, missing_area_ratio : float
        Mesh area outside the region, and region area outside the mesh, / region area.
    problems : tuple of str
        What breaks conformity, located in region coordinates.
    """

    conforming: bool
    sampled_outline: bool
    boundary_deviation: float
    outside_area_ratio: float
    missing_area_ratio: float
    problems: tuple[str, ...]


def boundary_report(mesh, sampled: "SampledBoundary | None" = None) -> BoundaryReport:
    """Measure how ``mesh`` (a PlanarMesh) follows its region's boundary.

    Parameters
    ----------
    mesh : PlanarMesh
    sampled : SampledBoundary, optional
        The chords of the mesh's boundary samples, when already computed.

    Returns
    -------
    BoundaryReport

    Examples
    --------
    >>> import numpy as np, shapely
    >>> from shapely.geometry import box
    >>> import pds_plugin as pds
    >>> square = box(0, 0, 1, 1)
    >>> triangles = shapely.get_parts(shapely.constrained_delaunay_triangles(square))
    >>> corners = shapely.get_coordinates(shapely.get_exterior_ring(triangles)).reshape(-1, 4, 2)[:, :3]
    >>> vertices, faces = np.unique(corners.reshape(-1, 2), axis=0, return_inverse=True)
    >>> faces = faces.reshape(-1, 3)[:, ::-1]          # shapely's triangles run clockwise
    >>> region = pds.Region.from_shapely(square)
    >>> mesh = pds.PlanarMesh(vertices, faces, np.ones(4, bool), region, 1.0)
    >>> report = boundary_report(mesh)
    >>> report.conforming, report.sampled_outline, report.boundary_deviation
    (True, True, 0.0)
    """
    if sampled is None:
        sampled = SampledBoundary(mesh.region, mesh.vertices, mesh.on_boundary, mesh.alpha)
    return _Conformity(mesh, sampled).report()


class SampledBoundary:
    """The boundary samples of a point set in order along the region's rings, their
    chords and arcs (see the module documentation).

    Parameters
    ----------
    region : Region
    points : (N, 2) float ndarray
    on_boundary : (N,) bool ndarray
        The samples placed on the boundary; each is put on its nearest boundary segment.
    alpha : float
    faces : (F, 3) int ndarray, optional
        The mesh's triangles: the third corner of the triangle on a chord may see a part
        of the region beyond it that neither chord end sees (:func:`_seen_in_parts`).
    radius : callable, optional
        A graded mesh's radius field: of two bounds on the coverage beyond a chord, the
        smaller relative to it at its place is kept.

    Attributes
    ----------
    a, b : (C,) int ndarray
        Sample indices of each chord, ``a -> b`` along the ring.
    ring : (C,) int ndarray
        The ring (index into ``region.rings``) of each chord.
    straight : (C,) bool ndarray
        Chords whose arc holds no ring vertex: the chord is a piece of a boundary segment.
    arc_length : (C,) float ndarray
        The length of each chord's arc.
    segment_of : (N,) int ndarray
        The boundary segment (index into ``region.segments``) each boundary sample lies
        on, -1 for the others.
    samples_per_ring : (R,) int ndarray
    offset : float
        The largest distance of a boundary sample from its ring.
    tol : float
        How far a boundary sample may lie off its ring: ``ON_BOUNDARY_TOL`` x alpha, or
        the rounding of the region's coordinates (``ON_BOUNDARY_ROUNDING`` spacings)
        where that is more (a region far from the origin).
    """

    def __init__(self, region, points, on_boundary, alpha, faces=None, radius=None):
        self.region, self.points, self.alpha = region, np.asarray(points, float), float(alpha)
        self.faces = faces
        self.radius = radius
        self.tol = max(ON_BOUNDARY_TOL * self.alpha, ON_BOUNDARY_ROUNDING * region.resolution)
        rings = region.rings
        sizes = np.array([len(r) for r in rings])
        segments = region.segments
        vector = segments[:, 1] - segments[:, 0]
        length = np.hypot(vector[:, 0], vector[:, 1])
        ring_of = np.repeat(np.arange(len(rings)), sizes)
        first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        along = np.cumsum(length) - length                 # start of each segment along all rings
        self.perimeter = np.add.reduceat(length, first)
        vertex_at = along                                  # ring vertex k starts segment k
        # each boundary sample on its nearest segment, as a position along all rings
        index = np.flatnonzero(on_boundary)
        tree = shapely.STRtree(shapely.linestrings(segments))
        (which, nearest), distance = tree.query_nearest(shapely.points(self.points[index]),
                                                        all_matches=False, return_distance=True)
        segment = np.empty(len(index), np.int64)
        segment[which] = nearest
        off = np.empty(len(index))
        off[which] = distance
        self.offset = float(off.max(initial=0.0))
        self.segment_of = np.full(len(self.points), -1, np.int64)
        self.segment_of[index] = segment
        t = np.einsum("ij,ij->i", self.points[index] - segments[segment, 0], vector[segment])
        t = np.clip(t / length[segment] ** 2, 0.0, 1.0) * length[segment]
        position = vertex_at[segment] + t
        sample_ring = ring_of[segment]
        order = np.lexsort((position, sample_ring))
        self.sample, position, sample_ring = index[order], position[order], sample_ring[order]
        self.samples_per_ring = np.bincount(sample_ring, minlength=len(rings))
        ring_first = np.concatenate([[0], np.cumsum(self.samples_per_ring)[:-1]])
        following = np.arange(len(self.sample)) + 1
        wraps = following == (ring_first + self.samples_per_ring)[sample_ring]
        following[wraps] = ring_first[sample_ring[wraps]]
        chord = np.flatnonzero(self.samples_per_ring[sample_ring] >= 2)
        self.a, self.b = self.sample[chord], self.sample[following[chord]]
        self.ring = sample_ring[chord]
        self.arc_length = position[following[chord]] - position[chord]
        self.arc_length[self.arc_length <= 0] += self.perimeter[self.ring[self.arc_length <= 0]]
        # ring vertices strictly inside each chord's arc, in order along it
        has_chords = self.samples_per_ring[ring_of] >= 2
        vertex = np.flatnonzero(has_chords)
        vring = ring_of[vertex]
        j = np.searchsorted(position, vertex_at[vertex], side="right") - 1
        before = j < ring_first[vring]                     # before the ring's first sample
        j[before] = (ring_first + self.samples_per_ring - 1)[vring[before]]
        key = vertex_at[vertex] + np.where(before, self.perimeter[vring], 0.0)
        chord_of_sorted = np.full(len(self.sample), -1)
        chord_of_sorted[chord] = np.arange(len(chord))
        arc_chord = chord_of_sorted[j]
        xy = region.segments[vertex, 0]
        tol = self.tol
        apart = ((np.hypot(*(xy - self.points[self.a[arc_chord]]).T) > tol)
                 & (np.hypot(*(xy - self.points[self.b[arc_chord]]).T) > tol))
        arc = np.lexsort((key[apart], arc_chord[apart]))
        self.arc_chord = arc_chord[apart][arc]
        self.arc_xy = xy[apart][arc]
        into = segments[vertex, 0] - segments[np.where(vertex == first[vring], vertex + sizes[vring],
                                                       vertex) - 1, 0]
        turn = into[:, 0] * vector[vertex, 1] - into[:, 1] * vector[vertex, 0]
        self.arc_turns_left = (turn >= -1e-12 * np.hypot(*into.T) * length[vertex])[apart][arc]
        self.straight = np.bincount(self.arc_chord, minlength=len(self.a)) == 0

    @cached_property
    def arc_offset(self) -> np.ndarray:
        """Signed distance of each arc vertex from its chord's line (> 0: into Q)."""
        a, b = self.points[self.a[self.arc_chord]], self.points[self.b[self.arc_chord]]
        ab, av = b - a, self.arc_xy - a
        return (ab[:, 0] * av[:, 1] - ab[:, 1] * av[:, 0]) / np.hypot(ab[:, 0], ab[:, 1])

    @cached_property
    def sliver(self) -> np.ndarray:
        """Chords whose arc bulges away from Q and with it bounds a convex sliver of region
        that Q misses (every arc vertex on the far side of the chord, turning towards it)."""
        tol = self.tol
        n = len(self.a)
        beyond = np.bincount(self.arc_chord, self.arc_offset < -tol, minlength=n) > 0
        inward = np.bincount(self.arc_chord, self.arc_offset > tol, minlength=n) > 0
        bends = np.bincount(self.arc_chord, ~self.arc_turns_left, minlength=n) > 0
        return beyond & ~inward & ~bends

    @cached_property
    def mixed(self) -> np.ndarray:
        """Chords whose arc reaches beyond the chord but is not a convex sliver: it crosses
        the chord, or bends both ways beyond it."""
        tol = self.tol
        beyond = np.bincount(self.arc_chord, self.arc_offset < -tol, minlength=len(self.a)) > 0
        return beyond & ~self.sliver

    @cached_property
    def _pieces(self):
        """For each mixed chord: the largest distance from its pieces beyond the chord to a
        chord end they see, where, their total area, and whether each piece is convex and
        holds a chord end (see :meth:`_chord_pieces`)."""
        found = [self._chord_pieces(k) for k in np.flatnonzero(self.mixed)]
        if not found:
            return np.zeros(0), np.zeros((0, 2)), np.zeros(0), np.zeros(0, bool)
        gap, where, area, seen = zip(*found)
        return np.array(gap), np.array(where), np.array(area), np.array(seen)

    def _chord_pieces(self, k):
        """The arc of chord k cut where it crosses the chord's line: each piece beyond the
        line is a polygon from a crossing (or a chord end) along the arc to the next. A
        piece star-shaped from a chord end it holds (the end on the inner side of every
        edge's line: a convex piece, or one with a shallow kink) is seen whole from it;
        the distance to an end is convex, so its farthest point from the ends it is
        star-shaped from is one of its vertices, or with both ends where the chord's
        bisector crosses its boundary (each side of the bisector is star-shaped from its
        own end too: a segment from that end to a point of it stays on that side). A
        piece that no chord end sees whole is cut into parts seen from the ends and the
        apex of the chord's triangle (:func:`_seen_in_parts`), and where that gives a
        smaller bound it is kept; a piece with no such cut is not certified. (A Python
        loop, over the few chords whose arc bends both ways.)"""
        on = self.arc_chord == k
        a, b = self.points[self.a[k]], self.points[self.b[k]]
        apex = self._apexes.get(int(k))
        xy = np.concatenate([[a], self.arc_xy[on], [b]])
        height = np.concatenate([[0.0], self.arc_offset[on], [0.0]])
        tol = self.tol
        height[np.abs(height) <= tol] = 0.0
        along = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])

        def crossing(i):                    # where segment i crosses the chord's line
            t = height[i] / (height[i] - height[i + 1])
            return xy[i] + t * (xy[i + 1] - xy[i]), along[i] + t * (along[i + 1] - along[i])

        pieces, current = [], None          # each piece's points and their arc lengths
        for i in range(len(xy) - 1):
            if height[i] >= 0 > height[i + 1]:                  # the arc leaves Q's side
                current = [crossing(i)]
            if current is not None and height[i + 1] < 0:
                current.append((xy[i + 1], along[i + 1]))
            if current is not None and height[i + 1] >= 0:     # back on the chord's line
                current.append(crossing(i))
                points, lengths = zip(*current)
                pieces.append((np.array(points), np.array(lengths)))
                current = None
        gap, where, area, seen = 0.0, a, 0.0, True
        for piece, piece_along in pieces:
            area += abs(float((piece[:, 0] * np.roll(piece[:, 1], -1)
                               - piece[:, 1] * np.roll(piece[:, 0], -1)).sum()) / 2)
            ends = [e for e, at in ((a, piece[0]), (b, piece[-1]))
                    if np.allclose(e, at, rtol=0, atol=tol) and star_shaped_from(piece, e, tol)]
            seers = self._seers.get(int(k), [])
            bounds = [] if len(ends) == 2 else [
                _seen_in_parts(piece, a, b, apex, tol, self._relative),
                _seen_from_samples(piece, a, b, seers, tol, self._relative),
                _along_the_arc(piece, piece_along, along[-1], a, b, self._relatives)]
            if ends:
                candidates = list(piece)
                if len(ends) == 2:              # where the bisector of ab crosses the arc
                    side = (piece - (a + b) / 2) @ (b - a)
                    for i in np.flatnonzero((side[:-1] < 0) & (side[1:] >= 0)):
                        t = side[i] / (side[i] - side[i + 1])
                        candidates.append(piece[i] + t * (piece[i + 1] - piece[i]))
                candidates = np.array(candidates)
                distance = np.min([np.hypot(*(candidates - e).T) for e in ends], axis=0)
                j = int(np.argmax(distance))
                bounds.append((float(distance[j]), candidates[j]))
            bounds = [bound for bound in bounds if bound is not None]
            if not bounds:
                seen = False
                continue
            bound = min(bounds, key=self._relative)             # the better proof
            if self._relative(bound) > self._relative((gap, where)):
                gap, where = bound
        return gap, where, area, seen

    def _relative(self, bound) -> float:
        """A coverage bound (distance, place), relative to the radius field there."""
        distance, place = bound
        return distance if self.radius is None else distance / float(
            self.radius(np.asarray(place, float)[None])[0])

    @cached_property
    def _apexes(self) -> dict:
        """Chord index -> the third corner of the mesh's triangle on it, for the mixed
        chords that are mesh edges (empty without ``faces``)."""
        return {k: seers[0][0] for k, seers in self._seers.items()}

    @cached_property
    def _seers(self) -> dict:
        """:meth:`_seers_of` the mixed chords."""
        return self._seers_of(np.flatnonzero(self.mixed))

    def _seers_of(self, chords) -> dict:
        """Chord index -> the samples of Q that see the chord (or a stretch of it) whole
        through the mesh's triangles, for those of ``chords`` that are mesh edges (empty
        without ``faces``): ``(point, lo, hi)``, the stretch from ``lo`` to ``hi`` along
        the chord from ``a``. The apex c of the triangle abc on the chord sees all of it;
        the third corner d of the triangle on ac (or cb) sees the points y of ab in its
        angle at d (:func:`_stretch_seen`): the segment dy crosses the edge between
        those triangles, and so stays in their union."""
        if self.faces is None or not len(chords):
            return {}
        faces = np.asarray(self.faces, np.int64)
        n = len(self.points)
        keys = np.concatenate([edge_keys(faces[:, i], faces[:, (i + 1) % 3], n) for i in range(3)])
        third = np.concatenate([faces[:, (i + 2) % 3] for i in range(3)])
        order = np.argsort(keys, kind="stable")
        keys, third = keys[order], third[order]

        def across(u, v, other):
            """The third corner of the triangle on edge uv that is not ``other``."""
            key = edge_keys(np.array([u]), np.array([v]), n)[0]
            lo, hi = np.searchsorted(keys, key), np.searchsorted(keys, key, side="right")
            found = [int(t) for t in third[lo:hi] if t != other]
            return found[0] if len(found) == 1 and hi - lo == 2 else None

        seers = {}
        for k in chords:
            a, b = int(self.a[k]), int(self.b[k])
            key = edge_keys(np.array([a]), np.array([b]), n)[0]
            lo, hi = np.searchsorted(keys, key), np.searchsorted(keys, key, side="right")
            if hi == lo:                     # not a mesh edge
                continue
            c = int(third[lo])
            pa, pb, pc = self.points[a], self.points[b], self.points[c]
            found = [(pc, 0.0, float(np.hypot(*(pb - pa))))]
            for e, d in ((a, across(a, c, b)), (b, across(c, b, a))):
                if d is not None:
                    stretch = _stretch_seen(self.points[d], self.points[e], pc, pa, pb)
                    if stretch is not None:
                        found.append((self.points[d], *stretch))
            seers[int(k)] = found
        return seers

    @property
    def uncertain(self) -> np.ndarray:
        """Chords beyond which some region is not certified to see a sample (see
        :meth:`_chord_pieces`)."""
        uncertain = np.zeros(len(self.a), bool)
        uncertain[np.flatnonzero(self.mixed)[~self._pieces[3]]] = True
        return uncertain

    def arcs(self, chords: np.ndarray):
        """The polylines ``a, arc vertices..., b`` of ``chords`` (bool mask): (K, 2, 2)
        segments and the chord of each."""
        xy, c = self._arc_points(chords)
        same = c[1:] == c[:-1]
        return np.stack([xy[:-1][same], xy[1:][same]], axis=1), c[:-1][same]

    def _arc_points(self, chords: np.ndarray):
        """The points ``a, arc vertices..., b`` of ``chords`` (bool mask), chord by chord
        in order along each arc, and the chord of each point."""
        if not chords.any():                # no arcs (every chord on straight boundary)
            return np.zeros((0, 2)), np.zeros(0, np.int64)
        pick = chords[self.arc_chord]
        c = np.concatenate([np.flatnonzero(chords), self.arc_chord[pick], np.flatnonzero(chords)])
        rank = np.concatenate([np.zeros(chords.sum()), 1 + np.arange(pick.sum()),
                               np.full(chords.sum(), np.inf)])
        xy = np.concatenate([self.points[self.a[chords]], self.arc_xy[pick],
                             self.points[self.b[chords]]])
        order = np.lexsort((rank, c))
        return xy[order], c[order]

    def loop_areas(self):
        """Q's area outside the region and the region's area outside Q, from the loops
        ``a``, arc, ``b``, back to ``a`` of the chords; None when the loops are not proven
        apart. Q is taken to be a polygon: its chords wind 0 or 1 times about every point
        (as they do about the outline of a mesh that tiles Q, see the module documentation).

        The indicator of the region is the sum of the winding numbers of its rings (each
        with the region on its left), so it is the winding number of Q's chords plus the
        sum of those of the loops (a chord and its arc add up to the loop, the chord's own
        terms cancelling). An arc (a piece of a simple ring) whose vertices all lie
        strictly on one side of its chord's line makes a simple loop: beyond the chord,
        it turns counter-clockwise (winding number 1 inside, 0 outside), on Q's side
        clockwise (-1 inside); an arc whose vertices all lie on the line is a piece of
        segment from ``a`` to ``b`` and encloses nothing. When, moreover, no two loops
        share interior points, region minus Q is, point by point, 1 inside the loops
        beyond their chords, -1 inside those on Q's side, 0 elsewhere: the areas are the
        sums of the loops' areas, exactly up to the rounding of the samples onto the rings
        and of the shoelace. None when an arc has vertices on both sides of its chord's
        line, or on it and off it, or when two loops overlap (the region's boundary
        passing within a sagitta of another chord).

        Examples
        --------
        >>> import pds_plugin as pds
        >>> from shapely.geometry import Point
        >>> disc = Point(0, 0).buffer(1.0, quad_segs=4)            # 16 vertices
        >>> region = pds.Region.from_shapely(disc.difference(Point(0, 0).buffer(0.5, quad_segs=4)))
        >>> at = region.segments[::2, 0]                           # samples on every other vertex
        >>> s = SampledBoundary(region, at, np.ones(len(at), bool), 0.5)
        >>> outside, missing = s.loop_areas()
        >>> Q = s.polygon()
        >>> overlay = Q.difference(region.geometry).area, region.geometry.difference(Q).area
        >>> bool(outside > 0 and missing > 0 and np.allclose((outside, missing), overlay))
        True
        """
        offset, n = self.arc_offset, len(self.a)
        beyond = np.bincount(self.arc_chord, offset < 0, minlength=n) > 0
        into = np.bincount(self.arc_chord, offset > 0, minlength=n) > 0
        on_line = np.bincount(self.arc_chord, offset == 0, minlength=n) > 0
        if (beyond & into).any() or (on_line & (beyond | into)).any():
            return None
        xy, chord = self._arc_points(beyond | into)
        if len(chord):
            loop = np.concatenate([[0], np.cumsum(chord[1:] != chord[:-1])])
            loops = shapely.polygons(shapely.linearrings(xy, indices=loop))
            first, second = shapely.STRtree(loops).query(loops)
            pair = first < second
            if shapely.relate_pattern(loops[first[pair]], loops[second[pair]], "T********").any():
                return None
        return -self.loop_area(into), self.loop_area(beyond)

    def sliver_gap(self):
        """The largest distance from a point of the region beyond the chords to a chord end
        it sees, and where. Over a convex sliver it peaks at an arc vertex, where the
        chord's bisector crosses the arc, or at the chord's midpoint (the vertices of the
        sliver's pieces in the two Voronoi cells of the chord's ends); the pieces of mixed
        arcs come from :meth:`_chord_pieces`. With a radius field, the largest relative
        to r at its place (the distance over r there), so that a graded certificate
        dividing by r at the place returned gets the largest ratio, not the ratio at the
        largest distance."""
        gap, at = 0.0, np.zeros(2)
        mixed_gap, mixed_at, _, _ = self._pieces
        if len(mixed_gap):
            k = int(np.argmax(self._relatives(mixed_gap, mixed_at)))
            gap, at = float(mixed_gap[k]), mixed_at[k]
        if not self.sliver.any():
            return gap, at
        segments, chord = self.arcs(self.sliver)
        a, b = self.points[self.a[chord]], self.points[self.b[chord]]
        ab = b - a
        side = np.einsum("kij,kj->ki", segments - ((a + b) / 2)[:, None], ab)   # g / 2 at both ends
        crossing = (side[:, 0] < 0) & (side[:, 1] >= 0)
        s = side[crossing]
        cross_xy = segments[crossing, 0] + (s[:, :1] / (s[:, :1] - s[:, 1:])) * \
            (segments[crossing, 1] - segments[crossing, 0])
        candidates = np.concatenate([segments[:, 1], cross_xy,
                                     (self.points[self.a[self.sliver]] + self.points[self.b[self.sliver]]) / 2])
        ends_of = np.concatenate([chord, chord[crossing], np.flatnonzero(self.sliver)])
        pa, pb = self.points[self.a[ends_of]], self.points[self.b[ends_of]]
        distance = np.minimum(np.hypot(*(candidates - pa).T), np.hypot(*(candidates - pb).T))
        relative = self._relatives(distance, candidates)
        for k, bound in self._slivers_seen_from_samples(ends_of, relative).items():
            relative[ends_of == k] = -np.inf             # a better proof for this sliver
            if self._relative(bound) > self._relative((gap, at)):
                gap, at = bound
        k = int(np.argmax(relative))
        if relative[k] > self._relative((gap, at)):
            gap, at = float(distance[k]), candidates[k]
        return gap, at

    def _slivers_seen_from_samples(self, chord, relative) -> dict:
        """Chord index -> a smaller bound (distance, place) on the coverage of its convex
        sliver than its ends give, for the slivers whose ends leave a point of them
        uncovered (``relative``: the bounds from the ends at their candidate points, of
        chord ``chord``): the sliver cut into parts each seen from a chord end or from
        a sample of Q that sees the chord through the mesh (the apex of its triangle,
        the far corners of the triangles beside it: :func:`_seen_from_samples`). At a
        steep grading the chords on arcs grow long, and the point of a sliver farthest
        from both ends can lie close to the apex (a flange's section at L = 0.45: 1.22 r
        from the ends, 0.59 r from the apex)."""
        worst = np.full(len(self.a), -np.inf)
        np.maximum.at(worst, chord, relative)
        uncovered = np.flatnonzero(worst > (1.0 if self.radius is not None else self.alpha))
        better = {}
        for k, seers in self._seers_of(uncovered).items():
            on = self.arc_chord == k
            a, b = self.points[self.a[k]], self.points[self.b[k]]
            bound = _seen_from_samples(np.concatenate([[a], self.arc_xy[on], [b]]), a, b,
                                       seers, self.tol, self._relative)
            if bound is not None and self._relative(bound) < worst[k]:
                better[k] = bound
        return better

    def _relatives(self, distance, places) -> np.ndarray:
        """Coverage bounds (distances at places), relative to the radius field there (the
        distances themselves without one)."""
        distance = np.asarray(distance, float)
        return distance if self.radius is None else distance / self.radius(
            np.asarray(places, float).reshape(-1, 2))

    def sliver_area(self) -> float:
        """Total area of the region beyond the chords: the convex slivers and the pieces
        of mixed arcs."""
        return self.loop_area(self.sliver) + float(self._pieces[2].sum())

    def loop_area(self, chords: np.ndarray) -> float:
        """Signed area enclosed by the closed polylines ``a``, arc vertices..., ``b``, back
        to ``a`` of ``chords`` (bool mask): positive for arcs beyond their chord. Each
        loop's shoelace is taken about its own ``a`` (about the origin, coordinates far
        from it would cancel a thin sliver to nothing).

        Examples
        --------
        >>> import pds_plugin as pds
        >>> from shapely.geometry import Point
        >>> disc = pds.Region.from_shapely(Point(0, 0).buffer(1.0, quad_segs=4))  # 16 vertices
        >>> at = disc.segments[::2, 0]                     # samples on every other vertex
        >>> s = SampledBoundary(disc, at, np.ones(len(at), bool), 0.5)
        >>> bool(np.isclose(s.loop_area(~s.straight), disc.area - s.area()))
        True
        """
        if not chords.any():
            return 0.0
        segments, chord = self.arcs(chords)
        closing = np.stack([self.points[self.b[chords]], self.points[self.a[chords]]], axis=1)
        start = self.points[self.a[np.concatenate([chord, np.flatnonzero(chords)])]]
        segments = np.concatenate([segments, closing]) - start[:, None]
        cross = segments[:, 0, 0] * segments[:, 1, 1] - segments[:, 0, 1] * segments[:, 1, 0]
        return float(cross.sum() / 2)

    def polygon(self):
        """The sampled boundary polygon Q (rings of fewer than 3 samples left out)."""
        rings = np.split(self.points[self.sample], np.cumsum(self.samples_per_ring)[:-1])
        owners = self.region.ring_owners
        parts = []
        for c, component in enumerate(self.region.geometry.geoms):
            mine = [rings[r] for r, (owner, _) in enumerate(owners) if owner == c]
            if len(mine[0]) < 3:
                continue
            parts.append(Polygon(mine[0], [h for h in mine[1:] if len(h) >= 3]))
        polygon = MultiPolygon(parts)
        return polygon if polygon.is_valid else shapely.make_valid(polygon)

    def area(self) -> float:
        """Signed area of Q from its chords (shoelace): exteriors count positive, holes negative.
        Taken about a point of Q (the sum over closed rings does not depend on it): about
        the origin, coordinates far from it would cancel to nothing."""
        origin = self.points[self.a].min(axis=0) if len(self.a) else np.zeros(2)
        a, b = self.points[self.a] - origin, self.points[self.b] - origin
        return float((a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum() / 2)


class _Conformity:
    """The checks of :func:`boundary_report` on one mesh."""

    def __init__(self, mesh, sampled: SampledBoundary):
        self.mesh, self.sampled = mesh, sampled
        self.points, self.alpha = sampled.points, sampled.alpha
        self.n = len(self.points)
        self.boundary_edges = mesh.boundary_edges
        self.problems = []

    def report(self) -> BoundaryReport:
        conforming = self._conforming()
        sampled_outline = conforming and self._sampled_outline()
        outside, missing = self._areas_off(sampled_outline)
        return BoundaryReport(
            conforming=conforming, sampled_outline=sampled_outline,
            boundary_deviation=self._deviation() / self.alpha,
            outside_area_ratio=outside, missing_area_ratio=missing,
            problems=tuple(self.problems))

    def _areas_off(self, sampled_outline):
        """Mesh area outside the region and region area outside the mesh, / region area.
        A mesh whose outline is Q (its triangles tile Q) needs no overlay when the loops
        between chords and arcs are proven apart (:meth:`SampledBoundary.loop_areas`);
        otherwise shapely's overlay measures both."""
        area = self.mesh.region.area
        found = self.sampled.loop_areas() if sampled_outline else None
        if found is not None:
            return max(0.0, found[0]) / area, max(0.0, found[1]) / area
        outline, region = self.mesh.outline, self.mesh.region.geometry
        return (float(shapely.difference(outline, region).area / area),
                float(shapely.difference(region, outline).area / area))

    def _say(self, count, what, where):
        say_located(self.problems, count, what, where)

    def _conforming(self) -> bool:
        s, mesh = self.sampled, self.mesh
        far = s.offset > s.tol
        if far:
            self.problems.append(f"samples marked on the boundary lie up to "
                                 f"{s.offset / self.alpha:.3g} alpha off it")
        owners = mesh.region.ring_owners
        for r in np.flatnonzero(s.samples_per_ring < 3):
            self.problems.append(f"the {_ring_name(owners[r])} holds {s.samples_per_ring[r]} "
                                 "boundary samples, too few to be a ring of the mesh")
        edges = self.mesh.edges
        edges = edges[mesh.on_boundary[edges[:, 0]] & mesh.on_boundary[edges[:, 1]]]
        missing = ~_isin(edge_keys(s.a, s.b, self.n), edge_keys(edges[:, 0], edges[:, 1], self.n))
        middle = (self.points[s.a[missing]] + self.points[s.b[missing]]) / 2
        self._say(int(missing.sum()), "pairs of consecutive boundary samples are not joined by "
                  "a mesh edge", middle)
        inner = ~mesh.on_boundary[self.boundary_edges]
        dents = inner.any(axis=1)
        self._say(int(dents.sum()), "mesh-boundary edges end at interior samples",
                  self.points[np.where(inner[:, 0], self.boundary_edges[:, 0],
                                       self.boundary_edges[:, 1])[dents]])
        return not (far or (s.samples_per_ring < 3).any() or missing.any() or dents.any())

    def _sampled_outline(self) -> bool:
        s = self.sampled
        edges = self.boundary_edges
        extra = ~_isin(edges[:, 0] * self.n + edges[:, 1], s.a * self.n + s.b)
        self._say(int(extra.sum()), "mesh-boundary edges are not chords between consecutive "
                  "boundary samples", self.points[edges[extra]].mean(axis=1) if extra.any() else ())
        faces = np.asarray(self.mesh.faces, np.int64).reshape(-1, 3)
        signed = signed_areas(self.points, faces)
        clockwise = signed <= 0
        self._say(int(clockwise.sum()), "triangles are clockwise or flat",
                  self.points[faces[clockwise]].mean(axis=1) if clockwise.any() else ())
        overlap = abs(signed.sum() - s.area()) > AREA_TOL * self.mesh.region.area
        if overlap:
            self.problems.append(f"the triangles' area {signed.sum():.9g} differs from the area "
                                 f"{s.area():.9g} of the polygon through the boundary samples: "
                                 "triangles overlap")
        return not (extra.any() or clockwise.any() or overlap) and len(edges) == len(s.a)

    def _deviation(self) -> float:
        """Hausdorff distance between the mesh's and the region's boundaries; exact (0)
        along chords on straight boundary that are mesh-boundary edges, probed elsewhere."""
        s, edges = self.sampled, self.boundary_edges
        if not len(edges):
            return np.inf
        edge_key = edge_keys(edges[:, 0], edges[:, 1], self.n)
        exact = _isin(edge_keys(s.a, s.b, self.n), edge_key) & s.straight
        exact_keys = edge_keys(s.a[exact], s.b[exact], self.n)
        mesh_side = ~_isin(edge_key, exact_keys)
        rings_probed = np.repeat(s.samples_per_ring < 2, [len(r) for r in self.mesh.region.rings])
        region_side = np.concatenate([s.arcs(~exact)[0], self.mesh.region.segments[rings_probed]])
        mesh_segments = self.points[edges]
        step = self.alpha / PROBES_PER_ALPHA
        return max(_farthest(mesh_segments[mesh_side], self.mesh.region.segments, step),
                   _farthest(region_side, mesh_segments, step))


def _farthest(curves, targets, step) -> float:
    """The largest distance from a point of the (k, 2, 2) segments ``curves`` to the
    nearest of ``targets``, to ``step / 2`` below.

    Each curve is cut in halves until every piece is settled: its distance cannot exceed
    the farthest point found by more than ``step / 2``. Bounds settle a piece from its
    ends p and q, at distances d(p) and d(q) from their nearest targets s(p) and s(q):
    the distance is 1-Lipschitz, so it stays under ``(d(p) + d(q) + |pq|) / 2``; and the
    distance to one segment is convex along a line, so it stays under
    ``max(d(p), |q s(p)|)`` and ``max(d(q), |p s(q)|)``, and, s(p) taken up to any point
    m of pq and s(q) from there, under ``max(d(p), d(q), |m s(p)|, |m s(q)|)``: with m
    where pq passes an end of s(p) (a piece across the vertex two targets share, along a
    straight boundary cut into segments, is settled at once instead of halved down to
    ``step``). A piece no longer than ``step`` is always settled.
    """
    if not len(curves):
        return 0.0

    def nearest(xy):
        """GEOS's point-to-segment distance, and the segment, on a grid of cells of side
        alpha; the few points not settled within 8 rings of cells by shapely's STRtree."""
        found, index = segment_distances(xy, targets, step * PROBES_PER_ALPHA, 8)
        far = np.isnan(found)
        if far.any():
            tree = shapely.STRtree(shapely.linestrings(targets))
            (_, index[far]), found[far] = tree.query_nearest(
                shapely.points(xy[far]), all_matches=False, return_distance=True)
        return found, index

    p, q = curves[:, 0], curves[:, 1]
    (dp, dq), (sp, sq) = (a.reshape(-1, 2).T for a in nearest(curves.reshape(-1, 2)))
    farthest = float(max(dp.max(), dq.max()))
    while len(p):
        lipschitz = (dp + dq + np.hypot(*(q - p).T)) / 2
        along_sp = np.maximum(dp, point_segment(q, targets[sp, 0], targets[sp, 1])[0])
        along_sq = np.maximum(dq, point_segment(p, targets[sq, 0], targets[sq, 1])[0])
        bound = np.minimum(lipschitz, np.minimum(along_sp, along_sq))
        open_ = bound > farthest + step / 2
        if open_.any():
            split = _split_bound(p[open_], q[open_], dp[open_], dq[open_],
                                 targets[sp[open_]], targets[sq[open_]])
            open_[open_] = split > farthest + step / 2
        p, q, dp, dq, sp, sq = (a[open_] for a in (p, q, dp, dq, sp, sq))
        if not len(p):
            break
        middle = (p + q) / 2
        dm, sm = nearest(middle)
        farthest = max(farthest, float(dm.max()))
        p, q = np.concatenate([p, middle]), np.concatenate([middle, q])
        dp, dq = np.concatenate([dp, dm]), np.concatenate([dm, dq])
        sp, sq = np.concatenate([sp, sm]), np.concatenate([sm, sq])
    return farthest


def _split_bound(p, q, dp, dq, at_p, at_q) -> np.ndarray:
    """:func:`_farthest`'s bound on pieces pq whose ends' nearest segments are ``at_p``
    and ``at_q`` ((k, 2, 2)), split where pq comes nearest an end of ``at_p`` (the
    better of its two ends)."""
    ends = np.maximum(dp, dq)
    bound = np.full(len(p), np.inf)
    for end in (0, 1):
        m = point_segment(at_p[:, end], p, q)[1]
        split = np.maximum(point_segment(m, at_p[:, 0], at_p[:, 1])[0],
                           point_segment(m, at_q[:, 0], at_q[:, 1])[0])
        bound = np.minimum(bound, np.maximum(ends, split))
    return bound


def _seen_in_parts(piece: np.ndarray, a: np.ndarray, b: np.ndarray, apex, tol: float,
                   measure=lambda bound: bound[0]):
    """A bound on the coverage of a piece of region beyond the chord ab (its arc running
    forward along the chord) that no chord end sees whole: the arc bends both ways (a
    shallow kink, as where a plane crosses a tessellation's seam). The piece is cut at
    arc vertices into up to three parts: one star-shaped from a (if the piece holds a),
    one seen whole from ``apex`` (the third corner of the mesh's triangle on ab, or None)
    and one star-shaped from b (if it holds b). Without an apex the cut runs straight
    across to the chord; with one, along the ray from the apex, and the middle part with
    the apex is star-shaped from it. Returns the largest distance from a point of the
    piece to the sample that sees its part, and where, for the best cut; None when no
    cut works (or the arc turns back along the chord, where a cut would leave the piece).

    Examples
    --------
    >>> kinked = np.array([[0, 0], [1, -0.1], [1.2, -0.05], [1.4, -0.1], [2, 0]])
    >>> _seen_in_parts(kinked, kinked[0], kinked[-1], None, 1e-12)  # cut at (1.2, -0.05)
    (1.2010412149464313, array([ 1.2 , -0.05]))
    >>> round(_seen_in_parts(kinked, kinked[0], kinked[-1], np.array([1.0, 0.9]), 1e-12)[0], 3)
    1.005
    """
    strip = _along_chord(piece, a, b, tol)
    if strip is None:
        return None
    direction, along, holds_a, holds_b = strip
    last = len(piece) - 1
    cut = _cuts(piece, a, direction, along, apex)

    best = None
    for i in range(last + 1):                   # the part seen from a: up to vertex i
        if cut[i] is None:
            continue
        first = np.concatenate([piece[:i + 1], [cut[i]]])
        if i > 0 and not (holds_a and star_shaped_from(first, a, tol)):
            continue
        for j in range(i, last + 1):             # the part seen from b: from vertex j
            if cut[j] is None:
                continue
            second = np.concatenate([[cut[j]], piece[j:]])
            if j < last and not (holds_b and star_shaped_from(second, b, tol)):
                continue
            parts = ([(first, a)] if i > 0 else []) + ([(second, b)] if j < last else [])
            if j > i:                            # the middle, seen from the apex
                middle = np.concatenate([[cut[i]], piece[i:j + 1], [cut[j]]])
                if apex is None or not star_shaped_from(
                        np.concatenate([piece[i:j + 1], [apex]]), apex, tol):
                    continue
                parts.append((middle, apex))
            bound = max((_reach(part, seer) for part, seer in parts), key=measure)
            if best is None or measure(bound) < measure(best):
                best = bound
    return best


def _along_chord(piece, a, b, tol):
    """``(direction, along, holds_a, holds_b)`` of a piece beyond the chord ab: the unit
    direction of ab, how far along it each arc vertex lies, and whether the piece starts
    at a and ends at b; None where the arc turns back along the chord or leaves its span
    (a cut across to the chord would leave the piece)."""
    length = np.hypot(*(b - a))
    direction = (b - a) / length
    along = (piece - a) @ direction
    if np.any(np.diff(along) <= 0) or along[0] < -tol or along[-1] > length + tol:
        return None
    return (direction, along, np.allclose(piece[0], a, rtol=0, atol=tol),
            np.allclose(piece[-1], b, rtol=0, atol=tol))


def _cuts(piece, a, direction, along, apex) -> list:
    """Where a cut of the piece at each arc vertex meets the chord's line: straight across
    without an apex, along the ray from the apex with one (None where that ray leaves the
    strip of the vertex's two arc edges, and could cross the arc, or misses the chord)."""
    def height(p):
        return direction[0] * (p[1] - a[1]) - direction[1] * (p[0] - a[0])

    cuts = []
    for k, point in enumerate(piece):
        if apex is None or height(point) == 0:
            cuts.append(a + along[k] * direction)
            continue
        t = height(apex) / (height(apex) - height(point))
        at = apex + t * (point - apex)
        x = (at - a) @ direction
        lo, hi = along[max(k - 1, 0)], along[min(k + 1, len(piece) - 1)]
        cuts.append(at if lo <= x <= hi else None)
    return cuts


def _stretch_seen(d, e, c, a, b):
    """The stretch ``(lo, hi)`` (along ab from a) of the chord ab that the corner d of the
    mesh's triangle on edge ec (e one of a, b; c the apex of the triangle abc) sees
    through the two triangles: the points y of ab in d's closed angle between the rays to
    e and to c. Such a y lies across the line ec from d, so the segment dy crosses that
    line inside the angle, on the edge ec: dy runs in triangle ecd, then in abc. None
    when d is not across ec from the chord or sees no stretch.

    Examples
    --------
    >>> a, b, c = np.array([0.0, 0.0]), np.array([2.0, 0.0]), np.array([1.0, 1.0])
    >>> _stretch_seen(np.array([0.5, 2.0]), a, c, a, b)   # up to where the ray dc meets ab
    (0.0, 1.5)
    >>> _stretch_seen(np.array([0.0, 1.5]), a, c, a, b)   # all of it
    (0.0, 2.0)
    >>> _stretch_seen(np.array([1.5, 0.5]), a, c, a, b) is None   # not across ac
    True
    """
    def cross(u, v):
        return float(u[0] * v[1] - u[1] * v[0])

    f = b if np.array_equal(e, a) else a     # the chord's other end, across ec from d
    if cross(c - e, d - e) * cross(c - e, f - e) >= 0:
        return None                          # d not strictly across ec from the chord
    length = float(np.hypot(*(b - a)))
    direction = (b - a) / length
    lo, hi = 0.0, length
    for ray, other in ((e, c), (c, e)):        # y on the side of the ray d->ray where other is
        sign = np.sign(cross(ray - d, other - d))
        c0, c1 = sign * cross(ray - d, a - d), sign * cross(ray - d, direction)
        if c1 > 0:
            lo = max(lo, -c0 / c1)
        elif c1 < 0:
            hi = min(hi, -c0 / c1)
        elif c0 < 0:
            return None
    return (float(lo), float(hi)) if lo < hi else None


def _along_the_arc(piece: np.ndarray, along: np.ndarray, total: float, a: np.ndarray,
                   b: np.ndarray, relatives):
    """A coverage bound (distance, place) for a piece beyond chord ab whose arc is a
    graph over the chord (its points' projections onto ab advance along it), or None.

    A point y of such a piece lies between the chord's line and the arc point p straight
    across from it, so the segment yp stays in the piece, and from p the arc, which is
    the region's boundary, leads to a chord end: y is at most |h| + min(s, S - s) from a
    sample along a path in the region (h the arc's offset from the chord's line at p, s
    the arc length from a to p, ``along``, of S, ``total``). That is linear between the
    arc's vertices: its largest value (relative to the radius field: ``relatives`` of
    the distances and places) is at one of them or where s = S / 2. It holds where the
    piece is not star-shaped from a chord end: a flattened B-spline bending a hair the
    other way just past the end (a held-out STEP vase: 0.04 from its end, the point was
    given the far end's 4.6).

    Where the piece reaches a chord end along the chord, the chord (the piece's edge)
    leads there too, from the point c of its line across from p: y at t from c is within
    min(t + u, h - t + w) of a sample (u = |c a| or |c b|, w = min(s, S - s)), so within
    the least of u + h, w + h and (h + u + w) / 2. Those are linear between the arc's
    vertices, the places where s = S / 2 and where c passes the chord's middle: over each
    such stretch the least of their largest values at its ends bounds it, taken relative
    to the smaller r at those ends. The better of the two bounds is returned (a thin
    wedge of an OpenCASCADE vase's section, its arc bending at a 190° vertex the chord's
    end cannot see past: 1.036 r along the arc, 0.997 r with the chord)."""
    ab = b - a
    length2 = float(ab @ ab)
    if length2 == 0 or np.any(np.diff((piece - a) @ ab) < 0):
        return None
    length = np.sqrt(length2)
    d = piece - a
    offset = np.abs(d[:, 0] * ab[1] - d[:, 1] * ab[0]) / length
    across = d @ ab / length                     # c's distance from a along the chord
    # the stretches' ends in order: the arc's vertices, and between them where s = S / 2
    # and where c passes the chord's middle (all four are linear along an arc edge)
    edge, step = [], []
    for i in range(len(piece) - 1):
        cuts = sorted((middle - values[i]) / (values[i + 1] - values[i])
                      for values, middle in ((along, total / 2), (across, length / 2))
                      if values[i] < middle < values[i + 1])
        edge += [i] * (1 + len(cuts))
        step += [0.0] + cuts
    edge, step = np.array(edge, np.int64), np.array(step)
    places, lengths, heights, feet = (_on_edges(v, edge, step)
                                      for v in (piece, along, offset, across))
    w = np.minimum(lengths, total - lengths)
    arc = heights + w
    relative = relatives(arc, places)
    k = int(np.argmax(relative))
    gaps = [float(np.hypot(*(piece[0] - a))), float(np.hypot(*(piece[-1] - b)))]
    near = 1e-12 * length
    if min(gaps) > near:                         # it reaches neither end along the chord
        return float(arc[k]), places[k]
    # each stretch cut in _SUBDIVISIONS parts (the four are linear along it), so that the
    # smaller r at a part's ends is close to r inside it
    edge = np.repeat(np.arange(len(places) - 1), _SUBDIVISIONS)
    step = np.tile(np.linspace(0.0, 1.0, _SUBDIVISIONS + 1)[:-1], len(places) - 1)
    places, lengths, heights, feet = (_on_edges(v, edge, step)
                                      for v in (places, lengths, heights, feet))
    w = np.minimum(lengths, total - lengths)
    u = np.minimum(np.where((gaps[0] <= near) & (feet >= 0), feet + gaps[0], np.inf),
                   np.where((gaps[1] <= near) & (feet <= length), length - feet + gaps[1],
                            np.inf))

    def largest(values):                         # over each part: at one of its ends
        return np.maximum(values[:-1], values[1:])

    bound = np.minimum(np.minimum(largest(u + heights), largest(heights + w)),
                       largest((heights + u + w) / 2))
    inverse = relatives(np.ones(len(places)), places)      # 1 / r (1 without a field)
    at = np.arange(len(bound)) + (inverse[1:] > inverse[:-1])   # its end of smaller r
    ratio = bound * inverse[at]
    j = int(np.argmax(ratio))
    if ratio[j] < relative[k]:
        return float(bound[j]), places[at[j]]
    return float(arc[k]), places[k]


_SUBDIVISIONS = 16
"""Parts of each stretch of :func:`_along_the_arc`'s bound with the chord."""


def _on_edges(values, edge, step) -> np.ndarray:
    """``values`` ((n,) or (n, 2), along a polyline) at the fractions ``step`` of its
    edges ``edge``, then its last value as it is."""
    step = step.reshape((-1,) + (1,) * (values.ndim - 1))
    return np.concatenate([values[edge] + step * (values[edge + 1] - values[edge]),
                           values[-1:]])


def _seen_from_samples(piece: np.ndarray, a: np.ndarray, b: np.ndarray, seers, tol: float,
                       measure=lambda bound: bound[0]):
    """A bound on the coverage of a piece of region beyond the chord ab (its arc running
    forward along the chord), cut straight across to the chord at arc vertices into parts
    each seen whole from one sample: a (the first part, if the piece holds a), b (the
    last, if it holds b), or a sample ``(point, lo, hi)`` of ``seers`` on Q's side that
    sees the stretch of the chord from ``lo`` to ``hi`` along it from a through Q. A part
    W whose base on the chord lies in the stretch of such a sample s is seen from s when
    the polygon of s and W (s, then W without its base) is star-shaped from s: it is W
    and the triangle of s over the base, which s sees, so it lies in D. A part may also
    be reached from a chord end e along a path: along the chord to the piece's end s
    next to e (e itself if the piece holds it, else where the arc crosses the chord),
    then to an arc vertex p that s sees (the piece from s to p is star-shaped from s);
    if the part is star-shaped from p, every point x of it is at most
    |es| + |sp| + |px| from e along a path through D (docs/conforming.md, "Routes
    around a kink"). Returns the largest such distance from a point of the piece to the
    sample that reaches its part, and
    where, minimised over the cuts (by dynamic programming over the arc vertices,
    ``measure`` of the worst part); None when no cut works or the arc turns back along
    the chord.

    Examples
    --------
    >>> kinked = np.array([[0, 0], [1, -0.1], [1.2, -0.05], [1.4, -0.1], [2, 0]])
    >>> a, b = kinked[0], kinked[-1]
    >>> _seen_from_samples(kinked, a, b, [], 1e-12)        # cut at (1.2, -0.05)
    (1.2010412149464313, array([ 1.2 , -0.05]))
    >>> seer = (np.array([1.2, 0.8]), 0.0, 2.0)             # a sample of Q seeing all of ab
    >>> round(_seen_from_samples(kinked, a, b, [seer], 1e-12)[0], 3)   # it sees the bump
    0.967
    >>> hidden = np.array([[0, 0], [0.6, -0.05], [0.8, -0.02], [1.0, -0.08], [1.4, -0.1], [3, 0]])
    >>> _seen_from_samples(hidden, hidden[0], hidden[-1], [], 1e-12)   # 2.2 in straight lines
    (1.6031219541881399, array([ 1.4, -0.1]))
    """
    piece = _subdivided(piece, np.hypot(*(b - a)) / _CUTS_PER_CHORD)
    strip = _along_chord(piece, a, b, tol)
    if strip is None:
        return None
    direction, along, holds_a, holds_b = strip
    foot = a + along[:, None] * direction
    last = len(piece) - 1
    above = [(point, lo, hi) for point, lo, hi in seers
             if direction[0] * (point[1] - a[1]) - direction[1] * (point[0] - a[0]) > tol]

    # whether the piece's end next to a (b) sees arc vertex m: the run of the piece from
    # that end to m, closed by the perpendicular to the chord, is star-shaped from it
    sees_from_end = {
        0: [m == 0 or star_shaped_from(np.concatenate([piece[:m + 1], [foot[m]]]), piece[0], tol)
            for m in range(last + 1)],
        last: [m == last or star_shaped_from(np.concatenate([[foot[m]], piece[m:]]), piece[last], tol)
               for m in range(last + 1)]}

    def part_bound(i, j):
        """The best bound of the part from arc vertex i to j over the routes reaching it."""
        part = np.concatenate([[foot[i]], piece[i:j + 1], [foot[j]]])
        bounds = [_reach(part, point) for point, lo, hi in above
                  if lo <= along[i] and along[j] <= hi
                  and star_shaped_from(np.concatenate([[point], part]), point, tol)]
        reached = {}           # arc vertex m -> lengths of paths to it from a chord end
        for end, start, pivots in ([(a, 0, range(j + 1))] if i == 0 else []) + (
                [(b, last, range(i, last + 1))] if j == last else []):
            along_chord = float(np.hypot(*(piece[start] - end)))
            for m in pivots:
                if sees_from_end[start][m]:
                    reached.setdefault(m, []).append(
                        along_chord + float(np.hypot(*(piece[m] - piece[start]))))
        for m, lengths in reached.items():
            if star_shaped_from(part, piece[m], tol):
                distance, at = _reach(part, piece[m])
                bounds += [(distance + length, at) for length in lengths]
        return min(bounds, key=measure) if bounds else None

    best = [None] * (last + 1)
    best[0] = (0.0, piece[0])
    for j in range(1, last + 1):
        for i in range(j):
            if best[i] is None:
                continue
            bound = part_bound(i, j)
            if bound is None:
                continue
            worst = max(best[i], bound, key=measure)
            if best[j] is None or measure(worst) < measure(best[j]):
                best[j] = worst
    return best[last]


def _subdivided(piece: np.ndarray, step: float) -> np.ndarray:
    """``piece`` with points added along its edges, at most ``step`` apart, so that a
    cut may fall inside a long edge: a piece from a crossing to a chord end whose one arc
    vertex is farthest from the chord had no cut but that vertex, which left the whole
    edge beyond it to the far end (a flange's notch, 1.26 alpha; halfway along it the
    edge is 0.6 alpha from the end). Points on an edge change neither the piece nor its
    star tests.

    Examples
    --------
    >>> _subdivided(np.array([[0.0, 0.0], [1.0, -0.1], [4.0, 0.0]]), 1.0).round(3).tolist()
    [[0.0, 0.0], [0.5, -0.05], [1.0, -0.1], [1.75, -0.075], [2.5, -0.05], [3.25, -0.025], [4.0, 0.0]]
    """
    edges = np.diff(piece, axis=0)
    counts = np.maximum(np.ceil(np.hypot(*edges.T) / step), 1).astype(np.int64)
    edge = np.repeat(np.arange(len(edges)), counts)
    t = (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)) / counts[edge]
    return np.vstack([piece[edge] + t[:, None] * edges[edge], piece[-1:]])


def _reach(points: np.ndarray, seer: np.ndarray) -> tuple:
    """The largest distance from ``seer`` to ``points``, and the point at it."""
    distance = np.hypot(*(points - seer).T)
    k = int(np.argmax(distance))
    return float(distance[k]), points[k]


def say_located(problems: list, count: int, what: str, where) -> None:
    """Append "``count`` ``what``, at (x, y), ..." to ``problems`` (the first few places of
    ``where``), if ``count`` is not 0.

    Examples
    --------
    >>> problems = []
    >>> say_located(problems, 4, "gaps", np.arange(8.0).reshape(4, 2))
    >>> problems
    ['4 gaps, at (0, 1), (2, 3), (4, 5) ...']
    """
    if count:
        places = ", ".join(point_text(p) for p in where[:_MAX_NAMED])
        problems.append(f"{count} {what}, at {places}{' ...' if count > _MAX_NAMED else ''}")


def _isin(values, among) -> np.ndarray:
    """``np.isin(values, among)`` for integer arrays, from one sort of ``among`` (numpy's
    own costs several times more on the few hundred keys of a patch)."""
    among = np.sort(among.ravel())
    if not len(among):
        return np.zeros(values.shape, bool)
    return among[np.minimum(np.searchsorted(among, values), len(among) - 1)] == values


def edge_keys(u, v, n) -> np.ndarray:
    """Undirected edge keys: one integer per edge (u, v) of ``n`` points, the same for
    (v, u).

    Examples
    --------
    >>> edge_keys(np.array([2, 0]), np.array([0, 2]), 5).tolist()
    [2, 2]
    """
    return np.minimum(u, v) * n + np.maximum(u, v)


def _ring_name(owner) -> str:
    component, hole = owner
    return f"outline of component {component}" if hole is None else f"hole {hole} of component {component}"


def point_text(point) -> str:
    """A point as the messages locate it: ``(x, y)`` to 4 significant digits.

    Examples
    --------
    >>> point_text((1.234567, -0.5))
    '(1.235, -0.5)'
    """
    return f"({float(point[0]):.4g}, {float(point[1]):.4g})"
