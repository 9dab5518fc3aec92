"""CAD solids cut by planes: :func:`section` and :func:`sections` turn a
``trimesh.Trimesh``, a ``manifold3d.Manifold`` or a mesh file (anything ``trimesh``
reads: STL, OBJ, PLY, OFF, 3MF, GLB) into :class:`Region` objects; B-rep solids (STEP,
IGES, BREP files and OCP shapes) are cut exactly by :mod:`.step`, in the same 2D frame.

A solid's backend module (:mod:`.trimesh`, :mod:`.manifold`) turns it into a float64
``trimesh.Trimesh``; everything else (the plane, its 2D frame, the checks and the exact
cut) is shared here, and the cut curves become polygons in :mod:`.polygons`, so one plane
gives the same 2D coordinates whichever library the solid comes from. The heavy
libraries are imported inside the backend modules only.
"""

from __future__ import annotations

import os
import sys
import warnings

import numpy as np
import shapely
import shapely.affinity

from .._checks import check_positive_int
from ..errors import ArgumentError, ArgumentTypeError, BudgetError, SectionError, SourceError
from ..region import Region, check_scale, check_tolerance
from . import manifold as manifold_backend
from . import step as step_backend
from . import trimesh as trimesh_backend
from .planes import checked_on_face as _on_face
from .planes import checked_plane as _plane
from .planes import plane_frames as _frames
from .planes import places_in_3d
from .polygons import outline_geometry, snap

__all__ = ["section", "sections", "mesh_tolerance", "MAX_SECTIONS"]

MAX_SECTIONS = 10_000
"""Most planes one call of :func:`sections` cuts (each section is a Region in memory)."""

# Backends by the library their solids come from: (library, class name, backend module).
_SOLIDS = (("trimesh", "Trimesh", trimesh_backend), ("manifold3d", "Manifold", manifold_backend))


def section(solid, plane_origin, plane_normal, *, on_face=None, tolerance=None) -> Region:
    """Cut a solid with a plane and return the section as a :class:`Region`.

    The 2D coordinates are those of ``trimesh.geometry.plane_transform(origin, normal)``:
    ``plane_origin`` is the 2D origin and the in-plane axes depend on the normal only, so
    the same plane gives the same coordinates with either backend, and parallel planes
    share their in-plane axes. ``region.frame`` is its exact inverse (2D -> 3D).

    Parameters
    ----------
    solid : trimesh.Trimesh, manifold3d.Manifold, str, os.PathLike or OCP shape
        A closed (watertight) solid, or the path of a mesh file trimesh reads; or a
        B-rep solid: a STEP, IGES or BREP file or an OCP ``TopoDS_Shape`` (the ``[step]``
        extra, :mod:`.step`), whose curves stay exact until flattened.
    plane_origin : (3,) array_like
        A point of the plane.
    plane_normal : (3,) array_like
        The plane's normal (any non-zero length).
    on_face : {None, "above", "below"}
        What to do when the plane lies on faces of the solid (a CAD part's step, say):
        None refuses it (the section is ambiguous there); "above" / "below" cut just above
        / below those faces instead, 1e-6 of the solid's size along the normal, and
        ``region.frame`` holds the plane used. A plane just outside the solid, within
        ``tolerance`` of its top or bottom (a face's height typed rounded), counts as on
        that face.
    tolerance : float, optional
        How far the section's boundary may lie from the solid's. For a mesh, to absorb
        its noise (:attr:`Region.tolerance`): by default :func:`mesh_tolerance`, the
        mesh's float precision, or the chord error of its tessellated curves if larger,
        taken for each polygon from its own bodies' coordinates (a body far from the
        origin is noisier: docs/conforming.md); 0 keeps every vertex of the cut. For a
        B-rep solid, the chord tolerance of its flattened curves: 1e-5 of the solid's
        diagonal by default.

    Returns
    -------
    Region
        Every component with its holes; islands inside holes are components too.

    Raises
    ------
    SectionError
        If the plane misses the solid (the message gives the solid's extent along the
        normal), lies on one of its faces, or cuts an open (not watertight) part of the
        mesh (the message gives the open ends).
    SourceError
        If the file is empty or unreadable, or the solid is invalid or empty.
    ArgumentError
        If the origin or normal is not finite or the normal is zero.
    FileNotFoundError
        If ``solid`` is a path that does not exist.
    ArgumentTypeError
        If ``solid`` is of an unsupported type.

    Examples
    --------
    >>> import trimesh, pds_plugin as pds
    >>> tube = trimesh.creation.annulus(r_min=1, r_max=2, height=4)
    >>> region = pds.section(tube, plane_origin=(0, 0, 0), plane_normal=(0, 0, 1))
    >>> region.betti
    (1, 1)
    >>> step = trimesh.creation.box(extents=(2, 2, 1)).union(
    ...     trimesh.creation.box(extents=(1, 1, 1)).apply_translation((0, 0, 1)))
    >>> round(pds.section(step, (0, 0, 0.5), (0, 0, 1), on_face="above").area, 6)
    1.0
    """
    origin, normal = _plane(plane_origin, plane_normal)
    return _solid(solid, tolerance).cut(origin, normal, _on_face(on_face))


