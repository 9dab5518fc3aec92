"""feature_size: hand-computed widths, the adjacency rule and a brute-force oracle for the
spatial search (suggest_alpha and auto_mesh, built on it, are tested in test_pipeline)."""

import itertools
import math

import numpy as np
import pytest
import shapely
import shapely.affinity
from hypothesis import given, settings, strategies as st
from shapely.geometry import MultiPolygon, Point, Polygon, box

from pds_plugin import Region, feature_size, suggest_alpha
from pds_plugin.analysis.feature import ADJACENT_TURNING, SHARP_TIP, STRIP_END


def region(geometry):
    return Region.from_shapely(geometry)


def on_boundary(reg, points):
    return shapely.distance(reg.geometry.boundary, shapely.points(points)).max()


def test_ring_wall_thickness_is_the_distance_between_its_circles():
    outer, inner = Point(0, 0).buffer(1.0, quad_segs=64), Point(0, 0).buffer(0.8, quad_segs=64)
    ring = region(outer.difference(inner))
    fs = feature_size(ring)
    assert fs.value == pytest.approx(outer.exterior.distance(inner.exterior), rel=1e-12)
    assert 0.2 * math.cos(math.pi / 256) - 1e-3 < fs.value <= 0.2
    assert fs.kind == "wall"
    assert {f.hole for f in fs.features} == {None, 0}


@pytest.mark.parametrize("gap", [0.01, 0.25, 3.0])
def test_two_squares_at_a_known_distance(gap):
    # squares of side 5, so the gap (< 5) is the smallest feature of the paper's complex
    squares = region(box(0, 0, 5, 5).union(box(5 + gap, 2, 10 + gap, 7)))
    fs = feature_size(squares, conforming=False)
    assert fs.value == pytest.approx(gap, rel=1e-12)
    assert fs.kind == "gap"
    assert sorted(f.component for f in fs.features) == [0, 1]
    assert np.linalg.norm(fs.points[0] - fs.points[1]) == pytest.approx(gap, rel=1e-12)
    # a conforming mesh keeps the gap open: the squares' width is what limits alpha
    walls = feature_size(squares)
    assert (walls.value, walls.kind) == (pytest.approx(5, rel=1e-12), "wall")


@pytest.mark.parametrize("width", [0.05, 0.3, 0.9])
def test_slot_width(width):
    # a slot 1.5 deep cut down from the top of a 4 x 3 plate; all walls are >= 1.5 thick
    plate = region(box(0, 0, 4, 3).difference(box(1.5, 1.5, 1.5 + width, 4)))
    fs = feature_size(plate, conforming=False)
    assert fs.value == pytest.approx(width, rel=1e-12)
    assert fs.kind == "gap"
    assert on_boundary(plate, fs.points) < 1e-12


def test_hole_to_hole_and_hole_to_outline_walls():
    plate = box(0, 0, 10, 10).difference(box(1, 1, 4, 9)).difference(box(4.15, 1, 8, 9))
    fs = feature_size(region(plate))
    assert fs.value == pytest.approx(0.15, rel=1e-12)
    assert (fs.kind, sorted(f.hole for f in fs.features)) == ("wall", [0, 1])
    fs = feature_size(region(box(0, 0, 10, 10).difference(box(0.07, 1, 8, 9))))
    assert fs.value == pytest.approx(0.07, rel=1e-12) and fs.kind == "wall"
    assert {f.hole for f in fs.features} == {None, 0}


