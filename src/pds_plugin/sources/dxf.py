"""DXF source: the outline drawing, or the hatched areas, of a DXF file as a Region.

Read with ezdxf (MIT), the reference Python library for DXF: every DXF version, ASCII
and binary, every entity this reader needs, OCS and block transforms. trimesh's own DXF
reader (``trimesh.load_path``) was the alternative. Both agree on the four public test
drawings of the shared data (same components and holes, areas within 2e-4), but trimesh's
puts arcs and ellipses of a mirrored coordinate system (extrusion -Z) on the wrong side,
draws the circle of a block scaled 3 x 1 as a circle of radius 5 elsewhere, fails on
nested mirrored blocks and on hatches, and does not read binary DXF
(``bench/dxf_readers.py``, docs/dxf_readers.md). ezdxf gives the exact entity geometry,
which this module cuts into chords itself, to an absolute tolerance, like
:func:`~.svg.load_svg`.

Curves (LINE, ARC, CIRCLE, ELLIPSE, LWPOLYLINE and POLYLINE with bulges, SPLINE) are
assembled into loops as in SVG outline drawings (:func:`.curves.outline`); HATCH
boundaries are filled by even-odd parity; INSERT places blocks (nested, scaled, rotated,
mirrored, MINSERT arrays) through ezdxf's own transforms.
"""

from __future__ import annotations

import math
import warnings
from collections import Counter

import numpy as np
import shapely

from .._checks import check_positive
from ..boundary_curves import curves_builder
from ..errors import ArgumentError, RegionError, SourceError
from ..region import Region
from ._sniff import misnamed
from ._dxf_limits import MAX_BYTES, MAX_ENTITIES, MAX_SEGMENTS, check_dxf_limits
from ._dxf_sheet import paper_sizes, sheet_border, sheet_format_name
from .curves import bezier_points, checked_file, default_tolerance, elliptic_points, outline
from .polygons import fill_geometry

__all__ = ["load_dxf"]

CURVES = ("LINE", "ARC", "CIRCLE", "ELLIPSE", "LWPOLYLINE", "POLYLINE", "SPLINE")
"""Entities read as outline curves."""

# Millimetres per $INSUNITS code (AutoCAD's list); 0 is "unitless".
_MILLIMETRES = {1: 25.4, 2: 304.8, 3: 1609344.0, 4: 1.0, 5: 10.0, 6: 1000.0, 7: 1e6,
                8: 2.54e-5, 9: 0.0254, 10: 914.4, 11: 1e-7, 12: 1e-6, 13: 1e-3, 14: 100.0,
                15: 1e4, 16: 1e5, 17: 1e12, 18: 1.495978707e14, 19: 9.4607304725808e18,
                20: 3.0856775814913673e19, 21: 1200 / 3.937}
_UNITS = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4, "ft": 304.8}
_MAX_NESTING = 64


