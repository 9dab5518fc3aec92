"""The regions every peer meshes, and the alpha each one is meshed at.

The unit square is meshed at several sizes (alpha from the sample-count estimate of
:func:`~pds_plugin.sampling.estimate_samples`); every other region at one size, with alpha
no larger than :func:`pds_plugin.suggest_alpha` so that its topology is recoverable.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.sampling import estimate_samples

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
"""The shared sample inputs (real CAD parts, SVG drawings); regions from them are
skipped when the folder is absent."""


@dataclass(frozen=True)
class Case:
    """One region at one alpha: a row group of the benchmark table."""

    key: str           # command-line name of the region family (``--regions``)
    name: str          # shown in the table
    region: pds.Region
    alpha: float
    expected: float    # pds_plugin's sample-count estimate at this alpha


def alpha_for(region: pds.Region, samples: float) -> float:
    """The alpha at which ``estimate_samples(region, alpha)`` equals ``samples``.

    Solves ``0.7 * area / alpha**2 + perimeter / alpha = samples`` for alpha.

    >>> round(alpha_for(pds.Region.from_shapely(box(0, 0, 1, 1)), 7400), 6)
    0.01
    """
    a, p = 0.7 * region.area, region.perimeter
    return (p + math.sqrt(p * p + 4 * samples * a)) / (2 * samples)


def two_holes() -> pds.Region:
    """The paper's Figure 6 (a-c): a unit disc with two round holes, radii 0.4 and 0.1."""
    holes = Point(-0.35, 0).buffer(0.4, quad_segs=64).union(Point(0.5, 0).buffer(0.1, quad_segs=32))
    return pds.Region.from_shapely(Point(0, 0).buffer(1, quad_segs=64).difference(holes))


def pipe_hole() -> pds.Region:
    """The paper's Figure 6 (d-f): a unit disc whose hole is two circles of radius 0.25
    joined by a pipe 0.06 high."""
    hole = shapely.union_all([Point(-0.5, 0).buffer(0.25, quad_segs=64),
                              Point(0.5, 0).buffer(0.25, quad_segs=64),
                              box(-0.5, -0.03, 0.5, 0.03)])
    return pds.Region.from_shapely(Point(0, 0).buffer(1, quad_segs=64).difference(hole))


def cad_plate() -> pds.Region:
    """Mid-height section of a manifold3d plate (100 x 60 x 10) with three bolt holes, a
    rectangular pocket through it and a sharp 20° V notch cut into one edge."""
    import manifold3d as m3

    def bolt(x, y, radius):
        return m3.Manifold.cylinder(20.0, radius, circular_segments=64).translate((x, y, -5.0))

    notch = m3.CrossSection([np.array([[100.5, 24.0], [100.5, 36.0], [66.0, 30.0]])])
    pocket = m3.Manifold.cube((18.0, 10.0, 20.0)).translate((40.0, 40.0, -5.0))
    plate = (m3.Manifold.cube((100.0, 60.0, 10.0)) - bolt(15, 15, 6) - bolt(15, 45, 6)
             - bolt(45, 20, 3) - pocket - m3.Manifold.extrude(notch, 20.0).translate((0, 0, -5.0)))
    return pds.section(plate, plane_origin=(0.0, 0.0, 5.0), plane_normal=(0.0, 0.0, 1.0))


def svg_drawing() -> pds.Region:
    """MIL.svg, a CAD outline drawing with eight holes (one of its strokes is open,
    which load_svg reports in a warning that is not repeated here)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return pds.load_svg(DATA / "MIL.svg")


def stl_section(name: str):
    """The mid-height z section of a real part from the shared data folder."""
    def make() -> pds.Region:
        import trimesh
        lo, hi = trimesh.load_mesh(DATA / name).bounds
        return pds.section(DATA / name, plane_origin=(lo + hi) / 2, plane_normal=(0.0, 0.0, 1.0))
    return make


# key -> (table name, builder, needs a shared data file)
FIXED = {
    "two-holes": ("disc, two holes r and 4r (paper Fig. 6)", two_holes, None),
    "pipe": ("disc, two-circle hole with thin pipe (paper Fig. 6)", pipe_hole, None),
    "cad-plate": ("CAD plate section, sharp notch (manifold3d)", cad_plate, None),
    "mil-svg": ("MIL.svg drawing, 8 holes", svg_drawing, "MIL.svg"),
    "featuretype": ("featuretype.STL z-mid section", stl_section("featuretype.STL"),
                    "featuretype.STL"),
    "angle-block": ("angle_block.STL z-mid section", stl_section("angle_block.STL"),
                    "angle_block.STL"),
}
KEYS = ("square", *FIXED)


def cases(square_sizes, region_size: int, keys=KEYS) -> tuple[list[Case], list[str]]:
    """The benchmark's cases, and a note for each region that had to be left out.

    Parameters
    ----------
    square_sizes : sequence of int
        Sample counts of the unit-square cases.
    region_size : int
        Sample count aimed at for every other region (alpha is lowered further when
        the region's feature size asks for it).
    keys : sequence of str
        Region families to include (see ``KEYS``).
    """
    unknown = set(keys) - set(KEYS)
    if unknown:
        raise ValueError(f"unknown region(s) {sorted(unknown)}; choose from {list(KEYS)}")
    found, missing = [], []
    if "square" in keys:
        square = pds.Region.from_shapely(box(0, 0, 1, 1))
        for size in square_sizes:
            alpha = alpha_for(square, size)
            found.append(Case("square", f"unit square {_count(size)}", square, alpha,
                              estimate_samples(square, alpha)))
    for key in (k for k in FIXED if k in keys):
        name, make, data_file = FIXED[key]
        if data_file and not (DATA / data_file).exists():
            missing.append(f"{name}: {DATA / data_file} not found")
            continue
        region = make()
        alpha = alpha_for(region, region_size)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            alpha = min(alpha, pds.suggest_alpha(region))
        found.append(Case(key, name, region, alpha,
                          estimate_samples(region, alpha)))
    return found, missing


def _count(n: float) -> str:
    """10000 -> '10k', 1000000 -> '1M'."""
    for scale, suffix in ((1e6, "M"), (1e3, "k")):
        if n >= scale:
            return f"{n / scale:.3g}{suffix}"
    return f"{n:.0f}"
