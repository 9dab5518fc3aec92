"""The certificate of a graded mesh (docs/graded.md): the uniform certificate's questions
(:mod:`.certificate`) asked against the radius field r instead of one alpha.

- **Separation**: the smallest ``|pq| / min(r(p), r(q))`` over the pairs of samples that
  share an edge or see each other through the region (every pair closer than r of one
  of them is looked at); at least 1.
- **Coverage gap**: the largest ``min_v |x - v| / r(x)`` over the points x of each
  triangle and its corners v, taken where ``min_v |x - v|`` peaks: the circumcentre, or
  on the longest edge of an obtuse triangle where the bisectors of the two shorter edges
  cross it (the points the uniform certificate measures, :mod:`.certificate`); with the
  slivers of region beyond the chords. At most 1. r is taken at those points, so this
  is exact for the distance and samples r where the distance peaks (docs/graded.md §7).
  Peaks in a chord's *lens*, where the sampler places no sample (one there would drop
  the chord's triangle), are measured apart (``lens_coverage``): at most 1 for ``ok``,
  at most the proven 1 / (1 - L) for ``ok_with_exceptions``.
- **Quality**: the angles against the proven ``θ_L = arcsin((1 - L)/2)`` and the aspect
  ratio against ``4 cot θ_L``; the triangles below θ_L are located.
- **Small features** (:mod:`.small_features`, with r for alpha): every pair closer than
  the smaller r of the two that see each other and every triangle below θ_L is explained
  by a sharp corner, short piece, small ring or thin wall within its proven bound
  (``exceptions``, ``excused_pairs``), or listed in ``unexplained``: ``ok`` stays strict,
  ``ok_with_exceptions`` holds when everything else does and every breach is explained.
- **Boundary and topology**: conformity, the outline as the polygon through the
  boundary samples, deviation and areas (:mod:`.conformity`), Betti numbers
  (:mod:`.topology`), exactly as for uniform meshes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..sizing import angle_bound
from .certificate import (COVERAGE_TOL, QUALITY_TOL, SEPARATION_TOL, Certificate, assemble,
                          coverage_peaks, sees, visibility_route_fails)
from .conformity import SampledBoundary, boundary_report
from .small_features import small_feature_exceptions

if TYPE_CHECKING:
    from ..mesh import PlanarMesh

__all__ = ["GradedCertificate", "certify_graded"]

_MAX_LOCATED = 5        # triangles below the angle bound located in the report


@dataclass(frozen=True)
class GradedCertificate(Certificate):
    """Measured guarantees of a graded :class:`~pds_plugin.PlanarMesh`: the fields of
    :class:`~pds_plugin.analysis.certificate.Certificate`, with separation and coverage
    gap as ratios to the local radius r, and the bounds of the grading L.

    Attributes
    ----------
    grading : float
        The Lipschitz constant L of the radius field.
    proven_angle : float
        θ_L = arcsin((1 - L)/2) in degrees: every angle is at least this.
    below_bound : tuple of (float, float)
        Centroids of the triangles with an angle below θ_L (at most 5 listed).
    below_bound_count : int
        How many there are.
    smallest_radius, largest_radius : float
        The extremes of r over the samples.
    lens_coverage : float
        The largest coverage ratio at a peak inside a chord's lens (0 if none is above
        1): the points on a chord's inner side where a sample would make the chord's
        triangle too large to keep, so the sampler leaves them to the chord's ends,
        which are within r(x) / (1 - L) of them.
    lens_coverage_at : tuple of float
        Where.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> region = pds.Region.from_shapely(box(0, 0, 9, 1))
    >>> cert = pds.mesh_region(region, "auto", graded=True).certificate()
    >>> cert.ok, cert.min_angle >= cert.proven_angle, cert.unit
    (True, True, 'r')
    """

    grading: float = 0.0
    proven_angle: float = 30.0
    below_bound: tuple = ()
    below_bound_count: int = 0
    smallest_radius: float = 0.0
    largest_radius: float = 0.0
    lens_coverage: float = 0.0
    lens_coverage_at: tuple = (0.0, 0.0)

    unit = "r"
    _aspect_name = "4 cot θ_L = "
    _bound_name = "θ_L"

    @property
    def aspect_bound(self) -> float:
        """4 cot θ_L: the aspect ratio L²/A of a triangle whose angles are all >= θ_L."""
        return 4 / math.tan(math.radians(self.proven_angle))

    @property
    def angle_range(self) -> tuple[float, float]:
        """(θ_L, 180° - 2 θ_L): the angles the proof allows."""
        return self.proven_angle, 180.0 - 2 * self.proven_angle

    @property
    def quality_ok(self) -> bool:
        """Every angle at least θ_L (so the aspect ratio at most 4 cot θ_L)."""
        return self.below_bound_count == 0 and (
            self.triangles == 0 or self.min_angle >= self.proven_angle * (1 - QUALITY_TOL))

    @property
    def lens_ok(self) -> bool:
        """The coverage in chords' lenses is within its proven 1 / (1 - L)."""
        return self.lens_coverage <= (1 + COVERAGE_TOL) / (1 - self.grading)

    @property
    def ok(self) -> bool:
        """Every guarantee holds, the coverage in chords' lenses included."""
        return super().ok and self.lens_coverage <= 1 + COVERAGE_TOL

    @property
    def ok_with_exceptions(self) -> bool:
        """As for uniform meshes, with the coverage in chords' lenses within its bound."""
        strict = self.sampling_ok and self.quality_ok and self._rest_ok
        excused = (self._excused and self.coverage_gap <= 1 + COVERAGE_TOL
                   and (self.quality_ok or bool(self.exceptions)) and self._rest_ok)
        return self.lens_ok and (strict or excused)

    def as_dict(self) -> dict:
        """:meth:`Certificate.as_dict` with the graded fields (``below_bound`` as lists)."""
        values = super().as_dict()
        values["below_bound"] = [list(c) for c in self.below_bound]
        values["lens_coverage_at"] = list(self.lens_coverage_at)
        values["lens_ok"] = self.lens_ok
        return values

    def __str__(self) -> str:
        lines = super().__str__().split("\n")
        lines[0] = "graded " + lines[0]
        lines.insert(1, f"  grading      L={self.grading:g}, r in [{self.smallest_radius:.4g}, "
                        f"{self.largest_radius:.4g}]; angles proven >= {self.proven_angle:.3f}°, "
                        f"{self.below_bound_count} triangles below")
        if self.lens_coverage > 1 + COVERAGE_TOL:
            at = ", ".join(f"{v:.4g}" for v in self.lens_coverage_at)
            bound = 1 / (1 - self.grading)
            lines.insert(4, f"  in a lens    coverage {self.lens_coverage:.6f} r at ({at}), in a "
                            f"chord's lens where no sample may go (<= 1/(1-L) = {bound:.4g})  "
                            f"{'exception' if self.lens_ok else 'FAILED'}")
        return "\n".join(lines)


