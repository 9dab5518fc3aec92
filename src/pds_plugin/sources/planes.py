"""The cutting plane, shared by the mesh (:mod:`.solids`) and B-rep (:mod:`.step`)
sections: its checks, and the 2D frame of a plane that both give their regions, so one
plane gives the same 2D coordinates whatever the solid comes from."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .._checks import check_vector
from ..errors import ArgumentError
from ..region import lift

__all__ = ["checked_plane", "plane_frames", "checked_on_face", "places_in_3d"]


def checked_plane(origin, normal) -> tuple[np.ndarray, np.ndarray]:
    """Validated plane origin and unit normal, as float64 (3,) arrays.

    Examples
    --------
    >>> checked_plane((0, 0, 1), (0, 0, 2))[1].tolist()
    [0.0, 0.0, 1.0]
    """
    origin, normal = check_vector(origin, "plane_origin"), check_vector(normal, "plane_normal")
    length = np.linalg.norm(normal)
    if not length > 0:
        raise ArgumentError("plane_normal is the zero vector; give the direction the plane "
                         "faces, e.g. (0, 0, 1)")
    return origin, normal / length


def plane_frames(origin, normal) -> tuple[np.ndarray, np.ndarray]:
    """``to_2d`` (trimesh's plane_transform: the plane onto z = 0, bit for bit) and its
    exact inverse.

    Examples
    --------
    >>> to_2d, to_3d = plane_frames(np.array([0.0, 0.0, 5.0]), np.array([0.0, 0.0, 1.0]))
    >>> bool(np.allclose(to_3d @ to_2d, np.eye(4)))
    True
    """
    to_2d = _rotation(np.asarray(normal, dtype=float).tobytes()).copy()
    to_2d[:3, 3] = -np.dot(to_2d, np.append(origin, 1))[:3]    # as plane_transform does
    to_3d = np.eye(4)
    to_3d[:3, :3] = to_2d[:3, :3].T   # a rotation: its inverse is its transpose
    to_3d[:3, 3] = origin             # (0, 0) is the plane origin
    return to_2d, to_3d


@lru_cache(maxsize=64)
def _rotation(normal: bytes) -> np.ndarray:
    """trimesh's ``align_vectors(normal, [0, 0, 1])`` (two SVDs, 0.1 ms), once per normal:
    parallel planes (``pds.sections``, a part cut in turn) share it. Not to be changed."""
    from trimesh.geometry import align_vectors

    rotation = align_vectors(np.frombuffer(normal), [0, 0, 1])
    rotation.flags.writeable = False
    return rotation


def checked_on_face(on_face):
    """``on_face`` itself if it is None, "above" or "below".

    Examples
    --------
    >>> checked_on_face("beside")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentError: on_face must be None, 'above' or 'below', got 'beside'
    """
    if on_face not in (None, "above", "below"):
        raise ArgumentError(f"on_face must be None, 'above' or 'below', got {on_face!r}")
    return on_face


def places_in_3d(points, to_3d, most: int = 5) -> str:
    """The first ``most`` plane points, lifted into 3D, for a message (open ends of a cut).

    Examples
    --------
    >>> places_in_3d([[1, 2], [3, 4]], np.eye(4), most=1)
    '(1, 2, 0), ...'
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    where = ", ".join(f"({x:.6g}, {y:.6g}, {z:.6g})" for x, y, z in lift(points[:most], to_3d))
    return where + (", ..." if len(points) > most else "")
