"""The certificate of a mesh: what the paper promises, measured exactly on the result.

- **Separation**: the smallest distance between samples.
- **Coverage gap**: the largest distance from a point of the region to its nearest
  sample.
- **Quality** (Theorem 1): the largest aspect ratio L²/A against 4√3, and the angles.
- **Topology** (Theorem 2): Betti numbers of mesh and region, see :mod:`.topology`.
- **Boundary**: conformity, deviation, area outside and missing, see :mod:`.conformity`.

A conforming mesh (``mesh.conforming``) is measured with the **visibility rule**: two
points see each other when the segment between them stays in the region (up to the
chords' sagitta: in the union of the region and the sampled boundary polygon Q). Its
separation is the shortest distance between samples that see each other or share an
edge; its coverage gap the largest distance from a point of the region to a sample along
a path through the region: straight to a sample it sees, or around a reflex vertex of
the boundary that hides it (docs/conforming.md, "Routes around a kink"). Both are exact from the mesh itself once the mesh is verified to be Q
(docs/conforming.md, "What the certificate measures"): every point of a triangle sees the
triangle's corners, and the farthest point of a triangle from its nearest corner is its
circumcentre, or on its longest edge when the triangle is obtuse; the slivers of region
between a chord and a convex arc add the farthest point from the chord's ends.

Other meshes (the paper's construction) are measured with the Euclidean distance. The
separation is the closest pair of samples, found on a grid of cells of side at least
2 alpha (two samples closer than a cell's side lie in the same or adjacent cells; a pair
found farther apart than that is confirmed on a grid of cells as large as its distance),
so it needs no triangulation: flat or nearly flat sets of samples, whose triangles
Qhull drops, are measured like any other. On a polygonal region the coverage gap peaks
at a Voronoi vertex inside the region (the circumcentre of a Delaunay triangle), where a
Voronoi edge crosses the boundary, or at a boundary vertex; the last two are found
exactly along every boundary piece (see ``_certificate_kernels``).

The Delaunay triangulation DT(P) is never built whole. The solid alpha-complex T holds
its triangles of circumradius <= alpha; every other Delaunay triangle has all three
vertices on the boundary of T (a vertex inside T has its whole Delaunay star in T) or in
no triangle of T. Those vertices B are few, so DT(B) (Qhull) costs far less than DT(P),
and its triangles whose circumcircle holds no sample are exactly the Delaunay triangles
missing from T. Only those with their circumcentre in the region count for the coverage
gap.

Every distance query (closest pair, pairs closer than the shortest edge, empty
circumcircles, the samples near each boundary piece) runs on one grid of the samples,
built once per certificate.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely
from scipy.spatial import Delaunay, QhullError, cKDTree

from .. import _certificate_kernels as kern
from .._checks import check_planar_mesh
from ..errors import ArgumentError
from .._complex_kernels import bin_points
from .._geometry_kernels import circumcircles
from .conformity import (AREA_TOL, FACE_BLOCK, PROBES_PER_ALPHA, SampledBoundary,
                         boundary_report)
from .quality import ASPECT_BOUND
from .small_features import ExceptionalTriangle, small_feature_exceptions
from .topology import TopologyReport, topology_report

if TYPE_CHECKING:
    from ..mesh import PlanarMesh

__all__ = ["Certificate", "certify", "assemble", "coverage_peaks", "visibility_route_fails",
           "sees", "curve_deviation", "SEPARATION_TOL", "COVERAGE_TOL", "QUALITY_TOL"]

_LISTED = 5              # exceptions printed by str(certificate); all are in .exceptions

SEPARATION_TOL = 1e-12   # relative tolerances of the verdicts
COVERAGE_TOL = 1e-9
QUALITY_TOL = 1e-9


@dataclass(frozen=True)
class Certificate:
    """Measured guarantees of a :class:`~pds_plugin.PlanarMesh`.

    Distances are ratios to ``alpha``; ``ok`` holds when the sampling is a maximal
    Poisson disc sampling (separation >= 1, coverage gap <= 1), every triangle meets
    Theorem 1, every sample is used, the mesh is manifold and its topology is the
    region's; for a mesh made conforming (``claims_conforming``) also when it conforms,
    its outline is the polygon through its boundary samples, and separation and coverage
    hold under the visibility rule.

    A conforming mesh of a region with features smaller than alpha (sharp corners,
    short pieces, small rings, thin walls) keeps them, and has triangles below Theorem 1
    there: ``ok`` is then false, and ``ok_with_exceptions`` true when every triangle
    below Theorem 1 and every pair of samples closer than alpha is explained by such a
    feature and meets the bound proven for it (listed in ``exceptions``), and everything
    else holds.

    Attributes
    ----------
    alpha : float
        The mesh's radius.
    samples, triangles : int
        How many samples (vertices) and triangles the mesh has.
    min_separation : float
        The smallest distance between two samples / alpha (>= 1: Poisson); for a
        conforming mesh between samples that share an edge or see each other.
    coverage_gap : float
        The largest distance from a point of the region to the samples / alpha
        (<= 1: maximal); for a conforming mesh to the samples the point sees.
    coverage_gap_at : tuple of float
        Where the coverage gap peaks, in region coordinates.
    max_aspect_ratio : float
        The largest L²/A, at most 4√3 by Theorem 1.
    min_angle, max_angle : float
        The extreme angles in degrees, within [30, 120] by Theorem 1.
    isolated_samples : int
        Samples in no triangle.
    nonmanifold_vertices : int
        Vertices where two fans of triangles touch.
    area_ratio : float
        Mesh area / region area.
    outside_area_ratio, missing_area_ratio : float
        Mesh area outside the region, and region area outside the mesh, / region area.
    boundary_deviation : float
        Hausdorff distance between the mesh's and the region's boundaries / alpha.
    tolerance : float
        The region's tolerance (absolute, :attr:`Region.tolerance`): how far its
        boundary may lie from the input's.
    source_deviation : float
        The Hausdorff distance between the region's boundary and the input's, measured
        exactly (absolute; at most ``tolerance``, or ``ok`` is false).
    curve_deviation : float or None
        For a region with exact curves (``region.curves``: SVG, DXF, STEP): how far the
        curves bounding the region get from the mesh's boundary, / alpha, probed every
        alpha / 50 (:meth:`~pds_plugin.boundary_curves.BoundaryCurves.deviation`); the
        mesh's deviation from the true boundary, where ``boundary_deviation`` is from
        the region's polygon. None without curves.
    quadratic : JacobianReport or None
        The certificate of a quadratic mesh (``mesh.quadratic().certificate()``): its
        curved triangles' Jacobians (:class:`pds_plugin.quadratic.JacobianReport`);
        ``ok`` is false when one is not positive or below its bound. None for the
        linear mesh.
    conforming : bool
        Consecutive boundary samples are joined by mesh edges, and no edge of the mesh's
        boundary ends at an interior sample.
    sampled_outline : bool
        The union of the triangles is the polygon through the boundary samples.
    claims_conforming : bool
        The mesh was made conforming (``PlanarMesh.conforming``): the boundary fields and
        the visibility rule are then part of ``ok``.
    visibility : bool
        Separation and coverage were measured with the visibility rule.
    boundary_problems : tuple of str
        What breaks conformity, or why coverage was not measured with visibility, located.
    topology : TopologyReport
        Betti numbers of mesh and region, per component, and what differs where.
    exceptions : tuple of ExceptionalTriangle
        Conforming meshes: every triangle below Theorem 1 that a small feature explains,
        with its place, cause and proven bound
        (:class:`~pds_plugin.analysis.small_features.ExceptionalTriangle`).
    excused_pairs : int
        Conforming meshes: pairs of samples closer than alpha that see each other, each
        kept apart by a small feature at least its proven distance.
    unexplained : tuple of str
        Conforming meshes: triangles below Theorem 1 and pairs closer than alpha that no
        small feature explains, located.
    aspect_bound : float
        4√3, Theorem 1's bound (a class constant).
    angle_range : tuple of float
        (30, 120), Theorem 1's angles in degrees (a class constant).

    A graded mesh's certificate (:class:`~pds_plugin.analysis.graded_certificate.GradedCertificate`)
    has the same fields, measured against its radius field r instead of alpha, and its
    own bounds.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> cert = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2).certificate()
    >>> cert.ok, cert.betti_mesh, cert.min_separation >= 1
    (True, (1, 0), True)
    """

    alpha: float
    samples: int
    triangles: int
    min_separation: float
    coverage_gap: float
    coverage_gap_at: tuple[float, float]
    max_aspect_ratio: float
    min_angle: float
    max_angle: float
    isolated_samples: int
    nonmanifold_vertices: int
    area_ratio: float
    outside_area_ratio: float
    missing_area_ratio: float
    boundary_deviation: float
    conforming: bool
    sampled_outline: bool
    claims_conforming: bool
    visibility: bool
    boundary_problems: tuple[str, ...]
    topology: TopologyReport
    exceptions: tuple[ExceptionalTriangle, ...] = ()
    excused_pairs: int = 0
    unexplained: tuple[str, ...] = ()
    tolerance: float = 0.0
    source_deviation: float = 0.0
    curve_deviation: float | None = None
    quadratic: object = None

    aspect_bound = ASPECT_BOUND
    angle_range = (30.0, 120.0)
    unit = "alpha"              # what separation and coverage are ratios to
    _bound_name = "Theorem 1"   # the angle bound the exceptions are below
    _aspect_name = "4√3 = "

    @property
    def betti_mesh(self) -> tuple[int, int]:
        """``(b0, b1)`` of the mesh: components and holes."""
        return self.topology.betti_mesh

    @property
    def betti_region(self) -> tuple[int, int]:
        """``(b0, b1)`` of the region: components and holes."""
        return self.topology.betti_region

    @property
    def sampling_ok(self) -> bool:
        """Poisson (separation >= alpha) and maximal (coverage gap <= alpha)."""
        return (self.min_separation >= 1 - SEPARATION_TOL
                and self.coverage_gap <= 1 + COVERAGE_TOL)

    @property
    def quality_ok(self) -> bool:
        """Theorem 1: aspect ratio <= 4√3 and angles in [30°, 120°]."""
        if self.triangles == 0:
            return True
        return (self.max_aspect_ratio <= self.aspect_bound * (1 + QUALITY_TOL)
                and self.min_angle >= self.angle_range[0] * (1 - QUALITY_TOL)
                and self.max_angle <= self.angle_range[1] * (1 + QUALITY_TOL))

    @property
    def topology_ok(self) -> bool:
        """Theorem 2: the mesh has the region's components and holes, each in place."""
        return self.topology.topology_ok

    @property
    def boundary_ok(self) -> bool:
        """The mesh conforms, is the polygon through its boundary samples (so it deviates
        from the region by the chords' sagitta only), and was measured with visibility."""
        return self.conforming and self.sampled_outline and self.visibility

    @property
    def tolerance_ok(self) -> bool:
        """The region lies within its tolerance of the input."""
        return self.source_deviation <= self.tolerance

    @property
    def input_deviation(self) -> float:
        """A bound on the Hausdorff distance between the mesh's boundary and the input's,
        / alpha: the mesh's deviation from the region plus the region's from the input
        (the triangle inequality); at most the tolerance plus the chords' sagitta."""
        return self.boundary_deviation + self.source_deviation / self.alpha

    @property
    def ok(self) -> bool:
        """Every guarantee holds: sampling, quality, topology, no isolated sample, manifold."""
        return (self.sampling_ok and self.quality_ok and self._rest_ok)

    @property
    def exceptions_ok(self) -> bool:
        """Every triangle below Theorem 1 and every pair of samples closer than alpha is
        explained by a small feature, within the bound proven for it."""
        return not self.unexplained and all(e.meets_bound for e in self.exceptions)

    @property
    def ok_with_exceptions(self) -> bool:
        """``ok``, or every guarantee holds but separation and Theorem 1 at small features,
        where each exception is listed and within its proven bound."""
        return self.ok or (self._excused and self.coverage_gap <= 1 + COVERAGE_TOL
                           and (self.quality_ok or bool(self.exceptions)) and self._rest_ok)

    @property
    def _excused(self) -> bool:
        """There are exceptions, and each is explained and within its bound."""
        return bool(self.exceptions or self.excused_pairs) and self.exceptions_ok

    @property
    def _rest_ok(self) -> bool:
        return (self.topology_ok and self.tolerance_ok and self.isolated_samples == 0
                and (self.quadratic is None or self.quadratic.ok)
                and self.nonmanifold_vertices == 0
                and (self.boundary_ok or not self.claims_conforming))

    def as_dict(self) -> dict:
        """Plain JSON-ready values, verdicts included.

        Returns
        -------
        dict
            Every attribute (``topology`` as :meth:`TopologyReport.as_dict`), and
            ``aspect_bound``, ``betti_mesh``, ``betti_region``, ``sampling_ok``,
            ``quality_ok``, ``topology_ok`` and ``ok``.

        Examples
        --------
        >>> import json, pds_plugin as pds
        >>> from shapely.geometry import box
        >>> cert = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2).certificate()
        >>> values = cert.as_dict()
        >>> values["ok"], values["topology"]["betti_region"], len(json.dumps(values)) > 0
        (True, (1, 0), True)
        """
        values = {name: getattr(self, name) for name in self.__dataclass_fields__}
        values["coverage_gap_at"] = list(self.coverage_gap_at)
        values["boundary_problems"] = list(self.boundary_problems)
        values["topology"] = self.topology.as_dict()
        values["exceptions"] = [e.as_dict() for e in self.exceptions]
        values["unexplained"] = list(self.unexplained)
        values["quadratic"] = None if self.quadratic is None else self.quadratic.as_dict()
        values.update(aspect_bound=self.aspect_bound, betti_mesh=self.betti_mesh,
                      betti_region=self.betti_region, sampling_ok=self.sampling_ok,
                      quality_ok=self.quality_ok, topology_ok=self.topology_ok,
                      boundary_ok=self.boundary_ok, exceptions_ok=self.exceptions_ok,
                      tolerance_ok=self.tolerance_ok, input_deviation=self.input_deviation,
                      ok=self.ok, ok_with_exceptions=self.ok_with_exceptions)
        return values

    def __str__(self) -> str:
        def mark(good):
            return "ok" if good else "FAILED"
        if self.visibility:
            rule = ("to samples seen through the region, coverage along paths in it "
                    "(visibility rule)")
        elif self.claims_conforming:
            rule = "separation to samples seen through the region, coverage Euclidean"
        else:
            rule = "Euclidean"
        if self.claims_conforming:
            boundary = f"conforming mesh   {mark(self.boundary_ok)}"
        else:
            boundary = "reported, not part of ok: the mesh was made with conforming=False"
        if self.ok or not self.ok_with_exceptions:
            verdict = mark(self.ok)
        else:
            verdict = (f"ok with {len(self.exceptions)} exceptions at small features, each "
                       "within its proven bound")

        def excused(good):
            return "ok" if good else "exceptions" if self._excused else "FAILED"
        return "\n".join([
            f"certificate: {verdict} (alpha={self.alpha:.6g}, {self.samples} samples, "
            f"{self.triangles} triangles)",
            f"  distances    {rule}",
            f"  separation   min {self.min_separation:.9f} {self.unit} (>= 1)      {excused(self.min_separation >= 1 - SEPARATION_TOL)}",
            f"  coverage gap max {self.coverage_gap:.9f} {self.unit} (<= 1)      {mark(self.coverage_gap <= 1 + COVERAGE_TOL)}",
            f"  aspect ratio max {self.max_aspect_ratio:.6f} (<= {self._aspect_name}{self.aspect_bound:.6f})  {excused(self.quality_ok)}",
            f"  angles       [{self.min_angle:.3f}°, {self.max_angle:.3f}°] (within "
            f"[{self.angle_range[0]:g}°, {self.angle_range[1]:g}°])",
            f"  isolated samples {self.isolated_samples}, non-manifold vertices "
            f"{self.nonmanifold_vertices}, area ratio {self.area_ratio:.6f}",
            f"  boundary     {boundary}",
            f"    conforming {_yes(self.conforming)}, outline = polygon through the boundary "
            f"samples {_yes(self.sampled_outline)}",
            f"    deviation {self.boundary_deviation:.3g} alpha, outside "
            f"{self.outside_area_ratio:.3g} and missing {self.missing_area_ratio:.3g} of the "
            "region's area",
            *self._tolerance_lines(),
            *([] if self.curve_deviation is None else [
                f"    exact curves within {self.curve_deviation:.3g} alpha of the mesh's "
                "boundary (probed every alpha/50)"]),
            *[f"    - {p}" for p in self.boundary_problems],
            *([] if self.quadratic is None else [f"  {self.quadratic}"]),
            *self._exception_lines(),
            "  " + str(self.topology).replace("\n", "\n  "),
        ])

    def _tolerance_lines(self) -> list[str]:
        """The tolerance pass's deviation from the input, if the region had one."""
        if not self.tolerance:
            return []
        return [f"    tolerance {self.tolerance:.3g}: region within {self.source_deviation:.3g} "
                f"of the input {'ok' if self.tolerance_ok else 'FAILED'}, mesh within "
                f"{self.input_deviation:.3g} alpha of it"]

    def _exception_lines(self) -> list[str]:
        """The small features' exceptions to Theorem 1, the first few located."""
        if not (self.exceptions or self.excused_pairs or self.unexplained):
            return []
        more = len(self.exceptions) - _LISTED
        return [f"  exceptions   {len(self.exceptions)} triangles below {self._bound_name} and "
                f"{self.excused_pairs} pairs closer than {self.unit} at small features, "
                f"{'each within its proven bound' if self.exceptions_ok else 'NOT all explained and bounded'}",
                *[f"    - {e}" for e in self.exceptions[:_LISTED]],
                *([f"    ... {more} more (certificate.exceptions)"] if more > 0 else []),
                *[f"    - unexplained: {u}" for u in self.unexplained]]


