"""Meshes of planar partitions: regions that share boundary chains, each chain sampled once.

Several regions of one plane (a steel core in a concrete section, the planar faces of a
solid unrolled into their planes) are meshed so that the meshes join with no T-junction:

1. **Chains.** The regions' rings, on shared vertex numbers (every ring vertex lying on
   another ring's segment is inserted there), are cut into *chains*: maximal runs of
   edges owned by the same regions (one side on the outer boundary, two on an
   interface), between *junctions* (vertices where the edges of other regions start, or
   the owners change, or that the caller pins). A ring with no junction is one closed
   chain.
2. **Samples, once per chain**, by the conforming sampler's rules
   (docs/conforming.md), which depend on the chain alone: its junctions are samples;
   its sharp vertices are samples, with the clearance of the sharper of the two sides'
   angles, ``corner_clearance(pi - |turn|)`` (the convex side's); its inflections are
   samples; the pieces between are cut into parts in [alpha, √3 alpha], the first and
   last at least the clearance of the sharpest corner any side has at that junction.
   Every such rule is at least what either side alone would ask, so both sides'
   proofs hold with the same samples (docs/partition.md).
3. **Each region** is then sampled inside (guards, darts, refinement: per side) with its
   boundary samples given (``poisson_disc(boundary_samples=...)``), meshed by the
   constrained solid alpha-complex and certified on its own.
4. **Joined.** The meshes share the chains' samples by number: an interface edge is an
   edge of both sides' meshes, once each, in opposite directions.
   :func:`interface_report` checks it on the result.

:func:`mesh_regions` is the public entry (composite sections, issue 23);
:mod:`pds_plugin.remeshing` (``pds.remesh``) uses :func:`sample_chains` with its patches in their own planes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, Polygon

from ._checks import check_alpha, check_positive_int, check_seed
from .errors import ArgumentError, ArgumentTypeError, RegionError
from .mesh import PlanarMesh
from .region import Region, _following, turning_angles
from .graded_sampling import TAU_MARGIN, cleared_piece, corner_leg, corner_side, tau_positions
from .sampling import (DEFAULT_MAX_SAMPLES, LADDER_ANGLE, STRAIGHT_TURN, check_budget,
                       corner_clearance, ring_positions)
from .sizing import DEFAULT_GRADING, RadiusField, _apart, graded_request, inradius, radius_field
from . import _sampling_kernels as kern
from . import _graded_kernels, _sizing_kernels

__all__ = ["mesh_regions", "CompositeMesh", "PartitionCertificate", "sample_chains",
           "graded_sample_chains", "junction_fields", "agreeing_fields", "chain_sample_radii",
           "partition_topology",
           "with_sample_cones", "fields_with_cones",
           "ChainSamples",
           "mesh_part", "interface_report", "InterfaceReport"]

_ON_SEGMENT = 1e-12
"""How close (relative to the extent) a vertex of one ring must be to a segment of
another to be inserted there: shared boundaries are shared up to rounding only."""


# --- chains and their samples -------------------------------------------------------

@dataclass(frozen=True)
class ChainSamples:
    """The boundary samples of a partition, each chain sampled once.

    A sample is the point ``x[u] + t (x[v] - x[u])`` of the vertex coordinates ``x`` of
    whichever frame it is read in (a junction is ``u = v``, ``t = 0``), so that the two
    sides of a chain, each in its own plane, read the same samples.

    Attributes
    ----------
    u, v : (S,) int64 ndarray
        The vertex numbers of the segment each sample lies on.
    t : (S,) float ndarray
        Where along it.
    rings : list of list of (k,) int64 ndarray
        Per region, per ring (in the order given), the sample numbers along it.
    chains : list of (k,) int64 ndarray
        The vertex numbers along each chain (a closed chain does not repeat its first).
    closed : list of bool
        Whether each chain is closed (a whole ring).
    sides : list of tuple of int
        The regions each chain bounds (one, or two for an interface).
    chain_samples : list of (m,) int64 ndarray
        The sample numbers along each chain, ends included.
    """

    u: np.ndarray
    v: np.ndarray
    t: np.ndarray
    rings: list
    chains: list
    closed: list
    sides: list
    chain_samples: list

    def chords(self, chain: int) -> np.ndarray:
        """The (m, 2) sample numbers of the consecutive samples along ``chain``."""
        samples = self.chain_samples[chain]
        ends = np.roll(samples, -1) if self.closed[chain] else samples[1:]
        return np.column_stack([samples[:len(ends)], ends])

    @cached_property
    def region_samples(self) -> list:
        """Per region, the sample numbers of its rings, ring after ring."""
        return [np.concatenate(rings) for rings in self.rings]

    def regions_points(self, frames) -> list:
        """Per region, the samples of its rings, ring after ring (:attr:`region_samples`),
        read in its frame (``frames``): all regions' looked up at once
        (:func:`read_frames`)."""
        ids = self.region_samples
        every = np.concatenate([np.zeros(0, np.int64), *ids])
        start = read_regions(frames, [self.u[region] for region in ids])
        end = read_regions(frames, [self.v[region] for region in ids])
        return split_counts(start + self.t[every, None] * (end - start),
                            [len(region) for region in ids])

    def points(self, coordinates) -> np.ndarray:
        """The samples read in ``coordinates`` (indexable by vertex number: an array, or
        :class:`Frame`)."""
        xu, xv = coordinates[self.u], coordinates[self.v]
        return xu + self.t[:, None] * (xv - xu)


class Frame:
    """Coordinates of some vertices, indexed by vertex number: ``frame[ids]``.

    Examples
    --------
    >>> frame = Frame([7, 3], [[1.0, 2.0], [3.0, 4.0]])
    >>> frame[np.array([3, 7])].tolist()
    [[3.0, 4.0], [1.0, 2.0]]
    """

    def __init__(self, ids, xy):
        ids = np.asarray(ids, dtype=np.int64)
        order = np.argsort(ids, kind="stable")
        self.ids, self.xy = ids[order], np.asarray(xy, dtype=float)[order]

    @classmethod
    def of_sorted(cls, ids, xy) -> "Frame":
        """The frame of ``ids`` already increasing (int64) and their ``xy`` (float), taken
        as they are (a remesh makes one for each of hundreds of patches)."""
        frame = cls.__new__(cls)
        frame.ids, frame.xy = ids, xy
        return frame

    def __getitem__(self, ids):
        # the array methods, not numpy's functions (their dispatch doubled the time of
        # the few thousand small look-ups of a remesh)
        ids = np.asarray(ids, dtype=np.int64)
        at = self.ids.searchsorted(ids)
        if ids.size and (not len(self.ids)
                         or not (self.ids.take(at, mode="clip") == ids).all()):
            raise KeyError("a vertex outside this frame")
        return self.xy.take(at, axis=0)


class Frames(tuple):
    """:class:`Frame` s, region by region, with all their vertices in one sorted index
    (:attr:`index`), made once for the many :func:`read_frames` calls of a remesh's
    steps over its hundreds of patches."""

    @cached_property
    def index(self) -> tuple:
        """(keys, span, xy): each vertex's key ``region x span + id``, increasing (by
        frame, then by id; ``span`` is one more than the largest id), and its xy."""
        ids = np.concatenate([np.zeros(0, np.int64), *(frame.ids for frame in self)])
        span = int(ids.max(initial=-1)) + 1
        owner = np.repeat(np.arange(len(self)), [len(frame.ids) for frame in self])
        return owner * span + ids, span, np.concatenate([np.zeros((0, 2)),
                                                         *(frame.xy for frame in self)])


def read_frames(frames, region, vertex) -> np.ndarray:
    """``frames[region[k]][vertex[k]]`` for every k: one search over all the frames when
    they are :class:`Frame` s (a remesh's hundreds of patches: a look-up each cost
    5 µs; pass them as :class:`Frames` to index them once), else one look-up per region.

    Examples
    --------
    >>> frames = [Frame([7, 3], [[1.0, 2.0], [3.0, 4.0]]), Frame([3], [[5.0, 6.0]])]
    >>> read_frames(frames, np.array([1, 0, 0]), np.array([3, 3, 7])).tolist()
    [[5.0, 6.0], [3.0, 4.0], [1.0, 2.0]]
    """
    region, vertex = np.asarray(region, np.int64), np.asarray(vertex, np.int64)
    if not isinstance(frames, Frames):
        if not all(isinstance(frame, Frame) for frame in frames):
            out = np.empty((len(region), 2))
            for r, at in _groups(region):
                out[at] = frames[r][vertex[at]]
            return out
        frames = Frames(frames)
    if not len(region):
        return np.empty((0, 2))
    keys, span, xy = frames.index
    wanted = region * span + vertex
    at = keys.searchsorted(wanted)
    if (vertex.min() < 0 or vertex.max() >= span or not len(keys)
            or not (keys.take(at, mode="clip") == wanted).all()):
        raise KeyError("a vertex outside its frame")
    return xy.take(at, axis=0)


def read_regions(frames, ids) -> np.ndarray:
    """Each region's vertices ``ids[r]`` read in its frame ``frames[r]``, region after
    region (:func:`read_frames`)."""
    counts = [len(region) for region in ids]
    return read_frames(frames, np.repeat(np.arange(len(ids)), counts),
                       np.concatenate([np.zeros(0, np.int64), *ids]))


def sample_chains(rings, frames, alpha: float, *, feature_angle: float = 30.0, seed: int = 0,
                  pinned=()) -> ChainSamples:
    """Sample the boundary chains of regions that share them, each chain once.

    Parameters
    ----------
    rings : list of list of (k,) int array_like
        Per region, its rings as vertex numbers, the region on the left; a vertex shared
        by two regions has one number, and a shared edge is run both ways.
    frames : list
        Per region, its vertices' 2D coordinates indexed by vertex number (an (n, 2)
        array over all vertices, or a :class:`Frame`).
    alpha : float
    feature_angle : float
        Chain vertices turning by at least this many degrees are sampled (corners).
    seed : int
        Seed of the chains' random cuts.
    pinned : iterable of int
        Vertices that must be samples (chains are cut there).

    Returns
    -------
    ChainSamples

    Raises
    ------
    RegionError
        If an edge is run the same way by two regions (they overlap) or bounds three.

    Examples
    --------
    >>> xy = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]], float)
    >>> left, right = [np.array([0, 1, 4, 5])], [np.array([1, 2, 3, 4])]
    >>> chains = sample_chains([left, right], [xy, xy], 0.3)
    >>> shared = [c for c, sides in zip(chains.chain_samples, chains.sides) if len(sides) == 2]
    >>> len(shared), chains.points(xy)[shared[0]][:, 0].tolist() == [1.0] * len(shared[0])
    (1, True)
    """
    alpha = check_alpha(alpha)
    rings = [[np.asarray(ring, dtype=np.int64) for ring in region] for region in rings]
    owner, angle, _ = _edge_owners(rings, frames)
    junction = _junctions(owner, pinned)
    chains = _chains(rings, owner, junction)
    positions = _chain_positions(chains, owner, angle, frames, alpha, feature_angle, seed,
                                 junction, _spikes(rings, frames, junction))
    return _assembled(rings, _sides(owner, chains), junction, chains, positions)


def _sides(owner, chains) -> list:
    """The regions each chain bounds, in increasing order (``owner`` of its first edge)."""
    return [sorted(set(owner[_key(vertices[0], vertices[1])])) for vertices, _ in chains]


def _assembled(rings, sides, junction, chains, positions) -> ChainSamples:
    """The :class:`ChainSamples` of ``chains`` (``sides``: the regions each bounds) from
    each chain's (segment, fraction) positions, junctions numbered once.

    Samples are numbered in the chains' order, each chain's positions then its far end
    (an open chain's): a position at a junction chain's start and a chain's far end
    are junction samples, numbered where their vertex is met first."""
    closed = np.array([bool(c[1]) for c in chains], bool)
    sizes = np.array([len(c[0]) for c in chains], np.int64)
    vertices = np.concatenate([c[0] for c in chains] + [np.zeros(0, np.int64)]).astype(np.int64)
    start = np.cumsum(sizes) - sizes
    counts = np.array([len(p[0]) for p in positions], np.int64)
    segment = np.concatenate([p[0] for p in positions] + [np.zeros(0)]).astype(np.int64)
    t = np.concatenate([p[1] for p in positions] + [np.zeros(0)]).astype(float)
    at_junction = np.array([int(c[0][0]) in junction for c in chains], bool)
    # the entries, chain by chain: its positions, then its far end if open
    entries = counts + ~closed
    chain = np.repeat(np.arange(len(chains)), entries)
    place = np.arange(len(chain)) - np.repeat(np.cumsum(entries) - entries, entries)
    end = place == counts[chain]
    here = np.zeros(len(chain), np.int64)
    here[~end] = segment
    fraction = np.zeros(len(chain))
    fraction[~end] = t
    u = vertices[start[chain] + np.where(end, sizes[chain] - 1, here)]
    v = vertices[start[chain] + (here + 1) % sizes[chain]]
    junction_sample = end | ((fraction == 0.0) & (here == 0) & at_junction[chain])
    # a junction's vertex is numbered where it is met first; every other entry is new
    at = np.flatnonzero(junction_sample)
    _, first, inverse = np.unique(u[at], return_index=True, return_inverse=True)
    new = ~junction_sample
    new[at[first]] = True
    number = np.cumsum(new) - 1
    number[at] = number[at[first]][inverse.ravel()]
    sample_v = np.where(junction_sample, u, v)[new]
    sample_t = np.where(junction_sample, 0.0, fraction)[new]
    chain_samples = split_counts(number, entries)
    ring_samples = _ring_samples(rings, chains, chain_samples)
    return ChainSamples(u[new], sample_v, sample_t, ring_samples, [c[0] for c in chains],
                        [bool(c[1]) for c in chains], [tuple(s) for s in sides], chain_samples)


def graded_sample_chains(rings, frames, fields, *, feature_angle: float = 30.0, seed: int = 0,
                         pinned=(), topology=None) -> ChainSamples:
    """Sample the boundary chains of regions that share them, each chain once, for
    graded meshes: by the graded sampler's rules (:mod:`pds_plugin.graded_sampling`) with
    the radius r = the smallest of the fields of the regions the chain bounds.

    Each chain is densified and measured in normalized arc length ``τ = ∫ dt / r``; its
    junctions and its vertices turning by at least ``feature_angle`` are corners (a
    junction with the clearance of the sharpest angle a region has there, a vertex
    with its convex side's), and each piece between corners is cut into equal parts of
    τ in ``[a, 2 a)``, ``a = 1.02 / (1 - L/2)``, or by the corners' clearances, as the
    graded sampler cuts a ring's pieces; a chain without junction is a ring to it.
    Samples are then ``min(r(p), r(q))`` apart along the chain in every region's frame,
    so the regions' own samplers take them as given (``boundary_samples``) once their
    fields agree on the chain (:func:`chain_sample_radii`).

    Parameters
    ----------
    rings, frames, feature_angle, seed, pinned
        As for :func:`sample_chains`.
    fields : list of RadiusField
        Per region, its radius field in its own frame (all of one grading L).

    topology : optional
        ``partition_topology(rings, frames, pinned)``, if already made (the same for
        :func:`junction_fields` and :func:`agreeing_fields` of the same partition).

    Returns
    -------
    ChainSamples

    Raises
    ------
    RegionError
        As :func:`sample_chains`.

    Examples
    --------
    >>> from pds_plugin.sizing import RadiusField
    >>> xy = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]], float)
    >>> left, right = [np.array([0, 1, 4, 5])], [np.array([1, 2, 3, 4])]
    >>> field = RadiusField([[0, 0]], [0.05], grading=0.2, cap=0.4)
    >>> chains = graded_sample_chains([left, right], [xy, xy], [field, field])
    >>> shared = [c for c, sides in zip(chains.chain_samples, chains.sides) if len(sides) == 2]
    >>> p = chains.points(xy)[shared[0]]                  # the interface x = 1
    >>> r = field(p)
    >>> bool(np.all(np.hypot(*np.diff(p, axis=0).T) >= np.minimum(r[:-1], r[1:])))
    True
    """
    top = topology if topology is not None else _Topology(rings, frames, pinned)
    rings, angle, junction, chains = top.rings, top.angle, top.junction, top.chains
    if not chains:
        return _assembled(rings, top.sides, junction, chains, [])
    grading = max(field.grading for field in fields)
    unit = TAU_MARGIN / (1.0 - 0.5 * grading)
    sides = top.sides
    chain_set = _ChainSet(chains, sides, frames, fields, top.layout_field(frames, fields))
    cid, segment, t, ((xy, radius), (_, other)) = chain_set.dense_reads(grading)
    radius = np.minimum(radius, other)
    bounds = np.searchsorted(cid, np.arange(len(chains) + 1))
    single = _single_edges(chains, bounds, xy, radius, top.edge_angles, junction, unit)
    taus, positions, cleared = [], [], []
    for c, (vertices, closed) in enumerate(chains):
        part = slice(bounds[c], bounds[c + 1])
        tau, at, clear = single.get(c) or _graded_chain(
            vertices, closed, sides[c], angle, xy[part], radius[part], segment[part], unit,
            feature_angle, junction, _chain_rng(seed, vertices) if closed else None)
        taus.append(tau)
        positions.append(at)
        cleared.append(clear)
    flat = _FlatTau(taus, segment, t, bounds)
    chain, at = _halved(chain_set, flat, positions, cleared)
    along_segment, along_t = flat.to_chain(chain, at)
    counts = np.bincount(chain, minlength=len(chains))
    return _assembled(rings, sides, junction, chains,
                      list(zip(split_counts(along_segment, counts),
                               split_counts(along_t, counts))))


class _ChainSet:
    """The chains of a partition as flat arrays, and their points (chain, segment,
    fraction) read in each owner's frame, with the smallest of the owners' fields there
    (one field call per region for all its chains' points, or one call of ``union``,
    :meth:`_Topology.layout_field`, for all regions)."""

    def __init__(self, chains, sides, frames, fields, union=None):
        self.union = union
        self.count = np.array([len(vertices) for vertices, _ in chains], dtype=np.int64)
        self.closed = np.array([closed for _, closed in chains], dtype=bool)
        self.offset = np.concatenate([[0], np.cumsum(self.count)[:-1]])
        self.vertex = np.concatenate([vertices for vertices, _ in chains])
        side = np.array([[s[0], s[1] if len(s) > 1 else -1] for s in sides], dtype=np.int64)
        self.side = side
        self.frames, self.fields = frames, fields
        # every chain vertex in its owners' frames (side 0, side 1)
        owners = np.repeat(side, self.count, axis=0)
        self.corner = np.full((2, len(self.vertex), 2), np.nan)
        for s in (0, 1):
            at = np.flatnonzero(owners[:, s] >= 0)
            self.corner[s, at] = read_frames(frames, owners[at, s], self.vertex[at])

    def read(self, cid, segment, t, side):
        """The points in the frame of each one's owner ``side`` (0 or 1), and that
        owner's r there (NaN and inf for chains with one owner)."""
        following = np.where(self.closed[cid], (segment + 1) % self.count[cid],
                             np.minimum(segment + 1, self.count[cid] - 1))
        a = self.corner[side, self.offset[cid] + segment]
        b = self.corner[side, self.offset[cid] + following]
        xy = a + t[:, None] * (b - a)
        radius = np.full(len(cid), np.inf)
        if self.union is not None:                  # every region's field in one call
            owned = self.side[cid, side] >= 0
            if owned.all():
                radius = self.union(xy)
            elif owned.any():
                radius[owned] = self.union(xy[owned])
            return xy, radius
        for r, at in _groups(self.side[cid, side]):
            radius[at] = self.fields[r](xy[at])
        return xy, radius

    def evaluate(self, cid, segment, t):
        """The points in their chain's first owner's frame, and r there."""
        xy, radius = self.read(cid, segment, t, 0)
        if np.any(self.side[cid, 1] >= 0):
            radius = np.minimum(radius, self.read(cid, segment, t, 1)[1])
        return xy, radius

    def dense_reads(self, grading):
        """:meth:`dense` and, at its points, :meth:`read` of both sides: (chain, segment,
        fraction, [(xy, r) of side 0, (xy, r) of side 1]). With fields searched in C (no
        user sizing), in one kernel call (``_graded_kernels.densified_chains``, each
        owner read by its own field: what the union reads there, the same numbers bit
        for bit, without building the union)."""
        done = _graded_kernels.densified_chains(
            [field._kernel for field in self.fields],
            np.ascontiguousarray(self.corner[0]), np.ascontiguousarray(self.corner[1]),
            self.side, self.count, np.ascontiguousarray(self.closed, dtype=np.uint8), grading)
        if done is not None:
            cid, segment, t, xy0, r0, xy1, r1 = done
            return cid, segment, t, [(xy0, r0), (xy1, r1)]
        cid, segment, t = self.dense(grading)
        return cid, segment, t, [self.read(cid, segment, t, side) for side in (0, 1)]

    def dense(self, grading):
        """Every chain's points: its vertices, and midpoints inserted until every part
        is at most 0.3 of the lowest r the field can have on it (as
        ``graded_sampling._tau_rings`` densifies rings); an open chain's last vertex is
        (n - 1, 0). Returns (chain, segment, fraction), chain by chain in order (each
        round reads the fields at the inserted points only)."""
        cid = np.repeat(np.arange(len(self.count)), self.count)
        segment = np.arange(len(cid)) - np.repeat(self.offset, self.count)
        t = np.zeros(len(cid))
        xy, radius = self.evaluate(cid, segment, t)
        for _ in range(60):
            last = np.append(cid[1:] != cid[:-1], True)
            following = np.arange(1, len(cid) + 1)
            first_of = np.flatnonzero(np.insert(cid[1:] != cid[:-1], 0, True))
            following[last] = np.where(self.closed[cid[last]], first_of, np.flatnonzero(last))
            step = np.hypot(*(xy[following] - xy).T)
            low = np.minimum(radius, radius[following]) - 0.5 * grading * step
            split = step > 0.3 * low
            if not split.any():
                break
            k = np.flatnonzero(split)
            t_end = np.where(segment[following[k]] == segment[k], t[following[k]], 1.0)
            new = (cid[k], segment[k], 0.5 * (t[k] + t_end))
            new_xy, new_radius = self.evaluate(*new)
            cid = np.insert(cid, k + 1, new[0])
            segment = np.insert(segment, k + 1, new[1])
            t = np.insert(t, k + 1, new[2])
            xy = np.insert(xy, k + 1, new_xy, axis=0)
            radius = np.insert(radius, k + 1, new_radius)
        return cid, segment, t


