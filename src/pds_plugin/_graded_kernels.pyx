# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of graded (variable-radius) sampling and of the radius field
(docs/graded.md).

Samples sit in a pyramid of uniform grids (``bins`` = (heads, offsets, nxs, nys, hs,
counts)): level l has square bins of side ``hs[l] = hs[0] 2^l`` and holds the samples
q with ``hs[l] <= r(q) < 2 hs[l]`` (level 0 also the smaller ones, the top level the
larger), ``heads[offsets[l] + c]`` one more than the last sample of its bin c (0: an
empty bin, so that a zeroed array, which the system hands out untouched, is an empty
pyramid: only the pages of bins that get samples are ever written), ``nxt[q]`` the
sample before q (-1: none). A sample q only matters within r(q) <= 2 hs[l], so a query looks at 5 x 5 bins
per level at most, whatever the radii around it. The radius field is evaluated outside
(sizing.py, ``_sizing_kernels``); the kernels get its values. Visibility is that of ``_visibility_kernels``
(a ``ChordBundle``), with chords binned by their own reach (:func:`bin_chords_by_reach`).

Conventions of the kernel modules: see ``_parallel.pyx``.
"""

import numpy as np

from cython.parallel cimport parallel, prange
from libc.math cimport INFINITY, hypot, sqrt
from libc.stdlib cimport free, malloc, realloc
from libc.stdint cimport int8_t, int32_t, int64_t, uint8_t, uint32_t, uint64_t
from libc.string cimport memcpy

from ._parallel cimport threads_for
from ._sizing_kernels cimport CONE_STACK, ConeTree, cone_at, cone_tree_of, quarters_at
from ._visibility_kernels cimport (CellMarks, ChordGrid, Chords, bin_chords_by, box_seen, chord_cell,
                                   box_state, chords_of, mark_cell, point_inside, sees)

cdef enum:
    CHUNK = 256     # iterations a thread takes at a time


cdef struct Bins:
    # the pyramid of sample grids (module docstring), as raw pointers into its arrays
    int32_t *heads
    const int64_t *offsets
    const int64_t *nxs
    const int64_t *nys
    const double *hs
    int64_t *counts
    Py_ssize_t levels


cdef Bins _bins_of(tuple bins) except *:
    cdef Bins b
    cdef int32_t[::1] heads = bins[0]
    cdef const int64_t[::1] offsets = bins[1]
    cdef const int64_t[::1] nxs = bins[2]
    cdef const int64_t[::1] nys = bins[3]
    cdef const double[::1] hs = bins[4]
    cdef int64_t[::1] counts = bins[5]
    b.heads, b.offsets, b.nxs, b.nys = &heads[0], &offsets[0], &nxs[0], &nys[0]
    b.hs, b.counts, b.levels = &hs[0], &counts[0], hs.shape[0]
    return b


cdef inline Py_ssize_t _clamp(double v, Py_ssize_t n) noexcept nogil:
    """The bin of coordinate ``v`` (already divided by the bin side), in [0, n)."""
    return min(max(<Py_ssize_t>v, 0), n - 1)


cdef void _cells_within_reach(double xa, double ya, double xb, double yb, double reach,
                              const ChordGrid *g, CellMarks *marks) noexcept nogil:
    """The cell rule of :func:`bin_chords_by_reach`: the cells of the chord's bounding box
    grown by ``reach`` whose distance to the chord (clamp and test) is within
    ``reach + h``."""
    cdef Py_ssize_t lo_x = _clamp((min(xa, xb) - reach - g.x0) / g.h, g.nx)
    cdef Py_ssize_t lo_y = _clamp((min(ya, yb) - reach - g.y0) / g.h, g.ny)
    cdef Py_ssize_t hi_x = _clamp((max(xa, xb) + reach - g.x0) / g.h, g.nx)
    cdef Py_ssize_t hi_y = _clamp((max(ya, yb) + reach - g.y0) / g.h, g.ny)
    cdef double dx = xb - xa, dy = yb - ya, length2 = dx * dx + dy * dy
    cdef double cx, cy, t, px, py, qx, qy, x_lo, y_lo, x_hi, y_hi
    cdef Py_ssize_t jx, jy
    for jy in range(lo_y, hi_y + 1):
        for jx in range(lo_x, hi_x + 1):
            x_lo, x_hi = g.x0 + jx * g.h, g.x0 + (jx + 1) * g.h
            y_lo, y_hi = g.y0 + jy * g.h, g.y0 + (jy + 1) * g.h
            cx = min(max(xa, x_lo), x_hi)
            cy = min(max(ya, y_lo), y_hi)
            t = 0.0
            if length2 != 0.0:
                t = min(max(((cx - xa) * dx + (cy - ya) * dy) / length2, 0.0), 1.0)
            px, py = xa + t * dx, ya + t * dy
            qx = min(max(px, x_lo), x_hi)
            qy = min(max(py, y_lo), y_hi)
            if (px - qx) * (px - qx) + (py - qy) * (py - qy) <= (reach + g.h) * (reach + g.h):
                mark_cell(marks, jy * g.nx + jx)


def bin_chords_by_reach(chords, reach, double x0, double y0, double h, Py_ssize_t nx,
                        Py_ssize_t ny):
    """CSR lists (start, items) of the chords within ``reach[e]`` of each cell."""
    cdef ChordGrid grid = ChordGrid(x0, y0, h, nx, ny)
    return bin_chords_by(chords, np.ascontiguousarray(reach, float), grid, _cells_within_reach)


cdef inline Py_ssize_t _level(double r, const Bins *b) noexcept nogil:
    """The pyramid level of a sample of radius r."""
    cdef Py_ssize_t level = 0
    while level + 1 < b.levels and b.hs[level + 1] <= r:
        level += 1
    return level


cdef bint _in_lens(double x, double y, double ax, double ay, double bx, double by,
                   double limit) noexcept nogil:
    """Is (x, y) on the inner side of chord ab, with an obtuse angle at x and the
    circumradius of (a, b, x) above ``limit``? That set is the circular segment between
    the chord and the arc of radius ``limit`` through a and b: convex."""
    cdef double cross = (bx - ax) * (y - ay) - (by - ay) * (x - ax)
    if cross <= 0.0 or (ax - x) * (bx - x) + (ay - y) * (by - y) >= 0.0:
        return False
    cdef double ab2 = (bx - ax) * (bx - ax) + (by - ay) * (by - ay)
    cdef double ax2 = (x - ax) * (x - ax) + (y - ay) * (y - ay)
    cdef double bx2 = (x - bx) * (x - bx) + (y - by) * (y - by)
    return ab2 * ax2 * bx2 > 4.0 * limit * limit * cross * cross


cdef inline Py_ssize_t _chord_cell(double x, double y, const Chords *c) noexcept nogil:
    return (_clamp((y - c.y0) / c.h, c.ny) * c.nx + _clamp((x - c.x0) / c.h, c.nx))


cdef bint _encroaches(double x, double y, double bound, const double[::1] chord_bound,
                      const Chords *c) noexcept nogil:
    """Would (x, y) make a chord's triangle too large to keep? True if x lies in the
    lens (:func:`_in_lens`) of a chord ab near it with limit min(bound,
    chord_bound[ab]): the constrained triangle on the chord would be dropped and the
    mesh dented. No sample goes there."""
    if c.empty:
        return False
    cdef Py_ssize_t cell = _chord_cell(x, y, c), t, e
    for t in range(c.start[cell], c.start[cell + 1]):
        e = c.items[t]
        if _in_lens(x, y, c.xy[4 * e], c.xy[4 * e + 1], c.xy[4 * e + 2], c.xy[4 * e + 3],
                    min(bound, chord_bound[e])):
            return True
    return False


cdef double LENS_STOP = 1e-3    # boxes smaller than this (relative to r) touching a lens stop there:
                        # at 1e-6 the boxes along a long chord's lens doubled for ~20 levels
                        # without a dart kept (random cut block 0: 1.8 million boxes, 7.8 s
                        # in one patch); from 1e-4 to 1e-3 the same samples on 192 graded
                        # meshes and every bench remesh, 21 % less time on a held-out
                        # cross-drilled block (30 000 boxes a level at the arcs of lenses
                        # at r = 0.03 alpha)


cdef bint _box_in_lens(double x_lo, double y_lo, double s, double low, double high,
                       double grading, const double[::1] chord_bound,
                       const Chords *c) noexcept nogil:
    """Is no dart in the box ever kept because of the chord lenses? True if its four
    corners are in one chord's lens for the largest radius r can have on the box
    (``high``, an upper bound of r on it: the lens is convex, and a dart's own lens is
    at least as large), or if the box is
    smaller than ``LENS_STOP`` low and touches a lens: refining along a lens's arc (or its
    chord, where a box straddles the region's edge) would never end, and a point so close
    to the arc is within LENS_STOP r of one that the chord's triangle covers."""
    if c.empty:
        return False
    cdef Py_ssize_t cell = _chord_cell(x_lo + 0.5 * s, y_lo + 0.5 * s, c), t, e
    cdef double limit
    cdef int inside
    for t in range(c.start[cell], c.start[cell + 1]):
        e = c.items[t]
        limit = min(chord_bound[e], high / (1.0 - grading))
        inside = (_in_lens(x_lo, y_lo, c.xy[4 * e], c.xy[4 * e + 1], c.xy[4 * e + 2],
                           c.xy[4 * e + 3], limit)
                  + _in_lens(x_lo + s, y_lo, c.xy[4 * e], c.xy[4 * e + 1], c.xy[4 * e + 2],
                             c.xy[4 * e + 3], limit)
                  + _in_lens(x_lo, y_lo + s, c.xy[4 * e], c.xy[4 * e + 1], c.xy[4 * e + 2],
                             c.xy[4 * e + 3], limit)
                  + _in_lens(x_lo + s, y_lo + s, c.xy[4 * e], c.xy[4 * e + 1],
                             c.xy[4 * e + 2], c.xy[4 * e + 3], limit))
        if inside == 4 or (inside > 0 and s < LENS_STOP * low):
            return True
    return False