def load_dxf(path, *, layers=None, layout=None, units=None, tolerance=None,
             mode: str = "auto", regions=None, max_bytes: int = MAX_BYTES,
             max_entities: int = MAX_ENTITIES, max_segments: int = MAX_SEGMENTS):
    """Read a DXF drawing's model space (or a paper-space sheet) as a :class:`Region` in
    the plane z = 0.

    Two kinds of content are understood, as in :func:`load_svg`:

    - **hatched** areas (HATCH): each hatch's boundary paths are filled by even-odd
      parity (islands in holes come out right), and the hatches are united;
    - **outline** drawings: the curves (LINE, ARC, CIRCLE, ELLIPSE, LWPOLYLINE and
      POLYLINE with bulges, SPLINE) are joined into closed loops where their ends are
      closer than ``tolerance``, and the loops are nested by containment (even-odd), so
      a loop inside a part is a hole and a loop inside a hole is an island. Ends that
      meet nothing are reported in a warning with their coordinates.

    INSERT places its block's entities (nested blocks, scale, rotation, mirroring and
    MINSERT arrays); an entity of a block on layer "0" takes the INSERT's layer. Text,
    dimensions and other entities with no outline (points, images, 3D faces, ...) are
    ignored and counted in one warning. The drawing is seen from above: entities in a
    tilted coordinate system are projected onto the XY plane.

    The model space is read. When it has no outline curve or hatch on the layers read,
    the first paper-space layout (in tab order) that has one is read instead, with a
    warning naming it: SolidWorks, among others, exports drawing sheets there. In paper
    space the sheet itself is left out, with a warning saying what: VIEWPORT entities,
    entities on layers or in blocks named like a sheet format (FORMAT, TITLE, BORDER),
    and the sheet border (a rectangle enclosing everything else, of the paper's size or
    with a title block drawn against it) with what is drawn against it and the hatches
    in its title block (the rules: docs/dxf_readers.md).

    Parameters
    ----------
    path : str or os.PathLike
        An ASCII or binary DXF file.
    layers : str or iterable of str, optional
        The layers to read (names are case-insensitive, as in CAD). Default: every layer
        with an outline curve or a hatch; layers that hold only text, dimensions and
        other annotation are left out without a warning.
    layout : str, optional
        The layout to read, by its name (case-insensitive): "Model" for the model space,
        or a paper-space sheet ("Layout1", "Sheet1", ...). Default: the model space, or
        the first paper-space layout with an outline when the model space has none.
    units : {None, "mm", "cm", "m", "in", "ft"}
        None keeps the drawing's numbers; a unit converts from the drawing's
        ``$INSUNITS`` (an error when the drawing is unitless).
    tolerance : float, optional
        Geometric accuracy in output units: arcs, circles, ellipses and splines are
        flattened so that no point of the curve is farther than this from its polyline
        (ezdxf's adaptive check for rational or unclamped splines), and curve ends closer
        than this are joined. Default: 1e-4 times the diagonal of the drawing's extent.
    mode : {"auto", "fill", "outline"}
        ``auto`` reads the hatched areas if the hatches enclose any area, and the outline
        of the curves otherwise.
    regions : {None, "layer"}
        None: one Region of everything read. ``"layer"``: a dict of Regions, one per
        layer whose curves (or hatches) close, by layer name, read with the drawing's
        one tolerance so that boundaries drawn on two layers match: the parts of a
        composite section for :func:`pds_plugin.mesh_regions`. Layers whose curves close
        no loop are left out with a warning.
    max_bytes, max_entities, max_segments : int
        Limits checked before the drawing is expanded (see :mod:`._dxf_limits`): the
        file's size (50 MB), the entities the layout read expands to with every INSERT
        copy (100,000), and its polyline vertices, spline control points and hatch edges
        (1,000,000). Raise them for bigger drawings.

    Returns
    -------
    Region, or dict of str to Region (``regions="layer"``)
        With the identity frame (the drawing lies in the plane z = 0).

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    SourceError
        If the file is empty, not DXF, truncated or damaged, exceeds a limit, a block
        inserts itself or is missing, or an entity has NaN or infinite coordinates.
    RegionError
        If nothing is left to mesh: no curve on the layers (in the model space nor in a
        paper-space layout), or no loop that closes (the message gives the open ends).
    ArgumentError
        If a layer or the layout does not exist (the message lists the layouts),
        ``units`` is given for a unitless drawing, or an argument is bad.

    Warns
    -----
    UserWarning
        When a paper-space layout is read because the model space is empty, when a sheet
        format is left out, and about ignored entities and open curve ends.

    Examples
    --------
    >>> import pathlib, tempfile, ezdxf, pds_plugin as pds
    >>> doc = ezdxf.new(units=4)                        # millimetres
    >>> _ = doc.modelspace().add_lwpolyline([(0, 0), (20, 0), (20, 10), (0, 10)], close=True)
    >>> _ = doc.modelspace().add_circle((10, 5), radius=2)
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "plate.dxf"
    >>> doc.saveas(path)
    >>> region = pds.load_dxf(path, units="cm", tolerance=1e-4)
    >>> region.betti, round(region.area, 3)
    ((1, 1), 1.874)
    >>> _ = doc.modelspace().add_circle((10, 5), radius=2, dxfattribs={"layer": "INSERT"})
    >>> doc.saveas(path)
    >>> parts = pds.load_dxf(path, regions="layer", mode="outline", tolerance=1e-4)
    >>> {layer: round(part.area, 1) for layer, part in parts.items()}   # plate, insert
    {'0': 187.4, 'INSERT': 12.6}
    """
    if mode not in ("auto", "fill", "outline"):
        raise ArgumentError(f"mode must be 'auto', 'fill' or 'outline', got {mode!r}")
    if units is not None and units not in _UNITS:
        raise ArgumentError(f"units must be None (the drawing's own) or one of "
                            f"{tuple(_UNITS)}, got {units!r}")
    if regions not in (None, "layer"):
        raise ArgumentError(f"regions must be None (one region) or 'layer' (one per layer), "
                            f"got {regions!r}")
    if layout is not None and not isinstance(layout, str):
        raise ArgumentError(f"layout must be the name of a layout ('Model' for the model "
                            f"space), got {layout!r}")
    tolerance = None if tolerance is None else check_positive(tolerance, "tolerance")
    document, name = _read(path, max_bytes)
    scale = _scale(document, units, name)
    read = dict(name=name, layers=_layer_names(layers), scale=scale, tolerance=tolerance,
                limits=(max_entities, max_segments))
    if layout is not None:
        drawing = _drawing(document, _layout(document, layout, name), **read)
        drawing.check_layers(name)
    else:
        drawing = _first_drawn(document, **read)
    drawing.warn(name)
    if not drawing.hatches and not drawing.curves:
        raise RegionError(f"{name} has no outline curve ({', '.join(CURVES)}) or HATCH in its "
                          f"{drawing.space} on the layers read: nothing to mesh")
    if regions is None:
        return _region(drawing.hatches, drawing.hatch_layers, drawing.curves,
                       drawing.curve_layers, drawing.tolerance, mode, name)
    found = {}
    for layer in sorted(set(drawing.hatch_layers) | set(drawing.curve_layers)):
        hatches = [(h, at) for h, at in zip(drawing.hatches, drawing.hatch_layers) if at == layer]
        curves = [(c, at) for c, at in zip(drawing.curves, drawing.curve_layers) if at == layer]
        try:
            found[layer] = _region(*(list(v) for v in zip(*hatches)) if hatches else ([], []),
                                   *(list(v) for v in zip(*curves)) if curves else ([], []),
                                   drawing.tolerance, mode, f"{name}, layer {layer!r}")
        except RegionError as error:
            warnings.warn(f"layer {layer!r} of {name} is left out: {error}", UserWarning,
                          stacklevel=2)
    if not found:
        raise RegionError(f"no layer of {name} closes a loop: nothing to mesh")
    return found