def split_counts(array, counts) -> list:
    """``array`` cut into consecutive pieces of ``counts`` items (views, as ``np.split``
    makes, at a fraction of its cost a piece).

    >>> [piece.tolist() for piece in split_counts(np.arange(5), [2, 0, 3])]
    [[0, 1], [], [2, 3, 4]]
    """
    ends = np.cumsum(counts).tolist()
    return [array[start:end] for start, end in zip([0] + ends[:-1], ends)]


def _groups(labels):
    """(label, indices) for each label >= 0 of ``labels``, in increasing label order."""
    order = np.argsort(labels, kind="stable")
    ordered = labels[order]
    cuts = np.concatenate([[0], np.flatnonzero(ordered[1:] != ordered[:-1]) + 1, [len(order)]])
    for lo, hi in zip(cuts[:-1].tolist(), cuts[1:].tolist()):
        if hi > lo and ordered[lo] >= 0:
            yield int(ordered[lo]), order[lo:hi]


def _single_edges(chains, bounds, dense, radius, table, junction, unit) -> dict:
    """What :func:`_graded_chain` gives the open chains of one edge between two junctions
    (most chains of a remeshed CAD part, whose faces meet kept tessellations pinned at
    every vertex; every chain of a sphere's facets), all at once: by chain, its τ, its
    samples' positions and its cleared corners. The same arithmetic, element by element;
    the other chains are left out. The legs of the junctions whose angles ask a
    clearance (:func:`_chain_clearance`'s, on the edge and on the chord back that closes
    the chain) are found for all chains in one pass (:func:`_first_reaches`), their
    angles read in ``table`` (:class:`_EdgeAngles`)."""
    two = [c for c, (vertices, closed) in enumerate(chains) if not closed and len(vertices) == 2]
    ends = np.array([chains[c][0] for c in two], dtype=np.int64).reshape(-1, 2)
    both = np.isin(ends, np.fromiter(junction, np.int64, len(junction))).all(axis=1)
    simple, ends = [c for c, ok in zip(two, both.tolist()) if ok], ends[both]
    if not simple:
        return {}
    sharpest = np.column_stack([table.sharpest(ends[:, 0], ends[:, 1]),
                                table.sharpest(ends[:, 1], ends[:, 0])])
    k = corner_clearance(np.pi - (np.pi - sharpest), 1.0)
    # τ increments along every chain's dense points, closed by its chord back
    cid = np.repeat(np.arange(len(bounds) - 1), np.diff(bounds))
    following = np.arange(1, len(cid) + 1)
    following[bounds[1:][np.diff(bounds) > 0] - 1] = bounds[:-1][np.diff(bounds) > 0]
    step = np.hypot(*(dense[following] - dense).T)
    inverse = 1.0 / radius
    increment = 0.5 * step * (inverse + inverse[following])
    lo, hi = bounds[simple], bounds[np.asarray(simple) + 1]
    taus = _running_sums(increment, lo, hi)
    after, before = _first_reaches(taus, lo, hi, dense, radius, k, unit)
    # τ = 0 at the first end; the far end is the chain's last dense point. Equal parts
    # (the first at 0), one part if too short for both clearances, else the parts
    # :func:`cleared_piece` gives where a clearance exceeds a unit (a chain whose ends
    # ask none has after = before = unit: equal parts)
    span = np.array([tau[-2] for tau in taus])
    first, last = after[:, 0], before[:, 1]
    short = span < first + last
    parts = np.where(short, 1, np.maximum(np.floor_divide(span, unit).astype(np.int64), 1))
    place = np.arange(parts.sum()) - np.repeat(np.cumsum(parts) - parts, parts)
    positions = split_counts(np.repeat(span, parts) * place / np.repeat(parts, parts), parts)
    for i in np.flatnonzero(~short & ((first > unit) | (last > unit))).tolist():
        positions[i] = np.concatenate([[0.0], cleared_piece(0.0, span[i], first[i], last[i],
                                                            unit)])
    # the cleared corners (τ 0 and the span) with parts after and before them
    corners = np.column_stack([np.zeros(len(span)), span])
    cleared_after = split_counts(corners[after > unit], (after > unit).sum(axis=1))
    cleared_before = split_counts(corners[before > unit], (before > unit).sum(axis=1))
    return {c: (tau, at, clear) for c, tau, at, clear in
            zip(simple, taus, positions, zip(cleared_after, cleared_before))}


