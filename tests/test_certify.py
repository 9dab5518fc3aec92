"""pds.certify: one entry point for every kind of mesh, agreeing with mesh.certificate()
and with the certificate measured afresh by that kind's own builder (not the cached one)."""

import json

import pytest
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.analysis.certificate import certify as certify_uniform
from pds_plugin.analysis.graded_certificate import certify_graded
from pds_plugin.partition import interface_report


@pytest.fixture(scope="module")
def plate():
    return pds.Region.from_shapely(box(0, 0, 3, 2).difference(Point(1, 1).buffer(0.4, 32)))


def same(a, b):
    """Two certificates measured the same: equal JSON (NaN and tuples compare as text)."""
    return json.dumps(a.as_dict(), sort_keys=True) == json.dumps(b.as_dict(), sort_keys=True)


def test_uniform_mesh_gets_the_uniform_certificate(plate):
    mesh = pds.mesh_region(plate, 0.15, seed=3)
    cert = pds.certify(mesh)
    assert type(cert) is pds.Certificate and cert is mesh.certificate()
    assert cert.ok and same(cert, certify_uniform(mesh))


def test_graded_mesh_gets_the_graded_certificate(plate):
    """The issue's bug: the uniform measure FAILED a valid graded mesh (separation / alpha)."""
    mesh = pds.mesh_region(plate, 0.5, seed=3, graded=True)
    assert isinstance(mesh.field, pds.RadiusField)
    cert = pds.certify(mesh)
    assert type(cert) is pds.GradedCertificate and cert is mesh.certificate()
    assert cert.ok and cert.grading == mesh.field.grading
    assert same(cert, certify_graded(mesh))
    with pytest.raises(pds.ArgumentError, match=r"graded.*pds_plugin\.certify"):
        certify_uniform(mesh)           # never a uniform certificate of a graded mesh


def test_composite_mesh_gets_the_partition_certificate():
    left, right = box(0, 0, 1, 1), box(1, 0, 2, 1).difference(Point(1.5, 0.5).buffer(0.2, 32))
    mesh = pds.mesh_regions({"steel": left, "rubber": right}, 0.1)
    cert = pds.certify(mesh)
    assert type(cert) is pds.PartitionCertificate and cert is mesh.certificate()
    assert cert.ok and cert.names == ("steel", "rubber")
    for part, part_cert in zip(mesh.parts, cert.parts):
        assert same(part_cert, pds.certify(part)) and same(part_cert, certify_uniform(part))
    fresh = interface_report(mesh.vertices, mesh.faces, mesh.interface_edges, mesh.on_boundary)
    assert fresh.as_dict() == cert.interfaces.as_dict() and len(mesh.interface_edges) > 0


@pytest.mark.parametrize("graded", [False, True])
def test_quadratic_mesh_gets_its_linear_certificate_with_the_jacobians(plate, graded):
    linear = pds.mesh_region(plate, 0.3, seed=1, graded=graded)
    curved = linear.quadratic()
    cert = pds.certify(curved)
    assert type(cert) is type(linear.certificate())        # graded stays graded
    assert cert.quadratic == curved.jacobian_report and cert.quadratic.ok
    assert same(cert, curved.certificate())
    assert {k: v for k, v in cert.as_dict().items() if k != "quadratic"} == {
        k: v for k, v in linear.certificate().as_dict().items() if k != "quadratic"}


def test_what_is_not_a_mesh_is_named(plate):
    with pytest.raises(pds.ArgumentTypeError, match="certify needs a pds_plugin.PlanarMesh"):
        pds.certify(plate)

    class Remeshed:             # the attributes a RemeshResult has
        patch_meshes, certificates = (), ()
    with pytest.raises(pds.ArgumentTypeError, match="result.certificates"):
        pds.certify(Remeshed())
