"""Sink to files: a PlanarMesh in 3D as a trimesh object or a file (PLY, OBJ, STL, OFF...).

Each file format registers its writer under its suffix with :func:`register_writer`;
:func:`export` only looks the suffix up and writes through a temporary name, so a file
under the final name is always complete. The PLY and OBJ writers are plain numpy and
write the coordinates as 64-bit floats (trimesh's own PLY exporter rounds them to
float32, which moves CAD coordinates of a few hundred millimetres by about 1e-5); the
other formats trimesh writes (STL, OFF, GLB, 3MF) go through :func:`to_trimesh`.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

from .._atomic import atomic_path
from .._checks import check_has_triangles, check_output_directory, check_path
from ..errors import ArgumentError
from .fem import MESHIO_SUFFIXES

if TYPE_CHECKING:
    import trimesh

    from ..mesh import PlanarMesh

__all__ = ["to_trimesh", "export", "register_writer", "writers"]

_WRITERS: dict[str, Callable] = {}


def register_writer(suffix: str):
    """Register ``writer(mesh, path)`` for files ending in ``suffix`` (decorator).

    Parameters
    ----------
    suffix : str
        Like ``".ply"``; case does not matter.

    Returns
    -------
    callable
        The decorator, which registers the writer and returns it unchanged.

    Raises
    ------
    ArgumentError
        If ``suffix`` does not start with a dot.

    Examples
    --------
    >>> @register_writer(".xyz")
    ... def write_xyz(mesh, path):
    ...     np.savetxt(path, mesh.vertices_3d)
    >>> ".xyz" in writers()
    True
    >>> del _WRITERS[".xyz"]
    """
    suffix = suffix.lower()
    if not suffix.startswith("."):
        raise ArgumentError(f"a suffix starts with a dot, like '.ply'; got {suffix!r}")

    def register(writer):
        _WRITERS[suffix] = writer
        return writer
    return register


def writers() -> list[str]:
    """The suffixes :func:`export` can write, sorted.

    Returns
    -------
    list of str

    Examples
    --------
    >>> {".obj", ".ply"} <= set(writers())
    True
    """
    return sorted(_WRITERS)


def to_trimesh(mesh: PlanarMesh) -> trimesh.Trimesh:
    """The mesh in 3D (in its region's plane) as a ``trimesh.Trimesh``.

    Vertices and faces are copied, not processed (no merging, no reordering), so vertex
    ``i`` of the result is sample ``i``. The face attribute ``aspect_ratio`` holds L²/A
    and the vertex attribute ``on_boundary`` marks the boundary samples.

    Parameters
    ----------
    mesh : PlanarMesh

    Returns
    -------
    trimesh.Trimesh

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.2)
    >>> tm = to_trimesh(mesh)
    >>> bool(tm.face_attributes["aspect_ratio"].max() <= 4 * 3 ** 0.5)
    True
    """
    import trimesh

    tm = trimesh.Trimesh(np.array(mesh.vertices_3d), np.array(mesh.faces), process=False)
    tm.face_attributes["aspect_ratio"] = np.array(mesh.quality().aspect_ratio, dtype=float)
    tm.vertex_attributes["on_boundary"] = np.array(mesh.on_boundary, dtype=bool)
    return tm


def export(mesh: PlanarMesh, path) -> None:
    """Write ``mesh`` in 3D to ``path``; the suffix chooses the format.

    - ``.ply``: binary PLY with double coordinates, per-face ``quality`` = aspect ratio
      L²/A and per-vertex ``quality`` = 1.0 on boundary samples, 0.0 inside. MeshLab
      reads both as its face and vertex quality.
    - ``.obj``: the geometry only (OBJ has no per-face scalars), 17 significant digits.
    - ``.stl``, ``.off``, ``.glb``, ``.3mf``: written by trimesh (:func:`to_trimesh`), in
      the precision of the format (STL and GLB store float32).
    - ``.msh`` (gmsh 2.2), ``.vtu``, ``.xdmf``, ``.inp`` (Abaqus) and the other formats
      of :data:`pds_plugin.sinks.fem.MESHIO_SUFFIXES`: in 2D with the region and
      boundary tags, through meshio (the ``fem`` extra; see
      :func:`pds_plugin.sinks.fem.write_meshio`).

    Every sample is written, including isolated ones (not in any triangle), so vertex
    ``i`` of the file is sample ``i`` of the mesh.

    Parameters
    ----------
    mesh : PlanarMesh
    path : str or os.PathLike

    Raises
    ------
    ArgumentError
        For an unsupported suffix.
    EmptyMeshError
        For a mesh without triangles.
    ArgumentTypeError
        If ``path`` is not a file name.
    FileNotFoundError, IsADirectoryError
        If the parent directory of ``path`` does not exist, or ``path`` is a folder.

    Examples
    --------
    >>> import tempfile, pathlib, pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.2)
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "square.ply"
    >>> export(mesh, out)
    >>> out.read_bytes()[:3]
    b'ply'
    """
    path = Path(check_path(path))
    writer = _WRITERS.get(path.suffix.lower())
    if path.is_dir():
        check_output_directory(path)          # "it is a directory", whatever its name
    if writer is None:
        what = f"suffix {path.suffix!r}" if path.suffix else "a path without a suffix"
        raise ArgumentError(f"cannot export to {what} ({path.name}): supported suffixes are "
                            f"{', '.join(writers())}")
    check_output_directory(path)
    check_has_triangles(mesh, "to export")
    with atomic_path(path) as partial:        # never a half-written file under the name
        writer(mesh, partial)


@register_writer(".ply")
def write_ply(mesh: PlanarMesh, path) -> None:
    """Binary little-endian PLY with per-face and per-vertex ``quality`` (see :func:`export`).

    Parameters
    ----------
    mesh : PlanarMesh
    path : str or os.PathLike

    Examples
    --------
    >>> import pathlib, tempfile, trimesh, pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.25)
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "square.ply"
    >>> write_ply(mesh, out)
    >>> len(trimesh.load_mesh(out, process=False).faces) == len(mesh.faces)
    True
    """
    vertices = np.empty(len(mesh.vertices), dtype=[("x", "<f8"), ("y", "<f8"), ("z", "<f8"),
                                                   ("quality", "<f8")])
    xyz = mesh.vertices_3d
    vertices["x"], vertices["y"], vertices["z"] = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    vertices["quality"] = mesh.on_boundary
    faces = np.empty(len(mesh.faces), dtype=[("n", "u1"), ("vertex_indices", "<i4", (3,)),
                                             ("quality", "<f8")])
    faces["n"] = 3
    faces["vertex_indices"] = mesh.faces
    faces["quality"] = mesh.quality().aspect_ratio
    header = "\n".join([
        "ply", "format binary_little_endian 1.0",
        f"comment pds_plugin mesh, alpha {mesh.alpha!r}",
        "comment face quality: aspect ratio L^2/A (4/sqrt(3) equilateral, <= 4*sqrt(3) certified)",
        "comment vertex quality: 1 on boundary samples, 0 inside",
        f"element vertex {len(vertices)}",
        *(f"property double {name}" for name in ("x", "y", "z", "quality")),
        f"element face {len(faces)}",
        "property list uchar int vertex_indices",
        "property double quality",
        "end_header\n"])
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(vertices.tobytes())
        f.write(faces.tobytes())


@register_writer(".obj")
def write_obj(mesh: PlanarMesh, path) -> None:
    """Wavefront OBJ: vertices with 17 significant digits (exact for float64) and faces.

    Parameters
    ----------
    mesh : PlanarMesh
    path : str or os.PathLike

    Examples
    --------
    >>> import os, tempfile, numpy as np, pds_plugin as pds
    >>> from shapely.geometry import Point
    >>> disc = pds.mesh_region(pds.Region.from_shapely(Point(0, 0).buffer(1)), alpha=0.3)
    >>> out = os.path.join(tempfile.mkdtemp(), "disc.obj")
    >>> write_obj(disc, out)
    >>> vertices = np.loadtxt(out, comments=("#", "f"), usecols=(1, 2, 3))
    >>> bool((vertices == disc.vertices_3d).all())      # 17 digits: exact
    True
    """
    with open(path, "w") as f:
        f.write(f"# pds_plugin mesh, alpha {mesh.alpha!r}\n")
        np.savetxt(f, mesh.vertices_3d, fmt="v %.17g %.17g %.17g")
        np.savetxt(f, np.asarray(mesh.faces) + 1, fmt="f %d %d %d")


_TRIMESH_FORMATS = (".stl", ".off", ".glb", ".3mf")
"""Formats written by trimesh's exporters (PLY and OBJ keep the exact writers above)."""


def _trimesh_writer(suffix: str) -> Callable:
    def write(mesh, path) -> None:
        tm = to_trimesh(mesh)
        for attributes in (tm.vertex_attributes, tm.face_attributes):   # glTF: no booleans
            attributes.update({k: np.asarray(v, np.float32) for k, v in attributes.items()})
        tm.export(path, file_type=suffix.lstrip("."))
    write.__doc__ = f"{suffix[1:].upper()} through trimesh's exporter (see :func:`export`)."
    return write


for _suffix in _TRIMESH_FORMATS:
    register_writer(_suffix)(_trimesh_writer(_suffix))


def _meshio_writer(suffix: str) -> Callable:
    def write(mesh, path) -> None:
        from .fem import write_meshio
        write_meshio(mesh, path, suffix)
    write.__doc__ = (f"{suffix[1:].upper()} through meshio, 2D with tags (see "
                     f":func:`pds_plugin.sinks.fem.write_meshio`).")
    return write


for _suffix in MESHIO_SUFFIXES:
    register_writer(_suffix)(_meshio_writer(_suffix))