def _region(hatch_loops, hatch_layers, curve_chains, curve_layers, tolerance, mode, name):
    """The Region of a drawing's hatches and curves (and the layer of each), read by
    ``mode`` as :func:`load_dxf` says."""
    geometry = shapely.Polygon()
    if mode != "outline":
        geometry = shapely.union_all([fill_geometry(
            [_points(chain, tolerance) for chain in chains], "evenodd")
            for chains in hatch_loops])
        drawn = [(layer, chain) for layer, chains in zip(hatch_layers, hatch_loops)
                 for chain in chains]
        if geometry.is_empty and mode == "fill":
            raise RegionError(f"the hatches of {name} enclose no area: nothing to mesh (for "
                              f"an outline drawing use mode='outline')")
    if geometry.is_empty:
        if not curve_chains:
            raise RegionError(f"{name} has no outline curve ({', '.join(CURVES)}) on the "
                              f"layers read and its hatches enclose no area: nothing to mesh")
        geometry = outline([_points(chain, tolerance) for chain in curve_chains], tolerance,
                           name, kind="curve")
        drawn = list(zip(curve_layers, curve_chains))
    return Region.from_shapely(geometry, curves=_curves(drawn, tolerance))


# --- layouts: the model space and the paper-space sheets ---------------------------

def _layout_names(document) -> list:
    """The layouts in tab order, "Model" first."""
    return document.layouts.names_in_taborder()


def _listed(names) -> str:
    return ", ".join(repr(title) for title in names)


def _layout(document, layout, name):
    """The layout called ``layout`` (case-insensitive, as in CAD)."""
    if layout not in document.layouts:
        raise ArgumentError(f"{name} has no layout {layout!r}; its layouts are "
                            f"{_listed(_layout_names(document))} ('Model' is the model "
                            f"space)")
    return document.layouts.get(layout)


