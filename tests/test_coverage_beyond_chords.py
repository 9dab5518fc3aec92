"""The coverage of the region beyond a chord whose arc bends both ways (docs/conforming.md,
Lemma 3), and beyond a convex one: the certificate's bound against brute force (dense
probes, shortest paths through the region), on a kinked torus section, a piece hidden
from both chord ends and the apex, random kinked pieces, and convex slivers seen from
the apex of the chord's triangle."""

import numpy as np
import pytest
import shapely
from scipy.spatial import Delaunay
from shapely.geometry import Polygon

import pds_plugin as pds
from pds_plugin.analysis.conformity import SampledBoundary

SQUARE = [(0, 0), (0, -2), (2, -2), (2, 0)]


def square_with(arc, inner):
    """The square [0, 2] x [-2, 0] with ``arc`` (from (2, 0) to (0, 0)) beyond its top
    side, sampled at its corners and at the interior samples ``inner``; the mesh is the
    Delaunay triangulation of the samples (counter-clockwise). The chord from (2, 0) to
    (0, 0) is the one whose arc bends both ways."""
    region = pds.Region.from_shapely(Polygon([*SQUARE, *arc]))
    points = np.array([(2, 0), (0, 0), (0, -2), (2, -2), *inner], float)
    on_boundary = np.arange(len(points)) < 4
    faces = Delaunay(points).simplices
    p, q, r = (points[faces[:, i]] for i in range(3))
    clockwise = (q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1]) < (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0])
    faces[clockwise] = faces[clockwise][:, ::-1]
    return region, points, on_boundary, faces


def visible_distance(region, points, probe):
    """For each probe point, the distance to the nearest sample it sees through the
    region (the chord polygon lies in it here): brute force."""
    inside = region.geometry.buffer(1e-9)
    distance = np.full(len(probe), np.inf)
    for p in points:
        lines = shapely.linestrings(np.stack([probe, np.broadcast_to(p, probe.shape)], 1))
        seen = shapely.covers(inside, lines)
        distance[seen] = np.minimum(distance[seen], np.hypot(*(probe[seen] - p).T))
    return distance


def path_distance(region, points, probe):
    """For each probe point, the length of the shortest path through the region to the
    nearest sample: brute force. Such a path bends only at the region's vertices, so it
    is a segment to a vertex or sample the probe sees, then the shortest path from there
    (Dijkstra over the graph of vertices and samples that see each other)."""
    inside = region.geometry.buffer(1e-9)
    nodes = np.concatenate([points, *region.rings])
    pairs = np.stack(np.triu_indices(len(nodes), 1), 1)
    lines = shapely.linestrings(nodes[pairs])
    seen = shapely.covers(inside, lines)
    graph = np.full((len(nodes), len(nodes)), np.inf)
    length = np.hypot(*(nodes[pairs[:, 0]] - nodes[pairs[:, 1]]).T)
    graph[pairs[seen, 0], pairs[seen, 1]] = graph[pairs[seen, 1], pairs[seen, 0]] = length[seen]
    to_sample = np.full(len(nodes), np.inf)
    to_sample[:len(points)] = 0.0
    for _ in range(len(nodes)):                         # Bellman-Ford: a few dozen nodes
        to_sample = np.minimum(to_sample, (graph + to_sample[None, :]).min(axis=1))
    distance = np.full(len(probe), np.inf)
    for node, rest in zip(nodes, to_sample):
        lines = shapely.linestrings(np.stack([probe, np.broadcast_to(node, probe.shape)], 1))
        sees = shapely.covers(inside, lines)
        distance[sees] = np.minimum(distance[sees], np.hypot(*(probe[sees] - node).T) + rest)
    return distance


def probes_in(arc, count, seed, ends=((2, 0), (0, 0))):
    sliver = Polygon([ends[0], *arc, ends[1]]).buffer(0)
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = sliver.bounds
    probe = rng.uniform((x0, y0), (x1, y1), (count, 2))
    return np.concatenate([probe[shapely.contains_xy(sliver, probe[:, 0], probe[:, 1])],
                           np.array(arc)])


