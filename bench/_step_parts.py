"""B-rep parts made with OCP (OpenCASCADE) for bench/step_vs_stl.py and the STEP tests:
plates with holes, fillets, a pocket, a bolt, overlapping bodies. Each builder returns an
OCP ``TopoDS_Shape``; :func:`write` saves one as STEP, IGES or BREP, :func:`write_stl` as
the STL a CAD system would export (the mesh path's input).
"""

from __future__ import annotations

import math
from pathlib import Path


def _box(x, y, z, dx, dy, dz):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.gp import gp_Pnt

    return BRepPrimAPI_MakeBox(gp_Pnt(x, y, z), dx, dy, dz).Shape()


def _cylinder(x, y, z, radius, height, direction=(0, 0, 1)):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, z), gp_Dir(*direction)), radius,
                                    height).Shape()


def _cut(shape, *tools):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut

    for tool in tools:
        shape = BRepAlgoAPI_Cut(shape, tool).Shape()
    return shape


def _fuse(shape, *others):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse

    for other in others:
        shape = BRepAlgoAPI_Fuse(shape, other).Shape()
    return shape


def _fillet_vertical_edges(shape, radius):
    """Round every edge of ``shape`` parallel to z."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    from OCP.GeomAbs import GeomAbs_CurveType
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    fillet = BRepFilletAPI_MakeFillet(shape)
    explorer = TopExp_Explorer(shape, TopAbs_EDGE)
    while explorer.More():
        edge = TopoDS.Edge(explorer.Current())
        curve = BRepAdaptor_Curve(edge)
        if (curve.GetType() == GeomAbs_CurveType.GeomAbs_Line
                and abs(curve.Line().Direction().Z()) > 1 - 1e-9):
            fillet.Add(radius, edge)
        explorer.Next()
    return fillet.Shape()


def _prism(points, height, z=0.0):
    """A straight prism over the polygon ``points`` (x, y), from z to z + height."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakePolygon
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Pnt, gp_Vec

    polygon = BRepBuilderAPI_MakePolygon()
    for x, y in points:
        polygon.Add(gp_Pnt(x, y, z))
    polygon.Close()
    face = BRepBuilderAPI_MakeFace(polygon.Wire()).Face()
    return BRepPrimAPI_MakePrism(face, gp_Vec(0, 0, height)).Shape()


def _elliptic_cylinder(x, y, major, minor, height, z=0.0):
    from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace,
                                    BRepBuilderAPI_MakeWire)
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Ax2, gp_Dir, gp_Elips, gp_Pnt, gp_Vec

    edge = BRepBuilderAPI_MakeEdge(gp_Elips(gp_Ax2(gp_Pnt(x, y, z), gp_Dir(0, 0, 1)),
                                            major, minor)).Edge()
    face = BRepBuilderAPI_MakeFace(BRepBuilderAPI_MakeWire(edge).Wire()).Face()
    return BRepPrimAPI_MakePrism(face, gp_Vec(0, 0, height)).Shape()


def plate_with_holes():
    """A 100 x 60 x 10 plate with four bolt holes (r 5) and a central bore (r 12)."""
    holes = [_cylinder(x, y, -1, 5, 12) for x in (12, 88) for y in (12, 48)]
    return _cut(_box(0, 0, 0, 100, 60, 10), *holes, _cylinder(50, 30, -1, 12, 12))


def filleted_block():
    """An 80 x 50 x 20 block with its vertical edges rounded (r 8), an elliptic slot
    (semi-axes 12 and 6) and a hole (r 4)."""
    block = _fillet_vertical_edges(_box(0, 0, 0, 80, 50, 20), 8.0)
    return _cut(block, _elliptic_cylinder(30, 25, 12, 6, 22, z=-1), _cylinder(62, 25, -1, 4, 22))


def pocketed_plate():
    """A 120 x 80 x 20 plate with a 60 x 40 pocket 12 deep (corners rounded r 6) and an
    island boss (r 8) standing in the pocket."""
    pocket = _fillet_vertical_edges(_box(30, 20, 8, 60, 40, 13), 6.0)
    return _fuse(_cut(_box(0, 0, 0, 120, 80, 20), pocket), _cylinder(60, 40, 5, 8, 10))


