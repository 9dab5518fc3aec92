# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of visibility through the mesh's boundary (see docs/conforming.md).

The boundary is a set of *chords*: straight segments between consecutive boundary
samples along each ring, oriented with the region on their left. Chord ``e`` runs from
sample ``a`` to the next sample of its ring; ``chord_prev[e]`` is the chord before it.
Samples that are chord vertices know their outgoing chord (``out_chord``, -1 for
interior samples).

Chords are binned in a grid of square cells of side ``h`` (CSR ``start``/``items``): a
cell lists every chord within ``reach`` of any of its points, so every visibility
question about points within ``reach`` of a point of the cell is answered from its list
alone. Far from the boundary the lists are empty and every test is a single lookup.

Python passes the chords around as a :class:`ChordBundle` (its fields named, made by
:func:`no_chords` and :func:`chord_bundle`); the sampling and complex kernels read it as
a :c:type:`Chords` struct (``chords_of``) and call the ``nogil`` tests of this module.

Orientation signs are exact: a floating-point filter with Shewchuk's error bound and an
exact expansion fallback; so is :func:`incircle_sign` (expansions all through).
Conventions of the kernel modules: see ``_parallel.pyx``.

>>> orient(0.0, 0.0, 1.0, 0.0, 0.5, 1e-300), orient(0.0, 0.0, 1.0, 1.0, 3.0, 3.0)
(1, 0)
"""

from collections import namedtuple

import numpy as np

from libc.math cimport ceil, hypot
from libc.stdlib cimport free, malloc
from libc.stdint cimport int64_t

cdef double _SPLITTER = 134217729.0                  # 2^27 + 1
cdef double _ORIENT_ERR = 3.3306690738754716e-16     # (3 + 16 eps) eps, Shewchuk's ccwerrboundA


cdef inline void _two_sum(double a, double b, double *x, double *y) noexcept nogil:
    cdef double s = a + b, bv, av
    bv = s - a
    av = s - bv
    x[0] = s
    y[0] = (a - av) + (b - bv)


cdef inline void _split(double a, double *hi, double *lo) noexcept nogil:
    cdef double c = _SPLITTER * a
    hi[0] = c - (c - a)
    lo[0] = a - hi[0]


cdef inline void _two_product(double a, double b, double *x, double *y) noexcept nogil:
    cdef double p = a * b, ahi, alo, bhi, blo, err
    _split(a, &ahi, &alo)
    _split(b, &bhi, &blo)
    err = p - ahi * bhi - alo * bhi - ahi * blo
    x[0] = p
    y[0] = alo * blo - err


cdef int _orient_exact(double ax, double ay, double bx, double by, double cx,
                       double cy) noexcept nogil:
    """Sign of ax*by - ax*cy - cx*by - ay*bx + ay*cx + cy*bx, summed exactly."""
    cdef double left[6]
    cdef double right[6]
    cdef double terms[12]
    cdef double expansion[13]
    cdef double q
    cdef int k, i, t, m = 0
    left[0], right[0] = ax, by
    left[1], right[1] = ax, -cy
    left[2], right[2] = -cx, by
    left[3], right[3] = -ay, bx
    left[4], right[4] = ay, cx
    left[5], right[5] = cy, bx
    for k in range(6):
        _two_product(left[k], right[k], &terms[2 * k], &terms[2 * k + 1])
    for t in range(12):                     # Shewchuk's grow-expansion
        q = terms[t]
        for i in range(m):
            _two_sum(q, expansion[i], &q, &expansion[i])
        expansion[m] = q
        m += 1
    for i in range(m - 1, -1, -1):          # the largest non-zero component has the sign
        if expansion[i] > 0.0:
            return 1
        if expansion[i] < 0.0:
            return -1
    return 0


cdef int orient_sign(double ax, double ay, double bx, double by, double cx,
                     double cy) noexcept nogil:
    """Exact sign of the orientation of (a, b, c): +1 counter-clockwise, -1 clockwise,
    0 collinear."""
    cdef double left = (ax - cx) * (by - cy)
    cdef double right = (ay - cy) * (bx - cx)
    cdef double det = left - right
    cdef double bound = _ORIENT_ERR * (abs(left) + abs(right))
    if det > bound:
        return 1
    if det < -bound:
        return -1
    # both products exactly zero (a difference of doubles is 0 only between equal ones):
    # c on an axis-parallel line through a and b, as a box's corner on a chord's line
    if (ax == cx or by == cy) and (ay == cy or bx == cx):
        return 0
    return _orient_exact(ax, ay, bx, by, cx, cy)


def orient(double ax, double ay, double bx, double by, double cx, double cy) -> int:
    """Exact sign of the orientation of (a, b, c): +1 counter-clockwise, -1 clockwise,
    0 collinear."""
    return orient_sign(ax, ay, bx, by, cx, cy)


# ---- The exact incircle determinant, by Shewchuk's expansions --------------------------
# An expansion is an array of doubles, nonoverlapping and in increasing magnitude, whose
# sum is exact; its sign is its last component's (zero components are dropped).

cdef inline void _fast_two_sum(double a, double b, double *x, double *y) noexcept nogil:
    """x + y = a + b exactly, x = fl(a + b), given |a| >= |b| or a == 0."""
    x[0] = a + b
    y[0] = b - (x[0] - a)


cdef inline int _kept(double *h, int k, double value) noexcept nogil:
    """Append ``value`` to the expansion ``h`` of length k unless it is 0 (zeros are
    dropped); the new length."""
    if value == 0.0:
        return k
    h[k] = value
    return k + 1


cdef inline int _closed(double *h, int k, double q) noexcept nogil:
    """Append the last (largest) component ``q``, kept even if 0 when it is the only
    one; the expansion's length."""
    h[k] = q
    return k + (q != 0.0 or k == 0)


