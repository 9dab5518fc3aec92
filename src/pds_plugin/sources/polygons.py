"""Polygon assembly: closed or loose curves turned into shapely polygons, exactly.

Shared by the sources whose geometry comes as curves: the cut segments of a solid
(:mod:`.solids`), the filled shapes and the outline drawings of an SVG file (:mod:`.svg`).

- :func:`fill_geometry`: the area closed rings fill under a fill rule (nonzero, evenodd);
- :func:`outline_geometry`: polygons bounded by loose curves, nested by even-odd
  containment, with the open ends where a loop does not close;
- :func:`winding_numbers`: winding numbers of points about closed curves.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..errors import ArgumentError

__all__ = ["winding_numbers", "fill_geometry", "outline_geometry", "snap", "ROUNDING"]

ROUNDING = 1e-12
"""Steps of a loose curve shorter than this fraction of the largest coordinate are rounding
error, dropped before noding (see :func:`outline_geometry`)."""


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

    Raises
    ------
    ArgumentError
        If ``rule`` is neither.

    Examples
    --------
    >>> outer = [(0, 0), (4, 0), (4, 4), (0, 4)]
    >>> inner = [(1, 1), (3, 1), (3, 3), (1, 3)]
    >>> fill_geometry([outer, inner], "nonzero").area, fill_geometry([outer, inner], "evenodd").area
    (16.0, 12.0)
    """
    if rule not in ("nonzero", "evenodd"):
        raise ArgumentError(f"fill rule must be 'nonzero' or 'evenodd', got {rule!r}")
    closed = [np.vstack([ring, ring[:1]]) for ring in map(np.asarray, rings) if len(ring) >= 3]
    if not closed:
        return shapely.Polygon()
    if len(closed) == 1:                  # a simple ring fills its inside under either rule
        single = shapely.Polygon(closed[0])
        if single.is_valid:
            return single
    _, faces = _arrangement(shapely.linestrings(np.concatenate(closed), indices=_chain_ids(closed)))
    segments = np.concatenate([np.stack([c[:-1], c[1:]], axis=1) for c in closed])
    winding = winding_numbers(shapely.get_coordinates(shapely.point_on_surface(faces)), segments)
    keep = winding != 0 if rule == "nonzero" else winding % 2 == 1
    return shapely.union_all(faces[keep])