def bolt():
    """An M10-like bolt: a hexagonal head (13 across flats, 6.4 high) on a shank (r 5,
    40 long), along z."""
    across = 13.0 / math.sqrt(3)
    head = _prism([(across * math.cos(k * math.pi / 3), across * math.sin(k * math.pi / 3))
                   for k in range(6)], 6.4, z=40.0)
    return _fuse(_cylinder(0, 0, 0, 5, 40.0 + 1.0), head)


def overlapping_bodies():
    """Two solids that overlap (a compound, not fused): a 40 x 40 x 10 block and a
    cylinder (r 15, height 10) centred on its corner."""
    from OCP.BRep import BRep_Builder
    from OCP.TopoDS import TopoDS_Compound

    compound, builder = TopoDS_Compound(), BRep_Builder()
    builder.MakeCompound(compound)
    builder.Add(compound, _box(0, 0, 0, 40, 40, 10))
    builder.Add(compound, _cylinder(40, 40, 0, 15, 10))
    return compound


PARTS = {"plate_with_holes": (plate_with_holes, 5.0), "filleted_block": (filleted_block, 10.0),
         "pocketed_plate": (pocketed_plate, 14.0), "bolt": (bolt, 20.0),
         "overlapping_bodies": (overlapping_bodies, 5.0)}
"""Each part's builder and the height of its z section."""


def _edges_rounded(shape, size, chamfer=False):
    """Every edge of ``shape`` filleted (radius ``size``) or chamfered (distance ``size``)."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeChamfer, BRepFilletAPI_MakeFillet
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    maker = (BRepFilletAPI_MakeChamfer if chamfer else BRepFilletAPI_MakeFillet)(shape)
    explorer = TopExp_Explorer(shape, TopAbs_EDGE)
    while explorer.More():
        maker.Add(size, TopoDS.Edge(explorer.Current()))
        explorer.Next()
    return maker.Shape()


def _flange(rng):
    """A disc with a hub, a bore and 4-8 bolt holes on a circle; cut through the hub."""
    radius, thick = rng.uniform(30, 60), rng.uniform(5, 12)
    body = _fuse(_cylinder(0, 0, 0, radius, thick),
                 _cylinder(0, 0, 0, radius * rng.uniform(0.35, 0.5), 2.5 * thick))
    turn = rng.uniform(0, 1)
    holes = [_cylinder(0.75 * radius * math.cos(a + turn), 0.75 * radius * math.sin(a + turn),
                       -1, rng.uniform(2, 0.12 * radius), 3 * thick + 2)
             for a in [2 * math.pi * k / n for n in [int(rng.integers(4, 9))] for k in range(n)]]
    bore = _cylinder(0, 0, -1, radius * rng.uniform(0.15, 0.3), 3 * thick + 2)
    return _cut(body, *holes, bore), (0.0, 0.0, thick * rng.uniform(1.2, 2.3))


def _rounded_box(rng):
    """A box with every edge filleted (cylinders and spherical corners)."""
    a, b, c = rng.uniform(20, 80, 3)
    shape = _edges_rounded(_box(0, 0, 0, a, b, c), rng.uniform(0.05, 0.2) * min(a, b, c))
    return shape, (a / 2, b / 2, c * rng.uniform(0.02, 0.98))


def _chamfered_block(rng):
    """A block with every edge chamfered and 1-4 holes."""
    a, b, c = rng.uniform(30, 90), rng.uniform(30, 90), rng.uniform(8, 25)
    block = _edges_rounded(_box(0, 0, 0, a, b, c), rng.uniform(0.5, 3), chamfer=True)
    holes = [_cylinder(rng.uniform(8, a - 8), rng.uniform(8, b - 8), -1, rng.uniform(1.5, 4),
                       c + 2) for _ in range(int(rng.integers(1, 5)))]
    return _cut(block, *holes), (a / 2, b / 2, c * rng.uniform(0.02, 0.98))


def _knob(rng):
    """A sphere on a cone."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCone, BRepPrimAPI_MakeSphere
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    radius = rng.uniform(10, 30)
    sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, radius), radius).Shape()
    cone = BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(0, 0, -radius), gp_Dir(0, 0, 1)),
                                0.3 * radius, 0.9 * radius, radius).Shape()
    return _fuse(sphere, cone), (0.0, 0.0, rng.uniform(-0.9, 1.9) * radius)


