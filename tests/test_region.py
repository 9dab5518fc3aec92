"""Region: validation with clear errors, repair, orientation, Betti numbers, frame."""

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, MultiPolygon, Point, Polygon, box

import pds_plugin as pds
from pds_plugin import Region
from pds_plugin.errors import ArgumentError, RegionError


def test_rings_are_oriented_and_open():
    region = pds.Region.from_shapely(Polygon([(0, 0), (0, 4), (4, 4), (4, 0)],
                                             [[(1, 1), (2, 1), (2, 2), (1, 2)]]))
    outer, hole = region.rings
    assert shapely.is_ccw(shapely.linearrings(outer)) and not shapely.is_ccw(shapely.linearrings(hole))
    assert not np.array_equal(outer[0], outer[-1])
    assert region.betti == (1, 1) and region.area == 15.0 and region.perimeter == 20.0


def test_rings_of_many_components_and_holes_drop_only_repeats_within_rounding():
    """Region.rings reads every ring in one pass: each polygon's exterior then its holes,
    in order, a vertex within FOLD_WIDTH float spacings of the one before it in its own
    ring (the last before the first) left out, and no other."""
    rng = np.random.default_rng(5)
    polygons, expected = [], []
    for k in range(40):
        x, y = 10.0 * (k % 8), 10.0 * (k // 8)
        outer = [(x, y), (x + 8, y), (x + 8, y + 8), (x, y + 8)]
        holes = [[(x + 1 + 2 * j, y + 1), (x + 1 + 2 * j, y + 2), (x + 2 + 2 * j, y + 1)]
                 for j in range(int(rng.integers(0, 4)))]
        if k % 3 == 0:            # a repeat of the vertex before it, within rounding
            outer.insert(2, (x + 8, y + 1e-15))
        if k % 5 == 0:            # a ring's first vertex repeating its last
            outer.append((x, y + 5e-15))
        polygons.append(Polygon(outer, holes))
        expected.append([(x + 8, y), (x + 8, y + 8), (x, y + 8), (x, y + 5e-15)] if k % 5 == 0
                        else [(x, y), (x + 8, y), (x + 8, y + 8), (x, y + 8)])
        expected.extend([list(map(tuple, hole)) for hole in holes])
    region = Region(MultiPolygon(polygons), np.eye(4))
    assert [ring.tolist() for ring in region.rings] == [list(map(list, r)) for r in expected]


def test_several_components_and_an_island_in_a_hole():
    ring = box(0, 0, 10, 10).difference(box(2, 2, 8, 8))
    region = pds.Region.from_shapely(MultiPolygon([ring, box(4, 4, 6, 6), box(20, 0, 21, 1)]))
    assert region.betti == (3, 1)


@pytest.mark.parametrize("geometry, message", [
    (Polygon(), "empty"),
    (Polygon([(0, 0), (1, 0), (np.nan, 1)]), "NaN or infinite"),
    (Polygon([(0, 0), (2, 2), (2, 0), (0, 2)]), r"Self-intersection\[1 1\].*repair=True"),
    (MultiPolygon([box(0, 0, 2, 2), box(1, 1, 3, 3)]), "invalid region geometry"),
])
def test_bad_geometry_is_refused_with_the_reason(geometry, message):
    with pytest.raises(ValueError, match=message):
        pds.Region.from_shapely(geometry)


def test_zero_area_part_is_refused_and_located():
    flat = Polygon([(5, 5), (6, 5), (7, 5)])
    with pytest.raises(ValueError, match=r"zero-area part.*near \(6, 5\)"):
        pds.Region.from_shapely(shapely.GeometryCollection([box(0, 0, 1, 1), flat]))


def test_repair_uses_make_valid_and_keeps_both_lobes():
    bowtie = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
    region = pds.Region.from_shapely(bowtie, repair=True)
    assert region.betti == (2, 0) and region.area == pytest.approx(2.0)   # buffer(0) gives 1.0


@pytest.mark.parametrize("thing", [LineString([(0, 0), (1, 1)]), Point(0, 0), "square", None])
def test_things_without_area_are_not_regions(thing):
    with pytest.raises(TypeError, match="expected"):
        pds.Region.from_shapely(thing)


def test_frame_must_be_a_finite_4x4_matrix():
    with pytest.raises(ValueError, match="4x4"):
        pds.Region.from_shapely(box(0, 0, 1, 1), frame=np.eye(3))
    frame = np.eye(4)
    frame[:3, 3] = [1, 2, 3]
    region = pds.Region.from_shapely(box(0, 0, 1, 1), frame=frame)
    assert np.allclose(region.to_3d([[1, 1]]), [[2, 3, 3]])


def test_the_callers_geometry_is_not_modified():
    polygon = Polygon([(0, 0), (0, 1), (1, 1), (1, 0)])           # clockwise
    before = shapely.get_coordinates(polygon).copy()
    pds.mesh_region(pds.Region.from_shapely(polygon), 0.3)
    assert np.array_equal(shapely.get_coordinates(polygon), before)
    assert not shapely.is_prepared(polygon)


def test_boundary_pieces_cover_the_boundary_in_short_steps():
    region = pds.Region.from_shapely(box(0, 0, 3, 1).difference(Point(1, 0.5).buffer(0.3)))
    start, direction, length = region.boundary_pieces(0.1)
    assert length.max() <= 0.1 and np.isclose(length.sum(), region.perimeter)
    assert np.allclose(np.linalg.norm(direction, axis=1), 1.0)


def test_ring_owners_name_the_component_and_hole_of_each_ring():
    ring = box(0, 0, 10, 10).difference(box(2, 2, 4, 4)).difference(box(6, 6, 8, 8))
    region = pds.Region.from_shapely(MultiPolygon([ring, box(20, 0, 21, 1)]))
    assert region.ring_owners == ((0, None), (0, 0), (0, 1), (1, None))
    assert len(region.ring_owners) == len(region.rings)


def test_turning_angles_of_a_ring_sum_to_one_turn_with_the_region_on_the_left():
    from pds_plugin.region import turning_angles

    outer, hole = pds.Region.from_shapely(Point(0, 0).buffer(2).difference(Point(0, 0).buffer(1))).rings
    assert turning_angles(outer).sum() == pytest.approx(2 * np.pi, rel=1e-12)
    assert turning_angles(hole).sum() == pytest.approx(-2 * np.pi, rel=1e-12)


@pytest.mark.parametrize("size", [1e-150, 1e101, 1e-54, 1e54, 1e-90, 1e90])
def test_regions_beyond_float64_powers_are_refused(size):
    """At 1e-150 the certificate found -17 holes (squares of coordinates underflow); at
    1e±54 the meshes had triangles of aspect ratio 9, at 1e±90 of 312 (powers of the
    coordinates in the predicates over- or underflow)."""
    with pytest.raises(RegionError, match="scale the geometry"):
        Region.from_shapely(box(0, 0, size, size))


@pytest.mark.parametrize("size", [1e-48, 1e48])
def test_regions_just_inside_the_scale_limits_mesh_within_the_aspect_bound(size):
    mesh = pds.mesh_region(Region.from_shapely(box(0, 0, size, size)), size / 10)
    a, b, c = (mesh.vertices[mesh.faces[:, k]] / size for k in range(3))   # exact scaling
    area = ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]) / 2
    longest = np.max([np.hypot(*(b - a).T), np.hypot(*(c - b).T), np.hypot(*(a - c).T)], axis=0)
    assert len(mesh.faces) and (area > 0).all()
    assert (longest**2 / area).max() <= 4 * np.sqrt(3) * (1 + 1e-9)


