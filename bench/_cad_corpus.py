"""The real-CAD corpus of issue 20: sections of STL parts as CAD systems export them, and
the three ways each is meshed. Shared by ``bench/cad_corpus.py`` (the whole corpus, its
tables) and the tests (``tests/test_cad_corpus.py``: a fast slice that must be
certified; ``tests/test_fuzz.py``: the rest, drawn at random).

Two sources of sections:

- **shared**: the parts of ``../shared/data`` (:data:`SHARED_PARTS`), each cut at 7
  z levels, one in the middle of each of 7 equal slabs of its height (so all strictly
  inside its bounding box), at 2 tilted planes through the centre of its bounding box,
  and at the planes issue 20 names (:data:`ISSUE_PLANES`). A plane that lies on faces of
  the part is moved just above them (``pds.section(..., on_face="above")``). A part whose
  file is absent gives no case.
- **generated**: :data:`GENERATED_PARTS` solids made with manifold3d and trimesh the
  way CAD parts are made (plates with bolt holes and slots, rounded edges and fillets,
  pockets, bosses, flanges, shafts, housings, a torus-like ring), each of random size
  (seeded), placed at random angles and position as a part in an assembly is, written
  to binary STL (coordinates rounded to float32, as every STL export does), read back
  and cut at :data:`PLANES_PER_PART` random planes (seeded) strictly between its
  extremes along their normal. The rotation is applied before the export, so no face
  stays axis-aligned and float32 rounding bends every straight edge, as in a real export
  (rotating after reading would only repeat what a random plane already does).
- **occt** (asked for by name: ``bench/cad_corpus.py --source occt``, it needs the
  ``[step]`` extra): :data:`OCCT_PARTS`, the random B-rep parts of
  ``bench/_step_parts.py`` (flanges, rounded and chamfered blocks, knobs, rings, vases)
  as OpenCASCADE tessellates and writes them (FreeCAD's and CadQuery's STL, at chordal
  deflections :data:`OCCT_DEFLECTIONS`), every other one turned at random and written
  again as float32; cut like the generated parts.

Every case is named ``"<part> <plane>"`` (e.g. ``"teapot.stl z5/7"``,
``"g07-flange p2"``); :func:`case` rebuilds one from its name, so a failure reported by
the script is reproduced with::

    import sys; sys.path.insert(0, "bench")
    from _cad_corpus import case, mesh
    m = mesh(case("teapot.stl z5/7").region(), "graded auto")
    print(m.certificate())

Examples
--------
>>> [c.name for c in generated_cases()][:2]
['g00-bolted-plate p0', 'g00-bolted-plate p1']
>>> len(generated_cases()) == len(GENERATED_PARTS) * PLANES_PER_PART
True
"""

from __future__ import annotations

import io
import math
import os
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
"""The shared sample inputs; cases from them are left out when the folder is absent."""

SHARED_PARTS = ("ADIS16480.STL", "teapot.stl", "7_8ths_cube.stl", "featuretype.STL",
                "angle_block.STL", "multibody.stl", "shared.STL", "cylinder.stl",
                "unit_sphere.STL", "20mm-xyz-cube.stl")
Z_LEVELS = 7
TILTS = {"tilt-x": (25.0, (1.0, 0.0, 0.0)), "tilt-xy": (40.0, (1.0, 1.0, 0.0))}
"""Tilted planes through the centre of the bounding box: the z normal turned by the
angle (degrees) about the axis."""
ISSUE_PLANES = {"7_8ths_cube.stl": (-16.51, -5.55), "teapot.stl": (23.64,)}
"""z levels issue 20 reports failures at."""

GENERATED_SEED = int(os.environ.get("PDS_CORPUS_SEED", 20))
"""The seed of the generated parts and their planes; another seed (``bench/cad_corpus.py
--seed``, which sets ``PDS_CORPUS_SEED``) gives parts the corpus has never seen."""
PLANES_PER_PART = 5

GRADING = float(os.environ.get("PDS_CORPUS_GRADING", 0.2))
"""The graded mode's grading L (``bench/cad_corpus.py --grading``, which sets
``PDS_CORPUS_GRADING``): the default 0.2, or a steeper one (docs/graded.md, "Limits")."""