def _running_sums(values, lo, hi) -> list:
    """``[np.concatenate([[0.0], np.cumsum(values[a:b])]) for a, b in zip(lo, hi)]``,
    the same numbers: the runs of about one length (within a factor of two) as the rows
    of one array, summed along its rows in one call.

    >>> [run.tolist() for run in _running_sums(np.arange(6.0), np.array([0, 3]), np.array([3, 6]))]
    [[0.0, 0.0, 1.0, 3.0], [0.0, 3.0, 7.0, 12.0]]
    """
    length = hi - lo
    out = [None] * len(lo)
    size = np.ceil(np.log2(np.maximum(length, 1))).astype(np.int64)
    for s in np.unique(size).tolist():
        rows = np.flatnonzero(size == s)
        width = int(length[rows].max())
        place = np.arange(width)
        inside = place < length[rows, None]
        padded = np.zeros((len(rows), width + 1))
        padded[:, 1:][inside] = values[(lo[rows, None] + place)[inside]]
        sums = np.cumsum(padded, axis=1)
        for row, r in enumerate(rows.tolist()):
            out[r] = sums[row, :length[r] + 1]
    return out


def _first_reaches(taus, lo, hi, dense, radius, k, unit):
    """:func:`_chain_clearance`'s (after, before) of single-edge chains (their τ ``taus``,
    their dense points ``lo:hi``) at both ends, ``k`` their clearances: for each end whose
    k exceeds 1, where |p - c| first reaches 1.02 k r(p) (``graded_sampling.corner_leg``)
    walking from the end c along the edge and along the chord back, every walk in one
    pass, the same arithmetic element by element; ``unit`` elsewhere."""
    after, before = np.full((len(taus), 2), unit), np.full((len(taus), 2), unit)
    count = hi - lo
    first_end, last_end = np.flatnonzero(k[:, 0] > 1), np.flatnonzero(k[:, 1] > 1)
    if not len(first_end) and not len(last_end):
        return after, before
    m0, m1 = count[first_end], count[last_end]
    # the legs, four kinds (chain end, its table, start, walk, direction): from the first
    # end along the edge (after) and along the chord back (before); from the last end
    # along the chord back (after) and along the edge (before)
    kinds = [(first_end, 0, True, 0 * m0, _ranges(m0), 1.0),
             (first_end, 0, False, 0 * m0, np.column_stack([0 * m0, m0 - 1]).ravel(), -1.0),
             (last_end, 1, True, m1 - 1, np.column_stack([m1 - 1, 0 * m1]).ravel(), 1.0),
             (last_end, 1, False, m1 - 1, np.repeat(m1 - 1, m1) - _ranges(m1), -1.0)]
    ends, which, kind_after, starts, walks, ways = zip(*kinds)
    legs = [len(chains) for chains in ends]
    chain, start, walk = np.concatenate(ends), np.concatenate(starts), np.concatenate(walks)
    end, is_after, direction = (np.repeat(v, legs) for v in (which, kind_after, ways))
    sizes = np.concatenate([m0, np.full(len(m0), 2), np.full(len(m1), 2), m1])
    leg = np.repeat(np.arange(len(chain)), sizes)
    offsets = np.cumsum([0] + [len(tau) for tau in taus[:-1]])
    flat_tau = np.concatenate(taus)
    length = flat_tau[offsets + count]                 # each chain's τ, closed
    last = np.cumsum(sizes) - 1
    ends_walk = np.zeros(len(leg), bool)
    ends_walk[last] = True

    def position(i):
        """corner_side's τ from the corner at the walks' points ``i`` (a walk's last
        point at 0 is the whole chain round)."""
        c = chain[leg[i]]
        out = np.remainder(direction[leg[i]] * (flat_tau[offsets[c] + walk[i]]
                                                - flat_tau[offsets[c] + start[leg[i]]]),
                           length[c])
        return np.where(ends_walk[i] & (out == 0), length[c], out)

    # corner_leg's reach, leg by leg; τ only where it is read
    at = lo[chain][leg] + walk
    g = (np.hypot(*(dense[at] - dense[(lo[chain] + start)[leg]]).T)
         - (TAU_MARGIN * k[chain, end])[leg] * radius[at])
    first = last - sizes + 1
    local = np.arange(len(leg)) - first[leg]
    j = np.minimum.reduceat(np.where(g >= 0, local, len(leg)), first)
    found = np.flatnonzero(j < len(leg))
    value = position(last)                         # never reached: the whole walk
    b = first[found] + j[found]
    a = b - 1                                      # g < 0 at a walk's first point
    t = g[a] / (g[a] - g[b])
    reach = position(a) + t * (position(b) - position(a))
    value[found] = np.where(reach > unit, reach, unit)
    after[chain[is_after], end[is_after]] = value[is_after]
    before[chain[~is_after], end[~is_after]] = value[~is_after]
    return after, before


def _ranges(sizes) -> np.ndarray:
    """``np.arange(m)`` for each m of ``sizes``, one after another."""
    return np.arange(sizes.sum()) - np.repeat(np.cumsum(sizes) - sizes, sizes)


