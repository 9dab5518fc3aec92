"""Exceptions to Theorem 1 at the small features of a conforming mesh, located and bounded.

Every triangle of the constrained solid alpha-complex has circumradius R <= alpha, so by
the law of sines the angle opposite an edge of length l is at least arcsin(l / 2 alpha):
Theorem 1's 30° holds wherever the edges are at least alpha long. In a conforming
sampling every interior and guard sample is at least alpha from every sample it sees, so
two samples closer than alpha that see each other are two *boundary* samples, at a small
feature of the region that keeps them apart by a proven distance d (docs/conforming.md,
"Theorem 1 and its exceptions"):

- **short piece**: consecutive corners of a ring less than alpha apart along it; every
  corner is a sample and such a piece gets no other, so d is the corners' distance.
- **small ring**: consecutive samples of a ring less than alpha apart although the arc
  between them is at least alpha long or they are not both corners: a ring too small for
  parts of alpha (three samples a third of its perimeter apart) or a curve of radius
  about alpha. d is their chord; the proof bounds the angles by it, not the chord itself.
- **sharp corner** of angle θ: samples on the two straight sides at arc length at least
  f = ``corner_clearance(θ)`` from the corner are at least d = 2 f sin(θ/2) apart (the
  squared distance d1² + d2² − 2 d1 d2 cos θ is convex and increasing in d1 and d2 from
  (f, f) on when θ < 90°). A side shorter than f holds no sample but the vertex ending
  it, at its fixed distance: d is then the least distance with that one fixed; a side
  too short for the clearances at both its ends but with a chord of 2 alpha or more is
  halved, its middle alpha or more from the corner: f is alpha for that sample.
- **thin wall**: samples seeing each other across material narrower than alpha, on two
  boundary segments d > 0 apart.

A triangle whose edges are explained that way has every angle at least
arcsin(d_e / 2 alpha) opposite each edge e (d_e = alpha for edges at least alpha long),
so its smallest angle is at least θ_p = arcsin(min d_e / 2 alpha), its largest at most
180° − 2 θ_p and its aspect ratio at most 4 cot θ_p. The certificate lists every
triangle below Theorem 1 with its feature and these proven bounds, checked on the
triangle; a triangle below Theorem 1 whose short edge no feature explains, or a pair of
samples closer than alpha that see each other without one, is reported as unexplained.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from ..sampling import LADDER_ANGLE, corner_clearance
from ..sizing import angle_bound
from .conformity import SampledBoundary, edge_keys, point_text, say_located
from .quality import ASPECT_BOUND

__all__ = ["ExceptionalTriangle", "small_feature_exceptions", "CAUSES"]

CAUSES = ("short piece", "small ring", "sharp corner", "thin wall")
_SHORT_PIECE, _SMALL_RING, _SHARP_CORNER, _THIN_WALL = range(4)
_TOL = 1e-9             # relative rounding allowed on the measured angles, lengths, radii
_ANGLE_ROUNDING = 1e-6  # degrees: an angle near 0 measured by acos is this far off


@dataclass(frozen=True)
class ExceptionalTriangle:
    """A triangle below Theorem 1 at a small feature, with the bound proven for it.

    Attributes
    ----------
    triangle : int
        Index into the mesh's faces.
    vertices : tuple of (float, float)
        Its three corners, in region coordinates.
    cause : str
        One of :data:`CAUSES`: "short piece", "small ring", "sharp corner", "thin wall".
    feature : float
        The feature's size: the corner's angle in degrees (sharp corner), the piece's
        length, the ring's perimeter or the wall's width, / alpha.
    place : tuple of float
        Where the feature is: the corner, or the middle of the short edge.
    separation : float
        The proven lower bound on the triangle's shortest edge there, / alpha.
    min_angle, max_angle : float
        The triangle's extreme angles, in degrees.
    aspect_ratio : float
        Its L²/A.
    circumradius : float
        Its circumradius / alpha (at most 1: the premise of the bound).
    proven_angle : float
        θ_p = arcsin(separation / 2) in degrees: every angle is at least this.
    meets_bound : bool
        The triangle meets its proven bounds: circumradius <= alpha, each angle at least
        arcsin(d_e / 2 alpha) opposite each edge e, the aspect ratio at most 4 cot θ_p.
    unit : str
        What the lengths are ratios to: "alpha", or "r" for a graded mesh (feature and
        separation to the smaller r of the pair, circumradius to the complex's bound
        min_v r(v) / (1 - L), and d_e / 2 alpha above reads d_e / 2 that bound).

    Examples
    --------
    >>> t = ExceptionalTriangle(7, ((0, 0), (1, 0), (0, 0.3)), "short piece", 0.3, (0, 0.15),
    ...                         0.3, 16.7, 90.0, 3.33, 0.52, 8.63, True)
    >>> print(t)
    triangle 7 at (0, 0.15): short piece 0.3 alpha long; angles [16.7°, 90°] >= 8.63°, aspect ratio 3.33 <= 26.4 ok
    """

    triangle: int
    vertices: tuple
    cause: str
    feature: float
    place: tuple
    separation: float
    min_angle: float
    max_angle: float
    aspect_ratio: float
    circumradius: float
    proven_angle: float
    meets_bound: bool
    unit: str = "alpha"

    @property
    def proven_aspect_ratio(self) -> float:
        """4 cot θ_p: the largest L²/A of a triangle whose angles are all at least θ_p."""
        return 4 / math.tan(math.radians(self.proven_angle)) if self.proven_angle > 0 else math.inf

    def describe_feature(self) -> str:
        """The feature in words, e.g. 'sharp corner of 20°'."""
        unit = self.unit
        return {"short piece": f"short piece {self.feature:.3g} {unit} long",
                "small ring": f"small ring or tight curve ({self.feature:.3g} {unit} round), "
                              f"chord {self.separation:.3g} {unit}",
                "sharp corner": f"sharp corner of {self.feature:.3g}°",
                "thin wall": f"wall {self.feature:.3g} {unit} thin"}[self.cause]

    def as_dict(self) -> dict:
        """Plain JSON-ready values, ``proven_aspect_ratio`` included."""
        values = {name: getattr(self, name) for name in self.__dataclass_fields__}
        values["vertices"] = [list(v) for v in self.vertices]
        values["place"] = list(self.place)
        values["proven_aspect_ratio"] = self.proven_aspect_ratio
        return values

    def __str__(self) -> str:
        return (f"triangle {self.triangle} at {point_text(self.place)}: {self.describe_feature()}; "
                f"angles [{self.min_angle:.3g}°, {self.max_angle:.3g}°] >= "
                f"{self.proven_angle:.3g}°, aspect ratio {self.aspect_ratio:.3g} <= "
                f"{self.proven_aspect_ratio:.3g} {'ok' if self.meets_bound else 'FAILED'}")


def small_feature_exceptions(mesh, quality, sampled: SampledBoundary, close_pairs,
                             radius=None, grading=0.0):
    """The triangles of a conforming ``mesh`` below Theorem 1, each explained by a small
    feature with its proven bound (see the module documentation), and what is not.

    A graded mesh (``radius`` given) is measured the same way with r for alpha: a pair is
    close below the smaller r of its two samples, a sharp corner keeps the samples on its
    sides ``corner_clearance(θ, 1)`` times their own r from it (the graded sampler's
    clearance, ``graded_sampling._corner_clearance``), and a triangle is below the bound
    ``θ_L = arcsin((1 - L)/2)`` of its grading, its circumradius bounded by
    ``min_v r(v) / (1 - L)`` (the graded complex's rule, docs/graded.md) in place of
    alpha.

    Parameters
    ----------
    mesh : PlanarMesh
        A conforming mesh.
    quality : Quality
        ``mesh.quality()``.
    sampled : SampledBoundary
        The mesh's chords.
    close_pairs : (P, 2) int ndarray
        The pairs of samples closer than alpha that see each other (the mesh's shorter
        edges among them).
    radius : (N,) float ndarray, optional
        A graded mesh's radius field at its samples (alpha everywhere if not given).
    grading : float
        The graded field's Lipschitz constant L (0 for uniform meshes).

    Returns
    -------
    exceptions : tuple of ExceptionalTriangle
    excused_pairs : int
        How many of ``close_pairs`` a small feature explains, at least its proven
        distance apart.
    unexplained : tuple of str
        Located breaches of separation or Theorem 1 that no small feature explains.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import Polygon
    >>> step = Polygon([(0, 0), (1, 0), (1, 0.5), (0.6, 0.5), (0.6, 0.515), (0, 0.515)])
    >>> cert = pds.mesh_region(pds.Region.from_shapely(step), 0.05, seed=4).certificate()
    >>> [(e.cause, round(e.feature, 3)) for e in cert.exceptions], cert.unexplained
    ([('short piece', 0.3)], ())
    """
    points, alpha = mesh.vertices, mesh.alpha
    n = len(points)
    graded = radius is not None
    scale = np.asarray(radius, float) if graded else np.full(n, float(alpha))
    faces = np.asarray(mesh.faces, np.int64).reshape(-1, 3)
    pairs = np.asarray(close_pairs, np.int64).reshape(-1, 2)
    if len(pairs):                  # np.unique's rows (sorted), by keys p n + q (its axis=0
        keys = np.unique(np.sort(pairs, axis=1) @ np.array([n, 1]))    # costs 10 times more)
        pairs = np.column_stack([keys // n, keys % n])
    angles, edges = quality.angles, quality.edge_lengths          # edge k opposite corner k
    smallest = angle_bound(grading) if graded else 30.0
    # the corners' min and max as np.minimum of the columns: min(axis=1) costs 30 times more
    first, second, third = angles.T
    below = ((np.minimum(np.minimum(first, second), third) < smallest * (1 - _TOL))
             | (np.maximum(np.maximum(first, second), third) > (180 - 2 * smallest) * (1 + _TOL))
             | (quality.aspect_ratio > (4 / math.tan(math.radians(smallest)) if graded
                                        else ASPECT_BOUND) * (1 + _TOL)))
    if not len(pairs) and not below.any():
        return (), 0, ()                # nothing to explain (most patches)
    cause, feature, bound, place = _explain(pairs, points, mesh.on_boundary, sampled, alpha,
                                            scale if graded else None)
    unit = np.minimum(scale[pairs[:, 0]], scale[pairs[:, 1]])
    length = np.hypot(*(points[pairs[:, 1]] - points[pairs[:, 0]]).T)
    excused = (cause >= 0) & (length >= bound * (1 - _TOL))
    unexplained = []
    say_located(unexplained, int((~excused).sum()), "pairs of samples closer than alpha see each "
                "other with no small feature between them that keeps them that far apart",
                place[~excused])

    rows = np.flatnonzero(below)
    opposite = np.stack([faces[rows][:, [1, 2, 0]], faces[rows][:, [2, 0, 1]]], axis=2)  # (k, 3, 2)
    keys = edge_keys(opposite[..., 0], opposite[..., 1], n)
    pair_keys = edge_keys(pairs[:, 0], pairs[:, 1], n)
    at = np.minimum(np.searchsorted(pair_keys, keys), max(len(pairs) - 1, 0))
    found = (pair_keys[at] == keys) & excused[at] if len(pairs) else np.zeros(keys.shape, bool)
    short = edges[rows] < scale[opposite].min(axis=2) * (1 - _TOL)
    # below Theorem 1 with every edge at least alpha: only a circumradius above alpha does it
    explained = short.any(axis=1) & ~(short & ~found).any(axis=1)
    say_located(unexplained, int((~explained).sum()), "triangles below Theorem 1 that no small "
                "feature explains (an edge shorter than alpha between samples no feature keeps "
                "apart, or a circumradius above alpha)",
                points[faces[rows[~explained]]].mean(axis=1))
    low = scale[faces[rows]].min(axis=1, initial=np.inf)         # alpha, or min_v r(v)
    allowed = (low / (1 - grading))[:, None]                       # the circumradius's bound
    edge_bound = np.where(short & found, bound[at] if len(pairs) else 0.0, low[:, None])
    proven = np.degrees(np.arcsin(np.minimum(edge_bound / (2 * allowed), 1.0)))  # per corner
    area = quality.area[rows]
    circumradius = np.prod(edges[rows], axis=1) / np.maximum(4 * area, 1e-300)
    theta = proven.min(axis=1, initial=90)
    cot = 1 / np.tan(np.radians(np.maximum(theta, 1e-300)))
    meets = ((circumradius <= allowed[:, 0] * (1 + _TOL))
             & (angles[rows] >= proven * (1 - _TOL) - _ANGLE_ROUNDING).all(axis=1)
             & (quality.aspect_ratio[rows] <= 4 * cot * (1 + _TOL)))
    tightest = np.argmin(np.where(short & found, edge_bound, np.inf), axis=1)
    exceptions = []
    for i in np.flatnonzero(explained):
        k = at[i, tightest[i]]
        exceptions.append(ExceptionalTriangle(
            triangle=int(rows[i]), vertices=tuple(tuple(map(float, v)) for v in points[faces[rows[i]]]),
            cause=CAUSES[cause[k]], feature=float(feature[k]),
            place=tuple(map(float, place[k])), separation=float(bound[k] / unit[k]),
            min_angle=float(angles[rows[i]].min()), max_angle=float(angles[rows[i]].max()),
            aspect_ratio=float(quality.aspect_ratio[rows[i]]),
            circumradius=float(circumradius[i] / allowed[i, 0]), proven_angle=float(theta[i]),
            meets_bound=bool(meets[i]), unit="r" if graded else "alpha"))
    return tuple(exceptions), int(excused.sum()), tuple(unexplained)


def _explain(pairs, points, on_boundary, sampled, alpha, scale=None):
    """For each pair of samples: the small feature that keeps them apart (index into
    :data:`CAUSES`, -1 if none), its size (/ alpha, or / the pair's smaller r when
    ``scale``, a graded mesh's r at the samples, is given), the proven distance and its
    place."""
    region = sampled.region
    k = len(pairs)
    cause, feature, bound = np.full(k, -1), np.zeros(k), np.zeros(k)
    p, q = pairs.T
    unit = np.full(k, float(alpha)) if scale is None else np.minimum(scale[p], scale[q])
    place = (points[p] + points[q]) / 2
    distance = np.hypot(*(points[q] - points[p]).T)
    both = on_boundary[p] & on_boundary[q]
    # chords: consecutive samples of a ring
    keys = edge_keys(p, q, len(points))
    chord_keys = edge_keys(sampled.a, sampled.b, len(points))
    order = np.argsort(chord_keys)
    chord = order[np.minimum(np.searchsorted(chord_keys[order], keys), len(order) - 1)] \
        if len(order) else np.zeros(k, np.int64)
    is_chord = both & (chord_keys[chord] == keys) if len(order) else np.zeros(k, bool)
    segments = region.segments
    segment_p, segment_q = sampled.segment_of[p], sampled.segment_of[q]
    tol = sampled.tol

    def at_vertex(sample, segment):
        ends = segments[np.maximum(segment, 0)]
        return np.minimum(np.hypot(*(points[sample] - ends[:, 0]).T),
                          np.hypot(*(points[sample] - ends[:, 1]).T)) <= tol

    corners = at_vertex(p, segment_p) & at_vertex(q, segment_q)
    short = is_chord & corners & (sampled.arc_length[chord] < unit)
    cause[short], feature[short], bound[short] = (
        _SHORT_PIECE, sampled.arc_length[chord[short]] / unit[short], distance[short])
    ring = is_chord & ~short
    cause[ring], bound[ring] = _SMALL_RING, distance[ring]
    feature[ring] = sampled.perimeter[sampled.ring[chord[ring]]] / unit[ring]
    # corners: a sample on each of two segments that meet at a convex corner. A sample
    # at a vertex lies on the segment before it too
    other = both & ~is_chord
    following = _following_segment(region)
    previous = np.argsort(following)
    # the two ring neighbours of one sample (a corner's, when they are on its two sides)
    after_sample = np.full(len(points), -1)
    after_sample[sampled.a] = sampled.b
    before_sample = np.full(len(points), -2)
    before_sample[sampled.b] = sampled.a
    flanking = (after_sample[p] == before_sample[q]) | (after_sample[q] == before_sample[p])
    sides = []
    for sample, segment in ((p, segment_p), (q, segment_q)):
        segment = np.maximum(segment, 0)
        at_start = np.hypot(*(points[sample] - segments[segment, 0]).T) <= tol
        sides.append((sample, (segment, np.where(at_start, previous[segment], segment))))
    for (a, a_segments), (b, b_segments) in (sides, sides[::-1]):
        for first in a_segments:
            for second in b_segments:
                meet = other & (cause < 0) & (following[first] == second)
                if meet.any():
                    scales = None if scale is None else (scale[a[meet]], scale[b[meet]])
                    _explain_corner(meet, points[a[meet]], points[b[meet]], segments[first[meet]],
                                    segments[second[meet]], alpha, tol, cause, feature, bound,
                                    place, scales, points[on_boundary], flanking[meet])
    # thin walls: samples on two boundary segments apart from each other, or on the two
    # sides of a spike sharper than any clearance separates (LADDER_ANGLE), as thick as
    # the larger distance from either sample to the other's side
    wall = other & (cause < 0)
    if wall.any():
        lines = shapely.linestrings(segments)
        width = shapely.distance(lines[segment_p[wall]], lines[segment_q[wall]])
        rows = np.flatnonzero(wall)
        tip = (width == 0) & (_spike_angle(segments[segment_p[rows]], segments[segment_q[rows]])
                              < LADDER_ANGLE)
        if tip.any():
            rows = rows[tip]
            width[tip] = np.maximum(
                shapely.distance(shapely.points(points[p[rows]]), lines[segment_q[rows]]),
                shapely.distance(shapely.points(points[q[rows]]), lines[segment_p[rows]]))
        rows = np.flatnonzero(wall)[width > 0]
        cause[rows], bound[rows] = _THIN_WALL, width[width > 0]
        feature[rows] = width[width > 0] / unit[rows]
    _explain_by_between(pairs, points, distance, both, cause, feature, bound, place)
    return cause, feature, bound, place


def _explain_by_between(pairs, points, distance, both, cause, feature, bound, place):
    """Explain the boundary pairs pq left unexplained that have a third sample s in the
    disc on pq as diameter, with both pairs ps and sq explained: the angle at s is at
    least 90°, so |pq|² >= |ps|² + |sq|², and their proven distances bound pq's. Two
    rungs across walls on either side of one sample of a plate's edge are such a pair
    (a laser sheet at alpha = extent / 25: holes 0.2 alpha wide, 0.05 alpha from the
    edge). The pair takes the feature of the closer of ps and sq. Pairs are taken
    shortest first, so that a chain of samples between them explains them in turn."""
    left = np.flatnonzero(both & (cause < 0))
    if not len(left):
        return
    from scipy.spatial import cKDTree

    row_of = {(int(p), int(q)): row for row, (p, q) in enumerate(pairs)}   # p < q
    tree = cKDTree(points)
    for row in left[np.argsort(distance[left], kind="stable")]:
        p, q = map(int, pairs[row])
        best = None
        for s in tree.query_ball_point((points[p] + points[q]) / 2, distance[row] / 2):
            if s in (p, q):
                continue
            first, second = row_of.get((min(p, s), max(p, s))), row_of.get((min(s, q), max(s, q)))
            if first is None or second is None or cause[first] < 0 or cause[second] < 0:
                continue
            proven = math.hypot(bound[first], bound[second])
            if best is None or proven > best[0]:
                best = (proven, min((first, second), key=lambda k: bound[k]))
        if best is not None:
            closer = best[1]
            cause[row], feature[row], place[row] = cause[closer], feature[closer], place[closer]
            bound[row] = best[0]


def _spike_angle(first, second) -> np.ndarray:
    """The angle between two segments (k, 2, 2) that share an end, at that end (π where
    they share none)."""
    angle = np.full(len(first), np.pi)
    for i, j in ((0, 0), (0, 1), (1, 0), (1, 1)):
        shared = np.all(first[:, i] == second[:, j], axis=1)
        u, v = first[shared, 1 - i] - first[shared, i], second[shared, 1 - j] - second[shared, j]
        angle[shared] = np.abs(np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], (u * v).sum(axis=1)))
    return angle


def _explain_corner(meet, a, b, first, second, alpha, tol, cause, feature, bound, place,
                    scales=None, boundary=None, flanking=None):
    """Explain the pairs ``meet``: ``a`` on the segments ``first``, ``b`` on ``second``,
    which follows it at a corner. Each sample is at least the corner's clearance from
    it (the boundary sampling's first part), or it is the vertex at its segment's far
    end, a corner of the region, itself a sample (a side shorter than the clearance).
    On a graded mesh (``scales`` = r at ``a`` and at ``b``) each sample's clearance is
    ``corner_clearance(θ, 1)`` times its own r (``graded_sampling._corner_clearance``);
    a side from the corner to another corner (a sample among the ``boundary`` samples),
    too short for the clearances at both its ends (together at most the corner's
    clearance and √3 r), holds one sample where the sampler divides it in their ratio
    (``graded_sampling.cleared_piece``), short of the clearance: it counts as fixed
    there. So do the corner's own two neighbours (``flanking``) when short of their
    clearances: the sampler shortens their legs until the corner's triangle is one the
    complex keeps (``graded_sampling._tip_kept``)."""
    corner = second[:, 0]
    into, out = first[:, 1] - first[:, 0], second[:, 1] - corner
    angle = np.pi - np.arctan2(into[:, 0] * out[:, 1] - into[:, 1] * out[:, 0],
                               np.einsum("ij,ij->i", into, out))
    at_a, at_b = np.hypot(*(a - corner).T), np.hypot(*(b - corner).T)
    if scales is None:
        clear = corner_clearance(angle, alpha)
        # a side too short for the clearances at both its ends, with a chord of 2 alpha
        # or more, is halved (sampling._halved_long_chords): its middle is alpha away
        clear_a, clear_b = (np.where(at < clear * (1 - _TOL), alpha, clear) for at in (at_a, at_b))
    else:
        c = corner_clearance(angle, 1.0)
        clear_a, clear_b = c * scales[0], c * scales[1]
    fixed_a = np.hypot(*(a - first[:, 0]).T) <= tol
    fixed_b = np.hypot(*(b - second[:, 1]).T) <= tol
    if scales is not None:
        legs_shortened = flanking & ((at_a < clear_a * (1 - _TOL)) | (at_b < clear_b * (1 - _TOL)))
        fixed_a |= legs_shortened
        fixed_b |= legs_shortened
        for fixed, at, clear, far, r in ((fixed_a, at_a, clear_a, first[:, 0], scales[0]),
                                         (fixed_b, at_b, clear_b, second[:, 1], scales[1])):
            short = ~fixed & (at < clear * (1 - _TOL)) & (
                np.hypot(*(far - corner).T) < clear + math.sqrt(3) * r)
            if short.any():
                from scipy.spatial import cKDTree

                fixed[short] = cKDTree(boundary).query(far[short])[0] <= tol
    # two free samples are alpha apart beside a corner of 60° or more: only sharper
    # corners keep them closer, and the bound's minimum needs less than 90°
    held_a = fixed_a | (at_a >= clear_a * (1 - _TOL))
    held_b = fixed_b | (at_b >= clear_b * (1 - _TOL))
    apart = held_a & held_b & ((angle < np.pi / 2) | fixed_a | fixed_b)
    # one sample inside its clearance, the other held by its own (or fixed), below 90°: a
    # rung across the corner's wedge (boundary_rules._rungs_across_walls: the point of the
    # side across from the held sample, which lies in the lens of the chord ending at the
    # corner) or the middle of a side halved by _guards_halved. That sample may be
    # anywhere on its side: the held one keeps it at least its own distance to that side,
    # clear sin θ (alpha cos(θ/2) below 60°), the least distance with a clearance of 0
    across = ~apart & (held_a != held_b) & (angle < np.pi / 2)
    clear_a = np.where(across & ~held_a, 0.0, clear_a)
    clear_b = np.where(across & ~held_b, 0.0, clear_b)
    apart |= across
    rows = np.flatnonzero(meet)[apart]
    cause[rows], feature[rows], place[rows] = _SHARP_CORNER, np.degrees(angle[apart]), corner[apart]
    bound[rows] = _nearest_on_sides(at_a[apart], fixed_a[apart], clear_a[apart], at_b[apart],
                                    fixed_b[apart], clear_b[apart], angle[apart])


def _nearest_on_sides(a, a_fixed, clear_a, b, b_fixed, clear_b, angle) -> np.ndarray:
    """The least distance between two points on the two sides of a corner of ``angle``
    (< 90° where both are free), each at distance ``a`` (``b``) from the corner if fixed,
    else at least ``clear_a`` (``clear_b``): the law of cosines, minimised where a point
    is free (its squared distance is convex in that point's distance, least at the
    other's times cos θ)."""
    cos = np.cos(angle)
    a = np.where(a_fixed, a, np.maximum(clear_a, np.where(b_fixed, b, clear_b) * cos))
    b = np.where(b_fixed, b, np.maximum(clear_b, a * cos))
    return np.sqrt(np.maximum(a * a + b * b - 2 * a * b * cos, 0.0))


def _following_segment(region) -> np.ndarray:
    """The index of the segment after each one along its ring."""
    sizes = np.array([len(r) for r in region.rings])
    first = np.repeat(np.cumsum(sizes) - sizes, sizes)
    index = np.arange(len(first)) + 1
    return np.where(index == first + np.repeat(sizes, sizes), first, index)

