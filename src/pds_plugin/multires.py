"""Multiresolution: meshes and certificates of one region for a series of alphas.

The paper's closing remark: as alpha decreases, a mesh first resolves the *topological*
features of a region (its components and holes), then its *geometric* ones (the shapes of
the holes). :func:`multiresolution` makes that series; each certificate says which
features a level has.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from .mesh import PlanarMesh, mesh_region
from .region import Region
from .sampling import DEFAULT_MAX_SAMPLES, estimate_samples

__all__ = ["Resolution", "multiresolution"]


class Resolution(NamedTuple):
    """One level of a multiresolution series; unpacks as ``alpha, mesh, certificate``."""

    alpha: float
    mesh: PlanarMesh
    certificate: object     # pds_plugin.Certificate

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
    ValueError
        If ``alphas`` is empty or holds a non-positive or non-finite value, or if the
        finest level would exceed the sample budget (checked before any meshing).

    Examples
    --------
    >>> from shapely.geometry import Point
    >>> import pds_plugin as pds
    >>> disc = Point(0, 0).buffer(1).difference(Point(0.5, 0).buffer(0.15))
    >>> levels = pds.multiresolution(pds.Region.from_shapely(disc), [0.4, 0.05])
    >>> [level.certificate.betti_mesh for level in levels]
    [(1, 0), (1, 1)]
    """
    if not isinstance(region, Region):
        raise TypeError(f"multiresolution needs a pds_plugin.Region, got {type(region).__name__}")
    try:
        alphas = [float(a) for a in alphas]
    except (TypeError, ValueError):
        raise TypeError(f"alphas must be an iterable of numbers, got {alphas!r}") from None
    if not alphas:
        raise ValueError("alphas is empty: give at least one radius")
    bad = [a for a in alphas if not (math.isfinite(a) and a > 0)]
    if bad:
        raise ValueError(f"every alpha must be a positive finite number, got {bad[0]}")
    budget = sampling_options.get("max_samples", DEFAULT_MAX_SAMPLES)
    finest = min(alphas)
    if estimate_samples(region, finest) > budget:
        raise ValueError(f"alpha {finest:.6g} would make about "
                         f"{estimate_samples(region, finest):.3g} samples, more than "
                         f"max_samples={budget}; drop it or raise max_samples")
    levels = []
    for alpha in alphas:
        mesh = mesh_region(region, alpha, seed=seed, **sampling_options)
        levels.append(Resolution(alpha, mesh, mesh.certificate()))
    return levels
