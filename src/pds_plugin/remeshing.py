"""Remeshing CAD meshes: every planar face re-triangulated with certified triangles, the
solid kept (issue 24, docs/remesh.md).

1. **Patches**: maximal sets of edge-connected faces that lie in one plane, to the
   mesh's float noise (16 units in the last place of its largest coordinate, in float32
   for an STL file, as :func:`pds_plugin.mesh_tolerance` counts it): two neighbours join
   when the far vertex of the smaller lies within it of the larger's plane (the larger's
   normal is the accurate one; a sliver's is not), and every patch is checked against
   its area-weighted plane.
2. A patch is **remeshed** when it is at least alpha wide (area / perimeter >= alpha / 2)
   and its boundary makes a valid polygon in its plane; the others (the strips of a
   tessellated cylinder, small faces) are **kept**, split where a remeshed neighbour puts
   samples on their edges.
3. The remeshed patches are a partition (:mod:`pds_plugin.partition`): their boundary
   chains, cut at the vertices where three patches meet, where the owners change and at
   every vertex of a kept face, are sampled once, in each patch's plane the same points of
   the input's edges; each patch is meshed and certified in its plane; interior samples
   go back to 3D on the input triangle they lie in.
4. The patches' planes are laid out side by side in one plane, a gap apart that no
   radius, disc or triangle crosses (:func:`_gap`), so that the small patches are
   meshed in one call (:func:`_patch_meshes`) and their samples placed with one tree.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from shapely.geometry import MultiPolygon, Polygon

from . import _sizing_kernels
from ._checks import check_alpha, check_grading, check_positive_int, check_seed
from .errors import ArgumentError, ArgumentTypeError, PdsError
from .partition import (ATTEMPTS, Frame, Frames, InterfaceReport, agreeing_fields,
                        chain_sample_radii, fields_with_cones, graded_sample_chains,
                        interface_report, junction_fields, partition_topology, read_regions,
                        split_counts)
from .region import Region, _following, check_tolerance, simple_regions, turning_angles
from .sampling import DEFAULT_MAX_SAMPLES, LADDER_ANGLE, check_budget
from .sizing import _PAIRWISE
from .sources.solids import check_coordinates, float_noise, needle_faces, welded

if TYPE_CHECKING:
    import pymeshlab
    import trimesh

__all__ = ["remesh", "RemeshResult", "AUTO_DIVISIONS"]

AUTO_DIVISIONS = 100
"""alpha="auto" is the bounding box's diagonal over this (MeshLab's isotropic remeshing
defaults to about 1 % of it as well)."""

_VOLUME_TOL = 1e-9      # relative volume change allowed by ``ok``
_INSIDE = 1e-9          # a barycentric coordinate down to -this still puts a point in
_CHECKED_CORNER = LADDER_ANGLE  # 33.56°: spikes that rings get mirror pairs at and graded
# chains do not; a patch with a sharper corner, or with a vertex that is one of another
# patch's (:func:`_at_spikes`), is certified as it is meshed, and kept if its certificate
# does not hold

KEEP_NARROWER = 1.0
"""A patch narrower than this many alpha (twice its area over its perimeter: a strip's
width) is kept as it is; measured in docs/remesh.md ("Strips: kept or remeshed")."""

_SHARP_FACET_NARROWER = 1.5
"""A facet of a curved surface (:func:`_facets`) narrower than this many alpha with a
convex corner sharper than :data:`_CHECKED_CORNER` is kept as it is: its mesh has a
triangle that sharp at the corner anyway, and had more along it, and such patches cost a
certificate each, or a second round of chains when their chords could not join.
Measured in docs/remesh.md ("Facets with a sharp corner"): on OpenCASCADE's coarse
spheres 2-10 times faster, and fewer triangles under 10° in the whole mesh; a wider
facet kept is fanned into slivers where its neighbours sample its edges."""


@dataclass(frozen=True, eq=False)
class RemeshResult:
    """A remeshed solid and what was checked on it (:func:`remesh`).

    Attributes
    ----------
    mesh : trimesh.Trimesh
        The remeshed surface.
    patch : (M,) int64 ndarray
        Per face of ``mesh``: the planar patch it was meshed in, -1 for kept faces.
    patch_meshes : tuple of PlanarMesh
        The remeshed patches' meshes, each in its plane (its region's 2D coordinates).
    certificates : tuple of Certificate
        One per remeshed patch (its 2D certificate, in its plane), measured when first
        asked for (``ok`` asks).
    interfaces : InterfaceReport
        How the patches and the kept faces join (no T-junction, fold or duplicate).
    alpha : float
    patches, kept_patches : int
        How many planar patches were found, and how many of them were kept as they were.
    watertight : tuple of bool
        (input, output).
    euler_number : tuple of int
        (input, output).
    volume_error : float
        ``|volume(output) - volume(input)| / |volume(input)|`` (nan for an open input).
    surface_distance : float
        The largest distance from an output vertex to the input triangle it was placed
        on (samples on edges are on them by construction), absolute.
    tolerance : float
        The coplanarity tolerance the patches were found with.
    graded : bool
        Whether the patches' fields follow their features (graded), or are alpha but
        around the input's short pieces (uniform). Either way each patch is meshed with
        its field and its certificate measures against it (r).
    turned : int
        How many input faces were turned to wind like their neighbours before the
        remesh (:func:`_wound_alike`); the input above is that surface.
    dropped : int
        How many input faces naming one vertex twice (no area: a tessellated pole's, a
        blend corner's) were dropped before the remesh (:func:`_needles_dropped`); the
        input above is the surface without them.
    welded : int
        How many input vertices were merged into others within the float noise, which
        closed an open input (:func:`pds_plugin.sources.solids.welded`); the input above
        is the closed one.
    """

    mesh: "trimesh.Trimesh"
    patch: np.ndarray
    patch_meshes: tuple
    interfaces: InterfaceReport
    alpha: float
    patches: int
    kept_patches: int
    watertight: tuple
    euler_number: tuple
    volume_error: float
    surface_distance: float
    tolerance: float
    graded: bool = False
    turned: int = 0
    dropped: int = 0
    welded: int = 0

    @cached_property
    def certificates(self) -> tuple:
        """The patches' certificates (:meth:`PlanarMesh.certificate`)."""
        return tuple(mesh.certificate() for mesh in self.patch_meshes)

    @property
    def solid_ok(self) -> bool:
        """Watertightness and Euler number kept, volume to 1e-9, joins clean, vertices on
        the input to its tolerance."""
        volume = not self.watertight[0] or self.volume_error <= _VOLUME_TOL
        return (self.interfaces.ok and self.watertight[1] == self.watertight[0]
                and self.euler_number[1] == self.euler_number[0] and volume
                and self.surface_distance <= self.tolerance)

    @property
    def ok(self) -> bool:
        """The solid is kept and every patch certificate is ``ok``."""
        return self.solid_ok and all(c.ok for c in self.certificates)

    @property
    def ok_with_exceptions(self) -> bool:
        """The solid is kept and every patch certificate is ``ok_with_exceptions``
        (triangles below 30° only at small features of the patch, within their bounds)."""
        return self.solid_ok and all(c.ok_with_exceptions for c in self.certificates)

    def angles(self, remeshed_only: bool = True) -> np.ndarray:
        """The smallest angle of each (remeshed) triangle, in degrees."""
        faces = self.mesh.faces[self.patch >= 0] if remeshed_only else self.mesh.faces
        return _min_angles(self.mesh.vertices, faces)

    def to_meshset(self) -> "pymeshlab.MeshSet":
        """A ``pymeshlab.MeshSet`` holding the remeshed surface; face quality is the
        patch index (-1 for kept faces)."""
        from ._checks import import_optional
        pymeshlab = import_optional("pymeshlab", "meshlab", "to_meshset")
        meshset = pymeshlab.MeshSet()
        meshset.add_mesh(pymeshlab.Mesh(vertex_matrix=np.asarray(self.mesh.vertices, float),
                                        face_matrix=np.asarray(self.mesh.faces, np.int32),
                                        f_scalar_array=self.patch.astype(float)), "pds remesh")
        return meshset

    def as_dict(self) -> dict:
        """Plain JSON-ready values (each patch's certificate by index)."""
        angles = self.angles()
        return {"alpha": self.alpha, "graded": self.graded, "vertices": len(self.mesh.vertices),
                "faces": len(self.mesh.faces), "patches": self.patches,
                "kept_patches": self.kept_patches, "watertight": list(self.watertight),
                "euler_number": list(self.euler_number), "volume_error": self.volume_error,
                "surface_distance": self.surface_distance, "tolerance": self.tolerance,
                "turned": self.turned, "dropped": self.dropped, "welded": self.welded,
                "min_angle_remeshed": float(angles.min(initial=180.0)),
                "angle_p1_remeshed": float(np.percentile(angles, 1)) if len(angles) else None,
                "interfaces": self.interfaces.as_dict(),
                "certificates": [c.as_dict() for c in self.certificates],
                "solid_ok": self.solid_ok, "ok": self.ok,
                "ok_with_exceptions": self.ok_with_exceptions}

    def __str__(self) -> str:
        verdict = ("ok" if self.ok else "ok with exceptions" if self.ok_with_exceptions
                   else "FAILED")
        angles = self.angles()
        failed = sum(not c.ok_with_exceptions for c in self.certificates)
        lines = [f"remesh {verdict}: {len(self.mesh.faces)} triangles, "
                 f"{'graded, largest radius' if self.graded else 'alpha'} {self.alpha:.6g}, "
                 f"{len(self.certificates)} patches remeshed, {self.kept_patches} kept",
                 f"  watertight {self.watertight[0]} -> {self.watertight[1]}, Euler "
                 f"{self.euler_number[0]} -> {self.euler_number[1]}, volume error "
                 f"{self.volume_error:.3g}, vertices on the input to {self.surface_distance:.3g}",
                 f"  remeshed triangles: min angle {angles.min(initial=180.0):.2f}°, 1st "
                 f"percentile {np.percentile(angles, 1) if len(angles) else float('nan'):.2f}°",
                 f"  interfaces {'ok' if self.interfaces.ok else 'FAILED'}"
                 + (f" ({self.interfaces.inherited_edges} non-manifold edge(s) of the input "
                    f"kept as they were)" if self.interfaces.inherited_edges else "")
                 + f"; patch certificates failed: {failed}"]
        lines += [f"    {problem}" for problem in self.interfaces.problems]
        if self.welded:
            lines.append(f"  input: {self.welded} vertices within the float noise of others "
                         f"merged first (it was open there)")
        if self.dropped:
            lines.append(f"  input: {self.dropped} face(s) naming one vertex twice (no "
                         f"area) dropped first")
        if self.turned:
            lines.append(f"  input: {self.turned} face(s) wound against their neighbours "
                         f"turned first (each body outward)")
        return "\n".join(lines)


def remesh(mesh, alpha="auto", *, graded: bool = True, grading: float | None = None,
           seed: int = 0, feature_angle: float = 30.0, tolerance: float | None = None,
           max_samples: int | None = None) -> RemeshResult:
    """Re-triangulate every planar face of a mesh with certified triangles, keeping the
    solid: same surface on its planar faces, same edges, no T-junction.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str or os.PathLike, or pymeshlab.MeshSet
        The mesh (its current mesh for a MeshSet); never modified.
    alpha : float or "auto"
        The disc radius in the mesh's units; "auto" is the bounding box's diagonal /
        :data:`AUTO_DIVISIONS`. Graded: the largest radius.
    graded : bool
        Graded patches (the default): each patch's radius field r <= alpha follows its
        walls, holes and corners (:func:`pds_plugin.sizing.radius_field`) and the
        spacing of the samples its boundary must keep (vertices of kept faces), so the
        triangles grow from small features instead of meeting them at alpha; every
        angle is then at least arcsin((1 - L)/2) (23.6° at L = 0.2) but at sharp input
        corners. A facet of a tessellated curved surface (convex, half its boundary on
        folds turning by less than ``feature_angle``) is meshed as uniform: its walls
        and corners are the tessellation's, not the part's (docs/remesh.md, "Facets").
        ``False`` (uniform): r = alpha everywhere but where the input forces
        boundary pieces shorter than alpha (vertices of kept faces, short edges between
        patches): there r is the piece's length and grows away from it at rate L, the
        same bound, no thin triangle at the short pieces; a patch with a wall thinner
        than alpha or a spike sharper than the bound takes its graded field
        (docs/remesh.md, "Uniform").
    grading : float, optional
        The Lipschitz constant L of the fields (graded) or of the cones around short
        pieces (uniform), in (0, 1); default :data:`pds_plugin.sizing.DEFAULT_GRADING`.
    seed : int
        The same seed gives the same mesh, bit for bit.
    feature_angle : float
        Patch boundary vertices turning by at least this many degrees are corners;
        patches whose normals turn by less meet at a fold (graded: facets).
    tolerance : float, optional
        Coplanarity tolerance (absolute); default 16 units in the last place of the
        largest coordinate, in float32 if every vertex is a float32 number (a binary
        STL), in the last decimal digit if every coordinate reads back from 5-15
        significant digits (a text file), else in float64
        (:func:`pds_plugin.sources.solids.float_noise`).
    max_samples : int, optional
        The sample budget of each patch.

    Returns
    -------
    RemeshResult

    Raises
    ------
    ArgumentError, ArgumentTypeError
        For a bad alpha or mesh.
    SourceError
        If the mesh file cannot be read or has no triangles, a vertex has NaN or
        infinite coordinates, or the mesh is too small or too large to hold
        (:func:`pds_plugin.sources.solids.check_coordinates`).
    BudgetError
        If ``alpha`` would make more than ``max_samples`` samples in a patch (said before
        anything is meshed, with the smallest alpha the budget allows).

    Examples
    --------
    >>> import trimesh, pds_plugin as pds
    >>> result = pds.remesh(trimesh.creation.box((2, 1, 1)), 0.2)
    >>> result.ok, result.watertight, result.volume_error < 1e-12
    (True, (True, True), True)
    >>> bool(result.angles().min() >= 23.5)
    True
    >>> uniform = pds.remesh(trimesh.creation.box((2, 1, 1)), 0.2, graded=False)
    >>> uniform.ok, bool(uniform.angles().min() >= 30)
    (True, True)
    >>> {float(m.field(m.vertices).min()) for m in uniform.patch_meshes}   # r = alpha
    {0.2}
    """
    read = _as_trimesh(mesh)
    dropped = _needles_dropped(read)
    source = welded(read)
    merged = len(read.vertices) - len(source.vertices)
    turned = _wound_alike(source)
    check_seed(seed)
    vertices = np.asarray(source.vertices, dtype=np.float64)
    faces = np.asarray(source.faces, dtype=np.int64)
    diagonal = float(np.linalg.norm(np.ptp(vertices, axis=0)))
    if isinstance(alpha, str):
        if alpha != "auto":
            raise ArgumentError(f"alpha must be a positive number or 'auto', got {alpha!r}")
        alpha = diagonal / AUTO_DIVISIONS
    alpha = check_alpha(alpha)
    if tolerance is None:
        tolerance = float_noise(vertices)
    tolerance = check_tolerance(tolerance)
    normals = np.asarray(source.face_normals, dtype=np.float64)
    areas = np.asarray(source.area_faces, dtype=np.float64)
    label = _coplanar_patches(source, vertices, faces, normals, areas, tolerance)
    from .sizing import (DEFAULT_GRADING, RadiusField, angle_bound, radius_field,
                         radius_fields)
    grading = check_grading(DEFAULT_GRADING if grading is None else grading)
    patches = _usable_patches(vertices, faces, normals, areas, label, alpha,
                              _gap(alpha, grading))
    remeshed = _manifold_patches([p for p in patches if p is not None])
    facet = (dict(zip(map(id, remeshed), _facets(remeshed, vertices, faces, normals,
                                                 feature_angle).tolist())) if remeshed else {})
    # a narrow facet of a curved surface with a convex corner sharper than
    # _CHECKED_CORNER is kept (_SHARP_FACET_NARROWER)
    remeshed = [p for p in remeshed
                if not (facet[id(p)] and _sharpest_corner(p) < _CHECKED_CORNER
                        and 2 * p.region.area < _SHARP_FACET_NARROWER * alpha
                        * p.region.perimeter)]
    options = {"feature_angle": feature_angle}
    if max_samples is not None:
        options["max_samples"] = check_positive_int(max_samples, "max_samples")
    if remeshed:                    # an alpha far too small, refused before any field
        check_budget(max((p.region for p in remeshed), key=lambda region: region.area),
                     alpha, options.get("max_samples", DEFAULT_MAX_SAMPLES))
    flat = RadiusField(np.zeros((0, 2)), [], grading, alpha)
    # uniform: every patch at alpha, graded: the facets of tessellated curved surfaces
    # (their walls and corners are the tessellation's, not the part's: _facets); alpha
    # is lowered where the input forces shorter pieces (the cones junction_fields and
    # the agreement add), and a patch whose mesh then has thinner walls or sharper spikes
    # than a uniform radius can shape takes its graded field (_graded_instead), one with
    # a convex corner sharper than the bound from the start (a triangle below it,
    # whatever the mesh) (docs/remesh.md, "Uniform" and "Facets")
    spiked = math.radians(angle_bound(grading))
    uniform = remeshed if not graded else [p for p in remeshed if facet[id(p)]]
    at_alpha = {id(p) for p in uniform if _sharpest_corner(p) >= spiked}
    shaped = [p for p in remeshed if id(p) not in at_alpha]
    # the small patches' fields measured together (the same fields, a few dozen numpy
    # calls a patch fewer: they lie a gap apart, sizing.radius_fields), the large ones
    # one by one (together, every round would measure all of them again)
    small = [p for p in shaped if p.region.area <= SMALL_PATCH * alpha ** 2]
    fields = dict(zip(map(id, small), radius_fields([p.region for p in small], grading,
                                                     alpha, feature_angle)))
    fields.update({id(p): flat if id(p) in at_alpha else
                   radius_field(p.region, grading, alpha, feature_angle=feature_angle)
                   for p in remeshed if id(p) not in fields})
    cache, topology = {}, None
    while True:
        if topology is None:                # the first round, or patches kept since
            kept = np.ones(len(faces), bool)
            for patch in remeshed:
                kept[patch.faces] = False
            on_kept = np.zeros(len(vertices), bool)
            on_kept[faces[kept].ravel()] = True
            rings, frames = [p.rings for p in remeshed], Frames(p.frame for p in remeshed)
            pinned = np.flatnonzero(on_kept).tolist()
            # the chains found once for the four steps (and again only when patches are
            # kept), the patches' fields read in one call (they lie apart in one plane)
            topology = partition_topology(rings, frames, pinned)
        own = junction_fields(rings, frames, [fields[id(p)] for p in remeshed], pinned,
                              topology=topology)
        own = agreeing_fields(rings, frames, own, pinned, topology=topology)
        chains = graded_sample_chains(rings, frames, own, feature_angle=feature_angle,
                                      seed=seed, pinned=pinned, topology=topology)
        # each patch's ring samples in its plane, computed once for both steps below
        given = _ring_samples(chains, frames)
        ring_points = [points for _, points, _, _ in given]
        sizes, coned = _agreeing_sizes(chains, frames, own,
                                       chain_sample_radii(chains, frames, own,
                                                          topology=topology,
                                                          points=ring_points),
                                       topology, ring_points)
        # a patch with a chord longer than any edge of its complex (a strip about 2 alpha
        # wide at a spike) would not join its neighbours whatever is drawn inside: it is
        # kept before any patch is meshed, and the chains sampled again without it
        joinable = _chords_joinable(given, coned)
        # a patch at alpha with a wall thinner than alpha (most seen across its samples
        # before it is meshed, in the same round as the chords that cannot join; a
        # graded remesh's patches at alpha are facets, convex and at least alpha wide)
        # or a spike sharper than the bound (exceptions in its mesh) takes its graded
        # field
        beyond = [] if graded else _thin_walled(
            [patch for patch, ok in zip(remeshed, joinable) if ok],
            [samples for samples, ok in zip(given, joinable) if ok], sizes, fields, flat)
        if all(joinable) and not beyond:
            meshes = _patch_meshes(remeshed, chains, seed, options, cache, own, sizes,
                                   coned, given)
            beyond = _graded_instead(remeshed, meshes, fields, flat, angle_bound(grading))
        fields.update({id(p): radius_field(p.region, grading, alpha,
                                           feature_angle=feature_angle) for p in beyond})
        if not all(joinable):
            remeshed = [patch for patch, ok in zip(remeshed, joinable) if ok]
            topology = None
            continue
        if beyond:
            continue
        # a patch whose mesh does not join all its chords is kept instead, and the
        # chains sampled again without it; so is a patch with a corner sharper than
        # 33.56° whose certificate does not hold (a spike where three faces meet: its
        # legs' samples closer than the clearance)
        joined = [mesh is not None and (not spiked or mesh.certificate().ok_with_exceptions)
                  for spiked, mesh in zip(_at_spikes(remeshed), meshes)]
        if all(joined):
            # patches whose volume change no move within the tolerance undoes (a bent
            # quad of a float32 export, with no interior point) are kept, likewise
            result, unkept = _assemble(source, vertices, faces, kept, remeshed, meshes,
                                       chains, tolerance, len(patches), alpha, graded)
            if not unkept:
                return replace(result, turned=turned, dropped=dropped, welded=merged)
            joined = [id(patch) not in unkept for patch in remeshed]
        remeshed = [patch for patch, ok in zip(remeshed, joined) if ok]
        topology = None


def _gap(alpha, grading) -> float:
    """How far apart the patches' places in the one plane of :func:`_layout` are (their
    bounding boxes): 1.25 alpha times the largest of 1 / L, 2 / (1 - L) and 2.5.

    Every radius is at most alpha (the fields' cap). A cone s + L d of another patch's
    feature (s > 0, in that patch's box) is at least L x gap >= 1.25 alpha there, over
    the cap: the union of the fields meshed in one call (:func:`_meshed_together`) reads
    on each patch exactly what the patch's own field reads. A disc (radius <= alpha), a
    chord's lens (within min r / (1 - L) of the chord) and a triangle of the complex
    (circumradius within r / (1 - L) of its corners) stay within 2 alpha / (1 - L) of
    their patch: none reaches another (docs/remesh.md, "Small patches in one call")."""
    return 1.25 * alpha * max(1.0 / grading, 2.0 / (1.0 - grading), 2.5)


SMALL_PATCH = 1000.0
"""Patches of at most this many alpha² are meshed with other small ones in one call
(:func:`_patch_meshes`, :func:`_groups`: up to this much area a call): their fixed
costs (the sampler's set-up, its bins, the complex) are paid once a group. Larger
patches are meshed one by one: in one call with small ones they would share one bin
grid, sized by the whole layout's box, too coarse for the small ones' radii (measured
in docs/remesh.md)."""


def _groups(todo, patches, alpha) -> list:
    """The patches to mesh (``todo``: (index, key, samples)) in the groups meshed by one
    call each: the small ones in order, a group closed when their areas add up to over
    :data:`SMALL_PATCH` alpha² (so that one call holds no more samples, nor cocircular
    ties for the complex's exact test, than a large patch's), then each large one."""
    limit = SMALL_PATCH * alpha ** 2
    groups, area, large = [[]], 0.0, []
    for item in todo:
        size = patches[item[0]].region.area
        if size > limit:
            large.append([item])
            continue
        if area + size > limit and groups[-1]:
            groups.append([])
            area = 0.0
        groups[-1].append(item)
        area += size
    return [group for group in groups if group] + large


def _ring_samples(chains, frames) -> list:
    """Per patch, its chain samples: their indices (its rings' in turn), their points in
    its plane (its frame of ``frames``), the rings' sample counts, and the points ring by
    ring (views, every patch's rings cut in one pass)."""
    points = chains.regions_points(frames)
    counts = [[len(ring) for ring in rings] for rings in chains.rings]
    rings = split_counts(np.concatenate([np.zeros((0, 2)), *points]),
                         [count for ring_counts in counts for count in ring_counts])
    ends = np.cumsum([len(ring_counts) for ring_counts in counts]).tolist()
    return [(ids, xy, ring_counts, rings[end - len(ring_counts):end]) for ids, xy, ring_counts, end
            in zip(chains.region_samples, points, counts, ends)]


def _patch_meshes(patches, chains, seed, options, cache, own, sizes, coned,
                  samples=None) -> list:
    """The mesh of each patch with its chains' samples, or None if its boundary edges
    are not exactly the chords between them (it would not join its neighbours) with any
    of the interiors drawn (``partition.ATTEMPTS`` seeds). Each patch is meshed with
    ``coned[k]``, its own field ``own[k]`` combined with cones of ``sizes`` at its chain
    samples (:func:`pds_plugin.partition.chain_sample_radii`), so that it reads the
    radius its neighbours read at their shared samples (:func:`_agreeing_sizes`).

    The patches lie in one plane, far apart (:func:`_layout`): all those to mesh are
    sampled and triangulated in one call, as one region of many components with one
    field (the union of their cones), and cut apart again (:func:`_meshed_together`).
    ``cache`` keeps the meshes by patch and samples: a patch whose samples did not
    change when another was dropped is not meshed again (the same mesh, bit for bit).
    ``samples``: per patch, :func:`_ring_samples` (computed here if not given)."""
    if samples is None:
        samples = _ring_samples(chains, [patch.frame for patch in patches])
    out, todo = [None] * len(patches), []
    for k, patch in enumerate(patches):
        ids, points, _, given = samples[k]
        key = (id(patch), points.tobytes(),                  # its rings' samples in turn
               own[k].sizes.tobytes() + sizes[ids].tobytes())
        if key in cache:
            out[k] = cache[key]
        else:
            todo.append((k, key, given))
    for attempt in range(ATTEMPTS):
        if not todo:
            break
        # a patch that is an exact translate of another to mesh (its region, samples and
        # field: a CAD part's repeated faces) gets that one's mesh, translated
        todo, copies = _translates(todo, patches, coned)
        groups = _groups(todo, patches, coned[0].cap)
        meshes = []
        for group in groups:
            meshes += _meshed_together([patches[k] for k, _, _ in group],
                                       [g for _, _, g in group],
                                       [coned[k] for k, _, _ in group], seed + attempt, options)
        left, made = [], {}
        for (k, key, given), (mesh, joined) in zip([item for group in groups for item in group],
                                                   meshes):
            made[k] = mesh
            if joined:
                out[k] = cache[key] = mesh
            else:
                left.append((k, key, given))
        for (k, key, given), source, turns, shift, rolls in copies:
            mesh, joined = made[source], False
            if mesh is not None:
                mesh = _translated(mesh, turns, shift, given, patches[k], coned[k], rolls)
                if mesh is None:                # not exact: meshed by itself
                    mesh, joined = _meshed_together([patches[k]], [given], [coned[k]],
                                                    seed + attempt, options)[0]
                else:
                    joined = _joined(mesh, given)
            if joined:
                out[k] = cache[key] = mesh
            else:
                left.append((k, key, given))
        todo = left
    for _, key, _ in todo:
        cache[key] = None
    return out


def _translates(todo, patches, fields) -> tuple:
    """``todo`` split into the patches to mesh and the copies: (item, the patch whose
    mesh it takes, the quarter turns q, the shift d, the rolls) for each patch that is a
    copy of an earlier one to mesh, turned by q quarter turns and moved by d: a CAD
    part's repeated faces (a patch's frame starts at an edge of its own, so their copies
    are turned by quarter turns in the plane). Its region's rings, its given samples and
    its field's features are that one's turned (exact: swaps and signs) plus d, in the
    same order, to :data:`_COPY_TOLERANCE` alpha, and its field's sizes to that
    relative: a float32 export's copies differ by its rounding, and the samples are
    points of input edges computed in each patch's own frame. The rolls are None then.

    A patch that is no such copy of any earlier one may still be one whose rings start
    at another vertex (7_8ths_cube's L-shaped faces: the same shape a quarter turn
    apart, each ring starting at the first edge of its own): its rings, its given
    samples per ring, rolled (the rolls, one per ring, in given samples), and its
    field's features as a set with their sizes (:func:`_rolled`).

    This only picks the candidates: a copy's mesh is kept only if its own certificate
    holds (:func:`_translated`). Patches under :data:`COPY_AREA` alpha² are meshed."""
    keep, copies, shapes, given_of = [], [], {}, {}
    for item in todo:
        k, _, given = item
        patch, field = patches[k], fields[k]
        if (field.sizing is not None or not len(given) or not len(given[0])
                or patch.region.area < COPY_AREA * field.cap ** 2):
            keep.append(item)
            continue
        rings = patch.region.rings
        shape = (tuple(len(ring) for ring in rings), tuple(len(ring) for ring in given),
                 len(field.sizes), field.grading, field.cap)
        found = None
        tolerance = _COPY_TOLERANCE * field.cap

        def near(a, b, turns, shift):
            return bool(np.all(np.abs(_turned(a, turns) + shift - b) <= tolerance))

        for j in shapes.get(shape, ()):
            if not np.all(np.abs(fields[j].sizes - field.sizes) <= _COPY_TOLERANCE * field.sizes):
                continue
            for turns in range(4):
                shift = rings[0][0] - _turned(patches[j].region.rings[0][:1], turns)[0]
                if (all(near(a, b, turns, shift) for a, b in zip(patches[j].region.rings, rings))
                        and all(near(a, b, turns, shift) for a, b in zip(given_of[j], given))
                        and near(fields[j].features, field.features, turns, shift)):
                    found = (j, turns, shift, None)
                    break
            if found is not None:
                break
        for j in shapes.get(shape, ()) if found is None else ():
            found = _rolled(patches[j], given_of[j], fields[j], patch, given, field, tolerance)
            if found is not None:
                found = (j, *found)
                break
        if found is None:
            shapes.setdefault(shape, []).append(k)
            given_of[k] = given
            keep.append(item)
        else:
            copies.append((item, *found))
    return keep, copies


def _rolled(source, source_given, source_field, patch, given, field, tolerance):
    """(quarter turns, shift, rolls) that put ``source``'s rings, given samples and
    field onto ``patch``'s, each ring rolled to start where the patch's starts (rolls:
    per ring, the given sample of ``source`` that becomes the patch's first), the
    field's features matched as a set with their sizes; or None (:func:`_translates`)."""
    from scipy.spatial import cKDTree

    rings = patch.region.rings
    first = rings[0][1] - rings[0][0]                  # the patch's first edge
    for turns in range(4):
        turned = [_turned(ring, turns) for ring in source.region.rings]
        outer = turned[0]
        # the starts whose edge is the patch's first, to three times the tolerance (a
        # start whose ring matches has it to twice, and rounding); each such start's
        # ring checked whole: a ring's length of work a turn, not its square
        step = np.r_[outer[1:], outer[:1]] - outer
        for start in np.flatnonzero(np.all(np.abs(step - first) <= 3 * tolerance,
                                           axis=1)).tolist():
            shift = rings[0][0] - outer[start]
            if not np.all(np.abs(np.roll(outer, -start, axis=0) + shift - rings[0])
                          <= tolerance):
                continue
            starts, rolls = [start], []
            for a, b in zip(turned[1:], rings[1:]):      # the holes' starts, by the shift
                at = int(np.argmin(np.abs(a + shift - b[0]).max(axis=1)))
                starts.append(at)
            ok = True
            for a, b, at in zip(turned[1:], rings[1:], starts[1:]):
                if not np.all(np.abs(np.roll(a, -at, axis=0) + shift - b) <= tolerance):
                    ok = False
                    break
            if not ok:
                continue
            for ring, a, b, at in zip(source.region.rings, source_given, given, starts):
                moved = _turned(a, turns) + shift
                roll = int(np.argmin(np.abs(a - ring[at]).max(axis=1)))
                if not np.all(np.abs(np.roll(moved, -roll, axis=0) - b) <= tolerance):
                    ok = False
                    break
                rolls.append(roll)
            if not ok:
                continue
            features = _turned(source_field.features, turns) + shift
            if len(features):
                distance, which = cKDTree(features).query(field.features)
                if not (np.all(distance <= tolerance)
                        and len(np.unique(which)) == len(which)
                        and np.all(np.abs(source_field.sizes[which] - field.sizes)
                                   <= _COPY_TOLERANCE * field.sizes)):
                    continue
            return turns, shift, rolls
    return None


COPY_AREA = 250.0
"""Patches of at least this many alpha² are copied (:func:`_translates`); a smaller
one costs less meshed (in a group: 10-15 µs a vertex, about 0.75 vertices an alpha²)
than its copy's certificate (about 1.3 ms and 2.2 µs a vertex, measured on
g-block-pockets' and featuretype's copies: 82 and 120 vertices, 1.6 and 2.6 ms)."""

_COPY_TOLERANCE = 1e-4
"""How far (times alpha; relative for the field's sizes) a copy's coordinates may lie
from the turned and moved ones of the patch it copies (:func:`_translates`)."""


def _turned(xy, turns) -> np.ndarray:
    """Points (n, 2) turned by ``turns`` quarter turns counterclockwise about the
    origin: exact (swaps and signs)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    turns %= 4
    if turns == 0:
        return xy
    if turns == 1:
        return np.column_stack([-xy[:, 1], xy[:, 0]])
    if turns == 2:
        return -xy
    return np.column_stack([xy[:, 1], -xy[:, 0]])


def _translated(mesh, turns, shift, given, patch, field, rolls=None):
    """``mesh`` turned by ``turns`` quarter turns and moved by ``shift`` onto ``patch``,
    its first vertices replaced by the patch's own given ring samples ``given`` (the
    same up to rounding; with ``rolls``, each ring's given samples of ``mesh`` rolled to
    start at its roll, the vertices renumbered), with the patch's region and field;
    None unless its certificate holds (``ok_with_exceptions``, as a patch at a spike is
    checked)."""
    from .mesh import PlanarMesh

    faces, on_boundary, points = mesh.faces, mesh.on_boundary, mesh.vertices
    n = sum(len(ring) for ring in given)
    if rolls is not None and any(rolls):
        sizes = [len(ring) for ring in given]
        first = np.cumsum([0] + sizes[:-1])
        old = np.arange(len(points))                 # the mesh's vertex at each new place
        old[:n] = np.concatenate([start + (np.arange(size) + roll) % size
                                  for start, size, roll in zip(first, sizes, rolls)])
        new = np.empty_like(old)
        new[old] = np.arange(len(old))
        points, on_boundary, faces = points[old], on_boundary[old], new[faces]
    points = _turned(points, turns) + shift
    points[:n] = np.concatenate(given)
    if not shapely.contains_xy(patch.region.geometry, points[n:, 0], points[n:, 1]).all():
        return None
    copy = PlanarMesh(points, faces, on_boundary, patch.region, field.cap, True,
                      field=field)
    if faces is mesh.faces and "_edges" in mesh.__dict__:
        # the same triangles: its edges are the mesh's (found by _joined), not found again
        copy.__dict__["_edges"] = mesh.__dict__["_edges"]
    return copy if copy.certificate().ok_with_exceptions else None


def _joined(mesh, given) -> bool:
    """Are the boundary edges of a patch's mesh exactly the chords between its
    ``given`` ring samples (as :func:`pds_plugin.partition.mesh_part` checks), the given
    samples its first vertices?"""
    following = _following([len(ring) for ring in given])
    boundary = mesh.boundary_edges
    if len(boundary) != len(following):
        return False
    n = len(mesh.vertices)
    chords = np.arange(len(following)) * n + following
    return np.array_equal(np.sort(boundary[:, 0] * n + boundary[:, 1]), chords)


def _meshed_together(patches, given, fields, seed, options) -> list:
    """The graded meshes of ``patches`` (regions a gap apart in one plane, :func:`_gap`)
    with their ring samples ``given`` and ``fields``, sampled and triangulated in one
    call (one region of many components, the union of the fields' cones) and cut apart
    by where their vertices lie (:func:`_cut_apart`), each with whether it joins its
    given samples (:func:`_joined`). Each mesh is the patch's own: its
    region, its field (which reads on the patch what the union read there), its given
    samples first. A patch alone, patches whose call fails (a budget) or whose fields'
    features do not lie in their boxes (the gap's premise), and a patch that a triangle
    would join to another (the gap excludes it) are meshed each by itself."""
    from .graded_complex import graded_alpha_complex
    from .graded_sampling import graded_poisson_disc
    from .mesh import PlanarMesh
    from .sizing import RadiusField

    out = [None] * len(patches)
    first = fields[0]
    boxes = shapely.bounds([patch.region.geometry for patch in patches])   # (x0, y0, x1, y1)
    if len(patches) > 1 and _features_inside(boxes, fields) and all(
            f.grading == first.grading and f.cap == first.cap and f.sizing is None
            for f in fields):
        budget = options.get("max_samples", DEFAULT_MAX_SAMPLES) * len(patches)
        region = Region(MultiPolygon([polygon for patch in patches
                                      for polygon in patch.region.geometry.geoms]), np.eye(4))
        union = RadiusField(np.concatenate([f.features for f in fields]),
                            np.concatenate([f.sizes for f in fields]), first.grading, first.cap)
        try:
            samples = graded_poisson_disc(region, union, seed,
                                          boundary_samples=[r for g in given for r in g],
                                          tile=True, **{**options, "max_samples": budget})
        except PdsError:
            samples = None
        if samples is not None:
            try:
                faces = graded_alpha_complex(samples.points, samples.radius, union.grading,
                                             boundary=samples.rings, chords=samples.chords)
            except PdsError:
                faces = None
            if faces is not None:
                out = _cut_apart(patches, boxes, given, fields, samples, faces)
    for k, (patch, rings, field) in enumerate(zip(patches, given, fields)):
        if out[k] is None:
            samples = graded_poisson_disc(patch.region, field, seed, boundary_samples=rings,
                                          tile=True, **options)
            faces = graded_alpha_complex(samples.points, samples.radius, field.grading,
                                         boundary=samples.rings, chords=samples.chords)
            mesh = PlanarMesh(samples.points, faces, samples.on_boundary, patch.region,
                              field.cap, True, field=field)
            out[k] = mesh, _joined(mesh, rings)
    return out


def _features_inside(boxes, fields) -> bool:
    """Does every feature of each field lie in its patch's bounding box (``boxes``: (x0,
    y0, x1, y1) rows), so that a whole gap lies between it and every other patch? All
    patches at once."""
    features = np.concatenate([np.zeros((0, 2)), *(field.features for field in fields)])
    box = boxes[np.repeat(np.arange(len(fields)), [len(field.features) for field in fields])]
    return bool(((features >= box[:, :2]) & (features <= box[:, 2:])).all())


def _cut_apart(patches, boxes, given, fields, samples, faces) -> list:
    """Per patch, its part of a mesh of them all (:func:`_meshed_together`): the samples
    in its bounding box (``boxes``; they are a gap apart), its given ring samples first, and
    whether it joins them (:func:`_joined`, for all patches at once); None for a patch
    with a triangle across two boxes (none can be: the gap)."""
    from ._mesh_kernels import edges_of
    from .mesh import PlanarMesh

    points, count = samples.points, len(samples.points)
    n_given = np.array([sum(len(ring) for ring in rings) for rings in given], np.int64)
    first = np.cumsum(np.append(0, n_given))
    owner = np.full(count, -1, np.int64)
    owner[:first[-1]] = np.repeat(np.arange(len(patches)), n_given)
    inner = np.arange(first[-1], count)
    if len(inner):                  # the box each interior sample lies in (boundary too)
        at, box = shapely.STRtree(shapely.box(*boxes.T)).query(shapely.points(points[inner]),
                                               predicate="intersects")
        owner[inner[at]] = box
    order = np.argsort(owner[first[-1]:], kind="stable") + first[-1]   # interiors by patch
    inner_start = np.searchsorted(owner[order], np.arange(len(patches) + 1))
    # each sample's number in its patch's mesh: its given samples, then its interior
    number = np.full(count, -1, np.int64)
    number[:first[-1]] = np.arange(first[-1]) - np.repeat(first[:-1], n_given)
    patch_of = owner[order]
    placed = patch_of >= 0
    number[order[placed]] = (np.arange(len(order)) - inner_start[patch_of]
                             + n_given[patch_of])[placed]
    face_owner = owner[faces]
    across = (face_owner != face_owner[:, :1]).any(axis=1) | (face_owner[:, 0] < 0)
    bad = set(face_owner[across].ravel().tolist())
    by_owner = np.argsort(face_owner[:, 0], kind="stable")
    face_start = np.searchsorted(face_owner[by_owner, 0], np.arange(len(patches) + 1))
    # a patch that no triangle crosses from another has the same edges, used as often,
    # in the whole mesh as in its own: it joins if its boundary edges there are its
    # chords, its given samples in turn
    edges, uses = edges_of(faces, count)
    boundary = edges[uses == 1]
    boundary = boundary[owner[boundary[:, 0]] >= 0]
    chords = np.arange(first[-1]) * count + _following([len(ring) for rings in given
                                                        for ring in rings])
    missed = ~np.isin(chords, boundary[:, 0] * count + boundary[:, 1])
    joined = ((np.bincount(owner[boundary[:, 0]], minlength=len(patches)) == n_given)
              & (np.bincount(owner[:first[-1]][missed], minlength=len(patches)) == 0))
    # every patch's points, flags and triangles as consecutive rows of one array each
    by_patch = np.lexsort((number, owner))
    by_patch = by_patch[owner[by_patch] >= 0]
    vertex_start = np.searchsorted(owner[by_patch], np.arange(len(patches) + 1))
    xy, on_boundary = points[by_patch], number[by_patch] < n_given[owner[by_patch]]
    triangles = number[faces[by_owner]]
    out = []
    for k, (patch, field) in enumerate(zip(patches, fields)):
        if k in bad:
            out.append(None)
            continue
        rows = slice(vertex_start[k], vertex_start[k + 1])
        out.append((PlanarMesh._made(xy[rows], triangles[face_start[k]:face_start[k + 1]],
                                     on_boundary[rows], patch.region, field.cap, True, field),
                    bool(joined[k])))
    return out


def _agreeing_sizes(chains, frames, fields, sizes, topology=None, points=None):
    """The chain samples' radii ``sizes`` lowered until every patch's field with its
    cones (:func:`_patch_mesh`) reads them at its own samples: at a sample s, the
    smallest of its patches' fields combined with cones of ``sizes`` at their samples,
    again until none is lower (to rounding). A cone of a patch's sample whose r another
    patch lowered (a neighbour's finer field, a pair made apart) can reach the patch's
    samples on other chains, which the patches beyond them do not see;
    :func:`pds_plugin.partition.agreeing_fields` leaves that to the spacing of the
    chains' dense points, and a chain sample's separation lowering
    (:func:`pds_plugin.partition.chain_sample_radii`) to this. Then the patches read the
    same r at every sample they share. Returns the radii and, per patch, its field with
    the cones (what :func:`_patch_mesh` meshes it with). ``points``: per patch, its
    chain samples' points (:func:`_ring_samples`), computed here if not given."""
    ids = chains.region_samples
    if points is None:
        points = chains.regions_points(frames)
    union = None if topology is None else topology.layout_field(frames, fields)
    if union is not None and points:            # the same in every round; one call
        own = split_counts(union(np.concatenate(points)), [len(xy) for xy in points])
    else:
        own = [field(xy) for field, xy in zip(fields, points)]
    few = _FewCones(ids, points, fields)
    changed = np.ones(len(sizes), bool)
    for _ in range(_AGREEMENT_ROUNDS):
        lowest = sizes.copy()
        cones = few(sizes)
        # a larger patch none of whose samples' sizes changed reads what it read in the
        # last round, which lowered nothing then and lowers nothing now
        touched = [k for k, i in enumerate(ids) if k in cones or changed[i].any()]
        if touched:                 # one minimum.at for them all (min is exact)
            reads = [np.minimum(own[k], cones[k] if k in cones else
                                _cones_at(points[k], sizes[ids[k]], fields[k]))
                     for k in touched]
            np.minimum.at(lowest, np.concatenate([ids[k] for k in touched]),
                          np.concatenate(reads))
        lower = lowest < sizes * (1 - _AGREEMENT_TOL)
        if not lower.any():
            break
        sizes, changed = np.where(lower, lowest, sizes), lower
    return sizes, fields_with_cones(fields, points, [sizes[i] for i in ids])


def _cones_at(xy, sizes, field) -> np.ndarray:
    """min_j sizes_j + L |x_i - x_j| at each point x_i of ``xy`` (cones of ``sizes`` at
    the points themselves, ``field``'s L), no more than its cap: pairwise for up to 32
    points (most patches of a CAD part), in NumPy, and then in C, else by the cone
    tree's exact minimum (the cones the dominance test of a field would drop change no
    minimum)."""
    if len(xy) <= 32:
        distance = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
        return np.minimum((sizes[None, :] + field.grading * distance).min(axis=1, initial=np.inf),
                          field.cap)
    xy, sizes = np.ascontiguousarray(xy), np.ascontiguousarray(sizes)
    if len(xy) ** 2 <= _PAIRWISE:
        return _sizing_kernels.cone_minimum_pairwise(xy, xy, sizes, field.grading, field.cap)
    return _sizing_kernels.cone_minimum(xy, xy, sizes, field.grading, field.cap,
                                        *_sizing_kernels.build_cone_tree(xy, sizes, 8))


class _FewCones:
    """:func:`_cones_at` of every patch of at most 32 samples at once (most patches of a
    CAD part: the 20 mm cube's letters, a sphere's facets), each a row of padded arrays
    (patches within a factor two of one sample count together), its distances times L
    found once for all rounds of :func:`_agreeing_sizes`: the same numbers (the padding's
    sizes are infinite, so it is no one's minimum)."""

    def __init__(self, ids, points, fields):
        counts = np.array([len(xy) for xy in points])
        size = np.ceil(np.log2(np.maximum(counts, 1))).astype(np.int64)
        self.classes = []
        for s in np.unique(size[(counts > 0) & (counts <= 32)]).tolist():
            which = np.flatnonzero((size == s) & (counts > 0) & (counts <= 32)).tolist()
            width = int(counts[which].max())
            mask = np.arange(width)[None, :] < counts[which, None]
            xy = np.zeros((len(which), width, 2))
            xy[mask] = np.concatenate([points[k] for k in which])
            distance = np.hypot(xy[:, :, None, 0] - xy[:, None, :, 0],
                                xy[:, :, None, 1] - xy[:, None, :, 1])
            grading = np.array([fields[k].grading for k in which])
            slope = grading[:, None, None] * distance          # field.grading * distance
            cap = np.array([fields[k].cap for k in which])[:, None]
            self.classes.append((which, mask, slope, cap, np.concatenate([ids[k] for k in which]),
                                 np.cumsum(counts[which])[:-1]))

    def __call__(self, sizes) -> dict:
        """Per patch of at most 32 samples (by index), its cones at its samples."""
        out = {}
        for which, mask, slope, cap, ids, cut in self.classes:
            padded = np.full(mask.shape, np.inf)
            padded[mask] = sizes[ids]
            cones = np.minimum((padded[:, None, :] + slope).min(axis=2, initial=np.inf), cap)
            out.update(zip(which, np.split(cones[mask], cut)))
        return out


_AGREEMENT_ROUNDS = 16
"""Rounds of :func:`_agreeing_sizes` at most (each carries a lowering across a patch)."""

_AGREEMENT_TOL = 1e-9
"""A sample's r read lower than this (relative) by another patch is rounding."""


def _chords_joinable(given, fields) -> list:
    """Per patch (its :func:`_ring_samples` ``given`` and its field), can every chord
    (two consecutive ring samples) be an edge of its graded complex? A triangle of it
    has its circumradius at most min r / (1 - L) over its corners
    (:mod:`.graded_complex`), so an edge ab at most 2 min(r(a), r(b)) / (1 - L); a
    longer chord (1e-9 of margin) is an edge of no triangle, and the patch would not
    join its neighbours. All patches at once, each read by its own field."""
    if not given:
        return []
    points = np.concatenate([xy for _, xy, _, _ in given])
    following = _following([count for _, _, counts, _ in given for count in counts])
    sizes = [len(xy) for _, xy, _, _ in given]
    r = np.concatenate([field(xy) for (_, xy, _, _), field in zip(given, fields)])
    grading = np.repeat([field.grading for field in fields], sizes)
    longest = 2.0 * np.minimum(r, r[following]) / (1.0 - grading) * (1.0 + 1e-9)
    too_long = np.hypot(*(points[following] - points).T) > longest
    owner = np.repeat(np.arange(len(given)), sizes)
    return (np.bincount(owner[too_long], minlength=len(given)) == 0).tolist()


def _facets(patches, vertices, faces, normals, feature_angle) -> np.ndarray:
    """Per patch: is it a facet of a tessellated curved surface, convex and with at
    least half of its boundary (by length) on folds, edges to faces turning from it by
    less than ``feature_angle`` (docs/remesh.md, "Facets")? A remeshed convex patch is
    at least alpha wide (2 area / perimeter >= alpha, :data:`KEEP_NARROWER`), so it has
    no wall a uniform radius cannot shape; a facet notched by a milled flat has one."""
    rings = [ring for patch in patches for ring in patch.rings]
    owner = np.repeat(np.arange(len(patches)),
                      [sum(len(ring) for ring in patch.rings) for patch in patches])
    start = np.concatenate(rings)
    end = start[_following([len(ring) for ring in rings])]
    n = len(vertices)
    code = (faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2) * [n, 1]).sum(axis=1)
    order = np.argsort(code, kind="stable")
    twin = end * n + start                      # the same edge, run by the face beyond
    at = np.minimum(np.searchsorted(code, twin, sorter=order), len(code) - 1)
    beyond = normals[order[at] // 3]
    normal = np.array([patch.basis[3] for patch in patches])[owner]
    fold = (code[order[at]] == twin) & (np.einsum("ij,ij->i", beyond, normal)
                                        > math.cos(math.radians(feature_angle)))
    length = np.linalg.norm(vertices[end] - vertices[start], axis=1)
    convex = [len(patch.region.rings) == 1
              and patch.turns[0].min() >= -_ROUNDED_TURN
              for patch in patches]
    return convex & (2 * np.bincount(owner, length * fold, minlength=len(patches))
                     >= np.bincount(owner, length, minlength=len(patches)))


_ROUNDED_TURN = 1e-6
"""A convex patch's corners turn right by at most this much (radians): rounding, at
vertices of a straight edge (:func:`_facets`)."""


def _sharpest_corner(patch) -> float:
    """The smallest angle, in radians, at a convex corner of ``patch`` (pi if none is
    sharper than _CHECKED_CORNER): the triangle at that corner has it or less."""
    if not len(patch.corners):
        return math.pi
    return min(float(np.min(np.pi - turns, initial=np.pi)) for turns in patch.turns)


def _graded_instead(patches, meshes, fields, flat, bound) -> list:
    """The patches still at the ``flat`` field (a uniform remesh's, a graded remesh's
    facets) whose mesh has a triangle below the proven ``bound`` that its certificate
    excuses (a wall thinner than alpha, a spike sharper than the bound): at r = alpha
    there are many such triangles across the wall or along the spike, and the graded
    field shrinks them with the wall (docs/remesh.md, "Uniform"). Only patches with such
    a triangle pay for the certificate."""
    todo = [(patch, mesh) for patch, mesh in zip(patches, meshes)
            if mesh is not None and fields[id(patch)] is flat and len(mesh.faces)]
    if not todo:
        return []
    # every mesh's triangles at once (the same arithmetic, triangle by triangle)
    corners = np.concatenate([mesh.vertices[mesh.faces] for _, mesh in todo])
    starts = np.cumsum([0] + [len(mesh.faces) for _, mesh in todo[:-1]])
    smallest = np.minimum.reduceat(_corner_angles(corners), starts)
    return [patch for (patch, mesh), angle in zip(todo, smallest.tolist())
            if angle < bound and len(mesh.certificate().exceptions) > 0]


_THIN = 0.5
"""Two boundary samples of a patch at alpha closer than this many times the smaller of
their radii, seeing each other across it, are across a thin wall (:func:`_thin_walled`).
Held out (seeds 4301 and 4401, uniform, 4,218 patches at alpha): 22 of the 23 patches
whose meshes had exceptions below the bound had such a pair, at 0.22-0.47; no other
patch had one under 0.50."""


def _thin_walled(patches, given, sizes, fields, flat) -> list:
    """The patches still at the ``flat`` field (:func:`_graded_instead`'s) with two
    boundary samples (``given``: per patch, :func:`_ring_samples`; ``sizes``: their
    radii) closer than :data:`_THIN` times the smaller radius, whose midpoint lies in the
    patch and which are more than two places apart along a ring: a wall much thinner
    than the radius, across which a mesh at alpha has triangles below the bound. Found
    before any patch is meshed, they take their graded fields a round of meshing
    earlier; :func:`_graded_instead` still checks the meshes."""
    from scipy.spatial import cKDTree

    todo = [k for k, patch in enumerate(patches) if fields[id(patch)] is flat]
    if not todo:
        return []
    points = np.concatenate([given[k][1] for k in todo])
    radius = sizes[np.concatenate([given[k][0] for k in todo])]
    lengths = np.array([count for k in todo for count in given[k][2]])
    ring = np.repeat(np.arange(len(lengths)), lengths)
    place = np.arange(len(ring)) - np.repeat(np.cumsum(lengths) - lengths, lengths)
    owner = np.repeat(todo, [sum(given[k][2]) for k in todo])
    i, j = cKDTree(points).query_pairs(_THIN * float(radius.max()), output_type="ndarray").T
    along = np.abs(place[i] - place[j])
    along = np.minimum(along, lengths[ring[i]] - along)
    close = ((np.hypot(*(points[i] - points[j]).T) < _THIN * np.minimum(radius[i], radius[j]))
             & (owner[i] == owner[j]) & ((ring[i] != ring[j]) | (along > 2)))
    i, j = i[close], j[close]
    middle = (points[i] + points[j]) / 2
    return [patches[k] for k in sorted(set(owner[i].tolist()))
            if shapely.contains_xy(patches[k].region.geometry,
                                   *middle[owner[i] == k].T).any()]


def _at_spikes(patches) -> list:
    """Per patch: is a corner of it sharper than :data:`_CHECKED_CORNER`, or is one of
    its vertices such a corner of another patch? The chains leaving that
    vertex keep their first part long, clear of the spike, with r there the smaller: in
    a patch whose own corner is not sharp (random cut block 44: 90° beside a 32° spike)
    that part is a chord longer than twice the r at its end, and the graded sampler
    keeps out of its lens (limit the smaller end's r / (1 - L)) where the certificate
    excuses only r(x) / (1 - L): a point between was 1.013 r from every sample."""
    if not patches:
        return []
    pointed = np.concatenate([p.corners for p in patches])
    ids = [ring for patch in patches for ring in patch.rings]
    owner = np.repeat(np.arange(len(patches)),
                      [sum(len(ring) for ring in patch.rings) for patch in patches])
    return (np.bincount(owner, np.isin(np.concatenate(ids), pointed), minlength=len(patches))
            > 0).tolist()


def _as_trimesh(mesh) -> "trimesh.Trimesh":
    """A fresh ``trimesh.Trimesh`` of ``mesh`` (a Trimesh, a file, or a MeshSet's current
    mesh), its duplicate vertices merged."""
    import trimesh

    if type(mesh).__name__ == "MeshSet":
        current = mesh.current_mesh()
        vertices, faces = current.vertex_matrix(), current.face_matrix()
    elif isinstance(mesh, trimesh.Trimesh):
        vertices, faces = mesh.vertices, mesh.faces
    elif isinstance(mesh, (str, os.PathLike)):
        from .sources.trimesh import load
        loaded = load(mesh)
        vertices, faces = loaded.vertices, loaded.faces
    else:
        raise ArgumentTypeError(f"remesh takes a trimesh.Trimesh, a mesh file path or a "
                                f"pymeshlab.MeshSet, got {type(mesh).__name__}")
    if len(faces) == 0:
        raise ArgumentError("the mesh has no triangles: there is nothing to remesh")
    check_coordinates(vertices)                 # before trimesh drops NaN vertices
    with np.errstate(invalid="ignore", over="ignore"):   # trimesh's merge past its range
        read = trimesh.Trimesh(np.array(vertices, dtype=np.float64),
                               np.array(faces, dtype=np.int64), process=True)
    check_coordinates(read.vertices, read.faces)
    return read


def _needles_dropped(source) -> int:
    """Drop the faces of ``source`` (the remesh's own copy, its vertices merged) that
    name one vertex twice, and return how many. Such a face has no area: OpenCASCADE's
    tessellation leaves one at each pole of a sphere and at each corner where fillets
    blend (FreeCAD, CadQuery). Its edge to the other vertex is run both ways by it, so
    the edge bounds four faces and the closed part read as open: its volume was not
    checked. Without it the surface is the same point set, and closed."""
    needle = needle_faces(source.faces)
    if needle.any():
        source.update_faces(~needle)
        source.remove_unreferenced_vertices()
    return int(np.count_nonzero(needle))


def _wound_alike(source) -> int:
    """Turn the faces of ``source`` (the remesh's own copy) that are wound against their
    neighbours, each body then outward (``trimesh.repair.fix_normals``), and return how
    many were turned. An exporter's slip (multibody.stl) leaves a surface with no volume
    to keep, and coplanar faces wound two ways in two patches that meet edge to edge
    the same way round: the remesh said FAILED (a box with every third face turned), or
    kept most of such a part's patches (multibody.stl: 18 of 31)."""
    if source.is_winding_consistent:
        return 0
    import trimesh

    before = source.faces.copy()
    trimesh.repair.fix_normals(source, multibody=True)
    return int(np.count_nonzero((source.faces != before).any(axis=1)))


def _coplanar_patches(source, vertices, faces, normals, areas, tolerance) -> np.ndarray:
    """The planar patch of each face: neighbours join when the far vertex of the smaller
    lies within ``tolerance`` of the larger's plane (same side up); a patch whose
    vertices spread farther than twice that from its area-weighted plane is split into
    its faces."""
    pairs = np.asarray(source.face_adjacency, dtype=np.int64).reshape(-1, 2)
    far = np.asarray(source.face_adjacency_unshared, dtype=np.int64).reshape(-1, 2)
    edge = np.asarray(source.face_adjacency_edges, dtype=np.int64).reshape(-1, 2)
    larger = areas[pairs[:, 0]] >= areas[pairs[:, 1]]
    big = np.where(larger, pairs[:, 0], pairs[:, 1])
    small_far = np.where(larger, far[:, 1], far[:, 0])
    height = np.abs(np.einsum("ij,ij->i", normals[big],
                              vertices[small_far] - vertices[edge[:, 0]]))
    same = (height <= tolerance) & (np.einsum("ij,ij->i", normals[pairs[:, 0]],
                                              normals[pairs[:, 1]]) > 0)
    graph = coo_matrix((np.ones(int(same.sum())), (pairs[same, 0], pairs[same, 1])),
                       shape=(len(faces), len(faces)))
    label = connected_components(graph, directed=False)[1]
    count = label.max() + 1
    plane = np.zeros((count, 3))
    np.add.at(plane, label, normals * areas[:, None])
    plane /= np.maximum(np.linalg.norm(plane, axis=1), 1e-300)[:, None]
    level = np.einsum("fkj,fj->fk", vertices[faces], plane[label])
    low, high = np.full(count, np.inf), np.full(count, -np.inf)
    np.minimum.at(low, label, level.min(axis=1))
    np.maximum.at(high, label, level.max(axis=1))
    bent = (high - low > 2 * tolerance)[label]
    label[bent] = count + np.arange(int(bent.sum()))
    return label


@dataclass
class _Patch:
    """A planar patch to remesh: its faces, rings (vertex numbers, the patch on the
    left seen from its outward normal), 2D frame, Region, corners sharper than
    :data:`_CHECKED_CORNER` and its region's rings' turning angles."""

    faces: np.ndarray
    rings: list
    frame: Frame
    region: object
    basis: tuple
    corners: np.ndarray
    turns: list


def _usable_patches(vertices, faces, normals, areas, label, alpha, gap) -> list:
    """Per patch, a :class:`_Patch` if it is remeshed, else None: kept when narrower than
    alpha (area / perimeter < alpha / 2), pinched, or not a valid polygon in its plane.
    The remeshed patches' 2D frames are laid out side by side in one plane, ``gap``
    apart (:func:`_layout`), so that they can be meshed in one call."""
    count = label.max() + 1
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    owner = np.repeat(label, 3)
    n = len(vertices)
    code = (directed[:, 0] * n + directed[:, 1]) * count + owner
    back = (directed[:, 1] * n + directed[:, 0]) * count + owner
    rim = ~np.isin(back, code)
    length = np.linalg.norm(vertices[directed[:, 1]] - vertices[directed[:, 0]], axis=1)
    perimeter = np.bincount(owner[rim], length[rim], minlength=count)
    area = np.bincount(label, areas, minlength=count)
    wide = 2 * area >= KEEP_NARROWER * alpha * np.maximum(perimeter, 1e-300)
    order = np.argsort(label, kind="stable")
    starts = np.searchsorted(label[order], np.arange(count + 1))
    rim_order = np.flatnonzero(rim)
    rim_order = rim_order[np.argsort(owner[rim_order], kind="stable")]
    rim_starts = np.searchsorted(owner[rim_order], np.arange(count + 1))
    # the small patches whose boundary could be one cycle through all their vertices (a
    # sphere's facets, a freeform surface's quads: most patches of a tessellated curved
    # surface) in one pass per size, the others, or those it does not take, one by one
    planes = [None] * count
    sizes = np.diff(starts)
    for size in range(1, _FAN_FACES + 1):
        which = np.flatnonzero(wide & (sizes == size) & (np.diff(rim_starts) == size + 2))
        members = order[starts[which][:, None] + np.arange(size)]
        edges = directed[rim_order[rim_starts[which][:, None] + np.arange(size + 2)]]
        for p, plane in zip(which.tolist(), _fan_planes(vertices, faces, normals, areas,
                                                        members, edges)):
            planes[p] = plane
    for p in np.flatnonzero(wide).tolist():
        if planes[p] is None:
            members = order[starts[p]:starts[p + 1]]
            edges = directed[rim_order[rim_starts[p]:rim_starts[p + 1]]]
            planes[p] = _plane_rings(vertices, faces, normals, areas, members, edges)
    shifts = _layout([None if plane is None else plane[4] for plane in planes], gap)
    # the patches of one ring (most: a CAD face, a facet) are valid polygons or not all
    # at once, their regions made together
    single = [k for k, plane in enumerate(planes) if plane is not None and len(plane[4]) == 1]
    regions = dict(zip(single, simple_regions([planes[k][4][0] + shifts[k] for k in single])))
    return _patches(planes, shifts, regions)


def _plane_rings(vertices, faces, normals, areas, members, edges):
    """The boundary cycles of faces ``members`` (boundary ``edges``) in their plane:
    (members, ids, xy, basis, rings, cycles), rings the 2D cycles with the outer one
    first and cycles their positions in ``ids``; or None if pinched, not closed, or not
    one outer ring."""
    following = dict(zip(edges[:, 0].tolist(), edges[:, 1].tolist()))
    if len(following) != len(edges):
        return None                                   # pinched at a vertex
    normal = (normals[members] * areas[members, None]).sum(axis=0)
    normal /= np.linalg.norm(normal)
    origin = vertices[edges[0, 0]]
    axis = vertices[edges[0, 1]] - origin
    axis -= normal * (axis @ normal)
    axis /= np.linalg.norm(axis)
    # np.cross's own arithmetic (a1 b2 - a2 b1, ...), without its checks and broadcasting
    # (6 µs a call, 360 calls on the 20 mm cube)
    basis = (origin, axis, np.array([normal[1] * axis[2] - normal[2] * axis[1],
                                     normal[2] * axis[0] - normal[0] * axis[2],
                                     normal[0] * axis[1] - normal[1] * axis[0]]), normal)
    ids = np.unique(faces[members])
    xy = (vertices[ids] - origin) @ np.column_stack([basis[1], basis[2]])
    position = dict(zip(ids.tolist(), range(len(ids))))
    cycles, left = [], set(following)
    while left:
        start = min(left)
        cycle, vertex = [], start
        while vertex in left:
            left.discard(vertex)
            cycle.append(position[vertex])
            vertex = following[vertex]
        if vertex != start:
            return None
        cycles.append(cycle)
    rings = [xy[cycle] for cycle in cycles]
    following = [xy[cycle[1:] + cycle[:1]] for cycle in cycles]      # np.roll(ring, -1)
    signed = [0.5 * float(np.sum(r[:, 0] * f[:, 1] - f[:, 0] * r[:, 1]))
              for r, f in zip(rings, following)]
    outer = [k for k, a in enumerate(signed) if a > 0]
    if len(outer) != 1:
        return None
    order = outer + [k for k in range(len(rings)) if k != outer[0]]
    return (members, ids, xy, basis, [rings[k] for k in order],
            [np.array(cycles[k], dtype=np.int64) for k in order])


_FAN_FACES = 8
"""Patches of up to this many faces are read by :func:`_fan_planes` when they can be."""


def _fan_planes(vertices, faces, normals, areas, members, edges) -> list:
    """:func:`_plane_rings` of patches of k faces each (``members``, (P, k)) whose k + 2
    boundary ``edges`` ((P, k + 2, 2), in :func:`_plane_rings`' order) can be one cycle
    through all their vertices, computed together with the same arithmetic; None where a
    patch is not that (pinched, more than one cycle, a vertex inside: read it one by
    one) or its ring runs clockwise (as :func:`_plane_rings`' None)."""
    count, size = edges.shape[:2]
    normal = normals[members[:, 0]] * areas[members[:, 0], None]
    for k in range(1, members.shape[1]):        # the order of .sum(axis=0): row by row
        normal += normals[members[:, k]] * areas[members[:, k], None]
    normal /= np.sqrt(_dots(normal, normal))
    origin = vertices[edges[:, 0, 0]]
    axis = vertices[edges[:, 0, 1]] - origin
    axis -= normal * _dots(axis, normal)
    axis /= np.sqrt(_dots(axis, axis))
    other = np.cross(normal, axis)
    # walk each boundary from its lowest vertex, as _plane_rings does
    by_start = np.argsort(edges[:, :, 0], axis=1)
    start = np.take_along_axis(edges[:, :, 0], by_start, axis=1)
    end = np.take_along_axis(edges[:, :, 1], by_start, axis=1)
    walk = np.empty((count, size), np.int64)
    walk[:, 0] = start[:, 0]
    rows = np.arange(count)
    for k in range(1, size):
        walk[:, k] = end[rows, (start == walk[:, k - 1, None]).argmax(axis=1)]
    closes = end[rows, (start == walk[:, -1, None]).argmax(axis=1)] == walk[:, 0]
    ids = np.sort(walk, axis=1)
    used = np.sort(faces[members].reshape(count, 3 * members.shape[1]), axis=1)
    one_cycle = (closes & (np.diff(start, axis=1) > 0).all(axis=1)        # not pinched
                 & (np.diff(ids, axis=1) > 0).all(axis=1)                # a simple cycle
                 & ((np.diff(used, axis=1) > 0).sum(axis=1) == size - 1))   # no inner one
    xy = (vertices[ids] - origin[:, None]) @ np.stack([axis, other], axis=2)
    cycle = np.argsort(np.argsort(walk, axis=1), axis=1)      # each vertex's place in ids
    ring = np.take_along_axis(xy, cycle[:, :, None], axis=1)
    following = np.roll(ring, -1, axis=1)
    signed = (ring[:, :, 0] * following[:, :, 1] - following[:, :, 0] * ring[:, :, 1]).sum(axis=1)
    return [(members[k], ids[k], xy[k], (origin[k], axis[k], other[k], normal[k]), [ring[k]],
             [cycle[k]]) if one_cycle[k] and signed[k] > 0 else None for k in range(count)]


def _dots(a, b) -> np.ndarray:
    """The dot products of the rows of ``a`` and ``b``, a column, each as ``a[k] @ b[k]``
    computes it (the same rounding)."""
    return (a[:, None, :] @ b[:, :, None])[:, 0]


def _layout(rings, gap) -> list:
    """Per patch (its 2D rings, outer first, or None), the shift that puts it in its
    own place of one plane: shelves of patches (tallest first), every two of them at
    least ``gap`` apart (their bounding boxes), None for None.

    Examples
    --------
    >>> square = [np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])]
    >>> shifts = _layout([square, None, square], 3.0)
    >>> [None if s is None else s.tolist() for s in shifts]
    [[0.0, 0.0], None, [4.0, 0.0]]
    """
    laid = [k for k, r in enumerate(rings) if r is not None]
    if not laid:
        return [None] * len(rings)
    outer = [rings[k][0] for k in laid]            # every patch's box, in one pass
    starts = np.cumsum([0] + [len(ring) for ring in outer[:-1]])
    outer = np.concatenate(outer)
    low = np.minimum.reduceat(outer, starts)
    size = np.maximum.reduceat(outer, starts) - low
    wide, tall = size[:, 0].tolist(), size[:, 1].tolist()
    width = max(math.sqrt(sum(((size + gap)[:, 0] * (size + gap)[:, 1]).tolist())), max(wide))
    at = np.empty((len(laid), 2))
    x = y = row = 0.0
    for i in sorted(range(len(laid)), key=lambda i: (-tall[i], laid[i])):
        if x > 0 and x + wide[i] > width:
            x, y, row = 0.0, y + row + gap, 0.0
        at[i] = x, y
        x += wide[i] + gap
        row = max(row, tall[i])
    shifts = [None] * len(rings)
    for k, shift in zip(laid, at - low):
        shifts[k] = shift
    return shifts


def _patches(planes, shifts, regions) -> list:
    """The :class:`_Patch` of each of :func:`_plane_rings`' outputs ``planes`` (None for
    None; their vertex numbers increasing), its 2D frame moved by its shift, or None if
    not a valid polygon. ``regions``: by patch of one ring, its region, made with the
    others' (``region.simple_regions``; None if not valid); a patch with holes has its
    region made here. The rings' turning angles and sharp corners are measured for all
    patches in one pass."""
    laid = []                                   # (k, its 2D vertices, its region)
    for k, (plane, shift) in enumerate(zip(planes, shifts)):
        if plane is None:
            continue
        rings, region = plane[4], regions.get(k)
        if len(rings) > 1:
            try:
                region = Region.from_shapely(Polygon(rings[0] + shift,
                                                     [ring + shift for ring in rings[1:]]))
            except PdsError:
                continue
        if region is not None:
            laid.append((k, plane[2] + shift, region))
    ring_ids = _ring_ids([(planes[k][1], xy, region, planes[k][5]) for k, xy, region in laid])
    made = [(k, xy, region, ids) for (k, xy, region), ids in zip(laid, ring_ids)
            if ids is not None]
    out = [None] * len(planes)
    if not made:
        return out
    rings = [ring for _, _, region, _ in made for ring in region.rings]
    counts = [len(ring) for ring in rings]
    turns = turning_angles(np.concatenate(rings), counts)
    sharp = np.pi - turns < _CHECKED_CORNER
    vertex = np.concatenate([ids for *_, ring_ids in made for ids in ring_ids])
    patch_of = np.repeat(np.arange(len(made)), [sum(map(len, ids)) for *_, ids in made])
    corners = split_counts(vertex[sharp], np.bincount(patch_of[sharp], minlength=len(made)))
    turns = split_counts(turns, counts)
    first = 0
    for (k, xy, region, ids), sharpest in zip(made, corners):
        members, vertices, _, basis = planes[k][:4]
        last = first + len(region.rings)
        out[k] = _Patch(members, ids, Frame.of_sorted(vertices, xy), region, basis, sharpest,
                        turns[first:last])
        first = last
    return out


def _ring_ids(patches) -> list:
    """Per patch (its vertex numbers, their 2D points, its region, its cycles: positions
    in the numbers), its region's rings as vertex numbers, or None if a point of them is
    no vertex. The rings are most often the cycles' own points (one ring, already
    counterclockwise, starting where the cycle does): checked for all patches at once,
    the others looked up."""
    alike = [k for k, (_, _, region, cycles) in enumerate(patches)
             if len(region.rings) == len(cycles)
             and all(len(ring) == len(cycle) for ring, cycle in zip(region.rings, cycles))]
    same = np.zeros(len(patches), bool)
    if alike:
        points = np.concatenate([patches[k][1][cycle] for k in alike for cycle in patches[k][3]])
        rings = np.concatenate([ring for k in alike for ring in patches[k][2].rings])
        sizes = [sum(map(len, patches[k][3])) for k in alike]
        same[alike] = np.logical_and.reduceat((points == rings).all(axis=1),
                                              np.cumsum([0] + sizes[:-1]))
    out = []
    for (ids, xy, region, cycles), ok in zip(patches, same.tolist()):
        if ok:
            out.append([ids[cycle] for cycle in cycles])
            continue
        lookup = {tuple(point): vertex for vertex, point in zip(ids.tolist(), xy.tolist())}
        try:
            out.append([np.array([lookup[tuple(point)] for point in ring.tolist()], np.int64)
                        for ring in region.rings])
        except KeyError:
            out.append(None)
    return out


def _manifold_patches(patches) -> list:
    """The patches whose boundary edges no other patch runs the same way, nor two others
    (non-manifold input: two bodies sharing a face); the rest are kept. (An edge a
    patch runs twice counts as two runs.)"""
    if not patches:
        return []
    rings = [(k, ring) for k, patch in enumerate(patches) for ring in patch.rings]
    start = np.concatenate([ring for _, ring in rings]).astype(np.int64)
    end = start[_following([len(ring) for _, ring in rings])]
    owner = np.repeat([k for k, _ in rings], [len(ring) for _, ring in rings])
    n = int(max(start.max(initial=0), end.max(initial=0))) + 1
    bad = np.zeros(len(start), bool)
    for code, most in ((start * n + end, 1), (np.minimum(start, end) * n + np.maximum(start, end), 2)):
        _, inverse, count = np.unique(code, return_inverse=True, return_counts=True)
        bad |= count[inverse.ravel()] > most
    bad = set(owner[bad].tolist())
    return [patch for k, patch in enumerate(patches) if k not in bad]


def _assemble(source, vertices, faces, kept, patches, meshes, chains, tolerance,
              patch_count, alpha, graded) -> RemeshResult:
    """Join the patches' meshes and the kept faces (split where samples fall on their
    edges) into one mesh, checked; and the ids of the patches to keep as they were for
    the volume (:func:`_volume_kept`)."""
    import trimesh

    junction = (chains.u == chains.v) & (chains.t == 0)
    number = np.where(junction, chains.u, len(vertices) + np.cumsum(~junction) - 1)
    points = [vertices, chains.points(vertices)[~junction]]
    count = len(vertices) + int(np.count_nonzero(~junction))
    given = [len(ids) for ids in chains.region_samples]
    placed = _on_input([mesh.vertices[n:] for mesh, n in zip(meshes, given)], patches,
                       vertices, faces)
    # every patch's vertices numbered in the output at once: its given samples are chain
    # samples, its interior points follow the chain samples, patch by patch
    sizes = np.array([len(mesh.vertices) for mesh in meshes], np.int64)
    inner = sizes - given
    starts = np.cumsum(sizes) - sizes
    interior = (np.arange(sizes.sum()) - np.repeat(starts, sizes)) >= np.repeat(given, sizes)
    to_out = np.empty(sizes.sum(), np.int64)
    to_out[~interior] = number[np.concatenate(chains.region_samples + [np.zeros(0, np.int64)])]
    to_out[interior] = count + np.arange(inner.sum())
    first_inner = count + np.cumsum(inner) - inner
    lifted = [(int(first), normal, height)
              for first, (_, normal, height) in zip(first_inner.tolist(), placed)]
    points += [points_in for points_in, _, _ in placed]
    count += int(inner.sum())
    triangles = [len(mesh.faces) for mesh in meshes]
    new_faces = split_counts(to_out[np.concatenate(
        [mesh.faces + start for mesh, start in zip(meshes, starts.tolist())]
        + [np.zeros((0, 3), np.int64)])], triangles)
    patch_of = [np.repeat(np.arange(len(meshes)), triangles)]
    centre = vertices[np.unique(faces)].mean(axis=0)
    (closed_in, euler_in, volume_in) = _surface_facts(vertices, faces, centre)
    distance, unkept = _volume_kept(points, lifted, new_faces, patches, vertices, faces,
                                    volume_in if closed_in else 0.0, tolerance, centre)
    split, centres = _split_kept(faces[kept], chains, number, count, vertices)
    points.append(centres)
    new_faces.append(split)
    patch_of.append(np.full(len(split), -1))
    all_points = np.concatenate(points)
    all_faces = np.concatenate(new_faces)
    used = np.zeros(len(all_points), bool)
    used[all_faces.ravel()] = True
    renumber = np.cumsum(used) - 1
    out = trimesh.Trimesh(all_points[used], renumber[all_faces], process=False)
    rim = source.edges[trimesh.grouping.group_rows(source.edges_sorted, require_count=1)]
    rim_keys = {(int(a), int(b)) for a, b in np.sort(rim, axis=1).tolist()}
    # every chain is an interface (two patches, or a patch and kept faces) but those on
    # the input's own open boundary
    interfaces = (range(len(chains.chains)) if not rim_keys else
                  [c for c, vertices in enumerate(chains.chains)
                   if tuple(sorted((int(vertices[0]), int(vertices[1])))) not in rim_keys])
    chords = _chords(chains, interfaces)
    on_rim = np.zeros(len(vertices), bool)
    on_rim[rim.ravel()] = True
    flags = np.zeros(len(all_points), bool)
    flags[:len(vertices)] = on_rim
    flags[number[on_rim[chains.u] & on_rim[chains.v]]] = True
    outer = flags[used]
    report = interface_report(out.vertices, out.faces, renumber[number[chords]], outer,
                              _inherited(faces, len(vertices), used, renumber))
    (closed_out, euler_out, volume_out) = _surface_facts(out.vertices, out.faces, centre)
    volume_error = (abs(volume_out - volume_in) / abs(volume_in)
                    if closed_in and volume_in else float("nan"))
    return RemeshResult(out, np.concatenate(patch_of).astype(np.int64), tuple(meshes),
                        report, alpha, patch_count, patch_count - len(patches),
                        (closed_in, closed_out), (euler_in, euler_out), volume_error,
                        distance, tolerance, bool(graded)), unkept


def _chords(chains, which) -> np.ndarray:
    """The (m, 2) sample numbers of the consecutive samples along the chains ``which``,
    chain after chain, a closed chain's last to its first at its end: what
    ``chains.chords(c)`` gives chain by chain (ADIS16480: 3 ms of numpy calls for its
    thousands of one-edge chains), in one pass."""
    samples = [chains.chain_samples[c] for c in which]
    if not samples:
        return np.zeros((0, 2), np.int64)
    length = np.array([len(s) for s in samples], np.int64)
    closed = np.array([bool(chains.closed[c]) for c in which])
    pairs = np.maximum(length - 1 + closed, 0) * (length > 0)
    every = np.concatenate(samples).astype(np.int64)
    chain = np.repeat(np.arange(len(samples)), pairs)
    k = np.arange(int(pairs.sum())) - np.repeat(np.cumsum(pairs) - pairs, pairs)
    first = np.cumsum(length) - length
    return np.column_stack([every[first[chain] + k],
                            every[first[chain] + (k + 1) % length[chain]]])


def _inherited(faces, count, used, renumber) -> tuple:
    """The input's own defects, for :func:`~pds_plugin.partition.interface_report`, in
    the output's numbering (the input's vertices come first there): rows (a, b, n) of
    its directed edges run by n > 1 triangles, and of its edges (a < b) of n > 2
    triangles (two bodies sharing an edge: such edges' patches are kept, and the edges
    with them). Edges with a vertex the output does not use are left out."""
    directed = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    rows = []
    for pairs, least in ((directed, 2), (np.sort(directed, axis=1), 3)):
        codes, counts = np.unique(pairs[:, 0] * count + pairs[:, 1], return_counts=True)
        edge = np.column_stack(divmod(codes[counts >= least], count))
        keep = used[:count][edge].all(axis=1)
        pair = renumber[edge[keep]]
        if least == 3:
            pair = np.sort(pair, axis=1)
        rows.append(np.column_stack([pair, counts[counts >= least][keep]]))
    return tuple(rows)


def _surface_facts(vertices, faces, centre) -> tuple[bool, int, float]:
    """Whether a triangle mesh is watertight (every edge in exactly two faces, as
    trimesh counts it), its Euler number (referenced vertices - edges + faces) and its
    signed volume about ``centre`` (the input's vertices' mean for input and output
    alike: a part far from the origin keeps its digits, and a solid whose faces are
    not all wound alike, whose signed volume depends on the point it is taken about,
    is compared with itself: multibody.stl's inverted body read as a 0.76 change), from
    one sort of its edges: a fifth of the time of trimesh's three properties on the
    28,000 triangles of a remeshed 7_8ths_cube.stl.

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box((2, 1, 1))
    >>> closed, euler, volume = _surface_facts(box.vertices, box.faces, (5, 0, 0))
    >>> closed, euler, round(volume, 12)
    (True, 2, 2.0)
    >>> _surface_facts(box.vertices, box.faces[1:], (0, 0, 0))[:2]
    (False, 1)
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if not len(faces):
        return False, 0, 0.0
    start, end = faces.ravel(), faces[:, [1, 2, 0]].ravel()
    code = np.sort(np.minimum(start, end) * len(vertices) + np.maximum(start, end))
    edges = 1 + int(np.count_nonzero(code[1:] != code[:-1]))
    closed = bool(len(code) % 2 == 0 and np.array_equal(code[0::2], code[1::2])
                  and np.all(code[2::2] != code[1:-1:2]))
    used = np.zeros(len(vertices), bool)
    used[start] = True
    # np.take: a fifth of the time of vertices[faces] (numpy's fancy indexing of rows);
    # the same numbers, each corner minus the centre
    volume = float(_determinants(np.take(vertices - np.asarray(centre, float), faces,
                                         axis=0)).sum() / 6)
    return closed, int(used.sum()) - edges + len(faces), volume


def _on_input(xy, patches, vertices, faces) -> list:
    """Per patch, the 3D points of its interior samples ``xy[k]``, each on the input
    triangle it lies in (barycentric), that triangle's unit normal, and each point's
    signed distance to that triangle's plane (rounding).

    Each point goes to the triangle whose bounding box holds it and whose smallest
    barycentric coordinate is the largest (the triangle it is in; of two that share an
    edge it lies on, the one the rounding favours), or to the nearest triangle if no box
    holds it within :data:`_INSIDE`: no geometric predicate per pair (shapely's
    ``intersects`` took a quarter of the remesh of shared.STL). The patches lie apart in
    one plane (:func:`_layout`), so one tree of all their triangles' boxes serves them
    all: a point finds only its own patch's triangles (the nearest one too: it lies in
    its patch's region, every other patch a gap away). A patch of a few input triangles
    (:data:`_FEW_TRIANGLES`: a CAD face fanned from its corners) scores each of its
    points against all of them, no tree; its points in none of them go to the tree."""
    sizes = [len(points) for points in xy]
    if not sum(sizes):
        return [(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0)) for _ in xy]
    xy = np.concatenate(xy)
    own_faces = [faces[patch.faces] for patch in patches]
    triangles = np.concatenate(own_faces)
    corners = read_regions([patch.frame for patch in patches],
                           [corner.ravel() for corner in own_faces]).reshape(-1, 3, 2)
    # each corner's coordinates apart and contiguous, gathered with np.take (the same
    # numbers as corners[which, k], in a fraction of the time)
    corner = [np.ascontiguousarray(corners[:, k]) for k in range(3)]
    count = np.array([len(patch.faces) for patch in patches])
    start = np.cumsum(count) - count
    own = np.repeat(np.arange(len(patches)), sizes)
    first, best = np.full(len(xy), -1), np.full(len(xy), -np.inf)
    few = np.flatnonzero(count[own] <= _FEW_TRIANGLES)
    if len(few):
        # every such point against each triangle of its patch, in one pass: the pairs
        # point by point, the triangles in order, each point's first best kept
        many = count[own[few]]
        before = np.cumsum(many) - many
        at = np.repeat(few, many)
        which = start[own[at]] + np.arange(len(at)) - np.repeat(before, many)
        beta, gamma = _barycentric(np.take(xy, at, axis=0),
                                   *(np.take(c, which, axis=0) for c in corner))
        pick, score = _first_best(beta, gamma, before, np.repeat(np.arange(len(few)), many))
        first[at[pick]], best[at[pick]] = which[pick], score
    rest = np.flatnonzero((count[own] > _FEW_TRIANGLES) | ~(best >= -_INSIDE))
    if len(rest):
        first[rest] = _triangle_of(xy[rest], corners)
    a, b, c = (np.take(c, first, axis=0) for c in corner)
    beta, gamma = _barycentric(xy, a, b, c)
    p = np.take(vertices, np.take(triangles, first, axis=0), axis=0)
    out = p[:, 0] + beta[:, None] * (p[:, 1] - p[:, 0]) + gamma[:, None] * (p[:, 2] - p[:, 0])
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    normal = np.column_stack([u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1],     # np.cross's
                              u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2],     # arithmetic
                              u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]])
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    height = np.einsum("ij,ij->i", out - p[:, 0], normal)
    return list(zip(split_counts(out, sizes), split_counts(normal, sizes),
                    split_counts(height, sizes)))


_FEW_TRIANGLES = 8
"""A patch of at most this many input triangles places its points without a tree
(:func:`_on_input`)."""


def _triangle_of(xy, corners) -> np.ndarray:
    """Per point, the triangle (of ``corners``, (m, 3, 2)) whose bounding box holds it
    and whose smallest barycentric coordinate is the largest (of equal ones the first
    the tree finds), or the triangle whose box is nearest if it is in none within
    :data:`_INSIDE` (:func:`_on_input`).

    The boxes holding each point come from a shapely tree of the boxes; the pairs are
    scored with ``np.take`` and each point's first best kept by
    ``np.maximum.reduceat`` over its run of pairs: the same triangles as the lexsort of
    all pairs this replaces, which took 24 of ADIS16480's 44 ms here (98,658 pairs for
    15,977 points: a fan of slivers across a face)."""
    low, high = corners.min(axis=1), corners.max(axis=1)
    tree = shapely.STRtree(shapely.box(low[:, 0], low[:, 1], high[:, 0], high[:, 1]))
    found, which = tree.query(shapely.points(xy))
    if len(found) and not np.all(found[1:] >= found[:-1]):
        order = np.argsort(found, kind="stable")      # point by point, in the tree's order
        found, which = found[order], which[order]
    first, best = np.full(len(xy), -1), np.full(len(xy), -np.inf)
    if len(found):
        a, b, c = (np.take(np.ascontiguousarray(corners[:, k]), which, axis=0)
                   for k in range(3))
        beta, gamma = _barycentric(np.take(xy, found, axis=0), a, b, c)
        starts = np.flatnonzero(np.r_[True, found[1:] != found[:-1]])
        pick, score = _first_best(beta, gamma, starts, np.repeat(
            np.arange(len(starts)), np.diff(np.r_[starts, len(found)])))
        first[found[pick]], best[found[pick]] = which[pick], score
    missing = np.flatnonzero(~(best >= -_INSIDE))        # in no triangle
    if len(missing):
        first[missing] = tree.query_nearest(shapely.points(xy[missing]), all_matches=False)[1]
    return first


def _first_best(beta, gamma, starts, run):
    """Of pairs (point, triangle) in runs, one run a point (``starts``; ``run``: each
    pair's run), each run's first pair whose smallest barycentric coordinate is the
    largest (a degenerate triangle's NaN never is), and that coordinate."""
    with np.errstate(invalid="ignore"):
        score = np.minimum(np.minimum(beta, gamma), 1 - beta - gamma)
    score = np.where(np.isnan(score), -np.inf, score)
    pick = np.flatnonzero(score == np.maximum.reduceat(score, starts)[run])
    pick = pick[np.r_[True, run[pick][1:] != run[pick][:-1]]]
    return pick, score[pick]


def _volume_kept(points, lifted, new_faces, patches, vertices, faces, volume, tolerance,
                 centre):
    """Move each patch's interior points along its normal, within the coplanarity
    ``tolerance`` of the input triangles they lie on, so that the patch's triangles
    bound the same volume as its input faces, when the remeshed patches together would
    change the (closed, ``volume`` != 0) solid's volume by more than an eighth of
    :data:`_VOLUME_TOL`; return the largest distance from an interior point to the
    plane of its input triangle, and the patches that must be kept as they were
    (:func:`_volume_spoilers`: what is left of their changes still adds up to over
    half of it).

    A patch of a float32 export tilted in space is planar to its rounding only: its new
    triangles, whose vertices lie on its input triangles, cut across their creases and
    bound another volume (2.6e-9 of a held-out filleted plate, docs/remesh.md). Moving
    every interior point by the same ``d`` along the unit normal ``n`` changes the
    patch's signed volume exactly linearly in ``d`` (in each triangle's determinant,
    a term with two columns along ``n`` vanishes), so one division finds the ``d`` that
    undoes the change; it is clipped to 0.99 of the room the tolerance leaves at the
    patch's points (a margin for rounding). ``points`` (the input vertices, the chain samples, then each patch's
    interior points) is changed in place; ``lifted`` holds per patch the first index of
    its interior points in the concatenation, their triangles' normals and their signed
    distances to those planes.

    The changes are measured about one point for all patches, ``centre`` (the solid's
    volume's): a patch's new boundary is its chains' samples, which skip the chains'
    input vertices between them, so a patch's change alone depends on the point it is
    measured from, and only the sum about one point is the solid's. About each patch's
    own origin a held-out float32 I-beam's patches summed to 2e-14 of its volume while
    the solid changed by 1.3e-9, past the 1e-9 kept, and its remesh was not ``ok``."""
    heights, unkept = [height for _, _, height in lifted], set()
    if not volume or not patches:
        return _largest(heights), unkept
    every = np.concatenate(points)
    # every patch's new triangles and input faces in one determinant call each, about
    # the one point the solid's volume is measured from
    counts = [len(triangles) for triangles in new_faces]
    every_triangle = np.concatenate(new_faces)
    taken = np.take(every, every_triangle, axis=0)
    input_faces = faces[np.concatenate([patch.faces for patch in patches])]
    old = _determinants(np.take(vertices, input_faces, axis=0) - centre)
    change = (_row_sums(_determinants(taken - centre), counts) / 6
              - _row_sums(old, [len(patch.faces) for patch in patches]) / 6)
    if abs(sum(change)) <= _VOLUME_TOL / 8 * abs(volume):
        return _largest(heights), unkept
    # each patch's slope: its triangles' determinants with the column of one moved
    # corner replaced by the normal, summed over its moved corners, the three columns
    # (in turn) for all patches at once
    owner = np.repeat(np.arange(len(patches)), counts)
    corner = taken - np.stack([patch.basis[0] for patch in patches])[owner][:, None]
    axes = np.stack([patch.basis[3] for patch in patches])
    first = np.array([start for start, _, _ in lifted])[owner][:, None]
    last = first + np.array([len(height) for height in heights])[owner][:, None]
    moved = (every_triangle >= first) & (every_triangle < last)
    slope = 0.0
    for j in range(3):
        column = _determinants(np.where((np.arange(3) == j)[:, None], axes[owner][:, None],
                                        corner))
        slope = slope + _row_sums(column[moved[:, j]],
                                  np.bincount(owner[moved[:, j]], minlength=len(patches)))
    slope = slope / 6
    highest = np.zeros(len(patches))
    with_points = np.flatnonzero([len(height) for height in heights])
    if len(with_points):
        highest[with_points] = np.maximum.reduceat(
            np.abs(np.concatenate(heights)), _starts([len(heights[k]) for k in with_points]))
    room = 0.99 * (tolerance - highest)                   # rounding's margin
    shifted = np.flatnonzero((slope != 0) & (room > 0))
    shift = np.clip(-change[shifted] / slope[shifted], -room[shifted], room[shifted])
    for k, by in zip(shifted.tolist(), shift.tolist()):
        points[2 + k] = points[2 + k] + by * axes[k]
        heights[k] = heights[k] + by * (lifted[k][1] @ axes[k])
    change[shifted] += shift * slope[shifted]
    return _largest(heights), _volume_spoilers(list(change), patches, volume)


def _row_sums(values, counts) -> np.ndarray:
    """``values[a:b].sum()`` of each run of ``counts`` items, the same numbers: the runs
    of one length summed as the rows of one array (numpy sums a row as it sums the run
    alone); 0 for an empty run."""
    counts = np.asarray(counts, np.int64)
    starts = _starts(counts)
    out = np.zeros(len(counts))
    for n in np.unique(counts[counts > 0]).tolist():
        rows = np.flatnonzero(counts == n)
        out[rows] = values[starts[rows, None] + np.arange(n)].sum(axis=1)
    return out


def _starts(counts) -> np.ndarray:
    """Where each run of ``counts`` items starts."""
    counts = np.asarray(counts, np.int64)
    return np.cumsum(counts) - counts


def _largest(heights) -> float:
    return max((float(np.abs(h).max()) for h in heights if len(h)), default=0.0)


def _volume_spoilers(change, patches, volume) -> set:
    """The ids of the patches to keep as they were so that the others' volume changes
    ``change`` add up to at most a quarter of :data:`_VOLUME_TOL` of ``volume``, the
    largest of the sign of the sum first; none if they add up to at most half of it."""
    total = sum(change)
    if abs(total) <= _VOLUME_TOL / 2 * abs(volume):
        return set()
    sign, unkept = np.sign(total), set()
    for k in np.argsort(-sign * np.asarray(change), kind="stable").tolist():
        if sign * total <= _VOLUME_TOL / 4 * abs(volume) or sign * change[k] <= 0:
            break
        unkept.add(id(patches[k]))
        total -= change[k]
    return unkept


def _determinants(corner):
    """det[a, b, c] of each triangle's corners (k, 3, 3), six times its signed volume
    about the origin."""
    a, b, c = corner[:, 0], corner[:, 1], corner[:, 2]
    return (a[:, 0] * (b[:, 1] * c[:, 2] - b[:, 2] * c[:, 1])
            + a[:, 1] * (b[:, 2] * c[:, 0] - b[:, 0] * c[:, 2])
            + a[:, 2] * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0]))


