"""Graded meshes of planar partitions (composite sections, issue 23, ``graded=True``):
one radius field for the whole composite, each interface sampled once with it, every
region meshed and certified against it (the graded certificate).

Oracles: shapely areas and lengths of the input, the parts' own boundary edges (an
interface edge is an edge of both sides), the field itself (separation of the shared
samples), and the graded sampler's given samples read back.
"""

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.analysis.graded_certificate import GradedCertificate
from pds_plugin.graded_sampling import graded_poisson_disc
from pds_plugin.sizing import radius_field

from test_partition import CASES, _directed

POLYGONS = ("square in square", "side by side", "tee")
HOLED_PLATE = {"left": box(0, 0, 10, 6).difference(Point(7, 3).buffer(0.25, 8)),
               "right": box(10, 0, 30, 6)}


@pytest.mark.parametrize("case", POLYGONS)
@pytest.mark.parametrize("alpha", ["auto", 0.25])
def test_graded_composites_are_certified_with_exact_areas_and_outline(case, alpha):
    regions, _ = CASES[case]
    mesh = pds.mesh_regions(regions, alpha, seed=2, graded=True)
    certificate = mesh.certificate()
    assert certificate.ok_with_exceptions and certificate.interfaces.ok, str(certificate)
    assert all(isinstance(part, GradedCertificate) for part in certificate.parts)
    assert all(part.field is mesh.field for part in mesh.parts)      # one field for all
    geometries = list(regions.values()) if isinstance(regions, dict) else regions
    area = mesh.quality().area
    for name, geometry in zip(mesh.names, geometries):
        assert area[mesh.region_tags.where(name)].sum() == pytest.approx(geometry.area, rel=1e-12)
    union = shapely.union_all(geometries)
    boundary = mesh.boundary_edges
    length = np.hypot(*(mesh.vertices[boundary[:, 1]] - mesh.vertices[boundary[:, 0]]).T).sum()
    assert length == pytest.approx(union.boundary.length, rel=1e-12)


@pytest.mark.parametrize("case", list(CASES))
def test_graded_interface_edges_are_edges_of_both_sides(case):
    regions, _ = CASES[case]
    mesh = pds.mesh_regions(regions, "auto", seed=0, graded=True)
    boundary = [_directed(maps[part.boundary_edges])
                for part, maps in zip(mesh.parts, mesh.vertex_maps)]
    assert len(mesh.interface_edges) > 0
    for a, b in mesh.interface_edges.tolist():
        sides = [k for k, edges in enumerate(boundary) if (a, b) in edges or (b, a) in edges]
        assert len(sides) == 2
        assert ((a, b) in boundary[sides[0]]) != ((a, b) in boundary[sides[1]])
    # consecutive interface samples are separated by the one field (both sides read it)
    ends = mesh.vertices[mesh.interface_edges]
    r = mesh.field(ends.reshape(-1, 2)).reshape(-1, 2)
    assert np.all(np.hypot(*(ends[:, 1] - ends[:, 0]).T) >= r.min(axis=1) * (1 - 1e-12))


def test_graded_composite_grades_towards_a_small_hole_across_the_interface():
    mesh = pds.mesh_regions(HOLED_PLATE, "auto", seed=0, graded=True)
    certificate = mesh.certificate()
    assert certificate.ok_with_exceptions and certificate.interfaces.ok, str(certificate)
    edges = mesh.edges
    length = np.hypot(*(mesh.vertices[edges[:, 1]] - mesh.vertices[edges[:, 0]]).T)
    middle = mesh.vertices[edges].mean(axis=1)
    near_hole = np.hypot(*(middle - [7, 3]).T) < 1
    assert length[near_hole].max() < length[~near_hole].max() / 3
    uniform = pds.mesh_regions(HOLED_PLATE, min(length), seed=0)
    assert len(mesh.vertices) < len(uniform.vertices) / 3