def test_a_wedge_behind_a_reflex_kink_is_reached_around_the_kink():
    """The chord of a held-out torus section (seed 24, g05-torus-ring p3, uniform "auto",
    in units of alpha): a 1.8 degree reflex kink 0.435 from the chord end a hides a thin
    wedge beyond it from a; b, 1.025 away, is the nearest sample that sees it. Through
    the region the wedge is nearer: from a to the kink, then on. The certificate's bound
    is that path (a, the kink, the part's farthest vertex: 0.87 alpha), at least the
    brute-force shortest path to a sample from every probe of the wedge; on the former
    code it was 1.025 alpha, the nearest sample seen in a straight line."""
    along = np.array([0.4353, 0.6681, 0.9678, 1.2672])
    depth = np.array([0.00274, 0.01154, 0.01445, 0.00897])
    length = 1.4602
    arc = [(2 - t, d) for t, d in zip(along, depth)]          # a = (2, 0), b = (2 - length, 0)
    region = pds.Region.from_shapely(Polygon([(2 - length, 0), (2 - length, -2), (2, -2), (2, 0), *arc]))
    a, b, apex = (2.0, 0.0), (2 - length, 0.0), (2 - 0.6, -1.1)
    points = np.array([a, b, (2 - length, -2), (2, -2), apex])
    faces = np.array([[1, 2, 4], [2, 3, 4], [3, 0, 4], [0, 1, 4]])
    sampled = SampledBoundary(region, points, np.arange(5) < 4, 1.0, faces)
    assert sampled.mixed.any() and not sampled.uncertain.any()
    gap, _ = sampled.sliver_gap()
    kink, next_ = np.array(arc[0]), np.array(arc[1])
    t = np.linspace(1e-3, 0.2, 50)[:, None]
    wedge = kink + t * (next_ - kink) - [0, 1e-7]               # just inside, past the kink
    assert visible_distance(region, points, wedge).max() > 1.0  # in a straight line
    probes = np.concatenate([wedge, probes_in(arc, 5000, 0, (a, b))])
    assert path_distance(region, points, probes).max() <= gap * (1 + 1e-9)
    assert gap < 0.9


def test_a_piece_hidden_from_both_ends_and_the_apex_is_seen_from_the_next_triangle():
    """A notch in the arc (reflex kinks at (1.13, 0.09) and (1.01, 0.02)) hides its top
    from both chord ends and from the apex of the chord's triangle; the corner (0, -2) of
    the triangle across the apex's edge sees it, across that edge, and the chord end
    (2, 0) reaches it around the kink at (1.13, 0.09). On the former code the chord was
    uncertain ("the boundary bends both ways"); now the piece is cut straight across into
    parts each reached from one sample, and the bound lies between the brute-force
    shortest paths and the distance to the nearest sample seen in a straight line."""
    arc = [(1.13, 0.09), (1.12, 0.13), (1.01, 0.02), (0.83, 0.11)]
    region = pds.Region.from_shapely(Polygon([*SQUARE, *arc]))
    points = np.array([(2, 0), (0, 0), (0, -2), (2, -2), (1.5, -0.7)])
    faces = np.array([[2, 4, 1], [4, 0, 1], [3, 4, 2], [4, 3, 0]])
    sampled = SampledBoundary(region, points, np.arange(5) < 4, 1.2, faces)
    assert not sampled.uncertain.any()
    gap, _ = sampled.sliver_gap()
    probes = probes_in(arc, 20000, 0)
    assert path_distance(region, points, probes).max() <= gap * (1 + 1e-9)
    assert gap < visible_distance(region, points, probes).max()


@pytest.mark.parametrize("seed", range(24))
def test_the_bound_beyond_a_kinked_chord_is_never_below_the_coverage(seed):
    """Random arcs of 3-6 vertices beyond a chord of length 2 (heights up to 0.15, so
    they bend both ways) over a square meshed through 1-3 random interior samples: where
    the certificate bounds the piece, no probe of 5,000 is farther from every sample
    through the region (shortest paths, brute force)."""
    rng = np.random.default_rng(seed)
    count = rng.integers(3, 7)
    arc = list(zip(np.sort(rng.uniform(0.1, 1.9, count))[::-1], rng.uniform(0.01, 0.15, count)))
    inner = rng.uniform((0.2, -1.8), (1.8, -0.3), (rng.integers(1, 4), 2))
    region, points, on_boundary, faces = square_with(arc, inner)
    sampled = SampledBoundary(region, points, on_boundary, 1.2, faces)
    if not sampled.mixed.any() or sampled.uncertain.any():
        pytest.skip("the arc bends one way, or no cut is proven")
    gap, _ = sampled.sliver_gap()
    distance = path_distance(region, points, probes_in(arc, 5000, seed))
    assert np.isfinite(distance).all() and distance.max() <= gap * (1 + 1e-9)


