"""Fuzz suite: random and hostile inputs against oracles that do not trust the package.

Every property is checked with oracles computed independently of the certificate:
shapely areas and Betti numbers (components and holes of the union of the triangles),
scipy's KD-tree for the separation, scipy's Delaunay for the complex, and the area of
the union of the boxes a solid is made of for its sections. Bad input must end in a
clean error (the package's error type, or OSError for files), never another exception,
never a silently wrong result, and the caller's input is never modified.

The number of examples per property is bounded for CI (the suite runs in well under a
minute); set ``PDS_FUZZ_EXAMPLES`` for a longer hunt, e.g.
``PDS_FUZZ_EXAMPLES=500 python -m pytest tests/test_fuzz.py``. Inputs that used to run
away (memory or time) are run in a subprocess with a time limit.
"""

import contextlib
import functools
import io
import math
import os
import re
import struct
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
import trimesh
from hypothesis import HealthCheck, Phase, assume, example, given, settings, strategies as st
from scipy.spatial import cKDTree
from shapely import affinity
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.errors import ArgumentError, PdsError, SectionError
from conftest import chord_region, delaunay_alpha_faces, probe_gap, visible_pairs_closer_than
from regions import box_unions, star_polygons

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
from _hostile import (HOSTILE_ALPHAS, HOSTILE_BUDGETS, betti, box_mesh,  # noqa: E402
                      box_section, digest, hostile_geometries, mesh_union, stl_with_value)

EXAMPLES = int(os.environ.get("PDS_FUZZ_EXAMPLES", "10"))
fuzz = settings(max_examples=EXAMPLES, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.function_scoped_fixture])
ASPECT_BOUND = 4 * math.sqrt(3)
CLEAN_ERRORS = (PdsError, OSError)
"""What bad input may raise: the package's error type (a ValueError), or OSError for files."""


# --- independent oracles -----------------------------------------------------------

def triangles(vertices, faces):
    return shapely.polygons(np.asarray(vertices)[np.asarray(faces)])


def ulp_slack(points, alpha) -> float:
    """Rounding of differences of coordinates this large, relative to alpha."""
    return 16 * np.spacing(np.abs(points).max(initial=1.0)) / alpha


def assert_certified_mesh(mesh, region_geometry, alpha):
    """Theorem 1 and the sampling conditions, measured without the package."""
    points, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    slack = 1e-9 + ulp_slack(points, alpha)
    assert len(faces) > 0
    separation = cKDTree(points).query(points, k=2)[0][:, 1].min()
    assert separation >= alpha * (1 - slack)
    assert probe_gap(region_geometry, points, alpha / 20) <= alpha * (1 + slack)
    a, b, c = (points[faces[:, k]] for k in range(3))
    lengths = np.stack([np.hypot(*(b - a).T), np.hypot(*(c - b).T), np.hypot(*(a - c).T)])
    area = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    assert (area > 0).all()                                      # counter-clockwise
    assert (lengths.max(axis=0) ** 2 / area).max() <= ASPECT_BOUND * (1 + slack)
    union = shapely.union_all(triangles(points, faces))
    assert math.isclose(union.area, area.sum(), rel_tol=1e-9 + slack)   # no overlaps
    # samples lie in the region (to rounding: a buffer of a few ulps is itself rounded)
    assert shapely.distance(region_geometry, shapely.points(points)).max() <= alpha * slack


