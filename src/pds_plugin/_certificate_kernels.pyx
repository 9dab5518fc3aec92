# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of the certificate: closest pairs, empty circles and the distance to
the samples along the boundary, all on one grid of the samples.

The grid is ``bin_points``' (``_complex_kernels``): the samples sorted into square cells
of side ``h`` from ``(x0, y0)``, ``nx`` by ``ny``, cell ``c`` holding the binned points
``start[c]:start[c+1]``. A point's cell is ``min(int((x - x0) / h), nx - 1)`` (likewise
in y), so two points closer than ``h`` are in the same or adjacent cells.

Squared distances are ``dx * dx + dy * dy`` (the mesh's edge lengths are the square
roots of the same sums). Conventions of the kernel modules: see ``_parallel.pyx``.
"""

import numpy as np

from cython.parallel cimport parallel, prange
from libc.math cimport INFINITY, floor, sqrt
from libc.stdlib cimport free, malloc
from libc.stdint cimport int64_t

from ._parallel cimport threads_for

cdef enum:
    CHUNK = 256     # iterations a thread takes at a time


cdef inline Py_ssize_t _cell_index(double value, double low, double h, Py_ssize_t count) noexcept nogil:
    """The cell row or column holding ``value``, clamped to [-1, count]: -1 and count
    stand for 'before the first' and 'after the last'."""
    cdef double at = floor((value - low) / h)
    if at < -1.0:
        return -1
    if at > <double>count:
        return count
    return <Py_ssize_t>at


cdef double _nearest_later(const double[:, ::1] b, const int64_t[::1] st, Py_ssize_t p,
                           Py_ssize_t cx, Py_ssize_t cy, Py_ssize_t nx, Py_ssize_t ny,
                           int64_t *which) noexcept nogil:
    """The squared distance from binned point p (in cell cx, cy) to the nearest point
    after it in its cell or in the four following neighbour cells (east, and the three
    to the north), and that point in ``which``: every adjacent pair once."""
    cdef double best = INFINITY, dx, dy, d2
    cdef Py_ssize_t k, q, gx, gy, c, first
    which[0] = -1
    for k in range(5):
        if k == 0:
            gx, gy = cx, cy
        elif k == 1:
            gx, gy = cx + 1, cy
        else:
            gx, gy = cx + k - 3, cy + 1
        if gx < 0 or gx >= nx or gy >= ny:
            continue
        c = gy * nx + gx
        first = p + 1 if k == 0 else st[c]
        for q in range(first, st[c + 1]):
            dx = b[q, 0] - b[p, 0]
            dy = b[q, 1] - b[p, 1]
            d2 = dx * dx + dy * dy
            if d2 < best:
                best = d2
                which[0] = q
    return best


def closest_pair(binned, start, Py_ssize_t nx, Py_ssize_t ny):
    """The closest pair of binned points among those in the same or adjacent cells:
    positions ``(p, q)`` in binned order and their squared distance, or ``(-1, -1, inf)``
    when no two points share or neighbour a cell. Every pair closer than the cell side is
    such a pair, so a result below the side is the closest pair of all. Ties go to the
    smallest ``p``: the result does not depend on the thread count."""
    cdef const double[:, ::1] b = binned
    cdef const int64_t[::1] st = start
    cdef Py_ssize_t n = b.shape[0], cells = nx * ny, c, p, best_p = -1
    best_array = np.empty(n)
    other_array = np.empty(n, np.int64)
    cdef double[::1] best = best_array
    cdef int64_t[::1] other = other_array
    for c in prange(cells, nogil=True, schedule="dynamic", chunksize=CHUNK,
                    num_threads=threads_for(n)):
        for p in range(st[c], st[c + 1]):
            best[p] = _nearest_later(b, st, p, c % nx, c // nx, nx, ny, &other[p])
    cdef double shortest = INFINITY
    with nogil:
        for p in range(n):
            if best[p] < shortest:
                shortest, best_p = best[p], p
    if best_p < 0:
        return -1, -1, INFINITY
    return best_p, other[best_p], shortest


cdef Py_ssize_t _pairs_of_cell(const double[:, ::1] b, const int64_t[::1] st, Py_ssize_t c,
                               Py_ssize_t nx, Py_ssize_t ny, Py_ssize_t reach, double limit2,
                               int64_t[:, ::1] out, Py_ssize_t at, bint fill) noexcept nogil:
    """Count (and with ``fill`` write from row ``at`` of ``out``) the pairs (p, q), p in
    cell c, q after p in c or in a following cell at most ``reach`` cells away in x and y,
    whose squared distance is at most ``limit2``."""
    cdef Py_ssize_t cx = c % nx, cy = c // nx, gx, gy, g, p, q, found = 0
    cdef double dx, dy
    for p in range(st[c], st[c + 1]):
        for gy in range(cy, min(cy + reach + 1, ny)):
            for gx in range(max(cx - reach, 0), min(cx + reach + 1, nx)):
                if gy == cy and gx < cx:
                    continue
                g = gy * nx + gx
                for q in range(p + 1 if g == c else st[g], st[g + 1]):
                    dx = b[q, 0] - b[p, 0]
                    dy = b[q, 1] - b[p, 1]
                    if dx * dx + dy * dy <= limit2:
                        if fill:
                            out[at + found, 0] = p
                            out[at + found, 1] = q
                        found += 1
    return found


def pairs_within(binned, start, Py_ssize_t nx, Py_ssize_t ny, double h, double limit):
    """Every pair of binned points at most ``limit`` apart (squared distance at most
    ``limit**2``), as (P, 2) positions in binned order, each pair once, cell by cell."""
    cdef const double[:, ::1] b = binned
    cdef const int64_t[::1] st = start
    cdef Py_ssize_t cells = nx * ny, c
    cdef Py_ssize_t reach = <Py_ssize_t>(limit / h) + 1
    cdef double limit2 = limit * limit
    counts_array = np.zeros(cells + 1, np.int64)
    cdef int64_t[::1] counts = counts_array
    cdef int64_t[:, ::1] none = np.empty((0, 2), np.int64)
    for c in prange(cells, nogil=True, schedule="dynamic", chunksize=CHUNK,
                    num_threads=threads_for(b.shape[0])):
        counts[c + 1] = _pairs_of_cell(b, st, c, nx, ny, reach, limit2, none, 0, False)
    np.cumsum(counts_array, out=counts_array)
    out_array = np.empty((counts[cells], 2), np.int64)
    cdef int64_t[:, ::1] out = out_array
    for c in prange(cells, nogil=True, schedule="dynamic", chunksize=CHUNK,
                    num_threads=threads_for(b.shape[0])):
        _pairs_of_cell(b, st, c, nx, ny, reach, limit2, out, counts[c], True)
    return out_array


def sample_within(centre, radius, binned, start, double x0, double y0, double h,
                  Py_ssize_t nx, Py_ssize_t ny):
    """For each circle, whether a binned point lies closer than ``radius`` to its
    ``centre`` (``sqrt(dx * dx + dy * dy) < radius``), as a bool array."""
    cdef const double[:, :] ct = np.asarray(centre, dtype=np.float64)
    cdef const double[:] rd = np.asarray(radius, dtype=np.float64)
    cdef const double[:, ::1] b = binned
    cdef const int64_t[::1] st = start
    cdef Py_ssize_t m = ct.shape[0], f, gx, gy, g, q, x_lo, x_hi, y_lo, y_hi
    cdef double dx, dy
    found_array = np.zeros(m, np.uint8)
    cdef unsigned char[::1] found = found_array
    for f in prange(m, nogil=True, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(m)):
        x_lo = max(_cell_index(ct[f, 0] - rd[f], x0, h, nx), 0)
        x_hi = min(_cell_index(ct[f, 0] + rd[f], x0, h, nx), nx - 1)
        y_lo = max(_cell_index(ct[f, 1] - rd[f], y0, h, ny), 0)
        y_hi = min(_cell_index(ct[f, 1] + rd[f], y0, h, ny), ny - 1)
        for gy in range(y_lo, y_hi + 1):
            for gx in range(x_lo, x_hi + 1):
                g = gy * nx + gx
                for q in range(st[g], st[g + 1]):
                    dx = b[q, 0] - ct[f, 0]
                    dy = b[q, 1] - ct[f, 1]
                    if sqrt(dx * dx + dy * dy) < rd[f]:
                        found[f] = 1
                        break
                if found[f]:
                    break
            if found[f]:
                break
    return found_array.view(bool)


cdef double _nearest2(double x, const double *t, const double *c, Py_ssize_t k) noexcept nogil:
    """Squared distance from the point at x to the nearest sample (t_i, c_i), i < k."""
    cdef double nearest = INFINITY
    cdef Py_ssize_t i
    for i in range(k):
        nearest = min(nearest, x * x - 2.0 * x * t[i] + c[i])
    return nearest


cdef Py_ssize_t _candidates(double mx, double my, double r, const double[:, ::1] b,
                            const int64_t[::1] order, const int64_t[::1] st, double x0,
                            double y0, double h, Py_ssize_t nx, Py_ssize_t ny,
                            int64_t *found) noexcept nogil:
    """The samples at most r from (mx, my), as input indices in increasing order."""
    cdef Py_ssize_t x_lo = max(_cell_index(mx - r, x0, h, nx), 0)
    cdef Py_ssize_t x_hi = min(_cell_index(mx + r, x0, h, nx), nx - 1)
    cdef Py_ssize_t y_lo = max(_cell_index(my - r, y0, h, ny), 0)
    cdef Py_ssize_t y_hi = min(_cell_index(my + r, y0, h, ny), ny - 1)
    cdef Py_ssize_t k = 0, gx, gy, g, q, a
    cdef int64_t index
    cdef double dx, dy
    for gy in range(y_lo, y_hi + 1):
        for gx in range(x_lo, x_hi + 1):
            g = gy * nx + gx
            for q in range(st[g], st[g + 1]):
                dx = b[q, 0] - mx
                dy = b[q, 1] - my
                if dx * dx + dy * dy <= r * r:
                    index = order[q]            # insertion sort: the lists are short
                    a = k
                    while a > 0 and found[a - 1] > index:
                        found[a] = found[a - 1]
                        a -= 1
                    found[a] = index
                    k += 1
    return k


def boundary_gaps(start, direction, length, reach, points, order, binned, cell_start,
                  double x0, double y0, double h, Py_ssize_t nx, Py_ssize_t ny,
                  Py_ssize_t most):
    """For each boundary piece ``start + t * direction``, t in [0, length], the largest
    distance to the nearest of the samples within ``0.5 * length + reach`` of its middle
    (found on the grid; at most ``most`` of them), and the t where it occurs; inf for a
    piece without such samples.

    Along a line the squared distance to sample i is (t - t_i)² + h_i², so the nearest
    distance is a lower envelope of parabolas whose maxima lie at the piece's ends or
    where two parabolas cross: t = (t_j² + h_j² - t_i² - h_i²) / (2 (t_j - t_i)).
    """
    cdef const double[:, :] st = np.asarray(start, dtype=np.float64)
    cdef const double[:, :] dr = np.asarray(direction, dtype=np.float64)
    cdef const double[:] ln = np.asarray(length, dtype=np.float64)
    cdef const double[:, ::1] pt = points
    cdef const int64_t[::1] od = order
    cdef const double[:, ::1] b = binned
    cdef const int64_t[::1] cs = cell_start
    cdef Py_ssize_t n = st.shape[0], p, a, q, k
    gap_array, where_array = np.zeros(n), np.zeros(n)
    cdef double[::1] gap = gap_array, where = where_array
    cdef double r = reach, dx, dy, best, best_t, at_end, x, crossing
    cdef int64_t *cand
    cdef double *t
    cdef double *c
    with nogil, parallel(num_threads=threads_for(n)):
        cand = <int64_t *>malloc(most * sizeof(int64_t))
        t = <double *>malloc(most * sizeof(double))
        c = <double *>malloc(most * sizeof(double))       # c: t_i² + h_i² = |sample - start|²
        for p in prange(n, schedule="dynamic", chunksize=CHUNK):
            k = _candidates(st[p, 0] + 0.5 * ln[p] * dr[p, 0], st[p, 1] + 0.5 * ln[p] * dr[p, 1],
                            0.5 * ln[p] + r, b, od, cs, x0, y0, h, nx, ny, cand)
            if k == 0:
                gap[p] = INFINITY
                where[p] = 0.0
                continue
            for a in range(k):
                dx = pt[cand[a], 0] - st[p, 0]
                dy = pt[cand[a], 1] - st[p, 1]
                t[a] = dx * dr[p, 0] + dy * dr[p, 1]
                c[a] = dx * dx + dy * dy
            best, best_t = _nearest2(0.0, t, c, k), 0.0
            at_end = _nearest2(ln[p], t, c, k)
            if at_end > best:
                best, best_t = at_end, ln[p]
            for a in range(k):
                for q in range(a + 1, k):
                    if t[a] == t[q]:
                        continue
                    x = (c[q] - c[a]) / (2.0 * (t[q] - t[a]))
                    if 0.0 < x < ln[p]:
                        crossing = _nearest2(x, t, c, k)
                        if crossing > best:
                            best, best_t = crossing, x
            gap[p] = sqrt(max(best, 0.0))
            where[p] = best_t
        free(cand)
        free(t)
        free(c)
    return gap_array, where_array


cdef inline double _point_segment(double px, double py, double ax, double ay, double bx,
                                  double by) noexcept nogil:
    """Distance from p to the segment ab, computed as GEOS does (Distance::pointToSegment),
    so that it equals shapely's distance bit for bit."""
    cdef double len2, r, s, dx, dy
    if ax == bx and ay == by:
        dx, dy = px - ax, py - ay
        return sqrt(dx * dx + dy * dy)
    len2 = (bx - ax) * (bx - ax) + (by - ay) * (by - ay)
    r = ((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / len2
    if r <= 0.0:
        dx, dy = px - ax, py - ay
        return sqrt(dx * dx + dy * dy)
    if r >= 1.0:
        dx, dy = px - bx, py - by
        return sqrt(dx * dx + dy * dy)
    s = ((ay - py) * (bx - ax) - (ax - px) * (by - ay)) / len2
    return abs(s) * sqrt(len2)


cdef void _bin_segment(const double[:, :, :] sg, Py_ssize_t s, double x0, double y0,
                       double h, Py_ssize_t nx, Py_ssize_t ny, int64_t[::1] fill,
                       int64_t[::1] entry, bint write) noexcept nogil:
    """Count (or with ``write`` file) segment s in every cell its pieces of length <= h
    touch, each piece's box widened by 1e-9 h against rounding."""
    cdef double ax = sg[s, 0, 0], ay = sg[s, 0, 1], bx = sg[s, 1, 0], by = sg[s, 1, 1]
    cdef double length = sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay))
    cdef Py_ssize_t pieces = <Py_ssize_t>(length / h) + 1, k, gx, gy
    cdef double u0, u1, px0, py0, px1, py1, pad = 1e-9 * h
    for k in range(pieces):
        u0, u1 = <double>k / pieces, <double>(k + 1) / pieces
        px0, px1 = ax + u0 * (bx - ax), ax + u1 * (bx - ax)
        py0, py1 = ay + u0 * (by - ay), ay + u1 * (by - ay)
        for gy in range(max(_cell_index(min(py0, py1) - pad, y0, h, ny), 0),
                        min(_cell_index(max(py0, py1) + pad, y0, h, ny), ny - 1) + 1):
            for gx in range(max(_cell_index(min(px0, px1) - pad, x0, h, nx), 0),
                            min(_cell_index(max(px0, px1) + pad, x0, h, nx), nx - 1) + 1):
                if write:
                    entry[fill[gy * nx + gx]] = s
                    fill[gy * nx + gx] += 1
                else:
                    fill[gy * nx + gx + 1] += 1


