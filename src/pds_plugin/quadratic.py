"""Quadratic (6-node) triangles of a PlanarMesh, with the boundary nodes on the true curves.

Every edge of the mesh gets a mid node: an interior edge at its midpoint; a boundary
edge, when the region kept the exact curves of its drawing (``region.curves``, see
:mod:`pds_plugin.boundary_curves`), on the curve piece it follows, halfway in arc length
between its ends. The boundary samples themselves lie on the region's polygon, within the
drawing's tolerance of the curves; they are moved onto the curves too (by at most that
tolerance, reported as :attr:`QuadraticMesh.moved`), so every boundary node of the
quadratic mesh is on the true boundary. Without curves the region is its polygon and the
boundary mid nodes are the edges' midpoints, exactly on it.

An edge that crosses from one piece to the next (past a corner or a junction that is
not a sample) gets its node halfway along the path through their common end.

The curved triangles are checked: the Jacobian of each triangle's quadratic map is a
quadratic polynomial, whose exact minimum over the triangle is
:attr:`QuadraticMesh.min_jacobian` (relative to the straight triangle's, so 1 for a
straight one). Where a boundary node on the curve would make it non-positive (the curve
turns too much between the edge's ends for the triangle), that edge is left straight,
listed in :attr:`QuadraticMesh.straightened` and reported in a warning; a triangle still
inverted (by its vertices' moves onto the curves) is listed in
:attr:`QuadraticMesh.inverted` and reported too. :meth:`QuadraticMesh.certificate` is the
linear mesh's certificate with these checks in its ``quadratic`` field
(:class:`JacobianReport`): it is not ``ok`` when a curved triangle's Jacobian falls to
:data:`MIN_JACOBIAN` of its straight triangle's or below.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
import shapely

from ._checks import check_has_triangles

__all__ = ["QuadraticMesh", "JacobianReport", "quadratic", "MIN_JACOBIAN"]

MIN_JACOBIAN = 0.1
"""The smallest Jacobian a curved triangle may have, relative to its straight triangle's,
for the quadratic mesh's certificate: a curved element whose map shrinks an area element
tenfold is on its way to folding (at 0 it inverts), and its quadrature and conditioning
degrade long before; the meshes here stay near 1 (a disc at alpha = r / 5: 0.93)."""
_MAX_LOCATED = 3

_REFERENCE = np.array([[0, 0], [1, 0], [0, 1], [0.5, 0], [0.5, 0.5], [0, 0.5]])
"""The nodes of the reference triangle, in the order of ``triangles``: corners, then the
mid nodes of edges 01, 12, 20 (gmsh's and meshio's ``triangle6``)."""


@dataclass(frozen=True, eq=False)
class QuadraticMesh:
    """A mesh of 6-node triangles made from a :class:`~pds_plugin.PlanarMesh` by
    :func:`quadratic`.

    Attributes
    ----------
    mesh : PlanarMesh
        The linear mesh it was made from (its tags are the quadratic mesh's).
    points : (N + E, 2) float ndarray
        The mesh's N vertices (boundary ones moved onto the curves), then the mid node of
        each of its E edges, in the order of ``mesh.edges``.
    triangles : (M, 6) int64 ndarray
        Corners as ``mesh.faces``, then the mid nodes of edges 01, 12 and 20.
    boundary_lines : (B, 3) int64 ndarray
        The boundary edges as ``mesh.boundary_edges``, then their mid nodes.
    min_jacobian : (M,) float ndarray
        The smallest Jacobian of each curved triangle over the triangle, divided by its
        straight triangle's (1 for a triangle left straight).
    moved : float
        The farthest a boundary vertex was moved onto its curve.
    straightened : (S,) int64 ndarray
        The boundary edges (indices into ``mesh.boundary_edges``) left straight, their
        mid node at the chord's midpoint, because on the curve it would invert their
        triangle (the curve turns too much between the edge's ends: a corner that is not
        a sample, or a curve too tight for alpha).

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> square = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.25)
    >>> q = square.quadratic()
    >>> q.triangles.shape[1], len(q.points) == len(square.vertices) + len(square.edges)
    (6, True)
    >>> q.inverted.tolist(), round(float(q.min_jacobian.min()), 12)   # straight sides
    ([], 1.0)
    """

    mesh: object
    points: np.ndarray
    triangles: np.ndarray
    boundary_lines: np.ndarray
    min_jacobian: np.ndarray
    moved: float
    straightened: np.ndarray

    @property
    def inverted(self) -> np.ndarray:
        """Indices of the triangles whose Jacobian is not positive somewhere."""
        return np.flatnonzero(~(self.min_jacobian > 0))

    @cached_property
    def jacobian_report(self) -> "JacobianReport":
        """The Jacobian checks of the curved triangles (see :class:`JacobianReport`)."""
        low = np.flatnonzero(~(self.min_jacobian > MIN_JACOBIAN))
        low = low[np.argsort(self.min_jacobian[low], kind="stable")]
        centres = self.points[self.triangles[low[:_MAX_LOCATED], :3]].mean(axis=1)
        return JacobianReport(float(self.min_jacobian.min(initial=1.0)), len(self.inverted),
                              len(low), len(self.straightened), float(self.moved),
                              tuple(tuple(map(float, c)) for c in centres))

    def certificate(self):
        """The linear mesh's certificate with this mesh's Jacobian checks as its
        ``quadratic`` field; its ``ok`` also needs every curved triangle's Jacobian above
        :data:`MIN_JACOBIAN` of its straight triangle's.

        Returns
        -------
        Certificate

        Examples
        --------
        >>> import pds_plugin as pds
        >>> from shapely.geometry import Point
        >>> disc = pds.Region.from_shapely(Point(0, 0).buffer(1, 64))
        >>> cert = pds.mesh_region(disc, 0.2).quadratic().certificate()
        >>> cert.ok, cert.quadratic.ok, cert.quadratic.min_jacobian > 0.9
        (True, True, True)
        """
        return replace(self.mesh.certificate(), quadratic=self.jacobian_report)

    @cached_property
    def area(self) -> float:
        """The area of the curved triangles (exact: quadrature of the quadratic Jacobian)."""
        return float(_jacobian_integral(self.points[self.triangles]).sum())

    def __repr__(self) -> str:
        return (f"QuadraticMesh(points={len(self.points)}, triangles={len(self.triangles)}, "
                f"inverted={len(self.inverted)}, straightened={len(self.straightened)}, "
                f"min_jacobian={self.min_jacobian.min():.3g})")


@dataclass(frozen=True)
class JacobianReport:
    """The Jacobian checks of a quadratic mesh's curved triangles, as its certificate
    holds them (``Certificate.quadratic``).

    Attributes
    ----------
    min_jacobian : float
        The smallest Jacobian over every triangle, relative to its straight triangle's
        (exact: the minimum of a quadratic polynomial over the triangle).
    inverted : int
        Triangles whose Jacobian is not positive somewhere.
    below_bound : int
        Triangles whose smallest Jacobian is at most :data:`MIN_JACOBIAN` (the inverted
        ones included).
    straightened : int
        Boundary edges left straight, their mid node on the chord, because on the curve
        it would invert their triangle (not a failure: the triangle is valid, the
        boundary there is the chord's).
    moved : float
        The farthest a boundary vertex was moved onto its curve.
    below_bound_at : tuple of (x, y)
        Where the first few triangles below the bound are, worst first.
    bound : float
        :data:`MIN_JACOBIAN`.

    Examples
    --------
    >>> report = JacobianReport(0.02, 0, 1, 0, 0.0, ((1.0, 2.0),))
    >>> report.ok
    False
    >>> print(report)
    quadratic    min Jacobian 0.02 of the straight triangle's (> 0.1)  FAILED: 1 triangle(s) at or below it, 0 inverted, the first at (1, 2)
    """

    min_jacobian: float
    inverted: int
    below_bound: int
    straightened: int
    moved: float
    below_bound_at: tuple = ()
    bound: float = MIN_JACOBIAN

    @property
    def ok(self) -> bool:
        """Every curved triangle's Jacobian is above the bound (so none is inverted)."""
        return self.inverted == 0 and self.below_bound == 0 and self.min_jacobian > self.bound

    def as_dict(self) -> dict:
        """Plain JSON-ready values, ``ok`` included."""
        values = {name: getattr(self, name) for name in self.__dataclass_fields__}
        values["below_bound_at"] = [list(xy) for xy in self.below_bound_at]
        values["ok"] = self.ok
        return values

    def __str__(self) -> str:
        line = (f"quadratic    min Jacobian {self.min_jacobian:.3g} of the straight "
                f"triangle's (> {self.bound:g})  ")
        if self.ok:
            line += "ok"
        else:
            line += (f"FAILED: {self.below_bound} triangle(s) at or below it, {self.inverted} "
                     f"inverted")
            if self.below_bound_at:
                line += ", the first at ({:.6g}, {:.6g})".format(*self.below_bound_at[0])
        if self.straightened:
            line += f"; {self.straightened} boundary edge(s) left straight"
        return line


def quadratic(mesh) -> QuadraticMesh:
    """The 6-node triangles of ``mesh``, boundary nodes on the true curves (module doc).

    Parameters
    ----------
    mesh : PlanarMesh

    Returns
    -------
    QuadraticMesh

    Raises
    ------
    EmptyMeshError
        If the mesh has no triangles.

    Warns
    -----
    UserWarning
        If boundary edges are left straight, or a triangle is inverted (its Jacobian not
        positive somewhere), with how many and where the first is.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import Point
    >>> disc = pds.Region.from_shapely(Point(0, 0).buffer(1, 64))
    >>> q = quadratic(pds.mesh_region(disc, 0.2))
    >>> bool(q.min_jacobian.min() > 0)
    True
    """
    check_has_triangles(mesh, "for quadratic triangles")
    points = np.array(mesh.vertices, dtype=float)
    edges, boundary, faces = mesh.edges, mesh.boundary_edges, mesh.faces
    curves = mesh.region.curves
    count = len(points)
    moved = 0.0
    curved = np.zeros(0, dtype=np.int64)                 # boundary edges given curve nodes
    if curves is not None and len(boundary):
        ring = mesh.boundary_tags.values - 1           # -1: not on a ring of the region
        curved = np.flatnonzero(ring >= 0)
        moved = _snap(points, np.unique(boundary[curved]), curves)
    middle = points[edges].mean(axis=1)
    chord_middle = middle.copy()
    boundary_edge = _edge_index(edges, boundary, count)
    if len(curved):
        middle[boundary_edge[curved]] = _curve_midpoints(
            points, boundary[curved], curves, mesh.vertices, ring[curved], mesh.region.rings)
    sides = np.stack([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]], axis=1)
    side_index = _edge_index(edges, sides.reshape(-1, 2), count).reshape(-1, 3)
    triangles = np.hstack([faces, count + side_index])
    boundary_lines = np.column_stack([boundary, count + boundary_edge])
    # a triangle without boundary vertices keeps straight sides and its corners: det J is
    # its own, ratio 1; the others are measured
    min_jacobian = np.ones(len(faces))
    measured = np.flatnonzero(mesh.on_boundary[faces].any(axis=1))
    corners = mesh.vertices[faces[measured]]
    straight = np.abs((corners[:, 1, 0] - corners[:, 0, 0]) * (corners[:, 2, 1] - corners[:, 0, 1])
                      - (corners[:, 1, 1] - corners[:, 0, 1]) * (corners[:, 2, 0] - corners[:, 0, 0]))
    nodes = np.vstack([points, middle])
    min_jacobian[measured] = _min_jacobian(nodes[triangles[measured]]) / straight
    # where a curved node inverts its triangle, the edge stays straight
    bad = ~(min_jacobian > 0)
    straightened = np.flatnonzero(np.isin(boundary_edge[curved], side_index[bad].ravel()))
    straightened = curved[straightened]
    if len(straightened):
        middle[boundary_edge[straightened]] = chord_middle[boundary_edge[straightened]]
        nodes = np.vstack([points, middle])
        again = measured[bad[measured]]
        min_jacobian[again] = (_min_jacobian(nodes[triangles[again]])
                               / straight[np.searchsorted(measured, again)])
    for array in (nodes, triangles, boundary_lines, min_jacobian, straightened):
        array.setflags(write=False)
    result = QuadraticMesh(mesh, nodes, triangles, boundary_lines, min_jacobian, moved,
                           straightened)
    if len(straightened):
        x, y = mesh.vertices[boundary[straightened[0]]].mean(axis=0)
        warnings.warn(f"{len(straightened)} boundary edge(s) of the quadratic mesh are left "
                      f"straight, the first near ({x:.6g}, {y:.6g}): on the curve their mid "
                      f"node would invert a triangle (a corner that is not a sample, or a "
                      f"curve too tight for alpha {mesh.alpha:.6g}); mesh with a smaller alpha "
                      f"or graded=True there", UserWarning, stacklevel=2)
    inverted = result.inverted
    if len(inverted):
        x, y = nodes[triangles[inverted[0], :3]].mean(axis=0)
        warnings.warn(f"{len(inverted)} triangle(s) of the quadratic mesh are inverted "
                      f"(Jacobian not positive somewhere), the first near ({x:.6g}, {y:.6g}): "
                      f"their boundary vertices moved onto the curves too far for alpha "
                      f"{mesh.alpha:.6g}; mesh with a smaller alpha or graded=True",
                      UserWarning, stacklevel=2)
    return result