def test_graded_is_deterministic_and_uniform_stays_the_default():
    regions, _ = CASES["tee"]
    first = pds.mesh_regions(regions, "auto", seed=5, graded=True)
    again = pds.mesh_regions(regions, "auto", seed=5, graded=True)
    assert np.array_equal(first.vertices, again.vertices) and np.array_equal(first.faces, again.faces)
    default, uniform = pds.mesh_regions(regions, 0.2), pds.mesh_regions(regions, 0.2, graded=False)
    assert default.field is None
    assert np.array_equal(default.vertices, uniform.vertices)
    with pytest.raises(pds.errors.ArgumentError, match="drop graded=False"):
        pds.mesh_regions(regions, 0.2, graded=False, grading=0.3)
    by_grading = pds.mesh_regions(regions, "auto", seed=5, grading=0.2)   # graded=True implied
    assert np.array_equal(by_grading.vertices, first.vertices)


def test_graded_sampler_keeps_the_given_boundary_samples():
    region = pds.Region.from_shapely(box(0, 0, 4, 2))
    field = radius_field(region, 0.2, 0.5)
    ring = np.array([[0, 0], [0.6, 0], [1.3, 0], [2, 0], [2.7, 0], [3.4, 0], [4, 0], [4, 0.7],
                     [4, 1.3], [4, 2], [3.3, 2], [2.6, 2], [2, 2], [1.4, 2], [0.7, 2], [0, 2],
                     [0, 1.3], [0, 0.7]], float)
    given = [np.roll(ring, -k, axis=0) for k in (0,)]
    samples = graded_poisson_disc(region, field, seed=0, boundary_samples=given)
    n = len(ring)
    assert np.array_equal(samples.points[:n], ring) and samples.on_boundary[:n].all()
    assert [r.tolist() for r in samples.rings] == [list(range(n))]
    assert not samples.on_boundary[n:].any()
    with pytest.raises(pds.errors.ArgumentError, match="at least 3 samples"):
        graded_poisson_disc(region, field, boundary_samples=[ring[:2]])


def test_single_edge_chains_at_sharp_junctions_take_the_general_rule_in_one_pass(monkeypatch):
    """A fan of nine triangles about a centre (40° there, a clearance of 1.46 r): every
    spoke is a chain of one edge between two junctions, sampled by the one-pass path
    (``partition._single_edges``); it gives exactly what the general rule of each chain
    (``_graded_chain``, forced by leaving that path out) gives, legs and all."""
    from pds_plugin import partition
    from pds_plugin.sizing import RadiusField

    turn = np.linspace(0, 2 * np.pi, 10)[:-1]
    xy = np.vstack([[0.0, 0.0], 3.0 * np.column_stack([np.cos(turn), np.sin(turn)])])
    rings = [[np.array([0, 1 + k, 1 + (k + 1) % 9])] for k in range(9)]
    field = RadiusField([[0.4, 0.1]], [0.08], grading=0.2, cap=0.5)
    topology = partition.partition_topology(rings, [xy] * 9)
    spokes = [c for c, (vertices, _) in enumerate(topology.chains)
              if len(vertices) == 2 and 0 in vertices.tolist()]
    assert len(spokes) == 9

    def sampled():
        chains = partition.graded_sample_chains(rings, [xy] * 9, [field] * 9, seed=3,
                                                topology=topology)
        return [chains.points(xy)[ids] for ids in chains.chain_samples]

    general_rule, asked = partition._graded_chain, []

    def recorded(vertices, *args):
        asked.append(sorted(vertices.tolist()))
        return general_rule(vertices, *args)

    monkeypatch.setattr(partition, "_graded_chain", recorded)
    one_pass = sampled()
    assert not any(0 in vertices for vertices in asked)      # no spoke asked one by one
    monkeypatch.setattr(partition, "_single_edges", lambda *args: {})
    general = sampled()
    assert all(np.array_equal(a, b) for a, b in zip(one_pass, general))
    # the spokes keep the centre's clearance: their first sample is over r beyond it
    for c in spokes:
        points = one_pass[c]
        centre = 0 if np.all(points[0] == 0) else -1
        nearest = points[1] if centre == 0 else points[-2]
        assert np.hypot(*nearest) > 1.02 * field(nearest[None])[0]
