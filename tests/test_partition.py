"""Meshes of planar partitions (composite sections, issue 23): shared boundary chains
sampled once, each region certified on its own, the meshes joined with no T-junction.

Oracles: shapely areas and lengths of the input, the parts' own boundary edges, and a
join made the naive way (each region meshed alone, vertices merged by coordinates),
which the interface check must refuse.
"""

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon, box

import pds_plugin as pds
from pds_plugin.partition import interface_report, sample_chains

DISC = {r: Point(0, 0).buffer(r, 64) for r in (1.0, 2.0, 3.0)}
CASES = {
    "square in square": ({"steel": box(1, 1, 2, 2),
                          "concrete": box(0, 0, 3, 3).difference(box(1, 1, 2, 2))}, 0.17),
    "concentric annuli": ({"core": DISC[1.0], "middle": DISC[2.0].difference(DISC[1.0]),
                           "outer": DISC[3.0].difference(DISC[2.0])}, 0.15),
    "side by side": ([box(0, 0, 1, 1), box(1, 0, 2.5, 1), box(2.5, 0, 3, 1)], 0.1),
    "tee": ({"base": box(0, 0, 3, 1), "post": box(0.7, 1, 2.2, 2)}, 0.1),
}


def _directed(edges):
    return {tuple(edge) for edge in np.asarray(edges).tolist()}


@pytest.mark.parametrize("case", CASES)
def test_every_region_is_certified_and_the_interfaces_join(case):
    regions, alpha = CASES[case]
    mesh = pds.mesh_regions(regions, alpha, seed=1)
    certificate = mesh.certificate()
    assert certificate.ok, str(certificate)
    for part in certificate.parts:     # Poisson, maximal and Theorem 1 in every region
        assert part.min_separation >= 1 - 1e-12 and part.coverage_gap <= 1 + 1e-9
        assert part.min_angle >= 30 - 1e-9 and part.max_aspect_ratio <= 4 * np.sqrt(3) + 1e-9
    assert certificate.interfaces.ok
    # every interface edge is an edge of both sides' meshes, run opposite ways
    boundary = [_directed(maps[part.boundary_edges])
                for part, maps in zip(mesh.parts, mesh.vertex_maps)]
    assert len(mesh.interface_edges) > 0
    for (a, b), tag in zip(mesh.interface_edges.tolist(), mesh.interface_tags.values):
        sides = [k for k, edges in enumerate(boundary) if (a, b) in edges or (b, a) in edges]
        assert len(sides) == 2
        assert ((a, b) in boundary[sides[0]]) != ((a, b) in boundary[sides[1]])
        names = set(mesh.interface_tags.name_of(tag).split("|"))
        assert names == {mesh.names[k] for k in sides}


@pytest.mark.parametrize("case", ["square in square", "side by side", "tee"])
def test_areas_per_region_and_the_outline_are_exact_on_polygons(case):
    regions, alpha = CASES[case]
    mesh = pds.mesh_regions(regions, alpha, seed=0)
    geometries = list(regions.values()) if isinstance(regions, dict) else regions
    area = mesh.quality().area
    for name, geometry in zip(mesh.names, geometries):
        assert area[mesh.region_tags.where(name)].sum() == pytest.approx(geometry.area, rel=1e-12)
    union = shapely.union_all(geometries)
    boundary = mesh.boundary_edges           # only the outer boundary is left open
    length = np.hypot(*(mesh.vertices[boundary[:, 1]] - mesh.vertices[boundary[:, 0]]).T).sum()
    assert length == pytest.approx(union.boundary.length, rel=1e-12)
    assert mesh.outline.symmetric_difference(union).area <= 1e-12 * union.area


def test_same_seed_same_mesh_other_seed_other_mesh():
    regions, alpha = CASES["concentric annuli"]
    first, again = pds.mesh_regions(regions, alpha, seed=3), pds.mesh_regions(regions, alpha, seed=3)
    assert np.array_equal(first.vertices, again.vertices)
    assert np.array_equal(first.faces, again.faces)
    other = pds.mesh_regions(regions, alpha, seed=4)
    assert not np.array_equal(first.vertices[:len(other.vertices)], other.vertices[:len(first.vertices)])


