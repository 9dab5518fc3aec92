# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of per-triangle geometry, one pass over the faces.

Conventions of the kernel modules: see ``_parallel.pyx``.
"""

import numpy as np

from cython.parallel cimport prange
from libc.math cimport INFINITY, NAN, M_PI, acos, sqrt
from libc.stdint cimport int64_t

from ._parallel cimport threads_for

cdef enum:
    CHUNK = 1024    # iterations a thread takes at a time
cdef double _DEGREES = 180 / M_PI


cdef double _edge2(const double[:, :] v, int64_t a, int64_t b, Py_ssize_t dim) noexcept nogil:
    """Squared distance from vertex a to vertex b."""
    cdef double s = 0.0, e
    cdef Py_ssize_t d
    for d in range(dim):
        e = v[b, d] - v[a, d]
        s = s + e * e
    return s


cdef double _angle(double l2_i, double l2_j, double l2_k, double l_i, double l_j) noexcept nogil:
    """The angle in degrees between edges i and j, opposite edge k (squared lengths l2)."""
    cdef double denominator = 2.0 * l_i * l_j, cosine = 1.0
    if denominator > 0:
        cosine = (l2_i + l2_j - l2_k) / denominator
    return acos(min(1.0, max(-1.0, cosine))) * _DEGREES


def triangle_measures(vertices, faces):
    """Edge lengths (M, 3) (edge k opposite corner k), areas (M,) and angles (M, 3) in
    degrees of triangles in 2D or 3D."""
    cdef const double[:, :] v = np.asarray(vertices, dtype=np.float64)
    cdef const int64_t[:, :] fc = np.asarray(faces, dtype=np.int64)
    cdef Py_ssize_t m = fc.shape[0], dim = v.shape[1], f, p, q, r
    lengths_array, area_array, angles_array = np.empty((m, 3)), np.empty(m), np.empty((m, 3))
    cdef double[:, ::1] lengths = lengths_array, angles = angles_array
    cdef double[::1] area = area_array
    cdef double cross, ux, uy, uz, vx, vy, vz, l2_0, l2_1, l2_2
    for f in prange(m, nogil=True, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(m)):
        l2_0 = _edge2(v, fc[f, 1], fc[f, 2], dim)     # squared length of edge k: l2_k
        l2_1 = _edge2(v, fc[f, 2], fc[f, 0], dim)
        l2_2 = _edge2(v, fc[f, 0], fc[f, 1], dim)
        lengths[f, 0], lengths[f, 1], lengths[f, 2] = sqrt(l2_0), sqrt(l2_1), sqrt(l2_2)
        # area from the cross product of the edges at corner 0
        p, q, r = fc[f, 0], fc[f, 1], fc[f, 2]
        if dim == 2:
            cross = ((v[q, 0] - v[p, 0]) * (v[r, 1] - v[p, 1])
                     - (v[q, 1] - v[p, 1]) * (v[r, 0] - v[p, 0]))
            area[f] = 0.5 * abs(cross)
        else:
            ux, uy, uz = v[q, 0] - v[p, 0], v[q, 1] - v[p, 1], v[q, 2] - v[p, 2]
            vx, vy, vz = v[r, 0] - v[p, 0], v[r, 1] - v[p, 1], v[r, 2] - v[p, 2]
            area[f] = 0.5 * sqrt((uy * vz - uz * vy) * (uy * vz - uz * vy)
                                 + (uz * vx - ux * vz) * (uz * vx - ux * vz)
                                 + (ux * vy - uy * vx) * (ux * vy - uy * vx))
        # law of cosines, clipped against rounding
        angles[f, 0] = _angle(l2_1, l2_2, l2_0, lengths[f, 1], lengths[f, 2])
        angles[f, 1] = _angle(l2_2, l2_0, l2_1, lengths[f, 2], lengths[f, 0])
        angles[f, 2] = _angle(l2_0, l2_1, l2_2, lengths[f, 0], lengths[f, 1])
    return lengths_array, area_array, angles_array


def circumcircles(points, faces):
    """Circumcentres (M, 2) and circumradii (M,) of 2D triangles (inf when flat)."""
    cdef const double[:, :] pt = np.asarray(points, dtype=np.float64)
    cdef const int64_t[:, :] fc = np.asarray(faces, dtype=np.int64)
    cdef Py_ssize_t m = fc.shape[0], f
    centre_array, radius_array = np.empty((m, 2)), np.empty(m)
    cdef double[:, ::1] centre = centre_array
    cdef double[::1] radius = radius_array
    cdef double ax, ay, bx, by, cx, cy, b2, c2, d, ux, uy
    for f in prange(m, nogil=True, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(m)):
        ax, ay = pt[fc[f, 0], 0], pt[fc[f, 0], 1]
        bx, by = pt[fc[f, 1], 0] - ax, pt[fc[f, 1], 1] - ay
        cx, cy = pt[fc[f, 2], 0] - ax, pt[fc[f, 2], 1] - ay
        b2, c2 = bx * bx + by * by, cx * cx + cy * cy
        d = 2.0 * (bx * cy - by * cx)
        if d == 0.0:
            centre[f, 0], centre[f, 1], radius[f] = NAN, NAN, INFINITY
            continue
        ux, uy = (cy * b2 - by * c2) / d, (bx * c2 - cx * b2) / d
        centre[f, 0], centre[f, 1] = ax + ux, ay + uy
        radius[f] = sqrt(ux * ux + uy * uy)
    return centre_array, radius_array
