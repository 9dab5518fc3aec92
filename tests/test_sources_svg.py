"""load_svg against hand-written SVGs whose areas are known in closed form."""

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely

from pds_plugin import load_svg
from pds_plugin.errors import RegionError, SourceError
from pds_plugin.sources.polygons import outline_geometry

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"   # ../shared/data


def write(tmp_path, body, attributes='viewBox="0 0 100 100"', name="drawing.svg"):
    path = tmp_path / name
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" '
                    f'xmlns:xlink="http://www.w3.org/1999/xlink" {attributes}>{body}</svg>')
    return path


def circle_path(cx, cy, r, clockwise=False):
    """A circle as two SVG elliptical arcs (a closed subpath)."""
    sweep = 0 if clockwise else 1
    return (f"M {cx + r} {cy} A {r} {r} 0 1 {sweep} {cx - r} {cy} "
            f"A {r} {r} 0 1 {sweep} {cx + r} {cy} Z")


def flattening_bound(perimeter, tolerance):
    """Chords within ``tolerance`` of a convex curve lose at most perimeter x tolerance."""
    return perimeter * tolerance


# --- filled shapes: areas in closed form ---

def test_ellipse_area_is_pi_a_b_within_the_chordal_tolerance(tmp_path):
    a, b, tolerance = 30.0, 12.0, 0.01
    region = load_svg(write(tmp_path, f'<ellipse cx="50" cy="50" rx="{a}" ry="{b}"/>'),
                      tolerance=tolerance)
    exact = math.pi * a * b
    assert 0 <= exact - region.area <= flattening_bound(2 * math.pi * a, tolerance)
    assert region.betti == (1, 0)


def test_circle_vertices_lie_on_the_circle_and_chords_within_tolerance(tmp_path):
    r, tolerance = 40.0, 0.05
    region = load_svg(write(tmp_path, f'<circle cx="50" cy="50" r="{r}"/>'), tolerance=tolerance)
    ring = region.rings[0]
    radius = np.linalg.norm(ring - [50, 50], axis=1)
    assert np.allclose(radius, r, atol=1e-9)
    sagitta = r - np.linalg.norm((ring + np.roll(ring, -1, axis=0)) / 2 - [50, 50], axis=1)
    assert sagitta.max() <= tolerance                 # absolute chordal tolerance honoured
    assert sagitta.max() >= tolerance / 4             # and not needlessly fine


def test_default_tolerance_is_1e4_of_the_drawing_diagonal(tmp_path):
    r = 100.0
    path = write(tmp_path, f'<circle cx="0" cy="0" r="{r}"/>', 'viewBox="-100 -100 200 200"')
    region = load_svg(path)
    tolerance = 1e-4 * math.hypot(2 * r, 2 * r)
    ring = region.rings[0]
    sagitta = r - np.linalg.norm((ring + np.roll(ring, -1, axis=0)) / 2, axis=1)
    assert tolerance / 4 <= sagitta.max() <= tolerance


def test_evenodd_ring_from_group_style_and_nonzero_same_direction(tmp_path):
    big, small = 40.0, 15.0
    d = circle_path(50, 50, big) + " " + circle_path(50, 50, small)  # same direction
    evenodd = load_svg(write(tmp_path, f'<g style="fill-rule:evenodd"><path d="{d}"/></g>'),
                       tolerance=1e-3)
    nonzero = load_svg(write(tmp_path, f'<path d="{d}"/>', name="nonzero.svg"), tolerance=1e-3)
    ring = math.pi * (big**2 - small**2)
    assert evenodd.betti == (1, 1)
    assert abs(evenodd.area - ring) <= flattening_bound(2 * math.pi * (big + small), 1e-3)
    assert nonzero.betti == (1, 0)
    assert abs(nonzero.area - math.pi * big**2) <= flattening_bound(2 * math.pi * big, 1e-3)


def test_nonzero_with_opposite_directions_makes_a_hole(tmp_path):
    d = circle_path(50, 50, 40) + " " + circle_path(50, 50, 15, clockwise=True)
    region = load_svg(write(tmp_path, f'<path fill-rule="nonzero" d="{d}"/>'), tolerance=1e-3)
    assert region.betti == (1, 1)


