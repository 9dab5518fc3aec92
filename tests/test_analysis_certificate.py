"""certify: every measure against an independent oracle, and every failure detected."""

import json

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon, box

import pds_plugin as pds
from conftest import min_distance, probe_gap, visible_min_distance, visible_probe_gap
from scipy.spatial import Delaunay, QhullError, cKDTree

from pds_plugin import _parallel
from pds_plugin._certificate_kernels import segment_distances, signed_areas
from pds_plugin._geometry_kernels import circumcircles
from pds_plugin.analysis.certificate import _SampleGrid
from pds_plugin.analysis.conformity import SampledBoundary, _farthest


def test_measures_agree_with_independent_oracles():
    region = pds.Region.from_shapely(box(0, 0, 2, 1).difference(Point(1, 0.5).buffer(0.3)))
    alpha = 0.05
    mesh = pds.mesh_region(region, alpha, seed=4)
    cert = mesh.certificate()
    assert np.isclose(cert.min_separation, min_distance(mesh.vertices) / alpha, rtol=1e-12)
    spacing = alpha / 200
    probed = probe_gap(region.geometry, mesh.vertices, spacing) / alpha
    assert probed <= cert.coverage_gap * (1 + 1e-12) <= probed + spacing / alpha
    assert cert.max_aspect_ratio == mesh.quality().aspect_ratio.max()
    assert cert.ok and cert.isolated_samples == 0 and cert.nonmanifold_vertices == 0


def test_a_hole_in_the_sampling_is_found_where_it_is():
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    alpha = 0.05
    full = pds.poisson_disc(region, alpha, seed=0)
    interior = np.flatnonzero(~full.on_boundary)
    gone = interior[np.argmin(np.linalg.norm(full.points[interior] - 0.5, axis=1))]
    keep = np.arange(len(full.points)) != gone
    points = full.points[keep]
    mesh = pds.PlanarMesh(points, pds.solid_alpha_complex(points, alpha), full.on_boundary[keep],
                          region, alpha)
    cert = mesh.certificate()
    assert cert.coverage_gap > 1 and not cert.sampling_ok and not cert.ok
    assert np.isclose(cert.coverage_gap, probe_gap(region.geometry, points, alpha / 100) / alpha,
                      atol=0.01)
    assert np.linalg.norm(np.array(cert.coverage_gap_at) - full.points[gone]) < alpha


def test_an_uncovered_boundary_stretch_is_found():
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    samples = pds.poisson_disc(region, 0.05, seed=1)
    far = np.linalg.norm(samples.points - [1, 1], axis=1) > 0.2     # empty the corner
    points = samples.points[far]
    mesh = pds.PlanarMesh(points, pds.solid_alpha_complex(points, 0.05), samples.on_boundary[far],
                          region, 0.05)
    cert = mesh.certificate()
    spacing = 0.05 / 200
    probed = probe_gap(region.geometry, points, spacing)
    assert probed <= cert.coverage_gap * 0.05 * (1 + 1e-12) <= probed + spacing
    assert np.linalg.norm(np.array(cert.coverage_gap_at) - [1, 1]) < 0.2


def test_samples_too_close_and_a_bad_triangle_are_flagged():
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    points = np.array([[0, 0], [1, 0], [0.5, 0.05], [0.5, 1], [0, 1], [1, 1]], float)
    faces = np.array([[0, 1, 2], [0, 2, 4], [2, 1, 5], [2, 5, 3], [2, 3, 4]])
    cert = pds.PlanarMesh(points, faces, np.ones(6, bool), region, 1.0).certificate()
    assert cert.min_separation < 1 and cert.max_aspect_ratio > cert.aspect_bound
    assert not cert.quality_ok and not cert.ok


