"""PlanarMesh: the triangle mesh of a region, and mesh_region, which makes it."""

from __future__ import annotations

from functools import cached_property

import numpy as np

from .complex import solid_alpha_complex
from .quality import Quality, triangle_quality
from .region import Region
from .sampling import poisson_disc
from .topology import mesh_edges, mesh_union

__all__ = ["PlanarMesh", "mesh_region"]


class PlanarMesh:
    """A triangle mesh of a :class:`Region`, in the region's 2D coordinates.

    Attributes
    ----------
    vertices : (N, 2) float ndarray
        The Poisson disc samples.
    faces : (M, 3) int ndarray
        Counter-clockwise triangles of the solid alpha-complex.
    on_boundary : (N,) bool ndarray
        True for samples placed on the region's boundary.
    region : Region
    alpha : float
        The radius used for both the sampling and the complex.
    """

    def __init__(self, vertices, faces, on_boundary, region: Region, alpha: float):
        self.vertices = vertices
        self.faces = faces
        self.on_boundary = on_boundary
        self.region = region
        self.alpha = float(alpha)
        for array in (vertices, faces, on_boundary):
            array.setflags(write=False)

    @cached_property
    def vertices_3d(self) -> np.ndarray:
        """(N, 3) vertices in the region's plane in 3D, through ``region.frame``."""
        return self.region.to_3d(self.vertices)

    @cached_property
    def edges(self) -> tuple[np.ndarray, np.ndarray]:
        """``(edges, boundary_edges)``: the undirected edges (E, 2) of the triangles, and
        those used by one triangle only, directed with the mesh on their left."""
        return mesh_edges(self.faces, len(self.vertices))

    @cached_property
    def outline(self):
        """The union of the triangles, as shapely geometry."""
        return mesh_union(self.vertices, self.edges[1])

    def quality(self) -> Quality:
        """Per-triangle aspect ratio L²/A, angles and edge lengths, with ``stats()`` and
        ``histogram()``. Computed once and cached."""
        return self._quality

    @cached_property
    def _quality(self) -> Quality:
        return triangle_quality(self.vertices, self.faces)

    def certificate(self):
        """The measured guarantees of this mesh (see :class:`pds_plugin.Certificate`).

        Computed once and cached.
        """
        return self._certificate

    @cached_property
    def _certificate(self):
        from .certificate import certify
        return certify(self)

    def to_trimesh(self):
        """The mesh in 3D as a ``trimesh.Trimesh``, with face attribute ``aspect_ratio``."""
        from .export import to_trimesh
        return to_trimesh(self)

    def to_meshset(self):
        """A ``pymeshlab.MeshSet`` holding the mesh, face quality = aspect ratio."""
        from .meshlab import to_meshset
        return to_meshset(self)

    def export(self, path) -> None:
        """Write the mesh in 3D: binary PLY with per-face quality, or OBJ, by suffix."""
        from .export import export
        export(self, path)

    def __repr__(self) -> str:
        return (f"PlanarMesh(vertices={len(self.vertices)}, faces={len(self.faces)}, "
                f"alpha={self.alpha:.6g})")


def mesh_region(region: Region, alpha, seed: int = 0, **sampling_options) -> PlanarMesh:
    """Sample ``region`` with a maximal Poisson disc sampling of radius ``alpha`` and
    mesh the samples with the solid alpha-complex of the same radius.

    By Theorem 1 of the paper every triangle then has aspect ratio L²/A ≤ 4√3 (all
    angles in [30°, 120°]); :meth:`PlanarMesh.certificate` measures it. With
    ``alpha="auto"`` the radius comes from the region's feature size and is lowered
    until the mesh has the region's topology (see :func:`pds_plugin.auto_mesh`, which
    takes the same keywords).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> import pds_plugin as pds
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.1, seed=0)
    >>> mesh.certificate().ok
    True
    """
    if isinstance(alpha, str) and alpha == "auto":
        from .feature import auto_mesh
        return auto_mesh(region, seed=seed, **sampling_options)
    samples = poisson_disc(region, alpha, seed=seed, **sampling_options)
    faces = solid_alpha_complex(samples.points, alpha)
    return PlanarMesh(samples.points, faces, samples.on_boundary, region, alpha)
