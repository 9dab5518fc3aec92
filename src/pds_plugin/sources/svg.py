"""SVG source: the filled shapes, or the outline drawing, of an SVG file as a Region.

Parsed with svgelements (nested transforms, units, ``<use>``, styles and inherited
``fill-rule``); every curve is flattened to an absolute chordal tolerance, and the fill
rule or the nesting of outline loops is resolved exactly by :mod:`.polygons`, the
outline's open ends reported as for every drawing (:mod:`.curves`).
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from .._checks import check_positive
from ..boundary_curves import curves_builder
from ..errors import ArgumentError, RegionError, SourceError
from ..region import Region
from ._sniff import misnamed
from ._svg_limits import MAX_BYTES, MAX_ELEMENTS, MAX_SEGMENTS, check_svg_limits
from .curves import checked_file, default_tolerance, elliptic_points, outline, steps
from .polygons import fill_geometry

__all__ = ["load_svg"]

_UNITS = ("px", "pt", "mm", "cm", "in")


def load_svg(path, tolerance=None, units=None, mode: str = "auto", *,
             max_bytes: int = MAX_BYTES, max_elements: int = MAX_ELEMENTS,
             max_segments: int = MAX_SEGMENTS) -> Region:
    """Read an SVG drawing as a :class:`Region` in the drawing's plane (z = 0).

    Two kinds of drawing are understood:

    - **filled** shapes (paths, polygons, circles, ellipses, rects with rounded corners):
      each is filled by its ``fill-rule`` (``nonzero`` or ``evenodd``, set on the shape,
      inherited from its groups or given in a ``style``), and the filled areas are
      united, whatever their colour;
    - **outline** drawings (CAD, DXF and laser-cutting exports: unfilled strokes whose
      ends meet): the strokes are joined into closed loops where their ends are closer
      than ``tolerance``, and the loops are nested by containment (even-odd), so a loop
      inside a part is a hole and a loop inside a hole is an island. Strokes are read
      as centre lines (their width is ignored); curves drawn twice count once. Ends
      that meet nothing are reported in a warning with their coordinates.

    ``<defs>``, ``<clipPath>``, ``<pattern>``, ``display:none`` and ``visibility:hidden``
    content are skipped, text and images are ignored. The y axis is flipped (SVG points
    down) so the drawing is not mirrored: the page rectangle maps onto itself upside
    down, or ``y -> -y`` when the file gives neither ``viewBox`` nor size.

    Parameters
    ----------
    path : str or os.PathLike
    tolerance : float, optional
        Geometric accuracy in output units: arcs, circles, ellipses and Béziers are
        flattened so that no point of the curve is farther than this from its polyline,
        and outline strokes whose ends are closer than this are joined. Default:
        1e-4 times the diagonal of the drawing's bounding box.
    units : {None, "mm", "cm", "in", "pt", "px"}
        None keeps the drawing's user units (its ``viewBox`` coordinates); a unit
        converts to that physical unit through the document's ``width``/``height``
        (at 96 px per inch when the document gives no physical size).
    mode : {"auto", "fill", "outline"}
        ``auto`` reads the filled shapes if they enclose any area, and the outline of all
        visible shapes otherwise (an outline drawing's strokes must then be unfilled,
        ``fill="none"``, as CAD exports write them; or pass ``mode="outline"``).
    max_bytes, max_elements, max_segments : int
        Limits checked before the drawing is built (see :mod:`._svg_limits`): the file's
        size (20 MB), the elements it expands to with every ``<use>`` copy (100,000), and
        its path and polygon segments (100,000). Raise them for bigger drawings.

    Returns
    -------
    Region
        With the identity frame (the drawing lies in the plane z = 0).

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    SourceError
        If the file is empty or not SVG, exceeds a limit, has a negative shape size or an
        empty ``viewBox``.
    RegionError
        If it has nothing to mesh (no visible shape, no area, or no loop that closes: the
        message gives the open ends).
    ArgumentError
        If ``tolerance``, ``units`` or ``mode`` is bad.

    Examples
    --------
    >>> import pathlib, tempfile, pds_plugin as pds
    >>> svg = pathlib.Path(tempfile.mkdtemp()) / "ring.svg"
    >>> _ = svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 20 20">'
    ...                    '<path fill-rule="evenodd" d="M0 0H20V20H0Z M5 5H15V15H5Z"/></svg>')
    >>> region = pds.load_svg(svg)
    >>> region.area, region.betti
    (300.0, (1, 1))
    """
    if mode not in ("auto", "fill", "outline"):
        raise ArgumentError(f"mode must be 'auto', 'fill' or 'outline', got {mode!r}")
    if units is not None and units not in _UNITS:
        raise ArgumentError(f"units must be None (the drawing's user units) or one of "
                         f"{_UNITS}, got {units!r}")
    document, name = _parse(path, max_bytes, max_elements, max_segments)
    matrix = _output_matrix(document, units)
    shapes = _visible_shapes(document)
    if not shapes:
        raise RegionError(f"{name} has no visible shapes: nothing to mesh")
    paths = [_absolute(shape) for shape in shapes]
    tolerance = _tolerance(tolerance, paths, matrix)
    step = tolerance / np.linalg.norm(matrix[:, :2], 2)  # the tolerance in svgelements units
    geometry = shapely.Polygon()
    drawn = list(enumerate(zip(shapes, paths)))
    if mode != "outline":
        drawn = [(index, pair) for index, pair in drawn if _is_filled(pair[0])]
        geometry = _fill([pair for _, pair in drawn], matrix, step)
        if geometry.is_empty and mode == "fill":
            raise RegionError(f"the filled shapes of {name} enclose no area: nothing to mesh "
                             f"(for an outline drawing use mode='outline')")
    if geometry.is_empty:
        drawn = list(enumerate(zip(shapes, paths)))
        chains = [_apply(matrix, points) for path in paths for points in _flatten(path, step)]
        geometry = outline(chains, tolerance, name, kind="stroke")
    return Region.from_shapely(geometry, curves=_curves(drawn, matrix, tolerance))


def _parse(path, max_bytes, max_elements, max_segments):
    import svgelements

    name = checked_file(path, "SVG", max_bytes)
    check_svg_limits(name, max_elements, max_segments)
    try:
        document = svgelements.SVG.parse(name, reify=True, ppi=96.0)
    except RecursionError as error:
        raise SourceError(f"cannot read {name!r} as SVG: its elements are nested too deep "
                          f"(thousands of groups inside groups); flatten the groups") from error
    except Exception as error:  # the XML parser raises several kinds
        raise SourceError(f"cannot read {name!r} as SVG: "
                          f"{misnamed(name, 'an SVG drawing', {'svg'}) or error}") from error
    if not isinstance(document, svgelements.SVG):
        raise SourceError(f"cannot read {name!r} as SVG: "
                          f"{misnamed(name, 'an SVG drawing', {'svg'}) or _not_svg(name)}")
    return document, repr(name)


def _not_svg(name) -> str:
    """Why the root element of an XML file is not an SVG drawing's."""
    import xml.etree.ElementTree as ElementTree

    try:
        tag = next(ElementTree.iterparse(name, events=("start",)))[1].tag
    except (ElementTree.ParseError, StopIteration, OSError):
        return "it has no <svg> element: it is not an SVG drawing"
    space, _, local = tag[1:].rpartition("}") if tag.startswith("{") else ("", "", tag)
    if local.lower() == "svg" and local != "svg":
        return f"its root element is <{local}>, but SVG element names are lower case (<svg>)"
    if local == "svg":
        return (f"its root <svg> element is in the namespace {space!r}, not SVG's "
                f"('{_SVG_NAMESPACE}'); set xmlns=\"{_SVG_NAMESPACE}\"")
    return f"its root element is <{local}>, not <svg>: it is not an SVG drawing"


