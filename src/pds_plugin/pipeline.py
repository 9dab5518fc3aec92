"""The pipeline: region -> samples -> complex -> mesh, and what is built on it.

- :func:`mesh_region` samples a region and meshes the samples (alpha given or ``"auto"``);
- :func:`suggest_alpha` and :func:`auto_mesh` choose alpha from the feature size and
  verify the mesh's topology (Theorem 2);
- :func:`multiresolution` meshes one region at a series of alphas;
- :func:`section_report` is the JSON-ready report of one meshed section (plane, region,
  feature size, quality, certificate), as ``pds-mesh --report`` writes it.
"""

from __future__ import annotations

import difflib
import inspect
import warnings
from typing import NamedTuple

import numpy as np

from ._checks import check_alpha, check_positive, check_positive_int, check_seed
from .analysis.certificate import Certificate
from .analysis.feature import FeatureSize, feature_size, past_small_components
from .analysis.topology import topology_report
from .complex import solid_alpha_complex
from .errors import ArgumentError, ArgumentTypeError, BudgetError, RegionError, TopologyError
from .graded_complex import graded_alpha_complex
from .graded_sampling import graded_poisson_disc
from .mesh import PlanarMesh
from .region import ALPHA_RESOLUTION, Region, require_region
from .sampling import (DEFAULT_MAX_SAMPLES, check_budget, estimate_samples, largest_alpha,
                       poisson_disc)
from .sizing import DEFAULT_GRADING, graded_request, inradius, radius_field

__all__ = ["mesh_region", "suggest_alpha", "auto_mesh", "Resolution", "multiresolution",
           "section_report"]

SAMPLING_OPTIONS = tuple(name for name, parameter in inspect.signature(poisson_disc).parameters.items()
                         if parameter.kind is parameter.KEYWORD_ONLY and name != "conforming")
"""The keywords of :func:`poisson_disc` that ``mesh_region(**sampling_options)`` passes on."""