def assert_certified_conforming_mesh(mesh, alpha, seed):
    """Theorem 1, and the separation and the outline with the visibility rule, measured
    without the package: samples that see each other through the region bounded by the
    chords are alpha apart, and the triangles tile that region."""
    points, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    slack = 1e-9 + ulp_slack(points, alpha)
    rings = pds.poisson_disc(mesh.region, alpha, seed=seed, conforming=True).rings
    domain = chord_region(points, rings, mesh.region)
    assert not len(visible_pairs_closer_than(points, domain, alpha * (1 - slack)))
    a, b, c = (points[faces[:, k]] for k in range(3))
    lengths = np.stack([np.hypot(*(b - a).T), np.hypot(*(c - b).T), np.hypot(*(a - c).T)])
    area = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    assert (area > 0).all()
    assert (lengths.max(axis=0) ** 2 / area).max() <= ASPECT_BOUND * (1 + slack)
    union = shapely.union_all(triangles(points, faces))
    assert math.isclose(union.area, area.sum(), rel_tol=1e-9 + slack)
    assert union.symmetric_difference(domain).area <= (1e-9 + slack) * domain.area


def refused_cleanly(call, *args, **kwargs):
    """Run ``call``; return its result, or None when it refused with a clean error."""
    try:
        return call(*args, **kwargs)
    except CLEAN_ERRORS as error:
        message = str(error)
        assert message and "Traceback" not in message
        return None


def conforming_mesh(geometry, region, alpha, seed):
    """The conforming mesh of ``region``; where its ring runs back onto itself within
    rounding through a vertex (a star's points all at y = 0), which the complex refuses,
    that of the region ``repair=True`` makes of ``geometry``, which drops those spikes:
    they are at most ``FOLD_WIDTH`` float spacings wide, so only that much area goes."""
    try:
        return pds.mesh_region(region, alpha, seed=seed)
    except ArgumentError as error:
        if "runs back onto itself" not in str(error):
            raise
    repaired = pds.Region.from_shapely(geometry, repair=True)
    width = pds.region.FOLD_WIDTH * region.resolution
    assert abs(repaired.area - region.area) <= width * region.perimeter
    return pds.mesh_region(repaired, alpha, seed=seed)


# --- strategies --------------------------------------------------------------------

geometries = st.one_of(star_polygons(), box_unions())


@st.composite
def placed_geometries(draw, offsets=(0.0, 1e3, 1e6, 1e8)):
    """A random region, scaled and moved far from the origin."""
    geometry = draw(geometries)
    scale = draw(st.sampled_from([1e-3, 1.0, 1e3]))
    offset = draw(st.sampled_from(offsets)) * scale
    angle = draw(st.floats(0, 360))
    geometry = affinity.rotate(geometry, angle, origin=(0, 0))
    geometry = affinity.scale(geometry, scale, scale, origin=(0, 0))
    return affinity.translate(geometry, offset, -0.5 * offset)


hostile_alphas = st.one_of(
    st.sampled_from(HOSTILE_ALPHAS),
    st.floats(allow_nan=True, allow_infinity=True).filter(lambda a: not 1e-3 < abs(a) < 1e6))

hostile_budgets = st.sampled_from([*HOSTILE_BUDGETS, None])


# --- regions and meshes ------------------------------------------------------------

@fuzz
@given(geometry=placed_geometries(), fraction=st.floats(0.04, 0.3), seed=st.integers(0, 2**16))
def test_random_regions_get_certified_meshes(geometry, fraction, seed):
    region = refused_cleanly(pds.Region.from_shapely, geometry)
    if region is None:                  # moved and scaled, the outline may cross itself
        assert not geometry.is_valid or geometry.area == 0
        return
    alpha = fraction * math.sqrt(region.area)
    before = digest(region, geometry)
    paper = pds.mesh_region(region, alpha, seed=seed, conforming=False)
    assert_certified_mesh(paper, region.geometry, alpha)
    # a conforming mesh keeps short edges and sharp corners, exceptions to Theorem 1 that
    # its certificate must report: whenever it says ok, the mesh is certified
    mesh = conforming_mesh(geometry, region, alpha, seed)
    if mesh.certificate().ok:
        assert_certified_conforming_mesh(mesh, alpha, seed)
    assert digest(region, geometry) == before


