# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of the boundary's feature size (analysis/feature.py): for each vertex
of the boundary, the nearest segment that is not adjacent to it (the adjacency rule of
feature.py: turning below 150° along the ring) and, for walls, that it faces through
material; by a depth-first search of a k-d tree of the segments that skips the nodes
whose segments all lie in the vertex's own adjacent stretch of ring.

Conventions of the kernel modules: see ``_parallel.pyx``.
"""

import numpy as np

from cython.parallel cimport parallel, prange
from libc.math cimport INFINITY, sqrt
from libc.stdlib cimport free, malloc
from libc.stdint cimport int64_t

from ._parallel cimport threads_for

cdef enum:
    CHUNK = 256     # iterations a thread takes at a time
    STACK = 256     # nodes a search holds at most (twice the tree's depth)


cdef struct Boundary:
    # the segments of analysis/feature.py's _Boundary, flat over all rings
    const double *p0               # (n, 2) segment starts (vertex k starts segment k)
    const double *p1               # (n, 2) segment ends
    const int64_t *ring            # ring of each segment
    const int64_t *component       # component of each segment (its ring's)
    const int64_t *local           # index within its ring
    const int64_t *size            # its ring's segment count
    const int64_t *previous        # the segment before each in its ring
    const double *cumulative       # (n + 1,) cumulative |turning| at vertices 0..k-1
    const double *total            # its ring's total |turning|
    double adjacent_turning        # ADJACENT_TURNING
    double tolerance               # slack of the facing test, in units of |v - q|


cdef inline bint _forward(const Boundary *b, Py_ssize_t i, Py_ssize_t j) noexcept nogil:
    """feature.py's forward_adjacent for segments i <= j of one ring."""
    return (b.cumulative[j + 1] - b.cumulative[i + 1] < b.adjacent_turning) or j - i <= 1


cdef inline bint _backward(const Boundary *b, Py_ssize_t i, Py_ssize_t j) noexcept nogil:
    """feature.py's backward_adjacent for segments i <= j of one ring."""
    return ((b.total[i] - (b.cumulative[j + 1] - b.cumulative[i + 1]) < b.adjacent_turning)
            or (b.local[i] == 0 and b.local[j] == b.size[j] - 1))


cdef inline bint _adjacent(const Boundary *b, Py_ssize_t i, Py_ssize_t j) noexcept nogil:
    """feature.py's adjacent for any two segments."""
    if b.ring[i] != b.ring[j]:
        return False
    if i > j:
        i, j = j, i
    return _forward(b, i, j) or _backward(b, i, j)


cdef inline double _cross(double ax, double ay, double bx, double by) noexcept nogil:
    return ax * by - ay * bx


cdef bint _in_cone(const Boundary *b, Py_ssize_t w, double ux, double uy,
                   double slack) noexcept nogil:
    """Is the direction u inside the region's angle at vertex w (the start of segment w),
    closed, up to ``slack`` (the region is on the left of every segment)?"""
    cdef Py_ssize_t p = b.previous[w]
    cdef double ix = b.p1[2 * p] - b.p0[2 * p], iy = b.p1[2 * p + 1] - b.p0[2 * p + 1]
    cdef double ox = b.p1[2 * w] - b.p0[2 * w], oy = b.p1[2 * w + 1] - b.p0[2 * w + 1]
    cdef double li = sqrt(ix * ix + iy * iy), lo = sqrt(ox * ox + oy * oy)
    cdef bint left_in = _cross(ix, iy, ux, uy) >= -slack * li
    cdef bint left_out = _cross(ox, oy, ux, uy) >= -slack * lo
    if _cross(ix, iy, ox, oy) >= 0.0:      # convex (or straight): both half-planes
        return left_in and left_out
    return left_in or left_out             # reflex: either


