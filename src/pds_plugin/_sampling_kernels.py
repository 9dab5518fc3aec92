"""Numba kernels of the Poisson disc sampler (see sampling.py for the algorithm).

The sampler keeps one background grid of square cells of side ``s < alpha/√2``, so a
cell holds at most one sample (``grid[iy, ix]`` is its index or -1), and every sample
closer than ``alpha`` to a point lies in the 5x5 block of cells around that point's cell.
Each cell is split into SUB x SUB sub-cells; ``covered[j, i]`` is set once a single sample
disc contains sub-cell (i, j) whole.
"""

import numpy as np
from numba import njit, prange

OUTSIDE, INSIDE, BOUNDARY = 0, 1, 2
SUB = 4


@njit(cache=True)
def _cell_of(x, y, x0, y0, s, nx, ny):
    ix = min(max(int((x - x0) / s), 0), nx - 1)
    iy = min(max(int((y - y0) / s), 0), ny - 1)
    return ix, iy


@njit(cache=True)
def classify_cells(seg, x0, y0, s, nx, ny):
    """Status of every cell: OUTSIDE, INSIDE or BOUNDARY (touched by the boundary).

    Boundary cells are found by walking each segment in steps of s/2 and marking the
    3x3 block around every step's cell, a conservative cover of the cells it crosses.
    The other cells take the status of their centre, found by even-odd scanlines.
    """
    status = np.zeros((ny, nx), np.int8)
    counts = np.zeros(ny + 1, np.int64)          # scanline crossings per row
    for phase in range(2):
        if phase == 1:
            start = np.cumsum(counts)
            xs = np.empty(start[-1])
            fill = start[:-1].copy()
        for k in range(seg.shape[0]):
            xa, ya, xb, yb = seg[k, 0, 0], seg[k, 0, 1], seg[k, 1, 0], seg[k, 1, 1]
            lo = int(np.ceil((min(ya, yb) - y0) / s - 0.5))
            hi = int(np.floor((max(ya, yb) - y0) / s - 0.5))
            for iy in range(max(lo, 0), min(hi, ny - 1) + 1):
                yc = y0 + (iy + 0.5) * s
                if (ya <= yc) != (yb <= yc):
                    if phase == 0:
                        counts[iy + 1] += 1
                    else:
                        xs[fill[iy]] = xa + (yc - ya) * (xb - xa) / (yb - ya)
                        fill[iy] += 1
    for iy in range(ny):
        row = np.sort(xs[start[iy]:start[iy + 1]])
        for p in range(0, row.shape[0] - 1, 2):
            a = int(np.ceil((row[p] - x0) / s - 0.5))
            b = int(np.floor((row[p + 1] - x0) / s - 0.5))
            for ix in range(max(a, 0), min(b, nx - 1) + 1):
                status[iy, ix] = INSIDE
    for k in range(seg.shape[0]):
        xa, ya, xb, yb = seg[k, 0, 0], seg[k, 0, 1], seg[k, 1, 0], seg[k, 1, 1]
        steps = int(np.ceil(np.hypot(xb - xa, yb - ya) / (0.5 * s))) + 1
        for q in range(steps + 1):
            f = q / steps
            ix, iy = _cell_of(xa + f * (xb - xa), ya + f * (yb - ya), x0, y0, s, nx, ny)
            for jy in range(max(iy - 1, 0), min(iy + 2, ny)):
                for jx in range(max(ix - 1, 0), min(ix + 2, nx)):
                    status[jy, jx] = BOUNDARY
    return status


@njit(cache=True)
def _free(x, y, grid, points, alpha2, x0, y0, s):
    """True if no sample is closer than alpha to (x, y)."""
    ny, nx = grid.shape
    ix, iy = _cell_of(x, y, x0, y0, s, nx, ny)
    for jy in range(max(iy - 2, 0), min(iy + 3, ny)):
        for jx in range(max(ix - 2, 0), min(ix + 3, nx)):
            q = grid[jy, jx]
            if q >= 0:
                dx = points[q, 0] - x
                dy = points[q, 1] - y
                if dx * dx + dy * dy < alpha2:
                    return False
    return True


