"""pds_plugin inside a MeshLab (pymeshlab) workflow.

- :func:`to_meshset`: a PlanarMesh as a ``pymeshlab.MeshSet`` with face quality = aspect
  ratio L²/A and vertex quality = 1.0 on boundary samples.
- :func:`add_section_meshes`: cut the current mesh of a MeshSet (a closed solid) with one
  or several planes and add a certified mesh of each section to the same MeshSet.
- :func:`meshlab_quality`: MeshLab's own per-face ``inradius/circumradius`` filter,
  statistics and histogram, an independent check of our numbers.
- :func:`silenced`: keeps MeshLab's C-level chatter off the terminal.

pymeshlab is an optional dependency: ``pip install "pds_plugin[meshlab]"``.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from dataclasses import dataclass

import numpy as np

__all__ = ["to_meshset", "add_section_meshes", "SectionMesh", "meshlab_quality",
           "MeshLabQuality", "radius_ratio", "RADIUS_RATIO_BOUND", "silenced"]

RADIUS_RATIO_BOUND = 2 * np.sqrt(3) - 3
"""Theorem 1 in MeshLab's terms: the normalised ``2r/R`` of the worst certified
triangle (angles 30°, 30°, 120°) is 8·sin²(15°)·sin(60°) = 2√3 − 3 ≈ 0.464
(equilateral = 1)."""


def _pymeshlab():
    try:
        with silenced():
            import pymeshlab
    except ImportError as error:
        raise ImportError('pymeshlab is needed for pds_plugin.meshlab: '
                          'pip install "pds_plugin[meshlab]"') from error
    return pymeshlab


def _flush_streams() -> None:
    """Flush Python's and C's buffered stdout/stderr into the descriptors they use now."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(AttributeError, ValueError, OSError):
            stream.flush()
    with contextlib.suppress(OSError, AttributeError, TypeError):   # no C runtime this way
        ctypes.CDLL(None).fflush(None)


@contextlib.contextmanager
def silenced():
    """Send everything written to file descriptors 1 and 2 to the null device.

    MeshLab, qhull and other C++ code print straight to the process's stdout/stderr,
    past ``sys.stdout`` (so ``contextlib.redirect_stdout`` cannot catch them, PyMeshLab
    issues #222, #267, #328). This swaps the file descriptors themselves and restores
    them on exit, exceptions included. Python exceptions still carry their messages.
    The descriptors are process-wide: other threads writing meanwhile are silenced too.

    Examples
    --------
    >>> import os
    >>> with silenced():
    ...     _ = os.write(1, b"not shown\\n")
    """
    _flush_streams()               # what was written before still reaches the terminal
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:                # no descriptors 1/2 (e.g. pythonw): nothing to silence
        yield
        return
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        os.dup2(null, 2)
        yield
    finally:
        _flush_streams()           # what was buffered inside goes to the null device
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (null, *saved):
            os.close(fd)


def _meshlab_mesh(mesh):
    """A ``pymeshlab.Mesh`` of a PlanarMesh in 3D, with face and vertex quality."""
    if len(mesh.faces) == 0:
        raise ValueError(f"{mesh!r} has no triangles; pymeshlab cannot hold an empty mesh "
                         "(alpha is probably too large for the region)")
    pm = _pymeshlab()
    return pm.Mesh(vertex_matrix=np.ascontiguousarray(mesh.vertices_3d, dtype=np.float64),
                   face_matrix=np.ascontiguousarray(mesh.faces, dtype=np.int32),
                   v_scalar_array=np.asarray(mesh.on_boundary, dtype=np.float64),
                   f_scalar_array=np.asarray(mesh.quality().aspect_ratio, dtype=np.float64))


def to_meshset(mesh, name: str = "pds_plugin mesh"):
    """A new ``pymeshlab.MeshSet`` holding ``mesh`` in 3D under ``name``.

    Face quality is the aspect ratio L²/A (≤ 4√3 on a certified mesh); vertex quality is
    1.0 on boundary samples and 0.0 inside, ready for MeshLab's selection and colour
    filters (``compute_selection_by_scalar_per_face``, ``compute_color_from_scalar_per_face``).

    Raises
    ------
    ValueError
        If the mesh has no triangles (pymeshlab cannot hold an empty mesh).

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.2)
    >>> ms = to_meshset(mesh)
    >>> ms.current_mesh().face_number() == len(mesh.faces)
    True
    """
    pm = _pymeshlab()
    meshset = pm.MeshSet()
    meshset.add_mesh(_meshlab_mesh(mesh), name)
    return meshset


