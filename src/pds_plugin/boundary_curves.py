"""The exact curves a region's boundary was flattened from, and where they came from.

A drawing reader flattens every arc, ellipse and Bézier into chords within its tolerance
(:mod:`pds_plugin.sources.curves`), so :class:`~pds_plugin.Region` itself is polygonal.
The reader can keep the curves beside it as :class:`BoundaryCurves`: every piece is
either an *elliptic* arc ``c + u cos θ + v sin θ`` (any affine image of a circular or
elliptic arc, in the form of :func:`~pds_plugin.sources.curves.elliptic_points`) or a
*cubic* Bézier (lines and quadratic Béziers raised to cubics, exactly), each with the
label of the drawing element it belongs to (the SVG element's id). A point of the
polygonal boundary is then located on its piece (:meth:`BoundaryCurves.locate`), so the
finite-element sinks can put nodes on the true curve (:mod:`pds_plugin.quadratic`) and
name boundaries after the drawing (:mod:`pds_plugin.tags`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from ._checks import check_positive

__all__ = ["BoundaryCurves", "curves_builder", "samples_onto_curves"]

_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(12)
_NEWTON_STEPS = 8
_PANELS = 4
_POLYLINE_POINTS = 64
"""Points per piece of the polyline that gives the first guess of a projection."""


@dataclass(frozen=True, eq=False)
class BoundaryCurves:
    """Exact curve pieces of a region's boundary, with the drawing element of each.

    Build it with :func:`curves_builder`. Pieces are evaluated on the parameter
    ``t`` in [0, 1].

    Attributes
    ----------
    elliptic : (P,) bool ndarray
        True for an elliptic arc, False for a cubic Bézier.
    control : (P, 4, 2) float ndarray
        The Bézier control points (unused for arcs).
    conic : (P, 8) float ndarray
        The arcs' ``cx, cy, ux, uy, vx, vy, start, sweep`` (unused for Béziers).
    source : (P,) int64 ndarray
        Index of each piece's label in :attr:`labels`.
    labels : tuple of str
        The drawing elements' names (an SVG element's id, else its tag and number).
    tolerance : float
        The distance within which the region's boundary follows the curves (the reader's
        flattening tolerance).

    Examples
    --------
    >>> build = curves_builder(1e-3)
    >>> build.arc((0, 0), [[1, 0], [0, 1]], 0.0, np.pi, "top")
    >>> build.line((-1, 0), (1, 0), "base")
    >>> curves = build.done()
    >>> piece, t, distance = curves.locate([[0, 1.0001], [0.5, 0]])
    >>> [curves.labels[s] for s in curves.source[piece]], np.round(t, 6).tolist()
    (['top', 'base'], [0.5, 0.75])
    >>> np.round(distance, 6).tolist()
    [0.0001, 0.0]
    """

    elliptic: np.ndarray
    control: np.ndarray
    conic: np.ndarray
    source: np.ndarray
    labels: tuple
    tolerance: float

    def __len__(self) -> int:
        return len(self.elliptic)

    def point(self, piece, t) -> np.ndarray:
        """Points of the pieces at parameters ``t`` (arrays of the same shape).

        Parameters
        ----------
        piece : (n,) int array_like
        t : (n,) float array_like

        Returns
        -------
        (n, 2) float ndarray
        """
        return self._derivatives(piece, t, 0)

    def arc_midpoint(self, piece, t0, t1) -> np.ndarray:
        """The parameter halfway in arc length between ``t0`` and ``t1`` on each piece.

        Parameters
        ----------
        piece, t0, t1 : (n,) array_like

        Returns
        -------
        (n,) float ndarray

        Examples
        --------
        >>> build = curves_builder(1e-3)
        >>> build.cubic([(0, 0), (0, 0), (0, 0), (3, 0)], "ramp")   # slow start
        >>> curves = build.done()
        >>> t = curves.arc_midpoint([0], [0.0], [1.0])
        >>> np.round(curves.point([0], t), 9).tolist()
        [[1.5, 0.0]]
        """
        piece = np.asarray(piece, dtype=np.int64)
        t0, t1 = np.asarray(t0, dtype=float), np.asarray(t1, dtype=float)
        return self.at_length(piece, t0, t1, 0.5 * self.length(piece, t0, t1))

    def length(self, piece, t0, t1) -> np.ndarray:
        """The arc length of each piece between parameters ``t0`` and ``t1``.

        Parameters
        ----------
        piece, t0, t1 : (n,) array_like

        Returns
        -------
        (n,) float ndarray
            Non-negative, whichever way round ``t0`` and ``t1`` are.
        """
        piece = np.asarray(piece, dtype=np.int64)
        return np.abs(self._length(piece, np.asarray(t0, float), np.asarray(t1, float)))

    def at_length(self, piece, t0, t1, length) -> np.ndarray:
        """The parameter ``length`` along each piece from ``t0`` towards ``t1``.

        Parameters
        ----------
        piece, t0, t1, length : (n,) array_like

        Returns
        -------
        (n,) float ndarray
            Between ``t0`` and ``t1``.
        """
        piece = np.asarray(piece, dtype=np.int64)
        t0, t1 = np.asarray(t0, dtype=float), np.asarray(t1, dtype=float)
        target = np.asarray(length, dtype=float) * np.sign(t1 - t0)
        total = self._length(piece, t0, t1)
        t = t0 + (t1 - t0) * np.divide(target, total, out=np.full(len(t0), 0.5),
                                       where=total != 0)
        for _ in range(_NEWTON_STEPS):
            speed = np.linalg.norm(self._derivatives(piece, t, 1), axis=1)
            step = (self._length(piece, t0, t) - target) / np.where(speed > 0, speed, 1.0)
            t = np.clip(t - step, np.minimum(t0, t1), np.maximum(t0, t1))
        return t

    def locate(self, points, piece=None):
        """The piece nearest each point, the parameter of its nearest point there, and
        the distance.

        Parameters
        ----------
        points : (n, 2) array_like
        piece : (n,) int array_like, optional
            The piece to project each point onto, instead of the nearest one.

        Returns
        -------
        piece : (n,) int64 ndarray
        t : (n,) float ndarray
            In [0, 1].
        distance : (n,) float ndarray
        """
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        if not len(points):
            return np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0)
        if piece is not None:
            return self._project(points, np.asarray(piece, dtype=np.int64))
        # the polylines stray from their curves by up to _sagitta: every piece whose
        # polyline is that much nearer than the nearest one's is a candidate
        shapes = shapely.points(points)
        distance = self._tree.query_nearest(shapes, all_matches=False, return_distance=True)[1]
        point, candidate = self._tree.query(shapes, predicate="dwithin",
                                            distance=distance + 2 * self._sagitta)
        _, t, gap = self._project(points[point], candidate)
        best = np.lexsort((candidate, gap, point))        # nearest first, ties by index
        first = best[np.r_[True, point[best][1:] != point[best][:-1]]]
        return candidate[first], t[first], gap[first]

    def _project(self, points, piece):
        """The nearest point of the given piece to each point: piece, t, distance. Newton
        from the point's angle on a circular arc, else from the nearest point of the
        piece's polyline; a point stops when its step no longer moves it."""
        t = np.empty(len(piece))
        circle = self._circular[piece]
        if circle.any():
            t[circle] = self._circle_parameter(points[circle], piece[circle])
        if not circle.all():
            polyline = self._polylines[piece[~circle]]
            along = shapely.line_locate_point(polyline, shapely.points(points[~circle]),
                                              normalized=True)
            t[~circle] = self._parameter_of(piece[~circle], along)
        active = np.arange(len(piece))
        for _ in range(_NEWTON_STEPS):
            point, first, second = _Jet(self, piece[active])(t[active])
            gap = point - points[active]
            slope = (gap * first).sum(axis=1)
            curvature = (first * first).sum(axis=1) + (gap * second).sum(axis=1)
            step = np.where(curvature > 0, slope / np.where(curvature > 0, curvature, 1), 0)
            moved = np.clip(t[active] - step, 0.0, 1.0)
            still = moved != t[active]
            t[active] = moved
            active = active[still]
            if not len(active):
                break
        distance = np.linalg.norm(_Jet(self, piece)(t, 0) - points, axis=1)
        return piece, t, distance

    @property
    def _circular(self) -> np.ndarray:
        """The arcs of circles: ``u`` and ``v`` orthogonal and of one length (to 1e-12)."""
        cached = self.__dict__.get("_circular_cache")
        if cached is None:
            u, v = self.conic[:, 2:4], self.conic[:, 4:6]
            uu, vv, uv = (u * u).sum(axis=1), (v * v).sum(axis=1), (u * v).sum(axis=1)
            cached = self.elliptic & (np.abs(uu - vv) <= 1e-12 * uu) & (np.abs(uv) <= 1e-12 * uu)
            object.__setattr__(self, "_circular_cache", cached)
        return cached

    def _circle_parameter(self, points, piece) -> np.ndarray:
        """The parameter of the nearest point of circular arcs: the point's angle on the
        arc, or the nearer end where that angle is off it."""
        c = self.conic[piece]
        w = points - c[:, :2]
        theta = np.arctan2((w * c[:, 4:6]).sum(axis=1), (w * c[:, 2:4]).sum(axis=1))
        start, sweep = c[:, 6], c[:, 7]
        turn = np.mod(np.where(sweep >= 0, theta - start, start - theta), 2 * np.pi)
        span = np.abs(sweep)
        beyond = np.where(turn - span < 2 * np.pi - turn, 1.0, 0.0)
        return np.where(turn <= span, turn / np.where(span > 0, span, 1.0), beyond)

    def onto_arcs(self, points):
        """``points`` moved onto the elliptic arc nearest each, where that arc is within
        the tolerance (``tolerance`` with a margin of 1e-9 of it): the nearest point of
        the arc, on it to rounding. Points on other pieces, or farther, stay.

        Parameters
        ----------
        points : (n, 2) array_like

        Returns
        -------
        moved : (n, 2) float ndarray
        on_arc : (n,) bool ndarray
            Which points were moved.

        Examples
        --------
        >>> build = curves_builder(0.01)
        >>> build.arc((0, 0), [[1, 0], [0, 1]], 0.0, np.pi, "top")
        >>> build.line((-1, 0), (1, 0), "base")
        >>> moved, on_arc = build.done().onto_arcs([[0, 0.995], [0.5, 0]])
        >>> np.round(moved, 12).tolist(), on_arc.tolist()
        ([[0.0, 1.0], [0.5, 0.0]], [True, False])
        """
        points = np.array(points, dtype=float).reshape(-1, 2)
        reach = self.tolerance * (1 + 1e-9)
        # a piece within ``reach`` of a point has its polyline within reach + _sagitta:
        # the pieces whose polyline's box is that near are all that can be moved onto
        owner, piece = self._boxes_near(reach).query(shapely.points(points))
        on_arc = np.zeros(len(points), bool)
        if not len(owner):
            return points, on_arc
        _, t, distance = self._project(points[owner], piece)
        best = np.lexsort((piece, distance, owner))        # nearest first, ties by index
        first = best[np.r_[True, owner[best][1:] != owner[best][:-1]]]
        owner, piece, t, distance = owner[first], piece[first], t[first], distance[first]
        move = self.elliptic[piece] & (distance > 0) & (distance <= reach)
        points[owner[move]] = self.point(piece[move], t[move])
        on_arc[owner[move]] = True
        return points, on_arc

    def deviation(self, segments, boundary, step) -> float:
        """How far the curves that bound a region get from ``segments`` (a mesh's
        boundary edges): the largest distance from a point of a piece, probed every
        ``step`` along it, to the nearest segment, over the probes within the tolerance
        of ``boundary`` (the region's boundary segments: parts of pieces inside the
        region, such as the walls of overlapping bodies in their union, are not its
        boundary).

        Parameters
        ----------
        segments, boundary : (m, 2, 2) array_like
        step : float
            The probes' spacing along each piece (arc length).

        Returns
        -------
        float

        Examples
        --------
        >>> build = curves_builder(1e-3)
        >>> build.arc((0, 0), [[1, 0], [0, 1]], 0.0, np.pi / 2, "quarter")
        >>> theta = np.linspace(0, np.pi / 2, 40)                 # within 1e-3 of the arc
        >>> ring = np.column_stack([np.cos(theta), np.sin(theta)])
        >>> boundary = np.stack([ring[:-1], ring[1:]], axis=1)
        >>> chord = [[[1, 0], [0, 1]]]                            # sagitta 1 - cos(pi/4)
        >>> found = build.done().deviation(chord, boundary, 1e-3)
        >>> bool(abs(found - (1 - np.sqrt(0.5))) < 1e-9)
        True
        """
        segments = np.asarray(segments, dtype=float).reshape(-1, 2, 2)
        boundary = np.asarray(boundary, dtype=float).reshape(-1, 2, 2)
        if not (len(segments) and len(boundary)):
            return 0.0
        piece = np.flatnonzero(self._bent)            # straight pieces: the mesh's own
        if not len(piece):                               # deviation measures them
            return 0.0
        counts = np.ceil(self.length(piece, np.zeros(len(piece)), np.ones(len(piece))) / step)
        counts = counts.astype(np.int64) + 2
        owner = np.repeat(piece, counts)
        t = (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)) \
            / np.repeat(counts - 1, counts)
        probes = shapely.points(self.point(owner, t))
        near = shapely.STRtree(shapely.linestrings(boundary)).query(
            probes, predicate="dwithin", distance=self.tolerance * (1 + 1e-9))[0]
        if not len(near):
            return 0.0
        _, distance = shapely.STRtree(shapely.linestrings(segments)).query_nearest(
            probes[np.unique(near)], all_matches=False, return_distance=True)
        return float(distance.max())

    @property
    def _bent(self) -> np.ndarray:
        """The pieces that are not straight: arcs, and cubics whose inner control points
        are off the line of their ends (lines are cubics with them at its thirds)."""
        p = self.control
        chord = p[:, 3] - p[:, 0]
        off = np.abs(chord[:, None, 0] * (p[:, 1:3, 1] - p[:, :1, 1])
                     - chord[:, None, 1] * (p[:, 1:3, 0] - p[:, :1, 0])).max(axis=1)
        scale = np.abs(p).max(axis=(1, 2)) * np.hypot(*chord.T)
        return self.elliptic | (off > 1e-12 * scale)

    # --- evaluation ----------------------------------------------------------------

    def _derivatives(self, piece, t, order: int) -> np.ndarray:
        piece = np.asarray(piece, dtype=np.int64)
        t = np.asarray(t, dtype=float)
        out = np.empty((len(piece), 2))
        arcs = self.elliptic[piece]
        if arcs.any():
            c = self.conic[piece[arcs]]
            theta = c[:, 6] + c[:, 7] * t[arcs]
            cos, sin = np.cos(theta), np.sin(theta)
            if order == 0:
                out[arcs] = c[:, :2] + cos[:, None] * c[:, 2:4] + sin[:, None] * c[:, 4:6]
            elif order == 1:
                out[arcs] = c[:, 7:8] * (-sin[:, None] * c[:, 2:4] + cos[:, None] * c[:, 4:6])
            else:
                out[arcs] = -c[:, 7:8] ** 2 * (cos[:, None] * c[:, 2:4] + sin[:, None] * c[:, 4:6])
        cubic = ~arcs
        if cubic.any():
            p = self.control[piece[cubic]]
            s = t[cubic][:, None]
            if order == 0:
                out[cubic] = ((1 - s) ** 3 * p[:, 0] + 3 * (1 - s) ** 2 * s * p[:, 1]
                              + 3 * (1 - s) * s ** 2 * p[:, 2] + s ** 3 * p[:, 3])
            elif order == 1:
                out[cubic] = 3 * ((1 - s) ** 2 * (p[:, 1] - p[:, 0])
                                  + 2 * (1 - s) * s * (p[:, 2] - p[:, 1])
                                  + s ** 2 * (p[:, 3] - p[:, 2]))
            else:
                out[cubic] = 6 * ((1 - s) * (p[:, 2] - 2 * p[:, 1] + p[:, 0])
                                  + s * (p[:, 3] - 2 * p[:, 2] + p[:, 1]))
        return out

    def _length(self, piece, t0, t1) -> np.ndarray:
        """Arc length from ``t0`` to ``t1`` (Gauss-Legendre on ``_PANELS`` panels; the
        pieces are smooth, but a Bézier's speed may nearly vanish)."""
        total = np.zeros(len(piece))
        width = (t1 - t0) / _PANELS
        for panel in range(_PANELS):
            middle, half = t0 + (panel + 0.5) * width, 0.5 * width
            for node, weight in zip(_GAUSS_NODES, _GAUSS_WEIGHTS):
                speed = np.linalg.norm(self._derivatives(piece, middle + half * node, 1), axis=1)
                total += weight * speed * half
        return total

    # --- locating ------------------------------------------------------------------

    @property
    def _parameters(self) -> np.ndarray:
        return np.linspace(0.0, 1.0, _POLYLINE_POINTS)

    @property
    def _polylines(self) -> np.ndarray:
        cached = self.__dict__.get("_polyline_cache")
        if cached is None:
            count = len(self)
            t = np.tile(self._parameters, count)
            piece = np.repeat(np.arange(count), _POLYLINE_POINTS)
            points = self._derivatives(piece, t, 0).reshape(count, _POLYLINE_POINTS, 2)
            cached = shapely.linestrings(points)
            object.__setattr__(self, "_polyline_cache", cached)
            object.__setattr__(self, "_tree_cache", shapely.STRtree(cached))
        return cached

    @property
    def _tree(self):
        self._polylines
        return self.__dict__["_tree_cache"]

    @property
    def _sagitta(self) -> float:
        """The farthest any piece strays from its polyline (measured at the middles of
        the polyline's segments, with a margin of a half)."""
        cached = self.__dict__.get("_sagitta_cache")
        if cached is None:
            count = len(self)
            grid = self._parameters
            middle = np.tile(0.5 * (grid[1:] + grid[:-1]), count)
            piece = np.repeat(np.arange(count), len(grid) - 1)
            chords = self._polyline_coords
            chord_middle = (0.5 * (chords[:, 1:] + chords[:, :-1])).reshape(-1, 2)
            cached = 1.5 * float(np.linalg.norm(self._derivatives(piece, middle, 0)
                                                - chord_middle, axis=1).max())
            object.__setattr__(self, "_sagitta_cache", cached)
        return cached

    def _boxes_near(self, distance: float):
        """An STRtree of the pieces' polyline boxes grown by ``distance + _sagitta``
        (cached for the last distance asked)."""
        cached = self.__dict__.get("_boxes_cache")
        if cached is None or cached[0] != distance:
            grow = distance + self._sagitta
            low, high = self._polyline_bounds
            boxes = shapely.box(low[:, 0] - grow, low[:, 1] - grow, high[:, 0] + grow,
                                high[:, 1] + grow)
            cached = (distance, shapely.STRtree(boxes))
            object.__setattr__(self, "_boxes_cache", cached)
        return cached[1]

    @property
    def _polyline_bounds(self):
        coords = self._polyline_coords
        return coords.min(axis=1), coords.max(axis=1)

    @property
    def _polyline_coords(self) -> np.ndarray:
        """(P, _POLYLINE_POINTS, 2): the polylines' points."""
        cached = self.__dict__.get("_coords_cache")
        if cached is None:
            cached = shapely.get_coordinates(self._polylines).reshape(len(self), -1, 2)
            object.__setattr__(self, "_coords_cache", cached)
        return cached

    @property
    def _fractions(self) -> np.ndarray:
        """(P, _POLYLINE_POINTS): the fraction of each polyline's length at its points."""
        cached = self.__dict__.get("_fractions_cache")
        if cached is None:
            steps = np.linalg.norm(np.diff(self._polyline_coords, axis=1), axis=2)
            cumulative = np.concatenate([np.zeros((len(self), 1)), np.cumsum(steps, axis=1)],
                                        axis=1)
            total = np.where(cumulative[:, -1] > 0, cumulative[:, -1], 1.0)
            cached = cumulative / total[:, None]
            object.__setattr__(self, "_fractions_cache", cached)
        return cached

    def _parameter_of(self, piece, along) -> np.ndarray:
        """The parameter at a fraction ``along`` of each piece's polyline length."""
        fraction = self._fractions[piece]
        along = np.asarray(along, dtype=float)
        right = np.clip((fraction < along[:, None]).sum(axis=1), 1, _POLYLINE_POINTS - 1)
        rows = np.arange(len(piece))
        left_at, right_at = fraction[rows, right - 1], fraction[rows, right]
        width = right_at - left_at
        share = np.clip((along - left_at) / np.where(width > 0, width, 1), 0, 1)
        return self._parameters[right - 1] + share / (_POLYLINE_POINTS - 1)