def certify(mesh: PlanarMesh) -> Certificate:
    """Measure the certificate of a uniform ``mesh`` (see the module docstring).

    :meth:`PlanarMesh.certificate` calls this once and caches the result;
    :func:`pds_plugin.certify` takes any kind of mesh.

    Parameters
    ----------
    mesh : PlanarMesh

    Returns
    -------
    Certificate

    Raises
    ------
    ArgumentError
        If ``mesh`` is graded (its certificate is :func:`.graded_certificate.certify_graded`'s).

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> cert = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 2, 1)), 0.1).certificate()
    >>> cert.min_separation >= 1, cert.coverage_gap <= 1, cert.max_aspect_ratio <= cert.aspect_bound
    (True, True, True)
    """
    check_planar_mesh(mesh, "certify")
    if getattr(mesh, "field", None) is not None:     # measured against alpha it would fail
        raise ArgumentError("pds_plugin.analysis.certificate.certify measures uniform meshes "
                            "and this mesh is graded (mesh.field): use pds_plugin.certify(mesh) "
                            "or mesh.certificate()")
    points, alpha = mesh.vertices, mesh.alpha
    faces = np.ascontiguousarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
    quality = mesh.quality()
    grid = _SampleGrid(points, 2 * alpha)     # the closest pair, about alpha, lies in adjacent cells
    rim_edges = mesh.boundary_edges
    sampled = SampledBoundary(mesh.region, points, mesh.on_boundary, alpha, faces)
    boundary = boundary_report(mesh, sampled)
    problems = list(boundary.problems)
    visibility = False
    features = ((), 0, ())
    if mesh.conforming:
        separation, close = _visible_separation(mesh, quality, grid, sampled)
        features = small_feature_exceptions(mesh, quality, sampled, close)
        why_not = visibility_route_fails(mesh, boundary, sampled)
        if why_not:
            problems.append(f"coverage not measured with the visibility rule: {why_not}")
        else:
            visibility = True
            gap, gap_at = _visible_coverage(points, faces, quality, sampled)
    if not visibility:
        gap, gap_at = _coverage_gap(mesh, faces, rim_edges, grid)
    if not mesh.conforming:
        separation = grid.closest_distance()
    return assemble(Certificate, mesh, faces, quality, boundary, alpha=alpha,
                    separation=separation / alpha, gap=gap / alpha, gap_at=gap_at,
                    claims_conforming=mesh.conforming, visibility=visibility,
                    problems=problems, features=features)