@fuzz
@given(geometry=geometries, seed=st.integers(0, 2**16))
def test_auto_alpha_keeps_the_topology_or_says_why(geometry, seed):
    """alpha='auto' gives a mesh with the region's components and holes (counted by
    shapely on the union of the triangles), or a clean error, or a warning."""
    region = pds.Region.from_shapely(geometry)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = refused_cleanly(pds.mesh_region, region, "auto", seed=seed, max_samples=10_000)
    if mesh is None or caught:
        return
    union = mesh_union(mesh.vertices, mesh.faces)
    assert betti(union) == betti(region.geometry)


@fuzz
@example(alpha=1e-300)
@given(alpha=hostile_alphas)
def test_hostile_alphas_are_refused_cleanly(alpha):
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    mesh = refused_cleanly(pds.mesh_region, region, alpha, max_samples=10_000)
    if mesh is None:
        return
    assert not isinstance(alpha, (bool, str)) and float(alpha) > 1e-3
    if len(mesh.faces) == 0:                   # an alpha too large: the certificate says so
        assert not mesh.certificate().ok
    if mesh.certificate().ok:
        assert_certified_mesh(mesh, region.geometry, float(alpha))


@fuzz
@example(budget=0, call="mesh")
@given(budget=hostile_budgets, call=st.sampled_from(["mesh", "suggest", "auto"]))
def test_hostile_sample_budgets_are_refused_cleanly(budget, call):
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    calls = {"mesh": lambda: pds.mesh_region(region, 0.1, max_samples=budget),
             "suggest": lambda: pds.suggest_alpha(region, max_samples=budget),
             "auto": lambda: pds.mesh_region(region, "auto", max_samples=budget)}
    result = refused_cleanly(calls[call])
    if result is not None:                    # None is the default budget
        assert budget is None or (isinstance(budget, int) and not isinstance(budget, bool)
                                  and budget >= 1)


@pytest.mark.parametrize("alpha", [1e-300, 5e-324, True])
def test_extreme_alphas_are_refused_with_the_package_error(alpha):
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    with pytest.raises(PdsError, match="alpha"):
        pds.mesh_region(region, alpha)


def test_an_alpha_larger_than_the_region_is_reported_by_the_certificate():
    mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 1e300, conforming=False)
    assert len(mesh.faces) == 0 and not mesh.certificate().ok
    assert "keep it with alpha <=" in str(mesh.certificate())
    # a conforming mesh keeps the four corners: two triangles, but samples 1e-300 alpha apart
    conforming = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 1e300)
    assert len(conforming.faces) == 2 and not conforming.certificate().ok


def test_zero_sample_budget_is_refused_with_the_package_error():
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    with pytest.raises(PdsError, match="max_samples"):
        pds.mesh_region(region, 0.1, max_samples=0)


hostile_values = st.sampled_from(hostile_geometries())


@fuzz
@given(geometry=hostile_values, repair=st.booleans())
def test_hostile_geometries_make_valid_regions_or_clean_errors(geometry, repair):
    region = refused_cleanly(pds.Region.from_shapely, geometry, repair=repair)
    if region is not None:
        assert region.area > 0 and region.geometry.is_valid
        assert np.isfinite(shapely.get_coordinates(region.geometry)).all()


@pytest.mark.parametrize("size", [1e-150, 1e-300])
def test_certificate_of_a_vanishing_region_is_refused_or_right(size):
    region = refused_cleanly(pds.Region.from_shapely, box(0, 0, size, size))
    mesh = region and refused_cleanly(pds.mesh_region, region, size / 4)
    if mesh is not None:
        certificate = refused_cleanly(mesh.certificate)
        assert certificate is None or certificate.ok


# --- point sets and the complex -----------------------------------------------------

