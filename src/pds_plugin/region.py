"""The planar region to mesh: validated shapely geometry plus its 3D frame, and the facts
about it that the layers above share (its rings and their owners, turning angles, the
one 2D -> 3D lift)."""

from __future__ import annotations

from functools import cached_property

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from ._checks import check_flag, check_instance
from .errors import ArgumentError, ArgumentTypeError, RegionError

__all__ = ["Region", "lift", "plane_label", "turning_angles", "require_region"]


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

    def __init__(self, geometry: MultiPolygon, frame: np.ndarray, curves=None):
        self.geometry = geometry
        self.frame = np.array(frame, dtype=float)      # a copy: the caller's stays writable
        self.frame.setflags(write=False)
        self.curves = curves

    @classmethod
    def from_shapely(cls, geometry, frame=None, *, repair: bool = False) -> "Region":
        """Validate a shapely Polygon or MultiPolygon and make a Region of it.

        Parameters
        ----------
        geometry : shapely Polygon, MultiPolygon or polygon-only GeometryCollection
        frame : (4, 4) array_like, optional
            2D -> 3D transform of the plane the region lies in; identity by default.
        repair : bool
            Mend invalid geometry with ``shapely.make_valid`` (never ``buffer(0)``,
            which drops lobes) and drop zero-area parts, instead of raising.

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
        """
        repair = check_flag(repair, "repair")
        polygons = _polygons_of(geometry)
        coords = shapely.get_coordinates(geometry)
        if not np.isfinite(coords).all():
            raise RegionError("region geometry has NaN or infinite coordinates; "
                             "clean the input coordinates first")
        if not polygons:
            raise RegionError("region geometry is empty: there is nothing to mesh")
        multi = MultiPolygon(polygons)
        if not multi.is_valid:
            if not repair:
                raise RegionError(_invalidity(polygons))
            multi = shapely.make_valid(multi)
        polygons = [p for p in _polygons_of(multi) if p.area > 0]
        if not polygons:
            raise RegionError("region geometry has no area after repair: there is nothing to mesh")
        geometry = shapely.orient_polygons(MultiPolygon(polygons))
        _check_scale(geometry)
        return cls(geometry, _checked_frame(frame))

    @cached_property
    def rings(self) -> list[np.ndarray]:
        """Boundary rings as (k, 2) float arrays without the closing duplicate.

        Exteriors run counter-clockwise, holes clockwise, so the region is on the left.
        """
        rings = []
        for polygon in self.geometry.geoms:
            for ring in (polygon.exterior, *polygon.interiors):
                xy = shapely.get_coordinates(ring)[:-1]
                keep = np.any(xy != np.roll(xy, 1, axis=0), axis=1)  # drop repeated vertices
                rings.append(np.ascontiguousarray(xy[keep]))
        return rings

    @cached_property
    def segments(self) -> np.ndarray:
        """All boundary segments as an (m, 2, 2) array ``[[x0, y0], [x1, y1]]``."""
        return np.concatenate([np.stack([r, np.roll(r, -1, axis=0)], axis=1) for r in self.rings])

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

    @property
    def area(self) -> float:
        """The region's area."""
        return float(self.geometry.area)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """``(xmin, ymin, xmax, ymax)`` in the region's 2D coordinates."""
        return tuple(float(v) for v in self.geometry.bounds)

    @property
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


def _polygons_of(geometry) -> list[Polygon]:
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


def _check_scale(geometry) -> None:
    low, high = SCALE_LIMITS
    xmin, ymin, xmax, ymax = geometry.bounds
    extent, largest = max(xmax - xmin, ymax - ymin), max(map(abs, geometry.bounds))
    if not (extent > low and largest < high):
        raise RegionError(f"the region spans {extent:.3g} with coordinates up to {largest:.3g}: "
                          f"areas and distances need an extent above {low:g} and coordinates "
                          f"below {high:g}; scale the geometry (e.g. change its units)")


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
    if not np.linalg.norm(np.cross(frame[:3, 0], frame[:3, 1])) > 0:
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


def turning_angles(ring: np.ndarray) -> np.ndarray:
    """Signed turning angle (radians) at each vertex of a closed ring: at vertex k, from
    segment k-1 (into it) to segment k (out of it); positive turns left.

    Parameters
    ----------
    ring : (k, 2) ndarray
        The ring's vertices without the closing duplicate, as :attr:`Region.rings`.

    Returns
    -------
    (k,) float ndarray
        In ``[-pi, pi]``.

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> np.degrees(turning_angles(square)).tolist()
    [90.0, 90.0, 90.0, 90.0]
    """
    out = np.roll(ring, -1, axis=0) - ring
    into = ring - np.roll(ring, 1, axis=0)
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
