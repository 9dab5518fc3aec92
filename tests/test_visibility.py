"""The exact tests of _visibility_kernels against the region bounded by the chords:
``points_inside`` and ``boxes_state`` give shapely's answers (``contains_xy``,
``intersects``, ``contains_properly``) on the chord polygons, also for points and boxes
on a vertex or an edge exactly."""

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon, box

import pds_plugin as pds
from pds_plugin import _visibility_kernels as vis_kern

STEP = 0.125    # lattice of the polygons, boxes and points: exact in binary


@st.composite
def lattice_regions(draw):
    """Unions of lattice boxes and lattice star polygons, minus lattice boxes: collinear
    edges, lattice points on slanted edges, several parts and holes."""
    def lattice_box():
        return st.tuples(st.integers(-8, 8), st.integers(-8, 8), st.integers(1, 10),
                         st.integers(1, 10)).map(
            lambda b: box(b[0] * STEP, b[1] * STEP, (b[0] + b[2]) * STEP, (b[1] + b[3]) * STEP))

    def star():
        n = draw(st.integers(3, 9))
        cx, cy = draw(st.integers(-6, 6)), draw(st.integers(-6, 6))
        angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
        radii = np.array(draw(st.lists(st.integers(2, 8), min_size=n, max_size=n)))
        xy = np.column_stack([cx + np.round(radii * np.cos(angles)),
                              cy + np.round(radii * np.sin(angles))]) * STEP
        polygon = Polygon(xy)
        return polygon if polygon.is_valid and polygon.area > 0 else box(0, 0, STEP, STEP)

    solids = draw(st.lists(lattice_box(), min_size=1, max_size=3)) + [star()]
    holes = draw(st.lists(lattice_box(), max_size=2))
    region = shapely.union_all(solids).difference(shapely.union_all(holes))
    parts = [p for p in shapely.get_parts(shapely.make_valid(region))
             if p.geom_type == "Polygon" and p.area > 0]
    return pds.Region.from_shapely(shapely.MultiPolygon(parts) if parts else box(0, 0, 1, 1))


def bundle(region, reach):
    """The chord bundle of the region's rings, and its cell sides."""
    points = np.concatenate(region.rings)
    ends = np.cumsum([len(ring) for ring in region.rings])
    rings = [np.arange(end - len(ring), end) for end, ring in zip(ends, region.rings)]
    vis = vis_kern.chord_bundle(points, rings, len(points), reach)
    return vis, vis_kern.cell_sides(vis)


reaches = st.sampled_from([0.01, STEP, 0.3, 2.0])


@settings(max_examples=60, deadline=None)
@given(lattice_regions(), reaches, st.integers(0, 2**32 - 1))
def test_points_inside_is_shapely_contains_xy(region, reach, seed):
    rng = np.random.default_rng(seed)
    lattice = rng.integers(-20, 21, (300, 2)) * STEP / rng.choice([1, 2], (300, 1))
    spread = rng.uniform(-2.5, 2.5, (300, 2))
    vertices = np.concatenate(region.rings)
    x, y = np.concatenate([lattice, spread, vertices]).T
    vis, sides = bundle(region, reach)
    expected = shapely.contains_xy(region.geometry, x, y)
    assert np.array_equal(vis_kern.points_inside(vis, sides, x, y), expected)


@settings(max_examples=60, deadline=None)
@given(lattice_regions(), reaches, st.integers(0, 2**32 - 1))
def test_boxes_state_is_shapely_intersects_and_contains_properly(region, reach, seed):
    rng = np.random.default_rng(seed)
    n = 300
    corner = np.concatenate([rng.integers(-20, 21, (n, 2)) * STEP,
                             rng.uniform(-2.5, 2.5, (n, 2))])
    size = np.concatenate([rng.integers(1, 6, n) * STEP / rng.choice([1, 2, 4], n),
                           rng.uniform(1e-3, 0.5, n)])
    bx, by = corner.T
    vis, sides = bundle(region, reach)
    state = vis_kern.boxes_state(vis, sides, bx, by, size)
    boxes = shapely.box(bx, by, bx + size, by + size)
    assert np.array_equal(state > 0, shapely.intersects(region.geometry, boxes))
    assert np.array_equal(state == 2, shapely.contains_properly(region.geometry, boxes))