def sections(solid, plane_normal, offsets=None, *, count=None, plane_origin=None,
             on_face=None, tolerance=None) -> list[Region]:
    """Cut a solid with parallel planes and return one :class:`Region` per plane.

    Give either ``offsets`` (the planes' signed distances along the unit normal from
    ``plane_origin``) or ``count`` (that many planes, one in the middle of each of
    ``count`` equal slabs of the solid's extent along the normal, so all strictly
    inside it). All regions share the same in-plane axes (see :func:`section`).

    The planes ``count`` places are automatic: one that lies on faces of the solid (a
    CAD part often has a face at half height) moves to the nearest plane that does not,
    just above them, with a warning. Planes at ``offsets`` follow ``on_face``.

    Parameters
    ----------
    solid : trimesh.Trimesh, manifold3d.Manifold, str, os.PathLike or OCP shape
    plane_normal : (3,) array_like
    offsets : sequence of float, optional
    count : int, optional
    plane_origin : (3,) array_like, optional
        The point offsets are measured from; the world origin by default.
    on_face : {None, "above", "below"}
        For planes at ``offsets`` that lie on faces, as in :func:`section`.
    tolerance : float, optional
        As in :func:`section`.

    Returns
    -------
    list of Region
        In the order of ``offsets``, or of increasing offset for ``count``.

    Raises
    ------
    PdsError
        As :func:`section` for any plane, and an :class:`~pds_plugin.errors.ArgumentError`
        if neither or both of ``offsets`` and ``count`` are given, or they are not finite /
        not a positive integer; a :class:`~pds_plugin.errors.BudgetError` for more than
        ``MAX_SECTIONS`` (10,000) planes.

    Examples
    --------
    >>> import trimesh, pds_plugin as pds
    >>> box = trimesh.creation.box(extents=(2, 2, 2))
    >>> [round(r.area, 9) for r in pds.sections(box, (0, 0, 1), count=3)]
    [4.0, 4.0, 4.0]
    >>> [float(r.frame[2, 3]) for r in pds.sections(box, (0, 0, 1), offsets=[-0.5, 0.5])]
    [-0.5, 0.5]
    """
    origin, normal = _plane((0.0, 0.0, 0.0) if plane_origin is None else plane_origin,
                            plane_normal)
    solid = _solid(solid, tolerance)
    heights = _offsets(offsets, count, solid.heights(origin, normal))
    on_face = "nearest" if count is not None else _on_face(on_face)
    return [solid.cut(origin + height * normal, normal, on_face) for height in heights]


def _solid(solid, tolerance):
    """The solid to cut: a B-rep one (:mod:`.step`) or a mesh one."""
    if step_backend.accepts(solid):
        return step_backend.StepSolid(solid, tolerance)
    return _Solid(solid, tolerance)


