"""Conforming, constrained meshes (issue 9): the mesh is the section.

Oracles are independent of the certificate: shapely unions of the triangles, shapely
visibility (a segment inside the region bounded by the chords), and a brute-force
constrained complex over every triple of samples.
"""

import itertools
import json
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given, settings, strategies as st
from shapely.geometry import MultiPolygon, Point, Polygon, box

import pds_plugin as pds
from conftest import chord_region, face_set, shared_file, visible_pairs_closer_than
from pds_plugin.analysis.conformity import SampledBoundary
from regions import regions, wedge

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import _regions  # noqa: E402

MAX_ASPECT = 4 * np.sqrt(3)


def notched_plate(angles, alpha, depth=0.6):
    """A 1 x 3 plate with V-notches of the given angles (degrees) cut from the top; the
    notch walls and the plate's pieces between them are longer than 2 alpha."""
    width = 3.0
    cuts = []
    for k, angle in enumerate(angles):
        x = width * (k + 1) / (len(angles) + 1)
        half = depth * np.tan(np.radians(angle) / 2)
        cuts.append(Polygon([(x, 1 - depth), (x + half, 1.5), (x - half, 1.5)]))
    return box(0, 0, width, 1).difference(shapely.union_all(cuts))


@st.composite
def notched_plates(draw):
    alpha = draw(st.floats(0.04, 0.08))
    angles = draw(st.lists(st.floats(5, 45), min_size=1, max_size=3))
    return notched_plate(angles, alpha), alpha


@st.composite
def parts_with_gaps(draw):
    """Two or three boxes side by side, gaps of 0.1-0.9 alpha between them, and a slot
    of that width cut into the first."""
    alpha = draw(st.floats(0.04, 0.08))
    gaps = draw(st.lists(st.floats(0.1, 0.9), min_size=1, max_size=2))
    slot = draw(st.floats(0.1, 0.9)) * alpha
    parts, x = [], 0.0
    for gap in [0.0, *gaps]:
        x += gap * alpha
        parts.append(box(x, 0, x + 0.7, 0.8))
        x += 0.7
    parts[0] = parts[0].difference(box(0.2, 0.3, 0.8, 0.3 + slot))
    return shapely.MultiPolygon(parts), alpha


@st.composite
def plates_with_pin_holes(draw):
    """A plate with holes smaller than alpha: triangles, squares and round ones."""
    alpha = draw(st.floats(0.04, 0.08))
    holes = []
    for k in range(draw(st.integers(1, 4))):
        size = draw(st.floats(0.1, 0.9)) * alpha
        x, y = 0.2 + 0.2 * k, draw(st.floats(0.2, 0.6))
        shape = draw(st.sampled_from(["triangle", "square", "disc"]))
        if shape == "triangle":
            holes.append(Polygon([(x, y), (x + size, y), (x, y + size)]))
        elif shape == "square":
            holes.append(box(x, y, x + size, y + size))
        else:
            holes.append(Point(x, y).buffer(size / 2, quad_segs=4))
    return box(0, 0, 1, 0.8).difference(shapely.union_all(holes)), alpha


def assert_quality(mesh):
    """Theorem 1 for every triangle whose edges are all at least alpha (all of them where
    no visible samples are closer, i.e. away from the exceptions of docs/conforming.md),
    and everywhere the bound the circumradius gives: the angle opposite an edge of
    length l is at least arcsin(l / 2 alpha)."""
    quality = mesh.quality()
    alpha = mesh.alpha
    regular = (quality.edge_lengths >= alpha * (1 - 1e-9)).all(axis=1)
    assert quality.aspect_ratio[regular].max(initial=0) <= MAX_ASPECT * (1 + 1e-9)
    bound = np.degrees(np.arcsin(np.minimum(quality.edge_lengths / (2 * alpha), 1)))
    # an angle near 0 (a spike a rounding wide) is measured by acos to about 1e-6°
    bad = ~(quality.angles >= bound - 1e-6).all(axis=1)
    assert not bad.any(), (mesh.vertices[mesh.faces[bad]].tolist(), quality.angles[bad])
    return regular