def pentagram(cx, cy, radius):
    angles = np.pi / 2 + 2 * np.pi * np.arange(5) / 5
    tips = np.column_stack([cx + radius * np.cos(angles), cy - radius * np.sin(angles)])
    order = tips[[0, 2, 4, 1, 3]].tolist()
    return "M " + " L ".join(f"{x!r} {y!r}" for x, y in order) + " Z"


def test_pentagram_under_both_fill_rules(tmp_path):
    R = 20.0
    inner = R * math.cos(2 * math.pi / 5) / math.cos(math.pi / 5)   # radius of the inner pentagon
    star = 5 * R * inner * math.sin(math.pi / 5)                     # 10 triangles (O, tip, notch)
    pentagon = 2.5 * inner**2 * math.sin(2 * math.pi / 5)
    d = pentagram(50, 50, R)
    nonzero = load_svg(write(tmp_path, f'<path d="{d}"/>'))
    evenodd = load_svg(write(tmp_path, f'<g fill-rule="evenodd"><path d="{d}"/></g>',
                             name="eo.svg"))
    assert nonzero.area == pytest.approx(star, rel=1e-12)
    assert evenodd.source.area == pytest.approx(star - pentagon, rel=1e-12)
    assert nonzero.betti == (1, 0)
    assert evenodd.betti == (5, 0)   # five points meeting at the notches, moved apart
    assert 0 < evenodd.source_deviation <= evenodd.tolerance <= 1e-7 * 2 * R


def test_rounded_rect_area(tmp_path):
    w, h, r, tolerance = 60.0, 30.0, 8.0, 1e-3
    region = load_svg(write(tmp_path, f'<rect x="10" y="10" width="{w}" height="{h}" rx="{r}"/>'),
                      tolerance=tolerance)
    exact = w * h - (4 - math.pi) * r**2
    assert 0 <= exact - region.area <= flattening_bound(2 * math.pi * r, tolerance)


def test_nested_transforms_scale_a_circle_into_an_ellipse(tmp_path):
    r, tolerance = 10.0, 1e-3
    body = (f'<g transform="translate(50 50)"><g transform="rotate(30)">'
            f'<g transform="scale(2 1)"><circle cx="0" cy="0" r="{r}"/></g></g></g>')
    region = load_svg(write(tmp_path, body), tolerance=tolerance)
    assert 0 <= 2 * math.pi * r**2 - region.area <= flattening_bound(4 * math.pi * r, tolerance)
    # the centre maps to (50, 100 - 50) and the long axis lies at -30° after the y flip
    centroid = region.geometry.centroid
    assert (centroid.x, centroid.y) == pytest.approx((50, 50), abs=1e-9)
    far = region.rings[0][np.argmax(np.linalg.norm(region.rings[0] - [50, 50], axis=1))] - [50, 50]
    assert math.degrees(math.atan2(far[1], far[0])) % 180 == pytest.approx(150, abs=0.5)


@pytest.mark.parametrize("transform", ["skewX(30)", "matrix(1 0.3 0.5 2 0 0)", "scale(-1 1)",
                                       "matrix(0.5 -1 -1.5 0.2 0 0)"])
def test_affine_images_of_arcs_stay_exact(tmp_path, transform):
    """Skews and reflections turn a circle's radii into non-perpendicular conjugate radii."""
    body = (f'<g transform="translate(50 50) {transform}">'
            f'<ellipse cx="3" cy="-2" rx="7" ry="3"/>'
            f'<path d="M -10 12 A 4 4 0 0 0 -2 12 Z"/></g>')   # half disc below its chord
    region = load_svg(write(tmp_path, body), tolerance=1e-4)
    a, b, c, d, e, f = [float(v) for v in re.findall(r"[-\d.]+", {
        "skewX(30)": f"1 0 {math.tan(math.radians(30))} 1 0 0", "scale(-1 1)": "-1 0 0 1 0 0"}.get(
        transform, transform))]
    matrix = np.array([[a, c], [b, d]])
    exact = abs(np.linalg.det(matrix)) * math.pi * (21 + 8)
    perimeter = np.linalg.norm(matrix, 2) * (2 * math.pi * 7 + math.pi * 4 + 8)
    assert 0 <= exact - region.area <= flattening_bound(perimeter, 1e-4)
    # map the output back into the shapes' own frame: every vertex is on an original curve
    back = np.concatenate([np.column_stack([r[:, 0] - 50, 50 - r[:, 1]]) for r in region.rings])
    back = back @ np.linalg.inv(matrix).T
    on_ellipse = np.abs(((back[:, 0] - 3) / 7) ** 2 + ((back[:, 1] + 2) / 3) ** 2 - 1) < 1e-9
    on_disc = np.abs(np.hypot(back[:, 0] + 6, back[:, 1] - 12) - 4) < 1e-9
    on_chord = np.abs(back[:, 1] - 12) < 1e-9
    assert (on_ellipse | on_disc | on_chord).all()
    assert (back[on_disc & ~on_chord, 1] > 12).all()   # the half disc lies below its chord


