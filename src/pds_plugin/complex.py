"""The solid alpha-complex of a planar point set, built locally.

Every triangle of the solid alpha-complex has circumradius <= alpha, so its edges are
at most 2 alpha long and its circumcircle holds no other point within alpha of its
centre. With the points binned in cells of side alpha, each point's triangles are found
among its neighbours within 2 alpha and checked against the points of 3x3 cells, with no
global Delaunay triangulation: linear time, in parallel over the points. The search,
its exact empty-circle test and the constraint by the boundary's chords are
:mod:`.local_complex`'s, shared with the graded complex (:mod:`.graded_complex`).
"""

from __future__ import annotations

import numpy as np

from . import _complex_kernels as kern
from . import _visibility_kernels as vis_kern
from ._checks import check_alpha
from .errors import BudgetError
from .local_complex import check_distinct, checked_points, checked_rings, local_faces

__all__ = ["solid_alpha_complex"]

_MAX_CELLS = 200_000_000
_MAX_NEIGHBOURS = 256      # points within 2 alpha of one point: the local work grows as its cube


def solid_alpha_complex(points, alpha: float, *, boundary=None) -> np.ndarray:
    """The triangles of the Delaunay triangulation of ``points`` with circumradius
    ``<= alpha``, counter-clockwise, as an (M, 3) int64 array.

    Isolated edges and points are dropped: the result is the set of triangles, in an
    order that depends only on the input.

    Parameters
    ----------
    points : (N, 2) array_like of float
        Distinct, finite points.
    alpha : float
        The largest circumradius kept.
    boundary : sequence of (k,) int array_like, optional
        Rings of point indices (at least 3 each), each with the region on its left, as
        :func:`pds_plugin.poisson_disc` gives them (``Samples.rings``): the complex is
        then constrained to the region they bound (constrained Delaunay).

    Returns
    -------
    (M, 3) int64 ndarray
        Indices into ``points``, each triangle counter-clockwise.

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``points`` is not an (N, 2) array of finite numbers, has two equal points, or
        ``alpha`` is not a positive number.
    BudgetError
        If the points span too many cells of side ``alpha``.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> solid_alpha_complex(square, 0.75).tolist()    # cocircular: one diagonal, consistently
    [[0, 1, 2], [0, 2, 3]]
    >>> len(solid_alpha_complex(square, 0.7))         # circumradius 0.707 > 0.7
    0
    >>> notch = np.array([[0, 0], [2, 0], [2, 2], [1, 0.2], [0, 2]], float)   # a V-notch
    >>> solid_alpha_complex(notch, 3.0).tolist()      # the notch bridged
    [[0, 1, 3], [0, 3, 4], [1, 2, 3], [2, 4, 3]]
    >>> solid_alpha_complex(notch, 3.0, boundary=[[0, 1, 2, 3, 4]]).tolist()
    [[0, 1, 3], [0, 3, 4], [1, 2, 3]]
    """
    points = checked_points(points)
    alpha = check_alpha(alpha)
    rings = checked_rings(boundary, len(points))
    if len(points) < 3:
        return np.empty((0, 3), np.int64)
    h = alpha
    x0, y0 = points.min(axis=0)
    with np.errstate(over="ignore"):                 # an inf span is refused just below
        cells = np.prod(np.floor((points.max(axis=0) - points.min(axis=0)) / h) + 1)
    if not cells <= _MAX_CELLS:
        raise BudgetError(f"the points span {cells:.3g} cells of side alpha={alpha:.6g} "
                          f"(the limit is {_MAX_CELLS:.0e}); use a larger alpha or split the "
                          "point set into parts that are far apart")
    nx = int((points[:, 0].max() - x0) / h) + 1
    ny = int((points[:, 1].max() - y0) / h) + 1
    order, start = kern.bin_points(points, x0, y0, h, nx, ny)
    _check_work(points, alpha, np.diff(start).reshape(ny, nx))
    binned = points[order]                       # cell by cell: local memory access
    check_distinct(binned, order, start, rings)
    vis = vis_kern.chord_bundle(points, rings, len(points), 2 * alpha)
    vis = vis._replace(out=np.ascontiguousarray(vis.out[order]))     # indexed like binned
    return order[local_faces(binned, order, start, x0, y0, h, nx, ny, vis, alpha)]


def _check_work(points, alpha, counts) -> None:
    """Refuse, before any work, a point set whose neighbourhoods of radius 2 alpha are so
    crowded that the local complex is far from linear time (alpha huge for the points).

    ``counts`` are the points per cell of side alpha: the points within 2 alpha of a
    point lie in the 5 x 5 cells around its cell, so when no such block holds more than
    the limit (a Poisson sampling: about 18) nothing is counted point by point.

    Examples
    --------
    >>> points = np.random.default_rng(0).random((300, 2))
    >>> _check_work(points, 0.01, np.full((100, 100), 3))         # at most 75 per block
    >>> _check_work(points, 1.0, np.array([[300]]))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    pds_plugin.errors.BudgetError: 300 points lie within 2 alpha=2 of one point, ...
    """
    block = np.pad(counts, 2).cumsum(axis=0).cumsum(axis=1)     # sums over 5 x 5 cells
    block = np.pad(block, ((1, 0), (1, 0)))
    if (block[5:, 5:] - block[:-5, 5:] - block[5:, :-5] + block[:-5, :-5]).max() <= _MAX_NEIGHBOURS:
        return
    from scipy.spatial import cKDTree

    crowd = int(cKDTree(points).query_ball_point(points, 2 * alpha, return_length=True).max())
    if crowd > _MAX_NEIGHBOURS:
        raise BudgetError(f"{crowd} points lie within 2 alpha={2 * alpha:.6g} of one point, "
                          f"more than {_MAX_NEIGHBOURS} (a Poisson sampling has about 20): alpha "
                          f"is far larger than the points' spacing (of a region: than its holes "
                          f"and features, each of which keeps samples of its own; graded=True "
                          f"(pds-mesh --graded) meshes them finer and the rest at most alpha); "
                          f"use a smaller alpha, or subsample a point set")