def assert_is_the_region(mesh, geometry):
    """Nothing outside, nothing missing (to rounding), the region's Betti numbers."""
    union = outline(mesh)
    assert union.difference(geometry).area <= 1e-9 * geometry.area
    assert union.symmetric_difference(geometry).area <= 1e-9 * geometry.area
    assert mesh_betti(mesh) == mesh.region.betti


def outline(mesh):
    """The union of the triangles, by shapely."""
    return shapely.union_all(shapely.polygons(mesh.vertices[mesh.faces]))


def mesh_betti(mesh):
    union = outline(mesh)
    parts = shapely.get_parts(union)
    return len(parts), sum(len(p.interiors) for p in parts)


@settings(max_examples=12, deadline=None)
@given(case=st.one_of(notched_plates(), parts_with_gaps()), seed=st.integers(0, 2**32 - 1))
def test_mesh_is_the_region_with_theorem_1(case, seed):
    """Notches of 5°-45°, gaps and slots of 0.1-0.9 alpha: exact union, the region's
    Betti numbers, Theorem 1 wherever samples are alpha apart, and samples closer than
    alpha see each other only across a boundary piece shorter than alpha (a slot's end)."""
    geometry, alpha = case
    region = pds.Region.from_shapely(geometry)
    mesh = pds.mesh_region(region, alpha, seed=seed)
    assert mesh.conforming
    assert_is_the_region(mesh, geometry)
    regular = assert_quality(mesh)
    rings = pds.poisson_disc(region, alpha, seed=seed, conforming=True).rings
    short = {tuple(sorted(e)) for ring in rings for e in zip(ring.tolist(), np.roll(ring, -1).tolist())
             if np.linalg.norm(mesh.vertices[e[0]] - mesh.vertices[e[1]]) < alpha}
    close = visible_pairs_closer_than(mesh.vertices, chord_region(mesh.vertices, rings, region), alpha)
    assert {tuple(sorted(e)) for e in close.tolist()} <= short
    if not short:
        assert regular.all()


@settings(max_examples=6, deadline=None)
@given(plate=plates_with_pin_holes(), seed=st.integers(0, 2**32 - 1))
def test_holes_smaller_than_alpha_stay_holes(plate, seed):
    geometry, alpha = plate
    region = pds.Region.from_shapely(geometry)
    mesh = pds.mesh_region(region, alpha, seed=seed)
    union = outline(mesh)
    assert mesh_betti(mesh) == region.betti
    assert_quality(mesh)
    holes = [Polygon(ring) for ring in geometry.interiors]
    for hole in holes:
        if len(hole.exterior.coords) <= 5:      # polygonal holes (all corners sharp) are exact
            assert union.intersection(hole).area <= 1e-9 * hole.area
    # round ones are replaced by the polygon of their samples (at least three)
    assert union.difference(geometry).area <= sum(h.area for h in holes)


@settings(max_examples=10, deadline=None)
@given(region=regions, alpha=st.floats(0.04, 0.2), seed=st.integers(0, 2**32 - 1))
def test_nothing_outside_on_generated_regions(region, alpha, seed):
    """Stars (spikes, short edges) and unions of boxes and discs minus holes (curves):
    no triangle leaves the region bounded by the chords, and the angle bounds hold. A
    spike of width 0 (its two sides a rounding apart) is kept too."""
    mesh = pds.mesh_region(region, alpha, seed=seed)
    rings = pds.poisson_disc(region, alpha, seed=seed, conforming=True).rings
    domain = chord_region(mesh.vertices, rings, region)
    assert outline(mesh).difference(domain).area <= 1e-9 * region.area
    assert_quality(mesh)


@pytest.mark.parametrize("angle", [10, 29, 31, 59, 61, 90])
def test_wedges(angle):
    """Sharp corners (the apex, and the other two when the apex is wider than 60°): the
    apex is a sample, nothing leaves the wedge, the angle bounds hold."""
    alpha = 0.04
    geometry = wedge(angle)
    for seed in range(3):
        mesh = pds.mesh_region(pds.Region.from_shapely(geometry), alpha, seed=seed)
        assert (mesh.vertices == 0).all(axis=1).any()
        assert outline(mesh).difference(geometry).area <= 1e-9 * geometry.area
        assert_quality(mesh)