cdef int _scaled(const double *e, int n, double b, double *h) noexcept nogil:
    """h = e b exactly (Shewchuk's scale-expansion, zeros dropped): at most 2 n
    components; returns how many."""
    cdef double q, product, low, sum_, error
    cdef int i, k = 0
    _two_product(e[0], b, &q, &error)
    k = _kept(h, k, error)
    for i in range(1, n):
        _two_product(e[i], b, &product, &low)
        _two_sum(q, low, &sum_, &error)
        k = _kept(h, k, error)
        _fast_two_sum(product, sum_, &q, &error)
        k = _kept(h, k, error)
    return _closed(h, k, q)


cdef int _summed(const double *e, int ne, const double *f, int nf, double *h) noexcept nogil:
    """h = e + f exactly (Shewchuk's fast-expansion-sum: the components merged by
    magnitude, then carried; zeros dropped): at most ne + nf components; returns how
    many."""
    cdef double q, now, error
    cdef int i = 0, j = 0, k = 0
    if (f[0] > e[0]) == (f[0] > -e[0]):            # |e[0]| < |f[0]|
        q = e[0]
        i = 1
    else:
        q = f[0]
        j = 1
    while i < ne or j < nf:
        if j == nf or (i < ne and (f[j] > e[i]) == (f[j] > -e[i])):
            now = e[i]
            i += 1
        else:
            now = f[j]
            j += 1
        if i + j == 2:                              # the second smallest: |now| >= |q|
            _fast_two_sum(now, q, &q, &error)
        else:
            _two_sum(q, now, &q, &error)
        k = _kept(h, k, error)
    return _closed(h, k, q)


cdef int _products(double a, double b, double c, double d, double *h) noexcept nogil:
    """h = a b - c d exactly: at most 4 components."""
    cdef double e[2]
    cdef double f[2]
    _two_product(a, b, &e[1], &e[0])
    _two_product(-c, d, &f[1], &f[0])
    return _summed(e, 2, f, 2, h)


cdef int _lifted(double ax, double ay, double bx, double by, double cx, double cy,
                 double *h) noexcept nogil:
    """h = (ax² + ay²)(bx cy - by cx) exactly: at most 32 components."""
    cdef double lift[4]
    cdef double cross[4]
    cdef double part[8]
    cdef double total[32]
    cdef int nl = _products(ax, ax, -ay, ay, lift), nc = _products(bx, cy, by, cx, cross)
    cdef int n = _scaled(cross, nc, lift[0], h), m, i, t
    for i in range(1, nl):
        m = _scaled(cross, nc, lift[i], part)
        n = _summed(h, n, part, m, total)
        for t in range(n):
            h[t] = total[t]
    return n


cdef int incircle_sign(double adx, double ady, double bdx, double bdy, double cdx,
                       double cdy) noexcept nogil:
    """Exact sign of the incircle determinant of a, b, c and d from the differences
    a - d, b - d and c - d (exact floats): +1 if d is inside the circle through
    counter-clockwise a, b, c, -1 outside, 0 on it."""
    cdef double ta[32]
    cdef double tb[32]
    cdef double tc[32]
    cdef double two[64]
    cdef double det[96]
    cdef int na = _lifted(adx, ady, bdx, bdy, cdx, cdy, ta)
    cdef int nb = _lifted(bdx, bdy, cdx, cdy, adx, ady, tb)
    cdef int nc = _lifted(cdx, cdy, adx, ady, bdx, bdy, tc)
    cdef int n = _summed(ta, na, tb, nb, two)
    n = _summed(two, n, tc, nc, det)
    return (det[n - 1] > 0.0) - (det[n - 1] < 0.0)


cdef bint exact_difference(double a, double b, double *difference) noexcept nogil:
    """``difference`` = a - b; is it exact?"""
    cdef double error
    _two_sum(a, -b, difference, &error)
    return error == 0.0