def outline_geometry(chains, tolerance: float, rule: str = "evenodd"):
    """Polygons bounded by loose curves: join, nest by even-odd containment, find open ends.

    Near-coincident points of different chains are merged, so chain ends meet and
    curves drawn twice coincide: each group merged has a diameter of at most
    ``tolerance``, and never holds two points of one chain (except the two ends of a
    chain of 3 or more segments, which closes it), so a finely drawn curve keeps every
    vertex and no loop can collapse, however small it is (only steps of a chain within
    rounding error, 1e-12 of the coordinates, are dropped first). The curves are then noded
    (duplicates merged, crossings split), the faces they bound are found, and a face is
    filled when it is nested inside an odd number of loops, so holes, islands in holes
    and holes of islands come out right whatever the curves' order and direction.

    Parameters
    ----------
    chains : list of (k, 2) array_like
        Polylines (k >= 2) in any order and direction, e.g. the segments of a CAD outline.
    tolerance : float
        The largest distance between points merged (chain ends, and vertices of curves
        drawn twice).
    rule : {"evenodd", "winding"}
        ``evenodd`` fills the faces nested inside an odd number of loops (drawings, whose
        curves have no direction); ``winding`` fills the faces of winding number >= 1
        about the chains as directed (sections of solids: the material on the left of
        every chain, so overlapping shells give their union).

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
    if rule not in ("evenodd", "winding"):
        raise ArgumentError(f"rule must be 'evenodd' or 'winding', got {rule!r}")
    chains = [np.array(c, dtype=float).reshape(-1, 2) for c in chains]
    chains = [c for c in chains if len(c) >= 2]
    if not chains:
        return shapely.Polygon(), np.empty((0, 2))
    coords, chain_ids = _without_rounding_steps(np.concatenate(chains), _chain_ids(chains))
    coords = _snap(coords, chain_ids, tolerance)
    lines = shapely.linestrings(coords, indices=chain_ids)
    noded, faces = _arrangement(lines[shapely.length(lines) > 0])
    edges = shapely.get_parts(noded)
    ends = shapely.get_coordinates(np.concatenate([shapely.get_point(edges, 0),
                                                   shapely.get_point(edges, -1)]))
    nodes, degree = np.unique(ends, axis=0, return_counts=True)
    open_ends = nodes[degree == 1]
    if not len(faces):
        return shapely.Polygon(), open_ends
    inside = shapely.get_coordinates(shapely.point_on_surface(faces))
    if rule == "winding":
        same = chain_ids[1:] == chain_ids[:-1]
        directed = np.stack([coords[:-1][same], coords[1:][same]], axis=1)
        return shapely.union_all(faces[winding_numbers(inside, directed) >= 1]), open_ends
    boundary = _unique_segments(np.concatenate(
        [_ring_segments(ring) for ring in shapely.get_rings(faces)]))
    return shapely.union_all(faces[winding_numbers(inside, boundary) % 2 == 1]), open_ends


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


def _without_rounding_steps(points, chain_ids):
    """Drop the inner points of chains within rounding error (1e-12 of the coordinates)
    of the point before them, or of a chain's last point: GEOS's noding may drop such a
    step and cut the chain there. Each chain keeps its two ends."""
    step = np.linalg.norm(np.diff(points, axis=0), axis=1)
    tiny = (step <= ROUNDING * np.abs(points).max()) & (chain_ids[1:] == chain_ids[:-1])
    first = np.r_[True, chain_ids[1:] != chain_ids[:-1]]
    last = np.r_[chain_ids[1:] != chain_ids[:-1], True]
    drop = np.r_[False, tiny] | np.r_[tiny, False] & np.r_[last[1:], False]
    keep = first | last | ~drop
    return points[keep], chain_ids[keep]


def _snap(points, chain_ids, tolerance, levels: int = 8) -> np.ndarray:
    """Merge the near-coincidences of ``points`` (of chains ``chain_ids``, in order).

    Points are grouped by single linkage at a distance ``radius``; a group is merged onto
    its first member when its bounding box is within ``tolerance`` across and it holds
    no two points of one chain (bar the ends of a chain of 4 or more points). The other
    groups are split again at a quarter of the radius, ``levels`` times at most: true
    near-coincidences are much closer than the points of a finely drawn curve, and
    separate from them. Points in no accepted group stay where they are.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    n = len(points)
    position = np.arange(n) - np.searchsorted(chain_ids, chain_ids)   # index in its chain
    length = np.bincount(chain_ids)[chain_ids]
    end = (position == 0) | (position == length - 1)
    target = np.arange(n)
    pending, radius = np.arange(n), float(tolerance)
    for _ in range(levels):
        if not len(pending):
            break
        pairs = cKDTree(points[pending]).query_pairs(radius, output_type="ndarray")
        m = len(pending)
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(m, m))
        count, group = connected_components(graph, directed=False)
        low = np.full((count, 2), np.inf)
        high = np.full((count, 2), -np.inf)
        np.minimum.at(low, group, points[pending])
        np.maximum.at(high, group, points[pending])
        accepted = np.linalg.norm(high - low, axis=1) <= tolerance
        # a chain met twice in a group: allowed only as the two ends of a long chain
        key = group * (int(chain_ids[-1]) + 1) + chain_ids[pending]
        _, first_of, member, times = np.unique(key, return_index=True, return_inverse=True,
                                               return_counts=True)
        ends = np.bincount(member, weights=end[pending])
        closes = (times == 2) & (ends == 2) & (length[pending][first_of] >= 4)
        accepted[group[first_of[(times > 1) & ~closes]]] = False
        keep = accepted[group]
        first = np.full(count, n)
        np.minimum.at(first, group[keep], pending[keep])
        target[pending[keep]] = first[group[keep]]
        pending, radius = pending[~keep], radius / 4
    return points[target]


def snap(points, tolerance) -> np.ndarray:
    """Replace each cluster of points closer than ``tolerance`` by its first member.

    Parameters
    ----------
    points : (n, 2) float ndarray
    tolerance : float
        Points closer than this (chains of them included) form one cluster.

    Returns
    -------
    (n, 2) float ndarray
        A new array: every point replaced by the first point of its cluster.

    Examples
    --------
    >>> snap(np.array([[0.0, 0.0], [1e-12, 0.0], [1.0, 0.0]]), 1e-9).tolist()
    [[0.0, 0.0], [0.0, 0.0], [1.0, 0.0]]
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(points).query_pairs(tolerance, output_type="ndarray")
    n = len(points)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    _, first = np.unique(label, return_index=True)
    return points[first[label]]