def _snap(points, vertices, curves) -> float:
    """Move ``points[vertices]`` onto their nearest curve pieces; the largest move."""
    if not len(vertices):
        return 0.0
    piece, t, distance = curves.locate(points[vertices])
    near = distance <= 2 * curves.tolerance
    points[vertices[near]] = curves.point(piece[near], t[near])
    return float(distance[near].max(initial=0.0))


def _curve_midpoints(points, edges, curves, vertices, ring, rings) -> np.ndarray:
    """Mid nodes of boundary edges (directed, on ring ``ring`` each) on the true curves,
    halfway in arc length between their ends.

    An edge whose ends are both on the piece nearest its midpoint takes its mid node on
    that piece. An edge that crosses from one piece to the next (a junction or a corner
    that is not a sample) takes it on the path through their common end. Any other
    (across several pieces) takes the point halfway along its ring's polygon between
    its ends (``vertices``, on the rings), moved onto the nearest curve when one is
    within the tolerance.
    """
    tolerance = 2 * curves.tolerance
    a, b = points[edges[:, 0]], points[edges[:, 1]]
    piece = curves.locate(0.5 * (a + b))[0]
    _, t0, d0 = curves.locate(a, piece)
    _, t1, d1 = curves.locate(b, piece)
    within = np.maximum(d0, d1) <= tolerance
    middle = curves.point(piece, curves.arc_midpoint(piece, t0, t1))
    across = np.flatnonzero(~within)
    if not len(across):
        return middle
    # two pieces: from a along its piece to the end nearer b, then on b's piece
    first, ta, da = curves.locate(a[across])
    second, tb, db = curves.locate(b[across])
    end_a = np.where(np.linalg.norm(curves.point(first, np.ones(len(across))) - b[across],
                                    axis=1)
                     < np.linalg.norm(curves.point(first, np.zeros(len(across))) - b[across],
                                      axis=1), 1.0, 0.0)
    end_b = np.where(np.linalg.norm(curves.point(second, np.ones(len(across))) - a[across],
                                    axis=1)
                     < np.linalg.norm(curves.point(second, np.zeros(len(across))) - a[across],
                                      axis=1), 1.0, 0.0)
    meet = np.linalg.norm(curves.point(first, end_a) - curves.point(second, end_b), axis=1)
    joined = (meet <= tolerance) & (np.maximum(da, db) <= tolerance) & (first != second)
    before = curves.length(first, ta, end_a)
    half = 0.5 * (before + curves.length(second, end_b, tb))
    on_first = half <= before
    result = np.where(on_first[:, None],
                      curves.point(first, curves.at_length(first, ta, end_a, half)),
                      curves.point(second, curves.at_length(second, end_b, tb, half - before)))
    rest = np.flatnonzero(~joined)
    if len(rest):
        halfway = _halfway_along_rings(vertices, edges[across[rest]], ring[across[rest]], rings)
        near, t, distance = curves.locate(halfway)
        result[rest] = np.where((distance <= tolerance)[:, None], curves.point(near, t),
                                halfway)
    middle[across] = result
    return middle