def test_short_edges_are_kept():
    """A step shorter than alpha: both its corners are samples and the mesh is still the
    region (the short-piece exception of docs/conforming.md, with its angle bound)."""
    alpha = 0.05
    step = 0.3 * alpha
    geometry = Polygon([(0, 0), (1, 0), (1, 0.5), (0.6, 0.5), (0.6, 0.5 + step), (0, 0.5 + step)])
    mesh = pds.mesh_region(pds.Region.from_shapely(geometry), alpha, seed=4)
    corners = shapely.points(shapely.get_coordinates(geometry.exterior)[:-1])
    assert (shapely.distance(corners, shapely.MultiPoint(mesh.vertices)) == 0).all()
    assert outline(mesh).symmetric_difference(geometry).area <= 1e-9 * geometry.area
    assert not assert_quality(mesh).all()        # the exception is there, and bounded


@pytest.mark.parametrize("angle", [5, 20, 45])
def test_sharp_spikes_keep_their_tip_and_stay_inside(angle):
    """A spike sharper than 60°: its tip is a sample, no triangle leaves the region, and
    the angle bound of the exception holds (the spike's thin end is material thinner
    than alpha, where the mesh may leave gaps)."""
    alpha = 0.05
    half = 0.6 * np.tan(np.radians(angle) / 2)
    geometry = box(0, 0, 1, 0.5).union(Polygon([(1, 0.25 - half), (1.6, 0.25), (1, 0.25 + half)]))
    mesh = pds.mesh_region(pds.Region.from_shapely(geometry), alpha, seed=angle)
    assert (np.abs(mesh.vertices - [1.6, 0.25]) == 0).all(axis=1).any()
    assert outline(mesh).difference(geometry).area <= 1e-9 * geometry.area
    assert_quality(mesh)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("angle, upper, lower", [(6, 6.4, 5.8), (6, 6.0, 6.0), (4, 8.0, 7.3)])
def test_spikes_thinner_than_alpha_are_meshed_along_their_length(angle, upper, lower, seed):
    """A spike of a few degrees, many alpha long, opening into a plate (as a plane cuts a
    thin wall at a slant: the teapot's spout). Its two sides are sampled in mirror pairs
    (a ladder), so consecutive samples on either side are joined across it; on main a
    part of one side spanned two of the other's and was not joined (15 of 80 meshes of
    these spikes at alpha 0.3 and 0.45 were not certified; 0 now)."""
    half = np.radians(angle) / 2
    u = upper * np.array([np.cos(half), np.sin(half)])
    lo = lower * np.array([np.cos(half), -np.sin(half)])
    spike = Polygon([(0, 0), lo, lo + (0.5, -3), (u[0] + 4, lo[1] - 3), (u[0] + 4, u[1] + 3),
                     u + (0.5, 3), u])
    certificate = pds.mesh_region(pds.Region.from_shapely(spike), 0.45, seed=seed).certificate()
    assert certificate.ok_with_exceptions and not certificate.unexplained, certificate


def test_pieces_too_short_to_split_get_a_guard():
    """A strip 1.9 alpha wide: its ends cannot be split into parts in [alpha, √3 alpha];
    a guard sample makes the end a mesh edge anyway, with angles in [45°, 90°]."""
    alpha = 0.05
    geometry = box(0, 0, 1.9 * alpha, 1)
    mesh = pds.mesh_region(pds.Region.from_shapely(geometry), alpha, seed=2)
    assert outline(mesh).symmetric_difference(geometry).area <= 1e-9 * geometry.area
    assert mesh.quality().aspect_ratio.max() <= MAX_ASPECT


