"""Variable-radius maximal Poisson disc sampling for graded meshes (docs/graded.md, §4).

The radius r(x) comes from a :class:`pds_plugin.sizing.RadiusField`. Two samples that
see each other are at least ``min(r(p), r(q))`` apart, and every point x of the region
is within ``r(x)`` of a sample that sees it. The stages follow the uniform conforming
sampler (sampling.py):

1. **Boundary.** Sharp corners, then each piece between them split at *normalized* arc
   length ``τ = ∫ dt / r`` into parts with ``τ`` in ``[a, 2 a)``, ``a = 1.02/(1 - L/2)``
   (so consecutive samples are at least ``min(r)`` apart), joined by chords; a guard
   sample inside each chord longer than ``√3 r``.
2. **Interior.** A quadtree whose leaves have side at most ``r_low`` (``r_low`` the
   Lipschitz lower bound of r on the leaf); a few passes of one dart per open leaf, then
   the refinement of Ebeida et al.: boxes that no single visible disc covers (farthest
   corner within ``min(r(q), r_low)``) are split in four and get a dart each, until none
   is left. After the first pass a box's dart goes into one of its 4 x 4 sub-boxes that
   no single visible disc covers (two tries against the samples near the box), and a
   box whose sub-boxes are all covered is closed (``_graded_kernels.throw``); a box smaller than ``1e-10 r_low`` is dropped (the coverage gap is then
   within that of r), so no box is split more than about 35 times. Boxes left open are
   counted: more than ``_MAX_BOXES_PER_SAMPLE`` per allowed sample is a BudgetError.
   With ``tile=True`` (remeshed faces) the points of a periodic maximal disc tile
   (:mod:`.disc_tile`) are inserted first, and the leaves they provably cover get no dart.

Random numbers come from ``numpy.random.default_rng(seed)`` in a fixed order: the same
region, field and seed give the same samples bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from . import _graded_kernels as kern
from . import _visibility_kernels as vis_kern
from . import disc_tile
from ._checks import check_positive_int, check_seed
from .errors import BudgetError, RegionError
from .region import ALPHA_RESOLUTION, Region
from .boundary_sampling import (RESOLUTION, along, chord_ends, chord_reach, given_boundary,
                                graded_chords, graded_domain, guard_candidates,
                                hidden_bends, joined, onto_curves)
from .boundary_rules import LONGEST_CHORD
from .sampling import DEFAULT_MAX_SAMPLES, Samples, check_rings_apart, corner_clearance
from .sizing import RadiusField

__all__ = ["graded_poisson_disc"]

_PASSES = 3
TAU_MARGIN = 1.02    # the trapezoid rule's error on τ, over parts of at most 0.3 r
_MAX_BINS = 4_000_000
                             # (a grid of half the smallest radius listed small sections' chords
                             # in a million cells: 17 ms of binning per section, issue 21)
_MIN_BINS = 65_536
_BINS_PER_SAMPLE = 64        # level-0 bins per boundary sample (a section has 2-4 samples
                             # inside per boundary sample)
_TILE_CELLS = 65_536          # the most cells of the grid that finds the boxes a tile covers
_MAX_BOXES_PER_SAMPLE = 4     # open refinement boxes (or quadtree leaves) per allowed sample


def graded_poisson_disc(region: Region, field: RadiusField, seed: int = 0, *,
                        max_samples: int = DEFAULT_MAX_SAMPLES,
                        feature_angle: float = 30.0, boundary_samples=None,
                        tile: bool = False) -> Samples:
    """Maximal Poisson disc sampling of ``region`` with the radius field ``field``,
    conforming and constrained (see the module docstring).

    Parameters
    ----------
    region : Region
    field : RadiusField
        The radius field r (L-Lipschitz, :func:`pds_plugin.sizing.radius_field`).
    seed : int
        The same region, field and seed give the same samples bit for bit.
    max_samples : int
        Refuse (with a :class:`~pds_plugin.errors.BudgetError`) a sampling that would make
        more samples, or need more refinement boxes than a few per sample.
    feature_angle : float
        Vertices turning by at least this many degrees are sharp corners (samples).
    boundary_samples : sequence of (k, 2) array_like, optional
        The boundary samples of each ring of ``region.rings``, in order along it, given
        instead of drawn (guards and interior as usual), as for
        :func:`pds_plugin.poisson_disc`: :mod:`pds_plugin.partition` gives them so that a
        boundary chain shared by two regions gets the same samples on both sides. They
        should be at least ``min(r(p), r(q))`` apart where consecutive (the certificate
        checks it).
    tile : bool
        Seed the interior with the periodic maximal disc tile of :mod:`.disc_tile`
        scaled by the cap, at an offset drawn from ``seed``, before the darts: its
        points that pass the insertion test are samples, and the leaves they provably
        cover get no dart (:meth:`_GradedSampler._tile_covered`). Fewer darts where r
        is the cap over large areas (remeshed planar faces: 3.5 to 7 times fewer);
        separation and maximality are the sampler's as without it, and the
        interior repeats the tile's pattern every ``side x cap``.

    Returns
    -------
    Samples
        Its ``radius`` holds r at each sample, its ``alpha`` the field's cap, its
        ``rings`` the boundary samples in order along each ring.

    Raises
    ------
    BudgetError
        As said under ``max_samples``.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> from pds_plugin.sizing import radius_field
    >>> region = Region.from_shapely(box(0, 0, 10, 1))
    >>> samples = graded_poisson_disc(region, radius_field(region, 0.2), seed=1)
    >>> bool(samples.radius.max() <= 0.5 + 1e-9), len(samples.rings)
    (True, 1)
    """
    max_samples = check_positive_int(max_samples, "max_samples")
    seed = check_seed(seed)
    check_rings_apart(region)
    _check_resolved(region, field)
    if boundary_samples is not None:
        boundary_samples = given_boundary(region, boundary_samples, True)
    rng = np.random.default_rng(seed)
    sampler = _GradedSampler(region, field, max_samples)
    n_boundary = sampler.add_boundary(feature_angle, rng, boundary_samples)
    sampler.add_interior(rng, tile)
    points = sampler.points[:sampler.count].copy()
    on_boundary = np.zeros(len(points), bool)
    on_boundary[:n_boundary] = True
    chords = sampler.vis._replace(out=sampler.vis.out[:sampler.count].copy())
    return Samples(points, on_boundary, field.cap, sampler.rings,
                   sampler.radius[:sampler.count].copy(), sampler.sampled_region, chords)


def _check_resolved(region: Region, field: RadiusField):
    """Refuse a field whose radius falls below what the region's coordinates resolve
    (``ALPHA_RESOLUTION``): where the boundary comes within rounding of itself."""
    if not len(field.sizes):
        return
    k = int(np.argmin(field.sizes))
    if field.sizes[k] < ALPHA_RESOLUTION * region.resolution:
        x, y = field.features[k]
        raise RegionError(
            f"the radius field falls to {field.sizes[k]:.3g} at ({x:.9g}, {y:.9g}), below "
            f"{ALPHA_RESOLUTION:g} float64 spacings ({region.resolution:.3g}) of the "
            "region's coordinates: the boundary comes within rounding of itself there; "
            "separate or merge those parts in the geometry, or move the region towards "
            "the origin (a spike of zero width, where the boundary runs out and back along "
            "itself: Region.from_shapely(..., repair=True) drops it)")


def _tau_rings(rings, field, grading, limit=None):
    """Each ring densified by bisection until every part is at most 0.3 of the lowest r
    the field can have on it (None if that takes more than ``limit`` points: a user's
    sizing far below the budget's radii), with r at its points, the flags of its own
    vertices among the points, and the normalized arc length τ = ∫ dt / r at its points
    and closing point (trapezoid rule). The number of points grows with ∫ dt / r, not with
    length / min r. All rings are densified together (one field evaluation per round for
    all of them); each round places the old points and the new midpoints by one index
    map instead of an ``np.insert`` per array, and a ring's next point comes from the
    flags of the rings' first points (a small section takes about ten rounds, and these
    calls were most of their cost)."""
    points = np.concatenate(rings)
    counts = np.array([len(r) for r in rings])
    done = kern.densified_rings(field._kernel, points, counts, grading)
    if done is not None:                        # the same, in one kernel call
        points, radius, first, counts, tau_of = done
        ends = np.cumsum(counts)
        return [(points[hi - c:hi], radius[hi - c:hi], first[hi - c:hi],
                 tau_of[hi - c + k:hi + k + 1]) for k, (c, hi) in enumerate(zip(counts, ends))]
    head = np.zeros(len(points), bool)          # each ring's first point
    head[np.cumsum(counts) - counts] = True
    radius = field(points)
    first = np.ones(len(points), bool)
    for round_ in range(61):          # at most 60 rounds of splits
        n = len(points)
        heads = np.flatnonzero(head)
        after = np.arange(1, n + 1)
        after[np.append(heads[1:], n) - 1] = heads
        following = _rows(points, after)
        step = np.hypot(*(following - points).T)
        if round_ == 60:
            break
        low = np.minimum(radius, radius[after]) - 0.5 * grading * step
        split = step > 0.3 * low
        if not split.any():
            break
        if limit is not None and n + np.count_nonzero(split) > limit:
            return None
        middle = 0.5 * (points[split] + following[split])
        # point i moves past the midpoints inserted before it; a midpoint follows its point
        old = np.arange(n) + np.cumsum(split) - split
        new = old[split] + 1
        points, radius, first, head = _spread(old, new, points, middle, radius, field(middle),
                                              first, head)
    inv = 1.0 / radius
    part = 0.5 * step * (inv + inv[after])      # τ of each part to the ring's next point
    tau_of = np.empty(len(points) + len(rings))
    out, lo = [], 0
    for k, count in enumerate(np.bincount(np.cumsum(head) - 1, minlength=len(rings))):
        hi = lo + count
        tau = tau_of[lo + k:hi + k + 1]
        tau[0] = 0.0
        np.cumsum(part[lo:hi], out=tau[1:])
        out.append((points[lo:hi], radius[lo:hi], first[lo:hi], tau))
        lo = hi
    return out


def _rows(points, index):
    """``points[index]`` for an (n, 2) float array, through a complex view (numpy takes
    single items much faster than rows)."""
    rows = np.ascontiguousarray(points).view(np.complex128)[index, 0]
    return rows.view(np.float64).reshape(-1, 2)


def _spread(old, new, points, middle, radius, middle_radius, first, head):
    """The arrays of :func:`_tau_rings` with the midpoints (``middle``, r there) at the
    indices ``new`` and the old entries at ``old``; new points are no ring's vertex and
    no ring's first point."""
    m = len(old) + len(new)
    grown_points, grown_radius = np.empty((m, 2)), np.empty(m)
    grown_first, grown_head = np.zeros(m, bool), np.zeros(m, bool)
    grown = grown_points.view(np.complex128)[:, 0]
    grown[old] = points.view(np.complex128)[:, 0]
    grown[new] = np.ascontiguousarray(middle).view(np.complex128)[:, 0]
    grown_radius[old], grown_radius[new] = radius, middle_radius
    grown_first[old], grown_head[old] = first, head
    return grown_points, grown_radius, grown_first, grown_head


