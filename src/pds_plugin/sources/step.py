"""B-rep solids cut by planes: STEP, IGES and BREP files and OpenCASCADE shapes, through
OCP (the ``[step]`` extra), with the section's curves kept exact until they are flattened.

:func:`pds_plugin.section` and :func:`pds_plugin.sections` come here for a file named
``.step``, ``.stp``, ``.iges``, ``.igs``, ``.brep`` or ``.brp`` and for an OCP
``TopoDS_Shape`` (or an object wrapping one as ``.wrapped``: a cadquery or build123d
shape). OCP is imported when such a solid is read, never by ``import pds_plugin``.

Each solid the plane meets is cut where it is, in the plane's frame (:func:`_boolean`):
by OCCT's ``BRepAlgoAPI_Section`` where every face of the solid is a plane, cylinder,
cone, sphere, torus or surface of extrusion (:func:`_analytic`; 0.2 to 0.65 times the
Common's time there), its edges chained into loops by their shared vertices and nested
here (:meth:`StepSolid._section_loops`, :func:`_nested`); else (free-form or revolved
faces, where the Section takes 1.3 to 6.4 times the Common's time, 6 to 19 on a
threaded screw), or where the Section's edges do not close into loops, by
``BRepAlgoAPI_Common`` with a square face of the plane, no options, whose faces' wires
are the loops. Its 2D coordinates are those of a mesh section of the same plane, and
each edge of the cut is read once by ``BRepAdaptor_Curve`` as the exact curve it is:

- a **line** gives its two end points;
- a **circle** or an **ellipse** gives ``center + u cos θ + v sin θ``, flattened by
  :func:`.curves.elliptic_points` as the SVG and DXF readers flatten arcs: the chords'
  sagitta is at most the tolerance (proven: max|B''| = ||[u v]||₂ sweep²), and every
  vertex lies on the curve to rounding;
- a non-rational **B-spline** (OCCT's approximation of a cut through a free-form face,
  within its edge tolerance of the true curve) is split into Bézier pieces, flattened with
  the bound of :func:`.curves.bezier_points` (max|B''| from the control points);
- any other curve (rational, offset) by OCCT's ``GCPnts_QuasiUniformDeflection`` to the
  same tolerance (OCCT's check, not a proof).

Where a line meets a circle or an ellipse, the junction is moved to where the exact
curves meet (:func:`_junctions_refined`: OCCT's vertex is within its edge tolerance of
the conic, up to 1.9e-9 of the radius off it). The loops of each solid are the Section's
chained edges or the wires of the Common's faces (assembled by
:func:`.polygons.outline_geometry`, even-odd, only where a wire does not close or the
Region refuses the polygons), and the solids' polygons are
united, so assemblies and overlapping bodies give their union; a solid whose box the
plane misses is not cut.
Circles and ellipses are flattened finer for the area (:data:`AREA_ERROR`), and
B-splines too (:data:`SPLINE_AREA_ERROR`).
"""

from __future__ import annotations

import math
import os
import sys
import warnings
from dataclasses import dataclass

import numpy as np
import shapely

from .._checks import check_path, check_positive, import_optional
from ..boundary_curves import BoundaryCurves
from ..errors import RegionError, SectionError, SourceError
from ..region import Region
from ._sniff import misnamed
from .curves import (MAX_CHORDS, bezier_points, checked_file,
                     elliptic_points, steps)
from .planes import checked_on_face, checked_plane, places_in_3d, plane_frames
from .polygons import outline_geometry

__all__ = ["SUFFIXES", "RELATIVE_TOLERANCE", "AREA_ERROR", "SPLINE_AREA_ERROR",
           "ARC_REFINEMENT", "SectionCurve",
           "accepts", "load", "section_curves", "StepSolid"]

SUFFIXES = frozenset({".step", ".stp", ".iges", ".igs", ".brep", ".brp"})
"""File suffixes read through OpenCASCADE (case-insensitive)."""
RELATIVE_TOLERANCE = 1e-5
"""Default chord tolerance, as a fraction of the solid's diagonal."""
AREA_ERROR = 0.5e-6
"""By default circles and ellipses are flattened finer, so that their chords miss at most
this fraction of the section's area (see :data:`ARC_REFINEMENT`)."""
SPLINE_AREA_ERROR = 0.5e-6
"""B-splines are flattened finer too, so that their chords miss at most this fraction of
the section's area (a proven bound, :func:`_splines_within`): with the arcs'
:data:`AREA_ERROR`, the issue's 1e-6. None keeps B-splines at the default tolerance.
(It was off while the finer B-spline of featuretype.STEP at mid-height left its graded
``"auto"`` mesh a coverage gap of 1.15 r, behind the reflex end of an arc that bends both
ways: the graded sampler now moves that chord's end, docs/step.md.)"""
ARC_REFINEMENT = 300
"""Circles, ellipses and B-splines are flattened at most this many times finer than the
default tolerance scaled by the section's size over the solid's (17 times the vertices):
enough for the 5 mm shank of a 100 mm bolt (100 times finer missed 1.3e-6 of its area;
docs/step.md), and, scaled, for a small circle of a large part."""
SECTION_BOOLEAN = True
"""Cut the solids whose faces are all analytic (planes, cylinders, cones, spheres, tori,
surfaces of extrusion) by OCCT's ``BRepAlgoAPI_Section``, its edges chained into loops and
nested here, instead of its ``BRepAlgoAPI_Common`` (whose faces' wires are the loops,
nested): 0.2-0.65 times the Boolean's time on such parts (docs/step.md); the other
solids, and those whose Section does not close into loops, are cut by the Common."""
_ON_PLANE = 1e-9        # a planar face within this fraction of the solid's size is on the plane
_STEP_OFF = 1e-6        # on_face moves the plane by this fraction of the solid's size


@dataclass(frozen=True)
class SectionCurve:
    """One edge of a section, as OpenCASCADE reports it, in the plane's 2D frame.

    Attributes
    ----------
    kind : str
        ``"line"``, ``"circle"``, ``"ellipse"``, ``"bspline"`` (flattened with a proven
        bound) or ``"adaptive"`` (any other curve, flattened by OCCT).
    points : (k, 2) ndarray
        The flattened curve: within the tolerance of the exact curve; circles and
        ellipses have every vertex on the curve.
    center : (2,) ndarray or None
        Circles and ellipses: the centre.
    radii : (2, 2) ndarray or None
        Circles and ellipses: the conjugate radii u, v as columns (the curve is
        ``center + u cos θ + v sin θ``).
    edge_tolerance : float
        OCCT's bound on the distance between this edge and the true intersection of the
        plane and the face (about 1e-7 for analytic faces, the approximation's error for
        free-form ones).
    start, sweep : float
        Circles and ellipses: the parameter θ of the first point and its signed range
        (the points run from θ = start over sweep).
    bezier : tuple of (d + 1, 2) ndarray or None
        Non-rational B-splines: the control points of their Bézier pieces, in the order
        of the points (what the flattening is made from).
    face : str
        The face of the solid the edge was cut from: ``"face i"`` (``"solid k face i"``
        when the shape has several solids), ``i`` counting the solid's faces in
        OpenCASCADE's order (``TopExp_Explorer``, as CAD tools number them); ``""`` if
        OCCT's history does not say.
    """

    kind: str
    points: np.ndarray
    center: np.ndarray | None = None
    radii: np.ndarray | None = None
    edge_tolerance: float = 0.0
    start: float = 0.0
    sweep: float = 0.0
    bezier: tuple | None = None
    face: str = ""


def _made(kind, points, center=None, radii=None, edge_tolerance=0.0, start=0.0, sweep=0.0,
          bezier=None, face="") -> SectionCurve:
    """``SectionCurve(...)``, the same frozen object, made at a quarter of the cost of
    its ``__init__`` (which sets each field through ``object.__setattr__``: 1.8 µs, and
    a section makes two or three per edge)."""
    curve = object.__new__(SectionCurve)
    curve.__dict__.update(kind=kind, points=points, center=center, radii=radii,
                          edge_tolerance=edge_tolerance, start=start, sweep=sweep,
                          bezier=bezier, face=face)
    return curve


def _replaced(curve, **changes) -> SectionCurve:
    """``dataclasses.replace(curve, **changes)``, made as :func:`_made` makes a curve."""
    fields = dict(curve.__dict__)
    fields.update(changes)
    made = object.__new__(SectionCurve)
    made.__dict__.update(fields)
    return made


def accepts(solid) -> bool:
    """Whether ``solid`` is read here: a path with a B-rep suffix (:data:`SUFFIXES`), an
    OCP ``TopoDS_Shape``, or an object wrapping one (``.wrapped``).

    OCP is not loaded here: an OCP object exists only if OCP was imported already.

    Examples
    --------
    >>> accepts("bracket.STEP"), accepts("bracket.stl")
    (True, False)
    """
    if isinstance(solid, (str, os.PathLike)):
        return os.path.splitext(os.fspath(solid))[1].lower() in SUFFIXES
    return _shape_of(solid) is not None


def _shape_of(solid):
    """The ``TopoDS_Shape`` that ``solid`` is or wraps, else None."""
    if sys.modules.get("OCP") is None:
        return None
    topods = sys.modules.get("OCP.TopoDS")
    if topods is None:
        try:
            from OCP import TopoDS as topods         # cheap: OCP is loaded already
        except ImportError:
            return None
    for candidate in (solid, getattr(solid, "wrapped", None)):
        if isinstance(candidate, topods.TopoDS_Shape):
            return candidate
    return None


