# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of the radius field of graded meshes (sizing.py):
``min(cap, min_i(s_i + L |x - f_i|))`` over feature points f_i with sizes s_i, exactly,
by a depth-first search of a k-d tree of the features that prunes the nodes whose lower
bound ``min s + L · distance to the node's box`` cannot beat the best value so far.

Conventions of the kernel modules: see ``_parallel.pyx``.
"""

import numpy as np

from cython.parallel cimport parallel, prange
from libc.math cimport INFINITY, sqrt
from libc.stdlib cimport free, malloc
from libc.stdint cimport int64_t, uint8_t

from ._parallel cimport threads_for

cdef enum:
    CHUNK = 256     # iterations a thread takes at a time
    STACK = CONE_STACK


def build_cone_tree(xy, s, Py_ssize_t leaf_size):
    """A k-d tree over the feature points ``xy`` for min_i(s_i + L|x - f_i|): returns
    (perm, first, stop, left, right, box, smin); node k holds features
    perm[first[k]:stop[k]] inside ``box[k]`` = (xmin, ymin, xmax, ymax), the smallest
    s of which is ``smin[k]``; leaves have left[k] = -1. Nodes split at the median of
    their wider side (a deterministic selection: the tree depends on the input only)."""
    xy = np.ascontiguousarray(xy, dtype=np.float64)
    s = np.ascontiguousarray(s, dtype=np.float64)
    cdef Py_ssize_t n = xy.shape[0], cap = 8 * (n // max(leaf_size, 1) + 1) + 1
    perm_array = np.arange(n, dtype=np.int64)
    first_array, stop_array = np.empty(cap, np.int64), np.empty(cap, np.int64)
    left_array, right_array = np.full(cap, -1, np.int64), np.full(cap, -1, np.int64)
    box_array, smin_array = np.empty((cap, 4)), np.empty(cap)
    todo_array = np.empty(cap, np.int64)
    cdef const double[:, ::1] p = xy
    cdef const double[::1] sz = s
    cdef int64_t[::1] perm = perm_array, first = first_array, stop = stop_array
    cdef int64_t[::1] left = left_array, right = right_array, todo = todo_array
    cdef double[:, ::1] box = box_array
    cdef double[::1] smin = smin_array
    cdef Py_ssize_t count = 1, top = 1, k, t, i, m, half
    cdef int axis
    first[0], stop[0], todo[0] = 0, n, 0
    with nogil:
        while top:
            top -= 1
            k = todo[top]
            box[k, 0] = box[k, 1] = 1e308
            box[k, 2] = box[k, 3] = -1e308
            smin[k] = 1e308
            for t in range(first[k], stop[k]):
                i = perm[t]
                box[k, 0], box[k, 1] = min(box[k, 0], p[i, 0]), min(box[k, 1], p[i, 1])
                box[k, 2], box[k, 3] = max(box[k, 2], p[i, 0]), max(box[k, 3], p[i, 1])
                smin[k] = min(smin[k], sz[i])
            m = stop[k] - first[k]
            if m <= leaf_size:
                continue
            axis = 0 if box[k, 2] - box[k, 0] >= box[k, 3] - box[k, 1] else 1
            half = first[k] + m // 2
            _select(perm, p, axis, first[k], stop[k] - 1, half)
            first[count], stop[count] = first[k], half
            first[count + 1], stop[count + 1] = half, stop[k]
            left[k], right[k] = count, count + 1
            todo[top], todo[top + 1] = count, count + 1
            top += 2
            count += 2
    return (perm_array, first_array[:count].copy(), stop_array[:count].copy(),
            left_array[:count].copy(), right_array[:count].copy(), box_array[:count].copy(),
            smin_array[:count].copy())


cdef void _select(int64_t[::1] perm, const double[:, ::1] p, int axis, Py_ssize_t lo,
                  Py_ssize_t hi, Py_ssize_t nth) noexcept nogil:
    """Reorder perm[lo..hi] so that perm[nth] holds the point whose ``axis`` coordinate
    would be there sorted, the ones before it no larger and the ones after no smaller
    (Hoare's selection, median-of-three pivots: deterministic)."""
    cdef Py_ssize_t i, j, mid
    cdef double pivot, a, b, c
    cdef int64_t swap
    while hi > lo:
        mid = lo + (hi - lo) // 2
        a, b, c = p[perm[lo], axis], p[perm[mid], axis], p[perm[hi], axis]
        pivot = max(min(a, b), min(max(a, b), c))
        i, j = lo, hi
        while i <= j:
            while p[perm[i], axis] < pivot:
                i += 1
            while p[perm[j], axis] > pivot:
                j -= 1
            if i <= j:
                swap = perm[i]
                perm[i] = perm[j]
                perm[j] = swap
                i += 1
                j -= 1
        if nth <= j:
            hi = j
        elif nth >= i:
            lo = i
        else:
            return


cdef inline double _box_distance(double x, double y, const double[:, ::1] box,
                                 Py_ssize_t k) noexcept nogil:
    cdef double dx = max(box[k, 0] - x, 0.0, x - box[k, 2])
    cdef double dy = max(box[k, 1] - y, 0.0, y - box[k, 3])
    return sqrt(dx * dx + dy * dy)


cdef inline double _node_distance(double x, double y, const ConeTree *t,
                                  Py_ssize_t k) noexcept nogil:
    """:func:`_box_distance` on the struct view of the tree."""
    cdef double dx = max(t.box[4 * k] - x, 0.0, x - t.box[4 * k + 2])
    cdef double dy = max(t.box[4 * k + 1] - y, 0.0, y - t.box[4 * k + 3])
    return sqrt(dx * dx + dy * dy)


cdef inline Py_ssize_t _push_children(double x, double y, Py_ssize_t k, double L,
                                      const int64_t[::1] left, const int64_t[::1] right,
                                      const double[:, ::1] box, const double[::1] smin,
                                      int64_t *stack, Py_ssize_t top) noexcept nogil:
    """Push node k's two children on a cone search's stack, the more promising for
    (x, y) (lower smin / L + distance) on top; returns the new top."""
    cdef Py_ssize_t a = left[k], b = right[k]
    if _box_distance(x, y, box, a) + smin[a] / L < _box_distance(x, y, box, b) + smin[b] / L:
        a, b = b, a
    stack[top] = a          # the less promising child waits
    stack[top + 1] = b
    return top + 2


cdef ConeTree cone_tree_of(features, sizes, double L, double cap, tuple tree) except *:
    """The struct view of a ``build_cone_tree`` tree of ``features`` with ``sizes`` (the
    arrays must outlive it; at least one feature)."""
    cdef const double[:, ::1] f = features
    cdef const double[::1] sz = sizes
    cdef const int64_t[::1] pm = tree[0], fs = tree[1], st = tree[2], lf = tree[3], rt = tree[4]
    cdef const double[:, ::1] bx = tree[5]
    cdef const double[::1] sm = tree[6]
    return ConeTree(&f[0, 0], &sz[0], &pm[0], &fs[0], &st[0], &lf[0], &rt[0], &bx[0, 0],
                    &sm[0], L, cap)


cdef double cone_at(const ConeTree *t, double x, double y, double best, int64_t *stack,
                    double *bound) noexcept nogil:
    """min(best, min_i(s_i + L|x - f_i|)) at (x, y): a depth-first search of the tree,
    the more promising child first, pruning nodes whose bound smin + L·distance is no
    better than the best so far (``best``: cap, or any number known to be above the
    minimum, which only prunes more). Each node's bound is computed once, when it is
    pushed (``bound`` beside ``stack``); a node pruned then would be pruned when popped
    (the best only falls). A bound is never above the value of a feature in its node,
    as computed (rounding is monotone), so the node of the minimum is visited unless
    ``best`` already equals it: the value is min(best, the exact minimum) whatever is
    pruned."""
    cdef double L = t.L, dx, dy, value, bound_a, bound_b
    cdef Py_ssize_t top = 1, k, j, i, a, b
    stack[0] = 0
    bound[0] = t.smin[0] + L * _node_distance(x, y, t, 0)
    while top:
        top -= 1
        if bound[top] >= best:
            continue
        k = stack[top]
        if t.left[k] < 0:
            for j in range(t.first[k], t.stop[k]):
                i = t.perm[j]
                dx, dy = t.xy[2 * i] - x, t.xy[2 * i + 1] - y
                value = t.s[i] + L * sqrt(dx * dx + dy * dy)
                if value < best:
                    best = value
            continue
        a, b = t.left[k], t.right[k]
        bound_a = t.smin[a] + L * _node_distance(x, y, t, a)
        bound_b = t.smin[b] + L * _node_distance(x, y, t, b)
        if bound_a < bound_b:                   # the more promising child on top
            a, b = b, a
            bound_a, bound_b = bound_b, bound_a
        if bound_a < best:
            stack[top], bound[top] = a, bound_a
            top += 1
        if bound_b < best:
            stack[top], bound[top] = b, bound_b
            top += 1
    return best


def cone_minimum(queries, xy, s, double L, double cap, perm, first, stop, left, right, box,
                 smin):
    """min(cap, min_i(s_i + L|x - f_i|)) at each query point, exactly."""
    cdef const double[:, ::1] q = queries
    cdef ConeTree t = cone_tree_of(xy, s, L, cap, (perm, first, stop, left, right, box, smin))
    cdef Py_ssize_t n = q.shape[0], k
    out_array = np.empty(n)
    cdef double[::1] out = out_array
    cdef int64_t *stack
    cdef double *bound
    with nogil, parallel(num_threads=threads_for(n)):
        stack = <int64_t *>malloc(STACK * sizeof(int64_t))
        bound = <double *>malloc(STACK * sizeof(double))
        for k in prange(n, schedule="dynamic", chunksize=CHUNK):
            out[k] = cone_at(&t, q[k, 0], q[k, 1], cap, stack, bound)
        free(bound)
        free(stack)
    return out_array


def cone_minimum_pairwise(queries, xy, s, double L, double cap):
    """:func:`cone_minimum` without the tree: every cone at every query point, for a few
    of them, where building the tree costs more than the pairs; the same numbers (each
    cone computed as :func:`cone_at` computes it, and a minimum does not depend on the
    order).

    >>> cone_minimum_pairwise(np.array([[1.0, 0.0]]), np.array([[0.0, 0.0]]),
    ...                       np.array([0.1]), 0.5, 1.0).tolist()
    [0.6]
    """
    cdef const double[:, ::1] q = np.ascontiguousarray(queries, np.float64)
    cdef const double[:, ::1] f = np.ascontiguousarray(xy, np.float64)
    cdef const double[::1] sz = np.ascontiguousarray(s, np.float64)
    cdef Py_ssize_t n = q.shape[0], m = f.shape[0], k, i
    cdef double x, y, dx, dy, value, best
    out_array = np.empty(n)
    cdef double[::1] out = out_array
    with nogil:
        for k in range(n):
            x, y, best = q[k, 0], q[k, 1], cap
            for i in range(m):
                dx, dy = f[i, 0] - x, f[i, 1] - y
                value = sz[i] + L * sqrt(dx * dx + dy * dy)
                if value < best:
                    best = value
            out[k] = best
    return out_array


cdef void quarters_at(const ConeTree *t, double x_lo, double y_lo, double size, double *best,
                      int64_t *stack) noexcept nogil:
    """:func:`cone_at` at the centres of the four quarters of the box
    [x_lo, x_lo + size]² at once, into best[0..3] (lower left, lower right, upper left,
    upper right; each starts as cap or a number known to be above the minimum there),
    each centre computed as the sampler computes it. One search: a node is pruned when
    its bound is no better than the best so far for all four, so each value is the
    same as four searches give."""
    cdef double half = 0.5 * size, dx, dy, value, L = t.L, da, db
    cdef double qx[4]
    cdef double qy[4]
    cdef Py_ssize_t top = 1, k, m, i, j, a, b
    cdef bint needed
    qx[0] = x_lo + 0.5 * half
    qx[1] = (x_lo + half) + 0.5 * half
    qx[2], qx[3] = qx[0], qx[1]
    qy[0] = y_lo + 0.5 * half
    qy[2] = (y_lo + half) + 0.5 * half
    qy[1], qy[3] = qy[0], qy[2]
    stack[0] = 0
    while top:
        top -= 1
        k = stack[top]
        needed = False
        for j in range(4):
            if t.smin[k] + L * _node_distance(qx[j], qy[j], t, k) < best[j]:
                needed = True
                break
        if not needed:
            continue
        if t.left[k] < 0:
            for m in range(t.first[k], t.stop[k]):
                i = t.perm[m]
                for j in range(4):
                    dx, dy = t.xy[2 * i] - qx[j], t.xy[2 * i + 1] - qy[j]
                    value = t.s[i] + L * sqrt(dx * dx + dy * dy)
                    if value < best[j]:
                        best[j] = value
            continue
        a, b = t.left[k], t.right[k]      # the more promising child for the box's centre on top
        da = _node_distance(x_lo + half, y_lo + half, t, a) + t.smin[a] / L
        db = _node_distance(x_lo + half, y_lo + half, t, b) + t.smin[b] / L
        if da < db:
            a, b = b, a
        stack[top] = a
        stack[top + 1] = b
        top += 2


def quarter_cone_minimum(bx, by, size, xy, s, double L, double cap, perm, first, stop, left,
                         right, box, smin):
    """min(cap, min_i(s_i + L|x - f_i|)) at the centres of the quarters of each box
    [bx, bx + size] x [by, by + size], exactly: an (4 n,) array, the lower left quarters
    of the n boxes first, then the lower right, upper left and upper right ones."""
    cdef const double[::1] x = bx, y = by, sd = size
    cdef ConeTree t = cone_tree_of(xy, s, L, cap, (perm, first, stop, left, right, box, smin))
    cdef Py_ssize_t n = x.shape[0], k, j
    out_array = np.empty(4 * n)
    cdef double[::1] out = out_array
    cdef int64_t *stack
    cdef double *best
    with nogil, parallel(num_threads=threads_for(n)):
        stack = <int64_t *>malloc(STACK * sizeof(int64_t))      # one of each per thread
        best = <double *>malloc(4 * sizeof(double))
        for k in prange(n, schedule="dynamic", chunksize=CHUNK):
            for j in range(4):
                best[j] = cap
            quarters_at(&t, x[k], y[k], sd[k], best, stack)
            for j in range(4):
                out[j * n + k] = best[j]
        free(best)
        free(stack)
    return out_array


cdef bint _dominated(double x, double y, double s_i, Py_ssize_t i, const double[:, ::1] xy,
                     const double[::1] s, double L, const int64_t[::1] perm,
                     const int64_t[::1] first, const int64_t[::1] stop,
                     const int64_t[::1] left, const int64_t[::1] right,
                     const double[:, ::1] box, const double[::1] smin,
                     int64_t *stack) noexcept nogil:
    """Is the cone of size s_i at (x, y) nowhere below one of the tree's cones: s_j +
    L|(x, y) - f_j| < s_i for some j, or equal with j < i? (Then it is at least cone j
    everywhere.)
    ``i``: the cone's own number among the tree's (skipped), or -1 for a cone counted
    before all of them. A depth-first search, the more promising child first, pruning
    nodes whose smin + L·distance is above s_i; it stops at the first such j."""
    cdef double dx, dy, value
    cdef Py_ssize_t top = 1, k, t, j
    stack[0] = 0
    while top:
        top -= 1
        k = stack[top]
        if smin[k] + L * _box_distance(x, y, box, k) > s_i:
            continue
        if left[k] < 0:
            for t in range(first[k], stop[k]):
                j = perm[t]
                if j == i:
                    continue
                dx, dy = xy[j, 0] - x, xy[j, 1] - y
                value = s[j] + L * sqrt(dx * dx + dy * dy)
                if value < s_i or (value == s_i and j < i):
                    return True
            continue
        top = _push_children(x, y, k, L, left, right, box, smin, stack, top)
    return False


def dominated_cones(xy, s, double L, perm, first, stop, left, right, box, smin,
                    Py_ssize_t start=0, queries=None, query_s=None):
    """True for the cones s_i + L|x - f_i| that another cone is nowhere above
    (:func:`_dominated`), over the ``build_cone_tree`` tree of all of them: dropping
    them leaves min_i(s_i + L|x - f_i|) unchanged. Only cones ``start`` on are tested
    (the others are False). With ``queries`` and ``query_s``: for those cones instead,
    against the tree's, counted before all of them (a tie keeps the query)."""
    own = queries is None
    cdef const double[:, ::1] f = xy
    cdef const double[::1] sz = s, sm = smin
    cdef const double[:, ::1] q = xy if own else queries
    cdef const double[::1] qs = s if own else query_s
    cdef const int64_t[::1] pm = perm, fs = first, st = stop, lf = left, rt = right
    cdef const double[:, ::1] bx = box
    cdef Py_ssize_t n = q.shape[0], k
    cdef bint mine = own
    out_array = np.zeros(n, np.bool_)
    cdef uint8_t[::1] out = out_array.view(np.uint8)
    cdef int64_t *stack
    with nogil, parallel(num_threads=threads_for(n - start)):
        stack = <int64_t *>malloc(STACK * sizeof(int64_t))
        for k in prange(start, n, schedule="dynamic", chunksize=CHUNK):
            out[k] = _dominated(q[k, 0], q[k, 1], qs[k], k if mine else -1, f, sz, L, pm, fs,
                                st, lf, rt, bx, sm, stack)
        free(stack)
    return out_array


def dominated_pairwise(xy, s, double L, Py_ssize_t start=0, queries=None, query_s=None):
    """:func:`dominated_cones` without the tree: each tested cone against every cone, for
    a few cones (a remeshed patch's tens), where building the tree and searching it cost
    more than the pairs. The same answers: the search prunes only nodes whose cones cannot
    pass the test, and each pair is computed as :func:`_dominated` computes it.

    >>> xy = np.array([[0.0, 0.0], [1.0, 0.0], [5.0, 0.0]])
    >>> dominated_pairwise(xy, np.array([0.1, 0.9, 0.5]), 0.5).tolist()
    [False, True, False]
    """
    cdef bint own = queries is None
    cdef const double[:, ::1] f = np.ascontiguousarray(xy, np.float64)
    cdef const double[::1] sz = np.ascontiguousarray(s, np.float64)
    cdef const double[:, ::1] q = f if own else np.ascontiguousarray(queries, np.float64)
    cdef const double[::1] qs = sz if own else np.ascontiguousarray(query_s, np.float64)
    cdef Py_ssize_t n = q.shape[0], m = f.shape[0], k, j, i
    cdef double x, y, s_i, dx, dy, value
    out_array = np.zeros(n, np.bool_)
    cdef uint8_t[::1] out = out_array.view(np.uint8)
    with nogil:
        for k in range(start, n):
            x, y, s_i, i = q[k, 0], q[k, 1], qs[k], k if own else -1
            for j in range(m):
                if j == i:
                    continue
                dx, dy = f[j, 0] - x, f[j, 1] - y
                value = sz[j] + L * sqrt(dx * dx + dy * dy)
                if value < s_i or (value == s_i and j < i):
                    out[k] = 1
                    break
    return out_array


cdef inline bint _faces(const double[:, ::1] p, const double[:, ::1] nm, Py_ssize_t i,
                        Py_ssize_t j, double e, double opposed) noexcept nogil:
    """True if j faces i through material at distance e > 0: the step i -> j goes along
    i's inward normal and against j's, the normals opposed (dot below ``opposed``)."""
    cdef double dx = p[j, 0] - p[i, 0], dy = p[j, 1] - p[i, 1]
    return (dx * nm[i, 0] + dy * nm[i, 1] > 1e-9 * e
            and dx * nm[j, 0] + dy * nm[j, 1] < -1e-9 * e
            and nm[i, 0] * nm[j, 0] + nm[i, 1] * nm[j, 1] < opposed)


def normal_bounds(normal, first, stop, perm):
    """(nx min, ny min, nx max, ny max) of the unit normals of each node's points
    perm[first[k]:stop[k]] of a ``build_cone_tree`` tree of the points."""
    cdef const double[:, ::1] nm = normal
    cdef const int64_t[::1] fs = first, st = stop, pm = perm
    cdef Py_ssize_t m = fs.shape[0], k, t, i
    bounds_array = np.empty((m, 4))
    cdef double[:, ::1] bounds = bounds_array
    with nogil:
        for k in range(m):
            bounds[k, 0] = bounds[k, 1] = 1e308
            bounds[k, 2] = bounds[k, 3] = -1e308
            for t in range(fs[k], st[k]):
                i = pm[t]
                bounds[k, 0], bounds[k, 1] = min(bounds[k, 0], nm[i, 0]), min(bounds[k, 1], nm[i, 1])
                bounds[k, 2], bounds[k, 3] = max(bounds[k, 2], nm[i, 0]), max(bounds[k, 3], nm[i, 1])
    return bounds_array


cdef int64_t _nearest_facing(Py_ssize_t i, double limit, double after_d, int64_t after_j,
                             double opposed, const double[:, ::1] p, const double[:, ::1] nm,
                             const int64_t[::1] perm, const int64_t[::1] first,
                             const int64_t[::1] stop, const int64_t[::1] left,
                             const int64_t[::1] right, const double[:, ::1] box,
                             const double[:, ::1] nbox, int64_t *stack,
                             double *distance) noexcept nogil:
    """The nearest point j facing point i at a distance 0 < e < limit after (after_d,
    after_j) in the order of (distance, index), -1 if none; its distance in *distance.
    Nodes whose normals cannot be opposed to i's (the smallest dot product over their
    normal box ``nbox`` is at least ``opposed``) are pruned: the points on i's own edge
    cost nothing however finely it is densified."""
    cdef double x = p[i, 0], y = p[i, 1], best = INFINITY, dx, dy, e
    cdef int64_t best_j = -1
    cdef Py_ssize_t top = 1, k, t, j, a, b
    stack[0] = 0
    while top:
        top -= 1
        k = stack[top]
        e = _box_distance(x, y, box, k)
        if (e >= limit or e > best
                or min(nm[i, 0] * nbox[k, 0], nm[i, 0] * nbox[k, 2])
                + min(nm[i, 1] * nbox[k, 1], nm[i, 1] * nbox[k, 3]) >= opposed):
            continue
        if left[k] < 0:
            for t in range(first[k], stop[k]):
                j = perm[t]
                dx, dy = p[j, 0] - x, p[j, 1] - y
                e = sqrt(dx * dx + dy * dy)
                if (e > 0.0 and e < limit
                        and (e < best or (e == best and j < best_j))
                        and (e > after_d or (e == after_d and j > after_j))
                        and _faces(p, nm, i, j, e, opposed)):
                    best, best_j = e, j
            continue
        a, b = left[k], right[k]
        if _box_distance(x, y, box, a) < _box_distance(x, y, box, b):
            a, b = b, a
        stack[top] = a          # the farther child waits
        stack[top + 1] = b
        top += 2
    distance[0] = best
    return best_j


def nearest_facing(xy, normal, rows, reach, after_d, after_j, double opposed, perm, first,
                   stop, left, right, box, normal_box):
    """For each point i = rows[r]: the nearest point j facing it through material
    (``_faces``) at a distance e with 0 < e < reach[r] that comes after (after_d[r],
    after_j[r]) in the order of (distance, index); returns the (distances, indices), inf
    and -1 where there is none. The points' k-d tree is ``build_cone_tree``'s (its sizes
    unused): a depth-first search, the nearer child first, pruning the nodes farther than
    the best so far or than the reach and those with no normal opposed to i's. Calling it again with the answer as ``after``
    gives the next facing point, so every facing point within reach can be visited in
    order of distance. ``normal_box`` is ``normal_bounds``'s for the tree."""
    cdef const double[:, ::1] p = xy, nm = normal, bx = box, nb = normal_box
    cdef const double[::1] rc = reach, ad = after_d
    cdef const int64_t[::1] rw = rows, aj = after_j
    cdef const int64_t[::1] pm = perm, fs = first, st = stop, lf = left, rt = right
    cdef Py_ssize_t n = rw.shape[0], r
    distance_array = np.full(n, np.inf)
    index_array = np.full(n, -1, np.int64)
    cdef double[::1] distance = distance_array
    cdef int64_t[::1] index = index_array
    cdef int64_t *stack
    with nogil, parallel(num_threads=threads_for(n)):
        stack = <int64_t *>malloc(STACK * sizeof(int64_t))
        for r in prange(n, schedule="dynamic", chunksize=CHUNK):
            index[r] = _nearest_facing(rw[r], rc[r], ad[r], aj[r], opposed, p, nm, pm, fs, st,
                                       lf, rt, bx, nb, stack, &distance[r])
        free(stack)
    return distance_array, index_array
