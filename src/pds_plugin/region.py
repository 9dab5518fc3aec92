"""The planar region to mesh: validated shapely geometry plus its 3D frame, and the facts
about it that the layers above share (its rings and their owners, turning angles, the
one 2D -> 3D lift)."""

from __future__ import annotations

from collections.abc import Sequence
from functools import cached_property

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from ._checks import check_flag, check_instance
from .errors import ArgumentError, ArgumentTypeError, RegionError

__all__ = ["Region", "lift", "plane_label", "turning_angles", "require_region", "check_tolerance",
           "check_scale", "source_deviation"]


class Region:
    """A planar region: one or several polygons with holes, in a 2D frame of 3D space.

    Build it with :meth:`Region.from_shapely` (or a source such as
    :func:`pds_plugin.section` or :func:`pds_plugin.load_svg`), which validates the
    geometry. A Region never changes after it is made.

    Attributes
    ----------
    geometry : shapely.MultiPolygon
        The region, exteriors counter-clockwise and holes clockwise.
    frame : (4, 4) ndarray
        Maps the 2D coordinates ``(x, y, 0, 1)`` into 3D (identity for plain 2D input).
    tolerance : float
        How far, at most, the region's boundary may lie from the input's: the boundary
        is known only up to it (0: exact, every input vertex is kept).
    source : shapely.MultiPolygon
        The validated input before the tolerance pass (``geometry`` itself at tolerance 0).
    curves : BoundaryCurves or None
        The exact curves the boundary was flattened from, with the drawing element of
        each, when a drawing reader kept them (:mod:`pds_plugin.boundary_curves`).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> region = Region.from_shapely(box(0, 0, 4, 4).difference(box(1, 1, 2, 2)))
    >>> region.betti, region.area
    ((1, 1), 15.0)
    """

    def __init__(self, geometry: MultiPolygon, frame: np.ndarray, tolerance: float = 0.0,
                 source: MultiPolygon | None = None, curves=None):
        self.geometry = geometry
        self.frame = np.array(frame, dtype=float)      # a copy: the caller's stays writable
        self.frame.setflags(write=False)
        self.tolerance = float(tolerance)
        self.source = geometry if source is None else source
        self.curves = curves

    @classmethod
    def from_shapely(cls, geometry, frame=None, *, repair: bool = False,
                     tolerance: float | Sequence[float] = 0.0, curves=None) -> "Region":
        """Validate a shapely Polygon or MultiPolygon and make a Region of it.

        With a ``tolerance`` τ > 0 the boundary is simplified within τ, keeping its
        topology (GEOS's topology-preserving Douglas-Peucker): vertices closer than τ to
        the chord of their neighbours go, which absorbs the float noise and the zigzags
        of tessellated curves that a CAD export leaves on its sections. Every removed
        vertex lies within τ of the segment that replaces it, so the Hausdorff distance
        between the two boundaries is at most τ (:attr:`source_deviation` measures it
        exactly); where the simplified rings would not make the same valid region, the
        input is kept as it is. Components that touch at a point (two parts of an assembly
        sharing an edge, cut across it) are moved apart there first, by half the tolerance
        or 1e-7 of the extent (``PINCH_STEP``), the tolerance raised to that if smaller;
        and cracks thinner than half the tolerance (slits into the material, the seams
        of bodies an export left unmerged) are closed, which grows the region by at most
        their width. The simplification then takes what is left of the tolerance, and at
        least half of it (the tolerance raised by what healing took beyond half).

        Parameters
        ----------
        geometry : shapely Polygon, MultiPolygon or polygon-only GeometryCollection
        frame : (4, 4) array_like, optional
            2D -> 3D transform of the plane the region lies in; identity by default.
        repair : bool
            Mend invalid geometry with ``shapely.make_valid`` (never ``buffer(0)``,
            which drops lobes) and drop zero-area parts, instead of raising; and drop
            the spikes of zero width where a ring folds back onto itself within
            rounding (:func:`_folds_dropped`), which shapely may call valid but no
            triangle fills.
        tolerance : float or sequence of float
            Absolute; 0 (the default) keeps every vertex: shapely input is taken as
            exact. :func:`pds_plugin.section` derives one from the mesh file. A sequence
            gives each polygon of ``geometry``, in order, its own (float noise grows with
            the coordinates: bodies far apart have different noise); healing takes the
            smallest, and :attr:`tolerance` is the largest.
        curves : BoundaryCurves, optional
            The exact curves the geometry was flattened from (the drawing readers').

        Returns
        -------
        Region

        Raises
        ------
        ArgumentTypeError
            If ``geometry`` is not a polygonal shapely geometry.
        RegionError
            If it is empty, has non-finite coordinates, is invalid (the message gives
            shapely's reason and location) or has zero-area parts, and ``repair`` is off.
        ArgumentError
            If ``frame`` is not a finite 4x4 matrix of rank 2 in its first two columns.
        ArgumentTypeError
            If ``frame`` is not numbers, or ``repair`` not a bool.
        ArgumentError
            If ``tolerance`` is negative or not finite.

        Examples
        --------
        >>> from shapely.geometry import Polygon
        >>> bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
        >>> Region.from_shapely(bowtie)
        Traceback (most recent call last):
        ...
        pds_plugin.errors.RegionError: invalid region geometry: Self-intersection[1 1]; fix the outline or pass repair=True (shapely.make_valid)
        >>> Region.from_shapely(bowtie, repair=True).betti
        (2, 0)
        >>> noisy = Polygon([(0, 0), (1, 1e-9), (2, 0), (2, 1), (0, 1)])
        >>> region = Region.from_shapely(noisy, tolerance=1e-6)
        >>> len(region.rings[0]), region.source_deviation
        (4, 1e-09)
        >>> far = Polygon([(1e6, 0), (1e6 + 1, 2e-3), (1e6 + 2, 0), (1e6 + 2, 1), (1e6, 1)])
        >>> both = Region.from_shapely(MultiPolygon([noisy, far]), tolerance=[1e-6, 0.01])
        >>> [len(ring) for ring in both.rings], both.tolerance
        ([4, 4], 0.01)
        """
        repair = check_flag(repair, "repair")
        polygons = _polygons_of(geometry)
        given = _tolerances(tolerance, len(polygons))
        coords = shapely.get_coordinates(geometry)
        if not np.isfinite(coords).all():
            raise RegionError("region geometry has NaN or infinite coordinates; "
                             "clean the input coordinates first")
        if not polygons:
            raise RegionError("region geometry is empty: there is nothing to mesh")
        # a MultiPolygon of non-empty polygons is the MultiPolygon they make: checked and
        # oriented as it is, not rebuilt (twice) from its parts
        whole = (type(geometry) is MultiPolygon
                 and len(polygons) == shapely.get_num_geometries(geometry))
        multi = geometry if whole else shapely.multipolygons(polygons)
        given_polygons, valid = polygons, multi.is_valid
        if valid:                          # its parts are the polygons: those with area
            areas = shapely.area(polygons)
            if not (areas > 0).all():
                polygons = [p for p, area in zip(polygons, areas.tolist()) if area > 0]
                multi = MultiPolygon(polygons) if polygons else None
        else:
            if not repair:
                raise RegionError(_invalidity(polygons))
            polygons = [p for p in _polygons_of(shapely.make_valid(multi)) if p.area > 0]
            multi = MultiPolygon(polygons) if polygons else None
        if multi is None:
            raise RegionError("region geometry has no area after repair: there is nothing to mesh")
        geometry = shapely.orient_polygons(multi)
        check_scale(geometry.bounds)
        if repair:
            geometry = _folds_dropped(geometry)
        # one tolerance, or each polygon's (the smallest of the given polygons it meets)
        tolerance = float(given.min())
        if given.max() > tolerance:
            # repaired, the given polygons may be invalid: no predicate on them
            tolerance = _matched(geometry, given_polygons, given) if valid else tolerance
        if (np.all(tolerance == 0) and shapely.get_num_geometries(geometry) == 1 and not
                shapely.get_num_interior_rings(shapely.get_geometry(geometry, 0))):
            healed, moved = geometry, 0.0   # one ring: nothing to touch, no crack to close
        else:
            healed, moved = _healed(geometry, float(np.min(tolerance)))
            if np.ndim(tolerance) and healed is not geometry:
                tolerance = _matched(healed, list(geometry.geoms), tolerance)
        # the simplification keeps at least half the tolerance where healing took more:
        # closing a zigzag's tips vertex by vertex adds their widths up to the whole
        # tolerance, and left the zigzag itself unsimplified (a held-out tube section)
        simplify = np.maximum(tolerance - moved, tolerance / 2)
        tolerance = float(np.max(np.maximum(tolerance, moved + simplify)))
        region = cls(_within_tolerance(healed, simplify), _checked_frame(frame),
                     tolerance, geometry, curves)
        if moved:
            region._healed = healed, moved
        return region

    _healed = None     # (the input healed, how far it moved): see _healed

    @cached_property
    def source_deviation(self) -> float:
        """How far :attr:`geometry` lies from :attr:`source`: the Hausdorff distance
        between the boundaries, measured exactly (see :func:`source_deviation`), plus, if
        the input was healed first, how far that moved it (touching components moved
        apart, cracks thinner than the tolerance closed; see :func:`_healed`)."""
        healed, moved = self._healed or (self.source, 0.0)
        return source_deviation(self.geometry, healed) + moved

    @cached_property
    def rings(self) -> list[np.ndarray]:
        """Boundary rings as (k, 2) float arrays without the closing duplicate.

        Exteriors run counter-clockwise, holes clockwise, so the region is on the left.
        A vertex within rounding of the one before it (``FOLD_WIDTH`` float spacings)
        repeats it and is left out: the samplers would put a sample on each.
        """
        # every ring at once (a drawing's hundreds of holes, a remesh's patches laid
        # out together): each exterior, then its holes, their closing points dropped
        rings = shapely.get_rings(shapely.get_parts(self.geometry))
        if not len(rings):
            return []
        xy, owner = shapely.get_coordinates(rings, return_index=True)
        sizes = np.bincount(owner, minlength=len(rings)) - 1
        closing = np.cumsum(sizes + 1) - 1
        xy = np.delete(xy, closing, axis=0)
        first = np.cumsum(sizes) - sizes
        before = np.arange(len(xy)) - 1
        before[first] = first + sizes - 1                   # a ring's first: its last
        # _repeats_dropped's test, every vertex against the one before it in its ring
        kept = (np.abs(xy - xy[before]) > FOLD_WIDTH * self.resolution).any(axis=1)
        ends = np.cumsum(np.add.reduceat(kept, first))
        return np.split(xy[kept], ends[:-1])

    @cached_property
    def segments(self) -> np.ndarray:
        """All boundary segments as an (m, 2, 2) array ``[[x0, y0], [x1, y1]]``, ring
        after ring, segment k of a ring from its vertex k to the next (all rings in one
        pass: a sheet's 300 holes took 4.9 ms ring by ring, now 0.4)."""
        xy = np.concatenate(self.rings)
        return np.stack([xy, xy[_following([len(ring) for ring in self.rings])]], axis=1)

    def boundary_pieces(self, max_length: float):
        """The boundary cut into straight pieces no longer than ``max_length``.

        Each segment is cut into equal pieces, segment by segment in ring order.

        Parameters
        ----------
        max_length : float

        Returns
        -------
        start : (P, 2) float ndarray
            Start points.
        direction : (P, 2) float ndarray
            Unit directions.
        length : (P,) float ndarray
            Lengths.

        Examples
        --------
        >>> from shapely.geometry import box
        >>> start, direction, length = Region.from_shapely(box(0, 0, 2, 1)).boundary_pieces(0.6)
        >>> len(start), length[:6].tolist()         # 4 pieces per side of 2, 2 per side of 1
        (12, [0.5, 0.5, 0.5, 0.5, 0.5, 0.5])
        """
        seg = self.segments
        vec = seg[:, 1] - seg[:, 0]
        seg_len = np.hypot(vec[:, 0], vec[:, 1])
        count = np.maximum(np.ceil(seg_len / max_length), 1).astype(np.int64)
        owner = np.repeat(np.arange(len(seg)), count)
        step = np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count)
        start = seg[owner, 0] + (step / count[owner])[:, None] * vec[owner]
        return start, vec[owner] / seg_len[owner, None], seg_len[owner] / count[owner]

    @cached_property
    def ring_owners(self) -> tuple[tuple[int, int | None], ...]:
        """``(component, hole)`` of each ring in :attr:`rings` (hole None for an outline)."""
        return tuple((c, h) for c, polygon in enumerate(self.geometry.geoms)
                     for h in (None, *range(len(polygon.interiors))))

    @cached_property
    def area(self) -> float:
        """The region's area."""
        return float(self.geometry.area)

    @cached_property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)`` in the region's 2D coordinates."""
        return tuple(float(v) for v in self.geometry.bounds)

    @cached_property
    def resolution(self) -> float:
        """The spacing of float64 numbers at the region's largest coordinate: no two
        points of the region closer than this can be told apart.

        >>> from shapely.geometry import box
        >>> Region.from_shapely(box(1e15, 0, 1e15 + 1, 1)).resolution
        0.125
        """
        return float(np.spacing(np.abs(self.bounds).max()))

    @property
    def perimeter(self) -> float:
        """The total length of the boundary rings."""
        return float(self.geometry.length)

    @property
    def betti(self) -> tuple[int, int]:
        """``(b0, b1)``: the number of components and the number of holes."""
        return (len(self.geometry.geoms),
                sum(len(p.interiors) for p in self.geometry.geoms))

    def to_3d(self, xy) -> np.ndarray:
        """Map (n, 2) region coordinates into 3D through :attr:`frame` (see :func:`lift`).

        Parameters
        ----------
        xy : (n, 2) array_like

        Returns
        -------
        (n, 3) float ndarray

        Examples
        --------
        >>> from shapely.geometry import box
        >>> Region.from_shapely(box(0, 0, 1, 1)).to_3d([[1, 2]]).tolist()
        [[1.0, 2.0, 0.0]]
        """
        return lift(xy, self.frame)

    def __repr__(self) -> str:
        b0, b1 = self.betti
        return (f"Region(components={b0}, holes={b1}, area={self.area:.6g}, "
                f"bounds={tuple(round(v, 6) for v in self.bounds)})")