cdef bint _box_outside(double ex, double ey, double length, double x, double y,
                       const double[:, ::1] box, Py_ssize_t k, double slack) noexcept nogil:
    """Are the four corners of node k's box strictly right of the line through (x, y)
    along e by more than ``slack`` times |e| (outside the half-plane on its left)?"""
    cdef double limit = -slack * length
    return (_cross(ex, ey, box[k, 0] - x, box[k, 1] - y) < limit
            and _cross(ex, ey, box[k, 2] - x, box[k, 1] - y) < limit
            and _cross(ex, ey, box[k, 0] - x, box[k, 3] - y) < limit
            and _cross(ex, ey, box[k, 2] - x, box[k, 3] - y) < limit)


cdef bint _unseen(const Boundary *b, Py_ssize_t v, const double[:, ::1] box,
                  Py_ssize_t k) noexcept nogil:
    """Is node k's box wholly outside the region's angle at vertex v, by more than the
    facing test's slack (:func:`_faces`, at the box's farthest corner)? Then no segment
    in it faces v."""
    cdef Py_ssize_t p = b.previous[v]
    cdef double x = b.p0[2 * v], y = b.p0[2 * v + 1]
    cdef double ix = b.p1[2 * p] - b.p0[2 * p], iy = b.p1[2 * p + 1] - b.p0[2 * p + 1]
    cdef double ox = b.p1[2 * v] - x, oy = b.p1[2 * v + 1] - y
    cdef double fx = max(abs(box[k, 0] - x), abs(box[k, 2] - x))
    cdef double fy = max(abs(box[k, 1] - y), abs(box[k, 3] - y))
    cdef double slack = b.tolerance * sqrt(fx * fx + fy * fy)
    cdef bint out_in = _box_outside(ix, iy, sqrt(ix * ix + iy * iy), x, y, box, k, slack)
    cdef bint out_out = _box_outside(ox, oy, sqrt(ox * ox + oy * oy), x, y, box, k, slack)
    if _cross(ix, iy, ox, oy) >= 0.0:      # convex: the angle is both half-planes
        return out_in or out_out
    return out_in and out_out              # reflex: either


cdef bint _faces(const Boundary *b, Py_ssize_t v, Py_ssize_t j, double fx, double fy,
                 double d) noexcept nogil:
    """Do vertex v and segment j face each other through material: the segment from v
    to its foot f on j leaves v into the region's angle there and reaches f from the
    region's side of j (its left), up to ``tolerance`` times its length? The exact test
    that it runs through the region (shapely, in feature.py) follows. The side of j is
    asked even when f is an end of j: across a slot whose bottom joins its two sides,
    the segment from one bottom corner to the other runs along the boundary, inside
    the closed angles at both, but it reaches the far side from the slot, not from that
    side's material (the slot is a gap, not a wall). Where f is j's start and the
    region's angle there is reflex, the material reaches past j's line: f may then be
    reached from anywhere in that angle (the base of a bump whose two reflex corners lie
    on one line of the boundary: the segment between them runs through material, on the
    wrong side of j by rounding)."""
    cdef double vx = b.p0[2 * v], vy = b.p0[2 * v + 1], slack = b.tolerance * d
    cdef double ex, ey, length
    if not _in_cone(b, v, fx - vx, fy - vy, slack):
        return False
    ex, ey = b.p1[2 * j] - b.p0[2 * j], b.p1[2 * j + 1] - b.p0[2 * j + 1]
    length = sqrt(ex * ex + ey * ey)
    if _cross(ex, ey, vx - fx, vy - fy) >= -slack * length:
        return True
    # at a convex start _in_cone asks j's side again, and says no
    return fx == b.p0[2 * j] and fy == b.p0[2 * j + 1] and _in_cone(b, j, vx - fx, vy - fy,
                                                                     slack)


cdef inline double _to_segment(const Boundary *b, double x, double y,
                               Py_ssize_t j) noexcept nogil:
    """The distance from (x, y) to segment j, as feature.py's _point_segment computes it."""
    cdef double ax = b.p0[2 * j], ay = b.p0[2 * j + 1]
    cdef double abx = b.p1[2 * j] - ax, aby = b.p1[2 * j + 1] - ay
    cdef double length2 = abx * abx + aby * aby
    cdef double t = ((x - ax) * abx + (y - ay) * aby) / (length2 if length2 > 0.0 else 1.0)
    t = min(max(t, 0.0), 1.0)
    cdef double dx = x - (ax + t * abx), dy = y - (ay + t * aby)
    return sqrt(dx * dx + dy * dy)


