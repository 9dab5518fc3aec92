"""Hypothesis strategies for the regions the theorems are tested on."""

import numpy as np
import shapely
from hypothesis import strategies as st
from shapely.geometry import Point, Polygon, box

import pds_plugin as pds


@st.composite
def star_polygons(draw):
    """Random star-shaped polygons: sorted angles, random radii."""
    n = draw(st.integers(5, 24))
    angles = np.sort(draw(st.lists(st.floats(0, 2 * np.pi, exclude_max=True), min_size=n,
                                   max_size=n, unique=True)))
    radii = draw(st.lists(st.floats(0.3, 1.0), min_size=n, max_size=n))
    polygon = Polygon(np.column_stack([radii * np.cos(angles), radii * np.sin(angles)]))
    return polygon if polygon.is_valid and polygon.area > 0.05 else box(-1, -1, 1, 1)


@st.composite
def box_unions(draw):
    """Unions of boxes and discs minus smaller holes: several components, holes, slots."""
    def shapes(count, lo, hi):
        return st.lists(st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(lo, hi),
                                  st.floats(lo, hi), st.booleans()), min_size=1, max_size=count)

    def make(x, y, w, h, disc):
        return Point(x, y).buffer(w / 2, quad_segs=8) if disc else box(x, y, x + w, y + h)

    solid = shapely.unary_union([make(*s) for s in draw(shapes(4, 0.3, 1.0))])
    holes = shapely.unary_union([make(*s) for s in draw(shapes(3, 0.05, 0.4))])
    region = shapely.make_valid(solid.difference(holes))
    polygons = [p for p in shapely.get_parts(region) if p.geom_type == "Polygon" and p.area > 1e-3]
    return shapely.MultiPolygon(polygons) if polygons else box(0, 0, 1, 1)


def wedge(angle_degrees, length=1.0):
    """A triangle with a corner of the given angle at the origin."""
    a = np.radians(angle_degrees)
    return Polygon([(0, 0), (length, 0), (length * np.cos(a), length * np.sin(a))])


def slotted_plate(slot_width):
    """A plate with a slot cut in from one side."""
    return box(0, 0, 2, 1).difference(box(0.5, 0.3, 2.5, 0.3 + slot_width))


regions = st.one_of(star_polygons(), box_unions()).map(pds.Region.from_shapely)


@st.composite
def multiscale_plates(draw):
    """A plate 8-30 units wide with holes from 0.1 to 3 units (boxes, or discs), a slot
    0.05-0.5 wide and a small separate part: features of very different sizes, for
    graded meshes. Holes never touch each other or the outline, so every convex corner
    is a right angle."""
    width = draw(st.floats(8, 30))
    plate = box(0, 0, width, 6)
    holes = []
    for size, x, y, disc in draw(st.lists(st.tuples(
            st.floats(0.1, 3.0), st.floats(0.1, 0.9), st.floats(0.1, 0.9), st.booleans()),
            min_size=1, max_size=6)):
        cx, cy = x * width, 1 + y * 4
        hole = Point(cx, cy).buffer(size / 2, quad_segs=6) if disc else box(
            cx - size / 2, cy - size / 2, cx + size / 2, cy + size / 2)
        if hole.buffer(0.3).within(plate) and not any(hole.buffer(0.3).intersects(h) for h in holes):
            holes.append(hole)
    slot = box(0.2 * width, 5 - draw(st.floats(0.05, 0.5)), 0.8 * width, 5)
    if not any(slot.buffer(0.3).intersects(h) for h in holes):
        holes.append(slot)
    part = box(width + draw(st.floats(0.05, 1.0)), 0, width + 2.5, draw(st.floats(0.3, 2)))
    return shapely.union_all([plate.difference(shapely.union_all(holes)), part])


def folded_star():
    """A star of the fuzz tests, scaled by 1e-3 and moved 1e5 away, whose ring runs out to
    a zero-width spike and back through the vertex before it (within rounding)."""
    return Polygon([
        (100000.00067095422, -49999.99996483678), (100000.00099862953, -49999.999947664044),
        (100000.00037448607, -49999.999980374014), (100000.00098431292, -49999.99982356851),
        (100000.00095463645, -49999.99970222614), (100000.00085128867, -49999.99947530238),
        (100000.0006950119, -49999.999281001765), (100000.00049552265, -49999.999131404984),
        (100000.00038336456, -49999.9990764029), (100000.00032492881, -49999.99905426152),
        (100000.00026522421, -49999.999035813235), (100000.0000184354, -49999.99900016995),
        (99999.99953683453, -49999.999113728176), (99999.99958431635, -49999.99972213833),
        (99999.9990039786, -49999.9999108856), (99999.99954159264, -50000.000199656424),
        (99999.99969343007, -50000.0003949872), (99999.99992032653, -50000.000493611326),
        (100000.0003650542, -50000.000085792926)])