def _ocp(module: str):
    return import_optional(f"OCP.{module}", "step", "STEP, IGES and BREP solids")


def load(solid):
    """The ``TopoDS_Shape`` of a STEP, IGES or BREP file, or of an OCP shape.

    Parameters
    ----------
    solid : str, os.PathLike, OCP TopoDS_Shape, or an object with a ``.wrapped`` shape

    Returns
    -------
    OCP.TopoDS.TopoDS_Shape

    Raises
    ------
    MissingDependencyError
        If OCP is not installed (``pip install "pds_plugin[step]"``).
    FileNotFoundError, IsADirectoryError
        If there is no such file, or it is a folder.
    SourceError
        If the file is empty or OpenCASCADE cannot read it, or it holds no shape.

    Examples
    --------
    >>> load("absent.step")
    Traceback (most recent call last):
    ...
    FileNotFoundError: no such STEP file: 'absent.step'
    """
    shape = _shape_of(solid)
    if shape is not None:
        return shape
    suffix = os.path.splitext(check_path(solid))[1].lower()
    kind = {".iges": "IGES", ".igs": "IGES", ".brep": "BREP", ".brp": "BREP"}.get(suffix, "STEP")
    name = checked_file(solid, kind)
    _ocp("TopoDS")
    from ..silence import silenced

    with silenced():                       # OCCT reports its progress on stdout
        shape = _read(name, kind)
    if shape is None or shape.IsNull():
        other = misnamed(name, f"a {kind} file")
        raise SourceError(f"cannot read {name!r} as a {kind} file: "
                          f"{other or 'OpenCASCADE found no shape in it'}")
    return shape


def _read(name, kind):
    """The shape OpenCASCADE reads from the file, or None."""
    if kind == "BREP":
        from OCP.BRep import BRep_Builder
        from OCP.BRepTools import BRepTools
        from OCP.TopoDS import TopoDS_Shape

        shape = TopoDS_Shape()
        try:
            ok = BRepTools.Read_s(shape, name, BRep_Builder())
        except Exception:      # a broken BREP file raises Standard_Failure
            ok = False
        return shape if ok else None
    from OCP.IFSelect import IFSelect_RetDone

    if kind == "IGES":
        from OCP.IGESControl import IGESControl_Reader as Reader
    else:
        from OCP.STEPControl import STEPControl_Reader as Reader
    reader = Reader()
    if reader.ReadFile(name) != IFSelect_RetDone:
        return None
    reader.TransferRoots()
    return reader.OneShape()


def _explore(shape, kind: str) -> list:
    """The sub-shapes of ``shape`` of a kind ("SOLID", "FACE", "EDGE"), in OCCT's order."""
    from OCP.TopAbs import TopAbs_ShapeEnum
    from OCP.TopExp import TopExp_Explorer

    explorer = TopExp_Explorer(shape, getattr(TopAbs_ShapeEnum, f"TopAbs_{kind}"))
    found = []
    while explorer.More():
        found.append(explorer.Current())
        explorer.Next()
    return found


