"""Hostile files for bench/reliability.py: DXF drawings, mesh files and SVG drawings,
written by hand or mutated from a good file with a seeded generator.

Hand-written files have a known answer (an area, a count of holes, or a clean refusal).
Mutated files (a number replaced by NaN, infinity or an out-of-range value, a line
deleted, the file cut short, bytes flipped) have no closed-form answer: they must give a
clean error or a valid region, and where the mutation leaves the geometry alone (a face
normal of an STL, a face of a box that the plane does not cross) the region must be the
original one. The cases follow bench/_hostile.py's conventions (:class:`Case`,
:class:`Trial`).
"""

from __future__ import annotations

import math
import re
import struct

import numpy as np

from _hostile import _SVG, Case, Trial, box_mesh, stl_bytes

SEED = 20261130
HOSTILE_NUMBERS = ["nan", "inf", "-inf", "1e308", "-1e308", "1e400", "1e-320", "0", "-0",
                   "abc", "", "99999999999999999999999", "1e15", "-1e-15"]
"""What a number of a file is replaced by in the mutated files."""


def _region_check(expected=None, holes=None, rel_tol=1e-3, within=None):
    """A check of a Region: its area, its holes, or its bounds inside a box."""
    def check(region):
        if expected is not None and not math.isclose(region.area, expected, rel_tol=rel_tol):
            return "wrong", f"area {region.area:.9g}, expected {expected:.9g}"
        if holes is not None and region.betti[1] != holes:
            return "wrong", f"{region.betti[1]} holes, expected {holes}"
        if within is not None:
            x0, y0, x1, y1 = region.bounds
            (a0, b0), (a1, b1) = within
            slack = 1e-6 * max(a1 - a0, b1 - b0, 1.0)
            if x0 < a0 - slack or y0 < b0 - slack or x1 > a1 + slack or y1 > b1 + slack:
                return "wrong", f"region bounds {region.bounds} outside the drawing {within}"
        return None
    return check


# --- DXF -------------------------------------------------------------------------------

def _plate(doc, msp):
    """A 20 x 10 plate with a hole of radius 2: area 200 - 4π."""
    msp.add_lwpolyline([(0, 0), (20, 0), (20, 10), (0, 10)], close=True,
                       dxfattribs={"layer": "OUTLINE"})
    msp.add_circle((5, 5), 2, dxfattribs={"layer": "HOLES"})


PLATE_AREA = 200 - 4 * math.pi


