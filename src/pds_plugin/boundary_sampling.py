"""The boundary stage the uniform and graded samplers share (:mod:`.sampling`,
:mod:`.graded_sampling`; :mod:`.partition` for chains shared by regions), and the chords
their complexes are constrained by (:mod:`.complex`, :mod:`.graded_complex`).

- :func:`given_boundary`: boundary samples given by the caller, checked;
- :func:`along`: the points at positions along a ring (arc length, or τ = ∫ dt / r);
- :func:`onto_curves`: boundary samples moved onto a drawing's exact arcs;
- :func:`vertex_chords`: the chord each ring vertex lies under; :func:`hidden_bends`:
  the reflex vertices that hide part of a ring beyond its chords; :func:`star_shaped_from`:
  whether a polygon is seen whole from a point (the samplers' and the certificate's test);
- :func:`joined`: the samples of every ring in one array, each ring's indices, the
  rings the chords join; :func:`chord_ends`: each chord's two ends;
- :func:`guard_candidates`: guard samples inside chords too long to split, in the order
  to try them (docs/conforming.md, "Why consecutive boundary samples are mesh edges");
- :func:`domain_of_rings`: the chords of polygon rings and their cells, for the exact
  in/out tests of the paper's (not conforming) sampler;
- :func:`chord_reach` and :func:`graded_chords`: the chords of a graded sampling, each
  binned within the reach a kept triangle's edge can have from it: one rule for the
  graded sampler and the graded complex; :func:`graded_domain`: the same chords binned
  where they pass, for the graded sampler's exact in/out tests.

The chords travel as :class:`~pds_plugin._visibility_kernels.ChordBundle`\\ s.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from . import _graded_kernels as graded_kern
from . import _visibility_kernels as vis_kern
from .boundary_curves import samples_onto_curves
from .errors import ArgumentError, RegionError
from .region import Region

__all__ = ["RESOLUTION", "given_boundary", "along", "onto_curves", "joined", "chord_ends",
           "guard_candidates", "domain_of_rings", "chord_reach", "graded_chords",
           "graded_domain",
           "vertex_chords", "hidden_bends", "star_shaped_from"]

RESOLUTION = 1e-10
"""The smallest refinement box and boundary margin of both samplers, relative to the
radius (alpha, or r where the box is)."""

_GUARD_SPREAD = (0.5, -0.5, 1.0, -1.0, 0.25, -0.25, 0.75, -0.75)  # other guard heights, / t_c
_GUARD_MARGIN = 1e-9     # guards stay this much (/ t_c) inside the heights of circumradius alpha
_CAP_SLACK = 0.03        # a corner guard's disc holds the open cap's sampled arcs by this much (/ alpha)
_MAX_CHORD_ENTRIES = 1_000_000  # cells listed for all chords of a graded sampling, at most
_CHORD_CELLS = 32            # cells of the chord grid a chord is listed in, on average, at most


def given_boundary(region: Region, boundary_samples, conforming: bool) -> list:
    """``boundary_samples`` as one (k, 2) float array per ring of ``region``, checked
    (``conforming`` must be true: only a conforming sampling takes them).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> square = Region.from_shapely(box(0, 0, 1, 1))
    >>> [ring.shape for ring in given_boundary(square, [[(0, 0), (1, 0), (1, 1)]], True)]
    [(3, 2)]
    """
    if not conforming:
        raise ArgumentError("boundary_samples apply to conforming samplings; pass conforming=True")
    rings = [np.asarray(ring, dtype=float).reshape(-1, 2) for ring in boundary_samples]
    if len(rings) != len(region.rings) or any(len(ring) < 3 for ring in rings):
        raise ArgumentError(f"boundary_samples must give at least 3 samples for each of the "
                            f"region's {len(region.rings)} rings, got "
                            f"{[len(ring) for ring in rings]}")
    return rings


def along(at, cum, closed) -> np.ndarray:
    """The points at arc positions ``at`` of a closed polyline ``closed`` whose vertices
    are at positions ``cum`` (arc length, or any increasing measure along it).

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], float)
    >>> along([0.5, 1.5, 3.75], np.arange(5.0), square).tolist()
    [[0.5, 0.0], [1.0, 0.5], [0.0, 0.25]]
    """
    return np.column_stack([np.interp(at, cum, closed[:, 0]), np.interp(at, cum, closed[:, 1])])


def onto_curves(region: Region, ring_xy, lower, upper):
    """The boundary samples moved onto the region's exact arcs, and the region through
    them (:func:`pds_plugin.boundary_curves.samples_onto_curves`); the samples as they
    are and None for a region without curves, with a tolerance pass (its boundary is not
    the curves'), or where the refined region would not be valid."""
    if region.curves is None or region.tolerance != 0:
        return ring_xy, None
    moved, geometry = samples_onto_curves(region.curves, region.rings, region.ring_owners,
                                          ring_xy, lower, upper)
    if geometry is None:
        return ring_xy, None
    try:
        return moved, Region.from_shapely(geometry, region.frame, curves=region.curves)
    except RegionError:
        return ring_xy, None


def joined(ring_xy):
    """The boundary samples of every ring in one array, and each ring's indices in it.

    Examples
    --------
    >>> points, rings = joined([np.zeros((3, 2)), np.ones((4, 2))])
    >>> len(points), [ring.tolist() for ring in rings]
    (7, [[0, 1, 2], [3, 4, 5, 6]])
    """
    sizes = [len(xy) for xy in ring_xy]
    ends = np.cumsum(sizes)
    return np.concatenate(ring_xy), tuple(np.arange(e - k, e) for e, k in zip(ends, sizes))


def vertex_chords(samples, ring):
    """For a ring's boundary ``samples`` (on ``ring``, in order along it): each vertex's
    chord (the one from sample k to sample k + 1 is k), the vertex's arc length from that
    chord's first end, and each chord's arc length.

    Examples
    --------
    >>> square = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> chord, offset, span = vertex_chords(np.array([[1, 0], [2, 1], [0, 1]]), square)
    >>> chord.tolist(), offset.tolist(), span.tolist()
    ([2, 0, 1, 1], [1.0, 1.0, 1.0, 3.0], [2.0, 4.0, 2.0])
    """
    n = len(samples)
    closed = np.vstack([ring, ring[:1]])
    vertex_at = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed, axis=0).T))])
    length, vertex_at = vertex_at[-1], vertex_at[:-1]
    sample_at = shapely.line_locate_point(shapely.LineString(closed),
                                          shapely.points(samples)) % length
    start = int(np.argmin(sample_at))
    chord = (np.searchsorted(np.roll(sample_at, -start), vertex_at, side="right") - 1
             + start) % n
    span = (np.roll(sample_at, -1) - sample_at) % length
    return chord, (vertex_at - sample_at[chord]) % length, span