_SVG_NAMESPACE = "http://www.w3.org/2000/svg"


def _output_matrix(document, units) -> np.ndarray:
    """2x3 affine map from svgelements pixels to output coordinates, y flipped."""
    import svgelements

    if units is None:  # undo the viewBox -> viewport map: back to user units
        try:
            view = svgelements.Matrix(document.viewbox_transform)
        except ZeroDivisionError:               # svgelements' own viewBox maths
            view = svgelements.Matrix([0, 0, 0, 0, 0, 0])
        if not (math.isfinite(view.determinant) and view.determinant != 0):
            raise SourceError(f"the drawing's viewBox or size ({document.values.get('viewBox')}"
                              f", width {document.values.get('width')}, height "
                              f"{document.values.get('height')}) is empty or not finite: give "
                              f"the <svg> element a viewBox with a positive width and height")
        view.inverse()
        matrix = np.array([[view.a, view.c, view.e], [view.b, view.d, view.f]])
    else:
        pixels = svgelements.Length(f"1{units}").value(ppi=96.0)  # svgelements' own factor
        matrix = np.hstack([np.eye(2) / pixels, np.zeros((2, 1))])
    sized = document.viewbox is not None or {"width", "height"} <= set(document.values)
    corners = [[0.0, 0.0], [document.width, document.height]] if sized else np.zeros((2, 2))
    page = _apply(matrix, corners) if sized else corners
    flip = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, page[:, 1].sum()], [0.0, 0.0, 1.0]])
    return (flip @ np.vstack([matrix, [0.0, 0.0, 1.0]]))[:2]