@njit(cache=True)
def _place(x, y, grid, covered, points, count, alpha2, x0, y0, s):
    """Add sample (x, y) and mark the sub-cells its disc contains. Returns the new count."""
    ny, nx = grid.shape
    ix, iy = _cell_of(x, y, x0, y0, s, nx, ny)
    points[count, 0] = x
    points[count, 1] = y
    grid[iy, ix] = count
    h = s / SUB
    alpha = np.sqrt(alpha2)
    # rows of sub-cells the disc can contain, and in each the columns it contains whole
    for j in range(max(int((y - alpha - y0) / h), 0), min(int((y + alpha - y0) / h) + 1, covered.shape[0])):
        fy = max(abs(y - y0 - j * h), abs(y - y0 - (j + 1) * h))     # farthest corner
        if fy * fy > alpha2:
            continue
        w = np.sqrt(alpha2 - fy * fy)
        for i in range(max(int(np.ceil((x - w - x0) / h)), 0),
                       min(int(np.floor((x + w - x0) / h)), covered.shape[1])):
            covered[j, i] = True
    return count + 1


@njit(cache=True, parallel=True)
def darts_in_open_subcells(cells, u, grid, covered, x0, y0, s):
    """For each cell without a sample, a dart uniform in one of its sub-cells that no
    disc covers yet, the sub-cell chosen uniformly (``u`` (n, 3) in [0, 1)).
    Returns (darts, is_open); closed cells get no dart."""
    nx = grid.shape[1]
    h = s / SUB
    darts = np.empty((cells.shape[0], 2))
    is_open = np.zeros(cells.shape[0], np.bool_)
    for k in prange(cells.shape[0]):
        iy, ix = cells[k] // nx, cells[k] % nx
        if grid[iy, ix] >= 0:
            continue
        free = 0
        for j in range(iy * SUB, iy * SUB + SUB):
            for i in range(ix * SUB, ix * SUB + SUB):
                free += not covered[j, i]
        if free == 0:
            continue
        pick = int(u[k, 0] * free)
        for j in range(iy * SUB, iy * SUB + SUB):
            for i in range(ix * SUB, ix * SUB + SUB):
                if not covered[j, i]:
                    if pick == 0:
                        darts[k, 0] = x0 + (i + u[k, 1]) * h
                        darts[k, 1] = y0 + (j + u[k, 2]) * h
                    pick -= 1
        is_open[k] = True
    return darts, is_open


@njit(cache=True)
def insert_where_free(cand, grid, covered, points, count, alpha, x0, y0, s):
    """Insert the candidates in order wherever the Poisson condition allows.

    Returns the new sample count.
    """
    alpha2 = alpha * alpha
    for k in range(cand.shape[0]):
        x, y = cand[k, 0], cand[k, 1]
        if _free(x, y, grid, points, alpha2, x0, y0, s):
            count = _place(x, y, grid, covered, points, count, alpha2, x0, y0, s)
    return count


