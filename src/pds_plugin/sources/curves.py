"""What the 2D drawing readers (:mod:`.svg`, :mod:`.dxf`) share: the file checks, the
default tolerance, curves cut into chords to an absolute tolerance, and the assembly of an
outline drawing with its report of open ends.
"""

from __future__ import annotations

import math
import os
import warnings

import numpy as np

from .._checks import check_path, check_positive_int
from ..errors import RegionError, SourceError
from ..region import SCALE_LIMITS, check_scale
from .polygons import ROUNDING, outline_geometry

__all__ = ["RELATIVE_TOLERANCE", "checked_file", "default_tolerance", "steps",
           "elliptic_points", "bezier_points", "outline"]

RELATIVE_TOLERANCE = 1e-4
"""Default tolerance of the drawing readers, as a fraction of the drawing's diagonal."""
MAX_CHORDS = 1_000_000
"""Chords of one curve beyond which it is refused: the curve is broken or the tolerance tiny."""


def checked_file(path, kind: str, max_bytes: int | None = None) -> str:
    """The path of an existing, non-empty drawing file of at most ``max_bytes``.

    Parameters
    ----------
    path : str or os.PathLike
    kind : str
        The format, for messages ("SVG", "DXF").
    max_bytes : int, optional
        The largest file accepted; the error names the reader's keyword ``max_bytes``.

    Returns
    -------
    str

    Raises
    ------
    FileNotFoundError, IsADirectoryError
        If there is no such file, or it is a folder.
    ArgumentTypeError
        If ``path`` is not a file name.
    SourceError
        If the file is empty or larger than ``max_bytes``.
    ArgumentError
        If ``max_bytes`` is not a positive integer.

    Examples
    --------
    >>> checked_file("absent.dxf", "DXF")
    Traceback (most recent call last):
    ...
    FileNotFoundError: no such DXF file: 'absent.dxf'
    """
    name = check_path(path)
    if os.path.isdir(name):
        raise IsADirectoryError(f"{name!r} is a folder, not a {kind} file")
    if not os.path.isfile(name):
        raise FileNotFoundError(f"no such {kind} file: {name!r}")
    size = os.path.getsize(name)
    if size == 0:
        raise SourceError(f"the {kind} file {name!r} is empty")
    if max_bytes is not None and size > check_positive_int(max_bytes, "max_bytes"):
        raise SourceError(f"{name!r} is {size:,} bytes, more than {max_bytes:,}; pass a larger "
                          f"max_bytes to read it")
    return name


