"""Sources: CAD solids cut by planes, and SVG drawings, turned into a :class:`Region`.

- :func:`section` and :func:`sections` cut a ``trimesh.Trimesh``, a ``manifold3d.Manifold``
  or a mesh file (anything ``trimesh`` reads: STL, OBJ, PLY, OFF, 3MF, GLB) with planes;
- :func:`load_svg` reads the filled shapes, or the outline drawing, of an SVG file.

A solid's source module (:mod:`.trimesh`, :mod:`.manifold`) turns it into a float64
``trimesh.Trimesh``; everything else (the plane, its 2D frame, the checks, the exact cut
and the assembly of the cut curves into polygons) is shared here, so one plane gives the
same 2D coordinates whichever library the solid comes from. The heavy libraries are
imported inside the source modules only.
"""

from __future__ import annotations

import os
import sys

import numpy as np
import shapely

from ..region import Region
from .svg import load_svg

__all__ = ["section", "sections", "load_svg"]

# Source modules by the library their solids come from: (library, class name, module).
_SOLIDS = (("trimesh", "Trimesh", "trimesh"), ("manifold3d", "Manifold", "manifold"))


def section(solid, plane_origin, plane_normal) -> Region:
    """Cut a solid with a plane and return the section as a :class:`Region`.

    The 2D coordinates are those of ``trimesh.geometry.plane_transform(origin, normal)``:
    ``plane_origin`` is the 2D origin and the in-plane axes depend on the normal only, so
    the same plane gives the same coordinates with either backend, and parallel planes
    share their in-plane axes. ``region.frame`` is its exact inverse (2D -> 3D).

    Parameters
    ----------
    solid : trimesh.Trimesh, manifold3d.Manifold, str or os.PathLike
        A closed (watertight) solid, or the path of a mesh file trimesh reads.
    plane_origin : (3,) array_like
        A point of the plane.
    plane_normal : (3,) array_like
        The plane's normal (any non-zero length).

    Returns
    -------
    Region
        Every component with its holes; islands inside holes are components too.

    Raises
    ------
    ValueError
        If the plane misses the solid (the message gives the solid's extent along the
        normal), lies on one of its faces, or cuts an open (not watertight) part of the
        mesh (the message gives the open ends); if the origin or normal is not finite or
        the normal is zero; if the file is empty or unreadable.
    FileNotFoundError
        If ``solid`` is a path that does not exist.
    TypeError
        If ``solid`` is of an unsupported type.

    Examples
    --------
    >>> import trimesh, pds_plugin as pds
    >>> tube = trimesh.creation.annulus(r_min=1, r_max=2, height=4)
    >>> region = pds.section(tube, plane_origin=(0, 0, 0), plane_normal=(0, 0, 1))
    >>> region.betti
    (1, 1)
    """
    origin, normal = _plane(plane_origin, plane_normal)
    return _Solid(solid).cut(origin, normal)


def sections(solid, plane_normal, offsets=None, *, count=None, plane_origin=None) -> list[Region]:
    """Cut a solid with parallel planes and return one :class:`Region` per plane.

    Give either ``offsets`` (the planes' signed distances along the unit normal from
    ``plane_origin``) or ``count`` (that many planes, one in the middle of each of
    ``count`` equal slabs of the solid's extent along the normal, so all strictly
    inside it). All regions share the same in-plane axes (see :func:`section`).

    Parameters
    ----------
    solid : trimesh.Trimesh, manifold3d.Manifold, str or os.PathLike
    plane_normal : (3,) array_like
    offsets : sequence of float, optional
    count : int, optional
    plane_origin : (3,) array_like, optional
        The point offsets are measured from; the world origin by default.

    Returns
    -------
    list of Region
        In the order of ``offsets``, or of increasing offset for ``count``.

    Raises
    ------
    ValueError
        As :func:`section` for any plane, and if neither or both of ``offsets`` and
        ``count`` are given, or they are not finite / not a positive integer.

    Examples
    --------
    >>> import trimesh, pds_plugin as pds
    >>> box = trimesh.creation.box(extents=(2, 2, 2))
    >>> [round(r.area, 9) for r in pds.sections(box, (0, 0, 1), count=3)]
    [4.0, 4.0, 4.0]
    >>> [float(r.frame[2, 3]) for r in pds.sections(box, (0, 0, 1), offsets=[-0.5, 0.5])]
    [-0.5, 0.5]
    """
    origin, normal = _plane((0.0, 0.0, 0.0) if plane_origin is None else plane_origin,
                            plane_normal)
    solid = _Solid(solid)
    heights = _offsets(offsets, count, solid.heights(origin, normal))
    return [solid.cut(origin + height * normal, normal) for height in heights]


