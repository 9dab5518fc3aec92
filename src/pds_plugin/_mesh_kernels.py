"""Numba kernel of mesh combinatorics: the edges of a triangle mesh in linear time."""

import numpy as np
from numba import njit


@njit(cache=True)
def edges_of(faces, n_vertices):
    """Each undirected edge of the triangles once, directed as in the first triangle
    that has it, with the number of triangles using it.

    Edges are grouped by their smaller vertex (a counting sort), then deduplicated
    inside each group, which is small: linear time, no global sort.
    """
    m = faces.shape[0] * 3
    low = np.empty(m, np.int64)
    start = np.zeros(n_vertices + 1, np.int64)
    for f in range(faces.shape[0]):
        for k in range(3):
            u, v = faces[f, k], faces[f, (k + 1) % 3]
            low[3 * f + k] = min(u, v)
            start[min(u, v) + 1] += 1
    for i in range(n_vertices):
        start[i + 1] += start[i]
    fill = start[:-1].copy()
    slot = np.empty(m, np.int64)                     # directed edge ids grouped by low vertex
    for e in range(m):
        slot[fill[low[e]]] = e
        fill[low[e]] += 1
    edges = np.empty((m, 2), np.int64)
    uses = np.zeros(m, np.int64)
    n = 0
    for i in range(n_vertices):
        first = n
        for s in range(start[i], start[i + 1]):
            e = slot[s]
            f, k = e // 3, e % 3
            u, v = faces[f, k], faces[f, (k + 1) % 3]
            other = u + v - i
            for q in range(first, n):
                if edges[q, 0] + edges[q, 1] - i == other:
                    uses[q] += 1
                    break
            else:
                edges[n, 0], edges[n, 1] = u, v
                uses[n] = 1
                n += 1
    return edges[:n], uses[:n]