@pytest.mark.parametrize("transform", ["skewX(30)", "matrix(1 0.3 0.5 2 0 0)", "scale(-1 1)",
                                       "matrix(0.5 -1 -1.5 0.2 0 0)", "rotate(17)"])
@pytest.mark.parametrize("flags", ["0 0", "0 1", "1 0", "1 1"])
def test_the_default_tolerance_comes_from_the_arcs_exact_extent(tmp_path, transform, flags):
    """An open arc's own points bound the drawing: the default tolerance is 1e-4 of the
    diagonal of their box, under skews and reflections too (svgelements' arc box assumes
    perpendicular radii)."""
    import svgelements

    from pds_plugin.sources import svg

    document = svgelements.SVG.parse(write(tmp_path, f'<path transform="{transform}" '
                                           f'd="M 10 0 A 10 6 30 {flags} -3 8" fill="none"/>'))
    path = svg._absolute(next(e for e in document.elements() if isinstance(e, svgelements.Path)))
    arc = next(segment for segment in path if isinstance(segment, svgelements.Arc))
    center, radii, start, sweep = svg._arc_frame(arc)
    dense = center + np.column_stack([np.cos(t := start + sweep * np.linspace(0, 1, 200_001)),
                                      np.sin(t)]) @ radii.T
    extremes = svg._arc_extremes(arc)
    assert np.ptp(extremes, axis=0) == pytest.approx(np.ptp(dense, axis=0), rel=1e-9)
    assert np.allclose(extremes.min(axis=0), dense.min(axis=0), atol=1e-9)
    assert svg._tolerance(None, [path], np.hstack([np.eye(2), np.zeros((2, 1))])) == \
        pytest.approx(1e-4 * np.linalg.norm(np.ptp(dense, axis=0)), rel=1e-9)


def bezier_area(control):
    """Exact area between a Bézier curve and its chord: Green's theorem on its polynomial."""
    n = len(control) - 1
    t = np.polynomial.Polynomial([0, 1])
    basis = [math.comb(n, k) * t**k * (1 - t)**(n - k) for k in range(n + 1)]
    x = sum(b * c for b, c in zip(basis, control[:, 0]))
    y = sum(b * c for b, c in zip(basis, control[:, 1]))
    curve = (x * y.deriv() - y * x.deriv()).integ()
    chord = control[-1, 0] * control[0, 1] - control[-1, 1] * control[0, 0]  # the way back
    return abs(curve(1) - curve(0) + chord) / 2


@pytest.mark.parametrize("command, control", [
    ("C", [[10, 20], [10, 80], [90, 90], [90, 20]]),
    ("Q", [[10, 20], [50, 95], [90, 20]]),
])
def test_bezier_area(tmp_path, command, control):
    control = np.array(control, float)
    tolerance = 1e-3
    d = f"M {control[0, 0]} {control[0, 1]} {command} " + " ".join(
        f"{x} {y}" for x, y in control[1:]) + " Z"
    region = load_svg(write(tmp_path, f'<path d="{d}"/>'), tolerance=tolerance)
    perimeter = np.linalg.norm(np.diff(control, axis=0), axis=1).sum() + 80
    assert 0 <= bezier_area(control) - region.area <= flattening_bound(perimeter, tolerance)


def test_elliptical_arc_area(tmp_path):
    tolerance = 1e-3
    region = load_svg(write(tmp_path, '<path d="M 60 80 A 20 10 0 0 1 100 80 L 60 80 Z"/>'),
                      tolerance=tolerance)
    assert 0 <= math.pi * 20 * 10 / 2 - region.area <= flattening_bound(100, tolerance)