@settings(max_examples=5, deadline=None)
@given(plate=notched_plates(), seed=st.integers(0, 2**32 - 1))
def test_consecutive_boundary_samples_are_mesh_edges(plate, seed):
    geometry, alpha = plate
    region = pds.Region.from_shapely(geometry)
    samples = pds.poisson_disc(region, alpha, seed=seed, conforming=True)
    faces = pds.solid_alpha_complex(samples.points, alpha, boundary=samples.rings)
    edges = {tuple(sorted(e)) for f in faces.tolist() for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    for ring in samples.rings:
        spacing = np.linalg.norm(samples.points[ring] - samples.points[np.roll(ring, -1)], axis=1)
        assert spacing.max() < 2 * alpha
        for a, b in zip(ring.tolist(), np.roll(ring, -1).tolist()):
            assert tuple(sorted((a, b))) in edges


def brute_force_constrained_faces(points, rings, region, alpha):
    """Every triangle of mutually visible samples, inside the chord region, with
    circumradius <= alpha and no sample inside its circumcircle that sees its inside
    (probed near each vertex)."""
    domain = chord_region(points, rings, region).buffer(1e-9 * alpha)
    shapely.prepare(domain)
    seen = {}

    def sees(a, b):
        """Sample a sees sample b (cached) or point b."""
        if not isinstance(b, int):
            return domain.covers(shapely.LineString([points[a], b]))
        key = (min(a, b), max(a, b))
        if key not in seen:
            seen[key] = domain.covers(shapely.LineString([points[a], points[b]]))
        return seen[key]

    faces = []
    n = len(points)
    for tri in itertools.combinations(range(n), 3):
        a, b, c = (points[v] for v in tri)
        cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        if cross == 0:
            continue
        radius = np.linalg.norm(b - a) * np.linalg.norm(c - a) * np.linalg.norm(c - b) / (2 * abs(cross))
        if radius > alpha:
            continue
        if not (sees(tri[0], tri[1]) and sees(tri[1], tri[2]) and sees(tri[0], tri[2])):
            continue
        if not domain.covers(Polygon([a, b, c])):
            continue
        d = 2 * cross
        bx, by, cx, cy = b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]
        centre = a + np.array([cy * (bx * bx + by * by) - by * (cx * cx + cy * cy),
                               bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)]) / d
        inside = np.flatnonzero(np.linalg.norm(points - centre, axis=1) < radius * (1 - 1e-9))
        centroid = (a + b + c) / 3
        probes = [v + 0.02 * (centroid - v) for v in (a, b, c)] + [centroid]
        if any(q not in tri and any(sees(int(q), p) for p in probes) for q in inside):
            continue
        faces.append(tri)
    return faces


@settings(max_examples=5, deadline=None)
@given(angle=st.floats(5, 45), seed=st.integers(0, 2**32 - 1))
def test_equals_a_brute_force_constrained_oracle(angle, seed):
    alpha = 0.12
    geometry = box(0, 0, 0.9, 0.6).difference(
        Polygon([(0.45, 0.2), (0.45 + 0.45 * np.tan(np.radians(angle) / 2), 0.7),
                 (0.45 - 0.45 * np.tan(np.radians(angle) / 2), 0.7)]))
    region = pds.Region.from_shapely(geometry)
    samples = pds.poisson_disc(region, alpha, seed=seed, conforming=True)
    assert len(samples) < 80
    faces = pds.solid_alpha_complex(samples.points, alpha, boundary=samples.rings)
    oracle = brute_force_constrained_faces(samples.points, samples.rings, region, alpha)
    assert face_set(faces) == face_set(oracle)


def test_same_seed_same_bits():
    region = pds.Region.from_shapely(notched_plate([10, 30], 0.05))
    a, b = (pds.mesh_region(region, 0.05, seed=11) for _ in range(2))
    assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)


def test_non_conforming_is_the_pure_solid_alpha_complex():
    region = pds.Region.from_shapely(notched_plate([10], 0.05))
    mesh = pds.mesh_region(region, 0.05, seed=1, conforming=False)
    samples = pds.poisson_disc(region, 0.05, seed=1)
    assert not mesh.conforming and samples.rings == ()
    assert np.array_equal(mesh.vertices, samples.points)
    assert np.array_equal(mesh.faces, pds.solid_alpha_complex(samples.points, 0.05))
    assert outline(mesh).difference(region.geometry).area > 0      # the notch is bridged


@pytest.mark.parametrize("boundary, message", [
    ([[0, 1]], "at least 3"),
    ([[0, 1, 7]], "distinct and in"),
    ([[0, 1, 1]], "distinct and in"),
])
def test_bad_boundary_rings_are_refused(boundary, message):
    points = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    with pytest.raises(ValueError, match=message):
        pds.solid_alpha_complex(points, 1.0, boundary=boundary)


