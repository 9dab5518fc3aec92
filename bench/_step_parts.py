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