def test_units_in_mm_and_the_y_flip(tmp_path):
    attributes = 'width="200mm" height="100mm" viewBox="0 0 100 50"'
    path = write(tmp_path, '<polygon points="10,5 30,5 10,15"/>', attributes)
    user, mm = load_svg(path), load_svg(path, units="mm")
    # the right angle is at the top left of the drawing: after the flip it is still there
    assert sorted(map(tuple, user.rings[0].round(9).tolist())) == [(10, 35), (10, 45), (30, 45)]
    assert sorted(map(tuple, mm.rings[0].round(9).tolist())) == [(20, 70), (20, 90), (60, 90)]
    assert mm.area == pytest.approx(4 * user.area, rel=1e-12)


def test_tolerance_is_in_output_units(tmp_path):
    path = write(tmp_path, '<circle cx="5" cy="5" r="1"/>',
                 'width="100mm" height="100mm" viewBox="0 0 10 10"')
    region = load_svg(path, tolerance=0.01, units="mm")        # a circle of radius 10 mm
    centre = np.array([50.0, 50.0])
    ring = region.rings[0]
    sagitta = 10 - np.linalg.norm((ring + np.roll(ring, -1, axis=0)) / 2 - centre, axis=1)
    assert 0.01 / 4 <= sagitta.max() <= 0.01


def test_defs_and_hidden_elements_are_skipped_use_is_drawn(tmp_path):
    body = ('<defs><rect id="square" width="10" height="10"/></defs>'
            '<use xlink:href="#square" x="60" y="60"/>'
            '<rect x="0" y="0" width="20" height="20"/>'
            '<rect x="30" y="0" width="20" height="20" display="none"/>'
            '<g style="visibility:hidden"><rect x="0" y="30" width="20" height="20"/>'
            '<rect x="30" y="30" width="5" height="5" visibility="visible"/></g>')
    region = load_svg(write(tmp_path, body))
    assert region.area == pytest.approx(100 + 400 + 25, rel=1e-12)
    assert region.betti == (3, 0)


def test_overlapping_filled_shapes_are_united(tmp_path):
    body = ('<rect x="0" y="0" width="20" height="20"/>'
            '<rect x="10" y="10" width="20" height="20" fill="red"/>')
    region = load_svg(write(tmp_path, body))
    assert region.area == pytest.approx(700, rel=1e-12)
    assert region.betti == (1, 0)


# --- outline drawings ---

def plate_segments(rng):
    """Loose segments of a 100 x 60 plate with a 64-gon hole, a square hole holding an
    island, and a hole in the island; shuffled, reversed at random, ends jittered."""
    angles = 2 * np.pi * np.arange(64) / 64
    circle = np.column_stack([25 + 10 * np.cos(angles), 30 + 10 * np.sin(angles)])
    squares = [np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)
               for x0, y0, x1, y1 in [(0, 0, 100, 60), (45, 5, 95, 55), (55, 15, 85, 45),
                                      (65, 25, 75, 35)]]
    loops = [circle, *squares]
    segments = np.concatenate([np.stack([r, np.roll(r, -1, axis=0)], axis=1) for r in loops])
    segments = np.concatenate([segments, segments[:3]])               # a few drawn twice
    segments = segments[rng.permutation(len(segments))]
    flip = rng.random(len(segments)) < 0.5
    segments[flip] = segments[flip][:, ::-1]
    segments = segments + rng.uniform(-1e-6, 1e-6, segments.shape)    # ends do not quite meet
    polygon64 = 32 * 10**2 * math.sin(2 * math.pi / 64)
    area = 100 * 60 - polygon64 - 50 * 50 + 30 * 30 - 10 * 10
    return segments, area


def outline_body(segments):
    return "".join(f'<line x1="{a[0]!r}" y1="{a[1]!r}" x2="{b[0]!r}" y2="{b[1]!r}" '
                   f'stroke="black" fill="none"/>' if i % 2 else
                   f'<path d="M {a[0]!r} {a[1]!r} L {b[0]!r} {b[1]!r}" stroke="black" fill="none"/>'
                   for i, (a, b) in enumerate(segments.tolist()))


def test_outline_from_loose_shuffled_segments(tmp_path):
    segments, area = plate_segments(np.random.default_rng(7))
    region = load_svg(write(tmp_path, outline_body(segments), 'viewBox="0 0 100 60"'))
    assert region.betti == (2, 3)       # plate + island; circle, square hole, island's hole
    assert region.area == pytest.approx(area, abs=1e-3)