def test_isolated_samples_and_touching_fans_are_counted():
    region = pds.Region.from_shapely(box(-1, -1, 3, 3))
    points = np.array([[0, 0], [1, 0], [0.5, 0.9], [2, 1.8], [1.5, 0.9], [-0.5, 2.5]], float)
    faces = np.array([[0, 1, 2], [2, 4, 3]])      # two triangles meeting at vertex 2
    cert = pds.PlanarMesh(points, faces, np.zeros(6, bool), region, 1.0).certificate()
    assert cert.isolated_samples == 1 and cert.nonmanifold_vertices == 1 and not cert.ok


def test_certificate_is_json_ready_and_printable():
    cert = pds.mesh_region(pds.Region.from_shapely(Point(0, 0).buffer(1)), 0.2).certificate()
    values = json.loads(json.dumps(cert.as_dict()))
    assert values["ok"] is True and values["aspect_bound"] == cert.aspect_bound
    assert "coverage gap" in str(cert) and "ok" in str(cert)


def test_certificate_of_a_mesh_whose_samples_fill_no_triangle():
    region = pds.Region.from_shapely(box(0, 0, 0.1, 0.1))
    mesh = pds.mesh_region(region, 1.0, conforming=False)     # a conforming mesh keeps the corners
    cert = mesh.certificate()
    assert cert.triangles == 0 and cert.coverage_gap <= 1 and cert.isolated_samples == len(mesh.vertices)
    assert shapely.intersects_xy(region.geometry, *np.array(cert.coverage_gap_at))


def test_a_bridged_notch_is_measured_outside_the_region():
    notch = Polygon([(0.45, 1), (0.5, 0.4), (0.55, 1)])          # a 9.5° V cut from the top
    region = pds.Region.from_shapely(box(0, 0, 1, 1).difference(notch))
    plain = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.1,
                            conforming=False).certificate()
    bridged = pds.mesh_region(region, 0.1, seed=1, conforming=False).certificate()  # the paper's
    assert plain.outside_area_ratio < 1e-12
    assert bridged.outside_area_ratio > 0 and bridged.boundary_deviation > 0.2
    assert bridged.boundary_deviation * 0.1 <= 0.6      # the notch's depth



# --- separation: the closest pair, exact without a triangulation --------------------------

def brute_force_separation(points):
    """Oracle: the smallest distance over every pair, sqrt(dx * dx + dy * dy) as the mesh's
    edge lengths are computed."""
    d = points[:, None, :] - points[None, :, :]
    squared = d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1]
    squared[np.diag_indices(len(points))] = np.inf
    return float(np.sqrt(squared.min()))