def _first_drawn(document, **read):
    """The model space's drawing, or else the first paper-space layout's with an outline
    (in tab order), said in a warning."""
    name = read["name"]
    drawing = _drawing(document, document.modelspace(), **read)
    papers = [document.layouts.get(title) for title in _layout_names(document)[1:]]
    if not drawing.empty or not papers:
        drawing.check_layers(name)
        return drawing
    for paper in papers:
        found = _drawing(document, paper, **read)
        if not found.unknown and not found.empty:
            warnings.warn(f"{name}: its model space has no outline curve or hatch on the "
                          f"layers read, so its paper-space layout {paper.name!r} is read "
                          f"instead (layout= chooses one of "
                          f"{_listed(_layout_names(document))})", UserWarning, stacklevel=3)
            return found
    drawing.check_layers(name)
    drawing.warn(name, stacklevel=4)           # what the model space holds instead
    raise RegionError(f"{name} has no outline curve ({', '.join(CURVES)}) or HATCH on the "
                      f"layers read in its model space nor, once viewports, sheet borders "
                      f"and title blocks are left out, in its paper-space layouts "
                      f"{_listed(paper.name for paper in papers)}: nothing to mesh")


class _Drawing:
    """What one layout gives: hatch boundaries and curve chains (in output units) with the
    layer of each, the tolerance, and what was left out, to be said in warnings."""

    def __init__(self, space, hatches, curves, tolerance, ignored, sheet, unknown, drawn):
        self.space = space
        self.hatch_layers, self.hatches = (list(v) for v in zip(*hatches)) if hatches else ([], [])
        self.curve_layers, self.curves = (list(v) for v in zip(*curves)) if curves else ([], [])
        self.tolerance, self.ignored, self.sheet = tolerance, ignored, sheet
        self.unknown, self.drawn = unknown, drawn     # layers asked for; layers drawn on

    def check_layers(self, name):
        """Refuse a layer asked for that is not in the drawing."""
        if self.unknown:
            raise ArgumentError(f"{name} has no layer {self.unknown[0]!r}; its layers with "
                                f"outline curves or hatches are: "
                                f"{', '.join(self.drawn) or 'none'}")

    @property
    def empty(self) -> bool:
        return not self.hatches and not self.curves

    def warn(self, name, stacklevel=3):
        """Say what was ignored and what was left out as the sheet format."""
        if self.ignored:
            counts = ", ".join(f"{count} {kind}" for kind, count in sorted(self.ignored.items()))
            warnings.warn(f"{name}: ignored {counts} (text, dimensions and entities without an "
                          f"outline are not part of the region)", UserWarning,
                          stacklevel=stacklevel)
        if self.sheet:
            warnings.warn(f"{name}: left out the sheet format of {self.space}: "
                          f"{'; '.join(self.sheet)} (the rules: docs/dxf_readers.md; "
                          f"layers= reads a layer named like a sheet format)", UserWarning,
                          stacklevel=stacklevel)