def mesh_region(region: Region, alpha, seed: int = 0, *, conforming: bool = True,
                graded: bool | None = None, grading: float | None = None, sizing=None,
                **sampling_options) -> PlanarMesh:
    """Sample ``region`` with a maximal Poisson disc sampling of radius ``alpha`` and
    mesh the samples with the solid alpha-complex of the same radius.

    By default the mesh is *conforming*: consecutive boundary samples are joined by mesh
    edges (the mesh's boundary is the chords between them, so on polygonal regions the
    union of the triangles is the region), and *constrained*: samples conflict, and
    triangles form, only between samples that see each other through the region, so
    notches, slots and gaps narrower than alpha stay open (docs/conforming.md).
    ``conforming=False`` gives the paper's pure solid alpha-complex.

    A *graded* mesh replaces the one radius by a radius field r(x) <= alpha that follows
    the region's walls, holes and corners and is ``grading``-Lipschitz, combined by min
    with a user ``sizing``; every angle is then at least arcsin((1 - grading)/2) (23.6°
    at the default 0.2) and the certificate measures against r (docs/graded.md). A
    ``sizing`` or a ``grading`` asks for it (``graded=True`` is then redundant), and
    ``graded=True`` alone for the region's own field; with ``alpha="auto"`` the field is
    capped only by the region's own size (its inradius): the coarsest mesh that keeps
    every feature. Without any of them the mesh is uniform.

    By Theorem 1 of the paper every triangle then has aspect ratio L²/A ≤ 4√3 (all
    angles in [30°, 120°]); :meth:`PlanarMesh.certificate` measures it. With
    ``alpha="auto"`` the radius comes from the region's feature size and is lowered
    until the mesh has the region's topology (see :func:`auto_mesh`, which takes the
    same keywords).

    Parameters
    ----------
    region : Region
    alpha : float or "auto"
        The radius of both the sampling and the complex, in the region's units.
    seed : int
        Seed of the random generator; the same seed gives the same mesh, bit for bit.
    conforming : bool
        Conforming and constrained (the default), or the paper's pure construction.
    graded : bool, optional
        True: a graded mesh (always conforming and constrained) with the region's own
        field; implied by ``grading`` and ``sizing``. False refuses them.
    grading : float, optional
        The Lipschitz constant L of the radius field, in (0, 1); default
        :data:`pds_plugin.sizing.DEFAULT_GRADING`. Makes the mesh graded.
    sizing : float, callable or RadiusField, optional
        The user's radius, which makes the mesh graded: a number is the largest radius
        (as ``alpha``); a callable ``sizing(x, y)`` on arrays, or a
        :class:`~pds_plugin.RadiusField`, is combined with the region's field by min
        (:func:`pds_plugin.sizing.graded_request`).
    **sampling_options
        Passed to :func:`pds_plugin.poisson_disc` (``max_samples``, ``feature_angle``),
        or with ``"auto"`` to :func:`auto_mesh` (also ``max_alpha``, ``refine``).

    Returns
    -------
    PlanarMesh

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``region`` is not a Region or ``alpha`` is not a positive number or "auto".
    BudgetError
        If the sampling would exceed ``max_samples``.

    With ``"auto"`` a valid region always gets a mesh: where the sample budget keeps
    alpha above what a feature needs and the topology is lost, the mesh at the smallest
    alpha the budget allows is returned with a warning (:func:`auto_mesh` raises a
    :class:`~pds_plugin.errors.TopologyError` there), and its certificate lists what it
    could not keep. Where that feature lies in a component smaller than the alpha the
    other components ask for (a speck of a section), that alpha is used instead if the
    budget allows it, the speck meshed whole as a small ring, with a warning.

    Examples
    --------
    >>> from shapely.geometry import box
    >>> import pds_plugin as pds
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.1, seed=0)
    >>> mesh.certificate().ok
    True
    >>> mesh.conforming, mesh.outline.equals(box(0, 0, 1, 1))
    (True, True)
    >>> plate = pds.Region.from_shapely(box(0, 0, 40, 10).difference(box(1, 1, 39, 1.5)))
    >>> graded = pds.mesh_region(plate, "auto", graded=True)
    >>> graded.certificate().ok, graded.certificate().betti_mesh
    (True, (1, 1))
    >>> finer_left = pds.mesh_region(plate, "auto", sizing=lambda x, y: 0.5 + 0.1 * x)
    >>> finer_left.field is not None, finer_left.certificate().ok    # graded by its sizing
    (True, True)
    """
    if isinstance(alpha, str) and alpha != "auto":
        raise ArgumentError(f"alpha must be a positive number or 'auto', got {alpha!r}")
    graded, alpha, sizing = graded_request(alpha, graded, grading, sizing)
    if graded:
        return _graded_mesh(region, alpha, seed, conforming, grading, sizing, sampling_options)
    if isinstance(alpha, str):
        try:
            return auto_mesh(region, seed=seed, conforming=conforming, **sampling_options)
        except TopologyError as error:
            warnings.warn(f"{error}; meshed at that alpha anyway: its certificate lists what "
                          "it could not keep", stacklevel=2)
            return error.mesh
    _check_resolution(require_region(region, "mesh_region"), check_alpha(alpha))
    check_seed(seed)
    _check_sampling_options(sampling_options)
    samples = poisson_disc(region, alpha, seed=seed, conforming=conforming, **sampling_options)
    faces = solid_alpha_complex(samples.points, alpha, boundary=samples.rings)
    sampled = region if samples.region is None else samples.region   # moved onto its arcs
    return PlanarMesh(samples.points, faces, samples.on_boundary, sampled, alpha, conforming)


def _graded_mesh(region, alpha, seed, conforming, grading, sizing, options) -> PlanarMesh:
    """mesh_region(graded=True): radius field, graded sampling, graded complex."""
    require_region(region, "mesh_region")
    check_seed(seed)
    if not conforming:
        raise ArgumentError("graded meshes are always conforming; leave conforming=True")
    cap = None if alpha == "auto" else check_alpha(alpha)
    _check_sampling_options(options)
    if cap is not None:              # the graded sampling makes at least the uniform's
        check_budget(region, cap, check_positive_int(
            options.get("max_samples", DEFAULT_MAX_SAMPLES), "max_samples"))
    field = radius_field(region, DEFAULT_GRADING if grading is None else grading, cap, sizing,
                         options.get("feature_angle", 30.0))
    samples = graded_poisson_disc(region, field, seed, **options)
    faces = graded_alpha_complex(samples.points, samples.radius, field.grading,
                                 boundary=samples.rings, chords=samples.chords)
    sampled = region if samples.region is None else samples.region   # moved onto its arcs
    return PlanarMesh(samples.points, faces, samples.on_boundary, sampled, field.cap, True,
                      field=field)