def _ring(rng):
    """A torus fused with a bar across it."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeTorus
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    big, small = rng.uniform(20, 50), rng.uniform(3, 10)
    torus = BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), big, small).Shape()
    bar = _box(-big - small, -2, -0.5 * small, 2 * (big + small), 4, small)
    return _fuse(torus, bar), (0.0, 0.0, rng.uniform(-0.8, 0.8) * small)


def _vase(rng):
    """A solid of revolution of a B-spline profile through 6 random radii, bored from
    above: a free-form face, whose cuts are B-splines."""
    from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace,
                                    BRepBuilderAPI_MakeWire)
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeRevol
    from OCP.GeomAPI import GeomAPI_PointsToBSpline
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt
    from OCP.OCP.collections import Array1_gp_Pnt

    height, radii = rng.uniform(40, 80), rng.uniform(8, 25, 6)
    profile = Array1_gp_Pnt(1, len(radii))
    for k, (radius, z) in enumerate(zip(radii, [height * k / 5 for k in range(6)])):
        profile.SetValue(k + 1, gp_Pnt(float(radius), 0, z))
    wire = BRepBuilderAPI_MakeWire()
    for edge in (BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(float(radii[0]), 0, 0)),
                 BRepBuilderAPI_MakeEdge(GeomAPI_PointsToBSpline(profile).Curve()),
                 BRepBuilderAPI_MakeEdge(gp_Pnt(float(radii[-1]), 0, height),
                                         gp_Pnt(0, 0, height)),
                 BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, height), gp_Pnt(0, 0, 0))):
        wire.Add(edge.Edge())
    solid = BRepPrimAPI_MakeRevol(BRepBuilderAPI_MakeFace(wire.Wire()).Face(),
                                  gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1))).Shape()
    bore = _cylinder(0, 0, 0.3 * height, 0.5 * radii.min(), height)
    return _cut(solid, bore), (0.0, 0.0, rng.uniform(0.05, 0.95) * height)


HELD_OUT = (_flange, _rounded_box, _chamfered_block, _knob, _ring, _vase)
"""Builders of random parts (each takes a numpy Generator) for ``step_vs_stl.py
--held-out SEED``: parts no rule was tuned on, drawn anew for each seed."""


def held_out(seed: int, count: int):
    """``count`` random parts of :data:`HELD_OUT` (in turn) and a plane through each:
    (name, shape, plane origin, unit normal), the normal tilted from z by up to 0.4 rad
    on every other part (ellipses, tilted B-splines)."""
    import numpy as np

    for k in range(count):
        rng = np.random.default_rng([seed, k])
        build = HELD_OUT[k % len(HELD_OUT)]
        shape, origin = build(rng)
        tilt = rng.uniform(0, 0.4) if k % 2 else 0.0
        yield (f"{seed}/{k} {build.__name__[1:]}", shape, origin,
               (math.sin(tilt), 0.0, math.cos(tilt)))


def write(shape, path) -> Path:
    """Save ``shape`` as STEP (.step, .stp), IGES (.iges, .igs) or BREP (.brep)."""
    from pds_plugin.silence import silenced

    path = Path(path)
    suffix = path.suffix.lower()
    with silenced():
        if suffix in (".step", ".stp"):
            from OCP.STEPControl import STEPControl_StepModelType, STEPControl_Writer

            writer = STEPControl_Writer()
            writer.Transfer(shape, STEPControl_StepModelType.STEPControl_AsIs)
            writer.Write(str(path))
        elif suffix in (".iges", ".igs"):
            from OCP.IGESControl import IGESControl_Writer

            writer = IGESControl_Writer("MM", 1)       # B-rep mode: faces and solids
            writer.AddShape(shape)
            writer.ComputeModel()
            writer.Write(str(path))
        else:
            from OCP.BRepTools import BRepTools

            BRepTools.Write_s(shape, str(path))
    return path


def write_stl(shape, path, deflection=0.01) -> Path:
    """Tessellate ``shape`` (chordal ``deflection``, 0.5 rad angular) and save it as STL."""
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.StlAPI import StlAPI_Writer

    BRepMesh_IncrementalMesh(shape, deflection, False, 0.5, True)
    StlAPI_Writer().Write(shape, str(path))
    return Path(path)