def test_a_naive_join_is_refused_by_the_interface_check():
    """Each region meshed alone and the vertices merged by coordinates: the two sides
    sample the interface differently, which the check must see."""
    left, right = box(0, 0, 1, 1), box(1, 0, 2, 1)
    meshes = [pds.mesh_region(pds.Region.from_shapely(g), 0.1, seed=s)
              for g, s in ((left, 0), (right, 1))]
    points = np.concatenate([m.vertices for m in meshes])
    unique, inverse = np.unique(points, axis=0, return_inverse=True)
    faces = inverse.reshape(-1)[np.concatenate([meshes[0].faces,
                                                 meshes[1].faces + len(meshes[0].vertices)])]
    interface = [k for k in range(len(unique)) if unique[k, 0] == 1.0]
    chords = np.column_stack([interface[:-1], interface[1:]])
    outer = (unique[:, 0] == 0) | (unique[:, 0] == 2) | (unique[:, 1] == 0) | (unique[:, 1] == 1)
    report = interface_report(unique, faces, chords, outer)
    assert not report.ok and report.open_edges > 0
    assert "T-junction" in " ".join(report.problems) or "open edge" in " ".join(report.problems)


def test_sharp_corners_at_junctions_are_exceptions_within_their_bounds():
    wedge = Polygon([(0, 0), (2, 0.5), (0, 1)])           # 14° corners of the other side
    mesh = pds.mesh_regions({"wedge": wedge, "rest": box(0, 0, 2.5, 1).difference(wedge)},
                            0.1, seed=0)
    certificate = mesh.certificate()
    assert certificate.ok_with_exceptions and certificate.interfaces.ok, str(certificate)
    assert not certificate.ok
    corners = np.array([(0, 0), (0, 1), (2, 0.5)])
    for part in certificate.parts:
        for exception in part.exceptions:
            assert exception.meets_bound
            assert np.hypot(*(corners - exception.place).T).min() < 2 * mesh.alpha


def test_chains_are_sampled_once_with_both_sides_rules():
    """The samples of a shared chain are one list read by both sides; the parts along a
    chain lie in [alpha, √3 alpha] except the junctions' clearances."""
    xy = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]], float)
    chains = sample_chains([[np.array([0, 1, 4, 5])], [np.array([1, 2, 3, 4])]], [xy, xy], 0.12)
    shared = [c for c, sides in enumerate(chains.sides) if sides == (0, 1)]
    assert len(shared) == 1
    samples = chains.chain_samples[shared[0]]
    for ring in chains.rings:                    # both rings hold the whole chain
        assert set(samples.tolist()) <= set(np.concatenate(ring).tolist())
    steps = np.diff(chains.points(xy)[samples][:, 1])
    assert np.all(steps >= 0.12 * (1 - 1e-12)) and np.all(steps <= np.sqrt(3) * 0.12 * (1 + 1e-12))


@pytest.mark.parametrize("pinned", [[], [0, 2], [1, 3, 5]])
def test_rings_read_at_once_are_the_rings_walked_chain_by_chain(pinned):
    # three regions side by side and one whose ring passes vertex 2 twice (a loop at a
    # junction); each ring's samples against the walk along its chains
    from pds_plugin.partition import _ChainEdges, _following, _ring_walk, split_counts
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [2, 1], [1.5, 2], [0.5, 2]], float)
    rings = [[np.array([0, 1, 2, 3])], [np.array([1, 4, 5, 2])],
             [np.array([3, 2, 5, 6, 2, 7])]]
    chains = sample_chains(rings, [xy] * 3, 0.2, pinned=pinned)
    every = np.concatenate([ring for region in rings for ring in region])
    counts = [len(ring) for region in rings for ring in region]
    pairs = list(zip(chains.chains, chains.closed))
    chain, forward = _ChainEdges(pairs).read(every, every[_following(counts)])
    first = np.array([c[0] for c in chains.chains])
    last = np.array([c[-1] for c in chains.chains])
    starts = ~np.array(chains.closed)[chain] & (every == np.where(forward, first[chain],
                                                                  last[chain]))
    walked = [_ring_walk(*run, pairs, chains.chain_samples) for run in zip(
        *(split_counts(a.tolist(), counts) for a in (chain, forward, starts)))]
    read = [ring for region in chains.rings for ring in region]
    assert len(read) == len(walked) == 3
    assert all(np.array_equal(a, b) for a, b in zip(read, walked))


def test_regions_running_an_edge_the_same_way_are_refused_by_name():
    xy = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [2, 1], [0.5, -1]], float)
    rings = [[np.array([0, 1, 2, 3])], [np.array([1, 4, 5, 2])], [np.array([0, 1, 6])]]
    with pytest.raises(ValueError, match="regions 0 and 2 overlap along the edge of "
                                         "vertices 0 and 1"):
        sample_chains(rings, [xy] * 3, 0.2)