def test_a_singular_frame_is_refused():
    frame = np.eye(4)
    frame[:3, 1] = frame[:3, 0]
    with pytest.raises(ArgumentError, match="rank 2"):
        Region.from_shapely(box(0, 0, 1, 1), frame=frame)


def test_a_ring_folded_back_onto_itself_is_mended_by_repair():
    """Found by the fuzz test: a star scaled by 1e-3 and moved 1e5 away runs out to a
    spike and back through the vertex before it, 3e-12 from it (a fifth of the float
    spacing there). Shapely calls it valid; the uniform complex refuses the two sides'
    samples there (one point), and the graded field fell to 6e-10 (a sampler that ran
    for minutes; now refused at once). repair=True drops the spike's tip, which removes
    no area, and both meshes are certified, far from the origin as it is (the
    certificate allows for the rounding of its coordinates)."""
    from regions import folded_star

    star = folded_star()
    region = Region.from_shapely(star)
    alpha = 0.1 * region.area ** 0.5
    with pytest.raises(ArgumentError, match="runs back onto itself.*repair=True"):
        pds.mesh_region(region, alpha, seed=1)
    with pytest.raises(RegionError, match="radius field falls to .* within rounding"):
        pds.mesh_region(region, alpha, seed=1, graded=True)
    repaired = Region.from_shapely(star, repair=True)
    tip = star.exterior.coords[1]
    assert len(repaired.rings[0]) == len(star.exterior.coords) - 2
    assert not np.any(np.all(repaired.rings[0] == tip, axis=1))
    assert abs(repaired.area - star.area) <= 1e-9 * star.area
    for graded in (False, True):
        mesh = pds.mesh_region(repaired, alpha, seed=1, graded=graded)
        assert mesh.certificate().ok_with_exceptions


