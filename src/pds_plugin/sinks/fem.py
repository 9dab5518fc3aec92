"""Sink to finite-element codes: meshio meshes and files, scikit-fem meshes, with tags.

A mesh goes out in its region's 2D coordinates (the plane the problem is solved in;
``region.frame`` lifts it to 3D), linear (``order=1``: ``triangle`` and ``line`` cells)
or quadratic (``order=2``: ``triangle6`` and ``line3``, boundary nodes on the true
curves, see :mod:`pds_plugin.quadratic`). The triangles carry their region tag and the
boundary edges their boundary tag (:mod:`pds_plugin.tags`), named in gmsh's
physical-group convention: ``field_data[name] = [tag, dimension]``, 2 for regions and 1
for boundaries. meshio and scikit-fem come with the ``fem`` extra.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .._checks import check_has_triangles, import_optional
from ..errors import ArgumentError

if TYPE_CHECKING:
    import meshio
    import skfem

    from ..mesh import PlanarMesh

__all__ = ["to_meshio", "to_skfem", "write_meshio", "write_dolfinx", "MESHIO_SUFFIXES"]

MESHIO_SUFFIXES = (".msh", ".vtu", ".vtk", ".xdmf", ".xmf", ".inp", ".mesh", ".meshb",
                   ".bdf", ".nas", ".fem", ".mdpa", ".vol")
"""Suffixes :func:`pds_plugin.sinks.files.export` writes through meshio (PLY, OBJ, STL
and OFF keep their own writers): the formats meshio 5.3 writes and reads back with
both kinds of cells and no further library (its SU2, AVS, Tecplot, UGRID and FLAC3D
writers fail on a mesh of triangles and lines; MED, H5M, CGNS and Exodus need h5py or
netCDF4)."""

_FORMAT = {".msh": "gmsh22"}
"""meshio's format where the suffix is ambiguous or its default loses the tags: gmsh 2.2
keeps the physical groups of lines and triangles without gmsh's own entity records."""


def _order(order) -> int:
    if isinstance(order, (bool, np.bool_)) or order not in (1, 2):
        raise ArgumentError(f"order must be 1 (linear triangles) or 2 (quadratic), got {order!r}")
    return int(order)


def _tagged(mesh: PlanarMesh, order: int, boundary: str):
    """Points, triangles, lines, and the tags of both, for ``order``: the lines are the
    boundary edges, then a composite mesh's interface edges (tagged after the boundary
    tags, named ``"a|b"``, :class:`pds_plugin.partition.CompositeMesh`)."""
    from ..tags import Tags, boundary_tags

    check_has_triangles(mesh, "for finite elements")
    if order == 1:
        points, triangles, lines = mesh.vertices, mesh.faces, mesh.boundary_edges
    else:
        q = mesh.quadratic()
        points, triangles, lines = q.points, q.triangles, q.boundary_lines
    regions = mesh.region_tags
    boundaries = mesh.boundary_tags if boundary == "ring" else boundary_tags(mesh, boundary)
    interfaces = getattr(mesh, "interface_edges", None)
    if interfaces is not None and len(interfaces):
        if order == 2:                # the mid node of each edge, in the order of mesh.edges
            count = len(mesh.vertices)
            keys = np.sort(mesh.edges, axis=1) @ np.array([count, 1])
            order_keys = np.argsort(keys)
            wanted = np.sort(interfaces, axis=1) @ np.array([count, 1])
            edge = order_keys[np.searchsorted(keys, wanted, sorter=order_keys)]
            interfaces = np.column_stack([interfaces, count + edge])
        offset = max(boundaries.names.values(), default=0)
        tags = mesh.interface_tags
        lines = np.concatenate([lines, interfaces])
        boundaries = Tags(np.concatenate([boundaries.values, tags.values + offset]),
                          {**boundaries.names,
                           **{name: tag + offset for name, tag in tags.names.items()}})
    return points, triangles, lines, regions, boundaries