def _drawing(document, space, *, name, layers, scale, tolerance, limits) -> _Drawing:
    """The outline and hatch entities of a layout, its sheet format left out."""
    check_dxf_limits(document, name, *limits, layout=space)
    paper = not space.is_modelspace
    where = f"paper-space layout {space.name!r}" if paper else "model space"
    placed, sheet = list(_placed(space)), []
    if paper:
        asked = None if layers is None else {layer.lower() for layer in layers}
        named = Counter()
        kept = []
        for entity, layer, blocks in placed:
            if entity.dxftype() == "VIEWPORT":
                continue                       # a window onto model space, not geometry
            reason = sheet_format_name(layer, blocks, asked)
            if reason is None:
                kept.append((entity, layer, blocks))
            else:
                named[reason] += 1
        placed = kept
        sheet += [f"{count} entities of {reason}" for reason, count in sorted(named.items())]
    entities, ignored, unknown = _selected(placed, layers, document)
    drawn = sorted({layer.lower() for entity, layer, _ in placed if _is_drawn(entity)})
    layer_of = {id(entity): layer for entity, layer, _ in placed}
    hatch_layers = [layer_of[id(entity)] for entity in entities if entity.dxftype() == "HATCH"]
    hatches = [[_chain(boundary, entity, scale) for boundary in _hatch_paths(entity)]
               for entity in entities if entity.dxftype() == "HATCH"]
    curve_layers = [layer_of[id(entity)] for entity in entities
                    if entity.dxftype() in CURVES for _ in _curve_pieces(entity)]
    curves = [_chain(pieces, entity, scale) for entity in entities
              if entity.dxftype() in CURVES for pieces in _curve_pieces(entity)]
    chosen = tolerance or _default_tolerance(hatches, curves)
    if paper and curves:
        code = document.header.get("$INSUNITS", 0)
        papers = [(scale * width, scale * height)
                  for width, height in paper_sizes(space, _MILLIMETRES.get(code))]
        border, size, cells = sheet_border([_points(chain, chosen) for chain in curves],
                                           chosen, papers)
        if border.any():
            sheet.append(f"the sheet border ({size[0]:.6g} x {size[1]:.6g}) and what is "
                         f"drawn against it, {int(border.sum())} curves")
            curve_layers = [layer for layer, dropped in zip(curve_layers, border) if not dropped]
            curves = [chain for chain, dropped in zip(curves, border) if not dropped]
            logos = [_within(chains, cells, chosen) for chains in hatches]
            if any(logos):
                sheet.append(f"{sum(logos)} HATCH in its title block")
                hatch_layers = [layer for layer, logo in zip(hatch_layers, logos) if not logo]
                hatches = [chains for chains, logo in zip(hatches, logos) if not logo]
            chosen = tolerance or _default_tolerance(hatches, curves)
    return _Drawing(where, list(zip(hatch_layers, hatches)), list(zip(curve_layers, curves)),
                    chosen, ignored, sheet, unknown, drawn)


def _within(chains, area, tolerance) -> bool:
    """Whether every boundary of a hatch lies in ``area`` (within ``tolerance``)."""
    if area.is_empty:
        return False
    near = area.buffer(tolerance)
    return all(near.covers(shapely.MultiPoint(_points(chain, tolerance))) for chain in chains)


def _default_tolerance(hatches, curves):
    """The default tolerance of these pieces' extent (None when there are none)."""
    every = [piece for chains in hatches for chain in chains for piece in chain]
    every += [piece for chain in curves for piece in chain]
    if not every:
        return None
    return default_tolerance([point for piece in every for point in piece.extent()])


# --- the file -----------------------------------------------------------------------

def _read(path, max_bytes):
    import ezdxf

    name = checked_file(path, "DXF", max_bytes)
    try:
        document = ezdxf.readfile(name)
    except Exception as error:  # ezdxf raises several kinds for damaged or foreign files
        other = misnamed(name, "a DXF drawing", {"dxf"})
        if other:
            raise SourceError(f"cannot read {name!r} as DXF: {other}") from error
        detail = str(error) or type(error).__name__
        raise SourceError(f"cannot read {name!r} as DXF ({detail}): the file is not DXF, or "
                          f"it is truncated or damaged; export it again from the CAD program "
                          f"as DXF") from error
    return document, repr(name)


def _scale(document, units, name) -> float:
    """Output units per drawing unit."""
    if units is None:
        return 1.0
    code = document.header.get("$INSUNITS", 0)
    if code not in _MILLIMETRES:
        raise ArgumentError(f"{name} does not say its units ($INSUNITS = {code}): pass "
                            f"units=None to keep the drawing's numbers")
    return _MILLIMETRES[code] / _UNITS[units]


# --- entities and layers ------------------------------------------------------------

