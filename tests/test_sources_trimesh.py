"""section / sections on trimesh solids and mesh files: topology, areas, frames, errors."""

import math
import re
from pathlib import Path

import numpy as np
import pytest
import trimesh

from pds_plugin import SectionError, section, sections
from conftest import cracked_stl

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"   # ../shared/data
SEGMENTS = 64


def polygon_area(radius, n=SEGMENTS):
    """Area of the regular n-gon inscribed in a circle: the section of a faceted cylinder."""
    return n / 2 * radius**2 * math.sin(2 * math.pi / n)


def cylinder(radius, height=2.0):
    return trimesh.creation.cylinder(radius=radius, height=height, sections=SEGMENTS)


def nested_part():
    """A ring (r 3..4), an island in its hole (r 1..2) with a hole, and a separate block."""
    block = trimesh.creation.box(extents=(1, 1, 2)).apply_translation([6, 0, 0])
    part = cylinder(4).difference(cylinder(3, 3)).union(cylinder(2)).difference(cylinder(1, 3))
    return part.union(block)


def data_file(name):
    path = DATA / name
    if not path.is_file():
        pytest.skip(f"{path} is not available")
    return path


def lift_rings(region):
    return np.concatenate([region.to_3d(ring) for ring in region.rings])


# --- topology and areas ---

def test_islands_in_holes_and_several_components():
    region = section(nested_part(), plane_origin=(0, 0, 0.3), plane_normal=(0, 0, 1))
    assert region.betti == (3, 2)   # ring, island, block; the ring's hole, the island's hole
    exact = polygon_area(4) - polygon_area(3) + polygon_area(2) - polygon_area(1) + 1
    assert region.area == pytest.approx(exact, rel=1e-6)   # trimesh booleans round to float32


def test_oblique_plane_through_a_cube():
    angle = math.radians(30)
    normal = (0, math.sin(angle), math.cos(angle))   # tilted about x: a 1 x 1/cos(30°) rectangle
    region = section(trimesh.creation.box(), (0, 0, 0), normal)
    assert region.betti == (1, 0)
    assert region.area == pytest.approx(1 / math.cos(angle), rel=1e-12)


@pytest.mark.parametrize("normal, area", [((0, 0, 1), 2.0), ((1, 1, 0), math.sqrt(2))])
def test_plane_through_vertices_and_edges(normal, area):
    """The octahedron |x|+|y|+|z| <= 1 cut through four (or two) of its vertices."""
    octahedron = trimesh.convex.convex_hull(np.vstack([np.eye(3), -np.eye(3)]))
    region = section(octahedron, (0, 0, 0), normal)
    assert region.betti == (1, 0)
    assert region.area == pytest.approx(area, rel=1e-12)


def test_frame_maps_the_section_back_onto_the_plane_and_the_surface():
    mesh = nested_part()
    origin, normal = np.array([0.3, -0.2, 0.1]), np.array([0.2, -0.5, 1.0])
    region = section(mesh, origin, normal)
    xyz = lift_rings(region)
    unit = normal / np.linalg.norm(normal)
    assert np.abs((xyz - origin) @ unit).max() < 1e-12
    _, distance, _ = trimesh.proximity.closest_point(mesh, xyz)
    assert distance.max() < 1e-9
    assert np.allclose(region.frame[:3, :3] @ region.frame[:3, :3].T, np.eye(3), atol=1e-15)
    assert np.array_equal(region.frame[:3, 3], origin)   # the 2D origin is the plane origin


def test_same_plane_same_coordinates():
    mesh = nested_part()
    first = section(mesh, (0, 0, 0.3), (0, 0, 2))
    second = section(mesh.copy(), [0.0, 0.0, 0.3], np.array([0, 0, 5.0]))
    assert np.array_equal(first.frame, second.frame)
    assert first.geometry.equals_exact(second.geometry, tolerance=0)


