"""Section source for ``manifold3d.Manifold`` solids.

The solid is read through ``Manifold.to_mesh64`` (float64) and cut by the same exact
plane-edge intersections as a trimesh solid (:mod:`pds_plugin.sources.trimesh`), so one
plane gives the same region, bit for bit, with either library. ``Manifold.slice`` is not
used: in manifold3d 3.5 its contours come back rounded to float32 (a unit cube moved by
0.2 slices at 0.2000000029802322), and it returns a face lying on the plane at the bottom
of a solid but not at its top.
"""

from __future__ import annotations

import numpy as np

from ..errors import SourceError


def load(manifold):
    """The solid as a ``trimesh.Trimesh`` with float64 vertices, after checking it.

    Parameters
    ----------
    manifold : manifold3d.Manifold

    Returns
    -------
    trimesh.Trimesh

    Raises
    ------
    SourceError
        If ``manifold.status()`` reports an error (it was built from a mesh that is not
        a closed, oriented 2-manifold) or the solid is empty.

    Examples
    --------
    >>> import manifold3d
    >>> round(float(load(manifold3d.Manifold.cube((1, 2, 3))).volume), 9)
    6.0
    """
    import manifold3d
    import trimesh

    status = manifold.status()
    if status != manifold3d.Error.NoError:
        raise SourceError(f"the Manifold is invalid (status {status.name}): it was built from a "
                         f"mesh that is not a closed, oriented 2-manifold; repair the mesh "
                         f"(e.g. with trimesh.repair or MeshLab) before making the Manifold")
    if manifold.is_empty():
        raise SourceError("the Manifold is empty: there is no solid to cut")
    mesh = manifold.to_mesh64()
    return trimesh.Trimesh(np.asarray(mesh.vert_properties[:, :3], dtype=np.float64),
                           np.asarray(mesh.tri_verts, dtype=np.int64), process=False)