@settings(max_examples=60, deadline=None)
@given(lattice_regions(), st.sampled_from([1, 2, 3, 5, 7]), st.integers(0, 2**32 - 1))
def test_the_graded_samplers_in_out_tests_are_shapelys(region, split, seed):
    """graded_domain bins each chord within half a cell of it, on a grid whose cell
    lines run along the lattice's edges up to rounding (cells of STEP / split, from a
    few cells below the lowest vertex, as the sampler places its grid): a chord on the
    line between two cells must be listed in both (with no reach it was listed in one,
    as rounding put it, and points and boxes were read outside)."""
    from pds_plugin.boundary_sampling import graded_domain

    points = np.concatenate(region.rings)
    ends = np.cumsum([len(ring) for ring in region.rings])
    rings = [np.arange(end - len(ring), end) for end, ring in zip(ends, region.rings)]
    cell = STEP / split
    low = points.min(axis=0) - 4 * cell
    width, height = points.max(axis=0) - low + 4 * cell
    domain = graded_domain(points, rings, len(points), low[0], low[1], width, height, cell)
    rng = np.random.default_rng(seed)
    lattice = rng.integers(-20, 21, (300, 2)) * STEP / rng.choice([1, 2], (300, 1))
    x, y = np.concatenate([lattice, rng.uniform(-2.5, 2.5, (300, 2)), points]).T
    assert np.array_equal(vis_kern.points_inside(*domain, x, y),
                          shapely.contains_xy(region.geometry, x, y))
    size = rng.integers(1, 6, len(x)) * STEP / rng.choice([1, 2, 4], len(x))
    state = vis_kern.boxes_state(*domain, x, y, size)
    boxes = shapely.box(x, y, x + size, y + size)
    assert np.array_equal(state > 0, shapely.intersects(region.geometry, boxes))
    assert np.array_equal(state == 2, shapely.contains_properly(region.geometry, boxes))


def test_a_chord_on_a_line_between_cells_is_found_from_both():
    """The graded sampler's grid starts a few cells below the region's lowest point: in
    exact arithmetic its lowest edges lie on cell lines, and rounding puts each in the
    cell below or above. graded_domain lists such a chord in both (with no reach it was
    listed in one, ``cell_sides`` missed its crossings, and on a strip of the bench's
    g-plate-holes 17,057 of 20,000 points read wrong); the in/out tests are shapely's."""
    from pds_plugin.boundary_sampling import graded_domain

    cell = 0.1
    xs, ys = np.linspace(1.5, 5.5, 41), np.linspace(1.5, 3.5, 21)
    ring = np.concatenate([np.column_stack([xs[:-1], np.full(40, 1.5)]),
                           np.column_stack([np.full(20, 5.5), ys[:-1]]),
                           np.column_stack([xs[:0:-1], np.full(40, 3.5)]),
                           np.column_stack([np.full(20, 1.5), ys[:0:-1]])])
    low = 1.5 - 4 * cell                     # (1.5 - low) / cell is 4 to rounding
    domain = graded_domain(ring, [np.arange(len(ring))], len(ring), low, low, 5.0, 3.0, cell)
    assert domain[0].h == cell
    x, y = np.random.default_rng(0).uniform(1.0, 6.0, (2, 2000))
    assert np.array_equal(vis_kern.points_inside(*domain, x, y),
                          shapely.contains_xy(Polygon(ring), x, y))


def test_a_box_touching_a_vertex_or_an_edge_crosses_the_boundary():
    region = pds.Region.from_shapely(Polygon([(0, 0), (1, 0), (1, 1)]))
    vis, sides = bundle(region, 0.25)
    # touching the corner (1, 1) from above right, lying on the edge y = 0 from below,
    # touching the slanted edge at (0.5, 0.5) from above left, strictly inside, apart
    bx = np.array([1.0, 0.25, 0.25, 0.6, -1.0])
    by = np.array([1.0, -0.25, 0.5, 0.1, -1.0])
    assert vis_kern.boxes_state(vis, sides, bx, by, 0.25).tolist() == [1, 1, 1, 2, 0]
    assert vis_kern.points_inside(vis, sides, [1.0, 0.5, 0.5, 0.7], [1.0, 0.0, 0.5, 0.2]).tolist() \
        == [False, False, False, True]


def test_without_chords_nothing_is_inside():
    vis = vis_kern.no_chords(3)
    sides = vis_kern.cell_sides(vis)
    assert not vis_kern.points_inside(vis, sides, [0.0], [0.0]).any()
    assert vis_kern.boxes_state(vis, sides, [0.0], [0.0], 1.0).tolist() == [0]
