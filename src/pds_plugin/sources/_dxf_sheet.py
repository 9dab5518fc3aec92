"""The sheet format of a paper-space layout: the border and title block around the views.

A drawing exported to paper space (SolidWorks writes its sheets there) holds, besides
the parts, what the sheet adds: VIEWPORT windows onto model space, a border, often a
second trim line, and a title block drawn against the border, full of text. None of it
is part of the region. Two rules find it, both only in paper space:

- **by name** (:func:`sheet_format_name`): an entity on a layer, or placed by an INSERT
  of a block, whose name contains FORMAT, TITLE or BORDER (case-insensitive: SolidWorks's
  sheet-format layer is FORMAT; AutoCAD templates use TITLE, TITLEBLOCK, BORDER) -- unless
  that layer was asked for by ``layers=``;
- **by shape** (:func:`sheet_border`): the curves are grouped into connected sets (curves
  closer than the tolerance touch). A set *encloses* the others when the area its lines
  close off covers every other remaining curve; peeling such sets from the outside in
  gives a chain of nested frames. A frame in that chain is a **sheet border** when the
  area it closes off is an axis-aligned rectangle and either its width and height are
  between :data:`PAPER_SHARE` and 101 % of the layout's paper (its plot settings or its
  limits, either orientation) or the title block is drawn against it: its lines divide the
  rectangle into several faces, some holding no other curve. The outermost frames down to
  the innermost border are left out, with everything connected to them and the hatches
  in their empty faces (a logo in a title-block cell).

A part is taken for a border only if it is an axis-aligned rectangle enclosing every
other curve of the sheet and either spans 75-101 % of the paper or is divided by lines
into faces of which one holds nothing; a drawing of several parts, or of one part smaller
than the sheet, is read whole. The warning names what was left out, with its size.
"""

from __future__ import annotations

import numpy as np
import shapely

__all__ = ["SHEET_WORDS", "PAPER_SHARE", "sheet_format_name", "sheet_border", "paper_sizes"]

SHEET_WORDS = ("FORMAT", "TITLE", "BORDER")
"""Words that name a sheet format's layer or block."""
PAPER_SHARE = 0.75
"""Smallest share of the paper's width and height a border spans (ISO 5457 borders of
A4 to A0 span 86-98 %, ANSI ones with half-inch margins 88-98 %)."""
_PAPER_SLACK = 1.01


def sheet_format_name(layer: str, blocks, asked=None) -> str | None:
    """The name that makes an entity part of the sheet format, or None.

    Parameters
    ----------
    layer : str
        The entity's layer.
    blocks : sequence of str
        The blocks whose INSERTs placed it, outermost first.
    asked : set of str, optional
        Layers (lower case) the user asked for: never the sheet format by name.

    Returns
    -------
    str or None
        ``"layer 'FORMAT'"`` or ``"block 'TITLEBLOCK'"``.

    Examples
    --------
    >>> sheet_format_name("Format", ())
    "layer 'Format'"
    >>> sheet_format_name("0", ("A3_TitleBlock", "LOGO"))
    "block 'A3_TitleBlock'"
    >>> sheet_format_name("FORMAT", (), asked={"format"}) is None
    True
    """
    for block in blocks:
        if any(word in block.upper() for word in SHEET_WORDS):
            return f"block {block!r}"
    if asked is not None and layer.lower() in asked:
        return None
    if any(word in layer.upper() for word in SHEET_WORDS):
        return f"layer {layer!r}"
    return None


def paper_sizes(layout, millimetres_per_unit) -> list[tuple[float, float]]:
    """The layout's paper (width, height) in drawing units: its plot settings' paper
    (given in millimetres) and its limits, when the file states them.

    Parameters
    ----------
    layout : ezdxf.layouts.Paperspace
    millimetres_per_unit : float or None
        From the drawing's ``$INSUNITS``; None (unitless): millimetres are assumed.

    Returns
    -------
    list of (float, float)

    Examples
    --------
    >>> import ezdxf
    >>> sheet = ezdxf.new().layouts.get("Layout1")
    >>> sheet.page_setup(size=(17, 11), margins=(0.5, 0.5, 0.5, 0.5), units="inch")
    >>> paper_sizes(sheet, 25.4)                          # plot settings, limits
    [(17.0, 11.0), (17.0, 11.0)]
    """
    sizes = []
    settings = layout.dxf_layout.dxf
    width, height = settings.get("paper_width", 0.0), settings.get("paper_height", 0.0)
    if width > 0 and height > 0:
        unit = millimetres_per_unit or 1.0
        sizes.append((width / unit, height / unit))
    low, high = layout.dxf.get("limmin"), layout.dxf.get("limmax")
    if low is not None and high is not None and high[0] > low[0] and high[1] > low[1]:
        sizes.append((high[0] - low[0], high[1] - low[1]))
    return sizes