cdef bint _closest_of_pair(const Boundary *b, Py_ssize_t v, Py_ssize_t a, Py_ssize_t j,
                           double e) noexcept nogil:
    """Is e, the distance from vertex v (an end of segment a) to segment j, the distance
    between the segments a and j: no other end of either is nearer the other segment?
    (Two segments that do not cross are nearest at an end of one of them.)"""
    cdef double ox, oy                      # the other end of segment a
    if a == v:
        ox, oy = b.p1[2 * a], b.p1[2 * a + 1]
    else:
        ox, oy = b.p0[2 * a], b.p0[2 * a + 1]
    return (e <= _to_segment(b, ox, oy, j)
            and e <= _to_segment(b, b.p0[2 * j], b.p0[2 * j + 1], a)
            and e <= _to_segment(b, b.p1[2 * j], b.p1[2 * j + 1], a))


cdef inline double _box_distance(double x, double y, const double[:, ::1] box,
                                 Py_ssize_t k) noexcept nogil:
    cdef double dx = max(box[k, 0] - x, 0.0, x - box[k, 2])
    cdef double dy = max(box[k, 1] - y, 0.0, y - box[k, 3])
    return sqrt(dx * dx + dy * dy)


cdef inline bint _all_near(const int64_t[:, ::1] span, Py_ssize_t k, Py_ssize_t ring,
                           Py_ssize_t lo, Py_ssize_t count, Py_ssize_t size) noexcept nogil:
    """Do node k's segments all lie on ``ring`` in the local indices lo, lo + 1, ...,
    lo + count - 1 (mod size)? ``span[k]`` = (ring min, ring max, local min, local max)."""
    if span[k, 0] != ring or span[k, 1] != ring or count <= 0:
        return False
    return ((span[k, 2] - lo) % size + size) % size + (span[k, 3] - span[k, 2]) < count


cdef inline bint _across(const Boundary *b, Py_ssize_t j, Py_ssize_t ring, Py_ssize_t size,
                         const int64_t *lo, const int64_t *count, const double *least,
                         double e) noexcept nogil:
    """Is segment j, at e from the vertex, in one of its two stretches across a spike
    (local start ``lo[s]``, ``count[s]`` segments) at least ``least[s]`` away?"""
    cdef int s
    if b.ring[j] != ring:
        return False
    for s in range(2):
        if (count[s] > 0 and e >= least[s]
                and ((b.local[j] - lo[s]) % size + size) % size < count[s]):
            return True
    return False


