"""The radius field of graded meshes (sizing.py): L-Lipschitz, capped, evaluated exactly,
following walls seen through material and not gaps, and bounded below by the real
features at sharp corners."""

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, Point, Polygon, box

import pds_plugin as pds
from pds_plugin._sizing_kernels import (build_cone_tree, cone_minimum, cone_minimum_pairwise,
                                        dominated_cones, dominated_pairwise, nearest_facing,
                                        normal_bounds)
from pds_plugin.errors import ArgumentError, ArgumentTypeError
from pds_plugin.sizing import RadiusField, angle_bound, inradius, radius_field

from regions import multiscale_plates


@settings(max_examples=10, deadline=None)
@given(multiscale_plates(), st.sampled_from([0.05, 0.2, 0.45]))
def test_the_radius_field_is_lipschitz_capped_and_exact(geometry, grading):
    region = pds.Region.from_shapely(geometry)
    field = radius_field(region, grading)
    rng = np.random.default_rng(0)
    xmin, ymin, xmax, ymax = region.bounds
    a = rng.uniform([xmin, ymin], [xmax, ymax], (4000, 2))
    b = a + rng.normal(scale=rng.choice([0.01, 0.3, 3.0], size=(4000, 1)), size=(4000, 2))
    ra, rb = field(a), field(b)
    assert np.all(np.abs(ra - rb) <= grading * np.hypot(*(a - b).T) * (1 + 1e-9) + 1e-12)
    assert np.all((ra > 0) & (ra <= field.cap))
    # the tree search equals the brute-force minimum over the cones (to hypot vs sqrt)
    cones = field.sizes + grading * np.hypot(*(a[:200, None, :] - field.features).transpose(2, 0, 1))
    assert np.allclose(ra[:200], np.minimum(cones.min(axis=1), field.cap), rtol=1e-13, atol=0)


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**16), st.sampled_from([0.05, 0.2, 0.45]), st.integers(1, 400))
def test_dropping_dominated_cones_leaves_the_field_unchanged(seed, grading, count):
    # clustered features, some of them duplicates: every cone dropped is nowhere below
    # the others, and of equal cones exactly one is kept
    rng = np.random.default_rng(seed)
    features = rng.normal(scale=rng.choice([0.1, 1.0, 10.0], size=(count, 1)), size=(count, 2))
    sizes = rng.uniform(0.01, 2.0, count)
    twins = rng.integers(0, count, count // 4)
    features, sizes = np.vstack([features, features[twins]]), np.append(sizes, sizes[twins])
    field = RadiusField(features, sizes, grading, cap=1e9)
    x = rng.uniform(-30, 30, (2000, 2))
    every = sizes + grading * np.hypot(*(x[:, None, :] - features).transpose(2, 0, 1))
    assert np.allclose(field(x), every.min(axis=1), rtol=1e-13, atol=0)
    f = field.features
    kept = field.sizes + grading * np.hypot(*(f[:, None, :] - f).transpose(2, 0, 1))
    np.fill_diagonal(kept, np.inf)
    assert np.all(kept.min(axis=1) > field.sizes)       # none of the kept is dominated
    assert len(np.unique(field.features, axis=0)) == len(field.features)


@pytest.mark.parametrize("threads", [1, 2])
def test_the_field_at_quarters_is_the_field_at_their_centres_bit_for_bit(threads):
    from pds_plugin._parallel import get_threads, set_threads
    plate = box(0, 0, 40, 10).difference(box(10, 3, 10.3, 3.3)).difference(box(20, 2, 30, 2.5))
    field = radius_field(pds.Region.from_shapely(plate), 0.2)
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-1, 40, 5000), rng.uniform(-1, 10, 5000)
    size = np.exp2(rng.integers(-20, 3, 5000)).astype(float)
    half = 0.5 * size
    quarter = 0.5 * np.tile(half, 4)
    centres = np.column_stack([np.concatenate([x, x + half, x, x + half]) + quarter,
                               np.concatenate([y, y, y + half, y + half]) + quarter])
    before = get_threads()
    set_threads(threads)
    try:
        assert field.at_quarters(x, y, size).tobytes() == field(centres).tobytes()
    finally:
        set_threads(before)