def certify_graded(mesh: PlanarMesh) -> GradedCertificate:
    """Measure the certificate of a graded ``mesh`` (see the module docstring).

    :meth:`PlanarMesh.certificate` calls this once for a mesh with a radius field.

    Parameters
    ----------
    mesh : PlanarMesh
        A graded mesh (``mesh.field`` is its radius field).

    Returns
    -------
    GradedCertificate
    """
    points, field = mesh.vertices, mesh.field
    faces = np.ascontiguousarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
    radius = field(points)
    quality = mesh.quality()
    sampled = SampledBoundary(mesh.region, points, mesh.on_boundary, field.cap, faces, field)
    boundary = boundary_report(mesh, sampled)
    problems = list(boundary.problems)
    why_not = visibility_route_fails(mesh, boundary, sampled)
    if why_not:
        problems.append(f"coverage not measured with the visibility rule: {why_not}")
    gap, gap_at, lens, lens_at = _relative_coverage(points, faces, quality.edge_lengths,
                                                    field, sampled)
    proven = angle_bound(field.grading)
    angles = quality.angles.reshape(-1, 3)
    smallest = np.minimum(np.minimum(angles[:, 0], angles[:, 1]), angles[:, 2])   # of each
    low = np.flatnonzero(smallest < proven * (1 - QUALITY_TOL))
    separation, close = _relative_separation(mesh, radius, sampled)
    features = small_feature_exceptions(mesh, quality, sampled, close, radius=radius,
                                        grading=field.grading)
    return assemble(
        GradedCertificate, mesh, faces, quality, boundary, alpha=field.cap,
        separation=separation, gap=gap, gap_at=gap_at, claims_conforming=True,
        visibility=not why_not, problems=problems, features=features,
        grading=field.grading, proven_angle=proven,
        below_bound=tuple(tuple(float(v) for v in points[faces[k]].mean(axis=0))
                          for k in low[:_MAX_LOCATED]),
        below_bound_count=len(low),
        smallest_radius=float(radius.min(initial=np.inf)),
        largest_radius=float(radius.max(initial=0.0)),
        lens_coverage=lens, lens_coverage_at=tuple(float(v) for v in lens_at),
    )