def simple_regions(rings) -> list:
    """A Region of each ring ((k, 2) arrays, no closing duplicate) as one valid polygon
    of it is taken by :meth:`Region.from_shapely` at tolerance 0 (oriented, nothing to
    heal), or None where that polygon is not valid; made together in a few vectorized
    shapely calls. A ring already counter-clockwise with no vertex to drop as a repeat
    is the region's :attr:`Region.rings` as given (the property would read it back).

    >>> square, bowtie = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float), np.array(
    ...     [[0, 0], [1, 1], [1, 0], [0, 1]], float)
    >>> [None if r is None else r.area for r in simple_regions([square, bowtie])]
    [1.0, None]
    """
    if not len(rings):
        return []
    sizes = np.array([len(ring) for ring in rings])
    owner = np.repeat(np.arange(len(rings)), sizes)
    flat = np.concatenate(rings)
    polygons = shapely.polygons(shapely.linearrings(flat, indices=owner))
    kept = np.flatnonzero(shapely.is_valid(polygons))
    if not len(kept):
        return [None] * len(rings)
    geometries = shapely.orient_polygons(shapely.multipolygons(polygons[kept],
                                                               indices=np.arange(len(kept))))
    # what Region.rings would read back, every ring at once: the oriented exterior's
    # points (the ring as given, unless turned) less the repeats (_repeats_dropped's
    # test); a ring read back as given is the cached property's value
    width = np.full(len(rings), np.nan)
    width[kept] = FOLD_WIDTH * np.spacing(np.abs(shapely.bounds(geometries)).max(axis=1))
    first = np.cumsum(sizes) - sizes
    before = np.arange(len(flat)) - 1
    before[first] = first + sizes - 1
    apart = (np.abs(flat - flat[before]) > width[owner, None]).any(axis=1)
    as_given = np.logical_and.reduceat(apart, first)
    count = sizes[kept] + 1                       # each kept ring closed: its first again
    start = np.cumsum(count) - count
    closed = np.repeat(first[kept] - start, count) + np.arange(count.sum())
    closed[start + count - 1] = first[kept]
    same = (shapely.get_coordinates(geometries) == flat[closed]).all(axis=1)
    as_given[kept] &= np.logical_and.reduceat(same, start)
    out = [None] * len(rings)
    for k, geometry in zip(kept.tolist(), geometries):
        region = out[k] = Region(geometry, np.eye(4))
        if as_given[k]:
            region.__dict__["rings"] = [np.ascontiguousarray(rings[k], dtype=float)]
    return out