@st.composite
def point_sets(draw):
    """Random, lattice (cocircular), collinear and clustered point sets, at any offset."""
    kind = draw(st.sampled_from(["random", "lattice", "collinear", "clusters", "circle"]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    n = draw(st.integers(3, 300))
    if kind == "random":
        points = rng.random((n, 2))
    elif kind == "lattice":
        side = max(2, int(math.sqrt(n)))
        points = np.stack(np.meshgrid(np.arange(side), np.arange(side)), -1).reshape(-1, 2) / side
    elif kind == "collinear":
        points = np.column_stack([np.sort(rng.random(n)), np.zeros(n)])
    elif kind == "circle":
        angles = np.arange(min(n, 24)) * 2 * np.pi / min(n, 24)
        points = np.column_stack([np.cos(angles), np.sin(angles)])
    else:
        centres = rng.random((4, 2))
        points = centres[rng.integers(0, 4, n)] + 1e-6 * rng.random((n, 2))
    offset = draw(st.sampled_from([0.0, 1e3, 1e6]))
    return np.unique(points.astype(float) + offset, axis=0)


@fuzz
@given(points=point_sets(), scale=st.floats(0.2, 1.5))
def test_complex_matches_delaunay_and_does_not_overlap(points, scale):
    alpha = scale * math.sqrt(np.ptp(points, axis=0).prod() / len(points) + 1e-12) + 1e-9
    before = digest(points)
    faces = refused_cleanly(pds.solid_alpha_complex, points, alpha)
    assert digest(points) == before
    if faces is None:
        return
    flat = len(points) < 3 or np.linalg.matrix_rank(points - points[0]) < 2
    # Qhull is exact only near the origin: translate (exactly, by Sterbenz) before it
    oracle = np.empty((0, 3), int) if flat else delaunay_alpha_faces(points - points.min(axis=0),
                                                                      alpha)
    area = shapely.area(triangles(points, faces)).sum()
    union = shapely.union_all(triangles(points, faces)).area
    expected = shapely.union_all(triangles(points, oracle)).area if len(oracle) else 0.0
    tolerance = 1e-9 * max(1.0, np.ptp(points, axis=0).prod()) + 1e3 * np.spacing(
        np.abs(points).max()) * np.ptp(points, axis=0).max()
    assert math.isclose(area, union, rel_tol=1e-9, abs_tol=tolerance)          # no overlaps
    assert math.isclose(union, expected, rel_tol=1e-9, abs_tol=tolerance)      # Delaunay's


@fuzz
@example(points=np.array([[1e308, 1e308], [-1e308, 0], [0, 1]]), alpha=0.5)
@given(points=st.sampled_from([
    np.zeros((0, 2)), np.zeros((5, 3)), np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 1.0]]),
    np.array([[0.0, math.nan], [1, 0], [0, 1]]), np.array([[0.0, math.inf], [1, 0], [0, 1]]),
    [[0, 0], [1, 0], [0, "x"]], "points", None, np.array([[1e308, 1e308], [-1e308, 0], [0, 1]]),
]), alpha=st.sampled_from([0.5, 1e300, 1e-300]))
def test_hostile_point_sets_are_refused_cleanly(points, alpha):
    faces = refused_cleanly(pds.solid_alpha_complex, points, alpha)
    if faces is not None:
        assert np.asarray(faces).reshape(-1, 3).shape[1] == 3


# --- SVG drawings and their mutations ------------------------------------------------

@st.composite
def svg_drawings(draw):
    """A filled SVG drawing and the shapely geometry it draws (the area oracle)."""
    shapes, elements = [], []
    for _ in range(draw(st.integers(1, 4))):
        x, y = draw(st.floats(0, 80)), draw(st.floats(0, 80))
        w, h = draw(st.floats(2, 20)), draw(st.floats(2, 20))
        if draw(st.booleans()):
            elements.append(f'<rect x="{x!r}" y="{y!r}" width="{w!r}" height="{h!r}"/>')
            shapes.append(box(x, 100 - y - h, x + w, 100 - y))
        else:
            elements.append(f'<circle cx="{x!r}" cy="{y!r}" r="{w!r}"/>')
            shapes.append(Point(x, 100 - y).buffer(w, quad_segs=256))
    text = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">'
            + "".join(elements) + "</svg>")
    return text, shapely.union_all(shapes)


