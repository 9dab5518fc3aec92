# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True, initializedcheck=False
"""Compiled kernels of mesh combinatorics: the edges of a triangle mesh and its
components, in linear time.

Conventions of the kernel modules: see ``_parallel.pyx``.
"""

import numpy as np

from libc.stdint cimport int64_t


def edges_of(faces, Py_ssize_t n_vertices):
    """Each undirected edge of the triangles once, directed as in the first triangle
    that has it, with the number of triangles using it.

    Edges are grouped by their smaller vertex (a counting sort), then deduplicated
    inside each group, which is small: linear time, no global sort.
    """
    cdef const int64_t[:, :] fc = np.asarray(faces, dtype=np.int64)
    cdef Py_ssize_t m = fc.shape[0] * 3, f, k, i, e, s, q, n = 0, first
    cdef int64_t u, v, other
    cdef int64_t[::1] start = np.zeros(n_vertices + 1, np.int64)
    cdef int64_t[::1] fill = np.empty(n_vertices, np.int64)
    cdef int64_t[::1] slot = np.empty(m, np.int64)          # directed edge ids grouped by low vertex
    edges_array = np.empty((m, 2), np.int64)
    uses_array = np.zeros(m, np.int32)
    cdef int64_t[:, ::1] edges = edges_array
    cdef int[::1] uses = uses_array
    cdef bint seen
    with nogil:
        for f in range(fc.shape[0]):
            for k in range(3):
                start[min(fc[f, k], fc[f, (k + 1) % 3]) + 1] += 1
        for i in range(n_vertices):
            start[i + 1] += start[i]
            fill[i] = start[i]
        for e in range(m):
            u = min(fc[e // 3, e % 3], fc[e // 3, (e % 3 + 1) % 3])
            slot[fill[u]] = e
            fill[u] += 1
        for i in range(n_vertices):
            first = n
            for s in range(start[i], start[i + 1]):
                e = slot[s]
                f, k = e // 3, e % 3
                u, v = fc[f, k], fc[f, (k + 1) % 3]
                other = u + v - i
                seen = False
                for q in range(first, n):
                    if edges[q, 0] + edges[q, 1] - i == other:
                        uses[q] += 1
                        seen = True
                        break
                if not seen:
                    edges[n, 0], edges[n, 1] = u, v
                    uses[n] = 1
                    n += 1
    # copies, so that the (3M, 2) buffer is not kept alive by the mesh's cached edges
    return edges_array[:n].copy(), uses_array[:n]


cdef inline int64_t _root(int64_t[::1] parent, int64_t v) noexcept nogil:
    """v's root, halving the path on the way."""
    while parent[v] != v:
        parent[v] = parent[parent[v]]
        v = parent[v]
    return v


def face_components(faces, Py_ssize_t n_vertices):
    """Component label of each vertex (-1 for a vertex in no triangle) and the number of
    components, triangles joined through shared vertices; components numbered in the
    order of their smallest vertex (as ``scipy.sparse.csgraph.connected_components``
    numbers them), by union-find over the triangles. An index outside the vertices is
    refused (ArgumentError) before any is used.
    """
    cdef const int64_t[:, :] fc = np.asarray(faces, dtype=np.int64)
    labels_array = np.full(n_vertices, -1, np.int64)
    cdef int64_t[::1] labels = labels_array
    cdef int64_t[::1] parent = np.arange(n_vertices, dtype=np.int64)
    cdef Py_ssize_t f, k, v, count = 0, bad = -1
    cdef int64_t a, b, r
    with nogil:
        for f in range(fc.shape[0]):
            for k in range(3):
                if fc[f, k] < 0 or fc[f, k] >= n_vertices:
                    bad = f
                    break
            if bad >= 0:
                break
    if bad >= 0:
        from .errors import ArgumentError
        raise ArgumentError(f"face {bad} refers to vertex {fc[bad, k]}, but there are "
                            f"{n_vertices} vertices (indices 0 to {n_vertices - 1})")
    with nogil:
        for f in range(fc.shape[0]):
            a = _root(parent, fc[f, 0])
            for k in range(1, 3):
                b = _root(parent, fc[f, k])
                if a != b:
                    if a < b:
                        parent[b] = a
                    else:
                        parent[a] = b
                        a = b
        for f in range(fc.shape[0]):           # mark the used vertices' roots
            for k in range(3):
                labels[fc[f, k]] = -2
        for v in range(n_vertices):            # each root is its component's smallest vertex
            if labels[v] == -2:
                r = _root(parent, v)
                if r == v:
                    labels[v] = count
                    count += 1
                else:
                    labels[v] = labels[r]
    return labels_array, count