def test_repair_drops_spikes_within_rounding_only():
    fold = Polygon([(0, 0), (2, 0), (2, 1), (1 + 1e-15, 1), (1, 3), (1, 1), (0, 1)])
    assert fold.is_valid
    assert Region.from_shapely(fold, repair=True).geometry.equals(box(0, 0, 2, 1))
    spike = Polygon([(0, 0), (2, 0), (2, 1), (1 + 1e-9, 1), (1, 3), (1, 1), (0, 1)])
    assert Region.from_shapely(spike, repair=True).geometry.equals(spike)     # thin, kept


def test_walls_within_rounding_are_refused_before_sampling():
    """A hole 3 float spacings from the outline, 1e5 from the origin: no alpha the
    coordinates resolve keeps the wall. 'auto' took 42 s and warned of dozens of
    uncovered holes (uniform), or gave a FAILED mesh (graded); both now refuse it."""
    x0 = 1e5
    u = float(np.spacing(x0))
    hole = [(x0 + 3 * u, 2e-4), (x0 + 5e-4, 2e-4), (x0 + 5e-4, 8e-4), (x0 + 3 * u, 8e-4)]
    region = Region.from_shapely(Polygon(box(x0, 0, x0 + 1e-3, 1e-3).exterior, [hole]))
    with pytest.raises(RegionError, match="within rounding of itself"):
        pds.mesh_region(region, "auto", seed=1)
    with pytest.raises(RegionError, match="radius field falls to .* within rounding"):
        pds.mesh_region(region, "auto", seed=1, graded=True)


def test_ring_vertices_within_rounding_of_the_one_before_are_repeats():
    """Found by the fuzz test: a spike whose tip is two vertices 7e-31 apart, at
    coordinates of 1e-3 (a spacing of 2e-19). With both in the ring, the conforming
    meshes failed their certificates (18 of 18 alphas and seeds); ``Region.rings``
    leaves the second out, as it left exact repeats out."""
    spike = Polygon([(0.001, 8.727e-6), (6.16e-33, -7.059e-31), (0, 0), (0.0002, 2.182e-6),
                     (0.0003, 0.0006), (0.0012, 0.0006)])
    region = Region.from_shapely(spike)
    assert len(region.rings[0]) == 5 and len(Region.from_shapely(box(0, 0, 1, 1)).rings[0]) == 4
    for fraction in (0.05, 0.25):
        mesh = pds.mesh_region(region, fraction * region.area ** 0.5, seed=0)
        assert mesh.certificate().ok_with_exceptions


def test_simple_regions_are_what_from_shapely_makes_of_each_ring():
    """region.simple_regions (the remesh's patches of one ring, made together): None
    exactly where the ring's polygon is not valid, else the region Region.from_shapely
    makes of it (same geometry); rings given as the region's own (counter-clockwise,
    nothing to drop) are exactly what Region.rings reads back from its geometry, and
    the others are read back by it. Oracle: shapely's validity and the property itself,
    on rings clockwise, with a repeated vertex, self-crossing and far from the origin."""
    from pds_plugin.region import simple_regions

    rng = np.random.default_rng(7)
    rings = []
    for k in range(200):
        n = int(rng.integers(3, 9))
        turn = np.sort(rng.uniform(0, 2 * np.pi, n))
        ring = (rng.uniform(0.5, 2, n)[:, None] * np.column_stack([np.cos(turn), np.sin(turn)])
                + rng.uniform(-1e3, 1e3, 2))
        ring = [ring, ring[::-1], np.insert(ring, 1, ring[0] + 1e-14, axis=0),
                rng.uniform(0, 1, (n, 2))][k % 4]
        rings.append(ring)
    made = simple_regions(rings)
    assert sum(region is None for region in made) > 10
    given = 0
    for ring, region in zip(rings, made):
        assert (region is None) == (not Polygon(ring).is_valid)
        if region is None:
            continue
        reference = Region.from_shapely(Polygon(ring))
        assert region.geometry.equals_exact(reference.geometry, 0)
        given += "rings" in vars(region)
        assert all(np.array_equal(a, b) for a, b in zip(region.rings, reference.rings))
        assert len(region.rings) == len(reference.rings) == 1
    assert 30 < given < len(rings)