def bulge(height, count=24):
    """A circular arc from (2, 0) to (0, 0) bulging ``height`` above the chord (a convex
    sliver beyond it), its inner vertices."""
    centre = (height ** 2 - 1) / (2 * height)                 # (1, centre), through both ends
    angle = np.linspace(np.arctan2(-centre, 1), np.arctan2(-centre, -1), count + 2)[1:-1]
    return [(1 + np.hypot(1, centre) * np.cos(t), centre + np.hypot(1, centre) * np.sin(t))
            for t in angle]


def test_a_convex_sliver_farther_than_alpha_from_the_chord_ends_is_seen_from_the_apex():
    """A chord of length 2 under an arc 0.3 high, alpha 1: the top of the sliver is 1.04
    from both chord ends, but 0.7 from the apex of the chord's triangle, which sees the
    middle of the sliver through the chord. The bound cuts the sliver into parts seen
    from the ends and from the apex: at most alpha, at least the brute-force distance to
    the nearest sample seen in a straight line from every probe (a steep graded mesh's
    long chords on arcs: flanges' sections at L = 0.45 said FAILED at 1.22 r from the
    ends while the apex was 0.59 r away). On the former code the bound was 1.04."""
    arc = bulge(0.3)
    region, points, on_boundary, faces = square_with(arc, [(1.0, -0.4)])
    sampled = SampledBoundary(region, points, on_boundary, 1.0, faces)
    assert sampled.sliver.any() and not sampled.mixed.any()
    gap, _ = sampled.sliver_gap()
    probes = probes_in(arc, 20000, 0)
    ends = np.minimum(*(np.hypot(*(probes - e).T) for e in ((2, 0), (0, 0))))
    assert ends.max() > 1.04
    assert visible_distance(region, points, probes).max() <= gap * (1 + 1e-9) <= 1.0


@pytest.mark.parametrize("seed", range(12))
def test_the_bound_over_a_convex_sliver_is_never_below_the_coverage(seed):
    """Random bulges (0.15-0.6 high) over a chord of length 2, the square meshed through
    1-3 random interior samples, alpha 0.8-1.1 (so that the ends alone often leave the
    sliver uncovered): the bound, from the ends or cut into parts seen from the samples
    of Q, is never below the brute-force distance to the nearest sample a probe sees."""
    rng = np.random.default_rng(seed)
    arc = bulge(rng.uniform(0.15, 0.6))
    inner = rng.uniform((0.2, -1.8), (1.8, -0.2), (rng.integers(1, 4), 2))
    region, points, on_boundary, faces = square_with(arc, inner)
    sampled = SampledBoundary(region, points, on_boundary, rng.uniform(0.8, 1.1), faces)
    gap, _ = sampled.sliver_gap()
    distance = visible_distance(region, points, probes_in(arc, 5000, seed))
    assert np.isfinite(distance).all() and distance.max() <= gap * (1 + 1e-9)