class StepSolid:
    """The solids of a B-rep shape, read once and cut by as many planes as asked (the
    counterpart of the mesh path's solid in :mod:`.solids`).

    Parameters
    ----------
    solid : str, os.PathLike or OCP shape
        As :func:`load`.
    tolerance : float, optional
        The chord tolerance of the flattened curves (absolute, in the part's units);
        :data:`RELATIVE_TOLERANCE` of the solid's diagonal by default.
    """

    def __init__(self, solid, tolerance=None):
        shape = load(solid)                # first: it says which extra OCP comes with
        self.name = "the shape" if _shape_of(solid) is not None else repr(os.fspath(solid))
        (self.solids, (low, high), self.planes, self.faces, self.boxes,
         self.face_boxes, self.analytic, self.face_index) = _facts(shape)
        if not self.solids:
            faces = len(_explore(shape, "FACE"))
            raise SourceError(f"{self.name} holds no solid ({faces} face(s) but no closed "
                              f"volume: a surface model?); export the part as a solid, or "
                              f"sew its faces into one")
        self.scale = float(np.linalg.norm(high - low))
        self.center = (low + high) / 2
        if not (np.isfinite(self.scale) and self.scale > 0):
            raise SourceError(f"{self.name} has no extent (an empty or degenerate solid)")
        self.tolerance = (RELATIVE_TOLERANCE * self.scale if tolerance is None
                          else check_positive(tolerance, "tolerance"))
        self.adaptive = tolerance is None       # arcs finer, for the area (_arc_tolerance)

    def heights(self, origin, normal) -> np.ndarray:
        """The solid's lowest and highest signed distance to the plane."""
        low, high = _box(self._moved(_to_2d(origin, normal)))
        return np.array([low[2], high[2]])

    def cut(self, origin, normal, on_face=None) -> Region:
        """The section by the plane through ``origin`` (unit ``normal``) as a Region, with
        its exact curves (``region.curves``, each labelled by the face it was cut from)."""
        origin = self._off_faces(origin, normal, on_face)
        to_2d, to_3d = plane_frames(origin, normal)
        offset = float(origin @ normal)
        cuts = []                                   # each solid's faces and curves
        for number in self._met(origin, normal):
            solid = self.solids[number]
            faces, curves = self._cut_curves(solid, number, origin, to_2d,
                                             arcs=None if self.adaptive else self.tolerance)
            if curves:
                cuts.append((faces, curves))
        if self.adaptive:
            cuts = self._refined(cuts, offset, to_3d)
        # one solid's polygons are checked by the Region (GEOS validity), not twice: if
        # they are not valid, the curves are assembled by even-odd nesting instead
        geometry = self._polygons(cuts, offset, to_3d, checked=len(cuts) > 1)
        if geometry.is_empty or geometry.area == 0:
            self._refuse_empty(to_2d, offset)
        pieces = [c for _, curves in cuts for c in curves]
        curves = _boundary_curves(pieces, self.tolerance)
        try:
            return Region.from_shapely(geometry, frame=to_3d, curves=curves)
        except RegionError:           # polygons not valid: the wires nested even-odd
            if len(cuts) != 1:            # (a second RegionError is the nesting's own)
                raise
        geometry = self._polygons(cuts, offset, to_3d, checked=True)
        return Region.from_shapely(geometry, frame=to_3d, curves=curves)

    def _refined(self, cuts, offset, to_3d) -> list:
        """The cuts with their circles and ellipses flattened (they come as their two
        ends), their chords missing at most :data:`AREA_ERROR` of the section's area, and
        their B-splines flattened again if :data:`SPLINE_AREA_ERROR` is set, within it
        (proven bounds), at most :data:`ARC_REFINEMENT` times finer than
        :attr:`tolerance`.

        The area is read before anything is flattened finer: exactly along circles and
        ellipses (½∮(x dy - y dx) in closed form), along the other curves' default
        flattening, from one solid's wires. Several solids may overlap: their union's
        area is at least the sum of theirs less the areas where their boxes overlap (and
        at least the largest), and that bound sets the budget (the union of coarse
        polygons, built for it, cost more than the rest of the refinement)."""
        if not cuts:
            return cuts
        if len(cuts) == 1:
            area = _wire_area(*cuts[0])
        else:
            areas = [_wire_area(faces, curves) for faces, curves in cuts]
            boxes = [_bounds(curves) for _, curves in cuts]
            overlap = 0.0
            for k, (lx, ly, hx, hy) in enumerate(boxes):
                for mx, my, nx, ny in boxes[k + 1:]:
                    overlap += (max(0.0, min(hx, nx) - max(lx, mx))
                                * max(0.0, min(hy, ny) - max(ly, my)))
            area = max(max(areas), sum(areas) - overlap)
        curves = [c for _, cs in cuts for c in cs]
        budget = AREA_ERROR * area
        # the floor scales with the section: a 3 mm circle of a 75 mm part (a sphere cut
        # near its pole) missed 1.1e-6 of its area at the part's floor
        floor = self.tolerance * min(1.0, _extent(curves) / self.scale) / ARC_REFINEMENT
        # an inscribed chord of sagitta s and length c misses at most 2 s c / 3 of its
        # arc's segment; an arc is at most its larger radius times |sweep| long (OCCT's
        # radii u, v are perpendicular)
        conics = [c for c in curves if c.center is not None]
        length = 0.0
        for c in conics:
            (ux, vx), (uy, vy) = c.radii.tolist()
            length += max(math.hypot(ux, uy), math.hypot(vx, vy)) * abs(c.sweep)
        arcs = (self.tolerance if length == 0 else
                min(self.tolerance, max(floor, 1.5 * budget / length)))
        splines = ({} if SPLINE_AREA_ERROR is None else
                   _splines_within([c for c in curves if c.bezier is not None],
                                   SPLINE_AREA_ERROR * area, self.tolerance, floor))
        splines.update(_arcs_flattened(conics, arcs))
        if not splines:
            return cuts
        return [(faces, [splines.get(id(c), c) for c in cs]) for faces, cs in cuts]

    def _polygons(self, cuts, offset, to_3d, checked=True):
        """The union of the solids' sections, each from its faces' wires (or its curves
        by even-odd nesting, which reports open ends, where the wires do not close or,
        if ``checked``, their polygons are not valid; unchecked, a Region checks them)."""
        parts = []
        for faces, curves in cuts:
            join = max(1e-9 * self.scale, 2 * max(c.edge_tolerance for c in curves))
            geometry = _face_polygons(faces, curves, join, checked)
            if geometry is None:           # the faces' wires do not close: say where
                geometry, open_ends = outline_geometry([c.points for c in curves], join)
                if len(open_ends):
                    raise SectionError(
                        f"the section of {self.name} at normal·x = {offset:.9g} is open "
                        f"({len(open_ends)} open end(s), at {places_in_3d(open_ends, to_3d)}): "
                        f"the solid is not closed where the plane cuts it; repair it in CAD "
                        f"(sew its faces) or move the plane")
            parts.append(geometry)
        if not parts:
            return shapely.Polygon()
        return parts[0] if len(parts) == 1 else shapely.union_all(parts)

    def curves(self, origin, normal, on_face=None) -> list[SectionCurve]:
        """The section's edges as :class:`SectionCurve` objects (see
        :func:`section_curves`)."""
        origin = self._off_faces(origin, normal, on_face)
        to_2d = _to_2d(origin, normal)
        curves = [curve for number in self._met(origin, normal)
                  for curve in self._cut_curves(self.solids[number], number, origin, to_2d,
                                                self.tolerance)[1]]
        if not curves:
            self._refuse_empty(to_2d, float(origin @ normal))
        return curves

    def _moved(self, to_2d) -> list:
        """The solids moved so that the plane is z = 0 (a location: no copy)."""
        from OCP.gp import gp_Trsf
        from OCP.TopLoc import TopLoc_Location

        transform = gp_Trsf()
        transform.SetValues(*np.asarray(to_2d, dtype=float)[:3].ravel())
        location = TopLoc_Location(transform)
        return [solid.Moved(location) for solid in self.solids]

    def _cut_curves(self, solid, number, origin, to_2d, arcs=None, section=None):
        """The faces of the cut of one solid by the plane whose frame is ``to_2d``
        (:meth:`_common_faces`, or the loops of :meth:`_section_loops` if ``section``,
        by default where :data:`SECTION_BOOLEAN` and the solid is :func:`_analytic`, and
        the Section's edges close into loops) and their edges' curves in that frame's 2D
        coordinates, wire after wire, each labelled by the solid's face it lies on;
        circles and ellipses flattened within ``arcs``, or as their two ends if None
        (:func:`_finer` flattens them later)."""
        normal = np.asarray(to_2d, dtype=float)[2, :3]
        if section is None:
            section = SECTION_BOOLEAN and self.analytic[number]
        faces = self._section_loops(solid, origin, to_2d) if section else None
        if faces is None:
            faces = self._common_faces(solid, origin, to_2d, self._reach(origin))
        edges = [edge for face in faces for wire in face for edge, _ in wire]
        prefix = number if len(self.solids) > 1 else None
        labels = (_ancestor_labels(edges, faces.common, self.faces[number],
                                   self.face_index[number], prefix)
                  if faces.loose else None)
        if labels is None:
            # the faces whose boxes the plane meets are asked first (the others cannot
            # have made an edge of the cut, and are asked only if some edge is unnamed)
            center, half = self.face_boxes[number]
            reach = half @ np.abs(normal) + _ON_PLANE * self.scale
            near = np.abs((center - origin) @ normal) <= reach
            order = np.concatenate([np.flatnonzero(near), np.flatnonzero(~near)]).tolist()
            labels = _face_labels(edges, self.faces[number], faces.common, prefix, order)
        frame = np.asarray(to_2d, dtype=float)[:2]
        rows = tuple(frame.ravel().tolist())            # the same map, as plain floats
        curves = [_flattened(edge, self.tolerance, frame, arcs, label, reversed_, rows)
                  for label, (edge, reversed_)
                  in zip(labels, (pair for face in faces for wire in face for pair in wire))]
        return faces, _junctions_refined(faces, curves, arcs)

    def _common_faces(self, solid, origin, to_2d, reach) -> list:
        """The cut of one solid by the plane through ``origin`` whose frame is ``to_2d``
        (its rows: the plane's x and y axes, then its normal): the faces of its common
        with the square [-reach, reach]² of that plane about ``origin``, in the frame's
        axes, each as its wires (outer first), each wire its edges in order with whether
        each runs reversed. The solid is cut where it is: moved so that the plane is
        z = 0 (a located shape), it made the Boolean 10-15 % slower. OCCT's Common gives
        the same curves as its Section (B-splines through a surface of extrusion within
        their edge tolerance: the Section approximates them without the Common's
        pcurves), and is faster on free-form faces: 0.85 s against 12-16 s on the thread
        of M6-1x12-countersunk-screw.step; and its faces' wires are the section's loops,
        already nested. The faces carry the Common as ``.common``."""
        occ = _occ()
        BRepTools, BRepTools_WireExplorer = occ.BRepTools, occ.BRepTools_WireExplorer
        TopoDS, TopoDS_Iterator = occ.TopoDS, occ.TopoDS_Iterator

        common = _boolean(solid, origin, to_2d, reach)
        if not common.IsDone():
            raise SectionError(f"OpenCASCADE could not cut {self.name} with the plane; "
                               f"check the solid (BRepCheck) or move the plane")
        faces = _Faces(common)
        reversed_ = occ.REVERSED
        explorer = occ.TopExp_Explorer(common.Shape(), occ.FACE)
        while explorer.More():        # a plane touching an edge gives a line, not
            face = TopoDS.Face(explorer.Current())      # material: no face
            explorer.Next()
            wires, children = [], TopoDS_Iterator(face)
            while children.More():
                wires.append(children.Value())
                children.Next()
            if len(wires) > 1:
                outer = BRepTools.OuterWire_s(face)
                wires = [outer] + [w for w in wires if not w.IsSame(outer)]
            ordered = []
            for wire in wires:
                if wire.NbChildren() == 1:   # one edge (a whole circle): nothing to order,
                    edge = TopoDS.Edge(TopoDS_Iterator(wire).Value())   # no explorer
                    ordered.append([(edge, edge.Orientation() == reversed_)])
                    continue
                walk, edges = BRepTools_WireExplorer(TopoDS.Wire(wire), face), []
                while walk.More():
                    edges.append((walk.Current(), walk.Orientation() == reversed_))
                    walk.Next()
                ordered.append(edges)
            faces.append(ordered)
        return faces

    def _section_loops(self, solid, origin, to_2d):
        """The cut of one solid by OCCT's Section (:func:`_boolean`): its edges chained
        into closed loops by the vertices they share, each loop a "face" of one wire of
        ``(edge, reversed)`` (not nested: :func:`_nested` nests their rings), the
        Section as ``.common``; None where the edges do not make closed loops (a plane
        touching a face, two loops meeting at a vertex, OCCT failing): the Common
        then cuts the solid."""
        occ = _occ()
        TopExp, TopoDS = occ.TopExp, occ.TopoDS
        cut = _boolean(solid, origin, to_2d, 0.0, section=True)      # (no face: no reach)
        if not cut.IsDone():
            return None
        edges, ends = [], {}
        explorer = occ.TopExp_Explorer(cut.Shape(), occ.EDGE)
        first, last = occ.TopoDS_Vertex(), occ.TopoDS_Vertex()     # filled edge by edge
        while explorer.More():
            edge = TopoDS.Edge(explorer.Current())
            explorer.Next()
            TopExp.Vertices_s(edge, first, last)       # its FirstVertex and LastVertex
            if first.IsNull() or last.IsNull():
                return None
            one, other = hash(first), hash(last)
            ends.setdefault(one, []).append(len(edges))
            ends.setdefault(other, []).append(len(edges))
            edges.append((edge, one, other))
        if any(len(at) != 2 for at in ends.values()):
            return None                     # an open end, or loops meeting at a vertex
        faces, used = _Faces(cut, loose=True), [False] * len(edges)
        for start in range(len(edges)):
            if used[start]:
                continue
            loop, k, vertex = [], start, edges[start][1]
            while not used[k]:
                used[k] = True
                edge, first, last = edges[k]
                reversed_ = first != vertex          # entered at its last vertex
                loop.append((edge, reversed_))
                vertex = first if reversed_ else last
                one, other = ends[vertex]
                k = other if one == k else one
            if k != start:
                return None
            faces.append([loop])
        return faces

    def _met(self, origin, normal) -> list[int]:
        """The solids (by number) whose boxes the plane meets: all of one solid's shape;
        in an assembly, a solid whose box, with its tolerances and 1e-9 of the part's
        size, lies on one side of the plane has no material in it and is not cut."""
        if self.boxes is None:
            return list(range(len(self.solids)))
        center = (self.boxes[:, :3] + self.boxes[:, 3:]) / 2
        half = (self.boxes[:, 3:] - self.boxes[:, :3]) / 2
        distance = (center - origin) @ normal
        reach = half @ np.abs(normal) + _ON_PLANE * self.scale
        return [int(k) for k in np.flatnonzero(np.abs(distance) <= reach)]

    def _reach(self, origin) -> float:
        """A half-width of the plane's square about ``origin`` that holds every solid."""
        return 2 * (float(np.linalg.norm(self.center - origin)) + self.scale)

    def _faces_on(self, origin, normal) -> int:
        """How many planar faces of the solids lie on the plane."""
        facing, offsets = self.planes
        parallel = np.abs(facing @ normal) >= 1 - 1e-12
        return int((parallel & (np.abs(offsets - facing @ origin)
                                <= _ON_PLANE * self.scale)).sum())

    def _off_faces(self, origin, normal, on_face):
        """The plane origin, moved off the planar faces it lies on as ``on_face`` says
        ("nearest": the automatic planes of :func:`pds_plugin.sections`, with a warning),
        or refused when ``on_face`` is None."""
        flat = self._faces_on(origin, normal)
        offset = float(origin @ normal)
        if flat and on_face is None:
            raise SectionError(
                f"the plane lies on {flat} face(s) of {self.name} (normal·x = {offset:.9g}), "
                f"so the section is ambiguous; pass on_face='above' or 'below' (CLI: "
                f"--on-face above or below), or move the plane")
        if not flat:
            return origin
        step = _STEP_OFF * self.scale
        for shift in ([step, -step] if on_face == "nearest" else
                      [step if on_face == "above" else -step]):
            for _ in range(20):
                moved = origin + shift * normal
                if not self._faces_on(moved, normal):
                    if on_face == "nearest":
                        warnings.warn(
                            f"the plane at normal·x = {offset:.9g} lies on {flat} face(s) of "
                            f"{self.name}; cut at {offset + shift:.9g} instead, just "
                            f"{'above' if shift > 0 else 'below'} them", UserWarning,
                            stacklevel=5)
                    return moved
                shift *= 2
        return origin

    def _refuse_empty(self, to_2d, offset):
        """The error for a plane that cuts no material: it misses the solid (the message
        gives the solid's extent along the normal), or only touches it."""
        low, high = _box(self._moved(to_2d))
        margin = _ON_PLANE * self.scale
        if low[2] > margin or high[2] < -margin:
            raise SectionError(
                f"the plane misses {self.name}: it is at normal·x = {offset:.9g} but the "
                f"solid spans normal·x in [{offset + low[2]:.9g}, {offset + high[2]:.9g}]; "
                f"put the plane origin inside that range")
        raise SectionError(
            f"the plane at normal·x = {offset:.9g} cuts no material of {self.name}, which "
            f"spans normal·x in [{offset + low[2]:.9g}, {offset + high[2]:.9g}] (it only "
            f"touches the solid, or passes through a gap between parts); move the plane")


