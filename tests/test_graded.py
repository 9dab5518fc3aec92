"""Graded meshes (docs/graded.md): the radius field is L-Lipschitz, separation and
coverage hold against it, every angle is at least arcsin((1 - L)/2), the topology and
the polygon are the region's, and the same seed gives the same mesh.

Oracles are independent of the certificate where they can be: shapely for areas and
containment, scipy for distances, the Euler characteristic for Betti numbers.
"""

import math

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.errors import ArgumentError, ArgumentTypeError, BudgetError
from pds_plugin.mesh import mesh_betti
from pds_plugin.sampling import estimate_samples
from pds_plugin.sizing import angle_bound, inradius

from conftest import shared_file
from regions import multiscale_plates


def graded_mesh(region, seed=0, grading=None, **options):
    return pds.mesh_region(region, "auto", seed, graded=True, grading=grading, **options)


def _betti(mesh):
    """(b0, b1) of the mesh from the Euler characteristic of each component."""
    _, per_component = mesh_betti(mesh.faces, len(mesh.vertices))
    return tuple(int(v) for v in np.asarray(per_component).reshape(-1, 2).sum(axis=0))


def _chord_polygon(mesh):
    """The polygon through the boundary samples, in order along each ring."""
    from pds_plugin.analysis.conformity import SampledBoundary
    return SampledBoundary(mesh.region, mesh.vertices, mesh.on_boundary, mesh.alpha).polygon()


def _check_mesh(mesh, polygonal):
    """Every property of a graded mesh that the issue asks for, against independent
    oracles where possible."""
    region = mesh.region
    field = mesh.field
    radius = field(mesh.vertices)
    # separation against r over the edges, and over all close pairs that see each other
    edges = mesh.edges
    gap = np.hypot(*(mesh.vertices[edges[:, 0]] - mesh.vertices[edges[:, 1]]).T)
    assert np.all(gap >= np.minimum(radius[edges[:, 0]], radius[edges[:, 1]]) * (1 - 1e-9))
    cert = mesh.certificate()
    assert cert.coverage_gap <= 1 + 1e-9
    # angles against the proven bound
    assert mesh.quality().angles.min() >= angle_bound(field.grading) - 1e-9
    # topology: Betti numbers of the mesh (Euler characteristic) and of the region
    assert _betti(mesh) == region.betti
    # nothing outside: the union of the triangles is the polygon of the chords ...
    union = shapely.union_all(shapely.polygons(mesh.vertices[mesh.faces]))
    chords = _chord_polygon(mesh)
    assert union.symmetric_difference(chords).area <= 1e-9 * region.area
    # ... which is the region itself when the region is polygonal
    if polygonal:
        assert union.symmetric_difference(region.geometry).area <= 1e-9 * region.area
    else:
        assert union.difference(region.geometry.buffer(0.05 * field.cap)).is_empty
    assert cert.ok, str(cert)


def _promises(geometry, seed, grading):
    region = pds.Region.from_shapely(geometry)
    polygonal = all(len(ring) <= 8 for ring in region.rings[1:]) and len(region.rings[0]) <= 8
    _check_mesh(graded_mesh(region, seed=seed, grading=grading), polygonal)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(multiscale_plates(), st.integers(0, 2**16), st.sampled_from([0.1, 0.2]))
def test_graded_meshes_keep_their_promises(geometry, seed, grading):
    _promises(geometry, seed, grading)


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(multiscale_plates(), st.integers(0, 2**16))
def test_graded_meshes_keep_their_promises_at_steep_grading(geometry, seed):
    _promises(geometry, seed, 0.3)