class _Solid:
    """A solid loaded once as a float64 trimesh mesh, cut by as many planes as asked."""

    def __init__(self, solid, tolerance=None):
        loaded = _source_of(solid).load(solid)
        check_coordinates(loaded.vertices, loaded.faces)
        self.mesh = _consistently_oriented(welded(loaded))
        self.vertices = np.asarray(self.mesh.vertices, dtype=np.float64)
        self.faces = np.asarray(self.mesh.faces)
        self.scale = float(np.linalg.norm(np.ptp(self.vertices, axis=0)))
        self.shell = _shells(self.faces, len(self.vertices))
        # outward normals give the material winding number +1; a mesh turned inside out
        # (negative volume) is read the other way round
        corners = self.vertices[self.faces] - self.vertices.mean(axis=0)
        volume = np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2]))
        self.outward = 1.0 if volume.sum() >= 0 else -1.0
        self.bodies = None                      # a tolerance given: the same for every part
        if tolerance is None:
            from_file = isinstance(solid, (str, os.PathLike))
            precision = _section_precision(self.mesh, from_file)
            self.bodies = _bodies(self.vertices, self.faces, self.shell, precision,
                                  _chord_error(self.mesh))
            tolerance = max(float(self.bodies[2].max()), self.bodies[3])
        self.tolerance = check_tolerance(tolerance)

    def heights(self, origin, normal) -> np.ndarray:
        """Signed distances of the vertices to the plane."""
        return (self.vertices - origin) @ normal

    def cut(self, origin, normal, on_face=None) -> Region:
        origin = self._off_faces(origin, normal, on_face)
        to_2d, to_3d = _frames(origin, normal)
        local = self.vertices @ to_2d[:3, :3].T + to_2d[:3, 3]   # z: height above the plane
        offset = float(origin @ normal)
        self._check_plane(local[:, 2], offset)
        self._check_compact(local)
        geometry, open_ends = self._section_geometry(local)
        if len(open_ends):
            raise SectionError(
                f"the section at normal·x = {offset:.9g} is open: the mesh is not watertight "
                f"where the plane cuts it ({len(open_ends)} open end(s), at "
                f"{places_in_3d(open_ends, to_3d)}); repair the mesh "
                f"(e.g. trimesh.repair.fill_holes) or move the plane")
        if geometry.is_empty:
            raise SectionError(
                f"the plane at normal·x = {offset:.9g} crosses the solid's extent but cuts no "
                f"material (it passes through a gap between parts); move the plane")
        return Region.from_shapely(geometry, frame=to_3d,
                                   tolerance=self._tolerances(geometry, to_3d))

    def _tolerances(self, geometry, to_3d):
        """The section's tolerance: the one given, or, by default, each polygon's own:
        the largest of the bodies it lies in (their boxes hold a point of it), each
        body's from its own coordinates' float noise (:func:`_bodies`). A body
        far from the origin has coarser noise than one at it, and its tolerance would
        simplify the other's small features away (a plate's 0.2-wide holes beside a box
        1e6 away): one number where every polygon gets the same."""
        if self.bodies is None:
            return self.tolerance
        low, high, noise, chord = self.bodies
        polygons = shapely.get_parts(geometry)
        inside = shapely.get_coordinates(shapely.point_on_surface(polygons))
        lifted = inside @ to_3d[:3, :2].T + to_3d[:3, 3]
        margin = self.tolerance + 1e-9 * self.scale
        holds = ((lifted[:, None] >= low - margin) & (lifted[:, None] <= high + margin)).all(axis=2)
        own = np.where(holds.any(axis=1), np.where(holds, noise, 0.0).max(axis=1), noise.max())
        # a body only a few ulps across (1 unit at 1e6 in float32) is no noise to simplify
        # away: its noise is at most NOISE_SHARE of its mean width, 2 area / perimeter
        width = 2 * shapely.area(polygons) / shapely.length(polygons)
        own = np.maximum(np.minimum(own, NOISE_SHARE * width), chord)
        return float(own[0]) if np.all(own == own[0]) else own.tolist()

    def _section_geometry(self, local):
        """The section in the plane's 2D coordinates, and the open ends of its curves.

        The solid is where the winding number of its shells is >= 1, so overlapping and
        nested shells (multi-body exports) give their union, and an inward shell a void.
        The cut is computed about the middle of the solid, not the plane origin, and each
        shell's cut points are joined within 1e-9 of that shell's size, so neither a far
        plane origin nor a far-away part inflates the tolerance.
        """
        centre = np.zeros(3)
        centre[:2] = (local[:, :2].min(axis=0) + local[:, :2].max(axis=0)) / 2
        unit = _unit(local[:, 2])
        local = (local - centre) / unit
        segments, face = trimesh_backend.cut(local, self.faces)
        corners = local[self.faces[face]]
        outward = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])[:, :2]
        direction = segments[:, 1] - segments[:, 0]
        material_right = (direction[:, 1] * outward[:, 0] - direction[:, 0] * outward[:, 1]) \
            * self.outward < 0
        segments[material_right] = segments[material_right, ::-1]     # material on the left
        segments = _snap_by_shell(segments, self.shell[face], local, self.shell, self.faces)
        floor = 64 * np.spacing(np.abs(segments).max(initial=1.0))
        geometry, open_ends = outline_geometry(list(segments), tolerance=floor, rule="winding")
        closing = _closing_segments(segments) if len(open_ends) else None
        if closing is not None:
            closed, still_open = outline_geometry(list(segments) + list(closing),
                                                  tolerance=floor, rule="winding")
            if not len(still_open) and shapely.contains(
                    closed, shapely.linestrings(closing)).all():
                warnings.warn(
                    f"the mesh is not watertight where the plane cuts it: {len(closing)} "
                    f"open shell(s) end inside other parts' material (a spout or handle "
                    f"pushed into a body without joining it); each was closed across that "
                    f"material, so the section is the union", UserWarning, stacklevel=4)
                geometry, open_ends = closed, still_open
        geometry = shapely.affinity.affine_transform(
            geometry, [unit, 0.0, 0.0, unit, centre[0], centre[1]])
        return geometry, open_ends * unit + centre[:2]

    def _check_compact(self, local) -> None:
        """Refuse a shell with stray vertices: the cut points of a shell are joined within
        1e-9 of its size, so a vertex 1e9 times farther out than the rest of its shell
        spans (a damaged file) would merge the whole part."""
        vertex_shell = np.full(len(local), -1)
        vertex_shell[self.faces.ravel()] = np.repeat(self.shell, 3)
        used = np.flatnonzero(vertex_shell >= 0)
        order = used[np.argsort(vertex_shell[used], kind="stable")]
        for members in np.split(order, np.flatnonzero(np.diff(vertex_shell[order])) + 1):
            corners = local[members]
            size = float(np.linalg.norm(np.ptp(corners, axis=0)))
            spread = float(np.median(np.abs(corners - np.median(corners, axis=0)), axis=0).max())
            if spread > 0 and 1e-9 * size > 1e-3 * spread:
                far = members[np.argmax(np.abs(corners - np.median(corners, axis=0)).max(axis=1))]
                raise SectionError(
                    f"a part of the mesh spans {size:.3g} but most of its vertices lie within "
                    f"{spread:.3g} of each other: a vertex far from the rest (one at "
                    f"({', '.join(f'{v:.6g}' for v in self.vertices[far])})) would merge the "
                    f"whole part when the cut is joined; remove the stray vertices (a "
                    f"damaged file?)")

    def _faces_on(self, heights) -> int:
        """How many faces lie on the plane, given the vertices' heights above it."""
        from trimesh.constants import tol

        return int((np.abs(heights / _unit(heights)) <= tol.merge)[self.faces].all(axis=1).sum())

    def _off_faces(self, origin, normal, on_face):
        """The plane origin, moved off the faces it lies on as ``on_face`` says; a plane
        beyond the solid by at most its tolerance is first moved onto its nearest vertex
        (on a face there, the plane is then on it): the height of a float32 part's top
        face typed to 7 digits, 1.3e-6 above it (a third of a float32 ulp there), was
        refused as missing the solid."""
        heights = self.heights(origin, normal)
        if on_face is not None:
            low, high = float(heights.min()), float(heights.max())
            if 0 < low <= self.tolerance or -self.tolerance <= high < 0:
                origin = origin + (low if low > 0 else high) * normal
                heights = self.heights(origin, normal)
        offset = float(origin @ normal)
        flat = self._faces_on(heights)
        if not flat or on_face is None:
            return origin                  # refused, if on faces, by _check_plane
        step = 1e-6 * self.scale
        for shift in ([step, -step] if on_face == "nearest" else
                      [step if on_face == "above" else -step]):
            for _ in range(20):            # past any other face within a few steps
                moved = origin + shift * normal
                if not self._faces_on(self.heights(moved, normal)):
                    if on_face == "nearest":
                        warnings.warn(
                            f"the plane at normal·x = {offset:.9g} lies on {flat} face(s) of "
                            f"the solid; cut at {offset + shift:.9g} instead, just "
                            f"{'above' if shift > 0 else 'below'} them", UserWarning,
                            stacklevel=4)
                    return moved
                shift *= 2
        return origin

    def _check_plane(self, heights, offset) -> None:
        """Refuse a plane that lies on a face or misses the solid, or a mesh whose stray
        vertices make the on-plane tolerance as coarse as the part (heights: of the
        vertices)."""
        from trimesh.constants import tol

        middle = np.median(heights)
        spread = float(np.median(np.abs(heights - middle)))
        if spread > 0 and tol.merge * _unit(heights) > 1e-2 * spread:
            raise SectionError(
                f"the mesh spans normal·x in [{offset + heights.min():.6g}, "
                f"{offset + heights.max():.6g}], but most of its vertices lie within "
                f"{spread:.3g} of normal·x = {offset + middle:.6g}: vertices far from the part "
                f"make the cut's tolerance ({tol.merge * _unit(heights):.3g}) as coarse as the "
                f"part itself; remove the stray vertices, or split the mesh into its parts")
        flat = self._faces_on(heights)
        if flat:
            raise SectionError(
                f"the plane lies on {flat} face(s) of the solid (normal·x = {offset:.9g}), "
                f"so the section is ambiguous; pass on_face='above' or 'below' (CLI: "
                f"--on-face above or below), or move the plane")
        margin = tol.merge * _unit(heights)
        if not (heights.min() < -margin and heights.max() > margin):
            low, high = offset + heights.min(), offset + heights.max()
            if heights.min() > margin or heights.max() < -margin:
                raise SectionError(
                    f"the plane misses the solid: it is at normal·x = {offset:.9g} but the "
                    f"solid spans normal·x in [{low:.9g}, {high:.9g}]; put the plane origin "
                    f"inside that range")
            raise SectionError(
                f"the plane at normal·x = {offset:.9g} only touches the solid (at an edge or "
                f"a corner where the solid spans normal·x in [{low:.9g}, {high:.9g}]), so the "
                f"section has no area; put the plane strictly inside that range")