def test_outline_arcs_join_into_a_ring_and_mode_can_be_forced(tmp_path):
    halves = [f"M {50 + r} 50 A {r} {r} 0 0 1 {50 - r} 50" for r in (40, 20)] + \
             [f"M {50 - r} 50 A {r} {r} 0 0 1 {50 + r} 50" for r in (40, 20)]
    body = "".join(f'<path d="{d}" fill="none" stroke="black"/>' for d in halves)
    region = load_svg(write(tmp_path, body), tolerance=1e-3)
    assert region.betti == (1, 1)
    assert abs(region.area - math.pi * (40**2 - 20**2)) <= flattening_bound(2 * math.pi * 60, 1e-3)
    ring = f"{circle_path(50, 50, 40)} {circle_path(50, 50, 20)}"
    filled = write(tmp_path, f'<path fill-rule="evenodd" d="{ring}"/>'
                   f'<circle cx="50" cy="50" r="10" fill="none" stroke="black"/>', name="both.svg")
    assert load_svg(filled, tolerance=1e-3).betti == (1, 1)                   # auto: fill
    assert load_svg(filled, tolerance=1e-3, mode="outline").betti == (2, 1)   # island r=10 too


def test_outline_reports_loops_that_do_not_close(tmp_path):
    segments, _ = plate_segments(np.random.default_rng(1))
    stray = '<path d="M 20 50 L 30 52 L 40 50" stroke="black" fill="none"/>'
    path = write(tmp_path, outline_body(segments) + stray, 'viewBox="0 0 100 60"')
    with pytest.warns(UserWarning, match=r"2 stroke end\(s\).*\(20, 10\).*\(40, 10\)"):
        region = load_svg(path)
    assert region.betti == (2, 3)


def test_outline_with_no_closed_loop_is_an_error_with_coordinates(tmp_path):
    path = write(tmp_path, '<path d="M 10 10 L 90 10 L 90 90" stroke="black" fill="none"/>')
    with pytest.raises(ValueError, match=r"no closed loop.*\(10, 90\).*\(90, 10\)"):
        load_svg(path)



def polygon_points(cx, cy, radius, sides):
    angles = 2 * np.pi * np.arange(sides) / sides
    return " ".join(f"{cx + radius * math.cos(t)!r},{cy + radius * math.sin(t)!r}" for t in angles)


def regular_polygon_area(radius, sides):
    return sides / 2 * radius**2 * math.sin(2 * math.pi / sides)


def test_outline_keeps_small_polygons_whose_sides_are_shorter_than_the_tolerance(tmp_path):
    """Issue 10.1: the 64-gons of radius 1 and 2 have sides under the default tolerance."""
    holes = [(100, 1), (200, 2), (500, 50)]
    body = '<rect x="0" y="0" width="1000" height="500" fill="none" stroke="black"/>' + "".join(
        f'<polygon points="{polygon_points(x, 250, r, 64)}" fill="none" stroke="black"/>'
        for x, r in holes)
    region = load_svg(write(tmp_path, body, 'viewBox="0 0 1000 500"'))
    assert region.betti == (1, 3)
    exact = 1000 * 500 - sum(regular_polygon_area(r, 64) for _, r in holes)
    assert region.area == pytest.approx(exact, rel=1e-12)


def test_outline_keeps_a_30000_gon_finer_than_the_tolerance(tmp_path):
    """Issue 10.1: the snapping merged the whole circle into a point (area 9604)."""
    body = ('<rect x="1" y="1" width="98" height="98" fill="none" stroke="black"/>'
            f'<polygon points="{polygon_points(50, 50, 40, 30000)}" fill="none" stroke="black"/>')
    region = load_svg(write(tmp_path, body))
    assert region.betti == (1, 1)
    assert region.area == pytest.approx(98 * 98 - regular_polygon_area(40, 30000), rel=1e-12)


def test_outline_joins_jittered_segments_of_a_curve_finer_than_the_tolerance():
    """Loose segments whose ends miss by 1e-7 still join, without merging the vertices."""
    sides, radius, tolerance = 2000, 3.0, 0.05          # sides of 0.0094 < tolerance
    angles = 2 * np.pi * np.arange(sides) / sides
    ring = np.column_stack([radius * np.cos(angles), radius * np.sin(angles)])
    segments = np.stack([ring, np.roll(ring, -1, axis=0)], axis=1)
    segments = segments + np.random.default_rng(3).uniform(-1e-7, 1e-7, segments.shape)
    geometry, open_ends = outline_geometry(list(segments), tolerance=tolerance)
    assert len(open_ends) == 0
    assert len(geometry.exterior.coords) == sides + 1
    assert geometry.area == pytest.approx(regular_polygon_area(radius, sides), abs=1e-5)