def hidden_bends(samples, ring, turns, tol):
    """Where a ring's chords hide part of it: for each chord of ``samples`` (in order along
    ``ring``; ``turns`` the turning angles at its vertices) whose arc reaches beyond the
    chord, the first and the last reflex vertex w of the arc. The ring turns back into
    the region at w, so the chord end e before w does not see the ring just past w,
    beyond the chord: only the far end f does (docs/graded.md, "Coverage behind a reflex
    vertex"). Vertices within ``tol`` of a chord or its ends count as on it.

    Returns None where nothing is hidden (a ring that turns one way only never is),
    else ``(bends, chord, reflex, beyond)``: ``bends`` the tuples (arc length from e to
    w, e, f, w, arc length to w from the chord's first end), shortest first; ``chord``
    each vertex's chord (:func:`vertex_chords`), ``reflex`` the reflex vertices off the
    chord ends, ``beyond`` per chord whether its arc reaches beyond it.

    Examples
    --------
    >>> from .region import turning_angles
    >>> ring = np.array([[0, 0], [4, 0], [4, 1], [2, 1], [1.5, 1.1], [1, 1.15], [0, 1]])
    >>> samples = np.array([[0, 0], [4, 0], [4, 1], [2.05, 1], [0, 1]])
    >>> bends = hidden_bends(samples, ring, turning_angles(ring), 1e-9)[0]
    >>> [(int(e), int(f), int(w)) for _, e, f, w, _ in bends]   # (2, 1) from either end
    [(3, 4, 3), (4, 3, 3)]
    """
    if not ((turns < 0).any() and (turns > 0).any()):
        return None             # an arc that turns one way only stays on one side of its chord
    n = len(samples)
    chord, offset, span = vertex_chords(samples, ring)
    a, b = samples[chord], samples[(chord + 1) % n]
    apart = (np.hypot(*(ring - a).T) > tol) & (np.hypot(*(ring - b).T) > tol)
    height = (b[:, 0] - a[:, 0]) * (ring[:, 1] - a[:, 1]) \
        - (b[:, 1] - a[:, 1]) * (ring[:, 0] - a[:, 0])
    beyond = np.bincount(chord, apart & (height < -tol * np.hypot(*(b - a).T)), minlength=n) > 0
    reflex = np.flatnonzero(apart & (turns < 0))
    vertex = reflex[beyond[chord[reflex]]]
    if not len(vertex):
        return None
    vertex = vertex[np.lexsort((offset[vertex], chord[vertex]))]
    k, along = chord[vertex], offset[vertex]
    first = np.append(True, k[1:] != k[:-1])
    last = np.append(k[1:] != k[:-1], True)
    bends = [(along[i], k[i], (k[i] + 1) % n, vertex[i], along[i]) for i in np.flatnonzero(first)]
    bends += [(span[k[i]] - along[i], (k[i] + 1) % n, k[i], vertex[i], along[i])
              for i in np.flatnonzero(last)]
    return sorted(bends, key=lambda bend: bend[0]), chord, reflex, beyond


