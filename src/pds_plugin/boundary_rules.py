"""The rules the uniform conforming sampler applies to each ring's boundary samples
before it joins them by chords (docs/conforming.md, "Construction" and "Fixed alphas"):
the chords must not hide part of the ring from both their ends, cross another ring, be
blocked by a sample in their lens, or need a guard that every sample across blocks.

- :func:`before_curves`: the rules on the samples placed along the rings
  (:func:`.sampling.ring_positions`), in order: what the chords hide
  (:func:`_unhidden`, :func:`_lobes_split`), chords across other rings
  (:func:`_clear_of_other_rings`), samples in lenses (:func:`_rungs_across_walls`),
  chords no guard can keep (:func:`_guards_halved`);
- :func:`after_curves`: what the chords hide and lenses again, after samples moved onto a
  drawing's exact curves (:func:`.boundary_sampling.onto_curves`).

Each rule only adds samples (on the ring, so on its curves too where the ring's vertices
are) or moves one onto a ring vertex; a pair it leaves closer than alpha is an itemised
small-feature exception of the certificate.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from .boundary_sampling import (RESOLUTION, bisector_guards, chord_ends, hidden_bends, joined,
                                star_shaped_from, vertex_chords)
from .region import Region, turning_angles

__all__ = ["before_curves", "after_curves", "LONGEST_CHORD", "LONGEST_MOVED_CHORD"]

LONGEST_CHORD = math.sqrt(3) * (1 - 1e-6)
"""The longest chord the uniform sampler makes, / alpha: first parts beside sharp corners
stay this much below √3 alpha."""

LONGEST_MOVED_CHORD = math.sqrt(3) * (1 - 1e-9)
"""The longest chord, / alpha, that moving a sample onto its exact curve may make: the
move may use the room LONGEST_CHORD leaves below √3 alpha. Beside a corner where a line
meets an arc the move is tiny (the flattened arc meets the arc there), but it lengthened
a first chord made at LONGEST_CHORD alpha, and was undone: the sample stayed on the
flattened arc, 1.6e-7 of the radius off the exact curve (a held-out STEP knob)."""


def before_curves(ring_xy, region: Region, alpha: float) -> list:
    """Each ring's boundary samples (``ring_xy``, in order along ``region.rings``) with
    the rules of this module applied.

    Examples
    --------
    >>> plate = Region.from_shapely(shapely.box(0, 0, 4, 1.3).difference(
    ...     shapely.box(1, 0.3, 3, 1)))                              # walls 0.3 thin
    >>> xy = [np.array([[0, 0], [1.6, 0], [3.2, 0], [4, 0], [4, 1.3], [2, 1.3], [0, 1.3]]),
    ...       np.array([[1, 0.3], [1, 1], [3, 1], [3, 0.3]])]
    >>> [len(samples) for samples in before_curves(xy, plate, 1.0)]   # rungs across the walls
    [10, 6]
    """
    rings = region.rings
    turns = [turning_angles(ring) for ring in rings]
    ring_xy = [_clear_of_own_ring(_seen(xy, ring, turn, alpha), ring, turn)
               for xy, ring, turn in zip(ring_xy, rings, turns)]
    ring_xy = _clear_of_other_rings(ring_xy, rings)
    ring_xy = _rungs_across_walls(ring_xy, rings, alpha)
    return _guards_halved(ring_xy, region, alpha)


def after_curves(ring_xy, rings, alpha: float) -> list:
    """Each ring's boundary samples, moved onto exact curves, with what their chords hide
    sampled and the samples across walls in lenses given rungs again, on ``rings``, the
    region through the moved samples."""
    return _rungs_across_walls([_seen(xy, ring, turning_angles(ring), alpha)
                                for xy, ring in zip(ring_xy, rings)], rings, alpha)


def _seen(samples, ring, turns, alpha) -> np.ndarray:
    """A ring's boundary samples (``turns`` the ring's turning angles) with what hides
    part of the ring beyond a chord from the chord's ends sampled (:func:`_unhidden`,
    :func:`_lobes_split`)."""
    return _lobes_split(_unhidden(samples, ring, turns, alpha), ring, turns, alpha)


def _unhidden(samples, ring, turns, alpha, passes=3) -> np.ndarray:
    """A ring's boundary samples (in order along ``ring``, ``turns`` the turning angles
    at its vertices) with each reflex vertex w sampled that hides part of the ring beyond
    a chord from the chord end e before it, where the far end f, the only one that sees
    it, is farther than alpha from w (:func:`.boundary_sampling.hidden_bends`).

    Where w is at least 0.3 alpha from e and f it is added as a sample of its own (a pair
    closer than alpha, itemised as a small-ring exception): moving e that far would take
    the chords beside it out of [alpha, √3 alpha]. On a held-out torus section e was 0.42
    alpha before a 1.8° reflex vertex and f 1.025 alpha from it: the wedge past w was
    uncovered. Nearer to e, e moves onto w or further along the run of reflex vertices
    that w starts (:func:`_move_along_run`): on MIL.svg at alpha = extent / 150 a sample
    on a fillet was 0.007 alpha before the fillet's last vertex, and 1.09 alpha of the
    straight side past it, beyond the chord, was seen from no sample; on a gentle concave
    stretch the run's vertices were 0.17 alpha apart, each hiding the next. Where e
    cannot move, the arc's reflex vertex nearest e but 0.3 alpha from it is added
    instead (an S-bend of MIL.svg at extent / 60). Each added sample makes new chords,
    so the search is repeated (``passes``).

    Examples
    --------
    >>> ring = np.array([[0, 0], [4, 0], [4, 1], [2, 1], [1.5, 1.1], [1, 1.15], [0, 1]])
    >>> samples = np.array([[0, 0], [1.5, 0], [3, 0], [4, 0], [4, 1], [3.3, 1], [2.05, 1], [0, 1]])
    >>> _unhidden(samples, ring, turning_angles(ring), 1.0)[6].tolist()   # onto (2, 1)
    [2.0, 1.0]
    """
    for _ in range(passes):
        found = hidden_bends(samples, ring, turns, 1e-9 * alpha)
        if found is None:
            return samples
        bends, chord_of, reflex, _ = found
        samples, n, added, moved = samples.copy(), len(samples), {}, False
        for _, end, other, w, _ in bends:
            e, f = samples[end], samples[other]
            if np.hypot(*(ring[w] - f)) <= alpha:
                continue
            chord = end if other == (end + 1) % n else other
            if np.hypot(*(ring[w] - e)) < 0.3 * alpha:
                run, after = _reflex_run(samples, end, other, w, ring, turns, chord_of)
                moved_to = _move_along_run(samples, end, other, run, ring, turns, alpha)
                if moved_to is not None:
                    samples[end], moved = ring[moved_to], True
                    continue
                # e cannot move: the reflex vertex of the arc nearest e but 0.3 alpha away,
                # or the vertex ending the run, where the ring turns back beyond the chord
                near = np.union1d(reflex[chord_of[reflex] == chord], after)
                away = np.hypot(*(ring[near] - e).T)
                near, away = near[away >= 0.3 * alpha], away[away >= 0.3 * alpha]
                if not len(near):
                    continue
                w = near[np.argmin(away)]
            if np.hypot(*(ring[w] - f)) >= 0.3 * alpha:
                added.setdefault(chord, set()).add(w)
        if not (added or moved):
            return samples
        rows = []
        for k in range(n):
            rows.append(samples[k:k + 1])
            if k in added:
                rows.append(ring[sorted(added[k], key=lambda w: np.hypot(*(ring[w] - samples[k])))])
        samples = np.concatenate(rows)
    return samples


def _lobes_split(samples, ring, turns, alpha, passes=3) -> np.ndarray:
    """A ring's boundary samples (in order along ``ring``, ``turns`` the turning angles at
    its vertices) with a sample added to every chord whose arc lies all beyond it, bends
    both ways, and is not seen whole within alpha from a chord end: the arc's vertex
    farthest beyond the chord.

    The region beyond such a chord, a lobe, is covered only by the samples that see it;
    where its boundary bends back (a reflex vertex) an end may see only part of it. On
    MIL.svg at alpha = extent / 30 a letter's lobe 1.5 alpha round with an S-bend was
    seen whole from neither end ("not all seen from one of them"); at extent / 20 a tab
    behind a scoop was seen whole only from the end 1.23 alpha from its corner. The
    sample on its tip cuts it in two, each seen from the ends of its chord.

    Examples
    --------
    >>> ring = np.array([[0, -1], [1, -1], [1, 0], [1.5, 0.5], [1.2, 1.2], [0.5, 0.3],
    ...                  [-0.2, 1.2], [-0.5, 0.5], [0, 0]], float)   # two lobes on a neck
    >>> samples = ring[[0, 1, 2, 8]]
    >>> _lobes_split(samples, ring, turning_angles(ring), 1.0)[3].tolist()
    [1.2, 1.2]
    """
    tol = 1e-9 * alpha
    if not ((turns < 0).any() and (turns > 0).any()):
        return samples                          # a lobe bends both ways
    for _ in range(passes):
        n = len(samples)
        chord, offset, _ = vertex_chords(samples, ring)
        a, b = samples[chord], samples[(chord + 1) % n]
        height = ((b[:, 0] - a[:, 0]) * (ring[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (ring[:, 0] - a[:, 0])) / np.maximum(
                      np.hypot(*(b - a).T), 1e-300)
        off_ends = (np.hypot(*(ring - a).T) > tol) & (np.hypot(*(ring - b).T) > tol)

        def count(mask):
            return np.bincount(chord[off_ends & mask], minlength=n)
        lobes = np.flatnonzero((count(height < -tol) > 0) & (count(height > tol) == 0)
                               & (count(turns < 0) > 0) & (count(turns > 0) > 0))
        added = {}
        for k in lobes:
            on = np.flatnonzero((chord == k) & off_ends)
            on = on[np.argsort(offset[on])]
            piece = np.vstack([samples[k], ring[on], samples[(k + 1) % n]])
            seers = [end for end in (piece[0], piece[-1]) if star_shaped_from(piece, end, tol)]
            if not seers or np.min([np.hypot(*(piece - end).T) for end in seers],
                                   axis=0).max() > alpha:
                added[k] = ring[on[np.argmin(height[on])]]
        if not added:
            return samples
        keys = sorted(added)
        samples = np.insert(samples, [k + 1 for k in keys], [added[k] for k in keys], axis=0)
    return samples


def _reflex_run(samples, end, other, w, ring, turns, chord_of):
    """The run of reflex vertices of a chord's arc that starts at ``w`` and goes on
    towards the chord's far end ``other`` from ``end``, and the arc's vertex that ends it
    (empty where the arc ends first)."""
    step = 1 if other == (end + 1) % len(samples) else -1
    run, k = [w], (w + step) % len(ring)
    while turns[k] < 0 and chord_of[k] == chord_of[w]:
        run.append(k)
        k = (k + step) % len(ring)
    return run, np.array([k] if chord_of[k] == chord_of[w] else [], dtype=np.int64)


def _move_along_run(samples, end, other, run, ring, turns, alpha):
    """Where chord end ``end`` (of a ring's ``samples``; ``other`` the chord's far end)
    moves along the ``run`` of reflex vertices towards the far end (:func:`_reflex_run`):
    the last vertex of the run, or the one before it, and so on back to its first, that
    keeps the end's other chord in [alpha, √3 alpha] (or no shorter than it was), the
    far end alpha away, and no part of the ring at the moved end's two chords hidden
    from the end beside it and farther than alpha from the other (:func:`_hides`).
    None where no vertex of the run does."""
    beside = samples[(2 * end - other) % len(samples)]              # e's other neighbour
    shortest = min(alpha, np.hypot(*(samples[end] - beside)))     # not shorter than it was
    tried = samples.copy()
    for v in reversed(run):
        if not (shortest <= np.hypot(*(ring[v] - beside)) <= LONGEST_CHORD * alpha
                and np.hypot(*(ring[v] - samples[other])) >= alpha):
            continue
        tried[end] = ring[v]
        if not _hides(tried, ring, turns, alpha, end):
            return v
    return None


def _hides(samples, ring, turns, alpha, k) -> bool:
    """Whether a chord at sample ``k`` of a ring's ``samples`` hides part of the ring
    from its end before a reflex vertex, the far end farther than alpha from that
    vertex (:func:`.boundary_sampling.hidden_bends`)."""
    found = hidden_bends(samples, ring, turns, 1e-9 * alpha)
    return found is not None and any(
        np.hypot(*(ring[w] - samples[f])) > alpha for _, e, f, w, _ in found[0] if k in (e, f))


def _clear_of_own_ring(samples, ring, turns, passes=4) -> np.ndarray:
    """A ring's boundary samples (in order along ``ring``, ``turns`` its turning angles)
    with, where the polygon through them crosses itself, a ring vertex added to every
    chord that crosses the ring outside its own arc: the arc's first vertex when the
    crossing is nearer the chord's first end, else its last.

    A fold of a section (the ring runs on, turns back by nearly 180°, and on again
    past the turn, a tip and a crack thinner than the tolerance) has samples at both of
    its tips; the next chord, from the crack's tip, cut the fold's tip off and crossed
    the chord along it. The polygon through the samples then crosses itself, and no mesh
    conforms to it: a held-out housing section left both tips isolated. The chord from
    an end to its arc's next vertex lies on the ring, which is simple, so it crosses
    nothing; the rest of the chord is checked again (``passes``). A vertex closer than
    alpha to the chord's end is an itemised small-feature exception.

    Examples
    --------
    >>> fold = np.array([[0, 0], [3, 0], [3, 1], [1, 1], [0.5, 1],       # tip (0.5, 1)
    ...                  [1.2, 0.99], [0.4, 0.985], [-0.5, 1.3], [-0.5, 0]])
    >>> samples = fold[[0, 1, 2, 4, 5, 7, 8]]     # (1.2, 0.99) -> (-0.5, 1.3) cuts the tip
    >>> _clear_of_own_ring(samples, fold, turning_angles(fold))[3:6].tolist()
    [[0.5, 1.0], [1.2, 0.99], [0.4, 0.985]]
    """
    samples = np.asarray(samples, float)
    if not ((turns < 0).any() and (turns > 0).any()):
        return samples                  # a convex ring holds its chords (a round hole)
    if shapely.is_simple(shapely.linearrings(samples)):
        return samples                  # no chord crosses another: some mesh conforms
    segments = shapely.linestrings(np.stack([ring, np.roll(ring, -1, axis=0)], axis=1))
    tree = shapely.STRtree(segments)
    for _ in range(passes):
        ends = np.stack([samples, np.roll(samples, -1, axis=0)], axis=1)
        chords, crossed = tree.query(shapely.linestrings(ends), predicate="crosses")
        chord_of, _, _ = vertex_chords(samples, ring)
        # a segment on the chord's arc, or the one its first end lies on (rounding)
        own = (chord_of[crossed] == chords) | (np.roll(chord_of, -1)[crossed] == chords)
        chords, crossed = chords[~own], crossed[~own]
        added = {}
        for k in np.unique(chords):
            a, b = ends[k]
            arc = np.flatnonzero(chord_of == k)
            arc = arc[(ring[arc] != a).any(axis=1) & (ring[arc] != b).any(axis=1)]
            if not len(arc):
                continue
            point = shapely.get_coordinates(shapely.intersection(
                shapely.linestrings(ends[k]), segments[crossed[chords == k]]))
            t = np.dot(point - a, b - a) / np.dot(b - a, b - a)
            added[k] = ring[arc[0] if t.min() < 1 - t.max() else arc[-1]]
        if not added:
            return samples
        samples = np.insert(samples, [k + 1 for k in added], list(added.values()), axis=0)
    return samples


def _clear_of_other_rings(ring_xy, rings, passes=4) -> list:
    """Each ring's boundary samples (``ring_xy``, in order along ``rings``) with a ring
    vertex added to every chord that crosses another ring: the farthest of its arc's
    vertices from the chord on the region's side (the bend the chord cuts across), else
    the farthest beyond it.

    A chord with another ring wholly between it and its arc counts as crossing it
    (:func:`_enclosing`).

    A chord over a reflex bend leaves the region by the bend's sagitta. Where another
    ring is nearer than that (a boss 0.05 alpha from a tube's 20° bends, on a held-out
    section) the chord crosses into the other ring's material, the chord polygons
    overlap, and no mesh conforms to them: samples were left isolated and chords
    unjoined. A chord across a convex bend (a plate's rounded corner at an alpha larger
    than the corner) crosses a hole near the bend instead: it gets the arc's vertex
    farthest beyond it. The vertex added is at most a chord from its neighbours; closer
    than alpha to them, it is an itemised small-ring exception.

    Examples
    --------
    >>> notched = np.array([[0, 0], [3, 0], [3, 1], [1.5, 0.8], [0, 1]], float)
    >>> pin = np.array([[1.4, 0.9], [1.6, 0.9], [1.5, 1.1]])   # a part in the notch
    >>> xy = _clear_of_other_rings([notched[[0, 1, 2, 4]], pin], [notched, pin[::-1]])
    >>> xy[0].tolist()
    [[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [1.5, 0.8], [0.0, 1.0]]
    """
    if len(rings) < 2:
        return ring_xy
    ring_xy = [np.asarray(xy, float) for xy in ring_xy]
    tree = shapely.STRtree(np.array([shapely.linearrings(ring) for ring in rings]))
    for _ in range(passes):
        ends = [np.stack([xy, np.roll(xy, -1, axis=0)], axis=1) for xy in ring_xy]
        sizes = [len(e) for e in ends]
        owner = np.repeat(np.arange(len(rings)), sizes)
        first = np.concatenate([[0], np.cumsum(sizes)])
        chord, other = tree.query(shapely.linestrings(np.concatenate(ends)),
                                  predicate="intersects")
        crossing = np.union1d(chord[other != owner[chord]],
                              _enclosing(ring_xy, rings, first))
        if not len(crossing):
            break
        for r in np.unique(owner[crossing]):
            ring, xy = rings[r], ring_xy[r]
            chord, offset, _ = vertex_chords(xy, ring)
            a, b = xy[chord], np.roll(xy, -1, axis=0)[chord]
            # each vertex's height over its chord, on the region's side (left)
            height = (b[:, 0] - a[:, 0]) * (ring[:, 1] - a[:, 1]) \
                - (b[:, 1] - a[:, 1]) * (ring[:, 0] - a[:, 0])
            added = []
            for k in crossing[owner[crossing] == r] - first[r]:
                arc = np.flatnonzero((chord == k) & (offset > 0))
                inside = arc[height[arc] > 0]
                if len(inside):     # the deepest bend the chord cuts across
                    added.append((k + 1, ring[inside[np.argmax(height[inside])]]))
                elif len(arc):      # or the arc's farthest point beyond it
                    added.append((k + 1, ring[arc[np.argmin(height[arc])]]))
            if added:
                ring_xy[r] = np.insert(xy, [k for k, _ in added], [v for _, v in added], axis=0)
    return ring_xy


def _enclosing(ring_xy, rings, first) -> np.ndarray:
    """The chords (numbered ring after ring from ``first``, each ring's first chord)
    with another ring wholly between them and their arcs: a small hole just inside a
    plate's rounded corner, which the chord across the corner cut off (a held-out laser
    sheet at alpha = extent / 25: the hole's samples isolated, the hole opened to the
    outside). Such a ring's first vertex is inside one ring and outside its chords, or
    the other way round; the chord is the one whose arc and chord go round it."""
    polygons = shapely.polygons([shapely.linearrings(ring) for ring in rings])
    chorded = shapely.polygons([shapely.linearrings(xy) for xy in ring_xy])
    starts = np.array([ring[0] for ring in rings])
    point, owner = shapely.STRtree(polygons).query(shapely.points(starts))
    point, owner = point[point != owner], owner[point != owner]
    x, y = starts[point].T
    cut = shapely.contains_xy(polygons[owner], x, y) != shapely.contains_xy(chorded[owner], x, y)
    found = []
    for p, r in zip(point[cut], owner[cut]):
        xy, ring = ring_xy[r], rings[r]
        chord_of, offset, _ = vertex_chords(xy, ring)
        for k in np.unique(chord_of):
            arc = np.flatnonzero(chord_of == k)
            loop = np.vstack([xy[k], ring[arc[np.argsort(offset[arc])]], xy[(k + 1) % len(xy)]])
            if _encircles(loop, starts[p]):
                found.append(first[r] + k)
    return np.array(found, dtype=np.int64)


def _encircles(loop, point) -> bool:
    """Whether the closed polyline ``loop`` goes round ``point`` an odd number of times
    (a ray to the right crosses it oddly often); the loop may cross itself."""
    a, b = loop - point, np.roll(loop, -1, axis=0) - point
    straddles = (a[:, 1] > 0) != (b[:, 1] > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (b[:, 0] - a[:, 0]) * (0 - a[:, 1]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(straddles & (x > 0)) % 2)


def _rungs_across_walls(ring_xy, rings, alpha, passes=4) -> list:
    """Each ring's boundary samples (``ring_xy``, in order along ``rings``) with a rung
    added to every chord that a sample across a wall thinner than alpha blocks: the
    point of the chord's arc across from that sample.

    A chord ab of length L is an edge of a triangle of circumradius <= alpha only if no
    sample p it sees lies in its *lens*, the part on the region's side of the disc of
    radius alpha through a and b whose centre lies beyond the chord: the constrained
    Delaunay triangle on ab is the first circle through a and b that reaches a sample,
    and reaching p inside the lens takes a circle larger than alpha. Inside the region
    only a boundary sample across a wall thinner than alpha - L/2·cot can be there (the
    lens is within alpha of a or b when L <= √3 alpha, where the guards and interior
    samples are not). On a held-out bolted plate at a fixed alpha the wall between a
    bolt hole and the plate's edge was 0.33 alpha, the hole's chord 1.7 alpha and the
    edge's sample across its middle; the chord was left unjoined. The rung m is the
    arc's point across from that sample along the chord (:func:`_across_from`; on a
    rounded corner the nearest point would be the chord's end). With the rung m the
    sample is across m, at the end of both new chords, each then joined by a triangle
    of circumradius about half its diagonal, as on a spike's ladder (:func:`_ladders`);
    the pairs closer than alpha are itemised small-ring and thin-wall exceptions.

    Examples
    --------
    >>> plate = np.array([[0, 0], [4, 0], [4, 2], [0, 2]], float)
    >>> hole = np.array([[1, 0.3], [1, 1], [3, 1], [3, 0.3]], float)   # 0.3 from the edge
    >>> edge = np.array([[0, 0], [1.6, 0], [3.2, 0], [4, 0], [4, 2], [2, 2], [0, 2]])
    >>> xy = _rungs_across_walls([edge, hole], [plate, hole], 1.0)
    >>> xy[0][:5].round(6).tolist()     # a rung across the hole's corner (1, 0.3)
    [[0.0, 0.0], [1.0, 0.0], [1.6, 0.0], [3.2, 0.0], [4.0, 0.0]]
    """
    ring_xy = [np.asarray(xy, float) for xy in ring_xy]
    for _ in range(passes):
        points, index = joined(ring_xy)
        first, second = chord_ends(index)
        a, b = points[first], points[second]
        along_chord = b - a
        length = np.hypot(*along_chord.T)
        middle = 0.5 * (a + b)
        near = cKDTree(points).query_ball_point(middle, 0.5 * length)  # holds every lens
        chord = np.repeat(np.arange(len(a)), [len(k) for k in near])
        if not len(chord):
            break
        p = np.concatenate(near).astype(np.int64)
        off = (p != first[chord]) & (p != second[chord])
        chord, p = chord[off], p[off]
        unit = along_chord[chord] / length[chord, None]
        rel = (points[p] - middle[chord]) / alpha                    # in units of alpha
        x = rel[:, 0] * unit[:, 0] + rel[:, 1] * unit[:, 1]
        y = rel[:, 1] * unit[:, 0] - rel[:, 0] * unit[:, 1]          # left: the region's side
        below = np.sqrt(np.maximum(1 - (0.5 * length[chord] / alpha) ** 2, 0.0))
        depth = (1 - 1e-9) - x ** 2 - (y + below) ** 2
        blocked = (y > RESOLUTION) & (depth > 0)
        chords, beside = _chords_tree(ring_xy), np.full(len(points), -1)
        beside[first] = second                            # each sample's next along its ring
        seer, ends = p[blocked], chord[blocked]
        blocked[blocked] = (_sees_or_joined(points, seer, first[ends], beside, chords)
                            & _sees_or_joined(points, seer, second[ends], beside, chords))
        if not blocked.any():
            break
        chord, p, depth = chord[blocked], p[blocked], depth[blocked]
        order = np.lexsort((-depth, chord))                   # the deepest one per chord
        chord, p = chord[order], p[order]
        keep = np.append(True, chord[1:] != chord[:-1])
        rungs, ends = {}, np.cumsum([len(i) for i in index])
        for k, q in zip(chord[keep], p[keep]):
            r = int(np.searchsorted(ends, k, side="right"))
            rungs.setdefault(r, []).append((k - index[r][0], points[q]))
        for r, found in rungs.items():
            xy, ring = ring_xy[r], rings[r]
            owner, offset, _ = vertex_chords(xy, ring)
            added = []
            for k, q in found:
                arc = np.vstack([xy[k], ring[owner == k][np.argsort(offset[owner == k])],
                                 xy[(k + 1) % len(xy)]])
                m = _across_from(arc, q)
                if min(np.hypot(*(m - arc[0])), np.hypot(*(m - arc[-1]))) > RESOLUTION * alpha:
                    added.append((k + 1, m))
            if added:
                ring_xy[r] = np.insert(xy, [k for k, _ in added], [m for _, m in added], axis=0)
    return ring_xy


def _chords_tree(ring_xy):
    """A tree of the chords between the boundary samples ``ring_xy`` (each ring's, in
    order), the boundary the complex conforms to, for :func:`_sees`."""
    return shapely.STRtree(shapely.linearrings(
        np.concatenate(ring_xy), indices=np.repeat(np.arange(len(ring_xy)),
                                                   [len(xy) for xy in ring_xy])))


def _sees_or_joined(points, p, q, beside, chords) -> np.ndarray:
    """Whether each sample ``p`` sees the sample ``q`` (indices into ``points``): they
    are consecutive along their ring (``beside``: each sample's next), their chord the
    boundary itself, or the segment meets none of the ``chords`` (:func:`_sees`). A
    chord's own segment meets the chords: a sliver component of three samples (a bulged
    slot cutting a drawing's outline, 0.15 wide at alpha 3.1) had its long chord blocked
    by the third sample, seen from neither end, so no rung was added, its one triangle
    was too large to keep, and the component was lost."""
    seen = (beside[p] == q) | (beside[q] == p)
    seen[~seen] = _sees(points[p[~seen]], points[q[~seen]], chords)
    return seen


def _sees(p, q, chords) -> np.ndarray:
    """Whether each point p sees its point q through the ``chords`` (:func:`_chords_tree`):
    the open segment meets no chord."""
    shrink = 1e-9 * (q - p)
    lines = shapely.linestrings(np.stack([p + shrink, q - shrink], axis=1))
    seen = np.ones(len(p), bool)
    seen[chords.query(lines, predicate="intersects")[0]] = False
    return seen


def _inside_chords(points, ring_xy) -> np.ndarray:
    """Whether each point is inside the polygons of the chords between the boundary
    samples ``ring_xy``: inside an odd number of them (holes lie in their outlines)."""
    polygons = [shapely.Polygon(xy) for xy in ring_xy]
    tree = shapely.STRtree(polygons)
    point, ring = tree.query(shapely.points(points), predicate="within")
    return np.bincount(point, minlength=len(points)) % 2 == 1


def _guards_halved(ring_xy, region, alpha) -> list:
    """Each ring's boundary samples (``ring_xy``, in order along ``region.rings``) with the
    middle of its arc added to every chord longer than √3 alpha that no guard can keep:
    each of its guard candidates (:func:`.boundary_sampling.bisector_guards`) is within
    alpha of a boundary sample that sees it, or outside the region.

    Such a chord is a mesh edge only with a third sample in the thin crescent where its
    triangle has circumradius <= alpha, and its guard at height alpha is what puts one
    there and keeps the darts out of the lens below (docs/conforming.md, "Why
    consecutive boundary samples are mesh edges"). Where the region is not much wider
    than alpha across the chord, the boundary samples across block every guard: the jaw
    of wrench.dxf at alpha = extent / 20 had two chords of 1.998 alpha, a dart in each
    lens and neither chord joined. Halved, the chord's two parts (just under alpha, a
    small-ring exception) need no guard.

    Examples
    --------
    >>> slot = np.array([[0, 0], [1.9, 0], [1.9, 1.0], [0, 1.0]], float)   # 1 wide
    >>> xy = _guards_halved([slot], Region.from_shapely(shapely.Polygon(slot)), 1.0)
    >>> xy[0].round(6).tolist()   # every guard of the 1.9 sides is within 1 of a corner
    [[0.0, 0.0], [0.95, 0.0], [1.9, 0.0], [1.9, 1.0], [0.95, 1.0], [0.0, 1.0]]
    """
    points, index = joined(ring_xy)
    first, second = chord_ends(index)
    a, b = points[first], points[second]
    long = np.flatnonzero(np.hypot(*(b - a).T) > math.sqrt(3) * alpha)
    if not len(long):
        return ring_xy
    guards = bisector_guards(a[long], b[long], np.full(len(long), alpha))
    levels = guards.shape[0]
    at = guards.reshape(-1, 2)
    rings = region.rings
    free = _inside_chords(at, ring_xy)
    near = cKDTree(points).query_ball_point(at, alpha * (1 - 1e-12))
    guard = np.repeat(np.arange(len(at)), [len(k) for k in near])
    seer = np.concatenate(near).astype(np.int64)
    seen = _sees(at[guard], points[seer], _chords_tree(ring_xy))
    free[guard[seen]] = False
    blocked = long[~free.reshape(levels, -1).any(axis=0)]
    # a chord from a tip whose triangle with its two neighbours the complex keeps is that
    # triangle's edge: halving it would put a sample inside the tip's clearance and make
    # the triangle obtuse, too large to keep (an 11.7° tip of a bracket's sliver, seed 44)
    following = np.empty(len(points), np.int64)
    following[first] = second
    preceding = np.empty(len(points), np.int64)
    preceding[second] = first
    tip = np.zeros(len(blocked), bool)
    for end in (first[blocked], second[blocked]):
        tip |= _kept_tip(points[preceding[end]], points[end], points[following[end]], alpha)
    blocked = blocked[~tip]
    if not len(blocked):
        return ring_xy
    ring_xy = list(ring_xy)
    sizes = np.cumsum([len(k) for k in index])
    for r in np.unique(np.searchsorted(sizes, blocked, side="right")):
        ring, xy = rings[r], ring_xy[r]
        line = shapely.LineString(np.vstack([ring, ring[:1]]))
        place = shapely.line_locate_point(line, shapely.points(xy))
        k = blocked[np.searchsorted(sizes, blocked, side="right") == r] - index[r][0]
        span = (place[(k + 1) % len(xy)] - place[k]) % line.length
        middle = shapely.get_coordinates(shapely.line_interpolate_point(
            line, (place[k] + span / 2) % line.length))
        ring_xy[r] = np.insert(xy, k + 1, middle, axis=0)
    return ring_xy


def _kept_tip(p, c, q, alpha) -> np.ndarray:
    """Whether each boundary sample c, between p and q along its ring (the region on the
    left), is a convex corner whose triangle p c q has circumradius at most ``alpha``:
    a triangle inside the region that the complex keeps, with the chords cp and cq as
    edges. (A reflex c's triangle lies outside the region: held-out seed 34.)"""
    u, v = c - p, q - c
    turn = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    angle = np.arctan2(np.abs(turn), -(u * v).sum(axis=1))     # the angle p c q
    return (turn > 0) & (np.hypot(*(q - p).T) <= 2 * alpha * np.sin(angle))


def _across_from(arc, q) -> np.ndarray:
    """The point of ``arc`` (a polyline from a chord's first end to its second) across
    from the point ``q``: where the arc first reaches q's place along the chord (its
    projection); the arc's end nearest q if it never does.

    Examples
    --------
    >>> corner = np.array([[0, 0], [1, 0.2], [1.5, 0.8], [1.6, 1.5]])   # a rounded corner
    >>> _across_from(corner, np.array([0.5, 1.0])).round(3).tolist()
    [1.118, 0.341]
    """
    direction = arc[-1] - arc[0]
    along = (arc - arc[0]) @ direction / (direction @ direction)
    place = (q - arc[0]) @ direction / (direction @ direction)
    crossing = np.flatnonzero((along[:-1] - place) * (along[1:] - place) <= 0)
    if not len(crossing):
        return arc[0] if place < 0.5 else arc[-1]
    i = crossing[0]
    t = (place - along[i]) / (along[i + 1] - along[i]) if along[i + 1] != along[i] else 0.0
    return arc[i] + t * (arc[i + 1] - arc[i])