_NUMBER = re.compile(r"(?<=\")-?[0-9.]+(?:e[-+]?[0-9]+)?(?=\")")


@st.composite
def svg_mutations(draw):
    """A drawing with one hostile edit: truncated, a number replaced, bytes inserted,
    a tag doubled, an entity or <use> expansion, a huge or degenerate viewBox."""
    text, _ = draw(svg_drawings())
    kind = draw(st.sampled_from(["truncate", "number", "bytes", "viewbox", "use", "entity",
                                 "nesting"]))
    if kind == "truncate":
        return text[:draw(st.integers(0, len(text) - 1))]
    if kind == "number":
        numbers = list(_NUMBER.finditer(text))
        match = numbers[draw(st.integers(0, len(numbers) - 1))]
        value = draw(st.sampled_from(["0", "-5", "1e300", "-1e300", "nan", "inf", "1e-300",
                                      "", "x", "1e30000"]))
        return text[:match.start()] + value + text[match.end():]
    if kind == "bytes":
        where = draw(st.integers(0, len(text)))
        return text[:where] + draw(st.text(max_size=8)) + text[where:]
    if kind == "viewbox":
        box_text = draw(st.sampled_from(["0 0 0 0", "0 0 -1 -1", "0 0 1e300 1e300",
                                         "0 0 1e-300 1e-300", "nan nan nan nan", "0 0 100"]))
        return text.replace('viewBox="0 0 100 100"', f'viewBox="{box_text}" '
                            + draw(st.sampled_from(['', 'width="0"', 'height="0" width="0"'])))
    if kind == "use":
        depth = draw(st.integers(1, 3))
        defs = ['<g id="g0"><rect width="1" height="1"/></g>']
        defs += [f'<g id="g{i}">' + f'<use href="#g{i - 1}"/>' * 10 + "</g>"
                 for i in range(1, depth + 1)]
        return text.replace("</svg>", f"<defs>{''.join(defs)}</defs><use href=\"#g{depth}\"/>"
                                      "</svg>")
    if kind == "entity":
        return ('<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY a "aaaaaaaaaa">'
                '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
                '<!ENTITY x SYSTEM "file:///etc/passwd">]>'
                + text.replace("</svg>", "<text>&b;&x;</text></svg>"))
    return text.replace("<rect", "<g><g><g><rect").replace("/>", "/></g></g></g>", 1)


def _write(tmp_path, name, content):
    path = tmp_path / name
    path.write_bytes(content if isinstance(content, bytes) else content.encode("utf-8"))
    return path


@fuzz
@given(drawing=svg_drawings())
def test_svg_drawings_give_the_drawn_area(tmp_path_factory, drawing):
    text, geometry = drawing
    path = _write(tmp_path_factory.mktemp("svg"), "drawing.svg", text)
    region = pds.load_svg(path, tolerance=1e-3)
    assert math.isclose(region.area, geometry.area, rel_tol=1e-3)
    assert betti(region.geometry) == betti(geometry)


@fuzz
@example(text='<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 0 0"><rect width="2" '
              'height="2"/></svg>')
@given(text=svg_mutations())
def test_mutated_svgs_give_regions_or_clean_errors(tmp_path_factory, text):
    path = _write(tmp_path_factory.mktemp("svg"), "mutated.svg", text)
    before = digest(path)
    region = refused_cleanly(pds.load_svg, path)
    assert digest(path) == before
    if region is not None:
        assert region.area > 0 and region.geometry.is_valid
        assert np.isfinite(shapely.get_coordinates(region.geometry)).all()
        assert "root:" not in str(shapely.to_wkt(region.geometry))


# --- DXF drawings and their mutations -------------------------------------------------