MODES = ("uniform auto", "graded auto", "uniform fine")
"""The three ways every section is meshed: uniform ``alpha="auto"``, graded
``alpha="auto"``, and uniform at alpha = the section's extent / :data:`FINE`."""
FINE = 150


def mesh(region, mode: str, seed: int = 0, **options):
    """Mesh ``region`` the way ``mode`` (one of :data:`MODES`) says; ``options`` go to
    :func:`pds_plugin.mesh_region` (e.g. ``max_samples``).

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> m = mesh(pds.Region.from_shapely(box(0, 0, 3, 1)), "uniform fine")
    >>> m.alpha == 3 / FINE
    True
    """
    import pds_plugin as pds

    if mode == "uniform auto":
        return pds.mesh_region(region, "auto", seed=seed, **options)
    if mode == "graded auto":
        return pds.mesh_region(region, "auto", seed=seed, graded=True, grading=GRADING,
                               **options)
    if mode == "uniform fine":
        x0, y0, x1, y1 = region.bounds
        return pds.mesh_region(region, max(x1 - x0, y1 - y0) / FINE, seed=seed, **options)
    raise ValueError(f"unknown mode {mode!r}; choose from {MODES}")


@dataclass(frozen=True)
class Case:
    """One section of one part: the part, the plane, and where the plane is."""

    source: str                   # "shared", "generated" or "occt"
    part: str                     # the file in ../shared/data, or the generated part's name
    plane: str                    # the plane's name within the part, e.g. "z3/7", "p2"
    origin: tuple                 # a point of the plane, in the part's coordinates
    normal: tuple                 # its unit normal

    @property
    def name(self) -> str:
        return f"{self.part} {self.plane}"

    def solid(self):
        """The part, as trimesh read it (from the shared file, or the generated STL)."""
        return {"shared": _shared_solid, "generated": _generated_solid,
                "occt": _occt_solid}[self.source](self.part)

    def region(self):
        """The section, as ``pds.section`` gives it (planes on faces moved just above)."""
        import pds_plugin as pds

        solid = DATA / self.part if self.source == "shared" else self.solid()
        return pds.section(solid, plane_origin=self.origin, plane_normal=self.normal,
                           on_face="above")

    def call(self) -> str:
        """The ``pds.section`` call that makes this region, for a bug report."""
        origin = ", ".join(repr(float(v)) for v in self.origin)
        normal = ", ".join(repr(float(v)) for v in self.normal)
        solid = (f'"../shared/data/{self.part}"' if self.source == "shared"
                 else f'_cad_corpus.case("{self.name}").solid()')
        return f'pds.section({solid}, ({origin}), ({normal}), on_face="above")'


# --- shared parts ------------------------------------------------------------------------

@lru_cache(maxsize=None)
def _shared_solid(name):
    import trimesh

    return trimesh.load_mesh(DATA / name)


def shared_cases(parts=SHARED_PARTS) -> list[Case]:
    """The sections of the shared parts present in ``../shared/data`` (none if absent)."""
    found = []
    for part in parts:
        if not (DATA / part).exists():
            continue
        lo, hi = _shared_solid(part).bounds
        centre = (lo + hi) / 2
        up = (0.0, 0.0, 1.0)
        for k in range(Z_LEVELS):
            z = lo[2] + (k + 0.5) / Z_LEVELS * (hi[2] - lo[2])
            found.append(Case("shared", part, f"z{k + 1}/{Z_LEVELS}",
                              _floats((centre[0], centre[1], z)), up))
        for name, (angle, axis) in TILTS.items():
            found.append(Case("shared", part, name, _floats(centre), _tilted(angle, axis)))
        for z in ISSUE_PLANES.get(part, ()):
            found.append(Case("shared", part, f"z={z:g}", _floats((centre[0], centre[1], z)), up))
    return found


def _tilted(angle, axis) -> tuple:
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    t = math.radians(angle)
    z = np.array([0.0, 0.0, 1.0])     # Rodrigues: z turned about the axis (axis ⟂ z)
    return _floats(z * math.cos(t) + np.cross(axis, z) * math.sin(t))


def _floats(values) -> tuple:
    return tuple(float(v) for v in values)


# --- generated parts ---------------------------------------------------------------------

