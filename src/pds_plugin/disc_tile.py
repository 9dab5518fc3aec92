"""A periodic maximal disc sampling of the plane: one square tile of points, radius 1,
whose copies side by side are a maximal Poisson disc sampling of the whole plane.

The graded sampler seeds the interior of large featureless regions with it (the planar
faces of :func:`pds_plugin.remesh`, ``graded_poisson_disc(..., tile=True)``). Every tile
point still has to pass the sampler's own insertion test, and the sampler's boxes prove
maximality as for darts; what the tile brings is a *known* Delaunay triangulation. Every
triangle of the periodic Delaunay triangulation of the tile has circumradius at most
:attr:`Tile.cover` (< 1), so a point x lying in one is within ``cover`` of its nearest
corner and within ``2 cover`` of all three: where every tile point within ``2 cover``
of a box was accepted, the box is covered and needs no dart.

The tile ships as ``_disc_tile.npy`` (its side, then its points), made once by
:func:`make_tile` (``python -m pds_plugin.disc_tile``): dart throwing on the torus, then a
sample at the circumcentre of every Delaunay triangle wider than 1 until none is left.
Its separation and its cover are measured when it is loaded, not trusted.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

__all__ = ["Tile", "tile", "make_tile", "periodic_cover", "periodic_separation"]

FILE = Path(__file__).with_name("_disc_tile.npy")


class Tile(NamedTuple):
    """A periodic disc sampling of radius 1 of the square [0, side)²."""
    points: np.ndarray      # (n, 2), in [0, side)²
    side: float
    cover: float            # the largest circumradius of its periodic Delaunay triangles


@functools.cache
def tile() -> Tile:
    """The shipped tile, its separation (at least 1 across the tile's edges too) and
    its cover measured.

    Examples
    --------
    >>> t = tile()
    >>> len(t.points) > 300, t.cover < 1
    (True, True)
    """
    data = np.load(FILE)
    side, points = float(data[0, 0]), np.ascontiguousarray(data[1:])
    if periodic_separation(points, side) < 1.0:
        raise RuntimeError(f"{FILE.name} is not a disc sampling of radius 1; remake it with "
                           f"python -m pds_plugin.disc_tile")
    return Tile(points, side, periodic_cover(points, side))


def _copies(points, side) -> np.ndarray:
    """The points and their 8 copies around the tile (the tile in the middle, first)."""
    shifts = np.array([(0, 0)] + [(a, b) for a in (-1, 0, 1) for b in (-1, 0, 1)
                                  if (a, b) != (0, 0)], float) * side
    return (points[None] + shifts[:, None]).reshape(-1, 2)


def periodic_separation(points, side) -> float:
    """The smallest distance between two points of the periodic sampling."""
    from scipy.spatial import cKDTree

    distance, _ = cKDTree(points, boxsize=side).query(points, k=2)
    return float(distance[:, 1].min())


def periodic_cover(points, side) -> float:
    """The largest circumradius of the periodic Delaunay triangles of ``points`` (the
    triangles with a corner in the tile, from the triangulation of the tile and its 8
    neighbours): the farthest a point of the plane lies from the sampling."""
    return float(_circumcircles(points, side)[1].max())


def _circumcircles(points, side):
    """Centres and radii of the periodic Delaunay triangles with a corner in the tile."""
    from scipy.spatial import Delaunay

    every = _copies(points, side)
    triangles = Delaunay(every).simplices
    triangles = triangles[(triangles < len(points)).any(axis=1)]
    a, b, c = (every[triangles[:, k]] for k in range(3))
    ab, ac = b - a, c - a
    d = 2.0 * (ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    bb, cc = (ab ** 2).sum(1), (ac ** 2).sum(1)
    centre = np.stack([ac[:, 1] * bb - ab[:, 1] * cc, ab[:, 0] * cc - ac[:, 0] * bb], 1)
    centre /= d[:, None]
    return a + centre, np.hypot(centre[:, 0], centre[:, 1])


def make_tile(cells: int, seed: int = 0) -> tuple[np.ndarray, float]:
    """A maximal disc sampling of radius 1 of the torus of side ``cells / √2`` (a grid
    of ``cells``² cells of side 1/√2, at most one point each): darts uniform on the
    torus, 40 per cell, each kept if no point lies within 1 across the tile's edges;
    then, while a periodic Delaunay triangle has circumradius above 1, a point at the
    circumcentre of the widest (more than 1 from every point: maximal at the end).

    Examples
    --------
    >>> points, side = make_tile(8, seed=1)
    >>> bool(periodic_separation(points, side) >= 1), bool(periodic_cover(points, side) <= 1)
    (True, True)
    """
    side = cells / math.sqrt(2)
    h = side / cells
    rng = np.random.default_rng(seed)
    grid = -np.ones((cells, cells), np.int64)
    points = []

    def cell(x, y):
        return int(x / h) % cells, int(y / h) % cells

    def free(x, y):
        i, j = cell(x, y)
        for di in range(-2, 3):
            for dj in range(-2, 3):
                k = grid[(i + di) % cells, (j + dj) % cells]
                if k >= 0:
                    dx = (points[k][0] - x + side / 2) % side - side / 2
                    dy = (points[k][1] - y + side / 2) % side - side / 2
                    if dx * dx + dy * dy < 1.0:
                        return False
        return True

    def add(x, y):
        x, y = x % side, y % side
        grid[cell(x, y)] = len(points)
        points.append((x, y))

    for x, y in rng.random((40 * cells * cells, 2)) * side:
        if grid[cell(x, y)] < 0 and free(x, y):
            add(x, y)
    while True:
        centre, radius = _circumcircles(np.array(points), side)
        if radius.max() <= 1.0:
            return np.array(points), side
        widest = centre[np.argmax(radius)]
        if not free(*widest):           # cannot be: the circumcircle is empty
            raise RuntimeError("the tile's Delaunay triangulation is degenerate")
        add(*widest)


if __name__ == "__main__":
    points, side = make_tile(34)
    np.save(FILE, np.vstack([[side, side], points]))
    print(f"{FILE}: {len(points)} points, side {side:.6g}, "
          f"cover {periodic_cover(points, side):.6f}")
