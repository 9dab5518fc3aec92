"""Small patches meshed in one call (pds_plugin.remeshing._patch_meshes): laid out a gap
apart in one plane, the components of one region do not see each other; each patch's
mesh is its own, certified against its own field, and the solid is kept."""

import numpy as np
import pytest
import trimesh

import pds_plugin as pds
from pds_plugin import remeshing
from pds_plugin.sizing import RadiusField


def studded_plate():
    """A 3 x 2 x 0.3 plate with a 4 x 3 grid of small square studs and round pins: many
    small patches (the studs' tops and sides), as float32."""
    manifold3d = pytest.importorskip("manifold3d")
    solid = manifold3d.Manifold.cube([3.0, 2.0, 0.3])
    for i in range(4):
        for j in range(3):
            x, y = 0.35 + 0.7 * i, 0.4 + 0.6 * j
            if (i + j) % 2:
                stud = manifold3d.Manifold.cube([0.3, 0.25, 0.2]).translate([x - 0.15, y - 0.125, 0.3])
            else:
                stud = manifold3d.Manifold.cylinder(0.25, 0.12, 0.12, 12).translate([x, y, 0.3])
            solid = solid + stud
    mesh = solid.to_mesh()
    vertices = np.asarray(mesh.vert_properties[:, :3], dtype=np.float32).astype(np.float64)
    return trimesh.Trimesh(vertices, np.asarray(mesh.tri_verts), process=True)


@pytest.mark.parametrize("seed", range(6))
def test_the_layout_keeps_every_two_patches_a_gap_apart(seed):
    rng = np.random.default_rng(seed)
    rings = []
    for _ in range(40):
        low, size = rng.uniform(-50, 50, 2), rng.uniform(0.01, 1, 2) * rng.choice([1, 10, 100])
        rings.append(None if rng.random() < 0.1 else
                     [low + size * np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)])
    gap = float(rng.uniform(0.1, 10))
    shifts = remeshing._layout(rings, gap)
    boxes = [(r[0].min(axis=0) + s, r[0].max(axis=0) + s)
             for r, s in zip(rings, shifts) if r is not None]
    assert all((s is None) == (r is None) for r, s in zip(rings, shifts))
    for a in range(len(boxes)):
        for b in range(a):
            apart = np.maximum(boxes[a][0] - boxes[b][1], boxes[b][0] - boxes[a][1])
            assert apart.max() >= gap * (1 - 1e-12)


@pytest.mark.parametrize("grading", [0.05, 0.2, 0.5, 0.8])
def test_a_cone_of_another_patch_is_over_the_cap_a_gap_away(grading):
    """The premise of the one call: a cone s + L d of a feature a gap away (s > 0) is
    over alpha, so the union of the fields reads each patch's own field there."""
    alpha = 0.7
    gap = remeshing._gap(alpha, grading)
    assert grading * gap > alpha and gap > 2 * alpha / (1 - grading)
    own = RadiusField([[0.0, 0.0], [1.0, 0.5]], [0.01, 0.2], grading, alpha)
    other = RadiusField([[1.0 + gap, 0.0], [-gap, 0.7]], [1e-9, 0.05], grading, alpha)
    union = RadiusField(np.concatenate([own.features, other.features]),
                        np.concatenate([own.sizes, other.sizes]), grading, alpha)
    points = np.random.default_rng(1).uniform([0, 0], [1, 0.7], (2000, 2))
    assert np.array_equal(union(points), own(points))


@pytest.mark.parametrize("graded", [True, False])
def test_small_patches_meshed_in_one_call_keep_the_solid(graded, monkeypatch):
    source = studded_plate()
    calls = []
    meshed_together = remeshing._meshed_together

    def counted(patches, *args):
        calls.append(len(patches))
        return meshed_together(patches, *args)

    monkeypatch.setattr(remeshing, "_meshed_together", counted)
    # every patch meshed (no copies of the repeated studs: test_repeated_faces_...)
    monkeypatch.setattr(remeshing, "_translates", lambda todo, patches, fields: (todo, []))
    result = pds.remesh(source, 0.05, graded=graded, seed=2)
    assert max(calls) >= 20                       # the studs' faces, in one call
    assert_solid_kept(result, source)
    # each patch's mesh is its own: in its own region, with its own field, certified
    for mesh, certificate in zip(result.patch_meshes, result.certificates):
        assert certificate.ok_with_exceptions
        x0, y0, x1, y1 = mesh.region.bounds
        assert ((mesh.vertices >= [x0, y0]) & (mesh.vertices <= [x1, y1])).all()
    angles = result.angles()
    assert angles.min() >= 20 and np.percentile(angles, 1) >= 25