def test_the_input_mesh_is_not_modified():
    mesh = nested_part()
    vertices, faces = mesh.vertices.copy(), mesh.faces.copy()
    section(mesh, (0, 0, 0.3), (0, 0, 1))
    assert np.array_equal(mesh.vertices, vertices) and np.array_equal(mesh.faces, faces)


@pytest.mark.parametrize("suffix", ["stl", "obj", "ply", "off", "3mf", "glb"])
def test_mesh_files(tmp_path, suffix):
    path = tmp_path / f"part.{suffix}"
    nested_part().export(path)
    region = section(path, (0, 0, 0.3), (0, 0, 1))
    assert region.betti == (3, 2)
    assert region.area == pytest.approx(polygon_area(4) - polygon_area(3) + polygon_area(2)
                                        - polygon_area(1) + 1, rel=1e-6)  # STL stores float32


def test_featuretype_stl_mid_height():
    path = data_file("featuretype.STL")
    z = trimesh.load_mesh(path).bounds[:, 2].mean()
    region = section(str(path), (0, 0, z), (0, 0, 1))
    assert region.betti == (2, 8)


def test_angle_block_stl_mid_height():
    path = data_file("angle_block.STL")
    z = trimesh.load_mesh(path).bounds[:, 2].mean()
    assert section(path, (0, 0, z), (0, 0, 1)).betti[0] == 1


# --- several planes ---

def test_sections_by_count_are_mid_slab_planes_with_shared_axes():
    mesh = cylinder(2, height=4).apply_translation([0, 0, 1])   # z in [-1, 3]
    regions = sections(mesh, (0, 0, 1), count=4)
    assert [r.frame[2, 3] for r in regions] == pytest.approx([-0.5, 0.5, 1.5, 2.5])
    assert all(np.array_equal(r.frame[:3, :2], regions[0].frame[:3, :2]) for r in regions)
    assert all(r.source.area == pytest.approx(polygon_area(2), rel=1e-12) for r in regions)
    assert [r.frame[2, 3] for r in sections(mesh, (0, 0, 1), count=1)] == pytest.approx([1.0])


def test_sections_by_offsets_from_an_origin():
    mesh = trimesh.creation.box(extents=(2, 2, 2))
    regions = sections(mesh, (0, 0, -1), offsets=[0.5, 1.5], plane_origin=(0, 0, 0.7))
    assert [r.frame[2, 3] for r in regions] == pytest.approx([0.2, -0.8])
    assert [r.area for r in regions] == pytest.approx([4, 4])


@pytest.mark.parametrize("keywords, message", [
    ({}, "either offsets"), ({"offsets": [0], "count": 2}, "either offsets"),
    ({"count": 0}, "positive integer"), ({"count": 2.5}, "positive integer"),
    ({"offsets": []}, "non-empty"), ({"offsets": [0, float("nan")]}, "finite"),
])
def test_sections_bad_arguments(keywords, message):
    with pytest.raises(ValueError, match=message):
        sections(trimesh.creation.box(), (0, 0, 1), **keywords)


def test_sections_report_the_plane_that_misses():
    with pytest.raises(ValueError, match=r"misses the solid.*\[-0.5, 0.5\]"):
        sections(trimesh.creation.box(), (0, 0, 1), offsets=[0, 0.75])


# --- errors ---

def test_plane_misses_the_solid_gives_the_extent():
    mesh = trimesh.creation.box(extents=(1, 1, 4)).apply_translation([0, 0, 10])
    with pytest.raises(ValueError, match=r"misses the solid.*normal·x = 0\b.*\[8, 12\]"):
        section(mesh, (0, 0, 0), (0, 0, 1))


@pytest.mark.parametrize("z", [0.5, -0.5, 0.5 - 1e-9])
def test_plane_on_a_face_is_refused_with_advice(z):
    with pytest.raises(ValueError, match="lies on 2 face.*on_face='above' or 'below'"):
        section(trimesh.creation.box(), (0, 0, z), (0, 0, 1))


