"""Section backend for ``manifold3d.Manifold`` solids.

The solid is moved so that the plane becomes z = 0 (in float64) and sliced there with
``Manifold.slice``; used through :func:`pds_plugin.section`, which shares the plane checks
and the assembly of the cut curves with the trimesh backend (:mod:`pds_plugin.sources`).
"""

from __future__ import annotations

import numpy as np


def load(manifold):
    """Check that the Manifold is valid and not empty, and return it.

    Raises
    ------
    ValueError
        If ``manifold.status()`` reports an error (e.g. it was built from a mesh that is
        not a closed manifold) or the solid is empty.
    """
    import manifold3d

    status = manifold.status()
    if status != manifold3d.Error.NoError:
        raise ValueError(f"the Manifold is invalid (status {status.name}): it was built from a "
                         f"mesh that is not a closed, oriented 2-manifold; repair the mesh "
                         f"(e.g. with trimesh.repair or MeshLab) before making the Manifold")
    if manifold.is_empty():
        raise ValueError("the Manifold is empty: there is no solid to cut")
    return manifold


def arrays(manifold) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) float64 and faces (m, 3) int of the solid, via ``Mesh64``."""
    mesh = manifold.to_mesh64()
    return np.asarray(mesh.vert_properties[:, :3], dtype=np.float64), np.asarray(mesh.tri_verts)


def cut(manifold, origin, normal, to_2d) -> list[np.ndarray]:
    """The closed contours of the section, as chains in the plane's 2D frame."""
    contours = manifold.transform(to_2d[:3, :]).slice(0.0).to_polygons()
    return [np.vstack([ring, ring[:1]]) for ring in map(np.asarray, contours) if len(ring)]
