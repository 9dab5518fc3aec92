"""The faster counts of the interface report and the certificate's checks against their
definitions (docs/remesh.md "Session 21, fixed costs")."""

from __future__ import annotations

import collections

import numpy as np
import pytest

from pds_plugin.analysis.conformity import _isin
from pds_plugin.partition import _where, interface_report


def _vertex_sets(count, seed):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        n, d = int(rng.integers(0, 30)), int(rng.choice([2, 3]))
        v = rng.integers(-2, 3, (n, d)).astype(float)
        v[rng.random((n, d)) < 0.2] = -0.0                 # equal to 0.0
        v[rng.random((n, d)) < 0.05] = np.nan               # equal to nothing
        v[rng.random((n, d)) < 0.05] = np.inf
        yield v


@pytest.mark.parametrize("seed", [0, 1])
def test_duplicate_vertices_are_the_rows_equal_to_an_earlier_row(seed):
    for v in _vertex_sets(300, seed):
        equal = np.all(v[:, None] == v[None, :], axis=2) if len(v) else np.zeros((0, 0), bool)
        earlier = np.tril(equal, -1).any(axis=1)            # equals a row before it
        first = ~earlier & np.triu(equal, 1).any(axis=1)    # the first of a group of two or more
        report = interface_report(v, np.zeros((0, 3), int), np.zeros((0, 2), int),
                                  np.ones(len(v), bool))
        assert report.duplicate_vertices == int(earlier.sum())
        listed = [p for p in report.problems if p.startswith("two vertices")]
        assert listed == [f"two vertices at {_where(v[k])}" for k in np.flatnonzero(first)[:3]]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_edge_counts_are_those_of_every_triangle_edge(seed):
    rng = np.random.default_rng(seed)
    for _ in range(200):
        n = int(rng.integers(3, 12))
        vertices = rng.random((n, 3))
        faces = rng.integers(0, n, (int(rng.integers(0, 15)), 3))
        directed = collections.Counter((int(f[k]), int(f[(k + 1) % 3]))
                                       for f in faces for k in range(3))
        undirected = collections.Counter((min(a, b), max(a, b))
                                         for (a, b), m in directed.items() for _ in range(m))
        interface = rng.integers(0, n, (int(rng.integers(0, 6)), 2))
        outer = rng.random(n) < 0.5
        report = interface_report(vertices, faces, interface, outer)
        assert report.misoriented_edges == sum(m > 1 for m in directed.values())
        assert report.nonmanifold_edges == sum(m > 2 for m in undirected.values())
        keys = {(min(a, b), max(a, b)) for a, b in interface.tolist()}
        assert report.unjoined_interface_edges == sum(
            undirected.get((min(a, b), max(a, b)), 0) != 2 for a, b in interface.tolist())
        assert report.open_edges == sum(m == 1 and (not (outer[e[0]] and outer[e[1]]) or e in keys)
                                        for e, m in undirected.items())


def test_isin_of_integer_keys_is_numpys():
    rng = np.random.default_rng(3)
    for _ in range(500):
        values = rng.integers(-5, 20, int(rng.integers(0, 30)))
        among = rng.integers(-5, 20, int(rng.integers(0, 30)))
        assert np.array_equal(_isin(values, among), np.isin(values, among))
