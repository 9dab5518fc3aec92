"""PlanarMesh -> trimesh, PLY and OBJ: round trips through independent readers."""

import numpy as np
import pytest
import trimesh
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.sinks import files as export_module
from pds_plugin.sinks.files import export, register_writer, to_trimesh, writers

# a CAD-like placement: tilted plane, coordinates of a few hundred units, where float32
# storage would move vertices by ~1e-5
FRAME = trimesh.geometry.plane_transform(origin=(250.3, -120.7, 87.1), normal=(1, 2, 3))
FRAME = np.linalg.inv(FRAME)


@pytest.fixture(scope="module")
def mesh():
    plate = box(0, 0, 3, 2).difference(Point(1.5, 1).buffer(0.5))
    return pds.mesh_region(pds.Region.from_shapely(plate, frame=FRAME), alpha=0.15, seed=1)


def test_to_trimesh_lifts_into_the_plane_with_the_aspect_ratio(mesh):
    tm = to_trimesh(mesh)
    np.testing.assert_array_equal(tm.vertices, mesh.vertices_3d)
    np.testing.assert_array_equal(tm.faces, mesh.faces)
    np.testing.assert_array_equal(tm.face_attributes["aspect_ratio"], mesh.quality().aspect_ratio)
    np.testing.assert_array_equal(tm.vertex_attributes["on_boundary"], mesh.on_boundary)
    # the frame is rigid: the 3D mesh lies in the plane and keeps the 2D area
    normal = FRAME[:3, 2]
    assert np.ptp(tm.vertices @ normal) < 1e-9
    assert tm.area == pytest.approx(mesh.quality().area.sum(), rel=1e-12)
    # triangles stay counter-clockwise seen from the plane's normal
    assert (tm.face_normals @ normal > 1 - 1e-9).all()


def test_to_trimesh_does_not_alias_the_mesh(mesh):
    before = mesh.vertices_3d.copy()
    tm = mesh.to_trimesh()
    tm.vertices[:] += 1.0
    tm.face_attributes["aspect_ratio"][:] = 0
    np.testing.assert_array_equal(mesh.vertices_3d, before)
    assert mesh.quality().aspect_ratio.min() > 2


def test_ply_round_trip_through_trimesh(mesh, tmp_path):
    path = tmp_path / "plate.ply"
    mesh.export(path)
    back = trimesh.load(path, process=False)
    np.testing.assert_array_equal(back.vertices, mesh.vertices_3d)   # doubles, bit for bit
    np.testing.assert_array_equal(back.faces, mesh.faces)
    raw = back.metadata["_ply_raw"]
    np.testing.assert_array_equal(raw["face"]["data"]["quality"], mesh.quality().aspect_ratio)
    np.testing.assert_array_equal(raw["vertex"]["data"]["quality"], mesh.on_boundary.astype(float))


def test_ply_layout_is_binary_with_double_quality(mesh, tmp_path):
    path = tmp_path / "plate.ply"
    export(mesh, path)
    data = path.read_bytes()
    header, _, body = data.partition(b"end_header\n")
    assert b"format binary_little_endian 1.0" in header
    assert header.count(b"property double quality") == 2
    n, m = len(mesh.vertices), len(mesh.faces)
    assert len(body) == n * 4 * 8 + m * (1 + 3 * 4 + 8)   # nothing more, nothing less


def test_ply_round_trip_through_pymeshlab(mesh, tmp_path):
    pymeshlab = pytest.importorskip("pymeshlab")
    path = tmp_path / "plate.ply"
    export(mesh, path)
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    back = ms.current_mesh()
    np.testing.assert_array_equal(back.vertex_matrix(), mesh.vertices_3d)
    np.testing.assert_array_equal(back.face_matrix(), mesh.faces)
    np.testing.assert_array_equal(back.face_scalar_array(), mesh.quality().aspect_ratio)
    np.testing.assert_array_equal(back.vertex_scalar_array(), mesh.on_boundary.astype(float))


@pytest.mark.parametrize("suffix", [".obj", ".OBJ"])
def test_obj_round_trip_through_trimesh_and_pymeshlab(mesh, tmp_path, suffix):
    path = tmp_path / f"plate{suffix}"
    export(mesh, path)
    back = trimesh.load(path, file_type="obj", process=False)
    np.testing.assert_array_equal(back.vertices, mesh.vertices_3d)   # 17 digits are exact
    np.testing.assert_array_equal(back.faces, mesh.faces)
    pymeshlab = pytest.importorskip("pymeshlab")
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    np.testing.assert_array_equal(ms.current_mesh().vertex_matrix(), mesh.vertices_3d)
    np.testing.assert_array_equal(ms.current_mesh().face_matrix(), mesh.faces)