def _barycentric(xy, a, b, c):
    """The barycentric coordinates (of b and of c) of points ``xy`` in triangles abc."""
    v0, v1, v2 = b - a, c - a, xy - a
    det = v0[:, 0] * v1[:, 1] - v0[:, 1] * v1[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        beta = (v2[:, 0] * v1[:, 1] - v2[:, 1] * v1[:, 0]) / det
        gamma = (v0[:, 0] * v2[:, 1] - v0[:, 1] * v2[:, 0]) / det
    return beta, gamma


def _split_kept(kept_faces, chains, number, count, vertices):
    """The kept faces, each split where chain samples lie inside its edges, and the new
    points that needs: a fan from the corner whose two edges carry no sample, or, when
    there is none, from the triangle's centroid (a new point, on the face)."""
    inside = (chains.t > 0) & (chains.t < 1)
    kept_faces = np.asarray(kept_faces, np.int64).reshape(-1, 3)
    # the faces with a sample inside an edge, found at once; the others stay as they are
    n = len(vertices)
    u, v = chains.u[inside].astype(np.int64), chains.v[inside].astype(np.int64)
    split = np.isin(kept_faces * n + kept_faces[:, [1, 2, 0]],
                    np.concatenate([u * n + v, v * n + u])).any(axis=1)
    if not split.any():
        return kept_faces.copy(), np.zeros((0, 3))
    # the samples inside the edges of the faces to split only (g-block-pockets: 1,932
    # samples inside edges, none on a kept face's), in one pass over their lists
    edge = np.column_stack([kept_faces[split].ravel(), kept_faces[split][:, [1, 2, 0]].ravel()])
    wanted = np.isin(u * n + v, np.concatenate([edge[:, 0] * n + edge[:, 1],
                                                edge[:, 1] * n + edge[:, 0]]))
    which = np.flatnonzero(inside)[wanted]
    on_edge = {}
    for s, a, b, t in zip(which.tolist(), u[wanted].tolist(), v[wanted].tolist(),
                          chains.t[which].tolist()):
        on_edge.setdefault((a, b), []).append((t, s))
        on_edge.setdefault((b, a), []).append((1 - t, s))
    pieces, centred = [], []
    for face in kept_faces[split].tolist():
        ring = []
        for k in range(3):
            a, b = face[k], face[(k + 1) % 3]
            ring.append(int(a))
            ring.extend(int(number[s]) for _, s in sorted(on_edge.get((a, b), [])))
        fan = _corner_fan(ring, face)
        if fan is None:
            centre = count + len(centred)
            centred.append(face)
            fan = [[centre, x, y] for x, y in zip(ring, ring[1:] + ring[:1])]
        pieces.append(fan)
    sizes = np.ones(len(kept_faces), np.int64)             # the faces in their order
    sizes[split] = [len(fan) for fan in pieces]
    out = np.repeat(kept_faces, sizes, axis=0)
    out[np.repeat(split, sizes)] = np.concatenate([np.array(fan, np.int64) for fan in pieces])
    return out, vertices[np.array(centred, np.int64).reshape(-1, 3)].mean(axis=1)


def _corner_fan(ring, face):
    """A fan over a triangle ``face`` whose edges carry extra points (``ring``, in
    order) from a corner whose two edges carry none, or None."""
    corners = [ring.index(v) for v in face]
    n = len(ring)
    for k, at in enumerate(corners):
        before, after = corners[k - 1], corners[(k + 1) % 3]
        if (at - before) % n == 1 and (after - at) % n == 1:
            others = [ring[(after + j) % n] for j in range((before - after) % n + 1)]
            return [[ring[at], x, y] for x, y in zip(others[:-1], others[1:])]
    return None


def _min_angles(vertices, faces) -> np.ndarray:
    """The smallest angle of each triangle, in degrees."""
    return _corner_angles(np.asarray(vertices)[np.asarray(faces)])


def _corner_angles(p) -> np.ndarray:
    """The smallest angle of each triangle (its corners ``p``, (n, 3, d)), in degrees."""
    lengths = np.linalg.norm(p[:, [1, 2, 0]] - p[:, [2, 0, 1]], axis=2)   # opposite each corner
    a, b, c = lengths.T
    cos = np.clip(np.stack([(b * b + c * c - a * a) / (2 * b * c), (a * a + c * c - b * b) / (2 * a * c),
                            (a * a + b * b - c * c) / (2 * a * b)], axis=1), -1, 1)
    return np.degrees(np.arccos(cos)).min(axis=1)
