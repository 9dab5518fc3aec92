"""The radius field of graded meshes: r(x) <= alpha, following the local feature size,
L-Lipschitz (docs/graded.md, section 3).

``r(x) = min(cap, sizing(x), min_i(s_i + L |x - f_i|))`` over feature points ``f_i`` on
the densified boundary with feature sizes ``s_i``: the wall thickness seen through
material (gaps, slots and notches do not count), a disc at each sharp corner, the
length of the boundary piece and of the ring, and the curvature of arcs. A minimum of
L-Lipschitz functions is L-Lipschitz.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np
import shapely
from scipy.spatial import cKDTree

from . import _sizing_kernels as kern
from ._checks import check_alpha, check_grading, check_positive
from .errors import ArgumentError, ArgumentTypeError
from .region import Region

__all__ = ["RadiusField", "radius_field", "angle_bound", "inradius", "curve_factor",
           "graded_request", "DEFAULT_GRADING"]

DEFAULT_GRADING = 0.2
"""Default Lipschitz constant L: proven angles >= arcsin(0.4) = 23.6° (docs/graded.md)."""

_WALL = 0.9          # r <= 0.9 x wall thickness (margin for the densification error)
_CORNER = 0.4        # corner disc: 0.4 x distance to the nearest non-incident boundary
_RING = 1 / 6        # r <= perimeter / 6 of the ring
_OPPOSED = -0.5      # walls face each other when their normals are opposed by > 120°
_FLAT_BELOW = math.pi / 3   # convex corners sharper than this keep their size along
_FLAT_REACH = 2             # their sides up to this many times it
_K = 24              # nearest neighbours looked at first for the corners' discs
_ROUNDS = 8          # densify-and-measure rounds of the wall sizes at most
_MAX_DENSE = 400_000 # densified boundary points at most (about 0.4 GB of neighbour lists)
_PAIRWISE = 4096     # cone pairs a dominance test takes one by one rather than by a tree


def angle_bound(grading: float) -> float:
    """The proven smallest angle, in degrees, of a graded mesh whose radius field is
    ``grading``-Lipschitz: arcsin((1 - L) / 2) (docs/graded.md, section 2).

    Parameters
    ----------
    grading : float
        The Lipschitz constant L, in (0, 1).

    Returns
    -------
    float

    Examples
    --------
    >>> round(angle_bound(0.2), 2), round(angle_bound(1e-12), 6)
    (23.58, 30.0)
    """
    return math.degrees(math.asin((1.0 - check_grading(grading)) / 2.0))


class RadiusField:
    """An L-Lipschitz radius field ``r(x) = min(cap, sizing(x), min_i(s_i + L|x - f_i|))``.

    Call it on an (n, 2) array of points to get the (n,) radii.

    Parameters
    ----------
    features : (m, 2) array_like
        Feature points f_i.
    sizes : (m,) array_like
        Feature sizes s_i > 0.
    grading : float
        The Lipschitz constant L, in (0, 1).
    cap : float
        The largest radius (alpha).
    sizing : callable, optional
        ``sizing(x, y)`` on arrays, combined by min.

    Examples
    --------
    >>> field = RadiusField([[0, 0]], [0.1], grading=0.5, cap=1.0)
    >>> field([[0, 0], [1, 0], [10, 0]]).tolist()
    [0.1, 0.6, 1.0]
    """

    def __init__(self, features, sizes, grading: float, cap: float, sizing=None):
        features = np.asarray(features, float).reshape(-1, 2)
        sizes = np.asarray(sizes, float).ravel()
        below = sizes < cap                 # a cone from the cap up is nowhere below it
        if not below.all():
            features, sizes = features[below], sizes[below]
        keep, tree = _undominated(features, sizes, grading, True)
        if keep.all():
            self.features, self.sizes = np.ascontiguousarray(features), np.ascontiguousarray(sizes)
            if tree is not None:            # the tree of the test is the field's
                self._tree = tree
        else:
            self.features = np.ascontiguousarray(features[keep])
            self.sizes = np.ascontiguousarray(sizes[keep])
        self.grading = float(grading)
        self.cap = float(cap)
        self.sizing = sizing

    def with_cones(self, points, sizes) -> "RadiusField":
        """This field combined by min with the cones ``sizes + L |x - points|``: the same
        field as a ``RadiusField`` of both feature sets (its own first), bit for bit and
        with the same cones kept, but its own features are tested against the new cones
        only (against each other they were tested when it was made).

        Examples
        --------
        >>> field = RadiusField([[0, 0]], [0.1], grading=0.5, cap=1.0)
        >>> lowered = field.with_cones([[4, 0], [0.1, 0]], [0.2, 0.5])    # the 2nd is dominated
        >>> lowered.sizes.tolist(), lowered([[4, 0]]).tolist()
        ([0.1, 0.2], [0.2])
        >>> field.with_cones([[4, 0]], [1.5]) is field          # no cone below the cap
        True
        """
        points = np.asarray(points, float).reshape(-1, 2)
        sizes = np.asarray(sizes, float).ravel()
        below = sizes < self.cap
        if not below.any():                 # no new cone below the cap: this field
            return self
        points, sizes = np.ascontiguousarray(points[below]), np.ascontiguousarray(sizes[below])
        features = np.concatenate([self.features, points])
        all_sizes = np.concatenate([self.sizes, sizes])
        own, L = len(self.sizes), self.grading
        if len(all_sizes) < 2:
            return RadiusField(features, all_sizes, L, self.cap, self.sizing)
        tree = None
        if len(sizes) * len(all_sizes) <= _PAIRWISE:
            keep = ~kern.dominated_pairwise(features, all_sizes, L, own)
            if own:
                keep[:own] = ~kern.dominated_pairwise(points, sizes, L, queries=self.features,
                                                      query_s=self.sizes)
        else:
            tree = kern.build_cone_tree(features, all_sizes, 8)
            keep = ~kern.dominated_cones(features, all_sizes, L, *tree, own)
            if own:
                keep[:own] = ~kern.dominated_cones(points, sizes, L,
                                                   *kern.build_cone_tree(points, sizes, 8),
                                                   queries=self.features, query_s=self.sizes)
        field = RadiusField.__new__(RadiusField)
        if keep.all():
            field.features, field.sizes = features, all_sizes
            if tree is not None:            # the tree of the test is the field's
                field._tree = tree
        else:
            field.features = np.ascontiguousarray(features[keep])
            field.sizes = np.ascontiguousarray(all_sizes[keep])
        field.grading, field.cap, field.sizing = L, self.cap, self.sizing
        return field

    @cached_property
    def _tree(self):
        """The cone tree of the features (``_sizing_kernels.build_cone_tree``), None
        without features; built when first searched (the fields a remesh combines with
        its patches' sample cones are mostly read only through their groups' union)."""
        return kern.build_cone_tree(self.features, self.sizes, 8) if len(self.sizes) else None

    @cached_property
    def _kernel(self):
        """The field as the compiled kernels search it (``_graded_kernels.Field``), made
        once (a remesh's steps ask each of its hundreds of patch fields several times)."""
        from . import _graded_kernels

        return _graded_kernels.Field(self)

    def __getstate__(self):
        state = dict(self.__dict__)         # a pickle leaves out the compiled view
        state.pop("_kernel", None)          # (made again when asked)
        return state

    def __call__(self, points) -> np.ndarray:
        points = np.ascontiguousarray(np.asarray(points, float).reshape(-1, 2))
        if not len(self.sizes) or not len(points):
            r = np.full(len(points), self.cap)
        elif len(self.sizes) * len(points) <= _PAIRWISE:
            r = kern.cone_minimum_pairwise(points, self.features, self.sizes, self.grading,
                                           self.cap)
        else:
            r = kern.cone_minimum(points, self.features, self.sizes, self.grading, self.cap,
                                  *self._tree)
        if self.sizing is not None:
            user = np.asarray(self.sizing(points[:, 0], points[:, 1]), float)
            user = np.broadcast_to(user, r.shape)
            bad = ~(np.isfinite(user) & (user > 0))
            if bad.any():
                raise ArgumentError("sizing(x, y) must return positive finite radii; got "
                                    f"{user[bad][:3].tolist()} at {points[bad][:3].tolist()}")
            r = np.minimum(r, user)
        return r

    def at_quarters(self, x, y, size) -> np.ndarray:
        """r at the centres of the four quarters of each box [x, x + size]², the same
        values as calling the field there, from one cone search per box: the lower left
        quarters of all boxes first, then the lower right, upper left and upper right.

        Examples
        --------
        >>> field = RadiusField([[0, 0]], [0.1], grading=0.5, cap=1.0)
        >>> field.at_quarters(np.array([0.0]), np.array([0.0]), np.array([4.0])).tolist()
        [0.8071067811865476, 1.0, 1.0, 1.0]
        """
        x, y, size = (np.ascontiguousarray(v, float) for v in (x, y, size))
        if self._tree is None or self.sizing is not None or not len(x):
            half = 0.5 * size
            quarter = 0.5 * np.tile(half, 4)
            return self(np.column_stack([np.concatenate([x, x + half, x, x + half]) + quarter,
                                         np.concatenate([y, y, y + half, y + half]) + quarter]))
        return kern.quarter_cone_minimum(x, y, size, self.features, self.sizes, self.grading,
                                         self.cap, *self._tree)

    def capped_within(self, points, reach: float) -> np.ndarray:
        """Whether r is the cap everywhere within ``reach`` of each point: the cones
        there are at least ``cap + L reach`` high (L-Lipschitz), and no ``sizing``.

        Examples
        --------
        >>> field = RadiusField([[0, 0]], [0.1], grading=0.5, cap=1.0)
        >>> field.capped_within([[1, 0], [3, 0]], 1.0).tolist()
        [False, True]
        """
        points = np.ascontiguousarray(np.asarray(points, float).reshape(-1, 2))
        if self.sizing is not None:
            return np.zeros(len(points), bool)
        if self._tree is None or not len(points):
            return np.ones(len(points), bool)
        above = self.cap + self.grading * reach
        return kern.cone_minimum(points, self.features, self.sizes, self.grading, above,
                                 *self._tree) >= above


def graded_request(alpha, graded: bool | None = None, grading: float | None = None,
                   sizing=None):
    """What :func:`pds_plugin.mesh_region`'s and :func:`pds_plugin.mesh_regions`'s
    keywords ask for: ``(graded, alpha, sizing)``, the one rule of both.

    ``sizing`` and ``grading`` describe a radius field, so either makes the mesh graded:
    ``graded=True`` is then redundant (and still accepted), ``graded=False`` with either
    is refused. ``graded=True`` alone asks for the region's own field. ``sizing`` is

    - a number s: the largest radius, as ``alpha=s`` (with a number ``alpha``, the
      smaller of the two): r = min(the region's field, s);
    - a callable ``sizing(x, y)`` on arrays, or a :class:`RadiusField` (e.g. another
      mesh's ``mesh.field``): combined with the region's field by min.

    Parameters
    ----------
    alpha : float or "auto"
    graded : bool, optional
    grading : float, optional
    sizing : float, callable or RadiusField, optional

    Returns
    -------
    tuple
        ``graded`` (bool), ``alpha`` (a number sizing folded in), ``sizing`` (a callable
        on (x, y), or None).

    Raises
    ------
    ArgumentError
        If ``graded=False`` comes with a grading or a sizing, or a number sizing is not
        a positive radius.
    ArgumentTypeError
        If ``sizing`` is neither a number nor a callable.

    Examples
    --------
    >>> graded_request("auto", sizing=0.5)
    (True, 0.5, None)
    >>> graded_request(0.2, sizing=0.5), graded_request(0.2)
    ((True, 0.2, None), (False, 0.2, None))
    >>> graded_request("auto", grading=0.3)[0], graded_request("auto", graded=True)[0]
    (True, True)
    """
    if isinstance(alpha, str) and alpha != "auto":
        raise ArgumentError(f"alpha must be a positive number or 'auto', got {alpha!r}")
    if graded is False and (grading is not None or sizing is not None):
        raise ArgumentError("grading and sizing make a graded mesh: drop graded=False for a "
                            "graded mesh, or grading and sizing for a uniform one")
    graded = bool(graded) or grading is not None or sizing is not None
    if isinstance(sizing, RadiusField):
        field = sizing
        sizing = lambda x, y: field(np.column_stack([x, y]))     # noqa: E731
    elif isinstance(sizing, (int, float, np.number)) and not isinstance(sizing, bool):
        size = check_positive(sizing, "sizing")
        alpha = size if isinstance(alpha, str) else min(check_alpha(alpha), size)
        sizing = None
    elif sizing is not None and not callable(sizing):
        raise ArgumentTypeError("sizing must be a number (the largest radius), a callable "
                                f"sizing(x, y) -> radii or a RadiusField, got "
                                f"{type(sizing).__name__}")
    return graded, alpha, sizing


def _undominated(features, sizes, L, with_tree=False):
    """Features whose cone s_i + L|x - f_i| is not everywhere above another's
    (s_i >= s_j + L|f_i - f_j| means cone i never attains the minimum; of equal cones
    the first is kept), against all the others (``_sizing_kernels.dominated_cones``).
    ``with_tree``: also the cone tree of all of them (None for fewer than two), which
    is the field's own tree when none is dominated."""
    if len(sizes) < 2:
        keep = np.ones(len(sizes), bool)
        return (keep, None) if with_tree else keep
    if len(sizes) ** 2 <= _PAIRWISE:
        keep = ~kern.dominated_pairwise(features, sizes, L)
        return (keep, None) if with_tree else keep
    features, sizes = np.ascontiguousarray(features), np.ascontiguousarray(sizes)
    tree = kern.build_cone_tree(features, sizes, 8)
    keep = ~kern.dominated_cones(features, sizes, L, *tree)
    return (keep, tree) if with_tree else keep


def radius_field(region: Region, grading: float = DEFAULT_GRADING, cap: float | None = None,
                 sizing=None, feature_angle: float = 30.0) -> RadiusField:
    """The radius field of ``region`` (docs/graded.md, section 3).

    Parameters
    ----------
    region : Region
    grading : float
        The Lipschitz constant L, in (0, 1); smaller is better shaped, larger coarser.
    cap : float, optional
        The largest radius; by default the region's inradius (its own size).
    sizing : callable, optional
        A user radius ``sizing(x, y)`` on arrays, combined by min.
    feature_angle : float
        Vertices turning by at least this many degrees are sharp corners.

    Returns
    -------
    RadiusField

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``grading`` is not in (0, 1) or ``sizing`` is not callable.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> plate = Region.from_shapely(box(0, 0, 100, 100).difference(box(10, 10, 90, 11)))
    >>> field = radius_field(plate, grading=0.2)
    >>> [round(float(r), 1) for r in field([[50, 9.5], [50, 50]])]
    [8.4, 11.6]

    Both come from the slot's corners: size 0.4 (0.4 x its 1-unit ends) plus L = 0.2
    per unit of distance; the 10-unit wall below the slot alone would give 9.
    """
    grading = check_grading(grading)
    if sizing is not None and not callable(sizing):
        raise ArgumentTypeError("sizing must be a callable sizing(x, y) -> radii, got "
                                f"{type(sizing).__name__}")
    if cap is None:
        cap = inradius(region)
    points, sizes = _features(region, cap, feature_angle, _factors(grading, feature_angle))
    return RadiusField(points, sizes, grading, cap, sizing)


def radius_fields(regions, grading: float, cap: float, feature_angle: float = 30.0) -> list:
    """:func:`radius_field` of each of ``regions`` with the same ``cap`` (no sizing), the
    same fields bit for bit, measured together: one pass of the feature rules over all
    their rings instead of a few dozen numpy calls per region (remeshing's small
    patches: 0.65 ms a patch, most of it fixed costs).

    Each region's field depends on its own rings only when the regions' bounding boxes
    lie more than :data:`_APART` x ``cap`` apart (as remeshing's layout places them):
    a wall is searched within 2^ceil(log2(min(size, cap) / _WALL)) < 2.23 cap of a
    point, so never across to another region; a corner's disc only counts its own
    region's points (and stops looking once it has seen all of them: the k-th nearest
    point is beyond its region's diameter); a midpoint of two points of a region lies in
    its box, so in no other region; a densified point is in another region's corner disc
    (radius <= cap) never. The densify-and-measure rounds stop region by region: a region
    whose sizes did not change keeps its sizes, as :func:`radius_field` would have
    stopped there. Regions too close, or a densification beyond _MAX_DENSE points
    together, are measured one by one.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> one, two = (Region.from_shapely(box(x, 0, x + 4, 1)) for x in (0, 20))
    >>> fields = radius_fields([one, two], 0.2, 1.0)
    >>> [np.array_equal(f.sizes, radius_field(g, 0.2, 1.0).sizes)
    ...  for f, g in zip(fields, [one, two])]
    [True, True]
    """
    grading = check_grading(grading)
    regions = list(regions)
    factors = _factors(grading, feature_angle)
    if len(regions) > 1 and _apart([region.bounds for region in regions], _APART * cap):
        done = _joint_features(regions, cap, feature_angle, factors)
        if done is not None:
            return [RadiusField(points, sizes, grading, cap) for points, sizes in done]
    return [radius_field(region, grading, cap, feature_angle=feature_angle)
            for region in regions]


_APART = 2.25
"""Regions whose bounding boxes lie more than this many caps apart have independent
fields (:func:`radius_fields`)."""


def _apart(bounds, distance) -> bool:
    """Do every two of the boxes ``bounds`` ((xmin, ymin, xmax, ymax) each) lie more
    than ``distance`` apart along x or along y? The pairs measured are those a box
    query finds within twice that (hundreds of a remesh's patches: all pairs took
    5 ms).

    >>> _apart([[0, 0, 1, 1], [3, 0, 4, 1]], 1.5), _apart([[0, 0, 1, 1], [3, 0, 4, 1]], 2.0)
    (True, False)
    """
    b = np.asarray(bounds, float).reshape(-1, 4)
    reach = np.array([-2.0, -2.0, 2.0, 2.0]) * distance
    i, j = shapely.STRtree(shapely.box(*b.T)).query(shapely.box(*(b + reach).T),
                                                     predicate="intersects")
    i, j = i[i != j], j[i != j]
    x_gap = np.maximum(b[i, 0] - b[j, 2], b[j, 0] - b[i, 2])
    y_gap = np.maximum(b[i, 1] - b[j, 3], b[j, 1] - b[i, 3])
    return bool(np.all(np.maximum(x_gap, y_gap) > distance))


def _joint_features(regions, cap, feature_angle, factors):
    """:func:`_features` of each region, measured together (:func:`radius_fields`): per
    region its feature points and sizes, or None if the densification would exceed
    _MAX_DENSE points."""
    import shapely.geometry as geometry

    ring_lists = [region.rings for region in regions]
    rings = [ring for ring_list in ring_lists for ring in ring_list]
    owner = np.repeat(np.arange(len(regions)), [len(r) for r in ring_lists])
    union = geometry.MultiPolygon([polygon for region in regions
                                   for polygon in region.geometry.geoms])
    shapely.prepare(union)
    whole = _Joined(union, owner, regions)
    edges = _edges(rings)
    edge_owner = owner[edges[3]]
    ring_size, vertex_size, piece, sharp, turn = _ring_sizes(
        edges, cap, math.radians(feature_angle), *factors)
    dense = _densify(edges, ring_size, ring_size, piece)
    corner_xy, corner_s, is_corner, corner_ring = _corner_discs(whole, rings, edges, sharp, turn,
                                                                piece, dense, True)
    discs = corner_xy[is_corner], corner_s[is_corner]
    corner_tree = cKDTree(discs[0]) if len(discs[0]) else None
    edge_size = ring_size.copy()
    flat_edge = edges[4][dense["ring"]] + dense["edge"]
    active = np.ones(len(regions), bool)
    final = [None] * len(regions)           # per region: its densified points and sizes
    for round_ in range(_ROUNDS):
        if round_:
            # the regions that stopped get one point an edge (their points' sizes are
            # kept from their last round, and no other region's walls see them)
            limit = np.where(active[edge_owner], edge_size, np.inf)
            parts = int(np.sum(np.maximum(np.ceil(4 * edges[2] / limit), 1)))
            if parts > _MAX_DENSE:
                return None
            dense = _densify(edges, limit, ring_size, piece)
            flat_edge = edges[4][dense["ring"]] + dense["edge"]
        size, new = _round(whole, dense, flat_edge, edge_size, cap, corner_tree, discs[1])
        changed = np.bincount(edge_owner, weights=new < 0.7 * edge_size,
                              minlength=len(regions)) > 0
        stopping = active & (~changed | (round_ == _ROUNDS - 1))
        if stopping.any():                  # a region stops at its first unchanged round
            dense_owner = owner[dense["ring"]]
            for k in np.flatnonzero(stopping).tolist():
                mine = dense_owner == k
                final[k] = dense["xy"][mine], size[mine]
        active &= changed
        edge_size = np.where(active[edge_owner], new, edge_size)
        if not active.any():
            break
    corner_owner = owner[corner_ring]
    out = []
    for k, (xy, sizes) in enumerate(final):
        corners, vertices = corner_owner == k, edge_owner == k
        out.append((np.concatenate([xy, corner_xy[corners], edges[0][vertices]]),
                    np.concatenate([sizes, corner_s[corners], vertex_size[vertices]])))
    return out


class _Joined:
    """The regions measured together (:func:`_joint_features`): their union (for the
    in-region tests), which region each ring belongs to, and each region's diameter."""

    def __init__(self, geometry, owner, regions):
        self.geometry = geometry
        self.owner = owner
        b = np.array([region.bounds for region in regions])
        self.diameter = np.hypot(b[:, 2] - b[:, 0], b[:, 3] - b[:, 1])


def inradius(region: Region) -> float:
    """The radius of the largest disc inside the region (its own size), to 1 %.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> round(inradius(Region.from_shapely(box(0, 0, 40, 10))), 1)
    5.0
    """
    return max(shapely.maximum_inscribed_circle(polygon, 0.01 * math.sqrt(polygon.area)).length
               for polygon in region.geometry.geoms)


def curve_factor(grading: float, feature_angle: float = 30.0) -> float:
    """The curvature rule's factor κ: r <= κ R on an arc of radius R (docs/graded.md,
    section 3, *curvature*).

    The sampler splits a closed arc into k equal parts of normalized length at least
    ``a = 1.02 / (1 - L/2)`` (graded_sampling._positions), so with r = κ R on it
    ``k = floor(2π / (a κ))`` chords turning by 2π / k each. κ is the largest value
    giving at least ``360° / (2/3 feature_angle)`` chords, so that they turn by at most
    two thirds of the feature angle (the sampler's own threshold for a corner) and their
    sagitta is at most ``R (1 - cos(feature_angle / 3))``: 1.5 % of R at 30°. The third is
    margin found on real parts: at the full feature angle (13 chords at 30°) a tilted
    featuretype.STL section lost a chord's triangle (bench/cad_corpus.py), and at three
    quarters (16 chords) the region beyond a chord of featuretype.STEP's mid-height
    section was 1.01 r from its ends (tests/test_sources_step.py).

    Parameters
    ----------
    grading : float
        The Lipschitz constant L.
    feature_angle : float
        Degrees; vertices turning by more are sharp corners.

    Returns
    -------
    float

    Examples
    --------
    >>> round(curve_factor(0.2), 4)          # 18 chords on a circle, 20° each
    0.308
    """
    a = 1.02 / (1.0 - 0.5 * grading)
    chords = math.ceil(360.0 / (2 / 3 * feature_angle) - 1e-9)
    return 2.0 * math.pi / (chords * a) * (1.0 - 1e-9)


def piece_factor(grading: float) -> float:
    """The pieces rule's factor: r <= this times the length of the piece between sharp
    corners (docs/graded.md, section 3, *pieces*).

    The sampler splits a piece of τ-length T into ``floor(T / a)`` equal parts,
    ``a = 1.02 / (1 - L/2)`` (graded_sampling.tau_positions); with T >= N a each is
    shorter than (1 + 1/N) a. A part longer than 2 is a chord longer than 2 r where r
    is flat, and the middle of its arc lies beyond r from both its ends (flanges'
    sections at L = 0.45: one part of τ 2.44 between two corners, 1.22 r). So N is the
    fewest parts with (1 + 1/N) a < 2, at least two, and at most four (L up to 0.72; past
    it parts can exceed 2, and more of them shrank r at the pieces without end: at
    L = 0.99 a plate's complex took 416 s, 0.08 s with four). The field holds the size s
    at points at most s / 4 apart along the piece, so r between them reaches s (1 + L/8),
    and the factor is 1 / (1.02 (1 + L/8) N a) (1.02: the trapezoid rule's error on τ);
    at most 0.4, the factor of every grading before, which it stays up to L = 0.25.

    Examples
    --------
    >>> piece_factor(0.2), round(piece_factor(0.45), 4), round(piece_factor(0.6), 4)
    (0.4, 0.3526, 0.2086)
    """
    a = 1.02 / (1.0 - 0.5 * grading)
    parts = 2
    while (1.0 + 1.0 / parts) * a >= 2.0 and parts < 4:
        parts += 1
    return min(0.4, 1.0 / (1.02 * (1.0 + grading / 8) * parts * a))


def _factors(grading: float, feature_angle: float) -> tuple:
    """The ring rules' factors of a grading: (:func:`curve_factor`, :func:`piece_factor`)."""
    return curve_factor(grading, feature_angle), piece_factor(grading)


def _features(region: Region, cap: float, feature_angle: float, factors: tuple):
    """Feature points and sizes: the boundary densified until every edge is split into
    parts at most a quarter of the smallest size found on it.

    Inside the disc of a sharp corner the two pieces meeting there are not walls of each
    other (their distance goes to 0 at the corner): the corner's own size holds there.
    Otherwise each round would find the two sides closer near the corner, densify them
    finer and find them closer again (an STL section's 46° corner reached 1e-7).

    Every ring is handled at once (flat arrays over all edges), so the cost grows with
    the boundary, not with the number of holes times a per-ring overhead."""
    rings = region.rings
    edges = _edges(rings)
    ring_size, vertex_size, piece, sharp, turn = _ring_sizes(
        edges, cap, math.radians(feature_angle), *factors)
    dense = _densify(edges, ring_size, ring_size, piece)
    corner_xy, corner_s, is_corner = _corner_discs(region, rings, edges, sharp, turn, piece, dense)
    discs = corner_xy[is_corner], corner_s[is_corner]        # the shoulders are no discs
    corner_tree = cKDTree(discs[0]) if len(discs[0]) else None   # one for every round
    edge_size = ring_size.copy()
    flat_edge = edges[4][dense["ring"]] + dense["edge"]
    for round_ in range(_ROUNDS):
        if round_:
            parts = int(np.sum(np.ceil(4 * edges[2] / edge_size)))
            if parts > _MAX_DENSE:
                break                   # keep the last densification: memory stays bounded
            dense = _densify(edges, edge_size, ring_size, piece)
            flat_edge = edges[4][dense["ring"]] + dense["edge"]
        size, new = _round(region, dense, flat_edge, edge_size, cap, corner_tree, discs[1])
        changed = bool(np.any(new < 0.7 * edge_size))
        edge_size = new
        if not changed:
            break
    return (np.concatenate([dense["xy"], corner_xy, edges[0]]),
            np.concatenate([size, corner_s, vertex_size]))


def _round(region, dense, flat_edge, edge_size, cap, corner_tree, corner_s):
    """One round of :func:`_features`: the size at each densified point (its wall's, or
    its corner's inside a corner's disc) and each edge's size, the smallest on it."""
    size = _wall_sizes(region, dense, cap)
    size = np.where(_in_corner_discs(dense, corner_tree, corner_s), dense["base"], size)
    smallest = np.full(len(edge_size), np.inf)
    np.minimum.at(smallest, flat_edge, size)
    return size, np.minimum(edge_size, smallest)


def _ring_sizes(edges, cap, sharp_turn, curve, per_piece):
    """Sizes from each ring alone, all rings at once (``edges`` from :func:`_edges`): per
    edge (piece length, perimeter) and per vertex (also the curvature), the piece index
    of each edge within its ring, which vertices are sharp corners, and the signed
    turning angle at each vertex (as :func:`pds_plugin.region.turning_angles`)."""
    start, d, length, ring_of, first = edges
    following = np.append(first[1:], len(start))                # one past each ring's end
    previous = np.arange(-1, len(start) - 1)
    previous[first] = following - 1
    into = d[previous]
    signed = np.arctan2(into[:, 0] * d[:, 1] - into[:, 1] * d[:, 0],
                        (into * d).sum(axis=1))
    turn = np.abs(signed)
    sharp = turn >= sharp_turn
    counts = np.bincount(ring_of, weights=sharp, minlength=len(first)).astype(np.int64)
    running = np.cumsum(sharp)
    before = np.where(first > 0, running[first - 1], 0)
    piece = (running - before[ring_of]) % np.maximum(counts, 1)[ring_of]   # within its ring
    offset = np.cumsum(np.maximum(counts, 1)) - np.maximum(counts, 1)
    piece_length = np.bincount(offset[ring_of] + piece, weights=length)
    perimeter = np.array([length[lo:hi].sum() for lo, hi in zip(first, following)])
    size = np.minimum(cap, _RING * perimeter)[ring_of]
    edge_size = np.minimum(size, per_piece * piece_length[offset[ring_of] + piece])
    size = np.minimum(edge_size, edge_size[previous])           # per vertex: both edges
    mean_edge = 0.5 * (length + length[previous])
    curved = ~sharp & (turn > 1e-12)
    size[curved] = np.minimum(size[curved], curve * mean_edge[curved] / turn[curved])
    return edge_size, size, piece, sharp, signed


def _edges(rings):
    """Every ring's edges at once: (start vertices, edge vectors, lengths, ring of each
    edge, index of each ring's first edge), edge k of a ring from its vertex k to k + 1."""
    start = np.concatenate(rings)
    counts = np.array([len(ring) for ring in rings])
    first = np.cumsum(counts) - counts
    following = np.arange(1, len(start) + 1)
    following[first + counts - 1] = first
    d = start[following] - start
    return start, d, np.hypot(d[:, 0], d[:, 1]), np.repeat(np.arange(len(rings)), counts), first


def _densify(edges, edge_size, ring_size, piece):
    """Points along every edge (``edges`` from :func:`_edges`) at spacing <= a quarter of
    its size, with the edge's inward unit normal, ring, edge and piece index, and its
    size from the ring alone; all rings at once."""
    start, d, length, ring_of, first = edges
    parts = np.maximum(np.ceil(4 * length / edge_size), 1).astype(np.int64)
    edge = np.repeat(np.arange(len(start)), parts)
    begin = np.cumsum(parts) - parts
    t = (np.arange(parts.sum()) - begin[edge] + 0.5) / parts[edge]
    return {"xy": start[edge] + t[:, None] * d[edge],
            "normal": np.column_stack([-d[edge, 1], d[edge, 0]]) / length[edge, None],
            "ring": ring_of[edge], "edge": edge - first[ring_of[edge]],
            "piece": piece[edge], "base": ring_size[edge]}


def _wall_sizes(region, dense, cap):
    """Each point's size: its ring size, lowered to _WALL x the distance to the nearest
    point facing it through material (normals opposed, midpoint in the region).

    Only walls nearer than ring size / _WALL can lower a size, so the facing points are
    searched that far (rounded up to a power of two), nearest first, in a k-d tree of the
    points (``_sizing_kernels.nearest_facing``): the nearest facing point, then for the
    points whose midpoint with it is outside the region the next one, and so on."""
    xy, normal = dense["xy"], dense["normal"]
    perm, first, stop, left, right, box, _ = kern.build_cone_tree(xy, np.zeros(len(xy)), 8)
    normal_box = kern.normal_bounds(normal, first, stop, perm)
    wall = np.full(len(xy), np.inf)
    reach = np.exp2(np.ceil(np.log2(np.minimum(dense["base"], cap) / _WALL)))
    rows = np.flatnonzero(reach > 0)
    after_d, after_j = np.zeros(len(rows)), np.full(len(rows), np.iinfo(np.int64).max)
    for attempt in range(_FACING_TRIES):
        if not len(rows):
            break
        d, j = kern.nearest_facing(xy, normal, rows, reach[rows], after_d, after_j, _OPPOSED,
                                   perm, first, stop, left, right, box, normal_box)
        found = j >= 0
        rows, d, j = rows[found], d[found], j[found]
        mid = 0.5 * (xy[rows] + xy[j])
        inside = shapely.contains_xy(region.geometry, mid[:, 0], mid[:, 1])
        if attempt == _FACING_TRIES - 1:
            inside[:] = True                # the last tried is taken as the wall: nearer
        wall[rows[inside]] = d[inside]
        rows, after_d, after_j = rows[~inside], d[~inside], j[~inside]
    return np.minimum(dense["base"], _WALL * wall)


_FACING_TRIES = 64
"""Facing points tried per point at most by :func:`_wall_sizes`, nearest first; the last
is taken as the wall even if the midpoint is not in the region (a nearer wall, a smaller
size: never a larger one). A ring folded back onto its own vertex (a zero-width spike)
had points with thousands of facing points whose midpoints lie on its boundary, tried
one call each: 37 s for one field."""


def _corner_discs(region, rings, edges, sharp, turn, piece, dense, with_rings=False):
    """Sharp corners and their disc radius: _CORNER x the distance to the nearest
    boundary point that is not on the two pieces incident to the corner and is seen
    through material (the midpoint in the region: a notch or gap does not count), at
    most the ring sizes of those pieces. Returns the features (the corners and their
    shoulders), their sizes, and which are corners: only a corner's own disc suspends the
    wall rule. Taken from the shoulders too, the discs reached 3 sizes along a spike's
    sides, and a 0.66 r thin spike kept r from its far-away corner (held-out corpus seed
    32, g06-shaft p4: the arc past the tip 1.08 r from every sample).

    A convex corner where the region's angle is below _FLAT_BELOW (60°) gets the same
    size along its two sides, up to _FLAT_REACH times it (:func:`_shoulders`): the field
    is then about flat where the sampler puts the corner's neighbours p, q (at most
    1.02 √3 r from it, graded_sampling._corner_clearance), and their triangle with the
    corner c, of circumradius |p - c| / (2 cos(θ/2)) <= 1.02 r / (2 sin θ) < 0.93 r above
    33.56°, stays within what the complex keeps, min r / (1 - L). Where the field grew
    at the rate L from the corner instead, r(p) reached (1 + 1.6 L) r(c) at 37° and the
    triangle was dropped: a tooth's tip came off at L = 0.3."""
    ring_of = edges[3]
    corner = np.flatnonzero(sharp)
    if not len(corner):
        none = np.empty((0, 2)), np.empty(0), np.zeros(0, bool)
        return (*none, np.zeros(0, np.int64)) if with_rings else none
    at, k = edges[0][corner], ring_of[corner]
    previous = np.arange(-1, len(sharp) - 1)
    previous[edges[4]] = np.append(edges[4][1:], len(sharp)) - 1
    incident = np.column_stack([piece[corner], piece[previous[corner]]])
    # the smallest ring size on each (ring, piece): the corner's size is at most that
    width = int(dense["piece"].max()) + 1
    keys, where = np.unique(dense["ring"] * width + dense["piece"], return_inverse=True)
    base = np.full(len(keys), np.inf)
    np.minimum.at(base, where, dense["base"])
    on_pieces = np.minimum(base[np.searchsorted(keys, k * width + incident[:, 0])],
                           base[np.searchsorted(keys, k * width + incident[:, 1])])
    far = _nearest_other(region, dense, edges, piece, at, k, incident,
                         on_pieces / _CORNER * (1 + 1e-9))
    size = np.minimum(_CORNER * far, on_pieces)
    if not np.any(turn[corner] > math.pi - _FLAT_BELOW):
        out = at, size, np.ones(len(corner), bool)
        return (*out, k) if with_rings else out
    xy, s, is_corner, of = [], [], [], []
    for c, v in enumerate(corner):
        xy.append(edges[0][v][None])
        s.append(size[c:c + 1])
        is_corner.append([True])
        of.append(k[c:c + 1])
        if turn[v] > math.pi - _FLAT_BELOW:
            ring = rings[k[c]]
            shoulders = _shoulders(ring, v - edges[4][k[c]], size[c])
            xy.append(shoulders)
            s.append(np.full(len(shoulders), size[c]))
            is_corner.append(np.zeros(len(shoulders), bool))
            of.append(np.full(len(shoulders), k[c]))
    out = np.concatenate(xy), np.concatenate(s), np.concatenate(is_corner)
    return (*out, np.concatenate(of)) if with_rings else out


def _nearest_other(region, dense, edges, piece, at, ring, incident, reach):
    """For each corner (at ``at``, on ``ring``, between the pieces ``incident``): the
    distance to the nearest boundary point not on those two pieces whose midpoint with
    the corner is in the region (inf if none, or if none is nearer than the corner's
    ``reach``): the nearest such densified point, then the feet on the edges of the
    densified points that near (:func:`_nearer_feet`).

    Only a point nearer than ``reach`` (where the corner's disc is as large as its
    pieces allow) can change the corner's size, so a corner stops searching once its
    nearest points beyond ``reach`` are seen: a large face's square corner sees only its
    own two sides, and its search widened to every point of the face (78 % of such a
    face's field, 1.2 ms, in remeshing).

    The nearest neighbours are searched in widening rounds (24, 96, 384, ... points), and
    within a round only each corner's nearest few candidates off its pieces are tested
    against the region (4, then 16, 64, ... more where no midpoint was inside): a
    corner's answer is the smallest distance of a qualifying point, so it depends on
    neither the rounds nor the batches, and the first batch usually settles it (the
    in-region test of all 96 neighbours of every corner was a third of the field's
    construction on small sections). The rounds grow fourfold: a corner of a small hole
    sees its own hole's points first, all with their midpoints in the hole, and a third
    round of all points for each such corner took 1.4 s on a drawing of 400 holes."""
    xy, n = dense["xy"], len(dense["xy"])
    joined = isinstance(region, _Joined)
    owner = region.owner if joined else None
    tree = cKDTree(xy)
    far = np.full(len(at), np.inf)
    todo = np.arange(len(at))
    count = _K
    while True:
        count = min(count, n)
        d, idx = tree.query(at[todo], k=count)
        d, idx = d.reshape(len(todo), -1), idx.reshape(len(todo), -1)
        other = ~((dense["ring"][idx] == ring[todo, None])
                  & ((dense["piece"][idx] == incident[todo, :1])
                     | (dense["piece"][idx] == incident[todo, 1:])))
        if joined:                          # only the corner's own region's points
            other &= owner[dense["ring"][idx]] == owner[ring[todo, None]]
        batch = 4
        while other.any():
            tested = other & (np.cumsum(other, axis=1) <= batch)
            row, column = np.nonzero(tested)
            mid = 0.5 * (xy[idx[row, column]] + at[todo[row]])
            inside = np.zeros_like(other)
            inside[row, column] = shapely.contains_xy(region.geometry, mid[:, 0], mid[:, 1])
            found = inside.any(axis=1)
            far[todo[found]] = d[found, np.argmax(inside[found], axis=1)]
            other[found] = False
            other &= ~tested
            batch *= 4
        left = np.isinf(far[todo]) & (d[:, -1] <= reach[todo])
        if joined:                          # all of its region's points seen: none counts
            left &= d[:, -1] <= region.diameter[owner[ring[todo]]]
        todo = todo[left]
        if not len(todo) or count >= n:
            return _nearer_feet(region, edges, piece, at, ring, incident, far, reach)
        count *= 4


def _nearer_feet(region, edges, piece, at, ring, incident, far, reach):
    """``far`` lowered to each corner's distance to its foot on an edge of another piece
    whose midpoint with the corner is in the region, where that is nearer than ``far``
    (or than ``reach``, where ``far`` is inf). The densified points are a quarter
    of their edge's size apart, which the first round takes from the ring alone: a
    reflex corner of a gear's section 0.0036 from a 46 long edge was 0.3 from that
    edge's nearest point, and its disc, 0.12 wide, hid the neck from the wall rule too
    (its graded mesh non-manifold there). The edges within that distance of each corner
    are asked of a tree of the edges."""
    within = np.where(np.isfinite(far), far, reach)
    corners = np.flatnonzero(np.isfinite(within))
    start, d, length = edges[0], edges[1], edges[2]
    segments = shapely.linestrings(np.stack([start, start + d], axis=1))
    c, e = shapely.STRtree(segments).query(shapely.points(at[corners]), predicate="dwithin",
                                            distance=within[corners])
    c = corners[c]
    other = ~((edges[3][e] == ring[c]) & ((piece[e] == incident[c, 0]) | (piece[e] == incident[c, 1])))
    if isinstance(region, _Joined):
        other &= region.owner[edges[3][e]] == region.owner[ring[c]]
    c, e = c[other], e[other]
    t = np.clip(((at[c] - start[e]) * d[e]).sum(axis=1) / np.maximum(length[e] ** 2, 1e-300), 0, 1)
    foot = start[e] + t[:, None] * d[e]
    distance = np.hypot(*(foot - at[c]).T)
    nearer = distance < within[c]
    mid = 0.5 * (foot[nearer] + at[c[nearer]])
    seen = shapely.contains_xy(region.geometry, mid[:, 0], mid[:, 1])
    far = far.copy()
    np.minimum.at(far, c[nearer][seen], distance[nearer][seen])
    return far


def _shoulders(ring, v, size):
    """Points along the two edges of ring vertex v, every quarter of ``size`` up to
    _FLAT_REACH x size from it (at most the edges' lengths): with the corner's size they
    keep the field within L size / 8 of it there."""
    steps = 0.25 * size * np.arange(1, 4 * _FLAT_REACH + 1)
    out = []
    for end in (ring[(v + 1) % len(ring)], ring[v - 1]):
        edge = end - ring[v]
        length = math.hypot(*edge)
        t = steps[steps < length]
        out.append(ring[v] + t[:, None] * (edge / length))
    return np.concatenate(out)


def _in_corner_discs(dense, corner_tree, corner_s):
    """True for the densified points inside some corner's disc (``corner_tree``: a
    k-d tree of the corners' centres, None without corners)."""
    if corner_tree is None:
        return np.zeros(len(dense["xy"]), bool)
    d, idx = corner_tree.query(dense["xy"], k=1)
    return d < corner_s[idx]