def test_groups_hold_at_most_the_small_patch_area_each():
    class Patch:
        def __init__(self, area):
            self.region = type("R", (), {"area": area})()

    rng = np.random.default_rng(3)
    alpha = 0.5
    limit = remeshing.SMALL_PATCH * alpha ** 2
    patches = [Patch(a) for a in rng.uniform(0, 1.5 * limit, 60) ** 2 / (1.5 * limit)]
    todo = [(k, None, None) for k in range(len(patches))]
    groups = remeshing._groups(todo, patches, alpha)
    assert sorted(k for group in groups for k, _, _ in group) == list(range(len(patches)))
    for group in groups:
        areas = [patches[k].region.area for k, _, _ in group]
        assert len(group) == 1 or sum(areas) <= limit
        assert len(group) == 1 or max(areas) <= limit


def test_a_call_that_fails_meshes_its_patches_one_by_one(monkeypatch):
    """A shaft of the held-out corpus (seed 4101, part 6): its small axis-aligned patches
    in one call gave the complex more cocircular ties than its exact test takes (a
    BudgetError); calls over SMALL_PATCH alpha² are now split, and a group call that
    fails still meshes each of its patches by itself."""
    import pds_plugin.graded_complex as graded_complex

    complex_of = graded_complex.graded_alpha_complex

    refused = []

    def refusing(points, radius, grading, boundary, chords=None):
        if len(boundary) > 13:        # more rings than any one patch has: a group
            refused.append(len(boundary))
            raise pds.errors.BudgetError("too many ties")
        return complex_of(points, radius, grading, boundary=boundary, chords=chords)

    monkeypatch.setattr(graded_complex, "graded_alpha_complex", refusing)
    source = studded_plate()
    result = pds.remesh(source, 0.05, seed=2)
    assert refused
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * source.volume


def assert_solid_kept(result, source):
    """The remesh is certified and is the input's solid: closed as it was, the same Euler
    number and volume, every vertex on the input."""
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert result.watertight == (True, True)
    assert result.euler_number[0] == result.euler_number[1]
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * source.volume
    _, distance, _ = trimesh.proximity.closest_point(source, result.mesh.vertices)
    assert distance.max() <= result.tolerance


def recorded_copies(monkeypatch) -> list:
    """Every copy the remesh makes, as (mesh, turns, shift, rolls, copy), appended to the
    returned list while the test runs."""
    made = []
    translated = remeshing._translated

    def recorded(mesh, turns, shift, given, patch, field, rolls=None):
        copy = translated(mesh, turns, shift, given, patch, field, rolls)
        made.append((mesh, turns, shift, rolls, copy))
        return copy

    monkeypatch.setattr(remeshing, "_translated", recorded)
    return made


@pytest.mark.parametrize("graded", [True, False])
def test_repeated_faces_take_a_copy_of_one_mesh_and_keep_every_guarantee(graded, monkeypatch):
    """The studs' repeated faces are meshed once: each copy is the mesh of the face it
    copies, turned by quarter turns and moved, on its own given samples; it is certified
    against its own region and field, and the solid is kept."""
    source = studded_plate()
    made = recorded_copies(monkeypatch)
    monkeypatch.setattr(remeshing, "COPY_AREA", 0.0)      # the studs' faces are small
    result = pds.remesh(source, 0.05, graded=graded, seed=2)
    copies = [item for item in made if item[4] is not None]
    assert len(copies) >= 10                       # the studs' sides and tops
    assert_solid_kept(result, source)
    kept = {id(mesh) for mesh in result.patch_meshes}
    for mesh, turns, shift, rolls, copy in copies:
        assert_a_moved_copy(mesh, turns, shift, rolls, copy)
        if id(copy) in kept:
            assert copy.certificate().ok_with_exceptions
    angles = result.angles()
    assert angles.min() >= 20 and np.percentile(angles, 1) >= 25