def _check_sampling_options(options: dict):
    """Refuse a keyword that :func:`poisson_disc` does not take, naming the nearest one."""
    for name in options:
        if name not in SAMPLING_OPTIONS:
            near = difflib.get_close_matches(name, SAMPLING_OPTIONS, n=1)
            raise ArgumentTypeError(f"mesh_region has no option {name!r}"
                                    + (f"; did you mean {near[0]!r}?" if near else "")
                                    + f" (its sampling options: {', '.join(SAMPLING_OPTIONS)})")


def suggest_alpha(region: Region, max_samples: int | None = None,
                  conforming: bool = True) -> float:
    """The largest alpha that satisfies the paper's sampling condition (3) for ``region``.

    Theorem 2 asks ``alpha <= ½ min LFS(∂R)``. Between two boundary features at distance
    ``d`` (:func:`pds_plugin.feature_size`) the medial axis runs midway, so ``LFS ≈ d/2`` and the
    suggestion is ``alpha = ½·(d/2) = d/4``: half the feature size in the paper's sense.
    For the paper's complex (``conforming=False``) a gap of width ``g`` then stays open
    (triangles of circumradius ``<= alpha`` can bridge it only when
    ``g <= (1 + √3/2)·alpha``), and so does a circular hole of radius ``r``:
    ``alpha ≈ 0.48·r`` (the paper's Figure 6 uses ``r/2``), while the hole closes near
    ``alpha = r`` -- which ``d/2 ≈ 0.97·r`` would not avoid. A conforming mesh keeps gaps
    and holes open at any alpha, so only walls count (``conforming=True``, the default).

    Parameters
    ----------
    region : Region
    max_samples : int, optional
        Sample budget (default: the sampler's). If the suggestion would need more samples,
        the alpha that fits the budget is returned instead, with a warning naming the
        feature that is then not guaranteed.
    conforming : bool
        Which features count, see :func:`pds_plugin.feature_size`.

    Returns
    -------
    float

    Raises
    ------
    RegionError
        If the boundary touches itself (feature size 0): no alpha keeps it apart.

    Examples
    --------
    >>> from shapely.geometry import Point
    >>> ring = Region.from_shapely(Point(0, 0).buffer(1.0).difference(Point(0, 0).buffer(0.8)))
    >>> round(suggest_alpha(ring), 3)      # wall 0.2 thick (up to the buffer's polygon)
    0.05
    """
    size = _usable_feature_size(region, conforming)
    alpha = size.lfs / 2
    budget = _budget(max_samples)
    capped = largest_alpha(region, budget)
    if alpha >= capped:
        return alpha
    rest = _past_small_rings(region, size, budget, capped) if conforming else None
    if rest is not None:
        return rest.lfs / 2
    _warn_over_budget(region, size, budget, capped)
    return capped


def _past_small_rings(region: Region, size: FeatureSize, budget: int,
                      smallest: float) -> FeatureSize | None:
    """Where the feature ``size`` asks for an alpha below ``smallest`` (the sample
    budget's), the thinnest wall outside the components smaller than its alpha
    (:func:`pds_plugin.analysis.feature.past_small_components`) if its alpha is within
    the budget, with a warning that those components are meshed whole, as small rings;
    else None."""
    rest = past_small_components(region, size)
    if rest is size or rest.lfs / 2 < smallest:
        return None
    warnings.warn(f"alpha {size.lfs / 2:.6g} needed for the {size} would take over the budget "
                  f"of {budget} samples; using alpha {rest.lfs / 2:.6g}, for the {rest}: the "
                  "components smaller than that are meshed whole, as small rings, their close "
                  "samples listed as exceptions (raise max_samples to resolve them)",
                  stacklevel=3)
    return rest


def _warn_over_budget(region: Region, size: FeatureSize, budget: int, used: float) -> None:
    """Say that the budget keeps alpha above what the narrowest feature needs."""
    needed = size.lfs / 2
    samples = estimate_samples(region, needed)
    over = (f"about {samples:.3g} samples, over the budget of {budget}" if samples > budget
            else "a sampling grid over the region's bounding box beyond its limit")
    warnings.warn(f"alpha {needed:.6g} needed for the {size} would take {over}; using alpha "
                  f"{used:.6g}, which may lose that feature (raise max_samples, or mesh the "
                  f"far-apart parts separately, to keep it)", stacklevel=3)


