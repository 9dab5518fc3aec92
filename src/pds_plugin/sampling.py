"""Maximal Poisson disc sampling of a planar region.

The sampling is built in three stages, each conditioned on the samples before it, with
the Euclidean distance between *all* samples respected (across narrow gaps and between
components):

1. **Feature corners.** Boundary vertices where the outline turns by at least
   ``feature_angle`` degrees, sharpest first, wherever the Poisson condition allows.
2. **Boundary.** The boundary is cut into pieces shorter than ``alpha``. Visiting them
   in random order, the part of each piece farther than ``alpha`` from every sample is
   computed exactly and a sample is placed uniformly in it. A sample covers its whole
   piece, so one pass gives a maximal sampling of the boundary curves.
3. **Interior.** Dart throwing on a grid of cells of side < alpha/√2 (one sample per
   cell at most), then the adaptive refinement of Ebeida et al. (2012): cells not yet
   covered by a single disc are split in four, children covered by one disc or outside
   the region are dropped, and a dart is thrown in each child, until no child is left
   or children are smaller than ``1e-10 * alpha`` (so the coverage radius is alpha to
   that tolerance).

Every random number comes from ``numpy.random.default_rng(seed)`` in a fixed order, so
the same region, alpha and seed give the same samples bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from . import _sampling_kernels as kern
from ._checks import check_alpha, check_positive_int
from .errors import BudgetError
from .region import Region, require_region, turning_angles

__all__ = ["Samples", "poisson_disc", "estimate_samples", "largest_alpha", "DEFAULT_MAX_SAMPLES"]

DEFAULT_MAX_SAMPLES = 5_000_000
"""Refuse samplings expected to exceed this many samples. At the cap, mesh_region of a unit
square makes 4.97 M samples and 9.9 M triangles and peaked at 2.0 GiB resident (measured
with /usr/bin/time -v with the numba kernels, before the compiled engine)."""

_MAX_GRID_CELLS = 50_000_000    # about 1.5 GB of grids
_PHASE1_PASSES = 3
_RESOLUTION = 1e-10   # smallest refinement cell and boundary margin, relative to alpha


@dataclass(frozen=True)
class Samples:
    """A Poisson disc sampling, as :func:`poisson_disc` makes it.

    Attributes
    ----------
    points : (N, 2) float ndarray
        The samples, boundary samples first.
    on_boundary : (N,) bool ndarray
        True for the samples placed on the region's boundary.
    alpha : float
        The disc radius.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> samples = poisson_disc(Region.from_shapely(box(0, 0, 1, 1)), 0.25, seed=0)
    >>> len(samples) == len(samples.points), bool(samples.on_boundary[0])
    (True, True)
    """

    points: np.ndarray
    on_boundary: np.ndarray
    alpha: float

    def __len__(self) -> int:
        return len(self.points)


def estimate_samples(region: Region, alpha: float) -> float:
    """About how many samples a maximal sampling of ``region`` with radius ``alpha`` has:
    ``0.7 * area / alpha² + perimeter / alpha``.

    Parameters
    ----------
    region : Region
    alpha : float

    Returns
    -------
    float

    Examples
    --------

    >>> from shapely.geometry import box
    >>> round(estimate_samples(Region.from_shapely(box(0, 0, 1, 1)), 0.01))
    7400
    """
    return 0.7 * region.area / alpha / alpha + region.perimeter / alpha   # inf, never an error


def largest_alpha(region: Region, max_samples: int) -> float:
    """The alpha at which :func:`estimate_samples` equals ``max_samples``: the smallest
    radius a sample budget allows.

    Parameters
    ----------
    region : Region
    max_samples : int

    Returns
    -------
    float

    Examples
    --------
    >>> from shapely.geometry import box
    >>> square = Region.from_shapely(box(0, 0, 1, 1))
    >>> round(estimate_samples(square, largest_alpha(square, 7400)))
    7400
    """
    a, p = 0.7 * region.area, region.perimeter
    return (p + math.sqrt(p * p + 4 * max_samples * a)) / (2 * max_samples)


def poisson_disc(region: Region, alpha: float, seed: int = 0, *,
                 max_samples: int = DEFAULT_MAX_SAMPLES,
                 feature_angle: float = 30.0) -> Samples:
    """Maximal Poisson disc sampling of ``region`` with radius ``alpha``.

    Every two samples are at least ``alpha`` apart, every point of the region is within
    ``alpha`` of a sample, and the boundary is sampled first (see the module docstring).

    Parameters
    ----------
    region : Region
    alpha : float
        The disc radius, in the region's units.
    seed : int
        Seed of the random generator; the same seed gives the same samples.
    max_samples : int
        Refuse (with a :class:`~pds_plugin.errors.BudgetError`) when about more samples
        than this would be made.
    feature_angle : float
        Boundary vertices where the outline turns by at least this many degrees are
        sampled first, as feature points.

    Returns
    -------
    Samples

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``region`` is not a Region or ``alpha`` is not a positive number.
    BudgetError
        If the sampling would exceed ``max_samples`` (the message gives the estimate and
        the largest acceptable alpha) or the grid would be too large.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> region = Region.from_shapely(box(0, 0, 1, 1))
    >>> samples = poisson_disc(region, 0.1, seed=1)
    >>> bool(samples.on_boundary.any()), samples.points.shape[1]
    (True, 2)
    """
    require_region(region, "poisson_disc")
    alpha = check_alpha(alpha)
    max_samples = check_positive_int(max_samples, "max_samples")
    expected = estimate_samples(region, alpha)
    if expected > max_samples:
        raise BudgetError(
            f"alpha={alpha:.6g} would make about {expected:.3g} samples, more than "
            f"max_samples={max_samples}; use alpha >= {largest_alpha(region, max_samples):.6g} "
            "or raise max_samples")
    rng = np.random.default_rng(seed)
    sampler = _Sampler(region, alpha)
    sampler.add_corners(feature_angle)
    sampler.add_boundary(rng)
    n_boundary = sampler.count
    sampler.add_interior(rng)
    points = sampler.points[:sampler.count].copy()
    on_boundary = np.zeros(len(points), bool)
    on_boundary[:n_boundary] = True
    return Samples(points, on_boundary, alpha)


class _Sampler:
    """The state of one sampling: grid of cells, cell status, samples so far."""

    def __init__(self, region: Region, alpha: float):
        self.region = region
        self.alpha = alpha
        self.s = alpha / math.sqrt(2) * (1 - 1e-9)   # cell side: < alpha/√2, one sample per cell
        xmin, ymin, xmax, ymax = region.bounds
        self.x0, self.y0 = xmin - 0.5 * self.s, ymin - 0.5 * self.s
        self.nx = int((xmax - self.x0) / self.s) + 2
        self.ny = int((ymax - self.y0) / self.s) + 2
        if self.nx * self.ny > _MAX_GRID_CELLS:
            raise BudgetError(
                f"the region's bounding box spans {self.nx * self.ny:.3g} grid cells at "
                f"alpha={alpha:.6g} (the limit is {_MAX_GRID_CELLS:.0e}); use a larger alpha "
                "or mesh the far-apart parts of the region separately")
        self.status = kern.classify_cells(region.segments, self.x0, self.y0, self.s,
                                          self.nx, self.ny)
        self.grid = np.full((self.ny, self.nx), -1, np.int32)
        self.covered = np.zeros((self.ny * kern.SUB, self.nx * kern.SUB), bool)
        self.head = np.full(self.ny * self.nx, -1, np.int64)     # scratch of throw_darts
        capacity = int(np.count_nonzero(self.status))
        self.points = np.empty((capacity, 2))
        self.count = 0
        self.geometry = region.geometry
        shapely.prepare(self.geometry)

    def _insert(self, candidates):
        self.count = kern.insert_where_free(np.ascontiguousarray(candidates, float), self.grid,
                                            self.covered, self.points, self.count, self.alpha,
                                            self.x0, self.y0, self.s)

    def add_corners(self, feature_angle: float):
        corners, turns = [], []
        for ring in self.region.rings:
            turn = np.abs(turning_angles(ring))
            sharp = turn >= np.radians(feature_angle)
            corners.append(ring[sharp])
            turns.append(turn[sharp])
        corners, turns = np.concatenate(corners), np.concatenate(turns)
        self._insert(corners[np.argsort(-turns, kind="stable")])

    def add_boundary(self, rng):
        start, direction, length = self.region.boundary_pieces(self.s)
        order = rng.permutation(len(start))
        u = rng.random(len(start))
        self.count = kern.sample_boundary_pieces(
            start, direction, length, order, u, self.grid, self.covered, self.points, self.count,
            self.alpha, _RESOLUTION * self.alpha, self.x0, self.y0, self.s)

    def add_interior(self, rng):
        s = self.s
        # stage 1: dart passes over the level-0 cells in random order; each dart goes to
        # a random sub-cell of its cell that no disc covers yet
        cells = np.flatnonzero(self.status.ravel())
        for _ in range(_PHASE1_PASSES):
            darts, is_open = kern.darts_in_open_subcells(cells, rng.random((len(cells), 3)),
                                                         self.grid, self.covered, self.x0, self.y0, s)
            cells = cells[is_open]
            self._throw(cells, darts[is_open], rng)
        # stage 2: throw darts in the sub-cells no single disc covers, splitting them in
        # four at each level, until none is left
        parent, sub_x, sub_y = kern.open_subcells(self.status, self.grid, self.covered)
        level = int(np.log2(kern.SUB))
        while len(parent):
            size = s / 2**level
            bx, by = self._box(parent, sub_x, sub_y, level)
            keep = self._uncovered(parent, bx, by, size)
            on_edge = keep & (self.status.ravel()[parent] == kern.BOUNDARY)
            keep[on_edge] = shapely.intersects(
                self.geometry, shapely.box(bx[on_edge], by[on_edge],
                                           bx[on_edge] + size, by[on_edge] + size))
            parent, sub_x, sub_y, bx, by = (a[keep] for a in (parent, sub_x, sub_y, bx, by))
            self._throw(parent, np.column_stack([bx, by]) + rng.random((len(bx), 2)) * size, rng)
            keep = self._uncovered(parent, bx, by, size)
            if size / 2 < _RESOLUTION * self.alpha:
                break
            level += 1
            parent = np.repeat(parent[keep], 4)
            sub_x = 2 * np.repeat(sub_x[keep], 4) + np.tile([0, 1, 0, 1], len(parent) // 4)
            sub_y = 2 * np.repeat(sub_y[keep], 4) + np.tile([0, 0, 1, 1], len(parent) // 4)

    def _box(self, cells, sub_x, sub_y, level):
        """Lower-left corners of the level-``level`` children (sub_x, sub_y) of cells."""
        size = self.s / 2**level
        return (self.x0 + (cells % self.nx) * self.s + sub_x * size,
                self.y0 + (cells // self.nx) * self.s + sub_y * size)

    def _uncovered(self, cells, bx, by, size):
        return kern.uncovered_boxes(cells, bx, by, size, self.grid, self.points, self.alpha)

    def _in_region(self, cells, darts):
        """True for darts in the region; only darts in boundary cells need the test."""
        inside = np.ones(len(cells), bool)
        on_edge = self.status.ravel()[cells] == kern.BOUNDARY
        inside[on_edge] = shapely.contains_xy(self.geometry, darts[on_edge, 0], darts[on_edge, 1])
        return inside

    def _throw(self, cells, darts, rng):
        """Throw the darts in random order (dart k lies in level-0 cell ``cells[k]``;
        ``cells`` is sorted)."""
        self.count = kern.throw_darts(darts, cells, rng.permutation(len(cells)),
                                      self._in_region(cells, darts), self.grid, self.covered,
                                      self.head, self.points, self.count, self.alpha, self.x0, self.y0, self.s)