cdef tuple bin_chords_by(chords, reach, ChordGrid grid, CellRule rule):
    """CSR lists (start, items) of the chords of each cell of ``grid``: chord e is
    listed in the cells that ``rule`` marks for it with its ``reach[e]``. Two passes
    over the chords: count each cell's chords, then place them."""
    cdef const double[:, :, ::1] ch = chords
    cdef const double[::1] rc = reach
    cdef Py_ssize_t cells = grid.nx * grid.ny, e
    stamp = np.full(cells, -1, np.int64)
    start_array = np.zeros(cells + 1, np.int64)
    items_array = np.empty(0, np.int64)
    fill = np.empty(0, np.int64)
    cdef int64_t[::1] stamp_view = stamp, count = start_array, items, fill_view
    cdef CellMarks marks
    marks.stamp, marks.count = &stamp_view[0], &count[0]
    marks.items = marks.fill = NULL
    cdef int phase
    for phase in range(2):
        if phase == 1:
            np.cumsum(start_array, out=start_array)
            items_array = np.empty(max(start_array[-1], 1), np.int64)
            fill = np.array(start_array[:-1])
            stamp[:] = -1
            items, fill_view = items_array, fill
            marks.items, marks.fill = &items[0], &fill_view[0]
        marks.counting = phase == 0
        with nogil:
            for e in range(ch.shape[0]):
                marks.chord = e
                rule(ch[e, 0, 0], ch[e, 0, 1], ch[e, 1, 0], ch[e, 1, 1], rc[e], &grid, &marks)
    return start_array, items_array[:start_array[-1]]


cdef Py_ssize_t _NO_CELL = 1 << 62     # an empty run of cells: x_min > x_max


cdef void _cells_along(double xa, double ya, double xb, double yb, double reach,
                       const ChordGrid *g, CellMarks *marks) noexcept nogil:
    """The cell rule of :func:`bin_chords`: the cells within ceil(reach / h) + 1 cells of
    points every h/2 along the chord.

    The points' cells (ix_q, iy_q) move by at most one cell per step, so in each row the
    union of their (2r + 1)-cell blocks is one run of cells, from r before the smallest
    ix_q of the points within r rows to r after the largest: each cell is marked once
    per row run, not once per block holding it (7 x 7 blocks every half cell overlapped
    some eight times)."""
    cdef Py_ssize_t r = <Py_ssize_t>ceil(reach / g.h) + 1, q, ix, iy, jx, jy
    cdef Py_ssize_t steps = <Py_ssize_t>ceil(hypot(xb - xa, yb - ya) / (0.5 * g.h)) + 1
    cdef Py_ssize_t row_lo = 0, row_hi = -1, rows, k
    cdef Py_ssize_t *x_min
    cdef Py_ssize_t *x_max
    cdef double f
    for q in range(steps + 1):                # the rows the blocks reach
        f = <double>q / steps
        iy = <Py_ssize_t>((ya + f * (yb - ya) - g.y0) / g.h)
        if q == 0 or iy - r < row_lo:
            row_lo = iy - r
        if q == 0 or iy + r > row_hi:
            row_hi = iy + r
    row_lo, row_hi = max(row_lo, 0), min(row_hi, g.ny - 1)
    if row_hi < row_lo:
        return
    rows = row_hi - row_lo + 1
    x_min = <Py_ssize_t *>malloc(2 * rows * sizeof(Py_ssize_t))
    if x_min == NULL:                         # no memory for the runs: block by block
        for q in range(steps + 1):
            f = <double>q / steps
            ix = <Py_ssize_t>((xa + f * (xb - xa) - g.x0) / g.h)
            iy = <Py_ssize_t>((ya + f * (yb - ya) - g.y0) / g.h)
            for jy in range(max(iy - r, 0), min(iy + r + 1, g.ny)):
                for jx in range(max(ix - r, 0), min(ix + r + 1, g.nx)):
                    mark_cell(marks, jy * g.nx + jx)
        return
    x_max = x_min + rows
    for k in range(rows):
        x_min[k], x_max[k] = _NO_CELL, -_NO_CELL
    for q in range(steps + 1):
        f = <double>q / steps
        ix = <Py_ssize_t>((xa + f * (xb - xa) - g.x0) / g.h)
        iy = <Py_ssize_t>((ya + f * (yb - ya) - g.y0) / g.h)
        for jy in range(max(iy - r, row_lo), min(iy + r, row_hi) + 1):
            x_min[jy - row_lo] = min(x_min[jy - row_lo], ix)
            x_max[jy - row_lo] = max(x_max[jy - row_lo], ix)
    for k in range(rows):
        if x_min[k] <= x_max[k]:
            jy = row_lo + k
            for jx in range(max(x_min[k] - r, 0), min(x_max[k] + r + 1, g.nx)):
                mark_cell(marks, jy * g.nx + jx)
    free(x_min)


def bin_chords(chords, double x0, double y0, double h, Py_ssize_t nx, Py_ssize_t ny,
               double reach):
    """CSR lists (start, items) of the chords within ``reach`` of each cell."""
    cdef ChordGrid grid = ChordGrid(x0, y0, h, nx, ny)
    return bin_chords_by(chords, np.full(len(chords), reach), grid, _cells_along)


ChordBundle = namedtuple("ChordBundle", ["xy", "prev", "out", "start", "items",
                                         "x0", "y0", "h", "nx", "ny"])