_OCC = None


def _occ():
    """The OCP classes a section uses, imported at the first section (not with this
    module: ``import pds_plugin`` loads no OCP) and kept: an import statement in a function
    runs importlib's Python-level ``_handle_fromlist`` at every call, 80 calls a section
    of plate_with_holes."""
    global _OCC
    if _OCC is None:
        from types import SimpleNamespace

        from OCP.BRep import BRep_Tool
        from OCP.BRepAdaptor import BRepAdaptor_Curve
        from OCP.BRepAlgoAPI import BRepAlgoAPI_Common, BRepAlgoAPI_Section
        from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
        from OCP.BRepTools import BRepTools, BRepTools_WireExplorer
        from OCP.GeomAbs import GeomAbs_CurveType
        from OCP.gp import gp_Ax3, gp_Dir, gp_Pln, gp_Pnt
        from OCP.TopAbs import TopAbs_Orientation, TopAbs_ShapeEnum
        from OCP.TopExp import TopExp, TopExp_Explorer
        from OCP.TopoDS import TopoDS, TopoDS_Iterator, TopoDS_Shape, TopoDS_Vertex

        _OCC = SimpleNamespace(
            BRep_Tool=BRep_Tool, BRepAdaptor_Curve=BRepAdaptor_Curve,
            BRepAlgoAPI_Common=BRepAlgoAPI_Common, BRepAlgoAPI_Section=BRepAlgoAPI_Section,
            BRepBuilderAPI_MakeFace=BRepBuilderAPI_MakeFace, BRepTools=BRepTools,
            BRepTools_WireExplorer=BRepTools_WireExplorer, Kind=GeomAbs_CurveType,
            gp_Ax3=gp_Ax3, gp_Dir=gp_Dir, gp_Pln=gp_Pln, gp_Pnt=gp_Pnt,
            REVERSED=TopAbs_Orientation.TopAbs_REVERSED, FACE=TopAbs_ShapeEnum.TopAbs_FACE,
            EDGE=TopAbs_ShapeEnum.TopAbs_EDGE, TopExp=TopExp, TopExp_Explorer=TopExp_Explorer, TopoDS=TopoDS, TopoDS_Iterator=TopoDS_Iterator,
            TopoDS_Shape=TopoDS_Shape, TopoDS_Vertex=TopoDS_Vertex,
            LINE=GeomAbs_CurveType.GeomAbs_Line.value,
            CIRCLE=GeomAbs_CurveType.GeomAbs_Circle.value,
            ELLIPSE=GeomAbs_CurveType.GeomAbs_Ellipse.value)
    return _OCC


def _facts(shape) -> tuple:
    """The solids of ``shape``, the corners of their bounding box, their planar faces
    (:func:`_planar_faces`) and each solid's faces in OCCT's order (for the labels),
    kept for the last :data:`_KEPT` shapes: a section of a loaded shape
    (``pds.section(shape, ...)`` in a loop over planes) reads them once, not 1 ms per
    call on a small part (a shape is not changed in place; the same object, at the
    same place and orientation, is the same solid)."""
    key = hash(shape)
    kept = _KEPT_FACTS.get(key)
    if kept is not None and kept[0].IsEqual(shape):
        return kept[1]
    from OCP.TopoDS import TopoDS

    solids = [TopoDS.Solid(s) for s in _explore(shape, "SOLID")]
    faces = [[TopoDS.Face(face) for face in _explore(solid, "FACE")] for solid in solids]
    # each solid's box (with its tolerances: never tighter than the solid) in an
    # assembly, so that a plane cuts only the solids it meets (one Boolean each)
    boxes = (np.array([np.concatenate(_box([solid], True)) for solid in solids])
             if len(solids) > 1 else None)
    facts = (solids, _box(solids) if solids else (np.zeros(3), np.zeros(3)),
             _planar_faces(faces), faces, boxes, [_face_boxes(f) for f in faces],
             [_analytic(f) for f in faces],
             [{hash(face): k for k, face in reversed(list(enumerate(f)))} for f in faces])
    _KEPT_FACTS[key] = (shape, facts)
    while len(_KEPT_FACTS) > _KEPT:
        _KEPT_FACTS.pop(next(iter(_KEPT_FACTS)))
    return facts