def star_shaped_from(piece: np.ndarray, point: np.ndarray, tol: float) -> bool:
    """Whether every point of the simple polygon ``piece`` (its vertices in order, either
    orientation) sees ``point`` inside it: ``point`` lies on the inner side of every
    edge's line (the polygon's kernel), up to ``tol``; edges shorter than ``tol`` (a vertex
    repeated, as where a cut meets the chord at an arc vertex on it) are left out.

    Examples
    --------
    >>> kinked = np.array([[0, 0], [4, 0], [4, 2], [2, 1.8], [0, 2]], float)
    >>> [star_shaped_from(kinked, kinked[k], 1e-12) for k in range(3)]   # (0, 2) hides behind the kink from (4, 2)
    [True, True, False]
    >>> notch = np.array([[0, 0], [4, 0], [4, 2], [2, 0.2], [0, 2]], float)
    >>> star_shaped_from(notch, notch[4], 1e-12)
    False
    """
    edges = np.roll(piece, -1, axis=0) - piece
    doubled = float((piece[:, 0] * np.roll(piece[:, 1], -1) - piece[:, 1] * np.roll(piece[:, 0], -1)).sum())
    to_point = point - piece
    side = (edges[:, 0] * to_point[:, 1] - edges[:, 1] * to_point[:, 0]) * np.sign(doubled)
    length = np.hypot(edges[:, 0], edges[:, 1])
    return bool(((side >= -tol * length) | (length <= tol)).all())   # a repeated vertex bounds nothing


