"""add_section_meshes: a MeshSet's solid cut by planes, each section meshed and added back
as a layer with face and vertex quality."""

from pathlib import Path

import numpy as np
import pytest
import trimesh

from pds_plugin.analysis.quality import ASPECT_BOUND

pymeshlab = pytest.importorskip("pymeshlab")
from pds_plugin.sinks.meshlab import meshlab_quality  # noqa: E402
from pds_plugin.workflows import add_section_meshes  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def meshset_of(solid: trimesh.Trimesh, name="solid"):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(solid.vertices, solid.faces), name)
    return ms


def test_add_section_meshes_with_count():
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


def test_add_section_meshes_errors():
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