def _analytic(faces) -> bool:
    """Whether every face is a plane, a cylinder, a cone, a sphere, a torus or a surface
    of linear extrusion: the solids that :data:`SECTION_BOOLEAN` cuts by OCCT's Section
    (0.2-0.65 times the time of its Common on such parts; 1.3-6.4 times on surfaces of
    revolution and B-spline surfaces, docs/step.md)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_SurfaceType as Kind

    kinds = {Kind.GeomAbs_Plane, Kind.GeomAbs_Cylinder, Kind.GeomAbs_Cone,
             Kind.GeomAbs_Sphere, Kind.GeomAbs_Torus, Kind.GeomAbs_SurfaceOfExtrusion}
    return all(BRepAdaptor_Surface(face, False).GetType() in kinds for face in faces)


def _face_boxes(faces) -> tuple[np.ndarray, np.ndarray]:
    """The centres (n, 3) and half-widths (n, 3) of the faces' bounding boxes, with
    their tolerances (OCCT's fast box: never tighter than the face)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    corners = []
    for face in faces:
        box = Bnd_Box()
        BRepBndLib.Add_s(face, box, False)
        if box.IsVoid():
            corners.append((-np.inf,) * 3 + (np.inf,) * 3)
        else:
            corners.append(box.CornerMin().Coord() + box.CornerMax().Coord())
    corners = np.array(corners, dtype=float).reshape(-1, 6)
    with np.errstate(invalid="ignore"):
        center = np.nan_to_num((corners[:, :3] + corners[:, 3:]) / 2)
    return center, (corners[:, 3:] - corners[:, :3]) / 2


_KEPT = 2
"""Shapes whose :func:`_facts` are kept (each keeps its shape alive)."""

_KEPT_FACTS: dict = {}


class _Faces(list):
    """The faces of a cut (each its wires of ``(edge, reversed)``), with the Boolean that
    made them as ``common`` (its history names the solid's face of each edge)."""

    def __init__(self, common, loose=False):
        super().__init__()
        self.common = common
        self.loose = loose          # each "face" one loop of a Section, not yet nested


def _boolean(solid, origin, to_2d, reach, section=False):
    """OpenCASCADE's Boolean that cuts one solid: ``BRepAlgoAPI_Common`` of ``solid`` and
    the square [-reach, reach]² of the plane through ``origin`` whose frame is ``to_2d``
    (its rows: the plane's x and y axes, then its normal), no options. It is the only
    Boolean a section runs (one per solid the plane meets): ``bench/step_vs_stl.py``
    times it alone as "the Boolean's own time".

    With ``section``, OCCT's ``BRepAlgoAPI_Section`` of ``solid`` and the plane instead
    (its edges only, with ``Approximation(True)``, as the Common computes its curves),
    the Boolean of the solids whose faces are all analytic (:func:`_analytic`).

    Returns
    -------
    OCP.BRepAlgoAPI.BRepAlgoAPI_Common or BRepAlgoAPI_Section
        Built (``.Shape()`` is the cut, ``.History()`` names the faces its edges are cut
        from).
    """
    occ = _occ()
    (xx, xy, xz, _), _, (nx, ny, nz, _) = np.asarray(to_2d, dtype=float)[:3].tolist()
    ox, oy, oz = np.asarray(origin, dtype=float).tolist()
    frame = occ.gp_Ax3(occ.gp_Pnt(ox, oy, oz), occ.gp_Dir(nx, ny, nz), occ.gp_Dir(xx, xy, xz))
    if section:
        cut = occ.BRepAlgoAPI_Section(solid, occ.gp_Pln(frame), False)
        cut.Approximation(True)
        cut.Build()
        return cut
    plane = occ.BRepBuilderAPI_MakeFace(occ.gp_Pln(frame), -reach, reach, -reach,
                                        reach).Face()
    return occ.BRepAlgoAPI_Common(solid, plane)


def _face_labels(edges, solid_faces, common, number, order=None) -> list[str]:
    """The face of a solid (``solid_faces``: its faces in OCCT's order) each section edge
    was cut from, as ``"face i"`` (``"solid k face i"`` when ``number`` is not None), from
    the Boolean's history, asking the faces in ``order`` (their indices; all, in OCCT's
    order, by default) until every edge is named; ``""`` where it says nothing."""
    if not edges:
        return []
    wanted = {}
    for edge in edges:
        wanted.setdefault(hash(edge), []).append(edge)
    found = {}
    prefix = "" if number is None else f"solid {number} "
    history = common.History()
    for index in range(len(solid_faces)) if order is None else order:
        generated = history.Generated(solid_faces[index])
        size = generated.Size()       # an OCCT list's ends cost microseconds, iterating
        if not size:                  # the list itself a quarter of a millisecond
            continue
        for made in ((generated.First(),) if size == 1 else
                     (generated.First(), generated.Last()) if size == 2 else list(generated)):
            for edge in wanted.get(hash(made), ()):
                if edge.IsSame(made):
                    found.setdefault(hash(made), f"{prefix}face {index}")
        if len(found) == len(wanted):
            break
    return [found.get(hash(edge), "") for edge in edges]


def _ancestor_labels(edges, section, solid_faces, index, number):
    """The labels of :func:`_face_labels` for the edges of OCCT's Section, each read
    directly: the solid's face it lies on (``HasAncestorFaceOn1``), found among
    ``solid_faces`` by ``index`` (their hashes); None if an edge's face is not found (the
    history then names them). A third of the time of the history, and no ordering of
    the faces by their boxes (0.03-0.05 ms a section)."""
    TopoDS_Shape = _occ().TopoDS_Shape
    prefix = "" if number is None else f"solid {number} "
    labels = []
    for edge in edges:
        face = TopoDS_Shape()
        if not section.HasAncestorFaceOn1(edge, face):
            return None
        at = index.get(hash(face))
        if at is None or not solid_faces[at].IsSame(face):
            return None
        labels.append(f"{prefix}face {at}")
    return labels


def _extent(curves) -> float:
    """The diagonal of a box holding the curves (circles and ellipses whole)."""
    low_x, low_y, high_x, high_y = _bounds(curves)
    return math.hypot(high_x - low_x, high_y - low_y)


def _bounds(curves) -> tuple[float, float, float, float]:
    """``(xmin, ymin, xmax, ymax)`` of a box holding the curves (circles and ellipses
    whole)."""
    boxes = [_box_of(curve) for curve in curves]
    if not boxes:
        return math.inf, math.inf, -math.inf, -math.inf
    low_x, low_y, high_x, high_y = zip(*boxes)
    return min(low_x), min(low_y), max(high_x), max(high_y)


def _box_of(curve) -> tuple[float, float, float, float]:
    """``(xmin, ymin, xmax, ymax)`` of a box holding one curve (a circle or an ellipse
    whole: |x - cx| <= hypot(ux, vx))."""
    if curve.center is not None:
        (cx, cy), ((ux, vx), (uy, vy)) = curve.center.tolist(), curve.radii.tolist()
        rx, ry = math.hypot(ux, vx), math.hypot(uy, vy)
        return cx - rx, cy - ry, cx + rx, cy + ry
    if len(curve.points) == 2:
        (x0, y0), (x1, y1) = curve.points.tolist()
        return min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)
    (x0, y0), (x1, y1) = curve.points.min(axis=0).tolist(), curve.points.max(axis=0).tolist()
    return x0, y0, x1, y1


def _wire_area(faces, curves) -> float:
    """The area of a cut's faces from their wires (outer wire less the others), each
    wire's the sum of its curves' :func:`_swept_area` (exact along circles and ellipses),
    before any polygon is built."""
    if getattr(faces, "loose", False):
        return _loops_area(faces, curves)
    area, at = 0.0, 0
    for face in faces:
        for number, wire in enumerate(face):
            ring = abs(sum(_swept_area(c) for c in curves[at:at + len(wire)]))
            at += len(wire)
            area += ring if number == 0 else -ring
    return area


def _loops_area(faces, curves) -> float:
    """A lower bound of the area of a Section's loops (not nested; :func:`_wire_area`):
    each loop's exact area (:func:`_swept_area`), added if it is certainly no hole (the
    box of its ends lies in no larger loop's box, whole circles and ellipses included),
    subtracted otherwise. Exact where loops nest at most once (holes in a plate)."""
    loops, at = [], 0
    for face in faces:
        for wire in face:
            chain = curves[at:at + len(wire)]
            at += len(wire)
            loops.append((abs(sum(_swept_area(c) for c in chain)), chain))
    if len(loops) == 1:
        return loops[0][0]
    wide = [_bounds(chain) for _, chain in loops]       # holds the loop
    tight = []                                          # held by the loop: its ends
    for _, chain in loops:
        ends = [xy for c in chain for xy in (c.points[0].tolist(), c.points[-1].tolist())]
        xs, ys = [x for x, _ in ends], [y for _, y in ends]
        tight.append((min(xs), min(ys), max(xs), max(ys)))
    area = 0.0
    for k, (own, _) in enumerate(loops):
        lx, ly, hx, hy = tight[k]
        held = any(other > own and mx <= lx and my <= ly and hx <= nx and hy <= ny
                   for j, ((other, _), (mx, my, nx, ny)) in enumerate(zip(loops, wide))
                   if j != k)
        area += -own if held else own
    return area


def _swept_area(curve) -> float:
    """½∫(x dy - y dx) along the curve, as its points run: in closed form along a circle
    or an ellipse (``center + u cos θ + v sin θ`` gives ½ (c × (P(θ1) - P(θ0)) + (u × v)
    sweep)), along the chords otherwise."""
    if curve.center is not None:
        (cx, cy), ((ux, vx), (uy, vy)) = curve.center.tolist(), curve.radii.tolist()
        start, end = curve.start, curve.start + curve.sweep
        c0, s0, c1, s1 = math.cos(start), math.sin(start), math.cos(end), math.sin(end)
        dx = (c1 * ux + s1 * vx) - (c0 * ux + s0 * vx)
        dy = (c1 * uy + s1 * vy) - (c0 * uy + s0 * vy)
        return 0.5 * (cx * dy - cy * dx + (ux * vy - uy * vx) * curve.sweep)
    if len(curve.points) == 2:
        (x0, y0), (x1, y1) = curve.points.tolist()
        return 0.5 * (x0 * y1 - x1 * y0)
    x, y = curve.points.T
    return 0.5 * float(x[:-1] @ y[1:] - x[1:] @ y[:-1])


def _face_polygons(faces, curves, join, checked=True):
    """The polygons of a cut's faces, each ring its wire's curves end to end, or None if
    a wire does not close within ``join`` or, if ``checked``, the polygons are not valid
    (the caller then assembles the curves by even-odd nesting, which finds the open ends).
    All rings are made by one concatenation (each closed by its first point), then one
    call of shapely per ring and per polygon with holes."""
    pieces, sizes, ring_of, at = [], [], [], 0
    for number, face in enumerate(faces):
        for wire in face:
            chain = curves[at:at + len(wire)]
            at += len(wire)
            ex, ey = chain[-1].points[-1].tolist()
            size = 1
            for curve in chain:
                sx, sy = curve.points[0].tolist()
                if math.hypot(ex - sx, ey - sy) > join:
                    return None
                ex, ey = curve.points[-1].tolist()
                pieces.append(curve.points[:-1])
                size += len(curve.points) - 1
            pieces.append(chain[0].points[:1])           # closed by its first vertex
            sizes.append(size)
            ring_of.append(number)
    closed = np.concatenate(pieces)
    sizes = np.array(sizes)
    # a repeated vertex can only follow a junction or come from a degenerate curve:
    # found by one comparison of each vertex with the next (the closing one included,
    # not across rings), the rings are then rebuilt without it
    repeated = (closed[1:, 0] == closed[:-1, 0]) & (closed[1:, 1] == closed[:-1, 1])
    repeated[np.cumsum(sizes)[:-1] - 1] = False
    if repeated.any():
        starts = np.cumsum(sizes) - sizes
        rings = [_unrepeated(closed[start:start + size - 1])
                 for start, size in zip(starts.tolist(), sizes.tolist())]
        if min(len(ring) for ring in rings) < 3:
            return None
        closed = np.concatenate([np.concatenate([ring, ring[:1]]) for ring in rings])
        sizes = np.array([len(ring) + 1 for ring in rings])
    elif sizes.min() < 4:
        return None
    if len(sizes) == 1:                    # one ring: shapely's calls without indices
        geometry = shapely.polygons(shapely.linearrings(closed))   # (a fifth of the time)
        if checked and not geometry.is_valid:
            return None
        return geometry if geometry.area > 0 else None
    # one call of shapely per ring, per polygon with holes: shapely's ``indices`` (one call
    # for all) sort and check them, twice the time on a plate's six rings
    starts = (np.cumsum(sizes) - sizes).tolist()
    linear = np.empty(len(sizes), dtype=object)
    linear[:] = [shapely.linearrings(closed[start:start + size])
                 for start, size in zip(starts, sizes.tolist())]
    if getattr(faces, "loose", False):
        groups, shells = _nested(linear, closed[starts])
    else:
        groups, shells = [], None
        for ring, number in enumerate(ring_of):
            if ring and number == ring_of[ring - 1]:
                groups[-1][1].append(ring)
            else:
                groups.append((ring, []))
    polygons = [shapely.polygons(linear[shell], holes=linear[holes]) if holes else
                shells[shell] if shells is not None else shapely.polygons(linear[shell])
                for shell, holes in groups]
    geometry = polygons[0] if len(polygons) == 1 else shapely.multipolygons(polygons)
    if checked and not geometry.is_valid:
        return None
    return geometry if geometry.area > 0 else None