HEAVY_UNIFORM = 200_000
"""Samples over which a uniform ``"auto"`` mesh whose alpha one feature sets far below
the region's own size (:data:`FAR_BELOW`) says that ``graded=True`` would be lighter."""
FAR_BELOW = 20.0
"""How many times below the region's inradius alpha is "far below" (:data:`HEAVY_UNIFORM`)."""


def _warn_if_one_feature_costs(region: Region, size: FeatureSize, alpha: float) -> None:
    """Say when the feature ``size`` sets a uniform alpha far below the region's own
    size and the mesh is heavy for it (a thin wall where a tessellated hole nears an
    outline: the whole region at a fraction of that wall's width), and what is lighter."""
    samples = estimate_samples(region, alpha)
    if samples <= HEAVY_UNIFORM:
        return
    own = inradius(region)
    if alpha * FAR_BELOW < own:
        warnings.warn(f"alpha 'auto' is {alpha:.3g}, set by the {size}: {own / alpha:.0f} "
                      f"times below the region's inradius {own:.3g}, about {samples:.2g} "
                      "samples; a graded mesh (graded=True, pds-mesh's default) is as fine "
                      f"at that feature and grows to {own:.3g} away from it", stacklevel=3)


def auto_mesh(region: Region, seed: int = 0, max_alpha: float | None = None,
              refine: float = 0.7, **sampling_options):
    """Mesh ``region`` with an alpha whose mesh has the region's topology, verified.

    Starts from ``max_alpha`` if given (the coarsest mesh the caller accepts), else from
    :func:`suggest_alpha`; meshes, checks the topology with
    :func:`pds_plugin.topology.topology_report`, and multiplies alpha by ``refine`` until
    every component's Betti numbers match and no hole is lost, merged, opened or split.
    The first alpha that passes is kept, so from ``max_alpha`` this finds the coarsest
    verified mesh of the series ``max_alpha·refine^k``.

    Parameters
    ----------
    region : Region
    seed : int
    max_alpha : float, optional
        The first alpha to try.
    refine : float
        Factor in (0, 1) applied to alpha after each failed check.
    **sampling_options
        Passed to :func:`pds_plugin.mesh_region`; ``max_samples`` is also the budget
        below whose alpha the refinement stops, and ``conforming`` (True unless given)
        chooses the features that set the first alpha (:func:`pds_plugin.feature_size`).

    Returns
    -------
    PlanarMesh
        Its ``certificate().topology_ok`` is True. When the sample budget keeps alpha
        above what the narrowest feature needs (a slot may then be bridged without
        changing the topology), a warning says so, as :func:`suggest_alpha` does; so
        does one, before sampling, when that feature sets alpha :data:`FAR_BELOW` times
        below the region's inradius and the mesh takes over :data:`HEAVY_UNIFORM`
        samples (a graded mesh is then a fraction of it).

    Raises
    ------
    TopologyError
        If the topology is still wrong at the smallest alpha the budget allows; the
        message names the feature that needs a smaller alpha, that alpha, and what the
        last mesh lost and where.

    Examples
    --------
    >>> from shapely.geometry import Point
    >>> region = Region.from_shapely(Point(0, 0).buffer(1).difference(Point(0.4, 0).buffer(0.2)))
    >>> mesh = auto_mesh(region, max_alpha=1.0, conforming=False)   # the paper's complex
    >>> mesh.certificate().topology_ok, mesh.alpha < 0.2
    (True, True)
    """
    if not 0 < refine < 1:
        raise ArgumentError(f"refine must lie in (0, 1), got {refine!r}")
    budget = _budget(sampling_options.pop("max_samples", None))
    size = _usable_feature_size(region, sampling_options.get("conforming", True))
    alpha = size.lfs / 2 if max_alpha is None else check_positive(max_alpha, "max_alpha")
    smallest = largest_alpha(region, budget) * (1 + 1e-9)     # the budget's smallest alpha
    if max_alpha is None and alpha < smallest and sampling_options.get("conforming", True):
        rest = _past_small_rings(region, size, budget, smallest)
        if rest is not None:
            size, alpha = rest, rest.lfs / 2
    alpha = max(alpha, smallest)
    if max_alpha is None and alpha == size.lfs / 2:        # set by the feature, not the budget
        _warn_if_one_feature_costs(region, size, alpha)
    while True:
        mesh = mesh_region(region, alpha, seed=seed, max_samples=budget, **sampling_options)
        report = topology_report(mesh)
        if report.topology_ok:
            # the paper's complex bridges gaps narrower than alpha too, topology kept
            needs = size if mesh.conforming else _usable_feature_size(region, False)
            if mesh.alpha > needs.lfs / 2 and smallest > needs.lfs / 2:
                _warn_over_budget(region, needs, budget, mesh.alpha)  # e.g. a slot bridged
            return mesh
        if alpha <= smallest:
            break
        alpha = max(alpha * refine, smallest)
    raise TopologyError(f"the {size} needs alpha <= {size.lfs / 2:.6g}, but alpha "
                        f"{alpha:.6g} is the smallest the sample budget of {budget} allows, "
                        f"and its mesh: {'; '.join(report.problems)}; raise max_samples or "
                        "widen that feature", mesh=mesh)


