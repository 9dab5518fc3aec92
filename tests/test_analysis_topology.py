"""Topology of meshes against their regions: Betti numbers of hand-built complexes,
Theorem 2 on generated regions with alpha <= suggest_alpha, and each kind of defect
located where it happens when alpha is too large."""

import re

import numpy as np
import pytest
import shapely
from hypothesis import given, settings, strategies as st
from shapely.geometry import Point, Polygon, box

import pds_plugin as pds
from pds_plugin.mesh import mesh_betti
from pds_plugin.analysis.topology import topology_report


def region(geometry):
    return pds.Region.from_shapely(geometry)


def located(problem):
    """The first (x, y) named in a problem sentence."""
    x, y = re.search(r"\((-?[\d.e+-]+), (-?[\d.e+-]+)\)", problem).groups()
    return np.array([float(x), float(y)])


# --- Betti numbers of complexes built by hand ---------------------------------------

SQUARE_RING = np.array([[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6],
                        [3, 0, 4], [3, 4, 7]])     # outer square 0-3, inner square 4-7


def test_betti_of_a_square_annulus():
    labels, betti = mesh_betti(SQUARE_RING, 8)
    assert betti.tolist() == [[1, 1]]
    assert (labels == 0).all()


def test_betti_counts_components_joined_through_a_vertex_once():
    # two triangles sharing only vertex 2 (a pinch): one component, no hole
    labels, betti = mesh_betti(np.array([[0, 1, 2], [2, 3, 4]]), 5)
    assert betti.tolist() == [[1, 0]]
    # and apart, two components; an unused vertex gets label -1
    labels, betti = mesh_betti(np.array([[0, 1, 2], [3, 4, 5]]), 7)
    assert betti.tolist() == [[1, 0], [1, 0]]
    assert labels[6] == -1 and labels[0] != labels[3]


def test_betti_of_a_ring_closed_through_a_pinch():
    # a cycle of 3 triangles, consecutive ones sharing one vertex: one hole
    faces = np.array([[0, 1, 2], [2, 3, 4], [4, 5, 0]])
    assert mesh_betti(faces, 6)[1].tolist() == [[1, 1]]


def test_betti_of_no_triangles():
    labels, betti = mesh_betti(np.empty((0, 3), dtype=int), 4)
    assert betti.shape == (0, 2) and (labels == -1).all()