class _Solid:
    """A solid loaded once as a float64 trimesh mesh, cut by as many planes as asked."""

    def __init__(self, solid):
        self.mesh = _source_of(solid).load(solid)
        self.vertices = np.asarray(self.mesh.vertices, dtype=np.float64)
        self.faces = np.asarray(self.mesh.faces)
        if not np.isfinite(self.vertices).all():
            raise ValueError("the solid has NaN or infinite vertex coordinates; "
                             "clean the mesh first")
        self.scale = float(np.linalg.norm(np.ptp(self.vertices, axis=0)))

    def heights(self, origin, normal) -> np.ndarray:
        """Signed distances of the vertices to the plane."""
        return (self.vertices - origin) @ normal

    def cut(self, origin, normal) -> Region:
        from .trimesh import cut

        to_2d, to_3d = _frames(origin, normal)
        local = self.vertices @ to_2d[:3, :3].T + to_2d[:3, 3]   # z: height above the plane
        offset = float(origin @ normal)
        self._check_plane(local[:, 2], offset)
        # the intersections' rounding is relative to the coordinates' magnitude
        snap = max(1e-9 * self.scale, 1e-12 * np.abs(local[:, :2]).max())
        geometry, open_ends = outline_geometry(list(cut(local, self.faces)), tolerance=snap)
        if len(open_ends):
            where = ", ".join(f"({x:.6g}, {y:.6g}, {z:.6g})" for x, y, z in
                              _lift(open_ends[:5], to_3d))
            raise ValueError(
                f"the section at normal·x = {offset:.9g} is open: the mesh is not watertight "
                f"where the plane cuts it ({len(open_ends)} open end(s), at {where}"
                f"{', ...' if len(open_ends) > 5 else ''}); repair the mesh "
                f"(e.g. trimesh.repair.fill_holes) or move the plane")
        if geometry.is_empty:
            raise ValueError(
                f"the plane at normal·x = {offset:.9g} crosses the solid's extent but cuts no "
                f"material (it passes through a gap between parts); move the plane")
        return Region.from_shapely(geometry, frame=to_3d)

    def _check_plane(self, heights, offset) -> None:
        """Refuse a plane that lies on a face or misses the solid (heights: of the vertices)."""
        from trimesh.constants import tol

        flat = (np.abs(heights) <= tol.merge)[self.faces].all(axis=1)
        if flat.any():
            raise ValueError(
                f"the plane lies on {int(flat.sum())} face(s) of the solid "
                f"(normal·x = {offset:.9g}), so the section is ambiguous; offset the plane "
                f"slightly along the normal, e.g. by ±{1e-6 * self.scale:.3g}")
        if not (heights.min() < -tol.merge and heights.max() > tol.merge):
            low, high = offset + heights.min(), offset + heights.max()
            raise ValueError(
                f"the plane misses the solid: it is at normal·x = {offset:.9g} but the solid "
                f"spans normal·x in [{low:.9g}, {high:.9g}]; put the plane origin inside "
                f"that range")


def _frames(origin, normal) -> tuple[np.ndarray, np.ndarray]:
    """``to_2d`` (trimesh's plane_transform: the plane onto z = 0) and its exact inverse."""
    from trimesh.geometry import plane_transform

    to_2d = plane_transform(origin, normal)
    to_3d = np.eye(4)
    to_3d[:3, :3] = to_2d[:3, :3].T   # a rotation: its inverse is its transpose
    to_3d[:3, 3] = origin             # (0, 0) is the plane origin
    return to_2d, to_3d


def _source_of(solid):
    from importlib import import_module

    if isinstance(solid, (str, os.PathLike)):
        return import_module(".trimesh", __name__)
    for library, class_name, source in _SOLIDS:
        module = sys.modules.get(library)  # a solid's library is imported already
        if module is not None and isinstance(solid, getattr(module, class_name)):
            return import_module(f".{source}", __name__)
    raise TypeError(f"cannot cut a {type(solid).__name__}: give a trimesh.Trimesh, a "
                    f"manifold3d.Manifold or the path of a mesh file")


def _plane(origin, normal) -> tuple[np.ndarray, np.ndarray]:
    """Validated plane origin and unit normal, as float64 (3,) arrays."""
    origin, normal = _vector(origin, "plane_origin"), _vector(normal, "plane_normal")
    length = np.linalg.norm(normal)
    if not length > 0:
        raise ValueError("plane_normal is the zero vector; give the direction the plane "
                         "faces, e.g. (0, 0, 1)")
    return origin, normal / length


