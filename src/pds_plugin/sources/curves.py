"""What the 2D drawing readers (:mod:`.svg`, :mod:`.dxf`) share: the file checks, the
default tolerance, curves cut into chords to an absolute tolerance, and the assembly of an
outline drawing with its report of open ends.
"""

from __future__ import annotations

import os
import warnings

import numpy as np

from ..errors import RegionError, SourceError
from .polygons import outline_geometry

RELATIVE_TOLERANCE = 1e-4
"""Default tolerance of the drawing readers, as a fraction of the drawing's diagonal."""


def checked_file(path, kind: str) -> str:
    """The path of an existing, non-empty drawing file (``kind``: "SVG", "DXF")."""
    name = os.fspath(path)
    if not os.path.isfile(name):
        raise FileNotFoundError(f"no such {kind} file: {name!r}")
    if os.path.getsize(name) == 0:
        raise SourceError(f"the {kind} file {name!r} is empty")
    return name


def default_tolerance(points) -> float:
    """``RELATIVE_TOLERANCE`` times the diagonal of the points' bounding box."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    diagonal = np.linalg.norm(np.ptp(points, axis=0)) if len(points) else 0.0
    if not diagonal > 0:
        raise RegionError("the drawing has zero size: nothing to mesh")
    return RELATIVE_TOLERANCE * diagonal


def steps(bound, tolerance) -> np.ndarray:
    """Parameters in (0, 1] of the chord ends for a curve with max|B''| <= bound.

    On a parameter interval of length h a chord deviates from the curve by at most
    h² max|B''| / 8, so ``ceil(sqrt(max|B''| / (8 tolerance)))`` uniform intervals suffice.
    """
    count = max(1, int(np.ceil(np.sqrt(bound / (8 * tolerance)))))
    return np.linspace(0, 1, count + 1)[1:]


def elliptic_points(center, radii, start, sweep, tolerance) -> np.ndarray:
    """Points ``center + u cos θ + v sin θ``, θ from ``start`` over ``sweep``, within
    ``tolerance`` of the curve; the first point is the start.

    ``radii`` holds two conjugate radii u, v as columns: any affine image of a circular
    or elliptical arc is exactly of this form. The chordal bound of :func:`steps` applies
    with max|B''| = ||[u v]||₂ sweep².

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
    theta = start + sweep * np.r_[0.0, steps(np.linalg.norm(radii, 2) * sweep**2, tolerance)]
    return np.asarray(center, dtype=float) + np.column_stack(
        [np.cos(theta), np.sin(theta)]) @ radii.T


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
        If no loop closes (the message gives the open ends).
    """
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
