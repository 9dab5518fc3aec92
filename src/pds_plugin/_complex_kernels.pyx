# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of the local solid alpha-complex (see complex.py).

Conventions of the kernel modules: see ``_parallel.pyx``.
"""

import numpy as np

from cython.parallel cimport parallel, prange
from libc.math cimport INFINITY, ceil, hypot
from libc.stdlib cimport free, malloc
from libc.stdint cimport int8_t, int32_t, int64_t

from ._parallel cimport threads_for
from ._visibility_kernels cimport (Chords, chords_of, exact_difference, incircle_sign,
                                  near_boundary, orient_sign, sees)

ACCEPT, REJECT, UNSURE = 1, 0, 2
COMPLETE, MORE_NEIGHBOURS, TOO_MANY_TIES = 0, 1, 2
cdef enum:
    C_ACCEPT = 1
    C_REJECT = 0
    C_UNSURE = 2
    SLOTS = 8       # triangles kept per point in the first pass
    MAX_TIES = 5000 # exact tie-breaks a point's triangles may take (cocircular sets)
    CHUNK = 256     # iterations a thread takes at a time
cdef double _INCIRCLE_ERR = 1e-12   # relative bound on the rounding error of the filtered incircle test


def bin_points(points, double x0, double y0, double h, Py_ssize_t nx, Py_ssize_t ny):
    """Sort points into square cells of side h: (order, cell_start) in CSR form, the
    points of a cell in their input order."""
    cdef const double[:, :] p = points
    cdef Py_ssize_t n = p.shape[0], i, c
    cdef int64_t[::1] cell = np.empty(n, np.int64)
    order_array = np.empty(n, np.int64)
    start_array = np.zeros(nx * ny + 1, np.int64)
    cdef int64_t[::1] order = order_array, start = start_array
    cdef int64_t[::1] fill
    with nogil:
        for i in range(n):
            cell[i] = min(<Py_ssize_t>((p[i, 1] - y0) / h), ny - 1) * nx \
                + min(<Py_ssize_t>((p[i, 0] - x0) / h), nx - 1)
            start[cell[i] + 1] += 1
        for c in range(nx * ny):
            start[c + 1] += start[c]
    fill = np.array(start_array[:nx * ny])
    with nogil:
        for i in range(n):                  # a stable counting sort
            order[fill[cell[i]]] = i
            fill[cell[i]] += 1
    return order_array, start_array


def first_duplicate(binned, start):
    """Positions (p, q) of two equal binned points, or (-1, -1). Equal points share a cell."""
    cdef const double[:, :] b = binned
    cdef const int64_t[::1] st = start
    cdef Py_ssize_t c, p, q
    with nogil:
        for c in range(st.shape[0] - 1):
            for p in range(st[c], st[c + 1]):
                for q in range(p + 1, st[c + 1]):
                    if b[p, 0] == b[q, 0] and b[p, 1] == b[q, 1]:
                        with gil:
                            return p, q
    return -1, -1


cdef int _incircle_sign(const double[:, ::1] points, Py_ssize_t a, Py_ssize_t b, Py_ssize_t c,
                        Py_ssize_t d) noexcept nogil:
    """+1 if d is inside the circle through counter-clockwise a, b, c, -1 outside,
    0 when rounding could decide either way."""
    cdef double adx = points[a, 0] - points[d, 0]
    cdef double ady = points[a, 1] - points[d, 1]
    cdef double bdx = points[b, 0] - points[d, 0]
    cdef double bdy = points[b, 1] - points[d, 1]
    cdef double cdx = points[c, 0] - points[d, 0]
    cdef double cdy = points[c, 1] - points[d, 1]
    cdef double alift = adx * adx + ady * ady
    cdef double blift = bdx * bdx + bdy * bdy
    cdef double clift = cdx * cdx + cdy * cdy
    cdef double bc = bdx * cdy - bdy * cdx
    cdef double ca = cdx * ady - cdy * adx
    cdef double ab = adx * bdy - ady * bdx
    cdef double det = alift * bc + blift * ca + clift * ab
    cdef double permanent = (alift * (abs(bdx * cdy) + abs(bdy * cdx))
                             + blift * (abs(cdx * ady) + abs(cdy * adx))
                             + clift * (abs(adx * bdy) + abs(ady * bdx)))
    if det > _INCIRCLE_ERR * permanent:
        return 1
    if det < -_INCIRCLE_ERR * permanent:
        return -1
    return 0


cdef inline bint _in_range(double difference) noexcept nogil:
    """Is ``difference`` 0 or between 2^-200 and 2^200 in magnitude? Then the incircle
    determinant's products (degree 4) and their rounding errors stay normal floats, so
    the expansions are exact (1e80 apart, they overflowed to a wrong sign)."""
    cdef double size = abs(difference)
    return size == 0.0 or (6.223015277861142e-61 <= size <= 1.6069380442589903e+60)


cdef int _tie_sign(const double[:, ::1] points, Py_ssize_t a, Py_ssize_t b, Py_ssize_t c,
                   Py_ssize_t d, const int64_t *rank) noexcept nogil:
    """The incircle sign of (a, b, c; d) where the filter could not decide, in exact
    arithmetic, cocircular points settled by symbolic perturbation: each point lifted by
    -eps^rank, the smallest rank perturbed most (Edelsbrunner and Mücke's simulation of
    simplicity), so the answer is never 0. The determinant's term in the largest
    perturbation with a non-zero factor decides; the factors are orientations: rank[a]'s
    -orient(d, b, c), rank[b]'s -orient(d, c, a), rank[c]'s -orient(d, a, b), rank[d]'s
    orient(a, b, c). Returns 0 when a difference to d is not an exact float (near the
    axes, or spanning magnitudes), or is out of the expansions' range (:func:`_in_range`):
    ``local_complex._exactly_empty`` settles those."""
    cdef double adx, ady, bdx, bdy, cdx, cdy
    if not (exact_difference(points[a, 0], points[d, 0], &adx)
            and exact_difference(points[a, 1], points[d, 1], &ady)
            and exact_difference(points[b, 0], points[d, 0], &bdx)
            and exact_difference(points[b, 1], points[d, 1], &bdy)
            and exact_difference(points[c, 0], points[d, 0], &cdx)
            and exact_difference(points[c, 1], points[d, 1], &cdy)
            and _in_range(adx) and _in_range(ady) and _in_range(bdx) and _in_range(bdy)
            and _in_range(cdx) and _in_range(cdy)):
        return 0
    cdef int sign = incircle_sign(adx, ady, bdx, bdy, cdx, cdy)
    if sign:
        return sign
    cdef Py_ssize_t roles[4]
    roles[0], roles[1], roles[2], roles[3] = a, b, c, d
    cdef Py_ssize_t done = 0, k, first, p, q, r
    while True:                             # the roles by increasing rank
        first = -1
        for k in range(4):
            if not (done >> k) & 1 and (first < 0 or rank[roles[k]] < rank[roles[first]]):
                first = k
        done |= 1 << first
        if first == 3:
            sign = orient_sign(points[a, 0], points[a, 1], points[b, 0], points[b, 1],
                               points[c, 0], points[c, 1])
        else:
            p, q, r = d, roles[(first + 1) % 3], roles[(first + 2) % 3]
            sign = -orient_sign(points[p, 0], points[p, 1], points[q, 0], points[q, 1],
                                points[r, 0], points[r, 1])
        if sign:
            return sign


def tie_sign(points, Py_ssize_t a, Py_ssize_t b, Py_ssize_t c, Py_ssize_t d, rank) -> int:
    """:func:`_tie_sign` of points a, b, c (counter-clockwise) and d of ``points`` (a
    C-contiguous (n, 2) float array), ``rank`` (n distinct integers) breaking ties: +1 if
    d is inside their circle, -1 outside, 0 if a difference to d is not an exact float.

    >>> import numpy as np
    >>> square = np.array([[10.0, 10.0], [11.0, 10.0], [11.0, 11.0], [10.0, 11.0]])
    >>> tie_sign(square, 0, 1, 2, 3, np.arange(4)), tie_sign(square, 0, 1, 2, 3, np.arange(4)[::-1].copy())
    (-1, 1)
    """
    cdef const double[:, ::1] p = points
    cdef const int64_t[::1] rk = rank
    return _tie_sign(p, a, b, c, d, &rk[0])


cdef inline Py_ssize_t _out(const Chords *vis, Py_ssize_t v) noexcept nogil:
    """The outgoing chord of point v, -1 if none."""
    return vis.out[v] if vis.out else -1


cdef bint _edge_ok(const double[:, ::1] points, Py_ssize_t u, Py_ssize_t v,
                   const Chords *vis) noexcept nogil:
    """Is u -> v, an edge of a counter-clockwise triangle, seen through the region and
    not a chord run backwards (the triangle would lie on the chord's outer side)?"""
    if not sees(points[u, 0], points[u, 1], _out(vis, u), points[v, 0], points[v, 1],
                _out(vis, v), vis):
        return False
    cdef Py_ssize_t e = _out(vis, v)
    return not (e >= 0 and vis.xy[4 * e + 2] == points[u, 0]
                and vis.xy[4 * e + 3] == points[u, 1])


cdef bint _constrained_ok(const double[:, ::1] points, Py_ssize_t i, Py_ssize_t a,
                          Py_ssize_t b, const Chords *vis) noexcept nogil:
    """May counter-clockwise (i, a, b) be a triangle of the constrained complex?"""
    return (_edge_ok(points, i, a, vis) and _edge_ok(points, a, b, vis)
            and _edge_ok(points, b, i, vis))


cdef bint _in_arc(const double[:, ::1] points, Py_ssize_t v, Py_ssize_t p, Py_ssize_t q,
                  double cx, double cy) noexcept nogil:
    """Is the direction from point v to (cx, cy) strictly inside the smaller angle
    between the directions from v to points p and q?"""
    cdef double vx = points[v, 0], vy = points[v, 1]
    cdef int turn = orient_sign(vx, vy, points[p, 0], points[p, 1], points[q, 0], points[q, 1])
    return (turn != 0 and orient_sign(vx, vy, points[p, 0], points[p, 1], cx, cy) == turn
            and orient_sign(vx, vy, cx, cy, points[q, 0], points[q, 1]) == turn)


cdef bint _wedge_between(const double[:, ::1] points, Py_ssize_t v, Py_ssize_t p, Py_ssize_t q,
                         double ux, double uy, double wx, double wy, double mx,
                         double my) noexcept nogil:
    """Does the outside wedge at v (rays to u and w, m inside it) meet the smaller angle
    between the directions to p and q?"""
    return (_in_arc(points, v, p, q, ux, uy) or _in_arc(points, v, p, q, wx, wy)
            or _in_arc(points, v, p, q, mx, my))


cdef bint _seen_near(const double[:, ::1] points, Py_ssize_t other, Py_ssize_t v, Py_ssize_t a,
                     Py_ssize_t b, const Chords *vis) noexcept nogil:
    """Does ``other`` see points of the triangle (v, a, b) near its vertex v? It must
    see v, and if v is a reflex boundary vertex, the smaller angle between the
    directions to ``other`` and to a (or b) must not pass through the outside wedge at
    v (the triangle and ``other`` may be on the two sides of a notch)."""
    if not sees(points[other, 0], points[other, 1], _out(vis, other), points[v, 0],
                points[v, 1], _out(vis, v), vis):
        return False
    cdef Py_ssize_t e = _out(vis, v), before
    if e < 0:
        return True
    before = vis.prev[e]
    cdef double ux = vis.xy[4 * before], uy = vis.xy[4 * before + 1]
    cdef double vx = points[v, 0], vy = points[v, 1]
    cdef double wx = vis.xy[4 * e + 2], wy = vis.xy[4 * e + 3]
    if orient_sign(ux, uy, vx, vy, wx, wy) >= 0:
        return True                     # convex: the region's cone holds both directions
    cdef double lu = hypot(ux - vx, uy - vy), lw = hypot(wx - vx, wy - vy)
    cdef double mx = vx + (ux - vx) / lu + (wx - vx) / lw      # inside the outside wedge
    cdef double my = vy + (uy - vy) / lu + (wy - vy) / lw
    return (not _wedge_between(points, v, other, a, ux, uy, wx, wy, mx, my)
            or not _wedge_between(points, v, other, b, ux, uy, wx, wy, mx, my))


cdef bint _seen_by_triangle(const double[:, ::1] points, Py_ssize_t i, Py_ssize_t a,
                            Py_ssize_t b, Py_ssize_t other, const Chords *vis) noexcept nogil:
    return (_seen_near(points, other, i, a, b, vis) or _seen_near(points, other, a, b, i, vis)
            or _seen_near(points, other, b, i, a, vis))


def seen_by_triangle(points, Py_ssize_t i, Py_ssize_t a, Py_ssize_t b, Py_ssize_t other,
                     vis) -> bool:
    """Does ``other`` see the inside of the triangle (i, a, b) (near one of its
    vertices)? Only those points count in the constrained empty-circle test."""
    cdef Chords ch = chords_of(vis)
    return _seen_by_triangle(points, i, a, b, other, &ch)


cdef Py_ssize_t _scan_point(const double[:, ::1] points, Py_ssize_t i, double alpha2,
                            const double *bound, const int64_t[::1] start, double x0, double y0, double h,
                            Py_ssize_t nx, Py_ssize_t ny, int64_t *nbr, Py_ssize_t max_nbr,
                            int32_t *found_j, int32_t *found_k, int8_t *found_flag,
                            Py_ssize_t room, const Chords *vis,
                            const int64_t *rank) noexcept nogil:
    """Triangles whose smallest vertex index is i, counter-clockwise as (i, j, k):
    written to found_* (the first ``room`` of them). Returns how many there are, -1 if
    i has more than ``max_nbr`` neighbours within 2 alpha (the size of ``nbr``), or -2
    if its triangles take more than MAX_TIES exact tie-breaks (a large cocircular set:
    the work would grow with its size to the fourth power).

    Every point inside the circumcircle (radius <= alpha) of a triangle at i is within
    2 alpha of i, so i's neighbours are the only points the empty-circle test needs.

    With a ``bound`` per point (graded complexes, not NULL) a triangle is kept when its
    circumradius is at most the smallest bound of its vertices, and i's neighbours are
    the points within 2 bound[i], in as many cells as that takes.

    Ties the filter cannot decide are settled exactly (:func:`_tie_sign`, the points'
    ``rank`` breaking them); a triangle is UNSURE only where that cannot be done.
    """
    cdef double xi = points[i, 0], yi = points[i, 1]
    cdef Py_ssize_t ix = min(<Py_ssize_t>((xi - x0) / h), nx - 1)
    cdef Py_ssize_t iy = min(<Py_ssize_t>((yi - y0) / h), ny - 1)
    cdef double reach2 = 4.0 * alpha2, least2 = alpha2
    cdef Py_ssize_t window = 2
    cdef Py_ssize_t m = 0, found = 0, ties = 0, jx, jy, c, j, k, p, r, q, other, a, b
    cdef double dx, dy, bx, by, b2, cx, cy, cross, c2, d2, ux, uy, far2, ox, oy
    cdef int status, sign
    cdef bint constrained = near_boundary(xi, yi, vis)
    if bound != NULL:
        reach2 = 4.0 * bound[i] * bound[i]
        window = <Py_ssize_t>ceil(2.0 * bound[i] / h)
    for jy in range(max(iy - window, 0), min(iy + window + 1, ny)):
        for jx in range(max(ix - window, 0), min(ix + window + 1, nx)):
            c = jy * nx + jx
            for j in range(start[c], start[c + 1]):
                dx = points[j, 0] - xi
                dy = points[j, 1] - yi
                if j != i and dx * dx + dy * dy <= reach2:
                    if m == max_nbr:
                        return -1
                    nbr[m] = j
                    m += 1
    for p in range(m):
        j = nbr[p]
        if j < i:
            continue
        bx, by = points[j, 0] - xi, points[j, 1] - yi
        b2 = bx * bx + by * by
        for r in range(m):
            k = nbr[r]
            if k <= j:
                continue
            cx, cy = points[k, 0] - xi, points[k, 1] - yi
            cross = bx * cy - by * cx
            c2 = cx * cx + cy * cy
            d2 = (cx - bx) * (cx - bx) + (cy - by) * (cy - by)
            # circumradius R = |ij| |ik| |jk| / (2 |cross|) <= alpha (or the bounds)
            if bound != NULL:
                least2 = min(bound[i], bound[j], bound[k])
                least2 = least2 * least2
            if cross == 0.0 or b2 * c2 * d2 > 4.0 * least2 * cross * cross:
                continue
            if cross > 0:
                a, b = j, k
            else:
                a, b = k, j
            # circumcentre relative to i; on a well-shaped triangle it is accurate to
            # far better than 1e-6 R, so points beyond R (1 + 1e-6) are surely outside
            ux = (cy * b2 - by * c2) / (2.0 * cross)
            uy = (bx * c2 - cx * b2) / (2.0 * cross)
            far2 = (ux * ux + uy * uy) * (1.0 + 2e-6)
            if abs(cross) < 1e-3 * max(b2, c2, d2):
                far2 = INFINITY
            status = C_ACCEPT
            for q in range(m):
                other = nbr[q]
                if other == j or other == k:
                    continue
                ox = points[other, 0] - xi - ux
                oy = points[other, 1] - yi - uy
                if ox * ox + oy * oy > far2:
                    continue
                sign = _incircle_sign(points, i, a, b, other)
                if sign >= 0 and constrained and not _seen_by_triangle(points, i, a, b, other,
                                                                       vis):
                    continue
                if sign == 0:
                    sign = _tie_sign(points, i, a, b, other, rank)
                    ties += sign != 0
                    if ties > MAX_TIES:
                        return -2
                if sign > 0:
                    status = C_REJECT
                    break
                if sign == 0:
                    status = C_UNSURE
            if status != C_REJECT and constrained and not _constrained_ok(points, i, a, b, vis):
                status = C_REJECT
            if status != C_REJECT:
                if found < room:
                    found_j[found] = <int32_t>a
                    found_k[found] = <int32_t>b
                    found_flag[found] = <int8_t>status
                found += 1
    return found


def local_complex(points, double alpha, start, double x0, double y0, double h,
                  Py_ssize_t nx, Py_ssize_t ny, Py_ssize_t max_neighbours, vis, rank,
                  bound=None):
    """Every triangle of ``points`` (binned: cell c holds points start[c]:start[c+1])
    with circumradius <= alpha and an empty circumcircle, found from its smallest
    vertex; with chords in ``vis`` (indexed like ``points``), constrained: edges seen
    through the region and only points that see the triangle in the empty-circle test.
    With ``bound`` (one value per point, graded complexes) a triangle is kept when its
    circumradius is at most the smallest bound of its vertices instead. Cocircular ties
    are broken by ``rank`` (one distinct integer per point: their original indices).
    Returns (faces, flags, status): flags ACCEPT or UNSURE (a tie whose differences
    are not exact floats, :func:`_tie_sign`); status COMPLETE, or, with nothing found,
    MORE_NEIGHBOURS if a point has more than ``max_neighbours`` neighbours within
    2 alpha, TOO_MANY_TIES if a point's triangles take more than MAX_TIES exact
    tie-breaks."""
    cdef const double[:, ::1] p = points
    cdef const int64_t[::1] st = start
    cdef Py_ssize_t n = p.shape[0], i, f, total = 0
    cdef double alpha2 = alpha * alpha
    cdef int64_t[::1] counts = np.zeros(n, np.int64)
    cdef int32_t[:, ::1] slot_j = np.empty((n, SLOTS), np.int32)
    cdef int32_t[:, ::1] slot_k = np.empty((n, SLOTS), np.int32)
    cdef int8_t[:, ::1] slot_flag = np.empty((n, SLOTS), np.int8)
    cdef int64_t *nbr
    cdef int32_t *more_j
    cdef int32_t *more_k
    cdef int8_t *more_flag
    cdef Chords ch = chords_of(vis)
    cdef const int64_t[::1] rk = rank
    cdef const double[::1] bound_view
    cdef const double *bd = NULL
    if bound is not None:
        bound_view = bound
        bd = &bound_view[0]
    with nogil, parallel(num_threads=threads_for(n)):
        nbr = <int64_t *>malloc(max_neighbours * sizeof(int64_t))
        for i in prange(n, schedule="dynamic", chunksize=CHUNK):
            counts[i] = _scan_point(p, i, alpha2, bd, st, x0, y0, h, nx, ny, nbr, max_neighbours,
                                    &slot_j[i, 0], &slot_k[i, 0], &slot_flag[i, 0], SLOTS, &ch,
                                    &rk[0])
        free(nbr)
    for i in range(n):
        if counts[i] < 0:
            return (np.empty((0, 3), np.int64), np.empty(0, np.int8),
                    MORE_NEIGHBOURS if counts[i] == -1 else TOO_MANY_TIES)
    offsets_array = np.zeros(n + 1, np.int64)
    np.cumsum(counts, out=offsets_array[1:])
    cdef int64_t[::1] offsets = offsets_array
    faces_array = np.empty((offsets[n], 3), np.int64)
    flags_array = np.empty(offsets[n], np.int8)
    cdef int64_t[:, ::1] faces = faces_array
    cdef int8_t[::1] flags = flags_array
    with nogil, parallel(num_threads=threads_for(n)):
        nbr = <int64_t *>malloc(max_neighbours * sizeof(int64_t))
        for i in prange(n, schedule="dynamic", chunksize=CHUNK):
            more_j = NULL
            more_k = NULL
            more_flag = NULL
            if counts[i] > SLOTS:       # rare: redo this point with room for all
                more_j = <int32_t *>malloc(counts[i] * sizeof(int32_t))
                more_k = <int32_t *>malloc(counts[i] * sizeof(int32_t))
                more_flag = <int8_t *>malloc(counts[i] * sizeof(int8_t))
                _scan_point(p, i, alpha2, bd, st, x0, y0, h, nx, ny, nbr, max_neighbours,
                            more_j, more_k, more_flag, counts[i], &ch, &rk[0])
                for f in range(counts[i]):
                    faces[offsets[i] + f, 0] = i
                    faces[offsets[i] + f, 1] = more_j[f]
                    faces[offsets[i] + f, 2] = more_k[f]
                    flags[offsets[i] + f] = more_flag[f]
                free(more_j)
                free(more_k)
                free(more_flag)
            else:
                for f in range(counts[i]):
                    faces[offsets[i] + f, 0] = i
                    faces[offsets[i] + f, 1] = slot_j[i, f]
                    faces[offsets[i] + f, 2] = slot_k[i, f]
                    flags[offsets[i] + f] = slot_flag[i, f]
        free(nbr)
    return faces_array, flags_array, COMPLETE
