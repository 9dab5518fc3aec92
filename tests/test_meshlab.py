"""pds_plugin inside a MeshLab workflow: MeshSets, section meshes, MeshLab's own quality
filters as an independent check, and silencing of MeshLab's C-level output."""

import ctypes
import os
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.analysis.quality import ASPECT_BOUND

pymeshlab = pytest.importorskip("pymeshlab")
from pds_plugin.silence import silenced  # noqa: E402
from pds_plugin.sinks.meshlab import (  # noqa: E402
    RADIUS_RATIO_BOUND, meshlab_quality, radius_ratio, to_meshset)
from pds_plugin.workflows import add_section_meshes  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


@pytest.fixture(scope="module")
def mesh():
    plate = box(0, 0, 3, 2).difference(Point(1.0, 1.0).buffer(0.5)).union(Point(4, 1).buffer(0.7))
    return pds.mesh_region(pds.Region.from_shapely(plate), alpha=0.12, seed=3)


def meshset_of(solid: trimesh.Trimesh, name="solid"):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(solid.vertices, solid.faces), name)
    return ms


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


# --- silencing ---

def _qhull_chatter():
    """A real MeshLab call that prints from C++ (qhull's report on stderr)."""
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(np.random.default_rng(0).random((10, 3))), "cloud")
    ms.generate_alpha_shape()
    ctypes.CDLL(None).fflush(None)


@pytest.mark.skipif(sys.platform == "win32", reason="C stdio flush through ctypes")
def test_silenced_keeps_meshlab_chatter_off_the_terminal(capfd):
    _qhull_chatter()
    out, err = capfd.readouterr()
    assert "facets" in out + err                   # the chatter is real ...
    with silenced():
        _qhull_chatter()
        os.write(1, b"fd 1 inside\n")
        os.write(2, b"fd 2 inside\n")
    assert capfd.readouterr() == ("", "")          # ... and silenced
    print("after")
    os.write(2, b"fd 2 after\n")
    assert capfd.readouterr() == ("after\n", "fd 2 after\n")   # and restored


def test_silenced_restores_the_descriptors_after_an_error(capfd):
    with pytest.raises(RuntimeError):
        with silenced():
            raise RuntimeError("inside")
    os.write(1, b"still here\n")
    assert capfd.readouterr().out == "still here\n"


# --- sections added to the MeshSet ---

def test_add_section_meshes_with_count(mesh):
    ms = meshset_of(trimesh.creation.box(extents=(2, 1, 1)), "box")
    added = add_section_meshes(ms, 0.1, plane_normal=(0, 0, 1), count=4)
    heights = [-0.375, -0.125, 0.125, 0.375]       # mid-points of 4 equal slabs of [-0.5, 0.5]
    assert [s.name for s in added] == [f"section z={h:g} alpha=0.1" for h in heights]
    assert [s.mesh_id for s in added] == [1, 2, 3, 4] and ms.mesh_number() == 5
    assert ms.current_mesh().label() == "box"      # the solid stays current
    for s, height in zip(added, heights):
        layer = ms.mesh(s.mesh_id)
        assert layer.label() == s.name
        assert s.mesh.region.area == pytest.approx(2.0, rel=1e-12)
        np.testing.assert_allclose(layer.vertex_matrix()[:, 2], height, atol=1e-12)
        np.testing.assert_array_equal(layer.vertex_matrix(), s.mesh.vertices_3d)
        np.testing.assert_array_equal(layer.face_scalar_array(), s.mesh.quality().aspect_ratio)
        assert layer.face_scalar_array().max() <= ASPECT_BOUND * (1 + 1e-9)


def test_add_section_meshes_tilted_plane_and_offsets():
    tube = trimesh.creation.annulus(r_min=1, r_max=2, height=4, sections=64)
    ms = meshset_of(tube, "tube")
    normal = np.array([1.0, 0.0, 1.0]) / np.sqrt(2)
    one = add_section_meshes(ms, 0.2, plane_normal=normal, plane_origin=(0, 0, 0.5))
    assert one[0].name.startswith("section n=(0.7071, 0, 0.7071) d=0.353553")
    assert one[0].mesh.region.betti == (1, 1)
    assert np.abs((one[0].mesh.vertices_3d - (0, 0, 0.5)) @ normal).max() < 1e-9
    several = add_section_meshes(ms, 0.2, plane_normal=(0, 0, -1), offsets=[-1.0, 0.5])
    assert [s.name for s in several] == ["section z=1 alpha=0.2", "section z=-0.5 alpha=0.2"]
    assert [s.mesh_id for s in several] == [2, 3] and ms.current_mesh().label() == "tube"


def test_add_section_meshes_cuts_the_solid_where_meshlab_shows_it():
    ms = meshset_of(trimesh.creation.box(extents=(1, 1, 1)), "box")
    ms.compute_matrix_from_translation(axisz=2.0, freeze=False)   # moves the layer only
    assert ms.current_mesh().vertex_matrix()[:, 2].max() == 0.5
    added = add_section_meshes(ms, 0.1, plane_origin=(0, 0, 2.25))
    np.testing.assert_allclose(added[0].mesh.vertices_3d[:, 2], 2.25)


def test_add_section_meshes_errors(mesh):
    with pytest.raises(ValueError, match="MeshSet is empty"):
        add_section_meshes(pymeshlab.MeshSet(), 0.1, count=1)
    ms = meshset_of(trimesh.creation.box(extents=(1, 1, 1)), "box")
    with pytest.raises(ValueError, match="say where to cut"):
        add_section_meshes(ms, 0.1)
    with pytest.raises(ValueError, match="not both"):
        add_section_meshes(ms, 0.1, offsets=[0.0], count=2)
    with pytest.raises(ValueError, match="misses the solid"):
        add_section_meshes(ms, 0.1, plane_origin=(0, 0, 3))
    with pytest.raises(ValueError, match="no mesh with id 7"):
        add_section_meshes(ms, 0.1, count=1, mesh_id=7)
    ms.add_mesh(pymeshlab.Mesh(np.random.default_rng(0).random((5, 3))), "cloud")
    with pytest.raises(ValueError, match="point cloud"):
        add_section_meshes(ms, 0.1, count=1)
    assert ms.mesh_number() == 2                    # nothing was added by the failures


def test_featuretype_sections_in_a_meshset():
    path = DATA / "featuretype.STL"
    if not path.exists():
        pytest.skip(f"{path} is absent")
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    bbox = ms.current_mesh().bounding_box()
    zmin, zmax = bbox.min()[2], bbox.max()[2]
    added = add_section_meshes(ms, 0.05, plane_origin=(0, 0, (zmin + zmax) / 2))
    section = added[0].mesh
    assert section.region.betti == (2, 8)         # data/README.md: 2 components, 8 holes
    ms.set_current_mesh(added[0].mesh_id)
    measured = meshlab_quality(ms)                 # the recipe on the layer in the MeshSet
    assert measured.certified
    assert measured.counts.sum() + measured.above == len(section.faces)


def test_meshlab_workflow_example_runs(tmp_path, capsys):
    import runpy

    example = Path(__file__).resolve().parents[1] / "examples" / "meshlab_workflow.py"
    runpy.run_path(str(example))["main"](tmp_path)
    assert "Theorem 1" in capsys.readouterr().out
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(tmp_path / "meshlab_section.ply"))
    quality = ms.current_mesh().face_scalar_array()          # aspect ratio L²/A per face
    assert len(quality) > 100 and quality.max() <= ASPECT_BOUND * (1 + 1e-9)
    assert quality.min() >= (4 / np.sqrt(3)) * (1 - 1e-9)
