"""Numba kernel of the coverage certificate: the distance to the samples along the boundary."""

import numpy as np
from numba import njit


@njit(cache=True)
def _nearest2(x, t, c):
    """Squared distance from the point at x to the nearest sample (t_i, c_i)."""
    nearest = np.inf
    for i in range(t.shape[0]):
        nearest = min(nearest, x * x - 2.0 * x * t[i] + c[i])
    return nearest


@njit(cache=True)
def boundary_gaps(start, direction, length, cand_start, cand, points):
    """For each boundary piece ``start + t * direction``, t in [0, length], the largest
    distance to the nearest of its candidate samples ``cand[cand_start[p]:cand_start[p+1]]``
    and the t where it occurs.

    Along a line the squared distance to sample i is (t - t_i)² + h_i², so the nearest
    distance is a lower envelope of parabolas whose maxima lie at the piece's ends or
    where two parabolas cross: t = (t_j² + h_j² - t_i² - h_i²) / (2 (t_j - t_i)).
    """
    n = start.shape[0]
    gap = np.zeros(n)
    where = np.zeros(n)
    for p in range(n):
        lo, hi = cand_start[p], cand_start[p + 1]
        k = hi - lo
        if k == 0:
            gap[p] = np.inf
            continue
        t = np.empty(k)
        c = np.empty(k)               # t_i² + h_i² = |sample - start|²
        for a in range(k):
            dx = points[cand[lo + a], 0] - start[p, 0]
            dy = points[cand[lo + a], 1] - start[p, 1]
            t[a] = dx * direction[p, 0] + dy * direction[p, 1]
            c[a] = dx * dx + dy * dy
        best, best_t = _nearest2(0.0, t, c), 0.0
        at_end = _nearest2(length[p], t, c)
        if at_end > best:
            best, best_t = at_end, length[p]
        for a in range(k):
            for b in range(a + 1, k):
                if t[a] == t[b]:
                    continue
                x = (c[b] - c[a]) / (2.0 * (t[b] - t[a]))
                if 0.0 < x < length[p]:
                    crossing = _nearest2(x, t, c)
                    if crossing > best:
                        best, best_t = crossing, x
        gap[p] = np.sqrt(max(best, 0.0))
        where[p] = best_t
    return gap, where