def near_collinear(seed, jitter=1e-15, n=12):
    """Samples 1 to 1.5 apart along the x axis, one pair 0.5 to 1 apart, lifted off the
    axis by ``jitter``: flat to Qhull's precision."""
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(1.0, 1.5, n))
    x[n // 2:] -= 0.5
    return np.column_stack([x, jitter * rng.standard_normal(n)])


def qhull_delaunay_edges(points):
    """The edges the certificate used to take the separation from: Qhull's triangles that
    are not flat and whose circumcircle holds no sample (none when Qhull finds the points
    flat)."""
    try:
        tri = Delaunay(points).simplices
    except QhullError:
        return set()
    centre, radius = circumcircles(points, tri)
    finite = np.isfinite(radius)
    nearest = cKDTree(points).query(centre[finite])[0]
    tri = tri[finite][nearest >= radius[finite] * (1 - 1e-9)]
    return {tuple(sorted(e)) for t in tri.tolist() for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("jitter", [1e-15, 1e-13])
@pytest.mark.parametrize("with_triangle", [True, False])
def test_separation_of_near_collinear_samples_is_exact(seed, jitter, with_triangle):
    points = near_collinear(seed, jitter)
    d = points[:, None] - points[None]
    length = np.hypot(d[..., 0], d[..., 1]) + np.diag(np.full(len(points), np.inf))
    closest = tuple(sorted(np.unravel_index(np.argmin(length), length.shape)))
    # Qhull drops the flat triangles that hold the closest pair: the Delaunay edges it
    # reports miss it, and the certificate took a longer edge for the separation
    assert closest not in qhull_delaunay_edges(points)
    faces = np.array([[0, 1, 2]]) if with_triangle else np.empty((0, 3), np.int64)
    region = pds.Region.from_shapely(box(-1, -1, points[:, 0].max() + 1, 1))
    cert = pds.PlanarMesh(points, faces, np.zeros(len(points), bool), region, 1.0).certificate()
    assert cert.min_separation == brute_force_separation(points)
    assert cert.min_separation < 1 and not cert.ok


@pytest.mark.parametrize("kind", ["random", "clustered", "sparse", "lattice", "crowded", "two"])
def test_separation_is_the_closest_pair_of_any_point_set(kind):
    rng = np.random.default_rng(7)
    alpha = 0.05
    points = {
        "random": rng.random((300, 2)),
        "clustered": np.concatenate([rng.normal(c, 0.01, (60, 2)) for c in rng.random((4, 2))]),
        "sparse": rng.random((40, 2)) * 100,           # pairs far beyond the grid's cells
        "lattice": np.stack(np.meshgrid(np.arange(12.0), np.arange(9.0)), -1).reshape(-1, 2) * 0.07,
        "crowded": rng.random((400, 2)) * 0.02,        # hundreds of samples in one cell
        "two": np.array([[0.0, 0.0], [30.0, 40.0]]),
    }[kind]
    region = pds.Region.from_shapely(shapely.box(*points.min(axis=0) - 1, *points.max(axis=0) + 1))
    mesh = pds.PlanarMesh(points, np.empty((0, 3), np.int64), np.zeros(len(points), bool),
                          region, alpha)
    assert mesh.certificate().min_separation * alpha == pytest.approx(
        brute_force_separation(points), rel=1e-15, abs=0)


def test_certificate_does_not_depend_on_the_thread_count():
    region = pds.Region.from_shapely(box(0, 0, 3, 1).difference(Point(1.5, 0.5).buffer(0.3)))
    mesh = pds.mesh_region(region, 0.01, seed=2)
    values = []
    for threads in (1, 2, 4):
        previous = _parallel.set_threads(threads)
        try:
            copy = pds.PlanarMesh(mesh.vertices, mesh.faces, mesh.on_boundary, region, mesh.alpha)
            values.append(json.dumps(copy.certificate().as_dict()))
        finally:
            _parallel.set_threads(previous)
    assert values[0] == values[1] == values[2]



@pytest.mark.parametrize("cell", [0.01, 0.05, 0.3])
def test_the_sample_grid_answers_pair_and_circle_queries_exactly(cell):
    rng = np.random.default_rng(3)
    points = np.concatenate([rng.random((400, 2)), rng.normal(0.5, 0.005, (30, 2))])
    grid = _SampleGrid(points, cell)
    d = points[:, None] - points[None]
    distance = np.sqrt(d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1])
    for limit in (0.004, 0.05, 0.2):
        i, j = np.nonzero(np.triu(distance <= limit, k=1))
        found = np.sort(grid.pairs_within(limit), axis=1)
        assert len(found) == len(i)
        assert set(map(tuple, found.tolist())) == set(zip(i.tolist(), j.tolist()))
    centre = rng.random((300, 2)) * 1.4 - 0.2
    radius = rng.random(300) * 0.1
    c = centre[:, None] - points[None]
    inside = (np.sqrt(c[..., 0] * c[..., 0] + c[..., 1] * c[..., 1]) < radius[:, None]).any(axis=1)
    assert 0 < inside.sum() < len(inside)
    assert np.array_equal(grid.sample_within(centre, radius), inside)

@pytest.mark.parametrize("seed", range(3))
def test_segment_distances_are_shapelys_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    # short boundary-like segments, a few long ones, a degenerate one, and a shared end
    starts = rng.random((300, 2)) * 10
    ends = starts + rng.normal(0, 0.05, (300, 2))
    ends[:5] = rng.random((5, 2)) * 10
    ends[5] = starts[5]
    starts[6] = ends[7]
    segments = np.stack([starts, ends], axis=1)
    near = starts[:, None] + rng.random((300, 8, 1)) * (ends - starts)[:, None]
    points = np.concatenate([near.reshape(-1, 2) + rng.normal(0, 0.01, (2400, 2)),
                             rng.random((500, 2)) * 30 - 10])       # and far ones
    found, nearest = segment_distances(points, segments, 0.1, 8)
    tree = shapely.STRtree(shapely.linestrings(segments))
    expected = tree.query_nearest(shapely.points(points), all_matches=False,
                                  return_distance=True)[1]
    settled = ~np.isnan(found)
    assert settled[:2400].mean() > 0.99 and not settled.all()
    assert np.array_equal(found[settled], expected[settled])
    assert np.array_equal(shapely.distance(shapely.points(points[settled]),
                                           shapely.linestrings(segments[nearest[settled]])),
                          found[settled]) and (nearest[~settled] == -1).all()
    assert np.array_equal(segment_distances(points, segments, 0.1, 10**6)[0], expected)


@pytest.mark.parametrize("seed", range(4))
def test_farthest_point_of_curves_from_targets_is_found_to_half_a_step(seed):
    rng = np.random.default_rng(seed)
    angle = np.sort(rng.random(40)) * 2 * np.pi       # chords of a wavy closed curve...
    radius = 1 + 0.1 * np.sin(5 * angle) + 0.02 * rng.random(40)
    ring = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    curves = np.stack([ring, np.roll(ring, -1, axis=0)], axis=1)
    fine = np.linspace(0, 2 * np.pi, 700, endpoint=False)          # ...against the curve
    smooth = np.column_stack([np.cos(fine), np.sin(fine)]) * (1 + 0.1 * np.sin(5 * fine))[:, None]
    targets = np.stack([smooth, np.roll(smooth, -1, axis=0)], axis=1)
    step = 0.02
    found = _farthest(curves, targets, step)
    t = np.linspace(0, 1, 2001)[:, None, None]                     # probes 1e-4 apart at most
    dense = (curves[None, :, 0] + t * (curves[None, :, 1] - curves[None, :, 0])).reshape(-1, 2)
    brute = shapely.STRtree(shapely.linestrings(targets)).query_nearest(
        shapely.points(dense), all_matches=False, return_distance=True)[1].max()
    assert brute - step / 2 <= found <= brute + 1e-4


@pytest.mark.parametrize("seed", range(6))
def test_farthest_point_of_chords_of_a_cut_polygon_is_found_to_half_a_step(seed):
    # a square's sides cut into collinear segments, chords between random points along
    # it: across a cut (the split bound settles it), across a corner (a true deviation)
    rng = np.random.default_rng(seed)
    corners = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    ring = np.concatenate([a + np.sort(rng.random(rng.integers(1, 6)))[:, None] * (b - a)
                           for a, b in zip(corners, np.roll(corners, -1, axis=0))]
                          + [corners])
    ring = ring[np.argsort(np.arctan2(*(ring - 0.5).T[::-1]))]
    targets = np.stack([ring, np.roll(ring, -1, axis=0)], axis=1)
    along = np.sort(rng.random(12)) * 4
    side = np.minimum(along.astype(int), 3)
    points = corners[side] + (along - side)[:, None] * (np.roll(corners, -1, axis=0)[side]
                                                        - corners[side])
    curves = np.stack([points, np.roll(points, -1, axis=0)], axis=1)
    step = 0.01
    found = _farthest(curves, targets, step)
    t = np.linspace(0, 1, 4001)[:, None, None]
    dense = (curves[None, :, 0] + t * (curves[None, :, 1] - curves[None, :, 0])).reshape(-1, 2)
    brute = shapely.STRtree(shapely.linestrings(targets)).query_nearest(
        shapely.points(dense), all_matches=False, return_distance=True)[1].max()
    assert brute - step / 2 <= found <= brute + 1e-9


def test_signed_areas_are_the_plain_float_expression_bit_for_bit():
    rng = np.random.default_rng(0)
    points = rng.random((500, 2)) * 1e3 - 300
    faces = rng.integers(0, 500, (20000, 3))
    faces[:3] = [[0, 1, 1], [2, 2, 2], [3, 4, 5]]                # flat ones, and one turned
    faces[3] = faces[2][::-1]
    u, v = points[faces[:, 1]] - points[faces[:, 0]], points[faces[:, 2]] - points[faces[:, 0]]
    expected = (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / 2
    found = signed_areas(points, faces)
    assert np.array_equal(found, expected) and found[0] == found[1] == 0
    assert found[2] * found[3] < 0


# --- conformity, and separation and coverage with the visibility rule ------------------

def cdt_mesh(polygon, alpha, region=None, conforming=True):
    """A conforming triangulation of ``polygon`` (shapely's constrained Delaunay
    triangles, made counter-clockwise), all its vertices boundary samples, as a mesh of
    ``region`` (the polygon itself by default)."""
    triangles = shapely.get_parts(shapely.constrained_delaunay_triangles(polygon))
    corners = shapely.get_coordinates(shapely.get_exterior_ring(triangles)).reshape(-1, 4, 2)[:, :3]
    vertices, faces = np.unique(corners.reshape(-1, 2), axis=0, return_inverse=True)
    faces = faces.reshape(-1, 3)
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    clockwise = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0] < 0
    faces[clockwise] = faces[clockwise][:, ::-1]
    region = pds.Region.from_shapely(polygon if region is None else region)
    return pds.PlanarMesh(vertices, faces, np.ones(len(vertices), bool), region, alpha,
                          conforming=conforming)


def with_faces(mesh, faces, conforming=True):
    return pds.PlanarMesh(mesh.vertices, np.asarray(faces), mesh.on_boundary, mesh.region,
                          mesh.alpha, conforming=conforming)


# a plate with a hole, and a V-notch and a second part both 0.03 away: much less than alpha
SLOTTED = shapely.union(
    box(0, 0, 2, 1).difference(box(0.5, 0.3, 1.0, 0.6)).difference(
        Polygon([(1.4, 1.0), (1.415, 0.4), (1.43, 1.0)])),
    box(2.03, 0, 2.5, 1))


def test_a_constrained_delaunay_triangulation_conforms_and_is_measured_with_visibility():
    alpha = 0.5
    mesh = cdt_mesh(SLOTTED, alpha)
    cert = mesh.certificate()
    assert cert.claims_conforming and cert.conforming and cert.sampled_outline
    assert cert.visibility and cert.boundary_ok and not cert.boundary_problems
    assert cert.boundary_deviation == 0
    assert cert.outside_area_ratio < 1e-12 and cert.missing_area_ratio < 1e-12
    # separation: the samples facing each other across the gaps do not see each other
    separation = visible_min_distance(SLOTTED, mesh.vertices, mesh.edges) / alpha
    assert cert.min_separation == pytest.approx(separation, rel=1e-12)
    assert min_distance(mesh.vertices) == pytest.approx(0.03, rel=1e-9)
    assert cert.min_separation * alpha == pytest.approx(0.3, rel=1e-12)     # the hole's side
    # coverage: every point of the plate against the samples it sees
    spacing = alpha / 100
    probed, _ = visible_probe_gap(SLOTTED, SLOTTED, mesh.vertices, spacing)
    assert probed / alpha <= cert.coverage_gap * (1 + 1e-12) <= (probed + spacing) / alpha
    assert shapely.intersects_xy(SLOTTED.buffer(1e-9), *cert.coverage_gap_at)
    # it is not a Poisson disc sampling: the verdict says so, the boundary is not blamed
    assert not cert.ok and not cert.quality_ok


def test_a_missing_boundary_triangle_is_found():
    mesh = cdt_mesh(SLOTTED, 0.5)
    chords = SampledBoundary(mesh.region, mesh.vertices, mesh.on_boundary, 0.5)
    chord = {(int(a), int(b)) for a, b in zip(chords.a, chords.b)}
    on_rim = [k for k, f in enumerate(mesh.faces)
              if any((int(f[i]), int(f[(i + 1) % 3])) in chord for i in range(3))]
    gone = on_rim[len(on_rim) // 2]
    cert = with_faces(mesh, np.delete(mesh.faces, gone, axis=0)).certificate()
    area = Polygon(mesh.vertices[mesh.faces[gone]]).area
    assert cert.missing_area_ratio == pytest.approx(area / SLOTTED.area, rel=1e-9)
    assert cert.outside_area_ratio < 1e-12 and cert.boundary_deviation > 0
    assert not cert.conforming and not cert.boundary_ok and not cert.ok
    assert any("not joined by a mesh edge" in p for p in cert.boundary_problems)


def test_the_paper_complex_dents_the_boundary_and_says_so():
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    alpha = 0.05
    mesh = pds.mesh_region(region, alpha, seed=0, conforming=False)
    cert = mesh.certificate()
    assert not cert.claims_conforming and not cert.visibility
    assert not cert.conforming and cert.ok               # reported, not part of ok
    assert any("end at interior samples" in p for p in cert.boundary_problems)
    assert cert.missing_area_ratio == pytest.approx(1 - cert.area_ratio, rel=1e-9)
    assert cert.outside_area_ratio < 1e-12
    oracle = shapely.hausdorff_distance(mesh.outline.boundary, region.geometry.boundary,
                                        densify=0.001) / alpha
    assert oracle - 0.01 <= cert.boundary_deviation <= oracle + 1e-9
    assert 0 < cert.boundary_deviation < 1
    # the same triangles claimed conforming: the certificate refuses them
    claimed = with_faces(mesh, mesh.faces).certificate()
    assert claimed.claims_conforming and not claimed.boundary_ok and not claimed.ok
    assert "conforming mesh   FAILED" in str(claimed)


def test_a_triangle_across_a_notch_is_outside_the_region():
    notch = Polygon([(0.45, 1), (0.5, 0.4), (0.55, 1)])
    region = box(0, 0, 1, 1).difference(notch)
    mesh = cdt_mesh(region, 0.5)
    ends = [int(np.flatnonzero((mesh.vertices == corner).all(axis=1))[0])
            for corner in [(0.45, 1), (0.5, 0.4), (0.55, 1)]]
    bridged = with_faces(mesh, np.vstack([mesh.faces, [ends[0], ends[1], ends[2]]]))
    cert = bridged.certificate()
    assert cert.outside_area_ratio == pytest.approx(notch.area / region.area, rel=1e-9)
    assert cert.missing_area_ratio < 1e-12
    oracle = shapely.hausdorff_distance(bridged.outline.boundary, region.boundary,
                                        densify=0.001) / 0.5
    assert oracle - 0.01 <= cert.boundary_deviation <= oracle + 1e-9
    assert cert.conforming and not cert.sampled_outline and not cert.ok
    assert any("not chords" in p for p in cert.boundary_problems)


def test_a_close_pair_that_sees_each_other_is_the_separation():
    mesh = cdt_mesh(SLOTTED, 0.5)
    extra = np.array([[0.2, 0.2], [0.2, 0.23], [1.7, 0.5]])
    vertices = np.vstack([mesh.vertices, extra])
    on_boundary = np.concatenate([mesh.on_boundary, np.zeros(3, bool)])
    cert = pds.PlanarMesh(vertices, mesh.faces, on_boundary, mesh.region, 0.5,
                          conforming=True).certificate()
    assert cert.min_separation * 0.5 == pytest.approx(0.03, rel=1e-9)
    assert cert.min_separation * 0.5 == pytest.approx(
        visible_min_distance(SLOTTED, vertices, mesh.edges), rel=1e-12)
    assert cert.isolated_samples == 3 and not cert.ok


def regular_polygon_area(radius, sides):
    return sides / 2 * radius ** 2 * np.sin(2 * np.pi / sides)


def test_curved_boundary_deviates_by_the_sagitta_only():
    # a 64-gon disc with a 64-gon hole; the boundary samples are every 4th vertex
    outer = shapely.get_coordinates(Point(0, 0).buffer(1, quad_segs=16).exterior)[:-1]
    inner = shapely.get_coordinates(Point(0.1, 0).buffer(0.4, quad_segs=16).exterior)[:-1]
    region = Polygon(outer, [inner])
    sampled = Polygon(outer[::4], [inner[::4]])
    alpha = 0.6
    mesh = cdt_mesh(sampled, alpha, region=region)
    cert = mesh.certificate()
    assert cert.conforming and cert.sampled_outline and cert.visibility and cert.boundary_ok
    # the chords span 4 of 64 sides: sagitta r (1 - cos(π/16)), areas of regular polygons
    sagitta = 1 - np.cos(np.pi / 16)
    assert cert.boundary_deviation * alpha == pytest.approx(sagitta, rel=1e-9)
    missing = regular_polygon_area(1, 64) - regular_polygon_area(1, 16)
    outside = regular_polygon_area(0.4, 64) - regular_polygon_area(0.4, 16)
    assert cert.missing_area_ratio * region.area == pytest.approx(missing, rel=1e-9)
    assert cert.outside_area_ratio * region.area == pytest.approx(outside, rel=1e-9)
    spacing = alpha / 100
    probed, _ = visible_probe_gap(region, region.union(sampled), mesh.vertices, spacing)
    assert probed / alpha <= cert.coverage_gap * (1 + 1e-12) <= (probed + spacing) / alpha


def test_a_boundary_crossing_its_chord_once_is_certified_from_the_end_it_holds():
    # the top edge bends up, then down through the chord from (1, 1) to (0, 1): the region
    # beyond the chord is the triangle (1, 1), (0.6, 1.04), p, seen whole from (1, 1)
    s_top = Polygon([(0, 0), (1, 0), (1, 1), (0.6, 1.04), (0.4, 0.97), (0, 1)])
    alpha = 0.8
    mesh = cdt_mesh(box(0, 0, 1, 1), alpha, region=s_top)
    cert = mesh.certificate()
    assert cert.conforming and cert.sampled_outline and cert.visibility and cert.boundary_ok
    p = 0.6 - 0.2 * 0.04 / 0.07                      # where the arc crosses y = 1
    assert cert.missing_area_ratio * s_top.area == pytest.approx((1 - p) * 0.04 / 2, rel=1e-9)
    assert cert.outside_area_ratio * s_top.area == pytest.approx(p * 0.03 / 2, rel=1e-9)
    spacing = alpha / 100
    probed, _ = visible_probe_gap(s_top, s_top.union(box(0, 0, 1, 1)), mesh.vertices, spacing)
    assert probed / alpha <= cert.coverage_gap * (1 + 1e-12) <= (probed + spacing) / alpha


def test_a_boundary_bending_both_ways_between_samples_is_not_certified():
    # beyond the chord from (1, 1) to (0, 1) lies a hooked piece that holds neither end
    # and turns back along the chord: no cut of it is seen whole from a sample
    wiggle = Polygon([(0, 0), (1, 0), (1, 1), (0.7, 1), (0.6, 1.05), (0.68, 1.08), (0.45, 1.07),
                      (0.3, 1), (0, 1)])
    mesh = cdt_mesh(box(0, 0, 1, 1), 0.8, region=wiggle)
    cert = mesh.certificate()
    assert cert.conforming and cert.sampled_outline
    assert not cert.visibility and not cert.boundary_ok and not cert.ok
    assert any("bends both ways" in p for p in cert.boundary_problems)


def test_boundary_rows_are_printed_and_json_ready():
    cert = cdt_mesh(SLOTTED, 0.5).certificate()
    values = json.loads(json.dumps(cert.as_dict()))
    for key in ("conforming", "sampled_outline", "boundary_deviation", "outside_area_ratio",
                "missing_area_ratio", "visibility", "boundary_ok", "boundary_problems"):
        assert key in values
    text = str(cert)
    assert "seen through the region" in text and "conforming yes" in text