def _nested(rings, firsts):
    """The closed rings of a Section's loops (which neither cross nor touch) grouped as
    polygons take them, each shell with its holes (``(shell, [holes])`` by ring number,
    shells in ring order), and each ring's own polygon (what a shell without holes
    is): a ring inside an even number of others is a shell, inside an odd number a hole
    of the smallest ring around it. ``firsts``: a vertex of each ring (what is tested)."""
    count = len(rings)
    shells = shapely.polygons(rings)
    if count == 1:
        return [(0, [])], shells
    areas = shapely.area(shells)
    low_x, low_y, high_x, high_y = shapely.bounds(shells).T
    inner, outer = np.nonzero((areas[None, :] > areas[:, None])           # [i, j]: i in j?
                              & (low_x[None, :] <= low_x[:, None])
                              & (low_y[None, :] <= low_y[:, None])
                              & (high_x[None, :] >= high_x[:, None])
                              & (high_y[None, :] >= high_y[:, None]))
    inside = shapely.contains_xy(shells[outer], firsts[inner, 0], firsts[inner, 1])
    inner, outer = inner[inside].tolist(), outer[inside].tolist()
    depth = [0] * count
    parent = [-1] * count
    for i, j in sorted(zip(inner, outer), key=lambda p: -areas[p[1]]):
        depth[i] += 1
        parent[i] = j                                   # the smallest ring around i last
    holes = {}
    for ring, around in enumerate(parent):
        if around >= 0:
            holes.setdefault(around, []).append(ring)
    return [(ring, holes.get(ring, [])) for ring in range(count) if depth[ring] % 2 == 0], shells


def _unrepeated(ring) -> np.ndarray:
    """A ring's vertices (not closed) without those equal to the one before, nor the
    first if it equals the last."""
    repeated = np.flatnonzero((ring[1:, 0] == ring[:-1, 0]) & (ring[1:, 1] == ring[:-1, 1]))
    keep = np.ones(len(ring), dtype=bool)
    keep[repeated + 1] = False
    keep[0] = keep[0] and not (ring[0] == ring[-1]).all()
    return ring[keep]


def _boundary_curves(curves, tolerance) -> BoundaryCurves | None:
    """The section's exact pieces for :attr:`Region.curves`: lines, and circles and
    ellipses as elliptic arcs (in two halves past half a turn, so that the seam of a
    whole circle is a junction of two pieces, as in the drawing readers); B-splines and
    other curves as their flattening (straight pieces within the tolerance of the
    curve). Each is labelled by its face.

    The arrays of :func:`.boundary_curves.curves_builder` for the same calls, bit for
    bit (lines as cubics with control points at thirds, then the polylines' segments,
    then the arcs; labels numbered as first met), made from plain floats and a handful
    of NumPy calls (the builder's per-piece calls were a tenth of a small section's
    time after its Boolean)."""
    labels, cubics, arcs, blocks = {}, [], [], []
    for curve in curves:
        label = curve.face or "section"
        if curve.kind == "line":
            (x0, y0), (x1, y1) = curve.points.tolist()
            if (x0, y0) != (x1, y1):
                cubics.append((x0, y0, (2 * x0 + x1) / 3, (2 * y0 + y1) / 3,
                               (x0 + 2 * x1) / 3, (y0 + 2 * y1) / 3, x1, y1,
                               labels.setdefault(label, len(labels))))
        elif curve.kind in ("circle", "ellipse"):        # halves past a half turn: a
            halves = 2 if abs(curve.sweep) > math.pi else 1  # whole one has a seam that an
            (cx, cy), ((ux, vx), (uy, vy)) = curve.center.tolist(), curve.radii.tolist()
            for half in range(halves):                       # edge across it must see
                arcs.append((cx, cy, ux, uy, vx, vy,
                             float(curve.start + half * curve.sweep / halves),
                             float(curve.sweep / halves), labels.setdefault(label, len(labels))))
        else:
            points = np.asarray(curve.points, dtype=float).reshape(-1, 2)
            first, last = points[:-1], points[1:]
            keep = np.any(first != last, axis=1)
            first, last = first[keep], last[keep]
            if len(first):
                control = np.stack([first, (2 * first + last) / 3, (first + 2 * last) / 3,
                                    last], axis=1)
                blocks.append((control, labels.setdefault(label, len(labels))))
    count = len(cubics) + sum(len(control) for control, _ in blocks)
    if not count + len(arcs):
        return None
    lines = np.array(cubics, dtype=float).reshape(-1, 9)
    conics = np.array(arcs, dtype=float).reshape(-1, 9)
    elliptic = np.zeros(count + len(arcs), dtype=bool)
    elliptic[count:] = True
    control = np.zeros((count + len(arcs), 4, 2))
    control[:len(lines)] = lines[:, :8].reshape(-1, 4, 2)
    at = len(lines)
    for block, _ in blocks:
        control[at:at + len(block)] = block
        at += len(block)
    conic = np.zeros((count + len(arcs), 8))
    conic[count:] = conics[:, :8]
    source = np.concatenate([lines[:, 8].astype(np.int64)]
                            + [np.full(len(b), k, np.int64) for b, k in blocks]
                            + [conics[:, 8].astype(np.int64)])
    return BoundaryCurves(elliptic, control, conic, source, tuple(labels), float(tolerance))