cdef inline Py_ssize_t _out(const Chords *c, Py_ssize_t q) noexcept nogil:
    return c.out[q] if c.out else -1


cdef struct Placed:
    # the samples placed so far, as raw pointers into the sampler's arrays
    const int32_t *nxt              # the sample before each in its bin
    const double *points            # (n, 2) samples
    const double *radius            # r at each sample
    double x0, y0                   # the pyramid's origin


cdef Placed _placed_of(nxt, points, radius, double x0, double y0) except *:
    """The struct view of the sampler's arrays (they must outlive it)."""
    cdef const int32_t[::1] nx = nxt
    cdef const double[:, ::1] pt = points
    cdef const double[::1] rd = radius
    return Placed(&nx[0], &pt[0, 0], &rd[0], x0, y0)


cdef struct Query:
    # a question to the samples near a point or box (:func:`_any_sample`)
    double x, y, size               # the box [x, x + size] x [y, y + size] (a point: size 0)
    double r                        # r at the point, or the lower bound of r on the box
    const Placed *placed
    const Chords *chords

# Does sample q answer the query (conflict with the point, cover the box)?
ctypedef bint (*SampleTest)(const Query *query, Py_ssize_t q) noexcept nogil


cdef bint _any_sample(const Query *query, SampleTest test, Py_ssize_t first, Py_ssize_t last,
                      Py_ssize_t since, const Bins *b, bint cover=False) noexcept nogil:
    """Does ``test`` hold for a sample numbered ``since`` or later on the levels
    first..last within min(r, 2 h) of the query's box (a sample of level l matters within
    r(q) < 2 h of it)? With ``cover``, only the samples within that distance of all four
    corners are asked (the box is covered by one of them or not at all): the bins that
    meet [x + size - w, x + w]² (w = min(r, 2 h), with a margin for rounding), none if
    that is empty. A bin lists its samples newest first, so the walk stops at the first
    one before ``since``."""
    cdef Py_ssize_t level, nx, ny, jx, jy, lo_x, lo_y, hi_x, hi_y
    cdef int32_t q
    cdef double h, reach, margin, x0 = query.placed.x0, y0 = query.placed.y0
    for level in range(first, last + 1):
        if b.counts[level] == 0:
            continue
        h, nx, ny = b.hs[level], b.nxs[level], b.nys[level]
        reach = min(query.r, 2.0 * h)
        if cover:
            margin = 1e-9 * (reach + query.size + abs(query.x) + abs(query.y))
            if query.size > 2.0 * reach + 2.0 * margin:
                continue
            lo_x = _clamp((query.x + query.size - reach - margin - x0) / h, nx)
            lo_y = _clamp((query.y + query.size - reach - margin - y0) / h, ny)
            hi_x = _clamp((query.x + reach + margin - x0) / h, nx)
            hi_y = _clamp((query.y + reach + margin - y0) / h, ny)
        else:
            lo_x = _clamp((query.x - reach - x0) / h, nx)
            lo_y = _clamp((query.y - reach - y0) / h, ny)
            hi_x = _clamp((query.x + query.size + reach - x0) / h, nx)
            hi_y = _clamp((query.y + query.size + reach - y0) / h, ny)
        for jy in range(lo_y, hi_y + 1):
            for jx in range(lo_x, hi_x + 1):
                q = b.heads[b.offsets[level] + jy * nx + jx] - 1
                while q >= since:
                    if test(query, q):
                        return True
                    q = query.placed.nxt[q]
    return False


cdef bint _conflicts(const Query *query, Py_ssize_t q) noexcept nogil:
    """Is sample q closer to the point than min(r(x), r(q)), and seen from it?"""
    cdef double qx = query.placed.points[2 * q], qy = query.placed.points[2 * q + 1]
    cdef double dx = qx - query.x, dy = qy - query.y
    cdef double bound = min(query.r, query.placed.radius[q])
    return dx * dx + dy * dy < bound * bound and sees(
        query.x, query.y, -1, qx, qy, _out(query.chords, q), query.chords)


cdef bint _covers(const Query *query, Py_ssize_t q) noexcept nogil:
    """Is the box's farthest corner within min(r(q), low) of sample q, and does q see
    all of the box that lies in the region?"""
    cdef double qx = query.placed.points[2 * q], qy = query.placed.points[2 * q + 1]
    cdef double fx = max(abs(qx - query.x), abs(qx - (query.x + query.size)))
    cdef double fy = max(abs(qy - query.y), abs(qy - (query.y + query.size)))
    cdef double bound = min(query.placed.radius[q], query.r)
    return fx * fx + fy * fy <= bound * bound and box_seen(
        qx, qy, _out(query.chords, q), query.x, query.y, query.size, 1e-9 * bound,
        query.chords)


cdef bint _free(double x, double y, double rx, double grading, const double[::1] chord_bound,
                const Bins *b, const Placed *p, const Chords *c,
                Py_ssize_t since=0) noexcept nogil:
    """True if no sample q that (x, y) sees has |x - q| < min(r(x), r(q)), and x does
    not encroach on a chord (:func:`_encroaches`). A conflicting q has r(q) within
    r(x) (1 ± L) (the field is L-Lipschitz), which picks the levels. With ``since`` > 0,
    only the samples numbered ``since`` or later are asked, and not the chords."""
    if since == 0 and _encroaches(x, y, rx / (1.0 - grading), chord_bound, c):
        return False
    cdef Query query = Query(x, y, 0.0, rx, p, c)
    return not _any_sample(&query, _conflicts, _level(rx * (1.0 - grading), b),
                           _level(rx * (1.0 + grading), b), since, b)


cdef void _place(double x, double y, double r, Bins *b, int32_t[::1] nxt, double[:, ::1] points,
                 double[::1] radius, Py_ssize_t count, double x0, double y0) noexcept nogil:
    """Make (x, y) with radius r sample number ``count``."""
    cdef Py_ssize_t level = _level(r, b)
    cdef Py_ssize_t ix = _clamp((x - x0) / b.hs[level], b.nxs[level])
    cdef Py_ssize_t iy = _clamp((y - y0) / b.hs[level], b.nys[level])
    cdef Py_ssize_t cell = b.offsets[level] + iy * b.nxs[level] + ix
    points[count, 0] = x
    points[count, 1] = y
    radius[count] = r
    nxt[count] = b.heads[cell] - 1
    b.heads[cell] = <int32_t>(count + 1)
    b.counts[level] += 1


def place(new, new_radius, tuple bins, nxt, points, radius, Py_ssize_t count, double x0,
          double y0):
    """Add the samples ``new`` with their radii as samples count, count + 1, ...;
    returns the new count."""
    cdef const double[:, ::1] nw = new
    cdef const double[::1] nr = new_radius
    cdef int32_t[::1] nx = nxt
    cdef double[:, ::1] pt = points
    cdef double[::1] rd = radius
    cdef Bins b = _bins_of(bins)
    cdef Py_ssize_t k
    with nogil:
        for k in range(nw.shape[0]):
            _place(nw[k, 0], nw[k, 1], nr[k], &b, nx, pt, rd, count, x0, y0)
            count += 1
    return count


