"""certify: every measure against an independent oracle, and every failure detected."""

import json

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon, box

import pds_plugin as pds
from conftest import min_distance, probe_gap, visible_min_distance, visible_probe_gap
from pds_plugin.analysis.conformity import SampledBoundary


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
    # beyond the chord from (1, 1) to (0, 1) lies a piece that holds neither end
    wiggle = Polygon([(0, 0), (1, 0), (1, 1), (0.7, 1), (0.6, 1.03), (0.4, 0.97), (0.3, 1), (0, 1)])
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
