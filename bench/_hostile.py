"""The bad and hostile inputs bench/reliability.py tries, by class, each with its oracle.

A case builds its inputs in a scratch folder and returns a :class:`Trial`: the call to
make, the inputs whose digest must not change, and a check of the result. The check
never trusts the package: areas and Betti numbers come from shapely, separations from
scipy's KD-tree, Delaunay triangles from Qhull, sections of boxes from the union of
rectangles, and files from re-reading them. A check returns ``None`` when the result is
right, or ``(verdict, message)`` with verdict "clean" (an honest refusal, e.g. a CLI
error line), "other" (a traceback, a crash), "hang" (a runaway) or "wrong".

The hostile values are shared with the fuzz suite (tests/test_fuzz.py).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import signal
import struct
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

HOSTILE_ALPHAS = [0, -1, -0.0, math.nan, math.inf, -math.inf, 1e-300, 5e-324, 1e300, True,
                  False, None, "abc", "", [0.1], 1j, np.float64(math.nan), np.array([0.1, 0.2])]
HOSTILE_BUDGETS = [0, -1, 1.5, True, math.nan, "many", 2**70, -2**70]


def hostile_geometries():
    """Shapely (and non-shapely) values that are not, or barely, a region."""
    import shapely
    from shapely.geometry import LineString, Point, Polygon, box

    return [shapely.Polygon(), Point(0, 0), LineString([(0, 0), (1, 1)]),
            Polygon([(0, 0), (1, 1), (1, 0), (0, 1)]), Polygon([(0, 0), (1, 0), (2, 0)]),
            Polygon([(0, 0), (math.nan, 0), (1, 1)]), Polygon([(0, 0), (math.inf, 0), (1, 1)]),
            box(0, 0, 1e-300, 1e-300), box(0, 0, 1e-150, 1e-150),
            box(-1e300, -1e300, 1e300, 1e300), "POLYGON ((0 0, 1 0, 1 1))", None, 3.0,
            shapely.GeometryCollection([Point(0, 0), box(0, 0, 1, 1)])]


def stl_bytes(mesh) -> bytes:
    return mesh.export(file_type="stl")


def stl_with_value(value, offset=0) -> bytes:
    """A binary STL of a 2x2x2 box centred on the origin whose float number ``offset``
    (of the first facet's 12: normal, then three vertices) is replaced by ``value``."""
    import trimesh

    data = bytearray(stl_bytes(trimesh.creation.box(extents=(2, 2, 2))))
    where = 84 + 4 * offset
    data[where:where + 4] = struct.pack("<f", value)
    return bytes(data)


def box_mesh(boxes, offset=(0.0, 0.0, 0.0)):
    """One trimesh of several box shells ``(x0, y0, z0, x1, y1, z1)``, as multi-body
    exports write them (overlapping or nested shells are not merged)."""
    import trimesh

    shells = []
    for x0, y0, z0, x1, y1, z1 in boxes:
        shell = trimesh.creation.box(extents=(x1 - x0, y1 - y0, z1 - z0))
        shell.apply_translation(((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2))
        shells.append(shell)
    mesh = trimesh.util.concatenate(shells)
    mesh.apply_translation(offset)
    return mesh


def box_section(boxes, height):
    """The oracle: the section of the union of boxes is the union of their rectangles."""
    import shapely
    from shapely.geometry import box

    return shapely.union_all([box(x0, y0, x1, y1) for x0, y0, z0, x1, y1, z1 in boxes
                              if z0 < height < z1])


# --- oracles ---------------------------------------------------------------------

def betti(geometry) -> tuple[int, int]:
    """(components, holes) of a shapely geometry."""
    import shapely

    parts = [p for p in shapely.get_parts(geometry) if not p.is_empty]
    return len(parts), sum(len(p.interiors) for p in parts)


def mesh_betti(vertices, faces) -> tuple[int, int]:
    """(components, holes) of the union of the closed triangles, from the simplicial
    complex itself: components joined through shared vertices (two triangles touching
    at a corner make one connected set, where shapely counts two parts), and
    holes = components - Euler characteristic (V - E + F). Valid for triangles that do
    not overlap (checked before)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    faces = np.asarray(faces)
    used = np.unique(faces)
    links = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]]])
    graph = coo_matrix((np.ones(len(links)), (links[:, 0], links[:, 1])),
                       shape=(len(vertices), len(vertices)))
    labels = connected_components(graph, directed=False)[1]
    components = len(np.unique(labels[used]))
    edges = np.unique(np.sort(np.concatenate([links, faces[:, [2, 0]]]), axis=1), axis=0)
    return components, components - (len(used) - len(edges) + len(faces))


def mesh_union(vertices, faces):
    import shapely

    return shapely.union_all(shapely.polygons(np.asarray(vertices)[np.asarray(faces)]))


def mesh_problem(mesh, geometry, alpha, topology=True, theorem=True) -> str | None:
    """What is wrong with a mesh of ``geometry`` at ``alpha`` (None if nothing): with
    ``theorem``, samples closer than alpha, a region point farther than alpha from them, a
    triangle above 4√3; always a flat or clockwise triangle, overlapping triangles; with
    ``topology``, other Betti numbers."""
    points, faces = np.asarray(mesh.vertices, float), np.asarray(mesh.faces)
    if len(faces) == 0:
        return "a mesh without triangles"
    slack = 1e-9 + 16 * np.spacing(np.abs(points).max()) / alpha
    a, b, c = (points[faces[:, k]] for k in range(3))
    area = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    if (area <= 0).any():
        return "a flat or clockwise triangle"
    if theorem:
        problem = _theorem_problem(points, faces, area, geometry, alpha, slack,
                                   getattr(mesh, "conforming", False))
        if problem is not None:
            return problem
    union = mesh_union(points, faces)
    if not math.isclose(union.area, area.sum(), rel_tol=1e-6 + slack):
        return f"overlapping triangles (area {area.sum():.9g}, union {union.area:.9g})"
    if topology and mesh_betti(points, faces) != betti(geometry):
        return f"Betti numbers {mesh_betti(points, faces)} for a region with {betti(geometry)}"
    return None


def _theorem_problem(points, faces, area, geometry, alpha, slack, conforming) -> str | None:
    """Samples closer than alpha (for a conforming mesh: that see each other through the
    region), a region point farther than alpha from every sample, or a triangle above the
    aspect bound 4√3 (Theorem 1 and the sampling conditions)."""
    import shapely
    from scipy.spatial import cKDTree

    pairs = cKDTree(points).query_pairs(alpha * (1 - slack), output_type="ndarray")
    if conforming and len(pairs):     # samples conflict only if they see each other
        segments = shapely.linestrings(points[pairs])
        pairs = pairs[shapely.covers(shapely.buffer(geometry, alpha * slack), segments)]
    if len(pairs):
        separation = np.hypot(*(points[pairs[:, 0]] - points[pairs[:, 1]]).T).min()
        return f"samples {separation / alpha:.6g} alpha apart"
    probes = shapely.get_coordinates(shapely.segmentize(geometry.boundary, alpha / 10))
    interior = shapely.get_coordinates(shapely.points(np.random.default_rng(0).uniform(
        *np.reshape(geometry.bounds, (2, 2)), size=(2000, 2))))
    interior = interior[shapely.contains_xy(geometry, *interior.T)]
    gap = cKDTree(points).query(np.concatenate([probes, interior]))[0].max()
    if gap > alpha * (1 + slack):
        return f"a point of the region {gap / alpha:.6g} alpha from every sample"
    a, b, c = (points[faces[:, k]] for k in range(3))
    longest = np.max([np.hypot(*(b - a).T), np.hypot(*(c - b).T), np.hypot(*(a - c).T)], axis=0)
    if (longest ** 2 / area).max() > 4 * math.sqrt(3) * (1 + slack):
        return "a triangle above the aspect bound 4√3"
    return None


def digest(*values) -> str:
    """A digest of inputs: arrays, shapely geometries, Regions, meshes, files."""
    import shapely

    h = hashlib.sha256()
    for value in values:
        if isinstance(value, Path):
            h.update(value.read_bytes() if value.is_file() else b"<not a file>")
        elif isinstance(value, shapely.Geometry):
            h.update(shapely.to_wkb(value))
        elif hasattr(value, "geometry") and hasattr(value, "frame"):
            h.update(shapely.to_wkb(value.geometry) + value.frame.tobytes())
        elif hasattr(value, "vertices") and hasattr(value, "faces"):
            h.update(np.asarray(value.vertices).tobytes() + np.asarray(value.faces).tobytes())
        elif isinstance(value, np.ndarray):
            h.update(value.tobytes())
        else:
            h.update(repr(value).encode())
    return h.hexdigest()


# --- cases -------------------------------------------------------------------------

@dataclass
class Trial:
    call: Callable
    inputs: list = field(default_factory=list)
    check: Callable = lambda result: None


@dataclass
class Case:
    name: str
    make: Callable          # make(folder: Path) -> Trial


def _square():
    import pds_plugin as pds
    from shapely.geometry import box

    return pds.Region.from_shapely(box(0, 0, 1, 1))


def _mesh_check(geometry, alpha, topology=True):
    def check(mesh):
        if len(mesh.faces) == 0 and not mesh.certificate().ok:
            return None        # alpha too large for any triangle: the certificate tells
        # a conforming mesh keeps sharp corners, short pieces and walls thinner than alpha,
        # exceptions to Theorem 1 that its certificate reports: then only the mesh itself
        # (orientation, overlaps, and the topology if claimed) must be right
        theorem = not mesh.conforming or mesh.certificate().ok
        problem = mesh_problem(mesh, geometry, float(alpha), topology, theorem)
        return None if problem is None else ("wrong", problem)
    return check


def alpha_cases():
    import pds_plugin as pds

    def case(alpha):
        def make(folder):
            region = _square()
            return Trial(lambda: pds.mesh_region(region, alpha, max_samples=100_000), [region],
                         _mesh_check(region.geometry, alpha if _number(alpha) else 1.0))
        return Case(f"alpha={alpha!r}", make)
    valid = [0.1, 0.37, 2.0, 1e-3, 1e-4]
    return [case(a) for a in HOSTILE_ALPHAS + valid]


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value) and value > 0


def budget_cases():
    import pds_plugin as pds

    cases = []
    for budget in HOSTILE_BUDGETS + [1, 10]:
        for call in ("mesh_region", "suggest_alpha", "auto"):
            def make(folder, budget=budget, call=call):
                region = _square()
                run = {"mesh_region": lambda: pds.mesh_region(region, 0.1, max_samples=budget),
                       "suggest_alpha": lambda: pds.suggest_alpha(region, max_samples=budget),
                       "auto": lambda: pds.mesh_region(region, "auto", max_samples=budget)}[call]
                return Trial(run, [region], lambda result: None if isinstance(budget, int) and
                             not isinstance(budget, bool) and budget >= 1 else
                             ("wrong", f"max_samples={budget!r} accepted"))
            cases.append(Case(f"{call}(max_samples={budget!r})", make))
    return cases


def geometry_cases():
    import pds_plugin as pds
    import shapely

    def case(geometry, repair):
        def make(folder):
            def check(region):
                if region.area > 0 and region.geometry.is_valid and \
                        np.isfinite(shapely.get_coordinates(region.geometry)).all():
                    return None
                return "wrong", f"made {region!r}"
            return Trial(lambda: pds.Region.from_shapely(geometry, repair=repair), [geometry],
                         check)
        text = str(geometry)[:40]
        return Case(f"Region.from_shapely({text}, repair={repair})", make)
    return [case(g, r) for g in hostile_geometries() for r in (False, True)]


def coordinate_cases():
    """Regions far from the origin or vanishingly small: mesh them right or refuse."""
    import pds_plugin as pds
    from shapely.geometry import Point, box

    def case(geometry, alpha, what):
        def make(folder):
            def run():
                region = pds.Region.from_shapely(geometry)
                mesh = pds.mesh_region(region, alpha)
                certificate = mesh.certificate()
                if certificate.betti_mesh != tuple(certificate.betti_region) and \
                        certificate.topology_ok:
                    raise AssertionError("certificate says ok for other Betti numbers")
                return mesh
            return Trial(run, [geometry], _mesh_check(geometry, alpha))
        return Case(f"{what}, alpha {alpha:g}", make)

    ring = Point(0, 0).buffer(1.0).difference(Point(0.3, 0).buffer(0.4))
    from shapely import affinity
    cases = []
    for offset in (0.0, 1e6, 1e8, 1e10, 1e12, 1e15):
        for alpha in (0.1, 0.05, 0.02):
            cases.append(case(affinity.translate(ring, offset, offset), alpha,
                              f"ring with a hole at {offset:g}"))
    for size in (1e-6, 1e-50, 1e-150, 1e-300):
        cases.append(case(box(0, 0, size, size), size / 4, f"square of side {size:g}"))
    cases.append(case(box(1e15, 1e15, 1e15 + 1, 1e15 + 1), 0.1, "unit square at 1e15"))
    return cases


def delaunay_area(points, alpha) -> float:
    """The oracle of the solid alpha-complex: the area of Qhull's Delaunay triangles whose
    circumradius is at most alpha."""
    from scipy.spatial import Delaunay

    if len(points) < 3 or np.linalg.matrix_rank(points - points[0]) < 2:
        return 0.0
    points = points - points.min(axis=0)         # exact (Sterbenz); Qhull is safe here
    tri = Delaunay(points).simplices
    a, b, c = (points[tri[:, k]] for k in range(3))
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    radius = (np.linalg.norm(b - a, axis=1) * np.linalg.norm(c - a, axis=1)
              * np.linalg.norm(c - b, axis=1) / (2 * cross))
    return mesh_union(points, tri[radius <= alpha]).area if (radius <= alpha).any() else 0.0


def complex_trial(points, alpha) -> Trial:
    """solid_alpha_complex(points, alpha), its triangles' area checked against Qhull's."""
    import pds_plugin as pds
    import shapely

    def check(faces):
        faces = np.asarray(faces)
        pts = np.asarray(points, float)
        area = 0.0 if not len(faces) else shapely.area(shapely.polygons(pts[faces])).sum()
        expected = delaunay_area(pts, alpha)
        if not math.isclose(area, expected, rel_tol=1e-6, abs_tol=1e-12):
            return "wrong", f"triangle area {area:.9g}, Delaunay's {expected:.9g}"
        return None
    return Trial(lambda: pds.solid_alpha_complex(points, alpha), [points], check)


def point_set_cases():
    """solid_alpha_complex on hostile point sets; accepted ones against Qhull."""
    def case(name, points, alpha):
        return Case(name, lambda folder: complex_trial(points, alpha))

    rng = np.random.default_rng(7)
    angles = np.arange(100) * 2 * np.pi / 100
    circle = np.column_stack([np.cos(angles), np.sin(angles)])
    lattice = np.stack(np.meshgrid(np.arange(30), np.arange(30)), -1).reshape(-1, 2) / 30.0
    return [
        case("no points", np.zeros((0, 2)), 0.5),
        case("3-column array", np.zeros((5, 3)), 0.5),
        case("duplicate points", np.array([[0.0, 0], [0, 0], [1, 1]]), 0.5),
        case("NaN coordinate", np.array([[0.0, math.nan], [1, 0], [0, 1]]), 0.5),
        case("infinite coordinate", np.array([[0.0, math.inf], [1, 0], [0, 1]]), 0.5),
        case("coordinates at ±1e308", np.array([[1e308, 1e308], [-1e308, 0], [0, 1]]), 0.5),
        case("strings", [[0, 0], [1, 0], [0, "x"]], 0.5),
        case("collinear points", np.column_stack([np.arange(50.0), np.zeros(50)]), 10.0),
        case("100 cocircular points", circle, 1.5),
        case("30x30 lattice, alpha 0.3", lattice, 0.3),
        case("5000 random points, alpha 10", rng.random((5000, 2)), 10.0),
        case("1000 random points at 1e6", rng.random((1000, 2)) + 1e6, 0.05),
        case("1000 random points, alpha 1e-300", rng.random((1000, 2)), 1e-300),
        case("1000 random points, alpha 1e300", rng.random((1000, 2)), 1e300),
    ]


_SVG = '<svg xmlns="http://www.w3.org/2000/svg" {attributes}>{body}</svg>'


def svg_cases():
    """SVG files: malformed, hostile (XXE, entity and <use> bombs, huge files), degenerate
    sizes, and drawings with a known area (filled) or known holes (outline)."""
    import pds_plugin as pds
    from shapely.geometry import Point, box

    def case(name, content, expected=None, holes=None, **options):
        def make(folder):
            path = folder / "drawing.svg"
            path.write_bytes(content() if callable(content) else content.encode())

            def check(region):
                if expected is not None and not math.isclose(region.area, expected, rel_tol=1e-3):
                    return "wrong", f"area {region.area:.6g}, drawn {expected:.6g}"
                if holes is not None and region.betti[1] != holes:
                    return "wrong", f"{region.betti[1]} holes, drawn {holes}"
                return None
            return Trial(lambda: pds.load_svg(path, **options), [path], check)
        return Case(name, make)

    square = '<rect width="10" height="10"/>'
    uses = ['<g id="g0"><rect width="1" height="1"/></g>'] + [
        f'<g id="g{i}">' + f'<use href="#g{i - 1}"/>' * 10 + "</g>" for i in range(1, 9)]
    use_bomb = _SVG.format(attributes='viewBox="0 0 10 10"',
                           body=f"<defs>{''.join(uses)}</defs><use href=\"#g8\"/>")
    laughs = ('<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY a "aaaaaaaaaa">'
              + "".join(f'<!ENTITY {chr(98 + i)} "{("&" + chr(97 + i) + ";") * 10}">'
                        for i in range(8))
              + ']>' + _SVG.format(attributes='viewBox="0 0 10 10"', body=square + "<text>&i;</text>"))
    xxe = ('<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY x SYSTEM "file:///etc/passwd">]>'
           + _SVG.format(attributes='viewBox="0 0 10 10"', body=square + "<text>&x;</text>"))

    def huge_comment():
        return (_SVG.format(attributes='viewBox="0 0 10 10"', body=square + "<!--{}-->")
                .replace("{}", "x" * 50_000_000).encode())

    def million_segments():
        steps = " ".join(f"L{(i % 1000) * 0.01:.2f} {(i // 1000) * 0.01:.2f}" for i in range(1_000_000))
        return _SVG.format(attributes='viewBox="0 0 10 10"', body=f'<path d="M0 0 {steps} Z"/>').encode()

    def outline(polygons, size):
        strokes = "".join(
            '<path fill="none" stroke="black" d="M' + " L".join(
                f"{float(x)!r} {float(size[1] - y)!r}" for x, y in p.exterior.coords) + '"/>'
            for p in polygons)
        return _SVG.format(attributes=f'viewBox="0 0 {size[0]} {size[1]}"', body=strokes)

    plate = [box(0, 0, 1000, 500)] + [Point(x, 250).buffer(r, quad_segs=16)
                                      for x, r in ((100, 1.0), (200, 2.0), (500, 50.0))]
    fine = [box(0, 0, 100, 100), Point(50, 50).buffer(30, quad_segs=7500)]
    return [
        case("empty file", ""),
        case("not XML", "this is not svg"),
        case("truncated", _SVG.format(attributes='viewBox="0 0 10 10"', body=square)[:40]),
        case("HTML, no <svg>", "<html><body>hi</body></html>"),
        case("XXE (external entity)", xxe, expected=100.0),
        case("billion laughs", laughs, expected=100.0),
        case("<use> bomb of 10^8 rects", use_bomb),
        case("50 MB comment", huge_comment, expected=100.0),
        case("1M-segment path", million_segments),
        case("viewBox 0 0 0 0", _SVG.format(attributes='viewBox="0 0 0 0"', body=square)),
        case("width and height 0", _SVG.format(attributes='width="0" height="0"', body=square)),
        case("viewBox with NaN", _SVG.format(attributes='viewBox="0 0 nan nan"', body=square)),
        case("Bézier control at 1e300",
             _SVG.format(attributes='viewBox="0 0 10 10"', body='<path d="M0 0 Q1e300 5 10 0 L5 5Z"/>')),
        case("circle of radius -5", _SVG.format(attributes='viewBox="0 0 10 10"',
                                                body='<circle cx="5" cy="5" r="-5"/>')),
        case("rect of width -10", _SVG.format(attributes='viewBox="0 0 10 10"',
                                              body='<rect width="-10" height="10"/>')),
        case("coordinates at 1e300", _SVG.format(attributes='viewBox="0 0 10 10"',
                                                 body='<rect x="1e300" width="10" height="10"/>')),
        case("tolerance -1", _SVG.format(attributes='viewBox="0 0 10 10"', body=square),
             tolerance=-1),
        case("filled square", _SVG.format(attributes='viewBox="0 0 10 10"', body=square),
             expected=100.0),
        case("outline plate with holes of radius 1, 2, 50", outline(plate, (1000, 500)),
             expected=plate[0].area - sum(p.area for p in plate[1:]), holes=3),
        case("outline square with a 30,000-gon hole", outline(fine, (100, 100)),
             expected=fine[0].area - fine[1].area, holes=1),
    ]


def mesh_file_cases():
    """Mesh files and solids: unreadable, degenerate, multi-shell, far away."""
    import pds_plugin as pds
    import shapely
    import trimesh
    from shapely.geometry import box

    def case(name, content, origin=(0, 0, 0), normal=(0, 0, 1), expected=None, suffix=".stl"):
        def make(folder):
            path = folder / f"part{suffix}"
            if isinstance(content, str) and content == "folder":
                path.mkdir()
            elif content is not None:
                path.write_bytes(content)

            def check(region):
                if expected is None:
                    return None
                if not math.isclose(region.area, expected.area, rel_tol=1e-6) or \
                        region.betti != betti(expected):
                    return "wrong", (f"area {region.area:.9g} in {region.betti}, the solid's "
                                     f"{expected.area:.9g} in {betti(expected)}")
                return None
            return Trial(lambda: pds.section(path, origin, normal), [path], check)
        return Case(name, make)

    unit = [(-1, -1, -1, 1, 1, 1)]
    two = [(0, 0, 0, 2, 2, 2), (1, 0, 0, 3, 2, 2)]
    nested = [(0, 0, 0, 4, 4, 4), (1, 1, 1, 3, 3, 3)]
    # a plate with ten 0.2-wide holes and a 1-unit box 1e6 away (float32 in STL: 1e8 + 1
    # is not a number there)
    plate = trimesh.creation.box(extents=(10, 10, 1))
    for i in range(10):
        plate = plate.difference(trimesh.creation.box(extents=(0.2, 0.2, 2)).apply_translation(
            (-4.5 + i, 0, 0)))
    stray = trimesh.util.concatenate([plate, trimesh.creation.box(extents=(1, 1, 1))
                                      .apply_translation((1e6, 1e6, 0))])
    stray_section = shapely.union_all([box(-5, -5, 5, 5).difference(shapely.union_all(
        [box(-4.6 + i, -0.1, -4.4 + i, 0.1) for i in range(10)])),
        box(1e6 - 0.5, 1e6 - 0.5, 1e6 + 0.5, 1e6 + 0.5)])
    open_box = trimesh.creation.box(extents=(2, 2, 2))
    open_box.update_faces(open_box.face_normals[:, 0] < 0.5)
    cloud = trimesh.PointCloud(np.random.default_rng(0).random((20, 3))).export(file_type="ply")
    good = stl_bytes(box_mesh(unit))
    return [
        case("missing file", None),
        case("a folder", "folder"),
        case("empty file", b""),
        case("garbage bytes", b"\x00\x01garbage" * 50),
        case("truncated STL", good[:300]),
        case("ASCII STL cut short", b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"),
        case("vertex at 1e30", stl_with_value(1e30, 3)),
        case("vertex NaN", stl_with_value(math.nan, 3)),
        case("vertex inf", stl_with_value(math.inf, 3)),
        case("open (not watertight) box", stl_bytes(open_box)),
        case("point cloud PLY", cloud, suffix=".ply"),
        case("an SVG given as a solid", b"<svg/>", suffix=".svg"),
        case("plane on a face", good, origin=(0, 0, 1)),
        case("plane missing the solid", good, origin=(0, 0, 5)),
        case("unit box", good, expected=box_section(unit, 0.0)),
        case("two overlapping shells", stl_bytes(box_mesh(two)), origin=(0, 0, 1),
             expected=box_section(two, 1.0)),
        case("a shell inside a shell", stl_bytes(box_mesh(nested)), origin=(0, 0, 2),
             expected=box_section(nested, 2.0)),
        case("plane origin at (1e11, 1e11, 0.5)", good, origin=(1e11, 1e11, 0.5),
             expected=box_section(unit, 0.5)),
        case("a stray box 1e6 away from a plate with ten holes", stl_bytes(stray),
             expected=stray_section),
        case("zero normal", good, normal=(0, 0, 0)),
        case("NaN origin", good, origin=(math.nan, 0, 0)),
    ]


def auto_alpha_cases():
    """alpha='auto' where the sample budget caps alpha below a gap's need."""
    import warnings

    import pds_plugin as pds
    from shapely.geometry import Point, box

    def case(name, geometry, gap_point=None, **options):
        def make(folder):
            region = pds.Region.from_shapely(geometry)

            def run():
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    mesh = pds.mesh_region(region, "auto", **options)
                return mesh, [str(w.message) for w in caught]

            def check(result):
                mesh, said = result
                union = mesh_union(mesh.vertices, mesh.faces)
                if said:
                    return None                      # the user was told
                if betti(union) != betti(geometry):
                    return "wrong", f"Betti numbers {betti(union)}, region {betti(geometry)}"
                if gap_point is not None and union.contains(Point(gap_point)):
                    return "wrong", f"the mesh bridges the gap at {gap_point}, no warning"
                return None
            return Trial(run, [region], check)
        return Case(name, make)

    slot = box(0, 0, 10, 10).difference(box(2, 5 - 5e-5, 10, 5 + 5e-5))
    return [
        case("plate with a 1e-4 slot, 20k samples", slot, (6, 5), max_samples=20_000),
        case("plate with a 1e-4 slot, 60k samples", slot, (6, 5), max_samples=60_000),
        case("two discs 1e-3 apart", Point(0, 0).buffer(1).union(Point(2.001, 0).buffer(1)),
             (1.0005, 0), max_samples=20_000),
        case("ring", Point(0, 0).buffer(1).difference(Point(0, 0).buffer(0.5))),
    ]


# --- command line, files and signals (each a real pds-mesh process) ---------------------

def _cli(folder, *argv, timeout=600):
    return subprocess.run([sys.executable, "-m", "pds_plugin.cli", *map(str, argv)], cwd=folder,
                          capture_output=True, text=True, timeout=timeout)


def _stl(folder, boxes=((0, 0, 0, 2, 1, 1),)):
    path = folder / "part.stl"
    path.write_bytes(stl_bytes(box_mesh(list(boxes))))
    return path


def cli_verdict(process, folder, keep=()):
    """Judge a pds-mesh run: 0 with complete outputs, or 1/2 with one error line and no
    files left behind; a traceback is a bug."""
    import trimesh

    lines = [line for line in process.stderr.splitlines() if line.strip()]
    if "Traceback" in process.stderr:
        return "other", lines[-1] if lines else "traceback"
    left = sorted(p.name for p in folder.iterdir() if p.name not in keep)
    if process.returncode in (1, 2):
        errors = [line for line in lines if line.startswith("pds-mesh: error: ")]
        if len(errors) != 1:
            return "other", f"exit {process.returncode} with {lines[-3:]}"
        if left:
            return "wrong", f"failed ({errors[0][:80]}) but left {left[:4]}"
        return "clean", errors[0]
    if process.returncode != 0:
        return "other", f"exit status {process.returncode}"
    for name in left:
        path = folder / name
        if path.suffix in (".ply", ".obj"):
            mesh = trimesh.load_mesh(path, process=False)
            if not len(mesh.faces) or not np.isfinite(mesh.vertices).all():
                return "wrong", f"{name} is incomplete"
        if path.suffix == ".json":
            json.loads(path.read_text())
    return None


def cli_cases():
    def case(*argv, keep=("part.stl", "drawing.svg", "exists")):
        def make(folder):
            stl = _stl(folder)
            (folder / "drawing.svg").write_text(_SVG.format(
                attributes='viewBox="0 0 10 10"', body='<rect width="10" height="10"/>'))
            (folder / "exists").mkdir()
            args = [str(stl) if a == "STL" else a for a in argv]
            return Trial(lambda: _cli(folder, *args), [stl],
                         lambda process: cli_verdict(process, folder, keep))
        return Case("pds-mesh " + " ".join(argv), make)

    PLY = ("STL", "-o", "out.ply", "--axis", "z", "--alpha")        # then alpha, options
    return [
        case(*PLY, "0.1"),
        case(*PLY, "0"),
        case(*PLY, "1e-300"),
        case(*PLY, "1e300"),
        case(*PLY, "0.1", "--max-samples", "0"),
        case(*PLY, "0.001", "--max-samples", "100"),
        case("STL", "-o", "out.stl", "--axis", "z", "--alpha", "0.1"),
        case("STL", "-o", "out", "--axis", "z", "--alpha", "0.1"),
        case("STL", "-o", "exists", "--axis", "z", "--alpha", "0.1"),
        case("STL", "-o", "no/such/dir/out.ply", "--axis", "z", "--alpha", "0.1"),
        case("STL", "-o", "STL", "--axis", "z", "--alpha", "0.1"),
        case(*PLY, "0.1", "--report", "exists"),
        case(*PLY, "0.1", "--plot", "exists.png/x.png"),
        case(*PLY, "0.1", "--plot", "p.xyz"),
        case(*PLY, "0.1", "--at", "0,0.5"),
        case(*PLY, "0.1", "--at", "0.5,5"),
        case(*PLY, "0.1", "--at", "0.5,1"),
        case(*PLY, "0.1", "--slices", "1000000000"),
        case(*PLY, "0.1", "--slices", "3", "--jobs", "1000"),
        case("STL", "-o", "out.ply", "--plane-normal", "0,0,0", "--alpha", "0.1"),
        case("STL", "-o", "out.ply", "--alpha", "0.1"),
        case("drawing.svg", "-o", "out.obj", "--alpha", "0.5"),
        case("drawing.svg", "-o", "out.obj", "--alpha", "0.5", "--axis", "z"),
        case("missing.stl", "-o", "out.ply", "--axis", "z", "--alpha", "0.1"),
        case("exists", "-o", "out.ply", "--axis", "z", "--alpha", "0.1"),
        case(*PLY, "0.1", "--jobs", "x"),
        case(*PLY, "0.1", "--seed", "-1"),
    ]


_WRITER = """
import json, sys, numpy as np, pds_plugin as pds
from shapely.geometry import box
mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.003)
path = sys.argv[1]
open(path + '.expected', 'w').write(json.dumps([len(mesh.vertices), len(mesh.faces)]))
print('ready', flush=True)
sys.stdin.readline()
mesh.export(path)
"""


def interrupted_write_cases():
    """kill -9 while a mesh is written: the file must be complete or absent."""
    import trimesh

    def case(suffix, delay):
        def make(folder):
            path = folder / f"mesh{suffix}"

            def run():
                child = subprocess.Popen([sys.executable, "-c", _WRITER, str(path)],
                                         stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
                child.stdout.readline()
                child.stdin.write("go\n")
                child.stdin.flush()
                time.sleep(delay)
                child.kill()
                child.wait()
                return path

            def check(path):
                if not path.exists():
                    return None
                vertices, faces = json.loads(Path(str(path) + ".expected").read_text())
                try:
                    mesh = trimesh.load_mesh(path, process=False)
                except Exception as error:
                    return "wrong", f"an unreadable {path.name} under the final name ({error})"
                if (len(mesh.vertices), len(mesh.faces)) != (vertices, faces):
                    return "wrong", (f"a truncated {path.name}: {len(mesh.vertices)} vertices, "
                                     f"{len(mesh.faces)} faces of {vertices}, {faces}")
                return None
            return Trial(run, [], check)
        return Case(f"kill -9 {delay:g} s into writing {suffix}", make)
    return [case(s, d) for s in (".ply", ".obj") for d in (0.0, 0.02, 0.1, 0.3)]


def _children(pid) -> list[int]:
    try:
        text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    except OSError:
        return []
    return [int(p) for p in text.split()]


def _alive(pid) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _is_pool_worker(pid) -> bool:
    try:
        command = Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return False
    return b"spawn_main" in command and b"resource_tracker" not in command


def signal_cases():
    """SIGTERM, SIGKILL and SIGINT to pds-mesh --jobs 2: no worker may outlive it."""
    def case(signum):
        def make(folder):
            stl = _stl(folder, [(0, 0, 0, 4, 4, 4)])

            def run():
                child = subprocess.Popen([sys.executable, "-m", "pds_plugin.cli", str(stl), "-o",
                                          "out.ply", "--axis", "z", "--slices", "6", "--alpha",
                                          "0.004", "--jobs", "2"], cwd=folder,
                                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
                workers, deadline = [], time.monotonic() + 60
                while time.monotonic() < deadline and child.poll() is None:
                    workers = [w for c in _children(child.pid) for w in [c, *_children(c)]]
                    if sum(_is_pool_worker(w) for w in workers) >= 2:
                        break
                    time.sleep(0.2)
                time.sleep(3.0)
                os.kill(child.pid, signum)
                child.wait(timeout=60)
                time.sleep(5.0)
                orphans = [w for w in workers if _alive(w)]
                for pid in orphans:               # ours: clean up before judging
                    os.kill(pid, signal.SIGKILL)
                return workers, orphans, child.returncode

            def check(result):
                workers, orphans, code = result
                if not workers:
                    return "other", "no worker process started"
                if orphans:
                    return "hang", f"{len(orphans)} of {len(workers)} processes outlived pds-mesh"
                return None
            return Trial(run, [stl], check)
        return Case(f"{signal.Signals(signum).name} to pds-mesh --jobs 2", make)
    return [case(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGKILL)]


def failed_run_cases():
    """A run that fails part-way must leave a consistent set of files, or none."""
    def case(name, boxes, *argv):
        def make(folder):
            stl = _stl(folder, boxes)
            return Trial(lambda: _cli(folder, stl, *argv), [stl],
                         lambda process: cli_verdict(process, folder, keep=("part.stl",)))
        return Case(name, make)
    gap = [(0, 0, 0, 2, 2, 1), (0, 0, 2, 2, 2, 3)]       # nothing between z = 1 and 2
    return [
        case("second of two sections fails", gap, "-o", "part.ply", "--axis", "z", "--at",
             "0.5,1.5", "--alpha", "0.1"),
        case("second of three fails, --jobs 2", gap, "-o", "part.ply", "--axis", "z", "--at",
             "0.5,1.5,2.5", "--alpha", "0.1", "--jobs", "2"),
        case("--report is a folder", [(0, 0, 0, 2, 2, 1)], "-o", "part.ply", "--axis", "z",
             "--alpha", "0.1", "--report", "."),
        case("--plot in a missing folder", [(0, 0, 0, 2, 2, 1)], "-o", "part.ply", "--axis",
             "z", "--alpha", "0.1", "--plot", "none/p.png"),
    ]