@pytest.mark.parametrize("segments", [32, 256, 4096])
def test_a_finely_segmented_circle_is_not_penalised(segments):
    # the chord spanning 150 degrees of arc, whatever the tessellation
    r = 2.0
    fs = feature_size(region(Point(0, 0).buffer(r, quad_segs=segments // 4)))
    step = 2 * math.pi / segments
    assert 2 * r * math.sin((ADJACENT_TURNING - step) / 2) - 1e-9 <= fs.value
    assert fs.value <= 2 * r * math.sin(ADJACENT_TURNING / 2) + 1e-9


def test_hole_circles_give_about_their_radius_and_the_smaller_one_wins():
    disc = Point(0, 0).buffer(10, quad_segs=64)
    big, small = Point(-4, 0).buffer(4, quad_segs=64), Point(5, 0).buffer(1, quad_segs=64)
    fs = feature_size(region(disc.difference(big).difference(small)), conforming=False)
    assert fs.features[0].hole == fs.features[1].hole == 1
    assert 2 * math.sin((ADJACENT_TURNING - 2 * math.pi / 256) / 2) - 1e-9 <= fs.value
    assert fs.value <= 2 * math.sin(ADJACENT_TURNING / 2) + 1e-9


def test_sharp_v_notch_is_measured_at_its_opening_not_at_its_tip():
    # notch from (4, 10) down to the apex (5, 2) and back up to (6, 10): the legs meet at
    # the apex (one feature); the nearest other feature is the opening corner (6, 10),
    # at distance |(-1, 8) x (1, 8)| / |(1, 8)| = 16 / sqrt(65) from the other leg
    notch = Polygon([(0, 0), (10, 0), (10, 10), (6, 10), (5, 2), (4, 10), (0, 10)])
    expected = 16 / math.sqrt(65)
    assert feature_size(region(notch), conforming=False).value == pytest.approx(expected, rel=1e-12)
    # splitting the legs and edges into collinear pieces changes nothing
    split = region(shapely.segmentize(notch, 0.05))
    assert len(split.segments) > 400
    assert feature_size(split, conforming=False).value == pytest.approx(expected, rel=1e-9)


def test_walls_count_and_gaps_do_not_for_conforming_meshes():
    # a 4 x 3 plate with a slot 0.1 wide (a gap) and a hole leaving a wall 0.25 thick
    plate = region(box(0, 0, 4, 3).difference(box(1, 1, 1.1, 4))
                   .difference(box(2.5, 1, 3.75, 2)))
    walls, both = feature_size(plate), feature_size(plate, conforming=False)
    assert (both.value, both.kind) == (pytest.approx(0.1, rel=1e-12), "gap")
    assert (walls.value, walls.kind) == (pytest.approx(0.25, rel=1e-12), "wall")
    assert {f.hole for f in walls.features} == {None, 0}
    assert on_boundary(plate, walls.points) < 1e-12
    middle = walls.points.mean(axis=0)
    assert plate.geometry.contains(Point(middle))            # the segment runs through material
    assert suggest_alpha(plate) == pytest.approx(0.25 / 4, rel=1e-12)
    assert suggest_alpha(plate, conforming=False) == pytest.approx(0.1 / 4, rel=1e-12)
    # between the long sides of a rectangle the closest points may be its corners, so the
    # segment between them is a short side, on the boundary: still a wall
    bar = feature_size(region(box(0.88, 0, 2.88, 1)))
    assert (bar.value, bar.kind) == (pytest.approx(1, rel=1e-12), "wall")


def test_a_segment_leaving_the_region_between_its_ends_is_no_wall():
    # a disc (radius 0.75, quad_segs=8) overlapping the right side x = 1 of a bar: between
    # the bar's side and the disc's lowest vertices the segment starts and ends in the
    # region but crosses the notch under the arc, so its midpoint alone would call it a
    # wall 0.787 thick; the thinnest wall is the bar's width, 1 (found by hypothesis)
    disc = Point(1.5, 6).buffer(0.75, quad_segs=8)
    reg = region(shapely.set_precision(box(0, 4, 1, 7).union(disc), 1e-6))
    fs = feature_size(reg)
    assert (fs.value, fs.kind) == (pytest.approx(1, rel=1e-12), "wall")
    assert fs.value == pytest.approx(brute_force(reg, walls_only=True), rel=1e-12)
    assert reg.geometry.buffer(1e-9).covers(shapely.LineString(fs.points))


def test_collinear_splits_are_one_feature():
    fs = feature_size(region(shapely.segmentize(box(0, 0, 3, 1), 0.01)))
    assert fs.value == pytest.approx(1.0, rel=1e-12)


def test_a_triangle_falls_back_to_its_smallest_altitude():
    fs = feature_size(region(Polygon([(0, 0), (4, 0), (0, 1)])))
    assert fs.value == pytest.approx(4 / math.hypot(4, 1), rel=1e-12)


def test_features_name_the_segments_that_hold_the_points():
    plate = region(box(0, 0, 4, 3).difference(box(1.5, 0.5, 1.8, 4)))
    fs = feature_size(plate, conforming=False)
    for feature, point in zip(fs.features, fs.points):
        ring = plate.rings[feature.ring]
        a, b = ring[feature.segment], ring[(feature.segment + 1) % len(ring)]
        assert shapely.LineString([a, b]).distance(Point(point)) < 1e-12
        assert feature.point == tuple(point)
    assert "gap of width 0.3" in str(fs) and "outline of component 0" in str(fs)


def test_touching_boundaries_have_no_usable_alpha():
    # a hole touching the outline at one point is valid, but no alpha can keep them apart
    # (Region.from_shapely opens the point: tests/test_tolerance.py; built directly, the
    # region keeps it)
    geometry = box(0, 0, 4, 4).difference(Polygon([(0, 2), (2, 1), (2, 3)]))
    touching = Region(MultiPolygon([geometry]), np.eye(4))
    assert feature_size(touching).value == 0
    with pytest.raises(ValueError, match="touches itself"):
        suggest_alpha(touching)
    assert feature_size(region(geometry)).value > 0


def test_bad_input():
    with pytest.raises(TypeError, match="Region"):
        feature_size(box(0, 0, 1, 1))


# --- the spatial search against a brute-force reading of the definition ----------------

def brute_force(reg, walls_only=False):
    """Minimum distance over all non-adjacent segment pairs, straight from the rule; with
    ``walls_only`` over the pairs whose closest points are joined through the region and
    are not one edge apart (but at a strip's end)."""
    rings = []
    for ring in reg.rings:
        turn = turning(ring)
        keep = np.abs(turn) > 1e-7
        rings.append((ring[keep], np.abs(turn[keep])))
    best = math.inf
    segments = [(r, k) for r, (ring, _) in enumerate(rings) for k in range(len(ring))]
    for (r1, i), (r2, j) in itertools.combinations(segments, 2):
        ring, turn = rings[r1]
        n = len(ring)
        if r1 == r2:
            forward = turn[i + 1:j + 1].sum()
            backward = turn.sum() - forward
            if j - i in (1, n - 1) or min(forward, backward) < ADJACENT_TURNING:
                continue
        a = shapely.LineString([ring[i], ring[(i + 1) % n]])
        other = rings[r2][0]
        b = shapely.LineString([other[j], other[(j + 1) % len(other)]])
        if walls_only and (not all(reg.geometry.buffer(1e-9).covers(line)
                                   for line in _closest_lines(a, b))
                               or r1 == r2 and _across_one_edge(a, b, (j - i) % n, n)):
            continue
        best = min(best, a.distance(b))
    return best


def _across_one_edge(a, b, steps, n):
    """Whether segments a and b of one ring of n segments, b ``steps`` segments after a
    along it, have one edge between them (two steps on or back) that is not a strip's
    end (both its corners convex, a and b opposed to within STRIP_END)."""
    (p0, p1), (q0, q1) = np.asarray(a.coords), np.asarray(b.coords)
    if steps == n - 2:
        (p0, p1), (q0, q1) = (q0, q1), (p0, p1)
    elif steps != 2:
        return False

    def turn(u, v):
        return math.atan2(u[0] * v[1] - u[1] * v[0], u @ v)

    first, second = turn(p1 - p0, q0 - p1), turn(q0 - p1, q1 - q0)
    return not (first > 0 and second > 0 and first + second >= math.pi - STRIP_END)


def turning(ring):
    into, out = ring - np.roll(ring, 1, 0), np.roll(ring, -1, 0) - ring
    return np.arctan2(into[:, 0] * out[:, 1] - into[:, 1] * out[:, 0], (into * out).sum(1))


def _closest_lines(a, b):
    """Shapely's shortest line between segments a and b, and, when they are parallel and
    face each other, also the one across the middle of their overlap: the closest points
    of parallel segments are not unique, and a shortest line along the boundary (from the
    end of one to the other) says nothing of what lies between them (a notch's sides
    are a gap, though the line along its end runs on the boundary)."""
    lines = [shapely.shortest_line(a, b)]
    (p0, p1), (q0, q1) = np.asarray(a.coords), np.asarray(b.coords)
    u, v = p1 - p0, q1 - q0
    if abs(u[0] * v[1] - u[1] * v[0]) <= 1e-12 * np.linalg.norm(u) * np.linalg.norm(v):
        t = sorted(np.clip([(q0 - p0) @ u / (u @ u), (q1 - p0) @ u / (u @ u)], 0, 1))
        if t[1] > t[0]:
            middle = p0 + (t[0] + t[1]) / 2 * u
            lines.append(shapely.shortest_line(shapely.Point(middle), b))
    return lines


@st.composite
def regions(draw):
    """Unions of boxes and discs with holes cut out: several components, thin walls."""
    coords = st.floats(0, 10, allow_nan=False).map(lambda v: round(v, 2))
    sizes = st.floats(0.3, 4).map(lambda v: round(v, 2))
    shape = st.tuples(st.booleans(), coords, coords, sizes, sizes)

    def make(is_disc, x, y, w, h):
        return Point(x, y).buffer(w / 2, quad_segs=draw(st.integers(2, 12))) if is_disc \
            else box(x, y, x + w, y + h)

    solid = shapely.union_all([make(*s) for s in draw(st.lists(shape, min_size=1, max_size=4))])
    for s in draw(st.lists(shape, max_size=3)):
        solid = solid.difference(make(*s))
    solid = shapely.set_precision(solid, 1e-6)
    parts = [p for p in shapely.get_parts(solid) if p.geom_type == "Polygon" and p.area > 0.05]
    if not parts or not shapely.MultiPolygon(parts).is_valid:
        from hypothesis import reject
        reject()
    return Region.from_shapely(shapely.MultiPolygon(parts))


def test_a_bump_between_two_reflex_corners_on_one_line_is_a_wall():
    # the base of a bump on an octagon's edge: its two reflex corners lie on that edge's
    # line (to rounding), the segment between them runs through material; the search
    # skipped it (it reaches the far corner from just behind the next segment's line)
    reg = Region.from_shapely(shapely.Polygon([
        (0, -2), (1.414214, -1.414214), (2, 0), (1.414214, 1.414214), (1, 1.585786),
        (1, 1.97), (0.072426, 1.97), (0, 2), (-1.414214, 1.414214), (-2, 0),
        (-1.414214, -1.414214)]))
    expected = brute_force(reg, walls_only=True)
    assert expected == pytest.approx(1.00399896577, rel=1e-9)
    assert feature_size(reg).value == pytest.approx(expected, rel=1e-9, abs=1e-12)


@settings(max_examples=40, deadline=None)
@given(regions())
def test_spatial_search_equals_brute_force(reg):
    if len(reg.segments) > 250:
        reg = Region.from_shapely(reg.geometry.simplify(0.05))
    spikes = any((turning(ring) > math.pi - SHARP_TIP).any() for ring in reg.rings)
    for conforming in (False, True) if not spikes else (False,):   # spikes: tested below
        expected = brute_force(reg, walls_only=conforming)
        fs = feature_size(reg, conforming=conforming)
        if math.isinf(expected):         # no non-adjacent pair: the altitude fallback
            assert fs.value > 0
        else:
            assert fs.value == pytest.approx(expected, rel=1e-9, abs=1e-12)
        assert np.linalg.norm(fs.points[0] - fs.points[1]) == pytest.approx(fs.value, abs=1e-12)
        assert on_boundary(reg, fs.points) < 1e-9


def test_scales_linearly():
    plate = box(0, 0, 10, 10).difference(Point(3, 3).buffer(2)).difference(box(6, 1, 6.4, 9))
    small = feature_size(region(plate)).value
    big = feature_size(region(shapely.affinity.scale(plate, 1000, 1000, origin=(0, 0)))).value
    assert big == pytest.approx(1000 * small, rel=1e-9)


@pytest.mark.parametrize("degrees", [0, 25, 40])
def test_a_tab_under_a_body_reads_as_the_rule_says_at_any_rotation(degrees):
    # an angle_block.STL section: a thin tab under a body, whose bottom and the body's
    # underside are parallel and overlap; the line across the middle of the overlap
    # leaves the region, so the pair is a gap. The search by runs of segments took
    # the line from the end of one (a corner) for the pair at 40° (0.079, not 0.669)
    tab = [(-0.3935, -0.5), (0.3935, -0.5), (0.3935, -0.48), (0.3345, -0.421),
           (0.6693, -0.421), (0.6693, 0.4741), (-0.6693, 0.4741), (-0.6693, -0.421),
           (-0.3345, -0.421), (-0.3935, -0.48)]
    reg = region(shapely.affinity.rotate(shapely.Polygon(tab), degrees, origin=(0, 0)))
    assert feature_size(reg).value == pytest.approx(brute_force(reg, walls_only=True),
                                                    rel=1e-12)
    assert feature_size(reg, conforming=False).value == pytest.approx(brute_force(reg),
                                                                      rel=1e-12)


def test_dense_arcs_are_measured_exactly_and_fast():
    # 160-vertex arcs against the brute force; a 40,000-vertex circle (quadratic in
    # pairs of runs of segments before: 5 s) has the chord spanning 150° of arc
    plate = region(box(-20, -20, 20, 20).difference(Point(3, 0).buffer(10, quad_segs=40)))
    for reg in (plate, region(Point(0, 0).buffer(10, quad_segs=40))):
        assert feature_size(reg).value == pytest.approx(brute_force(reg, walls_only=True),
                                                        rel=1e-12)
    disc = region(Point(0, 0).buffer(10, quad_segs=10_000))
    fs = feature_size(disc)
    assert fs.kind == "wall"
    assert fs.value == pytest.approx(20 * math.sin(math.radians(75)), rel=1e-3)


def test_a_spike_is_one_feature_for_conforming_meshes():
    """Two bores overlapping by a hair leave two 19.7° spikes of material between them,
    their sides tessellated arcs (as where cross-drilled holes meet in a CAD section).
    A spike thins to nothing at its tip at any alpha, and a conforming mesh samples its
    sides in mirror pairs: the width near a kink of its sides (0.015 here) asked
    "auto" for alpha 1/5000 of the part (a held-out cross-drilled block: 5 million
    samples, 78 s). For conforming meshes the spike is one feature; the paper's complex,
    which would bridge it, still counts it."""
    import pds_plugin as pds

    bores = Point(-2.95, 0).buffer(3, quad_segs=32).union(Point(2.95, 0).buffer(3, quad_segs=32))
    region = Region.from_shapely(box(-10, -10, 10, 10).difference(bores))
    size = feature_size(region)
    assert size.kind == "wall" and size.value == pytest.approx(4.05)   # bore to outline
    assert feature_size(region, conforming=False).value < 0.02
    mesh = pds.mesh_region(region, "auto", seed=0)
    assert mesh.certificate().ok_with_exceptions and len(mesh.vertices) < 1000


def test_a_corner_sharper_than_60_degrees_is_one_feature_with_a_kink_by_its_tip():
    """A 40° corner whose next vertex, 0.08 from the tip, turns by 10.2° (a twisted rod's
    section at a random plane): with the corner's 140° the ring turns by more than 150°
    there, so that vertex and the far side counted as a wall 0.05 wide, and uniform
    "auto" took 1.5 million samples in 10 s. The conforming sampler keeps the first
    samples beside a corner sharper than 60° its clearance away (alpha apart on straight
    sides): the width by its tip limits no alpha, as at a spike."""
    import pds_plugin as pds

    tip = np.array([0.0, 0.0])
    side = np.array([math.cos(math.radians(40)), math.sin(math.radians(40))])
    kink = tip + 0.08 * side
    bend = math.radians(40 - 10.2)                  # the side turns 10.2° outwards there
    corner = Polygon([tip, (12, 0), (12, 5), kink + 5 * np.array([math.cos(bend),
                                                                  math.sin(bend)]), kink])
    size = feature_size(Region.from_shapely(corner))
    assert size.value > 1.0                         # not 0.08 sin 40° = 0.05
    assert feature_size(Region.from_shapely(corner), conforming=False).value < 0.06
    mesh = pds.mesh_region(Region.from_shapely(corner), "auto", seed=0)
    assert mesh.certificate().ok_with_exceptions and len(mesh.vertices) < 2000


def test_an_edge_is_a_wall_only_at_a_strips_end():
    """A plate whose right side steps out by 0.03 halfway up (a plane cutting a gear's
    tessellated flank obliquely: a reflex corner, then a convex one), and a tooth whose
    18° tip is blunted by a 0.015 edge (a gear's tooth cut near its end): the ring turns
    by more than 150° across each, so the two ends of that edge counted as a wall, and
    uniform "auto" took 14-63 s on held-out gear sections. The segment between them is
    the boundary itself; only a strip's end, whose sides run opposite ways, is a wall."""
    import pds_plugin as pds

    plate = Polygon([(0, 0), (20, 0), (20, 5), (20.03, 5), (20.03, 10), (0, 10)])
    size = feature_size(Region.from_shapely(plate))
    assert size.kind == "wall" and size.value == pytest.approx(5)     # the step to the top
    assert feature_size(Region.from_shapely(plate), conforming=False).value == pytest.approx(0.03)
    half = math.radians(9)
    tooth = Polygon([(0, -3), (10, -3), (10, -10 * math.tan(half) - 0.0075), (20, -0.0075),
                     (20, 0.0075), (10, 10 * math.tan(half) + 0.0075), (10, 3), (0, 3)])
    assert feature_size(Region.from_shapely(tooth)).value > 1.0        # not 0.015
    strip = Region.from_shapely(box(0, 0, 20, 0.03))
    assert feature_size(strip).value == pytest.approx(0.03)
    for region in (plate, tooth):
        mesh = pds.mesh_region(Region.from_shapely(region), "auto", seed=0)
        assert mesh.certificate().ok_with_exceptions and len(mesh.vertices) < 5000


def circular_lens(half=6.75, tip_degrees=14.3, segments=400):
    """A plane near a cylinder's tangent: a chord 2 half long and its arc, meeting at
    tips of tip_degrees, the arc finely tessellated; and the lens's middle width."""
    tip = math.radians(tip_degrees)
    radius = half / math.sin(tip)
    theta = np.linspace(-tip, tip, segments)
    arc = np.column_stack([radius * (np.cos(theta) - math.cos(tip)), radius * np.sin(theta)])
    return Polygon(arc), radius * (1 - math.cos(tip))


def test_a_circular_lens_counts_at_its_middle():
    """A circular lens is 1 - s/2h of its tips' straight sides at s from a tip: at no
    point below one half, so with "half as wide" as the spike rule's bound no pair across
    it was a wall, and the feature size fell back to the distance from a tip's first
    vertex to the chord (0.008 here: uniform "auto" of a STEP knob's section, which holds
    such a lens, made 5 million samples in 40 s). It counts from 0.8 h on (LENS_RATIO)."""
    import pds_plugin as pds

    lens, middle = circular_lens()
    size = feature_size(Region.from_shapely(lens))
    assert size.kind == "wall" and 0.9 * middle < size.value <= middle
    mesh = pds.mesh_region(Region.from_shapely(lens), "auto", seed=0)
    assert mesh.certificate().ok_with_exceptions and len(mesh.vertices) < 1000


def test_walls_never_join_two_components():
    """A wall never joins two components (the segment between them leaves the region):
    beside a body, the lens's feature is still its own middle. The search skips the
    other components' segments (it tested every one facing the lens's tip pairs across
    the gap against the region first: 5 s for a STEP knob's section)."""
    lens, middle = circular_lens()
    body = box(-30, -15, -0.5, 15)
    size = feature_size(Region.from_shapely(lens.union(body)))
    assert size.kind == "wall" and 0.9 * middle < size.value <= middle
    assert len({f.ring_name for f in size.features}) == 1     # both on the lens


def test_a_lens_between_two_spikes_is_a_wall():
    """A sliver of a shaft's section (held out, seed 22): 18° spikes at both ends of a
    lens 0.12 wide in its middle. With it left out, "auto" took alpha 5 times its width,
    and the sliver's samples were left unjoined. Its segments are nearest each other by
    its tips, across the spikes (0.055 and 0.043: only the far tip's way round counted
    them as walls, when the near tip's verdict was overwritten), so it counts at its
    widest inscribed disc."""
    import pds_plugin as pds

    lens = Polygon([(-6.9535, -14.4168), (-8.339, -13.6302), (-8.2518, -13.7287),
                    (-7.7251, -14.117), (-7.1275, -14.3808)])
    size = feature_size(Region.from_shapely(lens))
    assert size.kind == "wall" and 0.1 < size.value < 0.13
    mesh = pds.mesh_region(Region.from_shapely(lens), "auto", seed=0)
    assert mesh.certificate().ok_with_exceptions


def test_a_region_of_spikes_only_is_as_thin_as_its_widest_disc():
    """A thin triangle whose long sides bulge out a hair (tessellated arcs): every pair
    facing across it is across its 5.7° spike, so no pair is a wall, and the fallback of
    a triangle, the smallest altitude, took a vertex by the tip (a held-out STEP vase's
    crescent: 0.00087 of its 0.45 width, 5 million samples). The width across its widest
    inscribed disc is its feature."""
    import pds_plugin as pds

    t = np.linspace(0, 1, 201)[:-1, None]
    bulge = 0.02 * np.sin(np.pi * t)                      # outwards, off each side's line
    apex, left, right = np.array([0.0, 10.0]), np.array([-0.5, 0.0]), np.array([0.5, 0.0])
    out_right, out_left = np.array([0.9988, 0.0499]), np.array([-0.9988, 0.0499])
    ring = np.concatenate([left + t * (right - left),
                           right + t * (apex - right) + bulge * out_right,
                           apex + t * (left - apex) + bulge * out_left])
    region = Region.from_shapely(Polygon(ring))
    size = feature_size(region)
    inradius = 2 * region.area / Polygon(ring).length                 # area / semiperimeter
    assert size.kind == "wall" and 0.8 * 2 * inradius < size.value <= 2 * inradius * 1.01
    mesh = pds.mesh_region(region, "auto", seed=0)
    assert mesh.certificate().ok_with_exceptions and len(mesh.vertices) < 2000