NOISE_ULPS = 16
"""Float noise of a mesh's sections, in units in the last place of its largest coordinate
in the precision its file stores (float32 for STL): a plane through two facets that
rounding left not quite coplanar bends there by a few of them."""
NOISE_SHARE = 1 / 8
"""A section polygon's float noise is taken at most this share of its mean width
(2 area / perimeter): the tolerance pass keeps the shape of a body only a few ulps
across, far from the origin."""
CURVED = (1e-4, np.radians(30))
"""Angles between neighbouring faces' normals (radians) of a tessellated curved surface:
above rounding, below a feature edge."""


def stored_precision(vertices):
    """The precision coordinates were stored in: ``np.float32`` for float32 numbers (a
    binary STL's) and for text that holds them (each coordinate is its nearest float32
    written with the file's digits); the count of significant decimal digits if they
    all read back from 5 to 15 of them (OpenCASCADE's ASCII STL: 13); else
    ``np.float64`` (round numbers that need fewer digits are exact). A tilted planar
    face of a text file is flat only to its last digit, far above float64's noise.

    >>> stored_precision([[0.1, 2.5]]), stored_precision([[0.25, 2.5]]), stored_precision([[1 / 3]])
    (<class 'numpy.float64'>, <class 'numpy.float32'>, <class 'numpy.float64'>)
    >>> stored_precision([[6.290878e+00, 3.957885e-01, -1.978882e+01]])   # "%.6e"
    <class 'numpy.float32'>
    >>> stored_precision([[6.290878129645e+00, 3.957885042599e-01, 1.978881966579e+01]])
    13
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    if np.array_equal(vertices.astype(np.float32), vertices):
        return np.float32
    values = np.abs(vertices[np.isfinite(vertices)])
    values = values[values > 0]
    values = values[::max(1, len(values) // _DIGITS_SAMPLE)]

    def reads_back(digits, written):
        return all(float(f"{x:.{digits - 1}e}") == value
                   for x, value in zip(written.tolist(), values.tolist()))

    if not len(values) or not reads_back(15, values) or reads_back(4, values):
        return np.float64
    low, high = 5, 15                         # reads_back(high, values) holds throughout
    while low < high:
        middle = (low + high) // 2
        low, high = (low, middle) if reads_back(middle, values) else (middle + 1, high)
    return np.float32 if reads_back(high, values.astype(np.float32)) else high


_DIGITS_SAMPLE = 1000
"""Coordinates :func:`stored_precision` reads back at most (evenly spread)."""


def check_coordinates(vertices, faces=()) -> None:
    """Refuse vertex coordinates that cannot be meshed: NaN or infinite ones, a mesh
    beyond the scale float64 holds (:func:`pds_plugin.region.check_scale`), or ``faces``
    that all name one vertex twice (every triangle collapsed when trimesh merged the
    vertices on its 1e-8 grid).

    >>> check_coordinates([[0.0, 0.0, 0.0], [1e-300, 1e-300, 1e-300]])
    Traceback (most recent call last):
    ...
    pds_plugin.errors.SourceError: the mesh spans 1e-300 with coordinates up to 1e-300: areas and distances need an extent above 1e-50 and coordinates below 1e+50; scale it (to millimetres, say) first
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    if not np.isfinite(vertices).all():
        raise SourceError("the mesh has NaN or infinite vertex coordinates; clean the mesh "
                          "first")
    if len(vertices):
        check_scale((*vertices.min(axis=0), *vertices.max(axis=0)), "the mesh spans",
                    "scale it (to millimetres, say) first", SourceError)
    if len(faces) and needle_faces(np.asarray(faces)).all():
        raise SourceError("no triangle of the mesh is left once trimesh merges its vertices "
                          "on its 1e-8 grid (a mesh much under 1e-6 or over 1e10 across "
                          "collapses); scale it (to millimetres, say) first")


