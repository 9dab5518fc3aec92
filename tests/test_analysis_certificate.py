"""certify: every measure against an independent oracle, and every failure detected."""

import json

import numpy as np
import shapely
from shapely.geometry import Point, Polygon, box

import pds_plugin as pds
from conftest import min_distance, probe_gap


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
    mesh = pds.mesh_region(region, 1.0)
    cert = mesh.certificate()
    assert cert.triangles == 0 and cert.coverage_gap <= 1 and cert.isolated_samples == len(mesh.vertices)
    assert shapely.intersects_xy(region.geometry, *np.array(cert.coverage_gap_at))


def test_a_bridged_notch_is_measured_outside_the_region():
    notch = Polygon([(0.45, 1), (0.5, 0.4), (0.55, 1)])          # a 9.5° V cut from the top
    region = pds.Region.from_shapely(box(0, 0, 1, 1).difference(notch))
    plain = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.1).certificate()
    bridged = pds.mesh_region(region, 0.1, seed=1).certificate()
    assert plain.outside_area_ratio < 1e-12 and plain.outside_distance < 1e-9
    assert bridged.outside_area_ratio > 0 and bridged.outside_distance > 0.2
    assert bridged.outside_distance * 0.1 <= 0.6 * np.hypot(0.05, 0.6)   # within the notch
