"""Shared fixtures and the independent oracles the tests compare against."""

import os
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import settings
from scipy.spatial import Delaunay, cKDTree

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"

# CI replays the same examples every run, so a red run is reproducible; locally
# hypothesis explores new ones each time.
settings.register_profile("ci", derandomize=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


def cracked_stl(mesh, path):
    """``mesh`` (a trimesh.Trimesh) as an STL whose facets store one vertex a float32
    unit in the last place apart (every other corner moved up by one): read back, the
    part is open everywhere."""
    import trimesh

    corners = mesh.vertices[mesh.faces].reshape(-1, 3).astype(np.float32)
    corners[::2] = np.nextafter(corners[::2], np.float32(np.inf))
    trimesh.Trimesh(corners, np.arange(len(corners)).reshape(-1, 3),
                    process=False).export(path)
    return path


def shared_file(name: str) -> Path:
    """A file of ../shared/data, or skip the test when it is absent."""
    path = DATA / name
    if not path.exists():
        pytest.skip(f"{path} not available")
    return path


def delaunay_alpha_faces(points, alpha):
    """Oracle: scipy's (Qhull) Delaunay triangles with circumradius <= alpha."""
    if len(points) < 3:
        return np.empty((0, 3), int)
    tri = Delaunay(points).simplices
    a, b, c = (points[tri[:, k]] for k in range(3))
    ab, ac, bc = b - a, c - a, c - b
    cross = np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    with np.errstate(divide="ignore"):
        radius = (np.linalg.norm(ab, axis=1) * np.linalg.norm(ac, axis=1)
                  * np.linalg.norm(bc, axis=1) / (2 * cross))
    return tri[radius <= alpha]


def face_set(faces):
    return set(map(tuple, np.sort(np.asarray(faces), axis=1).tolist()))


def min_distance(points):
    return cKDTree(points).query(points, k=2)[0][:, 1].min()


def probe_gap(geometry, points, spacing):
    """Oracle: the largest distance to the samples over probes of the region: every
    Voronoi vertex (scipy) inside it, and the boundary at ``spacing``. A lower bound of
    the true coverage gap, within ``spacing`` of it."""
    tree = cKDTree(points)
    probes = [shapely.get_coordinates(shapely.segmentize(geometry.boundary, spacing))]
    if len(points) >= 3:
        tri = Delaunay(points)
        a, b, c = (points[tri.simplices[:, k]] for k in range(3))
        b, c = b - a, c - a
        d = 2 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
        ux = (c[:, 1] * (b ** 2).sum(1) - b[:, 1] * (c ** 2).sum(1)) / d
        uy = (b[:, 0] * (c ** 2).sum(1) - c[:, 0] * (b ** 2).sum(1)) / d
        centres = a + np.column_stack([ux, uy])
        probes.append(centres[shapely.intersects_xy(geometry, centres[:, 0], centres[:, 1])])
    probes = np.concatenate(probes)
    return tree.query(probes)[0].max()


def visible_probe_gap(geometry, domain, points, spacing):
    """Oracle of the coverage gap with the visibility rule: over probes of ``geometry``
    (a grid of step ``spacing`` and its boundary at ``spacing``), the distance to the
    nearest sample whose segment to the probe stays in ``domain`` (shapely, buffered by
    1e-9 against rounding). Returns the largest distance and its probe."""
    xmin, ymin, xmax, ymax = geometry.bounds
    xs, ys = np.meshgrid(np.arange(xmin, xmax + spacing, spacing),
                         np.arange(ymin, ymax + spacing, spacing))
    grid = np.column_stack([xs.ravel(), ys.ravel()])
    grid = grid[shapely.intersects_xy(geometry, grid[:, 0], grid[:, 1])]
    probes = np.concatenate([grid, shapely.get_coordinates(
        shapely.segmentize(geometry.boundary, spacing))])
    domain = domain.buffer(1e-9)
    shapely.prepare(domain)
    best = np.full(len(probes), np.inf)
    for point in points:
        distance = np.hypot(*(probes - point).T)
        closer = np.flatnonzero(distance < best)
        segments = np.stack([probes[closer], np.broadcast_to(point, (len(closer), 2))], axis=1)
        seen = closer[shapely.covers(domain, shapely.linestrings(segments))]
        best[seen] = distance[seen]
    k = int(np.argmax(best))
    return best[k], probes[k]


def visible_min_distance(domain, points, edges=()):
    """Oracle of the separation with the visibility rule: the smallest distance between
    two points whose segment stays in ``domain`` (buffered by 1e-9), or joined by one of
    ``edges``; every pair is tested."""
    domain = domain.buffer(1e-9)
    i, j = np.triu_indices(len(points), k=1)
    seen = shapely.covers(domain, shapely.linestrings(np.stack([points[i], points[j]], axis=1)))
    distance = np.hypot(*(points[i] - points[j]).T)
    joined = [np.hypot(*(points[a] - points[b])) for a, b in edges]
    return min(distance[seen].min(initial=np.inf), min(joined, default=np.inf))


def chord_region(points, rings, region):
    """The region bounded by the chords between consecutive boundary samples."""
    rings = [points[r] for r in rings]
    polygons, k = [], 0
    for polygon in region.geometry.geoms:
        n = 1 + len(polygon.interiors)
        polygons.append(shapely.Polygon(rings[k], rings[k + 1:k + n]))
        k += n
    geometry = shapely.MultiPolygon(polygons)
    # chords of a spike of width 0 touch each other: GEOS overlays refuse that polygon
    return geometry if geometry.is_valid else shapely.make_valid(geometry)


def visible_pairs_closer_than(points, domain, alpha):
    """Pairs of samples closer than alpha whose segment stays in ``domain``."""
    pairs = cKDTree(points).query_pairs(alpha * (1 - 1e-9), output_type="ndarray")
    if not len(pairs):
        return pairs
    lines = shapely.linestrings(np.stack([points[pairs[:, 0]], points[pairs[:, 1]]], axis=1))
    return pairs[shapely.covers(domain.buffer(1e-9 * alpha), lines)]