def _polygons_of(geometry) -> list[Polygon]:
    if type(geometry) is Polygon:           # what get_parts makes of it, without arrays
        return [] if geometry.is_empty else [geometry]
    if not isinstance(geometry, shapely.Geometry):
        raise ArgumentTypeError(f"expected a shapely Polygon or MultiPolygon, got {type(geometry).__name__}")
    parts = shapely.get_parts(geometry)
    polygons = [p for p in parts if isinstance(p, Polygon) and not p.is_empty]
    nested = [q for p in parts if isinstance(p, (MultiPolygon, shapely.GeometryCollection))
              for q in _polygons_of(p)]
    others = [p for p in parts if not isinstance(p, (Polygon, MultiPolygon, shapely.GeometryCollection))
              and not p.is_empty]
    if others and not (polygons or nested):
        raise ArgumentTypeError(f"expected polygons, got {others[0].geom_type}: a region needs area")
    return polygons + nested


def check_tolerance(tolerance) -> float:
    """``tolerance`` as a float, if it is a finite number >= 0.

    >>> check_tolerance(-1)
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentError: tolerance must be a finite number >= 0 (0: exact), got -1
    """
    try:
        if isinstance(tolerance, (bool, str)):
            raise TypeError
        value = float(tolerance)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"tolerance must be a number, got {tolerance!r}") from None
    if not (np.isfinite(value) and value >= 0):
        raise ArgumentError(f"tolerance must be a finite number >= 0 (0: exact), got {tolerance!r}")
    return value