def insert_where_free(cand, cand_radius, order, double grading, chord_bound, tuple bins, nxt,
                      points, radius, Py_ssize_t count, double x0, double y0, vis, kept=None):
    """Insert the candidates in ``order`` wherever the variable-radius Poisson condition
    allows (:func:`_free`); ``kept`` (a bool array, one per candidate), if given, is set
    True for each inserted candidate. Returns the new sample count."""
    cdef const double[:, ::1] cd = cand
    cdef const double[::1] cr = cand_radius
    cdef const int64_t[::1] od = order
    cdef const double[::1] cb = chord_bound
    cdef int32_t[::1] nx = nxt
    cdef double[:, ::1] pt = points
    cdef double[::1] rd = radius
    cdef Bins b = _bins_of(bins)
    cdef Placed p = _placed_of(nxt, points, radius, x0, y0)
    cdef Chords c = chords_of(vis)
    cdef uint8_t[::1] mark = (np.zeros(cd.shape[0], np.bool_) if kept is None
                              else kept).view(np.uint8)
    cdef Py_ssize_t t, k
    with nogil:
        for t in range(od.shape[0]):
            k = od[t]
            if _free(cd[k, 0], cd[k, 1], cr[k], grading, cb, &b, &p, &c):
                _place(cd[k, 0], cd[k, 1], cr[k], &b, nx, pt, rd, count, x0, y0)
                mark[k] = 1
                count += 1
    return count


cdef double *_gathered(Py_ssize_t n, Py_ssize_t width) noexcept nogil:
    """Room for ``width`` doubles per item of n (at least one byte): the kernels gather
    the values of the items they take in a spatial order side by side first, since read
    in place, in that order, each array costs a cache miss per item (perf on the
    373-hole drawing: most of the time of those loops), while the gathering loop's loads
    do not wait on one another."""
    return <double *>malloc(max(n * width, 1) * sizeof(double))


cdef class Field:
    """The radius field as the kernels ask it: its cone tree searched in C (a field
    without a user sizing: ``fast``), else the field itself called (``RadiusField``).
    Each search starts from an upper bound of r (``ABOVE`` times the ``high`` bound of
    the box a point is in): it prunes more and finds the same exact minimum."""
    cdef ConeTree tree
    cdef bint fast
    cdef bint constant          # no cone and no user sizing: r is the cap everywhere
    cdef object field
    cdef object keep            # the arrays the tree points into

    def __init__(self, field):
        self.field = field
        self.fast = field.sizing is None and field._tree is not None
        self.constant = field.sizing is None and field._tree is None
        if self.fast:
            self.keep = (field.features, field.sizes, field._tree)
            self.tree = cone_tree_of(field.features, field.sizes, field.grading, field.cap,
                                     field._tree)

    cdef double low_on_box(self, double x, double y, double r, double spread,
                           int64_t *stack, double *bound) noexcept nogil:
        """A lower bound of r on a box centred at (x, y), where r is ``r`` and moves by at
        most ``spread``: r - spread; where r is the cap, min(cap, the cones at (x, y) -
        spread), searched up to cap + spread: the cap itself on boxes that no cone
        comes near, which one disc of the cap's radius may then cover. Exact: r(x) >=
        min(cap, min_i(s_i + L |c - f_i|) - L |x - c|). (A field without cones is the
        cap everywhere: its callers pass spread 0.)"""
        if not self.fast or r < self.tree.cap or stack == NULL or bound == NULL:
            return r - spread
        return min(self.tree.cap,
                   cone_at(&self.tree, x, y, self.tree.cap + spread, stack, bound) - spread)

    cdef object at(self, double[:, ::1] xy, const double[::1] high,
                   const int64_t[::1] order):
        """r at the points ``xy``, each in a box where r <= ``high``, searched in
        ``order`` (:func:`_spatial_order`: neighbours meet the same nodes in the cache)."""
        cdef Py_ssize_t n = xy.shape[0], k, t
        if not self.fast:
            return np.asarray(self.field(np.asarray(xy)), float)
        out_array = np.empty(n)
        cdef double[::1] out = out_array
        cdef int64_t *stack
        cdef double *bound
        cdef double *point = _gathered(n, 3)     # x, y, high in ``order``, then r there
        if point == NULL:
            raise MemoryError()
        with nogil:
            for t in range(n):
                k = order[t]
                point[3 * t], point[3 * t + 1], point[3 * t + 2] = xy[k, 0], xy[k, 1], high[k]
        with nogil, parallel(num_threads=threads_for(n)):
            stack = <int64_t *>malloc(CONE_STACK * sizeof(int64_t))
            bound = <double *>malloc(CONE_STACK * sizeof(double))
            for t in prange(n, schedule="dynamic", chunksize=CHUNK):
                point[3 * t] = cone_at(&self.tree, point[3 * t], point[3 * t + 1],
                                       min(self.tree.cap, ABOVE * point[3 * t + 2]), stack,
                                       bound)
            free(bound)
            free(stack)
        with nogil:
            for t in range(n):
                out[order[t]] = point[3 * t]
            free(point)
        return out_array

    cdef object at_quarters(self, const double[::1] x, const double[::1] y,
                            const double[::1] size, const double[::1] high,
                            const int64_t[::1] order):
        """r at the centres of the quarters of the boxes (``RadiusField.at_quarters``'
        order), r <= ``high`` on each box, the boxes searched in ``order``."""
        cdef Py_ssize_t n = x.shape[0], k, j, t
        cdef double x_lo, y_lo, side
        if not self.fast:
            return np.asarray(self.field.at_quarters(np.asarray(x), np.asarray(y),
                                                     np.asarray(size)), float)
        out_array = np.empty(4 * n)
        cdef double[::1] out = out_array
        cdef int64_t *stack
        cdef double *box = _gathered(n, 4)       # x, y, size, high in ``order``, then the
        if box == NULL:                          # four r of the quarters
            raise MemoryError()
        with nogil:
            for t in range(n):
                k = order[t]
                box[4 * t], box[4 * t + 1], box[4 * t + 2], box[4 * t + 3] = \
                    x[k], y[k], size[k], high[k]
        cdef double *v
        with nogil, parallel(num_threads=threads_for(n)):
            stack = <int64_t *>malloc(CONE_STACK * sizeof(int64_t))
            for t in prange(n, schedule="dynamic", chunksize=CHUNK):
                v = box + 4 * t
                x_lo, y_lo, side = v[0], v[1], v[2]
                v[0] = min(self.tree.cap, ABOVE * v[3])
                v[1], v[2], v[3] = v[0], v[0], v[0]
                quarters_at(&self.tree, x_lo, y_lo, side, v, stack)
            free(stack)
        with nogil:
            for t in range(n):
                k = order[t]
                for j in range(4):
                    out[j * n + k] = box[4 * t + j]
            free(box)
        return out_array


cdef struct Dense:
    # the growing output of :func:`densified_rings`
    double *xy
    double *r
    uint8_t *vertex
    Py_ssize_t n, room
    int64_t *stack
    double *bound


cdef bint _emit(Dense *d, double x, double y, double r, bint vertex) noexcept nogil:
    """Append a point (False if memory ran out)."""
    cdef Py_ssize_t room
    cdef double *xy
    cdef double *rr
    cdef uint8_t *vv
    if d.n == d.room:
        room = 2 * d.room
        xy = <double *>realloc(d.xy, 2 * room * sizeof(double))
        if xy == NULL:
            return False
        d.xy = xy
        rr = <double *>realloc(d.r, room * sizeof(double))
        if rr == NULL:
            return False
        d.r = rr
        vv = <uint8_t *>realloc(d.vertex, room * sizeof(uint8_t))
        if vv == NULL:
            return False
        d.vertex = vv
        d.room = room
    d.xy[2 * d.n], d.xy[2 * d.n + 1], d.r[d.n], d.vertex[d.n] = x, y, r, vertex
    d.n += 1
    return True