def _m3():
    import manifold3d
    return manifold3d


def _segments(rng) -> int:
    """Circular segments of a CAD export's tessellation: coarse to fine."""
    return int(rng.choice([24, 32, 48, 64, 96]))


def _bolt(x, y, radius, height, segments):
    """A through-hole cutter: a cylinder around z from -1 to height + 1."""
    return _m3().Manifold.cylinder(height + 2, radius, circular_segments=segments).translate(
        (x, y, -1.0))


def _rounded_rectangle(width, depth, radius, segments):
    """A width x depth rectangle from the origin with corners rounded to ``radius``: a
    smaller one offset outwards with round joins, as a fillet is made."""
    m3 = _m3()
    inner = m3.CrossSection.square((width - 2 * radius, depth - 2 * radius)).translate(
        (radius, radius))
    return inner.offset(radius, m3.JoinType.Round, circular_segments=segments)


def _slot(x0, y0, x1, y1, radius, segments):
    """A 2D slot: the hull of two circles."""
    m3 = _m3()
    return m3.CrossSection.batch_hull([
        m3.CrossSection.circle(radius, segments).translate((x0, y0)),
        m3.CrossSection.circle(radius, segments).translate((x1, y1))])


def bolted_plate(rng):
    """A plate with 3-6 bolt holes of random sizes and a slot."""
    m3, s = _m3(), _segments(rng)
    w, d, t = rng.uniform(60, 140), rng.uniform(40, 90), rng.uniform(4, 15)
    part = m3.Manifold.cube((w, d, t))
    for _ in range(int(rng.integers(3, 7))):
        r = rng.uniform(2, 7)
        part -= _bolt(rng.uniform(r + 3, w - r - 3), rng.uniform(r + 3, d - r - 3), r, t, s)
    slot = _slot(0.3 * w, 0.5 * d, 0.7 * w, 0.5 * d, rng.uniform(2, 5), s)
    return part - m3.Manifold.extrude(slot, t + 2).translate((0, 0, -1))


def filleted_plate(rng):
    """A plate with rounded corners (an offset outline) and rounded-rectangle cut-outs."""
    m3, s = _m3(), _segments(rng)
    w, d, t = rng.uniform(50, 120), rng.uniform(40, 80), rng.uniform(3, 10)
    part = m3.Manifold.extrude(_rounded_rectangle(w, d, rng.uniform(3, 12), s), t)
    for fx in (0.25, 0.7):
        cw, cd = rng.uniform(0.1, 0.25) * w, rng.uniform(0.2, 0.5) * d
        cut = _rounded_rectangle(cw, cd, rng.uniform(1, min(cw, cd) / 2 - 0.1), s)
        part -= m3.Manifold.extrude(cut, t + 2).translate((fx * w, 0.25 * d, -1))
    return part


def pocketed_block(rng):
    """A block with a rounded pocket milled into its top, a boss on one side and a
    counterbored hole."""
    m3, s = _m3(), _segments(rng)
    w, d, h = rng.uniform(40, 90), rng.uniform(40, 90), rng.uniform(15, 40)
    part = m3.Manifold.cube((w, d, h))
    pw, pd = rng.uniform(0.3, 0.5) * w, rng.uniform(0.3, 0.6) * d
    pocket = m3.Manifold.extrude(_rounded_rectangle(pw, pd, rng.uniform(2, 6), s), h)
    part -= pocket.translate((0.1 * w, 0.2 * d, rng.uniform(0.3, 0.7) * h))
    boss_r = rng.uniform(4, 0.2 * min(w, d))
    boss = m3.Manifold.cylinder(rng.uniform(5, 15), boss_r, circular_segments=s)
    part += boss.translate((0.75 * w, 0.7 * d, h))
    bore = _bolt(0.75 * w, 0.25 * d, rng.uniform(2, 4), h, s)
    counterbore = m3.Manifold.cylinder(h, rng.uniform(5, 7), circular_segments=s)
    return part - bore - counterbore.translate((0.75 * w, 0.25 * d, 0.7 * h))