def test_walls_shrink_the_field_gaps_and_notches_do_not():
    # two plates 0.02 apart and a notch 0.02 wide: along the gap and the notch's walls
    # the radius stays the plates' scale; a wall 0.5 thick shrinks it to below 0.5
    geometry = shapely.union_all([box(0, 0, 10, 10).difference(box(4.99, 3, 5.01, 10)),
                                  box(10.02, 0, 20, 10).difference(box(12, 1, 19.5, 9))])
    field = radius_field(pds.Region.from_shapely(geometry), 0.2)
    notch_wall, gap_side, thin_wall = field([[4.98, 8.0], [9.99, 5.0], [19.5, 5.0]])
    assert notch_wall > 1.0 and gap_side > 1.0
    assert thin_wall < 0.5


def test_the_wall_search_visits_every_facing_point_nearest_first():
    # random points and normals, a fifth on integer coordinates (ties and duplicates):
    # called again from each answer, the search lists exactly the points facing each one
    # within its reach, in order of (distance, index), as a scan of all points does
    rng = np.random.default_rng(3)
    xy = rng.uniform(0, 10, (500, 2))
    xy[:100] = np.round(xy[:100])
    angle = rng.uniform(0, 2 * np.pi, 500)
    normal = np.column_stack([np.cos(angle), np.sin(angle)])
    rows = np.arange(0, 500, 7)
    reach = rng.uniform(0.5, 6, len(rows))
    tree = build_cone_tree(xy, np.zeros(500), 8)[:6]
    tree += (normal_bounds(normal, tree[1], tree[2], tree[0]),)
    after_d, after_j = np.zeros(len(rows)), np.full(len(rows), np.iinfo(np.int64).max)
    found = [[] for _ in rows]
    while True:
        d, j = nearest_facing(xy, normal, rows, reach, after_d, after_j, -0.5, *tree)
        if not (j >= 0).any():
            break
        for r in np.flatnonzero(j >= 0):
            found[r].append(j[r])
        after_d, after_j = np.where(j >= 0, d, np.inf), j
    for r, i in enumerate(rows):
        step = xy - xy[i]
        e = np.sqrt(step[:, 0] * step[:, 0] + step[:, 1] * step[:, 1])
        faces = ((step @ normal[i] > 1e-9 * e) & (np.sum(step * normal, axis=1) < -1e-9 * e)
                 & (normal @ normal[i] < -0.5) & (e > 0) & (e < reach[r]))
        expected = np.flatnonzero(faces)
        assert found[r] == expected[np.lexsort((expected, e[expected]))].tolist()
    assert sum(map(len, found)) > 200


def test_a_sharp_corner_does_not_collapse_the_field():
    # a 46° wedge 10 long: near its tip the two sides are closer than any size, but
    # they are the corner's own pieces, so the corner disc (0.4 x the distance to other
    # boundary, here about 10) sizes the tip. Counting them as walls took an STL
    # section's 46° corner down to r = 1e-7, and its sampling never ended.
    half = math.tan(math.radians(23))
    wedge = Polygon([(0, 0), (10, -10 * half), (20, -10 * half), (20, 10 * half), (10, 10 * half)])
    field = radius_field(pds.Region.from_shapely(wedge), 0.2)
    assert field.sizes.min() > 1.0
    assert field([[0.0, 0.0]])[0] > 1.0