def float_noise(vertices) -> float:
    """``NOISE_ULPS`` units in the last place of the largest coordinate of ``vertices``,
    in the precision they were stored in (:func:`stored_precision`).

    >>> float_noise([[88.0, 0.5, 1.25]]), float_noise([[88.123456789012, 0.5, 1.25]])
    (0.0001220703125, 1.6e-11)
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    return float(_noise(np.abs(vertices).max(initial=0.0), stored_precision(vertices)))


def _section_precision(mesh, from_file: bool):
    """The precision of ``mesh``'s coordinates for its sections' noise: what
    :func:`stored_precision` finds, if it was read from a file or neighbouring faces
    are coplanar only up to rounding (normals apart by less than ``CURVED[0]`` but not
    0: a Trimesh read from an STL, a manifold3d solid); else float64 (a solid typed in
    with round coordinates is exact in any precision).

    >>> import trimesh
    >>> box = trimesh.creation.box()
    >>> turned = box.copy().apply_transform(trimesh.transformations.rotation_matrix(0.3, [1, 2, 3]))
    >>> turned.vertices = turned.vertices.astype(np.float32).astype(float)   # an STL export
    >>> [_section_precision(mesh, from_file).__name__ for mesh, from_file in
    ...  ((box, False), (box, True), (turned, False))]
    ['float64', 'float32', 'float32']
    """
    precision = stored_precision(mesh.vertices)
    if precision is np.float64 or from_file:
        return precision
    angle = np.asarray(mesh.face_adjacency_angles)
    return precision if np.any((angle > 0) & (angle < CURVED[0])) else np.float64


def mesh_tolerance(mesh, precision=np.float64) -> float:
    """The default tolerance of a mesh's sections: the larger of its float noise and the
    chord error of its tessellated curves.

    - Noise: ``NOISE_ULPS`` units in the last place of the largest coordinate, in the
      ``precision`` the mesh was stored in (:func:`section` gives float32 for a mesh
      whose vertices went through float32 rounding, as an STL file's did, read by
      trimesh or not, and a manifold3d solid's; the last decimal digit's unit for one
      read from text, :func:`stored_precision`).
    - Chord error: a facet of width w between neighbours whose normals turn by φ
      approximates an arc that lies up to w·tan(φ/4)/2 from it (the sagitta of a circle
      through the facet's ends, w = 2ρ sin(φ/2)); the median over the edges of curved
      surfaces (``CURVED``), w the narrower face's height over the edge. A plane through
      such a surface zigzags within about that much of the true curve; the median, not
      the largest, so that one coarse surface does not flatten the finer ones.

    Parameters
    ----------
    mesh : trimesh.Trimesh
    precision : numpy float type or int
        The precision the mesh's coordinates were stored in (an int: significant
        decimal digits).

    Returns
    -------
    float

    Examples
    --------
    >>> import trimesh
    >>> cylinder = trimesh.creation.cylinder(radius=1.0, height=2.0, sections=32)
    >>> round(mesh_tolerance(cylinder), 6)          # 1 - cos(π/32)
    0.004815
    >>> mesh_tolerance(trimesh.creation.box(), np.float32)   # flat: 16 float32 ulps of 0.5
    9.5367431640625e-07
    """
    largest = np.abs(np.asarray(mesh.vertices, dtype=np.float64)).max(initial=0.0)
    return max(float(_noise(largest, precision)), _chord_error(mesh))


def _noise(largest, precision):
    """``NOISE_ULPS`` units in the last place of the coordinates ``largest`` (a number or
    an array) in ``precision`` (a numpy float type, or a count of significant decimal
    digits: :func:`stored_precision`), as float64."""
    largest = np.asarray(largest, dtype=np.float64)
    if isinstance(precision, int):
        with np.errstate(divide="ignore"):
            unit = 10.0 ** (np.floor(np.log10(largest)) - precision + 1)
        return NOISE_ULPS * np.where(largest > 0, unit, 0.0)
    return NOISE_ULPS * np.spacing(largest.astype(precision)).astype(np.float64)


def _bodies(vertices, faces, shell, precision, chord) -> tuple:
    """Per body (shell) of a mesh: the low and high corners of its box and its float
    noise (as :func:`mesh_tolerance` counts it, from its own largest coordinate); and
    the mesh's ``chord`` error."""
    used = np.zeros(len(vertices), bool)
    used[faces.ravel()] = True
    body = np.full(len(vertices), -1)
    body[faces.ravel()] = np.repeat(shell, 3)
    order = np.flatnonzero(used)
    order = order[np.argsort(body[order], kind="stable")]
    starts = np.flatnonzero(np.r_[True, np.diff(body[order]) > 0])
    points = vertices[order]
    low = np.minimum.reduceat(points, starts, axis=0)
    high = np.maximum.reduceat(points, starts, axis=0)
    largest = np.maximum(np.abs(low), np.abs(high)).max(axis=1)
    return low, high, _noise(largest, precision), chord