def chord_ends(rings):
    """The first and second end (indices) of every chord of ``rings``, ring after ring:
    chord k joins ``a[k]`` to ``b[k]``, the next sample of its ring.

    Examples
    --------
    >>> a, b = chord_ends([np.arange(3), np.arange(3, 7)])
    >>> a.tolist(), b.tolist()
    ([0, 1, 2, 3, 4, 5, 6], [1, 2, 0, 4, 5, 6, 3])
    """
    a = np.concatenate(rings)
    sizes = np.array([len(ring) for ring in rings], dtype=np.int64)
    ends = np.cumsum(sizes)[sizes > 0]
    following = np.arange(1, len(a) + 1)
    following[ends - 1] = ends - sizes[sizes > 0]       # each ring's last to its first
    return a, a[following]


def guard_candidates(boundary, rings, alpha) -> np.ndarray:
    """Guard candidates inside each chord longer than √3 alpha (a piece that cannot be
    split into parts in [alpha, √3 alpha]), in the order to try them: first, for every
    such chord, the point on its bisector at height alpha, where the triangle of the
    chord and the guard has circumradius (alpha² + g²/4) / (2 alpha) <= alpha and angles
    in [45°, 90°]; then, for the chords whose first guard an earlier sample blocks,
    heights alpha ± f·t_c (f in ``_GUARD_SPREAD``, t_c = sqrt(alpha² - g²/4)), all of
    which keep the circumradius <= alpha and the chord an edge (docs/conforming.md,
    "Why consecutive boundary samples are mesh edges"). The candidates of one chord are
    less than alpha apart, so at most one becomes a sample. Before them all come the
    corner guards of :func:`_corner_guards`. ``alpha`` may be a radius field (a callable
    on points), taken at the chord's middle (graded samplings).

    Examples
    --------
    >>> plate = np.array([[0, 0], [1.9, 0], [1.9, 1.6], [1.9, 3.2], [0, 3.2], [0, 1.6]])
    >>> candidates = guard_candidates(plate, [np.arange(6)], 1.0)       # the chords of 1.9 are too long
    >>> len(candidates) == 2 * (1 + len(_GUARD_SPREAD)), candidates[0].round(3).tolist()
    (True, [0.95, 1.0])
    >>> square = np.array([[0, 0], [1.9, 0], [1.9, 1.9], [0, 1.9]])
    >>> guard_candidates(square, [np.arange(4)], 1.0)[0].round(3).tolist()   # a corner guard first
    [1.193, 0.707]
    """
    a, b = chord_ends(rings)
    p, q = boundary[a], boundary[b]
    chord = q - p
    g = np.hypot(chord[:, 0], chord[:, 1])
    alpha = np.broadcast_to(alpha(0.5 * (p + q)) if callable(alpha) else alpha, g.shape)
    long = g > math.sqrt(3) * alpha
    inward = np.column_stack([-chord[:, 1], chord[:, 0]]) / np.maximum(g, 1e-300)[:, None]
    first = boundary[a] + 0.5 * chord + alpha[:, None] * inward        # height alpha
    corner = _corner_guards(boundary, rings, a, b, long, first, inward, alpha)
    return np.ascontiguousarray(np.concatenate(
        [corner, bisector_guards(p[long], q[long], alpha[long]).reshape(-1, 2)]))


def bisector_guards(p, q, alpha) -> np.ndarray:
    """The guard candidates of chords p -> q (longer than √3 alpha) on their bisectors,
    in the order :func:`guard_candidates` tries them: (levels, chords, 2), level 0 at
    height alpha, the others at alpha ± f·t_c (f in ``_GUARD_SPREAD``)."""
    chord = q - p
    g = np.hypot(chord[:, 0], chord[:, 1])
    inward = np.column_stack([-chord[:, 1], chord[:, 0]]) / np.maximum(g, 1e-300)[:, None]
    spread = np.sqrt(np.maximum(alpha ** 2 - g ** 2 / 4, 0.0)) * (1 - _GUARD_MARGIN)
    height = alpha + np.multiply.outer((0.0, *_GUARD_SPREAD), spread)    # (levels, chords)
    return 0.5 * (p + q) + height[..., None] * inward