def _check_resolution(region: Region, alpha: float) -> None:
    """Refuse an alpha the region's coordinates cannot resolve (the sampler would run
    away trying to place samples that rounding puts on top of each other)."""
    if alpha < ALPHA_RESOLUTION * region.resolution:
        raise ArgumentError(
            f"alpha={alpha:.6g} is below {ALPHA_RESOLUTION:g} times the float64 spacing "
            f"{region.resolution:.3g} of the region's coordinates (up to "
            f"{np.abs(region.bounds).max():.6g}); translate the region towards the origin "
            f"(move its frame's origin with it) or use alpha >= "
            f"{ALPHA_RESOLUTION * region.resolution:.3g}")


def _budget(max_samples) -> int:
    return DEFAULT_MAX_SAMPLES if max_samples is None else check_positive_int(max_samples,
                                                                               "max_samples")


def _usable_feature_size(region: Region, conforming: bool) -> FeatureSize:
    """The feature size, refused where no alpha the coordinates resolve can keep it."""
    size = feature_size(region, conforming)
    if size.value == 0:
        raise RegionError(f"the region's boundary touches itself ({size}): no alpha can keep "
                         "those parts apart; separate them or merge them in the geometry")
    if size.value < ALPHA_RESOLUTION * region.resolution:
        raise RegionError(
            f"the region's boundary comes within rounding of itself ({size}, less than "
            f"{ALPHA_RESOLUTION:g} float64 spacings of its coordinates): no alpha they "
            "resolve can keep those parts apart; separate or merge them in the geometry, "
            "or move the region towards the origin (a spike of zero width, where the "
            "boundary runs out and back along itself: Region.from_shapely(..., "
            "repair=True) drops it)")
    return size


class Resolution(NamedTuple):
    """One level of a multiresolution series; unpacks as ``alpha, mesh, certificate``.

    Attributes
    ----------
    alpha : float
        The level's radius.
    mesh : PlanarMesh
        The level's mesh.
    certificate : Certificate
        Its certificate: which features of the region this level keeps.
    """

    alpha: float
    mesh: PlanarMesh
    certificate: Certificate

    def __str__(self) -> str:
        c = self.certificate
        topology = "topology ok" if c.topology_ok else \
            f"topology lost: mesh (b0, b1) = {c.betti_mesh}, region {c.betti_region}"
        return (f"alpha {self.alpha:.6g}: {len(self.mesh.vertices)} vertices, "
                f"{len(self.mesh.faces)} triangles, {topology}")