def _chord_error(mesh) -> float:
    """The median sagitta over the edges of ``mesh``'s curved surfaces, 0 if it has none
    (:func:`mesh_tolerance`)."""
    angle = np.asarray(mesh.face_adjacency_angles)
    curved = (angle > CURVED[0]) & (angle < CURVED[1])
    if not curved.any():
        return 0.0
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    edge = vertices[mesh.face_adjacency_edges[curved]]
    length = np.linalg.norm(edge[:, 1] - edge[:, 0], axis=1)
    width = 2 * np.asarray(mesh.area_faces)[mesh.face_adjacency[curved]].min(axis=1) / length
    return float(np.median(width * np.tan(angle[curved] / 4) / 2))


def welded(mesh):
    """``mesh``, or, if it is open and merging its vertices closer than its float noise
    (:func:`float_noise`) closes it, a copy so merged, with a warning. An exporter that
    writes each facet's corners on its own can leave one vertex a unit in the last
    place apart in two facets: the part read as open, and every section of it was
    refused. A mesh that merging does not close, or would close only by collapsing a
    face (the noise of a stray vertex far out is larger than the part), is returned as
    it is; faces naming one vertex twice already are dropped with the merge.

    >>> import trimesh
    >>> box = trimesh.creation.box()
    >>> corners = box.vertices[box.faces].reshape(-1, 3).astype(np.float32)
    >>> corners[::2] = np.nextafter(corners[::2], np.float32(2))        # an ulp apart
    >>> soup = trimesh.Trimesh(corners, np.arange(36).reshape(-1, 3))
    >>> soup.is_watertight, welded(box) is box
    (False, True)
    >>> import warnings
    >>> with warnings.catch_warnings(record=True):
    ...     closed = welded(soup)
    >>> closed.is_watertight, len(closed.vertices)
    (True, 8)
    """
    if mesh.is_watertight:
        return mesh
    import trimesh
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    noise = float_noise(vertices)
    pairs = cKDTree(vertices).query_pairs(noise, output_type="ndarray")
    if not len(pairs):
        return mesh
    count = len(vertices)
    _, group = connected_components(coo_matrix((np.ones(len(pairs)), tuple(pairs.T)),
                                               shape=(count, count)), directed=False)
    first = np.full(group.max() + 1, count)
    np.minimum.at(first, group, np.arange(count))    # each group's first vertex stays
    faces = group[np.asarray(mesh.faces)]
    needle = needle_faces(faces)
    if np.any(needle & ~needle_faces(mesh.faces)) or needle.all():
        return mesh                 # a face would collapse: not noise (a stray vertex's)
    closed = trimesh.Trimesh(vertices[first], faces[~needle], process=False)
    if not closed.is_watertight:
        return mesh
    warnings.warn(f"the mesh is open where {count - len(first)} of its vertices lie within "
                  f"its float noise ({noise:.3g}) of others: they were "
                  f"merged, which closes it", UserWarning, stacklevel=4)
    return closed


