"""Sink to MeshLab (pymeshlab): a PlanarMesh as a MeshSet, and MeshLab's own quality.

- :func:`to_meshset` (and :func:`meshlab_mesh`): a PlanarMesh as a ``pymeshlab.MeshSet``
  with face quality = aspect ratio L²/A and vertex quality = 1.0 on boundary samples.
- :func:`meshlab_quality`: MeshLab's own per-face ``inradius/circumradius`` filter,
  statistics and histogram, an independent check of our numbers.

Cutting a MeshSet's solid and adding the section meshes to it is
:func:`pds_plugin.workflows.add_section_meshes`.

pymeshlab is an optional dependency: ``pip install "pds_plugin[meshlab]"``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .._checks import check_has_triangles, check_planar_mesh, import_optional
from ..errors import ArgumentError, EmptyMeshError
from ..silence import silenced

if TYPE_CHECKING:
    import pymeshlab

    from ..analysis.quality import Quality
    from ..mesh import PlanarMesh

__all__ = ["to_meshset", "meshlab_mesh", "meshlab_quality", "MeshLabQuality", "radius_ratio",
           "RADIUS_RATIO_BOUND"]

RADIUS_RATIO_BOUND = 2 * np.sqrt(3) - 3
"""Theorem 1 in MeshLab's terms: the normalised ``2r/R`` of the worst certified
triangle (angles 30°, 30°, 120°) is 8·sin²(15°)·sin(60°) = 2√3 − 3 ≈ 0.464
(equilateral = 1)."""


def _pymeshlab():
    with silenced():               # pymeshlab prints while it loads its plugins
        return import_optional("pymeshlab", "meshlab", "pds_plugin.sinks.meshlab")


def meshlab_mesh(mesh: PlanarMesh) -> pymeshlab.Mesh:
    """A ``pymeshlab.Mesh`` of a PlanarMesh in 3D, with face and vertex quality.

    Parameters
    ----------
    mesh : PlanarMesh

    Returns
    -------
    pymeshlab.Mesh
        Face scalar = aspect ratio L²/A, vertex scalar = 1.0 on boundary samples.

    Raises
    ------
    EmptyMeshError
        If the mesh has no triangles (pymeshlab cannot hold an empty mesh).
    MissingDependencyError
        If pymeshlab is not installed.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.2)
    >>> meshlab_mesh(mesh).face_number() == len(mesh.faces)
    True
    """
    check_has_triangles(mesh, "for pymeshlab, which cannot hold an empty mesh")
    pm = _pymeshlab()
    return pm.Mesh(vertex_matrix=np.ascontiguousarray(mesh.vertices_3d, dtype=np.float64),
                   face_matrix=np.ascontiguousarray(mesh.faces, dtype=np.int32),
                   v_scalar_array=np.asarray(mesh.on_boundary, dtype=np.float64),
                   f_scalar_array=np.asarray(mesh.quality().aspect_ratio, dtype=np.float64))


def to_meshset(mesh: PlanarMesh, name: str = "pds_plugin mesh") -> pymeshlab.MeshSet:
    """A new ``pymeshlab.MeshSet`` holding ``mesh`` in 3D under ``name``.

    Face quality is the aspect ratio L²/A (≤ 4√3 on a certified mesh); vertex quality is
    1.0 on boundary samples and 0.0 inside, ready for MeshLab's selection and colour
    filters (``compute_selection_by_scalar_per_face``, ``compute_color_from_scalar_per_face``).

    Parameters
    ----------
    mesh : PlanarMesh
    name : str
        The mesh's label in the MeshSet.

    Returns
    -------
    pymeshlab.MeshSet

    Raises
    ------
    EmptyMeshError, MissingDependencyError
        As :func:`meshlab_mesh`.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import Point
    >>> disc = pds.Region.from_shapely(Point(0, 0).buffer(1))
    >>> ms = to_meshset(pds.mesh_region(disc, alpha=0.3), name="disc")
    >>> ms.current_mesh().label()
    'disc'
    """
    pm = _pymeshlab()
    meshset = pm.MeshSet()
    meshset.add_mesh(meshlab_mesh(mesh), name)
    return meshset


def radius_ratio(quality: Quality) -> np.ndarray:
    """MeshLab's ``inradius/circumradius`` (normalised ``2r/R``, equilateral = 1) from a
    :class:`pds_plugin.Quality`, through the angles: ``2r/R = 8 Π sin(θᵢ/2)``.

    Parameters
    ----------
    quality : Quality

    Returns
    -------
    (M,) float ndarray

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
    """What :func:`meshlab_quality` measured with MeshLab's own filters.

    Attributes
    ----------
    radius_ratio : (M,) float ndarray
        ``2r/R`` per face: 1 for the equilateral triangle, >= 2√3 - 3 when certified.
    statistics : dict
        ``avg``, ``max``, ``med``, ``min``, ``stddev`` and ``variance`` of radius_ratio.
    bin_edges : (bins + 1,) float ndarray
        Histogram edges over ``range``, as MeshLab rounded them (about 1e-8 off).
    counts : (bins,) int ndarray
        Faces per bin.
    below, above : int
        Faces under ``range[0]`` and over ``range[1]`` (MeshLab's underflow and overflow
        bins).
    """

    radius_ratio: np.ndarray
    statistics: dict[str, float]
    bin_edges: np.ndarray
    counts: np.ndarray
    below: int
    above: int

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

    Parameters
    ----------
    mesh_or_meshset : PlanarMesh or pymeshlab.MeshSet
        A MeshSet is measured on its current mesh.
    bins : int
    range : (float, float)
        The histogram's range of ``2r/R``.

    Returns
    -------
    MeshLabQuality

    Raises
    ------
    ArgumentError
        If the MeshSet is empty, or ``bins``/``range`` are not a positive count and an
        increasing pair.
    EmptyMeshError
        If the current mesh of the MeshSet, or the PlanarMesh, has no faces.
    MissingDependencyError
        If pymeshlab is not installed.

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
        raise ArgumentError(f"need bins > 0 and range[0] < range[1], "
                         f"got bins={bins!r}, range={range!r}")
    pm = _pymeshlab()
    work = pm.MeshSet()
    if isinstance(mesh_or_meshset, pm.MeshSet):
        meshset = mesh_or_meshset
        if meshset.mesh_number() == 0:
            raise ArgumentError("the MeshSet is empty: add a mesh first")
        current = meshset.current_mesh()
        if current.face_number() == 0:
            raise EmptyMeshError(f"the current mesh ({current.label()!r}) has no faces: "
                             "there is no triangle quality to measure")
        work.add_mesh(current, current.label())
    else:
        work.add_mesh(meshlab_mesh(check_planar_mesh(mesh_or_meshset, "meshlab_quality")),
                      "pds_plugin mesh")
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