@st.composite
def dxf_mutations(draw):
    """A plate drawing (a polyline outline with a bulge and a circle hole, in a block
    inserted twice) as ASCII DXF, with one number of its ENTITIES or BLOCKS sections
    replaced by a hostile value, or one line deleted, or the text cut short."""
    import io

    import ezdxf

    doc = ezdxf.new("R2010")
    block = doc.blocks.new("PLATE")
    block.add_lwpolyline([(0, 0, 0, 0, 0.3), (20, 0), (20, 10), (0, 10)], format="xyseb",
                         close=True)
    block.add_circle((5, 5), 2)
    doc.modelspace().add_blockref("PLATE", (0, 0))
    doc.modelspace().add_blockref("PLATE", (30, 0), dxfattribs={"rotation": 30})
    stream = io.StringIO()
    doc.write(stream)
    lines = stream.getvalue().split("\n")
    first = lines.index("BLOCKS")
    numbers = [i for i in range(first, len(lines)) if i and lines[i - 1].strip() in
               ("10", "20", "40", "41", "42", "50", "70", "90")]
    kind = draw(st.sampled_from(["number", "number", "delete", "cut"]))
    where = draw(st.sampled_from(numbers))
    if kind == "number":
        lines[where] = draw(st.sampled_from(["nan", "inf", "-1e308", "1e308", "1e400", "0",
                                             "-1", "1e-320", "x", "", "4294967297"]))
    elif kind == "delete":
        del lines[where]
    else:
        lines = lines[:where]
    return "\n".join(lines)