@pytest.mark.parametrize("seed", range(12))
def test_the_stretch_a_neighbouring_corner_sees_is_seen_through_the_two_triangles(seed):
    """:func:`_stretch_seen`: every point of the chord ab within the stretch it returns
    is joined to the corner d (across ac from b) by a segment inside the triangles abc
    and acd; a point just beyond it is not (None: no point but a is)."""
    from pds_plugin.analysis.conformity import _stretch_seen

    rng = np.random.default_rng(seed)
    a, b = np.array([0.0, 0.0]), np.array([2.0, 0.0])
    c = np.array([rng.uniform(0.3, 1.7), rng.uniform(-1.5, -0.3)])
    along_ac = (c - a) / np.hypot(*(c - a))
    away = np.array([along_ac[1], -along_ac[0]])             # across ac from b
    d = a + along_ac * rng.uniform(-0.5, 1.5) * np.hypot(*(c - a)) + away * rng.uniform(0.2, 1.5)
    union = shapely.union(Polygon([a, b, c]), Polygon([a, c, d])).buffer(1e-12)
    stretch = _stretch_seen(d, a, c, a, b)
    if stretch is None:                                      # d's angle turns away from ab
        assert not union.covers(shapely.LineString([d, (1e-3, 0.0)]))
        return
    lo, hi = stretch
    assert lo == 0.0 < hi <= 2.0
    inside = np.linspace(lo, hi, 50)
    y = np.column_stack([inside, np.zeros_like(inside)])
    assert shapely.covers(union, shapely.linestrings(np.stack([np.broadcast_to(d, y.shape), y], 1))).all()
    if hi < 2 - 1e-6:
        beyond = np.array([min(hi + 1e-3, 2.0), 0.0])
        assert not union.covers(shapely.LineString([d, beyond]))


def test_a_graded_bound_beyond_the_chords_is_the_largest_ratio_to_r_not_the_largest_distance():
    """A circle sampled at every fifth vertex, with a radius field falling from 1.5 to
    0.5 across it: every sliver beyond a chord peaks at about the same distance, so the
    largest ratio to r is where r is smallest. The graded certificate divides the bound
    by r at the place it is given; on the former code that place was the largest
    distance, wherever it fell (a held-out torus section, seed 22 g05-torus-ring p3
    graded, said ok at 0.93 while one of its pieces was bounded only at 1.29 r)."""
    angle = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ring = 10 * np.column_stack([np.cos(angle), np.sin(angle)])
    ring[52] *= 1 - 0.001                                      # one mixed chord too
    region = pds.Region.from_shapely(Polygon(ring))
    at = ring[::5]

    def radius(x):
        return 1.0 + 0.05 * np.asarray(x, float)[:, 0]

    sampled = SampledBoundary(region, at, np.ones(len(at), bool), 2.0, radius=radius)
    gap, place = sampled.sliver_gap()
    ratio = gap / radius(np.asarray(place)[None])[0]
    arc_vertices = ring[np.arange(len(ring)) % 5 != 0]
    chord = np.arange(len(ring))[np.arange(len(ring)) % 5 != 0] // 5
    ends = at[chord], at[(chord + 1) % len(at)]
    distance = np.minimum(*(np.hypot(*(arc_vertices - e).T) for e in ends))
    assert ratio >= (distance / radius(arc_vertices)).max() * (1 - 1e-12)
    assert place[0] < -9                                       # where r is smallest


def test_a_held_out_graded_section_reports_its_worst_piece_beyond_the_chords(monkeypatch):
    """Held out (seed 22), g05-torus-ring p3 graded "auto", with the sampler's move of
    chord ends onto the reflex vertices that hide pieces beyond their chords switched off
    (graded_sampling._unhidden): the code before the ratio fix certified it at 0.93 while
    one of its pieces was bounded only at 1.29 r in straight lines (brute force: points
    1.26 r from every sample they see). Along paths around the hiding vertex, and cut
    inside its long edges, that piece is within 0.68 r. The certificate's coverage is at
    least the ratio of every piece's bound to r at its place."""
    import sys
    from pathlib import Path

    from pds_plugin import graded_sampling

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
    import _cad_corpus

    def forget():
        _cad_corpus.generated_stl.cache_clear()
        _cad_corpus._generated_solid.cache_clear()

    monkeypatch.setattr(_cad_corpus, "GENERATED_SEED", 22)
    monkeypatch.setattr(graded_sampling, "_unhidden", lambda samples, *_: samples)
    forget()
    try:
        mesh = _cad_corpus.mesh(_cad_corpus.case("g05-torus-ring p3").region(), "graded auto")
    finally:
        forget()
    certificate = mesh.certificate()
    sampled = SampledBoundary(mesh.region, mesh.vertices, mesh.on_boundary, mesh.field.cap,
                              np.asarray(mesh.faces).reshape(-1, 3), mesh.field)
    gap, where, _, _ = sampled._pieces
    ratios = gap / mesh.field(where)
    assert 0.5 < ratios.max() <= certificate.coverage_gap * (1 + 1e-12)
    assert certificate.ok