def _vector(value, name) -> np.ndarray:
    try:
        vector = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be 3 numbers (x, y, z), got {value!r}") from None
    if vector.shape != (3,):
        raise ValueError(f"{name} must be 3 numbers (x, y, z), got shape {vector.shape}")
    if not np.isfinite(vector).all():
        raise ValueError(f"{name} has NaN or infinite values: {vector.tolist()}")
    return vector


def _offsets(offsets, count, heights) -> np.ndarray:
    """Plane offsets along the normal, from ``offsets`` or ``count`` (exactly one)."""
    if (offsets is None) == (count is None):
        raise ValueError("give either offsets (distances along the normal) or count "
                         "(number of evenly spaced planes), not both and not neither")
    if count is not None:
        if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 1:
            raise ValueError(f"count must be a positive integer, got {count!r}")
        low, high = heights.min(), heights.max()
        return low + (np.arange(count) + 0.5) * (high - low) / count
    try:
        offsets = np.atleast_1d(np.asarray(offsets, dtype=float))
    except (TypeError, ValueError):
        offsets = None
    if offsets is None or offsets.ndim != 1 or not len(offsets) or not np.isfinite(offsets).all():
        raise ValueError(f"offsets must be a non-empty list of finite numbers, got {offsets!r}")
    return offsets


def _lift(xy, to_3d) -> np.ndarray:
    return xy @ to_3d[:3, :2].T + to_3d[:3, 3]


# --- planar arrangements: curves -> polygons (shared by the solid backends and SVG) ---