@fuzz
@given(text=dxf_mutations())
def test_mutated_dxfs_give_regions_or_clean_errors(tmp_path_factory, text):
    path = _write(tmp_path_factory.mktemp("dxf"), "mutated.dxf", text)
    before = digest(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        region = refused_cleanly(pds.load_dxf, path)
    assert digest(path) == before
    if region is not None:
        assert region.area > 0 and region.geometry.is_valid
        assert np.isfinite(shapely.get_coordinates(region.geometry)).all()


# --- solids, STL files and their mutations -------------------------------------------

@st.composite
def box_scenes(draw):
    """Axis-aligned boxes, overlapping or nested, as one mesh of several shells, and
    the height of a cutting plane through the middle of the first."""
    boxes = []
    for _ in range(draw(st.integers(1, 3))):
        # no subnormal corner: the oracle's union (GEOS) of boxes at x = 2.2e-311 and
        # x = -0.5 is 0.1875 short (pds's is right: 2.125)
        x, y, z = (draw(st.floats(-2, 2, allow_subnormal=False)) for _ in range(3))
        dx, dy, dz = (draw(st.floats(0.3, 2)) for _ in range(3))
        boxes.append((x, y, z, x + dx, y + dy, z + dz))
    x0, y0, z0, x1, y1, z1 = boxes[0]
    height = z0 + draw(st.floats(0.2, 0.8)) * (z1 - z0)
    assume(all(abs(height - z) > 1e-3 for b in boxes for z in (b[2], b[5])))
    return boxes, height


@fuzz
@example(scene=([(0, 0, 0, 2, 1, 1), (1, 0, 0, 3, 1, 1)], 0.5), offset=0.0)
@given(scene=box_scenes(), offset=st.sampled_from([0.0, 1e4, 1e8]))
def test_sections_of_box_scenes_are_the_union_or_a_clean_error(scene, offset):
    """Several shells, overlapping or nested (as multi-body STL exports are): the solid
    is where the winding number is >= 1, so the section is the union of the shells'."""
    boxes, height = scene
    mesh = box_mesh(boxes, (offset, -offset, 0.0))
    before = digest(mesh)
    region = refused_cleanly(pds.section, mesh, (offset, -offset, height), (0, 0, 1))
    assert digest(mesh) == before
    if region is not None:
        expected = box_section(boxes, height).area
        assert math.isclose(region.area, expected, rel_tol=1e-6)
        oracle = trimesh.Trimesh(mesh.vertices, mesh.faces).section(
            plane_origin=(offset, -offset, height), plane_normal=(0, 0, 1))
        assert oracle is not None


@st.composite
def stl_mutations(draw):
    """A binary STL of a box with one hostile edit: truncated, bytes flipped, a float
    replaced by NaN, inf, 1e30 or a denormal, the triangle count lied about."""
    data = bytearray(trimesh.creation.box(extents=(2, 2, 2)).export(file_type="stl"))
    kind = draw(st.sampled_from(["truncate", "flip", "float", "count", "ascii"]))
    if kind == "truncate":
        return bytes(data[:draw(st.integers(0, len(data) - 1))])
    if kind == "flip":
        for _ in range(draw(st.integers(1, 8))):
            data[draw(st.integers(84, len(data) - 1))] ^= draw(st.integers(1, 255))
        return bytes(data)
    if kind == "float":
        facet = draw(st.integers(0, 11))
        where = 84 + 50 * facet + 12 + 4 * draw(st.integers(0, 8))
        value = draw(st.sampled_from([math.nan, math.inf, 1e30, -1e30, 1e-40, 3e38]))
        data[where:where + 4] = struct.pack("<f", value)
        return bytes(data)
    if kind == "count":
        data[80:84] = struct.pack("<I", draw(st.sampled_from([0, 13, 2**31, 2**32 - 1])))
        return bytes(data)
    return b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n" \
           + draw(st.binary(max_size=40)) + b"\nendsolid x\n"


@fuzz
@example(data=stl_with_value(1e30, 3), height=0.0)
@given(data=stl_mutations(), height=st.floats(-0.9, 0.9))
def test_mutated_stls_give_the_right_section_or_a_clean_error(tmp_path_factory, data, height):
    path = _write(tmp_path_factory.mktemp("stl"), "part.stl", data)
    before = digest(path)
    region = refused_cleanly(pds.section, path, (0, 0, height), (0, 0, 1))
    assert digest(path) == before
    mesh = trimesh.load_mesh(path) if region is not None else None
    if mesh is not None and mesh.is_watertight:    # a flipped byte may leave a closed mesh
        oracle = mesh.section(plane_origin=(0, 0, height), plane_normal=(0, 0, 1))
        planar, _ = oracle.to_2D()
        planar.merge_vertices()
        assert math.isclose(region.area, planar.area, rel_tol=1e-6)


# --- the command line ---------------------------------------------------------------

@pytest.fixture(scope="module")
def cli_inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cli_inputs")
    box_mesh([(0, 0, 0, 2, 1, 1)]).export(folder / "box.stl")
    _write(folder, "drawing.svg", '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">'
                                  '<path fill-rule="evenodd" d="M0 0H10V10H0Z M3 3H7V7H3Z"/></svg>')
    _write(folder, "garbage.stl", b"\x00\x01garbage" * 20)
    (folder / "folder.stl").mkdir()
    return folder


@contextlib.contextmanager
def _inside(folder):
    """Run the block in ``folder`` (contextlib.chdir needs Python 3.11)."""
    here = os.getcwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(here)


@st.composite
def cli_invocations(draw):
    """argv for pds-mesh: inputs, outputs, alphas, planes and options, good and bad."""
    source = draw(st.sampled_from(["box.stl", "drawing.svg", "garbage.stl", "missing.stl",
                                   "folder.stl"]))
    output = draw(st.sampled_from(["out.ply", "out.obj", "out.stl", "out", "no/dir/out.ply",
                                   "exists", "out.PLY"]))
    argv = [source, "-o", output]
    alpha = draw(st.sampled_from(["0.25", "auto", "0", "-1", "nan", "inf", "1e-300", "1e300",
                                  "x", None]))
    if alpha is not None:
        argv += ["--alpha", alpha]
    argv += draw(st.sampled_from([[], ["--axis", "z"], ["--axis", "q"],
                                  ["--plane-normal", "0,0,1"], ["--plane-normal", "0,0,0"],
                                  ["--plane-normal", "nan,0,1"]]))
    argv += draw(st.sampled_from([[], ["--at", "0.5"], ["--at", "0.25,0.75"], ["--at", "5"],
                                  ["--at", "0"], ["--slices", "2"], ["--slices", "0"],
                                  ["--slices", "1000000000"], ["--plane-origin", "1,0.5,0.5"]]))
    argv += draw(st.sampled_from([[], ["--report", "r.json"], ["--report", "exists"],
                                  ["--plot", "p.png"], ["--plot", "p.xyz"]]))
    argv += draw(st.sampled_from([[], ["--seed", "3"], ["--seed", "x"], ["--max-samples", "0"],
                                  ["--max-samples", "50"], ["--quiet"], ["--jobs", "0"]]))
    return argv


@fuzz
@given(argv=cli_invocations())
def test_cli_exits_cleanly_and_leaves_complete_files_or_none(cli_inputs, tmp_path_factory, argv):
    from pds_plugin.cli import main

    work = tmp_path_factory.mktemp("cli")
    (work / "exists").mkdir()
    argv = [str(cli_inputs / argv[0]), *argv[1:]]
    inputs = {p: digest(p) for p in cli_inputs.iterdir() if p.is_file()}
    stderr = io.StringIO()
    with _inside(work), contextlib.redirect_stderr(stderr), \
            contextlib.redirect_stdout(io.StringIO()):
        status = main(argv)
    lines = [line for line in stderr.getvalue().splitlines() if line.strip()]
    assert {p: digest(p) for p in inputs} == inputs                 # the input is untouched
    assert status in (0, 1, 2)
    assert not any("Traceback" in line for line in lines)
    written = sorted(p.name for p in work.iterdir() if p.name != "exists")
    if status == 0:
        meshes = [p for p in work.iterdir() if p.suffix.lower() in (".ply", ".obj", ".stl")]
        assert meshes
        for path in meshes:
            loaded = trimesh.load_mesh(path, process=False)
            assert len(loaded.faces) > 0 and np.isfinite(loaded.vertices).all()
    else:
        errors = [line for line in lines if line.startswith("pds-mesh: error: ")]
        assert len(errors) == 1, lines
        assert written == [], f"a failed run left {written}"


# --- real CAD exports (issue 20) ------------------------------------------------------

@functools.lru_cache(maxsize=None)
def _cad_corpus_rest():
    from _cad_corpus import rest_of_corpus

    return rest_of_corpus()


@settings(fuzz, phases=[Phase.explicit, Phase.reuse, Phase.generate])   # a case is minimal
@given(data=st.data())
def test_sections_of_cad_exports_are_certified_or_refused_by_section(data):
    """A section of the CAD corpus (bench/_cad_corpus.py) beyond tests/test_cad_corpus.py's
    slice: certified in its mode (within a budget of 20,000 samples), its triangles'
    union with the section's components and holes, or refused by ``pds.section`` because
    the plane has no valid section (an open part, a gap between bodies). The drawn name
    reproduces it: ``python bench/cad_corpus.py --only NAME``."""
    from _cad_corpus import case, mesh

    name, mode = data.draw(st.sampled_from(_cad_corpus_rest()), label="case, mode")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            region = case(name).region()
        except SectionError:
            return
        result = mesh(region, mode, max_samples=20_000)
    cert = result.certificate()
    assert cert.ok_with_exceptions, f"{name} / {mode}:\n{cert}"
    # the certificate found no overlap: the triangles are a coverage, united fast
    union = shapely.coverage_union_all(triangles(result.vertices, result.faces))
    assert betti(union) == betti(region.geometry)