def assemble(kind: type, mesh: PlanarMesh, faces, quality, boundary, *, alpha: float,
             separation: float, gap: float, gap_at, claims_conforming: bool,
             visibility: bool, problems, features, **fields):
    """The certificate of ``kind`` (:class:`Certificate` or a subclass) from what was
    measured on ``mesh``: the one place both kinds of certificate are put together.

    The fields every mesh has are read here (counts, quality extremes, isolated samples,
    non-manifold vertices, areas and deviations from ``boundary``, topology, the
    region's tolerance, the exact curves' deviation); the measures that depend on the
    kind come in.

    Parameters
    ----------
    kind : type
        The certificate class.
    mesh : PlanarMesh
    faces : (M, 3) int64 ndarray
        The mesh's triangles.
    quality : Quality
        ``mesh.quality()``.
    boundary : BoundaryReport
        :func:`.conformity.boundary_report` of the mesh.
    alpha : float
        The radius (a graded mesh's cap).
    separation, gap : float
        Separation and coverage gap, as ratios (to alpha, or to r).
    gap_at : (2,) array_like
        Where the gap peaks.
    claims_conforming, visibility : bool
    problems : list of str
        The boundary's problems and why visibility was not used.
    features : tuple
        ``(exceptions, excused_pairs, unexplained)`` of
        :func:`.small_features.small_feature_exceptions`.
    **fields
        The fields of ``kind`` beyond :class:`Certificate`'s.

    Returns
    -------
    Certificate
        An instance of ``kind``.
    """
    points = mesh.vertices
    exceptions, excused, unexplained = features
    used = np.zeros(len(points), bool)
    used[faces.ravel()] = True
    return kind(
        alpha=alpha, samples=len(points), triangles=len(faces),
        min_separation=separation,
        coverage_gap=gap, coverage_gap_at=tuple(float(v) for v in gap_at),
        max_aspect_ratio=float(quality.aspect_ratio.max(initial=0.0)),
        min_angle=float(quality.angles.min(initial=180.0)),
        max_angle=float(quality.angles.max(initial=0.0)),
        isolated_samples=int(np.count_nonzero(~used)),
        nonmanifold_vertices=_nonmanifold_vertices(mesh.boundary_edges, len(points)),
        area_ratio=float(quality.area.sum() / mesh.region.area),
        outside_area_ratio=boundary.outside_area_ratio,
        missing_area_ratio=boundary.missing_area_ratio,
        boundary_deviation=boundary.boundary_deviation,
        conforming=boundary.conforming, sampled_outline=boundary.sampled_outline,
        claims_conforming=claims_conforming, visibility=visibility,
        boundary_problems=tuple(problems),
        topology=topology_report(mesh),
        exceptions=exceptions, excused_pairs=excused, unexplained=unexplained,
        tolerance=mesh.region.tolerance, source_deviation=mesh.region.source_deviation,
        curve_deviation=curve_deviation(mesh),
        **fields,
    )