def _tolerances(tolerance, count: int) -> np.ndarray:
    """``tolerance`` (a number, or one per polygon of ``count``) as an array of finite
    numbers >= 0 (:func:`check_tolerance`)."""
    if np.ndim(tolerance) == 0:
        return np.array([check_tolerance(tolerance)])
    values = np.array([check_tolerance(value) for value in tolerance])
    if len(values) != count:
        raise ArgumentError(f"tolerance gives {len(values)} values for a geometry of {count} "
                            f"polygon(s): pass one number, or one per polygon")
    return values


def _matched(geometry: MultiPolygon, polygons, tolerances) -> np.ndarray:
    """Per polygon of ``geometry``: the smallest of ``tolerances`` (one per polygon of
    ``polygons``, which ``geometry`` was made from) among the polygons it meets, or the
    smallest of all if it meets none."""
    target = np.array(geometry.geoms)
    found, which = shapely.STRtree(np.array(polygons)).query(target, predicate="intersects")
    out = np.full(len(target), np.inf)
    np.minimum.at(out, found, tolerances[which])
    return np.where(np.isinf(out), tolerances.min(), out)


def _within_tolerance(geometry: MultiPolygon, tolerance: float) -> MultiPolygon:
    """The tolerance pass: ``geometry`` simplified within ``tolerance`` with its topology
    kept, or ``geometry`` itself where no result is the same valid region with a
    subsequence of each ring's vertices within the tolerance (see :func:`source_deviation`);
    with one tolerance per polygon, each polygon simplified within its own.
    GEOS's simplifier may move a ring's start past the tolerance (1.2 times it, on noisy
    rings): the pass then simplifies at half and a quarter of it before giving up."""
    if np.all(tolerance == 0):
        return geometry
    own = np.ndim(tolerance) > 0                # one per polygon: each simplified alone
    for fraction in _SIMPLIFY_FRACTIONS:
        if own:
            parts = [p for p in shapely.simplify(np.array(geometry.geoms), fraction * tolerance,
                                                 preserve_topology=True) if not p.is_empty]
        else:
            parts = _polygons_of(shapely.simplify(geometry, fraction * tolerance,
                                                  preserve_topology=True))
        if len(parts) != len(geometry.geoms) or not MultiPolygon(parts).is_valid:
            continue
        simplified = shapely.orient_polygons(MultiPolygon(parts))
        if own and all(source_deviation(MultiPolygon([after]), MultiPolygon([before])) <= limit
                       for after, before, limit in zip(simplified.geoms, geometry.geoms,
                                                       tolerance.tolist())):
            return simplified
        if not own and source_deviation(simplified, geometry) <= tolerance:
            return simplified
    return geometry


_SIMPLIFY_FRACTIONS = (1.0, 0.5, 0.25)


ALPHA_RESOLUTION = 1e3
"""Smallest alpha (or radius of a graded field), in float64 spacings at the region's
largest coordinate (:attr:`Region.resolution`): below it, rounding puts samples on top of
each other and the sampler runs away."""


FOLD_WIDTH = 16
"""The widest spike a ring may fold into and still count as folded back onto itself
(see :func:`_folds_dropped`), in float64 spacings at the region's largest coordinate."""


