"""PlanarMesh: the triangle mesh of a region, and its combinatorics.

The mesh owns what is computed from its faces alone (edges, boundary edges, the outline
they bound, connected components and Betti numbers), each once, as named cached
attributes. Its measurements, certificate and writers live in the layers above
(:mod:`pds_plugin.analysis`, :mod:`pds_plugin.sinks`); the methods of the same names
here are the public shortcuts to them (the README's Layout section).
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import shapely
from shapely.geometry import Polygon

from ._mesh_kernels import edges_of, face_components
from ._checks import check_alpha, check_faces
from .errors import ArgumentError
from .region import Region, lift, require_region

if TYPE_CHECKING:
    import meshio
    import pymeshlab
    import skfem
    import trimesh

    from .quadratic import QuadraticMesh
    from .tags import Tags

    from .analysis.certificate import Certificate
    from .analysis.quality import Quality

__all__ = ["PlanarMesh", "mesh_edges", "mesh_betti", "mesh_union"]


class PlanarMesh:
    """A triangle mesh of a :class:`Region`, in the region's 2D coordinates.

    The arrays are copies of those given (the caller's stay as they were), read-only.

    Parameters
    ----------
    vertices : (N, 2) array_like of float
    faces : (M, 3) array_like of int
    on_boundary : (N,) array_like of bool
    region : Region
    alpha : float
    conforming : bool, optional
    field : RadiusField, optional
        Graded meshes: the radius field r the mesh was made with (docs/graded.md).

    Raises
    ------
    ArgumentError
        If a face refers to a vertex that does not exist, ``on_boundary`` has not one
        flag per vertex, or ``alpha`` is not a positive finite number.
    ArgumentTypeError
        If ``region`` is not a :class:`Region`.

    Attributes
    ----------
    vertices : (N, 2) float ndarray
        The Poisson disc samples.
    faces : (M, 3) int64 ndarray
        Counter-clockwise triangles of the solid alpha-complex.
    on_boundary : (N,) bool ndarray
        True for samples placed on the region's boundary.
    region : Region
        The region the mesh was made of.
    alpha : float
        The radius used for both the sampling and the complex.
    field : RadiusField or None
        Graded meshes: the radius field r(x) <= alpha the mesh was made with; its
        certificate then measures against r (:mod:`pds_plugin.analysis.graded_certificate`).
        None for uniform meshes.
    conforming : bool
        True when the mesh was made to conform to the region's boundary (consecutive
        boundary samples joined by edges, no triangle leaving the region); its certificate
        then holds it to that.

    Examples
    --------
    >>> import numpy as np
    >>> from shapely.geometry import box
    >>> square = Region.from_shapely(box(0, 0, 1, 1))
    >>> corners = [[0, 0], [1, 0], [1, 1], [0, 1]]
    >>> mesh = PlanarMesh(corners, [[0, 1, 2], [0, 2, 3]], [True] * 4, square, 0.75)
    >>> mesh.edges.tolist(), mesh.boundary_edges.tolist()
    ([[0, 1], [2, 0], [3, 0], [1, 2], [2, 3]], [[0, 1], [3, 0], [1, 2], [2, 3]])
    >>> mesh.betti, mesh.outline.area
    ((1, 0), 1.0)
    """

    def __init__(self, vertices, faces, on_boundary, region: Region, alpha: float,
                 conforming: bool = False, *, field=None):
        self.vertices = np.array(vertices, dtype=float).reshape(-1, 2)
        self.faces = check_faces(faces, len(self.vertices))
        self.on_boundary = np.array(on_boundary, dtype=bool).reshape(-1)
        if len(self.on_boundary) != len(self.vertices):
            raise ArgumentError(f"on_boundary has {len(self.on_boundary)} flags for "
                                f"{len(self.vertices)} vertices; give one per vertex")
        self.region = require_region(region, "PlanarMesh")
        self.alpha = check_alpha(alpha)
        self.conforming = bool(conforming)
        self.field = field
        for array in (self.vertices, self.faces, self.on_boundary):
            array.setflags(write=False)

    @classmethod
    def _made(cls, vertices, faces, on_boundary, region: Region, alpha: float,
              conforming: bool, field=None) -> "PlanarMesh":
        """A mesh of new arrays made by this package, valid by construction ((N, 2)
        float, (M, 3) int64 indices into them, (N,) bool), taken as they are: the
        constructor without its checks and copies (a remesh makes hundreds of small
        patch meshes, 23 µs each through ``__init__``)."""
        mesh = cls.__new__(cls)
        mesh.vertices, mesh.faces, mesh.on_boundary = vertices, faces, on_boundary
        mesh.region, mesh.alpha, mesh.conforming, mesh.field = region, alpha, conforming, field
        for array in (vertices, faces, on_boundary):
            array.setflags(write=False)
        return mesh

    @cached_property
    def vertices_3d(self) -> np.ndarray:
        """(N, 3) vertices in the region's plane in 3D, through ``region.frame``."""
        return lift(self.vertices, self.region.frame)

    @cached_property
    def _edges(self) -> tuple[np.ndarray, np.ndarray]:
        return mesh_edges(self.faces, len(self.vertices))

    @property
    def edges(self) -> np.ndarray:
        """(E, 2) int64: the undirected edges of the triangles, each once."""
        return self._edges[0]

    @property
    def boundary_edges(self) -> np.ndarray:
        """(B, 2) int64: the edges used by one triangle only, directed as in that triangle
        (so the mesh lies on their left)."""
        return self._edges[1]

    @cached_property
    def outline(self):
        """The union of the triangles, as shapely geometry (from :attr:`boundary_edges`)."""
        return mesh_union(self.vertices, self.boundary_edges)

    @cached_property
    def _components(self) -> tuple[np.ndarray, np.ndarray]:
        return mesh_betti(self.faces, len(self.vertices), self.edges)

    @property
    def vertex_component(self) -> np.ndarray:
        """(N,) int64: the mesh component (triangles joined through shared vertices) of
        each vertex, -1 for a vertex in no triangle."""
        return self._components[0]

    @property
    def component_betti(self) -> np.ndarray:
        """(C, 2) int64: ``(b0, b1)`` of each mesh component, so ``b0`` is 1."""
        return self._components[1]

    @property
    def betti(self) -> tuple[int, int]:
        """``(b0, b1)`` of the whole mesh: its components and its holes."""
        per_component = self.component_betti
        return (len(per_component), int(per_component[:, 1].sum()) if len(per_component) else 0)

    def quality(self) -> Quality:
        """Per-triangle aspect ratio L²/A, angles and edge lengths, with ``stats()`` and
        ``histogram()`` (see :func:`pds_plugin.triangle_quality`). Computed once.

        Returns
        -------
        Quality

        Examples
        --------
        >>> import pds_plugin as pds
        >>> from shapely.geometry import box
        >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2)
        >>> mesh.quality().stats()["above_bound"], mesh.quality() is mesh.quality()
        (0, True)
        """
        return self._quality

    @cached_property
    def _quality(self) -> Quality:
        from .analysis.quality import triangle_quality
        return triangle_quality(self.vertices, self.faces)

    def certificate(self) -> Certificate:
        """The measured guarantees of this mesh (see :func:`pds_plugin.certify`).
        Computed once.

        Returns
        -------
        Certificate

        Examples
        --------
        >>> import pds_plugin as pds
        >>> from shapely.geometry import box
        >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2)
        >>> mesh.certificate().ok
        True
        """
        return self._certificate

    @cached_property
    def _certificate(self) -> Certificate:
        if self.field is not None:
            from .analysis.graded_certificate import certify_graded
            return certify_graded(self)
        from .analysis.certificate import certify
        return certify(self)

    def to_trimesh(self) -> trimesh.Trimesh:
        """The mesh in 3D as a ``trimesh.Trimesh`` (see :func:`pds_plugin.sinks.files.to_trimesh`).

        Returns
        -------
        trimesh.Trimesh
            With face attribute ``aspect_ratio`` and vertex attribute ``on_boundary``.

        Examples
        --------
        >>> import pds_plugin as pds
        >>> from shapely.geometry import box
        >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2)
        >>> round(float(mesh.to_trimesh().area), 12)
        1.0
        """
        from .sinks.files import to_trimesh
        return to_trimesh(self)

    def to_meshset(self) -> pymeshlab.MeshSet:
        """A ``pymeshlab.MeshSet`` holding the mesh (see :func:`pds_plugin.sinks.meshlab.to_meshset`).

        Returns
        -------
        pymeshlab.MeshSet
            Face quality = aspect ratio, vertex quality = 1.0 on boundary samples.

        Examples
        --------
        >>> import pds_plugin as pds
        >>> from shapely.geometry import box
        >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2)
        >>> meshset = mesh.to_meshset()
        >>> meshset.current_mesh().vertex_number() == len(mesh.vertices)
        True
        """
        from .sinks.meshlab import to_meshset
        return to_meshset(self)

    def export(self, path) -> None:
        """Write the mesh by suffix: in 3D as binary PLY with per-face quality, or OBJ; in
        2D with its tags through meshio (``.msh``, ``.vtu``, ``.xdmf``, ``.inp``...) (see
        :func:`pds_plugin.sinks.files.export`).

        Parameters
        ----------
        path : str or os.PathLike
            Ends in a registered suffix (``.ply``, ``.obj``, ``.msh``...).

        Examples
        --------
        >>> import pathlib, tempfile, pds_plugin as pds
        >>> from shapely.geometry import box
        >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2)
        >>> out = pathlib.Path(tempfile.mkdtemp()) / "square.obj"
        >>> mesh.export(out)
        >>> out.read_text().splitlines()[0]
        '# pds_plugin mesh, alpha 0.2'
        """
        from .sinks.files import export
        export(self, path)

    # --- finite elements (docs/fem.md) ----------------------------------------------

    @cached_property
    def region_tags(self) -> Tags:
        """The region component of each triangle, named (see :mod:`pds_plugin.tags`)."""
        from .tags import region_tags
        return region_tags(self)

    @cached_property
    def boundary_tags(self) -> Tags:
        """The ring of each of :attr:`boundary_edges`, named ``"outline c"`` or
        ``"hole c.h"``; 0 for none (see :mod:`pds_plugin.tags`)."""
        from .tags import boundary_tags
        return boundary_tags(self)

    def quadratic(self) -> QuadraticMesh:
        """The 6-node triangles of this mesh, boundary nodes on the true curves, with each
        curved triangle's Jacobian checked (see :func:`pds_plugin.quadratic.quadratic`).
        Computed once.

        Returns
        -------
        QuadraticMesh
        """
        return self._quadratic

    @cached_property
    def _quadratic(self) -> QuadraticMesh:
        from .quadratic import quadratic
        return quadratic(self)

    def to_meshio(self, order: int = 1, boundary: str = "ring") -> meshio.Mesh:
        """A tagged ``meshio.Mesh``, linear or quadratic (see
        :func:`pds_plugin.sinks.fem.to_meshio`; needs the ``fem`` extra).

        Returns
        -------
        meshio.Mesh
        """
        from .sinks.fem import to_meshio
        return to_meshio(self, order, boundary)

    def to_skfem(self, order: int = 1, boundary: str = "ring") -> skfem.Mesh:
        """A scikit-fem ``MeshTri`` (or ``MeshTri2``) with named boundaries and subdomains
        (see :func:`pds_plugin.sinks.fem.to_skfem`; needs the ``fem`` extra).

        Returns
        -------
        skfem.MeshTri1 or skfem.MeshTri2
        """
        from .sinks.fem import to_skfem
        return to_skfem(self, order, boundary)

    def __repr__(self) -> str:
        return (f"PlanarMesh(vertices={len(self.vertices)}, faces={len(self.faces)}, "
                f"alpha={self.alpha:.6g})")