def _placed(space, layer=None, blocks=()):
    """Yield (entity, layer, blocks) for every entity of ``space``, blocks expanded in
    place.

    ``layer``: the layer that entities on layer "0" take (the INSERT's); ``blocks``: the
    names of the blocks being expanded, outermost first (yielded with each entity they
    place), to refuse a block that inserts itself.
    """
    for entity in space:
        own = entity.dxf.get("layer", "0")
        effective = layer if layer is not None and own == "0" else own
        if entity.dxftype() != "INSERT":
            yield entity, effective, blocks
            continue
        block = entity.dxf.name
        if block in blocks:
            chain = " -> ".join([*blocks, block])
            raise SourceError(f"block {block!r} inserts itself ({chain}): the drawing is "
                              f"malformed; remove the INSERT of {block!r} from its own block")
        if entity.block() is None:
            raise SourceError(f"an INSERT on layer {own!r} places block {block!r}, which the "
                              f"drawing does not define: the file is damaged; export it again "
                              f"from the CAD program")
        if len(blocks) >= _MAX_NESTING:
            raise SourceError(f"blocks are nested more than {_MAX_NESTING} deep (at "
                              f"{block!r}): the drawing is malformed")
        for insert in (entity.multi_insert() if entity.mcount > 1 else [entity]):
            skipped = []
            parts = list(insert.virtual_entities(
                skipped_entity_callback=lambda part, reason: skipped.append(part)))
            yield from ((part, effective, (*blocks, block)) for part in skipped)   # ignored
            yield from _placed(parts, effective, (*blocks, block))


def _layer_names(layers):
    if layers is None:
        return None
    names = [layers] if isinstance(layers, str) else list(layers)
    if not names or not all(isinstance(name, str) for name in names):
        raise ArgumentError(f"layers must be a layer name or a list of names, got {layers!r}")
    return names


def _selected(placed, layers, document) -> tuple[list, Counter, list]:
    """The outline and hatch entities of the chosen layers, the count of each kind of the
    other entities on them (to be said in a warning), and the chosen layers that neither
    the drawing's layer table nor an entity here names."""
    if layers is None:
        unknown = []
        chosen = {layer.lower() for entity, layer, _ in placed if _is_drawn(entity)}
    else:
        known = {layer.dxf.name.lower() for layer in document.layers} | {
            layer.lower() for _, layer, _ in placed}
        unknown = [layer for layer in layers if layer.lower() not in known]
        chosen = {layer.lower() for layer in layers}
    kept = [entity for entity, layer, _ in placed if layer.lower() in chosen]
    ignored = Counter(entity.dxftype() for entity in kept if not _is_drawn(entity))
    return [entity for entity in kept if _is_drawn(entity)], ignored, unknown


def _is_drawn(entity) -> bool:
    kind = entity.dxftype()
    if kind == "POLYLINE":
        return entity.is_2d_polyline or entity.is_3d_polyline   # not meshes nor polyfaces
    return kind in CURVES or kind == "HATCH"


# --- geometry: pieces of curves in the drawing's coordinates ---------------------------

class _Polyline:
    """Straight segments through ``points`` (k, 2)."""

    def __init__(self, points):
        self.points = np.asarray(points, dtype=float)

    def extent(self):
        return self.points

    def flatten(self, tolerance):
        return self.points


class _Elliptic:
    """``center + u cos θ + v sin θ`` for θ from ``start`` over ``sweep`` (radii: [u v]).

    ``ends``: the exact end points when known (a bulge's vertices), which the computed
    ones would miss by a rounding error; a full turn ends exactly where it starts.
    """

    def __init__(self, center, radii, start, sweep, ends=None):
        self.center, self.radii = np.asarray(center, float), np.asarray(radii, float)
        self.start, self.sweep, self.ends = float(start), float(sweep), ends

    def extent(self):
        half = np.linalg.norm(self.radii, axis=1)   # the whole ellipse's box
        return np.array([self.center - half, self.center + half])

    def flatten(self, tolerance):
        points = elliptic_points(self.center, self.radii, self.start, self.sweep, tolerance)
        if self.ends is not None:
            points[[0, -1]] = self.ends
        elif self.sweep == 2 * math.pi:
            points[-1] = points[0]
        return points


class _Bezier:
    """A Bézier curve of control points (d + 1, 2)."""

    def __init__(self, control):
        self.control = np.asarray(control, dtype=float)

    def extent(self):
        return self.control

    def flatten(self, tolerance):
        return bezier_points(self.control, tolerance)