def _halfway_along_rings(vertices, edges, ring, rings) -> np.ndarray:
    """The point of each edge's ring halfway along it from the edge's start to its end
    (rings and boundary edges both run with the region on their left)."""
    out = np.empty((len(edges), 2))
    for k in np.unique(ring):
        mine = np.flatnonzero(ring == k)
        loop = shapely.LinearRing(rings[k])
        start = shapely.line_locate_point(loop, shapely.points(vertices[edges[mine, 0]]))
        end = shapely.line_locate_point(loop, shapely.points(vertices[edges[mine, 1]]))
        along = start + 0.5 * np.mod(end - start, loop.length)
        out[mine] = shapely.get_coordinates(shapely.line_interpolate_point(
            loop, np.mod(along, loop.length)))
    return out


def _edge_index(edges, pairs, count) -> np.ndarray:
    """The row of ``edges`` holding each undirected vertex pair of ``pairs``."""
    def key(pair):
        pair = np.sort(np.asarray(pair, dtype=np.int64).reshape(-1, 2), axis=1)
        return pair[:, 0] * count + pair[:, 1]
    known = key(edges)
    order = np.argsort(known)
    return order[np.searchsorted(known, key(pairs), sorter=order)]


def _shape_gradients(xi, eta) -> np.ndarray:
    """(6, 2) gradients of the quadratic shape functions at a reference point."""
    l1, l2, l3 = 1 - xi - eta, xi, eta
    d1, d2, d3 = np.array([-1.0, -1.0]), np.array([1.0, 0.0]), np.array([0.0, 1.0])
    return np.array([(4 * l1 - 1) * d1, (4 * l2 - 1) * d2, (4 * l3 - 1) * d3,
                     4 * (l1 * d2 + l2 * d1), 4 * (l2 * d3 + l3 * d2), 4 * (l3 * d1 + l1 * d3)])