def to_meshio(mesh: PlanarMesh, order: int = 1, boundary: str = "ring") -> meshio.Mesh:
    """The mesh as a ``meshio.Mesh`` with region and boundary tags.

    Parameters
    ----------
    mesh : PlanarMesh
    order : {1, 2}
        Linear cells ``triangle`` and ``line``, or quadratic ``triangle6`` and ``line3``.
    boundary : {"ring", "source"}
        How boundary edges are tagged (:func:`pds_plugin.tags.boundary_tags`).

    Returns
    -------
    meshio.Mesh
        ``points`` (2D), cells ``[triangles, lines]``: the lines are the boundary
        edges, then a composite mesh's interface edges (:func:`pds_plugin.mesh_regions`);
        cell data ``"region"`` (a line's is its triangle's, an interface's the first
        side's) and ``"boundary"`` (0 on triangles; interfaces numbered after the
        boundaries, named ``"a|b"``); ``field_data`` ``{name: [tag, dimension]}``.

    Raises
    ------
    MissingDependencyError
        If meshio is not installed (``pip install "pds_plugin[fem]"``).
    ArgumentError
        If ``order`` is not 1 or 2, or ``boundary`` is not a way of tagging.
    EmptyMeshError
        If the mesh has no triangles.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> plate = pds.Region.from_shapely(box(0, 0, 2, 1).difference(box(0.5, 0.25, 1, 0.75)))
    >>> m = to_meshio(pds.mesh_region(plate, 0.2))
    >>> [block.type for block in m.cells], sorted(m.field_data)
    (['triangle', 'line'], ['component 0', 'hole 0.0', 'outline 0'])
    >>> m.field_data["hole 0.0"].tolist()
    [2, 1]
    """
    meshio = import_optional("meshio", "fem", "meshio meshes and FEM file formats")
    order = _order(order)
    points, triangles, lines, regions, boundaries = _tagged(mesh, order, boundary)
    line_region = regions.values[_face_of(mesh, lines[:, :2])]
    cell_data = {"region": [regions.values, line_region],
                 "boundary": [np.zeros(len(triangles), np.int64), boundaries.values]}
    field_data = {**{name: np.array([tag, 2]) for name, tag in regions.names.items()},
                  **{name: np.array([tag, 1]) for name, tag in boundaries.names.items()}}
    kinds = ("triangle", "line") if order == 1 else ("triangle6", "line3")
    return meshio.Mesh(np.array(points), [(kinds[0], np.array(triangles)),
                                          (kinds[1], np.array(lines))],
                       cell_data=cell_data, field_data=field_data)


def _face_of(mesh: PlanarMesh, edges) -> np.ndarray:
    """The triangle that runs each of ``edges`` (a boundary edge, or an interface edge in
    its chain's direction) the way it is given, else the other way."""
    faces, count = mesh.faces, len(mesh.vertices)
    directed = np.stack([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]], axis=1)
    keys = (directed[..., 0] * count + directed[..., 1]).ravel()
    order = np.argsort(keys)

    def find(wanted):
        at = np.minimum(np.searchsorted(keys, wanted, sorter=order), len(keys) - 1)
        return order[at], keys[order[at]] == wanted

    found, ok = find(edges[:, 0] * count + edges[:, 1])
    back, _ = find(edges[:, 1] * count + edges[:, 0])
    return np.where(ok, found, back) // 3