def _folds_dropped(geometry: MultiPolygon) -> MultiPolygon:
    """``geometry`` with its folds mended: where a ring runs out and back along itself
    within rounding, a spike (of material, or a crack into it) whose two sides lie within
    ``FOLD_WIDTH`` float spacings of each other, the tip goes, vertex by vertex as
    :func:`_ring_cracks_closed` closes cracks. Shapely may call such a ring valid, but
    no triangle fits in the spike, and where one side passes through a vertex of the
    other, both get the same boundary sample (the complex refuses it). The spikes have
    no area to speak of. Mended by ``shapely.make_valid`` if what is left is not valid;
    ``geometry`` itself if nothing goes.

    >>> fold = Polygon([(0, 0), (2, 0), (2, 1), (1 + 1e-15, 1), (1, 3), (1, 1), (0, 1)])
    >>> _folds_dropped(MultiPolygon([fold])).geoms[0].exterior.coords[:-1]  # and its mouth
    [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)]
    """
    width = FOLD_WIDTH * float(np.spacing(np.abs(geometry.bounds).max()))
    polygons, dropped = [], False
    for polygon in geometry.geoms:
        rings = []
        for ring in (polygon.exterior, *polygon.interiors):
            xy = _repeats_dropped(shapely.get_coordinates(ring)[:-1], width)
            rings.append(_ring_cracks_closed(xy, width, folds=True)[0])
            dropped |= len(rings[-1]) < len(xy)
        polygons.append(Polygon(rings[0], rings[1:]))
    if not dropped:
        return geometry
    mended = MultiPolygon(polygons)
    if not mended.is_valid:
        mended = MultiPolygon([p for p in _polygons_of(shapely.make_valid(mended)) if p.area > 0])
    return shapely.orient_polygons(mended)


def _repeats_dropped(xy: np.ndarray, width: float) -> np.ndarray:
    """The vertices of a ring (no closing duplicate) more than ``width`` from the one
    before it along x or y: the others repeat it within rounding."""
    step = np.abs(xy - np.concatenate([xy[-1:], xy[:-1]]))     # np.roll costs 3 times this
    return xy[(step > width).any(axis=1)]


PINCH_STEP = 1e-7
"""How far, relative to the region's extent, the vertices where two components touch are
moved into their own component when the tolerance is smaller (see :func:`_pinches_opened`):
well above the rounding that the feature size allows for (1e-9 of the largest
coordinate), so that the gap it leaves is a gap."""


def _healed(geometry: MultiPolygon, tolerance: float):
    """``geometry`` with its pinch points opened (:func:`_pinches_opened`) and its cracks
    thinner than half the tolerance closed (:func:`_cracks_closed`), and a bound on how
    far that moved it (the Hausdorff distance between the regions, and between their
    boundaries away from the closed cracks, whose sides are at most that far apart)."""
    opened, step = _pinches_opened(geometry, tolerance)
    closed, width = _cracks_closed(opened, tolerance / 2)
    return closed, step + width


def _cracks_closed(geometry: MultiPolygon, width: float):
    """``geometry`` with every crack of its rings thinner than ``width`` closed, and the
    largest width closed (0.0 and ``geometry`` itself if none is).

    A crack is a slit into the material whose two sides run within ``width`` of each
    other to a tip where the ring turns back (a reflex spike): the seam between two
    bodies of an assembly or the two legs of a bracket that an export left unmerged,
    cut by the plane. Such a region is valid, but no sample sees across the slit and
    nothing between its sides is material to mesh. The tip of a crack (where the ring
    turns right and goes back) goes when the triangle it makes with its neighbours is
    thinner than ``width`` (its smallest altitude); the ring then runs straight from one
    neighbour to the other, and the same is tried at both, so a crack along a polyline
    closes vertex by vertex up to its mouth. Every point added lies within the
    triangle's altitude of its two sides, which lie within the widths closed before them
    of the input, so the region grows by at most the returned width (the Hausdorff
    distance between the regions). Spikes of material are never cut (that would move
    the boundary by their length), nor gaps between different rings (closing them would
    change the topology). The input is returned unchanged when the result would not be
    valid.

    Examples
    --------
    >>> slit = Polygon([(0, 0), (4, 0), (4, 2), (3, 2), (1, 1), (3, 2 + 1e-6), (0, 2)])
    >>> closed, width = _cracks_closed(MultiPolygon([slit]), 1e-4)
    >>> closed.geoms[0].exterior.coords[:-1], round(width, 9)    # the tip (1, 1) is gone
    ([(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (3.0, 2.000001), (0.0, 2.0)], 1.894e-06)
    """
    if width <= 0:
        return geometry, 0.0
    polygons, widest = [], 0.0
    for polygon in geometry.geoms:
        rings = []
        for ring in (polygon.exterior, *polygon.interiors):
            xy, closed = _ring_cracks_closed(shapely.get_coordinates(ring)[:-1], width)
            rings.append(xy)
            widest = max(widest, closed)
        polygons.append(Polygon(rings[0], rings[1:]))
    if not widest:
        return geometry, 0.0
    healed = MultiPolygon(polygons)
    if not healed.is_valid or len(healed.geoms) != len(geometry.geoms):
        return geometry, 0.0
    return healed, float(widest)


def _ring_cracks_closed(xy: np.ndarray, width: float, folds: bool = False):
    """One ring (region on its left) with its cracks thinner than ``width`` closed (see
    :func:`_cracks_closed`), and the largest width closed; with ``folds``, the tips of
    spikes of material that thin go too (:func:`_folds_dropped`)."""
    behind, ahead = np.roll(xy, 1, axis=0), np.roll(xy, -1, axis=0)
    tip = ((xy - behind) * (ahead - xy)).sum(axis=1) < 0     # the ring goes back there
    todo = list(np.flatnonzero(tip & (_thinness(behind, xy, ahead, folds) <= width))[::-1])
    if not todo:
        return xy, 0.0
    n = len(xy)
    before, after = (np.arange(n) - 1) % n, (np.arange(n) + 1) % n
    off = np.zeros(n)          # how far segment k (from vertex k) may lie from the input
    kept, widest = n, 0.0
    while todo and kept > 3:
        t = todo.pop()
        if before[t] < 0:
            continue                            # removed already
        p, q = before[t], after[t]
        w = _thinness(xy[p][None], xy[t][None], xy[q][None], folds)[0]
        if not w <= width:
            continue
        off[p] = w + max(off[p], off[t])        # the new segment p -> q
        widest = max(widest, off[p])
        after[p], before[q], before[t] = q, p, -1
        kept -= 1
        todo += [p, q]                          # the crack may go on past them
    return xy[before >= 0], widest


