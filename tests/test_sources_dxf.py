"""load_dxf against drawings written with ezdxf whose areas are known in closed form, and
the public test drawings against an independent reading."""

import functools
import math
import warnings
from pathlib import Path

import ezdxf
import numpy as np
import pytest
import shapely

from pds_plugin import ArgumentError, RegionError, SourceError, load_drawing, load_dxf

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"   # ../shared/data


def save(doc, tmp_path, name="drawing.dxf", **options):
    path = tmp_path / name
    doc.saveas(path, **options)
    return path


def new(units=0):
    doc = ezdxf.new("R2010", units=units)
    return doc, doc.modelspace()


def square(msp, x0, y0, side, **attributes):
    msp.add_lwpolyline([(x0, y0), (x0 + side, y0), (x0 + side, y0 + side), (x0, y0 + side)],
                       close=True, dxfattribs=attributes)


def segment_area(chord, bulge):
    """Area between a chord and its arc of bulge ``bulge`` (tan of a quarter of the sweep)."""
    sweep = 4 * math.atan(abs(bulge))
    radius = chord / (2 * math.sin(sweep / 2))
    return radius**2 / 2 * (sweep - math.sin(sweep))


def assert_area(region, exact, perimeter, tolerance):
    """Chords within ``tolerance`` of their curves change the area by <= perimeter x tolerance."""
    assert abs(region.area - exact) <= perimeter * tolerance


# --- entities: closed-form areas and Betti numbers ---

def test_lines_and_a_circle_make_a_plate_with_a_hole(tmp_path):
    doc, msp = new()
    corners = [(0, 0), (30, 0), (30, 20), (0, 20)]
    for a, b in zip(corners, corners[1:] + corners[:1]):
        msp.add_line(b, a)                                 # loose lines, any direction
    msp.add_circle((10, 10), radius=4)
    region = load_dxf(save(doc, tmp_path), tolerance=1e-3)
    assert region.betti == (1, 1)
    assert_area(region, 600 - math.pi * 16, 2 * math.pi * 4, 1e-3)
    hole = region.rings[1]
    assert np.allclose(np.linalg.norm(hole - [10, 10], axis=1), 4, atol=1e-12)   # on the circle
    sagitta = 4 - np.linalg.norm((hole + np.roll(hole, -1, axis=0)) / 2 - [10, 10], axis=1)
    assert 1e-3 / 4 <= sagitta.max() <= 1e-3


@pytest.mark.parametrize("kind", ["LWPOLYLINE", "POLYLINE"])
def test_bulges_in_both_directions(tmp_path, kind):
    """A 10 x 4 rectangle (counter-clockwise): bottom bulging out, top bulging in."""
    doc, msp = new()
    points = [(0, 0, 0.5), (10, 0, 0), (10, 4, -0.25), (0, 4, 0)]
    if kind == "LWPOLYLINE":
        msp.add_lwpolyline(points, format="xyb", close=True)
    else:
        msp.add_polyline2d(points, format="xyb", close=True)
    region = load_dxf(save(doc, tmp_path), tolerance=1e-4)
    assert region.betti == (1, 0)
    exact = 40 + segment_area(10, 0.5) - segment_area(10, 0.25)
    assert_area(region, exact, 60, 1e-4)
    assert region.bounds == pytest.approx((0, -2.5, 10, 4), abs=1e-12)   # sagitta = b c / 2


def test_clockwise_bulges_and_an_arc_with_a_mirrored_coordinate_system(tmp_path):
    doc, msp = new()
    msp.add_lwpolyline([(0, 0, -1), (4, 0, -1)], format="xyb", close=True)   # a full disc
    # an ARC in the OCS of extrusion -Z: x is mirrored; centre (-20, 0) in world coordinates
    msp.add_arc((20, 0), radius=3, start_angle=-90, end_angle=90,
                dxfattribs={"extrusion": (0, 0, -1)})
    msp.add_line((-20, 3), (-20, -3))
    region = load_dxf(save(doc, tmp_path), tolerance=1e-4)
    assert region.betti == (2, 0)
    assert_area(region, math.pi * 4 + math.pi * 9 / 2, 2 * math.pi * 5, 1e-4)
    half_disc = max(shapely.get_parts(region.geometry), key=lambda part: part.bounds[2] < 0)
    assert half_disc.bounds == pytest.approx((-23, -3, -20, 3), abs=1e-4)   # opens to -x


