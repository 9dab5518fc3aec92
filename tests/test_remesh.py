"""pds.remesh (issue 24): planar patches of a CAD mesh remeshed with certified triangles,
the solid kept. Oracles: trimesh's own watertightness, Euler number and volume of the
input, and the input's triangles (every output vertex lies on one)."""

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

import pds_plugin as pds
from conftest import cracked_stl


def bench_module(name):
    """A module of the repository's bench/ folder (its generated parts are inputs here)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    return importlib.import_module(name)


def part_with_hole(sections=24):
    """A 4 x 3 x 1 plate with a through hole and a pocket, as a float32 STL would give it."""
    manifold3d = pytest.importorskip("manifold3d")
    plate = manifold3d.Manifold.cube([4.0, 3.0, 1.0])
    hole = manifold3d.Manifold.cylinder(3.0, 0.5, 0.5, sections).translate([1.2, 1.5, -1.0])
    pocket = manifold3d.Manifold.cube([1.2, 1.0, 0.6]).translate([2.4, 1.0, 0.5])
    mesh = (plate - hole - pocket).to_mesh()
    vertices = np.asarray(mesh.vert_properties[:, :3], dtype=np.float32).astype(np.float64)
    return trimesh.Trimesh(vertices, np.asarray(mesh.tri_verts), process=True)


def _on_input(result, source):
    """Largest distance from an output vertex to the input surface."""
    _, distance, _ = trimesh.proximity.closest_point(source, result.mesh.vertices)
    return float(distance.max())


def test_a_box_is_remeshed_certified_with_its_solid_kept():
    box = trimesh.creation.box((2.0, 1.0, 0.5))
    result = pds.remesh(box, 0.15, seed=0)
    assert result.ok, str(result)
    assert result.watertight == (True, True) and result.euler_number == (2, 2)
    assert abs(result.mesh.volume - box.volume) <= 1e-12 * box.volume
    assert result.angles().min() >= 30 - 1e-9
    assert (result.patch >= 0).all() and len(result.certificates) == 6
    assert _on_input(result, box) <= 1e-12
    assert len(result.mesh.faces) > 20 * len(box.faces)


def test_a_part_with_a_hole_and_a_pocket_keeps_its_solid():
    source = part_with_hole()
    result = pds.remesh(source, 0.12, seed=1)
    assert result.ok_with_exceptions and result.solid_ok, str(result)
    assert result.watertight == (True, True)
    assert result.euler_number == (source.euler_number,) * 2
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * source.volume
    assert _on_input(result, source) <= 1e-9
    assert (result.patch == -1).any()             # the hole's strips are kept
    kept_area = result.mesh.area_faces[result.patch == -1].sum()
    assert 0 < kept_area < 0.5 * result.mesh.area
    # the remeshed triangles: only corners of the input below 30 degrees
    angles = result.angles()
    assert np.percentile(angles, 5) >= 30 - 1e-9
    for certificate in result.certificates:
        assert certificate.ok_with_exceptions
        assert all(e.meets_bound for e in certificate.exceptions)


def test_graded_patches_grade_towards_a_finely_tessellated_hole():
    """A hole of 96 sections at alpha = 0.12: its vertices (kept strips beside them) are
    samples 0.033 apart. Uniform patches meet them at alpha with slivers; graded ones
    (the default) grade away from them: the issue's targets, no remeshed triangle under
    20° (the part has no sharp corner) and the 1st percentile at least 25°, every patch
    certified (the graded certificate, against its field)."""
    source = part_with_hole(96)
    graded = pds.remesh(source, 0.12, seed=1)
    assert graded.solid_ok and graded.ok_with_exceptions, str(graded)
    assert abs(graded.mesh.volume - source.volume) <= 1e-9 * source.volume
    assert _on_input(graded, source) <= 1e-9
    angles = graded.angles()
    assert angles.min() >= 20 and np.percentile(angles, 1) >= 25
    assert all(c.unit == "r" and c.min_angle >= c.proven_angle - 1e-9
               for c in graded.certificates)


def test_uniform_patches_fit_the_short_pieces_the_input_forces():
    """Uniform (graded=False): alpha everywhere but at the hole's 96 kept vertices, 0.033
    apart at alpha = 0.12, where a triangle at alpha would have an angle of
    arcsin(0.033 / 0.24) = 8°; r there is the pieces' length and grows away from them,
    so the issue's targets hold as graded, every patch certified against its field; far
    from the hole r is alpha (graded, it also follows the patch's own walls and
    corners)."""
    source = part_with_hole(96)
    uniform = pds.remesh(source, 0.12, seed=1, graded=False)
    assert uniform.solid_ok and uniform.ok_with_exceptions, str(uniform)
    assert not uniform.graded
    assert abs(uniform.mesh.volume - source.volume) <= 1e-9 * source.volume
    angles = uniform.angles()
    assert angles.min() >= 20 and np.percentile(angles, 1) >= 25
    smallest = []
    for mesh, certificate in zip(uniform.patch_meshes, uniform.certificates):
        assert certificate.unit == "r" and certificate.min_angle >= certificate.proven_angle - 1e-9
        r = mesh.field(mesh.vertices)            # alpha away from the short pieces
        assert mesh.field.cap == 0.12 and r.max() == 0.12
        smallest.append(r.min())
    assert min(smallest) < 0.05
    # the same field shape at another grading, which only the cones use
    steeper = pds.remesh(source, 0.12, seed=1, graded=False, grading=0.3)
    assert steeper.ok_with_exceptions and steeper.patch_meshes[0].field.grading == 0.3


def block_with_thin_wall():
    """A 10 x 10 x 2 block whose top and bottom faces keep a wall 0.2 thin beside a slot."""
    block = trimesh.creation.box((10, 10, 2), trimesh.transformations.translation_matrix((5, 5, 1)))
    slot = trimesh.creation.box((8, 3, 4), trimesh.transformations.translation_matrix((5, 1.7, 1)))
    return block.difference(slot)


def test_uniform_patches_grade_at_walls_thinner_than_alpha():
    """A block whose top and bottom faces keep a wall 0.2 alpha thin beside a slot (a
    milled flat beside a tessellated cylinder's facet gives such faces). At r = alpha
    the wall's triangles fall to 11° (thin-wall exceptions, within their bound but not at
    a sharp input corner, which the issue's targets excuse alone); those two faces take
    their graded field, the others stay at alpha where the cones do not reach."""
    from pds_plugin.sizing import angle_bound

    source = block_with_thin_wall()
    uniform = pds.remesh(source, 1.0, graded=False)
    assert uniform.ok, str(uniform)
    assert abs(uniform.mesh.volume - source.volume) <= 1e-9 * source.volume
    assert uniform.angles().min() >= angle_bound(0.2) - 1e-9
    assert not any(c.exceptions for c in uniform.certificates)
    lowest = sorted(float(mesh.field(mesh.vertices).min()) for mesh in uniform.patch_meshes)
    assert lowest[1] <= 0.9 * 0.2 + 1e-9                # both faces with the wall, graded
    assert lowest[-1] == 1.0                            # the far side, at alpha


def test_walls_thinner_than_alpha_are_seen_before_any_patch_is_meshed(monkeypatch):
    """The wall's faces have boundary samples 0.2 alpha apart across it: they take their
    graded field before the patches are meshed (one round of meshing, not two), and the
    mesh has no exception, as when the wall was found in the mesh."""
    from pds_plugin import remeshing

    source = block_with_thin_wall()
    rounds, meshed = [], remeshing._patch_meshes
    monkeypatch.setattr(remeshing, "_patch_meshes",
                        lambda *args: rounds.append(1) or meshed(*args))
    uniform = pds.remesh(source, 1.0, graded=False)
    assert uniform.ok and len(rounds) == 1, str(uniform)
    assert not any(c.exceptions for c in uniform.certificates)
    lowest = sorted(float(mesh.field(mesh.vertices).min()) for mesh in uniform.patch_meshes)
    assert lowest[1] <= 0.9 * 0.2 + 1e-9                # both faces with the wall, graded


def test_a_thin_wall_and_chords_that_cannot_join_take_one_more_round_of_chains(monkeypatch):
    """Held-out cross-drilled block 4401/28, uniform: its first round of chains finds
    patches whose chords cannot join (kept) and a patch with a wall thinner than alpha
    (graded). Both changes take the next round: two rounds of chains, where the wall
    found a round later cost a third."""
    from pds_plugin import remeshing

    pytest.importorskip("manifold3d")
    _, source, _ = bench_module("remesh_vs_meshlab").held_out_part(4401, 28)
    found, walled = [], remeshing._thin_walled
    monkeypatch.setattr(remeshing, "_thin_walled",
                        lambda *a: found.append(walled(*a)) or found[-1])
    joinable, joins = [], remeshing._chords_joinable
    monkeypatch.setattr(remeshing, "_chords_joinable",
                        lambda *a: joinable.extend(joins(*a)) or joins(*a))
    rounds, sample = [], remeshing.graded_sample_chains        # where each round starts
    monkeypatch.setattr(remeshing, "graded_sample_chains", lambda *a, **k: rounds.append(
        (len(joinable), len(found))) or sample(*a, **k))
    uniform = pds.remesh(source, "auto", graded=False, seed=28)
    assert uniform.ok_with_exceptions and uniform.solid_ok, str(uniform)
    assert len(rounds) == 2
    assert not all(joinable[:rounds[1][0]]) and any(found[:rounds[1][1]])   # round one


def test_uniform_patches_grade_along_spikes_sharper_than_the_bound():
    """A wedge whose top and bottom are 2.4° needles 60 long (a tessellated tube's thin
    facet triangle, held-out 4404/39): at r = alpha its mesh has 38 triangles at the
    spike, excused as a sharp corner, and they were 1 % of the remesh's (1st percentile
    8.3°). The needles take their graded field, which shrinks r with the spike."""
    from shapely.geometry import Polygon

    source = trimesh.creation.extrude_polygon(Polygon([(0, 0), (60, 1.25), (60, -1.25)]), 3.0)
    uniform = pds.remesh(source, 1.0, graded=False)
    assert uniform.ok_with_exceptions and uniform.solid_ok, str(uniform)
    assert np.percentile(uniform.angles(), 1) >= 25
    assert all(e.cause == "sharp corner" and e.meets_bound
               for c in uniform.certificates for e in c.exceptions)
    radii = sorted((mesh.field(mesh.vertices) for mesh in uniform.patch_meshes), key=np.min)
    assert radii[1].min() < 0.1                          # both needles graded
    assert np.median(radii[-1]) == 1.0                   # the base: alpha but at the cones


def test_graded_facets_of_a_tessellated_cylinder_are_meshed_at_alpha():
    """A shaft with a milled flat, its cylinder in 24 facets 1.6 alpha wide. A facet's
    walls and corners are the tessellation's (its long sides are folds of 15° to the
    next facet): graded to them it had r down to 0.31 alpha and more triangles than
    uniform. Facets (half their boundary on folds) take alpha as uniform patches do,
    with every angle at least 30°; the caps, with the flat's sharp corners, and the
    facets beside the flat stay graded. The solid is kept and every patch certified."""
    from pds_plugin.remeshing import _min_angles

    cylinder = trimesh.creation.cylinder(radius=3.0, height=4.0, sections=24)
    source = cylinder.difference(trimesh.creation.box(
        (2, 8, 6), trimesh.transformations.translation_matrix((3.5, 0, 0))))
    graded = pds.remesh(source, 0.5)
    assert graded.graded and graded.solid_ok and graded.ok_with_exceptions, str(graded)
    assert abs(graded.mesh.volume - source.volume) <= 1e-9 * source.volume
    at_alpha = [m for m in graded.patch_meshes if not len(m.field.sizes)]
    assert len(at_alpha) >= 14
    assert all(m.field(m.vertices).min() == 0.5 for m in at_alpha)
    assert min(_min_angles(m.vertices, m.faces).min() for m in at_alpha) >= 30 - 1e-9
    shaped = [m for m in graded.patch_meshes if len(m.field.sizes)]
    assert min(m.field(m.vertices).min() for m in shaped) < 0.5 * 0.9


def test_the_command_line_remeshes_graded_or_uniform(tmp_path):
    import json

    from pds_plugin.cli import main

    trimesh.creation.box((2.0, 1.0, 0.5)).export(tmp_path / "box.stl")
    for flags, graded in (([], True), (["--uniform"], False)):
        report = tmp_path / f"report{len(flags)}.json"
        assert main(["remesh", str(tmp_path / "box.stl"), "-o", str(tmp_path / "out.ply"),
                     "--alpha", "0.2", "--report", str(report), *flags]) == 0
        values = json.loads(report.read_text())
        assert values["graded"] is graded and values["ok"]
        assert all("grading" in c for c in values["certificates"])


def test_the_command_line_refuses_an_output_it_cannot_write_before_remeshing(tmp_path, capsys):
    """A suffix trimesh writes no triangle mesh to (.xyz: point clouds) is refused by the
    argument parser, with the suffixes it takes; it raised trimesh's "object must be
    PointCloud" after the whole remesh."""
    from pds_plugin.cli import main

    trimesh.creation.box().export(tmp_path / "box.stl")
    assert main(["remesh", str(tmp_path / "box.stl"), "-o", str(tmp_path / "out.xyz")]) == 2
    assert "give a file ending in .stl, .ply, .obj" in capsys.readouterr().err
    assert not (tmp_path / "out.xyz").exists()