def _corner_guards(boundary, rings, a, b, long, first, inward, alpha) -> np.ndarray:
    """One guard for two long chords p -> q -> r that meet at a corner q where their
    guards at height alpha would be less than alpha apart (one would block the other, and
    no height on the blocked chord's bisector is free of it).

    The guard G is the first point, near the corner's bisector at alpha to 1.5 alpha from
    q, that makes triangles of circumradius <= alpha with both chords, lies at least alpha
    from p, q and r, and covers with its disc, for each chord, the part of the cap of the
    lower circle of circumradius alpha that the discs of the chord's ends leave open
    (:func:`_open_cap`): the conditions under which a chord with a guard is a mesh edge
    (docs/conforming.md, "Why consecutive boundary samples are mesh edges")."""
    following = np.arange(len(a)) + 1
    ends = np.cumsum([len(ring) for ring in rings])
    following[ends - 1] = ends - np.array([len(ring) for ring in rings])
    k = np.flatnonzero(long & long[following])
    n = following[k]
    radius = np.minimum(alpha[k], alpha[n])
    close = np.hypot(*(first[k] - first[n]).T) < radius
    guards = []
    for before, pivot, after, h, (u, v) in zip(boundary[a[k[close]]], boundary[b[k[close]]],
                                                boundary[b[n[close]]], radius[close],
                                                zip(inward[k[close]], inward[n[close]])):
        bisector = u + v
        if np.hypot(*bisector) < 1e-9:
            continue
        heading = math.atan2(bisector[1], bisector[0])
        turn = np.radians([0, 10, -10, 20, -20, 30, -30])
        reach = h * np.array([1.0, 1.1, 1.2, 1.3, 1.4, 1.5]) * (1 + _GUARD_MARGIN)
        angles, distances = (x.ravel() for x in np.meshgrid(heading + turn, reach))
        candidates = pivot + distances[:, None] * np.column_stack([np.cos(angles), np.sin(angles)])
        count = len(candidates)
        fits = ((_circumradius(np.broadcast_to(before, (count, 2)), np.broadcast_to(pivot, (count, 2)),
                               candidates) <= h * (1 - _GUARD_MARGIN))
                & (_circumradius(np.broadcast_to(pivot, (count, 2)), np.broadcast_to(after, (count, 2)),
                                 candidates) <= h * (1 - _GUARD_MARGIN))
                & (np.hypot(*(candidates - before).T) >= h)
                & (np.hypot(*(candidates - after).T) >= h))
        cap = np.concatenate([_open_cap(before, pivot, h), _open_cap(pivot, after, h)])
        fits &= (np.hypot(candidates[:, None, 0] - cap[None, :, 0],
                          candidates[:, None, 1] - cap[None, :, 1]) <= h * (1 - _CAP_SLACK)).all(axis=1)
        if fits.any():
            guards.append(candidates[np.argmax(fits)])
    return np.array(guards).reshape(-1, 2)


def _open_cap(p, q, alpha, count=16) -> np.ndarray:
    """Points along the boundary of the part of the inner cap of the circle of radius
    alpha through p and q with its centre t_c = sqrt(alpha² - g²/4) outside the chord
    that B(p, alpha) ∪ B(q, alpha) leaves open: arcs of the circles about p, about that
    centre and about q, from (0, t_c) over the cap's top and back (chord coordinates,
    the region to the left of p -> q). A guard whose disc holds it keeps the chord an
    edge; ``count`` points per arc, their spacing under alpha / 40 for g in (√3α, 2α).

    Examples
    --------
    >>> points = _open_cap(np.array([0.0, 0.0]), np.array([1.9, 0.0]), 1.0)
    >>> bool(np.all(points[:, 1] > 0)), round(float(points[:, 1].max()), 3)   # top: 1 - t_c
    (True, 0.688)
    """
    chord = q - p
    g = math.hypot(*chord)
    along, inward = chord / g, np.array([-chord[1], chord[0]]) / g
    t = math.sqrt(max(alpha ** 2 - g ** 2 / 4, 0.0))
    low = np.array([0.0, -t])
    ends = {"p": np.array([-g / 2, 0.0]), "q": np.array([g / 2, 0.0])}
    top = np.array([0.0, t])                                   # where the end circles meet
    corner = np.array([-g / 4 + math.sqrt(3) / 2 * t, -t / 2 + math.sqrt(3) / 4 * g])

    def arc(centre, start, stop):
        first, last = (math.atan2(*(point - centre)[::-1]) for point in (start, stop))
        angle = np.linspace(first, last, count)
        return centre + alpha * np.column_stack([np.cos(angle), np.sin(angle)])

    mirror = corner * np.array([-1.0, 1.0])
    local = np.concatenate([arc(ends["p"], top, corner), arc(low, corner, mirror),
                            arc(ends["q"], mirror, top)])
    return (p + q) / 2 + local[:, :1] * along + local[:, 1:] * inward


