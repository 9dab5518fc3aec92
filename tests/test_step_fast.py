"""The STEP section's short cuts give what the long ways give (issue 22's time target):
all arcs flattened at once are :func:`.curves.elliptic_points`' points bit for bit; the
rings made by one concatenation are the even-odd nesting's region; a one-edge wire read
without OCCT's wire explorer has that explorer's edge; the labels asked of the faces
near the plane first are those of all faces in order; the area is OCCT's. Skipped when
OCP (the [step] extra) is absent, except the pure-NumPy checks."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest
import shapely

import pds_plugin as pds
from pds_plugin.sources import step
from pds_plugin.sources.curves import elliptic_points
from pds_plugin.sources.planes import plane_frames
from pds_plugin.sources.polygons import outline_geometry

needs_ocp = pytest.mark.skipif(importlib.util.find_spec("OCP") is None,
                               reason="OCP (the [step] extra) is not installed")
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import _step_parts as parts  # noqa: E402
from step_vs_stl import exact_area as occt_section_area  # noqa: E402  (GProp, the reference)

TILTED = np.array([0.05, 0.0, 1.0]) / np.hypot(1, 0.05)
CASES = [(parts.plate_with_holes, (0.0, 0.0, 5.0), (0.0, 0.0, 1.0)),
         (parts.plate_with_holes, (50.0, 30.0, 5.0), tuple(TILTED)),     # ellipses
         (parts.pocketed_plate, (0.0, 0.0, 14.0), (0.0, 0.0, 1.0)),      # lines meet arcs
         (parts.filleted_block, (0.0, 0.0, 10.0), (0.0, 0.0, 1.0)),      # a B-spline
         (parts.bolt, (0.0, 0.0, 20.0), (0.0, 0.0, 1.0)),                # one circle
         (parts.overlapping_bodies, (0.0, 0.0, 5.0), (0.0, 0.0, 1.0))]   # two solids


def _conic(rng, closed=False):
    """A random circle or ellipse arc as SectionCurve (its two ends, as OCCT's come)."""
    center, radii = rng.normal(size=2) * 10, rng.normal(size=(2, 2)) * 5
    start = rng.uniform(-7, 7)
    sweep = 2 * np.pi if closed else rng.uniform(-6, 6)
    ends = center + np.array([[np.cos(start), np.sin(start)],
                              [np.cos(start + sweep), np.sin(start + sweep)]]) @ radii.T
    if closed:
        ends[-1] = ends[0]
    return step.SectionCurve("ellipse", ends, center, radii, 0.0, start, sweep)


def test_arcs_flattened_at_once_are_elliptic_points_bit_for_bit():
    rng = np.random.default_rng(22)
    for _ in range(50):
        conics = [_conic(rng, closed=k == 0) for k in range(int(rng.integers(1, 8)))]
        tolerance = 10 ** rng.uniform(-7, -2)
        flattened = step._arcs_flattened(conics, tolerance)
        for curve in conics:
            expected = elliptic_points(curve.center, curve.radii, curve.start, curve.sweep,
                                       tolerance)
            if np.array_equal(curve.points[0], curve.points[-1]):
                expected[-1] = expected[0]                 # a whole turn stays closed
            assert np.array_equal(flattened[id(curve)].points, expected)


def test_rings_with_repeated_vertices_drop_them_as_the_nesting_does():
    """A degenerate curve (one point twice) and a junction repeated: the concatenated
    rings take the slow path and give the region the even-odd nesting gives."""
    square = [np.array([[0.0, 0.0], [4.0, 0.0]]), np.array([[4.0, 0.0], [4.0, 0.0]]),
              np.array([[4.0, 0.0], [4.0, 4.0], [4.0, 4.0]]),
              np.array([[4.0, 4.0], [0.0, 4.0]]), np.array([[0.0, 4.0], [0.0, 0.0]])]
    hole = [np.array([[1.0, 1.0], [1.0, 2.0], [2.0, 2.0], [2.0, 1.0], [1.0, 1.0]])]
    curves = [step.SectionCurve("line", p) for p in square + hole]
    faces = [[[None] * len(square), [None]]]
    geometry = step._face_polygons(faces, curves, 1e-9)
    nested, open_ends = outline_geometry([c.points for c in curves], 1e-9)
    assert not len(open_ends)
    assert geometry.equals(nested) and geometry.area == 15.0
    assert [len(ring.coords) for ring in (geometry.exterior, *geometry.interiors)] == [5, 5]


@needs_ocp
@pytest.mark.parametrize("build, origin, normal", CASES)
def test_the_wires_rings_are_the_even_odd_nesting_of_the_curves(build, origin, normal):
    """The short way (each solid's wires, rings by one concatenation) and the long way
    (the curves nested even-odd, the fallback) give the same region, to rounding."""
    shape = build()
    region = pds.section(shape, origin, normal)
    solid = step.StepSolid(shape)
    to_2d, to_3d = plane_frames(np.asarray(origin, float), np.asarray(normal, float))
    cuts = []
    for number in solid._met(np.asarray(origin, float), np.asarray(normal, float)):
        cuts.append(solid._cut_curves(solid.solids[number], number,
                                      np.asarray(origin, float), to_2d))
    cuts = solid._refined(cuts, 0.0, to_3d)
    nested = shapely.union_all([outline_geometry([c.points for c in curves],
                                                 1e-9 * solid.scale)[0]
                                for _, curves in cuts])
    assert shapely.symmetric_difference(region.geometry, nested).area <= 1e-12 * nested.area
    assert region.area == pytest.approx(nested.area, rel=1e-14)


@needs_ocp
@pytest.mark.parametrize("build, origin, normal", CASES)
def test_the_area_is_occts_and_every_ring_vertex_on_a_circle_lies_on_it(build, origin,
                                                                       normal):
    shape = build()
    region = pds.section(shape, origin, normal)
    exact = occt_section_area(shape, origin, normal)
    assert region.area == pytest.approx(exact, rel=1e-6)
    vertices = np.concatenate(region.rings)
    curves = region.curves
    piece, _, distance = curves.locate(vertices)
    arc = curves.elliptic[piece]
    radius = np.hypot(*curves.conic[piece[arc], 2:4].T)
    assert (distance[arc] <= 1e-12 * radius).all()


@needs_ocp
@pytest.mark.parametrize("build, origin, normal", CASES)
def test_one_edge_wires_and_labels_are_the_explorers_and_all_faces(build, origin, normal):
    """Each wire read by the face's iterator (a one-edge wire without the wire explorer)
    has the edges BRepTools_WireExplorer walks, in its order; the labels asked first of
    the faces near the plane are those asked of all faces in OCCT's order."""
    from OCP.BRepTools import BRepTools_WireExplorer
    from OCP.TopoDS import TopoDS

    shape = build()
    solid = step.StepSolid(shape)
    origin, normal = np.asarray(origin, float), np.asarray(normal, float)
    to_2d = plane_frames(origin, normal)[0]
    for number in solid._met(origin, normal):
        faces = solid._common_faces(solid.solids[number], origin, to_2d,
                                    solid._reach(origin))
        for face, wires in zip(step._explore(faces.common.Shape(), "FACE"), faces):
            assert len(wires) == len(step._explore(face, "WIRE"))
            for wire in step._explore(face, "WIRE"):
                walk, walked = BRepTools_WireExplorer(TopoDS.Wire(wire), TopoDS.Face(face)), []
                while walk.More():
                    walked.append(walk.Current())
                    walk.Next()
                ours = [edges for edges in wires if edges[0][0].IsSame(walked[0])]
                assert len(ours) == 1 and len(ours[0]) == len(walked)
                assert all(a.IsSame(b) for (a, _), b in zip(ours[0], walked))
        _, curves = solid._cut_curves(solid.solids[number], number, origin, to_2d,
                                      section=False)
        edges = [edge for face in faces for wire in face for edge, _ in wire]
        every = step._face_labels(edges, solid.faces[number], faces.common,
                                  number if len(solid.solids) > 1 else None)
        assert [c.face for c in curves] == every and all(every)


@needs_ocp
@pytest.mark.parametrize("build, origin, normal", CASES)
def test_the_sections_loops_give_the_commons_region_curves_and_labels(build, origin, normal,
                                                                     monkeypatch):
    """Solids of analytic faces are cut by OCCT's Section, its edges chained into loops
    and nested here: the same region as the Common's wires (to the approximation of a
    B-spline: OCCT's Section approximates the cut through the elliptic slot's surface of
    extrusion without the Common's pcurves, within its edge tolerance), the same curves,
    labelled by the same faces (each edge's face asked directly, ``HasAncestorFaceOn1``,
    is the one the Section's history names)."""
    shape = build()
    solid = step.StepSolid(shape)
    origin, normal = np.asarray(origin, float), np.asarray(normal, float)
    to_2d = plane_frames(origin, normal)[0]
    assert all(solid.analytic)
    for number in solid._met(origin, normal):
        loops, curves = solid._cut_curves(solid.solids[number], number, origin, to_2d)
        assert loops.loose                            # the Section's loops were used
        edges = [edge for face in loops for wire in face for edge, _ in wire]
        history = step._face_labels(edges, solid.faces[number], loops.common,
                                    number if len(solid.solids) > 1 else None)
        assert [c.face for c in curves] == history and all(history)   # each edge's face
        _, common = solid._cut_curves(solid.solids[number], number, origin, to_2d,
                                      section=False)
        assert sorted((c.kind, c.face) for c in curves) == sorted((c.kind, c.face)
                                                                  for c in common)
        exact = abs(step._wire_area(*solid._cut_curves(solid.solids[number], number,
                                                       origin, to_2d, section=False)))
        assert 0 < step._wire_area(loops, curves) <= exact * (1 + 1e-12)   # a lower bound
    region = pds.section(shape, origin, normal)
    monkeypatch.setattr(step, "SECTION_BOOLEAN", False)
    common = pds.section(shape, origin, normal)
    assert region.betti == common.betti
    assert region.area == pytest.approx(common.area, rel=1e-8)
    # both flattenings within the area budgets of the true curves (the pocketed plate's
    # island, inside a hole, counts as a hole in the Section's lower bound of the area:
    # its arcs are finer)
    budget = 2 * (step.AREA_ERROR + step.SPLINE_AREA_ERROR) * common.area
    assert shapely.symmetric_difference(region.geometry, common.geometry).area <= budget


@needs_ocp
def test_a_plane_on_a_grooves_bottom_falls_back_to_the_common():
    """A plane touching a cylindrical groove along its bottom line: OCCT's Section gives
    that line too, whose ends meet the outline (vertices of three edges, no loops), so
    the Common cuts the solid; the region is OCCT's exact section."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut

    block = parts._box(0, 0, 0, 30, 30, 10)
    groove = parts._cylinder(-1, 15, 12, 4, 32, direction=(1, 0, 0))
    shape = BRepAlgoAPI_Cut(block, groove).Shape()
    origin, normal = np.array([0.0, 0.0, 8.0]), np.array([0.0, 0.0, 1.0])
    solid = step.StepSolid(shape)
    assert solid.analytic == [True]
    to_2d = plane_frames(origin, normal)[0]
    assert solid._section_loops(solid.solids[0], origin, to_2d) is None
    region = pds.section(shape, origin, normal)
    assert region.area == pytest.approx(occt_section_area(shape, origin, normal), rel=1e-9)
    assert region.betti == (1, 0)


@needs_ocp
def test_free_form_solids_are_cut_by_the_common_and_analytic_ones_by_the_section():
    """OCCT's Section is 1.3-6 times slower than its Common on surfaces of revolution and
    B-spline surfaces (a vase, a threaded screw): those solids keep the Common; a sphere
    on a cone (two solids) is cut by the Section, each solid's loops nested alone."""
    vase, origin = parts._vase(np.random.default_rng([5101, 5]))
    knob, knob_origin = parts._knob(np.random.default_rng([5101, 3]))
    normal = np.array([0.0, 0.0, 1.0])
    for shape, origin, analytic in ((vase, origin, False), (knob, knob_origin, True)):
        solid = step.StepSolid(shape)
        origin = np.asarray(origin, float)
        to_2d = plane_frames(origin, normal)[0]
        assert set(solid.analytic) == {analytic}
        for number in solid._met(origin, normal):
            faces, _ = solid._cut_curves(solid.solids[number], number, origin, to_2d)
            assert faces.loose == analytic
        region = pds.section(shape, origin, normal)
        assert region.area == pytest.approx(occt_section_area(shape, origin, normal),
                                            rel=1e-6)


def _rings_in_rings():
    """A plate with a ring groove round a boss with a bore round a pin (loops nested
    four deep: shell, hole, island, hole, island)."""
    plate = parts._cut(parts._box(0, 0, 0, 80, 80, 10), parts._cylinder(40, 40, 2, 35, 12))
    boss = parts._cut(parts._fuse(plate, parts._cylinder(40, 40, 0, 25, 10)),
                      parts._cylinder(40, 40, 2, 15, 12))
    return parts._fuse(boss, parts._cylinder(40, 40, 0, 5, 10))


def _holes_touching():
    """Two bores that touch at a point (the Section's loops meet at a vertex)."""
    return parts._cut(parts._box(0, 0, 0, 40, 40, 10), parts._cylinder(10, 20, -1, 5, 12),
                      parts._cylinder(20, 20, -1, 5, 12))


@needs_ocp
@pytest.mark.parametrize("build, loops, betti", [(_rings_in_rings, True, (3, 2)),
                                                 (_holes_touching, False, (1, 1))])
def test_nested_and_touching_loops_give_occts_section(build, loops, betti):
    """Loops nested four deep are nested by parity (each hole in the smallest ring round
    it); loops that meet at a vertex leave the Section for the Common. Both give OCCT's
    area to 1e-6 (the nested loops' lower bound of the area makes their arcs finer)."""
    shape = build()
    origin, normal = np.array([0.0, 0.0, 5.0]), np.array([0.0, 0.0, 1.0])
    solid = step.StepSolid(shape)
    found = solid._section_loops(solid.solids[0], origin, plane_frames(origin, normal)[0])
    assert (found is not None) == loops
    region = pds.section(shape, origin, normal)
    assert region.betti == betti
    assert region.area == pytest.approx(occt_section_area(shape, origin, normal), rel=1e-6)


def test_region_curves_are_the_builders_pieces_bit_for_bit():
    """``_boundary_curves`` makes the arrays the curves builder makes for the same calls:
    lines (a degenerate one left out, its label unnumbered), arcs halved past half a
    turn, polylines with repeated points, labels numbered as first met."""
    from pds_plugin.boundary_curves import curves_builder

    rng = np.random.default_rng(2204)
    for _ in range(40):
        curves = []
        for k in range(int(rng.integers(1, 9))):
            kind = rng.choice(["line", "point", "arc", "turn", "polyline"])
            face = f"face {int(rng.integers(0, 4))}" if rng.random() < 0.8 else ""
            if kind in ("arc", "turn"):
                curve = _conic(rng, closed=kind == "turn")
                curves.append(step.SectionCurve("circle", curve.points, curve.center,
                                                curve.radii, 0.0, curve.start, curve.sweep,
                                                face=face))
            elif kind == "polyline":
                points = rng.normal(size=(int(rng.integers(2, 12)), 2))
                points[1] = points[0]                      # a repeated point
                curves.append(step.SectionCurve("bspline", points, face=face))
            else:
                start = rng.normal(size=2)
                end = start if kind == "point" else rng.normal(size=2)
                curves.append(step.SectionCurve("line", np.array([start, end]), face=face))
        build = curves_builder(1e-3)
        for curve in curves:
            label = curve.face or "section"
            if curve.kind == "line":
                build.line(*curve.points.tolist(), label)
            elif curve.kind == "circle":
                halves = 2 if abs(curve.sweep) > np.pi else 1
                for half in range(halves):
                    build.arc(curve.center, curve.radii,
                              curve.start + half * curve.sweep / halves,
                              curve.sweep / halves, label)
            else:
                build.polyline(curve.points, label)
        expected, ours = build.done(), step._boundary_curves(curves, 1e-3)
        if expected is None:
            assert ours is None
            continue
        for field in ("elliptic", "control", "conic", "source"):
            a, b = getattr(expected, field), getattr(ours, field)
            assert a.dtype == b.dtype and np.array_equal(a, b), field
        assert expected.labels == ours.labels and expected.tolerance == ours.tolerance


def test_a_multipolygon_makes_the_region_its_polygons_make():
    """Region.from_shapely takes a MultiPolygon of non-empty polygons as it is (checked
    and oriented without rebuilding it): the region is bit for bit the one the same
    polygons make in a collection (rebuilt), holes, touching parts and wrong
    orientations included; invalid ones raise the same error."""
    from shapely.geometry import GeometryCollection, MultiPolygon, Polygon

    clockwise = Polygon([(0, 0), (0, 3), (3, 3), (3, 0)], [[(1, 1), (2, 1), (2, 2), (1, 2)]])
    cases = [MultiPolygon([clockwise]),
             MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(1, 1, 2, 2)]),
             MultiPolygon([Polygon([(0, 0), (4, 0), (4, 4), (0, 4)],
                                   [[(0, 2), (2, 1), (2, 3)]])])]
    for geometry in cases:
        whole = pds.Region.from_shapely(geometry)
        rebuilt = pds.Region.from_shapely(GeometryCollection(list(geometry.geoms)))
        assert shapely.to_wkb(whole.geometry) == shapely.to_wkb(rebuilt.geometry)
        assert whole.source_deviation == rebuilt.source_deviation
    overlapping = MultiPolygon([shapely.box(0, 0, 2, 2), shapely.box(1, 1, 3, 3)])
    errors = []
    for geometry in (overlapping, GeometryCollection(list(overlapping.geoms))):
        with pytest.raises(pds.PdsError) as raised:
            pds.Region.from_shapely(geometry)
        errors.append(str(raised.value))
    assert errors[0] == errors[1] and "Self-intersection" in errors[0]