@pytest.mark.parametrize("grading", [0.45, 0.6])
@pytest.mark.parametrize("seed", range(2))
def test_a_long_chord_at_a_steep_grading_is_covered_on_the_chord_as_in_its_lens(grading, seed):
    """A plate's edge 7 long between a notch and a corner, r = 2.8 at both ends: at
    L = 0.45 the points of the chord near its middle were 1.046 r from every sample and
    failed the certificate, while the lens beside them, where no sample may go, was
    excused. The chord is the lens's edge: its coverage is the lens's, within
    1 / (1 - L)."""
    plate = box(0, 0, 40, 25).difference(Point(12, 12).buffer(4)).difference(
        box(30, -1, 33, 10))
    mesh = graded_mesh(pds.Region.from_shapely(plate), seed=seed, grading=grading)
    certificate = mesh.certificate()
    assert certificate.ok_with_exceptions, str(certificate)
    assert certificate.coverage_gap <= 1 + 1e-9
    assert certificate.lens_coverage <= 1 / (1 - grading)
    radius = mesh.field(mesh.vertices)
    a, b = mesh.edges.T
    gap = np.hypot(*(mesh.vertices[a] - mesh.vertices[b]).T)
    assert np.all(gap >= np.minimum(radius[a], radius[b]) * (1 - 1e-9))


def test_many_seeds_on_features_three_orders_of_magnitude_apart():
    plate = box(0, 0, 200, 40).difference(box(10, 10, 10.2, 10.2)).difference(
        Point(100, 20).buffer(8, quad_segs=8)).difference(box(150, 5, 190, 5.3))
    region = pds.Region.from_shapely(plate)
    sizes = []
    for seed in range(6):
        mesh = graded_mesh(region, seed=seed)
        _check_mesh(mesh, polygonal=False)
        sizes.append(len(mesh.vertices))
    # graded: a uniform mesh at the smallest radius would need over 100 times more
    smallest = mesh.certificate().smallest_radius
    assert max(sizes) < 0.01 * estimate_samples(region, smallest)


def test_an_edge_made_of_vertices_1e8_off_a_line_is_covered_beyond_its_chords():
    # the top edge's vertices alternate 1e-8 above and below y = 1 (the rounding of an
    # STL section): the ring crosses a chord near one end, and the piece of region beyond
    # the chord reached 1.22 r from the only chord end that sees it
    top = [(x, 1 + s * 1e-8) for x, s in zip(np.linspace(3, 0, 6)[1:-1], (-1, 1, -1, -1))]
    region = pds.Region.from_shapely(shapely.Polygon([(0, 0), (3, 0), (3, 1), *top, (0, 1)]))
    _check_mesh(graded_mesh(region), polygonal=True)


def _tooth(angle):
    """A 10 x 3 plate with a triangular tooth on its top edge, 2 wide at its base, whose
    tip is a convex corner where the region's angle is ``angle`` degrees."""
    height = 1.0 / math.tan(math.radians(angle) / 2)
    return box(0, 0, 10, 3).union(shapely.Polygon([(4, 3), (6, 3), (5, 3 + height)]))


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.floats(34, 59), st.integers(0, 2**16), st.sampled_from([0.05, 0.2, 0.3]))
@example(36.9, 0, 0.3).via("the tip came off: the field grew at the rate L from it")
@example(41.0, 0, 0.05).via("the tip came off: the rest of its side in one long chord")
@example(42.0, 210, 0.05).via("coverage 1.013 r: the same long chord")
def test_the_neighbours_of_a_corner_sharper_than_60_degrees_are_separated(angle, seed,
                                                                          grading):
    # the first samples on the two sides of a convex corner of angle θ are
    # 2 d sin(θ/2) apart at distance d from it: parts of one r left them 0.83 r apart at
    # 46° (the angle_block section at L = 0.05, before the corner clearance); the
    # examples are what this test found after it
    _check_mesh(graded_mesh(pds.Region.from_shapely(_tooth(angle)), seed, grading),
                polygonal=True)


@pytest.mark.parametrize("grading", [0.05, 0.1, 0.2, 0.3])
def test_the_angle_block_section_is_certified(grading):
    # its 46° corners: separation 0.85 r at L = 0.05 before the corner clearance, and at
    # L = 0.3 a sample moved onto a crossing beside one (the edge's vertices 1e-8 off a
    # line) isolated the corner, its triangle too large to keep
    import trimesh
    stl = shared_file("angle_block.STL")
    lo, hi = trimesh.load_mesh(stl).bounds
    region = pds.section(stl, plane_origin=(lo + hi) / 2, plane_normal=(0.0, 0.0, 1.0))
    cert = graded_mesh(region, grading=grading).certificate()
    assert cert.coverage_gap <= 1 + 1e-9
    assert cert.ok, str(cert)