def _turning_angles(rings):
    """:func:`pds_plugin.region.turning_angles` of every ring, computed for all rings at
    once (the same arithmetic, so the same angles bit for bit)."""
    points = np.concatenate(rings)
    counts = np.array([len(ring) for ring in rings])
    begin = np.cumsum(counts) - counts
    following = np.arange(1, len(points) + 1)
    following[begin + counts - 1] = begin
    previous = np.arange(-1, len(points) - 1)
    previous[begin] = begin + counts - 1
    out = _rows(points, following) - points
    into = points - _rows(points, previous)
    cross = into[:, 0] * out[:, 1] - into[:, 1] * out[:, 0]
    dot = (into * out).sum(axis=1)
    return np.split(np.arctan2(cross, dot), np.cumsum(counts)[:-1])


def _plain_positions(taus, starts, unit):
    """:func:`tau_positions` of rings without sharp corners (``taus`` their τ at their
    dense points and closing point, ``starts`` the random fraction of τ where each
    begins), all rings at once; a ring of fewer than three parts goes through
    :func:`tau_positions` itself. The same positions bit for bit: a drawing's 373 round
    holes took a dozen numpy calls each."""
    if not taus:
        return []
    length = np.array([tau[-1] for tau in taus])
    lo = starts * length
    span = (lo + length) - lo
    parts = np.maximum(np.floor(span / unit), 1).astype(np.int64)
    ring = np.repeat(np.arange(len(taus)), parts - 1)
    k = np.arange(len(ring)) - np.repeat(np.cumsum(parts - 1) - (parts - 1), parts - 1) + 1
    inner = lo[ring] + span[ring] * k / parts[ring]
    owner = np.concatenate([np.arange(len(taus)), ring])
    at = np.concatenate([lo, inner]) % length[owner]
    at = at[np.lexsort((at, owner))]
    ends = np.cumsum(parts)
    return [tau_positions(tau, lo[j:j + 1], [unit], [unit], unit, None) if parts[j] < 3
            else at[ends[j] - parts[j]:ends[j]] for j, tau in enumerate(taus)]