@pytest.mark.parametrize("options", [{}, {"graded": True}])
def test_rings_touching_at_a_point_are_named(options):
    # a hole touching the outline at (0.00025, 0.00025), found by the fuzz suite: the
    # conforming sampler put a sample on both rings, and the complex blamed the caller for
    # duplicate points
    shell = [(0, 0.001), (0.001, 0.001), (0.001, 0), (0.00025, 0), (0.00025, 0.00025),
             (0, 0.00025)]
    hole = [(0.0005, 0.00025), (0.0005, 0.0005), (0.00025, 0.0005), (0.00025, 0.00025)]
    # (Region.from_shapely opens it: tests/test_tolerance.py; a Region built directly
    # still has it)
    region = pds.Region(MultiPolygon([Polygon(shell, [hole])]), np.eye(4))
    with pytest.raises(pds.RegionError, match=r"touches itself at \(0.00025, 0.00025\).*"
                                              r"conforming=False"):
        pds.mesh_region(region, 2.5e-4, **options)
    paper = pds.mesh_region(region, 2.5e-4, conforming=False)
    assert len(paper.faces) > 0


def s_plate(amplitude, wavelength, width=2.0):
    """A plate whose top edge is a sine wave (801 vertices, no sharp corner): an S-curve
    with an inflection every half wavelength."""
    x = np.linspace(0, width, 801)
    top = np.column_stack([x, 0.5 + amplitude * np.sin(2 * np.pi * x / wavelength)])[::-1]
    return Polygon(np.vstack([[[0, 0], [width, 0]], top]))


def assert_arcs_on_one_side_of_their_chords(mesh):
    """The boundary between consecutive boundary samples never crosses the line of their
    chord (by the region's vertices, independently of the certificate): the region beyond
    each chord is a convex sliver holding both chord ends, or nothing."""
    sampled = SampledBoundary(mesh.region, mesh.vertices, mesh.on_boundary, mesh.alpha)
    offset = sampled.arc_offset / mesh.alpha
    tol = 1e-9
    beyond = np.bincount(sampled.arc_chord, offset < -tol, minlength=len(sampled.a)) > 0
    inside = np.bincount(sampled.arc_chord, offset > tol, minlength=len(sampled.a)) > 0
    assert not (beyond & inside).any()


@pytest.mark.parametrize("amplitude, wavelength", [(0.03, 0.5), (0.05, 0.6), (0.1, 1.0)])
def test_s_curves_are_sampled_at_their_inflections(amplitude, wavelength):
    """Before inflections were samples, a chord across an S-curve's inflection left region
    beyond it that only one chord end sees, and every one of 20 seeds failed the
    certificate on these plates."""
    alpha = 0.05
    region = pds.Region.from_shapely(s_plate(amplitude, wavelength))
    for seed in range(4):
        mesh = pds.mesh_region(region, alpha, seed=seed)
        assert_arcs_on_one_side_of_their_chords(mesh)
        cert = mesh.certificate()
        assert cert.ok and cert.visibility, str(cert)
        # the inflections (the sine's zeros between the corners, 3 alpha clear of them)
        # are samples
        zeros = np.arange(1, int(2 / (wavelength / 2))) * wavelength / 2
        zeros = zeros[(zeros >= 3 * alpha) & (zeros <= 2 - 3 * alpha)]
        top = mesh.vertices[mesh.on_boundary & (mesh.vertices[:, 1] > 0.25)]
        assert (np.abs(top[:, 0][None, :] - zeros[:, None]).min(axis=1) < 2 / 800).all()