def test_the_same_seed_gives_the_same_mesh():
    box = trimesh.creation.box((1.0, 1.0, 1.0))
    first, again = pds.remesh(box, 0.2, seed=5), pds.remesh(box, 0.2, seed=5)
    assert np.array_equal(first.mesh.vertices, again.mesh.vertices)
    assert np.array_equal(first.mesh.faces, again.mesh.faces)


def test_the_input_is_not_modified_and_a_meshset_round_trips(tmp_path):
    pytest.importorskip("pymeshlab")
    box = trimesh.creation.box((1.0, 2.0, 1.0))
    before = box.vertices.copy()
    result = pds.remesh(box, 0.3)
    assert np.array_equal(box.vertices, before)
    meshset = result.to_meshset()
    assert meshset.current_mesh().face_number() == len(result.mesh.faces)
    again = pds.remesh(meshset, 0.3)
    assert again.solid_ok and again.watertight == (True, True)
    path = tmp_path / "box.stl"
    box.export(path)
    assert pds.remesh(path, 0.3).solid_ok


def test_bad_input_gets_a_clear_error():
    with pytest.raises(pds.ArgumentTypeError, match="trimesh.Trimesh"):
        pds.remesh([1, 2, 3], 0.1)
    with pytest.raises(pds.ArgumentError, match="'auto'"):
        pds.remesh(trimesh.creation.box(), "fine")
    with pytest.raises(FileNotFoundError):
        pds.remesh("no-such-file.stl", 0.1)