def test_bad_input_gets_a_clear_error():
    with pytest.raises(pds.RegionError, match="'a' and 'b' overlap .* around"):
        pds.mesh_regions({"a": box(0, 0, 2, 2), "b": box(1, 1, 3, 3)}, 0.2)
    with pytest.raises(pds.ArgumentError, match="empty"):
        pds.mesh_regions({}, 0.2)
    with pytest.raises(pds.ArgumentTypeError, match="Point"):
        pds.mesh_regions([Point(0, 0)], 0.2)
    with pytest.raises(pds.ArgumentError, match="'auto'"):
        pds.mesh_regions([box(0, 0, 1, 1)], "fine")


def test_auto_alpha_and_tags_for_finite_elements():
    regions = {"core": box(0.4, 0.4, 0.6, 0.6), "shell": box(0, 0, 1, 1).difference(box(0.4, 0.4, 0.6, 0.6))}
    mesh = pds.mesh_regions(regions, "auto")
    assert mesh.certificate().ok
    assert mesh.alpha <= min(pds.suggest_alpha(pds.Region.from_shapely(g)) for g in regions.values())
    assert sorted(mesh.region_tags.names) == ["core", "shell"]
    assert mesh.interface_tags.names == {"core|shell": 1}


def test_voronoi_cells_with_a_round_inclusion():
    """Junctions of three cells, cells meeting the outline at sharp angles, a curved
    interface cutting through several cells: every part certified (small features
    itemised) and the interfaces joined."""
    rng = np.random.default_rng(0)
    points = shapely.MultiPoint(rng.random((8, 2)) * 4)
    square, disc = box(0, 0, 4, 4), Point(2, 2).buffer(0.5, 32)
    cells = [cell.intersection(square).difference(disc) for cell in
             shapely.get_parts(shapely.voronoi_polygons(points, extend_to=box(-1, -1, 5, 5)))]
    mesh = pds.mesh_regions([cell for cell in cells if cell.area > 0] + [disc], 0.08, seed=0)
    certificate = mesh.certificate()
    assert certificate.ok_with_exceptions and certificate.interfaces.ok, str(certificate)
    assert mesh.quality().area.sum() == pytest.approx(16.0, rel=1e-12)   # the square, exactly
    assert len(set(mesh.interface_tags.names)) >= 10


def test_materials_reach_the_finite_element_codes():
    skfem = pytest.importorskip("skfem")
    regions, alpha = CASES["concentric annuli"]
    mesh = pds.mesh_regions(regions, 0.3)
    fem = mesh.to_skfem()
    assert isinstance(fem, skfem.MeshTri) and set(fem.subdomains) == set(regions)
    for name in regions:      # each material's elements are its triangles
        assert np.array_equal(np.sort(fem.subdomains[name]), mesh.region_tags.where(name))


def test_boundaries_that_nearly_touch_are_refused():
    with pytest.raises(pds.RegionError, match="nearly touch at .* without sharing"):
        pds.mesh_regions({"a": box(0, 0, 1, 1), "b": box(1 + 1e-11, 0.2, 2, 0.8)}, 0.1)


def test_frames_read_at_once_refuse_a_vertex_outside_its_frame():
    """read_frames searches all frames through one index of keys region x span + id
    (Frames keeps it for a remesh's many reads): the same points as frame by frame, and
    a vertex no frame holds, even one whose key would land in another frame's range
    (above every id, or negative), is refused, not read from the wrong frame."""
    from pds_plugin.partition import Frame, Frames, read_frames

    frames = Frames([Frame([7, 3], [[1.0, 2.0], [3.0, 4.0]]), Frame([3, 0], [[5.0, 6.0],
                                                                          [7.0, 8.0]])])
    region, vertex = np.array([1, 0, 0, 1]), np.array([3, 3, 7, 0])
    expected = [frames[r][[v]][0].tolist() for r, v in zip(region, vertex)]
    assert read_frames(frames, region, vertex).tolist() == expected
    assert read_frames(list(frames), region, vertex).tolist() == expected
    # span 8: (region 0, vertex 8) has the key of (region 1, vertex 0), and (region 1,
    # vertex -1) that of (region 0, vertex 7)
    for region, vertex in (([0], [8]), ([1], [-1]), ([0], [0])):
        with pytest.raises(KeyError):
            read_frames(frames, np.array(region), np.array(vertex))