def curve_deviation(mesh) -> float | None:
    """How far the exact curves bounding the mesh's region get from its boundary edges,
    / alpha, probed every alpha / :data:`PROBES_PER_ALPHA`; None without curves."""
    curves = mesh.region.curves
    if curves is None:
        return None
    return curves.deviation(mesh.vertices[mesh.boundary_edges], mesh.region.segments,
                            mesh.alpha / PROBES_PER_ALPHA) / mesh.alpha


def _yes(value: bool) -> str:
    return "yes" if value else "no"


def visibility_route_fails(mesh, boundary, sampled) -> str:
    """Why the exact coverage route of a conforming mesh does not apply ('' if it does):
    it needs the mesh to be the sampled boundary polygon Q, and the region that Q misses
    to be convex pieces beyond the chords, each seen whole from a chord end it holds.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2)
    >>> sampled = SampledBoundary(mesh.region, mesh.vertices, mesh.on_boundary, 0.2, mesh.faces)
    >>> visibility_route_fails(mesh, boundary_report(mesh, sampled), sampled)
    ''
    """
    if not len(mesh.faces):
        return "the mesh has no triangle"
    if not boundary.sampled_outline:
        return "the mesh is not the polygon through its boundary samples"
    if sampled.uncertain.any():
        where = (sampled.points[sampled.a[sampled.uncertain]]
                 + sampled.points[sampled.b[sampled.uncertain]])[0] / 2
        return (f"the boundary bends both ways between {int(sampled.uncertain.sum())} pairs of "
                f"consecutive boundary samples, e.g. near ({where[0]:.4g}, {where[1]:.4g}), "
                "and the region beyond their chord is not all seen from one of them")
    missing = boundary.missing_area_ratio * mesh.region.area
    if abs(missing - sampled.sliver_area()) > AREA_TOL * mesh.region.area:
        return (f"the region missing from the mesh ({missing:.6g}) is not the slivers between "
                f"chords and boundary ({sampled.sliver_area():.6g}): chords cross other boundary")
    return ""


