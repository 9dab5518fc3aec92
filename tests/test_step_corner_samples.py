"""Where a STEP section's exact curves meet, and the boundary samples beside such a corner
(issue 22: "boundary samples on circles lie on the circle to 1e-9 of the radius").

A line meeting a circle ends on it: OCCT's vertex was up to 1.9e-9 r off the circle on
held-out parts (the last test; ``step._junctions_refined``).

The held-out knob of seed 5106 (bench/_step_parts.py, part 9: a sphere on a cone, cut by
a plane tilted 0.161 rad) has a lens between a straight cut of the cone's top face and
the sphere's ellipse, with 14° corners. Its uniform "auto" mesh places the first samples
beside each corner just past the sampler's longest chord (LONGEST_CHORD alpha), and
``boundary_curves.samples_onto_curves`` undid any move that lengthens such a chord, so
the sample on the ellipse's first chord stayed on the chord, 1.7e-7 of the radius off
the ellipse. The section itself is exact there: its ring vertices lie on the curves to
rounding (the first test). The lens alone, meshed at a fixed alpha, showed the same
(1.6e-7 r at alpha 0.05, 3.6e-8 r at 0.02). The uniform sampler now lets the move
lengthen the chord up to √3 alpha (1 - 1e-9) (``boundary_rules.LONGEST_MOVED_CHORD``):
every sample is on the arcs (4.6e-16 r), the certificates as before (the second test).
"""

import importlib.util
import math
import warnings

import numpy as np
import pytest

import pds_plugin as pds
from pds_plugin.sources import step

pytestmark = pytest.mark.skipif(importlib.util.find_spec("OCP") is None,
                                reason="OCP (the [step] extra) is not installed")

RADIUS = 28.150580292143953          # seed 5106, part 9 of bench/_step_parts.held_out
HEIGHT = 3.973899562879117
TILT = 0.16133405132806727


def knob():
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCone, BRepPrimAPI_MakeSphere
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    sphere = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, RADIUS), RADIUS).Shape()
    cone = BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(0, 0, -RADIUS), gp_Dir(0, 0, 1)),
                                0.3 * RADIUS, 0.9 * RADIUS, RADIUS).Shape()
    return BRepAlgoAPI_Fuse(sphere, cone).Shape()


@pytest.fixture(scope="module")
def region():
    return pds.section(knob(), (0.0, 0.0, HEIGHT), (math.sin(TILT), 0.0, math.cos(TILT)))


def off_arcs(region, points):
    """How far each point located on an elliptic arc of the region lies from it, over
    the arc's larger radius."""
    curves = region.curves
    piece, _, distance = curves.locate(points)
    arc = curves.elliptic[piece]
    return distance[arc] / np.hypot(*curves.conic[piece[arc], 2:4].T)


def test_the_knobs_section_has_its_corners_on_the_exact_curves(region):
    kinds = sorted(c.kind for c in step.section_curves(
        knob(), (0.0, 0.0, HEIGHT), (math.sin(TILT), 0.0, math.cos(TILT))))
    assert kinds == ["circle", "ellipse", "ellipse", "line"]
    for ring in region.rings:
        assert off_arcs(region, ring).max(initial=0.0) <= 1e-12


@pytest.mark.parametrize("alpha", [0.05, 0.02])
def test_uniform_samples_beside_a_sharp_corner_lie_on_the_ellipse(region, alpha):
    lens = min(region.geometry.geoms, key=lambda polygon: polygon.area)
    assert lens.area < 10                          # the lens, not the disc
    part = pds.Region.from_shapely(lens, frame=region.frame, curves=region.curves)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")            # the lens's thin tips
        mesh = pds.mesh_region(part, alpha, graded=False, seed=0)
    assert mesh.certificate().ok_with_exceptions
    assert off_arcs(part, mesh.vertices[mesh.on_boundary]).max() <= 1e-9


# --- where a line meets a circle, the junction lies on both ------------------------------

def ring_with_bar(big=23.182602542579282, small=6.350657916233816):
    """bench/_step_parts._ring of held-out seed 5104, part 16: a torus fused with a bar
    across it; cut at z = 0.395 the bar's sides (lines) meet the torus's circles."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeTorus
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    torus = BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), big, small).Shape()
    bar = BRepPrimAPI_MakeBox(gp_Pnt(-big - small, -2, -0.5 * small),
                              2 * (big + small), 4, small).Shape()
    return BRepAlgoAPI_Fuse(torus, bar).Shape()


def off_conic(curve, point):
    """How far ``point`` lies from the whole conic of ``curve`` (a circle here), over its
    radius."""
    radius = np.hypot(*curve.radii[:, 0])
    return abs(np.hypot(*(point - curve.center)) - radius) / radius


def test_a_line_meeting_a_circle_ends_on_it_and_so_does_the_ring():
    """OCCT's vertex, where it ends the bar's side, was 1.9e-9 of the torus circle's
    radius off the circle (the edge tolerance, 1e-7 mm): the ring's vertex there too.
    The junction is now where the exact line and the exact circle meet."""
    shape, origin = ring_with_bar(), (0.0, 0.0, 0.3953912640952029)
    curves = step.section_curves(shape, origin, (0, 0, 1))
    circles = [c for c in curves if c.kind == "circle"]
    lines = [c for c in curves if c.kind == "line"]
    assert len(circles) == 4 and len(lines) == 8
    junctions = 0
    for line in lines:
        for end in (line.points[0], line.points[-1]):
            gap, circle = min((np.hypot(*(c.points[[0, -1]] - end).T).min(), k)
                              for k, c in enumerate(circles))
            circle = circles[circle]
            if gap < 1e-6 * np.hypot(*circle.radii[:, 0]):  # a junction with it:
                junctions += 1                               # the same point, on it
                assert gap <= 1e-12 * np.hypot(*circle.radii[:, 0])
                assert off_conic(circle, end) <= 1e-12
    assert junctions == 8
    region = pds.section(shape, origin, (0, 0, 1))
    vertices = np.concatenate(region.rings)
    for circle in circles:
        for end in circle.points[[0, -1]]:
            nearest = vertices[np.hypot(*(vertices - end).T).argmin()]
            assert off_conic(circle, nearest) <= 1e-12