def _graded_chain(vertices, closed, sides, angle, dense, radius, segment, unit,
                  feature_angle, junction, rng):
    """One chain's τ along its dense points (an open chain closed by a chord back to its
    start), its samples' positions in τ (an open chain's last end excluded), and the
    positions of its corners whose clearance exceeds a unit (after, before): the parts
    beside them are kept whole (:func:`_halved`). See :func:`graded_sample_chains`."""
    n = len(vertices)
    ring = np.vstack([dense, dense[:1]])
    step = np.hypot(*np.diff(ring, axis=0).T)
    inverse = 1.0 / np.append(radius, radius[0])
    tau = np.concatenate([[0.0], np.cumsum(0.5 * step * (inverse[:-1] + inverse[1:]))])
    at_vertex = np.flatnonzero(np.append(True, segment[1:] != segment[:-1]))   # t == 0
    xy = dense[at_vertex]
    turns = turning_angles(xy) if closed else np.concatenate([[0.0], _open_turns(xy), [0.0]])
    corner_vertex = np.abs(turns) >= np.radians(feature_angle)
    turn = np.abs(turns)                                # the convex side's clearance
    for end in ([0] if closed else [0, n - 1]):
        if int(vertices[end]) in junction:
            neighbours = [vertices[(end + 1) % n] if closed or end == 0 else vertices[end - 1]]
            if closed:
                neighbours.append(vertices[-1])
            sharpest = min(_junction_angle(vertices[end], other, angle) for other in neighbours)
            corner_vertex[end] = True
            turn[end] = np.pi - sharpest
    corner = at_vertex[corner_vertex]
    corner_turn = turn[corner_vertex]
    if not closed and len(corner) == 2 and np.all(corner_clearance(np.pi - corner_turn, 1.0) <= 1):
        span = tau[corner[1]]                   # one piece, no clearance: equal parts
        parts = max(int(span // unit), 1)
        return tau, span * np.arange(parts) / parts, (np.zeros(0), np.zeros(0))
    after, before = _chain_clearance(dense, radius, tau, corner, corner_turn, unit)
    clear = (tau[corner][after > unit], tau[corner][before > unit])
    if closed:
        return tau, tau_positions(tau, tau[corner], after, before, unit, rng), clear
    pieces = [tau[corner[:-1]]]
    for i in range(len(corner) - 1):
        lo, span = tau[corner[i]], tau[corner[i + 1]] - tau[corner[i]]
        first, last = after[i], before[i + 1]
        if len(corner) == 2 and span < first + last:
            continue             # a chain of two junctions, too short for both clearances:
        if first > unit or last > unit:          # its ends alone (junction_fields)
            pieces.append(cleared_piece(lo, span, first, last, unit))
        else:
            parts = max(int(span // unit), 1)
            pieces.append(lo + span * np.arange(1, parts) / parts)
    return tau, np.sort(np.concatenate(pieces)), clear


def _chain_clearance(dense, radius, tau, corner, turn, unit):
    """The τ-lengths kept free of samples after and before each sharp corner of a chain,
    by the graded sampler's rule (``graded_sampling._corner_clearance``): the part from
    the corner c to its neighbour p ends where |p - c| first reaches 1.02 k r(p),
    k = ``corner_clearance(π - turn, 1)``, ``unit`` where k <= 1. Unlike the ring
    sampler, the legs are not shortened to keep a spike's tip triangle (which leaves the
    tip's neighbours closer than their clearance, a pair the certificate cannot
    explain): a patch whose tip chord the complex then drops is kept by
    :func:`pds_plugin.remesh` instead, its solid the same."""
    length = tau[-1]
    k = corner_clearance(np.pi - np.asarray(turn, float), 1.0)
    after, before = np.full(len(corner), unit), np.full(len(corner), unit)
    for c in np.flatnonzero(k > 1.0):
        for out, stop, step in ((after, corner[(c + 1) % len(corner)], 1),
                                (before, corner[c - 1], -1)):
            side = corner_side(dense, tau, corner[c], stop, step, length)
            leg = corner_leg(dense, radius, side, k[c])
            out[c] = side[1][-1] if leg is None else max(unit, leg[0])
    return after, before


def _halved(chain_set, flat, positions, cleared):
    """The positions with every part longer than :data:`_LONGEST_PART` times the smallest
    r at its ends and its middle halved in τ, again until none is (at most
    :data:`_MAX_HALVINGS` rounds; r dips between the ends where a cone of the agreeing
    fields sits on the part: random cut block 55's part 0.81 long had r 0.41 at its ends
    and 0.374 at its middle, 1.015 r from both ends, a sharp corner blocking its guard); a part that keeps a sharp corner's neighbour clear of it (``cleared``: per
    chain, the positions of such corners, parts after and parts before them) only when
    longer than that times the larger r (the neighbour's: r at the corner may be far
    smaller, and halving there would undo the clearance). All chains at once, their τ
    in ``flat`` (:class:`_FlatTau`); returns the chain of each position and the
    positions, by chain and increasing."""
    chain = np.repeat(np.arange(len(positions)), [len(at) for at in positions])
    at = np.concatenate(positions)
    # the guarded parts' ends as chain + 1j x position: exact keys for np.isin
    starts, stops = ([c + 1j * position for c, clear in enumerate(cleared)
                      for position in clear[side].tolist()] for side in (0, 1))
    todo = np.ones(len(positions), bool)
    for _ in range(_MAX_HALVINGS):
        pick = todo[chain]
        if not pick.any():
            break
        c_in, a_in = chain[pick], at[pick]
        last = np.flatnonzero(np.append(c_in[1:] != c_in[:-1], True))
        first = np.append(0, last[:-1] + 1)
        ids = c_in[last]
        end = np.where(chain_set.closed[ids], a_in[first] + flat.length[ids], flat.before_end[ids])
        c_e = np.insert(c_in, last + 1, ids)
        e = np.insert(a_in, last + 1, end)
        xy, radius = chain_set.evaluate(c_e, *flat.to_chain(c_e, e % flat.length[c_e]))
        pair = np.flatnonzero(c_e[1:] == c_e[:-1])
        chord = np.hypot(*(xy[pair + 1] - xy[pair]).T)
        low, high = (f(radius[pair], radius[pair + 1]) for f in (np.minimum, np.maximum))
        middle = (0.5 * (e[pair] + e[pair + 1])) % flat.length[c_e[pair]]
        low = np.minimum(low, chain_set.evaluate(c_e[pair], *flat.to_chain(c_e[pair], middle))[1])
        beside = (np.isin(c_e[pair] + 1j * e[pair], starts)
                  | np.isin(c_e[pair] + 1j * e[pair + 1], stops))
        long = chord > _LONGEST_PART * np.where(beside, high, low)
        todo = np.zeros(len(positions), bool)
        todo[c_e[pair[long]]] = True
        chain = np.concatenate([chain, c_e[pair[long]]])
        at = np.concatenate([at, middle[long]])
        order = np.lexsort((at, chain))
        chain, at = chain[order], at[order]
    return chain, at


class _FlatTau:
    """The τ of all chains' dense points in one array, to read positions in τ as
    (segment, fraction) along their chains all at once: linear in τ between the dense
    points, as ``boundary_sampling.along`` reads a ring's."""

    def __init__(self, taus, segment, t, bounds):
        self.tau = np.concatenate(taus)
        self.size = np.array([len(tau) for tau in taus], np.int64)
        self.start = np.cumsum(self.size) - self.size
        self.length = np.array([tau[-1] for tau in taus])
        self.before_end = np.array([tau[-2] for tau in taus])      # an open chain's last end
        self.segment, self.t, self.bounds = segment, t, bounds

    def to_chain(self, chain, at):
        """Positions ``at`` along chains ``chain`` as (segment, fraction) pairs."""
        # the last τ <= at in its chain: a binary search of all positions at once
        low, high = self.start[chain], self.start[chain] + self.size[chain]
        while (searching := low < high).any():
            middle = (low + high) // 2
            right = self.tau[np.minimum(middle, len(self.tau) - 1)] <= at
            low = np.where(searching & right, middle + 1, low)
            high = np.where(searching & ~right, middle, high)
        before = low - 1
        count = self.bounds[chain + 1] - self.bounds[chain]
        j = np.clip(before - self.start[chain], 0, count - 1)
        k = self.start[chain] + j
        frac = (at - self.tau[k]) / np.maximum(self.tau[k + 1] - self.tau[k], 1e-300)
        here = self.bounds[chain] + j
        following = self.bounds[chain] + (j + 1) % count
        t_next = np.where(self.segment[following] == self.segment[here], self.t[following], 1.0)
        s = np.clip(self.t[here] + frac * (t_next - self.t[here]), 0.0, 1.0)
        return self.segment[here], np.where(frac > 0, s, self.t[here])


_LONGEST_PART = 2.0
"""A chain's part longer than this many times the smaller r at its ends is halved (in
τ): where r grows fast along it (beside a short edge between pinned vertices) a part of
less than two units of τ can still be 2.9 r long, and the graded sampler, which keeps
samples out of a chord's lens, cannot cover beside it."""

_MAX_HALVINGS = 8


def _junction_angle(vertex, neighbour, angle) -> float:
    """The sharpest angle a region running the edge (vertex, neighbour) has at ``vertex``."""
    angles = []
    for a, b, at_start in ((vertex, neighbour, True), (neighbour, vertex, False)):
        entry = angle.get((int(a), int(b)))
        if entry is not None:
            angles.append(float(entry[1] if at_start else entry[2]))
    return min(angles)


def junction_fields(rings, frames, fields, pinned=(), *, topology=None) -> list:
    """The regions' fields made to agree at the junctions of their chains (vertices
    that must be samples: where the owners change, or ``pinned``), before
    :func:`graded_sample_chains`.

    At a junction v, r(v) becomes, in every region that has v, the smallest of: the
    fields of those regions at v, and the distance from v to the other end w of each
    chain leaving it over 1.02 k(w), k(w) >= 1 the clearance factor of the sharpest
    corner a region has at w (``corner_clearance``): the ends of a chain too short to
    be cut are consecutive samples, so r there must not exceed their distance, and v is
    then w's neighbour, which must be clear of w's corner: a cone of that size at v is
    added to each of their fields. The samples beside
    a short edge then grade away from it instead of meeting it at the full radius, and
    every chain leaving v starts from the same r (a chord many times r at one end
    leaves the graded sampler no room to cover beside it).

    Returns
    -------
    list of RadiusField
        Per region, its field with the junctions' cones.

    Examples
    --------
    >>> from pds_plugin.sizing import RadiusField
    >>> xy = np.array([[0, 0], [1, 0], [1.01, 0], [2, 0], [2, 1], [0, 1]], float)
    >>> field = RadiusField(np.zeros((0, 2)), [], grading=0.2, cap=0.5)
    >>> [f(xy).round(3).tolist() for f in junction_fields([[np.arange(6)]], [xy], [field],
    ...                                                   pinned=[1, 2])]
    [[0.21, 0.01, 0.01, 0.208, 0.291, 0.293]]
    """
    top = topology if topology is not None else _Topology(rings, frames, pinned)
    rings, owner, junctions = top.rings, top.owner, top.junction
    junction = np.array(sorted(junctions), dtype=np.int64)
    size = np.full(len(junction), np.inf)
    # per region, its junctions (indices into ``junction``) and where they are, all
    # regions at once: (region, vertex) pairs, each once, by region then vertex
    counts = [sum(len(ring) for ring in region) for region in rings]
    vertex = np.concatenate([ring for region in rings for ring in region] + [junction[:0]])
    span = int(max(vertex.max(initial=0), junction.max(initial=0))) + 1
    pairs = np.unique(np.repeat(np.arange(len(rings)), counts) * span + vertex)
    pairs = pairs[np.isin(pairs % span, junction)]
    mine = split_counts(pairs % span, np.bincount(pairs // span, minlength=len(rings)))
    held = split_counts(np.searchsorted(junction, pairs % span), [len(ids) for ids in mine])
    at = split_counts(read_regions(frames, mine), [len(ids) for ids in mine])
    # one read of a few points a region: a call each costs less than the layout
    # field's cone tree over all their features (built for the chains' many reads)
    for r, (index, xy) in enumerate(zip(held, at)):
        np.minimum.at(size, index, fields[r](xy))
    # each open chain: its ends' distance (in its first owner's frame) over the
    # clearance of the other end, all chains at once
    chains = [vertices for vertices, closed in top.chains if not closed]
    if chains:
        ends = np.array([[vertices[0], vertices[-1]] for vertices in chains], dtype=np.int64)
        region = np.array([owner[_key(vertices[0], vertices[1])][0] for vertices in chains])
        xy = read_frames(frames, np.repeat(region, 2), ends.ravel()).reshape(-1, 2, 2)
        apart = np.array([math.hypot(*d) for d in (xy[:, 1] - xy[:, 0]).tolist()])
        beside = np.array([[vertices[1], vertices[-2]] for vertices in chains], dtype=np.int64)
        clearance = np.maximum(1.0, _end_clearances(ends.T.ravel(), beside.T.ravel(),
                                                    top.edge_angles)).reshape(2, -1)
        np.minimum.at(size, np.searchsorted(junction, ends[:, 0]),
                      apart / (TAU_MARGIN * clearance[1]))
        np.minimum.at(size, np.searchsorted(junction, ends[:, 1]),
                      apart / (TAU_MARGIN * clearance[0]))
    return fields_with_cones(fields, at, [size[index] for index in held])


def agreeing_fields(rings, frames, fields, pinned=(), *, topology=None) -> list:
    """The regions' fields lowered until the regions that share a chain read the same r
    along it, before :func:`graded_sample_chains` (regions in planes of their own, each
    with its field: the patches of :func:`pds_plugin.remesh`).

    A chain is cut with the smallest of its owners' fields, and each region is meshed
    with its own field combined by min with cones at all its chain samples
    (:func:`chain_sample_radii`). Where a neighbour's field is the smaller on one chain
    of a region, those cones lower the region's field on its other chains too, below
    the r they were cut with: a chord there is then longer than twice the region's r,
    beside it the graded sampler places no sample (the chord's lens), and the point of
    the chord between its ends is left uncovered (random cut block 6: a strip whose
    lower chain's neighbour is fine, its upper chain cut at alpha). So, at the chains'
    dense points (spacing at most 0.3 r, as the chain sampler's), each owner whose
    field is above the smallest of the owners' gets a cone of that value there, again
    until no owner is above (each round carries a lowering across one region). A
    chain's points lie on both of its owners' boundaries, so the cone is the same
    distance function in both planes along it. Fields that already agree are returned
    as they are.

    Returns
    -------
    list of RadiusField
        Per region, its field (the same object where nothing was lowered).

    Examples
    --------
    >>> from pds_plugin.sizing import RadiusField
    >>> xy = np.array([[0, 0], [1, 0], [2, 0], [2, 1], [1, 1], [0, 1]], float)
    >>> left, right = [np.array([0, 1, 4, 5])], [np.array([1, 2, 3, 4])]
    >>> fine = RadiusField([[0.5, 0.5]], [0.05], grading=0.2, cap=0.4)
    >>> coarse = RadiusField(np.zeros((0, 2)), [], grading=0.2, cap=0.4)
    >>> a, b = agreeing_fields([left, right], [xy, xy], [fine, coarse])
    >>> edge = np.column_stack([np.ones(5), np.linspace(0, 1, 5)])     # the shared chain
    >>> bool(np.allclose(a(edge), b(edge), rtol=0.02)), a is fine
    (True, True)
    """
    top = topology if topology is not None else _Topology(rings, frames, pinned)
    chains, sides = top.chains, top.sides
    shared = [c for c, s in enumerate(sides) if len(s) == 2]
    fields = list(fields)
    grading = max(field.grading for field in fields) if fields else 0.0
    todo = shared
    for _ in range(_AGREEMENT_ROUNDS):
        if not todo:
            break
        chain_set = _ChainSet([chains[c] for c in todo], [sides[c] for c in todo], frames,
                              fields)                   # dense_reads only: no union
        cid, segment, t, reads = chain_set.dense_reads(grading)
        lowest = np.minimum(reads[0][1], reads[1][1])
        lowered = set()
        for side, (xy, radius) in enumerate(reads):
            above = radius > lowest * (1 + _AGREEMENT_TOL)
            for r, at in _groups(np.where(above, chain_set.side[cid, side], -1)):
                fields[r] = with_sample_cones(fields[r], xy[at], lowest[at])
                lowered.add(r)
        todo = [c for c in shared if lowered.intersection(sides[c])]
    return fields


_AGREEMENT_ROUNDS = 16
"""Rounds of :func:`agreeing_fields` at most: a lowering reaches at most (cap - r) / L
beyond its chain, a few regions."""

_AGREEMENT_TOL = 1e-9
"""Relative differences of the owners' r below this are rounding (the same point read
in two planes), not a lowering."""


def chain_sample_radii(chains: ChainSamples, frames, fields, *, topology=None,
                       points=None) -> np.ndarray:
    """The radius each region's field is given at each chain sample so that the regions
    agree on their shared samples and keep them separated: at a sample s, the smallest
    of the fields (after :func:`junction_fields`) of the regions whose rings hold it;
    where two neighbours along those rings, or the two neighbours of a sample at a
    corner of at least the ladder angle (33.56°; a sharper spike's pairs are the
    certificate's exceptions, as in uniform meshes), are closer than both their radii (a part where r dips below its ends', a part halved
    beside a sharp corner), the smaller radius is lowered to their distance, which
    separates them and leaves the larger (a junction's, which other chains were cut
    for) as it was.

    A region's own field combined by min with cones of these sizes at its samples
    (:func:`with_sample_cones`) equals them at every sample (a minimum of L-Lipschitz
    fields is L-Lipschitz, so no cone undercuts another's sample), whichever region it
    is read in.

    ``points``: per region, its rings' samples read in its frame (:meth:`ChainSamples.
    regions_points`), if already read.

    Returns
    -------
    (S,) float ndarray
    """
    size = np.full(len(chains.u), np.inf)
    held = chains.region_samples
    if points is None:
        points = chains.regions_points(frames)
    union = None if topology is None else topology.layout_field(frames, fields)
    if union is not None and held:              # all regions' fields in one call
        np.minimum.at(size, np.concatenate(held), union(np.concatenate(points)))
    else:
        for r, (ids, xy) in enumerate(zip(held, points)):
            np.minimum.at(size, ids, fields[r](xy))
    radius = size.copy()
    # every ring of every region at once: each sample's next and next but one along
    # its ring (the same arithmetic, element by element, as ring by ring)
    rings = [ids for ring_ids in chains.rings for ids in ring_ids]
    if not rings:
        return size
    ids = np.concatenate(rings)
    p = np.concatenate(points)
    count = np.array([len(ring) for ring in rings])
    start = np.repeat(np.cumsum(count) - count, count)
    place = np.arange(len(ids)) - start
    length = np.repeat(count, count)
    after = [start + (place + step) % length for step in (0, 1, 2)]
    for step in (1, 2):                    # neighbours, and the two of a corner
        following = ids[after[step]]
        gap = np.hypot(*(p[after[step]] - p).T)
        close = gap < np.minimum(radius[ids], radius[following])
        if step == 2:                      # not across a spike (its pairs are exceptions)
            a, b = p - p[after[1]], p[after[2]] - p[after[1]]
            corner = np.arctan2(np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]),
                                (a * b).sum(axis=1))
            close &= corner >= LADDER_ANGLE
        lower = np.where(radius[ids] <= radius[following], ids, following)
        np.minimum.at(size, lower[close], gap[close])
    return size


def with_sample_cones(field, points, sizes):
    """``field`` combined by min with the cones ``sizes + L |x - points|`` (a
    :class:`~pds_plugin.sizing.RadiusField` of the same grading, cap and sizing)."""
    return field.with_cones(points, sizes)


def fields_with_cones(fields, points, sizes) -> list:
    """:func:`with_sample_cones` of each field with its points and sizes; a field given
    no cone below its cap (most fields of a remesh) is itself, found for all at once
    instead of call by call."""
    counts = [len(s) for s in sizes]
    below = np.concatenate([np.zeros(0), *sizes]) < np.repeat([f.cap for f in fields], counts)
    lowered = np.bincount(np.repeat(np.arange(len(fields)), counts), below,
                          minlength=len(fields)) > 0
    return [with_sample_cones(field, xy, size) if lower else field
            for field, xy, size, lower in zip(fields, points, sizes, lowered.tolist())]


class _Topology:
    """What :func:`junction_fields`, :func:`agreeing_fields`, :func:`graded_sample_chains`
    and :func:`chain_sample_radii` each found from the same rings, frames and pinned
    vertices (the edges' owners and angles, the junctions, the chains and their sides),
    found once (:func:`partition_topology`); and whether the regions' frames lie apart
    in one plane (:meth:`layout_field`)."""

    def __init__(self, rings, frames, pinned=()):
        self.rings = [[np.asarray(ring, dtype=np.int64) for ring in region] for region in rings]
        self.owner, self.angle, self.edge_angles = _edge_owners(self.rings, frames)
        self.junction = _junctions(self.owner, pinned)
        self.chains = _chains(self.rings, self.owner, self.junction)
        self.sides = _sides(self.owner, self.chains)
        self._frames = frames
        self._boxes = None
        self._union = None

    def boxes(self) -> np.ndarray:
        """Per region, the bounding box (xmin, ymin, xmax, ymax) of its rings' vertices
        in its frame."""
        if self._boxes is None:
            ids = [np.concatenate(region) for region in self.rings]
            xy = read_regions(self._frames, ids)
            counts = [len(region) for region in ids]
            first = np.cumsum(counts) - counts
            self._boxes = np.column_stack([np.minimum.reduceat(xy, first),
                                           np.maximum.reduceat(xy, first)])
        return self._boxes

    def layout_field(self, frames, fields):
        """One field (:class:`_Cones`) that reads, at every point of
        each region's bounding box, exactly what that region's own field reads there,
        or None when the regions' frames do not allow it.

        It is the union of the fields' cones, for fields of one grading L and cap and no
        sizing whose features lie in their regions' boxes, when every two boxes lie
        more than 1.125 cap / L apart (remeshing's layout: 1.25 cap / L at least).
        Then a cone s + L d of another region's feature (s > 0) is above the cap at
        every point of a region's box, so the union's minimum, capped, is the region's
        own, bit for bit (the cone minimum is exact; a cone the union finds dominated
        by another region's has s above the cap). Read only points in their own
        region's box: its chains' points, its samples."""
        if frames is not self._frames or len(fields) < 2:
            return None
        key = tuple(map(id, fields))
        if self._union is not None and self._union[0] == key:
            return self._union[2]                   # the same fields (kept alive in [1])
        first = fields[0]
        if not (0.0 < first.grading < 1.0) or any(
                f.sizing is not None or f.grading != first.grading or f.cap != first.cap
                for f in fields):
            return None
        boxes = self.boxes()
        if not hasattr(self, "_apart"):
            self._apart = _apart(boxes, 1.125 * first.cap / first.grading)
        if not self._apart:
            return None
        count = [len(f.sizes) for f in fields]
        features = np.concatenate([f.features for f in fields]).reshape(-1, 2)
        box = np.repeat(boxes, count, axis=0)
        if not np.all((features >= box[:, :2]) & (features <= box[:, 2:])):
            return None
        union = _Cones(features, np.concatenate([f.sizes for f in fields]), first.grading,
                       first.cap)
        self._union = (key, list(fields), union)
        return union


class _Cones:
    """min(cap, min_i(s_i + L|x - f_i|)) at points (n, 2): what a
    :class:`~pds_plugin.sizing.RadiusField` without sizing reads (the same exact cone
    minimum), without its test for dominated cones (the union of many regions'
    fields, :meth:`_Topology.layout_field`: each region's cones were tested in its own
    field; the test over all of them cost more than the reads it serves)."""

    sizing = None                   # as a RadiusField without sizing (_graded_kernels.Field)

    def __init__(self, features, sizes, grading, cap):
        self.features = np.ascontiguousarray(features, dtype=np.float64).reshape(-1, 2)
        self.sizes = np.ascontiguousarray(sizes, dtype=np.float64)
        self.grading, self.cap = float(grading), float(cap)
        self._tree = (_sizing_kernels.build_cone_tree(self.features, self.sizes, 8)
                      if len(self.sizes) else None)

    def __call__(self, points) -> np.ndarray:
        points = np.ascontiguousarray(np.asarray(points, dtype=np.float64).reshape(-1, 2))
        if self._tree is None or not len(points):
            return np.full(len(points), self.cap)
        return _sizing_kernels.cone_minimum(points, self.features, self.sizes, self.grading,
                                            self.cap, *self._tree)


def partition_topology(rings, frames, pinned=()):
    """The edges' owners, junctions and chains of regions that share chains (as
    :func:`graded_sample_chains` finds them), to pass as ``topology=`` to it and to
    :func:`junction_fields`, :func:`agreeing_fields` and :func:`chain_sample_radii` of
    the same ``rings``, ``frames`` (the same object) and ``pinned``: found once, and
    the regions' fields read in one call where their frames lie apart in one plane.

    Raises
    ------
    RegionError
        As :func:`sample_chains`.
    """
    return _Topology(rings, frames, pinned)


def _key(a, b):
    return (int(a), int(b)) if a < b else (int(b), int(a))


def _edge_owners(rings, frames):
    """Per undirected edge: the regions that run it; per directed edge: its region and
    that region's interior angles at the edge's start and end, as a dict and as an
    :class:`_EdgeAngles` table."""
    every = [(r, ring) for r, region in enumerate(rings) for ring in region]
    if not every:
        return {}, {}, _EdgeAngles(*[np.zeros(0, np.int64)] * 2, *[np.zeros(0)] * 2)
    counts = [len(ring) for _, ring in every]
    vertices = np.concatenate([ring for _, ring in every])
    region = np.repeat([r for r, _ in every], counts)
    xy = read_frames(frames, region, vertices)
    # the region's angle at each vertex, all rings at once
    inside = np.pi - turning_angles(xy, counts)
    following = _following(counts)
    tails = vertices[following]
    table = _EdgeAngles(vertices, tails, inside, inside[following])
    # no edge run twice the same way, so at most twice: each undirected edge's runs, in
    # the rings' order
    low, high = np.minimum(vertices, tails), np.maximum(vertices, tails)
    span = int(high.max()) + 1
    if len(np.unique(vertices * span + tails)) < len(vertices):
        _refuse_overlap(vertices, tails, region)
    code = low * span + high
    order = np.argsort(code, kind="stable")
    key = code[order]
    first = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    runs = np.diff(np.r_[first, len(key)])
    first_run, second_run = order[first], order[np.minimum(first + 1, len(order) - 1)]
    by_appearance = np.argsort(first_run)
    ones = region[first_run[by_appearance]].tolist()
    twos = np.where(runs == 2, region[second_run], -1)[by_appearance].tolist()
    owner = dict(zip(zip(low[first_run[by_appearance]].tolist(),
                         high[first_run[by_appearance]].tolist()),
                     [[a] if b < 0 else [a, b] for a, b in zip(ones, twos)]))
    angle = dict(zip(zip(vertices.tolist(), tails.tolist()),
                     zip(region.tolist(), inside, inside[following])))
    return owner, angle, table


def _refuse_overlap(heads, tails, region):
    """Raise the error of the first edge, in the rings' order, that a region runs the
    same way as another: they overlap along it."""
    way = {}
    for a, b, r in zip(heads.tolist(), tails.tolist(), region.tolist()):
        if (a, b) in way:
            raise RegionError(f"regions {way[(a, b)]} and {r} overlap along the edge of "
                              f"vertices {a} and {b} (both run it the same way)")
        way[(a, b)] = r


class _EdgeTable:
    """Directed edges (start, end) of vertex numbers, sorted to be found many at a time;
    of an edge given twice, the later one is found."""

    def __init__(self, start, end):
        start, end = np.asarray(start, np.int64), np.asarray(end, np.int64)
        self.span = int(max(start.max(initial=0), end.max(initial=0))) + 1
        codes = start * self.span + end
        order = np.argsort(codes, kind="stable")
        last = np.append(codes[order][1:] != codes[order][:-1], True)[:len(order)]
        self.codes, self.index = codes[order][last], order[last]

    def find(self, start, end) -> np.ndarray:
        """The index (among the edges given) of each edge (start[k], end[k]), -1 where
        there is none."""
        start, end = np.asarray(start, np.int64), np.asarray(end, np.int64)
        wanted = start * self.span + end
        if not len(self.codes):
            return np.full(len(wanted), -1)
        at = np.minimum(self.codes.searchsorted(wanted), len(self.codes) - 1)
        found = (self.codes[at] == wanted) & (start < self.span) & (end < self.span)
        return np.where(found, self.index[at], -1)


class _EdgeAngles:
    """Every directed edge of the rings with its region's interior angles at its start
    and end (:func:`_edge_owners`' ``angle``), to look many edges up at once."""

    def __init__(self, start, end, at_start, at_end):
        self.edges, self.at_start, self.at_end = _EdgeTable(start, end), at_start, at_end

    def at(self, vertex, neighbour) -> tuple[np.ndarray, np.ndarray]:
        """The angles at ``vertex`` of the regions that run each edge (vertex,
        neighbour): the one running it from ``vertex`` and the one running it back (NaN
        where no region does)."""
        forward, back = self.edges.find(vertex, neighbour), self.edges.find(neighbour, vertex)
        return (np.where(forward >= 0, self.at_start[forward], np.nan),
                np.where(back >= 0, self.at_end[back], np.nan))

    def sharpest(self, vertex, neighbour) -> np.ndarray:
        """:func:`_junction_angle` of every (vertex, neighbour) pair."""
        return np.fmin(*self.at(vertex, neighbour))


def _junctions(owner, pinned) -> set:
    """Vertices that end chains: pinned ones, those with other than two edges, and those
    where the owners of the edges change."""
    edges_at = {}
    for key in owner:
        for vertex in key:
            edges_at.setdefault(vertex, []).append(key)
    junction = {int(v) for v in pinned}
    for vertex, keys in edges_at.items():
        if len(keys) != 2 or sorted(owner[keys[0]]) != sorted(owner[keys[1]]):
            junction.add(vertex)
    return junction


def _chains(rings, owner, junction):
    """The chains, as (vertices, closed), in the order the rings run them: each starts
    at a junction (or is a whole ring without one) and follows the first region that
    runs it."""
    chains, done = [], set()
    for region in rings:
        for ring in region:
            ring = ring.tolist()
            n = len(ring)
            starts = [k for k, vertex in enumerate(ring) if vertex in junction]
            if not starts:
                if _key(ring[0], ring[1]) not in done:
                    done.update(_key(ring[k], ring[(k + 1) % n]) for k in range(n))
                    chains.append((np.array(ring, np.int64), True))
                continue
            for start in starts:
                if _key(ring[start], ring[(start + 1) % n]) in done:
                    continue
                vertices = [ring[start]]
                k = start
                while True:
                    done.add(_key(ring[k], ring[(k + 1) % n]))
                    k = (k + 1) % n
                    vertices.append(ring[k])
                    if ring[k] in junction:
                        break
                if vertices[0] == vertices[-1] and len(vertices) > 2 and len(starts) == 1:
                    chains.append((np.array(vertices[:-1], np.int64), True))   # a loop at a junction
                else:
                    chains.append((np.array(vertices, np.int64), False))
    return chains


def _chain_positions(chains, owner, angle, frames, alpha, feature_angle, seed, junction,
                     spikes=()):
    """Per chain, its samples as (segment, fraction) pairs along it, read in the frame of
    the first region that runs it (an open chain's last end excluded).

    Each chain draws from its own random generator, seeded by ``seed`` and its end
    vertices, so that its samples do not depend on the other chains (a patch dropped
    by :func:`pds_plugin.remesh` leaves the others' samples as they were). Straight open
    chains (the faces of a solid meet in straight lines) are cut by ``split_gaps``
    directly, then the two straight chains of each spike at a junction (``spikes``) are
    sampled in mirror pairs (:func:`_junction_ladder`); the others go through the
    conforming sampler's own ring rule (``ring_positions``, :func:`_bent_chain`), which
    makes the ladders of their own spikes."""
    out, straight = [], {}
    cap = float(corner_clearance(0.0, alpha))
    for c, (vertices, closed) in enumerate(chains):
        xy = frames[owner[_key(vertices[0], vertices[1])][0]][vertices]
        if closed:
            # a ring without junction, or a loop that leaves a junction and comes back
            ends = None if int(vertices[0]) not in junction else [max(
                _end_clearance(vertices[0], vertices[1], angle),
                _end_clearance(vertices[0], vertices[-1], angle))] * 2
        else:
            ends = [_end_clearance(vertices[0], vertices[1], angle),
                    _end_clearance(vertices[-1], vertices[-2], angle)]
        if closed or not _is_straight(xy):
            out.append(_bent_chain(xy, closed, ends, alpha, feature_angle, _chain_rng(seed, vertices)))
            continue
        cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])
        at = np.zeros(1)
        if cum[-1] >= 2 * alpha:          # else no room for two parts: nothing drawn
            first, last = (min(max(end * alpha, alpha), cap) for end in ends)
            u = _chain_rng(seed, vertices).random(int(cum[-1] // alpha) + 1)
            inner, _ = kern.split_gaps(np.zeros(1), cum[-1:], [first], [last], [alpha],
                                       math.sqrt(3) * alpha, u)
            at = np.concatenate([[0.0], np.sort(inner)])
        straight[c] = [at, cum, [min(max(end * alpha, alpha), cap) for end in ends]]
        out.append(None)
    along = _ChainEdges(chains)
    for spike in spikes:
        _junction_ladder(spike, along, chains, straight, alpha, seed)
    for c, (at, cum, _) in straight.items():
        out[c] = _segments_of(at, cum)
    return out


def _junction_ladder(spike, along, chains, straight, alpha, seed):
    """Sample the two straight chains of a spike whose tip is a junction in mirror pairs
    (the conforming sampler's ladders, ``sampling._ladders``): the shorter side's samples
    within the spike's reach alpha / (2 sin(θ/2)) (and its far end, if the spike is still
    thinner than alpha there, the end at least the tip's clearance from it, and the longer
    side goes on for alpha or more) are copied to
    the longer side at the same distance from the tip, and the longer side is cut again
    beyond the last copy. Mirrored samples are a part's length apart like the ones they
    copy, so every region running the longer chain keeps its parts in [alpha, √3 alpha]."""
    vertex, before, after, theta = spike
    sides = []
    for neighbour in (after, before):
        c, forward = along[(vertex, neighbour)]
        if c not in straight:
            return                                   # a bent side: no ladder
        at, cum, _ = straight[c]
        length = cum[-1]
        offsets = at[1:] if forward else np.sort(length - at[1:])
        sides.append((c, forward, length, offsets))
    if sides[0][0] == sides[1][0]:
        return
    short, long = sorted(sides, key=lambda side: side[2])
    reach = alpha / (2 * math.sin(max(theta, 1e-300) / 2))
    mirrored = short[3][short[3] < min(reach, short[2])]
    # the short side's far corner is mirrored too when at least the tip's clearance
    # from it (a copy closer to the tip would be a pair no small feature explains)
    if (float(corner_clearance(theta, alpha)) <= short[2] <= reach
            and long[2] - short[2] >= alpha):
        mirrored = np.append(mirrored, short[2])
    while len(mirrored) and long[2] - mirrored[-1] < alpha:
        mirrored = mirrored[:-1]                    # leave the long side a last part
    if not len(mirrored):
        return
    c, forward, length, _ = long
    far = straight[c][2][1 if forward else 0]
    vertices = chains[c][0]
    u = _chain_rng(seed + 1, vertices).random(int((length - mirrored[-1]) // alpha) + 1)
    split, _ = kern.split_gaps([mirrored[-1]], [length], [alpha], [far], [alpha],
                               math.sqrt(3) * alpha, u)
    offsets = np.sort(np.concatenate([mirrored, split]))
    inner = offsets if forward else np.sort(length - offsets)
    straight[c][0] = np.concatenate([[0.0], inner])


class _ChainEdges:
    """Per directed edge of the chains: (chain, whether the chain runs it that way),
    looked up for many edges at once (:meth:`read`) or one (``edges[a, b]``); an edge a
    chain runs both ways (a closed chain of two vertices) is run backwards."""

    def __init__(self, chains):
        sizes = [len(vertices) for vertices, _ in chains]
        heads = np.concatenate([vertices for vertices, _ in chains]
                               + [np.zeros(0, np.int64)]).astype(np.int64)
        chain = np.repeat(np.arange(len(chains)), sizes)
        edge = np.ones(len(heads), bool)          # an open chain's last vertex starts none
        edge[(np.cumsum(sizes) - 1)[[not closed for _, closed in chains]]] = False
        tails = heads[_following(sizes)][edge] if len(heads) else heads
        heads, chain = heads[edge], chain[edge]
        # forward, then backward: the later is found where a chain runs an edge both ways
        self.edges = _EdgeTable(np.concatenate([heads, tails]), np.concatenate([tails, heads]))
        self.chain = np.concatenate([chain, chain])
        self.forward = np.arange(2 * len(heads)) < len(heads)

    def read(self, heads, tails) -> tuple[np.ndarray, np.ndarray]:
        """The chain and direction of each edge (heads[k], tails[k]) (a chain's)."""
        at = self.edges.find(heads, tails)
        return self.chain[at], self.forward[at]

    def __getitem__(self, edge) -> tuple[int, bool]:
        at = int(self.edges.find([edge[0]], [edge[1]])[0])
        if at < 0:
            raise KeyError(edge)
        return int(self.chain[at]), bool(self.forward[at])


def _spikes(rings, frames, junction) -> list:
    """(tip, vertex before, vertex after, angle) of every corner of a region sharper than
    the sampler's ladder angle (33.56°) whose tip is a junction."""
    out = []
    for r, region in enumerate(rings):
        for ring in region:
            inner = np.pi - turning_angles(frames[r][ring])
            for k in np.flatnonzero(inner < LADDER_ANGLE).tolist():
                if int(ring[k]) in junction:
                    out.append((int(ring[k]), int(ring[k - 1]), int(ring[(k + 1) % len(ring)]),
                                float(inner[k])))
    return out


def _chain_rng(seed, vertices):
    """The random generator of one chain: seeded by ``seed`` and the chain's ends."""
    return np.random.default_rng([seed, int(vertices[0]), int(vertices[1]), int(vertices[-1])])


def _end_clearance(vertex, neighbour, angle) -> float:
    """The first part's lower bound beside a junction, / alpha: the clearance of the
    sharpest corner that a region running the chain's end segment has there."""
    clearances = []
    for a, b, at_start in ((vertex, neighbour, True), (neighbour, vertex, False)):
        entry = angle.get((int(a), int(b)))
        if entry is not None:
            clearances.append(float(corner_clearance(entry[1] if at_start else entry[2], 1.0)))
    return max(clearances)


def _end_clearances(vertex, neighbour, table) -> np.ndarray:
    """:func:`_end_clearance` of every (vertex, neighbour) pair, looked up in the
    :class:`_EdgeAngles` ``table`` (-inf where no region runs the edge)."""
    out = np.full(len(vertex), -np.inf)
    for angles in table.at(vertex, neighbour):
        found = ~np.isnan(angles)
        out[found] = np.maximum(out[found], corner_clearance(angles[found], 1.0))
    return out


def _is_straight(xy) -> bool:
    """Every interior vertex of the polyline turns by at most the straight turn."""
    return bool(np.all(np.abs(_open_turns(xy)) <= STRAIGHT_TURN))


def _open_turns(xy) -> np.ndarray:
    """The signed turns at the interior vertices of an open polyline."""
    d = np.diff(xy, axis=0)
    cross = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]
    return np.arctan2(cross, (d[:-1] * d[1:]).sum(axis=1))


def _segments_of(at, cum):
    """Arc positions ``at`` along a polyline of cumulative lengths ``cum`` as
    (segment, fraction) pairs."""
    k = np.clip(np.searchsorted(cum, at, side="right") - 1, 0, len(cum) - 2)
    span = cum[k + 1] - cum[k]
    t = np.where(span > 0, (at - cum[k]) / np.where(span > 0, span, 1.0), 0.0)
    return k, np.clip(t, 0.0, 1.0)


def _bent_chain(xy, closed, ends, alpha, feature_angle, rng):
    """Sample positions of a chain that bends, by the conforming sampler's
    ``ring_positions``: a closed chain as the ring it is, an open one closed by a
    detour of two points 4 alpha off its chord (turns there count as straight; the
    detour's samples are dropped). Sharp vertices get their turn made positive, so that
    their clearance is the convex side's, ``corner_clearance(pi - |turn|)``; a junction
    becomes a corner whose turn pi - A gives the junction's clearance
    (``corner_clearance(A)``, :func:`_angle_of_clearance`). Only sharp vertices use the
    turn's sign for the clearance, none for the inflections."""
    n = len(xy)
    floor = np.radians(feature_angle)
    if closed:
        ring, turns = xy, turning_angles(xy)
    else:
        chord = xy[-1] - xy[0]
        size = math.hypot(*chord)
        normal = np.array([-chord[1], chord[0]]) / size if size > 0 else np.array([0.0, 1.0])
        ring = np.vstack([xy, xy[-1] + 4 * alpha * normal, xy[0] + 4 * alpha * normal])
        turns = np.zeros(n + 2)
        turns[1:n - 1] = _open_turns(xy)
    sharp = np.abs(turns) >= floor
    turns[sharp] = np.abs(turns[sharp])
    if ends is not None:
        turns[0] = np.pi - _angle_of_clearance(ends[0], floor)
        if not closed:
            turns[n - 1] = np.pi - _angle_of_clearance(ends[1], floor)
    at, cum, _ = ring_positions(ring, turns, feature_angle, alpha, rng)
    if not closed:
        at = at[at < cum[n - 1] * (1 - 1e-12)]
    return _segments_of(at, cum[:n + 1] if closed else cum[:n])


def _angle_of_clearance(clearance, floor) -> float:
    """The corner angle A whose ``corner_clearance(A)`` (/ alpha) is ``clearance``, at
    most pi - ``floor`` so that a junction counts as a sharp corner."""
    if clearance <= 1.0:
        return min(np.pi / 2, np.pi - floor)
    return min(2 * math.asin(min(1.0, 1 / (2 * clearance))), np.pi - floor)


def _ring_samples(rings, chains, chain_samples):
    """Per region, per ring, the sample numbers along it, from the chains it runs (in
    the ring's direction; a closed chain is the whole ring, in cyclic order), starting
    where an open chain starts (each ring edge's chain looked up at once). Rings whose
    chains follow each other edge for edge from those starts (every ring met so far, a
    ring through a vertex twice too) are read in one pass; any other is walked chain by
    chain (:func:`_ring_walk`), as every ring was before."""
    every = [ring for region in rings for ring in region]
    if not every:
        return [[] for _ in rings]
    counts = [len(ring) for ring in every]
    heads = np.concatenate(every)
    chain, forward = _ChainEdges(chains).read(heads, heads[_following(counts)])
    first = np.array([vertices[0] for vertices, _ in chains], np.int64)
    last = np.array([vertices[-1] for vertices, _ in chains], np.int64)
    closed = np.array([closed for _, closed in chains], bool)
    starts = ~closed[chain] & (heads == np.where(forward, first[chain], last[chain]))
    # the pieces: an open chain at each start, a ring without one a chain from its first
    # edge; a ring is read so if its pieces follow each other edge for edge round it
    ring = np.repeat(np.arange(len(every)), counts)
    ring_first = np.cumsum(counts) - counts
    lonely = np.bincount(ring, starts, minlength=len(every)) == 0
    piece = np.flatnonzero(starts | (lonely[ring] & (np.arange(len(heads)) == ring_first[ring])))
    c, ahead = chain[piece], forward[piece]
    span = np.array([len(vertices) for vertices, _ in chains])[c] - ~closed[c]
    next_piece = np.append(piece[1:], -1)         # a ring's last piece has none
    follows = (next_piece == piece + span) | (ring[next_piece] != ring[piece])
    follows[-1] = True
    tiled = ((np.bincount(ring[piece], span, minlength=len(every)) == counts)
             & (np.bincount(ring[piece], ~follows, minlength=len(every)) == 0))
    # each piece's samples, forward or back, an open chain's far end left to the next
    samples = np.concatenate(chain_samples).astype(np.int64)
    size = np.array([len(numbers) for numbers in chain_samples])
    at = np.cumsum(size) - size
    taken = np.where(tiled[ring[piece]], size[c] - ~closed[c], 0)
    step = np.repeat(np.where(ahead, 1, -1), taken)
    ids = samples[np.repeat(np.where(ahead, at[c], at[c] + size[c] - 1), taken)
                  + step * _ranges(taken)]
    read = split_counts(ids, np.bincount(ring[piece], taken, minlength=len(every)).astype(int))
    for k in np.flatnonzero(~tiled).tolist():
        edges = slice(ring_first[k], ring_first[k] + counts[k])
        read[k] = _ring_walk(chain[edges].tolist(), forward[edges].tolist(),
                             starts[edges].tolist(), chains, chain_samples)
    ends = np.cumsum([len(region) for region in rings]).tolist()
    return [read[end - len(region):end] for region, end in zip(rings, ends)]


def _ring_walk(ring_chain, ring_forward, ring_starts, chains, chain_samples):
    """One ring's sample numbers (:func:`_ring_samples`), walked chain by chain from the
    first start (its edges' chains, directions and starts, as lists)."""
    n = len(ring_chain)
    start = ring_starts.index(True) if True in ring_starts else 0
    ids, seen = [], 0
    while seen < n:
        k = (start + seen) % n
        c = ring_chain[k]
        samples = chain_samples[c] if ring_forward[k] else chain_samples[c][::-1]
        if chains[c][1]:
            ids.extend(samples.tolist())
            seen += len(chains[c][0])
        else:
            ids.extend(samples[:-1].tolist())
            seen += len(chains[c][0]) - 1
    return np.array(ids, dtype=np.int64)


# --- composite sections --------------------------------------------------------------

def mesh_regions(regions, alpha, seed: int = 0, *, graded: bool | None = None,
                 grading: float | None = None, sizing=None, feature_angle: float = 30.0,
                 max_samples: int | None = None) -> "CompositeMesh":
    """Mesh regions that share boundaries (a composite section: several materials) as
    one conforming mesh: every shared boundary chain is sampled once, each region is
    meshed and certified on its own, and the meshes share the interfaces' vertices.

    ``graded=True`` meshes with one radius field for the whole composite (as
    :func:`pds_plugin.mesh_region` does for one region): the smallest of the regions'
    own fields (each follows its walls, holes and corners, an interface being a wall of
    both sides), combined by min with cones at the chains' samples that make both sides
    of an interface read the same r there; the chains are sampled once with it
    (:func:`graded_sample_chains`) and every region is meshed and certified against it.

    Parameters
    ----------
    regions : dict of str to Region or shapely polygon, or sequence of them
        The regions, in one plane (Regions must share their frame). Boundaries that
        coincide are interfaces; a vertex of one region lying on another's edge is
        inserted into it.
    alpha : float or "auto"
        The disc radius of every region; "auto" takes the smallest of the regions'
        :func:`pds_plugin.suggest_alpha`. Graded: the field's cap; "auto" caps it by the
        largest region's inradius only (the regions' walls and pieces bound it in the
        smaller ones).
    seed : int
        The same seed gives the same mesh, bit for bit.
    graded : bool, optional
        A graded mesh (default: uniform), as for :func:`pds_plugin.mesh_region`:
        implied by ``grading`` and ``sizing``.
    grading : float, optional
        The Lipschitz constant L of the field, in (0, 1); default
        :data:`pds_plugin.sizing.DEFAULT_GRADING`.
    sizing : float, callable or RadiusField, optional
        The user's radius: a number is the largest radius (as ``alpha``), a callable
        ``sizing(x, y)`` on arrays or a field is combined by min.
    feature_angle : float
        Boundary vertices turning by at least this many degrees are sampled as corners.
    max_samples : int, optional
        The sample budget of each region (:func:`pds_plugin.poisson_disc`).

    Returns
    -------
    CompositeMesh
        Its ``region_tags`` name each triangle's region, ``interface_edges`` and
        ``interface_tags`` the shared edges, ``parts`` the regions' own meshes and
        ``certificate()`` all their certificates and the interfaces' check.

    Raises
    ------
    RegionError
        If two regions overlap (the message names them and where), or a region is not
        a valid polygon.
    ArgumentError, ArgumentTypeError
        If ``regions`` is empty or not regions, or ``alpha`` not a positive number or
        "auto".
    BudgetError
        If ``alpha`` would make more than ``max_samples`` samples in a region (said
        before anything is sampled, with the smallest alpha the budget allows).

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> core, shell = box(1, 1, 2, 2), box(0, 0, 3, 3).difference(box(1, 1, 2, 2))
    >>> mesh = pds.mesh_regions({"steel": core, "concrete": shell}, 0.2)
    >>> mesh.certificate().ok, sorted(mesh.region_tags.names)
    (True, ['concrete', 'steel'])
    >>> round(float(mesh.quality().area[mesh.region_tags.where("steel")].sum()), 12)
    1.0
    >>> graded = pds.mesh_regions({"steel": core, "concrete": shell}, "auto", graded=True)
    >>> graded.certificate().ok_with_exceptions, len(graded.interface_edges) > 0
    (True, True)
    """
    names, geometries, frame = _named_geometries(regions)
    check_seed(seed)
    graded, alpha, sizing = graded_request(alpha, graded, grading, sizing)
    _check_no_overlap(names, geometries)
    noded, xy = _noded(geometries)
    _check_near_misses(names, noded)
    parts = []
    for name, geometry in zip(names, noded):
        parts.append(Region.from_shapely(geometry, frame))
    if isinstance(alpha, str) and alpha != "auto":
        raise ArgumentError(f"alpha must be a positive number or 'auto', got {alpha!r}")
    if not isinstance(alpha, str):    # an alpha far too small, refused before any chain
        alpha = check_alpha(alpha)
        budget = DEFAULT_MAX_SAMPLES if max_samples is None else check_positive_int(
            max_samples, "max_samples")
        for part in parts:
            check_budget(part, alpha, budget)
    lookup = {tuple(point): k for k, point in enumerate(xy.tolist())}
    rings = [[_ids_of(ring, lookup, name) for ring in part.rings]
             for name, part in zip(names, parts)]
    frames = [xy] * len(parts)
    if graded:
        field = _composite_field(parts, alpha, grading, sizing, feature_angle)
        joined = junction_fields(rings, frames, [field] * len(parts))     # one frame:
        field = with_sample_cones(field, np.concatenate([f.features for f in joined]),
                                  np.concatenate([f.sizes for f in joined]))  # one field
        chains = graded_sample_chains(rings, frames, [field] * len(parts),
                                      feature_angle=feature_angle, seed=seed)
        points = chains.points(xy)
        field = with_sample_cones(field, points,
                                  chain_sample_radii(chains, frames, [field] * len(parts)))
        return _joined_mesh(names, parts, chains, points, field.cap, seed, feature_angle,
                            max_samples, frame, field)
    if isinstance(alpha, str):
        from .pipeline import suggest_alpha
        alpha = min(suggest_alpha(part) for part in parts)
    alpha = check_alpha(alpha)
    chains = sample_chains(rings, frames, alpha, feature_angle=feature_angle, seed=seed)
    return _joined_mesh(names, parts, chains, chains.points(xy), alpha, seed, feature_angle,
                        max_samples, frame)


def _composite_field(parts, alpha, grading, sizing, feature_angle):
    """The radius field of a composite: the smallest of its regions' own fields
    (:func:`pds_plugin.sizing.radius_field`, each capped by ``alpha`` or, for "auto", by
    its inradius), capped by ``alpha`` or the largest inradius."""
    grading = DEFAULT_GRADING if grading is None else grading
    caps = ([inradius(part) for part in parts] if isinstance(alpha, str)
            else [check_alpha(alpha)] * len(parts))
    fields = [radius_field(part, grading, cap, sizing, feature_angle)
              for part, cap in zip(parts, caps)]
    return RadiusField(np.concatenate([f.features for f in fields]),
                       np.concatenate([f.sizes for f in fields]), fields[0].grading,
                       max(caps), sizing)


def _named_geometries(regions):
    """The names, the oriented MultiPolygons and the common frame of ``regions``."""
    if isinstance(regions, dict):
        names, values = [str(name) for name in regions], list(regions.values())
    elif isinstance(regions, (list, tuple)):
        names, values = [f"region {k}" for k in range(len(regions))], list(regions)
    else:
        raise ArgumentTypeError(f"regions must be a dict of names to regions or a list of "
                                f"regions, got {type(regions).__name__}")
    if not values:
        raise ArgumentError("regions is empty: give at least one region")
    frames, geometries = [], []
    for name, value in zip(names, values):
        region = value if isinstance(value, Region) else None
        if region is None:
            if not isinstance(value, (Polygon, MultiPolygon)):
                raise ArgumentTypeError(f"region {name!r} is a {type(value).__name__}; give a "
                                        "pds_plugin.Region or a shapely (Multi)Polygon")
            region = Region.from_shapely(value)
        frames.append(region.frame)
        geometries.append(region.geometry)
    for name, frame in zip(names[1:], frames[1:]):
        if not np.array_equal(frame, frames[0]):
            raise ArgumentError(f"region {name!r} lies in another plane than {names[0]!r}; "
                                "composite regions share one frame")
    return names, geometries, frames[0]


def _check_no_overlap(names, geometries):
    """Refuse regions whose interiors overlap, naming the first pair and where."""
    tree = shapely.STRtree(geometries)
    first, second = tree.query(geometries, predicate="intersects")
    for i, j in zip(first.tolist(), second.tolist()):
        if i >= j:
            continue
        overlap = shapely.intersection(geometries[i], geometries[j])
        smaller = min(geometries[i].area, geometries[j].area)
        if overlap.area > 1e-9 * smaller:
            x, y = shapely.get_coordinates(overlap.representative_point())[0]
            raise RegionError(f"regions {names[i]!r} and {names[j]!r} overlap over an area of "
                              f"{overlap.area:.6g} around ({x:.6g}, {y:.6g}); composite "
                              "regions may share boundaries but not area: subtract one from "
                              "the other (shapely's difference)")


_NEAR_MISS = 1e-9
"""Boundaries of two regions closer than this (relative to the extent) must share their
vertices: closer but apart, they leave a sliver that no alpha can mesh."""


def _check_near_misses(names, geometries):
    """Refuse a vertex of one region that lies within ``_NEAR_MISS`` of another region's
    boundary without lying on it (a boundary meant to be shared, drawn twice)."""
    extent = max(float(np.ptp(shapely.get_coordinates(g), axis=0).max()) for g in geometries) or 1.0
    boundaries = shapely.boundary(np.array(geometries, dtype=object))
    tree = shapely.STRtree(boundaries)
    for i, geometry in enumerate(geometries):
        points = shapely.points(np.unique(shapely.get_coordinates(geometry), axis=0))
        point, other = tree.query(points, predicate="dwithin", distance=_NEAR_MISS * extent)
        keep = other != i
        distance = shapely.distance(points[point[keep]], boundaries[other[keep]])
        near = distance > _ON_SEGMENT * extent
        if near.any():
            k = int(np.flatnonzero(near)[0])
            x, y = shapely.get_coordinates(points[point[keep][k]])[0]
            raise RegionError(f"regions {names[i]!r} and {names[other[keep][k]]!r} nearly touch at "
                              f"({x:.6g}, {y:.6g}), {distance[k]:.3g} apart, without sharing "
                              "their boundary there; snap them to one boundary (e.g. "
                              "shapely.set_precision) or move them apart")


def _noded(geometries):
    """The geometries with every ring vertex of any of them that lies on a segment of
    another's ring inserted there, and the table of all their vertices."""
    coords = np.unique(np.concatenate([shapely.get_coordinates(g) for g in geometries]), axis=0)
    extent = float(np.ptp(coords, axis=0).max()) or 1.0
    tree = shapely.STRtree(shapely.points(coords))
    eps = _ON_SEGMENT * extent
    out = []
    for geometry in geometries:
        polygons = []
        for polygon in geometry.geoms:
            rings = [_noded_ring(shapely.get_coordinates(ring)[:-1], coords, tree, eps)
                     for ring in (polygon.exterior, *polygon.interiors)]
            polygons.append(Polygon(rings[0], rings[1:]))
        out.append(MultiPolygon(polygons))
    table = np.unique(np.concatenate([shapely.get_coordinates(g) for g in out]), axis=0)
    return out, table


def _noded_ring(ring, coords, tree, eps):
    """``ring`` with the points of ``coords`` lying on its segments inserted in order."""
    following = np.roll(ring, -1, axis=0)
    segments = shapely.linestrings(np.stack([ring, following], axis=1))
    segment, point = tree.query(segments, predicate="dwithin", distance=eps)
    d = following[segment] - ring[segment]
    t = ((coords[point] - ring[segment]) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-300)
    inside = (t > 0) & (t < 1) & np.any(coords[point] != ring[segment], axis=1) \
        & np.any(coords[point] != following[segment], axis=1)
    segment, point, t = segment[inside], point[inside], t[inside]
    key = np.concatenate([np.arange(len(ring)), segment])
    order = np.lexsort((np.concatenate([np.zeros(len(ring)), t]), key))
    return np.concatenate([ring, coords[point]])[order]


def _ids_of(ring, lookup, name):
    """The vertex numbers of a ring's vertices."""
    try:
        return np.array([lookup[point] for point in map(tuple, ring.tolist())], dtype=np.int64)
    except KeyError:
        raise RegionError(f"region {name!r} was moved where it touches itself at a point; "
                          "composite regions need rings that do not touch") from None


def _joined_mesh(names, parts, chains, boundary_xy, alpha, seed, feature_angle, max_samples,
                 frame, field=None):
    """Mesh every part with its chains' samples (graded with ``field``, one field for
    all), and join the meshes by sample number."""
    options = {"feature_angle": feature_angle}
    if max_samples is not None:
        options["max_samples"] = max_samples
    points, faces, part_of_face, maps, meshes = [boundary_xy], [], [], [], []
    count = len(boundary_xy)
    for r, (part, ring_ids) in enumerate(zip(parts, chains.rings)):
        mesh, _ = mesh_part(part, alpha, [boundary_xy[ids] for ids in ring_ids], seed,
                            field=field, **options)
        given = np.concatenate(ring_ids)
        extra = len(mesh.vertices) - len(given)
        to_global = np.concatenate([given, count + np.arange(extra)])
        points.append(mesh.vertices[len(given):])
        count += extra
        faces.append(to_global[mesh.faces])
        part_of_face.append(np.full(len(mesh.faces), r))
        maps.append(to_global)
        meshes.append(mesh)
    outer = np.zeros(count, bool)
    for samples, sides in zip(chains.chain_samples, chains.sides):
        if len(sides) == 1:
            outer[samples] = True
    union = Region.from_shapely(shapely.union_all([part.geometry for part in parts]), frame)
    return CompositeMesh(np.concatenate(points), np.concatenate(faces), outer, union, alpha,
                         parts=tuple(meshes), names=tuple(names),
                         part_of_face=np.concatenate(part_of_face), vertex_maps=tuple(maps),
                         chains=chains, field=field)


ATTEMPTS = 3
"""Interiors drawn for a part (seeds ``seed``, ``seed + 1``, ...) until its boundary edges
are exactly the chords between its given samples."""


def mesh_part(region: Region, alpha: float, given, seed: int, *, field=None, **options):
    """Mesh one part of a partition with its ``given`` ring samples, drawing its interior
    again from the next seeds (up to :data:`ATTEMPTS`) while a chord is not a mesh edge.
    With a radius ``field`` the part is graded (the graded sampler and complex with
    that field, which the certificate then measures against; ``alpha`` is unused).

    The chords' proof (docs/conforming.md, "Why consecutive boundary samples are mesh
    edges") assumes no small feature near the chord; beside a short piece a chord may be
    left unjoined, depending on the interior samples. The boundary samples stay as given,
    so the part still joins its neighbours when a later draw succeeds.

    Returns
    -------
    mesh : PlanarMesh
        The first mesh whose boundary edges are exactly the chords, else the last one.
    joined : bool
        Whether it is.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> square = Region.from_shapely(box(0, 0, 1, 1))
    >>> ring = [[0, 0], [0.5, 0], [1, 0], [1, 0.5], [1, 1], [0.5, 1], [0, 1], [0, 0.5]]
    >>> mesh, joined = mesh_part(square, 0.3, [ring], seed=0)
    >>> joined, len(mesh.boundary_edges)
    (True, 8)
    """
    from .pipeline import mesh_region

    local = np.cumsum([0] + [len(ring) for ring in given])
    chords = np.unique(np.concatenate([np.column_stack([np.arange(a, b), np.roll(np.arange(a, b), -1)])
                                       for a, b in zip(local[:-1], local[1:])]), axis=0)
    for attempt in range(ATTEMPTS):
        if field is None:
            mesh = mesh_region(region, alpha, seed=seed + attempt, boundary_samples=given,
                               **options)
        else:
            mesh = _graded_part(region, field, given, seed + attempt, options)
        boundary = mesh.boundary_edges
        if len(boundary) == len(chords) and np.array_equal(np.unique(boundary, axis=0), chords):
            return mesh, True
    return mesh, False


def _graded_part(region, field, given, seed, options) -> PlanarMesh:
    """The graded mesh of ``region`` with its ring samples ``given`` and radius ``field``."""
    from .graded_complex import graded_alpha_complex
    from .graded_sampling import graded_poisson_disc

    samples = graded_poisson_disc(region, field, seed, boundary_samples=given, **options)
    faces = graded_alpha_complex(samples.points, samples.radius, field.grading,
                                 boundary=samples.rings)
    return PlanarMesh(samples.points, faces, samples.on_boundary, region, field.cap, True,
                      field=field)


class CompositeMesh(PlanarMesh):
    """The mesh of regions sharing interfaces (:func:`mesh_regions`): one
    :class:`~pds_plugin.PlanarMesh` of their union whose triangles are tagged by region.

    Attributes
    ----------
    parts : tuple of PlanarMesh
        Each region's own mesh (its certificate is the usual one).
    names : tuple of str
        The regions' names; ``region_tags`` tag ``k + 1`` is ``names[k]``.
    part_of_face : (M,) int64 ndarray
        The region of each triangle.
    vertex_maps : tuple of (n_k,) int64 ndarray
        For each part, the number in this mesh of each of its vertices.
    interface_edges : (I, 2) int64 ndarray
        The edges on an interface between two regions.
    interface_tags : Tags
        Which two regions each interface edge separates, named ``"a|b"``.
    """

    def __init__(self, vertices, faces, on_boundary, region, alpha, *, parts, names,
                 part_of_face, vertex_maps, chains, field=None):
        super().__init__(vertices, faces, on_boundary, region, alpha, conforming=True,
                         field=field)
        self.parts, self.names = parts, names
        self.part_of_face = np.asarray(part_of_face, dtype=np.int64)
        self.vertex_maps = vertex_maps
        self._chains = chains

    @cached_property
    def region_tags(self):
        """The region of each triangle, named as given to :func:`mesh_regions`."""
        from .tags import Tags
        return Tags(self.part_of_face + 1, {name: k + 1 for k, name in enumerate(self.names)})

    @cached_property
    def _interfaces(self):
        edges, tags, names = [], [], {}
        for chain, sides in enumerate(self._chains.sides):
            if len(sides) != 2:
                continue
            name = f"{self.names[sides[0]]}|{self.names[sides[1]]}"
            tag = names.setdefault(name, len(names) + 1)
            pairs = self._chains.chords(chain)
            edges.append(pairs)
            tags.append(np.full(len(pairs), tag))
        from .tags import Tags
        if not edges:
            return np.zeros((0, 2), np.int64), Tags(np.zeros(0, np.int64), names)
        return np.concatenate(edges), Tags(np.concatenate(tags), names)

    @property
    def interface_edges(self) -> np.ndarray:
        """(I, 2) int64: the edges between consecutive samples of the interfaces."""
        return self._interfaces[0]

    @property
    def interface_tags(self):
        """The two regions of each of :attr:`interface_edges`, named ``"a|b"``."""
        return self._interfaces[1]

    @cached_property
    def _certificate(self) -> "PartitionCertificate":
        return PartitionCertificate(self.names, tuple(part.certificate() for part in self.parts),
                                    interface_report(self.vertices, self.faces,
                                                     self.interface_edges, self.on_boundary))

    def __repr__(self) -> str:
        return (f"CompositeMesh(regions={len(self.parts)}, vertices={len(self.vertices)}, "
                f"faces={len(self.faces)}, alpha={self.alpha:.6g})")


# --- the joined mesh's check ---------------------------------------------------------

@dataclass(frozen=True)
class InterfaceReport:
    """How the meshes of a partition join, checked on the joined triangles alone.

    Attributes
    ----------
    duplicate_vertices : int
        Vertices at the same coordinates as an earlier one (a seam not shared).
    misoriented_edges : int
        Directed edges run by two triangles (two triangles folded onto each other).
    nonmanifold_edges : int
        Edges of more than two triangles.
    unjoined_interface_edges : int
        Interface edges not shared by exactly two triangles.
    open_edges : int
        Edges of one triangle only that do not join two samples of the outer boundary,
        or lie on an interface: a T-junction or a gap.
    problems : tuple of str
        The first few of them, located.
    inherited_edges : int
        Edges that are non-manifold or run twice the same way exactly as in the input
        they were kept from (``inherited``: a remeshed solid of two bodies sharing an
        edge), not counted above.
    """

    duplicate_vertices: int
    misoriented_edges: int
    nonmanifold_edges: int
    unjoined_interface_edges: int
    open_edges: int
    problems: tuple
    inherited_edges: int = 0

    @property
    def ok(self) -> bool:
        """The meshes join with no T-junction, gap, fold or duplicate vertex."""
        return not (self.duplicate_vertices or self.misoriented_edges or self.nonmanifold_edges
                    or self.unjoined_interface_edges or self.open_edges)

    def as_dict(self) -> dict:
        """Plain JSON-ready values, ``ok`` included."""
        values = {name: getattr(self, name) for name in self.__dataclass_fields__}
        values["problems"] = list(self.problems)
        values["ok"] = self.ok
        return values


def interface_report(vertices, faces, interface_edges, outer, inherited=None) -> InterfaceReport:
    """Check that triangles meshed part by part join along their interfaces.

    Parameters
    ----------
    vertices : (N, 2) or (N, 3) array_like of float
    faces : (M, 3) array_like of int
        The joined triangles, all oriented alike.
    interface_edges : (I, 2) array_like of int
        The edges that two parts share.
    outer : (N,) array_like of bool
        The samples of the outer boundary (none for a closed surface).
    inherited : tuple of two (K, 3) array_like of int, optional
        The input these triangles were kept from: rows (a, b, n) of the directed edges
        it ran more than once (n times), and of its edges (a < b) of more than two
        triangles (n). A directed edge run as often here, and an edge with as many
        triangles here, are the input's own and counted apart (``inherited_edges``).

    Returns
    -------
    InterfaceReport

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]], float)
    >>> report = interface_report(square, [[0, 1, 2], [0, 2, 3]], [[0, 2]], [True] * 4 + [False])
    >>> report.ok
    True
    >>> t_junction = interface_report(square, [[0, 1, 2], [0, 4, 3], [4, 2, 3]], [[0, 2]],
    ...                               [True] * 4 + [False])
    >>> t_junction.ok, t_junction.unjoined_interface_edges, t_junction.open_edges
    (False, 1, 3)
    """
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    outer = np.asarray(outer, dtype=bool)
    interface = np.sort(np.asarray(interface_edges, dtype=np.int64).reshape(-1, 2), axis=1)
    problems = []
    duplicate, firsts = _duplicate_vertices(vertices)
    for k in firsts[:3]:
        problems.append(f"two vertices at {_where(vertices[k])}")
    base = len(vertices) + 1                 # an edge (a, b) as the integer a base + b
    first, second = faces.T[[0, 1, 2]], faces.T[[1, 2, 0]]      # directed edges, corner k on
    run_codes, run_count = _counted(first * base + second)
    runs, many_edges = ((np.asarray(rows, dtype=np.int64).reshape(-1, 3) for rows in inherited)
                        if inherited is not None else (np.zeros((0, 3), np.int64),) * 2)
    kept_run = _as_before(run_codes, run_count, runs, base) & (run_count > 1)
    run_count = np.where(kept_run, 1, run_count)
    for code in run_codes[run_count > 1][:3]:
        edge = np.array(divmod(int(code), base))
        problems.append(f"two triangles run the edge at {_where(vertices[edge].mean(axis=0))} "
                        "the same way")
    edge_code, uses = _counted(np.minimum(first, second) * base + np.maximum(first, second))
    kept_many = _as_before(edge_code, uses, many_edges, base) & (uses > 2)
    many = (uses > 2) & ~kept_many
    for code in edge_code[many][:3]:
        edge = np.array(divmod(int(code), base))
        problems.append(f"the edge at {_where(vertices[edge].mean(axis=0))} has {uses.max()} triangles")
    interface_code = interface[:, 0] * base + interface[:, 1]
    shared = np.zeros(len(interface), bool)
    found = _found(edge_code, interface_code)
    shared[found >= 0] = uses[found[found >= 0]] == 2
    for edge in interface[~shared][:3]:
        problems.append(f"the interface edge at {_where(vertices[edge].mean(axis=0))} is not "
                        "shared by two triangles (a T-junction or a gap)")
    single_code = edge_code[uses == 1]
    single = np.column_stack([single_code // base, single_code % base])
    open_edge = ~outer[single].all(axis=1) | (_found(np.sort(interface_code), single_code) >= 0)
    for edge in single[open_edge][:3]:
        problems.append(f"an open edge inside at {_where(vertices[edge].mean(axis=0))}")
    return InterfaceReport(duplicate, int(np.count_nonzero(run_count > 1)),
                           int(np.count_nonzero(many)), int(np.count_nonzero(~shared)),
                           int(np.count_nonzero(open_edge)), tuple(problems),
                           int(np.count_nonzero(kept_run) + np.count_nonzero(kept_many)))


def _duplicate_vertices(vertices):
    """How many rows of ``vertices`` equal another row before them in the rows' order by
    every coordinate, and the first row of each group of equal rows, in increasing order:
    what a lexsort of all rows finds (rows equal under ``==``: -0.0 is 0.0, NaN nothing),
    from a sort of one integer hash per row; only the rows whose hash another row shares
    (in practice the duplicates themselves) are lexsorted (a lexsort of all 14,000 rows
    took 1.8 ms of the interface report)."""
    if len(vertices) < 2:
        return 0, np.zeros(0, np.int64)
    bits = np.ascontiguousarray(vertices + 0.0).view(np.uint64)     # -0.0 as 0.0
    key = np.zeros(len(vertices), np.uint64)
    for column in bits.T:
        key = (key ^ column) * np.uint64(0x9E3779B97F4A7C15)
        key ^= key >> np.uint64(29)
    order = np.argsort(key)
    key = key[order]
    tie = key[1:] == key[:-1]
    if not tie.any():
        return 0, np.zeros(0, np.int64)
    shares = np.r_[tie, False] | np.r_[False, tie]
    rows = np.sort(order[shares])
    sub = vertices[rows]
    # rows sorted by every coordinate (np.unique(axis=0) is ten times slower)
    order = np.lexsort(sub.T[::-1])
    same = np.all(sub[order[1:]] == sub[order[:-1]], axis=1)
    starts = np.flatnonzero(same & np.r_[True, ~same[:-1]])
    return int(np.count_nonzero(same)), np.sort(rows[order[starts]])


def _counted(codes):
    """The distinct integer ``codes`` in increasing order and how often each occurs (as
    ``np.unique(codes, return_counts=True)``, from one sort)."""
    codes = np.sort(codes.ravel())
    if not len(codes):
        return codes, np.zeros(0, np.int64)
    start = np.flatnonzero(np.r_[True, codes[1:] != codes[:-1]])
    return codes[start], np.diff(np.r_[start, len(codes)])


def _found(sorted_codes, codes) -> np.ndarray:
    """The index of each of ``codes`` in the increasing ``sorted_codes``, -1 where absent."""
    if not len(sorted_codes):
        return np.full(len(codes), -1, np.int64)
    at = np.minimum(np.searchsorted(sorted_codes, codes), len(sorted_codes) - 1)
    return np.where(sorted_codes[at] == codes, at, -1)


def _as_before(codes, counts, known, base) -> np.ndarray:
    """Which edges (sorted integer ``codes`` a base + b, each used ``counts`` times) the
    ``known`` rows (a, b, n) list with the same n."""
    if not len(known) or not len(codes):
        return np.zeros(len(codes), bool)
    known_codes = known[:, 0] * base + known[:, 1]
    order = np.argsort(known_codes)
    known_codes, known_counts = known_codes[order], known[order, 2]
    at = np.minimum(np.searchsorted(known_codes, codes), len(known_codes) - 1)
    return (known_codes[at] == codes) & (known_counts[at] == counts)


def _where(point) -> str:
    return "(" + ", ".join(f"{float(v):.6g}" for v in point) + ")"


@dataclass(frozen=True)
class PartitionCertificate:
    """The certificate of a partition's mesh: each part's own, and how they join.

    Attributes
    ----------
    names : tuple of str
    parts : tuple of Certificate
        Each region's certificate (:func:`pds_plugin.certify`), in ``names`` order.
    interfaces : InterfaceReport
    """

    names: tuple
    parts: tuple
    interfaces: InterfaceReport

    @property
    def ok(self) -> bool:
        """Every part is ``ok`` and the parts join."""
        return self.interfaces.ok and all(part.ok for part in self.parts)

    @property
    def ok_with_exceptions(self) -> bool:
        """Every part is ``ok_with_exceptions`` and the parts join."""
        return self.interfaces.ok and all(part.ok_with_exceptions for part in self.parts)

    def as_dict(self) -> dict:
        """Plain JSON-ready values: each part's certificate by name, the interfaces'
        check, ``ok`` and ``ok_with_exceptions``."""
        return {"parts": {name: part.as_dict() for name, part in zip(self.names, self.parts)},
                "interfaces": self.interfaces.as_dict(), "ok": self.ok,
                "ok_with_exceptions": self.ok_with_exceptions}

    def __str__(self) -> str:
        verdict = ("ok" if self.ok else "ok with exceptions" if self.ok_with_exceptions
                   else "FAILED")
        lines = [f"composite certificate: {verdict} ({len(self.parts)} regions)",
                 f"  interfaces: {'ok' if self.interfaces.ok else 'FAILED'}"]
        lines += [f"    {problem}" for problem in self.interfaces.problems]
        for name, part in zip(self.names, self.parts):
            part_verdict = ("ok" if part.ok else "ok with exceptions" if part.ok_with_exceptions
                            else "FAILED")
            lines.append(f"  {name}: {part_verdict}")
        return "\n".join(lines)