def _planar_faces(faces) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals (n, 3) and offsets n·x (n,) of the planes of the planar faces among
    ``faces`` (each solid's list; read off each face's surface, with its location: a third
    of the time of ``BRepAdaptor_Surface``)."""
    from OCP.BRep import BRep_Tool
    from OCP.Geom import Geom_Plane, Geom_RectangularTrimmedSurface

    facing, offsets = [], []
    for faces_of_solid in faces:
        for face in faces_of_solid:
            surface = BRep_Tool.Surface_s(face)
            if isinstance(surface, Geom_RectangularTrimmedSurface):
                surface = surface.BasisSurface()
            if isinstance(surface, Geom_Plane):
                plane = surface.Pln()
                direction, location = plane.Axis().Direction(), plane.Location()
                normal = np.array([direction.X(), direction.Y(), direction.Z()])
                facing.append(normal)
                offsets.append(normal @ [location.X(), location.Y(), location.Z()])
    return np.array(facing).reshape(-1, 3), np.array(offsets, dtype=float)


def _to_2d(origin, normal) -> np.ndarray:
    return plane_frames(origin, normal)[0]


def _box(solids, tolerances=False) -> tuple[np.ndarray, np.ndarray]:
    """The corners of the tight bounding box of the solids (from their exact geometry;
    enlarged by their faces', edges' and vertices' tolerances if ``tolerances``)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    for solid in solids:
        BRepBndLib.AddOptimal_s(solid, box, False, tolerances)
    if box.IsVoid():
        return np.zeros(3), np.zeros(3)
    low, high = box.CornerMin(), box.CornerMax()
    return (np.array([low.X(), low.Y(), low.Z()]), np.array([high.X(), high.Y(), high.Z()]))


def _xy(point, frame) -> np.ndarray:
    """The 2D coordinates of an OCCT point in ``frame`` (the first two rows of the
    plane's ``to_2d``)."""
    return frame[:, :3] @ (point.X(), point.Y(), point.Z()) + frame[:, 3]


def _mapped(xyz, rows) -> tuple[float, float]:
    """The 2D coordinates of a 3D point ``(x, y, z)`` under ``rows``, the first two rows
    of the plane's ``to_2d`` as 8 floats (plain arithmetic: a NumPy product of a 2x3
    matrix costs more than the edge's whole reading)."""
    x, y, z = xyz
    a, b, c, d, e, f, g, h = rows
    return a * x + b * y + c * z + d, e * x + f * y + g * z + h


def _along(direction, frame) -> np.ndarray:
    """The 2D components of an OCCT direction in ``frame`` (a direction in the plane)."""
    return frame[:, :3] @ (direction.X(), direction.Y(), direction.Z())


def _curve(edge, tolerance, arcs, frame, reversed_=False, face="") -> SectionCurve:
    """One edge of a cut by a plane, in the 2D coordinates of its ``frame`` (the first
    two rows of ``to_2d``), flattened within ``tolerance`` (circles and ellipses within
    ``arcs``, or as their two ends if None); it runs the other way if ``reversed_`` (the
    edge's orientation in its wire)."""
    return _flattened(edge, tolerance, np.asarray(frame, dtype=float), arcs, face, reversed_)


def _reversed(curve) -> SectionCurve:
    """``curve`` run the other way: its points, ``start`` / ``sweep`` and Bézier pieces."""
    return _replaced(curve, points=curve.points[::-1], start=curve.start + curve.sweep,
                   sweep=-curve.sweep, bezier=None if curve.bezier is None else
                   tuple(control[::-1] for control in curve.bezier[::-1]))


def _conic_ends(center, radii, first, last) -> np.ndarray:
    """The points of ``center + u cos θ + v sin θ`` at θ = ``first`` and ``last``."""
    (cx, cy), ((ux, vx), (uy, vy)) = center, radii
    c0, s0, c1, s1 = math.cos(first), math.sin(first), math.cos(last), math.sin(last)
    return np.array([[cx + (c0 * ux + s0 * vx), cy + (c0 * uy + s0 * vy)],
                     [cx + (c1 * ux + s1 * vx), cy + (c1 * uy + s1 * vy)]])


def _junctions_refined(faces, curves, arcs) -> list:
    """The curves of a cut's wires (in wire order) with each junction of a line and a
    circle or ellipse moved onto both curves.

    OCCT ends a line where its vertex is, within the edge tolerance of the conic it meets
    (up to 1.9e-9 of the radius on held-out parts): the junction, the ring's vertex, was
    off the conic by that much. Here the conic ``center + u cos θ + v sin θ`` and the
    line through the line's two ends (points of OCCT's exact line) meet where
    ``n·(center - p) + (n·u) cos θ + (n·v) sin θ = 0``, in closed form: the root nearest
    the conic's own end is taken (where they miss each other, by less than the gap, the
    point of the conic nearest the line). The line's end and the conic's parameter range
    move there: both curves stay exact, and the boundary moves by at most the gap closed.
    A root more than a quarter of the conic's sweep or of the line's length away is left
    (not this junction). Circles and ellipses are flattened again within ``arcs`` if they
    were flattened (else they stay as their two ends). Plain float arithmetic throughout:
    a cut has a handful of junctions, and NumPy's per-call cost on 2-vectors was most of
    this step's time."""
    lines = {}                      # index -> new (start, end) of a line
    conics = {}                     # index -> new (start θ, end θ) of a conic
    at = 0
    for face in faces:
        for wire in face:
            base, count = at, len(wire)
            at += count
            if count < 2:
                continue
            for k in range(count):
                i, j = base + k, base + (k + 1) % count          # i ends where j starts
                a, b = curves[i], curves[j]
                if a.kind == "line" and b.center is not None:
                    line, conic, index, conic_ends = a, b, i, False
                elif b.kind == "line" and a.center is not None:
                    line, conic, index, conic_ends = b, a, j, True
                else:
                    continue
                (x0, y0), (x1, y1) = conic.points[0].tolist(), conic.points[-1].tolist()
                if x0 == x1 and y0 == y1:
                    continue                              # a whole turn: no junction
                theta0 = conic.start + (conic.sweep if conic_ends else 0.0)
                (px, py), (qx, qy) = line.points[0].tolist(), line.points[-1].tolist()
                theta = _line_meets_conic((px, py, qx, qy), conic, theta0)
                if theta is None:
                    continue
                (cx, cy), ((ux, vx), (uy, vy)) = conic.center.tolist(), conic.radii.tolist()
                cos, sin = math.cos(theta), math.sin(theta)
                point = (cx + (ux * cos + vx * sin), cy + (uy * cos + vy * sin))
                jx, jy = (b.points[0] if conic_ends else a.points[-1]).tolist()
                if math.hypot(point[0] - jx, point[1] - jy) > 0.25 * math.hypot(qx - px,
                                                                                 qy - py):
                    continue
                ends = list(lines.get(index, ((px, py), (qx, qy))))
                ends[0 if conic_ends else 1] = point      # the line starts where a ends
                lines[index] = tuple(ends)
                conic_index = i if conic_ends else j
                first, last = conics.get(conic_index,
                                         (conic.start, conic.start + conic.sweep))
                conics[conic_index] = (first, theta) if conic_ends else (theta, last)
    if not lines:
        return curves
    refined = list(curves)
    for index, (start, end) in lines.items():
        refined[index] = _replaced(curves[index], points=np.array([start, end]))
    for index, (first, last) in conics.items():
        curve = curves[index]
        if (last - first) * curve.sweep <= 0:             # a flipped range: keep OCCT's
            continue
        points = (elliptic_points(curve.center, curve.radii, first, last - first, arcs)
                  if arcs else _conic_ends(curve.center.tolist(), curve.radii.tolist(),
                                           first, last))
        refined[index] = _replaced(curve, points=points, start=first, sweep=last - first)
    return refined


def _line_meets_conic(line, conic, theta0):
    """The parameter θ of the conic (``center + u cos θ + v sin θ``) where it meets the
    line through ``line`` = (px, py, qx, qy), two points, nearest ``theta0`` and within a
    quarter of the conic's sweep of it; the conic's point nearest the line (within it)
    where they miss each other; None if there is no such θ."""
    px, py, qx, qy = line
    length = math.hypot(qx - px, qy - py)
    if not length > 0:
        return None
    nx, ny = (py - qy) / length, (qx - px) / length
    (cx, cy), ((ux, vx), (uy, vy)) = conic.center.tolist(), conic.radii.tolist()
    a = nx * (cx - px) + ny * (cy - py)
    c = nx * ux + ny * uy                                 # n·u
    d = nx * vx + ny * vy                                 # n·v
    radius = math.hypot(c, d)
    if not radius > 0:
        return None
    phi = math.atan2(d, c)                                # f(θ) = a + radius cos(θ - φ)
    spread = math.acos(min(1.0, max(-1.0, -a / radius)))
    best = None
    for root in (phi + spread, phi - spread):
        root += 2 * math.pi * round((theta0 - root) / (2 * math.pi))
        if best is None or abs(root - theta0) < abs(best - theta0):
            best = root
    return best if abs(best - theta0) <= 0.25 * abs(conic.sweep) else None


def _finer(curve, tolerance) -> SectionCurve:
    """A circle or ellipse flattened (again) within ``tolerance``, closed if it was;
    other curves as they are."""
    if curve.center is None:
        return curve
    return _arcs_flattened([curve], tolerance)[id(curve)]


def _arcs_flattened(conics, tolerance) -> dict:
    """Circles and ellipses flattened (again) within ``tolerance``, closed if they were,
    by ``id`` of the curve: the points of :func:`.curves.elliptic_points`, bit for bit
    (its chord counts and parameters, one cosine and sine call for all, then each arc's
    own product with its radii), at a fraction of its per-call cost: the chord counts
    in plain float arithmetic (the same IEEE operations as its NumPy scalars)."""
    if not conics:
        return {}
    counts = []
    for curve in conics:
        sweep = curve.sweep
        (a, b), (c, d) = curve.radii.tolist()               # _spectral_norm, on floats
        squares, determinant = a * a + b * b + c * c + d * d, a * d - b * c
        norm = math.sqrt(0.5 * (squares + math.sqrt(max(squares * squares
                                                         - 4 * determinant * determinant,
                                                         0.0))))
        bound = norm * sweep**2
        ratio = bound / (8 * tolerance)
        root = math.sqrt(ratio) if ratio >= 0 else math.nan
        if not root <= MAX_CHORDS:                          # (ceil(r) <= N iff r <= N)
            steps(bound, tolerance)                         # raises, naming the limit
        counts.append(max(1, math.ceil(root)))
    # each arc's θ = start + sweep t, t = linspace(0, 1, m + 1) = arange(m + 1) * (1 / m)
    # with its last value 1, written in place into one array for one cosine and sine call
    offsets, sizes = [], []
    theta = np.empty(sum(counts) + len(counts))
    at = 0
    for curve, count in zip(conics, counts):
        t = theta[at:at + count + 1]
        np.multiply(np.arange(count + 1), 1.0 / count, out=t)
        t[-1] = 1.0
        t *= curve.sweep
        t += curve.start
        offsets.append(at)
        sizes.append(count + 1)
        at += count + 1
    trig = np.empty((len(theta), 2))
    np.cos(theta, out=trig[:, 0])
    np.sin(theta, out=trig[:, 1])
    flattened = {}
    for curve, at, size in zip(conics, offsets, sizes):
        # the product with a C-ordered copy of the radii' transpose (BLAS's other path:
        # the same bits, a third of the time), the centre added column by column (a
        # broadcast of (2,) over (k, 2) runs NumPy's loop k times, for two elements)
        points = trig[at:at + size] @ np.ascontiguousarray(curve.radii.T)
        (cx, cy) = curve.center.tolist()
        points[:, 0] += cx
        points[:, 1] += cy
        (x0, y0), (x1, y1) = curve.points[0].tolist(), curve.points[-1].tolist()
        if x0 == x1 and y0 == y1:
            points[-1] = points[0]
        flattened[id(curve)] = _made(curve.kind, points, curve.center, curve.radii,
                                            curve.edge_tolerance, curve.start, curve.sweep,
                                            curve.bezier, curve.face)
    return flattened


def _splines_within(splines, budget, tolerance, floor) -> dict:
    """The B-splines flattened again so that their chords miss at most ``budget`` of
    area in all, within ``tolerance`` at most and ``floor`` at least, by ``id`` of the
    curve (those already within it are left out).

    A chord of length c whose curve piece B stays within s of it (B - L = D, |D| <= s)
    bounds with it the area ∫ D × L' + ½ ∫ D × D', at most s c + ½ s ∫|D'|; on a
    Bézier piece flattened by :func:`.curves.steps` (s = M h² / 8, M >= |B''|) |D'| <=
    M h, so ½ s ∫|D'| <= 4 s². The chords then miss at most t (C + 4 n t) in all, for
    n chords of total length C at tolerance t: t shrinks until that is within budget."""
    def flattened(curve, t):
        return _replaced(curve, points=_bezier_chain(curve.bezier, t))

    def missed(curves, t):
        return t * sum(float(np.hypot(*np.diff(c.points, axis=0).T).sum())
                       + 4 * t * (len(c.points) - 1) for c in curves)

    if not splines or missed(splines, tolerance) <= budget:
        return {}
    t = min(tolerance, max(floor, 0.99 * budget * tolerance / missed(splines, tolerance)))
    while True:
        finer = [flattened(c, t) for c in splines]
        if t == floor or missed(finer, t) <= budget:
            return {id(c): f for c, f in zip(splines, finer)}
        t = max(floor, t / 1.5)


def _flattened(edge, tolerance, frame, arcs=None, face="", reversed_=False,
               rows=None) -> SectionCurve:
    """One edge of a cut by a plane, in its ``frame``'s 2D coordinates (the first two rows
    of ``to_2d``; ``rows``: the same as 8 floats), flattened within ``tolerance`` (circles
    and ellipses within ``arcs``, or as their two ends if None), labelled ``face``; it
    runs the other way if ``reversed_`` (the edge's orientation in its wire).

    The edge is read once (its adaptor, type, parameters and tolerance); lines and the
    ends of circles and ellipses are mapped by plain float arithmetic."""
    occ = _occ()
    BRep_Tool = occ.BRep_Tool
    if rows is None:
        rows = tuple(np.asarray(frame, dtype=float)[:2].ravel().tolist())
    curve = occ.BRepAdaptor_Curve(edge)
    kind, first, last = curve.GetType(), curve.FirstParameter(), curve.LastParameter()
    code = kind.value                  # (an int: a pybind enum's == costs 0.5 µs)
    bound = BRep_Tool.Tolerance_s(edge)
    if code == occ.LINE:
        ends = [_mapped(curve.Value(first).Coord(), rows),
                _mapped(curve.Value(last).Coord(), rows)]
        return _made("line", np.array(ends[::-1] if reversed_ else ends),
                     edge_tolerance=bound, face=face)
    if code == occ.CIRCLE or code == occ.ELLIPSE:
        if code == occ.CIRCLE:
            conic = curve.Circle()
            major = minor = conic.Radius()
        else:
            conic = curve.Ellipse()
            major, minor = conic.MajorRadius(), conic.MinorRadius()
        axes = conic.Position()
        a, b, c, _, e, f, g, _ = rows
        center = _mapped(axes.Location().Coord(), rows)
        (xx, xy, xz), (yx, yy, yz) = axes.XDirection().Coord(), axes.YDirection().Coord()
        radii = ((major * (a * xx + b * xy + c * xz), minor * (a * yx + b * yy + c * yz)),
                 (major * (e * xx + f * xy + g * xz), minor * (e * yx + f * yy + g * yz)))
        sweep = last - first
        closed = BRep_Tool.IsClosed_s(edge)
        if arcs:
            points = elliptic_points(center, radii, first, sweep, arcs)
            if closed:
                points[-1] = points[0]       # a whole turn ends where it starts
            if reversed_:
                points = points[::-1]
        else:
            points = (_conic_ends(center, radii, last, first) if reversed_ else
                      _conic_ends(center, radii, first, last))
            if closed:
                points[-1 if not reversed_ else 0] = points[0 if not reversed_ else -1]
        if reversed_:
            first, sweep = first + sweep, -sweep
        return _made("circle" if code == occ.CIRCLE else "ellipse", points,
                     np.array(center), np.array(radii), bound, first, sweep, face=face)
    Kind = occ.Kind
    frame = np.asarray(frame, dtype=float)[:2]
    if kind == Kind.GeomAbs_BSplineCurve or kind == Kind.GeomAbs_BezierCurve:
        pieces = _bezier_pieces(curve, kind, first, last, frame)
        if pieces is not None:
            flat = _made("bspline", _bezier_chain(pieces, tolerance),
                         edge_tolerance=bound, bezier=tuple(pieces), face=face)
            return _reversed(flat) if reversed_ else flat
    from OCP.GCPnts import GCPnts_QuasiUniformDeflection

    sampler = GCPnts_QuasiUniformDeflection(curve, tolerance, first, last)
    if not sampler.IsDone():
        raise SourceError("OpenCASCADE could not flatten a curve of the section; pass a "
                          "larger tolerance or move the plane")
    points = np.array([_xy(sampler.Value(i), frame) for i in range(1, sampler.NbPoints() + 1)])
    flat = _made("adaptive", points, edge_tolerance=bound, face=face)
    return _reversed(flat) if reversed_ else flat


def _bezier_chain(pieces, tolerance) -> np.ndarray:
    """The Bézier pieces (each (d + 1, 2) control points, end to end) flattened within
    ``tolerance``, as :func:`.curves.bezier_points` flattens each (the same bound,
    d (d - 1) max|ΔΔP| >= max|B''|, and uniform steps), all pieces of one degree at once."""
    if len({len(control) for control in pieces}) > 1:
        flat = [bezier_points(control, tolerance) for control in pieces]
        return np.concatenate([flat[0]] + [piece[1:] for piece in flat[1:]])
    control = np.asarray(pieces, dtype=float)                   # (k, d + 1, 2)
    degree = control.shape[1] - 1
    if degree < 2:
        return np.concatenate([control[:, 0], control[-1:, -1]])
    second = control[:, 2:] - 2 * control[:, 1:-1] + control[:, :-2]
    bound = degree * (degree - 1) * np.linalg.norm(second, axis=2).max(axis=1)
    with np.errstate(all="ignore"):                             # steps' count, at once
        counts = np.ceil(np.sqrt(bound / (8 * tolerance)))
    if not np.all(counts <= MAX_CHORDS):
        steps(bound.max(), tolerance)                           # raises, naming the limit
    counts = np.maximum(counts, 1).astype(np.int64)
    piece = np.repeat(np.arange(len(control)), counts)
    t = ((np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts) + 1)
         / counts[piece])[:, None]
    power = np.arange(degree + 1)
    choose = np.array([math.comb(degree, i) for i in power], dtype=float)
    basis = choose * t**power * (1 - t) ** (degree - power)      # (m, d + 1)
    return np.concatenate([control[:1, 0], np.einsum("md,mdx->mx", basis, control[piece])])