def test_an_open_surface_keeps_its_rim():
    box = trimesh.creation.box((1.0, 1.0, 1.0))
    open_box = trimesh.Trimesh(box.vertices, box.faces[2:], process=True)   # one side off
    result = pds.remesh(open_box, 0.2)
    assert result.ok, str(result)
    assert result.watertight == (False, False) and result.euler_number == (1, 1)
    outline = result.mesh.outline()           # the same square rim, sampled
    assert outline.length == pytest.approx(open_box.outline().length, rel=1e-12)
    assert len(outline.entities) == 1 and len(outline.entities[0].points) > 5


def test_a_curved_solid_without_planar_faces_is_kept_as_it_is():
    sphere = trimesh.creation.icosphere(2)
    result = pds.remesh(sphere, 0.3)
    assert result.solid_ok and len(result.certificates) == 0
    assert (result.patch == -1).all()
    assert len(result.mesh.faces) == len(sphere.faces)
    assert result.mesh.volume == pytest.approx(sphere.volume, rel=1e-12)


def test_a_spike_face_is_remeshed_with_mirror_pairs():
    """A 5° prism: its triangular faces are spikes whose tips are junctions of three
    patches; their two sides are chains of their own, sampled in mirror pairs so that
    every chord joins (without them the faces were left as they were)."""
    manifold3d = pytest.importorskip("manifold3d")
    tip = np.radians(5.0)
    outline = manifold3d.CrossSection([[(0, 0), (3, 0), (3 * np.cos(tip), 3 * np.sin(tip))]])
    solid = manifold3d.Manifold.extrude(outline, 1.0).to_mesh()
    prism = trimesh.Trimesh(solid.vert_properties[:, :3], solid.tri_verts)
    result = pds.remesh(prism, 0.1, seed=0)
    assert result.ok_with_exceptions and result.kept_patches == 0, str(result)
    assert result.angles().min() >= 5.0 - 1e-6            # the tip's own angle
    for certificate in result.certificates:
        assert all(e.meets_bound for e in certificate.exceptions)