def test_a_spike_is_a_wall_beyond_its_tips_disc():
    """A 20° spike on a plate: within its tip's disc (0.4 x the 20 units to the plate's
    side, the corner's size) the tip sets r; beyond it the spike is a wall like any
    other, r <= 0.9 x its width. The shoulders along the tip's sides (features that keep
    the field flat where the tip's neighbours go) also suspended the wall rule, up to
    three sizes from the tip: r was 4.7 where the spike is 3.5 wide (a held-out shaft
    section, seed 32, was left uncovered past such a tip)."""
    spike = box(0, 0, 20, 20).union(Polygon([(20, 6.5), (40, 10), (20, 13.5)]))
    field = radius_field(pds.Region.from_shapely(spike))
    for x in (25.0, 30.0):
        width = 2 * (40 - x) * math.tan(math.radians(10))
        assert field([[x, 10.0]])[0] <= 0.9 * width * (1 + 1e-9)


def test_a_corner_near_a_long_edge_is_sized_by_its_foot_on_it():
    """A reflex corner 0.0036 from a 46 long edge (the root of a gear's tooth at a held-out
    plane, nearly pinching the section): the corner's disc is 0.4 x its distance to the
    nearest boundary point off its own pieces, and that point is its foot on the edge,
    not the edge's nearest densified point (0.3 away at the first densification): the
    disc was 0.06 wide, hid the neck from the wall rule, and the graded mesh was
    non-manifold there (FAILED)."""
    ring = [(-19.1924, 1.1375), (27.1251, 5.7166), (27.5089, 6.5365), (26.4326, 8.3352),
            (23.5739, 5.3691), (22.9011, 6.3661), (22.21, 7.3302), (22.21, 14.0),
            (-19.1924, 14.0)]
    region = pds.Region.from_shapely(Polygon(ring))
    neck = Point(ring[4]).distance(LineString(ring[:2]))
    assert radius_field(region)([ring[4]])[0] <= 0.4 * neck * (1 + 1e-9)
    for seed in range(2):
        cert = pds.mesh_region(region, "auto", graded=True, seed=seed).certificate()
        assert cert.ok, str(cert)


@settings(max_examples=6, deadline=None)
@given(multiscale_plates())
def test_a_corner_stops_searching_where_no_point_can_change_its_size(geometry):
    """A corner's size is min(0.4 x the distance to its nearest other point, its pieces'
    size): the search for that point stops at the distance where the first term passes
    the second (a large face's square corner saw every point of the face). The sizes are
    those of the unbounded search, bit for bit, the gear's corner by its foot too."""
    from pds_plugin import sizing

    gear = Polygon([(-19.1924, 1.1375), (27.1251, 5.7166), (27.5089, 6.5365),
                    (26.4326, 8.3352), (23.5739, 5.3691), (22.9011, 6.3661), (22.21, 7.3302),
                    (22.21, 14.0), (-19.1924, 14.0)])
    slotted = box(0, 0, 100, 60).difference(box(20, 29.5, 80, 30.5))
    regions = [pds.Region.from_shapely(g) for g in (geometry, gear, box(0, 0, 100, 60),
                                                    box(0, 0, 100, 6), slotted)]
    caps = [None, 0.5, 2.0]                # a remeshed face's cap is small beside it
    bounded = [radius_field(region, cap=cap) for region in regions for cap in caps]
    search = sizing._nearest_other
    sizing._nearest_other = lambda *args: search(*args[:-1], np.full(len(args[4]), np.inf))
    try:
        unbounded = [radius_field(region, cap=cap) for region in regions for cap in caps]
    finally:
        sizing._nearest_other = search
    for a, b in zip(bounded, unbounded):
        assert np.array_equal(a.features, b.features) and np.array_equal(a.sizes, b.sizes)


def test_the_proven_bound():
    assert angle_bound(0.1) == pytest.approx(math.degrees(math.asin(0.45)))
    assert angle_bound(0.1) > math.degrees(math.asin((1 - 2 * 0.1) / 2))    # the issue's
    field = RadiusField([[0, 0]], [1.0], 0.3, cap=5.0)
    assert field([[0, 0], [3, 4]]).tolist() == [1.0, 2.5]