def _jacobians(nodes, at) -> np.ndarray:
    """det J of each triangle's quadratic map at reference points ``at`` (k, 2): (M, k)."""
    out = np.empty((len(nodes), len(at)))
    x, y = np.ascontiguousarray(nodes[..., 0]), np.ascontiguousarray(nodes[..., 1])
    for k, (xi, eta) in enumerate(at):
        gradients = _shape_gradients(xi, eta)
        dx, dy = x @ gradients, y @ gradients              # (M, 2): d/dξ, d/dη
        out[:, k] = dx[:, 0] * dy[:, 1] - dx[:, 1] * dy[:, 0]
    return out


_MONOMIALS = np.column_stack([np.ones(6), _REFERENCE[:, 0], _REFERENCE[:, 1],
                              _REFERENCE[:, 0] ** 2, _REFERENCE.prod(axis=1),
                              _REFERENCE[:, 1] ** 2])


def _min_jacobian(nodes) -> np.ndarray:
    """The exact minimum of det J over each triangle.

    det J is quadratic: its values at the six nodes give its coefficients, and its
    minimum is at a corner, at a stationary point of an edge, or at the interior
    stationary point (any point of the triangle is a safe candidate, so the stationary
    points are clipped into it).
    """
    c = np.linalg.solve(_MONOMIALS, _jacobians(nodes, _REFERENCE).T).T   # 1 x y x² xy y²
    candidates = [np.broadcast_to(p, (len(nodes), 2)) for p in _REFERENCE[:3]]
    for a, b in ((0, 1), (1, 2), (2, 0)):
        start, direction = _REFERENCE[a], _REFERENCE[b] - _REFERENCE[a]
        # q(start + s d) = q0 + s (g·d) + s² (dᵀ H d) / 2 along the edge
        gradient = np.column_stack([c[:, 1] + 2 * c[:, 3] * start[0] + c[:, 4] * start[1],
                                    c[:, 2] + c[:, 4] * start[0] + 2 * c[:, 5] * start[1]])
        slope = gradient @ direction
        bend = (2 * c[:, 3] * direction[0] ** 2 + 2 * c[:, 4] * direction[0] * direction[1]
                + 2 * c[:, 5] * direction[1] ** 2)
        with np.errstate(all="ignore"):
            s = np.clip(np.where(bend > 0, -slope / bend, 0.0), 0.0, 1.0)
        candidates.append(start + s[:, None] * direction)
    hessian = np.stack([np.column_stack([2 * c[:, 3], c[:, 4]]),
                        np.column_stack([c[:, 4], 2 * c[:, 5]])], axis=1)
    determinant = np.linalg.det(hessian)
    safe = np.where(np.abs(determinant)[:, None, None] > 1e-300, hessian, np.eye(2))
    inner = np.linalg.solve(safe, -c[:, 1:3, None])[..., 0]
    inside = (inner >= 0).all(axis=1) & (inner.sum(axis=1) <= 1) & (np.abs(determinant) > 1e-300)
    candidates.append(np.where(inside[:, None], inner, 0.0))
    values = [c[:, 0] + c[:, 1] * p[:, 0] + c[:, 2] * p[:, 1] + c[:, 3] * p[:, 0] ** 2
              + c[:, 4] * p[:, 0] * p[:, 1] + c[:, 5] * p[:, 1] ** 2 for p in candidates]
    return np.min(values, axis=0)


_GAUSS_POINTS = np.array([[1 / 6, 1 / 6], [2 / 3, 1 / 6], [1 / 6, 2 / 3]])
"""Degree-2 exact quadrature on the reference triangle (weights 1/6 each)."""


def _jacobian_integral(nodes) -> np.ndarray:
    """The area of each curved triangle: the integral of its (quadratic) det J."""
    return _jacobians(nodes, _GAUSS_POINTS).sum(axis=1) / 6
