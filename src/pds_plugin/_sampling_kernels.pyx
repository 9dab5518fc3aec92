# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of the Poisson disc sampler (see sampling.py for the algorithm).

The sampler keeps one background grid of square cells of side ``s < alpha/√2``, and
every sample closer than ``alpha`` to a point lies in the 5x5 block of cells around that
point's cell. ``grid[iy, ix]`` is the last sample placed in a cell (or -1) and
``nxt[q]`` the sample placed there before q: without a boundary to see through, a cell
holds at most one sample; conforming samplings may hold samples on both sides of a wall.
Each cell is split into SUB x SUB sub-cells; ``covered[j, i]`` is set once a single sample
disc contains sub-cell (i, j) whole and the sample sees all of it (``vis``, see
_visibility_kernels: two samples conflict only if they see each other).

Conventions of the kernel modules: see ``_parallel.pyx`` (bool arrays are passed to the
typed code as ``uint8`` views).
"""

import numpy as np

from cython.parallel cimport prange
from libc.math cimport INFINITY, ceil, floor, hypot, sqrt
from libc.stdlib cimport qsort
from libc.stdint cimport INT64_MAX, int8_t, int32_t, int64_t, uint8_t

from ._parallel cimport threads_for
from ._visibility_kernels cimport (Chords, box_seen, box_state, chord_cell, chords_of,
                                  near_boundary, point_inside, sees, sees_near_chords)

cdef enum:
    C_OUTSIDE = 0
    C_INSIDE = 1
    C_BOUNDARY = 2
    CSUB = 4        # sub-cells per cell side
    CONFLICT_SLOTS = 8   # conflicts listed per dart in the first scan
    SEQUENTIAL_DARTS = 32768   # fewer open darts: decided one by one in rank order
    CHUNK = 256     # iterations a thread takes at a time
    MAX_RUNS = 32   # intervals of gap lengths listed by _lengths
    BOX_OUTSIDE = 0  # _visibility_kernels.box_state of a box outside the region
    RANDOM_ROWS = 65536  # rows of random numbers drawn at a time by darts_in_open_subcells

OUTSIDE, INSIDE, BOUNDARY = C_OUTSIDE, C_INSIDE, C_BOUNDARY
SUB = CSUB

ctypedef const uint8_t[:, ::1] const_flags2


_LARGE_BYTES = 1 << 20
_MAPPED_BYTES = 1 << 25
"""Workspace buffers of _LARGE_BYTES or more are reserved at least this large (32 MiB): glibc
maps blocks that large on their own and gives them back to the OS when they are freed.
Smaller blocks come from the heap, where what is freed after the sampling mostly stays
resident: the certificate of a 1M square then peaked 22 MB higher (docs/engine.md). Only
the pages written become resident."""


class Workspace:
    """Scratch arrays kept across the passes and refinement levels of one sampling.

    The first dart pass needs the largest arrays (one dart per cell of the region), the
    later passes and levels smaller ones. Arrays that large come from the OS as fresh
    pages, which the OS clears on first touch, and return to it when freed: allocated anew
    for every pass and level they cost 1.0-1.5 s of system time at 1M samples
    (docs/engine.md). ``array`` hands out views of buffers that only grow.

    >>> work = Workspace()
    >>> a = work.array("darts", 10, np.float64)
    >>> b = work.array("darts", 4, np.float64)       # the same memory, valid until the next call
    >>> bool(np.shares_memory(a, b)), b.shape
    (True, (4,))
    >>> ranks = work.permutation("rank", 6, np.random.default_rng(1))
    >>> bool((ranks == np.random.default_rng(1).permutation(6)).all())
    True
    """

    def __init__(self):
        self._buffers = {}

    def array(self, name, n, dtype):
        """A contiguous 1-D array of ``n`` items of ``dtype`` (contents undefined), the same
        memory as the previous request of ``name``: valid until the next one."""
        buffer = self._buffers.get(name)
        if buffer is None or len(buffer) < n:
            size, item = n + n // 8, np.dtype(dtype).itemsize
            if size * item >= _LARGE_BYTES:        # reserved, not touched: see _MAPPED_BYTES
                size = max(size, _MAPPED_BYTES // item)
            buffer = self._buffers[name] = np.empty(size, dtype)
        return buffer[:n]

    def release(self, name):
        """Free the buffer ``name`` (an array too large to keep beside the next steps)."""
        self._buffers.pop(name, None)

    def permutation(self, name, Py_ssize_t n, rng):
        """``rng.permutation(n)`` (the same values, drawn the same way: 0..n-1 shuffled)
        in the reused array ``name``."""
        ranks = self.array(name, n, np.int64)
        cdef int64_t[::1] r = ranks
        cdef Py_ssize_t k
        for k in range(n):
            r[k] = k
        rng.shuffle(ranks)
        return ranks


cdef inline Py_ssize_t _clamp(Py_ssize_t i, Py_ssize_t n) noexcept nogil:
    return min(max(i, 0), n - 1)


cdef inline void _cell_of(double x, double y, double x0, double y0, double s,
                          Py_ssize_t nx, Py_ssize_t ny, Py_ssize_t *ix, Py_ssize_t *iy) noexcept nogil:
    ix[0] = _clamp(<Py_ssize_t>((x - x0) / s), nx)
    iy[0] = _clamp(<Py_ssize_t>((y - y0) / s), ny)


cdef int _compare_doubles(const void *a, const void *b) noexcept nogil:
    cdef double u = (<const double *>a)[0], v = (<const double *>b)[0]
    return (u > v) - (u < v)


def classify_cells(seg, double x0, double y0, double s, Py_ssize_t nx, Py_ssize_t ny):
    """Status of every cell: OUTSIDE, INSIDE or BOUNDARY (touched by the boundary).

    Boundary cells are found by walking each segment in steps of s/2 and marking the
    3x3 block around every step's cell, a conservative cover of the cells it crosses.
    The other cells take the status of their centre, found by even-odd scanlines.
    """
    cdef const double[:, :, :] sg = np.asarray(seg, dtype=np.float64)
    status_array = np.zeros((ny, nx), np.int8)
    cdef int8_t[:, ::1] status = status_array
    cdef int64_t[::1] counts = np.zeros(ny + 1, np.int64)      # scanline crossings per row
    cdef int64_t[::1] start, fill
    cdef double[::1] xs
    cdef Py_ssize_t k, iy, ix, lo, hi, p, a, b, q, steps, jx, jy, cx, cy
    cdef double xa, ya, xb, yb, yc, f
    cdef int phase
    for phase in range(2):
        if phase == 1:
            start = np.cumsum(counts)
            xs = np.empty(start[ny])
            fill = np.array(start[:ny])
        with nogil:
            for k in range(sg.shape[0]):
                xa, ya, xb, yb = sg[k, 0, 0], sg[k, 0, 1], sg[k, 1, 0], sg[k, 1, 1]
                lo = <Py_ssize_t>ceil((min(ya, yb) - y0) / s - 0.5)
                hi = <Py_ssize_t>floor((max(ya, yb) - y0) / s - 0.5)
                for iy in range(max(lo, 0), min(hi, ny - 1) + 1):
                    yc = y0 + (iy + 0.5) * s
                    if (ya <= yc) != (yb <= yc):
                        if phase == 0:
                            counts[iy + 1] += 1
                        else:
                            xs[fill[iy]] = xa + (yc - ya) * (xb - xa) / (yb - ya)
                            fill[iy] += 1
    with nogil:
        for iy in range(ny):
            qsort(&xs[0] + start[iy], start[iy + 1] - start[iy], sizeof(double), _compare_doubles)
            for p in range(start[iy], start[iy + 1] - 1, 2):
                a = <Py_ssize_t>ceil((xs[p] - x0) / s - 0.5)
                b = <Py_ssize_t>floor((xs[p + 1] - x0) / s - 0.5)
                for ix in range(max(a, 0), min(b, nx - 1) + 1):
                    status[iy, ix] = C_INSIDE
        for k in range(sg.shape[0]):
            xa, ya, xb, yb = sg[k, 0, 0], sg[k, 0, 1], sg[k, 1, 0], sg[k, 1, 1]
            steps = <Py_ssize_t>ceil(hypot(xb - xa, yb - ya) / (0.5 * s)) + 1
            for q in range(steps + 1):
                f = <double>q / steps
                _cell_of(xa + f * (xb - xa), ya + f * (yb - ya), x0, y0, s, nx, ny, &cx, &cy)
                for jy in range(max(cy - 1, 0), min(cy + 2, ny)):
                    for jx in range(max(cx - 1, 0), min(cx + 2, nx)):
                        status[jy, jx] = C_BOUNDARY
    return status_array


cdef bint _free(double x, double y, const int32_t[:, ::1] grid, const int32_t[::1] nxt,
                const double[:, ::1] points, double alpha2, double x0, double y0, double s,
                const Chords *vis) noexcept nogil:
    """True if no sample that (x, y) sees is closer than alpha to it."""
    cdef Py_ssize_t ny = grid.shape[0], nx = grid.shape[1], ix, iy, jx, jy
    cdef int32_t q
    cdef double dx, dy
    _cell_of(x, y, x0, y0, s, nx, ny, &ix, &iy)
    for jy in range(max(iy - 2, 0), min(iy + 3, ny)):
        for jx in range(max(ix - 2, 0), min(ix + 3, nx)):
            q = grid[jy, jx]
            while q >= 0:
                dx = points[q, 0] - x
                dy = points[q, 1] - y
                if dx * dx + dy * dy < alpha2 and sees(x, y, -1, points[q, 0], points[q, 1],
                                                       vis.out[q] if vis.out else -1, vis):
                    return False
                q = nxt[q]
    return True


cdef void _link(double x, double y, int32_t[:, ::1] grid, int32_t[::1] nxt,
                double[:, ::1] points, Py_ssize_t count, double x0, double y0,
                double s) noexcept nogil:
    """Store sample ``count`` at (x, y) and put it in its cell."""
    cdef Py_ssize_t ny = grid.shape[0], nx = grid.shape[1], ix, iy
    _cell_of(x, y, x0, y0, s, nx, ny, &ix, &iy)
    points[count, 0] = x
    points[count, 1] = y
    nxt[count] = grid[iy, ix]
    grid[iy, ix] = <int32_t>count


cdef void _place(double x, double y, int32_t[:, ::1] grid, int32_t[::1] nxt,
                 uint8_t[:, ::1] covered, double[:, ::1] points, Py_ssize_t count,
                 double alpha2, double x0, double y0, double s, const Chords *vis) noexcept nogil:
    """Add sample (x, y) as sample ``count`` and mark the sub-cells its disc contains."""
    _link(x, y, grid, nxt, points, count, x0, y0, s)
    _mark(count, points, covered, alpha2, x0, y0, s, vis)


cdef void _mark(Py_ssize_t q, const double[:, ::1] points, uint8_t[:, ::1] covered,
                double alpha2, double x0, double y0, double s, const Chords *vis) noexcept nogil:
    """Mark the sub-cells that the disc of sample q contains and q sees whole."""
    cdef double x = points[q, 0], y = points[q, 1]
    cdef Py_ssize_t q_out = vis.out[q] if vis.out else -1, i, j
    cdef bint walls = near_boundary(x, y, vis)
    cdef double h = s / CSUB, alpha = sqrt(alpha2), fy, w
    # rows of sub-cells the disc can contain, and in each the columns it contains whole
    for j in range(max(<Py_ssize_t>((y - alpha - y0) / h), 0),
                   min(<Py_ssize_t>((y + alpha - y0) / h) + 1, covered.shape[0])):
        fy = max(abs(y - y0 - j * h), abs(y - y0 - (j + 1) * h))     # farthest corner
        if fy * fy > alpha2:
            continue
        w = sqrt(alpha2 - fy * fy)
        for i in range(max(<Py_ssize_t>ceil((x - w - x0) / h), 0),
                       min(<Py_ssize_t>floor((x + w - x0) / h), covered.shape[1])):
            if not walls or (not covered[j, i] and box_seen(x, y, q_out, x0 + i * h, y0 + j * h,
                                                            h, 1e-9 * alpha, vis)):
                covered[j, i] = True


def darts_in_open_subcells(cells, rng, darts, grid, covered, double x0, double y0, double s,
                           bint one_per_cell, work):
    """For each cell without a sample (any cell unless ``one_per_cell``), a dart uniform
    in one of its sub-cells that no disc covers yet, the sub-cell chosen uniformly by
    three numbers of ``rng.random((len(cells), 3))`` (drawn RANDOM_ROWS rows at a time,
    the same stream). Closed cells get no dart: ``cells`` and ``darts`` (n, 2) are
    rewritten in place to list the open cells and their darts first, in order.
    Returns how many there are."""
    cdef int64_t[::1] c = cells
    cdef const int32_t[:, ::1] g = grid
    cdef const_flags2 cov = covered.view(np.uint8)
    cdef Py_ssize_t n = c.shape[0], nx = g.shape[1], k, iy, ix, i, j, free, pick, n_open = 0
    cdef Py_ssize_t first, stop
    cdef double h = s / CSUB
    cdef double[:, ::1] dt = darts
    cdef const double[:, ::1] uu
    cdef uint8_t[::1] is_open = work.array("is_open", n, np.uint8)
    random_rows = work.array("u", 3 * min(n, RANDOM_ROWS), np.float64).reshape(-1, 3)
    for first in range(0, n, RANDOM_ROWS):
        stop = min(first + RANDOM_ROWS, n)
        uu = rng.random(out=random_rows[:stop - first])
        for k in prange(first, stop, nogil=True, schedule="dynamic", chunksize=CHUNK,
                        num_threads=threads_for(stop - first)):
            is_open[k] = False
            iy = c[k] // nx
            ix = c[k] % nx
            if one_per_cell and g[iy, ix] >= 0:
                continue
            free = 0
            for j in range(iy * CSUB, iy * CSUB + CSUB):
                for i in range(ix * CSUB, ix * CSUB + CSUB):
                    free = free + (not cov[j, i])
            if free == 0:
                continue
            pick = <Py_ssize_t>(uu[k - first, 0] * free)
            for j in range(iy * CSUB, iy * CSUB + CSUB):
                for i in range(ix * CSUB, ix * CSUB + CSUB):
                    if not cov[j, i]:
                        if pick == 0:
                            dt[k, 0] = x0 + (i + uu[k - first, 1]) * h
                            dt[k, 1] = y0 + (j + uu[k - first, 2]) * h
                        pick = pick - 1
            is_open[k] = True
    with nogil:
        for k in range(n):
            if is_open[k]:
                c[n_open] = c[k]
                dt[n_open, 0] = dt[k, 0]
                dt[n_open, 1] = dt[k, 1]
                n_open += 1
    return n_open


def insert_where_free(cand, grid, nxt, covered, points, Py_ssize_t count, double alpha,
                      double x0, double y0, double s, vis):
    """Insert the candidates in order wherever the Poisson condition allows.

    Returns the new sample count.
    """
    cdef const double[:, ::1] cd = cand
    cdef int32_t[:, ::1] g = grid
    cdef int32_t[::1] nx_ = nxt
    cdef uint8_t[:, ::1] cov = covered.view(np.uint8)
    cdef double[:, ::1] pts = points
    cdef double alpha2 = alpha * alpha, x, y
    cdef Py_ssize_t k
    cdef Chords ch = chords_of(vis)
    with nogil:
        for k in range(cd.shape[0]):
            x, y = cd[k, 0], cd[k, 1]
            if _free(x, y, g, nx_, pts, alpha2, x0, y0, s, &ch):
                _place(x, y, g, nx_, cov, pts, count, alpha2, x0, y0, s, &ch)
                count += 1
    return count


cdef void _sort_by(const double *key, Py_ssize_t *index, Py_ssize_t m) noexcept nogil:
    """Insertion sort of index[:m] by key (m is at most 64)."""
    cdef Py_ssize_t a, b, r
    for a in range(m):
        index[a] = a
    for a in range(1, m):
        r = index[a]
        b = a
        while b > 0 and key[index[b - 1]] > key[r]:
            index[b] = index[b - 1]
            b -= 1
        index[b] = r


def sample_boundary_pieces(start, direction, length, order, u, grid, nxt, covered, points,
                           Py_ssize_t count, double alpha, double margin, double x0, double y0,
                           double s, vis):
    """Maximal 1D sampling of the boundary pieces (each shorter than alpha).

    Pieces are visited in ``order``; on each, the part farther than ``alpha`` from
    every sample (trimmed by ``margin`` at the disc edges) is computed exactly, and a
    sample is placed uniformly in it (``u[k]`` in [0, 1)). A sample covers its whole
    piece, so one pass leaves every piece covered. Returns the new sample count.
    """
    cdef const double[:, :] st = start
    cdef const double[:, :] dr = direction
    cdef const double[:] ln = length
    cdef const int64_t[:] od = order
    cdef const double[:] uu = u
    cdef int32_t[:, ::1] g = grid
    cdef int32_t[::1] nx_ = nxt
    cdef uint8_t[:, ::1] cov = covered.view(np.uint8)
    cdef double[:, ::1] pts = points
    cdef double alpha2 = alpha * alpha
    cdef Chords ch = chords_of(vis)
    cdef Py_ssize_t ny = g.shape[0], nx = g.shape[1], k, p, ix, iy, jx, jy, m, gcount, r, a
    cdef int32_t q
    cdef double lo[64]
    cdef double hi[64]
    cdef Py_ssize_t rank[64]
    cdef double gap_lo[65]
    cdef double gap_hi[65]
    cdef double ax, ay, ux, uy, L, dx, dy, t, h2, half, total, reach, target, width, x, y
    with nogil:
        for k in range(od.shape[0]):
            p = od[k]
            ax, ay = st[p, 0], st[p, 1]
            ux, uy = dr[p, 0], dr[p, 1]
            L = ln[p]
            _cell_of(ax + 0.5 * L * ux, ay + 0.5 * L * uy, x0, y0, s, nx, ny, &ix, &iy)
            m = 0
            for jy in range(max(iy - 3, 0), min(iy + 4, ny)):
                for jx in range(max(ix - 3, 0), min(ix + 4, nx)):
                    q = g[jy, jx]
                    while q >= 0:
                        dx = pts[q, 0] - ax
                        dy = pts[q, 1] - ay
                        t = dx * ux + dy * uy
                        h2 = dx * dx + dy * dy - t * t
                        if h2 < alpha2:
                            half = sqrt(alpha2 - h2)
                            if t + half > 0.0 and t - half < L and m < 64:
                                lo[m] = t - half - margin
                                hi[m] = t + half + margin
                                m += 1
                        q = nx_[q]
            # free gaps of [0, L] minus the chords, left to right (the order of equal
            # chord starts does not change the gaps)
            total = 0.0
            gcount = 0
            reach = 0.0
            _sort_by(lo, rank, m)
            for a in range(m):
                r = rank[a]
                if lo[r] > reach:
                    gap_lo[gcount] = reach
                    gap_hi[gcount] = lo[r]
                    total += lo[r] - reach
                    gcount += 1
                reach = max(reach, hi[r])
            if reach < L:
                gap_lo[gcount] = reach
                gap_hi[gcount] = L
                total += L - reach
                gcount += 1
            if total <= 0.0:
                continue
            target = uu[k] * total
            t = gap_hi[gcount - 1]
            for r in range(gcount):
                width = gap_hi[r] - gap_lo[r]
                if target < width:
                    t = gap_lo[r] + target
                    break
                target -= width
            x = ax + t * ux
            y = ay + t * uy
            if _free(x, y, g, nx_, pts, alpha2, x0, y0, s, &ch):
                _place(x, y, g, nx_, cov, pts, count, alpha2, x0, y0, s, &ch)
                count += 1
    return count


cdef Py_ssize_t _darts_near(Py_ssize_t d, const double[:, ::1] darts, const int64_t[::1] cell,
                            const int64_t[::1] rank, const int8_t[::1] state,
                            const int32_t[::1] head, double alpha2, Py_ssize_t nx,
                            Py_ssize_t ny, const Chords *vis, int8_t wanted, int64_t below,
                            int32_t *out, Py_ssize_t room, bint first) noexcept nogil:
    """Count the darts in ``state`` ``wanted`` of rank below ``below``, closer than alpha
    to dart d, that it sees; list the first ``room`` of them in ``out``; with ``first``,
    stop at the first one."""
    cdef Py_ssize_t m = darts.shape[0], found = 0, iy = cell[d] // nx, ix = cell[d] % nx
    cdef Py_ssize_t jy, c, e, stop
    cdef double dx, dy, x = darts[d, 0], y = darts[d, 1]
    cdef bint walls = near_boundary(x, y, vis)      # else dart d sees every dart near it
    cdef Py_ssize_t k = chord_cell(x, y, vis) if walls else 0
    for jy in range(max(iy - 2, 0), min(iy + 3, ny)):
        # darts are sorted by cell: those of the row's five cells are contiguous, from
        # the first dart of the first of them that has one
        c = jy * nx + max(ix - 2, 0)
        stop = jy * nx + min(ix + 3, nx)
        while c < stop and head[c] < 0:
            c += 1
        if c == stop:
            continue
        e = head[c]
        while e < m and cell[e] < stop:
            if state[e] == wanted and rank[e] < below:
                dx = darts[e, 0] - x
                dy = darts[e, 1] - y
                if dx * dx + dy * dy < alpha2 and (not walls or sees_near_chords(
                        x, y, -1, darts[e, 0], darts[e, 1], -1, vis, k)):
                    if found < room:
                        out[found] = <int32_t>e
                    found += 1
                    if first:
                        return found
            e += 1
    return found


def throw_darts(darts, cell, rank, status, tuple domain, grid, nxt, head, points,
                double alpha, double x0, double y0, double s, vis, work):
    """Throw the darts one by one in the order of ``rank`` (a permutation), keeping
    each that is in the region and at least alpha from every sample so far. Returns
    the kept darts' indices, increasing (:func:`place_all` adds them: the caller makes
    room for exactly as many samples as were kept); the array is ``work``'s, valid
    until the next throw.

    Darts in cells whose ``status`` is BOUNDARY are tested against ``domain`` (the
    chord bundle and cell sides of ``_visibility_kernels.points_inside``).

    Thrown in random order they would cost a cache miss each, so the same result is
    computed cell by cell instead: it is the lexicographically first maximal
    independent set of the conflict graph (darts closer than alpha) by rank. Darts
    are given sorted by their level-0 ``cell``. A first sweep lists each dart's
    conflicts of lower rank (a dart of higher rank cannot be accepted before it is
    decided, so those never matter); later sweeps accept a dart once all of them are
    rejected, and reject it as soon as one is accepted. ``head`` (one
    int32 per cell, all -1) is scratch space. With fewer than SEQUENTIAL_DARTS open
    darts the same set is found directly: the open darts in the order of their rank,
    each accepted unless it sees an accepted one closer than alpha (one scan per dart,
    no conflict lists). Their data then stays in the cache and this is the cheaper way
    (a 10k-vertex square's throws: 25 % less CPU time; at 100k the sweeps win).
    """
    cdef int8_t UNDECIDED = 0, ACCEPTED = 1, REJECTED = 2
    cdef const double[:, ::1] dt = darts
    cdef const int64_t[::1] cl = cell
    cdef const int64_t[::1] rk = rank
    cdef const int8_t[::1] st = status.reshape(-1)
    cdef const int8_t[::1] sides = domain[1]
    cdef const int8_t *sd = &sides[0] if sides.shape[0] else NULL
    cdef Chords region = chords_of(domain[0])
    cdef const int32_t[:, ::1] g = grid
    cdef const int32_t[::1] nx_ = nxt
    cdef int32_t[::1] hd = head
    cdef Chords ch = chords_of(vis)
    cdef const double[:, ::1] pts = points
    cdef double alpha2 = alpha * alpha
    cdef Py_ssize_t ny = g.shape[0], nx = g.shape[1], m = dt.shape[0], d, t
    cdef Py_ssize_t n_todo, n_accepted
    cdef int8_t[::1] state = work.array("state", m, np.int8)
    cdef int64_t[::1] degree = work.array("degree", m + 1, np.int64)
    todo_array = work.array("todo", m, np.int32)
    cdef int32_t[::1] todo = todo_array
    cdef int32_t[::1] by_rank
    with nogil:
        for d in range(m - 1, -1, -1):
            hd[cl[d]] = <int32_t>d
        degree[0] = 0
    for d in prange(m, nogil=True, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(m)):
        if ((st[cl[d]] != C_BOUNDARY or point_inside(&region, sd, dt[d, 0], dt[d, 1]))
                and _free(dt[d, 0], dt[d, 1], g, nx_, pts, alpha2, x0, y0, s, &ch)):
            state[d] = UNDECIDED
        else:
            state[d] = REJECTED
        degree[d + 1] = 0
    n_todo = 0
    with nogil:
        for d in range(m):
            if state[d] == UNDECIDED:
                todo[n_todo] = <int32_t>d
                n_todo += 1
    if n_todo < SEQUENTIAL_DARTS:
        by_rank = work.array("by_rank", m, np.int32)
        with nogil:
            for d in range(m):
                by_rank[rk[d]] = <int32_t>d
            for t in range(m):
                d = by_rank[t]
                if state[d] == UNDECIDED:
                    # an accepted dart near d that d sees rejects it
                    state[d] = REJECTED if _darts_near(d, dt, cl, rk, state, hd, alpha2, nx,
                                                       ny, &ch, ACCEPTED, INT64_MAX, NULL, 0,
                                                       True) else ACCEPTED
        n_todo = 0
    else:
        _conflict_sweeps(dt, cl, rk, state, degree, todo, n_todo, hd, alpha2, nx, ny, &ch,
                         work)
    with nogil:
        for d in range(m):
            hd[cl[d]] = -1
        n_accepted = 0
        for d in range(m):
            if state[d] == ACCEPTED:
                todo[n_accepted] = <int32_t>d
                n_accepted += 1
    return todo_array[:n_accepted]


cdef void _conflict_sweeps(const double[:, ::1] dt, const int64_t[::1] cl,
                           const int64_t[::1] rk, int8_t[::1] state, int64_t[::1] degree,
                           int32_t[::1] todo, Py_ssize_t n_todo, const int32_t[::1] hd,
                           double alpha2, Py_ssize_t nx, Py_ssize_t ny, const Chords *ch,
                           work) except *:
    """:func:`throw_darts`'s sweeps over the ``n_todo`` open darts listed in ``todo``:
    accept or reject each (``state``) as the lexicographically first maximal
    independent set by rank."""
    cdef int8_t UNDECIDED = 0, ACCEPTED = 1, REJECTED = 2
    cdef Py_ssize_t m = dt.shape[0], d, t, q, e, kept
    cdef bint blocked
    cdef int32_t[::1] slot
    cdef int32_t[::1] conflict
    # the conflict lists of the open darts, in CSR form over all darts: one scan lists
    # up to CONFLICT_SLOTS per dart, the few darts with more are scanned again
    slot = work.array("slots", n_todo * CONFLICT_SLOTS, np.int32)
    for t in prange(n_todo, nogil=True, schedule="dynamic", chunksize=CHUNK,
                    num_threads=threads_for(n_todo)):
        d = todo[t]
        degree[d + 1] = _darts_near(d, dt, cl, rk, state, hd, alpha2, nx, ny, ch, UNDECIDED,
                                    rk[d], &slot[t * CONFLICT_SLOTS], CONFLICT_SLOTS, False)
    with nogil:
        for d in range(m):
            degree[d + 1] += degree[d]
    conflict = work.array("conflicts", degree[m], np.int32)
    for t in prange(n_todo, nogil=True, schedule="dynamic", chunksize=CHUNK,
                    num_threads=threads_for(n_todo)):
        d = todo[t]
        if degree[d + 1] - degree[d] > CONFLICT_SLOTS:
            _darts_near(d, dt, cl, rk, state, hd, alpha2, nx, ny, ch, UNDECIDED, rk[d],
                        &conflict[degree[d]], degree[d + 1] - degree[d], False)
        else:
            for q in range(degree[d + 1] - degree[d]):
                conflict[degree[d] + q] = slot[t * CONFLICT_SLOTS + q]
    # the slots are the largest array of the throw (8 int32 per open dart): kept, they
    # would add to the memory peak of the caller's next step (the marks of place_all)
    del slot
    work.release("slots")
    with nogil:
        while n_todo:
            kept = 0
            for t in range(n_todo):
                d = todo[t]
                blocked = False
                for q in range(degree[d], degree[d + 1]):
                    e = conflict[q]
                    if state[e] == ACCEPTED:
                        state[d] = REJECTED
                        break
                    if state[e] == UNDECIDED:
                        blocked = True
                if state[d] == UNDECIDED:
                    if blocked:
                        todo[kept] = <int32_t>d
                        kept += 1
                    else:
                        state[d] = ACCEPTED
            n_todo = kept


def place_all(new, grid, nxt, covered, points, Py_ssize_t count, double alpha, double x0,
              double y0, double s, vis):
    """Add the samples ``new`` as samples count, count + 1, ... (linked into their cells
    in that order), and mark what their discs cover."""
    cdef const double[:, ::1] nw = new
    cdef int32_t[:, ::1] g = grid
    cdef int32_t[::1] nx_ = nxt
    cdef uint8_t[:, ::1] cov = covered.view(np.uint8)
    cdef double[:, ::1] pts = points
    cdef Chords ch = chords_of(vis)
    cdef Py_ssize_t k
    with nogil:
        for k in range(nw.shape[0]):
            _link(nw[k, 0], nw[k, 1], g, nx_, pts, count + k, x0, y0, s)
    _mark_all(count, count + nw.shape[0], pts, cov, alpha * alpha, x0, y0, s, &ch)


cdef void _mark_all(Py_ssize_t first, Py_ssize_t stop, const double[:, ::1] points,
                    uint8_t[:, ::1] covered, double alpha2, double x0, double y0, double s,
                    const Chords *vis) noexcept:
    """Mark the covered sub-cells of samples first..stop-1. Sub-cells are only ever set,
    and whether one is set does not depend on the others, so the result does not
    depend on the order."""
    cdef Py_ssize_t q
    for q in prange(first, stop, nogil=True, schedule="dynamic", chunksize=CHUNK,
                    num_threads=threads_for(stop - first)):
        _mark(q, points, covered, alpha2, x0, y0, s, vis)


def open_subcells(status, grid, covered, bint one_per_cell):
    """Flat level-0 cell and (sub_x, sub_y) of every uncovered sub-cell of the region's
    cells (that have no sample, if ``one_per_cell``)."""
    cdef const int8_t[:, ::1] st = status
    cdef const int32_t[:, ::1] g = grid
    cdef const_flags2 cov = covered.view(np.uint8)
    cdef Py_ssize_t ny = g.shape[0], nx = g.shape[1], n = 0, iy, ix, i, j
    cdef int phase
    cdef int64_t[::1] cell, sub_x, sub_y
    for phase in range(2):
        if phase == 1:
            cell_array, sub_x_array, sub_y_array = (np.empty(n, np.int64) for _ in range(3))
            cell, sub_x, sub_y = cell_array, sub_x_array, sub_y_array
            n = 0
        with nogil:
            for iy in range(ny):
                for ix in range(nx):
                    if st[iy, ix] == C_OUTSIDE or (one_per_cell and g[iy, ix] >= 0):
                        continue
                    for j in range(CSUB):
                        for i in range(CSUB):
                            if not cov[iy * CSUB + j, ix * CSUB + i]:
                                if phase == 1:
                                    cell[n] = iy * nx + ix
                                    sub_x[n] = i
                                    sub_y[n] = j
                                n += 1
    return cell_array, sub_x_array, sub_y_array


cdef bint _box_covered(Py_ssize_t ix, Py_ssize_t iy, double x_lo, double y_lo, double size,
                       const int32_t[:, ::1] grid, const int32_t[::1] nxt,
                       const double[:, ::1] points, Py_ssize_t first, double alpha2,
                       const Chords *vis) noexcept nogil:
    """True if the disc of one sample numbered ``first`` or later contains the box
    [x_lo, x_lo+size]² of level-0 cell (ix, iy) and the sample sees all of the box that
    is in the region. (A cell's samples are linked newest first.)"""
    cdef Py_ssize_t ny = grid.shape[0], nx = grid.shape[1], jx, jy
    cdef double x_hi = x_lo + size, y_hi = y_lo + size, qx, qy, fx, fy
    cdef int32_t q
    for jy in range(max(iy - 2, 0), min(iy + 3, ny)):
        for jx in range(max(ix - 2, 0), min(ix + 3, nx)):
            q = grid[jy, jx]
            while q >= first:
                qx, qy = points[q, 0], points[q, 1]
                fx = max(abs(qx - x_lo), abs(qx - x_hi))   # farthest corner
                fy = max(abs(qy - y_lo), abs(qy - y_hi))
                if fx * fx + fy * fy <= alpha2 and box_seen(
                        qx, qy, vis.out[q] if vis.out else -1, x_lo, y_lo, size,
                        1e-9 * sqrt(alpha2), vis):
                    return True
                q = nxt[q]
    return False


def open_boxes(parent, sub_x, sub_y, double size, status, tuple domain, grid, nxt, points,
               double alpha, vis, double x0, double y0, double s, bx, by, work):
    """The boxes of a refinement level still to get a dart: box k is the child
    (sub_x[k], sub_y[k]), of side ``size``, of level-0 cell ``parent[k]``; it stays open
    if no single disc contains it whole (and its sample sees it) and, in a BOUNDARY
    cell, it meets the region (``domain``, as in :func:`throw_darts`). ``parent``,
    ``sub_x`` and ``sub_y`` are rewritten in place to list the open boxes first, in
    order, and ``bx``, ``by`` get their lower-left corners. Returns how many are open."""
    cdef int64_t[::1] pr = parent
    cdef int64_t[::1] sx = sub_x
    cdef int64_t[::1] sy = sub_y
    cdef double[::1] x = bx
    cdef double[::1] y = by
    cdef const int8_t[::1] st = status.reshape(-1)
    cdef const int8_t[::1] sides = domain[1]
    cdef const int8_t *sd = &sides[0] if sides.shape[0] else NULL
    cdef Chords region = chords_of(domain[0])
    cdef const int32_t[:, ::1] g = grid
    cdef const int32_t[::1] nx_ = nxt
    cdef const double[:, ::1] pts = points
    cdef Chords ch = chords_of(vis)
    cdef double alpha2 = alpha * alpha
    cdef Py_ssize_t nx = g.shape[1], n = pr.shape[0], k, ix, iy, n_open = 0
    cdef uint8_t[::1] is_open = work.array("is_open", n, np.uint8)
    for k in prange(n, nogil=True, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(n)):
        ix = pr[k] % nx
        iy = pr[k] // nx
        x[k] = x0 + ix * s + sx[k] * size
        y[k] = y0 + iy * s + sy[k] * size
        is_open[k] = (not _box_covered(ix, iy, x[k], y[k], size, g, nx_, pts, 0, alpha2, &ch)
                      and (st[pr[k]] != C_BOUNDARY
                           or box_state(&region, sd, x[k], y[k], size) != BOX_OUTSIDE))
    with nogil:
        for k in range(n):
            if is_open[k]:
                pr[n_open], sx[n_open], sy[n_open] = pr[k], sx[k], sy[k]
                x[n_open], y[n_open] = x[k], y[k]
                n_open += 1
    return n_open


def split_uncovered(parent, sub_x, sub_y, bx, by, double size, Py_ssize_t first, grid, nxt,
                    points, double alpha, vis, child_parent, child_sub_x, child_sub_y,
                    work):
    """Split in four the boxes (as in :func:`open_boxes`) that no single disc of a sample
    numbered ``first`` or later contains (the earlier samples are known not to): the
    children of the j-th such box are written at 4j..4j+3 of the ``child_`` arrays, in
    the order (0, 0), (1, 0), (0, 1), (1, 1) of the next level. Returns how many boxes
    were split."""
    cdef const int64_t[::1] pr = parent
    cdef const int64_t[::1] sx = sub_x
    cdef const int64_t[::1] sy = sub_y
    cdef const double[::1] x = bx
    cdef const double[::1] y = by
    cdef int64_t[::1] cp = child_parent
    cdef int64_t[::1] cx = child_sub_x
    cdef int64_t[::1] cy = child_sub_y
    cdef const int32_t[:, ::1] g = grid
    cdef const int32_t[::1] nx_ = nxt
    cdef const double[:, ::1] pts = points
    cdef Chords ch = chords_of(vis)
    cdef double alpha2 = alpha * alpha
    cdef Py_ssize_t nx = g.shape[1], n = pr.shape[0], k, c, j = 0
    cdef uint8_t[::1] uncovered = work.array("uncovered", n, np.uint8)
    for k in prange(n, nogil=True, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(n)):
        uncovered[k] = not _box_covered(pr[k] % nx, pr[k] // nx, x[k], y[k], size, g, nx_, pts,
                                        first, alpha2, &ch)
    with nogil:
        for k in range(n):
            if uncovered[k]:
                for c in range(4):
                    cp[4 * j + c] = pr[k]
                    cx[4 * j + c] = 2 * sx[k] + (c & 1)
                    cy[4 * j + c] = 2 * sy[k] + (c >> 1)
                j += 1
    return j


cdef int _lengths(double first, double last, double m, double big, double *lo,
                  double *hi) noexcept nogil:
    """The lengths a gap may have to be cut into parts of length in [m, big], the first
    at least ``first`` and the last at least ``last`` (both in [m, big]): a union of
    intervals, written sorted and merged to lo/hi (room for MAX_RUNS); returns their
    count. k parts give [first + last + (k - 2) m, k big] for k >= 2, and once two of
    these meet every later one does: the last interval is then unbounded."""
    cdef int n = 0, k
    cdef double a = max(first, last), b
    if a <= big:
        lo[0], hi[0] = a, big
        n = 1
    for k in range(2, MAX_RUNS + 1):
        a = first + last + (k - 2) * m
        b = k * big
        if k * big >= first + last + (k - 1) * m or k == MAX_RUNS:
            b = INFINITY                    # the next interval meets this one, and so on
        if n and a <= hi[n - 1]:
            hi[n - 1] = max(hi[n - 1], b)
        else:
            lo[n], hi[n] = a, b
            n += 1
        if b == INFINITY:
            break
    return n


def split_gaps(lo, hi, first, last, part_min, double part_max, u):
    """Random points splitting each gap (lo[g], hi[g]) of a line into parts of length in
    [part_min[g], part_max], the first part at least first[g] long and the last at least
    last[g] (e.g. beside a sharp corner), where the gap allows it.

    A gap that is not already one valid part gets a point x uniform among the positions
    that leave both sides cut-able that way (:func:`_lengths`), and the two sides are
    split again; a gap with no such position is left whole (a piece too short, or one
    of length in (part_max, first + last): see the guards of sampling.py). Random
    numbers ``u`` are used in order, one per split point (at most
    sum(G / part_min) of them). Returns (positions, gap index of each).
    """
    cdef const double[:] lo_ = np.ascontiguousarray(lo, np.float64)
    cdef const double[:] hi_ = np.ascontiguousarray(hi, np.float64)
    cdef const double[:] fm = np.ascontiguousarray(first, np.float64)
    cdef const double[:] lm = np.ascontiguousarray(last, np.float64)
    cdef const double[:] pm = np.ascontiguousarray(part_min, np.float64)
    cdef const double[:] uu = np.ascontiguousarray(u, np.float64)
    cdef double big = part_max, a, b, G, m, t, total, target, width, s_lo, s_hi
    cdef double left_lo[MAX_RUNS]
    cdef double left_hi[MAX_RUNS]
    cdef double right_lo[MAX_RUNS]
    cdef double right_hi[MAX_RUNS]
    cdef double ends[4 * MAX_RUNS]
    cdef Py_ssize_t cap = 0, n = 0, used = 0, top, g, k
    cdef int n_left, n_right, i, j, count
    for g in range(lo_.shape[0]):
        cap += <Py_ssize_t>((hi_[g] - lo_[g]) / pm[g]) + 1
    pos_array = np.empty(cap)
    owner_array = np.empty(cap, np.int64)
    cdef double[::1] pos = pos_array
    cdef int64_t[::1] owner = owner_array
    cdef double[::1] stack_lo = np.empty(cap + 1)
    cdef double[::1] stack_hi = np.empty(cap + 1)
    cdef double[::1] stack_first = np.empty(cap + 1)
    cdef double[::1] stack_last = np.empty(cap + 1)
    with nogil:
        for g in range(lo_.shape[0]):
            m = pm[g]
            stack_lo[0], stack_hi[0], stack_first[0], stack_last[0] = lo_[g], hi_[g], fm[g], lm[g]
            top = 1
            while top:
                top -= 1
                a, b = stack_lo[top], stack_hi[top]
                G = b - a
                if max(stack_first[top], stack_last[top]) <= G <= big:
                    continue                                  # one part already
                # t = x - a: the left side cut-able with its first part >= first, the
                # right side with its last >= last
                n_left = _lengths(stack_first[top], m, m, big, left_lo, left_hi)
                n_right = _lengths(m, stack_last[top], m, big, right_lo, right_hi)
                count = 0
                total = 0.0
                for i in range(n_left):
                    for j in range(n_right - 1, -1, -1):      # G - right, increasing
                        s_lo = max(left_lo[i], G - right_hi[j])
                        s_hi = min(left_hi[i], G - right_lo[j])
                        if s_hi > s_lo:
                            ends[2 * count], ends[2 * count + 1] = s_lo, s_hi
                            total += s_hi - s_lo
                            count += 1
                if count == 0:
                    continue                                  # left whole
                target = uu[used] * total
                used += 1
                t = ends[2 * count - 1]
                for k in range(count):
                    width = ends[2 * k + 1] - ends[2 * k]
                    if target < width:
                        t = ends[2 * k] + target
                        break
                    target -= width
                pos[n] = a + t
                owner[n] = g
                n += 1
                stack_lo[top + 1], stack_hi[top + 1] = a + t, b
                stack_first[top + 1], stack_last[top + 1] = m, stack_last[top]
                stack_lo[top], stack_hi[top] = a, a + t
                stack_last[top] = m
                top += 2
    return pos_array[:n], owner_array[:n]
