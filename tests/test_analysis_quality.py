"""Quality measures on triangles whose values are known in closed form."""

import numpy as np
import pytest

from pds_plugin.analysis.quality import ASPECT_BOUND, ASPECT_EQUILATERAL, triangle_quality


def test_equilateral_triangle():
    q = triangle_quality(np.array([[0, 0], [2, 0], [1, np.sqrt(3)]]), np.array([[0, 1, 2]]))
    assert q.aspect_ratio[0] == pytest.approx(4 / np.sqrt(3))
    assert np.allclose(q.angles, 60) and np.allclose(q.edge_lengths, 2)


def test_the_tight_case_of_theorem_1():
    """Sides alpha, alpha, alpha·√3 and circumradius alpha: L²/A = 4√3, angles 30-30-120."""
    alpha = 0.7
    apex = np.array([0, 0])
    left = alpha * np.array([np.cos(np.radians(150)), np.sin(np.radians(150))])
    right = alpha * np.array([np.cos(np.radians(30)), np.sin(np.radians(30))])
    q = triangle_quality(np.array([apex, right, left]), np.array([[0, 1, 2]]))
    assert q.aspect_ratio[0] == pytest.approx(ASPECT_BOUND)
    assert sorted(np.round(q.angles[0], 9)) == [30, 30, 120]


def test_3d_triangles_and_degenerate_ones():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]], float)
    q = triangle_quality(vertices, np.array([[0, 1, 2], [0, 1, 3]]))
    assert q.aspect_ratio[0] == pytest.approx(4.0) and q.area[0] == pytest.approx(0.5)
    assert np.isinf(q.aspect_ratio[1])


def test_stats_and_histogram():
    rng = np.random.default_rng(0)
    points = rng.random((40, 2))
    from scipy.spatial import Delaunay
    q = triangle_quality(points, Delaunay(points).simplices)
    stats = q.stats()
    assert stats["aspect_min"] >= ASPECT_EQUILATERAL * (1 - 1e-12)
    assert stats["triangles"] == len(q.aspect_ratio)
    counts, edges = q.histogram(bins=10)
    assert counts.sum() == len(q.aspect_ratio) and edges[0] == ASPECT_EQUILATERAL