def _thinness(p, t, q, folds: bool = False) -> np.ndarray:
    """For rows of three consecutive ring vertices p, t, q (region on its left): the
    smallest altitude of the triangle p t q where the ring turns right at t (every point
    of the triangle is that near the sides p t and t q), infinity where it turns left
    (cutting the corner off would take material away), unless ``folds`` (the width of
    a spike of material too)."""
    u, v = t - p, q - t
    cross = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    longest = np.maximum(np.maximum(np.hypot(*u.T), np.hypot(*v.T)), np.hypot(*(u + v).T))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where((folds | (cross <= 0)) & (longest > 0), np.abs(cross) / longest,
                        np.inf)


def _pinches_opened(geometry: MultiPolygon, tolerance: float):
    """``geometry`` with the points where its boundary touches itself opened, and how far
    the boundary moved there.

    A valid MultiPolygon may touch itself at points: two parts of an assembly sharing an
    edge, cut across it; a hole touching its outline or another hole (a plane tangent to
    a bore at the part's edge). A conforming mesh joins each ring's samples by chords,
    and one sample cannot end the chords of two rings; the interiors do not meet there
    anyway. So, by a step of half the tolerance or ``PINCH_STEP`` of the extent,
    whichever is larger:

    - each ring vertex where two components touch moves into its own polygon along the
      bisector of its corner (two open squares touching at a corner are two components);
    - where rings of one polygon touch, a square of that radius about the point is cut
      out: material of width zero is no material, so the hole opens there (to the
      outside, or into the other hole) and the region has one hole fewer.

    The boundary moves by at most the step. The input is returned unchanged (step 0)
    when nothing touches or the result would not be valid.

    Examples
    --------
    >>> from shapely.geometry import box, Polygon
    >>> touching = MultiPolygon([box(0, 0, 1, 1), box(1, 1, 2, 2)])
    >>> opened, step = _pinches_opened(touching, 0.0)
    >>> step, opened.is_valid, opened.geoms[0].touches(opened.geoms[1])
    (2e-07, True, False)
    >>> hole = Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(0, 2), (2, 1), (2, 3)]])
    >>> opened, step = _pinches_opened(MultiPolygon([hole]), 0.0)
    >>> step, opened.is_valid, len(opened.geoms[0].interiors)   # the hole opens at (0, 2)
    (4e-07, True, 0)
    """
    xmin, ymin, xmax, ymax = geometry.bounds
    step = max(tolerance / 2, PINCH_STEP * max(xmax - xmin, ymax - ymin))
    apart = _components_apart(geometry, step)
    opened = _rings_opened(apart, step)
    return (geometry, 0.0) if opened is geometry else (opened, step)


def _components_apart(geometry: MultiPolygon, step: float) -> MultiPolygon:
    """``geometry`` with its components moved apart by ``step`` where they touch (see
    :func:`_pinches_opened`), or ``geometry`` itself."""
    polygons = np.array(geometry.geoms)
    if len(polygons) < 2:
        return geometry
    # boxes first, the predicate on the pairs only (not on each polygon with itself)
    first, second = shapely.STRtree(polygons).query(polygons)
    i, j = first[first < second], second[first < second]
    touching = shapely.touches(polygons[i], polygons[j])
    i, j = i[touching], j[touching]
    if not len(i):
        return geometry
    contacts = shapely.get_coordinates(shapely.intersection(shapely.boundary(polygons[i]),
                                                            shapely.boundary(polygons[j])))
    moved = polygons.copy()
    for k in np.unique(np.concatenate([i, j])):
        moved[k] = Polygon(_moved_ring(polygons[k].exterior, contacts, step),
                           [_moved_ring(hole, contacts, step) for hole in polygons[k].interiors])
    opened = MultiPolygon(list(moved))
    if (not opened.is_valid or len(opened.geoms) != len(polygons)
            or shapely.intersects(moved[i], moved[j]).any()):
        return geometry
    return opened


def _rings_opened(geometry: MultiPolygon, step: float) -> MultiPolygon:
    """``geometry`` with a square of radius ``step`` cut out where two rings of one
    polygon touch (see :func:`_pinches_opened`), or ``geometry`` itself."""
    contacts = []
    for polygon in geometry.geoms:
        rings = np.array([polygon.exterior, *polygon.interiors])
        if len(rings) < 2:
            continue
        first, second = shapely.STRtree(rings).query(rings)      # boxes, then the pairs
        first, second = first[first < second], second[first < second]
        meet = shapely.intersects(rings[first], rings[second])
        contacts.extend(shapely.intersection(rings[first[meet]], rings[second[meet]]))
    if not contacts:
        return geometry
    points = shapely.get_coordinates(np.array(contacts))
    cut = shapely.union_all(shapely.buffer(shapely.points(points), step, quad_segs=1))
    opened = _polygons_of(shapely.difference(geometry, cut))
    if not opened or not MultiPolygon(opened).is_valid:
        return geometry
    return shapely.orient_polygons(MultiPolygon(opened))


def _moved_ring(ring, contacts, step) -> np.ndarray:
    """The closed coordinates of ``ring`` (the region on its left) with its vertices at
    ``contacts`` moved by ``step`` along their corner's inward bisector (see
    :func:`_pinches_opened`)."""
    xy = shapely.get_coordinates(ring)[:-1]
    at = np.flatnonzero((xy[:, None, :] == contacts[None, :, :]).all(axis=2).any(axis=1))
    if len(at):
        into = xy[at] - xy[at - 1]
        out = xy[(at + 1) % len(xy)] - xy[at]
        left = (np.column_stack([-into[:, 1], into[:, 0]]) / np.hypot(*into.T)[:, None]
                + np.column_stack([-out[:, 1], out[:, 0]]) / np.hypot(*out.T)[:, None])
        xy[at] += step * left / np.hypot(*left.T)[:, None]
    return np.vstack([xy, xy[:1]])