def sheet_border(curves, tolerance: float, papers=()):
    """The curves of a paper-space layout that form its sheet border and title block.

    Parameters
    ----------
    curves : list of (k, 2) array_like
        The layout's flattened curves.
    tolerance : float
        Curves closer than this touch.
    papers : iterable of (float, float)
        The layout's paper sizes (:func:`paper_sizes`).

    Returns
    -------
    dropped : ndarray of bool
        Per curve: part of the sheet border or its title block.
    size : (float, float) or None
        The width and height of the outermost border left out.
    cells : shapely geometry
        The faces of the borders left out that hold no other curve (the title block's
        cells, where a hatched logo is no part either), empty when none.

    Examples
    --------
    >>> border = [(0, 0), (400, 0), (400, 280), (0, 280), (0, 0)]
    >>> title = [(300, 0), (300, 40), (400, 40)]                # a cell against it
    >>> plate = [(50, 50), (150, 50), (150, 100), (50, 100), (50, 50)]
    >>> dropped, size, cells = sheet_border([border, title, plate], 1e-3)
    >>> dropped, size, cells.bounds
    (array([ True,  True, False]), (400.0, 280.0), (300.0, 0.0, 400.0, 40.0))
    >>> sheet_border([border, plate], 1e-3)[:2]                  # no paper, no title block
    (array([False, False]), None)
    >>> sheet_border([border, plate], 1e-3, papers=[(420, 297)])[:2]
    (array([ True, False]), (400.0, 280.0))
    >>> sheet_border([border, plate], 1e-3, papers=[(297, 210)])[:2]   # larger than paper
    (array([False, False]), None)
    """
    lines = np.array([shapely.LineString(curve) if len(curve) > 1 else shapely.Point(curve[0])
                      for curve in (np.asarray(curve, dtype=float) for curve in curves)],
                     dtype=object)
    group = _connected(lines, tolerance)
    bounds = shapely.bounds(lines)
    low = np.full((group.max() + 1, 2), np.inf)
    high = np.full((group.max() + 1, 2), -np.inf)
    np.minimum.at(low, group, bounds[:, :2])
    np.maximum.at(high, group, bounds[:, 2:])
    extents = {g: np.r_[low[g], high[g]] for g in dict.fromkeys(group.tolist())}
    remaining, chain = list(extents), []             # chain: (group, frame), outside in
    while remaining:
        everything = np.r_[np.min([extents[g][:2] for g in remaining], axis=0),
                           np.max([extents[g][2:] for g in remaining], axis=0)]
        found = None
        for g in remaining:
            if np.array_equal(extents[g], everything):    # only it can enclose the others
                alive = np.isin(group, remaining)
                frame = _frame(lines[group == g], lines[alive & (group != g)], tolerance,
                               papers)
                if frame is not None:
                    found = g, frame
                    break
        if found is None:
            break
        chain.append(found)
        remaining.remove(found[0])
    borders = [index for index, (_, (border, _, _)) in enumerate(chain) if border]
    if not borders:
        return np.zeros(len(lines), dtype=bool), None, shapely.Polygon()
    left_out = chain[:borders[-1] + 1]
    cells = shapely.union_all([cells for _, (_, _, cells) in left_out])
    return np.isin(group, [g for g, _ in left_out]), chain[0][1][1], cells


def _connected(lines, tolerance) -> np.ndarray:
    """The connected set of each line (lines within ``tolerance`` touch)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    pairs = shapely.STRtree(lines).query(lines, predicate="dwithin", distance=tolerance)
    graph = coo_matrix((np.ones(pairs.shape[1]), pairs), shape=(len(lines),) * 2)
    return connected_components(graph, directed=False)[1]


def _frame(members, others, tolerance, papers):
    """``(is a border, (width, height), empty cells)`` when the lines ``members`` close
    off an area covering every line of ``others`` (arrays of geometries), else None."""
    noded = shapely.union_all(shapely.set_precision(members, tolerance))
    faces = shapely.get_parts(shapely.polygonize(shapely.get_parts(noded)))
    if len(faces) == 0:
        return None
    closed = shapely.union_all(faces)
    if not isinstance(closed, shapely.Polygon):
        return None
    area = shapely.Polygon(closed.exterior)
    shapely.prepare(area)
    if not shapely.covers(area, others).all():
        return None
    box = area.envelope
    rectangle = box.area - area.area <= tolerance * box.length
    x0, y0, x1, y1 = shapely.total_bounds(members)        # exact, not on the grid
    size = (float(x1 - x0), float(y1 - y0))
    paper = any(PAPER_SHARE * w <= size[0] <= _PAPER_SLACK * w
                and PAPER_SHARE * h <= size[1] <= _PAPER_SLACK * h
                for width, height in papers for w, h in ((width, height), (height, width)))
    holding = np.isin(np.arange(len(faces)),
                      shapely.STRtree(others).query(faces, predicate="intersects")[0])
    title_block = len(faces) > 1 and not holding.all()
    cells = shapely.union_all(faces[~holding]) if len(faces) > 1 else shapely.Polygon()
    return rectangle and (paper or title_block), size, cells
