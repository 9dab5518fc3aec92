# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernel of the coverage certificate: the distance to the samples along the boundary.

Conventions of the kernel modules: see ``_parallel.pyx``.
"""

import numpy as np

from libc.math cimport INFINITY, sqrt
from libc.stdint cimport int64_t


cdef double _nearest2(double x, const double[::1] t, const double[::1] c, Py_ssize_t k) noexcept nogil:
    """Squared distance from the point at x to the nearest sample (t_i, c_i), i < k."""
    cdef double nearest = INFINITY
    cdef Py_ssize_t i
    for i in range(k):
        nearest = min(nearest, x * x - 2.0 * x * t[i] + c[i])
    return nearest


def boundary_gaps(start, direction, length, cand_start, cand, points):
    """For each boundary piece ``start + t * direction``, t in [0, length], the largest
    distance to the nearest of its candidate samples ``cand[cand_start[p]:cand_start[p+1]]``
    and the t where it occurs.

    Along a line the squared distance to sample i is (t - t_i)² + h_i², so the nearest
    distance is a lower envelope of parabolas whose maxima lie at the piece's ends or
    where two parabolas cross: t = (t_j² + h_j² - t_i² - h_i²) / (2 (t_j - t_i)).
    """
    cdef const double[:, :] st = np.asarray(start, dtype=np.float64)
    cdef const double[:, :] dr = np.asarray(direction, dtype=np.float64)
    cdef const double[:] ln = np.asarray(length, dtype=np.float64)
    cdef const int64_t[:] cs = np.asarray(cand_start, dtype=np.int64)
    cdef const int64_t[:] cd = np.asarray(cand, dtype=np.int64)
    cdef const double[:, :] pt = np.asarray(points, dtype=np.float64)
    cdef Py_ssize_t n = st.shape[0], p, a, b, lo, hi, k, most = 0
    for p in range(n):
        most = max(most, cs[p + 1] - cs[p])
    gap_array, where_array = np.zeros(n), np.zeros(n)
    cdef double[::1] gap = gap_array, where = where_array
    cdef double[::1] t = np.empty(most), c = np.empty(most)    # c: t_i² + h_i² = |sample - start|²
    cdef double dx, dy, best, best_t, at_end, x, crossing
    with nogil:
        for p in range(n):
            lo, hi = cs[p], cs[p + 1]
            k = hi - lo
            if k == 0:
                gap[p] = INFINITY
                continue
            for a in range(k):
                dx = pt[cd[lo + a], 0] - st[p, 0]
                dy = pt[cd[lo + a], 1] - st[p, 1]
                t[a] = dx * dr[p, 0] + dy * dr[p, 1]
                c[a] = dx * dx + dy * dy
            best, best_t = _nearest2(0.0, t, c, k), 0.0
            at_end = _nearest2(ln[p], t, c, k)
            if at_end > best:
                best, best_t = at_end, ln[p]
            for a in range(k):
                for b in range(a + 1, k):
                    if t[a] == t[b]:
                        continue
                    x = (c[b] - c[a]) / (2.0 * (t[b] - t[a]))
                    if 0.0 < x < ln[p]:
                        crossing = _nearest2(x, t, c, k)
                        if crossing > best:
                            best, best_t = crossing, x
            gap[p] = sqrt(max(best, 0.0))
            where[p] = best_t
    return gap_array, where_array