def test_ellipse_arcs_rotated_and_mirrored(tmp_path):
    """Two half ellipses (a = 5, b = 2) closed by their major axes, one mirrored."""
    doc, msp = new()
    axis = 5 * np.array([math.cos(0.3), math.sin(0.3), 0])
    msp.add_ellipse((0, 0), major_axis=axis, ratio=0.4, start_param=0, end_param=math.pi)
    msp.add_line(axis, -axis)
    msp.add_ellipse((20, 0), major_axis=(5, 0, 0), ratio=0.4, start_param=0, end_param=math.pi,
                    dxfattribs={"extrusion": (0, 0, -1)})        # the lower half in WCS
    msp.add_line((15, 0), (25, 0))
    region = load_dxf(save(doc, tmp_path), tolerance=1e-4)
    assert region.betti == (2, 0)
    assert_area(region, math.pi * 5 * 2, 2 * math.pi * 5, 1e-4)
    lower = [part for part in shapely.get_parts(region.geometry) if part.bounds[0] > 10]
    assert lower[0].bounds == pytest.approx((15, -2, 25, 0), abs=1e-4)
    upper = [part for part in shapely.get_parts(region.geometry) if part.bounds[0] < 10][0]
    assert upper.centroid.y > 0 and upper.centroid.x < 0   # the side θ in (0, π) of the axis


@pytest.mark.parametrize("degree", [2, 3])
def test_spline_area_under_a_bezier_arch(tmp_path, degree):
    """Clamped splines with degree + 1 control points are Bézier curves: the area under
    (0,0) (0,h) (10,h) (10,0) is 6h, under (0,0) (5,2h) (10,0) it is 20h / 3."""
    h = 3.0
    control = [(0, 0), (0, h), (10, h), (10, 0)] if degree == 3 else [(0, 0), (5, 2 * h), (10, 0)]
    exact = 6 * h if degree == 3 else 20 * h / 3
    doc, msp = new()
    msp.add_open_spline(control, degree=degree)
    msp.add_line((0, 0), (10, 0))
    region = load_dxf(save(doc, tmp_path), tolerance=1e-4)
    assert region.betti == (1, 0)
    assert_area(region, exact, 30, 1e-4)


def test_spline_through_several_knot_spans_matches_its_exact_points(tmp_path):
    doc, msp = new()
    control = [(0, 0), (2, 5), (6, 7), (9, 3), (12, 6), (14, 0)]
    spline = msp.add_open_spline(control, degree=3)
    msp.add_line((14, 0), (0, 0))
    region = load_dxf(save(doc, tmp_path), tolerance=1e-5)
    curve = spline.construction_tool()                      # 3 knot spans: t in [0, 3]
    exact = [tuple(p)[:2] for p in curve.points(np.linspace(0, curve.max_t, 20000))]
    assert region.geometry.boundary.hausdorff_distance(
        shapely.LineString(exact + [(0, 0)])) <= 1e-5 + 1e-12


def test_nested_mirrored_rotated_scaled_blocks(tmp_path):
    """Block A: a 2 x 1 rectangle with a half-disc on its right end (an asymmetric part).
    Block B inserts A at (1, 0) scaled 0.5; model space inserts B mirrored in x, scaled 2,
    rotated 90°: the part keeps its area and lands where the composed transform puts it."""
    doc, msp = new()
    a = doc.blocks.new("A")
    a.add_lwpolyline([(0, 0), (2, 0, 1), (2, 1), (0, 1)], format="xyb", close=True)
    b = doc.blocks.new("B")
    b.add_blockref("A", (1, 0), dxfattribs={"xscale": 0.5, "yscale": 0.5})
    msp.add_blockref("B", (10, 10), dxfattribs={"xscale": -2, "yscale": 2, "rotation": 90})
    region = load_dxf(save(doc, tmp_path), tolerance=1e-5)
    assert region.betti == (1, 0)
    assert_area(region, 2 + math.pi / 8, 6, 1e-5)

    def placed(x, y):        # A -> B: (1 + x/2, y/2); B -> model: mirror x, scale 2, turn 90°
        u, v = -2 * (1 + x / 2), 2 * (y / 2)
        return 10 - v, 10 + u
    tip = placed(2.5, 0.5)                               # the half-disc's far point in A
    assert region.geometry.boundary.distance(shapely.Point(tip)) <= 1e-5
    assert region.bounds == pytest.approx((9, tip[1], 10, 8), abs=1e-5)


