"""The local search both solid alpha-complexes share (:mod:`.complex`, one radius;
:mod:`.graded_complex`, a bound per point), and the checks of their inputs.

Each point's triangles are found among its binned neighbours (``_complex_kernels
.local_complex``, in parallel over the points), with no global Delaunay triangulation.

The empty-circle test is exact. A floating-point test with a proven error bound settles
almost every case; the rest are redone in exact arithmetic (in the kernel, Shewchuk's
expansions; here, integers, for the few whose coordinates' differences are not exact
floats), and ties (four or more cocircular points) are broken by symbolic perturbation
(Edelsbrunner and Mücke's simulation of simplicity, a lifting perturbation that
decreases with the point index).
The result is always part of one Delaunay triangulation: no overlaps, every edge shared
by at most two triangles.

Given the ``boundary`` (rings of points joined by chords, the region on their left) the
complex is *constrained*: a triangle's edges must run through the region bounded by the
chords, no chord may be an edge with the triangle on its outer side, and only points
that see a vertex of the triangle through the region count in the empty-circle test
(a constrained Delaunay triangulation, docs/conforming.md). The chords
(:class:`~pds_plugin._visibility_kernels.ChordBundle`) are looked up in a grid, only near
the boundary.
"""

from __future__ import annotations

import numpy as np

from . import _complex_kernels as kern
from .errors import ArgumentError, ArgumentTypeError, BudgetError
from .region import check_scale

__all__ = ["local_faces", "checked_points", "checked_rings", "check_distinct"]

_MAX_UNSURE = 5000         # triangles left to the exact (integer) empty-circle test


def local_faces(binned, order, start, x0, y0, h, nx, ny, vis, alpha, bound=None):
    """The triangles of the local complex of the binned points (``kern.local_complex``,
    with room for more neighbours until it completes), cocircular ties settled exactly;
    positions in ``binned``. With ``bound`` (graded complexes) a triangle is kept when its
    circumradius is at most the smallest bound of its vertices.

    Parameters
    ----------
    binned : (N, 2) float ndarray
        The points, cell by cell (``binned = points[order]``).
    order, start : int64 ndarray
        ``_complex_kernels.bin_points``'s CSR of the cells of side ``h`` from (x0, y0),
        nx by ny of them.
    x0, y0, h : float
    nx, ny : int
    vis : ChordBundle
        The boundary's chords, ``out`` indexed like ``binned``
        (:func:`~pds_plugin._visibility_kernels.no_chords` for none).
    alpha : float
        The largest circumradius kept (graded: the largest bound).
    bound : (N,) float ndarray, optional
        Graded complexes: each binned point's bound.

    Returns
    -------
    (M, 3) int64 ndarray
        Counter-clockwise triangles, positions in ``binned``.

    Raises
    ------
    BudgetError
        If too many triangles need the exact empty-circle test.

    Examples
    --------
    >>> from pds_plugin import _visibility_kernels as vis_kern
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> order, start = kern.bin_points(square, 0.0, 0.0, 1.0, 2, 2)
    >>> faces = local_faces(square[order], order, start, 0.0, 0.0, 1.0, 2, 2,
    ...                     vis_kern.no_chords(4), 0.75)
    >>> order[faces].tolist()                   # cocircular: one diagonal, consistently
    [[0, 1, 2], [0, 2, 3]]
    """
    max_neighbours = 64
    while True:
        faces, flags, status = kern.local_complex(binned, alpha, start, x0, y0, h, nx, ny,
                                                  max_neighbours, vis, order, bound)
        if status != kern.MORE_NEIGHBOURS:
            break
        max_neighbours *= 4
    unsure = np.flatnonzero(flags == kern.UNSURE)
    if status == kern.TOO_MANY_TIES or len(unsure) > _MAX_UNSURE:
        raise BudgetError("too many candidate triangles have four or more cocircular points "
                          "(a circle or lattice of points) for the exact tie-break to settle "
                          "in reasonable time; perturb the points slightly or use a smaller "
                          "alpha")
    if len(unsure):
        keep = np.ones(len(faces), bool)
        keep[unsure] = _exactly_empty(binned, order, faces[unsure], start, x0, y0, h, nx, ny,
                                      vis, None if bound is None else bound[faces[unsure]].max(axis=1))
        faces = faces[keep]
    return faces