def needle_faces(faces) -> np.ndarray:
    """Which faces (k, 3) name one vertex twice: they have no area.

    >>> needle_faces(np.array([[0, 1, 2], [3, 3, 4]])).tolist()
    [False, True]
    """
    faces = np.asarray(faces)
    return (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])


def _consistently_oriented(mesh):
    """``mesh``, or a copy whose faces agree in orientation with their neighbours and face
    out of each body, with a warning. One triangle written the wrong way round (common in
    STL exports) would otherwise turn its part of the section inside out."""
    if mesh.is_winding_consistent:
        return mesh
    import trimesh

    fixed = mesh.copy()                        # the caller's mesh is never modified
    trimesh.repair.fix_normals(fixed, multibody=True)
    warnings.warn("the mesh's faces are not consistently oriented (some triangles are "
                  "written the wrong way round); each body was re-oriented outwards before "
                  "cutting (trimesh.repair.fix_normals): a cavity drawn as an inward shell "
                  "is then read as solid", UserWarning, stacklevel=4)
    return fixed


def _unit(heights) -> float:
    """The solid's extent along the normal, rounded to a power of two (so scaling by it is
    exact): the cut runs in these units, so that trimesh's absolute tolerance for a vertex
    on the plane (``tol.merge``) is relative to the part, tiny or huge."""
    extent = float(np.ptp(heights))
    return 2.0 ** np.round(np.log2(extent)) if extent > 0 else 1.0