def test_non_uniform_block_scale_turns_a_circle_into_an_ellipse_and_minsert_repeats(tmp_path):
    doc, msp = new()
    doc.blocks.new("DOT").add_circle((0, 0), radius=1)
    msp.add_blockref("DOT", (0, 0), dxfattribs={"xscale": 3, "yscale": 1})
    grid = msp.add_blockref("DOT", (20, 0))
    grid.grid(size=(2, 3), spacing=(5, 4))                   # MINSERT: 2 rows x 3 columns
    region = load_dxf(save(doc, tmp_path), tolerance=1e-5)
    assert region.betti == (7, 0)
    assert_area(region, 3 * math.pi + 6 * math.pi, 7 * 2 * math.pi * 3, 1e-5)


@pytest.mark.parametrize("code, units, factor", [(1, "mm", 25.4), (1, "ft", 1 / 12),
                                                 (4, "cm", 0.1), (6, "in", 1000 / 25.4),
                                                 (5, None, 1.0)])
def test_units_from_insunits(tmp_path, code, units, factor):
    doc, msp = new(units=code)
    square(msp, 0, 0, 2)
    region = load_dxf(save(doc, tmp_path), units=units)
    assert region.area == pytest.approx(4 * factor**2, rel=1e-12)


def test_unitless_drawing_cannot_be_converted(tmp_path):
    doc, msp = new(units=0)
    square(msp, 0, 0, 2)
    path = save(doc, tmp_path)
    with pytest.raises(ArgumentError, match=r"does not say its units.*units=None"):
        load_dxf(path, units="mm")
    assert load_dxf(path).area == 4.0


def test_hatch_boundaries_fill_even_odd_and_auto_prefers_them(tmp_path):
    """A hatch: a 20 x 20 square, a circular hole (arc edge), an elliptical island in it."""
    doc, msp = new()
    hatch = msp.add_hatch()
    hatch.paths.add_polyline_path([(0, 0), (20, 0), (20, 20), (0, 20)])
    hatch.paths.add_edge_path().add_arc((10, 10), radius=8)
    hatch.paths.add_edge_path().add_ellipse((10, 10), major_axis=(4, 0), ratio=0.5)
    msp.add_circle((40, 10), radius=5)                      # an outline shape elsewhere
    path = save(doc, tmp_path)
    exact = 400 - math.pi * 64 + math.pi * 4 * 2
    for region in (load_dxf(path, tolerance=1e-4), load_dxf(path, tolerance=1e-4, mode="fill")):
        assert region.betti == (2, 1)
        assert_area(region, exact, 2 * math.pi * 12, 1e-4)
    outline = load_dxf(path, tolerance=1e-4, mode="outline")
    assert outline.betti == (1, 0)
    assert_area(outline, math.pi * 25, 2 * math.pi * 5, 1e-4)


def test_fill_mode_without_hatches_is_an_error(tmp_path):
    doc, msp = new()
    square(msp, 0, 0, 2)
    with pytest.raises(RegionError, match="hatches .* enclose no area.*mode='outline'"):
        load_dxf(save(doc, tmp_path), mode="fill")


# --- layers and annotation ---

def annotated(tmp_path):
    doc, msp = new()
    doc.layers.add("PART")
    doc.layers.add("HOLES")
    doc.layers.add("DIM")
    square(msp, 0, 0, 10, layer="PART")
    msp.add_circle((5, 5), 2, dxfattribs={"layer": "HOLES"})
    msp.add_text("plate", dxfattribs={"layer": "DIM"})
    msp.add_linear_dim(base=(0, -2), p1=(0, 0), p2=(10, 0),
                       dxfattribs={"layer": "DIM"}).render()
    msp.add_text("part no. 7", dxfattribs={"layer": "PART"})
    return save(doc, tmp_path)


def test_default_layers_leave_out_annotation_layers_and_warn_once_about_the_rest(tmp_path):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        region = load_dxf(annotated(tmp_path), tolerance=1e-4)
    assert region.betti == (1, 1)
    assert [str(w.message) for w in caught] == [
        f"{str(tmp_path / 'drawing.dxf')!r}: ignored 1 TEXT (text, dimensions and entities "
        f"without an outline are not part of the region)"]