class _Jet:
    """A curve's point and first two derivatives at parameters ``t`` on fixed pieces
    (the pieces' numbers gathered once, the angles' sines shared by the three)."""

    def __init__(self, curves: BoundaryCurves, piece):
        piece = np.asarray(piece, dtype=np.int64)
        self.size = len(piece)
        self.arcs = curves.elliptic[piece]
        self.conic = curves.conic[piece[self.arcs]]
        self.cubic = ~self.arcs
        self.control = curves.control[piece[self.cubic]]

    def __call__(self, t, orders=2):
        """(point, first, second) at ``t``; the point alone if ``orders`` is 0."""
        out = np.empty((3, self.size, 2))
        if len(self.conic):
            c = self.conic
            theta = c[:, 6] + c[:, 7] * t[self.arcs]
            cos, sin = np.cos(theta)[:, None], np.sin(theta)[:, None]
            u, v, sweep = c[:, 2:4], c[:, 4:6], c[:, 7:8]
            out[0, self.arcs] = c[:, :2] + cos * u + sin * v
            if orders:
                out[1, self.arcs] = sweep * (-sin * u + cos * v)
                out[2, self.arcs] = -sweep ** 2 * (cos * u + sin * v)
        if len(self.control):
            p = self.control
            s = t[self.cubic][:, None]
            out[0, self.cubic] = ((1 - s) ** 3 * p[:, 0] + 3 * (1 - s) ** 2 * s * p[:, 1]
                                  + 3 * (1 - s) * s ** 2 * p[:, 2] + s ** 3 * p[:, 3])
            if orders:
                out[1, self.cubic] = 3 * ((1 - s) ** 2 * (p[:, 1] - p[:, 0])
                                          + 2 * (1 - s) * s * (p[:, 2] - p[:, 1])
                                          + s ** 2 * (p[:, 3] - p[:, 2]))
                out[2, self.cubic] = 6 * ((1 - s) * (p[:, 2] - 2 * p[:, 1] + p[:, 0])
                                          + s * (p[:, 3] - 2 * p[:, 2] + p[:, 1]))
        return out if orders else out[0]