def test_the_inradius_is_the_region_size():
    assert inradius(pds.Region.from_shapely(box(0, 0, 40, 10))) == pytest.approx(5.0, rel=0.02)


def test_a_user_sizing_is_combined_by_min():
    region = pds.Region.from_shapely(box(0, 0, 20, 10))
    field = radius_field(region, 0.2, sizing=lambda x, y: 0.2 + 0.1 * x)
    points = np.array([[0.0, 5.0], [19.0, 5.0]])
    assert field(points).tolist() == pytest.approx([0.2, min(0.2 + 1.9, field.cap)])


@pytest.mark.parametrize("options, error, message", [
    ({"grading": 1.0}, ArgumentError, "grading must lie in"),
    ({"grading": "steep"}, ArgumentTypeError, "grading must be a number"),
    ({"sizing": 3.0}, ArgumentTypeError, "sizing must be a callable"),
])
def test_bad_field_options_are_named(options, error, message):
    region = pds.Region.from_shapely(box(0, 0, 4, 1))
    with pytest.raises(error, match=message):
        radius_field(region, **{"grading": 0.2, **options})


def test_a_bad_user_sizing_is_named_where_it_fails():
    field = radius_field(pds.Region.from_shapely(box(0, 0, 4, 1)), 0.2,
                         sizing=lambda x, y: np.where(x > 2, -1.0, 1.0))
    with pytest.raises(ArgumentError, match="positive finite radii"):
        field([[3.0, 0.5]])


def test_fields_measured_together_are_the_fields_one_by_one():
    """radius_fields of regions a gap apart gives each region's radius_field bit for bit
    (walls, corners with shoulders, holes, a spike, regions of different round counts);
    regions too close are measured one by one, likewise."""
    from shapely.geometry import Polygon, box
    from pds_plugin.region import Region
    from pds_plugin.sizing import radius_field, radius_fields

    shapes = [box(0, 0, 4, 1), box(0, 0, 6, 6).difference(box(1, 1, 2, 5)),
              Polygon([(0, 0), (5, 0), (0.4, 0.3)]), box(0, 0, 3, 3).difference(box(1, 1, 2, 2)),
              Polygon([(0, 0), (3, 0), (3, 0.2), (0.2, 0.2), (0.2, 3), (0, 3)])]
    cap = 0.8
    for spacing in (10.0, 7.0):                 # apart, and closer than 2.25 cap
        regions = [Region.from_shapely(shapely.affinity.translate(shape, spacing * k, 0))
                   for k, shape in enumerate(shapes)]
        together = radius_fields(regions, 0.2, cap)
        for field, region in zip(together, regions):
            alone = radius_field(region, 0.2, cap)
            assert np.array_equal(field.features, alone.features)
            assert np.array_equal(field.sizes, alone.sizes)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("old, new", [(400, 60), (20, 10)])     # by trees, by pairs
def test_a_field_with_cones_added_is_the_field_of_both_feature_sets(seed, old, new):
    """RadiusField.with_cones tests the field's own features against the new cones only;
    it must keep exactly the cones a RadiusField of both sets keeps (ties, cones equal
    to an old one, cones at the cap, a dominated old one), so the fields read the same
    bit for bit."""
    rng = np.random.default_rng(seed)
    cap, L = 1.0, float(rng.uniform(0.1, 0.6))
    field = RadiusField(rng.uniform(0, 10, (old, 2)), rng.uniform(0.01, 1.2, old), L, cap)
    points = np.vstack([rng.uniform(0, 10, (new, 2)), field.features[:5], field.features[5:7]])
    sizes = np.concatenate([rng.uniform(0.005, 1.3, new), field.sizes[:5],
                            0.5 * field.sizes[5:7]])            # equal, and below two old
    both = RadiusField(np.vstack([field.features, points]),
                       np.concatenate([field.sizes, sizes]), L, cap)
    added = field.with_cones(points, sizes)
    np.testing.assert_array_equal(added.features, both.features)
    np.testing.assert_array_equal(added.sizes, both.sizes)
    assert len(both.sizes) < len(field.sizes) + len(sizes)      # some were dropped
    x = rng.uniform(-1, 11, (2000, 2))
    np.testing.assert_array_equal(added(x), both(x))
    for added, reference in ((field.with_cones(np.zeros((0, 2)), []), field),
                             (RadiusField(np.zeros((0, 2)), [], L, cap).with_cones(points, sizes),
                              RadiusField(points, sizes, L, cap))):
        np.testing.assert_array_equal(added.sizes, reference.sizes)
        np.testing.assert_array_equal(added(x), reference(x))