def random_cut_block(seed):
    """A 40 x 30 x 12 block less one to four boxes and prisms (6 to 40 sides) at random
    places, every other one rotated by random angles, its vertices float32 (an STL)."""
    manifold3d = pytest.importorskip("manifold3d")
    rng = np.random.default_rng(seed)
    body = manifold3d.Manifold.cube([40.0, 30.0, 12.0])
    for k in range(rng.integers(1, 5)):
        if rng.random() < 0.5:
            size = rng.uniform(4, 15, 3)
            tool = manifold3d.Manifold.cube(size.tolist()).translate((-size / 2).tolist())
        else:
            radius = rng.uniform(2, 7)
            tool = manifold3d.Manifold.cylinder(30.0, radius, radius, int(rng.integers(6, 41)))
            tool = tool.translate([0, 0, -15.0])
        if k % 2:
            tool = tool.rotate(rng.uniform(0, 90, 3).tolist())
        body = body - tool.translate([rng.uniform(0, 40), rng.uniform(0, 30),
                                      rng.uniform(0, 12)])
    mesh = body.to_mesh()
    vertices = np.asarray(mesh.vert_properties[:, :3], dtype=np.float32).astype(np.float64)
    return trimesh.Trimesh(vertices, np.asarray(mesh.tri_verts), process=True)


def test_a_sharp_corner_where_faces_meet_is_certified_or_the_patch_kept():
    """Random cut block 1: a rotated cut leaves a face with a sharp corner where three
    patches meet, whose graded legs' samples came closer than their clearance (an
    unexplained pair: that patch's certificate failed). A patch with a corner under 33.56°
    (where rings get mirror pairs and graded chains do not) is certified as it is meshed and kept if its certificate does not hold, so every
    remeshed patch is certified, and every remeshed triangle under 20° is one of its
    certificate's exceptions (a sharp input corner, within its bound)."""
    source = random_cut_block(1)
    result = pds.remesh(source, "auto", seed=1)
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * source.volume
    for mesh, certificate in zip(result.patch_meshes, result.certificates):
        smallest = mesh.quality().angles.reshape(-1, 3).min(axis=1)
        excused = {e.triangle for e in certificate.exceptions if e.meets_bound}
        assert set(np.flatnonzero(smallest < 20).tolist()) <= excused


@pytest.fixture(scope="module")
def block_6():
    """Random cut block 6, remeshed with seed 6: a strip of a face whose lower chain
    meets a finely graded neighbour and whose upper chain was cut at alpha."""
    source = random_cut_block(6)
    return source, pds.remesh(source, "auto", seed=6)


def test_patches_read_the_same_radius_at_every_vertex_they_share(block_6):
    """Each patch is meshed with its own field combined with cones at its chain samples;
    a cone of a sample whose r a neighbour lowered reached the patch's other chains,
    which the patches beyond did not see (block 6: 0.29 against 0.51 at the same
    sample). The fields must agree at every shared sample (docs/remesh.md, step 3)."""
    _, result = block_6
    faces = result.mesh.faces
    read = {}
    for k, mesh in enumerate(result.patch_meshes):
        radius = mesh.field(mesh.vertices)
        local, out = mesh.faces.ravel(), faces[result.patch == k].ravel()
        for vertex, r in zip(out.tolist(), radius[local].tolist()):
            read.setdefault(vertex, {})[k] = r
    shared = [list(by_patch.values()) for by_patch in read.values() if len(by_patch) > 1]
    assert shared
    assert all(max(r) <= min(r) * (1 + 1e-9) for r in shared)


def test_a_strip_between_fine_and_coarse_chains_is_certified(block_6):
    """Block 6's strip had chords cut for r = 0.51 where its field read 0.29: twice its
    r long, the point between their ends was 1.00015 r from every sample (the sampler
    places none in a chord's lens). Every patch certificate holds now."""
    source, result = block_6
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * source.volume
    assert max(c.coverage_gap for c in result.certificates) <= 1 + 1e-9