def _shells(faces, count) -> np.ndarray:
    """The connected component (shell) of each face, through shared vertices."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    rows = np.repeat(np.arange(len(faces)), 3)
    graph = coo_matrix((np.ones(rows.size), (rows, faces.ravel())),
                       shape=(len(faces), count)).tocsr()
    _, label = connected_components(graph @ graph.T, directed=False)
    return label


def _closing_segments(segments):
    """The segments that close a cut's open paths across the material they end in, or
    None when some path branches.

    ``segments`` (m, 2, 2) are directed with the material on their left; an open path
    runs from a point no segment ends at to one no segment starts at. Its closing
    segment runs from that end back to its start, so that the path closes the way its
    shell's material winds.

    Examples
    --------
    >>> path = np.array([[(0, 0), (1, 0)], [(1, 0), (1, 1)], [(1, 1), (0, 1)]], float)
    >>> _closing_segments(path).tolist()
    [[[0.0, 1.0], [0.0, 0.0]]]
    """
    points, index = np.unique(segments.reshape(-1, 2), axis=0, return_inverse=True)
    index = index.reshape(-1, 2)
    leaving = np.bincount(index[:, 0], minlength=len(points))
    arriving = np.bincount(index[:, 1], minlength=len(points))
    if (leaving > 1).any() or (arriving > 1).any():
        return None
    following = np.full(len(points), -1)
    following[index[:, 0]] = index[:, 1]
    closing = []
    for start in np.flatnonzero(arriving == 0):
        end = start
        while following[end] >= 0:
            end = following[end]
        closing.append((points[end], points[start]))
    return np.array(closing) if closing else None


def _snap_by_shell(segments, shell_of_segment, local, shell, faces) -> np.ndarray:
    """Join the cut points of each shell within 1e-9 of that shell's diagonal."""
    snapped = segments.copy()
    for label in np.unique(shell_of_segment):
        corners = local[faces[shell == label]].reshape(-1, 3)
        tolerance = 1e-9 * float(np.linalg.norm(np.ptp(corners, axis=0)))
        mine = shell_of_segment == label
        snapped[mine] = snap(segments[mine].reshape(-1, 2), tolerance).reshape(-1, 2, 2)
    return snapped


def _source_of(solid):
    if isinstance(solid, (str, os.PathLike)):
        return trimesh_backend
    for library, class_name, backend in _SOLIDS:
        module = sys.modules.get(library)  # a solid's library is imported already
        if module is not None and isinstance(solid, getattr(module, class_name)):
            return backend
    raise ArgumentTypeError(f"cannot cut a {type(solid).__name__}: give a trimesh.Trimesh, a "
                            f"manifold3d.Manifold, an OCP TopoDS_Shape or the path of a mesh "
                            f"or STEP file")


def _offsets(offsets, count, heights) -> np.ndarray:
    """Plane offsets along the normal, from ``offsets`` or ``count`` (exactly one)."""
    if (offsets is None) == (count is None):
        raise ArgumentError("give either offsets (distances along the normal) or count "
                         "(number of evenly spaced planes), not both and not neither")
    if count is not None:
        if check_positive_int(count, "count") > MAX_SECTIONS:
            raise BudgetError(f"count={count:,} sections is more than {MAX_SECTIONS:,}; cut "
                              f"the solid in several calls")
        low, high = heights.min(), heights.max()
        return low + (np.arange(count) + 0.5) * (high - low) / count
    try:
        offsets = np.atleast_1d(np.asarray(offsets, dtype=float))
    except (TypeError, ValueError):
        offsets = None
    if offsets is None or offsets.ndim != 1 or not len(offsets) or not np.isfinite(offsets).all():
        raise ArgumentError(f"offsets must be a non-empty list of finite numbers, got {offsets!r}")
    if len(offsets) > MAX_SECTIONS:
        raise BudgetError(f"{len(offsets):,} offsets is more than {MAX_SECTIONS:,} sections; "
                          f"cut the solid in several calls")
    return offsets