@settings(max_examples=60, deadline=None)
@given(n=st.integers(3, 40), data=st.data())
def test_component_labels_are_the_graph_components_numbered_by_smallest_vertex(n, data):
    """The union-find labels are the connected components of the triangles' edge graph
    (scipy's), components numbered in the order of their smallest vertex, -1 unused."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    triples = st.lists(st.integers(0, n - 1), min_size=3, max_size=3, unique=True)
    faces = np.array(data.draw(st.lists(triples, max_size=25)), dtype=np.int64).reshape(-1, 3)
    labels, betti = mesh_betti(faces, n)
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    component = connected_components(graph, directed=False)[1]
    used = np.isin(np.arange(n), faces)
    assert (labels[~used] == -1).all()
    same = component[used][:, None] == component[used][None, :]
    assert ((labels[used][:, None] == labels[used][None, :]) == same).all()
    first = [np.flatnonzero(labels == c)[0] for c in range(len(betti))]
    assert first == sorted(first)


@pytest.mark.parametrize("bad", [[[0, 1, 5]], [[0, -1, 2]]])
def test_betti_of_faces_outside_the_vertices_is_refused(bad):
    with pytest.raises(pds.errors.ArgumentError, match="refers to vertex"):
        mesh_betti(np.array(bad), 3)


# --- Theorem 2 on generated regions -----------------------------------------------------

@st.composite
def parts(draw, x0):
    """One component in the 3 x 3 cell starting at x0: a plate with holes or a thin frame."""
    kind = draw(st.sampled_from(["plate", "frame", "disc"]))
    if kind == "frame":
        wall = draw(st.sampled_from([0.15, 0.25, 0.4]))
        return box(x0, 0, x0 + 2.5, 2.5).difference(box(x0 + wall, wall, x0 + 2.5 - wall, 2.5 - wall))
    if kind == "disc":
        outer = Point(x0 + 1.25, 1.25).buffer(1.25, quad_segs=24)
        radius = draw(st.sampled_from([0.2, 0.5, 0.9]))
        return outer.difference(Point(x0 + 1.25, 1.25).buffer(radius, quad_segs=16))
    plate = box(x0, 0, x0 + 2.5, 2.5)
    count = draw(st.integers(0, 3))
    for k in range(count):          # square holes in a row, walls >= 0.2 between them
        side = draw(st.sampled_from([0.3, 0.45]))
        left = x0 + 0.2 + 0.75 * k
        plate = plate.difference(box(left, 0.8, left + side, 0.8 + side))
    return plate


@st.composite
def generated_regions(draw):
    gap = draw(st.sampled_from([0.2, 0.5]))
    count = draw(st.integers(1, 3))
    shapes = [draw(parts(k * (2.5 + gap))) for k in range(count)]
    return region(shapely.union_all(shapes))


@settings(max_examples=8, deadline=None)
@given(generated_regions(), st.integers(0, 2**16))
def test_theorem_2_betti_numbers_match_per_component(reg, seed):
    alpha = pds.suggest_alpha(reg, conforming=False)      # gaps count: the paper's complex
    for s in (seed, seed + 1):
        report = topology_report(pds.mesh_region(reg, alpha, seed=s))
        assert report.topology_ok, report
        assert report.betti_mesh == reg.betti
        assert all(c.betti_mesh == c.betti_region == (1, len(p.interiors))
                   for c, p in zip(report.per_component, reg.geometry.geoms))


def test_a_component_inside_another_ones_hole_keeps_both_holes():
    # a ring inside the hole of a ring (a pipe in a pipe): the outer hole's face of the
    # mesh's complement is the gap between the rings, not the inner ring's hole too
    nested = region(shapely.union_all([box(0, 0, 10, 10).difference(box(2, 2, 8, 8)),
                                       box(3, 3, 7, 7).difference(box(4, 4, 6, 6))]))
    for seed in (0, 1):
        report = topology_report(pds.mesh_region(nested, alpha=0.1, seed=seed))
        assert report.topology_ok, report
        assert [c.betti_mesh for c in report.per_component] == [(1, 1), (1, 1)]
    mesh = pds.mesh_region(nested, "auto")
    assert mesh.certificate().ok and mesh.alpha == pytest.approx(0.25)
    bridged = topology_report(pds.mesh_region(nested, alpha=0.9, seed=0, conforming=False))
    assert not bridged.topology_ok and any("joined" in p for p in bridged.problems)


# --- defects, located ---------------------------------------------------------------
# The paper's complex (conforming=False) makes these defects; a conforming mesh keeps
# gaps, notches and small holes open (tests/test_conforming.py).

@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_gap_narrower_than_alpha_is_flagged_and_named(seed):
    gap = 0.1
    two = region(box(0, 0, 3, 3).union(box(3 + gap, 0, 6 + gap, 3)))
    report = topology_report(pds.mesh_region(two, alpha=gap, seed=seed, conforming=False))
    assert not report.topology_ok
    assert report.betti_mesh[0] < 2 and report.betti_region == (2, 0)
    problem, = [p for p in report.problems if "joined" in p]
    assert "components 0 and 1" in problem and f"({gap:.4g} wide" in problem
    assert 3 <= located(problem)[0] <= 3 + gap


def test_a_gap_wider_than_twice_alpha_stays_open():
    two = region(box(0, 0, 3, 3).union(box(3.1, 0, 6.1, 3)))
    for seed in range(3):
        assert topology_report(pds.mesh_region(two, alpha=0.05, seed=seed)).topology_ok


def test_a_small_hole_is_reported_filled_at_its_centre():
    disc = region(Point(0, 0).buffer(3).difference(Point(1, 0.5).buffer(0.2, quad_segs=32)))
    report = topology_report(pds.mesh_region(disc, alpha=0.4, seed=0, conforming=False))
    assert report.betti_mesh == (1, 0) and not report.topology_ok
    problem, = report.problems
    assert "hole 0 of component 0" in problem and "filled" in problem
    assert np.linalg.norm(located(problem) - [1, 0.5]) < 0.01
    assert report.per_component[0].betti_mesh == (1, 0)
    assert report.per_component[0].betti_region == (1, 1)


def test_two_holes_merged_through_a_thin_wall():
    plate = region(box(0, 0, 8, 5).difference(box(1, 1, 3.95, 4)).difference(box(4, 1, 7, 4)))
    # the plain alpha-complex: a conforming mesh keeps the wall (tests/test_fixed_alpha.py)
    report = topology_report(pds.mesh_region(plate, alpha=0.3, seed=0, conforming=False))
    assert not report.topology_ok
    problem, = [p for p in report.problems if "merged" in p]
    assert "hole 0 of component 0 is merged with hole 1" in problem or \
        "hole 1 of component 0 is merged with hole 0" in problem
    assert 3.95 <= located(problem)[0] <= 4 and "0.05 thick" in problem


def test_a_hole_opened_to_the_outside():
    plate = region(box(0, 0, 6, 6).difference(box(0.04, 1, 4, 5)))
    report = topology_report(pds.mesh_region(plate, alpha=0.3, seed=0, conforming=False))
    problem, = [p for p in report.problems if "opened" in p]
    assert located(problem)[0] == pytest.approx(0.02, abs=1e-9)


def test_a_component_broken_at_a_thin_neck_and_a_lost_one():
    dumbbell = box(0, 0, 2, 2).union(box(2, 0.95, 4, 1.0)).union(box(4, 0, 6, 2))
    speck = box(10, 0, 10.05, 0.05)
    report = topology_report(pds.mesh_region(region(dumbbell.union(speck)), alpha=0.3, seed=0, conforming=False))
    broken, = [p for p in report.problems if "broken" in p]
    assert "component 0 is broken into" in broken and 2 <= located(broken)[0] <= 4
    lost, = [p for p in report.problems if "lost" in p]
    assert "component 1" in lost and np.linalg.norm(located(lost) - [10.025, 0.025]) < 0.01
    assert report.per_component[1].betti_mesh == (0, 0)


def test_a_bottle_shaped_notch_closed_off_into_a_hole():
    # a 2 x 2 cavity reached from outside through a 0.1 wide, 0.5 long neck
    bottle = box(0, 0, 6, 6).difference(box(2, 2, 4, 4).union(box(2.95, 3.9, 3.05, 6.5)))
    report = topology_report(pds.mesh_region(region(bottle), alpha=0.3, seed=0, conforming=False))
    assert report.betti_mesh == (1, 1) and report.betti_region == (1, 0)
    problem, = report.problems
    assert "notch of the outline is closed off" in problem
    assert 2.9 <= located(problem)[0] <= 3.1 and 3.9 <= located(problem)[1] <= 6


def test_a_hole_split_by_a_bridge_across_its_pipe():
    hole = shapely.union_all([Point(-1, 0).buffer(0.5), Point(1, 0).buffer(0.5),
                              box(-1, -0.05, 1, 0.05)])
    reg = region(Point(0, 0).buffer(3).difference(hole))
    report = topology_report(pds.mesh_region(reg, alpha=0.25, seed=0, conforming=False))
    assert report.betti_mesh == (1, 2)
    problem, = report.problems
    assert "hole 0 of component 0 is split into 2" in problem
    x, y = located(problem)
    assert -0.5 < x < 0.5 and abs(y) <= 0.05


def test_a_mesh_without_triangles_loses_everything():
    reg = region(box(0, 0, 1, 1))
    mesh = pds.mesh_region(reg, alpha=5.0, conforming=False)
    assert len(mesh.faces) == 0
    report = topology_report(mesh)
    assert report.betti_mesh == (0, 0) and not report.topology_ok
    assert "component 0" in report.problems[0] and "lost" in report.problems[0]


def test_report_is_plain_data():
    reg = region(box(0, 0, 2, 2).difference(box(0.5, 0.5, 1.5, 1.5)))
    report = topology_report(pds.mesh_region(reg, alpha=0.1))
    data = report.as_dict()
    assert data["betti_mesh"] == (1, 1) and data["topology_ok"] is True
    assert data["per_component"][0] == {"component": 0, "betti_region": (1, 1),
                                        "betti_mesh": (1, 1), "ok": True}
    assert "topology ok" in str(report)


def test_a_filled_hole_and_a_closed_notch_are_both_reported_when_the_betti_numbers_agree():
    """Coarse paper mesh (conforming=False) of a disc, a square and a bar with a small
    square hole: the mesh fills the hole and closes a notch off into a hole elsewhere, so
    (b0, b1) agree by chance; the report names both. Every mesh hole's centre lying in
    material or outside once made the hole matching index an empty array (IndexError)."""
    disc_and_bar = [  # as hypothesis drew it: a disc's 32-gon, a square and a bar
        (0.4157348061512726, -0.2777851165098011), (0.4619397662556434, -0.1913417161825449),
        (0.4903926402016152, -0.0975451610080641), (0.5, 0.0), (1.0, 0.0), (1.0, 1.0),
        (0.0, 1.0), (0.0, 0.5), (-0.0975451610080643, 0.4903926402016152),
        (-0.1913417161825452, 0.4619397662556433), (-0.2777851165098011, 0.4157348061512726),
        (-0.3125, 0.3872450375447784), (-0.3125, 1.0), (-0.9375, 1.0), (-0.9375, 0.0),
        (-0.5, 0.0), (-0.4903926402016152, -0.0975451610080643),
        (-0.4619397662556434, -0.191341716182545), (-0.4157348061512727, -0.2777851165098011),
        (-0.3535533905932737, -0.3535533905932738), (-0.277785116509801, -0.4157348061512727),
        (-0.1913417161825449, -0.4619397662556434), (-0.0975451610080641, -0.4903926402016152),
        (0.0, -0.5), (0.0975451610080642, -0.4903926402016152),
        (0.1913417161825449, -0.4619397662556434), (0.2777851165098011, -0.4157348061512726),
        (0.3535533905932738, -0.3535533905932737),
    ]
    hole = [(0.25, 0.25), (0.25, 0), (0, 0), (0, 0.25)]
    region = pds.Region.from_shapely(Polygon(disc_and_bar, [hole]))
    report = pds.mesh_region(region, 0.1875, seed=0, conforming=False).certificate().topology
    assert report.betti_mesh == report.betti_region == (1, 1) and not report.topology_ok
    assert any("is filled by the mesh" in p for p in report.problems)
    assert any("closed off into a hole" in p for p in report.problems)