def tau_positions(tau, corners, after, before, unit, rng):
    """Positions (in τ) of a ring's boundary samples, increasing: its sharp corners (or
    one random point if it has none) and each piece between them split into the most
    equal parts of τ-length at least ``unit``, so in [unit, 2 unit) when the piece is at
    least 2 unit long, which the field makes every piece (sizing.piece_factor: a single
    part longer than √3 r needs a guard, which a neighbouring sample can refuse); at
    least three in all. A piece whose first part must be longer than ``unit`` (``after``
    its corner) or whose last part must (``before`` the next: :func:`_corner_clearance`)
    is split by :func:`cleared_piece` instead."""
    length = tau[-1]
    if not len(corners):
        corners, after, before = np.array([rng.random() * length]), [unit], [unit]
    lo = corners
    span = np.append(corners[1:], corners[0] + length) - lo
    parts = np.maximum(np.floor(span / unit), 1).astype(np.int64)
    first, last = np.asarray(after), np.roll(before, -1)
    cleared = (first > unit) | (last > unit)
    parts[cleared] = 1
    piece = np.repeat(np.arange(len(lo)), parts - 1)
    k = np.arange(len(piece)) - np.repeat(np.cumsum(parts - 1) - (parts - 1), parts - 1) + 1
    inner = [lo[piece] + span[piece] * k / parts[piece]]
    inner += [cleared_piece(lo[i], span[i], first[i], last[i], unit)
              for i in np.flatnonzero(cleared)]
    at = np.sort(np.concatenate([corners, *inner]) % length)
    while len(at) < 3:                       # a ring smaller than r: keep it a ring
        gaps = np.diff(np.append(at, at[0] + length))
        g = int(np.argmax(gaps))
        at = np.sort(np.append(at, (at[g] + 0.5 * gaps[g]) % length))
    return at


