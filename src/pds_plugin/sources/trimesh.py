"""Section source for ``trimesh.Trimesh`` solids and mesh files (STL, OBJ, PLY, OFF, 3MF, GLB).

``load`` gives the mesh to cut and ``cut`` intersects it with a plane; used through
:func:`pds_plugin.section`, which checks the plane and assembles the segments into
polygons (:mod:`pds_plugin.sources.solids`). Manifold solids are cut here too, in float64.
"""

from __future__ import annotations

import os

import numpy as np

from ..errors import SectionError, SourceError
from ._sniff import MESH_KINDS, misnamed
from .drawing import is_drawing


def load(solid):
    """The ``trimesh.Trimesh`` to cut: ``solid`` itself, or the mesh read from a file.

    Parameters
    ----------
    solid : trimesh.Trimesh, str or os.PathLike

    Returns
    -------
    trimesh.Trimesh

    Raises
    ------
    FileNotFoundError, IsADirectoryError
        If the path does not exist, or is a folder.
    SourceError
        If the file is empty, a binary STL cut short, or holds no triangles trimesh can
        read, or the mesh has none.

    Examples
    --------
    >>> import trimesh
    >>> len(load(trimesh.creation.box()).faces)
    12
    """
    import trimesh

    if isinstance(solid, trimesh.Trimesh):
        mesh, name = solid, "the mesh"
    else:
        path = os.fspath(solid)
        if os.path.isdir(path):
            raise IsADirectoryError(f"{path!r} is a folder, not a mesh file")
        if not os.path.isfile(path):
            raise FileNotFoundError(f"no such mesh file: {path!r}")
        if os.path.getsize(path) == 0:
            raise SourceError(f"the mesh file {path!r} is empty")
        if is_drawing(path):
            raise SourceError(f"{path!r} is a 2D drawing, not a solid to cut: read it with "
                              f"pds_plugin.load_{os.path.splitext(path)[1].lower()[1:]}")
        _check_binary_stl(path)
        try:
            mesh = trimesh.load_mesh(path)
        except Exception as error:  # trimesh raises many kinds for unreadable files
            raise SourceError(f"cannot read {path!r} as a mesh: {_unreadable(path, error)}") \
                from error
        name = f"the file {path!r}"
    if len(mesh.faces) == 0:
        # with charset_normalizer installed trimesh reads any bytes as text and finds no
        # triangles in them: a picture or binary noise is named as when trimesh refuses it
        if not isinstance(solid, trimesh.Trimesh) and (
                misnamed(path, "a mesh file", MESH_KINDS) or _binary(path)):
            raise SourceError(f"cannot read {path!r} as a mesh: {_unreadable(path, None)}")
        raise SourceError(f"{name} has no triangles (it is empty, a point cloud, or not a mesh "
                         f"format trimesh reads); give a closed triangle mesh")
    return mesh


def _unreadable(path, error) -> str:
    """Why trimesh could not read ``path`` (``error`` None: it read no triangles from a
    binary file), in the user's terms."""
    other = misnamed(path, "a mesh file", MESH_KINDS)
    if other:
        return other
    if error is None or isinstance(error, ImportError):   # trimesh guesses a text encoding
        # with an optional module (charset_normalizer): without it, binary noise raises
        detail = "it is neither a valid binary mesh nor plain text"
    elif isinstance(error, IndexError):
        detail = f"a face refers to a vertex the file does not have ({error})"
    else:
        detail = str(error) or type(error).__name__
    return f"{detail}; give a file trimesh reads: STL, OBJ, PLY, OFF, 3MF or GLB"


def _binary(path) -> bool:
    """Whether ``path`` holds bytes that no mesh format has: a NUL in its first 64 KiB (no
    mesh text has one), and no binary mesh's signature (PLY, GLB, 3MF) or size (STL)."""
    with open(path, "rb") as file:
        head = file.read(1 << 16)
    if b"\x00" not in head or head.startswith((b"ply", b"glTF", b"PK\x03\x04")):
        return False
    count = int.from_bytes(head[80:84], "little") if len(head) >= 84 else -1
    return os.path.getsize(path) != 84 + 50 * count       # not a binary STL, empty or not


def _check_binary_stl(path) -> None:
    """Refuse a binary STL shorter than its header says (an interrupted download or copy)."""
    if not path.lower().endswith(".stl"):
        return
    with open(path, "rb") as file:
        head = file.read(84)
    if len(head) < 84 or head[:5].lower() == b"solid":      # text STL: trimesh judges
        return
    count = int.from_bytes(head[80:84], "little")
    size, expected = os.path.getsize(path), 84 + 50 * count
    if size < expected:
        other = misnamed(path, "a mesh file", MESH_KINDS)
        if other:
            raise SourceError(f"cannot read {path!r} as a mesh: {other}")
        raise SourceError(f"{path!r} is a binary STL cut short, or not an STL at all: its "
                          f"header announces {count} triangles ({expected:,} bytes) but the "
                          f"file has {size:,} bytes; copy or export it again")


def cut(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    """Where the plane z = 0 cuts a mesh given in the plane's frame.

    Intersections are computed in float64 by trimesh's ``mesh_plane``, on coordinates
    relative to the plane so that rounding stays relative to the part's size; a vertex
    within ``trimesh.tol.merge`` of the plane counts as on it.

    Parameters
    ----------
    vertices : (n, 3) float ndarray
        In the plane's frame: the plane is z = 0.
    faces : (m, 3) int ndarray

    Returns
    -------
    segments : (s, 2, 2) float64 ndarray
        The segments' 2D end points, in no particular order or direction.
    face : (s,) int ndarray
        The face each segment comes from.

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box(extents=(2, 2, 2))
    >>> segments, face = cut(box.vertices, box.faces)
    >>> float(np.linalg.norm(segments[:, 1] - segments[:, 0], axis=1).sum())   # perimeter
    8.0
    """
    import trimesh
    from trimesh.intersections import mesh_plane

    local = trimesh.Trimesh(vertices, faces, process=False, validate=False)
    try:
        lines, face = mesh_plane(local, plane_normal=[0.0, 0.0, 1.0],
                                 plane_origin=[0.0, 0.0, 0.0], return_faces=True)
    except AssertionError:            # trimesh's intersections lost to rounding
        low, high = vertices.min(axis=0), vertices.max(axis=0)
        raise SectionError(
            f"the plane cannot be cut through this mesh in float64: its vertices span "
            f"{low.tolist()} to {high.tolist()} about the plane, too wide for its smallest "
            f"faces; look for stray vertices far from the part") from None
    return (np.asarray(lines, dtype=np.float64).reshape(-1, 2, 3)[:, :, :2],
            np.asarray(face, dtype=np.int64))