ChordBundle.__doc__ = """The chords of a region's boundary and the grid they are binned in, as
the kernels take them (``vis``).

Made by :func:`chord_bundle` (the rings' chords) or :func:`no_chords` (none: every point
sees every point); a field is changed with ``bundle._replace(out=...)``.

Attributes
----------
xy : (m, 2, 2) float ndarray
    Chord e runs from ``xy[e, 0]`` to ``xy[e, 1]``, the region on its left.
prev : (m,) int64 ndarray
    The chord before chord e along its ring.
out : (n,) int64 ndarray
    Each point's outgoing chord, -1 for a point on no ring (indexed like the points the
    kernel is given: reorder it with them).
start, items : int64 ndarray
    CSR lists of the chords near each cell of the grid, ``start`` (nx * ny + 1,).
x0, y0, h : float
    The grid's lower left corner and cell side.
nx, ny : int
    Its cells along x and y.

>>> bundle = no_chords(3)
>>> bundle.out.tolist(), bundle.nx, len(bundle.xy)
([-1, -1, -1], 1, 0)
"""


cdef Chords chords_of(vis) except *:
    """The struct view of a :class:`ChordBundle` (its arrays must outlive the struct)."""
    cdef Chords c
    cdef const double[:, :, ::1] xy = vis.xy
    cdef const int64_t[::1] prev = vis.prev
    cdef const int64_t[::1] out = vis.out
    cdef const int64_t[::1] start = vis.start
    cdef const int64_t[::1] items = vis.items
    c.empty = start.shape[0] <= 1
    c.xy = &xy[0, 0, 0] if xy.shape[0] else NULL
    c.prev = &prev[0] if prev.shape[0] else NULL
    c.out = &out[0] if out.shape[0] else NULL
    c.start = &start[0]
    c.items = &items[0] if items.shape[0] else NULL
    c.x0, c.y0, c.h = vis.x0, vis.y0, vis.h
    c.nx, c.ny = vis.nx, vis.ny
    return c


cdef inline double _x(const Chords *c, Py_ssize_t e, int end) noexcept nogil:
    return c.xy[4 * e + 2 * end]


cdef inline double _y(const Chords *c, Py_ssize_t e, int end) noexcept nogil:
    return c.xy[4 * e + 2 * end + 1]


cdef bint _in_cone(const Chords *c, Py_ssize_t out, double bx, double by) noexcept nogil:
    """Does the direction from chord vertex v (start of chord ``out``) to b point into
    the closed region at v (left of the incoming and outgoing chords)?"""
    cdef Py_ssize_t ein = c.prev[out]
    cdef double ux = _x(c, ein, 0), uy = _y(c, ein, 0)
    cdef double vx = _x(c, out, 0), vy = _y(c, out, 0)
    cdef double wx = _x(c, out, 1), wy = _y(c, out, 1)
    cdef bint left_in = orient_sign(ux, uy, vx, vy, bx, by) >= 0
    cdef bint left_out = orient_sign(vx, vy, wx, wy, bx, by) >= 0
    cdef int turn = orient_sign(ux, uy, vx, vy, wx, wy)
    if turn > 0 or (turn == 0 and (vx - ux) * (wx - vx) + (vy - uy) * (wy - vy) > 0):
        return left_in and left_out        # convex (or straight): a wedge
    return left_in or left_out             # reflex: the complement of a wedge


cdef inline bint _strictly_between(double px, double py, double ax, double ay, double bx,
                                   double by) noexcept nogil:
    """For p collinear with a, b: is p strictly inside the segment ab?"""
    return ((px - ax) * (bx - ax) + (py - ay) * (by - ay) > 0.0
            and (px - bx) * (ax - bx) + (py - by) * (ay - by) > 0.0)


cdef bint sees_near_chords(double ax, double ay, Py_ssize_t a_out, double bx, double by,
                           Py_ssize_t b_out, const Chords *c, Py_ssize_t k) noexcept nogil:
    """Is the segment ab inside the closed region bounded by the chords?

    ``a_out``/``b_out``: the outgoing chord of a/b if it is a chord vertex, else -1.
    b must be within ``reach`` of a; ``k`` is a's cell of the chord grid. The segment is
    blocked if it crosses a chord properly, passes through a chord vertex, leaves a
    chord vertex a or b outside the region's cone there, or an interior point a or b
    lies on a chord and the other end on its outer side.
    """
    cdef Py_ssize_t t, e
    cdef double lox = min(ax, bx), hix = max(ax, bx), loy = min(ay, by), hiy = max(ay, by)
    cdef double px, py, qx, qy
    cdef int o1, o2, o3, o4
    for t in range(c.start[k], c.start[k + 1]):
        e = c.items[t]
        px, py, qx, qy = _x(c, e, 0), _y(c, e, 0), _x(c, e, 1), _y(c, e, 1)
        if max(px, qx) < lox or min(px, qx) > hix or max(py, qy) < loy or min(py, qy) > hiy:
            continue                           # bounding boxes apart
        if a_out >= 0 and (e == a_out or e == c.prev[a_out]):
            continue
        if b_out >= 0 and (e == b_out or e == c.prev[b_out]):
            continue
        o1 = orient_sign(ax, ay, bx, by, px, py)
        o2 = orient_sign(ax, ay, bx, by, qx, qy)
        if o1 * o2 > 0:
            continue
        o3 = orient_sign(px, py, qx, qy, ax, ay)
        o4 = orient_sign(px, py, qx, qy, bx, by)
        if o3 * o4 > 0:
            continue
        if o1 * o2 < 0 and o3 * o4 < 0:
            return False                       # proper crossing
        if o1 == 0 and o2 == 0:
            continue                           # collinear: ab runs along the boundary
        if o1 == 0 and _strictly_between(px, py, ax, ay, bx, by):
            return False                       # through a chord vertex
        if o2 == 0 and _strictly_between(qx, qy, ax, ay, bx, by):
            return False
        if o3 == 0 and o4 < 0:
            return False                       # a on the chord, b outside
        if o4 == 0 and o3 < 0:
            return False
    if a_out >= 0 and not _in_cone(c, a_out, bx, by):
        return False
    if b_out >= 0 and not _in_cone(c, b_out, ax, ay):
        return False
    return True


