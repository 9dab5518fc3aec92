"""What the table measures on every mesh, the same way for every peer.

Nothing here trusts the mesher: quality comes from :func:`pds_plugin.triangle_quality`,
topology from the Euler characteristic (:func:`pds_plugin.mesh.mesh_betti`), and the
coverage gap and boundary distance from independent computations with scipy and shapely
(not from pds_plugin's certificate, which the pds rows are checked against).
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy.spatial import Delaunay, cKDTree

from pds_plugin.analysis.quality import ASPECT_BOUND, triangle_quality
from pds_plugin.mesh import mesh_betti

PROBES_PER_ALPHA = 50
"""Boundary probes per length alpha: distances are then exact to alpha / 100."""


def measure(region, vertices, faces, alpha, samples=None) -> dict:
    """Every column of the table for one mesh (see the module docstring).

    ``samples`` is the point set of a sampler, whose coverage gap is measured; the gap
    and the boundary distance are ratios to ``alpha``.
    """
    vertices = np.asarray(vertices, float)
    faces = np.asarray(faces, np.int64).reshape(-1, 3)
    quality = triangle_quality(vertices, faces)
    aspect, angles = quality.aspect_ratio, quality.angles
    betti = betti_numbers(faces, len(vertices))
    empty = len(faces) == 0
    return {
        "vertices": int(len(vertices)),
        "triangles": int(len(faces)),
        "min_angle": np.nan if empty else float(angles.min()),
        "max_angle": np.nan if empty else float(angles.max()),
        "max_aspect": np.nan if empty else float(aspect.max()),
        "mean_aspect": np.nan if empty else float(aspect[np.isfinite(aspect)].mean()),
        "above_bound": np.nan if empty else float(np.mean(aspect > ASPECT_BOUND * (1 + 1e-9))),
        "coverage_gap": np.nan if samples is None else coverage_gap(region, samples, alpha) / alpha,
        "betti": betti,
        "topology_ok": betti == region.betti,
        "area_ratio": float(quality.area.sum() / region.area),
        "hausdorff": (np.nan if empty
                      else boundary_hausdorff(region, vertices, faces, alpha) / alpha),
        "nonmanifold_edges": nonmanifold_edges(faces),
        "aspect": aspect,
    }


def coverage_gap(region, points, alpha) -> float:
    """The largest distance from a point of ``region`` to the nearest of ``points``.

    The distance to a point set peaks at a Voronoi vertex (the circumcentre of a Delaunay
    triangle, at distance its circumradius) inside the region, or on the boundary. The
    first are exact; the boundary is probed every ``alpha / PROBES_PER_ALPHA`` (the
    distance is 1-Lipschitz, so the probes miss at most half a step).
    """
    points = np.asarray(points, float)
    if len(points) == 0:
        return np.inf
    probes = _probes(region.segments, alpha / PROBES_PER_ALPHA)
    gap = float(cKDTree(points).query(probes)[0].max())
    if len(points) >= 3:
        triangulation = Delaunay(points)
        corners = points[triangulation.simplices]
        centre, radius = _circumcircles(corners)
        inside = shapely.contains_xy(region.geometry, centre[:, 0], centre[:, 1])
        gap = max(gap, float(radius[inside].max(initial=0.0)))
    return gap


def boundary_hausdorff(region, vertices, faces, alpha) -> float:
    """Hausdorff distance between the region's boundary and the mesh's boundary edges.

    Each boundary's farthest point from the other is found to ``alpha / 100`` (see
    :func:`_farthest`), with exact point-to-segment distances (shapely STRtree nearest):
    shapely's Hausdorff distance of the two curves without the quadratic cost of
    ``shapely.hausdorff_distance`` on a million-vertex boundary.
    """
    mesh_segments = vertices[boundary_edges(faces)]
    if len(mesh_segments) == 0:
        return np.inf
    step = alpha / PROBES_PER_ALPHA
    return max(_farthest(region.segments, mesh_segments, step),
               _farthest(mesh_segments, region.segments, step))


def betti_numbers(faces, n_vertices) -> tuple[int, int]:
    """(components, holes) of a triangle mesh, summed over its components."""
    if len(faces) == 0:
        return (0, 0)
    _, per_component = mesh_betti(faces, n_vertices)
    b0, b1 = per_component.sum(axis=0)
    return (int(b0), int(b1))


def boundary_edges(faces) -> np.ndarray:
    """(K, 2) vertex pairs of the edges in exactly one triangle."""
    edges, counts = _edge_counts(faces)
    return edges[counts == 1]


def nonmanifold_edges(faces) -> int:
    """Edges shared by more than two triangles."""
    return int(np.count_nonzero(_edge_counts(faces)[1] > 2))


def _edge_counts(faces):
    """The distinct edges (K, 2) of ``faces`` and how many triangles hold each."""
    pairs = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    n = int(faces.max(initial=0)) + 1
    keys, counts = np.unique(pairs[:, 0] * n + pairs[:, 1], return_counts=True)
    return np.column_stack([keys // n, keys % n]), counts


def _circumcircles(corners):
    """Centres (M, 2) and radii (M,) of the circles through each triangle's corners."""
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    b, c = b - a, c - a
    d = 2 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    b2, c2 = (b * b).sum(axis=1), (c * c).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        offset = np.column_stack([c[:, 1] * b2 - b[:, 1] * c2,
                                  b[:, 0] * c2 - c[:, 0] * b2]) / d[:, None]
    offset[~np.isfinite(offset).all(axis=1)] = np.inf     # collinear corners: no circle
    return a + offset, np.hypot(offset[:, 0], offset[:, 1])


def _probes(segments, step) -> np.ndarray:
    """Points along (m, 2, 2) segments, both ends included, at most ``step`` apart."""
    vector = segments[:, 1] - segments[:, 0]
    count = np.maximum(np.ceil(np.hypot(vector[:, 0], vector[:, 1]) / step), 1).astype(np.int64)
    owner = np.repeat(np.arange(len(segments)), count + 1)
    t = np.arange(len(owner)) - np.repeat(np.cumsum(count + 1) - (count + 1), count + 1)
    return segments[owner, 0] + (t / count[owner])[:, None] * vector[owner]


def _farthest(curve, segments, step) -> float:
    """The largest distance from a point of ``curve`` (its (m, 2, 2) segments) to the
    nearest of ``segments``, to ``step / 2``.

    The distance ``d`` is 1-Lipschitz along a segment of length L, so it stays below
    ``(d(start) + d(end) + L) / 2`` there: only the segments whose bound beats the
    farthest end point so far are probed every ``step`` (a mesh with thousands of
    pinholes has millions of probes otherwise).
    """
    tree = shapely.STRtree(shapely.linestrings(segments))

    def distances(points):
        _, found = tree.query_nearest(shapely.points(points), return_distance=True,
                                      all_matches=False)
        return found

    ends = distances(curve.reshape(-1, 2)).reshape(-1, 2)
    lengths = np.hypot(*(curve[:, 1] - curve[:, 0]).T)
    farthest = float(ends.max())
    open_ = (ends.sum(axis=1) + lengths) / 2 > farthest + step / 2
    if open_.any():
        farthest = max(farthest, float(distances(_probes(curve[open_], step)).max()))
    return farthest