def _visible_separation(mesh, quality, grid, sampled):
    """The smallest distance between samples that share an edge or see each other: the
    shortest edge, or a closer pair (on the grid) whose segment stays in the region (up
    to the chords' sagitta). And the (P, 2) pairs closer than alpha among them."""
    alpha = mesh.alpha
    shortest = float(quality.edge_lengths.min(initial=np.inf))
    reach = max(shortest, alpha) if np.isfinite(shortest) else 2.0 * alpha
    pairs = grid.pairs_within(reach)
    points = mesh.vertices
    segments = points[pairs]
    length = np.hypot(*(segments[:, 1] - segments[:, 0]).T)
    close = length < max(shortest, alpha * (1 - SEPARATION_TOL))
    edges = mesh.edges
    short_edges = edges[np.hypot(*(points[edges[:, 1]] - points[edges[:, 0]]).T)
                        < alpha * (1 - SEPARATION_TOL)]
    if not close.any():
        return shortest, short_edges
    seen = sees(shapely.union(mesh.region.geometry, sampled.polygon()), segments[close], alpha)
    nearest = float(min(shortest, length[close][seen].min(initial=np.inf)))
    near = pairs[close][seen & (length[close] < alpha * (1 - SEPARATION_TOL))]
    return nearest, np.concatenate([short_edges, near])