def test_layers_select_what_is_read(tmp_path):
    path = annotated(tmp_path)
    with pytest.warns(UserWarning, match="ignored 1 TEXT"):
        part = load_dxf(path, layers="part")                    # case-insensitive
    assert part.area == 100.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        holes = load_dxf(path, layers=["HOLES"], tolerance=1e-4)
    assert not caught and holes.betti == (1, 0)
    with pytest.warns(UserWarning, match=r"ignored 1 DIMENSION, 1 TEXT"), \
            pytest.raises(RegionError, match="no outline curve"):
        load_dxf(path, layers=["DIM"])
    with pytest.raises(ArgumentError, match=r"no layer 'NOPE'.*holes, part"):
        load_dxf(path, layers=["NOPE"])


def test_block_entities_on_layer_0_take_the_insert_layer(tmp_path):
    doc, msp = new()
    doc.layers.add("KEEP")
    doc.layers.add("DROP")
    block = doc.blocks.new("SQ")
    square(block, 0, 0, 1)                                  # on layer 0
    square(block, 5, 5, 1, layer="DROP")
    msp.add_blockref("SQ", (0, 0), dxfattribs={"layer": "KEEP"})
    region = load_dxf(save(doc, tmp_path), layers=["keep"])
    assert region.area == 1.0 and region.bounds == (0.0, 0.0, 1.0, 1.0)


# --- real drawings against an independent reading ---

def independent_reading(path, distance=1e-6):
    """Shapely polygons from ezdxf's own flattening: blocks decomposed by ezdxf, ends put
    on a grid by shapely, loops nested by the symmetric difference of the face shells."""
    from ezdxf.disassemble import recursive_decompose

    def flattened(entity):
        kind = entity.dxftype()
        if kind == "LINE":
            return [[entity.dxf.start, entity.dxf.end]]
        if kind in ("LWPOLYLINE", "POLYLINE"):
            return [points for part in entity.virtual_entities() for points in flattened(part)]
        if kind in ("ARC", "CIRCLE", "ELLIPSE", "SPLINE"):
            return [list(entity.flattening(distance))]
        return []
    entities = recursive_decompose(ezdxf.readfile(path).modelspace())
    lines = [shapely.LineString([(p[0], p[1]) for p in points])
             for entity in entities for points in flattened(entity)]
    noded = shapely.union_all(shapely.set_precision(lines, distance))
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(noded)))
    return functools.reduce(shapely.symmetric_difference,
                            [shapely.Polygon(face.exterior) for face in faces], shapely.Polygon())


@pytest.mark.parametrize("name", ["wrench.dxf", "sliding-base.dxf", "insert.dxf", "spline.DXF"])
def test_public_drawings_match_independent_readings(name):
    path = DATA / name
    if not path.exists():
        pytest.skip(f"{path} is absent (the shared data sits beside the repository)")
    import trimesh

    tolerance = 1e-5
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # sliding-base's MTEXT, insert's zero-area marks
        region = load_dxf(path, tolerance=tolerance)
    reference = independent_reading(path)
    parts = shapely.get_parts(reference)
    assert region.betti == (len(parts), sum(len(part.interiors) for part in parts))
    assert abs(region.area - reference.area) <= region.perimeter * tolerance
    polygons = trimesh.load_path(path).polygons_full          # trimesh's own reader
    assert region.betti == (len(polygons), sum(len(p.interiors) for p in polygons))
    assert region.area == pytest.approx(sum(p.area for p in polygons), rel=1e-3)


def test_same_file_same_region_bit_for_bit(tmp_path):
    doc, msp = new()
    msp.add_open_spline([(0, 0), (2, 5), (6, 7), (9, 0)], degree=3)
    msp.add_line((9, 0), (0, 0))
    msp.add_circle((4, 2), 1)
    path = save(doc, tmp_path)
    assert load_dxf(path).geometry.equals_exact(load_dxf(path).geometry, tolerance=0)


def test_load_drawing_chooses_the_reader_by_suffix(tmp_path):
    doc, msp = new()
    square(msp, 0, 0, 3)
    assert load_drawing(save(doc, tmp_path, "part.DXF")).area == 9.0
    svg = tmp_path / "part.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 4 4">'
                   '<rect width="4" height="4"/></svg>')
    assert load_drawing(svg).area == 16.0
    with pytest.raises(SourceError, match=r"suffix must be one of \.svg, \.dxf"):
        load_drawing(tmp_path / "part.dwg")


# --- bad input ---