def test_plane_on_an_inner_step_face_is_refused():
    steps = trimesh.creation.box(extents=(2, 1, 1)).union(
        trimesh.creation.box(extents=(1, 1, 1)).apply_translation([0.5, 0, 1]))
    with pytest.raises(ValueError, match="lies on .* face"):
        section(steps, (0, 0, 0.5), (0, 0, 1))


def test_open_mesh_gives_the_open_ends():
    box = trimesh.creation.box()
    side = np.flatnonzero(np.isclose(box.triangles_center[:, 0], -0.5))[0]   # one face at x = -0.5
    open_box = trimesh.Trimesh(box.vertices, np.delete(box.faces, side, axis=0), process=False)
    corners = box.vertices[box.faces[side]]
    with pytest.raises(ValueError, match=r"is open: the mesh is not watertight.*open end") as error:
        section(open_box, (0, 0, 0.1), (0, 0, 1))
    triples = re.findall(r"\(([-\d.e]+), ([-\d.e]+), ([-\d.e]+)\)", str(error.value))
    ends = np.array(triples, dtype=float)
    assert len(ends) == 2
    assert np.allclose(ends[:, 0], -0.5) and np.allclose(ends[:, 2], 0.1)        # on the gap
    low, high = corners[:, 1].min() - 1e-9, corners[:, 1].max() + 1e-9
    assert ((low <= ends[:, 1]) & (ends[:, 1] <= high)).all()


def spout(start, body=True):
    """A tube along x from ``start`` to 3, closed at x = 3 and open at ``start`` (a
    cylinder without its cap there), with a closed 2-cube about the origin if ``body``:
    a spout pushed into a body without being joined to it."""
    tube = trimesh.creation.cylinder(radius=0.4, segment=[(start, 0, 0), (3, 0, 0)], sections=24)
    kept = tube.face_normals[:, 0] > -0.5                         # no cap at x = start
    tube = trimesh.Trimesh(tube.vertices, tube.faces[kept], process=False)
    return trimesh.util.concatenate([trimesh.creation.box(extents=(2, 2, 2)), tube]) if body \
        else tube


def test_an_open_shell_ending_inside_another_part_is_closed_across_it():
    """The spout's cut is a U from inside the cube round its closed end and back: its
    two ends are in the cube's material. Closed across it (with a warning) the section is
    the union of the square and the spout's strip beyond it, and meshes certified."""
    import pds_plugin as pds

    with pytest.warns(UserWarning, match="1 open shell.*closed across that material"):
        region = section(spout(0.5), (0, 0, 0.05), (0, 0, 1))
    strip = spout(0.5, body=False).section(plane_origin=(0, 0, 0.05),
                                           plane_normal=(0, 0, 1)).vertices[:, 1]
    assert region.betti == (1, 0)
    assert region.area == pytest.approx(4 + 2 * (strip.max() - strip.min()), rel=1e-9)
    mesh = pds.mesh_region(region, "auto", seed=0)
    assert mesh.certificate().ok_with_exceptions


def test_an_open_shell_is_not_closed_across_empty_space():
    """The same spout alone: the U's ends are in no material, and closing it would make
    a boundary the mesh file does not have. Refused, as before."""
    with pytest.raises(ValueError, match="is open: the mesh is not watertight"):
        section(spout(0.5, body=False), (0, 0, 0.05), (0, 0, 1))


def test_open_mesh_is_fine_where_the_plane_does_not_meet_the_gap():
    box = trimesh.creation.box()
    top = np.flatnonzero(np.isclose(box.triangles_center[:, 2], 0.5))
    open_box = trimesh.Trimesh(box.vertices, np.delete(box.faces, top, axis=0), process=False)
    assert section(open_box, (0, 0, 0), (0, 0, 1)).area == pytest.approx(1)