def multiresolution(region: Region, alphas, seed: int = 0, **sampling_options) -> list[Resolution]:
    """Mesh ``region`` at each of ``alphas``, with the certificate of each mesh.

    Every level is an independent maximal Poisson disc sampling with the same ``seed``,
    meshed by its solid alpha-complex, so each satisfies Theorem 1 on its own; Theorem 2
    says from which alpha on a level has the region's topology (see
    :func:`pds_plugin.suggest_alpha`).

    Parameters
    ----------
    region : Region
    alphas : iterable of float
        The radii, in the order the levels are returned (typically coarse to fine).
    seed : int
    **sampling_options
        Passed to :func:`pds_plugin.poisson_disc` (``max_samples``, ``feature_angle``).

    Returns
    -------
    list of Resolution
        ``(alpha, mesh, certificate)`` per level.

    Raises
    ------
    ArgumentTypeError
        If ``region`` is not a Region or ``alphas`` not numbers.
    ArgumentError
        If ``alphas`` is empty or holds a non-positive or non-finite value, or if the
        finest level would exceed the sample budget (checked before any meshing;
        a :class:`~pds_plugin.errors.BudgetError`).

    Examples
    --------
    >>> from shapely.geometry import Point
    >>> import pds_plugin as pds
    >>> disc = Point(0, 0).buffer(1).difference(Point(0.5, 0).buffer(0.15))
    >>> levels = pds.multiresolution(pds.Region.from_shapely(disc), [0.4, 0.05],
    ...                              conforming=False)   # conforming meshes keep the hole
    >>> [level.certificate.betti_mesh for level in levels]
    [(1, 0), (1, 1)]
    """
    require_region(region, "multiresolution")
    try:
        alphas = [float(a) for a in alphas]
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"alphas must be an iterable of numbers, got {alphas!r}") from None
    if not alphas:
        raise ArgumentError("alphas is empty: give at least one radius")
    alphas = [check_positive(a, "every alpha") for a in alphas]
    budget = sampling_options.get("max_samples", DEFAULT_MAX_SAMPLES)
    finest = min(alphas)
    if estimate_samples(region, finest) > budget:
        raise BudgetError(f"alpha {finest:.6g} would make about "
                         f"{estimate_samples(region, finest):.3g} samples, more than "
                         f"max_samples={budget}; drop it or raise max_samples")
    levels = []
    for alpha in alphas:
        mesh = mesh_region(region, alpha, seed=seed, **sampling_options)
        levels.append(Resolution(alpha, mesh, mesh.certificate()))
    return levels


def section_report(mesh: PlanarMesh, *, seed: int, alpha_mode: str = "given",
                   output=None, plot=None, warnings=()) -> dict:
    """The JSON-ready report of one meshed section, as ``pds-mesh --report`` writes it.

    Parameters
    ----------
    mesh : PlanarMesh
        The mesh of the section (its region carries the plane).
    seed : int
        The seed the mesh was made with.
    alpha_mode : {"given", "auto"}
        How alpha was chosen.
    output, plot : str or os.PathLike, optional
        The files the mesh and its picture were written to, if any.
    warnings : sequence of str
        Warnings raised while making the mesh.

    Returns
    -------
    dict
        Keys ``output``, ``plot``, ``plane`` (origin, normal), ``frame``, ``region``
        (area, perimeter, bounds, betti), ``feature_size`` (value, kind, where),
        ``alpha``, ``alpha_mode``, ``seed``, ``samples``, ``triangles``, ``quality``
        (:meth:`Quality.stats`), ``certificate`` (:meth:`Certificate.as_dict`) and
        ``warnings``; plain lists, numbers and strings only.

    Raises
    ------
    ArgumentError
        If ``alpha_mode`` is not "given" or "auto".
    ArgumentTypeError
        If ``mesh`` is not a PlanarMesh.

    Examples
    --------
    >>> import json
    >>> from shapely.geometry import box
    >>> import pds_plugin as pds
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 2, 1)), 0.2)
    >>> report = pds.section_report(mesh, seed=0)
    >>> report["region"]["betti"], report["certificate"]["ok"], report["feature_size"]["kind"]
    ([1, 0], True, 'wall')
    >>> _ = json.dumps(report)
    """
    if alpha_mode not in ("given", "auto"):
        raise ArgumentError(f"alpha_mode must be 'given' or 'auto', got {alpha_mode!r}")
    if not isinstance(mesh, PlanarMesh):
        raise ArgumentTypeError(f"section_report takes a PlanarMesh (pds.mesh_region's), "
                                f"got {type(mesh).__name__}")
    check_seed(seed)
    region, frame = mesh.region, mesh.region.frame
    feature = feature_size(region)
    return {
        "output": None if output is None else str(output),
        "plot": None if plot is None else str(plot),
        "plane": {"origin": frame[:3, 3].tolist(), "normal": frame[:3, 2].tolist()},
        "frame": frame.tolist(),
        "region": {"area": region.area, "perimeter": region.perimeter,
                   "bounds": list(region.bounds), "betti": list(region.betti)},
        "feature_size": {"value": feature.value, "kind": feature.kind, "where": str(feature)},
        "alpha": mesh.alpha,
        "alpha_mode": alpha_mode,
        "seed": seed,
        "samples": len(mesh.vertices),
        "triangles": len(mesh.faces),
        "quality": mesh.quality().stats(),
        "certificate": mesh.certificate().as_dict(),
        "warnings": [str(w) for w in warnings],
    }
