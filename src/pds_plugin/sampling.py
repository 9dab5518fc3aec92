"""Maximal Poisson disc sampling of a planar region.

The sampling is built in three stages, each conditioned on the samples before it, with
the Euclidean distance between *all* samples respected (across narrow gaps and between
components):

1. **Feature corners.** Boundary vertices where the outline turns by at least
   ``feature_angle`` degrees, sharpest first, wherever the Poisson condition allows.
2. **Boundary.** The boundary is cut into pieces shorter than ``alpha``. Visiting them
   in random order, the part of each piece farther than ``alpha`` from every sample is
   computed exactly and a sample is placed uniformly in it. A sample covers its whole
   piece, so one pass gives a maximal sampling of the boundary curves.
3. **Interior.** Dart throwing on a grid of cells of side < alpha/√2 (one sample per
   cell at most), then the adaptive refinement of Ebeida et al. (2012): cells not yet
   covered by a single disc are split in four, children covered by one disc or outside
   the region are dropped, and a dart is thrown in each child, until no child is left
   or children are smaller than ``1e-10 * alpha`` (so the coverage radius is alpha to
   that tolerance).

**Conforming** samplings (the default of :func:`pds_plugin.mesh_region`) change stages 1
and 2 and constrain stage 3 (docs/conforming.md): every sharp corner is sampled; the
boundary between corners gets samples at consecutive distances in [alpha, √3 alpha]
(a "guard" sample is added inside where a piece is too short to split that way);
consecutive boundary samples are joined by *chords*, the mesh's boundary; and two samples
conflict, and a sample covers a point, only if they see each other through the region
bounded by the chords. Walls of notches and gaps narrower than alpha are then sampled on
both sides.

Every random number comes from ``numpy.random.default_rng(seed)`` in a fixed order, so
the same region, alpha and seed give the same samples bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely

from . import _sampling_kernels as kern
from . import _visibility_kernels as vis_kern
from . import boundary_rules
from ._checks import check_alpha, check_positive_int, check_seed
from .boundary_rules import LONGEST_CHORD, LONGEST_MOVED_CHORD
from .boundary_sampling import (RESOLUTION, along, chord_ends, domain_of_rings, given_boundary,
                                guard_candidates, joined, onto_curves)
from .errors import BudgetError, RegionError
from .region import Region, require_region, turning_angles

__all__ = ["Samples", "poisson_disc", "estimate_samples", "largest_alpha", "check_budget",
           "check_rings_apart", "DEFAULT_MAX_SAMPLES"]

DEFAULT_MAX_SAMPLES = 5_000_000
"""Refuse samplings expected to exceed this many samples. At the cap, mesh_region of a unit
square makes 4.97 M samples and 9.9 M triangles and peaked at 2.0 GiB resident (measured
with /usr/bin/time -v with the numba kernels, before the compiled engine)."""

_MAX_GRID_CELLS = 50_000_000    # about 1.5 GB of grids
_PHASE1_PASSES = 3
_CURVE_PASSES = 6     # boundary splits redone with longer arcs where a chord is below alpha
_CROWDED_CELL = 256  # conforming refinement stops in a boundary cell with more open boxes
_REFINEMENT_BOXES = 2  # and everywhere above this many boxes per cell of the region
_MAX_CURVE_SCALE = 1.5  # the longest those arcs get, / alpha (they stay <= √3 alpha)
STRAIGHT_TURN = 1e-9   # turns (radians) below this are straight: rounding, not a bend
_INFLECTION_APART = 3.0  # inflections sampled only this far (/ alpha) from other breaks
_NOISY_INFLECTION_APART = 1.5  # the same where the boundary is known up to a tolerance
_NOISY_KINK_APART = 1.0  # kinks there: just separated (each one unsampled hides region)
LADDER_ANGLE = 2 * math.asin(1 / (2 * math.sqrt(3)))  # spikes sharper (33.56°) get mirror pairs


@dataclass(frozen=True)
class Samples:
    """A Poisson disc sampling, as :func:`poisson_disc` makes it.

    Attributes
    ----------
    points : (N, 2) float ndarray
        The samples, boundary samples first.
    on_boundary : (N,) bool ndarray
        True for the samples placed on the region's boundary.
    alpha : float
        The disc radius.
    rings : tuple of (k,) int ndarray
        Conforming samplings: the boundary rings as sample indices, each with the region
        on its left (consecutive samples are joined by the mesh's boundary); else empty.
    radius : (N,) float ndarray or None
        Graded samplings (:func:`pds_plugin.graded_sampling.graded_poisson_disc`): the
        radius r of the field at each sample; None for uniform ones.
    region : Region or None
        Conforming samplings of a region with exact curves (``region.curves``): the
        region refined through the boundary samples, which were moved onto its arcs
        (:func:`pds_plugin.boundary_curves.samples_onto_curves`); None otherwise.
    chords : ChordBundle or None
        Graded samplings: the rings' chords, each binned within its reach
        (:func:`pds_plugin.boundary_sampling.graded_chords`), which
        :func:`pds_plugin.graded_complex.graded_alpha_complex` takes instead of binning
        them again; None otherwise.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> samples = poisson_disc(Region.from_shapely(box(0, 0, 1, 1)), 0.25, seed=0)
    >>> len(samples) == len(samples.points), bool(samples.on_boundary[0])
    (True, True)
    """

    points: np.ndarray
    on_boundary: np.ndarray
    alpha: float
    rings: tuple = ()
    radius: np.ndarray | None = None
    region: Region | None = None
    chords: object = None

    def __len__(self) -> int:
        return len(self.points)


def estimate_samples(region: Region, alpha: float) -> float:
    """About how many samples a maximal sampling of ``region`` with radius ``alpha`` has:
    ``0.7 * area / alpha² + perimeter / alpha``.

    Parameters
    ----------
    region : Region
    alpha : float

    Returns
    -------
    float

    Examples
    --------

    >>> from shapely.geometry import box
    >>> round(estimate_samples(Region.from_shapely(box(0, 0, 1, 1)), 0.01))
    7400
    """
    return 0.7 * region.area / alpha / alpha + region.perimeter / alpha   # inf, never an error


def check_budget(region: Region, alpha: float, max_samples: int) -> None:
    """Refuse an ``alpha`` whose sampling of ``region`` :func:`estimate_samples` puts over
    ``max_samples``, before anything is allocated; the message gives the largest alpha the
    budget allows. A graded sampling capped at ``alpha`` makes at least as many.

    >>> from shapely.geometry import box
    >>> check_budget(Region.from_shapely(box(0, 0, 1, 1)), 1e-9, 1000)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    pds_plugin.errors.BudgetError: alpha=1e-09 would make about 7e+17 samples, more than max_samples=1000; use alpha >= 0.0...
    """
    expected = estimate_samples(region, alpha)
    if expected > max_samples:
        raise BudgetError(
            f"alpha={alpha:.6g} would make about {expected:.3g} samples, more than "
            f"max_samples={max_samples}; use alpha >= {largest_alpha(region, max_samples):.6g} "
            "or raise max_samples")


def largest_alpha(region: Region, max_samples: int) -> float:
    """The alpha at which :func:`estimate_samples` equals ``max_samples``: the smallest
    radius a sample budget allows; or, if larger, the smallest whose sampling grid over
    the region's bounding box stays within the grid's limit (a thin part across a wide
    box, as a tilted plane through a plate gives).

    Parameters
    ----------
    region : Region
    max_samples : int

    Returns
    -------
    float

    Examples
    --------
    >>> from shapely.geometry import box
    >>> square = Region.from_shapely(box(0, 0, 1, 1))
    >>> round(estimate_samples(square, largest_alpha(square, 7400)))
    7400
    """
    a, p = 0.7 * region.area, region.perimeter
    samples = (p + math.sqrt(p * p + 4 * max_samples * a)) / (2 * max_samples)
    # (w / s + 3) (h / s + 3) cells of side s = alpha / √2 at most, 1 % to spare
    xmin, ymin, xmax, ymax = region.bounds
    w, h, cells = xmax - xmin, ymax - ymin, 0.99 * _MAX_GRID_CELLS
    per_side = (-3 * (w + h) + math.sqrt(9 * (w + h) ** 2 + 4 * w * h * (cells - 9))) / (2 * w * h)
    return max(samples, math.sqrt(2) / per_side * (1 + 1e-9))


def poisson_disc(region: Region, alpha: float, seed: int = 0, *,
                 max_samples: int = DEFAULT_MAX_SAMPLES,
                 feature_angle: float = 30.0, conforming: bool = False,
                 boundary_samples=None) -> Samples:
    """Maximal Poisson disc sampling of ``region`` with radius ``alpha``.

    Every two samples are at least ``alpha`` apart, every point of the region is within
    ``alpha`` of a sample, and the boundary is sampled first (see the module docstring).

    Parameters
    ----------
    region : Region
    alpha : float
        The disc radius, in the region's units.
    seed : int
        Seed of the random generator; the same seed gives the same samples.
    max_samples : int
        Refuse (with a :class:`~pds_plugin.errors.BudgetError`) when about more samples
        than this would be made.
    feature_angle : float
        Boundary vertices where the outline turns by at least this many degrees are
        sampled first, as feature points.
    conforming : bool
        Sample for a conforming, constrained mesh (see the module docstring): the
        result's ``rings`` give the boundary to pass to
        :func:`pds_plugin.solid_alpha_complex`.
    boundary_samples : sequence of (k, 2) array_like, optional
        Conforming samplings: the boundary samples of each ring of ``region.rings``, in
        order along it, given instead of drawn (guards and interior as usual).
        :mod:`pds_plugin.partition` gives them so that a boundary chain shared by two
        regions gets the same samples on both sides.

    Returns
    -------
    Samples

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``region`` is not a Region or ``alpha`` is not a positive number.
    BudgetError
        If the sampling would exceed ``max_samples`` (the message gives the estimate and
        the largest acceptable alpha) or the grid would be too large.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> region = Region.from_shapely(box(0, 0, 1, 1))
    >>> samples = poisson_disc(region, 0.1, seed=1)
    >>> bool(samples.on_boundary.any()), samples.points.shape[1]
    (True, 2)
    >>> conforming = poisson_disc(region, 0.1, seed=1, conforming=True)
    >>> [len(ring) >= 4 for ring in conforming.rings]     # corners and more, in order
    [True]
    """
    require_region(region, "poisson_disc")
    alpha = check_alpha(alpha)
    seed = check_seed(seed)
    max_samples = check_positive_int(max_samples, "max_samples")
    check_budget(region, alpha, max_samples)
    if conforming:
        check_rings_apart(region)
    if boundary_samples is not None:
        boundary_samples = given_boundary(region, boundary_samples, conforming)
    rng = np.random.default_rng(seed)
    sampler = _Sampler(region, alpha, conforming)
    if conforming:
        n_boundary = sampler.add_conforming_boundary(feature_angle, rng, boundary_samples)
    else:
        sampler.add_corners(feature_angle)
        sampler.add_boundary(rng)
        n_boundary = sampler.count
    sampler.add_interior(rng)
    points = sampler.points[:sampler.count].copy()
    on_boundary = np.zeros(len(points), bool)
    on_boundary[:n_boundary] = True
    return Samples(points, on_boundary, alpha, sampler.rings, region=sampler.sampled_region)


def check_rings_apart(region: Region):
    """Refuse, for conforming samplings, a region whose boundary rings touch.

    A valid polygon may have a hole touching its outline at a point. A conforming
    sampling joins each ring's samples by chords, so such a point would be a sample of
    two rings at once. :meth:`Region.from_shapely` opens such points (parts touching
    move apart, a touching hole opens there); a Region built otherwise that still has
    one gets a :class:`~pds_plugin.errors.RegionError` naming the point.

    Examples
    --------
    >>> from shapely.geometry import MultiPolygon, Polygon
    >>> touching = Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(0, 2), (2, 1), (2, 3)]])
    >>> check_rings_apart(Region(MultiPolygon([touching]), np.eye(4)))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    pds_plugin.errors.RegionError: the region's boundary touches itself at (0, 2) ...
    """
    if len(region.rings) < 2:
        return
    sizes = [len(ring) for ring in region.rings]
    rings = shapely.linearrings(np.concatenate(region.rings),
                                indices=np.repeat(np.arange(len(sizes)), sizes))
    first, second = shapely.STRtree(rings).query(rings, predicate="intersects")
    pairs = first < second
    if pairs.any():
        i, j = first[pairs][0], second[pairs][0]
        x, y = shapely.get_coordinates(shapely.intersection(rings[i], rings[j]))[0]
        raise RegionError(
            f"the region's boundary touches itself at ({x:.6g}, {y:.6g}) (a hole touching "
            "the outline or another hole); a conforming mesh needs rings "
            "that do not touch: mesh it with conforming=False (pds-mesh --no-conforming), or "
            "open the point, e.g. region.geometry.buffer(-tiny)")


def corner_clearance(angle, alpha):
    """The arc length a conforming sampling keeps free of samples on each side of a
    corner where the region's angle is ``angle`` (radians): alpha / (2 sin(angle / 2))
    below 60°, so that on straight sides the first samples on the two sides are alpha
    apart, and alpha otherwise; capped just below √3 alpha, the longest part (a bound of
    exactly √3 alpha would leave ``split_gaps`` an interval of width 0 to draw that part
    from, and the side whole, up to 2√3 alpha long).

    Examples
    --------
    >>> [round(float(corner_clearance(np.radians(a), 1.0)), 4) for a in (90, 45, 20)]
    [1.0, 1.3066, 1.732]
    """
    angle = np.asarray(angle, float)
    guard = np.where(angle < np.pi / 3, alpha / (2 * np.sin(np.maximum(angle, 1e-300) / 2)),
                     alpha)
    return np.minimum(guard, LONGEST_CHORD * alpha)


def _inflections(cum, turns, sharp, alpha, apart=_INFLECTION_APART,
                 kinks_apart=_INFLECTION_APART) -> np.ndarray:
    """Arc positions where a ring's boundary changes the way it bends between two sharp
    corners (an S-curve's inflection), to be sampled like corners, so that the arc
    between consecutive samples bends one way only and lies on one side of its chord
    (docs/conforming.md, "Inflections").

    The vertices turning by more than ``STRAIGHT_TURN`` (and less than a sharp corner)
    define the bends; between two consecutive ones that turn opposite ways, with no sharp
    corner between them, the inflection is the middle of the arc that joins them, and a
    vertex turning against both its neighbours (a kink) is one itself. One is
    kept only at least ``apart`` alpha along the ring from every sharp corner and every
    inflection kept before it. At ``_INFLECTION_APART`` (3) the pieces it bounds hold a
    corner's clearance (at most √3 alpha) and parts of up to 1.5 alpha, the longest the
    curve rescaling asks for (a piece of one part cannot be rescaled, and its chord falls
    below alpha on a curve). A boundary known up to a tolerance (a tessellated curve cut
    by a plane) has inflections wherever the noise bends it, and each one not sampled may
    leave an arc bending both ways: ``_NOISY_INFLECTION_APART`` (1.5) samples twice as
    many, at the price of chords below alpha on pieces of one part (itemised exceptions).
    Kinks are kept first, ``kinks_apart`` apart (there ``_NOISY_KINK_APART``, 1: just
    separated), reflex ones before convex ones, and the other inflections then clear of
    them: a reflex kink left unsampled hides the region just past it from the chord end
    before it, while the inflection of a long arc between two opposite turns may fall
    anywhere on that arc.

    Examples
    --------
    >>> s_curve = np.array([[0, 0], [1, 0.1], [2, 0], [3, -0.1], [4, 0], [4, -1], [0, -1]], float)
    >>> from pds_plugin.region import turning_angles
    >>> turns = turning_angles(s_curve)
    >>> closed = np.vstack([s_curve, s_curve[:1]])
    >>> cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    >>> _inflections(cum, turns, np.abs(turns) >= np.radians(30), 0.2).round(4).tolist()  # at (2, 0)
    [2.01]
    """
    length = cum[-1]
    bending = np.flatnonzero((np.abs(turns) > STRAIGHT_TURN) & ~sharp)
    if len(bending) < 2:
        return np.zeros(0)
    at = cum[bending]
    after = np.roll(bending, -1)
    span = np.roll(at, -1) - at
    span[span <= 0] += length
    flips = np.sign(turns[bending]) != np.sign(turns[after])
    # no sharp corner strictly between the two bending vertices
    corners = cum[:-1][sharp]
    if len(corners):
        ahead = (corners[None, :] - at[:, None]) % length
        flips &= ~((ahead > 0) & (ahead < span[:, None])).any(axis=1)
    # a kink (one vertex turning against both its neighbours, as where a plane crosses a
    # tessellation's seam) is sampled itself: the arcs on its two sides then bend one way,
    # where the two inflections around it, closer than the rule below allows, would
    # keep only one
    kink = flips & np.roll(flips, 1)
    single = flips & ~kink & ~np.roll(kink, -1)
    # reflex kinks first: one left unsampled hides the ring past it from the chord end
    # before it, where a convex one hides nothing
    reflex = turns[bending] < 0
    kinks = np.zeros(0)
    for chosen in (kink & reflex, kink & ~reflex):
        found = _clear_of(_clear_of(np.sort(at[chosen] % length), corners, apart * alpha, length),
                          kinks, kinks_apart * alpha, length)
        kinks = np.sort(np.append(kinks, _thinned(found, kinks_apart * alpha, length)))
    singles = np.sort((at[single] + 0.5 * span[single]) % length)
    blocking = np.sort(np.concatenate([corners, kinks]))
    singles = _thinned(_clear_of(singles, blocking, apart * alpha, length), apart * alpha, length)
    return np.sort(np.concatenate([kinks, singles]))


def _clear_of(candidates, blocking, distance, length) -> np.ndarray:
    """The sorted ring positions ``candidates`` at least ``distance`` from every one of
    the sorted positions ``blocking``, either way round a ring of ``length``."""
    if not len(blocking):
        return candidates
    after = np.searchsorted(blocking, candidates) % len(blocking)
    clear = np.minimum((blocking[after] - candidates) % length,
                       (candidates - blocking[after - 1]) % length) >= distance
    return candidates[clear]


def _thinned(candidates, distance, length) -> np.ndarray:
    """The sorted ring positions ``candidates`` kept in order when at least ``distance``
    from the last kept and, round the ring, from the first."""
    kept = []
    for x in candidates:
        if not kept or (x - kept[-1] >= distance and length - (x - kept[0]) >= distance):
            kept.append(x)
    return np.array(kept)


def ring_positions(ring, turns, feature_angle, alpha, rng,
                   inflections_apart=(_INFLECTION_APART, _INFLECTION_APART)):
    """Arc-length positions of a ring's boundary samples, increasing: its sharp corners
    and the inflections of its curves (:func:`_inflections`; or one random point if it
    has neither), the pieces between them split by ``split_gaps`` into parts of arc
    length in [alpha, √3 alpha], and at least three in all.

    Beside a convex corner sharper than 60° the first part is at least
    alpha / (2 sin(θ/2)) long (θ the corner's angle, at most √3 alpha), so the samples on
    its two sides are alpha apart. On a curve a chord is shorter than its arc: where a
    chord of a piece falls below alpha, that piece is split again with its lower bounds
    scaled by alpha / that chord (its parts stay at most √3 alpha, so their chords do).
    Inflections and kinks are kept ``inflections_apart`` alpha apart
    (:func:`_inflections`); spikes sharper than 33.56° are sampled in mirror pairs
    (:func:`_ladders`). :mod:`pds_plugin.partition` samples shared boundary chains with
    it too."""
    closed = np.vstack([ring, ring[:1]])
    cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    length = cum[-1]
    sharp = np.abs(turns) >= np.radians(feature_angle)
    longest = math.sqrt(3) * alpha
    first_cap = corner_clearance(0.0, alpha)       # the cap (a corner of angle 0)
    bends = _inflections(cum, turns, sharp, alpha, *inflections_apart)
    if sharp.any() or len(bends):
        corners = np.concatenate([cum[:-1][sharp], bends])
        angle = np.concatenate([np.pi - turns[sharp], np.full(len(bends), np.pi)])  # the region's
        order = np.argsort(corners, kind="stable")
        corners, angle = corners[order], angle[order]
    else:
        corners, angle = np.array([rng.random() * length]), np.array([np.pi])
    guard = corner_clearance(angle, alpha)
    after, before, pins = _clearances(corners, angle, guard, cum, closed, alpha)
    if len(pins):                             # breaks of their own: see _clearances
        order = np.argsort(np.concatenate([corners, pins]), kind="stable")
        corners = np.concatenate([corners, pins])[order]
        angle = np.concatenate([angle, np.full(len(pins), np.pi)])[order]
        guard = corner_clearance(angle, alpha)
        after, before, _ = _clearances(corners, angle, guard, cum, closed, alpha)
    lo = corners
    hi = np.append(corners[1:], corners[0] + length)
    scale = np.ones(len(lo))
    todo = np.arange(len(lo))                     # the pieces (re)split in this pass
    inner, owner = np.zeros(0), np.zeros(0, np.int64)
    for _ in range(_CURVE_PASSES):
        shortest = scale * alpha
        first = np.minimum(np.maximum(after * scale, shortest), first_cap)
        last = np.minimum(np.maximum(before * scale, shortest), first_cap)
        u = rng.random(int(np.sum((hi[todo] - lo[todo]) // shortest[todo])) + len(todo))
        new, new_owner = kern.split_gaps(lo[todo], hi[todo], first[todo], last[todo],
                                         shortest[todo], longest, u)
        kept = ~np.isin(owner, todo)              # the pieces whose chords were all fine
        inner = np.concatenate([inner[kept], new])
        owner = np.concatenate([owner[kept], todo[new_owner]])
        # corners closer than the sampler's resolution (a zero-length edge, or one a
        # rounding long) give one sample: two would block each other's view
        at, keep = np.unique(np.concatenate([corners, inner]) % length, return_index=True)
        apart = np.diff(at, prepend=at[-1] - length) > RESOLUTION * min(alpha, length)
        apart[0] |= not apart.any()
        at, keep = at[apart], keep[apart]
        piece = np.concatenate([np.arange(len(corners)), owner])[keep]
        ends = np.append(at, at[0] + length)
        xy = np.column_stack([np.interp(ends % length, cum, closed[:, 0]),
                              np.interp(ends % length, cum, closed[:, 1])])
        chord = np.hypot(*np.diff(xy, axis=0).T)
        arc = np.diff(ends)
        regular = arc >= shortest[piece] * (1 - 1e-12)      # not a piece too short to split
        ratio = np.ones(len(lo))
        np.minimum.at(ratio, piece[regular], chord[regular] / (alpha * (1 - 1e-12)))
        if ratio.min() >= 1 or not len(inner):
            break
        # only the pieces with a chord below alpha are split again. The next split is
        # random too, and may put a part where the curve bends more: scale by the square
        # of what this one needed (at most 1.5, so that parts in [1.5, √3] alpha still
        # leave room to split)
        todo = np.flatnonzero(ratio < 1)
        scale[todo] = np.minimum(scale[todo] / ratio[todo] ** 2 * (1 + 1e-9), _MAX_CURVE_SCALE)
        # but a piece longer than √3 alpha must still split into parts (its first and
        # last at least their scaled lower bounds, and as many parts between as its
        # length needs): left whole, its chord could exceed 2 alpha, which no triangle
        # of circumradius <= alpha has as an edge, or cut off a whole bend (on
        # spline.DXF a 4.4 alpha piece round a 0.4 alpha tip, at scale 1.5, could not be
        # cut into parts of [1.5, √3] alpha: its chord left a lobe of the region out)
        parts = np.maximum(np.ceil((hi - lo) / longest), 2.0)
        fits = (hi - lo) / (np.maximum(after, alpha) + np.maximum(before, alpha)
                            + (parts - 2) * alpha)
        splittable = hi - lo > longest
        scale[splittable] = np.minimum(scale[splittable],
                                       np.maximum(1.0, fits[splittable] * (1 - 1e-9)))
    # halved before the ladders too, so that a spike's side too short for its clearances
    # gets its middle mirrored: halved only after them, one side's middle had no image (a
    # sliver of shared.STL at a random plane: its 16° tip's triangle too large, the tip
    # isolated)
    at = _ladders(_halved_long_chords(at, cum, closed, alpha), corners, angle, guard, alpha,
                  length, rng, (cum, closed))
    if len(at) == 1:                         # a ring smaller than alpha: keep it a ring
        at = np.sort((at[0] + length * np.arange(3) / 3) % length)
    while len(at) < 3:
        gaps = np.diff(np.append(at, at[0] + length))
        k = int(np.argmax(gaps))
        at = np.sort(np.append(at, (at[k] + 0.5 * gaps[k]) % length))
    return _halved_long_chords(at, cum, closed, alpha), cum, closed


def _clearances(corners, angle, guard, cum, closed, alpha):
    """The arc length kept free of samples at the start and at the end of each piece
    between a ring's breaks (at arc lengths ``corners``, the region's ``angle`` there,
    their clearances ``guard``; ``cum`` the arc length at the vertices of the ``closed``
    ring): the clearances of the breaks at the piece's ends, but beside a corner of
    33.56°–60° whose other side is shorter than its clearance. That side holds no sample
    but the break p ending it, s from the corner; the first sample q on this side then
    goes where it is just alpha from p (on straight sides ℓ = s cos θ + √(alpha² −
    s² sin² θ), at least alpha), so that the corner's triangle p c q, of circumradius
    |pq| / (2 sin θ) < alpha, is one the complex keeps. With the clearance (1.58 alpha at
    37°) that triangle was too large and the corner's sample was left isolated (a
    held-out housing section: a step 0.07 alpha deep). Sharper corners are spikes
    (:func:`_ladders`).

    That q is also where it must stay: the split takes ℓ as the first part's least
    length and drew it up to √3 alpha, |pq| up to 1.24 alpha, and a 34° tip's triangle
    was again too large (a held-out gear section at a fixed alpha). So q is also
    returned, as an arc length, to be a break of its own (``pins``) where the long side
    has room beyond it for a part of at least alpha and its other end's clearance.
    Returns (after, before, pins)."""
    after, before = guard.copy(), np.roll(guard, -1)
    pins = []
    if len(corners) < 2:
        return after, before, np.array(pins)
    xy = np.column_stack([np.interp(corners, cum, closed[:, 0]),
                          np.interp(corners, cum, closed[:, 1])])
    span = np.diff(np.append(corners, corners[0] + cum[-1]))     # piece i: corner i to i + 1
    chord = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)
    reach = alpha * (1 + 1e-2)                  # |pq| from alpha by more than a rounding
    for i in np.flatnonzero((angle >= LADDER_ANGLE) & (angle < np.pi / 3)):
        cos, sin = math.cos(angle[i]), math.sin(angle[i])
        for short, long in ((i - 1, i), (i, i - 1)):      # the side before, then after
            if span[short] < guard[i]:
                s = chord[short]
                first = max(alpha, s * cos + math.sqrt(max(reach ** 2 - (s * sin) ** 2, 0.0)))
                (after if long == i else before)[long] = first
                far = (before if long == i else after)[long]     # the other end's clearance
                if span[long] >= first + max(reach, far):
                    pins.append((corners[i] + (first if long == i else -first)) % cum[-1])
    return after, before, np.array(pins)


def _halved_long_chords(at, cum, closed, alpha) -> np.ndarray:
    """The positions ``at`` with the middle of every piece added whose chord is 2 alpha or
    longer: no triangle of circumradius <= alpha has such an edge, and the sample at its
    end was left isolated. A piece too short for the clearances of the sharp corners at
    both its ends (at most 2√3 alpha: a small triangle of a section, a spike's side) is
    left whole by the split; its halves are at most √3 alpha, their ends closer than the
    clearances (an exception the certificate itemises, where a whole chord broke the
    mesh)."""
    length = cum[-1]
    ends = np.append(at, at[0] + length)
    xy = np.column_stack([np.interp(ends % length, cum, closed[:, 0]),
                          np.interp(ends % length, cum, closed[:, 1])])
    long = np.flatnonzero(np.hypot(*np.diff(xy, axis=0).T) >= 2 * alpha * (1 - 1e-9))
    if not len(long):
        return at
    return np.sort(np.append(at, (at[long] + 0.5 * np.diff(ends)[long]) % length))


def _ladders(at, corners, angle, guard, alpha, length, rng, ring=None) -> np.ndarray:
    """Boundary positions ``at`` with the samples beside each convex corner sharper than
    33.56° (a spike, whose first samples are √3 alpha from it) placed in mirror pairs,
    at equal arc length from the corner on its two sides, as far as the spike is thinner
    than alpha (alpha / (2 sin(θ/2)) from the corner on straight sides).

    Consecutive samples on one side of a spike thinner than alpha make a mesh edge only
    with a third sample at a height above their chord that the spike has no room for;
    mirror pairs make it a ladder of near isosceles trapezoids, each nearly cocircular
    with circumradius about half its diagonal, at most alpha (docs/conforming.md,
    "Spikes"). The shorter side's samples are kept and mirrored (and the break ending it,
    if the spike is still thin there and the longer side goes on for alpha or more); the
    longer side is split again beyond the last mirrored one. ``corners`` are the ring's
    breaks (sharp corners and inflections) in order, ``angle`` the region's angle at
    each, ``guard`` their clearances; ``ring`` its arc lengths at its vertices and the
    closed ring (``cum``, ``closed``), by which a ladder also stops at the first sample
    of the shorter side alpha or more from the longer side (without it, straight sides:
    the spike's own width grows as from its angle). A spike whose longer side bends away
    is alpha wide sooner: a needle's two 4-5° tips, whose shorter sides met at its blunt
    top and whose longer side was one concave arc, each mirrored all of its shorter side
    by its angle alone, the first ladder left the second no room on the arc, and the
    second tip's first samples, 3.1 and 3.5 alpha away, made a triangle too large to keep
    (held-out bracket seed 60 p3: the tip isolated at 30 of 50 alphas).

    Examples
    --------
    >>> at = np.array([0.0, 2.0, 4.0, 5.5, 7.0, 8.5, 10.2])  # a 6° tip at 0, a ring of 12
    >>> _ladders(at, np.array([0.0, 5.5]), np.radians([6.0, 90.0]), np.array([1.7, 1.0]),
    ...          1.0, 12.0, np.random.default_rng(0)).round(2).tolist()   # 2, 4, 5.5 mirrored
    [0.0, 2.0, 4.0, 5.5, 6.5, 8.0, 10.0]
    """
    if len(corners) < 2:
        return at
    reach = alpha / (2 * np.sin(np.maximum(angle, 1e-300) / 2))
    rungs = np.empty(0)                       # positions the ladders so far have mirrored
    for i in np.flatnonzero(angle < LADDER_ANGLE):
        c = corners[i]
        before, after = corners[i - 1], corners[(i + 1) % len(corners)]
        sides = ((after - c) % length or length, (c - before) % length or length)
        short = int(sides[1] < sides[0])              # 0: the side after the corner
        sign = (1.0, -1.0)[short]                     # along the short side
        offset = (sign * (at - c)) % length           # from c along the short side
        beyond = sides[1 - short] - sides[short]       # how far the long side goes on
        if sides[short] <= reach[i] and 0 < beyond < alpha:
            # the short side ends inside the spike and the long side soon after: its last
            # part ends where the long side's last one, from the mirror image, stays at
            # most √3 alpha (a chord that long has a triangle in the spike)
            lo = max(sides[short] + beyond - math.sqrt(3) * alpha, guard[i] + alpha)
            hi = sides[short] - alpha
            if lo <= hi:
                last = lo + rng.random() * (hi - lo)
                inner = np.append(_split(0.0, last, guard[i], alpha, alpha, rng), last)
                on_short = (offset > 0) & (offset < sides[short])
                at = np.sort(np.concatenate([at[~on_short], (c + sign * inner) % length]))
                offset = (sign * (at - c)) % length
        mirrored = np.sort(offset[(offset > 0) & (offset < min(reach[i], sides[short]))])
        ends_inside = sides[short] <= reach[i]
        if ring is not None:
            thin = _thinner_than(np.append(mirrored, sides[short]), c, sign, sides[1 - short],
                                 alpha, length, *ring)
            ends_inside &= thin > len(mirrored)
            mirrored = mirrored[:thin]
        if len(mirrored) and 2 * math.sin(angle[i] / 2) * mirrored.min() < RESOLUTION * alpha:
            continue                            # a needle: its sides are one line
        if ends_inside and beyond >= alpha:
            # the short side ends inside the spike: its last rung is the corner there, even
            # nearer the tip than its clearance (a fold's two 4° tips 0.6 alpha apart: the
            # tip's triangle with a far neighbour was too large to keep, the tip isolated)
            mirrored = np.append(mirrored, sides[short])
        if not len(mirrored):
            continue
        # the long side: the mirror images, then parts in [alpha, √3 alpha] to its far end,
        # or to the first rung of another spike's ladder on it (a needle with a spike at
        # each end: rewriting the side both share took the first tip's rungs away, and
        # the tip was isolated), the images then at least alpha before that rung
        far = i - 1 if short == 0 else (i + 1) % len(corners)
        along_long = (sign * (c - at)) % length
        on_long = (along_long > 0) & (along_long < sides[1 - short])
        end, last = sides[1 - short], max(guard[far], alpha)
        held = on_long.copy()
        held[on_long] = _near(at[on_long], rungs, 1e-12 * length)
        if held.any():
            end, last = along_long[held].min(), alpha
            mirrored = mirrored[mirrored <= end - alpha]
            if not len(mirrored):
                continue
            on_long &= along_long < end
        rest = _split(mirrored.max(), end, alpha, last, alpha, rng)
        images = (c - sign * mirrored) % length
        rungs = np.sort(np.concatenate([rungs, images, (c + sign * mirrored) % length]))
        at = np.sort(np.concatenate([at[~on_long], images, (c - sign * rest) % length]))
    return at


def _near(values, points, tolerance) -> np.ndarray:
    """Whether each of ``values`` lies within ``tolerance`` of one of the sorted
    ``points`` (the nearest is beside its place among them: no values x points table,
    which a star of 1,000 spikes made 40 s long).

    >>> _near(np.array([0.5, 2.0]), np.array([1.0, 2.0 + 1e-13]), 1e-12).tolist()
    [False, True]
    """
    if not len(points):
        return np.zeros(len(values), bool)
    k = np.searchsorted(points, values)
    below, above = points[np.maximum(k - 1, 0)], points[np.minimum(k, len(points) - 1)]
    return (np.abs(values - below) <= tolerance) | (np.abs(values - above) <= tolerance)


def _thinner_than(offsets, c, sign, long, alpha, length, cum, closed) -> int:
    """How many of the sorted ``offsets`` (arc lengths from the corner at ``c`` along the
    side in direction ``sign``) lie before the first that is ``alpha`` or more from the
    other side (the ring from ``c`` the other way, ``long`` long)."""
    way = (sign * (c - cum[:-1])) % length             # the vertices along the other side
    inner = np.sort(way[(way > 0) & (way < long)])
    other = along((c - sign * np.concatenate([[0.0], inner, [long]])) % length, cum, closed)
    width = shapely.distance(shapely.points(along((c + sign * offsets) % length, cum, closed)),
                             shapely.LineString(other))
    wide = np.flatnonzero(width >= alpha)
    return int(wide[0]) if len(wide) else len(offsets)


def _split(lo, hi, first, last, alpha, rng) -> np.ndarray:
    """Random inner points splitting [lo, hi] into parts of length in [alpha, √3 alpha],
    the first at least ``first`` long and the last at least ``last`` (each capped just
    below √3 alpha), where the length allows it (``split_gaps``)."""
    cap = corner_clearance(0.0, alpha)
    u = rng.random(int((hi - lo) // alpha) + 1)
    return kern.split_gaps([lo], [hi], [min(first, cap)], [min(last, cap)], [alpha],
                           math.sqrt(3) * alpha, u)[0]


class _Sampler:
    """The state of one sampling: grid of cells, cell status, samples so far."""

    def __init__(self, region: Region, alpha: float, conforming: bool = False, bounds=None):
        self.region = region
        self.alpha = alpha
        self.s = alpha / math.sqrt(2) * (1 - 1e-9)   # cell side: < alpha/√2, one sample per cell
        # the grid spans ``bounds`` when given (a tile's sampler: room for the fixed
        # samples of its halo, pds_plugin.tiled), else the region's bounding box
        xmin, ymin, xmax, ymax = region.bounds if bounds is None else bounds
        self.x0, self.y0 = xmin - 0.5 * self.s, ymin - 0.5 * self.s
        self.nx = int((xmax - self.x0) / self.s) + 2
        self.ny = int((ymax - self.y0) / self.s) + 2
        if self.nx * self.ny > _MAX_GRID_CELLS:
            raise BudgetError(
                f"the region's bounding box spans {self.nx * self.ny:.3g} grid cells at "
                f"alpha={alpha:.6g} (the limit is {_MAX_GRID_CELLS:.0e}); use a larger alpha "
                "or mesh the far-apart parts of the region separately")
        self.status = kern.classify_cells(region.segments, self.x0, self.y0, self.s,
                                          self.nx, self.ny)
        self.grid = np.full((self.ny, self.nx), -1, np.int32)
        self.covered = np.zeros((self.ny * kern.SUB, self.nx * kern.SUB), bool)
        self.head = np.full(self.ny * self.nx, -1, np.int32)     # scratch of throw_darts
        self.work = kern.Workspace()        # the kernels' scratch, reused pass after pass
        # room for the samples expected, grown as needed (_reserve)
        capacity = int(1.1 * estimate_samples(region, alpha)) + 64
        self.points = np.empty((capacity, 2))
        self.nxt = np.empty(capacity, np.int32)
        self.vis = vis_kern.no_chords(capacity)
        self.one_per_cell = not conforming
        self.rings = ()
        self.sampled_region = None          # the region through samples moved onto its arcs
        self.count = 0
        # the chords whose region darts and refinement boxes must be in: the region's
        # own rings, or (conforming) the chords between the boundary samples
        self.domain = None if conforming else domain_of_rings(region.rings, alpha)

    def _reserve(self, extra: int):
        """Room for ``extra`` more samples (a conforming sampling may need more than
        one per cell)."""
        need = self.count + extra
        if need > len(self.points):
            size = max(need, len(self.points) + len(self.points) // 4)
            self.points = np.concatenate([self.points, np.empty((size - len(self.points), 2))])
            self.nxt = np.concatenate([self.nxt, np.empty(size - len(self.nxt), np.int32)])
            out = np.full(size, -1, np.int64)
            out[:len(self.vis.out)] = self.vis.out
            self.vis = self.vis._replace(out=out)

    def _insert(self, candidates):
        self._reserve(len(candidates))
        self.count = kern.insert_where_free(np.ascontiguousarray(candidates, float), self.grid,
                                            self.nxt, self.covered, self.points, self.count,
                                            self.alpha, self.x0, self.y0, self.s, self.vis)

    def add_corners(self, feature_angle: float):
        corners, turns = [], []
        for ring in self.region.rings:
            turn = np.abs(turning_angles(ring))
            sharp = turn >= np.radians(feature_angle)
            corners.append(ring[sharp])
            turns.append(turn[sharp])
        corners, turns = np.concatenate(corners), np.concatenate(turns)
        self._insert(corners[np.argsort(-turns, kind="stable")])

    def add_boundary(self, rng):
        start, direction, length = self.region.boundary_pieces(self.s)
        order = rng.permutation(len(start))
        u = rng.random(len(start))
        self._reserve(len(start))                    # at most one sample per piece
        self.count = kern.sample_boundary_pieces(
            start, direction, length, order, u, self.grid, self.nxt, self.covered, self.points,
            self.count, self.alpha, RESOLUTION * self.alpha, self.x0, self.y0, self.s, self.vis)

    def add_conforming_boundary(self, feature_angle: float, rng, given=None) -> int:
        """Sample every ring (sharp corners, then the pieces between them; or take the
        ``given`` samples of each ring), join consecutive samples by chords, and add guard
        samples inside pieces too short to split. The chords become the boundary that
        visibility is measured through and the chord polygons the domain of the interior.
        Returns the number of boundary samples."""
        alpha = self.alpha
        ring_xy = given
        if given is None:
            apart = ((_NOISY_INFLECTION_APART, _NOISY_KINK_APART) if self.region.tolerance
                     else (_INFLECTION_APART, _INFLECTION_APART))
            ring_xy = [along(*ring_positions(ring, turning_angles(ring), feature_angle,
                                               alpha, rng, apart)) for ring in self.region.rings]
            ring_xy = boundary_rules.before_curves(ring_xy, self.region, alpha)
            ring_xy, self.sampled_region = onto_curves(    # chords stay in [1, √3) alpha
                self.region, ring_xy, alpha, LONGEST_MOVED_CHORD * alpha)
            if self.sampled_region is not None:
                ring_xy = boundary_rules.after_curves(ring_xy, self.sampled_region.rings, alpha)
        boundary, self.rings = joined(ring_xy)
        self._reserve(len(boundary))
        # the sampler asks only about points within alpha of a sample (conflicts, and
        # boxes inside a disc): chords within alpha of a cell are all it needs
        self.vis = vis_kern.chord_bundle(boundary, self.rings, len(self.points), alpha)
        kern.place_all(boundary, self.grid, self.nxt, self.covered, self.points, 0, alpha,
                       self.x0, self.y0, self.s, self.vis)
        self.count = len(boundary)
        self.domain = self.vis, vis_kern.cell_sides(self.vis)
        guards = guard_candidates(boundary, self.rings, alpha)
        self._insert(guards[vis_kern.points_inside(*self.domain, guards[:, 0], guards[:, 1])])
        return len(boundary)

    def add_interior(self, rng):
        s = self.s
        # stage 1: dart passes over the level-0 cells in random order; each dart goes to
        # a random sub-cell of its cell that no disc covers yet
        cells = np.flatnonzero(self.status.ravel())
        box_limit = _REFINEMENT_BOXES * len(cells)
        darts = np.empty((len(cells), 2))
        for _ in range(_PHASE1_PASSES):
            n_open = kern.darts_in_open_subcells(cells, rng, darts, self.grid, self.covered, self.x0,
                                                 self.y0, s, self.one_per_cell, self.work)
            cells, darts = cells[:n_open], darts[:n_open]
            self._throw(cells, darts, rng)
        # the first pass's arrays (one dart per cell) are 2-3 times the largest
        # level's: free them, so that the refinement does not add to the peak memory
        del cells, darts
        self.work = kern.Workspace()
        # stage 2: throw darts in the sub-cells no single disc covers, splitting them in
        # four at each level, until none is left
        parent, sub_x, sub_y = kern.open_subcells(self.status, self.grid, self.covered,
                                                  self.one_per_cell)
        level = int(np.log2(kern.SUB))
        while len(parent):
            size = s / 2**level
            bx, by = (self.work.array(name, len(parent), float) for name in ("bx", "by"))
            n_open = kern.open_boxes(parent, sub_x, sub_y, size, self.status, self.domain,
                                     self.grid, self.nxt, self.points, self.alpha, self.vis,
                                     self.x0, self.y0, s, bx, by, self.work)
            parent, sub_x, sub_y, bx, by = (a[:n_open] for a in (parent, sub_x, sub_y, bx, by))
            darts = rng.random(out=self.work.array("darts", 2 * n_open, float).reshape(-1, 2))
            darts *= size                   # a dart uniform in each box
            darts[:, 0] += bx
            darts[:, 1] += by
            before = self.count
            self._throw(parent, darts, rng)
            # no sample before the throw covers these boxes: only the new ones can
            children = [self.work.array(f"{name}{level % 2}", 4 * n_open, np.int64)
                        for name in ("parent", "sub_x", "sub_y")]
            n_split = kern.split_uncovered(parent, sub_x, sub_y, bx, by, size, before, self.grid,
                                           self.nxt, self.points, self.alpha, self.vis, *children,
                                           self.work)
            if size / 2 < RESOLUTION * self.alpha or (not self.one_per_cell
                                                      and n_split > box_limit):
                # (where the conservative visibility test failed over a whole area the
                # boxes would multiply by four per level, to gigabytes: the certificate
                # measures the coverage left)
                break
            level += 1
            parent, sub_x, sub_y = (a[:4 * n_split] for a in children)
            if not self.one_per_cell:
                parent, sub_x, sub_y = _uncrowded(parent, sub_x, sub_y, self.status,
                                                  self._by_a_chord(size / 2))

    def _by_a_chord(self, size):
        """A test of refinement boxes of side ``size`` (as in ``_uncrowded``): whether
        each is within its side of a chord."""
        def near(parent, sub_x, sub_y):
            x = self.x0 + (parent % self.nx) * self.s + (sub_x + 0.5) * size
            y = self.y0 + (parent // self.nx) * self.s + (sub_y + 0.5) * size
            box = np.zeros(len(parent), bool)
            box[self._chords.query(shapely.points(x, y), predicate="dwithin",
                                   distance=size)[0]] = True
            return box
        return near

    @cached_property
    def _chords(self):
        """A tree of the chords between the boundary samples (the first samples)."""
        a, b = chord_ends(self.rings)
        return shapely.STRtree(shapely.linestrings(np.stack([self.points[a], self.points[b]],
                                                            axis=1)))

    def _throw(self, cells, darts, rng):
        """Throw the darts in random order (dart k lies in level-0 cell ``cells[k]``;
        ``cells`` is sorted) and add the ones kept."""
        rank = self.work.permutation("rank", len(cells), rng)
        kept = kern.throw_darts(darts, cells, rank, self.status, self.domain, self.grid,
                                self.nxt, self.head, self.points, self.alpha, self.x0, self.y0,
                                self.s, self.vis, self.work)
        self._reserve(len(kept))
        kern.place_all(darts[kept], self.grid, self.nxt, self.covered, self.points, self.count,
                       self.alpha, self.x0, self.y0, self.s, self.vis)
        self.count += len(kept)


def _uncrowded(parent, sub_x, sub_y, status, by_a_chord=None):
    """The refinement boxes (as in ``_sampling_kernels.open_boxes``; ``parent`` sorted)
    but those of level-0 cells on the region's boundary (``status``) that hold more than
    :data:`_CROWDED_CELL` of them and lie by a chord (``by_a_chord(parent, sub_x, sub_y)``
    says which; all of them if not given).

    A conforming sampling leaves open, at each level, the boxes that no single sample
    sees whole within alpha: a few around each chord vertex, along the arcs where discs
    meet until they are inside one (many, about a thin gap between discs), along a slot
    narrower than alpha until they are narrower than it. Along a crack (a slit thinner
    than any box, whose two sides no sample sees both of) they double at every level,
    forever: such boundary cells are left as they are (the certificate measures the
    coverage there), and the refinement goes on everywhere else. Boxes away from the
    chords go on too: a sliver between discs 0.84 alpha from a plate's edge, 0.06 long
    and 2e-4 wide, took 300 boxes of its cell before the darts could land in it, and was
    left uncovered (1.0001 alpha, a held-out laser sheet at extent / 300).

    Examples
    --------
    >>> status = np.full((1, 8), kern.BOUNDARY, np.int8)
    >>> boxes = np.repeat([3, 5], [2, _CROWDED_CELL + 1]), np.zeros(259, int), np.zeros(259, int)
    >>> _uncrowded(*boxes, status)[0]
    array([3, 3])
    """
    first = np.flatnonzero(np.diff(parent, prepend=-1))
    counts = np.diff(first, append=len(parent))
    crowded = (counts > _CROWDED_CELL) & (status.ravel()[parent[first]] == kern.BOUNDARY)
    if not crowded.any():
        return parent, sub_x, sub_y
    drop = np.repeat(crowded, counts)
    if by_a_chord is not None:
        drop[drop] = by_a_chord(parent[drop], sub_x[drop], sub_y[drop])
    return parent[~drop], sub_x[~drop], sub_y[~drop]