def flange(rng):
    """A turned flange (a revolved profile: disc, hub, bore) with a bolt circle."""
    m3, s = _m3(), _segments(rng)
    r_disc, r_hub, r_bore = rng.uniform(40, 80), rng.uniform(15, 25), rng.uniform(6, 12)
    t_disc, t_hub = rng.uniform(6, 14), rng.uniform(15, 35)
    profile = m3.CrossSection([np.array([[r_bore, 0], [r_disc, 0], [r_disc, t_disc],
                                         [r_hub, t_disc], [r_hub, t_hub], [r_bore, t_hub]])])
    part = m3.Manifold.revolve(profile, s)
    holes = int(rng.integers(4, 9))
    circle = 0.5 * (r_disc + r_hub)
    for k in range(holes):
        a = 2 * math.pi * k / holes
        part -= _bolt(circle * math.cos(a), circle * math.sin(a), rng.uniform(2.5, 5), t_disc, s)
    return part


def bracket(rng):
    """An L bracket: two plates joined with a round fillet inside the bend, holes in
    both legs."""
    m3, s = _m3(), _segments(rng)
    w, leg, t = rng.uniform(30, 70), rng.uniform(40, 80), rng.uniform(4, 10)
    fillet = rng.uniform(3, 10)
    part = m3.Manifold.cube((leg, w, t)) + m3.Manifold.cube((t, w, leg))
    corner = m3.Manifold.cube((fillet, w, fillet)).translate((t, 0, t))
    round_ = m3.Manifold.cylinder(w + 2, fillet, circular_segments=s).rotate((-90, 0, 0))
    part += corner - round_.translate((t + fillet, -1, t + fillet))
    r = rng.uniform(2, 5)
    part -= _bolt(0.7 * leg, 0.5 * w, r, t, s)
    return part - _bolt(0.7 * leg, 0.5 * w, r, t, s).rotate((0, -90, 0)).translate((-1e-3, 0, 0))


def torus_ring(rng):
    """A torus-like ring: a rounded rectangle revolved (an O-ring groove insert)."""
    m3, s = _m3(), _segments(rng)
    r_in, width, height = rng.uniform(10, 40), rng.uniform(4, 15), rng.uniform(4, 15)
    rounding = rng.uniform(0.5, min(width, height) / 2 - 0.1)
    profile = _rounded_rectangle(width, height, rounding, s).translate((r_in, 0))
    return m3.Manifold.revolve(profile, int(rng.choice([32, 48, 64, 128])))


def shaft(rng):
    """A stepped shaft with a groove and a flat (turned, then milled)."""
    m3, s = _m3(), _segments(rng)
    r1, r2 = rng.uniform(8, 15), rng.uniform(4, 7)
    l1, l2 = rng.uniform(20, 50), rng.uniform(20, 50)
    groove = rng.uniform(0.5, 2)
    profile = m3.CrossSection([np.array([[0, 0], [r1, 0], [r1, l1], [r2, l1], [r2, l1 + l2 / 2],
                                         [r2 - groove, l1 + l2 / 2],
                                         [r2 - groove, l1 + l2 / 2 + 2], [r2, l1 + l2 / 2 + 2],
                                         [r2, l1 + l2], [0, l1 + l2]])])
    part = m3.Manifold.revolve(profile, s)
    flat = m3.Manifold.cube((2 * r1, 2 * r1, 0.6 * l1)).translate((r1 * rng.uniform(0.6, 0.85),
                                                                   -r1, 0.2 * l1))
    return part - flat


def housing(rng):
    """A hollow box with rounded edges (the hull of eight spheres, minus a smaller one):
    a shell whose walls are curved at every edge."""
    m3, s = _m3(), _segments(rng)
    w, d, h = rng.uniform(30, 80), rng.uniform(30, 80), rng.uniform(20, 50)
    r, wall = rng.uniform(3, 8), rng.uniform(2, 5)

    def rounded_box(x, y, z, radius):
        balls = [m3.Manifold.sphere(radius, s).translate((i, j, k))
                 for i in (radius, x - radius) for j in (radius, y - radius)
                 for k in (radius, z - radius)]
        return m3.Manifold.batch_hull(balls)
    inside = rounded_box(w - 2 * wall, d - 2 * wall, h, max(r - wall, 1.0))
    part = rounded_box(w, d, h, r) - inside.translate((wall, wall, wall))
    return part - _bolt(w / 2, d / 2, rng.uniform(2, 5), h, s).translate((0, 0, -h / 2))