def assert_a_moved_copy(mesh, turns, shift, rolls, copy):
    """``copy`` is ``mesh`` turned and moved: its interior vertices exactly, its given
    ring samples to the copy tolerance, each ring rolled by its roll (its vertices
    renumbered), the same triangles."""
    n = int(copy.on_boundary.sum())
    old = np.arange(len(mesh.vertices))
    if rolls is not None:
        assert len(rolls) == len(copy.region.rings)            # a given ring a region ring
        # the given rings' lengths are the mesh's boundary cycles: read them off the
        # copy's boundary edges (each ring's samples consecutive, closed)
        edges = copy.boundary_edges
        following = dict(zip(edges[:, 0].tolist(), edges[:, 1].tolist()))
        ring_sizes, at = [], 0
        while at < n:
            size, vertex = 1, following[at]
            while vertex != at:
                size, vertex = size + 1, following[vertex]
            ring_sizes.append(size)
            at += size
        starts = np.cumsum([0] + ring_sizes[:-1])
        old[:n] = np.concatenate([start + (np.arange(size) + roll) % size
                                  for start, size, roll in zip(starts, ring_sizes, rolls)])
    new = np.empty_like(old)
    new[old] = np.arange(len(old))
    moved = remeshing._turned(mesh.vertices[old], turns) + shift
    tolerance = remeshing._COPY_TOLERANCE * copy.field.cap
    assert np.abs(moved - copy.vertices).max() <= tolerance
    assert np.array_equal(moved[n:], copy.vertices[n:])          # interiors moved as is
    assert np.array_equal(new[mesh.faces], copy.faces)


def seven_eighths_cube():
    """A 40 mm cube without one 20 mm octant, as float32, its vertices numbered at
    random: its three L-shaped faces (and its squares) are quarter turns of each other
    whose rings start at different corners (a patch's ring starts at its least vertex)."""
    manifold3d = pytest.importorskip("manifold3d")
    solid = (manifold3d.Manifold.cube([40.0, 40.0, 40.0])
             - manifold3d.Manifold.cube([20.0, 20.0, 20.0]).translate([20.0, 20.0, 20.0]))
    mesh = solid.to_mesh()
    vertices = np.asarray(mesh.vert_properties[:, :3], dtype=np.float32).astype(np.float64)
    number = np.random.default_rng(2).permutation(len(vertices))   # vertex k is number[k]
    return trimesh.Trimesh(vertices[np.argsort(number)], number[np.asarray(mesh.tri_verts)],
                           process=True)


@pytest.mark.parametrize("graded", [True, False])
def test_repeated_faces_whose_rings_start_elsewhere_are_copies_too(graded, monkeypatch):
    """A face that is a quarter turn of another but whose rings start at another corner
    takes that one's mesh with its rings rolled: the copy is the mesh turned, moved and
    renumbered, certified against its own region and field, and the solid is kept."""
    source = seven_eighths_cube()
    made = recorded_copies(monkeypatch)
    result = pds.remesh(source, graded=graded, seed=3)
    rolled = [item for item in made if item[3] is not None and any(item[3])]
    assert rolled and all(item[4] is not None for item in rolled)
    assert_solid_kept(result, source)
    kept = {id(mesh) for mesh in result.patch_meshes}
    for mesh, turns, shift, rolls, copy in made:
        assert copy is not None
        assert_a_moved_copy(mesh, turns, shift, rolls, copy)
        assert id(copy) in kept and copy.certificate().ok
    assert result.ok
    angles = result.angles()
    assert angles.min() >= 20 and np.percentile(angles, 1) >= 25