def _apply(matrix, points) -> np.ndarray:
    return np.asarray(points, dtype=float) @ matrix[:, :2].T + matrix[:, 2]


def _visible_shapes(document) -> list:
    import svgelements

    return [element for element in document.elements()
            if isinstance(element, svgelements.Shape)
            and element.values.get("visibility") not in ("hidden", "collapse")]


def _absolute(shape):
    """The shape as a path whose segments have its transform applied (a copy)."""
    import svgelements

    return abs(svgelements.Path(shape))


def _tolerance(tolerance, paths, matrix) -> float:
    if tolerance is not None:
        return check_positive(tolerance, "tolerance")
    extremes = [_extremes(segment) for path in paths for segment in path]
    return default_tolerance(_apply(matrix, np.concatenate(extremes)) if extremes else [])


def _extremes(segment) -> np.ndarray:
    """Points of a segment whose bounding box is the segment's (an arc's computed on its
    conjugate radii: svgelements' own arc box is slow, and wrong under a skew)."""
    import svgelements

    if isinstance(segment, svgelements.Arc):
        return _arc_extremes(segment)
    return np.reshape(np.asarray(segment.bbox(), dtype=float), (2, 2))


def _is_filled(shape) -> bool:
    return shape.fill is not None and shape.fill.value is not None


def _fill(filled, matrix, step):
    return shapely.union_all([
        fill_geometry([_apply(matrix, points) for points in _flatten(path, step)],
                      shape.values.get("fill-rule", "nonzero"))
        for shape, path in filled])


def _flatten(path, step):
    """Yield the points (k, 2) of each subpath of an absolute path, flattened to ``step``.

    A closed subpath ends on its first point; fill rules close the others implicitly.
    """
    for subpath in path.as_subpaths():
        segments = list(subpath)
        if not segments:
            continue
        points = [np.asarray([segments[0].end], dtype=float)]  # the Move's point
        points += [_points(segment, step) for segment in segments[1:]]
        points = np.concatenate(points)
        points = points[np.r_[True, np.any(points[1:] != points[:-1], axis=1)]]
        if len(points) >= 2:
            yield points