@pytest.mark.parametrize("grading", [0.4, 0.45, 0.6])
@pytest.mark.parametrize("apart", [1.6, 2.0, 2.4])
def test_steep_gradings_cut_every_piece_between_sharp_corners(grading, apart):
    """A plate with a lens-shaped hole (two arcs between two sharp corners) at steep
    gradings: every piece between sharp corners (the plate's sides, the lens's arcs) is
    cut by a sample, and the mesh is certified. The sampler splits a piece into parts of
    τ-length at least a = 1.02 / (1 - L/2); with r at most 0.4 of the piece, τ >= 2.5 was
    one part whenever 2a > 2.5 (L above about 0.37): a chord as long as the piece, whose
    arc's middle lay 1.22 r from every sample on flanges' sections, and here plates whose
    16-long sides were single chords left holes in the mesh (FAILED at L = 0.45 for
    three of these lenses, sizing.piece_factor)."""
    lens = Point(0, 0).buffer(1.5, quad_segs=64).intersection(Point(apart, 0).buffer(1.5, quad_segs=64))
    region = pds.Region.from_shapely(box(-12, -8, 14, 8).difference(lens))
    mesh = graded_mesh(region, grading=grading)
    samples = mesh.vertices[mesh.on_boundary]
    x, y = samples.T
    for inside in (np.abs(y) < 8 - 1e-9, np.abs(x - 1) < 14 - 1e-9):      # sides
        assert ((np.abs(x - 1) == 13) | (np.abs(y) == 8))[inside].any()
    for upper in (True, False):                                          # the arcs
        arc = (np.abs(y) < 1.5) & ((y > 1e-9) if upper else (y < -1e-9))
        assert arc.any()
    assert mesh.certificate().ok_with_exceptions, str(mesh.certificate())