def test_a_rolled_match_needs_every_ring_sample_and_feature():
    """:func:`remeshing._rolled` finds the turn, shift and rolls of a square turned and
    started at another corner, and none when a given sample or a feature moves."""
    from types import SimpleNamespace

    import shapely
    from pds_plugin.region import Region
    from shapely.geometry import MultiPolygon, Polygon

    square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    samples = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]], float)

    def patch_of(ring):
        geometry = shapely.orient_polygons(MultiPolygon([Polygon(ring)]))  # as _patch makes it
        return SimpleNamespace(region=Region(geometry, np.eye(4)))

    field = RadiusField([[0.5, 0.5]], [0.1], 0.2, 1.0)
    turned = remeshing._turned(square, 1) + [10.0, 5.0]        # (10, 5), (10, 7), ...
    start = 2                                                  # starts at its third corner
    copy = patch_of(np.roll(turned, -start, axis=0))
    copy_samples = np.roll(remeshing._turned(samples, 1) + [10.0, 5.0], -3, axis=0)
    copy_field = RadiusField(remeshing._turned(field.features, 1) + [10.0, 5.0], [0.1], 0.2, 1.0)
    source = patch_of(square)
    assert source.region.rings[0][0].tolist() == [0.0, 0.0]
    found = remeshing._rolled(source, [samples], field, copy, [copy_samples], copy_field, 1e-9)
    assert found is not None
    turns, shift, rolls = found
    assert turns == 1 and rolls == [3]
    assert np.allclose(shift, [10.0, 5.0])
    moved = copy_samples.copy()
    moved[1] += [0.0, 1e-6]
    assert remeshing._rolled(source, [samples], field, copy, [moved], copy_field, 1e-9) is None
    elsewhere = RadiusField(copy_field.features + 1e-6, [0.1], 0.2, 1.0)
    assert remeshing._rolled(source, [samples], field, copy, [copy_samples], elsewhere,
                             1e-9) is None


@pytest.mark.parametrize("seed", range(8))
def test_points_find_the_triangle_they_are_in_as_a_scan_of_every_box_would(seed):
    """:func:`remeshing._triangle_of` (a tree of the triangles' boxes, each point's best
    pair kept in one pass) picks, per point, of the triangles whose box holds it one
    with the largest smallest barycentric coordinate, as scoring every triangle would; a
    point in no triangle goes to one whose box is nearest."""
    rng = np.random.default_rng(seed)
    m = int(rng.integers(1, 80))
    corners = (rng.uniform(0, 10, (m, 1, 2))
               + rng.uniform(-3, 3, (m, 3, 2)) * rng.choice([1.0, 0.01, 5.0], (m, 1, 1)))
    if seed % 2:
        corners[0, 2] = corners[0, 1]                  # a degenerate triangle
    xy = rng.uniform(-2, 12, (int(rng.integers(1, 500)), 2))
    if seed % 3 == 0:
        xy = np.round(xy)                              # on box edges and corners
    first = remeshing._triangle_of(xy, corners)
    low, high = corners.min(axis=1), corners.max(axis=1)
    for k, point in enumerate(xy):
        holds = np.flatnonzero(((point >= low) & (point <= high)).all(axis=1))
        beta, gamma = remeshing._barycentric(np.repeat(point[None], len(holds), axis=0),
                                             *(corners[holds, j] for j in range(3)))
        with np.errstate(invalid="ignore"):
            score = np.minimum(np.minimum(beta, gamma), 1 - beta - gamma)
        score = np.where(np.isnan(score), -np.inf, score)
        if len(holds) and score.max() >= -remeshing._INSIDE:
            assert first[k] in holds[score == score.max()]
        else:
            outside = np.maximum(np.maximum(low - point, point - high), 0)
            distance = np.hypot(outside[:, 0], outside[:, 1])
            assert distance[first[k]] == distance.min()


def test_a_copy_whose_certificate_fails_is_meshed_by_itself(monkeypatch):
    """A copy is only a candidate: when its own certificate does not hold, the patch is
    meshed on its own, and the result is as good as without copies."""
    source = studded_plate()
    monkeypatch.setattr(remeshing, "_translated", lambda *args: None)
    monkeypatch.setattr(remeshing, "COPY_AREA", 0.0)
    result = pds.remesh(source, 0.05, seed=2)
    assert result.solid_ok and result.ok_with_exceptions, str(result)
    assert abs(result.mesh.volume - source.volume) <= 1e-9 * source.volume


@pytest.mark.parametrize("turns", range(4))
def test_quarter_turns_are_exact_and_compose(turns):
    points = np.random.default_rng(turns).normal(size=(50, 2)) * 1e3
    turned = remeshing._turned(points, turns)
    assert np.array_equal(remeshing._turned(turned, 4 - turns), points)
    angle = turns * np.pi / 2
    rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    assert np.allclose(turned, points @ rotation.T, atol=1e-9)


