"""The built-in CAD part of ``pds-mesh demo``, the examples and the tests.

A plate with two round holes, a rounded slot and a sharp V notch, made with manifold3d
(a 2D profile extruded into a prism). Its section at mid-thickness is known in closed
form (:func:`demo_section_area`), so it doubles as a test part.
"""

from __future__ import annotations

import math

__all__ = ["demo_part", "demo_section_area", "PLATE", "THICKNESS", "HOLES", "SLOT", "NOTCH",
           "SEGMENTS"]

PLATE = (4.0, 2.0)
"""Width and height of the plate, which is centred on the origin."""
THICKNESS = 0.5
"""Extent along z, from ``-THICKNESS/2`` to ``THICKNESS/2``."""
HOLES = ((-1.2, 0.0, 0.45), (-0.1, 0.4, 0.2))
"""Round holes as ``(x, y, radius)``."""
SLOT = ((0.4, -0.4), (1.4, -0.4), 0.15)
"""Rounded slot: the centres of its two round ends and its half-width."""
NOTCH = (1.2, 0.5, 0.7)
"""V notch cut into the top edge: ``(x of its axis, mouth width, depth)``; its tip has
an angle of ``2·atan(0.25/0.7)``, about 39°."""
SEGMENTS = 64
"""Edges of each polygonal circle (a multiple of 4, so a slot's ends have their
top and bottom points)."""


def demo_part():
    """The demo part as a ``manifold3d.Manifold``: a 4 x 2 x 0.5 plate centred on the
    origin, with two round holes, a rounded slot and a sharp V notch, all through.

    Returns
    -------
    manifold3d.Manifold

    Examples
    --------
    >>> import pds_plugin as pds
    >>> part = demo_part()
    >>> region = pds.section(part, plane_origin=(0, 0, 0), plane_normal=(0, 0, 1))
    >>> region.betti                      # one plate; the holes and the slot
    (1, 3)
    >>> abs(region.area - demo_section_area()) < 1e-8   # manifold3d rounds 2D to 1e-8
    True
    """
    import manifold3d as m3

    width, height = PLATE
    profile = m3.CrossSection.square((width, height), center=True)
    for x, y, radius in HOLES:
        profile -= m3.CrossSection.circle(radius, SEGMENTS).translate((x, y))
    first, second, half_width = SLOT
    ends = [m3.CrossSection.circle(half_width, SEGMENTS).translate(c) for c in (first, second)]
    profile -= m3.CrossSection.batch_hull(ends)
    x, mouth, depth = NOTCH
    top, spill = height / 2, 0.1 * depth          # overshoot the top edge for a clean cut
    half = mouth / 2 * (depth + spill) / depth
    notch = m3.CrossSection([[(x, top - depth), (x + half, top + spill), (x - half, top + spill)]])
    profile -= notch
    return m3.Manifold.extrude(profile, THICKNESS).translate((0.0, 0.0, -THICKNESS / 2))


def demo_section_area() -> float:
    """Area of every section of :func:`demo_part` by a plane ``z = c``, ``|c| < 0.25``.

    The plate minus regular ``SEGMENTS``-gons of the holes' radii, the slot (a
    ``SEGMENTS``-gon stretched by the distance between its ends) and the notch triangle.

    Returns
    -------
    float

    Examples
    --------
    >>> round(demo_section_area(), 6)
    6.693815
    """
    def polygon(radius):
        return SEGMENTS / 2 * radius**2 * math.sin(2 * math.pi / SEGMENTS)

    width, height = PLATE
    first, second, half_width = SLOT
    x, mouth, depth = NOTCH
    return (width * height - sum(polygon(r) for _, _, r in HOLES)
            - polygon(half_width) - 2 * half_width * math.dist(first, second)
            - mouth * depth / 2)
