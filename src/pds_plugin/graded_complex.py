"""The constrained complex of a graded sampling (docs/graded.md, section 1): the
constrained Delaunay triangles of the samples whose circumradius ρ is at most
min_v r(v) / (1 - L) over their three vertices v.

This keeps every triangle with ρ <= r at its circumcentre z (r(v) >= r(z) - L ρ), and
the angle bound of docs/graded.md holds for it as it is: the shortest edge pq has
|pq| >= min(r(p), r(q)) >= (1 - L) ρ. It needs r only at the samples. The search is the
uniform complex's (:mod:`.local_complex`) with a bound per point: a kept
triangle is found from its smallest vertex i among the points within 2 r(i) / (1 - L).
Near-cocircular ties are settled exactly, as the uniform complex does (complex.py).
"""

from __future__ import annotations

import math

import numpy as np

from . import _complex_kernels as ckern
from . import _visibility_kernels as vis_kern
from ._checks import check_grading
from .boundary_sampling import chord_reach, graded_chords
from .errors import ArgumentError
from .local_complex import check_distinct, checked_points, checked_rings, local_faces

__all__ = ["graded_alpha_complex"]

_MAX_BINS = 4_000_000


def graded_alpha_complex(points, radius, grading: float, *, boundary=None,
                         chords=None) -> np.ndarray:
    """The constrained Delaunay triangles of ``points`` with circumradius at most
    min r(v) / (1 - L) over their vertices v, counter-clockwise, as an (M, 3) int64
    array.

    Parameters
    ----------
    points : (N, 2) array_like
        Distinct, finite points.
    radius : (N,) array_like
        r at each point (an L-Lipschitz radius field, e.g. ``Samples.radius``).
    grading : float
        The Lipschitz constant L of the field, in (0, 1).
    boundary : sequence of (k,) int array_like, optional
        Rings of point indices with the region on their left (``Samples.rings``): the
        complex is then constrained to the region they bound.
    chords : ChordBundle, optional
        The chords of ``boundary``, each binned within its reach
        (:func:`.boundary_sampling.graded_chords` with
        :func:`.boundary_sampling.chord_reach` of these points and radii), its ``out``
        indexed like ``points``: the graded sampler's (``Samples.chords``), taken
        instead of binning the chords again. The triangles are the same.

    Returns
    -------
    (M, 3) int64 ndarray

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If the points are not distinct finite 2D points, ``radius`` is not positive and
        one per point, ``grading`` is not in (0, 1) or ``chords`` does not index the
        points.
    BudgetError
        If too many triangles need the exact empty-circle test.

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> graded_alpha_complex(square, [0.8] * 4, 0.2).tolist()     # ρ 0.707 <= 0.8 / 0.8
    [[0, 1, 2], [0, 2, 3]]
    >>> graded_alpha_complex(square, [0.8, 0.8, 0.8, 0.5], 0.2).tolist()  # at 3: 0.707 > 0.5 / 0.8
    [[0, 1, 2]]
    """
    points = checked_points(points)
    grading = check_grading(grading)
    radius = np.asarray(radius, float).reshape(-1)
    if len(radius) != len(points) or not (np.isfinite(radius).all() and (radius > 0).all()):
        raise ArgumentError(f"radius must hold one positive finite value per point "
                            f"({len(points)}), got {len(radius)} values")
    rings = checked_rings(boundary, len(points))
    if len(points) < 3:
        return np.empty((0, 3), np.int64)
    bound = radius / (1.0 - grading) * (1 + 1e-12)
    lo = points.min(axis=0)
    hi = points.max(axis=0)
    area = max(float(np.prod(hi - lo)), 1e-300)
    h = max(float(np.median(bound)), math.sqrt(area / _MAX_BINS), 1e-300)
    nx, ny = (int(v) + 1 for v in (hi - lo) / h)
    order, start = ckern.bin_points(points, lo[0], lo[1], h, nx, ny)
    binned = np.ascontiguousarray(points[order])
    check_distinct(binned, order, start, rings)
    if chords is None or not rings:
        vis = _chords(points, rings, radius, grading)
    elif len(chords.out) != len(points):
        raise ArgumentError(f"chords must index the {len(points)} points (its out has "
                            f"{len(chords.out)} entries): pass the sampling's Samples.chords")
    else:
        vis = chords
    vis = vis._replace(out=np.ascontiguousarray(vis.out[order]))     # indexed like binned
    bound = np.ascontiguousarray(bound[order])
    return order[local_faces(binned, order, start, lo[0], lo[1], h, nx, ny, vis,
                             float(bound.max()), bound)]


def _chords(points, rings, radius, grading):
    """The rings' chords, each binned within its reach
    (:func:`.boundary_sampling.chord_reach`) on a grid over the points grown by the
    largest reach, of cells at least the smallest r."""
    if not rings:
        return vis_kern.no_chords(len(points))
    reach = chord_reach(points, rings, radius, grading)
    lo = points.min(axis=0) - reach.max()
    hi = points.max(axis=0) + reach.max()
    smallest = max(float(radius.min()), math.sqrt(float(np.prod(hi - lo)) / _MAX_BINS))
    return graded_chords(points, rings, reach, len(points), float(lo[0]), float(lo[1]),
                         *(hi - lo), smallest)