_ONE_REACH = 2.0
"""Where the largest r is at most this many times the smallest, the pairs closer than
the largest search radius are found in one search (``query_pairs``) and filtered, which
costs a third of one search per point; beyond it that search would return too many."""


def _relative_separation(mesh, radius, sampled):
    """min |pq| / min(r(p), r(q)) over the mesh edges and the pairs that see each other,
    and the (P, 2) pairs among them closer than the smaller r of the two: a pair below
    the edges' minimum m (or below 1) has |pq| < max(m, 1) r(p), so the samples within
    that of each p are the only ones to look at."""
    points = mesh.vertices
    edges = mesh.edges
    ratio = np.hypot(*(np.take(points, edges[:, 0], axis=0)
                       - np.take(points, edges[:, 1], axis=0)).T) / np.minimum(
        radius[edges[:, 0]], radius[edges[:, 1]])
    best = float(ratio.min(initial=np.inf))
    short_edges = edges[ratio < 1 - SEPARATION_TOL]
    if not np.isfinite(best) or len(points) < 2:
        return best, short_edges
    # unbalanced and not shrunk to its points: built in half the time, the same pairs
    tree = cKDTree(points, balanced_tree=False, compact_nodes=False)
    reach = max(best, 1.0) * radius
    if reach.max() <= _ONE_REACH * reach.min():     # one search radius serves every point
        p, q = tree.query_pairs(reach.max(), output_type="ndarray").T
    else:
        near = tree.query_ball_point(points, reach, return_sorted=False)
        count = np.fromiter(map(len, near), np.int64, len(near))
        p = np.repeat(np.arange(len(points)), count)
        q = np.fromiter((j for group in near for j in group), np.int64, int(count.sum()))
        p, q = p[p < q], q[p < q]
    order = np.lexsort((q, p))
    p, q = p[order], q[order]
    ratio = np.hypot(*(points[p] - points[q]).T) / np.minimum(radius[p], radius[q])
    close = ratio < max(best, 1 - SEPARATION_TOL)
    if not close.any():
        return best, short_edges
    # a pair sees each other through the region or through the mesh's polygon Q: the
    # region alone first, their union (a GEOS overlay) only for the pairs it does not see
    segments = np.stack([points[p[close]], points[q[close]]], axis=1)
    seen = sees(mesh.region.geometry, segments, mesh.alpha)
    if not seen.all():
        seen[~seen] = sees(shapely.union(mesh.region.geometry, sampled.polygon()),
                           segments[~seen], mesh.alpha)
    below = seen & (ratio[close] < 1 - SEPARATION_TOL)
    pairs = np.column_stack([p[close][below], q[close][below]])
    nearest = float(min(best, ratio[close][seen].min(initial=np.inf)))
    return nearest, np.concatenate([short_edges, pairs])