class _Adaptive:
    """A curve ezdxf flattens itself (rational or unclamped splines)."""

    def __init__(self, curve, transform):
        self.curve, self.transform = curve, transform

    def extent(self):
        return self.transform(self.curve.control_points)

    def flatten(self, tolerance):
        return self.transform(list(self.curve.flattening(tolerance)))


def _chain(pieces, entity, scale) -> list:
    """The pieces of one connected curve, in the drawing's 2D output coordinates."""
    to_2d = _to_2d(entity, scale)
    chain = [piece(to_2d) for piece in pieces]
    if not all(np.isfinite(piece.extent()).all() for piece in chain):
        raise SourceError(f"a {entity.dxftype()} on layer {entity.dxf.get('layer', '0')!r} "
                          f"has NaN or infinite coordinates or radius; fix it in the drawing")
    return chain


def _to_2d(entity, scale):
    """Map (k, 3) points of the entity's coordinate system (OCS or WCS) to output 2D."""
    kind = entity.dxftype()
    planar = kind in ("ARC", "CIRCLE", "LWPOLYLINE", "HATCH") or (
        kind == "POLYLINE" and entity.is_2d_polyline)
    ocs = entity.ocs() if planar else None
    elevation = _elevation(entity) if planar else 0.0

    def to_2d(points, direction=False):
        """``direction``: map vectors (no elevation), not points."""
        points = np.asarray([tuple(p)[:3] + (0.0,) * (3 - len(p)) for p in points], dtype=float)
        if ocs is not None:
            points[:, 2] = 0.0 if direction else elevation
            points = np.asarray(list(ocs.points_to_wcs(points)), dtype=float)
        return scale * points[:, :2]
    return to_2d


def _elevation(entity) -> float:
    """The z of an OCS entity's plane (ARC, CIRCLE, LWPOLYLINE, HATCH, 2D POLYLINE)."""
    kind = entity.dxftype()
    if kind in ("ARC", "CIRCLE"):
        return entity.dxf.center[2]
    if kind == "LWPOLYLINE":
        return entity.dxf.get("elevation", 0.0)
    return entity.dxf.get("elevation", (0.0, 0.0, 0.0))[2]   # a point for HATCH, POLYLINE


def _line(start, end):
    return lambda to_2d: _Polyline(to_2d([start, end]))


def _arc(center, radius, start_degrees, end_degrees):
    """A circular arc of the entity's coordinate system, counter-clockwise; equal start
    and end angles draw nothing (a point), as ezdxf reads them, while 0 to 360 is a
    full turn."""
    if start_degrees == end_degrees:
        theta = math.radians(start_degrees)
        point = (center[0] + radius * math.cos(theta), center[1] + radius * math.sin(theta),
                 center[2] if len(center) > 2 else 0.0)
        return _line(point, point)
    sweep = (end_degrees - start_degrees) % 360.0
    return _conic(center, (radius, 0, 0), (0, radius, 0), math.radians(start_degrees),
                  math.radians(sweep) if sweep else 2 * math.pi)


def _conic(center, u, v, start, sweep, ends=None):
    def piece(to_2d):
        return _Elliptic(to_2d([center])[0], to_2d([u, v], direction=True).T, start, sweep,
                         None if ends is None else to_2d(ends))
    return piece


def _ellipse(ellipse):
    """An ezdxf ConstructionEllipse."""
    sweep = (ellipse.end_param - ellipse.start_param) % (2 * math.pi) or 2 * math.pi
    return _conic(ellipse.center, ellipse.major_axis, ellipse.minor_axis, ellipse.start_param,
                  sweep)


def _bulge(start, end, bulge):
    """The segment from ``start`` to ``end`` (2D) with a bulge: tan(sweep / 4)."""
    p0, p1 = np.asarray(start[:2], float), np.asarray(end[:2], float)
    chord = np.linalg.norm(p1 - p0)
    if bulge == 0 or chord == 0:
        return _line(p0, p1)
    sweep = 4 * math.atan(bulge)
    left = np.array([p0[1] - p1[1], p1[0] - p0[0]]) / chord
    center = (p0 + p1) / 2 + left * (chord / 2) / math.tan(sweep / 2)
    radius = np.linalg.norm(p0 - center)
    begin = math.atan2(p0[1] - center[1], p0[0] - center[0])
    return _conic(center, (radius, 0, 0), (0, radius, 0), begin, sweep, ends=(p0, p1))