@dataclass(frozen=True)
class SectionMesh:
    """One section added to a MeshSet by :func:`add_section_meshes`."""

    mesh_id: int     # its id in the MeshSet
    name: str        # its name there, e.g. "section z=0.5 alpha=0.1"
    mesh: object     # the PlanarMesh (2D, with region, certificate, quality)


def add_section_meshes(meshset, alpha: float, *, plane_normal=(0.0, 0.0, 1.0),
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
    1.0 on boundary samples (as :func:`to_meshset`). The solid stays the current mesh, so
    calls can be repeated with other planes.

    Returns
    -------
    list of SectionMesh
        The new mesh ids, their names and the PlanarMeshes, one per plane.

    Raises
    ------
    ValueError
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
    from .mesh import mesh_region
    from .sources import section, sections

    solid_id = _solid_id(meshset, mesh_id)
    if plane_origin is None and offsets is None and count is None:
        raise ValueError("say where to cut: plane_origin=(x, y, z) for one plane, or "
                         "offsets=[...] / count=N for several planes along plane_normal")
    solid = _solid_trimesh(meshset, solid_id)
    if offsets is None and count is None:
        regions = [section(solid, plane_origin=plane_origin, plane_normal=plane_normal)]
    else:
        regions = sections(solid, plane_normal=plane_normal, offsets=offsets, count=count,
                           plane_origin=plane_origin)
    meshes = [mesh_region(region, alpha, seed=seed) for region in regions]
    layers = [_meshlab_mesh(mesh) for mesh in meshes]  # all checked before the MeshSet changes
    added = []
    for mesh, layer in zip(meshes, layers):
        name = f"section {_plane_label(mesh.region.frame)} alpha={mesh.alpha:.6g}"
        meshset.add_mesh(layer, name)
        added.append(SectionMesh(meshset.current_mesh_id(), name, mesh))
    meshset.set_current_mesh(solid_id)
    return added


def _solid_id(meshset, mesh_id) -> int:
    if meshset.mesh_number() == 0:
        raise ValueError("the MeshSet is empty: load a solid first (ms.load_new_mesh(path))")
    if mesh_id is None:
        return meshset.current_mesh_id()
    if not meshset.mesh_id_exists(mesh_id):
        raise ValueError(f"the MeshSet has no mesh with id {mesh_id}")
    return int(mesh_id)


def _solid_trimesh(meshset, mesh_id):
    import trimesh

    solid = meshset.mesh(mesh_id)
    if solid.face_number() == 0:
        raise ValueError(f"mesh {mesh_id} ({solid.label()!r}) of the MeshSet has no faces: "
                         "a section needs a closed triangle mesh, not a point cloud")
    # merge the duplicated vertices of STL-like soups so the solid is watertight
    return trimesh.Trimesh(solid.transformed_vertex_matrix(), solid.face_matrix())


def _plane_label(frame) -> str:
    """"z=0.5" for an axis-aligned plane, else "n=(a, b, c) d=0.5" (n·x = d)."""
    frame = np.asarray(frame)
    normal, origin = frame[:3, 2], frame[:3, 3]
    axis = int(np.argmax(np.abs(normal)))
    if np.isclose(abs(normal[axis]), 1.0, rtol=0, atol=1e-12):
        return f"{'xyz'[axis]}={origin[axis] + 0.0:.6g}"
    return f"n=({', '.join(f'{c + 0.0:.4g}' for c in normal)}) d={normal @ origin:.6g}"


def radius_ratio(quality) -> np.ndarray:
    """MeshLab's ``inradius/circumradius`` (normalised ``2r/R``, equilateral = 1) from a
    :class:`pds_plugin.Quality`, through the angles: ``2r/R = 8 Π sin(θᵢ/2)``.

    Examples
    --------
    >>> import numpy as np, pds_plugin as pds
    >>> q = pds.triangle_quality(np.array([[0, 0], [1, 0], [0.5, np.sqrt(3) / 2]]), [[0, 1, 2]])
    >>> radius_ratio(q).round(12).tolist()
    [1.0]
    """
    return 8 * np.prod(np.sin(np.radians(quality.angles) / 2), axis=1)


@dataclass(frozen=True)
class MeshLabQuality:
    """What :func:`meshlab_quality` measured with MeshLab's own filters."""

    radius_ratio: np.ndarray   # (M,) per face, 2r/R: equilateral 1, certified >= 2√3-3
    statistics: dict           # avg, max, med, min, stddev, variance of radius_ratio
    bin_edges: np.ndarray      # (bins + 1,) histogram edges over ``range`` (MeshLab's, ~1e-8 off)
    counts: np.ndarray         # (bins,) faces per bin
    below: int                 # faces under range[0] (MeshLab's underflow bin)
    above: int                 # faces over range[1] (MeshLab's overflow bin)

    @property
    def certified(self) -> bool:
        """Theorem 1 checked by MeshLab: no face below :data:`RADIUS_RATIO_BOUND`."""
        return bool(self.statistics["min"] >= RADIUS_RATIO_BOUND * (1 - 1e-9))


def meshlab_quality(mesh_or_meshset, bins: int = 20, range=(0.0, 1.0)) -> MeshLabQuality:
    """Measure triangle quality with MeshLab's own filters (an independent check).

    The recipe, on the current mesh of a MeshSet (or on a PlanarMesh)::

        ms.compute_scalar_by_aspect_ratio_per_face(metric="inradius/circumradius")
        ms.get_scalar_statistics_per_face()
        ms.get_scalar_histogram_per_face(histmin=0, histmax=1, binnum=20)

    MeshLab's ``inradius/circumradius`` is normalised to 1 for the equilateral triangle;
    our L²/A maps to it through the angles (:func:`radius_ratio`). Theorem 1 (every angle
    in [30°, 120°]) reads ``2r/R >= 2√3 − 3 ≈ 0.464`` (:data:`RADIUS_RATIO_BOUND`). The
    histogram range is explicit because MeshLab's automatic one puts the maximum into the
    overflow bin. The filters run on a copy: the given MeshSet keeps its face quality.

    Raises
    ------
    ValueError
        If the MeshSet is empty or its current mesh has no faces, or ``bins``/``range``
        are not a positive count and an increasing pair.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.1)
    >>> measured = meshlab_quality(mesh)
    >>> measured.certified, int(measured.counts.sum()) == len(mesh.faces)
    (True, True)
    """
    lo, hi = (float(v) for v in range)
    if not (isinstance(bins, (int, np.integer)) and bins > 0 and lo < hi):
        raise ValueError(f"need bins > 0 and range[0] < range[1], "
                         f"got bins={bins!r}, range={range!r}")
    pm = _pymeshlab()
    work = pm.MeshSet()
    if isinstance(mesh_or_meshset, pm.MeshSet):
        meshset = mesh_or_meshset
        if meshset.mesh_number() == 0:
            raise ValueError("the MeshSet is empty: add a mesh first")
        current = meshset.current_mesh()
        if current.face_number() == 0:
            raise ValueError(f"the current mesh ({current.label()!r}) has no faces: "
                             "there is no triangle quality to measure")
        work.add_mesh(current, current.label())
    else:
        work.add_mesh(_meshlab_mesh(mesh_or_meshset), "pds_plugin mesh")
    with silenced():
        work.compute_scalar_by_aspect_ratio_per_face(metric="inradius/circumradius")
        statistics = work.get_scalar_statistics_per_face()
        histogram = work.get_scalar_histogram_per_face(histmin=lo, histmax=hi, binnum=int(bins))
    # MeshLab's bins: [underflow, bins..., overflow], edges as MeshLab rounded them
    counts = np.asarray(histogram["hist_count"]).astype(np.int64)
    edges = np.asarray(histogram["hist_bin_min"][1:])   # bins' lower ends, then the overflow's
    return MeshLabQuality(radius_ratio=work.current_mesh().face_scalar_array(),
                          statistics={k: float(v) for k, v in statistics.items()},
                          bin_edges=edges, counts=counts[1:-1],
                          below=int(counts[0]), above=int(counts[-1]))