@pytest.mark.parametrize("seed", range(8))
def test_the_pairwise_cone_kernels_answer_as_the_tree_search(seed):
    """A few cones are tested and read pair by pair (``dominated_pairwise``,
    ``cone_minimum_pairwise``), not through a cone tree: the same answers bit for bit,
    twins (equal cones) and the queries' form (old cones against new) included."""
    rng = np.random.default_rng(seed)
    count, L, cap = int(rng.integers(2, 80)), float(rng.uniform(0.05, 0.6)), 1.5
    xy = rng.normal(scale=rng.choice([0.1, 1.0, 10.0]), size=(count, 2))
    s = rng.uniform(0.01, 2.0, count)
    twins = rng.integers(0, count, count // 3 + 1)
    xy, s = np.vstack([xy, xy[twins]]), np.append(s, s[twins])
    tree = build_cone_tree(xy, s, 8)
    for start in (0, count // 2):
        assert np.array_equal(dominated_pairwise(xy, s, L, start),
                              dominated_cones(xy, s, L, *tree, start))
    old = np.vstack([xy[twins], rng.normal(size=(30, 2))])
    old_s = np.append(s[twins], rng.uniform(0.01, 2.0, 30))
    assert np.array_equal(dominated_pairwise(xy, s, L, queries=old, query_s=old_s),
                          dominated_cones(xy, s, L, *tree, queries=old, query_s=old_s))
    x = np.vstack([xy, rng.uniform(-20, 20, (500, 2))])
    assert np.array_equal(cone_minimum_pairwise(x, xy, s, L, cap),
                          cone_minimum(x, xy, s, L, cap, *tree))


def test_the_wall_search_tries_a_bounded_number_of_facing_points(monkeypatch):
    """A ring folded back onto its own vertex (a zero-width spike): its points face
    thousands of points whose midpoints lie on its boundary, and the wall search tried
    them one call each (3,276 calls, 37 s for one field). It now takes the last of
    _FACING_TRIES as the wall (nearer: a smaller size, never a larger one)."""
    from regions import folded_star
    from pds_plugin import sizing

    calls = []
    monkeypatch.setattr(sizing.kern, "nearest_facing",
                        lambda *args: calls.append(1) or nearest_facing(*args))
    region = pds.Region.from_shapely(folded_star())
    field = sizing.radius_field(region, 0.2, 3e-4)
    assert len(calls) <= sizing._ROUNDS * sizing._FACING_TRIES
    assert 0 < field.sizes.min() < 3e-4


def test_a_field_searched_from_c_still_pickles():
    """A field keeps its compiled view (``_kernel``) once made; a pickle (Dask ships a
    batch's meshes with their fields) leaves it out, and the copy reads the same."""
    import pickle

    field = RadiusField([[0, 0], [3, 1]], [0.1, 0.2], 0.3, cap=1.0)
    assert field._kernel is field._kernel
    copy = pickle.loads(pickle.dumps(field))
    x = np.random.default_rng(0).uniform(-2, 5, (100, 2))
    np.testing.assert_array_equal(copy(x), field(x))
    assert copy._kernel is not field._kernel