def _circumradius(u, v, w) -> np.ndarray:
    """Circumradius of each triangle (u, v, w) of (n, 2) points (infinite if flat)."""
    uv, vw, wu = (np.hypot(*(y - x).T) for x, y in ((u, v), (v, w), (w, u)))
    twice_area = np.abs((v - u)[:, 0] * (w - u)[:, 1] - (v - u)[:, 1] * (w - u)[:, 0])
    with np.errstate(divide="ignore"):
        return uv * vw * wu / (2 * twice_area)


def domain_of_rings(rings, alpha: float) -> tuple:
    """The chord bundle of polygon ``rings`` (each a (k, 2) array with the region on its
    left) and its cell sides: the arguments of the exact in/out tests
    ``_visibility_kernels.points_inside`` and ``boxes_state``.

    The cells are at least alpha/2 wide, and wider where the rings have few segments
    for the area (a square gets a handful of cells, not one per alpha).

    Examples
    --------
    >>> from shapely.geometry import box
    >>> from pds_plugin import _visibility_kernels as vis_kern
    >>> square = Region.from_shapely(box(0, 0, 1, 1))
    >>> domain = domain_of_rings(square.rings, 0.01)
    >>> vis_kern.points_inside(*domain, [0.5, 1.0, 2.0], [0.5, 0.5, 0.5])
    array([ True, False, False])
    """
    points, indices = joined(rings)
    (xmin, ymin), (xmax, ymax) = points.min(axis=0), points.max(axis=0)
    cell = max(alpha / 2, math.sqrt((xmax - xmin) * (ymax - ymin) / (4 * len(points))))
    vis = vis_kern.chord_bundle(points, indices, len(points), 2 * cell)   # cells of side reach/2
    return vis, vis_kern.cell_sides(vis)


def chord_reach(points, rings, radius, grading: float) -> np.ndarray:
    """How far from each chord of ``rings`` an edge of a triangle a graded complex keeps
    can reach: a segment of a triangle kept at circumcentre z has length
    <= 2 r(z) / (1 - L) from any chord point it meets, with r there at most the chord's
    larger end radius plus L times half its length (``radius``: r at the ``points``).

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> chord_reach(square, [np.arange(4)], np.full(4, 0.4), 0.2).round(6).tolist()  # 2 (0.4 + 0.1) / 0.8
    [1.25, 1.25, 1.25, 1.25]
    """
    a, b = chord_ends(rings)
    length = np.hypot(*(points[b] - points[a]).T)
    return (2.0 * (np.maximum(radius[a], radius[b]) + 0.5 * grading * length)
            / (1.0 - grading) * (1 + 1e-9))


