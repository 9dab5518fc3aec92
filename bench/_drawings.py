"""Laser-cut drawings as CAD writes them, for ``bench/fixed_alpha.py``: a sheet of plates
with rounded corners (LINE + ARC), hundreds of CIRCLE holes of mixed sizes, slots (LINE +
ARC ends) and hexagonal cut-outs (LWPOLYLINE), written to DXF with ezdxf and read back
with :func:`pds_plugin.load_dxf`. Holes are placed on a jittered grid, some of them close
to a plate's edge or to each other (walls of a tenth of a hole's radius and up), so that
a fixed alpha meets walls, bands and holes both larger and smaller than itself.

Examples
--------
>>> region = laser_drawing(0)
>>> region.betti[0], region.betti[1] > 100       # plates, holes
(4, True)
"""

from __future__ import annotations

import math
import tempfile
import warnings
from functools import lru_cache
from pathlib import Path

import numpy as np

import pds_plugin as pds

PLATES = 4


@lru_cache(maxsize=None)
def laser_drawing(seed: int) -> pds.Region:
    """Sheet ``seed``: :data:`PLATES` plates of 60-110 x 40-80 units, each with a grid of
    features at a random pitch, read back from DXF."""
    import ezdxf

    rng = np.random.default_rng(seed)
    doc = ezdxf.new("R2010", units=4)
    space = doc.modelspace()
    x0 = 0.0
    for _ in range(PLATES):
        width, height = rng.uniform(60, 110), rng.uniform(40, 80)
        corner = rng.uniform(2, 8)
        rounded_plate(space, x0, 0.0, width, height, corner)
        _features(space, rng, x0, 0.0, width, height, corner)
        x0 += width + rng.uniform(5, 15)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"sheet-{seed}.dxf"
        doc.saveas(path)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return pds.load_dxf(path)


def rounded_plate(space, x0, y0, width, height, r):
    """A width x height rectangle from (x0, y0) with corners rounded to radius r: four
    LINEs and four ARCs in ezdxf's ``space``."""
    x1, y1 = x0 + width, y0 + height
    space.add_line((x0 + r, y0), (x1 - r, y0))
    space.add_line((x1, y0 + r), (x1, y1 - r))
    space.add_line((x1 - r, y1), (x0 + r, y1))
    space.add_line((x0, y1 - r), (x0, y0 + r))
    for (cx, cy), start in [((x1 - r, y0 + r), 270), ((x1 - r, y1 - r), 0),
                            ((x0 + r, y1 - r), 90), ((x0 + r, y0 + r), 180)]:
        space.add_arc((cx, cy), r, start, start + 90)


def _features(space, rng, x0, y0, width, height, corner):
    """Holes, slots and hexagons on a jittered grid inside the plate; the first and last
    row and column may come within a tenth of a feature's size of the plate's edge."""
    pitch = rng.uniform(6, 12)
    columns, rows = int((width - 2 * corner) // pitch), int((height - 2 * corner) // pitch)
    for i in range(columns):
        for j in range(rows):
            if rng.random() < 0.08 or i == j == 0:
                continue                   # a gap in the pattern; the rounded corner
            size = pitch * rng.uniform(0.15, 0.42)              # the feature's half-width
            cx = x0 + corner + pitch * (i + 0.5) + rng.uniform(-0.05, 0.05) * pitch
            cy = y0 + corner + pitch * (j + 0.5) + rng.uniform(-0.05, 0.05) * pitch
            wall = size * rng.uniform(0.1, 1.0)                 # to the plate's edge
            if i == 0:
                cx = x0 + size + wall
            if j == 0:
                cy = y0 + size + wall
            kind = rng.random()
            if kind < 0.75:
                space.add_circle((cx, cy), size)
            elif kind < 0.9 and size > 1.0:
                _slot(space, cx, cy, size, rng.uniform(0, math.pi))
            else:
                t = rng.uniform(0, math.pi / 3) + np.arange(6) * math.pi / 3
                space.add_lwpolyline(np.column_stack([cx + size * np.cos(t),
                                                      cy + size * np.sin(t)]).tolist(),
                                     close=True)


def _slot(space, cx, cy, size, angle):
    """A slot of length 2 size and width size, turned by ``angle``."""
    r, half = size / 2, size / 2
    u = np.array([math.cos(angle), math.sin(angle)])
    v = np.array([-u[1], u[0]])
    c = np.array([cx, cy])
    a, b = c - half * u, c + half * u
    space.add_line(tuple(a + r * v), tuple(b + r * v))
    space.add_line(tuple(b - r * v), tuple(a - r * v))
    degrees = math.degrees(angle)
    space.add_arc(tuple(b), r, degrees - 90, degrees + 90)
    space.add_arc(tuple(a), r, degrees + 90, degrees + 270)