def test_binary_dxf_reads_like_ascii(tmp_path):
    doc, msp = new()
    square(msp, 0, 0, 10)
    msp.add_circle((5, 5), 2)
    ascii_region = load_dxf(save(doc, tmp_path, "a.dxf"))
    binary = save(doc, tmp_path, "b.dxf", fmt="bin")
    assert binary.read_bytes().startswith(b"AutoCAD Binary DXF")
    assert load_dxf(binary).geometry.equals_exact(ascii_region.geometry, tolerance=0)


def test_unreadable_files_are_clear_errors(tmp_path):
    doc, msp = new()
    square(msp, 0, 0, 10)
    whole = save(doc, tmp_path).read_bytes()
    cases = {"text.dxf": b"hello, this is not a drawing\n",
             "truncated.dxf": whole[:len(whole) // 2],
             "damaged_binary.dxf": b"AutoCAD Binary DXF\r\n\x1a\x00" + bytes(range(256)) * 3}
    for name, content in cases.items():
        path = tmp_path / name
        path.write_bytes(content)
        with pytest.raises(SourceError, match=r"cannot read .* as DXF .*not DXF, or it is "
                                             r"truncated or damaged"):
            load_dxf(path)
    (tmp_path / "empty.dxf").write_bytes(b"")
    with pytest.raises(SourceError, match="is empty"):
        load_dxf(tmp_path / "empty.dxf")
    with pytest.raises(FileNotFoundError, match="no such DXF file"):
        load_dxf(tmp_path / "absent.dxf")


def test_no_closed_loop_is_an_error_with_the_open_ends(tmp_path):
    doc, msp = new()
    msp.add_lwpolyline([(10, 10), (90, 10), (90, 90)])
    with pytest.raises(RegionError, match=r"no closed loop.*2 curve end\(s\).*\(10, 10\).*"
                                         r"\(90, 90\)"):
        load_dxf(save(doc, tmp_path))


def test_a_loop_that_does_not_close_is_reported_beside_the_ones_that_do(tmp_path):
    doc, msp = new()
    square(msp, 0, 0, 10)
    msp.add_lwpolyline([(20, 0), (30, 0), (30, 10)])
    with pytest.warns(UserWarning, match=r"2 curve end\(s\).*\(20, 0\).*\(30, 10\)"):
        region = load_dxf(save(doc, tmp_path))
    assert region.area == 100.0


def test_a_block_inserting_itself_is_refused(tmp_path):
    doc, msp = new()
    loop = doc.blocks.new("LOOP")
    square(loop, 0, 0, 1)
    doc.blocks.new("OUTER").add_blockref("LOOP", (2, 0))
    loop.add_blockref("OUTER", (0, 2))
    msp.add_blockref("LOOP", (0, 0))
    with pytest.raises(SourceError, match=r"block 'LOOP' inserts itself \(LOOP -> OUTER -> LOOP\)"):
        load_dxf(save(doc, tmp_path))


def nested_bomb(doc, levels, copies=10):
    """Blocks B1..B{levels}, each inserting the one below ``copies`` times in a row, along
    x and y in turn; B0 is a unit square: B{levels} expands to copies**levels disjoint
    squares."""
    square(doc.blocks.new("B0"), 0, 0, 1)
    for level in range(1, levels + 1):
        block = doc.blocks.new(f"B{level}")
        step = 2 * copies ** ((level - 1) // 2)
        for copy in range(copies):
            block.add_blockref(f"B{level - 1}", (step * copy, 0) if level % 2 else
                               (0, step * copy))
    return f"B{levels}"


def test_nested_insert_bomb_is_refused_before_it_is_expanded(tmp_path):
    import time

    doc, msp = new()
    msp.add_blockref(nested_bomb(doc, 8), (0, 0))                  # 10^8 squares, 26 kB
    path = save(doc, tmp_path)
    assert path.stat().st_size < 100_000
    began = time.monotonic()
    with pytest.raises(SourceError, match=r"expands to more than 100,000 entities \(every "
                                          r"block INSERT counted.*pass a larger max_entities"):
        load_dxf(path)
    # the limit is counted, not hit while expanding: 10^8 entities would take hours
    assert time.monotonic() - began < 20
    with pytest.raises(SourceError, match="max_entities"):
        load_dxf(path, max_entities=10**7)


def test_minsert_array_and_long_polylines_count_their_copies(tmp_path):
    doc, msp = new()
    square(doc.blocks.new("CELL"), 0, 0, 0.5)
    msp.add_blockref("CELL", (0, 0)).grid(size=(10_000, 10_000), spacing=(1, 1))
    with pytest.raises(SourceError, match="more than 100,000 entities"):
        load_dxf(save(doc, tmp_path, "minsert.dxf"))
    doc, msp = new()
    ring = doc.blocks.new("RING")                                 # a 10,000-gon, 200 copies
    angles = np.linspace(0, 2 * np.pi, 10_000, endpoint=False)
    ring.add_lwpolyline(np.column_stack([np.cos(angles), np.sin(angles)]), close=True)
    for copy in range(200):
        msp.add_blockref("RING", (3 * copy, 0))
    path = save(doc, tmp_path, "rings.dxf")
    with pytest.raises(SourceError, match=r"more than 1,000,000 polyline vertices.*pass a "
                                          r"larger max_segments"):
        load_dxf(path)
    with pytest.raises(SourceError, match="max_segments"):
        load_dxf(path, max_segments=1_999_999)


def test_limits_below_the_drawing_refuse_it_and_above_read_it(tmp_path):
    doc, msp = new()
    msp.add_blockref(nested_bomb(doc, 2), (0, 0))     # 100 squares: 211 entities with the INSERTs
    path = save(doc, tmp_path)
    assert load_dxf(path, max_entities=211, max_segments=400).area == pytest.approx(100.0)
    for options, keyword in [({"max_entities": 210}, "max_entities"),
                             ({"max_segments": 399}, "max_segments"),
                             ({"max_bytes": 1000}, "max_bytes")]:
        with pytest.raises(SourceError, match=f"pass a larger {keyword} to read it"):
            load_dxf(path, **options)
    for keyword in ("max_bytes", "max_entities", "max_segments"):
        with pytest.raises(ArgumentError, match=f"{keyword} must be a positive integer"):
            load_dxf(path, **{keyword: 0})


def test_an_insert_of_an_undefined_block_is_a_damaged_file(tmp_path):
    doc, msp = new()
    square(msp, 0, 0, 10)
    msp.add_blockref("NOWHERE", (0, 0), dxfattribs={"layer": "PARTS"})
    with pytest.raises(SourceError, match=r"INSERT on layer 'PARTS' places block 'NOWHERE', "
                                          r"which the drawing does not define"):
        load_dxf(save(doc, tmp_path))


@pytest.mark.parametrize("bad", ["nan", "inf"])
def test_non_finite_coordinates_are_named(tmp_path, bad):
    doc, msp = new()
    square(msp, 0, 0, 10)
    if bad == "nan":
        msp.add_line((0, 0), (float("nan"), 5))
    else:
        msp.add_circle((5, 5), float("inf"))
    with pytest.raises(SourceError, match=r"a (LINE|CIRCLE) on layer '0' has NaN or infinite"):
        load_dxf(save(doc, tmp_path))


def test_empty_drawing_and_bad_arguments(tmp_path):
    doc, msp = new()
    msp.add_point((1, 1))
    doc.paperspace().add_circle((0, 0), 1)          # read unless the model space is asked for
    path = save(doc, tmp_path)
    with pytest.raises(RegionError, match="no outline curve.*model space"):
        load_dxf(path, layout="Model")
    empty_hatch, hatch_space = new()
    hatch_space.add_hatch()                                  # no boundary path
    with pytest.raises(RegionError, match="nothing to mesh"):
        load_dxf(save(empty_hatch, tmp_path, "hatch.dxf"))
    square(msp, 0, 0, 1)
    path = save(doc, tmp_path, "square.dxf")
    for options, message in [({"mode": "stroke"}, "mode must be"), ({"units": "px"}, "units"),
                             ({"tolerance": -1}, "tolerance must be a positive"),
                             ({"layers": [3]}, "layers must be")]:
        with pytest.raises(ArgumentError, match=message):
            load_dxf(path, **options)


def test_example_meshes_its_bracket_with_an_ok_certificate(tmp_path, capsys):
    import runpy

    example = Path(__file__).resolve().parents[1] / "examples" / "dxf_drawing.py"
    runpy.run_path(str(example))["main"](tmp_path)
    printed = capsys.readouterr().out
    assert printed.count("certificate: ok") == 1 + sum(
        (DATA / name).exists() for name in ("wrench.dxf", "sliding-base.dxf"))
    assert (tmp_path / "bracket.ply").exists()
    region = load_dxf(tmp_path / "bracket.dxf", units="mm", tolerance=1e-3)
    corners, slot, holes = (4 - math.pi) / 16, 0.2 + math.pi / 100, 2 * math.pi * 0.04
    assert region.betti == (1, 3)
    assert_area(region, (8 - corners - slot - holes) * 25.4**2, region.perimeter, 1e-3)


def test_an_arc_with_equal_start_and_end_angles_draws_nothing(tmp_path):
    """ezdxf reads such an ARC as empty (span 0); it used to become a full circle, a
    phantom hole of radius 2 in this square (area 87.4 instead of 100)."""
    doc, msp = new()
    square(msp, 0, 0, 10)
    arc = msp.add_arc((5, 5), 2, 30, 30)
    assert arc.construction_tool().angle_span == 0
    assert load_dxf(save(doc, tmp_path)).area == pytest.approx(100.0, rel=1e-12)
    full, full_msp = new()
    square(full_msp, 0, 0, 10)
    full_msp.add_arc((5, 5), 2, 30, 390)                      # a whole turn
    assert load_dxf(save(full, tmp_path, "full.dxf"), tolerance=1e-6).area == \
        pytest.approx(100 - 4 * math.pi, rel=1e-5)


@pytest.mark.parametrize("far", [1e308, -1e308, 1e60])
def test_an_outline_vertex_beyond_the_scale_limit_is_a_region_error(tmp_path, far):
    """A polyline vertex at 1e308 used to overflow scipy's KD-tree (a ValueError about
    Minkowski p) while joining the curve ends."""
    doc, msp = new()
    msp.add_lwpolyline([(0, 0), (far, 0), (10, 10), (0, 10)], close=True)
    with pytest.raises(RegionError, match="coordinates up to .*below 1e\\+50"):
        load_dxf(save(doc, tmp_path))


def test_a_drawing_far_from_the_origin_says_to_translate_it(tmp_path):
    """A unit square at 1e15 used to be 'no closed loop ... nothing to mesh': its sides
    were dropped as rounding steps before the curves were joined."""
    doc, msp = new()
    square(msp, 1e15, 1e15, 1)
    with pytest.raises(RegionError, match="rounding .* exceeds the tolerance .* translate "
                                          "the drawing towards the origin"):
        load_dxf(save(doc, tmp_path))
    near, near_msp = new()
    square(near_msp, 1e6, 1e6, 1)
    assert load_dxf(save(near, tmp_path, "near.dxf")).area == pytest.approx(1.0, rel=1e-9)


# --- one region per layer: composite sections (issue 23) ----------------------------

def test_one_region_per_layer_meshes_as_a_composite_section(tmp_path):
    """A concrete section with a steel core, drawn as CAD users draw materials: each on
    its own layer, the concrete's outline and the core's edge (its hole), the core on
    the STEEL layer; a centre line on a third layer closes nothing and is left out. The
    two layers' regions share the core's edge exactly (one tolerance for the drawing), so
    pds.mesh_regions meshes them as one conforming, certified mesh whose tags and areas
    are the materials'."""
    import pds_plugin as pds

    doc, msp = new()
    square(msp, 0, 0, 10, layer="CONCRETE")
    square(msp, 3, 3, 4, layer="CONCRETE")
    square(msp, 3, 3, 4, layer="STEEL")
    msp.add_line((5, -1), (5, 11), dxfattribs={"layer": "AXIS"})
    path = save(doc, tmp_path)
    with pytest.warns(UserWarning, match="layer 'AXIS'.*left out"):
        parts = load_dxf(path, regions="layer", mode="outline")
    assert list(parts) == ["CONCRETE", "STEEL"]
    assert parts["CONCRETE"].betti == (1, 1) and parts["STEEL"].betti == (1, 0)
    mesh = pds.mesh_regions(parts, 1.0, seed=0)
    assert mesh.certificate().ok, mesh.certificate()
    area = mesh.quality().area
    assert area[mesh.region_tags.where("CONCRETE")].sum() == pytest.approx(84, rel=1e-12)
    assert area[mesh.region_tags.where("STEEL")].sum() == pytest.approx(16, rel=1e-12)
    interface = np.hypot(*np.diff(mesh.vertices[mesh.interface_edges], axis=1)[:, 0].T).sum()
    assert interface == pytest.approx(16, rel=1e-12)
    with pytest.raises(ArgumentError, match="regions must be None"):
        load_dxf(path, regions="layers")