@pytest.mark.parametrize("sheet, grading", [(0, 0.45), (4, 0.6)])
def test_laser_cut_sheets_at_steep_gradings_are_certified(sheet, grading):
    """Generated DXF sheets (bench/_drawings.py: 100-260 holes, slots and hexagons) at
    steep gradings: every mesh of sheets 0-3 said FAILED at L = 0.45, and sheets 4 and 7
    at L = 0.6, before the pieces rule grew finer with L (sizing.piece_factor)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    from _drawings import laser_drawing

    cert = graded_mesh(laser_drawing(sheet), grading=grading).certificate()
    assert cert.ok_with_exceptions, str(cert)


def test_the_piece_rule_gives_every_piece_two_parts_no_longer_than_two():
    """sizing.piece_factor: with the size at most that share of a piece, held at points
    a quarter of it apart (r between them up to (1 + L/8) times it), the piece's
    τ-length T is at least 1 / (factor (1 + L/8)), so the sampler's floor(T / a) parts
    number at least two and are each shorter than 2 in τ (a chord under 2 r where r is
    flat), for gradings up to 0.72; beyond, exactly four parts (more shrank r at short
    pieces without end); up to L = 0.25 it is the 0.4 every grading had before."""
    from pds_plugin.sizing import piece_factor

    for grading in np.linspace(0.01, 0.99, 99):
        a = 1.02 / (1 - grading / 2)
        fewest = math.floor(1 / (piece_factor(grading) * (1 + grading / 8)) / a)
        assert fewest >= 2, grading
        if grading <= 0.72:
            assert (1 + 1 / fewest) * a < 2, grading
        else:
            assert fewest == 4, grading
        if grading <= 0.25:
            assert piece_factor(grading) == 0.4


def test_the_certificates_chord_lens_is_the_samplers():
    """A chord ab 2 long with r(a) = r(b) = 0.9 at L = 0.4, r growing away from them: the
    sampler refuses darts where the triangle on the chord would have a circumradius above
    min(r(x), r(a), r(b)) / (1 - L) = 1.5 (``_graded_kernels._encroaches``), so x =
    (1, 0.3) (circumradius 1.82) takes no sample; the certificate's lens counted it only
    above r(x) / (1 - L) = 2.2, and a peak there was plain coverage above 1 (a held-out
    vase's section: 1.10 r, FAILED). Such an x is within the limit of a chord end."""
    from types import SimpleNamespace

    from pds_plugin.analysis.graded_certificate import _in_a_lens
    from pds_plugin.sizing import RadiusField

    field = RadiusField([[0, 0], [2, 0]], [0.9, 0.9], grading=0.4, cap=2.0)
    chord = SimpleNamespace(points=np.array([[0.0, 0.0], [2.0, 0.0]]), a=np.array([0]),
                            b=np.array([1]))
    x = np.array([[1.0, 0.3], [1.0, 0.8], [1.0, -0.3]])    # in, too far in, outside
    assert _in_a_lens(x, field(x), field, chord).tolist() == [True, False, False]
    assert np.hypot(*x[0]) <= 0.9 / (1 - 0.4) < field(x[:1])[0] / (1 - 0.4)


def test_the_same_seed_gives_the_same_mesh_bit_for_bit():
    region = pds.Region.from_shapely(box(0, 0, 30, 5).difference(box(2, 2, 2.3, 2.3)))
    first, again, other = (graded_mesh(region, seed=s) for s in (3, 3, 4))
    assert first.vertices.tobytes() == again.vertices.tobytes()
    assert first.faces.tobytes() == again.faces.tobytes()
    assert first.vertices.tobytes() != other.vertices.tobytes()


@pytest.mark.parametrize("threads", [1, 2])
def test_a_sizing_above_the_field_changes_no_sample(threads):
    """A user sizing makes the kernels ask the field through Python (``RadiusField``);
    without one they search its cones in C from each box's upper bound of r. Where
    the sizing never binds, both give the same samples bit for bit."""
    from pds_plugin import _parallel
    region = pds.Region.from_shapely(box(0, 0, 30, 5).difference(box(2, 2, 2.3, 2.3))
                                     .difference(Point(20, 2.5).buffer(1.0)))
    previous = _parallel.set_threads(threads)
    try:
        plain = graded_mesh(region, seed=5)
        sized = graded_mesh(region, seed=5, sizing=lambda x, y: np.full(np.shape(x), 1e9))
    finally:
        _parallel.set_threads(previous)
    assert plain.vertices.tobytes() == sized.vertices.tobytes()
    assert plain.faces.tobytes() == sized.faces.tobytes()


@pytest.mark.parametrize("case", ["holes", "off a line", "thin"])
def test_the_boundary_stage_for_all_rings_at_once_is_the_ring_by_ring_one(case, monkeypatch):
    """The graded boundary stage densifies every ring in one kernel call
    (``_graded_kernels.densified_rings``), places the rings without sharp corners all
    at once (``_plain_positions``) and asks only the rings ``_crossed_rings`` flags to
    be uncrossed and unhidden: each gives, bit for bit, what the ring by ring
    computation it replaces gives (the numpy rounds of ``_tau_rings``, kept for fields
    with a user sizing; ``tau_positions``; ``_uncrossed`` and ``_unhidden`` on every
    ring: the first moves a sample only on the edge whose vertices are 1e-8 off a
    line)."""
    from pds_plugin import graded_sampling as gs
    from pds_plugin.sizing import RadiusField, radius_field
    shape = {
        "holes": box(0, 0, 30, 6).difference(box(2, 2, 2.3, 2.3))
                 .difference(Point(20, 3).buffer(1.5, quad_segs=6))
                 .difference(Point(10, 3).buffer(0.2, quad_segs=3)),
        "off a line": shapely.Polygon([(0, 0), (3, 0), (3, 1), *[
            (x, 1 + s * 1e-8) for x, s in zip(np.linspace(3, 0, 6)[1:-1], (-1, 1, -1, -1))],
            (0, 1)]),
        "thin": box(0, 0, 10, 0.05).union(box(4, 0, 4.03, 2)),
    }[case]
    region = pds.Region.from_shapely(shape)
    field = radius_field(region)
    slow = RadiusField(field.features, field.sizes, field.grading, field.cap,
                       sizing=lambda x, y: np.full(np.shape(x), 1e9))
    fast, rounds = (gs._tau_rings(region.rings, f, field.grading) for f in (field, slow))
    assert len(fast) == len(rounds) == len(region.rings)
    for mine, theirs in zip(fast, rounds):
        for a, b in zip(mine, theirs):
            assert a.dtype == b.dtype and a.tobytes() == b.tobytes()
    unit = gs.TAU_MARGIN / (1.0 - 0.5 * field.grading)
    starts = np.random.default_rng(1).random(len(fast))
    for (_, _, _, tau), start, at in zip(fast, starts, gs._plain_positions(
            [tau for *_, tau in fast], starts, unit)):
        alone = gs.tau_positions(tau, np.array([start * tau[-1]]), [unit], [unit], unit, None)
        assert at.tobytes() == alone.tobytes()
    flags = []

    def spy(*args):
        flags.append(crossed_rings(*args))
        return flags[-1]

    crossed_rings = gs._crossed_rings
    monkeypatch.setattr(gs, "_crossed_rings", spy)
    flagged = gs.graded_poisson_disc(region, field, seed=3)
    monkeypatch.setattr(gs, "_crossed_rings",
                        lambda samples, *_: (np.ones(len(samples), bool),) * 2)
    every = gs.graded_poisson_disc(region, field, seed=3)
    assert flagged.points.tobytes() == every.points.tobytes()
    assert flags[0][0].any() == (case == "off a line")


def test_the_complex_on_the_samplers_chords_is_the_complex_on_its_own():
    """The graded complex takes the sampler's binned chords (``Samples.chords``) instead
    of binning them again: the same triangles; chords of another sampling are refused."""
    from pds_plugin.graded_complex import graded_alpha_complex
    from pds_plugin.graded_sampling import graded_poisson_disc
    from pds_plugin.sizing import radius_field
    region = pds.Region.from_shapely(box(0, 0, 30, 5).difference(box(2, 2, 2.3, 2.3)))
    field = radius_field(region)
    samples = graded_poisson_disc(region, field, seed=2)
    own = graded_alpha_complex(samples.points, samples.radius, field.grading,
                               boundary=samples.rings)
    shared = graded_alpha_complex(samples.points, samples.radius, field.grading,
                                  boundary=samples.rings, chords=samples.chords)
    assert len(own) and own.tobytes() == shared.tobytes()
    other = graded_poisson_disc(region, field, seed=3)
    if len(other.chords.out) != len(samples.points):
        with pytest.raises(ArgumentError, match="chords must index the"):
            graded_alpha_complex(samples.points, samples.radius, field.grading,
                                 boundary=samples.rings, chords=other.chords)


@pytest.mark.parametrize("max_samples", [100, 140])
def test_a_refinement_too_large_for_the_budget_is_refused(max_samples):
    region = pds.Region.from_shapely(box(0, 0, 30, 5).difference(box(2, 2, 2.3, 2.3)))
    with pytest.raises(BudgetError, match=f"would refine .* boxes at once, more than 4 per "
                                          f"sample of max_samples={max_samples}"):
        graded_mesh(region, max_samples=max_samples)


def test_gaps_and_notches_do_not_shrink_the_field_and_stay_open():
    # two plates 0.02 apart and a notch 0.02 wide: along the gap and the notch's walls
    # the radius stays the plates' scale (only the notch's 0.02 bottom edge is small,
    # and its influence grows by L per unit away from it)
    geometry = shapely.union_all([box(0, 0, 10, 10).difference(box(4.99, 3, 5.01, 10)),
                                  box(10.02, 0, 20, 10)])
    region = pds.Region.from_shapely(geometry)
    mesh = graded_mesh(region, seed=0)
    assert np.all(mesh.field([[9.99, 5.0], [4.98, 8.0]]) > 1.0)
    assert _betti(mesh) == (2, 0)
    _check_mesh(mesh, polygonal=True)


def test_auto_caps_only_by_the_region_size_and_alpha_caps_the_field():
    region = pds.Region.from_shapely(box(0, 0, 40, 10))
    assert math.isclose(graded_mesh(region).alpha, inradius(region))
    assert math.isclose(inradius(region), 5.0, rel_tol=0.02)
    mesh = pds.mesh_region(region, 0.5, graded=True)
    assert mesh.field(mesh.vertices).max() <= 0.5
    assert mesh.certificate().ok


def test_a_user_sizing_is_combined_by_min():
    region = pds.Region.from_shapely(box(0, 0, 20, 10))
    def finer_on_the_left(x, y):
        return 0.2 + 0.1 * x
    mesh = pds.mesh_region(region, "auto", graded=True, sizing=finer_on_the_left)
    radius = mesh.field(mesh.vertices)
    assert np.all(radius <= finer_on_the_left(mesh.vertices[:, 0], mesh.vertices[:, 1]) + 1e-12)
    assert mesh.certificate().ok
    assert len(mesh.vertices[mesh.vertices[:, 0] < 5]) > len(mesh.vertices[mesh.vertices[:, 0] > 15])


@pytest.mark.parametrize("options, error, message", [
    ({"grading": 1.0}, ArgumentError, "grading must lie in"),
    ({"grading": "steep"}, ArgumentTypeError, "grading must be a number"),
    ({"sizing": "fine"}, ArgumentTypeError, "sizing must be a number"),
    ({"sizing": -3.0}, ArgumentError, "sizing must be a positive finite number"),
    ({"sizing": lambda x, y: -1 + 0 * x}, ArgumentError, "positive finite radii"),
    ({"conforming": False}, ArgumentError, "always conforming"),
    ({"refine": 0.5}, ArgumentError, "no option 'refine'"),
])
def test_bad_graded_options_are_named(options, error, message):
    region = pds.Region.from_shapely(box(0, 0, 4, 1))
    with pytest.raises(error, match=message):
        pds.mesh_region(region, "auto", graded=True, **options)


def test_a_sizing_or_a_grading_makes_the_mesh_graded_and_graded_false_refuses_them():
    """graded=True is redundant beside a sizing or a grading: the same mesh, bit for bit,
    with or without it; a number sizing is the largest radius, as alpha."""
    region = pds.Region.from_shapely(box(0, 0, 4, 1).difference(box(1, 0.4, 3, 0.6)))
    def same(a, b):
        return np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    assert same(pds.mesh_region(region, 0.5, grading=0.3),
                pds.mesh_region(region, 0.5, graded=True, grading=0.3))
    finer = pds.mesh_region(region, "auto", sizing=lambda x, y: 0.05 + 0.05 * x)
    assert finer.field is not None and finer.certificate().ok
    assert same(finer, pds.mesh_region(region, "auto", graded=True,
                                       sizing=lambda x, y: 0.05 + 0.05 * x))
    capped = pds.mesh_region(region, "auto", sizing=0.15)
    assert same(capped, pds.mesh_region(region, 0.15, graded=True))
    assert capped.alpha == 0.15 and capped.field(capped.vertices).max() <= 0.15
    reused = pds.mesh_region(region, "auto", sizing=finer.field)
    assert np.all(reused.field(reused.vertices) <= finer.field(reused.vertices))
    assert pds.mesh_region(region, 0.5).field is None               # uniform without them
    with pytest.raises(ArgumentError, match="drop graded=False"):
        pds.mesh_region(region, 0.5, graded=False, grading=0.2)


def test_a_budget_too_small_is_refused_with_what_to_do():
    region = pds.Region.from_shapely(box(0, 0, 30, 5).difference(box(2, 2, 2.3, 2.3)))
    with pytest.raises(BudgetError, match="max_samples=50.*smallest radius here is"):
        graded_mesh(region, max_samples=50)



def test_leaves_from_the_cells_near_the_rings_are_the_leaves_of_the_whole_grid(monkeypatch):
    """Components far apart (remeshing's layout): the quadtree starts only from the grid
    cells near a ring's box, and the samples are those of the whole grid, bit for bit."""
    from shapely.geometry import MultiPolygon, Point, box
    from pds_plugin import graded_sampling
    from pds_plugin.graded_sampling import graded_poisson_disc
    from pds_plugin.region import Region
    from pds_plugin.sizing import RadiusField, radius_field

    parts = [box(0, 0, 3, 1), box(40, 0, 42, 5).difference(Point(41, 2.5).buffer(0.4)),
             box(10, 30, 11, 31), box(60, 50, 64, 53)]
    region = Region.from_shapely(MultiPolygon(parts))
    fields = [radius_field(Region.from_shapely(p), 0.2, 0.5) for p in parts]
    field = RadiusField(np.concatenate([f.features for f in fields]),
                        np.concatenate([f.sizes for f in fields]), 0.2, 0.5)
    cells = []
    near = graded_sampling._GradedSampler._cells_near_rings

    def recorded(self, *args):
        cells.append(near(self, *args))
        return cells[-1]

    monkeypatch.setattr(graded_sampling._GradedSampler, "_cells_near_rings", recorded)
    fast = graded_poisson_disc(region, field, seed=3)
    side = 0.5 / math.sqrt(2)                     # the leaves' grid: cap / sqrt(2)
    assert cells[0] is not None and len(cells[0]) < 0.1 * (64 / side) * (53 / side)
    monkeypatch.setattr(graded_sampling._GradedSampler, "_cells_near_rings",
                        lambda self, *args: None)
    whole = graded_poisson_disc(region, field, seed=3)
    assert np.array_equal(fast.points, whole.points)
    assert np.array_equal(fast.radius, whole.radius)


def heat_sink_section():
    """A held-out CAD section (tests/data/heat_sink_section.json): six slanted cuts of a
    float32 heat sink's fins and base."""
    import json
    from pathlib import Path

    data = json.loads((Path(__file__).parent / "data" / "heat_sink_section.json").read_text())
    return pds.Region.from_shapely(shapely.MultiPolygon([shapely.Polygon(r) for r in data["rings"]]))


@pytest.mark.parametrize("seed", range(3))
def test_a_move_onto_a_hidden_bend_keeps_every_chord_short_enough_to_join(seed):
    """The base's slanted side hides a reflex vertex (float32 noise) 0.45 r from a chord
    end, which the sampler moved onto it (graded_sampling._unhidden): its other chord grew
    to 3.11 between r = 1.81 and 1.19, past 2 min r / (1 - L) = 2.97, beyond what any
    triangle on it can have. The two samples were left unjoined and the lens beside the
    chord, where no dart goes, uncovered: FAILED on every seed. A move now keeps each
    chord it lengthens within √3 min r of its ends."""
    from pds_plugin.graded_sampling import graded_poisson_disc

    region = heat_sink_section()
    mesh = graded_mesh(region, seed)
    certificate = mesh.certificate()
    assert certificate.ok_with_exceptions, str(certificate)
    samples = graded_poisson_disc(region, mesh.field, seed)
    assert np.array_equal(samples.points, mesh.vertices)
    L = mesh.field.grading
    for ring in samples.rings:
        following = np.roll(ring, -1)
        length = np.hypot(*(samples.points[following] - samples.points[ring]).T)
        bound = 2 * np.minimum(samples.radius[ring], samples.radius[following]) / (1 - L)
        assert np.all(length < bound)


def test_the_quadtree_boxes_bound_r_from_below_and_reach_the_cap_away_from_cones():
    """Each leaf carries a lower bound ``low`` of r on it (the boxes a single disc covers,
    and the darts' refusal test, read it). r(c) - L x half-diagonal was the bound; where
    r is the cap, the cones' own minimum less that is tighter, and it is the cap itself
    on boxes no cone comes near (narrow facets meshed at alpha: the boundary discs cover
    them, but not with radius 0.9 alpha, and 10,000 darts were refused on 50 strips).
    Checked against r at random points of every leaf."""
    from pds_plugin import graded_sampling
    from pds_plugin.sizing import RadiusField

    region = pds.Region.from_shapely(box(0, 0, 20, 3))
    field = RadiusField([[1.0, 1.0], [15.0, 2.0]], [0.2, 0.35], 0.2, 1.0)
    sampler = graded_sampling._GradedSampler(region, field, 10**5)
    sampler.add_boundary(30.0, np.random.default_rng(0))
    sampler.kernel_field = graded_sampling.kern.Field(field)
    x, y, size, low, high, _ = sampler._leaves()
    u = np.random.default_rng(0).random((len(x), 16, 2))
    points = np.stack([x, y], axis=1)[:, None, :] + u * size[:, None, None]
    r = field(points.reshape(-1, 2)).reshape(len(x), 16)
    assert np.all(r >= low[:, None] - 1e-12) and np.all(r <= high[:, None] + 1e-12)
    far = np.hypot(x + size / 2 - 1, y + size / 2 - 1) > 5
    far &= np.hypot(x + size / 2 - 15, y + size / 2 - 2) > 4
    assert far.any() and np.all(low[far] == 1.0)