class _Builder:
    """Collects pieces for :class:`BoundaryCurves` (see :func:`curves_builder`): single
    pieces as rows of numbers, polylines as blocks of arrays, joined by ``done()``."""

    def __init__(self, tolerance):
        self.tolerance = check_positive(tolerance, "tolerance")
        self.cubics: list[tuple] = []         # (8 control coordinates, source)
        self.arcs: list[tuple] = []           # (cx, cy, ux, uy, vx, vy, start, sweep, source)
        self.blocks: list[tuple] = []         # ((k, 4, 2) controls, source) of polylines
        self.labels: dict[str, int] = {}

    def _source(self, label) -> int:
        return self.labels.setdefault(str(label), len(self.labels))

    def line(self, start, end, label) -> None:
        """A straight segment (as the cubic with control points at thirds)."""
        (x0, y0), (x1, y1) = start, end
        if (x0, y0) != (x1, y1):
            self.cubics.append((x0, y0, (2 * x0 + x1) / 3, (2 * y0 + y1) / 3,
                                (x0 + 2 * x1) / 3, (y0 + 2 * y1) / 3, x1, y1,
                                self._source(label)))

    def polyline(self, points, label) -> None:
        """The straight segments through ``points`` (k, 2), each a line (none repeated)."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        start, end = points[:-1], points[1:]
        keep = np.any(start != end, axis=1)
        start, end = start[keep], end[keep]
        if len(start):
            control = np.stack([start, (2 * start + end) / 3, (start + 2 * end) / 3, end], axis=1)
            self.blocks.append((control, self._source(label)))

    def quadratic(self, control, label) -> None:
        """A quadratic Bézier (raised to the cubic of the same curve)."""
        p = np.asarray(control, dtype=float)
        self.cubic([p[0], (p[0] + 2 * p[1]) / 3, (2 * p[1] + p[2]) / 3, p[2]], label)

    def cubic(self, control, label) -> None:
        """A cubic Bézier from its four control points."""
        control = np.asarray(control, dtype=float).reshape(8)
        self.cubics.append((*control.tolist(), self._source(label)))

    def arc(self, center, radii, start, sweep, label) -> None:
        """``center + u cos θ + v sin θ``, θ from ``start`` over ``sweep``; ``radii``
        holds u and v as columns."""
        radii = np.asarray(radii, dtype=float).reshape(2, 2)
        self.arcs.append((*np.asarray(center, dtype=float).tolist(), *radii[:, 0].tolist(),
                          *radii[:, 1].tolist(), float(start), float(sweep),
                          self._source(label)))

    def done(self) -> BoundaryCurves | None:
        """The curves collected, or None if there are none."""
        cubics = np.array(self.cubics, dtype=float).reshape(-1, 9)
        arcs = np.array(self.arcs, dtype=float).reshape(-1, 9)
        control = [cubics[:, :8].reshape(-1, 4, 2)] + [block for block, _ in self.blocks]
        count = sum(len(c) for c in control)
        if not count + len(arcs):
            return None
        source = np.concatenate([cubics[:, 8].astype(np.int64)]
                                + [np.full(len(b), s, np.int64) for b, s in self.blocks]
                                + [arcs[:, 8].astype(np.int64)])
        return BoundaryCurves(
            np.r_[np.zeros(count, bool), np.ones(len(arcs), bool)],
            np.concatenate(control + [np.zeros((len(arcs), 4, 2))]),
            np.concatenate([np.zeros((count, 8)), arcs[:, :8]]),
            source, tuple(self.labels), self.tolerance)


def curves_builder(tolerance) -> _Builder:
    """A collector of exact pieces: call ``line``, ``quadratic``, ``cubic`` or ``arc``
    with each piece's label, then ``done()`` for the :class:`BoundaryCurves`.

    Parameters
    ----------
    tolerance : float
        How far the region's polygonal boundary may be from the curves (the reader's
        flattening tolerance).

    Returns
    -------
    builder

    Raises
    ------
    ArgumentError
        If ``tolerance`` is not a positive number.

    Examples
    --------
    >>> build = curves_builder(0.01)
    >>> build.quadratic([(0, 0), (1, 1), (2, 0)], "hump")
    >>> build.done().labels
    ('hump',)
    """
    return _Builder(tolerance)


def samples_onto_curves(curves: BoundaryCurves, rings, owners, ring_xy, lower, upper):
    """Boundary samples moved onto the elliptic arcs they were placed within the
    tolerance of, and the polygon they lie on: the sampler's hook for regions with
    exact curves (see :func:`pds_plugin.sampling.poisson_disc`).

    A sample placed on a chord of a flattened arc moves onto the arc, by at most the
    flattening's tolerance. A move is undone where it would bring two samples closer than
    ``lower`` (if they were not already), or lengthen a chord between consecutive samples
    past ``upper`` (or past its length, if it was longer): the sampling's distances stay
    within the bounds it chose them by. The region is then refined through the samples: each ring
    keeps its vertices (on the curves) and gets the moved samples inserted in order, so
    the samples are on its boundary and it stays within the tolerance of the curves.

    Parameters
    ----------
    curves : BoundaryCurves
    rings : list of (k, 2) ndarray
        The region's rings (:attr:`pds_plugin.Region.rings`).
    owners : sequence of (int, int or None)
        ``(component, hole)`` of each ring (:attr:`pds_plugin.Region.ring_owners`).
    ring_xy : list of (m, 2) ndarray
        Each ring's samples, in order along it, on its segments.
    lower : float or callable
        The smallest distance between two samples that the sampling keeps, or a function
        giving the radius at each of an (n, 2) array of points (a graded sampling's field:
        two samples then stay ``min`` of their radii apart).
    upper : float
        The longest chord between consecutive samples that the sampling keeps.

    Returns
    -------
    ring_xy : list of (m, 2) ndarray
        The samples, those moved onto the arcs.
    geometry : shapely MultiPolygon or None
        The region through them, or None if no sample moved.

    Examples
    --------
    >>> from shapely.geometry import Point
    >>> build = curves_builder(1e-3)
    >>> build.arc((0, 0), [[1, 0], [0, 1]], 0.0, np.pi, "top")
    >>> build.arc((0, 0), [[1, 0], [0, 1]], np.pi, np.pi, "bottom")
    >>> theta = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    >>> ring = np.column_stack([np.cos(theta), np.sin(theta)])      # on the circle
    >>> chord = (ring + np.roll(ring, -1, axis=0))[::4] / 2          # sagitta 3e-3 > 1e-3
    >>> samples = (0.95 * ring + 0.05 * np.roll(ring, -1, axis=0))[::4]
    >>> moved, geometry = samples_onto_curves(build.done(), [ring], [(0, None)], [samples],
    ...                                       0.5, 1.0)
    >>> bool(np.allclose(np.hypot(*moved[0].T), 1, rtol=0, atol=1e-15))
    True
    >>> len(geometry.geoms[0].exterior.coords) - 1                  # 40 vertices, 10 samples
    50
    """
    before = [np.asarray(xy, dtype=float) for xy in ring_xy]
    sizes = np.array([len(xy) for xy in before])
    flat_before = np.concatenate(before)
    on_arcs, flat_on = curves.onto_arcs(flat_before)            # all rings in one search
    if not flat_on.any():
        return before, None
    ring_of = np.repeat(np.arange(len(before)), sizes)
    first = np.cumsum(sizes) - sizes
    nxt = np.arange(len(flat_before)) + 1
    nxt[first + sizes - 1] = first
    apart = lower if callable(lower) else (lambda xy: np.full(len(xy), float(lower)))
    chord_before = np.hypot(*(flat_before[nxt] - flat_before).T)
    close_before = _close_pairs(flat_before, apart(flat_before), flat_on)
    for _ in range(len(flat_before)):
        flat_after = np.where(flat_on[:, None], on_arcs, flat_before)
        radius = apart(flat_after)
        chord = np.hypot(*(flat_after[nxt] - flat_after).T)
        bad = ((chord < np.minimum(chord_before, np.minimum(radius, radius[nxt])))
               | (chord > np.maximum(chord_before, upper)))
        new = _close_pairs(flat_after, radius, flat_on)
        new = new[~np.isin(new, close_before)]
        n = len(flat_before)
        ends = np.concatenate([np.flatnonzero(bad), nxt[bad], new // n, new % n])
        ends = ends[flat_on[ends]]
        if not len(ends):
            break
        flat_on[ends] = False                    # those samples stay where they were
    if not flat_on.any():
        return before, None
    flat_after = np.where(flat_on[:, None], on_arcs, flat_before)
    moved = np.split(flat_after, first[1:])
    refined, ring_id = _through(rings, flat_before, flat_after, ring_of)
    linear = shapely.linearrings(refined, indices=ring_id)
    component = np.array([c for c, _ in owners])
    hole = np.array([h is not None for _, h in owners])
    shells_first = np.lexsort((hole, component))
    polygons = shapely.polygons(linear[shells_first], indices=component[shells_first])
    return moved, shapely.MultiPolygon(list(polygons))


def _close_pairs(points, radius, moving) -> np.ndarray:
    """The pairs (i < j) of ``points`` closer than the smaller of their radii with ``i``
    or ``j`` among the ``moving`` ones, as ``i * n + j`` (n points), sorted."""
    from scipy.spatial import cKDTree

    pairs = cKDTree(points).query_pairs(float(radius.max()), output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    gap = np.hypot(*(points[i] - points[j]).T)
    keep = (moving[i] | moving[j]) & (gap < np.minimum(radius[i], radius[j]))
    return np.sort(i[keep] * len(points) + j[keep])


def _through(rings, old, new, ring_of):
    """Every ring (k, 2) with the points ``new`` inserted at the places along it of
    ``old`` (points on its segments; ``ring_of`` names each one's ring), replacing the
    vertices they fall on: the refined rings' points, one after the other, and the ring
    of each point."""
    count = np.array([len(ring) for ring in rings])
    ring_id = np.repeat(np.arange(len(rings)), count)
    vertices = np.concatenate(rings)
    closed = shapely.linearrings(vertices, indices=ring_id)
    length = shapely.length(closed)
    at = shapely.line_locate_point(closed[ring_of], shapely.points(old))
    at = np.where(at >= length[ring_of], 0.0, at)
    cum = np.concatenate([np.r_[0.0, np.cumsum(np.hypot(*np.diff(np.vstack([r, r[:1]]),
                                                                  axis=0).T))[:-1]]
                          for r in rings])
    # a vertex is replaced by a point within 1e-12 of its ring's length along it: the
    # points just before and after each vertex along its ring, from one sort of both
    place = np.concatenate([cum, at])
    ring = np.concatenate([ring_id, ring_of])
    is_point = np.r_[np.zeros(len(cum), bool), np.ones(len(at), bool)]
    order = np.lexsort((place, ring))
    rank = np.arange(len(order))
    previous = np.maximum.accumulate(np.where(is_point[order], rank, -1))
    following = np.minimum.accumulate(np.where(is_point[order], rank, len(order))[::-1])[::-1]
    gap = np.full(len(order), np.inf)
    for neighbour in (previous, following):
        found = (neighbour >= 0) & (neighbour < len(order))
        other = order[np.where(found, neighbour, 0)]
        same = found & (ring[other] == ring[order])
        gap = np.where(same, np.minimum(gap, np.abs(place[other] - place[order])), gap)
    far = np.empty(len(order), bool)
    far[order] = gap > 1e-12 * length[ring[order]]
    kept = far[:len(cum)]
    where = np.concatenate([cum[kept], at])
    points = np.concatenate([vertices[kept], new])
    ring = np.concatenate([ring_id[kept], ring_of])
    order = np.lexsort((where, ring))           # stable: a vertex before a point at its place
    return points[order], ring[order]