@pytest.mark.parametrize("name", ["plate.xyz", "plate", "plate.ply.gz"])
def test_unknown_suffix_names_it_and_the_supported_ones(mesh, tmp_path, name):
    message = r"cannot export to .*supported suffixes are .*\.obj, \.off, \.ply, \.stl"
    with pytest.raises(ValueError, match=message):
        export(mesh, tmp_path / name)
    assert not (tmp_path / name).exists()


def test_missing_directory_is_named(mesh, tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        export(mesh, tmp_path / "nowhere" / "plate.ply")


def test_mesh_without_triangles_is_refused(mesh, tmp_path):
    empty = pds.PlanarMesh(np.array(mesh.vertices[:2]), np.empty((0, 3), dtype=np.int64),
                           np.array(mesh.on_boundary[:2]), mesh.region, mesh.alpha)
    with pytest.raises(ValueError, match="no triangles"):
        export(empty, tmp_path / "empty.ply")


def test_registered_writer_is_used_by_suffix(mesh, tmp_path, monkeypatch):
    monkeypatch.setattr(export_module, "_WRITERS", dict(export_module._WRITERS))

    @register_writer(".XYZ")
    def write_xyz(mesh, path):
        np.savetxt(path, mesh.vertices_3d)

    assert ".xyz" in writers() and writers() == sorted(writers())
    export(mesh, tmp_path / "plate.xyz")
    np.testing.assert_allclose(np.loadtxt(tmp_path / "plate.xyz"), mesh.vertices_3d, rtol=1e-15)
    with pytest.raises(ValueError, match="starts with a dot"):
        register_writer("xyz")


@pytest.mark.parametrize("suffix", [".stl", ".off", ".glb", ".3mf"])
def test_every_format_trimesh_writes(mesh, tmp_path, suffix):
    """Through trimesh, read back by trimesh: the same triangles, in the format's
    precision (STL, GLB and 3MF store float32)."""
    path = tmp_path / f"plate{suffix}"
    export(mesh, path)
    back = trimesh.load(path, force="mesh", process=False)
    assert len(back.faces) == len(mesh.faces)
    assert np.isclose(back.area, to_trimesh(mesh).area, rtol=1e-5)
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


def test_a_failing_writer_leaves_no_file_and_keeps_the_old_one(mesh, tmp_path, monkeypatch):
    monkeypatch.setattr(export_module, "_WRITERS", dict(export_module._WRITERS))

    @register_writer(".half")
    def write_half(mesh, path):
        path.write_text("half a mesh")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        export(mesh, tmp_path / "plate.half")
    assert list(tmp_path.iterdir()) == []
    (tmp_path / "plate.half").write_text("the old file")
    with pytest.raises(KeyboardInterrupt):
        export(mesh, tmp_path / "plate.half")
    assert [p.name for p in tmp_path.iterdir()] == ["plate.half"]
    assert (tmp_path / "plate.half").read_text() == "the old file"


WRITER = """
import sys, pds_plugin as pds
from shapely.geometry import box
mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.002)
print(len(mesh.vertices), len(mesh.faces), flush=True)
sys.stdin.readline()
mesh.export(sys.argv[1])
"""


@pytest.mark.parametrize("suffix", [".ply", ".obj"])
def test_kill_during_export_leaves_the_whole_file_or_none(tmp_path, suffix):
    """SIGKILL at several moments of a ~300k-triangle write: whatever exists under the
    final name is the complete mesh."""
    import subprocess
    import sys
    import time

    path = tmp_path / f"mesh{suffix}"
    for delay in (0.0, 0.05, 0.2):
        path.unlink(missing_ok=True)
        child = subprocess.Popen([sys.executable, "-c", WRITER, str(path)], text=True,
                                 stdin=subprocess.PIPE, stdout=subprocess.PIPE)
        vertices, faces = map(int, child.stdout.readline().split())
        child.stdin.write("go\n")
        child.stdin.flush()
        time.sleep(delay)
        child.kill()
        child.wait()
        if path.exists():
            back = trimesh.load_mesh(path, process=False)
            assert (len(back.vertices), len(back.faces)) == (vertices, faces)