def segment_distances(points, segments, double h, Py_ssize_t rings):
    """Distance from each point to the nearest of the (K, 2, 2) ``segments``, equal bit
    for bit to shapely's (GEOS) point-to-segment distance, and the index of that segment
    (the first found at that distance); NaN and -1 for a point whose nearest segment is
    not settled within ``rings`` rings of cells around it.

    The segments are filed in square cells of side ``h`` (or larger, at most about four
    cells per segment); each point searches ring after ring of cells around its own until
    no segment in a farther ring can be nearer.
    """
    cdef const double[:, :] pt = np.asarray(points, dtype=np.float64)
    cdef const double[:, :, :] sg = np.asarray(segments, dtype=np.float64)
    cdef Py_ssize_t m = pt.shape[0], k = sg.shape[0], s, f, c, ring, gx, gy, e, cx, cy
    distance_array = np.full(m, np.nan)
    nearest_array = np.full(m, -1, np.int64)
    if k == 0 or m == 0:
        return distance_array, nearest_array
    flat = np.asarray(segments, dtype=np.float64).reshape(-1, 2)
    low, high = flat.min(axis=0), flat.max(axis=0)
    span = high - low
    h = max(h, float(np.sqrt(span[0] * span[1] / (4 * k))), float(span.max()) / (4 * k))
    cdef double x0 = low[0], y0 = low[1]
    cdef Py_ssize_t nx = int(span[0] / h) + 1, ny = int(span[1] / h) + 1
    start_array = np.zeros(nx * ny + 1, np.int64)
    cdef int64_t[::1] start = start_array
    cdef int64_t[::1] none = np.empty(0, np.int64)
    with nogil:
        for s in range(k):
            _bin_segment(sg, s, x0, y0, h, nx, ny, start, none, False)
    np.cumsum(start_array, out=start_array)
    entry_array = np.empty(start[nx * ny], np.int64)
    cdef int64_t[::1] entry = entry_array
    cdef int64_t[::1] fill = start_array[:nx * ny].copy()
    with nogil:
        for s in range(k):
            _bin_segment(sg, s, x0, y0, h, nx, ny, fill, entry, True)
    cdef double[::1] distance = distance_array
    cdef int64_t[::1] nearest = nearest_array
    cdef double best, d
    cdef int64_t best_segment
    for f in prange(m, nogil=True, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(m)):
        cx = min(max(_cell_index(pt[f, 0], x0, h, nx), 0), nx - 1)
        cy = min(max(_cell_index(pt[f, 1], y0, h, ny), 0), ny - 1)
        best = INFINITY
        best_segment = -1
        for ring in range(rings + 1):
            for gy in range(max(cy - ring, 0), min(cy + ring, ny - 1) + 1):
                for gx in range(max(cx - ring, 0), min(cx + ring, nx - 1) + 1):
                    if gy != cy - ring and gy != cy + ring and gx != cx - ring and gx != cx + ring:
                        continue                        # inside the ring: searched already
                    c = gy * nx + gx
                    for e in range(start[c], start[c + 1]):
                        d = _point_segment(pt[f, 0], pt[f, 1], sg[entry[e], 0, 0],
                                           sg[entry[e], 0, 1], sg[entry[e], 1, 0],
                                           sg[entry[e], 1, 1])
                        if d < best:
                            best = d
                            best_segment = entry[e]
            if best <= (ring - 1e-6) * h or (ring >= cx and ring >= cy and ring >= nx - 1 - cx
                                             and ring >= ny - 1 - cy):
                distance[f] = best                  # no farther cell holds a nearer segment
                nearest[f] = best_segment
                break
    return distance_array, nearest_array


def signed_areas(points, faces):
    """Signed area of each triangle of ``faces`` (M, 3) over ``points`` (N, 2): with
    ``u = b - a`` and ``v = c - a``, ``(u_x * v_y - u_y * v_x) / 2``, positive for a
    counter-clockwise triangle; the faces' indices must lie in [0, N)."""
    cdef const double[:, ::1] pt = np.ascontiguousarray(points, dtype=np.float64)
    cdef const int64_t[:, ::1] fc = np.ascontiguousarray(faces, dtype=np.int64)
    cdef Py_ssize_t m = fc.shape[0], f
    area_array = np.empty(m)
    cdef double[::1] area = area_array
    cdef double ux, uy, vx, vy
    for f in prange(m, nogil=True, schedule="static", num_threads=threads_for(m)):
        ux = pt[fc[f, 1], 0] - pt[fc[f, 0], 0]
        uy = pt[fc[f, 1], 1] - pt[fc[f, 0], 1]
        vx = pt[fc[f, 2], 0] - pt[fc[f, 0], 0]
        vy = pt[fc[f, 2], 1] - pt[fc[f, 0], 1]
        area[f] = (ux * vy - uy * vx) / 2
    return area_array