def _relative_coverage(points, faces, lengths, field, sampled):
    """The largest min_v |x - v| / r(x) at the points of each triangle where the distance
    to its nearest corner peaks (:func:`.certificate.coverage_peaks`, as for uniform
    meshes), and at the farthest point of the slivers beyond the chords (see the module
    docstring), and where; then the same over the peaks above 1 that lie in a chord's
    lens (:func:`_in_a_lens`), measured apart."""
    worst, at, lens, lens_at = 0.0, np.zeros(2), 0.0, np.zeros(2)
    if len(faces):
        peaks, reach, _ = coverage_peaks(points, faces, lengths)
        radii = field(peaks.reshape(-1, 2)).reshape(-1, 2)      # r point by point, in one call
        for side in (0, 1):
            peak = peaks[:, side]
            radius = radii[:, side]
            ratio = reach[:, side] / radius
            high = np.flatnonzero(ratio > 1 + COVERAGE_TOL)
            high = high[_in_a_lens(peak[high], radius[high], field, sampled)]
            if len(high) and ratio[high].max() > lens:
                k = high[np.argmax(ratio[high])]
                lens, lens_at = float(ratio[k]), peak[k]
            ratio[high] = 0.0
            k = int(np.argmax(ratio))
            if ratio[k] > worst:
                worst, at = float(ratio[k]), peak[k]
    sliver, sliver_at = sampled.sliver_gap()
    if sliver > 0:
        ratio = sliver / float(field(np.asarray(sliver_at, float)[None])[0])
        if ratio > worst:
            worst, at = ratio, np.asarray(sliver_at, float)
    return worst, at, lens, lens_at


def _in_a_lens(x, radius, field, sampled) -> np.ndarray:
    """Which points ``x`` (r there ``radius``) lie in the lens of a chord ab of
    ``sampled`` with the limit min(r(x), r(a), r(b)) / (1 - L) (r: ``field``): on the
    chord's inner side, with an obtuse angle at x and the circumradius of (a, b, x)
    above that limit, the graded sampler's rule for a place where no sample goes
    (``_graded_kernels._encroaches``, the same limit), or on the chord itself, the lens's edge (where the coverage is the limit of the lens's; 1e-9
    of its length² across it, a peak on it computed a rounding outside). Such an x is
    in the circular segment of radius ``l`` (that limit) on ab, and sees a or b within
    the distance from a to the middle of that segment's arc, √(2 l h) ≤ l for a chord of
    at most √3 l (h the segment's height): within l ≤ r(x) / (1 - L) of a sample. A
    chord 7 long between r = 2.8 at L = 0.45 (a plate's edge) left its points near the
    middle 1.046 r from the ends and the guard: counted as uncovered, though the lens
    beside them was excused. With r(x) alone, the lenses of chords along which r grows
    were narrower than the sampler's: a held-out vase's section at L = 0.4 left a
    circumcentre 1.10 r from every sample where the sampler had refused darts."""
    found = np.zeros(len(x), bool)
    if not len(x) or not len(sampled.a):
        return found
    a, b = sampled.points[sampled.a], sampled.points[sampled.b]
    limit = radius / (1 - field.grading)
    chord_limit = np.minimum(field(a), field(b)) / (1 - field.grading)
    ab, ab2 = b - a, np.sum((b - a) ** 2, axis=1)
    # an obtuse angle at x puts x in the disc on ab: near the chord's middle
    near = cKDTree(0.5 * (a + b)).query_ball_point(x, 0.5 * math.sqrt(ab2.max()))
    for k, (point, reach, chords) in enumerate(zip(x, limit, near)):
        chords = np.asarray(chords, np.int64)
        reach = np.minimum(reach, chord_limit[chords])
        ax, bx = point - a[chords], point - b[chords]
        cross = ab[chords, 0] * ax[:, 1] - ab[chords, 1] * ax[:, 0]
        found[k] = ((cross >= -1e-9 * ab2[chords]) & (np.sum(ax * bx, axis=1) < 0)
                    & (ab2[chords] * np.sum(ax * ax, axis=1) * np.sum(bx * bx, axis=1)
                       > 4 * reach ** 2 * cross ** 2)).any()
    return found
