"""Numba kernels of per-triangle geometry, one pass over the faces."""

import numpy as np
from numba import njit, prange


@njit(cache=True, parallel=True)
def triangle_measures(vertices, faces):
    """Edge lengths (M, 3) (edge k opposite corner k), areas (M,) and angles (M, 3) in
    degrees of triangles in 2D or 3D."""
    m = faces.shape[0]
    dim = vertices.shape[1]
    lengths = np.empty((m, 3))
    area = np.empty(m)
    angles = np.empty((m, 3))
    for f in prange(m):
        l2 = np.empty(3)
        for k in range(3):
            a, b = faces[f, (k + 1) % 3], faces[f, (k + 2) % 3]
            s = 0.0
            for d in range(dim):
                s += (vertices[b, d] - vertices[a, d]) ** 2
            l2[k] = s
            lengths[f, k] = np.sqrt(s)
        # area from the cross product of the edges at corner 0
        p, q, r = faces[f, 0], faces[f, 1], faces[f, 2]
        if dim == 2:
            cross = ((vertices[q, 0] - vertices[p, 0]) * (vertices[r, 1] - vertices[p, 1])
                     - (vertices[q, 1] - vertices[p, 1]) * (vertices[r, 0] - vertices[p, 0]))
            area[f] = 0.5 * abs(cross)
        else:
            ux, uy, uz = (vertices[q, 0] - vertices[p, 0], vertices[q, 1] - vertices[p, 1],
                          vertices[q, 2] - vertices[p, 2])
            vx, vy, vz = (vertices[r, 0] - vertices[p, 0], vertices[r, 1] - vertices[p, 1],
                          vertices[r, 2] - vertices[p, 2])
            area[f] = 0.5 * np.sqrt((uy * vz - uz * vy) ** 2 + (uz * vx - ux * vz) ** 2
                                    + (ux * vy - uy * vx) ** 2)
        for k in range(3):               # law of cosines, clipped against rounding
            i, j = (k + 1) % 3, (k + 2) % 3
            denominator = 2.0 * lengths[f, i] * lengths[f, j]
            cosine = (l2[i] + l2[j] - l2[k]) / denominator if denominator > 0 else 1.0
            angles[f, k] = np.degrees(np.arccos(min(1.0, max(-1.0, cosine))))
    return lengths, area, angles


@njit(cache=True, parallel=True)
def circumcircles(points, faces):
    """Circumcentres (M, 2) and circumradii (M,) of 2D triangles (inf when flat)."""
    m = faces.shape[0]
    centre = np.empty((m, 2))
    radius = np.empty(m)
    for f in prange(m):
        ax, ay = points[faces[f, 0], 0], points[faces[f, 0], 1]
        bx, by = points[faces[f, 1], 0] - ax, points[faces[f, 1], 1] - ay
        cx, cy = points[faces[f, 2], 0] - ax, points[faces[f, 2], 1] - ay
        b2, c2 = bx * bx + by * by, cx * cx + cy * cy
        d = 2.0 * (bx * cy - by * cx)
        if d == 0.0:
            centre[f, 0], centre[f, 1], radius[f] = np.nan, np.nan, np.inf
            continue
        ux, uy = (cy * b2 - by * c2) / d, (bx * c2 - cx * b2) / d
        centre[f, 0], centre[f, 1] = ax + ux, ay + uy
        radius[f] = np.sqrt(ux * ux + uy * uy)
    return centre, radius
