"""Numba kernels of the local solid alpha-complex (see complex.py)."""

import numpy as np
from numba import njit, prange

ACCEPT, REJECT, UNSURE = 1, 0, 2
_INCIRCLE_ERR = 1e-12   # relative bound on the rounding error of the filtered incircle test


@njit(cache=True)
def bin_points(points, x0, y0, h, nx, ny):
    """Sort points into square cells of side h: (order, cell_start) in CSR form."""
    n = points.shape[0]
    cell = np.empty(n, np.int64)
    for i in range(n):
        ix = min(int((points[i, 0] - x0) / h), nx - 1)
        iy = min(int((points[i, 1] - y0) / h), ny - 1)
        cell[i] = iy * nx + ix
    order = np.argsort(cell, kind="mergesort")
    start = np.zeros(nx * ny + 1, np.int64)
    for i in range(n):
        start[cell[i] + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    return order, start


@njit(cache=True)
def first_duplicate(binned, start):
    """Positions (p, q) of two equal binned points, or (-1, -1). Equal points share a cell."""
    for c in range(start.shape[0] - 1):
        for p in range(start[c], start[c + 1]):
            for q in range(p + 1, start[c + 1]):
                if binned[p, 0] == binned[q, 0] and binned[p, 1] == binned[q, 1]:
                    return p, q
    return -1, -1


@njit(cache=True)
def _incircle_sign(points, a, b, c, d):
    """+1 if d is inside the circle through counter-clockwise a, b, c, -1 outside,
    0 when rounding could decide either way."""
    adx = points[a, 0] - points[d, 0]
    ady = points[a, 1] - points[d, 1]
    bdx = points[b, 0] - points[d, 0]
    bdy = points[b, 1] - points[d, 1]
    cdx = points[c, 0] - points[d, 0]
    cdy = points[c, 1] - points[d, 1]
    alift = adx * adx + ady * ady
    blift = bdx * bdx + bdy * bdy
    clift = cdx * cdx + cdy * cdy
    bc = bdx * cdy - bdy * cdx
    ca = cdx * ady - cdy * adx
    ab = adx * bdy - ady * bdx
    det = alift * bc + blift * ca + clift * ab
    permanent = (alift * (abs(bdx * cdy) + abs(bdy * cdx)) + blift * (abs(cdx * ady) + abs(cdy * adx))
                 + clift * (abs(adx * bdy) + abs(ady * bdx)))
    if det > _INCIRCLE_ERR * permanent:
        return 1
    if det < -_INCIRCLE_ERR * permanent:
        return -1
    return 0


@njit(cache=True)
def _scan_point(points, i, alpha2, start, x0, y0, h, nx, ny, nbr, found_j, found_k, found_flag):
    """Triangles whose smallest vertex index is i, counter-clockwise as (i, j, k):
    written to found_* (as many as fit). Returns how many there are, or -1 if i has
    more neighbours within 2 alpha than ``nbr`` holds.

    Every point inside the circumcircle (radius <= alpha) of a triangle at i is within
    2 alpha of i, so i's neighbours are the only points the empty-circle test needs.
    """
    xi, yi = points[i, 0], points[i, 1]
    ix = min(int((xi - x0) / h), nx - 1)
    iy = min(int((yi - y0) / h), ny - 1)
    reach2 = 4.0 * alpha2
    m = 0
    for jy in range(max(iy - 2, 0), min(iy + 3, ny)):
        for jx in range(max(ix - 2, 0), min(ix + 3, nx)):
            c = jy * nx + jx
            for j in range(start[c], start[c + 1]):
                dx = points[j, 0] - xi
                dy = points[j, 1] - yi
                if j != i and dx * dx + dy * dy <= reach2:
                    if m == nbr.shape[0]:
                        return -1
                    nbr[m] = j
                    m += 1
    found = 0
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
            # circumradius R = |ij| |ik| |jk| / (2 |cross|) <= alpha
            if cross == 0.0 or b2 * c2 * d2 > 4.0 * alpha2 * cross * cross:
                continue
            a, b = (j, k) if cross > 0 else (k, j)
            # circumcentre relative to i; on a well-shaped triangle it is accurate to
            # far better than 1e-6 R, so points beyond R (1 + 1e-6) are surely outside
            ux = (cy * b2 - by * c2) / (2.0 * cross)
            uy = (bx * c2 - cx * b2) / (2.0 * cross)
            far2 = (ux * ux + uy * uy) * (1.0 + 2e-6)
            if abs(cross) < 1e-3 * max(b2, c2, d2):
                far2 = np.inf
            status = ACCEPT
            for q in range(m):
                other = nbr[q]
                if other == j or other == k:
                    continue
                ox = points[other, 0] - xi - ux
                oy = points[other, 1] - yi - uy
                if ox * ox + oy * oy > far2:
                    continue
                sign = _incircle_sign(points, i, a, b, other)
                if sign > 0:
                    status = REJECT
                    break
                if sign == 0:
                    status = UNSURE
            if status != REJECT:
                if found < found_j.shape[0]:
                    found_j[found] = a
                    found_k[found] = b
                    found_flag[found] = status
                found += 1
    return found


@njit(cache=True, parallel=True)
def local_complex(points, alpha, start, x0, y0, h, nx, ny, max_neighbours):
    """Every triangle of ``points`` (binned: cell c holds points start[c]:start[c+1])
    with circumradius <= alpha and an empty circumcircle, found from its smallest
    vertex. Returns (faces, flags, complete): flags ACCEPT or UNSURE; complete is False,
    with nothing found, if a point has more than ``max_neighbours`` neighbours within
    2 alpha."""
    n = points.shape[0]
    alpha2 = alpha * alpha
    slots = 8                       # triangles kept per point in the first pass
    counts = np.zeros(n, np.int64)
    slot_j = np.empty((n, slots), np.int32)
    slot_k = np.empty((n, slots), np.int32)
    slot_flag = np.empty((n, slots), np.int8)
    for i in prange(n):
        nbr = np.empty(max_neighbours, np.int64)
        counts[i] = _scan_point(points, i, alpha2, start, x0, y0, h, nx, ny, nbr,
                                slot_j[i], slot_k[i], slot_flag[i])
    if (counts < 0).any():
        return np.empty((0, 3), np.int64), np.empty(0, np.int8), False
    offsets = np.zeros(n + 1, np.int64)
    offsets[1:] = np.cumsum(counts)
    faces = np.empty((offsets[-1], 3), np.int64)
    flags = np.empty(offsets[-1], np.int8)
    for i in prange(n):
        found_j, found_k, found_flag = slot_j[i], slot_k[i], slot_flag[i]
        if counts[i] > slots:       # rare: redo this point with room for all
            nbr = np.empty(max_neighbours, np.int64)
            found_j = np.empty(counts[i], np.int32)
            found_k = np.empty(counts[i], np.int32)
            found_flag = np.empty(counts[i], np.int8)
            _scan_point(points, i, alpha2, start, x0, y0, h, nx, ny, nbr,
                        found_j, found_k, found_flag)
        for f in range(counts[i]):
            faces[offsets[i] + f, 0] = i
            faces[offsets[i] + f, 1] = found_j[f]
            faces[offsets[i] + f, 2] = found_k[f]
            flags[offsets[i] + f] = found_flag[f]
    return faces, flags, True