def _nested(doc, levels, copies=10, name="B"):
    """Blocks B1..B{levels} each inserting the one below ``copies`` times; B0 a unit square."""
    doc.blocks.new(f"{name}0").add_lwpolyline([(0, 0), (1, 0), (1, 1), (0, 1)], close=True)
    for level in range(1, levels + 1):
        block = doc.blocks.new(f"{name}{level}")
        step = 2 * copies ** ((level - 1) // 2)
        for copy in range(copies):
            block.add_blockref(f"{name}{level - 1}",
                               (step * copy, 0) if level % 2 else (0, step * copy))
    return f"{name}{levels}"


def _dxf_bytes(build, binary=False) -> bytes:
    import io

    import ezdxf

    doc = ezdxf.new("R2010", units=4)
    build(doc, doc.modelspace())
    if binary:
        import pathlib
        import tempfile

        with tempfile.TemporaryDirectory() as folder:
            path = pathlib.Path(folder) / "b.dxf"
            doc.saveas(path, fmt="bin")
            return path.read_bytes()
    stream = io.StringIO()
    doc.write(stream)
    return stream.getvalue().encode()


def dxf_cases():
    """Hand-written DXF drawings: bombs, damaged structure, non-finite and degenerate
    entities, bad arguments, and drawings of known area."""
    import pds_plugin as pds

    def case(name, content, check=None, **options):
        def make(folder):
            path = folder / "drawing.dxf"
            path.write_bytes(content() if callable(content) else content)
            return Trial(lambda: pds.load_dxf(path, **options), [path], check or (lambda r: None))
        return Case(name, make)

    def built(build, binary=False):
        return lambda: _dxf_bytes(build, binary)

    def chain(depth):
        def build(doc, msp):
            doc.blocks.new("C0").add_lwpolyline([(0, 0), (1, 0), (1, 1), (0, 1)], close=True)
            for level in range(1, depth + 1):
                doc.blocks.new(f"C{level}").add_blockref(f"C{level - 1}", (0, 0))
            msp.add_blockref(f"C{depth}", (0, 0))
        return build

    def cycle(doc, msp):
        a, b = doc.blocks.new("A"), doc.blocks.new("B")
        a.add_blockref("B", (1, 0))
        b.add_blockref("A", (0, 1))
        a.add_lwpolyline([(0, 0), (1, 0), (1, 1)], close=True)
        msp.add_blockref("A", (0, 0))

    def polygon_ring(doc, msp, count=10_000, copies=200):
        ring = doc.blocks.new("RING")
        angles = np.linspace(0, 2 * np.pi, count, endpoint=False)
        ring.add_lwpolyline(np.column_stack([np.cos(angles), np.sin(angles)]), close=True)
        for copy in range(copies):
            msp.add_blockref("RING", (3 * copy, 0))

    def with_entity(add):
        def build(doc, msp):
            msp.add_lwpolyline([(0, 0), (10, 0), (10, 10), (0, 10)], close=True)
            add(doc, msp)
        return build

    def hatch(paths):
        def build(doc, msp):
            h = msp.add_hatch()
            for path in paths:
                h.paths.add_polyline_path(path)
        return build

    def huge_comment():
        text = _dxf_bytes(_plate).decode()
        return ("999\n" + "x" * 60_000_000 + "\n" + text).encode()

    square = [(0, 0), (10, 0), (10, 10), (0, 10)]
    bowtie = [(0, 0), (2, 2), (2, 0), (0, 2)]
    plate = built(_plate)
    return [
        case("plate with a hole", plate, _region_check(PLATE_AREA, holes=1)),
        case("binary DXF plate", built(_plate, binary=True), _region_check(PLATE_AREA, holes=1)),
        case("plate, layers=['outline'] (any case)", plate, _region_check(200.0, holes=0),
             layers=["outline"]),
        case("plate, units='cm'", plate, _region_check(PLATE_AREA / 100, holes=1), units="cm"),
        case("nested INSERT bomb of 10^8 squares",
             built(lambda doc, msp: msp.add_blockref(_nested(doc, 8), (0, 0)))),
        case("MINSERT array of 10^4 x 10^4", built(lambda doc, msp: (
            doc.blocks.new("CELL").add_circle((0, 0), 0.1),
            msp.add_blockref("CELL", (0, 0)).grid(size=(10_000, 10_000), spacing=(1, 1))))),
        case("200 copies of a 10,000-gon", built(polygon_ring)),
        case("100 squares through 2 block levels",
             built(lambda doc, msp: msp.add_blockref(_nested(doc, 2), (0, 0))),
             _region_check(100.0)),
        case("INSERT of an undefined block", built(with_entity(
            lambda doc, msp: msp.add_blockref("NOWHERE", (0, 0))))),
        case("two blocks inserting each other", built(cycle)),
        case("blocks nested 60 deep", built(chain(60)), _region_check(1.0)),
        case("blocks nested 100 deep", built(chain(100))),
        case("LINE to NaN", built(with_entity(lambda d, m: m.add_line((0, 0), (math.nan, 5))))),
        case("CIRCLE of infinite radius", built(with_entity(
            lambda d, m: m.add_circle((5, 5), math.inf)))),
        case("CIRCLE of radius 0 inside a square", built(with_entity(
            lambda d, m: m.add_circle((5, 5), 0.0))), _region_check(100.0)),
        case("CIRCLE of radius 1e300", built(with_entity(
            lambda d, m: m.add_circle((5, 5), 1e300)))),
        case("ARC of zero sweep", built(with_entity(
            lambda d, m: m.add_arc((5, 5), 2, 30, 30))), _region_check(100.0)),
        case("ELLIPSE of ratio 1e-12", built(with_entity(
            lambda d, m: m.add_ellipse((5, 5), (2, 0), ratio=1e-12)))),
        case("bulge of 1e10", built(lambda d, m: m.add_lwpolyline(
            [(0, 0, 0, 0, 1e10), (10, 0), (10, 10)], format="xyseb", close=True))),
        case("bulge of NaN", built(lambda d, m: m.add_lwpolyline(
            [(0, 0, 0, 0, math.nan), (10, 0), (10, 10)], format="xyseb", close=True))),
        case("closed polyline of 1 vertex", built(lambda d, m: m.add_lwpolyline(
            [(1, 1)], close=True))),
        case("closed polyline of 2 vertices", built(lambda d, m: m.add_lwpolyline(
            [(1, 1), (5, 5)], close=True))),
        case("hatch: a bowtie (even-odd)", built(hatch([bowtie])), _region_check(2.0)),
        case("hatch: a square with an island", built(hatch(
            [square, [(3, 3), (7, 3), (7, 7), (3, 7)]])), _region_check(84.0, holes=1)),
        case("unit square at 1e15", built(lambda d, m: m.add_lwpolyline(
            [(1e15, 1e15), (1e15 + 1, 1e15), (1e15 + 1, 1e15 + 1), (1e15, 1e15 + 1)],
            close=True)), _region_check(1.0, rel_tol=1e-9)),
        case("square of side 1e-200", built(lambda d, m: m.add_lwpolyline(
            [(0, 0), (1e-200, 0), (1e-200, 1e-200), (0, 1e-200)], close=True))),
        case("text only", built(lambda d, m: m.add_text("hello"))),
        case("paper space only", built(lambda d, m: d.paperspace().add_circle((0, 0), 1))),
        case("units='mm' on a unitless drawing",
             lambda: _dxf_bytes(_plate).replace(b"$INSUNITS\n 70\n4\n", b"$INSUNITS\n 70\n0\n"),
             units="mm"),
        case("layers=['NOPE']", plate, layers=["NOPE"]),
        case("layers=[3]", plate, layers=[3]),
        case("mode='stroke'", plate, mode="stroke"),
        case("tolerance=-1", plate, tolerance=-1),
        case("tolerance=nan", plate, tolerance=math.nan),
        case("max_entities=0", plate, max_entities=0),
        case("max_bytes=True", plate, max_bytes=True),
        case("60 MB comment", huge_comment),
        case("empty file", b""),
        case("not DXF text", b"hello, this is not a drawing\n"),
        case("PNG renamed .dxf", b"\x89PNG\r\n\x1a\n" + bytes(200)),
        case("SVG renamed .dxf", _SVG.format(attributes='viewBox="0 0 9 9"',
                                             body='<rect width="9" height="9"/>').encode()),
        case("binary DXF header then garbage", b"AutoCAD Binary DXF\r\n\x1a\x00" + bytes(range(256))),
        case("plate cut in half", lambda: _dxf_bytes(_plate)[:len(_dxf_bytes(_plate)) // 2]),
    ]


def _entities_span(text: str) -> tuple[int, int]:
    """Character range of the ENTITIES section of an ASCII DXF."""
    start = text.index("ENTITIES")
    return start, text.index("ENDSEC", start)


def dxf_mutation_cases(count=260):
    """The plate drawing with one mutation in its ENTITIES section: a number replaced by a
    hostile value, a line deleted, bytes flipped, or the file cut short. A region, if
    any, must lie inside the numbers the file still holds (the drawing's own box)."""
    import pds_plugin as pds

    base = _dxf_bytes(_plate).decode()
    lines = base.split("\n")
    start, stop = _entities_span(base)
    first, last = base[:start].count("\n"), base[:stop].count("\n")
    numeric = [i for i in range(first, last) if re.fullmatch(r"\s*-?[\d.]+(e[-+]?\d+)?\s*",
                                                             lines[i], re.I)
               and lines[i - 1].strip() in ("10", "20", "40", "42", "43", "38", "90", "70")]
    rng = np.random.default_rng(SEED)

    def mutated(kind):
        if kind == "number":
            where = int(rng.choice(numeric))
            value = str(rng.choice(HOSTILE_NUMBERS))
            copy = lines.copy()
            copy[where] = value
            return "\n".join(copy), f"line {where + 1} ({lines[where - 1].strip()}) -> {value!r}"
        if kind == "delete":
            where = int(rng.integers(first, last))
            return "\n".join(lines[:where] + lines[where + 1:]), f"line {where + 1} deleted"
        if kind == "flip":
            data = bytearray(base.encode())
            spots = rng.integers(start, stop, size=int(rng.integers(1, 6)))
            for spot in spots:
                data[spot] = int(rng.integers(0, 256))
            return bytes(data), f"{len(spots)} byte(s) flipped"
        where = int(rng.integers(start, len(base)))
        return base[:where], f"cut at byte {where:,}"

    def case(content, what):
        def make(folder):
            path = folder / "drawing.dxf"
            path.write_bytes(content if isinstance(content, bytes) else content.encode())
            return Trial(lambda: pds.load_dxf(path), [path],
                         _region_check(within=_box_of_numbers(path)))
        return Case(f"plate.dxf, {what}", make)

    kinds = ["number"] * 5 + ["delete"] * 2 + ["flip"] * 2 + ["cut"]
    return [case(*mutated(kinds[i % len(kinds)])) for i in range(count)]


def _box_of_numbers(path):
    """The box of the x (group 10) and y (group 20) values an ASCII DXF holds, widened by
    its radii (group 40): every point of a drawing lies inside (arcs bulging beyond it
    are covered by their radius)."""
    lines = path.read_bytes().decode("utf-8", "replace").split("\n")
    values = {"10": [], "20": [], "40": []}
    for code, value in zip(lines, lines[1:]):
        code = code.strip()
        if code in values:
            try:
                number = float(value)
            except ValueError:
                continue
            if math.isfinite(number):
                values[code].append(number)
    if not values["10"] or not values["20"]:
        return ((-math.inf, -math.inf), (math.inf, math.inf))
    radius = max(map(abs, values["40"]), default=0.0)
    # a bulge can bow a segment out by up to its length (a half circle): allow it
    reach = radius + max(np.ptp(values["10"]), np.ptp(values["20"]))
    return ((min(values["10"]) - reach, min(values["20"]) - reach),
            (max(values["10"]) + reach, max(values["20"]) + reach))


# --- mesh files ----------------------------------------------------------------------------

_BOX = [(-1, -1, -1, 1, 1, 1)]
"""The 2 x 2 x 2 box the mutated mesh files are made of: every section through it
parallel to a face has area 4."""
_PLANES = [((0, 0, 0.3), (0, 0, 1)), ((0.3, 0, 0), (1, 0, 0)), ((0, -0.2, 0), (0, 1, 0))]


def _faces_crossing(mesh, origin, normal) -> np.ndarray:
    heights = (np.asarray(mesh.vertices) - origin) @ np.asarray(normal, float)
    per_face = heights[np.asarray(mesh.faces)]
    return (per_face.min(axis=1) < 0) & (per_face.max(axis=1) > 0)


def mesh_mutation_cases(float_count=120):
    """Mesh files of the 2 x 2 x 2 box with bad faces: a face deleted (the section must be
    refused as open where the plane crosses the hole, and be the square elsewhere), a
    face reversed or doubled (the square), numbers of a binary STL replaced (a normal:
    the square; a vertex: a region inside the mutated vertices' box), the file cut at
    every facet, header counts that lie, and OBJ, PLY and OFF files with faces that
    point past their vertices."""
    import pds_plugin as pds
    import trimesh

    box = box_mesh(_BOX)
    cases = []

    def case(name, content, origin, normal, check, suffix=".stl"):
        def make(folder):
            path = folder / f"part{suffix}"
            path.write_bytes(content() if callable(content) else content)
            return Trial(lambda: pds.section(path, origin, normal), [path], check)
        cases.append(Case(name, make))

    square = _region_check(4.0, holes=0, rel_tol=1e-9)
    for origin, normal in _PLANES:
        crossing = _faces_crossing(box, origin, normal)
        for face in range(len(box.faces)):
            kept = np.arange(len(box.faces)) != face
            holed = trimesh.Trimesh(box.vertices, box.faces[kept], process=False)

            def open_check(region, crossed=bool(crossing[face])):
                if crossed:
                    return "wrong", "a section through a hole of the mesh was accepted"
                return square(region)
            cases_name = f"face {face} deleted, plane normal {normal}"
            case(cases_name, stl_bytes(holed), origin, normal, open_check)
            for change, faces in (("reversed", box.faces.copy()),
                                  ("doubled", np.vstack([box.faces, box.faces[face:face + 1]]))):
                if change == "reversed":
                    faces[face] = faces[face][::-1]
                case(f"face {face} {change}, plane normal {normal}",
                     stl_bytes(trimesh.Trimesh(box.vertices, faces, process=False)), origin,
                     normal, square)

    good = bytearray(stl_bytes(box))
    rng = np.random.default_rng(SEED)
    values = [math.nan, math.inf, -math.inf, 1e30, -1e30, 1e-30, 0.0, 3.4e38, 1e-45]
    for _ in range(float_count):
        facet, slot = int(rng.integers(0, len(box.faces))), int(rng.integers(0, 12))
        value = float(rng.choice(values))
        data = bytearray(good)
        where = 84 + 50 * facet + 4 * slot
        data[where:where + 4] = struct.pack("<f", value)
        vertices = np.frombuffer(bytes(data[84:]), dtype=np.dtype(
            [("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")]))["corners"]
        corners = vertices.reshape(-1, 3).astype(float)
        finite = corners[np.isfinite(corners).all(axis=1)]
        check = square if slot < 3 else _region_check(within=(
            tuple(finite[:, :2].min(axis=0)), tuple(finite[:, :2].max(axis=0))))
        case(f"binary STL facet {facet} float {slot} ({'normal' if slot < 3 else 'vertex'}) "
             f"= {value:g}", bytes(data), (0, 0, 0.3), (0, 0, 1), check)

    for facet in range(len(box.faces)):
        for cut in (84 + 50 * facet, 84 + 50 * facet + 25):
            if cut < len(good):
                case(f"binary STL cut at byte {cut}", bytes(good[:cut]), (0, 0, 0.3),
                     (0, 0, 1), square)
    for count in (0, 11, 13, 2**32 - 1):
        data = bytearray(good)
        data[80:84] = struct.pack("<I", count)
        case(f"binary STL header announcing {count} triangles", bytes(data), (0, 0, 0.3),
             (0, 0, 1), square)

    corners = "".join(f"v {x} {y} {z}\n" for x in (-1, 1) for y in (-1, 1) for z in (-1, 1))
    quads = ["1 3 4 2", "5 6 8 7", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6"]
    obj = corners + "".join(f"f {q}\n" for q in quads)
    def refused(region):
        return "wrong", "a section through the hole of an open box was accepted"

    # the box is the solid whatever bad face is added: an accepted section is its square
    obj_cases = [
        ("OBJ box of quads", obj, square),
        ("OBJ with negative (relative) indices", corners + "".join(
            "f " + " ".join(str(int(i) - 9) for i in q.split()) + "\n" for q in quads), square),
        ("OBJ face with index 0", obj + "f 0 1 2\n", square),
        ("OBJ face with index 99", obj + "f 1 2 99\n", square),
        ("OBJ face with index -99", obj + "f 1 2 -99\n", square),
        ("OBJ face with index 1.5", obj + "f 1 2 1.5\n", square),
        ("OBJ face with a letter", obj + "f 1 2 x\n", square),
        ("OBJ face of 2 vertices", obj + "f 1 2\n", square),
        ("OBJ face repeating a vertex", obj + "f 1 1 2\n", square),
        ("OBJ faces without vertices", "".join(f"f {q}\n" for q in quads), None),
        ("OBJ vertex with NaN", obj.replace("v -1 -1 -1", "v nan -1 -1"), None),
        ("OBJ vertex with 1e400", obj.replace("v -1 -1 -1", "v 1e400 -1 -1"), None),
        ("OBJ box missing a side crossed by the plane",
         corners + "".join(f"f {q}\n" for q in quads[:1] + quads[2:]), refused),
        ("OBJ box missing its top", corners + "".join(f"f {q}\n" for q in quads[:-1]), square),
    ]
    ply_head = ("ply\nformat ascii 1.0\nelement vertex {v}\nproperty float x\nproperty float y\n"
                "property float z\nelement face {f}\nproperty list uchar int vertex_indices\n"
                "end_header\n")
    ply_vertices = "".join(f"{x} {y} {z}\n" for x in (-1, 1) for y in (-1, 1) for z in (-1, 1))
    ply_faces = "".join(f"4 {' '.join(str(int(i) - 1) for i in q.split())}\n" for q in quads)
    off = "OFF\n8 6 0\n" + ply_vertices + ply_faces
    text_cases = obj_cases + [
        ("PLY box", ply_head.format(v=8, f=6) + ply_vertices + ply_faces, square, ".ply"),
        ("PLY announcing 9 faces", ply_head.format(v=8, f=9) + ply_vertices + ply_faces,
         square, ".ply"),
        ("PLY announcing 20 vertices", ply_head.format(v=20, f=6) + ply_vertices + ply_faces,
         square, ".ply"),
        ("PLY face index 8", ply_head.format(v=8, f=6) + ply_vertices + ply_faces.replace(
            "4 0 2 3 1", "4 0 2 3 8"), square, ".ply"),
        ("PLY face of 2 vertices", ply_head.format(v=8, f=7) + ply_vertices + ply_faces
         + "2 0 1\n", square, ".ply"),
        ("OFF box", off, square, ".off"),
        ("OFF announcing 100 vertices", off.replace("8 6 0", "100 6 0"), square, ".off"),
        ("OFF face index 99", off.replace("4 0 2 3 1", "4 0 2 3 99"), square, ".off"),
        ("OFF face of 2 vertices", off.replace("8 6 0", "8 7 0") + "2 0 1\n", square, ".off"),
    ]
    for entry in text_cases:
        name, text, check = entry[:3]
        # None: no answer to compare with (no vertices, non-finite ones): a clean error
        # is expected, and an accepted region is checked by Region itself (valid, finite)
        case(name, text.encode(), (0, 0, 0.3), (0, 0, 1), check or (lambda region: None),
             entry[3] if len(entry) > 3 else ".obj")
    return cases


# --- SVG ---------------------------------------------------------------------------------

def svg_structure_cases():
    """Hostile SVG structure: deep nesting, references, styles, transforms, encodings,
    namespaces; with known areas where the drawing is valid."""
    import pds_plugin as pds

    def svg(body, attributes='viewBox="0 0 10 10"'):
        return _SVG.format(attributes=attributes, body=body)

    def case(name, content, expected=None, holes=None, **options):
        def make(folder):
            path = folder / "drawing.svg"
            data = content() if callable(content) else content
            path.write_bytes(data if isinstance(data, bytes) else data.encode())
            return Trial(lambda: pds.load_svg(path, **options), [path],
                         _region_check(expected, holes))
        return Case(name, make)

    rect = '<rect width="10" height="10"/>'
    ring = '<path fill-rule="evenodd" d="M0 0H10V10H0Z M3 3H7V7H3Z"/>'
    return [
        case("10,000 nested groups", svg("<g>" * 10_000 + rect + "</g>" * 10_000)),
        case("200 nested groups", svg("<g>" * 200 + rect + "</g>" * 200), 100.0),
        case("<use> of a missing id", svg(rect + '<use href="#nowhere"/>'), 100.0),
        case("<use> of itself", svg('<use id="u" href="#u"/>' + rect)),
        case("<use> chain of 1,000", svg('<rect id="r0" width="1" height="1"/>' + "".join(
            f'<g id="r{i}"><use href="#r{i - 1}"/></g>' for i in range(1, 1000)))),
        case("xlink:href <use>", '<svg xmlns="http://www.w3.org/2000/svg" '
             'xmlns:xlink="http://www.w3.org/1999/xlink" viewBox="0 0 10 10"><defs>'
             '<rect id="r" width="10" height="5"/></defs><use xlink:href="#r"/></svg>', 50.0),
        case("1 MB attribute", svg(f'<rect width="10" height="10" data-x="{"y" * 1_000_000}"/>'),
             100.0),
        case("10,000 tiny rects", svg("".join(f'<rect x="{i % 250 * 0.04}" y="{i // 250 * 0.05}"'
                                              f' width="0.02" height="0.02"/>'
                                              for i in range(10_000))), holes=0),
        case("path of 90,000 segments", svg('<path d="M0 0 ' + " ".join(
            f"L{(i % 300) / 30:.3f} {(i // 300) / 30:.3f}" for i in range(90_000)) + ' Z"/>')),
        case("ring, fill-rule evenodd", svg(ring), 84.0, 1),
        case("ring, fill-rule in a style", svg(ring.replace('fill-rule="evenodd"',
                                                            'style="fill-rule:evenodd"')), 84.0, 1),
        case("ring, fill-rule nonzero (same direction)", svg(ring.replace("evenodd", "nonzero")),
             100.0, 0),
        case("display:none on the only shape", svg('<rect width="10" height="10" '
                                                   'style="display:none"/>')),
        case("visibility hidden group, visible child",
             svg('<g visibility="hidden"><rect width="10" height="10" visibility="visible"/></g>')),
        case("shape only in <defs>", svg(f"<defs>{rect}</defs>")),
        case("shape in a <clipPath>", svg(f'<clipPath id="c">{rect}</clipPath>'
                                          '<rect width="5" height="5"/>'), 25.0),
        case("nested <svg> with its own viewBox", svg('<svg x="0" y="0" width="10" height="10" '
                                                      'viewBox="0 0 1 1"><rect width="1" '
                                                      'height="1"/></svg>')),
        case("rotate(45) of a square", svg('<rect x="3" y="3" width="4" height="4" '
                                           'transform="rotate(45 5 5)"/>'), 16.0),
        case("scale(-1) of a square", svg('<rect x="-7" y="-7" width="4" height="4" '
                                          'transform="scale(-1)"/>'), 16.0),
        case("skewX(89.9999)", svg('<rect width="1" height="1" transform="skewX(89.9999)"/>')),
        case("matrix of zeros", svg(f'<g transform="matrix(0 0 0 0 0 0)">{rect}</g>')),
        case("arc with zero radii", svg('<path d="M0 0 A0 0 0 0 1 10 10 L10 0 Z"/>'), 50.0),
        case("arc with flags 7 and 9", svg('<path d="M0 0 A5 5 0 7 9 10 0 Z"/>')),
        case("arc radius 1e300", svg('<path d="M0 0 A1e300 1e300 0 0 1 10 0 L5 5 Z"/>')),
        case("circle of radius 1e-300", svg('<circle cx="5" cy="5" r="1e-300"/>' + rect), 100.0),
        case("stroke-only square (outline)", svg('<path fill="none" stroke="black" '
                                                 'd="M0 0 H10 V10 H0 Z"/>'), 100.0),
        case("negative stroke-width outline", svg('<path fill="none" stroke="black" '
                                                  'stroke-width="-3" d="M0 0 H10 V10 H0 Z"/>'),
             100.0),
        case("UTF-16 with BOM", svg(rect).encode("utf-16"), 100.0),
        case("UTF-8 BOM", b"\xef\xbb\xbf" + svg(rect).encode(), 100.0),
        case("comments and PI before the root", "<?xml version='1.0'?><!-- x --><?pi x?>"
             + svg(rect), 100.0),
        case("CDATA in a <style>", svg("<style><![CDATA[ rect { fill: black } ]]></style>"
                                       + rect), 100.0),
        case("no xmlns", f'<svg viewBox="0 0 10 10">{rect}</svg>'),
        case("wrong namespace", f'<svg xmlns="http://example.com/x" viewBox="0 0 10 10">{rect}'
             '</svg>'),
        case("upper-case tags", '<SVG xmlns="http://www.w3.org/2000/svg"><RECT width="10" '
             'height="10"/></SVG>'),
        case("external DTD", '<?xml version="1.0"?><!DOCTYPE svg SYSTEM '
             '"http://example.com/evil.dtd">' + svg(rect)),
        case("image with a 2 MB data URI", svg('<image width="10" height="10" href="data:'
                                               'image/png;base64,' + "A" * 2_000_000 + '"/>'
                                               + rect), 100.0),
        case("<text> only", svg("<text>hello</text>")),
        case("viewBox 0 0 -10 10", svg(rect, 'viewBox="0 0 -10 10"')),
        case("viewBox of 3 numbers", svg(rect, 'viewBox="0 0 10"')),
        case("width -10", svg(rect, 'width="-10" height="10"')),
        case("width 10 km", svg(rect, 'width="10km" height="10"')),
        case("units='mm' without a size", svg(rect), units="mm"),
        case("max_elements=1", svg(rect), max_elements=1),
        case("max_segments='x'", svg(rect), max_segments="x"),
        case("gzip-compressed (svgz)", lambda: __import__("gzip").compress(svg(rect).encode())),
        case("a DXF renamed .svg", lambda: _dxf_bytes(_plate)),
        case("a PNG renamed .svg", b"\x89PNG\r\n\x1a\n" + bytes(200)),
    ]


def svg_mutation_cases(count=160):
    """A ring drawing with one mutation: a number of its path replaced by a hostile value,
    a character deleted or flipped, or the file cut short. A region, if any, must lie
    inside the finite numbers of the drawing (it maps the page onto itself)."""
    import pds_plugin as pds

    base = _SVG.format(attributes='viewBox="0 0 10 10"',
                       body='<path fill-rule="evenodd" d="M0 0 L10 0 L10 10 L0 10 Z '
                            'M3 3 L7 3 C7 5 7 5 7 7 L3 7 Z"/><circle cx="5" cy="8" r="1"/>')
    numbers = [m.span() for m in re.finditer(r"-?\d+(\.\d+)?", base)]
    rng = np.random.default_rng(SEED)

    def mutated(kind):
        if kind == "number":
            a, b = numbers[int(rng.integers(0, len(numbers)))]
            value = str(rng.choice(HOSTILE_NUMBERS))
            return base[:a] + value + base[b:], f"{base[a:b]!r} at {a} -> {value!r}"
        where = int(rng.integers(0, len(base)))
        if kind == "delete":
            return base[:where] + base[where + 1:], f"character {where} deleted"
        if kind == "flip":
            return (base[:where] + chr(int(rng.integers(32, 127))) + base[where + 1:],
                    f"character {where} replaced")
        return base[:where], f"cut at {where}"

    def case(content, what):
        def make(folder):
            path = folder / "drawing.svg"
            path.write_text(content)
            finite = [float(n) for n in re.findall(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?",
                                                   content) if math.isfinite(float(n))]
            low, high = min(finite, default=0.0), max(finite, default=0.0)
            span = high - low          # the y axis is flipped about the page's height
            return Trial(lambda: pds.load_svg(path), [path], _region_check(
                within=((low - span, low - span), (high + span, high + span))))
        return Case(f"ring.svg, {what}", make)

    kinds = ["number"] * 5 + ["delete"] * 2 + ["flip"] * 2 + ["cut"]
    return [case(*mutated(kinds[i % len(kinds)])) for i in range(count)]