def default_tolerance(points) -> float:
    """``RELATIVE_TOLERANCE`` times the diagonal of the points' bounding box.

    Parameters
    ----------
    points : (n, 2) array_like
        Points whose bounding box is the drawing's (or contains it).

    Returns
    -------
    float

    Raises
    ------
    RegionError
        If the box has zero size (no points, or all the same), a point is not finite, or
        the box is beyond the scale float64 holds (:func:`pds_plugin.region.check_scale`).

    Examples
    --------
    >>> default_tolerance([(0, 0), (30, 40)])
    0.005
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if not np.isfinite(points).all():
        raise RegionError("the drawing's coordinates overflow float64 (a transform or a size "
                          "beyond ±1.8e308 makes them infinite): fix the drawing or its units")
    if len(points):
        check_scale((*points.min(axis=0), *points.max(axis=0)), "the drawing spans",
                    "fix the drawing or its units")
    diagonal = np.linalg.norm(np.ptp(points, axis=0)) if len(points) else 0.0
    if not diagonal > 0:
        raise RegionError("the drawing has zero size: nothing to mesh")
    return float(RELATIVE_TOLERANCE * diagonal)


def steps(bound, tolerance) -> np.ndarray:
    """Parameters in (0, 1] of the chord ends for a curve with max|B''| <= bound.

    On a parameter interval of length h a chord deviates from the curve by at most
    h² max|B''| / 8, so ``ceil(sqrt(max|B''| / (8 tolerance)))`` uniform intervals suffice.

    Parameters
    ----------
    bound : float
        A bound of the second derivative's length over the parameter interval [0, 1].
    tolerance : float
        The largest distance allowed between a chord and the curve.

    Returns
    -------
    (m,) ndarray
        Uniform parameters, the last one 1 (a straight curve, bound 0, gets just [1]).

    Examples
    --------
    >>> steps(8.0, 0.25).tolist()                      # sqrt(8 / 2) = 2 intervals
    [0.5, 1.0]
    """
    with np.errstate(all="ignore"):
        count = np.ceil(np.sqrt(bound / (8 * tolerance)))
    if not count <= MAX_CHORDS:                  # also NaN, from control points near 1e308
        raise SourceError(f"a curve of the drawing needs more than {MAX_CHORDS:,} chords to "
                          f"stay within the tolerance (its control points span {bound:.3g}); "
                          f"pass a larger tolerance or fix the curve")
    return np.linspace(0, 1, max(1, int(count)) + 1)[1:]


def elliptic_points(center, radii, start, sweep, tolerance) -> np.ndarray:
    """Points ``center + u cos θ + v sin θ``, θ from ``start`` over ``sweep``, within
    ``tolerance`` of the curve; the first point is the start.

    ``radii`` holds two conjugate radii u, v as columns: any affine image of a circular
    or elliptical arc is exactly of this form. The chordal bound of :func:`steps` applies
    with max|B''| = ||[u v]||₂ sweep².

    Parameters
    ----------
    center : (2,) array_like
    radii : (2, 2) array_like
        The conjugate radii u and v as columns.
    start : float
        The parameter θ of the first point (radians).
    sweep : float
        The parameter's signed range (radians; negative turns from u away from v).
    tolerance : float
        The largest distance allowed between a chord and the arc.

    Returns
    -------
    (m, 2) ndarray

    Examples
    --------
    >>> points = elliptic_points((0, 0), np.eye(2), 0.0, np.pi / 2, 1e-3)
    >>> points[0].tolist(), np.round(points[-1], 12).tolist(), len(points)
    ([1.0, 0.0], [0.0, 1.0], 19)
    >>> sagitta = 1 - np.linalg.norm((points[1:] + points[:-1]) / 2, axis=1)
    >>> bool(sagitta.max() <= 1e-3)
    True
    """
    radii = np.asarray(radii, dtype=float)
    theta = start + sweep * np.r_[0.0, steps(_spectral_norm(radii) * sweep**2, tolerance)]
    return np.asarray(center, dtype=float) + np.column_stack(
        [np.cos(theta), np.sin(theta)]) @ radii.T


def _spectral_norm(matrix) -> float:
    """||M||₂ of a 2x2 matrix in closed form (its largest singular value; ``np.linalg.norm
    (M, 2)`` takes an SVD, 40 µs a call).

    >>> _spectral_norm(np.array([[3.0, 0.0], [4.0, 5.0]])) ** 2      # eigenvalues 45, 5
    45.00000000000001
    """
    (a, b), (c, d) = matrix
    squares, determinant = a * a + b * b + c * c + d * d, a * d - b * c
    return math.sqrt(0.5 * (squares + math.sqrt(max(squares * squares
                                                    - 4 * determinant * determinant, 0.0))))


def bezier_points(control, tolerance) -> np.ndarray:
    """Points of a Bézier curve within ``tolerance`` of it; the first and last are its ends.

    For degree d, max|B''| <= d (d - 1) max|P[i+2] - 2 P[i+1] + P[i]|, and :func:`steps`
    gives uniform parameters for that bound.

    Parameters
    ----------
    control : (d + 1, 2) array_like
        The control points.
    tolerance : float
        The largest distance allowed between a chord and the curve.

    Returns
    -------
    (m, 2) ndarray

    Examples
    --------
    >>> points = bezier_points([(0, 0), (1, 2), (2, 0)], 0.01)   # y = 2x - x², |B''| = 8
    >>> len(points), bool(np.allclose(points[:, 1], 2 * points[:, 0] - points[:, 0] ** 2))
    (11, True)
    """
    control = np.asarray(control, dtype=float)
    degree = len(control) - 1
    second = control[2:] - 2 * control[1:-1] + control[:-2]
    bound = degree * (degree - 1) * np.linalg.norm(second, axis=1).max() if degree > 1 else 0
    t = np.r_[0.0, steps(bound, tolerance)][:, None]
    power = np.arange(degree + 1)
    choose = np.array([math.comb(degree, i) for i in power], dtype=float)
    return (choose * t**power * (1 - t) ** (degree - power)) @ control


def outline(chains, tolerance, name, kind="curve"):
    """Assemble loose curves into polygons; warn about open ends, raise if none close.

    Parameters
    ----------
    chains : list of (k, 2) array_like
        The drawing's flattened curves.
    tolerance : float
        Ends closer than this are joined (see :func:`.polygons.outline_geometry`).
    name : str
        The drawing, for messages.
    kind : str
        What the curves are called in messages ("stroke", "curve").

    Returns
    -------
    shapely Polygon or MultiPolygon

    Raises
    ------
    RegionError
        If no loop closes (the message gives the open ends), or a coordinate is beyond
        the region's limit (:data:`pds_plugin.region.SCALE_LIMITS`).

    Warns
    -----
    UserWarning
        With the ends that meet nothing, when some loops close and others do not.

    Examples
    --------
    >>> square = [[(0, 0), (4, 0), (4, 4)], [(4, 4), (0, 4), (0, 0)]]
    >>> outline(square, 1e-9, "'square.svg'", kind="stroke").area
    16.0
    """
    largest = max((float(np.abs(chain).max()) for chain in chains if len(chain)), default=0.0)
    if not largest < SCALE_LIMITS[1]:          # before the KD-tree of the ends overflows
        raise RegionError(f"the outline drawing {name} has coordinates up to {largest:.3g}: "
                          f"a region needs coordinates below {SCALE_LIMITS[1]:g}; fix the "
                          f"drawing or scale it (e.g. change its units)")
    if ROUNDING * largest >= tolerance:        # every step would be taken for rounding
        raise RegionError(f"the outline drawing {name} lies at coordinates up to "
                          f"{largest:.3g}, where rounding ({ROUNDING:g} of them) exceeds the "
                          f"tolerance {tolerance:.3g}: its curves cannot be joined; translate "
                          f"the drawing towards the origin, or pass a larger tolerance")
    geometry, open_ends = outline_geometry(chains, tolerance)
    where = ", ".join(f"({x:.6g}, {y:.6g})" for x, y in open_ends[:5])
    where += ", ..." if len(open_ends) > 5 else ""
    if geometry.is_empty:
        raise RegionError(
            f"no closed loop in the outline drawing {name}: nothing to mesh"
            + (f"; {len(open_ends)} {kind} end(s) meet no other {kind} within the tolerance "
               f"{tolerance:.3g}, at {where}; pass a larger tolerance" if len(open_ends) else ""))
    if len(open_ends):
        warnings.warn(f"{len(open_ends)} {kind} end(s) of {name} meet no other {kind} within "
                      f"the tolerance {tolerance:.3g}, at {where}; the open {kind}s are ignored "
                      f"(pass a larger tolerance to join them)", UserWarning, stacklevel=3)
    return geometry