def test_a_kink_is_sampled_before_a_nearby_inflection():
    """A long segment between opposite turns (its inflection its middle) followed, 1.2
    alpha on, by a kink (a tessellation seam: one vertex turning against both
    neighbours). The two are closer than the rule allows, and the kink is kept: an
    unsampled kink hides region from both ends of its chord (a torus section's was 1.195
    alpha from every sample it saw), while the inflection may fall anywhere on its
    segment."""
    from pds_plugin.region import turning_angles
    from pds_plugin.sampling import _NOISY_INFLECTION_APART, _inflections

    alpha = 1.0
    # a right turn, a 1.5 alpha segment, then a left bend with a kink (a right turn) inside
    xy, heading = [(-3.0, -0.2), (-1.5, 0.0), (0.0, 0.0)], 0.0
    for k in range(24):                    # the kink 1.35 alpha on, 1.8 from the corner
        heading += np.radians(-10 if k == 6 else 1.4)
        xy.append((xy[-1][0] + 0.1, xy[-1][1] + 0.1 * np.tan(heading)))
    ring = np.array(xy + [(xy[-1][0], -3.0), (-3.0, -3.0)])
    turns = turning_angles(ring)
    closed = np.vstack([ring, ring[:1]])
    cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    sharp = np.abs(turns) >= np.radians(30)
    kink = cum[2 + 6]
    assert turns[8] < 0 < min(turns[7], turns[9]) and kink - (cum[1] + cum[2]) / 2 < 1.5
    kept = _inflections(cum, turns, sharp, alpha, _NOISY_INFLECTION_APART)
    assert np.isclose(kept, kink).any(), (kept, kink)


def test_a_side_too_short_for_its_corners_clearances_is_still_joined():
    """A small triangle (a held-out bracket section's component at "auto"): its sides of
    2.39 and 2.67 alpha beside a 32.5° corner are shorter than the clearances of their two
    corners, and were left whole: chords over 2 alpha, which no triangle of circumradius
    <= alpha has, left the tip's sample isolated and 60 % of the area unmeshed. They are
    halved now; the mesh is the whole triangle, every boundary sample joined. The halves'
    middles, alpha or more from the corner but closer to each other than alpha, are an
    exception the certificate explains (it called them unexplained, and FAILED)."""
    t = np.radians(32.5)
    triangle = Polygon([(0, 0), (2.39, 0), (2.67 * np.cos(t), 2.67 * np.sin(t))])
    for seed in range(3):
        mesh = pds.mesh_region(pds.Region.from_shapely(triangle), 1.0, seed=seed)
        cert = mesh.certificate()
        assert cert.conforming and cert.isolated_samples == 0, str(cert)
        assert outline(mesh).area == pytest.approx(triangle.area, rel=1e-12)
        assert cert.ok_with_exceptions and not cert.unexplained, str(cert)
        assert {e.cause for e in cert.exceptions} <= {"sharp corner"}


def test_a_tip_beside_a_short_side_keeps_its_triangle_at_any_seed():
    """A 34.1° tip whose short side (0.57 alpha) ends at a sharp reflex corner p (a
    held-out gear section at extent / 150): the first sample q on the long side must lie
    where |pq| is in [alpha, 2 alpha sin θ], so that the tip's triangle is kept. The split
    took that place as the least length of the first part and drew it up to √3 alpha:
    |pq| up to 1.24 alpha, the tip isolated on half the seeds. It is a break now."""
    ring = [(15.1609, 5.513), (12.2845, 4.5808), (10.9066, 5.7372), (9.4888, 6.8434),
            (9.5067, 7.0362), (-2.3795, -7.4145), (-2.38, -12), (15.16, -12)]
    region = pds.Region.from_shapely(Polygon(ring))
    for seed in range(10):
        mesh = pds.mesh_region(region, 0.3378754171168962, seed=seed)
        cert = mesh.certificate()
        assert cert.conforming and cert.isolated_samples == 0, (seed, str(cert))
        assert cert.ok_with_exceptions and not cert.unexplained, (seed, str(cert))