cdef int _hull(double px, double py, double bx, double by, double size, double *hx,
               double *hy) noexcept nogil:
    """Counter-clockwise convex hull of p and the box [bx, bx+size] x [by, by+size],
    written to hx, hy (room for 6); returns its vertex count."""
    cdef double cx[4]
    cdef double cy[4]
    cdef bint faces[4]
    cdef bint before
    cdef int k, k1, n = 0
    cx[0], cx[1], cx[2], cx[3] = bx, bx + size, bx + size, bx
    cy[0], cy[1], cy[2], cy[3] = by, by, by + size, by + size
    for k in range(4):
        k1 = (k + 1) % 4
        faces[k] = (cx[k1] - cx[k]) * (py - cy[k]) - (cy[k1] - cy[k]) * (px - cx[k]) < 0.0
    for k in range(4):
        before = faces[(k + 3) % 4]
        if not (before and faces[k]):
            hx[n] = cx[k]
            hy[n] = cy[k]
            n += 1
        if faces[k] and not before:
            hx[n] = px
            hy[n] = py
            n += 1
    return n


cdef inline double _side(const double *hx, const double *hy, int k, int n, double x,
                         double y) noexcept nogil:
    """Signed area of (hull edge k, point): > 0 on the hull's inner side."""
    cdef int k1 = (k + 1) % n
    return (hx[k1] - hx[k]) * (y - hy[k]) - (hy[k1] - hy[k]) * (x - hx[k])


cdef bint box_seen_near_chords(double px, double py, Py_ssize_t p_out, double bx, double by,
                               double size, double tol, const Chords *c,
                               Py_ssize_t k) noexcept nogil:
    """Does p see every point of the box [bx, bx+size]² that lies in the region?

    Conservative (False when unsure; ``tol`` is a length; ``k`` is p's cell of the chord
    grid). Let H be the convex hull of p and the box. Chords ending at p never block.
    Every other chord meeting H must cross it (both ends outside H) with p on its inner
    side: then the chords cut H into convex cells, only the one holding p is in the
    region, and p sees all of it (docs/conforming.md, "Visible coverage").
    """
    cdef Py_ssize_t t, e
    cdef double lox = min(px, bx) - tol, hix = max(px, bx + size) + tol
    cdef double loy = min(py, by) - tol, hiy = max(py, by + size) + tol
    cdef double hx[6]
    cdef double hy[6]
    cdef double ex, ey, fx, fy, length, edge, s, x, y
    cdef int n = -1, i, end
    cdef bint apart, above, below, inside
    for t in range(c.start[k], c.start[k + 1]):
        e = c.items[t]
        ex, ey, fx, fy = _x(c, e, 0), _y(c, e, 0), _x(c, e, 1), _y(c, e, 1)
        if max(ex, fx) < lox or min(ex, fx) > hix or max(ey, fy) < loy or min(ey, fy) > hiy:
            continue                           # apart from H's bounding box
        if p_out >= 0 and (e == p_out or e == c.prev[p_out]):
            continue
        if n < 0:
            n = _hull(px, py, bx, by, size, hx, hy)
        length = hypot(fx - ex, fy - ey)
        # separating axis: a hull edge with the chord beyond it, or the chord's line
        apart = False
        for i in range(n):
            edge = hypot(hx[(i + 1) % n] - hx[i], hy[(i + 1) % n] - hy[i])
            if (_side(hx, hy, i, n, ex, ey) < -tol * edge
                    and _side(hx, hy, i, n, fx, fy) < -tol * edge):
                apart = True
                break
        if not apart:
            above = False
            below = False
            for i in range(n):
                s = (fx - ex) * (hy[i] - ey) - (fy - ey) * (hx[i] - ex)
                above = above or s > -tol * length
                below = below or s < tol * length
            apart = not (above and below)
        if apart:
            continue
        # the chord meets H: it must cut across H, with p on its inner side
        for end in range(2):
            x = fx if end else ex
            y = fy if end else ey
            inside = True
            for i in range(n):
                edge = hypot(hx[(i + 1) % n] - hx[i], hy[(i + 1) % n] - hy[i])
                if _side(hx, hy, i, n, x, y) < -tol * edge:
                    inside = False
                    break
            if inside:
                return False
        if (fx - ex) * (py - ey) - (fy - ey) * (px - ex) < -tol * length:
            return False
    return True


def no_chords(n_points=0):
    """The :class:`ChordBundle` of an unconstrained point set: every point sees every
    point (no chord; ``out`` is -1 for each of the ``n_points``)."""
    return ChordBundle(np.empty((0, 2, 2)), np.empty(0, np.int64),
                       np.full(n_points, -1, np.int64), np.zeros(1, np.int64),
                       np.empty(0, np.int64), 0.0, 0.0, 1.0, 1, 1)