@pytest.mark.parametrize("seed", [44, 66])
def test_random_blocks_beside_spikes_and_fine_neighbours_are_certified(seed):
    """Block 66 failed like block 6 (1.07 r: its patches' fields disagreed); block 44,
    once they agreed, at a patch with a 90° corner where its neighbour has a 32° spike:
    the chain leaving the spike keeps its first part long, twice the r at the spike, and
    the graded sampler keeps out of that chord's lens (limit the smaller end's r /
    (1 - L)) where the certificate excuses only r(x) / (1 - L) (1.013 r). Such a patch
    is certified as it is meshed and kept if its certificate does not hold."""
    source = random_cut_block(seed)
    result = pds.remesh(source, "auto", seed=seed)
    assert result.solid_ok and result.ok_with_exceptions, str(result)


def test_a_chain_part_is_halved_where_r_dips_between_its_ends():
    """Random cut block 55: a chain's part 0.81 long beside a patch's sharp corner had r
    0.41 at its ends but 0.374 at its middle (a cone of the agreeing fields sits on it),
    so its middle was 1.015 r from both ends, and the corner left no room for a sample
    beside it (FAILED). A part is halved when longer than twice the smallest r at its
    ends and its middle."""
    source = random_cut_block(55)
    result = pds.remesh(source, "auto", seed=55)
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert max(c.coverage_gap for c in result.certificates) <= 1 + 1e-9


def tilted_float32_part(builder, seed):
    """A generated CAD part (bench/_cad_corpus) turned by random angles and written as a
    float32 STL, read back: its planar faces are planar to their rounding only."""
    pytest.importorskip("manifold3d")
    _cad_corpus = bench_module("_cad_corpus")
    rng = np.random.default_rng(seed)
    return tilted_float32(getattr(_cad_corpus, builder)(rng), rng)


def tilted_float32(solid, rng):
    """A manifold3d solid turned by random angles (``rng``), written as a float32 STL
    and read back."""
    import io

    from trimesh.transformations import random_rotation_matrix

    shape = solid.to_mesh()
    turn = random_rotation_matrix(rand=rng.random(3))[:3, :3]
    vertices = np.asarray(shape.vert_properties[:, :3], float) @ turn.T
    written = trimesh.Trimesh(vertices.astype(np.float32), np.asarray(shape.tri_verts),
                              process=False).export(file_type="stl")
    return trimesh.load(io.BytesIO(written), file_type="stl")


@pytest.mark.parametrize("builder, seed, graded", [("filleted_plate", [4101, 1], True),
                                                   ("filleted_plate", [4101, 1], False),
                                                   ("housing", [4102, 17], False)])
def test_a_tilted_float32_part_keeps_its_volume(builder, seed, graded):
    """Held-out parts, tilted and rounded to float32. A filleted plate (seed 4101, part
    1): its remeshed top and bottom faces, whose vertices lie on the input triangles,
    cut across their rounding creases and changed the volume by 2.6e-9 (graded) and
    3.9e-9 (uniform); each patch's interior points now move along its normal, within
    the coplanarity tolerance, until its triangles bound its input faces' volume. A
    housing (seed 4102, part 17, 1.8e-9 uniform): quads bent by up to the tolerance,
    with two interior points or none, cannot undo their change that way and are kept."""
    source = tilted_float32_part(builder, seed)
    result = pds.remesh(source, "auto", graded=graded, seed=seed[1])
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * abs(source.volume)
    assert _on_input(result, source) <= result.tolerance
    assert result.mesh.is_watertight and result.mesh.euler_number == source.euler_number


def test_an_i_beam_keeps_its_volume_summed_about_one_point():
    """A held-out I-beam (51 high, flanges 16.5 x 2.9, web 1.6, 124 long, four holes
    through its web), tilted and rounded to float32, uniform "auto": its patches'
    volume changes, each measured about its own origin, summed to 2e-14 of the volume
    where the solid's changed by 1.3e-9 (found at another turn; 1.02e-9 at this one),
    past the 1e-9 kept. A patch's new boundary is its chains' samples, which skip the
    chains' bent input vertices, so only the sum about one point is the solid's change;
    measured so, the moves undo it (1e-15)."""
    m3 = pytest.importorskip("manifold3d")
    h, b, web, flange, length = 51.258815, 16.505703, 1.621421, 2.928053, 124.214677
    profile = (m3.CrossSection.square((b, flange))
               + m3.CrossSection.square((b, flange)).translate((0, h - flange))
               + m3.CrossSection.square((web, h)).translate((b / 2 - web / 2, 0)))
    beam = profile.extrude(length)
    for k in range(4):
        hole = m3.Manifold.cylinder(2 * b, 0.2 * h, 0.2 * h, 48).rotate((0, 90, 0))
        beam = beam - hole.translate((-b / 2, h / 2, (k + 1) * length / 7))
    source = tilted_float32(beam, np.random.default_rng(7))
    result = pds.remesh(source, "auto", graded=False, seed=0)
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * abs(source.volume)