def cleared_piece(lo, span, first, last, unit):
    """The inner positions of a piece [lo, lo + span] whose first part must be at least
    ``first`` and last part at least ``last`` long (τ): as many parts as fit with the
    others at least ``unit``, split as equally as those two bounds allow (the inner
    parts equal, each end part equal to them unless its bound needs more), as pieces
    without a clearance are. A long part beside a short one makes a long chord, and
    across a narrow spike the triangles of such chords had circumradii above r at their
    centres or were dropped (53 of 494 random stars failed their certificate, 2 now, for
    another reason: docs/graded.md §9). A piece too short for both
    clearances gets one point dividing it in their ratio (its parts then fall short of
    them by the same factor: the corner's neighbours may be closer than r).

    Examples
    --------
    >>> cleared_piece(0.0, 10.0, 3.0, 1.0, 1.0).tolist()     # 3, then parts of 1
    [3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    >>> cleared_piece(0.0, 7.5, 2.0, 1.0, 1.0).round(6).tolist()   # 2, then 5 parts of 1.1
    [2.0, 3.1, 4.2, 5.3, 6.4]
    """
    rest = span - first - last
    if rest < 0:
        return np.array([lo + span * first / (first + last)])
    parts = 2 + int(rest // unit)
    high, low = max(first, last), min(first, last)
    size = span / parts                     # equal parts, unless an end needs more
    if size < high:
        size = (span - high) / (parts - 1)
        if size < low and parts > 2:
            size = (span - first - last) / (parts - 2)
    return lo + max(first, size) + size * np.arange(parts - 1)


def _corner_clearance(dense, radius, tau, corner, turn, unit, vertex, grading):
    """The τ-lengths kept free of samples after and before each sharp corner of a ring
    (``dense`` its densified points with r at them and τ along them, ``vertex`` flags the
    ring's own vertices among them, ``corner`` the corners' indices, ``turn`` their
    turning angles, positive left: convex with the region on the left), so that a
    corner's two neighbours p, q are separated.

    ``unit`` where the region's angle θ = π - turn is at least 60°. Below, the part from
    the corner c to p ends where |p - c| first reaches 1.02 k r(p), k = 1 / (2 sin(θ/2))
    (capped just below √3, :func:`pds_plugin.sampling.corner_clearance`; 1.02 covers the
    linear interpolation between the dense points): on straight sides
    |pq| >= 2 sin(θ/2) min(|p - c|, |q - c|) >= min(r(p), r(q)) (docs/conforming.md,
    "Sharp corner"; below 33.56° the cap leaves them closer, as for uniform meshes). The
    first such point, not a later one: |p - c| - k r(p) grows along a straight side (r is
    L-Lipschitz, k L < 1), and a longer part would make the corner's triangle (of
    circumradius |p - c| / (2 cos(θ/2)) when |p - c| = |q - c|) larger than separation
    needs, and too large for the complex where r(c) is small. Where a side bends away
    before its neighbour (a drilled hole's arc running into a spike), the chords cp and
    cq make a wider angle than the tangents, and k is taken from it
    (:func:`_chord_angle_clearance`); the legs are then shortened if the corner's
    triangle is still too large for the complex (:func:`_tip_kept`)."""
    length = tau[-1]
    k = corner_clearance(np.pi - np.asarray(turn, float), 1.0)
    after, before = np.full(len(corner), unit), np.full(len(corner), unit)
    for c in np.flatnonzero(k > 1.0):
        sides = [corner_side(dense, tau, corner[c], corner[(c + 1) % len(corner)], 1, length),
                 corner_side(dense, tau, corner[c], corner[c - 1], -1, length)]
        legs = [corner_leg(dense, radius, side, k[c]) for side in sides]
        if all(leg is not None for leg in legs) and any(
                vertex[side[0][1:leg[2] + 1]].any() for side, leg in zip(sides, legs)):
            legs = _chord_angle_clearance(dense, radius, sides, legs, k[c])
        legs = _tip_kept(dense, radius, sides, legs, k[c], grading)
        for out, side, leg in zip((after, before), sides, legs):
            out[c] = side[1][-1] if leg is None else max(unit, leg[0])     # None: too short
    return after, before


def corner_side(dense, tau, start, stop, step, length):
    """The dense points from a corner to the next (``step`` 1) or previous (-1) corner:
    their indices and τ from the corner."""
    n = len(dense)
    steps = (step * (stop - start)) % n or n
    walk = (start + step * np.arange(steps + 1)) % n
    position = (step * (tau[walk] - tau[start])) % length
    position[-1] = position[-1] or length
    return walk, position


def corner_leg(dense, radius, side, k):
    """Where along ``side`` |p - c| first reaches 1.02 k r(p): (τ, point, the index of
    the dense point before it within the side), or None if it never does."""
    walk, position = side
    apart = np.hypot(*(dense[walk] - dense[walk[0]]).T)
    g = apart - TAU_MARGIN * k * radius[walk]
    j = int(np.argmax(g >= 0))          # g[0] = -k r(c) < 0
    if not j:
        return None
    t = g[j - 1] / (g[j - 1] - g[j])
    point = dense[walk[j - 1]] + t * (dense[walk[j]] - dense[walk[j - 1]])
    return position[j - 1] + t * (position[j] - position[j - 1]), point, j - 1


def _tip_kept(dense, radius, sides, legs, k, grading):
    """The legs of a corner shortened, if need be, until the corner's triangle c p q has
    a circumradius the complex keeps (at most min r / (1 - L) over c, p, q, with 2 %
    to spare): below 33.56° (where the clearance is capped and cannot separate p and q
    anyway) or where r grew from a small r(c), the clearance's legs made a triangle the
    complex dropped, leaving the corner's sample isolated. The legs are those of a
    smaller k, found by bisection; p and q may then be closer than r (an exception the
    certificate itemises, as for every corner sharper than 33.56°)."""
    if any(leg is None for leg in legs):
        return legs
    c = dense[sides[0][0][0]]
    rc = radius[sides[0][0][0]]

    def too_big(legs):
        p, q = legs[0][1], legs[1][1]
        edges = math.hypot(*(p - q)) * math.hypot(*(p - c)) * math.hypot(*(q - c))
        area = abs((p[0] - c[0]) * (q[1] - c[1]) - (p[1] - c[1]) * (q[0] - c[0])) / 2
        r = [np.interp(leg[0], side[1], radius[side[0]]) for side, leg in zip(sides, legs)]
        return edges > 4 * area * min(rc, *r) / (1 - grading) / TAU_MARGIN

    if not too_big(legs):
        return legs
    low, high, kept = 0.0, 1.0, None
    for _ in range(30):
        middle = 0.5 * (low + high)
        trial = [corner_leg(dense, radius, side, middle * k) for side in sides]
        if any(leg is None for leg in trial) or too_big(trial):
            high = middle
        else:
            low, kept = middle, trial
    return kept or legs


def _chord_angle_clearance(dense, radius, sides, legs, k):
    """The legs of a corner whose side bends away before them, from the angle between
    the chords to the legs rather than between the sides' tangents: the bend opens that
    angle, and the tangents' k made the corner's triangle larger than the complex keeps
    at a small r(c) (a tip sample left isolated). k is set from the chords' angle and the
    legs found again, a few times; kept only if the neighbours it gives are separated.
    A side bending in (closing the angle) keeps the tangents' k: longer legs would
    separate the neighbours but leave the corner's triangle's circumcentre uncovered."""
    c = dense[sides[0][0][0]]
    best, tangents_k = legs, k
    for _ in range(4):
        u, v = legs[0][1] - c, legs[1][1] - c
        k = min(tangents_k, float(corner_clearance(
            abs(math.atan2(u[0] * v[1] - u[1] * v[0], u @ v)), 1.0)))
        if k == tangents_k:
            break
        legs = [corner_leg(dense, radius, side, k) for side in sides]
        if any(leg is None for leg in legs):
            break
        r = [np.interp(leg[0], side[1], radius[side[0]]) for side, leg in zip(sides, legs)]
        if math.hypot(*(legs[0][1] - legs[1][1])) >= TAU_MARGIN * min(r):
            best = legs
    return best


def _fixed(at, corners, cleared_after, cleared_before):
    """Which of a ring's boundary samples (at positions ``at``) must not move: its sharp
    corners (at positions ``corners``), and the neighbour after (before) each corner
    whose first part was chosen by its clearance: that part is the shortest that
    separates the corner's two neighbours, and a longer one would grow the corner's
    triangle beyond what the complex keeps at a small r(c) (:func:`_corner_clearance`)."""
    fixed = np.isin(at, corners)
    where = np.searchsorted(at, corners)
    fixed[(where[cleared_after] + 1) % len(at)] = True
    fixed[where[cleared_before] - 1] = True
    return fixed


def _uncrossed(samples, at, fixed, vertices, vertex_at, length, field):
    """A ring's boundary samples (at positions ``at`` along it, ``fixed`` the ones that
    must not move, :func:`_fixed`; ``vertices`` its own vertices at positions
    ``vertex_at``, of ``length`` in all) with a chord end moved onto the point where the
    ring crosses the chord, wherever the ring's piece beyond the chord would otherwise
    reach farther than r from the only chord end that sees it.

    A ring that crosses its chord leaves a piece of region beyond the chord that only the
    chord end it touches sees (the segment to the other end leaves the region, if only by
    rounding: an STL section's straight edges are chains of vertices 1e-8 off a line).
    When the crossing c, the piece's far point, is more than r(c) from that end, the
    other end (unless fixed) moves onto c: a point of the ring between the two
    ends, so the order of the samples stays, and the piece then lies between the chord
    and its arc, seen from both ends. The move is made only when the moved sample stays
    at least ``min(r(p), r(q))`` from both its neighbours q along the ring (the
    separation of consecutive boundary samples, checked exactly rather than by τ).
    Heights within 1e-9 cap of a chord count as on it, and ring vertices that close to a
    chord end are not on its arc, as for the certificate (analysis/conformity.py).
    """
    n, tol = len(samples), 1e-9 * field.cap
    chord = (np.searchsorted(at, vertex_at, side="right") - 1) % n
    a, b = samples[chord], samples[(chord + 1) % n]
    apart = (np.hypot(*(vertices - a).T) > tol) & (np.hypot(*(vertices - b).T) > tol)
    chord, vertices, vertex_at, a, b = (v[apart] for v in (chord, vertices, vertex_at, a, b))
    ab = b - a
    height = (ab[:, 0] * (vertices[:, 1] - a[:, 1]) - ab[:, 1] * (vertices[:, 0] - a[:, 0])) \
        / np.hypot(ab[:, 0], ab[:, 1])
    height[np.abs(height) <= tol] = 0.0
    beyond = np.bincount(chord, height < 0, minlength=n) > 0
    back = np.bincount(chord, height >= 0, minlength=n) > 0     # the arc crosses back
    samples = samples.copy()
    for k in np.flatnonzero(beyond & back):
        on = chord == k
        order = np.argsort((vertex_at[on] - at[k]) % length, kind="stable")
        arc = np.vstack([samples[k], vertices[on][order], samples[(k + 1) % n]])
        h = np.concatenate([[0.0], height[on][order], [0.0]])
        for end, step in ((k + 1, 1), (k, -1)):         # the piece at b, then at a
            j = len(h) - 2 if step == 1 else 1          # the arc vertex next to that end
            if h[j] >= 0:
                continue
            while h[j] < 0:                             # back along the piece to where
                j -= step                               # the arc is on Q's side again
            t = h[j] / (h[j] - h[j + step])
            crossing = arc[j] + t * (arc[j + step] - arc[j])
            holder = samples[end % n]
            if np.hypot(*(crossing - holder)) > field(crossing[None])[0]:
                _move_onto(samples, (k if step == 1 else k + 1) % n, crossing, fixed, field)
    return samples


def _crossed_rings(ring_samples, ring_at, rings, ring_vertex_at, ring_turns, tol):
    """For each ring (its boundary samples at positions ``ring_at``, its vertices at
    ``ring_vertex_at``, turning by ``ring_turns``): whether some chord has ring vertices
    both beyond it and on or inside it (off its ends), the only chords
    :func:`_uncrossed` may move an end of; and whether a reflex vertex off its chord's
    ends may be on a chord whose arc reaches beyond it, the only case where
    :func:`_unhidden` moves anything (``boundary_sampling.hidden_bends``). The same tests
    as there, all rings at once (the second with half their tolerances, so that it never
    misses what they find: hidden_bends measures along the ring from the samples'
    projections, here their τ), where the ring by ring calls took a dozen numpy calls
    each on the drawing's 383 rings and a shapely projection each on a section's."""
    counts = np.array([len(at) for at in ring_at])
    sizes = np.array([len(ring) for ring in rings])
    ring_of_sample = np.repeat(np.arange(len(rings)), counts)
    ring_of_vertex = np.repeat(np.arange(len(rings)), sizes)
    # the chord of each vertex: the last sample at or before it along its ring (as
    # searchsorted(at, vertex_at, "right") - 1 ring by ring; -1 is the ring's last chord)
    value = np.concatenate([*ring_at, *ring_vertex_at])
    is_vertex = np.repeat([False, True], [len(ring_of_sample), len(ring_of_vertex)])
    owner = np.concatenate([ring_of_sample, ring_of_vertex])
    order = np.lexsort((is_vertex, value, owner))
    before = np.cumsum(~is_vertex[order])[is_vertex[order]]
    begin = np.cumsum(counts) - counts
    local = (before - begin[ring_of_vertex] - 1) % counts[ring_of_vertex]
    chord = begin[ring_of_vertex] + local
    samples = np.concatenate(ring_samples)
    a = samples[chord]
    b = samples[begin[ring_of_vertex] + (local + 1) % counts[ring_of_vertex]]
    vertices = np.concatenate(rings)
    end = np.minimum(np.hypot(*(vertices - a).T), np.hypot(*(vertices - b).T))
    ab = b - a
    height = (ab[:, 0] * (vertices[:, 1] - a[:, 1]) - ab[:, 1] * (vertices[:, 0] - a[:, 0])) \
        / np.hypot(ab[:, 0], ab[:, 1])
    loose = end > 0.5 * tol
    reaches = np.bincount(chord, loose & (height < -0.5 * tol), minlength=len(samples)) > 0
    reflex = loose & (np.concatenate(ring_turns) < 0)
    hides = np.bincount(ring_of_vertex, reflex & reaches[chord], minlength=len(rings)) > 0
    apart = end > tol
    chord, height = chord[apart], height[apart]
    height[np.abs(height) <= tol] = 0.0
    beyond = np.bincount(chord, height < 0, minlength=len(samples)) > 0
    back = np.bincount(chord, height >= 0, minlength=len(samples)) > 0
    return np.bincount(ring_of_sample, beyond & back, minlength=len(rings)) > 0, hides


def _unhidden(samples, fixed, ring, turns, radius, tol):
    """A ring's boundary samples (in order along ``ring``; ``fixed`` flags the ones that
    must not move, :func:`_fixed`; ``turns`` are the turning angles at the ring's
    vertices, ``radius`` gives r at points) with chord ends moved onto reflex vertices of
    their chords' arcs, where the arc reaches beyond its chord.

    The ring turns back into the region at a reflex vertex w, so a chord end e on the
    ring before w does not see the ring just past w: the segment from e leaves the
    region through the wedge outside w, and leaves Q too where it runs beyond the chord.
    That piece of region is then covered only by the chord's far end f: on tessellated
    tori, bosses and flanges 1.05–1.5 r from it (held-out corpus sections), with e
    0.002–0.2 r from w, sometimes after :func:`_uncrossed` had moved e just past w. On w,
    e sees both of w's edges. So where f is farther than r(w) from w, the end e nearer
    to w along the arc moves onto it (the first and the last reflex vertex of each arc,
    the shortest moves first), unless that takes e farther than r from a reflex vertex
    of its other chord that it was the far end within r of (where that chord's arc
    reaches beyond it). The samples keep their
    order (w is between the chord's ends); a sample moves only if it is not ``fixed``
    and stays at least ``min(r(p), r(q))`` from both its neighbours q along the ring.
    Vertices within ``tol`` of a chord (or of its ends) count as on it.

    Examples
    --------
    >>> from pds_plugin.region import turning_angles
    >>> ring = np.array([[0, 0], [4, 0], [4, 1], [2, 1], [1.5, 1.1], [1, 1.15], [0, 1]])
    >>> samples = np.array([[0, 0], [4, 0], [4, 1], [2.05, 1], [0, 1]])
    >>> moved = _unhidden(samples, np.zeros(5, bool), ring, turning_angles(ring),
    ...                  lambda x: np.full(len(x), 1.2), 1e-9)
    >>> moved[3].tolist()     # the bump beyond the chord is seen from (2, 1), reflex
    [2.0, 1.0]
    """
    found = hidden_bends(samples, ring, turns, tol)
    if found is None:
        return samples
    bends, chord, reflex, beyond = found
    n = len(samples)
    samples = samples.copy()
    for _, end, other, w, _ in bends:           # the shortest moves first
        if np.hypot(*(ring[w] - samples[other])) <= radius(ring[w][None])[0]:
            continue
        # the reflex vertices of end's other chord that end covered as their far end
        # must stay covered (an arc all on Q's side leaves nothing to cover)
        beside = (end - 1) % n if other == (end + 1) % n else end
        near = reflex[chord[reflex] == beside] if beyond[beside] else reflex[:0]
        r = radius(ring[near])
        before = np.hypot(*(ring[near] - samples[end]).T) <= r
        if not np.any(before & (np.hypot(*(ring[near] - ring[w]).T) > r)):
            _move_onto(samples, end, ring[w], fixed, radius)
    return samples


def _move_onto(samples, mover, target, fixed, radius):
    """Move sample ``mover`` of a ring's ``samples`` (in place) onto ``target`` if it is
    not ``fixed``, stays at least ``min(r(p), r(q))`` from its two neighbours q along the
    ring (``radius`` gives r at points) and makes no chord to them longer than it was and
    than √3 min(r(p), r(q)) (``LONGEST_CHORD``, the guards' threshold).

    A longer chord can be one no triangle on it is kept for: the complex keeps
    circumradii up to min r / (1 - L), so a chord beyond 2 min r / (1 - L) is never
    joined, and its lens refuses every dart beside it. A move onto a reflex vertex 0.45 r
    away made a chord of 3.11 between r = 1.81 and 1.19 (> 2.97) on a held-out heat
    sink's section: the chord's ends were left unjoined and the region beside it
    uncovered."""
    n = len(samples)
    neighbours = samples[[(mover - 1) % n, (mover + 1) % n]]
    r = radius(np.vstack([target, neighbours]))
    smaller = np.minimum(r[0], r[1:])
    now = np.hypot(*(neighbours - target).T)
    before = np.hypot(*(neighbours - samples[mover]).T)
    if not fixed[mover] and np.all(now >= smaller) and np.all(
            (now <= before) | (now <= LONGEST_CHORD * smaller)):
        samples[mover] = target


class _GradedSampler:
    """The state of one graded sampling: sample bins, radii, chords, samples so far."""

    def __init__(self, region: Region, field: RadiusField, max_samples: int):
        self.region = region
        self.field = field
        self.max_samples = max_samples
        xmin, ymin, xmax, ymax = region.bounds
        pad = field.cap
        self.x0, self.y0 = xmin - pad, ymin - pad
        width, height = xmax - xmin + 2 * pad, ymax - ymin + 2 * pad
        self.points = np.empty((1024, 2))
        self.radius = np.empty(1024)
        self.nxt = np.empty(1024, np.int32)
        self.count = 0
        self.rings = ()
        self.sampled_region = None          # the region through samples moved onto its arcs
        self.vis = vis_kern.no_chords(1024)
        self.chord_bound = np.empty(0)
        self.width, self.height = width, height

    def _bins(self, smallest: float, boundary_samples: int):
        """The pyramid of sample grids (_graded_kernels): level 0 with bins of about
        half the smallest radius, up to bins >= cap / 2; level 0 has fewer than
        _BINS_PER_SAMPLE bins per boundary sample (at least _MIN_BINS) and _MAX_BINS.

        The bins only speed the searches up (a sample of level l is looked for within
        min(r, 2 h) of a query, wherever it is binned), so their size changes no answer.
        Half the smallest radius over the whole bounding box made a 300-vertex section's
        level 0 up to a million bins (4 MB zeroed per call, the section's largest array)."""
        cells = min(_MAX_BINS, max(_MIN_BINS, _BINS_PER_SAMPLE * boundary_samples))
        h = max(0.5 * smallest, math.sqrt(self.width * self.height / cells))
        hs = [h]
        while hs[-1] < 0.5 * self.field.cap:
            hs.append(2 * hs[-1])
        hs = np.array(hs)
        nxs = (self.width / hs).astype(np.int64) + 1
        nys = (self.height / hs).astype(np.int64) + 1
        offsets = np.concatenate([[0], np.cumsum(nxs * nys)])
        self.h = h
        self.bins = (np.zeros(offsets[-1], np.int32), offsets, nxs, nys, hs,
                     np.zeros(len(hs), np.int64))

    def _reserve(self, extra: int):
        """Room for ``extra`` more samples in the arrays (candidates: not all are kept)."""
        need = self.count + extra
        if need > len(self.points):
            size = max(need, 2 * len(self.points))
            grow = size - len(self.points)
            self.points = np.concatenate([self.points, np.empty((grow, 2))])
            self.radius = np.concatenate([self.radius, np.empty(grow)])
            self.nxt = np.concatenate([self.nxt, np.empty(grow, np.int32)])
            out = np.full(size, -1, np.int64)
            out[:len(self.vis.out)] = self.vis.out
            self.vis = self.vis._replace(out=out)

    def _insert(self, cand, order, kept=None) -> np.ndarray:
        """Insert the candidates in ``order`` where the insertion test allows (``kept``,
        if given, marks them); returns r at the candidates."""
        cand = np.ascontiguousarray(cand, float)
        radius = self.field(cand)
        self._reserve(len(cand))
        self.count = kern.insert_where_free(cand, radius, order, self.field.grading,
                                            self.chord_bound, self.bins, self.nxt,
                                            self.points, self.radius, self.count, self.x0,
                                            self.y0, self.vis, kept)
        self._check_count()
        return radius

    def _check_count(self):
        if self.count > self.max_samples:
            raise BudgetError(f"the graded sampling made more than max_samples="
                              f"{self.max_samples} samples; {self._what_to_do()}")

    def add_boundary(self, feature_angle: float, rng, given=None) -> int:
        """Sample every ring (sharp corners, then the pieces between them in normalized
        arc length; or take the ``given`` samples of each ring), join consecutive samples
        by chords, bin the chords by their reach and add guards. Returns the number of
        boundary samples."""
        if given is not None:
            return self._place_boundary(given)
        L = self.field.grading
        unit = TAU_MARGIN / (1.0 - 0.5 * L)
        rings = self.region.rings
        # about 7 densified points a boundary sample (parts of 0.3 r, at most halved)
        dense_rings = _tau_rings(rings, self.field, L, 8 * self.max_samples)
        if dense_rings is None:
            raise BudgetError(f"the graded sampling's boundary alone would take more than "
                              f"max_samples={self.max_samples} samples; {self._what_to_do()}")
        all_turns = _turning_angles(rings)
        sharp_turn = np.radians(feature_angle)
        plain = [k for k, turns in enumerate(all_turns) if not np.any(np.abs(turns) >= sharp_turn)]
        # a ring without sharp corners starts at a random point (tau_positions), drawn
        # here for all of them in ring order, as the ring by ring loop drew them
        plain_at = dict(zip(plain, _plain_positions([dense_rings[k][3] for k in plain],
                                                    rng.random(len(plain)), unit)))
        placed = []
        for k, (dense, radius, first, tau) in enumerate(dense_rings):
            if k in plain_at:
                at = plain_at[k]
                fixed = np.zeros(len(at), bool)
            else:
                turns = all_turns[k]
                sharp_vertex = np.abs(turns) >= sharp_turn
                sharp = np.zeros(len(dense), bool)
                sharp[first] = sharp_vertex
                corner = np.flatnonzero(sharp)
                after, before = _corner_clearance(dense, radius, tau, corner,
                                                  turns[sharp_vertex], unit, first, L)
                at = tau_positions(tau, tau[corner], after, before, unit, rng)
                fixed = _fixed(at, tau[corner], after > unit, before > unit)
            placed.append((along(at, tau, np.vstack([dense, dense[:1]])), at, fixed))
        tol = 1e-9 * self.field.cap
        crossed, hides = _crossed_rings(
            [p[0] for p in placed], [p[1] for p in placed], rings,
            [tau[:-1][first] for _, _, first, tau in dense_rings], all_turns, tol)
        ring_xy = []
        for k, ((samples, at, fixed), ring) in enumerate(zip(placed, rings)):
            if crossed[k]:
                tau, first = dense_rings[k][3], dense_rings[k][2]
                samples = _uncrossed(samples, at, fixed, ring, tau[:-1][first], tau[-1],
                                     self.field)
            turns = all_turns[k]
            if (crossed[k] or hides[k]) and (turns < 0).any() and (turns > 0).any():
                samples = _unhidden(samples, fixed, ring, turns, self.field, tol)
            ring_xy.append(samples)
        ring_xy, self.sampled_region = onto_curves(self.region, ring_xy, self.field, np.inf)
        return self._place_boundary(ring_xy)

    def _place_boundary(self, ring_xy) -> int:
        """Place the samples of each ring (``ring_xy``, in order along it), join them by
        chords, bin the chords and add guards; returns the number of boundary samples."""
        boundary, self.rings = joined(ring_xy)
        radius = self.field(boundary)
        self._bins(0.5 * radius.min(), len(boundary))
        self._reserve(len(boundary))
        self._chords(boundary, radius)
        self.count = kern.place(boundary, radius, self.bins, self.nxt, self.points, self.radius,
                                0, self.x0, self.y0)
        self._check_count()
        self.domain = graded_domain(boundary, self.rings, len(self.points), self.x0, self.y0,
                                    self.width, self.height, self.h)     # exact in/out tests
        guards = guard_candidates(boundary, self.rings, self.field)
        guards = guards[vis_kern.points_inside(*self.domain, guards[:, 0], guards[:, 1])]
        self._insert(guards, np.arange(len(guards)))
        return len(boundary)

    def _chords(self, boundary, radius):
        """The chords, each binned within its reach (:func:`.boundary_sampling.chord_reach`)
        on the sampler's grid, and each chord's bound min r / (1 - L) over its ends."""
        L = self.field.grading
        a, b = chord_ends(self.rings)
        reach = chord_reach(boundary, self.rings, radius, L)
        self.vis = graded_chords(boundary, self.rings, reach, len(self.points), self.x0,
                                 self.y0, self.width, self.height, self.h)
        self.chord_bound = np.minimum(radius[a], radius[b]) / (1.0 - L)

    def add_interior(self, rng, tile=False):
        """Dart passes over the quadtree's leaves, then the refinement of uncovered boxes.
        Boxes are (x, y, size, low, high, edge): ``low`` and ``high`` bounds of r on the
        box, ``edge`` whether it may reach outside the chord polygons. A box found open
        is tested again, after the darts, against the new samples only. Each level of
        the refinement is one kernel call (``_graded_kernels.split_open``: the coverage
        test, the split, r at the quarters, the in/out test and the coverage test of the
        quarters) and one throw. With ``tile``, the disc tile's points come first
        (:meth:`_add_tile`), and the leaves they cover get no dart."""
        self.kernel_field = self.field._kernel
        tiled = self._add_tile(rng) if tile else None
        boxes, since = self._leaves(), 0
        if tiled is not None:
            open_ = ~self._tile_covered(boxes, *tiled)
            boxes = tuple(a[open_] for a in boxes)
        for k in range(_PASSES):
            boxes, since = self._open(boxes, since), self.count
            boxes = self._throw(boxes, rng, plain=k == 0 and tiled is None)
        while len(boxes[0]):
            boxes = kern.split_open(boxes, since, RESOLUTION,
                                    _MAX_BOXES_PER_SAMPLE * self.max_samples,
                                    self.kernel_field, self.domain, self.chord_bound,
                                    self.bins, self.nxt, self.points, self.radius, self.x0,
                                    self.y0, self.vis)
            if isinstance(boxes, int):
                self._check_boxes(boxes)
            since = self.count                  # darts only where no disc covers already
            boxes = self._throw(boxes, rng)

    def _add_tile(self, rng) -> tuple | None:
        """Insert the points of the periodic disc tile (:mod:`.disc_tile`), scaled by the
        cap and at a random offset, that lie in the region and pass the insertion test,
        tile by tile. Returns those in the region that are no sample with r at the cap
        (refused, or r below the cap there): the holes in the tile's cover.

        Only the tile's points in the boxes of the region's polygons, widened by the cap
        (boundary samples on exact arcs lie beyond the flattened polygons), are asked (a
        layout of small patches far apart, ``remeshing._meshed_together``, is mostly
        gaps), each once: by its number (tile row, tile column, point); and none in a
        polygon whose box is at most ``4 cover`` (x cap) wide (most of it would be
        within reach of its boundary, where :meth:`_tile_covered` closes no box): the
        boxes of those polygons are returned too, as ``(holes, untiled)``. None if no
        polygon is wider."""
        tile = disc_tile.tile()
        cap, side, count = self.field.cap, tile.side, len(tile.points)
        offset = rng.random(2) * side
        bounds = shapely.bounds(shapely.get_parts(self.region.geometry))
        wide = (np.minimum(bounds[:, 2] - bounds[:, 0], bounds[:, 3] - bounds[:, 1])
                > 4.0 * tile.cover * cap)
        bounds = bounds + np.array([-cap, -cap, cap, cap])     # samples moved onto arcs
        untiled, bounds = bounds[~wide], bounds[wide]
        if not len(bounds):
            return None
        low = np.floor((bounds[:, :2] / cap - offset) / side).astype(np.int64)
        high = np.floor((bounds[:, 2:] / cap - offset) / side).astype(np.int64)
        base, columns = low.min(axis=0), int(high[:, 1].max() - low[:, 1].min()) + 1
        # the tiles (i, j) over each box, row by row, all boxes at once
        rows, cols = (high - low + 1).T
        box = np.repeat(np.arange(len(bounds)), rows * cols)
        k = np.arange(len(box)) - np.repeat(np.cumsum(rows * cols) - rows * cols, rows * cols)
        i, j = low[box, 0] + k // cols[box], low[box, 1] + k % cols[box]
        xy = ((np.column_stack([i, j]) * side + offset)[:, None, :] + tile.points) * cap
        x0, y0, x1, y1 = (bounds[box, c, None] for c in range(4))
        tiles, at = np.nonzero((xy[..., 0] >= x0) & (xy[..., 0] <= x1)
                               & (xy[..., 1] >= y0) & (xy[..., 1] <= y1))
        numbers = ((i[tiles] - base[0]) * columns + j[tiles] - base[1]) * count + at
        # the polygons' boxes may overlap: each point once, by its number
        points = xy[tiles, at][np.unique(numbers, return_index=True)[1]]
        points = points[vis_kern.points_inside(*self.domain, points[:, 0], points[:, 1])]
        kept = np.zeros(len(points), bool)
        radius = self._insert(points, np.arange(len(points)), kept)
        return points[~(kept & (radius >= cap))], untiled

    def _tile_covered(self, boxes, holes, untiled) -> np.ndarray:
        """The boxes (leaves) that the tile's samples cover, so that no dart is needed:
        r is the cap on the box, and no hole in the tile's cover, no chord and no box of
        an ``untiled`` polygon (:meth:`_add_tile`) lies within ``2 cover`` (x cap) of it.
        Then every point x of the box lies in a periodic Delaunay triangle of the tile
        whose corners are within ``2 cover`` of x, so in the region (no chord between),
        tile points asked and samples with r at the cap (no hole); the nearest is within
        ``cover`` (the triangle lies in its circumcircle), and x sees it.

        Distances are bounded from the boxes' centres on a grid of cells of side cap / 2
        (of at most :data:`_TILE_CELLS` cells): a point within d of a centre is within
        ceil(d / side) cells of its cell. A chord within d of a point has an end within
        d + its length / 2, and 1e-9 of the cap is added for rounding."""
        bx, by, size = boxes[:3]
        cap, cover = self.field.cap, disc_tile.tile().cover
        half = float(size.max(initial=0.0)) / math.sqrt(2)       # half the diagonal
        boundary = self.points[:sum(len(ring) for ring in self.rings)]    # rings are runs
        first, second = chord_ends(self.rings)
        longest = float(np.hypot(*(boundary[second] - boundary[first]).T).max(initial=0.0))
        reach = half + 2.0 * cover * cap + 0.5 * longest + 1e-9 * cap
        cell = max(0.5 * cap, math.sqrt(self.width * self.height / _TILE_CELLS))
        nx, ny = int(self.width / cell) + 1, int(self.height / cell) + 1

        def cells(x, y):
            return (np.clip(((x - self.x0) / cell).astype(np.int64), 0, nx - 1),
                    np.clip(((y - self.y0) / cell).astype(np.int64), 0, ny - 1))

        far = np.vstack([holes, boundary])
        fx, fy = cells(far[:, 0], far[:, 1])
        marks = np.bincount(fy * nx + fx, minlength=nx * ny).reshape(ny, nx)
        if len(untiled):                    # every cell of the boxes, by a difference grid
            (lx, ly), (hx, hy) = cells(untiled[:, 0], untiled[:, 1]), cells(untiled[:, 2],
                                                                            untiled[:, 3])
            step = np.zeros((ny + 1, nx + 1), np.int64)
            for dx, dy, sign in ((lx, ly, 1), (hx + 1, ly, -1), (lx, hy + 1, -1),
                                 (hx + 1, hy + 1, 1)):
                np.add.at(step, (dy, dx), sign)
            marks = marks + step.cumsum(0).cumsum(1)[:ny, :nx]
        within = np.zeros((ny + 1, nx + 1), np.int64)     # marks in cells [0, i) x [0, j)
        within[1:, 1:] = marks.cumsum(0).cumsum(1)
        centres = np.column_stack([bx + 0.5 * size, by + 0.5 * size])
        cx, cy = cells(centres[:, 0], centres[:, 1])
        k = int(math.ceil(reach / cell))
        x0, x1 = np.clip(cx - k, 0, nx), np.clip(cx + k + 1, 0, nx)
        y0, y1 = np.clip(cy - k, 0, ny), np.clip(cy + k + 1, 0, ny)
        covered = (within[y1, x1] - within[y0, x1] - within[y1, x0] + within[y0, x0]) == 0
        covered[covered] = self.field.capped_within(centres[covered], half)
        return covered

    def _leaves(self):
        """Quadtree leaves over the region (``_graded_kernels.leaves``): boxes split while
        their side exceeds r_low, boxes outside the chord polygons dropped."""
        s = self.field.cap / math.sqrt(2)
        xmin, ymin, xmax, ymax = self.region.bounds
        nx, ny = int(math.ceil((xmax - xmin) / s)) or 1, int(math.ceil((ymax - ymin) / s)) or 1
        leaves = kern.leaves(xmin, ymin, s, nx, ny, _MAX_BOXES_PER_SAMPLE * self.max_samples,
                             self.kernel_field, self.domain,
                             self._cells_near_rings(xmin, ymin, s, nx, ny))
        if isinstance(leaves, int):
            self._check_boxes(leaves)
        return leaves

    def _cells_near_rings(self, xmin, ymin, side, nx, ny):
        """The cells of the leaves' grid (numbers row x nx + column, ascending) within
        one cell of some ring's box (the box of its samples, which holds its chords), or
        None (the whole grid) when those are most of it. The region bounded by the
        chords lies in its rings' boxes, so every other cell is outside it: the leaves
        are the same (:func:`._graded_kernels.leaves`)."""
        if len(self.rings) < 2 or min(len(ring) for ring in self.rings) == 0:
            return None
        starts = np.array([ring[0] for ring in self.rings])        # rings are runs
        boundary = self.points[:int(self.rings[-1][-1]) + 1]
        lo = np.minimum.reduceat(boundary, starts, axis=0)
        hi = np.maximum.reduceat(boundary, starts, axis=0)
        i0 = np.clip(np.floor((lo[:, 0] - xmin) / side).astype(np.int64) - 1, 0, nx - 1)
        i1 = np.clip(np.floor((hi[:, 0] - xmin) / side).astype(np.int64) + 1, 0, nx - 1)
        j0 = np.clip(np.floor((lo[:, 1] - ymin) / side).astype(np.int64) - 1, 0, ny - 1)
        j1 = np.clip(np.floor((hi[:, 1] - ymin) / side).astype(np.int64) + 1, 0, ny - 1)
        widths, heights = i1 - i0 + 1, j1 - j0 + 1
        if int(np.sum(widths * heights)) >= nx * ny // 2:
            return None
        rows = np.repeat(np.arange(len(lo)), heights)
        j = np.arange(len(rows)) - np.repeat(np.cumsum(heights) - heights, heights) + j0[rows]
        starts = j * nx + i0[rows]                 # each ring's row of cells: a run
        counts = widths[rows]
        cells = np.repeat(starts - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())
        cells.sort()                # np.unique's result, sorted here: numpy 2.4's unique of
        return cells[np.append(True, cells[1:] != cells[:-1])]    # ints hashes (10x slower)

    def _check_boxes(self, count: int):
        """Refuse a refinement that would hold more than _MAX_BOXES_PER_SAMPLE boxes per
        allowed sample (each box gets a dart: the work would outgrow the budget)."""
        if count > _MAX_BOXES_PER_SAMPLE * self.max_samples:
            raise BudgetError(f"the graded sampling would refine {count} boxes at once, more "
                              f"than {_MAX_BOXES_PER_SAMPLE} per sample of max_samples="
                              f"{self.max_samples}; {self._what_to_do()}")

    def _what_to_do(self) -> str:
        return ("raise max_samples or the grading, or pass a larger alpha or sizing (the "
                f"field's smallest radius here is {self.field.sizes.min(initial=self.field.cap):.3g})")

    def _open(self, boxes, since=0):
        """The boxes no single visible disc covers; with ``since``, boxes found open
        before sample ``since`` was placed, tested against the later samples only."""
        bx, by, size, low, high, edge = boxes
        keep = kern.uncovered_boxes(bx, by, size, low, high, self.field.grading,
                                    self.chord_bound, self.bins, self.nxt, self.points,
                                    self.radius, self.x0, self.y0, self.vis, since)
        return tuple(a[keep] for a in boxes)

    def _throw(self, boxes, rng, plain=False):
        """One dart in each box, in a sub-box of it that no single disc covers (uniform
        in the box if ``plain``); darts in the region thrown in random order
        (``_graded_kernels.throw``: the refusal test, r and the insertion). Returns the
        boxes not found covered (each sub-box by a visible disc) before the throw."""
        n = len(boxes[0])
        u = rng.random((n, 3))
        order = rng.permutation(n)
        self._reserve(n)
        self.count, closed = kern.throw(boxes, u, order, self.kernel_field, self.domain,
                                        self.chord_bound, self.bins, self.nxt, self.points,
                                        self.radius, self.count, self.x0, self.y0, self.vis,
                                        plain)
        self._check_count()
        if closed.any():
            return tuple(a[~closed] for a in boxes)
        return boxes