@njit(cache=True)
def sample_boundary_pieces(start, direction, length, order, u, grid, covered, points, count,
                           alpha, margin, x0, y0, s):
    """Maximal 1D sampling of the boundary pieces (each shorter than alpha).

    Pieces are visited in ``order``; on each, the part farther than ``alpha`` from
    every sample (trimmed by ``margin`` at the disc edges) is computed exactly, and a
    sample is placed uniformly in it (``u[k]`` in [0, 1)). A sample covers its whole
    piece, so one pass leaves every piece covered. Returns the new sample count.
    """
    alpha2 = alpha * alpha
    ny, nx = grid.shape
    lo = np.empty(64)
    hi = np.empty(64)
    gap_lo = np.empty(65)
    gap_hi = np.empty(65)
    for k in range(order.shape[0]):
        p = order[k]
        ax, ay = start[p, 0], start[p, 1]
        ux, uy = direction[p, 0], direction[p, 1]
        L = length[p]
        ix, iy = _cell_of(ax + 0.5 * L * ux, ay + 0.5 * L * uy, x0, y0, s, nx, ny)
        m = 0
        for jy in range(max(iy - 3, 0), min(iy + 4, ny)):
            for jx in range(max(ix - 3, 0), min(ix + 4, nx)):
                q = grid[jy, jx]
                if q >= 0:
                    dx = points[q, 0] - ax
                    dy = points[q, 1] - ay
                    t = dx * ux + dy * uy
                    h2 = dx * dx + dy * dy - t * t
                    if h2 < alpha2:
                        half = np.sqrt(alpha2 - h2)
                        if t + half > 0.0 and t - half < L and m < 64:
                            lo[m] = t - half - margin
                            hi[m] = t + half + margin
                            m += 1
        # free gaps of [0, L] minus the chords, left to right
        total = 0.0
        g = 0
        reach = 0.0
        for r in np.argsort(lo[:m]):
            if lo[r] > reach:
                gap_lo[g] = reach
                gap_hi[g] = lo[r]
                total += lo[r] - reach
                g += 1
            reach = max(reach, hi[r])
        if reach < L:
            gap_lo[g] = reach
            gap_hi[g] = L
            total += L - reach
            g += 1
        if total <= 0.0:
            continue
        target = u[k] * total
        t = gap_hi[g - 1]
        for r in range(g):
            width = gap_hi[r] - gap_lo[r]
            if target < width:
                t = gap_lo[r] + target
                break
            target -= width
        x = ax + t * ux
        y = ay + t * uy
        if _free(x, y, grid, points, alpha2, x0, y0, s):
            count = _place(x, y, grid, covered, points, count, alpha2, x0, y0, s)
    return count


@njit(cache=True, parallel=True)
def _open_darts(darts, ok, grid, points, alpha2, x0, y0, s):
    """True for darts in the region and at least alpha from every sample."""
    result = np.empty(darts.shape[0], np.bool_)
    for d in prange(darts.shape[0]):
        result[d] = ok[d] and _free(darts[d, 0], darts[d, 1], grid, points, alpha2, x0, y0, s)
    return result


@njit(cache=True)
def _each_conflict(d, darts, cell, state, head, alpha2, nx, ny, out):
    """Count the open darts closer than alpha to open dart d; list them in ``out`` if
    it is not empty."""
    m = darts.shape[0]
    found = 0
    iy, ix = cell[d] // nx, cell[d] % nx
    for jy in range(max(iy - 2, 0), min(iy + 3, ny)):
        for jx in range(max(ix - 2, 0), min(ix + 3, nx)):
            c = jy * nx + jx
            e = head[c]
            while 0 <= e < m and cell[e] == c:
                if e != d and state[e] == 0:
                    dx = darts[e, 0] - darts[d, 0]
                    dy = darts[e, 1] - darts[d, 1]
                    if dx * dx + dy * dy < alpha2:
                        if out.shape[0]:
                            out[found] = e
                        found += 1
                e += 1
    return found


@njit(cache=True, parallel=True)
def _conflicts(todo, darts, cell, state, head, alpha2, nx, ny):
    """The conflict lists of the open darts ``todo``, in CSR form over all darts."""
    m = darts.shape[0]
    degree = np.zeros(m + 1, np.int64)
    nothing = np.empty(0, np.int64)
    for t in prange(todo.shape[0]):
        d = todo[t]
        degree[d + 1] = _each_conflict(d, darts, cell, state, head, alpha2, nx, ny, nothing)
    degree = np.cumsum(degree)
    conflict = np.empty(degree[m], np.int64)
    for t in prange(todo.shape[0]):
        d = todo[t]
        _each_conflict(d, darts, cell, state, head, alpha2, nx, ny, conflict[degree[d]:degree[d + 1]])
    return degree, conflict