def source_deviation(geometry: MultiPolygon, source: MultiPolygon) -> float:
    """The Hausdorff distance between the boundaries of ``geometry`` and ``source``, when
    each ring of ``geometry`` keeps a subsequence of the vertices of the same ring of
    ``source`` (as the tolerance pass makes it); infinity otherwise (not measured).

    Each removed chain runs from one kept vertex to the next, and the distance to the
    segment between them is convex along each of its segments, so the farthest the chain
    gets from that segment is at one of its vertices; and the segment is as close to the
    chain (the chain's projection onto it covers it). So the distance is exactly the
    largest distance from a removed vertex to its segment.

    Examples
    --------
    >>> from shapely.geometry import MultiPolygon, Polygon
    >>> noisy = MultiPolygon([Polygon([(0, 0), (1, 1e-9), (2, 0), (2, 1), (0, 1)])])
    >>> square = MultiPolygon([Polygon([(0, 0), (2, 0), (2, 1), (0, 1)])])
    >>> source_deviation(square, noisy), source_deviation(noisy, square)
    (1e-09, inf)
    """
    if geometry is source:
        return 0.0
    if len(geometry.geoms) != len(source.geoms):
        return np.inf
    deviation = 0.0
    for after, before in zip(geometry.geoms, source.geoms):
        if len(before.interiors) != len(after.interiors):
            return np.inf
        for ring, kept in zip((before.exterior, *before.interiors),
                              (after.exterior, *after.interiors)):
            farthest = _removed_distance(shapely.get_coordinates(ring),
                                         shapely.get_coordinates(kept))
            if farthest is None:
                return np.inf
            deviation = max(deviation, farthest)
    return deviation


def _removed_distance(ring: np.ndarray, kept: np.ndarray):
    """The largest distance from a vertex of the closed ``ring`` to the segment of
    ``kept`` that replaces it; None if ``kept`` (closed too, possibly starting elsewhere
    on the ring) is not a subsequence of ``ring`` in order."""
    ring, kept = ring[:-1], kept[:-1]
    start = np.flatnonzero((ring == kept[0]).all(axis=1))
    if len(kept) < 3 or len(start) != 1:
        return None
    ring = np.roll(ring, -start[0], axis=0)
    keys = ring[:, 0] + 1j * ring[:, 1]
    order = np.argsort(keys, kind="stable")
    found = np.searchsorted(keys[order], kept[:, 0] + 1j * kept[:, 1])
    index = order[np.minimum(found, len(ring) - 1)]
    if not (np.array_equal(ring[index], kept) and (np.diff(index) > 0).all()):
        return None                 # not found in order (a ring through a point twice)
    owner = np.searchsorted(index, np.arange(len(ring)), side="right") - 1
    a, b = kept[owner], kept[(owner + 1) % len(kept)]
    ab, ap = b - a, ring - a
    t = np.clip(np.einsum("ij,ij->i", ap, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab),
                                                           np.finfo(float).tiny), 0.0, 1.0)
    return float(np.hypot(*(ap - t[:, None] * ab).T).max(initial=0.0))


def _invalidity(polygons) -> str:
    """Why these polygons do not make a valid region, and what to do."""
    flat = [p for p in polygons if shapely.make_valid(p).area == 0]
    if flat:
        x, y = shapely.get_coordinates(flat[0].exterior)[:-1].mean(axis=0)
        return (f"region has {len(flat)} zero-area part(s), one near ({x:.6g}, {y:.6g}); "
                "remove them or pass repair=True to drop them")
    return (f"invalid region geometry: {shapely.is_valid_reason(MultiPolygon(polygons))}; "
            "fix the outline or pass repair=True (shapely.make_valid)")


SCALE_LIMITS = (1e-50, 1e50)
"""Smallest extent and largest coordinate of a region. The sampler's and the complex's
predicates raise coordinates to powers of up to about six, which float64 holds only
within about 1e±51: a square of side 1e54 (or 1e-54) got triangles of aspect ratio 9 and
more, a square of side 1e90 of 312."""


def check_scale(bounds, what: str = "the region spans",
                fix: str = "scale the geometry (e.g. change its units)",
                error=RegionError) -> None:
    """Refuse what lies in the box ``bounds`` (the lowest coordinates, then the highest:
    xmin, ymin, xmax, ymax, or in 3D xmin, ymin, zmin, xmax, ymax, zmax) if it spans at
    most ``SCALE_LIMITS[0]`` (but more than 0) or has a coordinate of
    ``SCALE_LIMITS[1]`` or more (``what`` and ``fix`` name it in the message).

    >>> check_scale((0.0, 0.0, 1e60, 1.0))
    Traceback (most recent call last):
    ...
    pds_plugin.errors.RegionError: the region spans 1e+60 with coordinates up to 1e+60: areas and distances need an extent above 1e-50 and coordinates below 1e+50; scale the geometry (e.g. change its units)
    """
    low, high = SCALE_LIMITS
    bounds = [float(bound) for bound in bounds]
    half = len(bounds) // 2
    extent = max(top - bottom for bottom, top in zip(bounds[:half], bounds[half:]))
    largest = max(map(abs, bounds))
    if not largest < high or 0 < extent <= low:
        raise error(f"{what} {extent:.3g} with coordinates up to {largest:.3g}: areas and "
                    f"distances need an extent above {low:g} and coordinates below {high:g}; "
                    f"{fix}")


