"""The MeshLab sink: MeshSets with face and vertex quality, and MeshLab's own quality
filters as an independent check (sections added to a MeshSet: test_workflows; silencing
MeshLab's C-level output: test_silence)."""

import sys

import numpy as np
import pytest
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.analysis.quality import ASPECT_BOUND

pymeshlab = pytest.importorskip("pymeshlab")
from pds_plugin.sinks.meshlab import (  # noqa: E402
    RADIUS_RATIO_BOUND, meshlab_quality, radius_ratio, to_meshset)


@pytest.fixture(scope="module")
def mesh():
    plate = box(0, 0, 3, 2).difference(Point(1.0, 1.0).buffer(0.5)).union(Point(4, 1).buffer(0.7))
    return pds.mesh_region(pds.Region.from_shapely(plate), alpha=0.12, seed=3)


def empty_mesh(mesh):
    return pds.PlanarMesh(np.array(mesh.vertices[:3]), np.empty((0, 3), dtype=np.int64),
                          np.array(mesh.on_boundary[:3]), mesh.region, mesh.alpha)


# --- to_meshset ---

def test_to_meshset_holds_the_mesh_with_face_and_vertex_quality(mesh):
    ms = to_meshset(mesh, name="plate")
    current = ms.current_mesh()
    assert ms.mesh_number() == 1 and current.label() == "plate"
    np.testing.assert_array_equal(current.vertex_matrix(), mesh.vertices_3d)
    np.testing.assert_array_equal(current.face_matrix(), mesh.faces)
    np.testing.assert_array_equal(current.face_scalar_array(), mesh.quality().aspect_ratio)
    np.testing.assert_array_equal(current.vertex_scalar_array(), mesh.on_boundary.astype(float))
    # MeshLab filters run on it: select the faces above the Theorem 1 bound (there are none)
    ms.compute_selection_by_scalar_per_face(minq=ASPECT_BOUND * (1 + 1e-9), maxq=1e9)
    assert ms.current_mesh().selected_face_number() == 0
    assert mesh.to_meshset().current_mesh().face_number() == len(mesh.faces)


def test_to_meshset_refuses_an_empty_mesh(mesh):
    with pytest.raises(ValueError, match="no triangles"):
        to_meshset(empty_mesh(mesh))


def test_missing_pymeshlab_names_the_extra(mesh, monkeypatch):
    monkeypatch.setitem(sys.modules, "pymeshlab", None)
    with pytest.raises(ImportError, match=r'pip install "pds_plugin\[meshlab\]"'):
        to_meshset(mesh)


# --- MeshLab's quality filters agree with ours ---

def test_radius_ratio_of_the_extreme_triangles():
    vertices = np.array([[0, 0], [1, 0], [0.5, np.sqrt(3) / 2],      # equilateral
                         [2, 0], [2 + np.sqrt(3), 0], [2 + np.sqrt(3) / 2, 0.5]])  # 30-30-120
    ratio = radius_ratio(pds.triangle_quality(vertices, [[0, 1, 2], [3, 4, 5]]))
    np.testing.assert_allclose(ratio, [1.0, RADIUS_RATIO_BOUND], rtol=1e-12)


def test_meshlab_inradius_circumradius_matches_ours(mesh):
    measured = meshlab_quality(mesh)
    ours = radius_ratio(mesh.quality())
    np.testing.assert_allclose(measured.radius_ratio, ours, rtol=1e-9, atol=1e-12)
    # and both match 2r/R from the side lengths (r = A/s, R = abc/4A), a third formula
    a, b, c = mesh.quality().edge_lengths.T
    area = mesh.quality().area
    np.testing.assert_allclose(measured.radius_ratio, 8 * area**2 / ((a + b + c) / 2 * a * b * c),
                               rtol=1e-9)
    stats = measured.statistics
    assert stats["min"] == pytest.approx(ours.min(), rel=1e-9)
    assert stats["max"] == pytest.approx(ours.max(), rel=1e-9)
    assert stats["avg"] == pytest.approx(ours.mean(), rel=1e-9)
    # Theorem 1 seen through MeshLab: no angle outside [30°, 120°]
    assert measured.certified and stats["min"] >= RADIUS_RATIO_BOUND * (1 - 1e-9)


def test_meshlab_histogram_counts_every_face_once(mesh):
    measured = meshlab_quality(mesh, bins=10, range=(0.4, 1.0))
    assert len(measured.counts) == 10 and len(measured.bin_edges) == 11
    assert measured.counts.sum() + measured.below + measured.above == len(mesh.faces)
    assert measured.below == 0                    # all >= 2√3-3 > 0.4
    np.testing.assert_allclose(measured.bin_edges, np.linspace(0.4, 1.0, 11), atol=1e-6)
    numpy_counts, _ = np.histogram(measured.radius_ratio, bins=measured.bin_edges)
    near_an_edge = np.abs(measured.radius_ratio[:, None] - measured.bin_edges).min(axis=1) < 1e-6
    assert np.abs(measured.counts - numpy_counts).sum() <= 2 * near_an_edge.sum()


def test_meshlab_quality_leaves_the_meshset_unchanged(mesh):
    ms = to_meshset(mesh)
    measured = meshlab_quality(ms)
    np.testing.assert_allclose(measured.radius_ratio, radius_ratio(mesh.quality()), rtol=1e-9)
    np.testing.assert_array_equal(ms.current_mesh().face_scalar_array(),
                                  mesh.quality().aspect_ratio)
    assert ms.mesh_number() == 1


def test_meshlab_quality_refuses_what_it_cannot_measure(mesh):
    with pytest.raises(ValueError, match="empty"):
        meshlab_quality(pymeshlab.MeshSet())
    cloud = pymeshlab.MeshSet()
    cloud.add_mesh(pymeshlab.Mesh(np.random.default_rng(0).random((5, 3))), "cloud")
    with pytest.raises(ValueError, match="no faces"):
        meshlab_quality(cloud)
    with pytest.raises(ValueError, match="no triangles"):
        meshlab_quality(empty_mesh(mesh))
    with pytest.raises(ValueError, match="bins > 0"):
        meshlab_quality(mesh, bins=0)
    with pytest.raises(ValueError, match="range"):
        meshlab_quality(mesh, range=(1.0, 0.5))