def winding_numbers(points, segments) -> np.ndarray:
    """Winding number of each point about closed curves given as oriented segments.

    Counts the signed crossings of the ray from each point towards +x, with the
    half-open rule on y so that a vertex on the ray counts once. Only the segments whose
    bounding box meets a ray are examined (an STRtree query), so the cost grows with the
    number of crossings, not with points x segments.

    Parameters
    ----------
    points : (n, 2) array_like
    segments : (m, 2, 2) array_like
        ``[[x0, y0], [x1, y1]]`` for each directed segment of the closed curves.

    Returns
    -------
    (n,) int64 ndarray

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> segments = np.stack([square, np.roll(square, -1, axis=0)], axis=1)
    >>> winding_numbers([[0.5, 0.5], [2, 0.5]], np.concatenate([segments, segments])).tolist()
    [2, 0]
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    segments = np.asarray(segments, dtype=float).reshape(-1, 2, 2)
    if not len(points) or not len(segments):
        return np.zeros(len(points), dtype=np.int64)
    end = segments[:, :, 0].max() + 1.0
    rays = shapely.linestrings(np.stack([points, np.column_stack(
        [np.full(len(points), end), points[:, 1]])], axis=1))
    point, segment = shapely.STRtree(shapely.linestrings(segments)).query(rays)
    (x, y), (a, b) = points[point].T, segments[segment].transpose(1, 0, 2)
    left = (b[:, 0] - a[:, 0]) * (y - a[:, 1]) - (x - a[:, 0]) * (b[:, 1] - a[:, 1])
    up = (a[:, 1] <= y) & (y < b[:, 1]) & (left > 0)
    down = (b[:, 1] <= y) & (y < a[:, 1]) & (left < 0)
    crossings = up.astype(float) - down
    return np.bincount(point, weights=crossings, minlength=len(points)).astype(np.int64)


def fill_geometry(rings, rule: str = "nonzero"):
    """The area a set of closed rings fills under an SVG/PostScript fill rule.

    Overlaps, self-intersections and nested rings are resolved exactly: the rings are
    noded into an arrangement, and each face is kept by the winding number of one of its
    interior points (``nonzero``: winding ≠ 0; ``evenodd``: winding odd).

    Parameters
    ----------
    rings : list of (k, 2) array_like
        Closed curves, in drawing order (a closing duplicate point is optional).
    rule : {"nonzero", "evenodd"}

    Returns
    -------
    shapely Polygon or MultiPolygon (empty if nothing is filled)

    Examples
    --------
    >>> outer = [(0, 0), (4, 0), (4, 4), (0, 4)]
    >>> inner = [(1, 1), (3, 1), (3, 3), (1, 3)]
    >>> fill_geometry([outer, inner], "nonzero").area, fill_geometry([outer, inner], "evenodd").area
    (16.0, 12.0)
    """
    if rule not in ("nonzero", "evenodd"):
        raise ValueError(f"fill rule must be 'nonzero' or 'evenodd', got {rule!r}")
    closed = [np.vstack([ring, ring[:1]]) for ring in map(np.asarray, rings) if len(ring) >= 3]
    if not closed:
        return shapely.Polygon()
    _, faces = _arrangement(shapely.linestrings(np.concatenate(closed), indices=_chain_ids(closed)))
    segments = np.concatenate([np.stack([c[:-1], c[1:]], axis=1) for c in closed])
    winding = winding_numbers(shapely.get_coordinates(shapely.point_on_surface(faces)), segments)
    keep = winding != 0 if rule == "nonzero" else winding % 2 == 1
    return shapely.union_all(faces[keep])


def outline_geometry(chains, tolerance: float):
    """Polygons bounded by loose curves: join, nest by even-odd containment, find open ends.

    Points closer than ``tolerance`` are merged, so chain ends meet and curves drawn
    twice coincide; the curves are then noded (duplicates merged, crossings split), the
    faces they bound are found, and a face is filled when it is nested inside an odd
    number of loops, so holes, islands in holes and holes of islands come out right
    whatever the curves' order and direction.

    Parameters
    ----------
    chains : list of (k, 2) array_like
        Polylines (k >= 2) in any order and direction, e.g. the segments of a CAD outline.
    tolerance : float
        Points (chain ends, and vertices of curves drawn twice) closer than this are merged.

    Returns
    -------
    geometry : shapely Polygon or MultiPolygon (empty if no loop closes)
    open_ends : (p, 2) ndarray
        Ends that no other curve meets: the places where a loop does not close.

    Examples
    --------
    >>> square = [[(0, 0), (2, 0)], [(2, 2), (2, 0)], [(0, 2), (2, 2)], [(0, 0), (0, 2)]]
    >>> hole = [[(0.5, 0.5), (1.5, 0.5), (1.5, 1.5), (0.5, 1.5), (0.5, 0.5)]]
    >>> geometry, open_ends = outline_geometry(square + hole, tolerance=1e-9)
    >>> geometry.area, len(open_ends)
    (3.0, 0)
    """
    chains = [np.array(c, dtype=float).reshape(-1, 2) for c in chains]
    chains = [c for c in chains if len(c) >= 2]
    if not chains:
        return shapely.Polygon(), np.empty((0, 2))
    coords = _snap(np.concatenate(chains), tolerance)
    lines = shapely.linestrings(coords, indices=_chain_ids(chains))
    noded, faces = _arrangement(lines[shapely.length(lines) > 0])
    edges = shapely.get_parts(noded)
    ends = shapely.get_coordinates(np.concatenate([shapely.get_point(edges, 0),
                                                   shapely.get_point(edges, -1)]))
    nodes, degree = np.unique(ends, axis=0, return_counts=True)
    open_ends = nodes[degree == 1]
    if not len(faces):
        return shapely.Polygon(), open_ends
    boundary = _unique_segments(np.concatenate(
        [_ring_segments(ring) for ring in shapely.get_rings(faces)]))
    depth = winding_numbers(shapely.get_coordinates(shapely.point_on_surface(faces)), boundary)
    return shapely.union_all(faces[depth % 2 == 1]), open_ends


def _arrangement(lines):
    """Noded union of shapely lines and the bounded faces (positive area) they enclose."""
    noded = shapely.union_all(lines)
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(noded)))
    return noded, faces[shapely.area(faces) > 0]


def _ring_segments(ring) -> np.ndarray:
    xy = shapely.get_coordinates(ring)
    return np.stack([xy[:-1], xy[1:]], axis=1)


def _unique_segments(segments) -> np.ndarray:
    """Each undirected segment once (a face edge appears in both faces it separates)."""
    a, b = segments[:, 0], segments[:, 1]
    swap = (a[:, 0] > b[:, 0]) | ((a[:, 0] == b[:, 0]) & (a[:, 1] > b[:, 1]))
    canonical = np.where(swap[:, None, None], segments[:, ::-1], segments)
    return np.unique(canonical.reshape(-1, 4), axis=0).reshape(-1, 2, 2)


def _chain_ids(chains) -> np.ndarray:
    return np.repeat(np.arange(len(chains)), [len(c) for c in chains])


def _snap(points, tolerance) -> np.ndarray:
    """Replace each cluster of points closer than ``tolerance`` by its first member."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(points).query_pairs(tolerance, output_type="ndarray")
    n = len(points)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    _, first = np.unique(label, return_index=True)
    return points[first[label]]