def test_outline_closes_a_loop_smaller_than_the_tolerance_without_collapsing_it():
    """A polyline whose end misses its start: closed, and its 12 vertices all kept."""
    angles = 2 * np.pi * np.arange(13) / 12
    loop = 0.01 * np.column_stack([np.cos(angles), np.sin(angles)])
    loop[-1] += 1e-9
    geometry, open_ends = outline_geometry([loop], tolerance=0.1)
    assert len(open_ends) == 0
    assert geometry.area == pytest.approx(regular_polygon_area(0.01, 12), rel=1e-6)


def test_outline_chain_with_a_rounding_error_step_stays_closed():
    """A corner arc computed with cos/sin starts 6e-16 from the line before it: GEOS
    dropped that step and cut the loop there (a false open end at (0, 5))."""
    angles = np.linspace(np.pi, 1.5 * np.pi, 9)
    arc = np.column_stack([5 + 5 * np.cos(angles), 5 + 5 * np.sin(angles)])  # (0, 5) to (5, 0)
    chain = np.vstack([[[5, 0], [20, 0], [20, 20], [0, 20], [0, 5]], arc])
    geometry, open_ends = outline_geometry([chain], tolerance=0.01)
    assert len(open_ends) == 0
    assert geometry.area == pytest.approx(shapely.Polygon(chain).area, rel=1e-12)


# --- errors ---

def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such SVG file"):
        load_svg(tmp_path / "absent.svg")


@pytest.mark.parametrize("content, message", [
    ("", "is empty"),
    ("this is not xml", "cannot read"),
    ("<svg xmlns='http://www.w3.org/2000/svg'><rect", "cannot read"),
    ("<html><body>hello</body></html>", "not an SVG"),
    ("<svg xmlns='http://www.w3.org/2000/svg'><text>hi</text></svg>", "no visible shapes"),
    ("<svg xmlns='http://www.w3.org/2000/svg'><defs><rect width='5' height='5'/></defs></svg>",
     "no visible shapes"),
])
def test_unreadable_or_empty_files(tmp_path, content, message):
    path = tmp_path / "bad.svg"
    path.write_text(content)
    with pytest.raises(ValueError, match=message):
        load_svg(path)


def test_fill_mode_without_filled_area(tmp_path):
    path = write(tmp_path, '<circle cx="50" cy="50" r="10" fill="none" stroke="black"/>')
    with pytest.raises(ValueError, match="enclose no area.*mode='outline'"):
        load_svg(path, mode="fill")
    assert load_svg(path).betti == (1, 0)   # auto falls back to the outline


@pytest.mark.parametrize("keyword, value", [("mode", "stroke"), ("units", "furlong"),
                                            ("tolerance", 0), ("tolerance", float("nan"))])
def test_bad_arguments(tmp_path, keyword, value):
    path = write(tmp_path, '<rect width="10" height="10"/>')
    with pytest.raises(ValueError, match=keyword):
        load_svg(path, **{keyword: value})


# --- real drawings (skipped when ../shared/data is absent) ---

def data_file(name):
    path = DATA / name
    if not path.is_file():
        pytest.skip(f"{path} is not available")
    return path


def test_mil_outline_drawing_is_one_part_with_eight_holes():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        region = load_svg(data_file("MIL.svg"))
    assert region.betti == (1, 8)
    # one slot of the drawing lacks a side: reported, not silently closed
    assert any("2 stroke end(s)" in str(w.message) for w in caught)


def test_polygon_svg_matches_the_shoelace_area_of_its_vertices():
    path = data_file("polygon.svg")
    d = re.search(r'\bd="([^"]+)"', path.read_text()).group(1)
    numbers = np.array(re.findall(r"-?(?:\d+\.?\d*|\.\d+)", d), float).reshape(-1, 2)
    vertices = np.cumsum(numbers, axis=0)          # "M x y l dx dy ..." : relative moves
    exact = shapely.Polygon(vertices).area
    region = load_svg(path)
    assert region.betti == (1, 0)
    assert region.area == pytest.approx(exact, rel=1e-9)


# --- the arrangement helpers behind the fill rules and the outline nesting ---