def _bezier_pieces(curve, kind, first, last, frame):
    """Control points (d + 1, 2) of the non-rational Bézier pieces of the curve between
    ``first`` and ``last``, in ``frame``'s 2D coordinates (a Bézier curve's image under
    an affine map is the Bézier curve of its mapped poles), or None if it is rational."""
    from OCP.GeomAbs import GeomAbs_CurveType as Kind
    from OCP.GeomConvert import GeomConvert_BSplineCurveToBezierCurve

    def poles(piece):
        # one product per piece: one for all pieces, the same bits and a quarter of the
        # time alone, made inside sections 0.1 ms slower (OpenBLAS, unless limited to one
        # thread) and the stages after it slower too (docs/step.md, session 21)
        return np.array([piece.Pole(i).Coord() for i in range(1, piece.NbPoles() + 1)]
                        ) @ frame[:, :3].T + frame[:, 3]

    if kind == Kind.GeomAbs_BezierCurve:
        bezier = curve.Bezier()
        return None if bezier.IsRational() else [poles(bezier)]
    spline = curve.BSpline()
    if spline.IsRational():
        return None
    split = GeomConvert_BSplineCurveToBezierCurve(spline, first, last, 1e-12)
    return [poles(split.Arc(i)) for i in range(1, split.NbArcs() + 1)]


def section_curves(solid, plane_origin, plane_normal, *, on_face=None,
                   tolerance=None) -> list[SectionCurve]:
    """The edges of a B-rep solid's section, exact curves with their flattening.

    Parameters
    ----------
    solid : str, os.PathLike or OCP shape
        A STEP, IGES or BREP file, or an OCP ``TopoDS_Shape`` (see :func:`load`).
    plane_origin, plane_normal : (3,) array_like
        The plane, as :func:`pds_plugin.section`; the curves are in the same 2D frame
        as that section's region.
    on_face : {None, "above", "below"}
        As :func:`pds_plugin.section`.
    tolerance : float, optional
        The chord tolerance of the flattening (see :class:`StepSolid`).

    Returns
    -------
    list of SectionCurve
        One per edge of the cut, solid after solid.

    Raises
    ------
    PdsError, OSError
        As :func:`pds_plugin.section`.

    Examples
    --------
    >>> section_curves("absent.brep", (0, 0, 0), (0, 0, 1))
    Traceback (most recent call last):
    ...
    FileNotFoundError: no such BREP file: 'absent.brep'
    """
    origin, normal = checked_plane(plane_origin, plane_normal)
    return StepSolid(solid, tolerance).curves(origin, normal, checked_on_face(on_face))