def chord_bundle(points, rings, n_points, reach):
    """The :class:`ChordBundle` of the chords along ``rings`` (sequences of indices into
    ``points``, each ring with the region on its left and at least 3 samples), binned
    within ``reach`` of each cell."""
    starts, prevs, outs = [], [], np.full(n_points, -1, np.int64)
    total = 0
    for ring in rings:
        ring = np.asarray(ring, np.int64)
        k = len(ring)
        starts.append(ring)
        prevs.append(total + (np.arange(k) - 1) % k)
        outs[ring] = total + np.arange(k)
        total += k
    if not total:
        return no_chords(n_points)
    a = np.concatenate(starts)
    b = np.concatenate([np.roll(np.asarray(r, np.int64), -1) for r in rings])
    chords = np.ascontiguousarray(np.stack([points[a], points[b]], axis=1), float)
    # every chord is within the bounding box's diagonal of every point in it: a reach
    # beyond that lists the same chords (and an alpha near the float limit would overflow)
    reach = min(reach, 2.0 * max(float(np.ptp(chords.reshape(-1, 2), axis=0).max()), 1e-300))
    lo = chords.reshape(-1, 2).min(axis=0) - reach
    hi = chords.reshape(-1, 2).max(axis=0) + reach
    h = reach / 2.0
    nx, ny = (int(v) + 1 for v in (hi - lo) / h)
    start, items = bin_chords(chords, lo[0], lo[1], h, nx, ny, reach)
    return ChordBundle(chords, np.concatenate(prevs), outs, start, items, float(lo[0]),
                       float(lo[1]), float(h), nx, ny)


# ---- Inside the region bounded by the chords: exact point and box tests ----------------
#
# The region bounded by the chords is the set of points whose rays to infinity cross an
# odd number of chords (the crossing number, even-odd), the chords themselves excluded: a
# point on a chord is not inside, a box touching a chord crosses the boundary. These are the conventions of
# shapely's contains_xy, intersects and contains_properly on the chord polygons, and the
# answers are the same as theirs (tests/test_visibility.py), with the exact orientation
# signs above. A cell of the chord grid whose list is empty lies wholly on one side
# (``cell_sides``); a point elsewhere counts the chords its ray crosses in the cells
# between it and the nearest such cell along its row or column.

from libc.math cimport INFINITY
from libc.stdint cimport int8_t, uint8_t

cdef enum:
    C_SIDE_OUT = 0
    C_SIDE_IN = 1
    C_SIDE_NEAR = -1      # a chord is listed in the cell
    C_BOX_OUTSIDE = 0
    C_BOX_CROSSING = 1
    C_BOX_INSIDE = 2

BOX_OUTSIDE, BOX_CROSSING, BOX_INSIDE = C_BOX_OUTSIDE, C_BOX_CROSSING, C_BOX_INSIDE


cdef inline double _cell_x(const Chords *c, Py_ssize_t i) noexcept nogil:
    return c.x0 + i * c.h


cdef inline double _cell_y(const Chords *c, Py_ssize_t j) noexcept nogil:
    return c.y0 + j * c.h


cdef inline Py_ssize_t _span(double origin, double h, Py_ssize_t n, double v) noexcept nogil:
    """The i of the n spans [origin + i h, origin + (i + 1) h) that holds v, exactly
    (v in the grid; the ends computed as _cell_x and _cell_y do)."""
    cdef Py_ssize_t i = min(max(<Py_ssize_t>((v - origin) / h), 0), n - 1)
    while i > 0 and v < origin + i * h:
        i -= 1
    while i < n - 1 and v >= origin + (i + 1) * h:
        i += 1
    return i


cdef inline Py_ssize_t _column(const Chords *c, double x) noexcept nogil:
    return _span(c.x0, c.h, c.nx, x)


cdef inline Py_ssize_t _row(const Chords *c, double y) noexcept nogil:
    return _span(c.y0, c.h, c.ny, y)


cdef inline bint _crosses_within(double ax, double ay, double bx, double by, double line,
                                 double lo, double hi) noexcept nogil:
    """Does the segment ab cross the horizontal line y = ``line`` (an end on the line
    counts as below it) at an x in [lo, hi)? (lo may be -inf, hi +inf.)"""
    cdef double ux, uy, wx, wy
    if (ay > line) == (by > line):
        return False
    if ay > line:                       # u below the line, w above it
        ux, uy, wx, wy = bx, by, ax, ay
    else:
        ux, uy, wx, wy = ax, ay, bx, by
    # orient(u, w, (c, line)) is the sign of X - c, X the crossing's x
    if lo != -INFINITY and orient_sign(ux, uy, wx, wy, lo, line) < 0:
        return False
    if hi != INFINITY and orient_sign(ux, uy, wx, wy, hi, line) >= 0:
        return False
    return True