def test_plane_through_a_gap_between_parts():
    parts = trimesh.util.concatenate([trimesh.creation.box(),
                                      trimesh.creation.box().apply_translation([3, 0, 0])])
    with pytest.raises(ValueError, match="cuts no material"):
        section(parts, (1.5, 0, 0), (1, 0, 0))


@pytest.mark.parametrize("origin, normal, error, message", [
    ((0, 0, 0), (0, 0, 0), ValueError, "zero vector"),
    ((0, 0, float("nan")), (0, 0, 1), ValueError, "plane_origin has NaN"),
    ((0, 0, 0), (0, float("inf"), 1), ValueError, "plane_normal has NaN or infinite"),
    ((0, 0), (0, 0, 1), ValueError, "3 numbers"),
    ((0, 0, 0), "up", TypeError, "plane_normal must be 3 numbers"),
])
def test_bad_planes(origin, normal, error, message):
    with pytest.raises(error, match=message):
        section(trimesh.creation.box(), origin, normal)


def test_missing_empty_and_unreadable_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such mesh file"):
        section(tmp_path / "absent.stl", (0, 0, 0), (0, 0, 1))
    empty = tmp_path / "empty.stl"
    empty.write_bytes(b"")
    with pytest.raises(ValueError, match="is empty"):
        section(empty, (0, 0, 0), (0, 0, 1))
    garbage = tmp_path / "garbage.stl"
    garbage.write_text("this is not a mesh")
    with pytest.raises(ValueError, match="has no triangles"):
        section(garbage, (0, 0, 0), (0, 0, 1))
    unknown = tmp_path / "part.xyz"
    unknown.write_text("not a mesh")
    with pytest.raises(ValueError, match="cannot read .* STL, OBJ, PLY"):
        section(unknown, (0, 0, 0), (0, 0, 1))
    drawing = tmp_path / "part.svg"
    drawing.write_text('<svg xmlns="http://www.w3.org/2000/svg"><rect width="1" height="1"/></svg>')
    with pytest.raises(ValueError, match="2D drawing.*load_svg"):
        section(drawing, (0, 0, 0), (0, 0, 1))
    cloud = tmp_path / "cloud.ply"
    trimesh.PointCloud(np.random.default_rng(0).random((10, 3))).export(cloud)
    with pytest.raises(ValueError, match="has no triangles"):
        section(cloud, (0, 0, 0.5), (0, 0, 1))


def test_unsupported_solid_type():
    with pytest.raises(TypeError, match="cannot cut a list"):
        section([[0, 0, 0]], (0, 0, 0), (0, 0, 1))


def test_small_part_far_from_the_origin_cut_obliquely_closes():
    """Intersections are computed relative to the plane, so rounding scales with the part."""
    centre = np.array([123456.789, -234567.891, 34567.8])
    ball = trimesh.creation.icosphere(subdivisions=3, radius=1e-3).apply_translation(centre)
    region = section(ball, centre, (0.3, -0.7, 0.5))
    assert region.betti == (1, 0)
    assert 0.95 * math.pi * 1e-6 < region.area < math.pi * 1e-6
    assert np.abs(np.linalg.norm(lift_rings(region) - centre, axis=1) - 1e-3).max() < 2e-5


def test_offsets_that_are_not_numbers():
    with pytest.raises(ValueError, match="offsets must be"):
        sections(trimesh.creation.box(), (0, 0, 1), offsets=["middle"])