def test_a_solid_of_two_bodies_sharing_an_edge_keeps_that_edge_and_is_certified():
    """Two boxes touching along an edge (shared.STL's case, and a held-out bracket whose
    float32 rounding merged two vertices): that edge has four triangles in the input.
    The patches along it are kept, so the output has the same edge with the same four
    triangles; the interface check counts it as the input's own (``inherited_edges``)
    instead of failing the remesh, and still fails a defect the remesh would add."""
    from pds_plugin.partition import interface_report

    first = trimesh.creation.box((1.0, 1.0, 1.0))
    second = trimesh.creation.box((1.0, 1.0, 1.0)).apply_translation((1.0, 1.0, 0.0))
    source = trimesh.util.concatenate([first, second])
    source.merge_vertices()
    assert (np.unique(np.sort(source.edges, axis=1), axis=0, return_counts=True)[1] == 4).any()
    result = pds.remesh(source, 0.15, seed=0)
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    # the edge of four triangles, and each of its directions run by two of them
    assert result.interfaces.inherited_edges == 3 and "non-manifold edge" in str(result)
    assert result.euler_number[0] == result.euler_number[1]
    assert abs(result.mesh.volume - source.volume) <= 1e-12 * source.volume
    # an edge with more triangles than the input had is still a problem
    from pds_plugin.remeshing import _inherited

    faces, count = np.asarray(source.faces), len(source.vertices)
    runs, edges = _inherited(faces, count, np.ones(count, bool), np.arange(count))
    assert len(runs) == 2 and edges[:, 2].tolist() == [4]
    outer = np.zeros(count, bool)
    assert interface_report(source.vertices, faces, [], outer, (runs, edges)).ok
    fewer = edges - [0, 0, 1]
    assert not interface_report(source.vertices, faces, [], outer, (runs, fewer)).ok
    assert not interface_report(source.vertices, faces, [], outer).ok


def test_a_solid_wound_inconsistently_is_compared_with_itself():
    """multibody.stl's second body has faces wound against the rest: the signed volume of
    such a surface depends on the point it is taken about, and taken about each mesh's
    own vertex mean the input and the remesh differed by 0.76 of it (FAILED). Both are
    taken about the input's vertex mean now; the remesh keeps it to rounding."""
    path = Path(__file__).resolve().parents[2] / "shared" / "data" / "multibody.stl"
    if not path.exists():
        pytest.skip("../shared/data/multibody.stl is absent")
    source = trimesh.load_mesh(path)
    assert not source.is_winding_consistent
    result = pds.remesh(source, seed=0)
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert result.volume_error <= 1e-12
    assert result.turned > 0 and result.mesh.is_winding_consistent


def test_faces_wound_against_their_neighbours_are_turned_first():
    """Every third face of a box turned (an exporter's slip): its coplanar faces were
    patches of their own that met edge to edge the same way round, and the remesh said
    FAILED. They are turned on the remesh's copy, each body outward; the result says
    how many, and the mesh is the consistent box's, volume and all."""
    box = trimesh.creation.box((2, 1, 1)).subdivide()
    faces = box.faces.copy()
    faces[::3] = faces[::3, ::-1]
    given = trimesh.Trimesh(box.vertices, faces, process=False)
    assert not given.is_winding_consistent
    result = pds.remesh(given, 0.2)
    assert result.ok, str(result)
    assert result.turned == len(faces[::3]) and "turned first" in str(result)
    assert result.mesh.is_winding_consistent
    assert result.mesh.volume == pytest.approx(2.0, rel=1e-12)
    assert np.array_equal(given.faces, faces)                 # the input is not modified
    assert pds.remesh(box, 0.2).turned == 0


def test_faces_naming_a_vertex_twice_are_dropped_and_the_solid_checked():
    """A face [a, a, b] (no area) runs its edge ab both ways, so ab bounds four faces and
    a closed box read as open: its volume was not checked (watertight False -> False,
    volume error nan). Dropped first, the box is closed and its volume kept."""
    box = trimesh.creation.box((2, 1, 1))
    a, b = box.faces[0, :2]
    given = trimesh.Trimesh(box.vertices, np.vstack([box.faces, [[a, a, b]]]), process=False)
    faces = given.faces.copy()
    assert not given.is_watertight
    result = pds.remesh(given, 0.2)
    assert result.ok, str(result)
    assert result.dropped == 1 and "dropped first" in str(result)
    assert result.watertight == (True, True) and result.euler_number == (2, 2)
    assert result.volume_error <= 1e-12
    assert np.array_equal(given.faces, faces)                 # the input is not modified
    assert pds.remesh(box, 0.2).dropped == 0


def test_an_opencascade_export_of_a_ball_and_fillets_is_closed_and_kept(tmp_path):
    """OpenCASCADE's tessellation (FreeCAD's, CadQuery's STL) leaves a face naming one
    vertex twice at a sphere's pole and at each corner where three fillets blend: such
    exports are remeshed as the closed solids they are."""
    pytest.importorskip("OCP", reason="OCP (the [step] extra) is not installed")
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakeSphere
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    from OCP.StlAPI import StlAPI_Writer
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    knob = BRepAlgoAPI_Fuse(BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 30), 12).Shape(),
                            BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)),
                                                     5, 24).Shape()).Shape()
    block = BRepAlgoAPI_Cut(BRepPrimAPI_MakeBox(60, 40, 20).Shape(), BRepPrimAPI_MakeCylinder(
        gp_Ax2(gp_Pnt(30, 20, -1), gp_Dir(0, 0, 1)), 8, 30).Shape()).Shape()
    fillet, edges = BRepFilletAPI_MakeFillet(block), TopExp_Explorer(block, TopAbs_EDGE)
    while edges.More():
        fillet.Add(3.0, TopoDS.Edge(edges.Current()))
        edges.Next()
    for name, shape in (("knob", knob), ("filleted", fillet.Shape())):
        BRepMesh_IncrementalMesh(shape, 0.05, False, 0.3, True)
        path = tmp_path / f"{name}.stl"
        StlAPI_Writer().Write(shape, str(path))
        result = pds.remesh(str(path))
        assert result.dropped >= 1, name
        assert result.watertight == (True, True), str(result)
        assert result.volume_error <= 1e-9 and result.ok_with_exceptions, str(result)
        assert result.angles().min() >= 20