def checked_points(points) -> np.ndarray:
    """``points`` as a C-contiguous (N, 2) float array of finite numbers (a copy), or a
    clear error."""
    try:
        points = np.array(points, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError("points must be an (N, 2) array of numbers") from None
    if points.ndim != 2 or points.shape[1] != 2:
        raise ArgumentError(f"points must be an (N, 2) array, got shape {points.shape}")
    if not np.isfinite(points).all():
        raise ArgumentError("points contain NaN or infinite coordinates")
    if len(points):                  # the predicates raise coordinates to powers up to 6
        check_scale((*points.min(axis=0), *points.max(axis=0)), "the points span",
                    "scale the points (e.g. change their units)", ArgumentError)
    return np.ascontiguousarray(points)


def checked_rings(boundary, n) -> list[np.ndarray]:
    """The ``boundary`` rings (None: none) as int64 arrays of at least 3 distinct indices
    into ``n`` points, or a clear error."""
    if boundary is None:
        return []
    rings = [np.asarray(ring) for ring in boundary]
    for ring in rings:
        if ring.ndim != 1 or len(ring) < 3 or ring.dtype.kind not in "iu":
            raise ArgumentError("each boundary ring must be a sequence of at least 3 point indices")
    if not rings:
        return []
    # every ring's indices checked at once: in range, and distinct within their ring
    sizes = [len(ring) for ring in rings]
    every = np.concatenate(rings).astype(np.int64)
    owner = np.repeat(np.arange(len(rings)), sizes)
    wrong = owner[(every < 0) | (every >= n)]
    codes = np.sort(owner * n + np.clip(every, 0, n - 1))
    wrong = np.concatenate([wrong, codes[1:][codes[1:] == codes[:-1]] // max(n, 1)])
    if len(wrong):
        raise ArgumentError(f"boundary ring indices must be distinct and in [0, {n}); "
                            f"got {rings[int(wrong.min())].tolist()[:8]}")
    ends = np.cumsum(sizes).tolist()
    return [every[end - size:end] for size, end in zip(sizes, ends)]


def check_distinct(binned, order, start, rings=()):
    """Duplicate points make the Delaunay triangulation undefined: refuse them. Two
    samples of the ``rings`` (index arrays) at one point are a boundary that runs back
    onto itself there: the message says so too (a region's samples, not a user's)."""
    p, q = kern.first_duplicate(binned, start)
    if p >= 0:
        i, j = sorted((int(order[p]), int(order[q])))
        point = tuple(binned[p].tolist())
        if len(rings) and np.isin([i, j], np.concatenate(rings)).all():
            raise ArgumentError(
                f"boundary samples {i} and {j} are the same point {point}: the boundary runs "
                f"back onto itself there (a spike or fold of zero width, its sides within "
                f"rounding of each other); remove that spike from the outline, or make "
                f"the region with Region.from_shapely(..., repair=True), which drops it")
        raise ArgumentError(f"points {i} and {j} are the same point {point}; "
                            "remove duplicates first (e.g. numpy.unique(points, axis=0))")


def _exactly_empty(binned, order, faces, start, x0, y0, h, nx, ny, vis, radius=None):
    """The empty-circle test of counter-clockwise faces (positions in ``binned``), in
    exact arithmetic, ties broken by the points' original indices ``order``; only the
    points that see a face count (``vis``). A circumradius is at most ``h`` (the cells
    around the circumcentre's hold every point in the circle), or at most its face's
    ``radius`` when given (graded complexes: as many cells as that takes). Every face
    and candidate point at once through the floating-point filter; the exact test and
    the visibility only where it finds a point inside or cannot decide."""
    a, b, c = binned[faces[:, 0]], binned[faces[:, 1]], binned[faces[:, 2]]
    # circumcentres (floating point is fine here: they only select the cells to look in)
    bx, by, cx, cy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1], c[:, 0] - a[:, 0], c[:, 1] - a[:, 1]
    cross = 2.0 * (bx * cy - by * cx)
    ux = a[:, 0] + (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / cross
    uy = a[:, 1] + (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / cross
    ix, iy = np.floor((ux - x0) / h).astype(np.int64), np.floor((uy - y0) / h).astype(np.int64)
    cells = (np.ones(len(faces), np.int64) if radius is None
             else np.ceil(np.asarray(radius) / h).astype(np.int64) + 1)
    low_x, high_x = np.maximum(ix - cells, 0), np.minimum(ix + cells + 1, nx)
    low_y, high_y = np.maximum(iy - cells, 0), np.minimum(iy + cells + 1, ny)
    wide, tall = np.maximum(high_x - low_x, 0), np.maximum(high_y - low_y, 0)
    # every (face, cell) of the blocks, then every (face, point) of those cells
    face_of_cell = np.repeat(np.arange(len(faces)), wide * tall)
    k = np.arange(len(face_of_cell)) - np.repeat(np.cumsum(wide * tall) - wide * tall, wide * tall)
    cell = ((low_y[face_of_cell] + k // wide[face_of_cell]) * nx
            + low_x[face_of_cell] + k % wide[face_of_cell])
    count = start[cell + 1] - start[cell]
    face_of = np.repeat(face_of_cell, count)
    point = (np.repeat(start[cell], count) + np.arange(count.sum())
             - np.repeat(np.cumsum(count) - count, count))
    other = np.all(faces[face_of] != point[:, None], axis=1)
    face_of, point = face_of[other], point[other]
    sign = _incircle_signs_filtered(a[face_of], b[face_of], c[face_of], binned[point])
    empty = np.ones(len(faces), bool)
    asked = sign >= 0
    face_of, point, sign = face_of[asked], point[asked], sign[asked]
    # the points of the undecided quadruples as exact integers, converted once each (the
    # floating-point filter above already found those determinants undecided)
    undecided = sign == 0
    involved = np.unique(np.concatenate([faces[face_of[undecided]].ravel(), point[undecided]]))
    exact = dict(zip(involved.tolist(), _integer_points(binned[involved])))
    rank = order.tolist()
    for f, m, decided in zip(face_of.tolist(), point.tolist(), sign.tolist()):
        if not empty[f]:
            continue
        u, v, w = faces[f].tolist()
        if ((decided or _perturbed_inside(exact[u], exact[v], exact[w], exact[m],
                                          rank[u], rank[v], rank[w], rank[m]))
                and kern.seen_by_triangle(binned, u, v, w, m, vis)):
            empty[f] = False
    return empty


def _integer_points(xy) -> list[tuple[int, int]]:
    """The (k, 2) float points as integer pairs, all scaled by one power of two (each
    float is m 2^e with m a 53-bit integer, from ``numpy.frexp``), so signs of
    polynomials homogeneous in the coordinates' differences are exact.

    >>> _integer_points(np.array([(0.5, 3.0), (0.25, -1.0)]))
    [(2, 12), (1, -4)]
    """
    if not len(xy):
        return []
    mantissa, exponent = np.frexp(np.asarray(xy, float))
    m = (mantissa * 2.0 ** 53).astype(np.int64)
    e = exponent.astype(np.int64) - 53
    nonzero = m != 0
    zeros = np.where(nonzero, np.log2(np.where(nonzero, m & -m, 1)).astype(np.int64), 0)
    m, e = m >> zeros, e + zeros          # odd mantissas: the smallest integers
    low = int(e[nonzero].min()) if nonzero.any() else 0
    shift = np.where(nonzero, e - low, 0)
    return [(x << s, y << t) for (x, y), (s, t) in zip(m.tolist(), shift.tolist())]


def _perturbed_inside(pa, pb, pc, pd, ia, ib, ic, id_) -> bool:
    """Is point d inside the circle through counter-clockwise a, b, c, given as integer
    points ``pa``..``pd`` (one scale) with indices ``ia``..``id_``? Exact; ties are broken
    by lifting each point by -eps**index (the smaller the index, the larger the
    perturbation)."""
    adx, ady = pa[0] - pd[0], pa[1] - pd[1]
    bdx, bdy = pb[0] - pd[0], pb[1] - pd[1]
    cdx, cdy = pc[0] - pd[0], pc[1] - pd[1]
    bc = bdx * cdy - bdy * cdx
    ca = cdx * ady - cdy * adx
    ab = adx * bdy - ady * bdx
    det = (adx * adx + ady * ady) * bc + (bdx * bdx + bdy * bdy) * ca + (cdx * cdx + cdy * cdy) * ab
    if det != 0:
        return det > 0
    # d's coefficient, bc + ca + ab, is twice the triangle's area: never zero
    coefficient = {ia: -bc, ib: -ca, ic: -ab, id_: bc + ca + ab}
    return next(coefficient[i] > 0 for i in sorted(coefficient) if coefficient[i] != 0)


_INCIRCLE_BOUND = (10 + 96 * 2.0 ** -53) * 2.0 ** -53
"""Shewchuk's error bound A of the floating-point incircle determinant, relative to its
permanent (Adaptive Precision Floating-Point Arithmetic, 1997: ``iccerrboundA``)."""


def _incircle_signs_filtered(pa, pb, pc, pd) -> np.ndarray:
    """The sign of the incircle determinant of many quadruples (each argument (m, 2): d
    inside the circle through counter-clockwise a, b, c) in floating point: 1 inside, -1
    outside, 0 where Shewchuk's error bound does not decide (the caller then computes it
    exactly)."""
    adx, ady = pa[:, 0] - pd[:, 0], pa[:, 1] - pd[:, 1]
    bdx, bdy = pb[:, 0] - pd[:, 0], pb[:, 1] - pd[:, 1]
    cdx, cdy = pc[:, 0] - pd[:, 0], pc[:, 1] - pd[:, 1]
    bc, cb = bdx * cdy, cdx * bdy
    ca, ac = cdx * ady, adx * cdy
    ab, ba = adx * bdy, bdx * ady
    alift, blift, clift = adx * adx + ady * ady, bdx * bdx + bdy * bdy, cdx * cdx + cdy * cdy
    det = alift * (bc - cb) + blift * (ca - ac) + clift * (ab - ba)
    permanent = (alift * (np.abs(bc) + np.abs(cb)) + blift * (np.abs(ca) + np.abs(ac))
                 + clift * (np.abs(ab) + np.abs(ba)))
    return np.where(np.abs(det) > _INCIRCLE_BOUND * permanent, np.sign(det), 0).astype(np.int64)