def mesh_edges(faces, n_vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """The undirected edges of triangles, and their boundary edges.

    Parameters
    ----------
    faces : (M, 3) array_like of int
    n_vertices : int

    Returns
    -------
    edges : (E, 2) int64 ndarray
        Each undirected edge once (grouped by smaller vertex; directed as in one of its
        triangles).
    boundary_edges : (B, 2) int64 ndarray
        The edges used by one triangle only, directed as in that triangle, so the mesh
        lies on their left.

    Examples
    --------
    >>> edges, boundary = mesh_edges([[0, 1, 2]], 3)
    >>> edges.tolist(), boundary.tolist()
    ([[0, 1], [2, 0], [1, 2]], [[0, 1], [2, 0], [1, 2]])
    """
    edges, uses = edges_of(np.asarray(faces, dtype=np.int64).reshape(-1, 3), n_vertices)
    return edges, edges[uses == 1]


def mesh_betti(faces, n_vertices: int, edges: np.ndarray | None = None):
    """Component label per vertex (-1 if unused) and ``(b0, b1)`` per mesh component.

    Components are triangles joined through shared vertices; ``b1 = b0 - χ`` with
    ``χ = V - E + F`` over the vertices, edges and faces used by triangles.

    Parameters
    ----------
    faces : (M, 3) array_like of int
    n_vertices : int
    edges : (E, 2) ndarray, optional
        The undirected edges of the triangles; found from ``faces`` when not given
        (see :func:`mesh_edges`).

    Returns
    -------
    labels : (n_vertices,) int64 ndarray
    betti : (C, 2) int64 ndarray

    Raises
    ------
    ArgumentError
        If a face refers to a vertex index outside ``0 .. n_vertices - 1``.

    Examples
    --------
    >>> import numpy as np
    >>> square_ring = np.array([[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7],
    ...                         [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    >>> labels, betti = mesh_betti(square_ring, 8)
    >>> betti.tolist()
    [[1, 1]]
    """
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    labels, count = face_components(faces, n_vertices)     # refuses an index past the end
    if edges is None:
        edges = mesh_edges(faces, n_vertices)[0]
    used = labels >= 0
    chi = (np.bincount(labels[used], minlength=count)
           - np.bincount(labels[edges[:, 0]], minlength=count)
           + np.bincount(labels[faces[:, 0]], minlength=count))
    return labels, np.stack([np.ones(count, dtype=np.int64), 1 - chi], axis=1)


def mesh_union(vertices, boundary):
    """The union of the triangles, from their ``boundary`` edges alone (directed with the
    mesh on their left, as :func:`mesh_edges` gives them).

    The boundary edges cut the plane into faces (``shapely.polygonize``); a face is
    covered by the mesh when its counter-clockwise exterior runs along a boundary edge in
    that edge's own direction (the mesh lies left of its boundary edges).

    Parameters
    ----------
    vertices : (N, 2) ndarray
    boundary : (B, 2) int ndarray
        Directed boundary edges.

    Returns
    -------
    shapely Polygon or MultiPolygon (empty without boundary edges)

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> mesh_union(square, np.array([[0, 1], [1, 2], [2, 3], [3, 0]])).area
    1.0
    """
    if not len(boundary):
        return Polygon()
    pieces = shapely.get_parts(shapely.polygonize(shapely.linestrings(vertices[boundary])))
    pieces = shapely.orient_polygons(pieces)
    first = shapely.get_coordinates(shapely.get_exterior_ring(pieces), return_index=True)
    starts = np.flatnonzero(np.diff(first[1], prepend=-1))
    begin, end = first[0][starts], first[0][starts + 1]
    edges = np.concatenate([vertices[boundary].reshape(-1, 4), np.hstack([begin, end])])
    _, same = np.unique(edges, axis=0, return_inverse=True)
    covered = np.isin(same[len(boundary):], same[:len(boundary)])
    return shapely.union_all(pieces[covered])

