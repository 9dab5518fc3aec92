"""mesh_region and PlanarMesh: Theorem 1 on every mesh, determinism, the 3D frame."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.analysis.quality import ASPECT_BOUND
from regions import regions, wedge


def assert_theorem_1(mesh):
    q = mesh.quality()
    assert q.aspect_ratio.max(initial=0) <= ASPECT_BOUND * (1 + 1e-9)
    assert q.angles.min(initial=90) >= 30 * (1 - 1e-9)
    assert q.angles.max(initial=90) <= 120 * (1 + 1e-9)


@settings(max_examples=30, deadline=None)
@given(region=regions, alpha=st.floats(0.04, 0.2), seed=st.integers(0, 2**32 - 1))
def test_theorem_1_and_a_maximal_sampling_on_generated_regions(region, alpha, seed):
    """The paper's construction; conforming meshes are tested in test_conforming.py."""
    mesh = pds.mesh_region(region, alpha, seed=seed, conforming=False)
    assert_theorem_1(mesh)
    cert = mesh.certificate()
    assert cert.sampling_ok and cert.quality_ok, str(cert)


@pytest.mark.parametrize("angle", [10, 29, 31, 59, 61, 90])
def test_theorem_1_at_sharp_corners(angle):
    for seed in range(3):
        assert_theorem_1(pds.mesh_region(pds.Region.from_shapely(wedge(angle)), 0.04, seed=seed,
                                         conforming=False))


def test_certified_mesh_of_a_plate_with_holes():
    plate = box(0, 0, 4, 2).difference(Point(1, 1).buffer(0.5)).difference(Point(3, 1).buffer(0.4))
    mesh = pds.mesh_region(pds.Region.from_shapely(plate), 0.05, seed=2)
    cert = mesh.certificate()
    assert cert.ok, str(cert)
    assert cert.betti_mesh == (1, 2)
    # the holes' chords cut circular segments of height <= (√3 alpha)² / 8r off them
    assert 1.0 <= cert.area_ratio <= 1.002


def test_same_seed_gives_the_same_mesh_bit_for_bit():
    region = pds.Region.from_shapely(Point(0, 0).buffer(1))
    a, b = (pds.mesh_region(region, 0.07, seed=11) for _ in range(2))
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)


def test_vertices_3d_lie_in_the_frame_plane():
    normal = np.array([1.0, 2.0, 2.0]) / 3
    u = np.cross(normal, [0, 0, 1.0]); u /= np.linalg.norm(u)
    frame = np.eye(4)
    frame[:3, 0], frame[:3, 1], frame[:3, 2], frame[:3, 3] = u, np.cross(normal, u), normal, [5, -1, 2]
    region = pds.Region.from_shapely(box(0, 0, 1, 1), frame=frame)
    mesh = pds.mesh_region(region, 0.1)
    assert np.abs((mesh.vertices_3d - [5, -1, 2]) @ normal).max() < 1e-12
    assert np.allclose(np.linalg.norm(np.diff(mesh.vertices_3d[:2], axis=0)),
                       np.linalg.norm(np.diff(mesh.vertices[:2], axis=0)))


def test_mesh_arrays_are_read_only():
    mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2)
    with pytest.raises(ValueError):
        mesh.vertices[0, 0] = 5.0