def _checked_frame(frame) -> np.ndarray:
    if frame is None:
        return np.eye(4)
    try:
        frame = np.array(frame, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"frame must be a 4x4 matrix of numbers, got {frame!r}") from None
    if frame.shape != (4, 4):
        raise ArgumentError(f"frame must be a 4x4 matrix, got shape {frame.shape}")
    if not np.isfinite(frame).all():
        raise ArgumentError("frame has NaN or infinite entries; give a finite 4x4 matrix")
    (ux, uy, uz), (vx, vy, vz) = frame[:3, 0].tolist(), frame[:3, 1].tolist()
    if not (uy * vz - uz * vy) ** 2 + (uz * vx - ux * vz) ** 2 + (ux * vy - uy * vx) ** 2 > 0:
        raise ArgumentError("frame maps the plane onto a line or a point (its first two "
                            "columns are parallel or zero); give a 2D -> 3D map of rank 2, "
                            "e.g. a rigid transform")
    return frame


def lift(xy, frame) -> np.ndarray:
    """Map (n, 2) plane coordinates into 3D through a 4x4 ``frame`` (2D -> 3D).

    Parameters
    ----------
    xy : (n, 2) array_like
    frame : (4, 4) array_like
        Maps ``(x, y, 0, 1)`` into 3D, as :attr:`Region.frame`.

    Returns
    -------
    (n, 3) float ndarray

    Examples
    --------
    >>> frame = np.eye(4)
    >>> frame[2, 3] = 5.0          # the plane z = 5
    >>> lift([[1, 2]], frame).tolist()
    [[1.0, 2.0, 5.0]]
    """
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    frame = np.asarray(frame)
    return xy @ frame[:3, :2].T + frame[:3, 3]


def plane_label(frame) -> str:
    """A short name of the plane a 2D -> 3D ``frame`` maps onto.

    ``"z=0.5"`` for a plane normal to a coordinate axis (either direction), else
    ``"n=(a, b, c) d=0.5"`` for the plane ``n·x = d``.

    Parameters
    ----------
    frame : (4, 4) array_like
        As :attr:`Region.frame`: its third column is the plane's unit normal, its fourth
        the plane's origin.

    Returns
    -------
    str

    Examples
    --------
    >>> frame = np.eye(4)
    >>> frame[2, 3] = 0.5
    >>> plane_label(frame)
    'z=0.5'
    >>> frame[:3, 2] = (np.sqrt(0.5), 0, np.sqrt(0.5))
    >>> plane_label(frame)
    'n=(0.7071, 0, 0.7071) d=0.353553'
    """
    frame = np.asarray(frame)
    normal, origin = frame[:3, 2], frame[:3, 3]
    axis = int(np.argmax(np.abs(normal)))
    if np.isclose(abs(normal[axis]), 1.0, rtol=0, atol=1e-12):
        return f"{'xyz'[axis]}={origin[axis] + 0.0:.6g}"
    return f"n=({', '.join(f'{c + 0.0:.4g}' for c in normal)}) d={normal @ origin:.6g}"


def _following(counts) -> np.ndarray:
    """For closed rings of lengths ``counts`` laid one after another, the index of each
    vertex's next one (a ring's last vertex is followed by its first)."""
    ends = np.cumsum(counts, dtype=np.int64)
    following = np.arange(1, ends[-1] + 1 if len(ends) else 1)
    following[ends - 1] = ends - counts
    return following


def turning_angles(ring: np.ndarray, counts=None) -> np.ndarray:
    """Signed turning angle (radians) at each vertex of a closed ring: at vertex k, from
    segment k-1 (into it) to segment k (out of it); positive turns left.

    Parameters
    ----------
    ring : (k, 2) ndarray
        The ring's vertices without the closing duplicate, as :attr:`Region.rings`.
    counts : sequence of int, optional
        ``ring`` is several closed rings one after another, of these lengths: their
        angles in one pass, each the same as its ring's alone.

    Returns
    -------
    (k,) float ndarray
        In ``[-pi, pi]``.

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> np.degrees(turning_angles(square)).tolist()
    [90.0, 90.0, 90.0, 90.0]
    >>> np.degrees(turning_angles(np.concatenate([square, square[::-1]]), [4, 4])).tolist()
    [90.0, 90.0, 90.0, 90.0, -90.0, -90.0, -90.0, -90.0]
    """
    if counts is None:
        out = np.empty_like(ring)                   # segment k (np.roll costs 3x, and this
        np.subtract(ring[1:], ring[:-1], out=out[:-1])      # runs once per ring and patch)
        np.subtract(ring[:1], ring[-1:], out=out[-1:])
        into = np.concatenate([out[-1:], out[:-1]])        # segment k - 1
    else:
        following = _following(counts)
        out = ring[following] - ring
        into = np.empty_like(out)
        into[following] = out
    cross = into[:, 0] * out[:, 1] - into[:, 1] * out[:, 0]
    dot = (into * out).sum(axis=1)
    return np.arctan2(cross, dot)


def require_region(value, who: str) -> Region:
    """``value`` itself if it is a :class:`Region`, else a clear error.

    Parameters
    ----------
    value : object
    who : str
        The function that needs the Region, for the message.

    Returns
    -------
    Region

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a Region.

    Examples
    --------
    >>> require_region("a square", "poisson_disc")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentTypeError: poisson_disc needs a pds_plugin.Region, got str; make one with Region.from_shapely(polygon)
    """
    return check_instance(value, Region, who, "Region.from_shapely(polygon)")