cdef Py_ssize_t _nearest(const Boundary *b, Py_ssize_t v, Py_ssize_t near_lo,
                         Py_ssize_t near_count, double limit, double after_d,
                         Py_ssize_t after_j, bint walls, const int64_t *skip_lo,
                         const int64_t *skip_count, const double *skip_least,
                         const int64_t[::1] perm,
                         const int64_t[::1] first, const int64_t[::1] stop,
                         const int64_t[::1] left, const int64_t[::1] right,
                         const double[:, ::1] box, const int64_t[:, ::1] span,
                         int64_t *stack, double *out) noexcept nogil:
    """The nearest segment j not adjacent to vertex v (to neither segment meeting there:
    then some segment pair with v as an end is not adjacent) at a distance e < limit,
    after (after_d, after_j) in the order of (distance, index), facing v through
    material when ``walls`` and nearest it of a segment a meeting at v that is not
    adjacent to j (so that v and its foot are closest points of a and j); -1 if none.
    Its distance, foot and that segment a go to out[0..3]. Nodes on v's own ring within local indices near_lo .. near_lo +
    near_count - 1 (a stretch of ring every segment of which is adjacent to both) are
    skipped whole. A wall never joins two components (the segment between them leaves
    the region): for walls the other components' segments are skipped, and so are those
    across a spike from v (two stretches of v's ring and their least distances,
    ``skip_*``: analysis/feature.py's _spike_stretches)."""
    cdef double x = b.p0[2 * v], y = b.p0[2 * v + 1], best = INFINITY, e
    cdef double ax, ay, abx, aby, length2, t, fx, fy, dx, dy
    cdef Py_ssize_t best_j = -1, top = 1, k, s, j, a, c
    cdef Py_ssize_t ring = b.ring[v], size = b.size[v], before = b.previous[v]
    cdef bint far_before, far_after
    cdef Py_ssize_t anchor
    stack[0] = 0
    while top:
        top -= 1
        k = stack[top]
        e = _box_distance(x, y, box, k)
        if (e >= limit or e > best or _all_near(span, k, ring, near_lo, near_count, size)
                or (walls and _unseen(b, v, box, k))):
            continue
        if left[k] < 0:
            for s in range(first[k], stop[k]):
                j = perm[s]
                if walls and b.component[j] != b.component[v]:
                    continue
                far_before = not _adjacent(b, before, j)
                far_after = not _adjacent(b, v, j)
                if not (far_before or far_after):
                    continue
                ax, ay = b.p0[2 * j], b.p0[2 * j + 1]
                abx, aby = b.p1[2 * j] - ax, b.p1[2 * j + 1] - ay
                length2 = abx * abx + aby * aby
                t = ((x - ax) * abx + (y - ay) * aby) / (length2 if length2 > 0.0 else 1.0)
                t = min(max(t, 0.0), 1.0)
                fx, fy = ax + t * abx, ay + t * aby
                dx, dy = x - fx, y - fy
                e = sqrt(dx * dx + dy * dy)
                if not (e < limit and (e < best or (e == best and j < best_j))
                        and (e > after_d or (e == after_d and j > after_j))):
                    continue
                if walls and _across(b, j, ring, size, skip_lo, skip_count, skip_least, e):
                    continue
                if walls:
                    if far_before and _closest_of_pair(b, v, before, j, e):
                        anchor = before
                    elif far_after and _closest_of_pair(b, v, v, j, e):
                        anchor = v
                    else:
                        continue
                    if not _faces(b, v, j, fx, fy, e):
                        continue
                else:
                    anchor = before if far_before else v
                best, best_j = e, j
                out[0], out[1], out[2], out[3] = e, fx, fy, <double>anchor
            continue
        a, c = left[k], right[k]
        if _box_distance(x, y, box, a) < _box_distance(x, y, box, c):
            a, c = c, a
        stack[top] = a          # the farther child waits
        stack[top + 1] = c
        top += 2
    return best_j


def segment_tree(p0, p1, ring, local, Py_ssize_t leaf_size, tree):
    """The boxes and spans of a k-d tree of the segments: ``tree`` =
    (perm, first, stop, left, right) of ``_sizing_kernels.build_cone_tree`` over their
    midpoints; returns box (xmin, ymin, xmax, ymax of the segments, both ends) and span
    (ring min, ring max, local index min, local index max) per node."""
    cdef const double[:, ::1] a = p0, b = p1
    cdef const int64_t[::1] rg = ring, lc = local
    cdef const int64_t[::1] perm = tree[0], first = tree[1], stop = tree[2]
    cdef Py_ssize_t m = first.shape[0], k, t, i
    box_array = np.empty((m, 4))
    span_array = np.empty((m, 4), np.int64)
    cdef double[:, ::1] box = box_array
    cdef int64_t[:, ::1] span = span_array
    with nogil:
        for k in range(m):
            box[k, 0] = box[k, 1] = INFINITY
            box[k, 2] = box[k, 3] = -INFINITY
            span[k, 0] = span[k, 2] = 1 << 62
            span[k, 1] = span[k, 3] = -1
            for t in range(first[k], stop[k]):
                i = perm[t]
                box[k, 0] = min(box[k, 0], a[i, 0], b[i, 0])
                box[k, 1] = min(box[k, 1], a[i, 1], b[i, 1])
                box[k, 2] = max(box[k, 2], a[i, 0], b[i, 0])
                box[k, 3] = max(box[k, 3], a[i, 1], b[i, 1])
                span[k, 0], span[k, 1] = min(span[k, 0], rg[i]), max(span[k, 1], rg[i])
                span[k, 2], span[k, 3] = min(span[k, 2], lc[i]), max(span[k, 3], lc[i])
    return box_array, span_array