def _points(segment, step) -> np.ndarray:
    """The points after the start of one segment, the chords within ``step`` of the curve.

    On a parameter interval of length h a chord deviates from the curve by at most
    h² max|B''| / 8, so ``ceil(sqrt(max|B''| / (8 step)))`` uniform intervals suffice.
    """
    import svgelements

    if isinstance(segment, svgelements.Arc):
        return _arc_points(segment, step)
    if isinstance(segment, svgelements.QuadraticBezier):
        p = np.array([segment.start, segment.control, segment.end], dtype=float)
        bound = 2 * np.linalg.norm(p[0] - 2 * p[1] + p[2])
    elif isinstance(segment, svgelements.CubicBezier):
        p = np.array([segment.start, segment.control1, segment.control2, segment.end], dtype=float)
        bound = 6 * np.linalg.norm(p[:2] - 2 * p[1:3] + p[2:], axis=1).max()
    else:  # Line, Close: straight
        return np.asarray([segment.end], dtype=float)
    return np.asarray(segment.npoint(steps(bound, step)), dtype=float)


def _curves(drawn, matrix, tolerance):
    """The exact pieces of the shapes drawn, in output coordinates, each labelled with its
    element's id (else its tag and number among the visible shapes)."""
    import svgelements

    build = curves_builder(tolerance)
    linear = matrix[:, :2]
    for index, (shape, path) in drawn:
        label = shape.id or f"{type(shape).__name__.lower()} {index}"
        for segment in path:
            if isinstance(segment, svgelements.Move) or segment.start is None:
                continue
            start, end = _apply(matrix, [segment.start, segment.end])
            frame = _arc_frame(segment) if isinstance(segment, svgelements.Arc) else None
            if frame is not None:
                center, radii, theta, sweep = frame
                build.arc(_apply(matrix, [center])[0], linear @ radii, theta, sweep, label)
            elif isinstance(segment, svgelements.QuadraticBezier):
                build.quadratic(_apply(matrix, [segment.start, segment.control, segment.end]),
                                label)
            elif isinstance(segment, svgelements.CubicBezier):
                build.cubic(_apply(matrix, [segment.start, segment.control1, segment.control2,
                                            segment.end]), label)
            else:
                build.line(start, end, label)
    return build.done()


def _arc_points(arc, step) -> np.ndarray:
    """Points of an elliptical arc after its start, within ``step`` of it."""
    frame = _arc_frame(arc)
    if frame is None:                            # degenerate: a straight segment
        return np.asarray([arc.end], dtype=float)
    points = elliptic_points(*frame, step)[1:]
    points[-1] = arc.end
    return points


def _arc_extremes(arc) -> np.ndarray:
    """The ends of an arc and its points of extreme x and y within its sweep."""
    ends = np.array([arc.start, arc.end], dtype=float)
    frame = _arc_frame(arc)
    if frame is None:
        return ends
    center, radii, start, sweep = frame
    peaks = np.arctan2(radii[:, 1], radii[:, 0])      # x = c + u cos θ + v sin θ peaks there
    angles = np.concatenate([peaks, peaks + np.pi])
    swept = angles[np.mod((angles - start) * np.sign(sweep), 2 * np.pi) <= abs(sweep)]
    return np.vstack([ends, center + np.column_stack([np.cos(swept), np.sin(swept)]) @ radii.T])


def _arc_frame(arc):
    """``(center, radii, start, sweep)`` with the arc = ``c + u cos θ + v sin θ``, θ from
    ``start`` over ``sweep`` (radii: u, v as columns), or None for a straight arc.

    svgelements keeps a transformed arc as its centre and the images ``prx``, ``pry`` of
    two perpendicular radii, which a skew leaves non-perpendicular (its own evaluation
    assumes them perpendicular). This form is exact for any affine image, and svgelements
    negates ``sweep`` under reflections, when ``det[u v]`` turns negative.
    """
    center = np.array(arc.center, dtype=float)
    radii = np.array([arc.prx, arc.pry], dtype=float).T - center[:, None]  # columns u, v
    determinant = np.linalg.det(radii)
    if arc.sweep == 0 or not abs(determinant) > 0:
        return None
    cosine, sine = np.linalg.solve(radii, np.array(arc.start, dtype=float) - center)
    return center, radii, np.arctan2(sine, cosine), arc.sweep * np.sign(determinant)