cdef int _crossings(const Chords *c, Py_ssize_t k, bint vertical, double line, double lo,
                    double hi) noexcept nogil:
    """Parity of the chords listed in cell k that cross the horizontal line y = ``line``
    at an x in [lo, hi) (``vertical``: the line x = ``line``, at a y in [lo, hi))."""
    cdef Py_ssize_t t, e
    cdef int parity = 0
    for t in range(c.start[k], c.start[k + 1]):
        e = c.items[t]
        if vertical:                   # the same test with x and y swapped
            parity ^= _crosses_within(_y(c, e, 0), _x(c, e, 0), _y(c, e, 1), _x(c, e, 1),
                                      line, lo, hi)
        else:
            parity ^= _crosses_within(_x(c, e, 0), _y(c, e, 0), _x(c, e, 1), _y(c, e, 1),
                                      line, lo, hi)
    return parity


def cell_sides(vis):
    """The side of each cell of the chord grid, int8 (ny * nx,): 1 for a cell inside
    the region bounded by the chords, 0 outside, -1 for a cell with chords listed (near
    the boundary). The argument of :func:`points_inside` and :func:`boxes_state`.

    Each row is swept from the left at the height of its cells' centres, counting the
    chords crossing it in each cell's half-open span of x.

    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> vis = chord_bundle(square, [np.arange(4)], 4, 0.1)    # 25 x 25 cells
    >>> sides = cell_sides(vis)
    >>> int((sides == 1).sum()), int((sides == 0).sum()), int((sides == -1).sum())
    (169, 0, 456)
    """
    cdef Chords c = chords_of(vis)
    if c.empty:
        return np.zeros(0, np.int8)
    sides_array = np.empty(c.nx * c.ny, np.int8)
    cdef int8_t[::1] sides = sides_array
    cdef Py_ssize_t ix, iy, k
    cdef int parity
    cdef double yc, lo, hi
    with nogil:
        for iy in range(c.ny):
            yc = c.y0 + (iy + 0.5) * c.h
            parity = 0
            for ix in range(c.nx):
                k = iy * c.nx + ix
                if c.start[k + 1] == c.start[k]:
                    sides[k] = parity
                    continue
                sides[k] = C_SIDE_NEAR
                lo = _cell_x(&c, ix) if ix > 0 else -INFINITY
                hi = _cell_x(&c, ix + 1) if ix < c.nx - 1 else INFINITY
                parity ^= _crossings(&c, k, False, yc, lo, hi)
    return sides_array


cdef bint _on_chord(const Chords *c, Py_ssize_t k, double x, double y) noexcept nogil:
    """Is (x, y) on a chord listed in cell k?"""
    cdef Py_ssize_t t, e
    cdef double ex, ey, fx, fy
    for t in range(c.start[k], c.start[k + 1]):
        e = c.items[t]
        ex, ey, fx, fy = _x(c, e, 0), _y(c, e, 0), _x(c, e, 1), _y(c, e, 1)
        if (min(ex, fx) <= x <= max(ex, fx) and min(ey, fy) <= y <= max(ey, fy)
                and orient_sign(ex, ey, fx, fy, x, y) == 0):
            return True
    return False


cdef bint point_inside(const Chords *c, const int8_t *sides, double x,
                       double y) noexcept nogil:
    """Is (x, y) strictly inside the region bounded by the chords? (``sides`` from
    :func:`cell_sides`.) Exact."""
    if c.empty or not (_cell_x(c, 0) <= x < _cell_x(c, c.nx)
                       and _cell_y(c, 0) <= y < _cell_y(c, c.ny)):
        return False
    cdef Py_ssize_t ix = _column(c, x), iy = _row(c, y), d, steps, k, i, j
    cdef int direction = -1, parity = 0
    k = iy * c.nx + ix
    if sides[k] != C_SIDE_NEAR:
        return sides[k] == C_SIDE_IN
    if _on_chord(c, k, x, y):
        return False
    # the nearest cell along the row or column that is off the grid (outside) or has
    # no chord: its side is known, and the chords between it and (x, y) are listed in
    # the cells in between
    d = 0
    while direction < 0:
        d += 1
        for direction in range(4):
            i = ix + (d if direction == 1 else -d if direction == 0 else 0)
            j = iy + (d if direction == 3 else -d if direction == 2 else 0)
            if i < 0 or i >= c.nx or j < 0 or j >= c.ny:
                break
            if sides[j * c.nx + i] != C_SIDE_NEAR:
                parity = sides[j * c.nx + i]
                break
        else:
            direction = -1
    steps = d
    for d in range(steps):
        if direction == 0:          # leftwards: crossings at x in [cell's left, x)
            i = ix - d
            parity ^= _crossings(c, iy * c.nx + i, False, y,
                                 _cell_x(c, i) if i > 0 else -INFINITY,
                                 min(_cell_x(c, i + 1), x))
        elif direction == 1:        # rightwards: at x in (x, cell's right)
            i = ix + d
            parity ^= _crossings(c, iy * c.nx + i, False, y, max(_cell_x(c, i), x),
                                 _cell_x(c, i + 1) if i < c.nx - 1 else INFINITY)
        elif direction == 2:        # downwards
            j = iy - d
            parity ^= _crossings(c, j * c.nx + ix, True, x,
                                 _cell_y(c, j) if j > 0 else -INFINITY,
                                 min(_cell_y(c, j + 1), y))
        else:                       # upwards
            j = iy + d
            parity ^= _crossings(c, j * c.nx + ix, True, x, max(_cell_y(c, j), y),
                                 _cell_y(c, j + 1) if j < c.ny - 1 else INFINITY)
    return parity == C_SIDE_IN