def sees(domain, segments, alpha) -> np.ndarray:
    """Whether each (k, 2, 2) segment stays in ``domain``, up to 1e-9 alpha of its length
    (boundary samples are on the boundary only to rounding).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> notch = box(0, 0, 2, 2).difference(box(0.9, 1, 1.1, 2))
    >>> sees(notch, np.array([[[0.5, 1.5], [1.5, 1.5]], [[0.5, 0.5], [1.5, 0.5]]]), 0.1).tolist()
    [False, True]
    """
    shapely.prepare(domain)
    lines = shapely.linestrings(segments)
    inside = shapely.covers(domain, lines)
    doubt = ~inside
    if doubt.any():
        inside[doubt] = shapely.length(shapely.difference(lines[doubt], domain)) <= 1e-9 * alpha
    return inside


def _visible_coverage(points, faces, quality, sampled):
    """The coverage gap of a conforming mesh that is its sampled boundary polygon Q.

    Every point of a triangle sees the triangle's corners, so its distance to a sample it
    sees is at most the distance to the nearest corner. Over a triangle that peaks at the
    circumcentre (distance R) when no angle is obtuse, else at one of the two points of
    the longest edge AB equidistant from C and A (at ``|AC|/(2 cos A)`` from A) or from C
    and B; both are below R. The slivers of region outside Q add
    :meth:`SampledBoundary.sliver_gap`.
    """
    gap, at = -np.inf, None
    for start in range(0, len(faces), FACE_BLOCK):       # a block at a time: (M, 3) transients
        part = slice(start, start + FACE_BLOCK)          # would set a 1M mesh's peak memory
        block_gap, block_at = _triangles_reach(points, faces[part], quality.edge_lengths[part])
        if block_gap > gap:
            gap, at = block_gap, block_at
    sliver, sliver_at = sampled.sliver_gap()
    if sliver > gap:
        gap, at = sliver, sliver_at
    return gap, np.asarray(at, float)


def _triangles_reach(points, faces, lengths):
    """The farthest any point of these triangles is from its nearest corner, and where
    (see :func:`_visible_coverage`; the points of :func:`coverage_peaks`)."""
    peaks, reach, obtuse = coverage_peaks(points, faces, lengths)
    value = np.where(obtuse, -np.inf, reach[:, 0])
    best = int(np.argmax(value))
    gap, at = float(value[best]), peaks[best, 0]
    k = np.flatnonzero(obtuse)            # below their circumradius: only beat a larger one
    if len(k):
        farther = reach[k].max(axis=1)
        j = int(np.argmax(farther))
        if farther[j] > gap:
            gap = float(farther[j])
            at = peaks[k[j], 0] if reach[k[j], 0] >= reach[k[j], 1] else peaks[k[j], 1]
    return gap, at