def graded_chords(points, rings, reach, n_points: int, x0: float, y0: float, width: float,
                  height: float, smallest_cell: float):
    """The chords along ``rings`` binned for a graded sampling or complex: each chord
    listed in the cells within its ``reach`` (:func:`chord_reach`).

    Parameters
    ----------
    points : (N, 2) float ndarray
        The samples the rings index.
    rings : sequence of (k,) int ndarray
        Each ring's samples in order, the region on the left (at least one ring).
    reach : (m,) float ndarray
        Each chord's reach, chord by chord as :func:`chord_ends` orders them.
    n_points : int
        The length of the bundle's ``out`` (the sampler's room for samples).
    x0, y0, width, height : float
        The chord grid's lower left corner and extent.
    smallest_cell : float
        Its cells are at least this wide, and wide enough that a chord is listed in
        about 32 cells on average (a million entries in all at most).

    Returns
    -------
    ChordBundle
        Its grid from (x0, y0) over width x height.

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> reach = chord_reach(square, [np.arange(4)], np.full(4, 0.4), 0.2)
    >>> vis = graded_chords(square, [np.arange(4)], reach, 4, -1.5, -1.5, 4.0, 4.0, 0.1)
    >>> len(vis.xy), vis.out.tolist(), vis.nx * vis.ny + 1 == len(vis.start)
    (4, [0, 1, 2, 3], True)
    """
    xy, prev, out = _ring_chords(points, rings, n_points)
    length = np.hypot(*(xy[:, 1] - xy[:, 0]).T)
    entries = np.sum((length + 2 * reach) ** 2)
    h = max(smallest_cell, math.sqrt(entries / min(_MAX_CHORD_ENTRIES,
                                                   _CHORD_CELLS * len(length))))
    nx, ny = int(width / h) + 1, int(height / h) + 1
    start, items = graded_kern.bin_chords_by_reach(xy, reach, x0, y0, h, nx, ny)
    return vis_kern.ChordBundle(xy, prev, out, start, items, x0, y0, h, nx, ny)


def graded_domain(points, rings, n_points: int, x0: float, y0: float, width: float,
                  height: float, smallest_cell: float) -> tuple:
    """The arguments of the exact in/out tests (``_visibility_kernels.points_inside`` and
    ``boxes_state``) of a graded sampling: its chords (:func:`graded_chords`'s bundle)
    each listed only in the cells near it (a reach of half a cell), and the cells'
    sides. The visibility tests' bundle lists each chord within its reach, some 36
    cells, where these tests look for the few that cross a box or a ray. The half cell
    lists a chord that lies on the line between two cells in both of them (with no
    reach, rounding listed it in one, and the sweep of ``cell_sides`` missed its
    crossings).

    Examples
    --------
    >>> from pds_plugin import _visibility_kernels as vis_kern
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> domain = graded_domain(square, [np.arange(4)], 4, -0.5, -0.5, 2.0, 2.0, 0.25)
    >>> vis_kern.points_inside(*domain, [0.5, 1.0, 2.0], [0.5, 0.5, 0.5])
    array([ True, False, False])
    """
    count = sum(len(ring) for ring in rings)
    chords = graded_chords(points, rings, np.full(count, 0.5 * smallest_cell), n_points, x0,
                           y0, width, height, smallest_cell)
    return chords, vis_kern.cell_sides(chords)


def _ring_chords(points, rings, n_points: int):
    """The chords of ``rings`` as :func:`._visibility_kernels.chord_bundle` lists them,
    without its grid (:func:`graded_chords` bins them by reach instead): their ends
    (m, 2, 2), the chord before each along its ring, and each sample's outgoing chord
    (-1 for the ``n_points`` entries no ring holds). All rings at once."""
    a = np.concatenate(rings).astype(np.int64, copy=False)
    counts = np.array([len(ring) for ring in rings], np.int64)
    begin = np.cumsum(counts) - counts
    following = np.arange(1, len(a) + 1)
    following[begin + counts - 1] = begin
    prev = np.arange(-1, len(a) - 1)
    prev[begin] = begin + counts - 1
    out = np.full(n_points, -1, np.int64)
    out[a] = np.arange(len(a))
    xy = np.ascontiguousarray(np.stack([points[a], points[a[following]]], axis=1), float)
    return xy, prev, out