def test_kinks_of_a_noisy_boundary_are_sampled_one_alpha_apart():
    """A tessellated curve cut by a plane: a gentle bend with a kink (a right turn) every
    1.2 alpha. On a boundary known up to a tolerance every kink is sampled; at 1.5 alpha
    apart every other one was left out, and a sample just before it could not see the
    region just past it (a held-out torus section: 1.075 alpha from every sample it
    saw). No two are closer than alpha."""
    from pds_plugin.region import turning_angles
    from pds_plugin.sampling import _NOISY_INFLECTION_APART, _NOISY_KINK_APART, _inflections

    xy, heading = [(0.0, -2.0), (0.0, 0.0)], np.radians(5)
    for k in range(1, 80):
        heading += np.radians(-6 if k % 12 == 0 else 1.0)
        xy.append((xy[-1][0] + 0.1 * np.cos(heading), xy[-1][1] + 0.1 * np.sin(heading)))
    ring = np.array(xy + [(xy[-1][0], -2.0)])
    turns = turning_angles(ring)
    closed = np.vstack([ring, ring[:1]])
    cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    sharp = np.abs(turns) >= np.radians(30)
    kinks = cum[np.arange(12, 80, 12)]
    kinks = kinks[(kinks - cum[1] >= 1.5) & (cum[len(xy) - 1] - kinks >= 1.5)]
    kept = _inflections(cum, turns, sharp, 1.0, _NOISY_INFLECTION_APART, _NOISY_KINK_APART)
    assert len(kinks) >= 3 and np.isin(kinks, kept).all(), (kept, kinks)
    assert np.diff(kept).min() >= 1.0


@pytest.mark.parametrize("seed", [0, 2])
def test_the_mil_drawing_is_covered_at_the_benchmark_alpha(seed):
    """The benchmark's MIL.svg at its alpha: coverage failed at 1.10 and 1.25 alpha with
    seeds 0 and 2 beyond chords across inflections of its outline."""
    shared_file("MIL.svg")
    (case,), _ = _regions.cases([], 50_000, keys=("mil-svg",))
    mesh = pds.mesh_region(case.region, case.alpha, seed=seed)
    assert_arcs_on_one_side_of_their_chords(mesh)
    cert = mesh.certificate()
    assert cert.ok and cert.visibility and cert.coverage_gap <= 1, str(cert)



@pytest.mark.parametrize("tip", [1.9, 2.5])
def test_loop_areas_are_the_overlay_or_refused(tip):
    """A house (roof peak skipped by the samples: a sliver of area 2 beyond the chord
    y = 2) with a hole whose tip is skipped too (a bulge into Q, on the chord y = 1.4).
    With the tip below y = 2 the loops are apart and their areas are Q's area outside the
    region and the region's outside Q; with the tip above it, the tip is cut out of both
    (the loops overlap) and no answer is given."""
    house = Polygon([(0, 0), (4, 0), (4, 2), (2, 3), (0, 2)],
                    [[(1.5, 1), (1.5, 1.4), (2, tip), (2.5, 1.4), (2.5, 1)]])
    region = pds.Region.from_shapely(house)
    skipped = np.isin(region.segments[:, 0, 1], [3.0, tip])
    samples = region.segments[~skipped, 0]
    sampled = SampledBoundary(region, samples, np.ones(len(samples), bool), 0.5)
    Q = sampled.polygon()
    outside, missing = Q.difference(region.geometry).area, region.geometry.difference(Q).area
    bulge = (tip - 1.4) / 2
    if tip < 2:
        assert np.allclose((outside, missing), (bulge, 2.0), rtol=1e-12, atol=0)
        assert np.allclose(sampled.loop_areas(), (outside, missing), rtol=1e-12, atol=0)
    else:
        assert outside < bulge - 0.1 and missing < 2.0 - 0.1
        assert sampled.loop_areas() is None