@needs_ocp
def test_a_splines_bezier_poles_are_occts_pieces_mapped():
    """The Bézier pieces' poles are OCCT's conversion's, each piece's mapped into the
    plane by its own product, bit for bit (what the flattening and the region's bits
    rest on), end to end."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GeomConvert import GeomConvert_BSplineCurveToBezierCurve

    build, origin, normal = CASES[3]                  # the filleted block's slot
    shape = build()
    solid = step.StepSolid(shape)
    origin, normal = np.asarray(origin, float), np.asarray(normal, float)
    to_2d = plane_frames(origin, normal)[0]
    frame = np.asarray(to_2d, dtype=float)[:2]
    splines = 0
    for number in solid._met(origin, normal):
        faces = solid._common_faces(solid.solids[number], origin, to_2d,
                                    solid._reach(origin))
        for edge, _ in (pair for face in faces for wire in face for pair in wire):
            curve = BRepAdaptor_Curve(edge)
            kind = curve.GetType()
            if kind.name != "GeomAbs_BSplineCurve" or curve.BSpline().IsRational():
                continue
            splines += 1
            first, last = curve.FirstParameter(), curve.LastParameter()
            pieces = step._bezier_pieces(curve, kind, first, last, frame)
            split = GeomConvert_BSplineCurveToBezierCurve(curve.BSpline(), first, last, 1e-12)
            assert len(pieces) == split.NbArcs()
            for i, ours in enumerate(pieces, start=1):
                arc = split.Arc(i)
                xyz = np.array([arc.Pole(k).Coord() for k in range(1, arc.NbPoles() + 1)])
                assert np.array_equal(ours, xyz @ frame[:, :3].T + frame[:, 3])
            assert all(np.array_equal(a[-1], b[0]) for a, b in zip(pieces, pieces[1:]))
    assert splines