def test_a_tilted_part_read_from_text_finds_its_planar_faces(tmp_path):
    """An ASCII STL keeps a few decimal digits ("%.6e": 7), so a tilted planar face is
    flat only to its last digit, far above float64's noise: its faces were patches of
    their own (1,889 patches instead of 483, 1st percentile 15.5°). The tolerance is
    the noise of the digits the file holds now (sources.solids.stored_precision)."""
    pytest.importorskip("manifold3d")
    _, binary, _ = bench_module("remesh_vs_meshlab").held_out_part(4401, 3)   # turned
    path = tmp_path / "flange.stl"
    corner = "vertex %.6e %.6e %.6e\n"
    path.write_text("solid flange\n" + "".join(
        "facet normal 0 0 0\nouter loop\n" + "".join(corner % tuple(binary.vertices[v])
                                                     for v in face) + "endloop\nendfacet\n"
        for face in binary.faces) + "endsolid flange\n")
    text, read = pds.remesh(str(path), seed=3), pds.remesh(binary, seed=3)
    assert text.ok and text.patches == read.patches and text.kept_patches == read.kept_patches
    assert np.percentile(text.angles(), 1) >= 25
    assert text.tolerance > 1e6 * np.spacing(88.0)


def test_an_stl_whose_facets_hold_a_vertex_an_ulp_apart_is_welded_first(tmp_path):
    """An exporter that writes each facet's corners on its own can leave one vertex a
    float32 unit in the last place apart in two facets: the part read as open, and its
    remesh kept 1,715 of its patches (1st percentile 14.8°). Merged within the float
    noise it is closed, and remeshed as the intact part is."""
    pytest.importorskip("manifold3d")
    _, part, _ = bench_module("remesh_vs_meshlab").held_out_part(4401, 3)
    path = cracked_stl(part, tmp_path / "cracked.stl")
    assert not trimesh.load_mesh(path).is_watertight
    with pytest.warns(UserWarning, match="merged, which closes it"):
        result = pds.remesh(str(path), seed=3)
    intact = pds.remesh(part, seed=3)
    assert result.ok and result.welded > 0 and "merged first" in str(result)
    assert result.watertight == (True, True) and result.volume_error <= 1e-9
    assert (result.patches, result.kept_patches) == (intact.patches, intact.kept_patches)

def test_narrow_facets_with_a_sharp_corner_are_kept(monkeypatch):
    """OpenCASCADE tessellates a sphere coarsely into facets with corners of 20-30°
    (held-out STEP knob 5109/3 at deflection 0.1). Remeshed, each had a triangle that
    sharp at its corner (1st percentile 21.4°, under the 25° target), 50 of them could
    not join (a second round of chains), and the rest paid a certificate each. Narrow
    ones are kept as they are; wider ones (a cone's sides, two quads of this knob) are
    still remeshed, their sharp corners the certificates' exceptions."""
    from pds_plugin import remeshing

    pytest.importorskip("OCP", reason="OCP (the [step] extra) is not installed")
    _, source, _ = bench_module("remesh_vs_meshlab").occt_part(5109, 3, 0.1)
    rounds, sample = [], remeshing.graded_sample_chains
    monkeypatch.setattr(remeshing, "graded_sample_chains",
                        lambda *a, **k: rounds.append(1) or sample(*a, **k))
    result = pds.remesh(source)
    assert result.ok_with_exceptions and result.solid_ok, str(result)
    assert np.percentile(result.angles(), 1) >= 25 and len(rounds) == 1
    cone = trimesh.creation.cone(20, 12, sections=24)        # sides 4.6 alpha wide, 15°
    assert len(pds.remesh(cone).patch_meshes) == 25


@pytest.mark.parametrize("seed", range(4))
def test_no_edge_of_the_graded_complex_is_longer_than_a_joinable_chord(seed):
    """What pds.remesh keeps a patch by, before meshing it (remeshing._chords_joinable):
    an edge pq of the graded complex is at most 2 min(r(p), r(q)) / (1 - L) long, so a
    longer chord joins nothing, whatever is drawn inside."""
    from pds_plugin.graded_complex import graded_alpha_complex
    from pds_plugin.remeshing import _chords_joinable
    from pds_plugin.sizing import RadiusField

    rng = np.random.default_rng(seed)
    points = rng.uniform(0, 10, (300, 2))
    radius = rng.uniform(0.3, 2.0, 300)
    faces = graded_alpha_complex(points, radius, 0.2)
    assert len(faces) > 100
    p, q = faces.ravel(), np.roll(faces, -1, axis=1).ravel()
    length = np.hypot(*(points[p] - points[q]).T)
    assert np.all(length <= 2 * np.minimum(radius[p], radius[q]) / 0.8 * (1 + 1e-12))
    # a unit square's chords: joinable at r = 0.8, not when two corners read 0.39
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    flat = RadiusField(np.zeros((0, 2)), [], 0.2, 0.8)
    dented = RadiusField([[0, 0], [1, 0]], [0.39, 0.39], 0.2, 0.8)
    given = [(None, square, [4], [square])] * 2
    assert _chords_joinable(given, [flat, dented]) == [True, False]
    assert len(graded_alpha_complex(square, dented(square), 0.2, boundary=[[0, 1, 2, 3]])) == 0


