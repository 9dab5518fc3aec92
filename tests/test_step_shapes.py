"""Sections of OCP shapes cut in turn: each shape's solids, box and planar faces are read
once and kept (``sources.step._facts``), and a shape moved or another shape is never
taken for one read before. Skipped when OCP (the [step] extra) is absent."""

import pytest

import pds_plugin as pds
from pds_plugin.errors import SectionError

pytest.importorskip("OCP")


def _box(size, lift=0.0):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.gp import gp_Trsf, gp_Vec
    from OCP.TopLoc import TopLoc_Location

    shape = BRepPrimAPI_MakeBox(size, size, size).Shape()
    if lift:
        move = gp_Trsf()
        move.SetTranslation(gp_Vec(0.0, 0.0, lift))
        shape = shape.Moved(TopLoc_Location(move))
    return shape


def test_shapes_cut_in_turn_keep_their_own_extent_and_faces():
    """The same box at z in [0, 10] and moved to [100, 110] (the same solid, another
    place), and a larger box, cut in turn: each section is its own (area, misses,
    the plane on a face refused), whichever was cut before."""
    box, lifted, large = _box(10.0), _box(10.0, lift=100.0), _box(20.0)
    for _ in range(2):
        assert pds.section(box, (0, 0, 5), (0, 0, 1)).area == pytest.approx(100.0, rel=1e-12)
        assert pds.section(lifted, (0, 0, 105), (0, 0, 1)).area == pytest.approx(100.0, rel=1e-12)
        assert pds.section(large, (0, 0, 15), (0, 0, 1)).area == pytest.approx(400.0, rel=1e-12)
        with pytest.raises(SectionError, match="misses"):
            pds.section(box, (0, 0, 105), (0, 0, 1))
        with pytest.raises(SectionError, match="lies on 1 face"):
            pds.section(lifted, (0, 0, 110), (0, 0, 1))
        with pytest.raises(SectionError, match="lies on 1 face"):
            pds.section(large, (0, 0, 20), (0, 0, 1))