cdef inline bint _meets_box(double ex, double ey, double fx, double fy, double x_lo,
                            double y_lo, double x_hi, double y_hi) noexcept nogil:
    """Does the segment ef meet the closed box [x_lo, x_hi] x [y_lo, y_hi]? Exact: they
    are apart iff an axis or the segment's line separates them."""
    if max(ex, fx) < x_lo or min(ex, fx) > x_hi or max(ey, fy) < y_lo or min(ey, fy) > y_hi:
        return False
    cdef int s = (orient_sign(ex, ey, fx, fy, x_lo, y_lo) + orient_sign(ex, ey, fx, fy, x_hi, y_lo)
                  + orient_sign(ex, ey, fx, fy, x_hi, y_hi)
                  + orient_sign(ex, ey, fx, fy, x_lo, y_hi))
    return s != 4 and s != -4


cdef int box_state(const Chords *c, const int8_t *sides, double bx, double by,
                   double size) noexcept nogil:
    """Where the closed box [bx, bx+size]² lies: 0 outside the region bounded by the
    chords, 1 crossing or touching a chord, 2 inside (no point on a chord). Exact."""
    if c.empty:
        return C_BOX_OUTSIDE
    cdef double x_hi = bx + size, y_hi = by + size
    cdef Py_ssize_t i, j, t, e, i_lo, i_hi, j_lo, j_hi
    if (x_hi < _cell_x(c, 0) or bx >= _cell_x(c, c.nx) or y_hi < _cell_y(c, 0)
            or by >= _cell_y(c, c.ny)):
        return C_BOX_OUTSIDE
    i_lo, i_hi = _column(c, max(bx, _cell_x(c, 0))), _column(c, min(x_hi, _cell_x(c, c.nx)))
    j_lo, j_hi = _row(c, max(by, _cell_y(c, 0))), _row(c, min(y_hi, _cell_y(c, c.ny)))
    for j in range(j_lo, j_hi + 1):
        for i in range(i_lo, i_hi + 1):
            for t in range(c.start[j * c.nx + i], c.start[j * c.nx + i + 1]):
                e = c.items[t]
                if _meets_box(_x(c, e, 0), _y(c, e, 0), _x(c, e, 1), _y(c, e, 1), bx, by,
                              x_hi, y_hi):
                    return C_BOX_CROSSING
    return C_BOX_INSIDE if point_inside(c, sides, bx, by) else C_BOX_OUTSIDE


def points_inside(vis, sides, x, y):
    """True for the points (x, y) strictly inside the region bounded by the chords of
    ``vis`` (a point on a chord is not inside: shapely's ``contains_xy``). ``sides``
    from :func:`cell_sides`.

    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> vis = chord_bundle(square, [np.arange(4)], 4, 0.25)
    >>> points_inside(vis, cell_sides(vis), [0.5, 0.0, 1.5, 0.999], [0.5, 0.5, 0.5, 0.999])
    array([ True, False, False,  True])
    """
    cdef const double[::1] xs = np.ascontiguousarray(x, np.float64)
    cdef const double[::1] ys = np.ascontiguousarray(y, np.float64)
    cdef const int8_t[::1] sd = sides
    cdef Chords c = chords_of(vis)
    cdef Py_ssize_t k
    inside_array = np.zeros(xs.shape[0], bool)
    cdef uint8_t[::1] inside = inside_array.view(np.uint8)
    with nogil:
        for k in range(xs.shape[0]):
            inside[k] = point_inside(&c, &sd[0] if sd.shape[0] else NULL, xs[k], ys[k])
    return inside_array


def boxes_state(vis, sides, bx, by, size):
    """Where each closed box [bx, bx+size] x [by, by+size] lies against the region
    bounded by the chords of ``vis``: int8, 0 outside (shapely's ``intersects`` is
    False), 1 crossing or touching a chord, 2 inside (``contains_properly``). ``size``
    is one number or one per box; ``sides`` from :func:`cell_sides`.

    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> vis = chord_bundle(square, [np.arange(4)], 4, 0.25)
    >>> boxes_state(vis, cell_sides(vis), [0.25, 0.9, 1.0, 1.5], [0.25, 0.5, 0.5, 0.5], 0.1)
    array([2, 1, 1, 0], dtype=int8)
    """
    cdef const double[::1] xs = np.ascontiguousarray(bx, np.float64)
    cdef const double[::1] ys = np.ascontiguousarray(by, np.float64)
    cdef const double[::1] sz = np.ascontiguousarray(
        np.broadcast_to(np.asarray(size, np.float64), (xs.shape[0],)))
    cdef const int8_t[::1] sd = sides
    cdef Chords c = chords_of(vis)
    cdef Py_ssize_t k
    state_array = np.empty(xs.shape[0], np.int8)
    cdef int8_t[::1] state = state_array
    with nogil:
        for k in range(xs.shape[0]):
            state[k] = box_state(&c, &sd[0] if sd.shape[0] else NULL, xs[k], ys[k], sz[k])
    return state_array