def test_winding_numbers_agree_with_point_in_polygon():
    from pds_plugin.sources.polygons import winding_numbers

    rng = np.random.default_rng(3)
    angles = np.sort(rng.uniform(0, 2 * np.pi, 40))
    star = np.column_stack([np.cos(angles), np.sin(angles)]) * rng.uniform(0.3, 1, (40, 1))
    polygon = shapely.Polygon(star)
    assert polygon.is_valid and shapely.is_ccw(polygon.exterior)
    points = np.vstack([rng.uniform(-1.1, 1.1, (4000, 2)), star, (star + np.roll(star, 1, 0)) / 2])
    segments = np.stack([star, np.roll(star, -1, axis=0)], axis=1)
    inside = shapely.contains_xy(polygon, points[:4000, 0], points[:4000, 1])
    assert np.array_equal(winding_numbers(points[:4000], segments), inside.astype(int))
    assert np.array_equal(winding_numbers(points[:4000], segments[:, ::-1]), -inside.astype(int))
    assert set(winding_numbers(points, segments).tolist()) <= {0, 1}   # vertices, edges: once


def test_example_runs_on_its_builtin_drawing(tmp_path):
    import importlib.util

    import trimesh

    path = Path(__file__).resolve().parents[1] / "examples" / "svg_drawing.py"
    spec = importlib.util.spec_from_file_location("svg_drawing_example", path)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    example.DATA = tmp_path / "absent"              # only the built-in drawing
    example.main(tmp_path)
    written = trimesh.load_mesh(tmp_path / "builtin_drawing.ply")
    assert len(written.faces) > 0
    assert written.bounds[:, :2].ravel().tolist() == pytest.approx([10, 10, 105, 70], abs=1.5)


def _svg(tmp_path, body, attributes='viewBox="0 0 10 10"'):
    path = tmp_path / "drawing.svg"
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" {attributes}>{body}</svg>')
    return path


def test_a_use_bomb_is_refused_before_it_is_built(tmp_path):
    """Eight levels of ten <use> each: 10^8 rects from 1 KB."""
    groups = "".join(f'<g id="g{i}">' + f'<use href="#g{i - 1}"/>' * 10 + "</g>"
                     for i in range(1, 9))
    bomb = _svg(tmp_path, f'<defs><g id="g0"><rect width="1" height="1"/></g>{groups}</defs>'
                          '<use href="#g8"/>')
    with pytest.raises(SourceError, match="max_elements"):
        load_svg(bomb)


def test_a_use_cycle_is_named(tmp_path):
    cycle = _svg(tmp_path, '<g id="a"><use href="#b"/></g><g id="b"><use href="#a"/></g>'
                           '<rect width="2" height="2"/>')
    with pytest.raises(SourceError, match="<use> cycle"):
        load_svg(cycle)


def test_size_and_segment_limits_name_their_keywords(tmp_path):
    steps = " ".join(f"L{i % 100} {i // 100}" for i in range(2000))
    path = _svg(tmp_path, f'<path d="M0 0 {steps} Z"/>')
    with pytest.raises(SourceError, match="max_segments"):
        load_svg(path, max_segments=1000)
    assert load_svg(path, max_segments=5000).area > 0
    with pytest.raises(SourceError, match="max_bytes"):
        load_svg(path, max_bytes=1000)


@pytest.mark.parametrize("body, attributes, words", [
    ('<rect width="10" height="10"/>', 'viewBox="0 0 0 0"', "viewBox"),
    ('<circle cx="5" cy="5" r="-5"/>', 'viewBox="0 0 10 10"', "negative size"),
    ('<rect width="-10" height="10"/>', 'viewBox="0 0 10 10"', "negative size"),
])
def test_degenerate_drawings_get_the_package_error(tmp_path, body, attributes, words):
    with pytest.raises(SourceError, match=words):
        load_svg(_svg(tmp_path, body, attributes))


@pytest.mark.parametrize("body", ['<path d="M0 0 Q1e300 5 10 0 L5 5Z"/>',
                                  '<path d="M0 0 L1e300 0 L1e300 1e300 Z"/>'])
def test_a_drawing_beyond_float64s_scale_is_refused_by_its_size(tmp_path, body):
    """A control point or a vertex at 1e300: refused by the drawing's size, as regions are
    (region.check_scale), not by its chords' count or a tolerance of inf."""
    with pytest.raises(RegionError, match=r"the drawing spans \S+ .* fix the drawing"):
        load_svg(_svg(tmp_path, body, 'viewBox="0 0 10 10"'))
