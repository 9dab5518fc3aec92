"""Section backend for ``trimesh.Trimesh`` solids and mesh files (STL, OBJ, PLY, OFF, 3MF, GLB).

Used through :func:`pds_plugin.section`; the plane checks and the assembly of the cut
segments into polygons are shared with the manifold3d backend (:mod:`pds_plugin.sources`).
"""

from __future__ import annotations

import os

import numpy as np


def load(solid):
    """The ``trimesh.Trimesh`` to cut: ``solid`` itself, or the mesh read from a file.

    Raises
    ------
    FileNotFoundError
        If the path does not exist.
    ValueError
        If the file is empty or holds no triangles trimesh can read, or the mesh has none.
    """
    import trimesh

    if isinstance(solid, trimesh.Trimesh):
        mesh, name = solid, "the mesh"
    else:
        path = os.fspath(solid)
        if not os.path.isfile(path):
            raise FileNotFoundError(f"no such mesh file: {path!r}")
        if os.path.getsize(path) == 0:
            raise ValueError(f"the mesh file {path!r} is empty")
        try:
            mesh = trimesh.load_mesh(path)
        except Exception as error:  # trimesh raises many kinds for unreadable files
            raise ValueError(f"cannot read {path!r} as a mesh ({error}); give a file trimesh "
                             f"reads: STL, OBJ, PLY, OFF, 3MF or GLB") from error
        name = f"the file {path!r}"
    if len(mesh.faces) == 0:
        raise ValueError(f"{name} has no triangles (it is empty, a point cloud, or not a mesh "
                         f"format trimesh reads); give a closed triangle mesh")
    return mesh


def arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) float64 and faces (m, 3) int of the mesh."""
    return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces)


def cut(mesh, origin, normal, to_2d) -> list[np.ndarray]:
    """The segments where the plane cuts the mesh, as (2, 2) chains in the plane's 2D frame."""
    from trimesh.intersections import mesh_plane

    lines = mesh_plane(mesh, plane_normal=normal, plane_origin=origin)
    xy = np.asarray(lines, dtype=np.float64).reshape(-1, 3) @ to_2d[:2, :3].T + to_2d[:2, 3]
    return list(xy.reshape(-1, 2, 2))