def coverage_peaks(points, faces, lengths):
    """Where the distance from a point of each triangle to the triangle's nearest corner
    peaks, and that distance: the geometry of both kinds of certificate's coverage.

    When no angle is obtuse, at the circumcentre (distance R); else at one of the two
    points of the longest edge AB equidistant from C and A (at ``|AC|²|AB| / (2 AB·AC)``
    from A) or from C and B, both closer than R.

    Parameters
    ----------
    points : (N, 2) float ndarray
    faces : (M, 3) int ndarray
    lengths : (M, 3) float ndarray
        Each triangle's edge lengths, edge k opposite corner k (``Quality.edge_lengths``).

    Returns
    -------
    peaks : (M, 2, 2) float ndarray
        Two places per triangle (the circumcentre twice when it is not obtuse).
    reach : (M, 2) float ndarray
        Their distances to the triangle's nearest corner.
    obtuse : (M,) bool ndarray

    Examples
    --------
    >>> from pds_plugin.analysis.quality import triangle_quality
    >>> points = np.array([[0, 0], [4, 0], [2, 1], [2, 3]], float)
    >>> faces = np.array([[0, 1, 2], [0, 1, 3]])
    >>> peaks, reach, obtuse = coverage_peaks(points, faces,
    ...                                       triangle_quality(points, faces).edge_lengths)
    >>> obtuse.tolist(), peaks[0].round(6).tolist(), reach[0].round(6).tolist()
    ([True, False], [[1.25, 0.0], [2.75, 0.0]], [1.25, 1.25])
    >>> peaks[1, 0].round(6).tolist(), round(float(reach[1, 0]), 6)   # R = 13/6
    ([2.0, 0.833333], 2.166667)
    """
    centre, radius = circumcircles(points, faces)
    squared = lengths ** 2                                     # edge k opposite corner k
    # np.argmax and sum over axis 1 (first of equal ones; (s0 + s1) + s2) from the columns:
    # on (M, 3) arrays those reductions cost five times more
    s0, s1, s2 = squared.T
    longest = np.where(s0 >= s1, np.where(s0 >= s2, 0, 2), np.where(s1 >= s2, 1, 2))
    obtuse = 2 * np.take_along_axis(squared, longest[:, None], axis=1)[:, 0] > s0 + s1 + s2
    peaks = np.hstack([centre, centre]).reshape(-1, 2, 2)
    reach = np.column_stack([radius, radius])
    k = np.flatnonzero(obtuse)
    if len(k):
        c = faces[k, longest[k]]
        a = faces[k, (longest[k] + 1) % 3]
        b = faces[k, (longest[k] + 2) % 3]
        pa, pb, pc = points[a], points[b], points[c]
        ab = pb - pa
        length = np.hypot(ab[:, 0], ab[:, 1])
        unit = ab / length[:, None]
        from_a = squared[k, (longest[k] + 2) % 3] * length / (2 * np.einsum("ij,ij->i", ab, pc - pa))
        from_b = squared[k, (longest[k] + 1) % 3] * length / (2 * np.einsum("ij,ij->i", -ab, pc - pb))
        peaks[k, 0] = pa + unit * from_a[:, None]
        peaks[k, 1] = pb - unit * from_b[:, None]
        reach[k, 0], reach[k, 1] = from_a, from_b
    return peaks, reach, obtuse


def _nonmanifold_vertices(boundary_edges, n_vertices) -> int:
    """Vertices on more than two boundary edges: two fans of triangles meet there."""
    return int(np.count_nonzero(np.bincount(boundary_edges.ravel(), minlength=n_vertices) > 2))


class _SampleGrid:
    """The samples sorted into square cells (``bin_points``: CSR, cell by cell), for every
    distance query of the certificate. The side is ``cell`` (2 alpha), or larger when the
    samples are sparse in their bounding box: at most about three cells per sample.

    Examples
    --------
    >>> grid = _SampleGrid(np.array([[0, 0], [3, 0], [3, 0.5], [0, 2]], float), 1.0)
    >>> float(grid.closest_distance()), grid.pairs_within(2.0).tolist()
    (0.5, [[0, 3], [1, 2]])
    """

    _CROWDED = 64        # samples in one cell above which the KD-tree finds the closest pair

    def __init__(self, points, cell):
        self.points = np.ascontiguousarray(points, dtype=float).reshape(-1, 2)
        n = len(self.points)
        low = self.points.min(axis=0) if n else np.zeros(2)
        span = self.points.max(axis=0) - low if n else np.zeros(2)
        self.h = float(max(cell, np.sqrt(span[0] * span[1] / max(n, 1)), span.max() / max(n, 1)))
        self.x0, self.y0 = (float(v) for v in low)
        self.nx, self.ny = (int(v / self.h) + 1 for v in span)
        self.order, self.start = bin_points(self.points, self.x0, self.y0, self.h,
                                            self.nx, self.ny)
        self.binned = np.ascontiguousarray(self.points[self.order])
        self.crowd = int(np.diff(self.start).max(initial=0))

    def _cells(self):
        return self.binned, self.start, self.x0, self.y0, self.h, self.nx, self.ny

    def closest_distance(self) -> float:
        """The smallest distance between two samples, exact (inf for fewer than two)."""
        if len(self.points) < 2:
            return np.inf
        if self.crowd > self._CROWDED:
            i, j = _closest_by_tree(self.points)
        else:
            p, q, squared = kern.closest_pair(self.binned, self.start, self.nx, self.ny)
            if not np.sqrt(squared) <= self.h * (1 - 1e-6):     # (no underflow of h²)
                # the pair found may not be the closest: cells as large as its distance
                # (or four times larger when no two samples were neighbours) settle it
                side = np.sqrt(squared) * 1.001 if np.isfinite(squared) else 4 * self.h
                return _SampleGrid(self.points, side).closest_distance()
            i, j = self.order[p], self.order[q]
        dx, dy = self.points[j] - self.points[i]
        return float(np.sqrt(dx * dx + dy * dy))

    def pairs_within(self, limit) -> np.ndarray:
        """(P, 2) sample indices of the pairs at most ``limit`` apart, each pair once."""
        pairs = kern.pairs_within(self.binned, self.start, self.nx, self.ny, self.h, limit)
        return self.order[pairs]

    def sample_within(self, centre, radius) -> np.ndarray:
        """For each circle, whether a sample lies closer than ``radius`` to its centre."""
        return kern.sample_within(centre, radius, *self._cells())

    def boundary_gaps(self, start, direction, length, reach):
        """:func:`_certificate_kernels.boundary_gaps` with the samples within
        ``0.5 * length + reach`` of each piece's middle."""
        span = int(2 * (0.5 * length.max(initial=0) + reach) / self.h) + 3
        most = min(self.crowd * span * span, len(self.points))
        return kern.boundary_gaps(start, direction, length, reach, self.points, self.order,
                                  *self._cells(), most)