def nearest_nonadjacent(rows, near_lo, near_count, limit, after_d, after_j, bint walls,
                        skip_lo, skip_count, skip_least,
                        p0, p1, ring, component, local, size, previous, cumulative, total,
                        double adjacent_turning, double tolerance, perm, first, stop, left,
                        right, box, span):
    """For each vertex v = rows[r] (the start of segment v): the nearest segment j not
    adjacent to it (:func:`_nearest`) at a distance below limit[r], after
    (after_d[r], after_j[r]) in the order of (distance, index), and facing it through
    material when ``walls``. Returns (distance, j, foot (n, 2), a): a is a segment
    meeting at v, not adjacent to j, of which v and the foot are closest points (for
    walls); inf and -1 where there is none. Calling it again with the answer as
    ``after`` gives the next one. ``skip_lo``, ``skip_count``, ``skip_least`` ((n, 2)
    per row): the stretches across a spike whose segments walls skip (:func:`_across`)."""
    cdef Boundary b
    cdef const double[:, ::1] a0 = p0, a1 = p1
    cdef const int64_t[::1] rg = ring, cp = component, lc = local, sz = size, pv = previous
    cdef const double[::1] cm = cumulative, tt = total
    b.p0, b.p1, b.ring, b.local, b.size = &a0[0, 0], &a1[0, 0], &rg[0], &lc[0], &sz[0]
    b.component = &cp[0]
    b.previous, b.cumulative, b.total = &pv[0], &cm[0], &tt[0]
    b.adjacent_turning, b.tolerance = adjacent_turning, tolerance
    cdef const int64_t[::1] rw = rows, nl = near_lo, nc = near_count, aj = after_j
    cdef const double[::1] lm = limit, ad = after_d
    cdef const int64_t[:, ::1] slo = skip_lo, scnt = skip_count
    cdef const double[:, ::1] sls = skip_least
    cdef const int64_t[::1] pm = perm, fs = first, st = stop, lf = left, rt = right
    cdef const double[:, ::1] bx = box
    cdef const int64_t[:, ::1] sp = span
    cdef Py_ssize_t n = rw.shape[0], r
    distance_array = np.full(n, np.inf)
    index_array = np.full(n, -1, np.int64)
    foot_array = np.zeros((n, 2))
    anchor_array = np.full(n, -1, np.int64)
    cdef double[::1] distance = distance_array
    cdef int64_t[::1] anchor = anchor_array
    cdef int64_t[::1] index = index_array
    cdef double[:, ::1] foot = foot_array
    cdef int64_t *stack
    cdef double *out
    with nogil, parallel(num_threads=threads_for(n)):
        stack = <int64_t *>malloc(STACK * sizeof(int64_t))
        out = <double *>malloc(4 * sizeof(double))
        for r in prange(n, schedule="dynamic", chunksize=CHUNK):
            index[r] = _nearest(&b, rw[r], nl[r], nc[r], lm[r], ad[r], aj[r], walls,
                                &slo[r, 0], &scnt[r, 0], &sls[r, 0], pm, fs, st, lf, rt, bx,
                                sp, stack, out)
            if index[r] >= 0:
                distance[r], foot[r, 0], foot[r, 1] = out[0], out[1], out[2]
                anchor[r] = <int64_t>out[3]
        free(out)
        free(stack)
    return distance_array, index_array, foot_array, anchor_array