cdef bint _bisect(Dense *d, const ConeTree *t, double px, double py, double rp, double qx,
                  double qy, double rq, double grading, int depth) noexcept nogil:
    """The points strictly between p and q (r there ``rp``, ``rq``) in order: the midpoint
    and those of both halves, while the part is longer than 0.3 of the lowest r the
    field can have on it, at most 60 halvings deep."""
    cdef double step = hypot(qx - px, qy - py)
    cdef double low = min(rp, rq) - 0.5 * grading * step
    cdef double mx, my, rm
    if depth >= 60 or not step > 0.3 * low:
        return True
    mx, my = 0.5 * (px + qx), 0.5 * (py + qy)
    rm = cone_at(t, mx, my, t.cap, d.stack, d.bound)
    return (_bisect(d, t, px, py, rp, mx, my, rm, grading, depth + 1)
            and _emit(d, mx, my, rm, False)
            and _bisect(d, t, mx, my, rm, qx, qy, rq, grading, depth + 1))


def densified_rings(Field field, points, counts, double grading):
    """``graded_sampling._tau_rings`` in one call for a field searched in C (None for a
    field with a user sizing): the rings (``points`` concatenated, ``counts`` points
    each) densified by halving every part longer than 0.3 of the lowest r the field can
    have on it, r at the points, which are the rings' own vertices, and τ = ∫ dt / r
    at each ring's points and closing point (trapezoid rule), all rings' τ one after the
    other. Returns (points, r, vertex flags, points per ring, τ), the same numbers bit
    for bit as the numpy rounds: each part is halved or not by its own ends, so halving
    part by part, depth first, finds the same points in ring order, and every midpoint,
    r, step and sum is computed as there."""
    if not field.fast:
        return None
    cdef const double[:, ::1] xy = points
    cdef const int64_t[::1] count = counts
    cdef const ConeTree *t = &field.tree
    cdef Py_ssize_t rings = count.shape[0], ring, j, k, lo = 0, n0, i, nxt
    cdef double step
    cdef double *r0 = <double *>malloc(max(xy.shape[0], 1) * sizeof(double))
    cdef Dense d
    d.room = max(4 * xy.shape[0], 16)
    d.n = 0
    d.xy = <double *>malloc(2 * d.room * sizeof(double))
    d.r = <double *>malloc(d.room * sizeof(double))
    d.vertex = <uint8_t *>malloc(d.room * sizeof(uint8_t))
    d.stack = <int64_t *>malloc(CONE_STACK * sizeof(int64_t))
    d.bound = <double *>malloc(CONE_STACK * sizeof(double))
    dense_counts = np.empty(rings, np.int64)
    cdef int64_t[::1] dc = dense_counts
    cdef bint ok = (r0 != NULL and d.xy != NULL and d.r != NULL and d.vertex != NULL
                    and d.stack != NULL and d.bound != NULL)
    with nogil:
        if ok:
            for i in range(xy.shape[0]):
                r0[i] = cone_at(t, xy[i, 0], xy[i, 1], t.cap, d.stack, d.bound)
        for ring in range(rings):
            if not ok:
                break
            n0 = d.n
            for j in range(count[ring]):
                i = lo + j
                k = lo + (j + 1) % count[ring]
                ok = (_emit(&d, xy[i, 0], xy[i, 1], r0[i], True)
                      and _bisect(&d, t, xy[i, 0], xy[i, 1], r0[i], xy[k, 0], xy[k, 1], r0[k],
                                  grading, 0))
                if not ok:
                    break
            dc[ring] = d.n - n0
            lo += count[ring]
    if ok:
        dense = np.empty((d.n, 2))
        radius = np.empty(d.n)
        vertex = np.empty(d.n, np.bool_)
        tau = np.empty(d.n + rings)
    cdef double[:, ::1] dn
    cdef double[::1] rd, ta
    cdef uint8_t[::1] vx
    if ok:
        dn, rd, ta, vx = dense, radius, tau, vertex.view(np.uint8)
        with nogil:
            for i in range(d.n):
                dn[i, 0], dn[i, 1] = d.xy[2 * i], d.xy[2 * i + 1]
                rd[i], vx[i] = d.r[i], d.vertex[i]
            lo = 0
            for ring in range(rings):
                ta[lo + ring] = 0.0
                for j in range(dc[ring]):
                    i = lo + j
                    nxt = lo + (j + 1) % dc[ring]
                    step = hypot(dn[nxt, 0] - dn[i, 0], dn[nxt, 1] - dn[i, 1])
                    ta[lo + ring + j + 1] = (ta[lo + ring + j]
                                             + 0.5 * step * (1.0 / rd[i] + 1.0 / rd[nxt]))
                lo += dc[ring]
    free(r0)
    free(d.xy)
    free(d.r)
    free(d.vertex)
    free(d.stack)
    free(d.bound)
    if not ok:
        raise MemoryError()
    return dense, radius, vertex, dense_counts, tau


cdef struct ChainDense:
    # the growing output of :func:`densified_chains`, per point: its chain and segment
    # (ids), its fraction, its place in each owner's frame and r there (values: t, x0,
    # y0, x1, y1, r0, r1)
    int64_t *ids
    double *values
    Py_ssize_t n, room
    int64_t *stack
    double *bound


cdef struct ChainPart:
    # one segment of a chain: its ends in both owners' frames, which owners read it and
    # their fields (NULL: no cone, r the cap)
    int64_t cid, segment
    double ax0, ay0, bx0, by0, ax1, ay1, bx1, by1
    bint owned0, owned1
    const ConeTree *tree0
    const ConeTree *tree1
    double cap0, cap1


cdef inline double _owner_r(ChainDense *d, bint owned, const ConeTree *tree, double cap,
                            double x, double y) noexcept nogil:
    """An owner's field at (x, y): inf without owner, the cap without cones."""
    if not owned:
        return INFINITY
    if tree == NULL:
        return cap
    return cone_at(tree, x, y, tree.cap, d.stack, d.bound)


cdef void _chain_point(ChainDense *d, const ChainPart *part, double t,
                       double *v) noexcept nogil:
    """The point at fraction ``t`` of ``part``, a + t (b - a) in each owner's frame (as
    ``partition._ChainSet.read`` computes it), and each owner's field there:
    v = x0, y0, x1, y1, r0, r1."""
    v[0] = part.ax0 + t * (part.bx0 - part.ax0)
    v[1] = part.ay0 + t * (part.by0 - part.ay0)
    v[2] = part.ax1 + t * (part.bx1 - part.ax1)
    v[3] = part.ay1 + t * (part.by1 - part.ay1)
    v[4] = _owner_r(d, part.owned0, part.tree0, part.cap0, v[0], v[1])
    v[5] = _owner_r(d, part.owned1, part.tree1, part.cap1, v[2], v[3])


cdef bint _chain_emit(ChainDense *d, const ChainPart *part, double t,
                      const double *v) noexcept nogil:
    """Append a point (False if memory ran out)."""
    cdef void *grown
    if d.n == d.room:
        grown = realloc(d.ids, 4 * d.room * sizeof(int64_t))
        if grown == NULL:
            return False
        d.ids = <int64_t *>grown
        grown = realloc(d.values, 14 * d.room * sizeof(double))
        if grown == NULL:
            return False
        d.values = <double *>grown
        d.room *= 2
    d.ids[2 * d.n], d.ids[2 * d.n + 1] = part.cid, part.segment
    d.values[7 * d.n] = t
    memcpy(&d.values[7 * d.n + 1], v, 6 * sizeof(double))
    d.n += 1
    return True


cdef bint _chain_bisect(ChainDense *d, const ChainPart *part,
                        double tp, double xp, double yp, double rp, double tq, double xq,
                        double yq, double rq, double grading, int depth) noexcept nogil:
    """The points of ``part`` strictly between fractions ``tp`` and ``tq`` (at ``xp``,
    ``yp`` and ``xq``, ``yq`` in the first owner's frame, the smaller r of the owners
    there ``rp``, ``rq``) in order: the midpoint and those of both halves, while the
    part is longer than 0.3 of the lowest r the field can have on it, at most 60
    halvings deep."""
    cdef double step = hypot(xq - xp, yq - yp)
    cdef double low = min(rp, rq) - 0.5 * grading * step
    cdef double tm, rm
    cdef double v[6]
    if depth >= 60 or not step > 0.3 * low:
        return True
    tm = 0.5 * (tp + tq)
    _chain_point(d, part, tm, v)
    rm = min(v[4], v[5])
    return (_chain_bisect(d, part, tp, xp, yp, rp, tm, v[0], v[1], rm, grading, depth + 1)
            and _chain_emit(d, part, tm, v)
            and _chain_bisect(d, part, tm, v[0], v[1], rm, tq, xq, yq, rq, grading,
                              depth + 1))