def _closest_by_tree(points):
    """The closest pair of samples (i, j) by KD-tree: for crowded grids."""
    distance, neighbour = cKDTree(points).query(points, k=2)
    i = int(np.argmin(distance[:, 1]))
    return i, int(neighbour[i, 1])


def _missing_delaunay_circles(points, faces, rim_edges, grid, geometry):
    """Circumcentres and radii of the Delaunay triangles of ``points`` that are not in
    ``faces`` (see the module documentation) and whose centre lies in ``geometry``."""
    rim = np.ones(len(points), bool)
    rim[faces.ravel()] = False           # vertices in no triangle...
    rim[rim_edges.ravel()] = True        # ...and those on the complex's boundary
    rim = np.flatnonzero(rim)
    if len(rim) < 3:
        return np.empty((0, 2)), np.empty(0)
    try:
        local = Delaunay(points[rim]).simplices
    except QhullError:            # all collinear: no triangle at all
        return np.empty((0, 2)), np.empty(0)
    centre, radius = circumcircles(points, rim[local])
    keep = np.isfinite(radius)                  # Qhull's slivers on collinear points
    keep[keep] = shapely.intersects_xy(geometry, centre[keep, 0], centre[keep, 1])
    centre, radius = centre[keep], radius[keep]
    empty = ~grid.sample_within(centre, radius * (1 - 1e-9))
    return centre[empty], radius[empty]


def _coverage_gap(mesh, faces, rim_edges, grid):
    """The largest distance from the region to the samples, and where it is."""
    region, points = mesh.region, mesh.vertices
    geometry = region.geometry
    shapely.prepare(geometry)
    best, best_at = _boundary_gap(region, grid, mesh.alpha)
    # Voronoi vertices of the missing Delaunay triangles that lie in the region
    centre, radius = _missing_delaunay_circles(points, faces, rim_edges, grid, geometry)
    if len(radius):
        k = np.argmax(radius)
        if radius[k] > best:
            best, best_at = radius[k], centre[k]
    # those of the complex: the largest circumradius above `best` whose centre is in the region
    centre, radius = circumcircles(points, faces)
    larger = np.flatnonzero(radius > best)
    larger = larger[np.argsort(-radius[larger])]
    for chunk in np.array_split(larger, len(larger) // 4096 + 1):
        inside = shapely.intersects_xy(geometry, centre[chunk, 0], centre[chunk, 1])
        if inside.any():
            k = chunk[np.argmax(inside)]
            best, best_at = radius[k], centre[k]
            break
    return float(best), np.asarray(best_at, float)


def _boundary_gap(region, grid, alpha):
    """Largest distance to the samples along the boundary, exact: candidates within
    ``reach`` of a piece settle every point whose nearest sample is nearer than ``reach``;
    pieces whose gap exceeds it are redone with a larger reach, until every sample is a
    candidate."""
    start, direction, length = region.boundary_pieces(alpha)
    middle = start + 0.5 * length[:, None] * direction
    gap = np.full(len(start), np.inf)
    where = np.zeros(len(start))
    todo = np.arange(len(start))
    corners = np.array([[grid.x0, grid.y0], [grid.x0 + grid.nx * grid.h, grid.y0 + grid.ny * grid.h]])
    reach = 2.0 * alpha
    while len(todo):
        gap[todo], where[todo] = grid.boundary_gaps(start[todo], direction[todo], length[todo],
                                                    reach)
        farthest = np.abs(middle[todo, None, :] - corners[None]).max(axis=1)
        if (0.5 * length[todo] + reach >= np.hypot(*farthest.T)).all():
            break                               # every sample was a candidate
        todo = todo[gap[todo] > reach]
        reach *= 4.0
    p = int(np.argmax(gap))
    return gap[p], start[p] + where[p] * direction[p]