def _spline(curve):
    """Bézier pieces of an ezdxf BSpline, or one adaptive piece."""
    if curve.is_rational or not curve.is_clamped:
        return [lambda to_2d: _Adaptive(curve, to_2d)]
    return [lambda to_2d, control=control: _Bezier(to_2d(control))
            for control in curve.bezier_decomposition()]


def _vertices(points, closed):
    """Pieces of a polyline given as (x, y, bulge) vertices."""
    points = list(points)
    pairs = zip(points, points[1:] + points[:1] if closed else points[1:])
    return [_bulge(a[:2], b[:2], a[2]) for a, b in pairs]


def _curve_pieces(entity) -> list:
    """The curves of an outline entity: a list of chains, each a list of pieces."""
    kind = entity.dxftype()
    dxf = entity.dxf
    if kind == "LINE":
        return [[_line(dxf.start, dxf.end)]]
    if kind == "CIRCLE":
        return [[_arc(dxf.center, dxf.radius, 0.0, 360.0)]]
    if kind == "ARC":
        return [[_arc(dxf.center, dxf.radius, dxf.start_angle, dxf.end_angle)]]
    if kind == "ELLIPSE":
        return [[_ellipse(entity.construction_tool())]]
    if kind == "SPLINE":
        return [_spline(entity.construction_tool())]
    if kind == "LWPOLYLINE":
        return [_vertices([(x, y, b) for x, y, b in entity.get_points("xyb")], entity.closed)]
    if entity.is_3d_polyline:
        return [_vertices([(v.dxf.location.x, v.dxf.location.y, 0.0) for v in entity.vertices
                           if not v.dxf.flags & 16], entity.is_closed)]
    vertices = [(v.dxf.location.x, v.dxf.location.y, v.dxf.get("bulge", 0.0))
                for v in entity.vertices if not v.dxf.flags & 16]   # not spline frame points
    return [_vertices(vertices, entity.is_closed)]


def _hatch_paths(hatch) -> list:
    """The boundary paths of a hatch, each a list of pieces."""
    from ezdxf.entities.boundary_paths import EdgeType, PolylinePath

    paths = []
    for path in hatch.paths:
        if isinstance(path, PolylinePath):
            paths.append(_vertices(path.vertices, closed=True))
            continue
        pieces = []
        for edge in path.edges:
            if edge.type == EdgeType.LINE:
                pieces.append(_line(edge.start, edge.end))
            elif edge.type == EdgeType.ARC:
                arc = edge.construction_tool()
                pieces.append(_arc(arc.center, arc.radius, arc.start_angle, arc.end_angle))
            elif edge.type == EdgeType.ELLIPSE:
                pieces.append(_ellipse(edge.construction_tool()))
            else:
                pieces.extend(_spline(edge.construction_tool()))
        paths.append(pieces)
    return paths


def _curves(drawn, tolerance):
    """The exact pieces of the chains drawn, each labelled with its entity's layer;
    splines beyond cubics and rational ones as their polylines within ``tolerance``."""
    build = curves_builder(tolerance)
    for layer, chain in drawn:
        for piece in chain:
            if isinstance(piece, _Elliptic):
                build.arc(piece.center, piece.radii, piece.start, piece.sweep, layer)
            elif isinstance(piece, _Bezier) and len(piece.control) == 4:
                build.cubic(piece.control, layer)
            elif isinstance(piece, _Bezier) and len(piece.control) == 3:
                build.quadratic(piece.control, layer)
            else:
                build.polyline(piece.flatten(tolerance), layer)
    return build.done()


def _points(chain, tolerance) -> np.ndarray:
    """The polyline of a chain of pieces, each turned to continue from the last one."""
    points = [chain[0].flatten(tolerance)]
    for piece in chain[1:]:
        following = piece.flatten(tolerance)
        end = points[-1][-1]
        if np.linalg.norm(following[-1] - end) < np.linalg.norm(following[0] - end):
            following = following[::-1]
        points.append(following)
    points = np.concatenate(points)
    return points[np.r_[True, np.any(points[1:] != points[:-1], axis=1)]]
