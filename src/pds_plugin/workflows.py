"""Workflows for library users: from a source through the pipeline to a sink in one call.

- :func:`add_section_meshes`: cut the current mesh of a MeshLab ``MeshSet`` (a closed
  solid) with one or several planes and add a certified mesh of each section to the same
  MeshSet.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from .errors import ArgumentError, ArgumentTypeError, SourceError
from .mesh import PlanarMesh
from .pipeline import mesh_region
from .region import plane_label
from .sinks.meshlab import meshlab_mesh
from .sources.solids import section, sections

if TYPE_CHECKING:
    import pymeshlab
    import trimesh

__all__ = ["SectionMesh", "add_section_meshes"]


@dataclass(frozen=True)
class SectionMesh:
    """One section added to a MeshSet by :func:`add_section_meshes`.

    Attributes
    ----------
    mesh_id : int
        Its id in the MeshSet.
    name : str
        Its name there, e.g. ``"section z=0.5 alpha=0.1"``.
    mesh : PlanarMesh
        The mesh in 2D, with its region, certificate and quality.
    """

    mesh_id: int
    name: str
    mesh: PlanarMesh


def add_section_meshes(meshset: pymeshlab.MeshSet, alpha: float, *, plane_normal=(0.0, 0.0, 1.0),
                       plane_origin=None, offsets=None, count=None, seed: int = 0,
                       mesh_id: int | None = None) -> list[SectionMesh]:
    """Cut a solid of ``meshset`` with planes and add a mesh of each section to it.

    The solid is the current mesh (or mesh ``mesh_id``), a closed triangle mesh, taken in
    its transformed (world) position. Give ``plane_origin`` alone for one plane through
    that point, or ``offsets`` (signed distances along the unit normal from
    ``plane_origin``, the world origin by default) or ``count`` (that many evenly spaced
    planes strictly inside the solid) for several parallel planes, as
    :func:`pds_plugin.sections`. Each section is meshed with
    :func:`pds_plugin.mesh_region` at radius ``alpha`` and added as a new mesh named like
    ``"section z=0.5 alpha=0.1"``, with face quality = aspect ratio and vertex quality =
    1.0 on boundary samples (as :func:`pds_plugin.sinks.meshlab.to_meshset`). The solid
    stays the current mesh, so calls can be repeated with other planes.

    Parameters
    ----------
    meshset : pymeshlab.MeshSet
    alpha : float
        The radius of every section's mesh.
    plane_normal : (3,) array_like
    plane_origin : (3,) array_like, optional
    offsets : sequence of float, optional
    count : int, optional
    seed : int
    mesh_id : int, optional
        The solid's id in the MeshSet; its current mesh by default.

    Returns
    -------
    list of SectionMesh
        The new mesh ids, their names and the PlanarMeshes, one per plane.

    Raises
    ------
    PdsError
        If the MeshSet is empty, the solid has no faces, the plane arguments are missing
        or contradictory, a plane misses the solid, lies on a face or cuts an open part of
        it (see :func:`pds_plugin.section`), or a section mesh has no triangles.

    Examples
    --------
    >>> import pymeshlab, trimesh
    >>> box = trimesh.creation.box(extents=(2, 1, 1))
    >>> ms = pymeshlab.MeshSet()
    >>> ms.add_mesh(pymeshlab.Mesh(box.vertices, box.faces), "box")
    >>> added = add_section_meshes(ms, 0.1, plane_normal=(0, 0, 1), count=3)
    >>> [s.name for s in added]
    ['section z=-0.333333 alpha=0.1', 'section z=0 alpha=0.1', 'section z=0.333333 alpha=0.1']
    >>> ms.mesh_number(), ms.current_mesh().label()
    (4, 'box')
    """
    solid_id = _solid_id(meshset, mesh_id)
    if plane_origin is None and offsets is None and count is None:
        raise ArgumentError("say where to cut: plane_origin=(x, y, z) for one plane, or "
                         "offsets=[...] / count=N for several planes along plane_normal")
    solid = _solid_trimesh(meshset, solid_id)
    if offsets is None and count is None:
        regions = [section(solid, plane_origin=plane_origin, plane_normal=plane_normal)]
    else:
        regions = sections(solid, plane_normal=plane_normal, offsets=offsets, count=count,
                           plane_origin=plane_origin)
    meshes = [mesh_region(region, alpha, seed=seed) for region in regions]
    layers = [meshlab_mesh(mesh) for mesh in meshes]  # all checked before the MeshSet changes
    added = []
    for mesh, layer in zip(meshes, layers):
        name = f"section {plane_label(mesh.region.frame)} alpha={mesh.alpha:.6g}"
        meshset.add_mesh(layer, name)
        added.append(SectionMesh(meshset.current_mesh_id(), name, mesh))
    meshset.set_current_mesh(solid_id)
    return added


def _solid_id(meshset, mesh_id) -> int:
    if not hasattr(meshset, "mesh_number"):
        raise ArgumentTypeError(f"add_section_meshes needs a pymeshlab.MeshSet, got "
                                f"{type(meshset).__name__}")
    if meshset.mesh_number() == 0:
        raise ArgumentError("the MeshSet is empty: load a solid first (ms.load_new_mesh(path))")
    if mesh_id is None:
        return meshset.current_mesh_id()
    if not meshset.mesh_id_exists(mesh_id):
        raise ArgumentError(f"the MeshSet has no mesh with id {mesh_id}")
    return int(mesh_id)


def _solid_trimesh(meshset, mesh_id) -> trimesh.Trimesh:
    import trimesh

    solid = meshset.mesh(mesh_id)
    if solid.face_number() == 0:
        raise SourceError(f"mesh {mesh_id} ({solid.label()!r}) of the MeshSet has no faces: "
                         "a section needs a closed triangle mesh, not a point cloud")
    # merge the duplicated vertices of STL-like soups so the solid is watertight
    return trimesh.Trimesh(solid.transformed_vertex_matrix(), solid.face_matrix())