def test_a_sliver_bending_a_hair_the_other_way_is_bounded_along_its_arc():
    """A piece beyond a chord that no chord end sees whole (its arc bends a hair the
    other way just past the end, as a flattened B-spline of a held-out STEP vase did):
    a point of it lies straight across from an arc point p, and p a path along the arc
    from a chord end, so it is within |h| + min(s, S - s) of a sample. The vase's point
    0.04 from its chord end was given the far end's 4.6 (coverage 1.09 r, FAILED)."""
    from pds_plugin.analysis.conformity import _along_the_arc, star_shaped_from

    a, b = np.array([0.0, 0.0]), np.array([4.0, 0.0])
    x = np.linspace(0, 4, 801)
    dents = [0.003 * np.exp(-((x - c) / 0.02) ** 2) for c in (0.1, 3.9)]  # steep flanks
    y = -0.02 * np.sin(np.pi * x / 4) - dents[0] - dents[1]
    arc = np.column_stack([x, y])
    assert not star_shaped_from(arc, a, 1e-12) and not star_shaped_from(arc, b, 1e-12)
    along = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(arc, axis=0).T))])
    distance, place = _along_the_arc(arc, along, along[-1], a, b, lambda d, _: d)
    # the largest is at the middle: along the arc, half its length and the height there,
    # or along the chord to its middle and across; the least of both reached at once
    assert distance == pytest.approx((0.02 + 2.0 + along[-1] / 2) / 2, rel=1e-3)
    assert distance < along[-1] / 2 + 0.02 and distance >= np.hypot(2.0, 0.02)
    assert place == pytest.approx([2.0, -0.02], abs=0.02)
    near_a = np.flatnonzero(x <= 0.04)                 # the point 0.04 from a: about 0.04
    bounds = [-y[i] + along[i] for i in near_a]
    assert max(bounds) < 0.05
    # an arc that is no graph over the chord (doubling back) gets no such bound
    back = arc.copy()
    back[400:410, 0] = back[400:410, 0][::-1]
    assert _along_the_arc(back, along, along[-1], a, b, lambda d, _: d) is None


@pytest.mark.parametrize("seed", range(40))
def test_the_bound_along_arc_and_chord_is_never_below_the_distance_to_an_end(seed):
    """The bound of a piece beyond a chord along its arc and its chord is a path length
    in the region, so never less than the straight distance from a point of the piece
    to the nearer chord end. Random arcs with kinks both ways (graphs over the chord),
    4,000 random points of each piece."""
    from pds_plugin.analysis.conformity import _along_the_arc

    rng = np.random.default_rng(seed)
    a, b = np.array([0.0, 0.0]), np.array([rng.uniform(0.5, 3.0), 0.0])
    x = np.sort(np.concatenate([[0.0, b[0]], rng.uniform(0, b[0], rng.integers(1, 6))]))
    y = -np.abs(rng.normal(0, 0.05 * b[0], len(x)))
    y[[0, -1]] = 0.0
    arc = np.column_stack([x, y])
    along = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(arc, axis=0).T))])
    distance, _ = _along_the_arc(arc, along, along[-1], a, b, lambda d, _: np.asarray(d))
    t = rng.uniform(0, 1, (4000, 2))         # points between the chord's line and the arc
    px = t[:, 0] * b[0]
    inside = np.column_stack([px, t[:, 1] * np.interp(px, x, y)])
    straight = np.minimum(np.hypot(*(inside - a).T), np.hypot(*(inside - b).T))
    assert distance >= straight.max()


def test_a_wedge_whose_arc_bends_at_a_hidden_vertex_is_certified():
    """A graded section of an OpenCASCADE vase export (tests/data/vase_wedge_section.json,
    corpus seed 7324): a thin wedge whose last chord skips a 190° and a 164° arc vertex,
    the second not seen from the chord's near end. Along the arc alone its piece was
    bounded at 1.036 r (FAILED); along the chord too, 0.997 r."""
    data = json.loads((Path(__file__).parent / "data" / "vase_wedge_section.json").read_text())
    region = pds.Region(MultiPolygon([Polygon(shell, holes) for shell, holes in data["polygons"]]),
                        np.eye(4), tolerance=data["tolerance"])
    cert = pds.mesh_region(region, "auto", seed=0, graded=True, grading=0.2).certificate()
    assert cert.ok_with_exceptions and cert.coverage_gap <= 1 + 1e-9, str(cert)


def test_a_spike_folded_onto_its_own_vertex_gives_no_numpy_error():
    """Found by the fuzz test (a star scaled by 1e-3 and moved 1e5 away): the ring runs
    out to a zero-width spike and back through the vertex before it. The sampler's
    search for the reflex vertex ending a hidden run indexed the ring with an empty
    float array (IndexError). Such a ring is meshed or refused with an error that names
    the fold, not duplicates the user would have given."""
    from regions import folded_star

    region = pds.Region.from_shapely(folded_star())
    try:
        mesh = pds.mesh_region(region, 0.00031156577880263016, seed=0)
    except pds.PdsError as error:                  # the two sides' samples coincide
        assert "boundary runs back onto itself" in str(error)
    else:
        assert mesh.certificate().ok_with_exceptions