@njit(cache=True)
def throw_darts(darts, cell, rank, ok, grid, covered, head, points, count, alpha, x0, y0, s):
    """Throw the darts one by one in the order of ``rank`` (a permutation), keeping
    each that is in the region (``ok``) and at least alpha from every sample so far.

    Thrown in random order they would cost a cache miss each, so the same result is
    computed cell by cell instead: it is the lexicographically first maximal
    independent set of the conflict graph (darts closer than alpha) by rank. Darts
    are given sorted by their level-0 ``cell``. A first sweep lists each dart's
    conflicts; later sweeps accept a dart once every conflicting dart of lower rank is
    rejected, and reject it as soon as a conflicting dart is accepted. ``head`` (one
    entry per cell, all -1) is scratch space. Returns the new sample count.
    """
    UNDECIDED, ACCEPTED, REJECTED = 0, 1, 2
    alpha2 = alpha * alpha
    ny, nx = grid.shape
    m = darts.shape[0]
    for d in range(m - 1, -1, -1):
        head[cell[d]] = d
    state = np.where(_open_darts(darts, ok, grid, points, alpha2, x0, y0, s),
                     UNDECIDED, REJECTED).astype(np.int8)
    todo = np.flatnonzero(state == UNDECIDED)
    degree, conflict = _conflicts(todo, darts, cell, state, head, alpha2, nx, ny)
    n_todo = todo.shape[0]
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
                if state[e] == UNDECIDED and rank[e] < rank[d]:
                    blocked = True
            if state[d] == UNDECIDED:
                if blocked:
                    todo[kept] = d
                    kept += 1
                else:
                    state[d] = ACCEPTED
        n_todo = kept
    for d in range(m):
        head[cell[d]] = -1
    accepted = np.flatnonzero(state == ACCEPTED)
    _place_all(darts[accepted], grid, covered, points, count, alpha2, x0, y0, s)
    return count + accepted.shape[0]


@njit(cache=True, parallel=True)
def _place_all(new, grid, covered, points, count, alpha2, x0, y0, s):
    """Add the samples ``new``, at most one per cell and alpha apart, as samples count,
    count + 1, ... Each writes its own cell and point; the sub-cells two discs both
    cover are only ever set to True, so the result does not depend on the order."""
    for k in prange(new.shape[0]):
        _place(new[k, 0], new[k, 1], grid, covered, points, count + k, alpha2, x0, y0, s)


@njit(cache=True)
def open_subcells(status, grid, covered):
    """Flat level-0 cell and (sub_x, sub_y) of every uncovered sub-cell of the region's
    cells that have no sample."""
    ny, nx = grid.shape
    n = 0
    for phase in range(2):
        if phase == 1:
            cell = np.empty(n, np.int64)
            sub_x = np.empty(n, np.int64)
            sub_y = np.empty(n, np.int64)
            n = 0
        for iy in range(ny):
            for ix in range(nx):
                if status[iy, ix] == OUTSIDE or grid[iy, ix] >= 0:
                    continue
                for j in range(SUB):
                    for i in range(SUB):
                        if not covered[iy * SUB + j, ix * SUB + i]:
                            if phase == 1:
                                cell[n] = iy * nx + ix
                                sub_x[n] = i
                                sub_y[n] = j
                            n += 1
    return cell, sub_x, sub_y


@njit(cache=True)
def _box_covered(ix, iy, x_lo, y_lo, size, grid, points, alpha2):
    """True if one sample disc contains the box [x_lo, x_lo+size]² of level-0 cell (ix, iy)."""
    ny, nx = grid.shape
    x_hi, y_hi = x_lo + size, y_lo + size
    for jy in range(max(iy - 2, 0), min(iy + 3, ny)):
        for jx in range(max(ix - 2, 0), min(ix + 3, nx)):
            q = grid[jy, jx]
            if q >= 0:
                qx, qy = points[q, 0], points[q, 1]
                fx = max(abs(qx - x_lo), abs(qx - x_hi))   # farthest corner
                fy = max(abs(qy - y_lo), abs(qy - y_hi))
                if fx * fx + fy * fy <= alpha2:
                    return True
    return False


@njit(cache=True, parallel=True)
def uncovered_boxes(parent, bx, by, size, grid, points, alpha):
    """For boxes [bx, bx+size] x [by, by+size] inside level-0 cells ``parent``: True
    where no single sample disc contains the whole box."""
    alpha2 = alpha * alpha
    nx = grid.shape[1]
    keep = np.empty(parent.shape[0], np.bool_)
    for k in prange(parent.shape[0]):
        keep[k] = not _box_covered(parent[k] % nx, parent[k] // nx, bx[k], by[k], size,
                                   grid, points, alpha2)
    return keep