def test_example_runs_on_its_builtin_part(tmp_path):
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "examples" / "section_trimesh.py"
    spec = importlib.util.spec_from_file_location("section_trimesh_example", path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    example.STL = tmp_path / "absent.STL"          # force the built-in part
    example.main(tmp_path)
    written = trimesh.load_mesh(tmp_path / "section_trimesh.ply")
    assert len(written.faces) > 0 and np.abs(written.vertices[:, 2]).max() < 1e-12


def shells(*boxes):
    """One mesh of several box shells (x0, y0, z0, x1, y1, z1), not merged: what
    multi-body STL exports write."""
    meshes = []
    for x0, y0, z0, x1, y1, z1 in boxes:
        box = trimesh.creation.box(extents=(x1 - x0, y1 - y0, z1 - z0))
        meshes.append(box.apply_translation(((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)))
    return trimesh.util.concatenate(meshes)


def test_overlapping_shells_give_their_union():
    """Two overlapping 2x2x2 boxes: the solid (winding number >= 1) is one 3x2 block,
    not the even-odd 2 x (1x2) of the cut curves."""
    region = section(shells((0, 0, 0, 2, 2, 2), (1, 0, 0, 3, 2, 2)), (0, 0, 1), (0, 0, 1))
    assert region.betti == (1, 0)
    assert math.isclose(region.area, 6.0, rel_tol=1e-12)


def test_a_shell_inside_a_shell_is_no_hole_but_an_inward_shell_is_a_void():
    nested = shells((0, 0, 0, 4, 4, 4), (1, 1, 1, 3, 3, 3))
    region = section(nested, (0, 0, 2), (0, 0, 1))
    assert region.betti == (1, 0) and math.isclose(region.area, 16.0, rel_tol=1e-12)
    void = trimesh.creation.box(extents=(1, 1, 1))
    void.invert()                                  # normals inward: a cavity in the solid
    hollow = trimesh.util.concatenate([trimesh.creation.box(extents=(3, 3, 3)), void])
    region = section(hollow, (0, 0, 0), (0, 0, 1))
    assert region.betti == (1, 1) and math.isclose(region.area, 8.0, rel_tol=1e-12)


def test_a_mesh_turned_inside_out_is_read_as_its_solid():
    box = trimesh.creation.box(extents=(2, 2, 2))
    box.invert()
    assert math.isclose(section(box, (0, 0, 0), (0, 0, 1)).area, 4.0, rel_tol=1e-12)


def test_far_plane_origin_keeps_the_holes():
    """The plane origin is the 2D origin: at (1e11, 1e11) the section's coordinates are
    1.4e11 large, but the cut points are joined relative to the part, not to that."""
    path = data_file("featuretype.STL")
    mesh = trimesh.load_mesh(path)
    middle = mesh.bounds.mean(axis=0)
    near = section(path, middle, (0, 0, 1))
    far = section(path, (1e11, 1e11, middle[2]), (0, 0, 1))
    assert far.betti == near.betti == (2, 8)
    assert math.isclose(far.area, near.area, rel_tol=1e-5)


def test_a_stray_part_far_away_does_not_inflate_the_tolerance():
    """A 1-unit box 1e8 away from a 10-unit box with ten 0.2-wide holes: the holes stay."""
    plate = trimesh.creation.box(extents=(10, 10, 1))
    for i in range(10):
        hole = trimesh.creation.box(extents=(0.2, 0.2, 2)).apply_translation((-4.5 + i, 0, 0))
        plate = plate.difference(hole)
    stray = trimesh.creation.box(extents=(1, 1, 1)).apply_translation((1e8, 1e8, 0))
    region = section(trimesh.util.concatenate([plate, stray]), (0, 0, 0), (0, 0, 1))
    assert region.betti == (2, 10)
    assert math.isclose(region.area, 100 - 10 * 0.04 + 1, rel_tol=1e-6)   # shoelace at 1e8


def stepped_block():
    """A 2 x 2 x 1 block with a 1 x 1 x 1 step on top, made with manifold3d: a face at
    exactly half the height, as CAD parts often have."""
    import manifold3d as m3

    part = m3.Manifold.cube((2, 2, 1)) + m3.Manifold.cube((1, 1, 1)).translate((0, 0, 1))
    mesh = part.to_mesh64()
    return trimesh.Trimesh(np.asarray(mesh.vert_properties)[:, :3], mesh.tri_verts)


def test_an_explicit_plane_on_a_face_is_cut_above_or_below_on_request():
    block = stepped_block()
    with pytest.raises(ValueError, match="lies on .* face.*on_face"):
        section(block, (0, 0, 1), (0, 0, 1))
    above = section(block, (0, 0, 1), (0, 0, 1), on_face="above")
    below = section(block, (0, 0, 1), (0, 0, 1), on_face="below")
    assert math.isclose(above.area, 1.0, rel_tol=1e-9) and math.isclose(below.area, 4.0,
                                                                          rel_tol=1e-9)
    assert 0 < above.frame[2, 3] - 1 < 1e-5 and 0 < 1 - below.frame[2, 3] < 1e-5
    with pytest.raises(ValueError, match="on_face must be"):
        section(block, (0, 0, 1), (0, 0, 1), on_face="middle")


def test_a_face_height_typed_rounded_counts_as_on_the_face(tmp_path):
    """An STL part's top face at z = 33.95000076 (float32): the plane at 33.950002, 1.3e-6
    above it (a third of a float32 ulp there, within the file's tolerance), was refused as
    missing the solid with on_face="below"; it is on the top face, and cut just below it.
    Without on_face, and farther than the tolerance, the plane still misses."""
    box = trimesh.creation.box((2.0, 1.0, 0.5))
    box.apply_translation((10.3, 3.7, 33.7))
    path = tmp_path / "box.stl"
    box.export(path)
    top, bottom = 33.95000076293945, 33.45000076293945
    below = section(path, (10.3, 3.7, 33.950002), (0, 0, 1), on_face="below")
    above = section(path, (10.3, 3.7, bottom - 1.3e-6), (0, 0, 1), on_face="above")
    assert math.isclose(below.area, 2.0, rel_tol=1e-6) and math.isclose(above.area, 2.0,
                                                                        rel_tol=1e-6)
    assert 0 < top - below.frame[2, 3] < 1e-4 and 0 < above.frame[2, 3] - bottom < 1e-4
    for z, on_face in ((33.950002, None), (33.951, "below")):
        with pytest.raises(ValueError, match="misses the solid"):
            section(path, (10.3, 3.7, z), (0, 0, 1), on_face=on_face)


def test_automatic_planes_move_off_faces_and_say_so():
    """The middle plane of the stepped block (count=1) is on its step: it moves just
    above it, with a warning, instead of failing."""
    with pytest.warns(UserWarning, match="lies on .* face.*just above"):
        (region,) = sections(stepped_block(), (0, 0, 1), count=1)
    assert math.isclose(region.area, 1.0, rel_tol=1e-9)


def test_a_tiny_part_is_not_on_its_faces():
    """trimesh's absolute tolerance (1e-8) flagged every face of a 1e-9 box."""
    tiny = trimesh.creation.box(extents=(1e-9, 2e-9, 1e-9))
    region = section(tiny, (0, 0, 0), (0, 0, 1))
    assert math.isclose(region.area, 2e-18, rel_tol=1e-9)


def test_a_truncated_binary_stl_and_a_folder_are_named(tmp_path):
    """Was: "No module named 'charset_normalizer'" and "no such file"."""
    data = trimesh.creation.box().export(file_type="stl")
    (tmp_path / "cut.stl").write_bytes(data[:300])
    with pytest.raises(ValueError, match="binary STL cut short.*12 triangles"):
        section(tmp_path / "cut.stl", (0, 0, 0), (0, 0, 1))
    (tmp_path / "folder.stl").mkdir()
    with pytest.raises(IsADirectoryError, match="is a folder"):
        section(tmp_path / "folder.stl", (0, 0, 0), (0, 0, 1))


@pytest.mark.parametrize("flipped", range(12))
def test_one_triangle_the_wrong_way_round_is_reoriented_with_a_warning(flipped):
    """An STL with one reversed triangle used to lose the section ("cuts no material ...
    a gap between parts") when that triangle crossed the plane."""
    box = trimesh.creation.box(extents=(2, 2, 2))
    faces = box.faces.copy()
    faces[flipped] = faces[flipped][::-1]
    mesh = trimesh.Trimesh(box.vertices, faces, process=False)
    given = mesh.faces.copy()
    for origin, normal in [((0, 0, 0.3), (0, 0, 1)), ((0.3, 0, 0), (1, 0, 0)),
                           ((0, 0.3, 0), (0, 1, 0))]:
        with pytest.warns(UserWarning, match="not consistently oriented"):
            region = section(mesh, origin, normal)
        assert region.area == pytest.approx(4.0, rel=1e-12) and region.betti == (1, 0)
    assert np.array_equal(mesh.faces, given)                 # the caller's mesh is untouched


@pytest.mark.parametrize("slot, value, words", [
    (5, 3.4e38, "most of its vertices lie within"),       # along the normal: was "lies on
    (8, -1e30, "most of its vertices lie within"),        # 11 face(s) of the solid"
    (3, -1e30, "a vertex far from the rest"),             # across: was "cuts no material
    (3, 1e12, "a vertex far from the rest"),              # (a gap between parts)"
])
def test_a_stray_vertex_of_a_damaged_stl_is_named(tmp_path, slot, value, words):
    import struct

    data = bytearray(trimesh.creation.box(extents=(2, 2, 2)).export(file_type="stl"))
    where = 84 + 50 * 4 + 4 * slot                           # facet 4, one float
    data[where:where + 4] = struct.pack("<f", value)
    path = tmp_path / "damaged.stl"
    path.write_bytes(bytes(data))
    with pytest.raises(ValueError) as caught:
        section(path, (0, 0, 0.3), (0, 0, 1))
    message = str(caught.value)
    assert words in message and "stray vertices" in message
    assert "gap between parts" not in message and "lies on" not in message


def test_a_far_separate_part_is_not_a_stray_vertex():
    plate = trimesh.creation.box(extents=(10, 10, 1))
    far = trimesh.creation.box(extents=(1, 1, 1)).apply_translation((1e6, 1e6, 0))
    region = section(trimesh.util.concatenate([plate, far]), (0, 0, 0), (0, 0, 1))
    assert region.area == pytest.approx(101.0, rel=1e-9) and region.betti == (2, 0)


def test_an_stl_whose_facets_hold_a_vertex_an_ulp_apart_is_welded_and_cut(tmp_path):
    """Such a file read as open, and every section of it was refused. Its vertices
    within its float noise of each other are merged when that closes it (with a
    warning); a mesh that merging does not close is refused as before."""
    part = trimesh.creation.annulus(r_min=1.0, r_max=2.0, height=1.0, sections=48)
    part.apply_transform(trimesh.transformations.rotation_matrix(0.4, [1, 2, 3]))
    part.export(tmp_path / "intact.stl")
    path = cracked_stl(part, tmp_path / "cracked.stl")
    assert not trimesh.load_mesh(path).is_watertight
    with pytest.warns(UserWarning, match="merged, which closes it"):
        region = section(path, plane_origin=(0, 0, 0), plane_normal=(0, 0, 1))
    intact = section(tmp_path / "intact.stl", plane_origin=(0, 0, 0), plane_normal=(0, 0, 1))
    assert region.betti == intact.betti == (1, 1)
    assert math.isclose(region.area, intact.area, rel_tol=1e-6)
    opened = cracked_stl(trimesh.Trimesh(part.vertices, part.faces[1:]), tmp_path / "open.stl")
    with pytest.raises(SectionError, match="not watertight"):
        section(opened, plane_origin=(0, 0, 0), plane_normal=(0, 0, 1))