def write_meshio(mesh: PlanarMesh, path, suffix: str) -> None:
    """Write ``mesh`` (linear, tagged) through meshio in the format of ``suffix``.

    The tags go where the format keeps them: as cell data ``region`` and ``boundary``
    (VTU, VTK, XDMF), as gmsh physical groups with their names (``.msh``, gmsh 2.2), as
    Abaqus element sets named after the tags (``.inp``, spaces and ``|`` made
    underscores; meshio types the elements ``R3D3`` and ``B31H``, retype them for your
    analysis). XDMF is written with its data inline (XML), in one file. A composite
    mesh's interface edges go out as lines with their tags (:func:`to_meshio`).

    Parameters
    ----------
    mesh : PlanarMesh
    path : str or os.PathLike
    suffix : str
        One of :data:`MESHIO_SUFFIXES`.

    Examples
    --------
    >>> import pathlib, tempfile, meshio, pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.25)
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "square.vtu"
    >>> write_meshio(mesh, out, ".vtu")
    >>> len(meshio.read(out).cells_dict["triangle"]) == len(mesh.faces)
    True
    """
    meshio = import_optional("meshio", "fem", f"writing {suffix} files")
    tagged = to_meshio(mesh)
    # XDMF's data inline: one self-contained file, written atomically, without h5py
    options = {"data_format": "XML"} if suffix in (".xdmf", ".xmf") else {}
    physical = [tagged.cell_data["region"][0], tagged.cell_data["boundary"][1]]
    if suffix == ".msh":                       # the tags as gmsh's physical groups
        tagged.cell_data = {"gmsh:physical": physical, "gmsh:geometrical": physical}
    elif suffix == ".inp":                     # Abaqus: the tags as element sets
        tagged = meshio.Mesh(tagged.points, tagged.cells, cell_sets=_element_sets(tagged))
    if suffix in (".vtu", ".vtk", ".inp"):     # 3D points (z = 0), as these formats want
        tagged.points = np.column_stack([tagged.points, np.zeros(len(tagged.points))])
    file_format = _FORMAT.get(suffix) or meshio._helpers.extension_to_filetypes[suffix][0]
    meshio.write(path, tagged, file_format=file_format, **options)


def write_dolfinx(mesh: PlanarMesh, path, order: int = 1, boundary: str = "ring"):
    """Write ``mesh`` as the two XDMF files dolfinx reads: the triangles with their region
    tags, and the boundary lines with their boundary tags.

    dolfinx reads one cell type per XDMF grid, and its mesh tags from a grid of the cells
    they tag, so the triangles go to ``path`` and the boundary lines to ``path`` with
    ``_facets`` before the suffix. Each file holds one grid named ``"Grid"`` (meshio's
    name, which dolfinx's ``read_mesh`` and ``read_meshtags`` take as ``name=``) with the
    2D points, its cells (``triangle`` / ``line``, or ``triangle6`` / ``line3`` for
    ``order=2``) and one integer attribute (``region`` / ``boundary``); the arrays go in
    an HDF5 file beside each, as dolfinx wants them (meshio with h5py, both in the
    ``fem`` extra). docs/fem.md shows the dolfinx side.

    Parameters
    ----------
    mesh : PlanarMesh
    path : str or os.PathLike
        The triangles' file, ending in ``.xdmf``.
    order : {1, 2}
    boundary : {"ring", "source"}
        How boundary edges are tagged (:func:`pds_plugin.tags.boundary_tags`).

    Returns
    -------
    (pathlib.Path, pathlib.Path)
        The triangles' file and the facets' file.

    Raises
    ------
    MissingDependencyError
        If meshio or h5py is not installed (``pip install "pds_plugin[fem]"``).
    ArgumentError
        If ``path`` does not end in ``.xdmf``, or ``order`` or ``boundary`` is not valid.

    Examples
    --------
    >>> import pathlib, tempfile, meshio, pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.25)
    >>> domain, facets = write_dolfinx(mesh, pathlib.Path(tempfile.mkdtemp()) / "square.xdmf")
    >>> facets.name, [block.type for block in meshio.read(facets).cells]
    ('square_facets.xdmf', ['line'])
    """
    from pathlib import Path

    meshio = import_optional("meshio", "fem", "dolfinx's XDMF files")
    import_optional("h5py", "fem", "dolfinx's XDMF files (their HDF5 data)")
    path = Path(path)
    if path.suffix.lower() != ".xdmf":
        raise ArgumentError(f"dolfinx reads .xdmf files; got {str(path)!r}: name it "
                            f"{path.stem}.xdmf")
    tagged = to_meshio(mesh, order, boundary)
    facets = path.with_name(f"{path.stem}_facets{path.suffix}")
    for target, block, name in ((path, 0, "region"), (facets, 1, "boundary")):
        cells = tagged.cells[block]
        meshio.write(target, meshio.Mesh(tagged.points, [(cells.type, cells.data)],
                                         cell_data={name: [tagged.cell_data[name][block]]}),
                     file_format="xdmf")
    return path, facets