def test_patches_whose_chords_no_triangle_joins_are_kept_before_meshing(monkeypatch):
    """A block drilled along its three axes (float32, 48 sections): strips about 2 alpha
    wide beside the holes have a chord at a spike longer than their complex can join.
    They are kept before any patch is meshed (each was meshed three times and thrown
    away before), the chains are sampled again without them, and the rest is certified
    with the solid kept."""
    refused = []
    joinable = pds.remeshing._chords_joinable
    monkeypatch.setattr(pds.remeshing, "_chords_joinable",
                        lambda *args: refused.extend(not ok for ok in joinable(*args))
                        or joinable(*args))
    source = trimesh.creation.box(extents=(13.924, 14.93, 16.767))
    for axis, radius, shift in ((0, 1.584, (0, -1.024, 1.91)), (1, 1.482, (0.748, 0, -1.372)),
                                (2, 2.639, (1.555, -2.157, 0))):
        hole = trimesh.creation.cylinder(radius=radius, height=30, sections=48)
        hole.apply_transform(trimesh.geometry.align_vectors((0, 0, 1), np.eye(3)[axis]))
        hole.apply_translation(shift)
        source = source.difference(hole)
    source = trimesh.Trimesh(np.asarray(source.vertices, np.float32).astype(float),
                             source.faces, process=True)
    result = pds.remesh(source, "auto")
    assert any(refused)
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * source.volume
    assert 0 < result.kept_patches < result.patches


def test_small_patches_are_read_together_as_one_by_one():
    """remeshing._fan_planes, the one-pass reading of small patches whose boundary is one
    cycle through all their vertices (a sphere's facets, a freeform surface's quads),
    gives what _plane_rings gives each, bit for bit; a pinched patch it leaves to
    _plane_rings (which refuses it)."""
    from pds_plugin.remeshing import _fan_planes, _plane_rings

    def both(vertices, faces, members):
        normals = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]],
                           vertices[faces[:, 2]] - vertices[faces[:, 0]])
        areas = np.linalg.norm(normals, axis=1) / 2
        normals = normals / (2 * areas[:, None])
        directed = faces[members][:, :, [0, 1, 1, 2, 2, 0]].reshape(len(members), -1, 2)
        edges = []
        for patch in directed:                  # the edges no other face of it runs back
            runs = {tuple(e) for e in patch.tolist()}
            edges.append([e for e in patch.tolist() if (e[1], e[0]) not in runs])
        edges = np.array(edges, dtype=np.int64)
        return (_fan_planes(vertices, faces, normals, areas, members, edges),
                [_plane_rings(vertices, faces, normals, areas, m, e)
                 for m, e in zip(members, edges)])

    turn = trimesh.transformations.random_rotation_matrix(np.random.default_rng(3).random(3))
    sphere = trimesh.creation.uv_sphere(7.0, count=[12, 16]).apply_transform(turn)
    vertices, faces = np.asarray(sphere.vertices), np.asarray(sphere.faces, np.int64)
    quads = np.flatnonzero(np.isin(faces, faces[1]).sum(axis=1) == 2)[:1]   # a quad's pair
    for members in (np.arange(len(faces))[:, None], np.array([[1, quads[0]]])):
        together, alone = both(vertices, faces, members)
        for plane, one in zip(together, alone):
            assert plane is not None and one is not None
            for mine, theirs in zip([*plane[:3], *plane[3], *plane[4], *plane[5]],
                                    [*one[:3], *one[3], *one[4], *one[5]]):
                assert np.array_equal(mine, theirs)
    # a square annulus less one triangle: its two ends touch at a corner (pinched)
    square = [(0, 0), (3, 0), (3, 3), (0, 3), (1, 1), (2, 1), (2, 2), (1, 2)]
    vertices = np.array([(x, y, 0.0) for x, y in square])
    faces = np.array([[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6],
                      [3, 0, 4]], dtype=np.int64)
    together, alone = both(vertices, faces, np.arange(7)[None])
    assert together == [None] and alone == [None]


def test_row_sums_are_each_runs_own_sum_bit_for_bit():
    # the volume kept sums each patch's determinants this way: the same numbers as the
    # patch's own sum, runs short and long (numpy's pairwise blocks), empty ones zero
    from pds_plugin.remeshing import _row_sums
    rng = np.random.default_rng(5)
    counts = np.concatenate([rng.integers(0, 20, 200), [0, 1, 7, 8, 9, 128, 129, 300]])
    values = rng.standard_normal(counts.sum()) * 10.0 ** rng.integers(-8, 8, counts.sum())
    starts = np.cumsum(counts) - counts
    expected = [values[a:a + n].sum() for a, n in zip(starts, counts)]
    assert np.array_equal(_row_sums(values, counts), expected)