def densified_chains(fields, corner0, corner1, owner, counts, closed, double grading):
    """``partition._ChainSet.dense`` and the owners' reads at its points in one call,
    each owner read by its own field searched in C (``fields``: per region, its
    :class:`Field`; None if one has a user sizing). ``corner0``, ``corner1``: (n, 2) the
    chains' vertices (concatenated, ``counts`` each) in the frame of their owner on side
    0 and 1 (NaN where none); ``owner``: (chains, 2) the region on each side (-1: none);
    ``closed``: which chains are closed. Each part between two
    vertices (and from the last to the first of a closed chain) is halved while longer
    than 0.3 of the lowest r the field can have on it (its ends' smaller r over both
    owners), at most 60 halvings deep.

    Returns (chain, segment, fraction, xy0, r0, xy1, r1) per point, chain by chain
    along each: the same numbers bit for bit as the numpy rounds (each part is halved
    or not by its own ends, so halving part by part, depth first, finds the same points
    in order, and every point, r and step is computed as there)."""
    cdef Field field
    for field in fields:
        if not (field.fast or field.constant):
            return None
    cdef const double[:, ::1] c0 = corner0
    cdef const double[:, ::1] c1 = corner1
    cdef const int64_t[:, ::1] own = owner
    cdef const int64_t[::1] count = counts
    cdef const uint8_t[::1] shut = closed
    cdef Py_ssize_t regions = len(fields), r
    cdef ConeTree *trees = <ConeTree *>malloc(max(regions, 1) * sizeof(ConeTree))
    cdef double *caps = <double *>malloc(max(regions, 1) * sizeof(double))
    cdef uint8_t *coned = <uint8_t *>malloc(max(regions, 1) * sizeof(uint8_t))
    if trees == NULL or caps == NULL or coned == NULL:
        free(trees)
        free(caps)
        free(coned)
        raise MemoryError()
    for r in range(regions):
        field = fields[r]
        coned[r], caps[r] = field.fast, field.field.cap
        if field.fast:
            trees[r] = field.tree
    cdef Py_ssize_t chains = count.shape[0], n = c0.shape[0], c, j, k, lo, parts, i
    cdef int step
    cdef ChainPart part
    cdef ChainDense d
    cdef double *at = <double *>malloc(max(6 * n, 1) * sizeof(double))   # the vertices'
    d.room = max(4 * n, 16)
    d.n = 0
    d.ids = <int64_t *>malloc(2 * d.room * sizeof(int64_t))
    d.values = <double *>malloc(7 * d.room * sizeof(double))
    d.stack = <int64_t *>malloc(CONE_STACK * sizeof(int64_t))
    d.bound = <double *>malloc(CONE_STACK * sizeof(double))
    cdef bint ok = (at != NULL and d.ids != NULL and d.values != NULL and d.stack != NULL
                    and d.bound != NULL)
    with nogil:
        for step in range(2):      # the vertices' points first, then chain by chain in order
            lo = 0
            for c in range(chains):
                if not ok:
                    break
                part.cid = c
                part.owned0, part.owned1 = own[c, 0] >= 0, own[c, 1] >= 0
                part.tree0 = &trees[own[c, 0]] if part.owned0 and coned[own[c, 0]] else NULL
                part.tree1 = &trees[own[c, 1]] if part.owned1 and coned[own[c, 1]] else NULL
                part.cap0 = caps[own[c, 0]] if part.owned0 else 0.0
                part.cap1 = caps[own[c, 1]] if part.owned1 else 0.0
                parts = count[c] if shut[c] else count[c] - 1
                for j in range(count[c]):
                    k = (j + 1) % count[c] if shut[c] else min(j + 1, count[c] - 1)
                    part.segment = j
                    part.ax0, part.ay0 = c0[lo + j, 0], c0[lo + j, 1]
                    part.bx0, part.by0 = c0[lo + k, 0], c0[lo + k, 1]
                    part.ax1, part.ay1 = c1[lo + j, 0], c1[lo + j, 1]
                    part.bx1, part.by1 = c1[lo + k, 0], c1[lo + k, 1]
                    i = 6 * (lo + j)
                    if step == 0:
                        _chain_point(&d, &part, 0.0, &at[i])
                        continue
                    ok = _chain_emit(&d, &part, 0.0, &at[i])
                    if ok and j < parts:
                        k = 6 * (lo + k)
                        ok = _chain_bisect(&d, &part, 0.0, at[i], at[i + 1],
                                           min(at[i + 4], at[i + 5]), 1.0, at[k], at[k + 1],
                                           min(at[k + 4], at[k + 5]), grading, 0)
                    if not ok:
                        break
                lo += count[c]
    cdef int64_t[:, ::1] id_view
    cdef double[:, ::1] value_view
    if ok:
        ids, values = np.empty((d.n, 2), np.int64), np.empty((d.n, 7))
        id_view, value_view = ids, values
        if d.n:
            memcpy(&id_view[0, 0], d.ids, 2 * d.n * sizeof(int64_t))
            memcpy(&value_view[0, 0], d.values, 7 * d.n * sizeof(double))
    free(at)
    free(d.ids)
    free(d.values)
    free(d.stack)
    free(d.bound)
    free(trees)
    free(caps)
    free(coned)
    if not ok:
        raise MemoryError()
    return (ids[:, 0].copy(), ids[:, 1].copy(), values[:, 0].copy(), values[:, 1:3],
            values[:, 5], values[:, 3:5], values[:, 6])


cdef double ABOVE = 1.0 + 1e-9      # r at a point of a box is at most ABOVE x its ``high``:
                                    # high is r at the centre + L x the half-diagonal, and
                                    # rounding is far below 1e-9 of it
cdef double SQRT2 = sqrt(2.0)       # math.sqrt(2), as the sampler's bounds use it