def _element_sets(tagged) -> dict:
    """``{name: [triangles, lines]}`` of each tag, spaces and an interface's ``|`` in
    names made underscores (Abaqus names are letters, digits and underscores)."""
    sets = {}
    for name, (tag, dimension) in tagged.field_data.items():
        block = 0 if dimension == 2 else 1
        values = tagged.cell_data["region" if dimension == 2 else "boundary"][block]
        members = [np.zeros(0, np.int64), np.zeros(0, np.int64)]
        members[block] = np.flatnonzero(values == tag)
        sets[name.replace(" ", "_").replace("|", "_")] = members
    return sets


def to_skfem(mesh: PlanarMesh, order: int = 1, boundary: str = "ring") -> skfem.Mesh:
    """The mesh as a scikit-fem ``MeshTri`` (``order=1``) or ``MeshTri2`` (``order=2``,
    boundary nodes on the true curves), with ``boundaries`` and ``subdomains`` named
    after the tags.

    Parameters
    ----------
    mesh : PlanarMesh
    order : {1, 2}
    boundary : {"ring", "source"}
        How boundary facets are named (:func:`pds_plugin.tags.boundary_tags`).

    Returns
    -------
    skfem.MeshTri1 or skfem.MeshTri2
        ``boundaries[name]``: the facet indices of each boundary tag, and of each
        interface of a composite mesh (``"a|b"``, inner facets);
        ``subdomains[name]``: the element indices of each region tag. Only the mesh's
        triangles' vertices are kept (isolated samples would be unknowns of no element).

    Raises
    ------
    MissingDependencyError
        If scikit-fem is not installed (``pip install "pds_plugin[fem]"``).
    ArgumentError
        If ``order`` is not 1 or 2.
    EmptyMeshError
        If the mesh has no triangles.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> plate = pds.Region.from_shapely(box(0, 0, 2, 1).difference(box(0.5, 0.25, 1, 0.75)))
    >>> m = to_skfem(pds.mesh_region(plate, 0.2))
    >>> sorted(m.boundaries), sorted(m.subdomains)
    (['hole 0.0', 'outline 0'], ['component 0'])
    >>> bool(set(m.boundaries["outline 0"]) <= set(m.boundary_facets()))
    True
    """
    skfem = import_optional("skfem", "fem", "scikit-fem meshes")
    order = _order(order)
    points, triangles, lines, regions, boundaries = _tagged(mesh, order, boundary)
    used = np.zeros(len(mesh.vertices), dtype=bool)
    used[mesh.faces.ravel()] = True
    renumber = np.cumsum(used) - 1
    t = np.ascontiguousarray(renumber[mesh.faces].T)
    linear = skfem.MeshTri(np.ascontiguousarray(points[:len(used)][used].T), t)
    facets = linear.facets
    count = linear.p.shape[1]
    keys = np.sort(facets, axis=0).astype(np.int64)         # skfem's may be int32
    keys = keys[0] * count + keys[1]
    ends = np.sort(renumber[lines[:, :2]], axis=1).astype(np.int64)
    order_keys = np.argsort(keys)
    facet = order_keys[np.searchsorted(keys, ends[:, 0] * count + ends[:, 1], sorter=order_keys)]
    named_boundaries = {name: np.sort(facet[boundaries.values == tag])
                        for name, tag in boundaries.names.items()}
    subdomains = {name: np.flatnonzero(regions.values == tag)
                  for name, tag in regions.names.items()}
    if order == 1:
        return skfem.MeshTri(linear.p, linear.t, _boundaries=named_boundaries,
                             _subdomains=subdomains)
    q = mesh.quadratic()
    middle = np.empty((len(keys), 2))
    edge_ends = np.sort(renumber[mesh.edges], axis=1).astype(np.int64)
    edge_keys = edge_ends[:, 0] * count + edge_ends[:, 1]
    middle[order_keys[np.searchsorted(keys, edge_keys, sorter=order_keys)]] = q.points[len(used):]
    doflocs = np.ascontiguousarray(np.hstack([linear.p, middle.T]))
    return skfem.MeshTri2(doflocs, linear.t, _boundaries=named_boundaries,
                          _subdomains=subdomains)