def cross_drilled_block(rng):
    """trimesh: a box with cylinder holes drilled along three axes (trimesh booleans)."""
    import trimesh

    s = _segments(rng)
    size = rng.uniform(20, 60, 3)
    part = trimesh.creation.box(extents=size)
    for axis, direction in enumerate(np.eye(3)):
        r = rng.uniform(0.08, 0.2) * np.delete(size, axis).min()
        hole = trimesh.creation.cylinder(radius=r, height=size[axis] * 1.5, sections=s)
        hole.apply_transform(trimesh.geometry.align_vectors((0, 0, 1), direction))
        hole.apply_translation(rng.uniform(-0.15, 0.15, 3) * size * (1 - direction))
        part = part.difference(hole)
    return part


def tube_with_bosses(rng):
    """trimesh: a tube (annulus) with capsule bosses welded on and a cross hole."""
    import trimesh

    s = _segments(rng)
    r_out, r_in, length = rng.uniform(10, 25), 0, rng.uniform(30, 80)
    r_in = r_out * rng.uniform(0.4, 0.8)
    part = trimesh.creation.annulus(r_min=r_in, r_max=r_out, height=length, sections=s)
    for z in (-0.25 * length, 0.25 * length):
        boss = trimesh.creation.capsule(height=2 * r_out, radius=rng.uniform(3, 0.4 * r_out),
                                        count=[s, s // 2])
        boss.apply_transform(trimesh.geometry.align_vectors((0, 0, 1), (1, 0, 0)))
        boss.apply_translation((0, 0, z))
        part = part.union(boss)
    hole = trimesh.creation.cylinder(radius=0.3 * r_in, height=4 * r_out, sections=s)
    hole.apply_transform(trimesh.geometry.align_vectors((0, 0, 1), (0, 1, 0)))
    return part.difference(hole)


BUILDERS = (bolted_plate, filleted_plate, pocketed_block, flange, bracket, torus_ring, shaft,
            housing, cross_drilled_block, tube_with_bosses)
GENERATED_PARTS = tuple(f"g{k:02d}-{BUILDERS[k % len(BUILDERS)].__name__.replace('_', '-')}"
                        for k in range(2 * len(BUILDERS)))
"""Each builder twice, with different random sizes."""


@lru_cache(maxsize=None)
def generated_stl(name: str) -> bytes:
    """The generated part ``name`` placed at random angles and position, as binary STL."""
    import trimesh
    from trimesh.transformations import random_rotation_matrix

    index = GENERATED_PARTS.index(name)
    rng = np.random.default_rng([GENERATED_SEED, index])
    solid = BUILDERS[index % len(BUILDERS)](rng)
    if not isinstance(solid, trimesh.Trimesh):
        shape = solid.to_mesh()
        solid = trimesh.Trimesh(shape.vert_properties[:, :3], shape.tri_verts)
    placement = random_rotation_matrix(rand=rng.random(3))
    placement[:3, 3] = rng.uniform(-200, 200, 3)
    solid.apply_transform(placement)
    return solid.export(file_type="stl")


@lru_cache(maxsize=None)
def _generated_solid(name):
    import trimesh

    return trimesh.load(io.BytesIO(generated_stl(name)), file_type="stl")


def generated_cases(parts=GENERATED_PARTS) -> list[Case]:
    """:data:`PLANES_PER_PART` random planes through each generated part, strictly between
    its extremes along the plane's normal (10 % of the extent kept clear at each end)."""
    return [found for part in parts for found in _random_planes(
        "generated", part, GENERATED_PARTS.index(part), _generated_solid(part).vertices)]


def _random_planes(source, part, index, vertices) -> list[Case]:
    """:func:`generated_cases`' planes through one part (``index``: its seed)."""
    rng = np.random.default_rng([GENERATED_SEED, index, 1])
    found = []
    for k in range(PLANES_PER_PART):
        normal = rng.normal(size=3)
        normal /= np.linalg.norm(normal)
        height = vertices @ normal
        level = height.min() + rng.uniform(0.1, 0.9) * np.ptp(height)
        centre = vertices.mean(axis=0)
        origin = centre + (level - centre @ normal) * normal
        found.append(Case(source, part, f"p{k}", _floats(origin), _floats(normal)))
    return found


# --- OpenCASCADE's exports ---------------------------------------------------------------

OCCT_DEFLECTIONS = (0.02, 0.1)
"""The chordal deflections (mm) the OCCT parts are tessellated at: fine and coarse."""
OCCT_PARTS = tuple(f"o{k:02d}-{name}@{deflection:g}" for k, name in enumerate(
    ("flange", "rounded-box", "chamfered-block", "knob", "ring", "vase") * 2)
                   for deflection in OCCT_DEFLECTIONS)
"""Each builder of ``_step_parts.HELD_OUT`` twice, at each deflection."""


@lru_cache(maxsize=None)
def occt_stl(name: str) -> bytes:
    """The OCCT part ``name`` as OpenCASCADE writes its STL (``_step_parts.write_stl``);
    odd parts turned at random and written again (float32)."""
    import tempfile

    import trimesh
    from trimesh.transformations import random_rotation_matrix

    import _step_parts

    index = int(name[1:3])
    rng = np.random.default_rng([GENERATED_SEED, index])
    shape, _ = _step_parts.HELD_OUT[index % len(_step_parts.HELD_OUT)](rng)
    with tempfile.TemporaryDirectory() as folder:
        written = _step_parts.write_stl(shape, Path(folder) / "part.stl",
                                        float(name.rsplit("@", 1)[1])).read_bytes()
    if not index % 2:
        return written
    solid = trimesh.load(io.BytesIO(written), file_type="stl")
    solid.apply_transform(random_rotation_matrix(rand=rng.random(3)))
    return solid.export(file_type="stl")


@lru_cache(maxsize=None)
def _occt_solid(name):
    import trimesh

    return trimesh.load(io.BytesIO(occt_stl(name)), file_type="stl")


def occt_cases(parts=OCCT_PARTS) -> list[Case]:
    """:func:`generated_cases`' planes through each OCCT part."""
    return [found for part in parts for found in _random_planes(
        "occt", part, OCCT_PARTS.index(part), _occt_solid(part).vertices)]


def all_cases() -> list[Case]:
    """Every case: the shared parts present, then the generated ones."""
    return shared_cases() + generated_cases()


FAST_SLICE = (
    ("featuretype.STL z4/7", "uniform auto"), ("featuretype.STL z4/7", "graded auto"),
    ("featuretype.STL z4/7", "uniform fine"), ("ADIS16480.STL z7/7", "uniform auto"),
    ("ADIS16480.STL z7/7", "graded auto"), ("multibody.stl tilt-x", "uniform fine"),
    ("20mm-xyz-cube.stl z4/7", "graded auto"), ("unit_sphere.STL tilt-xy", "graded auto"),
    ("7_8ths_cube.stl z=-16.51", "uniform auto"), ("7_8ths_cube.stl z=-5.55", "uniform auto"),
    ("teapot.stl z=23.64", "graded auto"), ("angle_block.STL z2/7", "uniform fine"),
    ("featuretype.STL tilt-x", "graded auto"), ("shared.STL z4/7", "uniform fine"),
    ("multibody.stl z7/7", "graded auto"))
"""(case, mode) pairs of shared parts the test suite meshes (``tests/test_cad_corpus.py``),
each in well under a second, among them every failure class of issue 20 that a shared
part shows; the fuzz suite draws from the rest (:func:`rest_of_corpus`)."""


def rest_of_corpus() -> list[tuple[str, str]]:
    """Every (case, mode) pair of the corpus but :data:`FAST_SLICE`'s."""
    return [(c.name, mode) for c in all_cases() for mode in MODES
            if (c.name, mode) not in FAST_SLICE]


def case(name: str) -> Case:
    """The case called ``name`` (e.g. ``"teapot.stl z5/7"``)."""
    part = name.rsplit(" ", 1)[0]
    pool = (shared_cases([part]) if part in SHARED_PARTS
            else generated_cases([part]) if part in GENERATED_PARTS
            else occt_cases([part]) if part in OCCT_PARTS else [])
    for found in pool:
        if found.name == name:
            return found
    raise KeyError(f"no case {name!r} (is ../shared/data present?)")