def test_the_layout_field_reads_each_patch_its_own_field_bit_for_bit():
    """partition's layout-wide field (one call for all patches' points) reads, at every
    point of a patch's box, exactly what the patch's own field reads: the premise of
    reading the fields of the chains' and samples' points in one call."""
    from pds_plugin.partition import Frame, partition_topology

    source = studded_plate()
    result = pds.remesh(source, 0.05, seed=2)
    meshes = result.patch_meshes
    fields = [mesh.field for mesh in meshes]
    rings, frames, vertex = [], [], 0
    for mesh in meshes:                 # each patch's outline as a region of its own
        region = []
        for ring in mesh.region.rings:
            region.append(np.arange(vertex, vertex + len(ring)))
            vertex += len(ring)
        rings.append(region)
    for k, mesh in enumerate(meshes):
        ids = np.concatenate(rings[k])
        frames.append(Frame(ids, np.concatenate(mesh.region.rings)))
    union = partition_topology(rings, frames).layout_field(frames, fields)
    assert union is not None
    rng = np.random.default_rng(0)
    for mesh, field in zip(meshes, fields):
        x0, y0, x1, y1 = mesh.region.bounds
        points = np.concatenate([mesh.vertices, rng.uniform([x0, y0], [x1, y1], (500, 2))])
        assert np.array_equal(union(points), field(points))


@pytest.mark.parametrize("seed", range(4))
def test_the_chords_of_many_chains_at_once_are_each_chains_own(seed):
    """:func:`remeshing._chords` gives, chain after chain, what ``ChainSamples.chords``
    gives chain by chain: open chains' consecutive pairs, a closed chain's last to its
    first too, none for a chain of one sample."""
    from types import SimpleNamespace

    from pds_plugin.partition import ChainSamples

    rng = np.random.default_rng(seed)
    count = int(rng.integers(0, 30))
    samples = [rng.integers(0, 1000, int(rng.integers(1, 7))).astype(np.int64)
               for _ in range(count)]
    chains = SimpleNamespace(chain_samples=samples, closed=[bool(rng.random() < 0.3)
                                                            for _ in range(count)])
    which = sorted(rng.choice(count, size=int(rng.integers(0, count + 1)),
                              replace=False).tolist()) if count else []
    expected = [ChainSamples.chords(chains, c) for c in which]
    expected = np.concatenate(expected) if expected else np.zeros((0, 2), np.int64)
    assert np.array_equal(remeshing._chords(chains, which), expected)


@pytest.mark.parametrize("graded", [True, False])
def test_the_compiled_chain_densification_is_the_numpy_one_bit_for_bit(monkeypatch, graded):
    """partition._ChainSet.dense_reads (one kernel call, each owner read by its own
    field: _graded_kernels.densified_chains) against its numpy rounds and reads, at
    every call of a remesh whose chains meet finely graded neighbours (the studs), and
    of its uniform remesh, whose first fields have no cone (r is the cap)."""
    from pds_plugin import partition

    compiled, numpy_rounds = partition._ChainSet.dense_reads, partition._ChainSet.dense
    calls = {True: [], False: []}                   # by: does the field have cones?

    def unused(self, grading):
        raise AssertionError("the numpy rounds ran: the kernel was not used")

    def compared(self, grading):
        monkeypatch.setattr(partition._ChainSet, "dense", unused)
        cid, segment, t, reads = compiled(self, grading)
        monkeypatch.setattr(partition._ChainSet, "dense", numpy_rounds)
        expected = self.dense(grading)
        for got, want in zip((cid, segment, t), expected):
            np.testing.assert_array_equal(got, want)
        for (xy, r), side in zip(reads, (0, 1)):
            want_xy, want_r = self.read(cid, segment, t, side)
            np.testing.assert_array_equal(xy, want_xy)
            np.testing.assert_array_equal(r, want_r)
        calls[any(len(field.sizes) for field in self.fields)].append(len(cid))
        return cid, segment, t, reads

    monkeypatch.setattr(partition._ChainSet, "dense_reads", compared)
    result = pds.remesh(studded_plate(), 0.05, graded=graded)
    assert result.ok_with_exceptions
    assert len(calls[graded]) >= 2 and max(calls[graded]) > 1000
