"""section / sections on manifold3d solids, and agreement with the trimesh backend."""

import math
from pathlib import Path

import numpy as np
import pytest
import trimesh

from pds_plugin import section, sections

m3 = pytest.importorskip("manifold3d")
DATA = Path(__file__).resolve().parents[2] / "shared" / "data"   # ../shared/data
SEGMENTS = 64


def polygon_area(radius, n=SEGMENTS):
    return n / 2 * radius**2 * math.sin(2 * math.pi / n)


def cylinder(radius, height=2.0):
    return m3.Manifold.cylinder(height, radius, circular_segments=SEGMENTS, center=True)


def nested_part():
    """A ring (r 3..4), an island in its hole (r 1..2) with a hole, and a separate block."""
    block = m3.Manifold.cube((1, 1, 2), center=True).translate((6, 0, 0))
    return cylinder(4) - cylinder(3, 3) + cylinder(2) - cylinder(1, 3) + block


def to_manifold(mesh):
    return m3.Manifold(m3.Mesh64(vert_properties=np.asarray(mesh.vertices, np.float64),
                                 tri_verts=np.asarray(mesh.faces, np.uint64)))


def to_trimesh(manifold):
    mesh = manifold.to_mesh64()
    return trimesh.Trimesh(mesh.vert_properties[:, :3], mesh.tri_verts, process=False)


def test_islands_in_holes_and_several_components():
    region = section(nested_part(), (0, 0, 0.3), (0, 0, 1))
    assert region.betti == (3, 2)
    exact = polygon_area(4) - polygon_area(3) + polygon_area(2) - polygon_area(1) + 1
    assert region.area == pytest.approx(exact, rel=1e-12)


@pytest.mark.parametrize("origin, normal", [
    ((0, 0, 0.3), (0, 0, 1)), ((0, 0, 0), (0, 0, -1)), ((0.3, -0.2, 0.1), (0.2, -0.5, 1.0)),
    ((1, 2, 0), (1, 1, 0)), ((0, 0.25, 0), (0, 1, 0)),
])
def test_backends_agree_on_area_topology_and_frame(origin, normal):
    manifold = nested_part()
    with_manifold = section(manifold, origin, normal)
    with_trimesh = section(to_trimesh(manifold), origin, normal)
    assert np.array_equal(with_manifold.frame, with_trimesh.frame)
    assert with_manifold.betti == with_trimesh.betti
    assert with_manifold.area == pytest.approx(with_trimesh.area, rel=1e-12)
    assert with_manifold.geometry.boundary.hausdorff_distance(with_trimesh.geometry.boundary) == 0


def test_backends_agree_on_featuretype_stl():
    path = DATA / "featuretype.STL"
    if not path.is_file():
        pytest.skip(f"{path} is not available")
    mesh = trimesh.load_mesh(path)
    origin = (0, 0, mesh.bounds[:, 2].mean())
    with_trimesh = section(path, origin, (0, 0, 1))
    with_manifold = section(to_manifold(mesh), origin, (0, 0, 1))
    assert with_trimesh.betti == with_manifold.betti == (2, 8)
    assert with_manifold.area == pytest.approx(with_trimesh.area, rel=1e-12)
    assert np.array_equal(with_manifold.frame, with_trimesh.frame)


def test_float64_precision_far_from_the_origin():
    """A 1e-6 section 1e5 units away: float32 (Manifold.slice, Mesh) would ruin it."""
    far = (123456.789, -98765.4321, 5e4)
    tiny = m3.Manifold.cube((1e-3, 1e-3, 1e-3), center=True).translate(far)
    region = section(tiny, far, (0, 0, 1))
    assert region.area == pytest.approx(1e-6, rel=1e-7)
    assert region.to_3d([[0.0, 0.0]])[0] == pytest.approx(far, abs=1e-9)


def test_sections_of_a_manifold():
    cone = m3.Manifold.cylinder(4, 2, 0, circular_segments=SEGMENTS)   # z in [0, 4], r = 2 - z/2
    regions = sections(cone, (0, 0, 1), count=4)
    heights = [0.5, 1.5, 2.5, 3.5]
    assert [r.frame[2, 3] for r in regions] == pytest.approx(heights)
    exact = [polygon_area(2 - z / 2) for z in heights]
    assert [r.source.area for r in regions] == pytest.approx(exact, rel=1e-12)   # the cut
    assert all(r.source_deviation <= r.tolerance for r in regions)    # the region within τ of it


def test_invalid_manifold_status_is_an_error():
    box = trimesh.creation.box()
    open_box = m3.Manifold(m3.Mesh64(vert_properties=np.asarray(box.vertices, np.float64),
                                     tri_verts=np.asarray(box.faces[1:], np.uint64)))
    assert open_box.status() != m3.Error.NoError
    with pytest.raises(ValueError, match="Manifold is invalid .*NotManifold.*repair"):
        section(open_box, (0, 0, 0), (0, 0, 1))


def test_empty_manifold_is_an_error():
    with pytest.raises(ValueError, match="Manifold is empty"):
        section(m3.Manifold(), (0, 0, 0), (0, 0, 1))


@pytest.mark.parametrize("z", [0.5, -0.5])
def test_plane_on_a_face_is_refused_at_top_and_bottom_alike(z):
    # manifold's own slice returns the bottom face but nothing at the top: we refuse both
    with pytest.raises(ValueError, match="lies on 2 face"):
        section(m3.Manifold.cube((1, 1, 1), center=True), (0, 0, z), (0, 0, 1))


def test_plane_misses_a_manifold():
    with pytest.raises(ValueError, match=r"misses the solid.*\[-1, 1\]"):
        section(m3.Manifold.cube((2, 2, 2), center=True), (5, 0, 0), (1, 0, 0))


def test_example_runs_on_its_builtin_part(tmp_path):
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "examples" / "section_manifold.py"
    spec = importlib.util.spec_from_file_location("section_manifold_example", path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    example.STL = tmp_path / "absent.STL"          # force the built-in part
    example.main(tmp_path)
    written = trimesh.load_mesh(tmp_path / "section_manifold.ply")
    normal = np.array([0.0, 1.0, 0.3]) / np.linalg.norm([0.0, 1.0, 0.3])
    assert len(written.faces) > 0 and np.abs(written.vertices @ normal).max() < 1e-12