def leaves(double xmin, double ymin, double side, Py_ssize_t nx, Py_ssize_t ny,
           Py_ssize_t max_boxes, Field field, tuple domain, cells=None):
    """The quadtree's leaves over the grid of nx x ny boxes of ``side`` from (xmin, ymin)
    (row by row): each level's boxes that may reach into the region (all of the grid's
    and the edge quarters tested by ``_visibility_kernels.box_state`` against
    ``domain``; ``edge`` whether one may reach outside), with r at their centres from
    ``field`` and its bounds low, high = r -+ L x half-diagonal; those with side at most
    low are leaves, the others split in four (lower left quarters of all of them first,
    then lower right, upper left, upper right). Returns (bx, by, size, low, high, edge)
    of the leaves, level by level, or the number of boxes if the leaves so far and the
    next level's boxes would be more than ``max_boxes``.

    ``cells``, if given, are the grid's boxes to start from (their numbers k = row x nx +
    column, ascending): a superset of those that meet the region (the others are
    outside, ``box_state`` 0, and would be dropped first) gives the same leaves in the
    same order, without testing the whole grid (a layout of many small patches far
    apart, ``remeshing._layout``, is mostly gaps)."""
    cdef const int8_t[::1] sides = domain[1]
    cdef const int8_t *sd = &sides[0] if sides.shape[0] else NULL
    cdef Chords region = chords_of(domain[0])
    cdef double grading = field.field.grading, half, spread, lowest
    cdef int64_t *stack
    cdef double *bound
    cdef double slope = 0.0 if field.constant else grading   # r's spread over a box
    cdef const int64_t[::1] start
    if cells is not None:
        start = np.ascontiguousarray(cells, np.int64)
    cdef Py_ssize_t n = nx * ny if cells is None else start.shape[0], m, k, j, i, split
    cdef Py_ssize_t total = 0, cell
    cdef double[::1] x = np.empty(n), y = np.empty(n), s = np.full(n, side)
    cdef double[::1] parent_high = np.full(n, np.inf)
    cdef uint8_t[::1] e = np.ones(n, np.uint8)
    cdef int8_t[::1] state
    cdef double[:, ::1] centre
    cdef const double[::1] r
    cdef double[:, ::1] kept
    cdef uint8_t[::1] kept_edge
    for k in range(n):
        cell = k if cells is None else start[k]
        x[k] = xmin + side * (cell % nx)
        y[k] = ymin + side * (cell // nx)
    done = []
    while n:
        state = np.empty(n, np.int8)
        for k in prange(n, nogil=True, schedule="dynamic", chunksize=CHUNK,
                        num_threads=threads_for(n)):
            state[k] = box_state(&region, sd, x[k], y[k], s[k]) if e[k] else 2
        m = 0
        with nogil:
            for k in range(n):
                if state[k] != 0:
                    x[m], y[m], s[m], parent_high[m] = x[k], y[k], s[k], parent_high[k]
                    e[m] = e[k] and state[k] != 2
                    m += 1
        centre = np.empty((m, 2))
        for k in range(m):
            centre[k, 0] = x[k] + 0.5 * s[k]
            centre[k, 1] = y[k] + 0.5 * s[k]
        r = field.at(centre, parent_high[:m],
                     _grid_order(np.ascontiguousarray(centre[:, 0]),
                                 np.ascontiguousarray(centre[:, 1]), xmin, ymin, nx * side,
                                 ny * side))
        kept_array = np.empty((5, m))
        kept = kept_array
        kept_edge_array = np.empty(m, np.bool_)
        kept_edge = kept_edge_array.view(np.uint8)
        j = 0
        split = 0
        with nogil:
            stack = <int64_t *>malloc(CONE_STACK * sizeof(int64_t))
            bound = <double *>malloc(CONE_STACK * sizeof(double))
            for k in range(m):
                spread = slope * (s[k] / SQRT2)
                lowest = field.low_on_box(x[k] + 0.5 * s[k], y[k] + 0.5 * s[k], r[k], spread,
                                          stack, bound)
                if s[k] <= lowest:
                    kept[0, j], kept[1, j], kept[2, j] = x[k], y[k], s[k]
                    kept[3, j], kept[4, j] = lowest, r[k] + spread
                    kept_edge[j] = e[k]
                    j += 1
                else:                       # the boxes to split, first in place
                    x[split], y[split], s[split], e[split] = x[k], y[k], s[k], e[k]
                    parent_high[split] = r[k] + spread
                    split += 1
            free(bound)
            free(stack)
        done.append((kept_array[:, :j], kept_edge_array[:j]))
        total += j
        if total + 4 * split > max_boxes:
            return total + 4 * split
        n = 4 * split
        x = np.concatenate([x[:split]] * 4)
        y = np.concatenate([y[:split]] * 4)
        s = np.concatenate([s[:split]] * 4)
        e = np.concatenate([e[:split]] * 4)
        parent_high = np.concatenate([parent_high[:split]] * 4)
        for i in range(1, 4):
            for k in range(split):
                half = 0.5 * s[k]
                if i & 1:
                    x[i * split + k] = x[k] + half
                if i & 2:
                    y[i * split + k] = y[k] + half
        for k in range(n):
            s[k] = 0.5 * s[k]
    bounds = np.concatenate([part[0] for part in done], axis=1)
    return (*(np.ascontiguousarray(row) for row in bounds),
            np.concatenate([part[1] for part in done]))


cdef enum:
    SUB = 4             # a box's darts go into one of its SUB x SUB sub-boxes left open
    TRIES = 2           # points tried per box (against the samples near it)
    NEAR = 96           # room for the samples near one box (more: the whole box, as before)


cdef Py_ssize_t _near_samples(double x, double y, double s, double low, double high,
                              double grading, const Bins *b, const Placed *p,
                              int32_t *near) noexcept nogil:
    """The samples q on the levels of r in [(1 - L) low, (1 + L) high] whose distance to
    the box [x, x + s]^2 is within min(r(q), low) (with a margin for rounding): every
    sample that can cover part of the box for :func:`_covers` or refuse a dart in it for
    :func:`_conflicts` (query r = low). Returns their number, -1 if more than NEAR."""
    cdef Py_ssize_t level, nx, ny, jx, jy, lo_x, lo_y, hi_x, hi_y, n = 0
    cdef int32_t q
    cdef double h, reach, margin, qx, qy, dx, dy, bound, x0 = p.x0, y0 = p.y0
    for level in range(_level(low * (1.0 - grading), b), _level(high * (1.0 + grading), b) + 1):
        if b.counts[level] == 0:
            continue
        h, nx, ny = b.hs[level], b.nxs[level], b.nys[level]
        reach = min(low, 2.0 * h)
        margin = 1e-9 * (reach + s + abs(x) + abs(y))
        lo_x = _clamp((x - reach - margin - x0) / h, nx)
        lo_y = _clamp((y - reach - margin - y0) / h, ny)
        hi_x = _clamp((x + s + reach + margin - x0) / h, nx)
        hi_y = _clamp((y + s + reach + margin - y0) / h, ny)
        for jy in range(lo_y, hi_y + 1):
            for jx in range(lo_x, hi_x + 1):
                q = b.heads[b.offsets[level] + jy * nx + jx] - 1
                while q >= 0:
                    qx, qy = p.points[2 * q], p.points[2 * q + 1]
                    dx = qx - min(max(qx, x), x + s)
                    dy = qy - min(max(qy, y), y + s)
                    bound = min(p.radius[q], low) + margin
                    if dx * dx + dy * dy <= bound * bound:
                        if n == NEAR:
                            return -1
                        near[n] = q
                        n += 1
                    q = p.nxt[q]
    return n


cdef inline uint64_t _mix(uint64_t *state) noexcept nogil:
    """splitmix64: the next number of a box's own stream."""
    state[0] += 0x9E3779B97F4A7C15ULL
    cdef uint64_t z = state[0]
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL
    return z ^ (z >> 31)


cdef inline double _unit(uint64_t *state) noexcept nogil:
    """A double uniform in [0, 1) from the stream (its 53 high bits)."""
    return (_mix(state) >> 11) * (1.0 / 9007199254740992.0)


cdef int _dart_in_open_part(double *v, double grading, const Bins *b, const Placed *p,
                            const Chords *c, const Chords *region, const int8_t *sd,
                            int32_t *near, bint plain) noexcept nogil:
    """The dart of one box, ``v`` = (x, y, size, low, high, u0, u1, u2, edge), written to
    v[0], v[1]: the first of TRIES points that no sample before the throw refuses
    whatever r is in [low, high] (:func:`throw`), each uniform in one of the box's SUB x
    SUB sub-boxes that no single sample covers (:func:`_covers`, with the box's
    ``low``) picked uniformly among them; the first try by u2 (the sub-box) and u0, u1,
    the others by a stream seeded with their bits (splitmix64: per box, so the same
    whatever the threads). Returns 2 if every sub-box is covered (then so is the box: no
    dart), 1 if no try is free or the dart is outside the region, 0 if it is a
    candidate. ``plain`` (or more than NEAR samples near the box, or low <= 0): one dart
    uniform in the whole box (u0, u1), tested as in :func:`_any_sample`, as before.

    The samples near the box are gathered once (:func:`_near_samples`) and serve the
    sub-boxes' coverage and the tries' refusal test. A sample's reach over the sub-boxes
    is computed per column and row (the farthest corner's distance is separable), and its
    visibility of them is asked once for the whole box (``box_seen``), per sub-box only
    where that fails: near the drawing's holes, asked per sub-box first, it was a fifth
    of the throw's time."""
    cdef double x = v[0], y = v[1], s = v[2], low = v[3], high = v[4]
    cdef double sub = s / SUB, px = 0.0, py = 0.0, dx, dy, bound, qx, qy, a0, a1, a2
    cdef Py_ssize_t n = -1
    if not plain and low > 0.0:
        n = _near_samples(x, y, s, low, high, grading, b, p, near)
    cdef Py_ssize_t t, j
    cdef uint32_t covered = 0
    cdef int free = SUB * SUB, pick, attempt
    cdef Query query
    cdef int32_t q
    cdef uint64_t state
    cdef bint refused = True
    if n < 0:
        px, py = x + v[5] * s, y + v[6] * s
        v[0], v[1] = px, py
        if v[8] != 0.0 and not point_inside(region, sd, px, py):
            return 1
        query = Query(px, py, 0.0, low, p, c)
        return 1 if _any_sample(&query, _conflicts, _level(low * (1.0 - grading), b),
                                _level(high * (1.0 + grading), b), 0, b) else 0
    cdef double fx[SUB]
    cdef double fy[SUB]
    cdef uint32_t reach, fresh
    cdef bint clear
    for t in range(n):
        q = near[t]
        qx, qy = p.points[2 * q], p.points[2 * q + 1]
        bound = min(p.radius[q], low)
        bound = bound * bound
        for j in range(SUB):            # the sub-boxes' farthest corners, per column, row
            fx[j] = max(abs(qx - (x + j * sub)), abs(qx - (x + (j + 1) * sub)))
            fx[j] = fx[j] * fx[j]
            fy[j] = max(abs(qy - (y + j * sub)), abs(qy - (y + (j + 1) * sub)))
            fy[j] = fy[j] * fy[j]
        reach = 0
        for j in range(SUB * SUB):
            if fx[j % SUB] + fy[j // SUB] <= bound:
                reach |= 1u << j
        fresh = reach & ~covered
        if not fresh:
            continue
        clear = (c.empty
                 or c.start[chord_cell(qx, qy, c) + 1] == c.start[chord_cell(qx, qy, c)]
                 or box_seen(qx, qy, _out(c, q), x, y, s, 1e-9 * min(p.radius[q], low), c))
        for j in range(SUB * SUB):
            if (fresh >> j) & 1 and (clear or box_seen(
                    qx, qy, _out(c, q), x + (j % SUB) * sub, y + (j // SUB) * sub, sub,
                    1e-9 * min(p.radius[q], low), c)):
                covered |= 1u << j
                free -= 1
        if free == 0:
            return 2
    a0, a1, a2 = v[5], v[6], v[7]
    memcpy(&state, &v[5], sizeof(uint64_t))
    for attempt in range(TRIES):
        if attempt:
            a0, a1, a2 = _unit(&state), _unit(&state), _unit(&state)
        pick = min(<int>(a2 * free), free - 1)
        for j in range(SUB * SUB):
            if not (covered >> j) & 1:
                if pick == 0:
                    break
                pick -= 1
        px, py = x + ((j % SUB) + a0) * sub, y + ((j // SUB) + a1) * sub
        refused = False
        for t in range(n):
            q = near[t]
            qx, qy = p.points[2 * q], p.points[2 * q + 1]
            dx, dy = qx - px, qy - py
            bound = min(low, p.radius[q])
            if dx * dx + dy * dy < bound * bound and sees(px, py, -1, qx, qy, _out(c, q), c):
                refused = True
                break
        if not refused:
            break
    v[0], v[1] = px, py
    if refused or (v[8] != 0.0 and not point_inside(region, sd, px, py)):
        return 1
    return 0


def throw(tuple boxes, u, order, Field field, tuple domain, chord_bound, tuple bins, nxt,
          points, radius, Py_ssize_t count, double x0, double y0, vis, bint plain=False):
    """One dart in each box [bx, bx+size]^2 (:func:`_dart_in_open_part`: in a part of it
    no sample covers yet, by the three numbers of ``u[k]``), taken in ``order``; the
    darts in the region (boxes flagged ``edge`` are tested against ``domain``, the chord
    bundle and cell sides of ``_visibility_kernels.points_inside``) that no sample
    refuses whatever r(x) is in [low, high] of the dart's box (a sample q that the dart
    x sees with |x - q| < min(low, r(q)) <= min(r(x), r(q)): samples are only ever
    added, so :func:`insert_where_free` would refuse those darts too; testing them
    first, in parallel, spares the radius field and the sequential insertion) get r from
    ``field`` and are inserted in that order where :func:`insert_where_free` allows.
    ``boxes`` = (bx, by, size, low, high, edge); the sample arrays must have room for
    one sample per box. ``plain``: one dart uniform in each box (the first pass over
    the leaves, where no sample but the boundary's is placed yet, so the sub-boxes
    would cost without closing any). Returns the new sample count and a flag per box:
    covered by the samples before the throw (each sub-box by one visible disc within
    min(r(q), low) of its farthest corner, :func:`_covers`' rule), so closed for good."""
    bx, by, size, low, high, edge = boxes
    cdef const double[::1] x = bx, y = by, s = size, lw = low, hg = high
    cdef const uint8_t[::1] ed = edge.view(np.uint8)
    cdef const double[:, ::1] uu = u
    cdef const int64_t[::1] od = order
    cdef const int8_t[::1] sides = domain[1]
    cdef const int8_t *sd = &sides[0] if sides.shape[0] else NULL
    cdef const double[::1] cb = chord_bound
    cdef Chords region = chords_of(domain[0])
    cdef Bins b = _bins_of(bins)
    cdef Placed p = _placed_of(nxt, points, radius, x0, y0)
    cdef Chords c = chords_of(vis)
    cdef int32_t[::1] nx = nxt
    cdef double[:, ::1] pt = points
    cdef double[::1] rd = radius
    cdef double grading = field.field.grading
    cdef Py_ssize_t n = od.shape[0], kept = 0, k, t
    closed_array = np.zeros(n, np.bool_)
    if not n:
        return count, closed_array
    cdef uint8_t[::1] closed = closed_array.view(np.uint8)
    cdef int64_t[::1] spatial = _spatial_order(x, y, &b, x0, y0)
    cdef double *box = _gathered(n, 9)      # the box, u, edge in the spatial order
    if box == NULL:
        raise MemoryError()
    cdef double *v
    cdef int32_t *near
    cdef uint8_t[::1] state = np.empty(n, np.uint8)
    cdef double[:, ::1] dart = np.empty((n, 2)), dt = np.empty((n, 2))
    cdef double[::1] dh = np.empty(n)
    with nogil:
        for t in range(n):
            k = spatial[t]
            v = box + 9 * t
            v[0], v[1], v[2], v[3], v[4] = x[k], y[k], s[k], lw[k], hg[k]
            v[5], v[6], v[7], v[8] = uu[k, 0], uu[k, 1], uu[k, 2], ed[k]
    with nogil, parallel(num_threads=threads_for(n)):
        near = <int32_t *>malloc(NEAR * sizeof(int32_t))
        for t in prange(n, schedule="dynamic", chunksize=CHUNK):
            v = box + 9 * t
            if near == NULL:
                v[2] = 1.0
            else:
                v[2] = _dart_in_open_part(v, grading, &b, &p, &c, &region, sd, near, plain)
        free(near)
    with nogil:
        for t in range(n):
            k = spatial[t]
            v = box + 9 * t
            state[k] = <uint8_t>v[2]
            dart[k, 0], dart[k, 1] = v[0], v[1]
        free(box)
        for t in range(n):                  # the candidates, in order
            k = od[t]
            closed[k] = state[k] == 2
            if state[k] == 0:
                dt[kept, 0], dt[kept, 1], dh[kept] = dart[k, 0], dart[k, 1], hg[k]
                kept += 1
    if not kept:
        return count, closed_array
    cdef double[::1] kx = np.empty(kept), ky = np.empty(kept)
    for t in range(kept):
        kx[t], ky[t] = dt[t, 0], dt[t, 1]
    cdef const double[::1] r = field.at(dt[:kept], dh[:kept], _spatial_order(kx, ky, &b, x0, y0))
    cdef uint8_t[::1] out = state
    for t in prange(kept, nogil=True, schedule="dynamic", chunksize=CHUNK,
                    num_threads=threads_for(kept)):
        out[t] = not _free(dt[t, 0], dt[t, 1], r[t], grading, cb, &b, &p, &c, 0)
    cdef Py_ssize_t before = count    # the samples before the throw are known: _free against
    with nogil:                       # them above, in parallel; against the new ones here
        for t in range(kept):
            if not out[t] and _free(dt[t, 0], dt[t, 1], r[t], grading, cb, &b, &p, &c, before):
                _place(dt[t, 0], dt[t, 1], r[t], &b, nx, pt, rd, count, x0, y0)
                count += 1
    return count, closed_array


cdef int64_t[::1] _spatial_order(const double[::1] x, const double[::1] y, const Bins *b,
                                 double x0, double y0):
    """An order of the points (x, y) by rows of a coarse grid over the pyramid (about 4
    points a cell), row by row and cell by cell (a stable counting sort): queries taken
    in it meet the bins and samples of their neighbours (or the nodes of the field's
    tree), still in the cache, instead of missing it at almost every bin. The answers
    do not depend on the order."""
    return _grid_order(x, y, x0, y0, b.nxs[0] * b.hs[0], b.nys[0] * b.hs[0])


cdef int64_t[::1] _grid_order(const double[::1] x, const double[::1] y, double x0, double y0,
                              double width, double height):
    """:func:`_spatial_order` over the rectangle from (x0, y0) of ``width`` x ``height``."""
    cdef Py_ssize_t n = x.shape[0], k, cell
    cdef double side = max(2.0 * sqrt(width * height / max(n, 1)), 1e-300)
    cdef Py_ssize_t nx = min(<Py_ssize_t>(width / side) + 1, n + 1)
    cdef Py_ssize_t ny = min(<Py_ssize_t>(height / side) + 1, n + 1)
    start_array = np.zeros(nx * ny + 1, np.int64)
    order_array = np.empty(n, np.int64)
    cells_array = np.empty(n, np.int64)
    cdef int64_t[::1] start = start_array, order = order_array, cells = cells_array
    with nogil:
        for k in range(n):
            cell = _clamp((y[k] - y0) / side, ny) * nx + _clamp((x[k] - x0) / side, nx)
            cells[k] = cell
            start[cell + 1] += 1
        for cell in range(nx * ny):
            start[cell + 1] += start[cell]
        for k in range(n):
            order[start[cells[k]]] = k
            start[cells[k]] += 1
    return order


cdef bint _box_covered(double x_lo, double y_lo, double s, double low, double high,
                       double grading, Py_ssize_t since, const Bins *b, const Placed *p,
                       const Chords *c) noexcept nogil:
    """Does one sample q numbered ``since`` or later cover the box (see
    :func:`uncovered_boxes`)? Such a q is within ``low`` of every corner of the box, where
    r lies in [low, high], so r(q) lies in [(1 - L) low, high + L low]: that picks the
    levels."""
    cdef Query query = Query(x_lo, y_lo, s, low, p, c)
    return _any_sample(&query, _covers, _level((1.0 - grading) * low, b),
                       _level(high + grading * low, b), since, b, True)


cdef void _uncovered(const double[::1] x, const double[::1] y, const double[::1] s,
                     const double[::1] lw, const double[::1] hg, double grading,
                     const double[::1] cb, Py_ssize_t since, const Bins *b, const Placed *p,
                     const Chords *c, const int64_t[::1] order, uint8_t[::1] keep) noexcept nogil:
    """:func:`uncovered_boxes` into ``keep``, the boxes taken in ``order``.

    The boxes' values are first gathered in that order (:func:`_gathered`): read in place
    they were a third of this loop's time on the 373-hole drawing (perf)."""
    cdef Py_ssize_t n = x.shape[0], k, t
    cdef double *box = _gathered(n, 5)
    cdef double *v
    if box == NULL:
        for t in prange(n, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(n)):
            k = order[t]
            keep[k] = lw[k] <= 0.0 or not (
                _box_covered(x[k], y[k], s[k], lw[k], hg[k], grading, since, b, p, c)
                or (since == 0 and _box_in_lens(x[k], y[k], s[k], lw[k], hg[k], grading, cb,
                                                c)))
        return
    for t in range(n):
        k = order[t]
        box[5 * t], box[5 * t + 1], box[5 * t + 2] = x[k], y[k], s[k]
        box[5 * t + 3], box[5 * t + 4] = lw[k], hg[k]
    for t in prange(n, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(n)):
        v = box + 5 * t
        keep[order[t]] = v[3] <= 0.0 or not (
            _box_covered(v[0], v[1], v[2], v[3], v[4], grading, since, b, p, c)
            or (since == 0 and _box_in_lens(v[0], v[1], v[2], v[3], v[4], grading, cb, c)))
    free(box)


def uncovered_boxes(bx, by, size, low, high, double grading, chord_bound, tuple bins, nxt,
                    points, radius, double x0, double y0, vis, Py_ssize_t since=0):
    """True for boxes [bx, bx+size]² that no single sample q covers and that are not in
    a chord's lens (:func:`_box_in_lens`): covering needs the box's farthest corner
    within min(r(q), low) and q to see all of the box that lies in the region (``low``
    and ``high`` bound r on the box). With ``since`` > 0 the boxes are ones found open
    before sample ``since`` was placed: only the later samples are tested, and not the
    lenses (a box's lens test does not depend on the samples)."""
    cdef const double[::1] x = bx, y = by, s = size, lw = low, hg = high, cb = chord_bound
    cdef Bins b = _bins_of(bins)
    cdef Placed p = _placed_of(nxt, points, radius, x0, y0)
    cdef Chords c = chords_of(vis)
    keep_array = np.empty(x.shape[0], np.bool_)
    cdef uint8_t[::1] keep = keep_array.view(np.uint8)
    cdef int64_t[::1] order = _spatial_order(x, y, &b, x0, y0)
    with nogil:
        _uncovered(x, y, s, lw, hg, grading, cb, since, &b, &p, &c, order, keep)
    return keep_array


def split_open(tuple boxes, Py_ssize_t since, double resolution, Py_ssize_t max_boxes,
               Field field, tuple domain, chord_bound, tuple bins, nxt, points, radius,
               double x0, double y0, vis):
    """One refinement level: of ``boxes`` = (bx, by, size, low, high, edge), found open
    before sample ``since``, those still open (:func:`uncovered_boxes`) and at least
    ``resolution`` x low in size are split in four; the quarters (lower left ones of all
    boxes first, then lower right, upper left, upper right) that may reach into the
    region (edge quarters tested by ``_visibility_kernels.box_state`` against
    ``domain``), with r at their centres from ``field`` and its bounds
    r -+ L x half-diagonal on each, are returned if open (:func:`uncovered_boxes`).
    If there would be more than ``max_boxes`` quarters, their number instead."""
    bx, by, size, low, high, edge = boxes
    cdef const double[::1] x = bx, y = by, s = size, lw = low, hg = high, cb = chord_bound
    cdef const uint8_t[::1] ed = edge.view(np.uint8)
    cdef const int8_t[::1] sides = domain[1]
    cdef const int8_t *sd = &sides[0] if sides.shape[0] else NULL
    cdef Chords region = chords_of(domain[0])
    cdef Bins b = _bins_of(bins)
    cdef Placed p = _placed_of(nxt, points, radius, x0, y0)
    cdef Chords c = chords_of(vis)
    cdef double grading = field.field.grading, half, spread
    cdef double slope = 0.0 if field.constant else grading   # r's spread over a box
    cdef Py_ssize_t n = x.shape[0], m = 0, k, i, q, kept = 0
    open_array = np.empty(n, np.bool_)
    cdef uint8_t[::1] still = open_array.view(np.uint8)
    cdef int64_t[::1] order = _spatial_order(x, y, &b, x0, y0)
    with nogil:
        _uncovered(x, y, s, lw, hg, grading, cb, since, &b, &p, &c, order, still)
    cdef double[::1] fx = np.empty(n), fy = np.empty(n), fs = np.empty(n), fh = np.empty(n)
    cdef uint8_t[::1] fe = np.empty(n, np.uint8)
    with nogil:
        for k in range(n):
            if still[k] and s[k] >= resolution * lw[k]:
                fx[m], fy[m], fs[m], fh[m], fe[m] = x[k], y[k], s[k], hg[k], ed[k]
                m += 1
    if 4 * m > max_boxes:
        return 4 * m
    cdef const double[::1] r = field.at_quarters(fx[:m], fy[:m], fs[:m], fh[:m],
                                                 _spatial_order(fx[:m], fy[:m], &b, x0, y0))
    children = np.empty((5, 4 * m))
    cdef double[:, ::1] ch = children
    edges = np.empty(4 * m, np.bool_)
    cdef uint8_t[::1] ce = edges.view(np.uint8)
    cdef int8_t[::1] states = np.empty(4 * m, np.int8)
    for q in prange(4 * m, nogil=True, schedule="dynamic", chunksize=CHUNK,
                    num_threads=threads_for(4 * m)):
        i = q % m
        half = 0.5 * fs[i]
        ch[0, q] = fx[i] + half if (q // m) & 1 else fx[i]
        ch[1, q] = fy[i] + half if (q // m) & 2 else fy[i]
        states[q] = box_state(&region, sd, ch[0, q], ch[1, q], half) if fe[i] else 2
    cdef int64_t *stack
    cdef double *bound
    with nogil:
        stack = <int64_t *>malloc(CONE_STACK * sizeof(int64_t))
        bound = <double *>malloc(CONE_STACK * sizeof(double))
        for q in range(4 * m):             # the quarters in the region, in order
            if states[q] == 0:
                continue
            i = q % m
            half = 0.5 * fs[i]
            spread = slope * (half / SQRT2)
            ch[0, kept], ch[1, kept], ch[2, kept] = ch[0, q], ch[1, q], half
            ch[3, kept] = field.low_on_box(ch[0, q] + 0.5 * half, ch[1, q] + 0.5 * half, r[q],
                                           spread, stack, bound)
            ch[4, kept] = r[q] + spread
            ce[kept] = fe[i] and states[q] != 2
            kept += 1
        free(bound)
        free(stack)
    cx, cy, cs, cl, chh = (np.ascontiguousarray(children[a, :kept]) for a in range(5))
    keep_array = uncovered_boxes(cx, cy, cs, cl, chh, grading, chord_bound, bins, nxt, points,
                                 radius, x0, y0, vis)
    return (cx[keep_array], cy[keep_array], cs[keep_array], cl[keep_array],
            chh[keep_array], edges[:kept][keep_array])
