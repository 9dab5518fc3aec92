"""load_dxf on paper-space drawings: SolidWorks-like sheets (model space empty, the parts
in a paper-space layout with a viewport, a border and a title block) written with ezdxf.

The oracle is the same parts drawn alone in model space: reading the sheet must give that
region bit for bit, whatever the sheet format around it."""

import math
import sys
import warnings
from pathlib import Path

import ezdxf
import numpy as np
import pytest

import pds_plugin as pds
from pds_plugin import ArgumentError, RegionError, load_dxf

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
from _drawings import rounded_plate  # noqa: E402

PAPER = (841.0, 594.0)                      # A1 landscape, millimetres
MARGIN = 10.0
TITLE = (180.0, 56.0)                       # the title block, in the lower right corner
CORNER = 4.0                                # the plates' corner radius
HOLE = 2.5                                  # the holes' radius


def hole_counts(plates, holes):
    """``holes`` spread over ``plates`` as evenly as possible (373 over 10: 37 and 38)."""
    return [holes // plates + (k < holes % plates) for k in range(plates)]


def draw_plates(doc, space, plates, holes):
    """Plates with rounded corners (LINE and ARC entities, as SolidWorks writes them) and
    grids of CIRCLE holes, in two rows; the upper row is a block (a drawing view).
    Returns the exact area."""
    view = doc.blocks.new("Drawing View1")
    area = 0.0
    for k, count in enumerate(hole_counts(plates, holes)):
        columns = 7
        rows = math.ceil(count / columns)
        width, height = 8 + 12 * columns, 8 + 12 * rows
        upper = k % 2
        x0, y0 = 40 + (k // 2) * 120.0, (90.0, 20.0)[upper]
        target = view if upper else space
        rounded_plate(target, x0, y0, width, height, CORNER)
        for j in range(count):
            target.add_circle((x0 + 10 + 12 * (j % columns), y0 + 10 + 12 * (j // columns)),
                              HOLE)
        area += width * height - (4 - math.pi) * CORNER**2 - count * math.pi * HOLE**2
    space.add_blockref("Drawing View1", (0, 300))
    return area


def draw_sheet_format(space, layer="0", paper=PAPER, trim=False):
    """A border of LINEs at the margin, a title block drawn against its lower right
    corner with text and a hatched logo in its cells; ``trim``: a trim line at the
    paper's edge too."""
    attributes = {"layer": layer}
    x1, y1 = paper[0] - MARGIN, paper[1] - MARGIN
    corners = [(MARGIN, MARGIN), (x1, MARGIN), (x1, y1), (MARGIN, y1)]
    for a, b in zip(corners, corners[1:] + corners[:1]):
        space.add_line(a, b, dxfattribs=attributes)
    if trim:
        space.add_lwpolyline([(0, 0), (paper[0], 0), paper, (0, paper[1])], close=True,
                             dxfattribs=attributes)
    left, top = x1 - TITLE[0], MARGIN + TITLE[1]
    space.add_line((left, MARGIN), (left, top), dxfattribs=attributes)
    space.add_line((left, top), (x1, top), dxfattribs=attributes)
    space.add_line((left, MARGIN + 28), (x1, MARGIN + 28), dxfattribs=attributes)
    space.add_line((left + 90, MARGIN), (left + 90, MARGIN + 28), dxfattribs=attributes)
    for text, at in [("PLATES", (left + 4, top - 10)), ("SCALE 1:1", (left + 4, MARGIN + 8)),
                     ("SHEET 1 OF 1", (left + 94, MARGIN + 8))]:
        space.add_text(text, height=3.5, dxfattribs=attributes).set_placement(at)
    logo = space.add_hatch(dxfattribs=attributes)                # a filled logo in a cell
    logo.paths.add_polyline_path([(left + 150, MARGIN + 5), (left + 170, MARGIN + 5),
                                  (left + 160, MARGIN + 22)])


def sheet(tmp_path, plates=10, holes=373, format="layer", model=False, name="sheet.dxf"):
    """A SolidWorks-like drawing. ``format``: where the sheet format is -- on the layer
    FORMAT ("layer"), in a block named like a sheet format ("block"), as plain lines on
    layer 0 ("lines"), plain lines with a trim line ("trimmed"), or plain lines on a
    layout left at ezdxf's default paper, A3, smaller than the A1 border: only the title
    block drawn against it tells ("unsized"). ``model``: the plates are in model
    space (the sheet then shows them through its viewport). Returns (path, exact area)."""
    doc = ezdxf.new("R2010", units=4)
    doc.layouts.rename("Layout1", "Sheet1")
    paper = doc.layouts.get("Sheet1")
    if format != "unsized":
        paper.page_setup(size=PAPER, margins=(0, 0, 0, 0), units="mm")   # + main VIEWPORT
    paper.add_viewport(center=(320, 300), size=(600, 500), view_center_point=(320, 300),
                       view_height=500)
    if format == "block":
        draw_sheet_format(doc.blocks.new("SheetFormat1"))
        paper.add_blockref("SheetFormat1", (0, 0))
    else:
        draw_sheet_format(paper, "FORMAT" if format == "layer" else "0",
                          trim=format == "trimmed")
    area = draw_plates(doc, doc.modelspace() if model else paper, plates, holes)
    path = tmp_path / name
    doc.saveas(path)
    return path, area


def alone(tmp_path, plates=10, holes=373):
    """The same plates alone in model space: the oracle."""
    doc = ezdxf.new("R2010", units=4)
    draw_plates(doc, doc.modelspace(), plates, holes)
    path = tmp_path / "alone.dxf"
    doc.saveas(path)
    return load_dxf(path)


def read(path, **options):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        region = load_dxf(path, **options)
    return region, [str(warning.message) for warning in caught]


@pytest.mark.parametrize("format", ["layer", "block", "lines", "trimmed", "unsized"])
def test_a_paper_space_sheet_gives_its_plates_and_holes_without_the_sheet(tmp_path, format):
    path, area = sheet(tmp_path, format=format)
    region, said = read(path)
    assert region.betti == (10, 373)
    assert abs(region.area - area) <= region.perimeter * 1e-4 * math.hypot(*PAPER)
    assert region.geometry.equals_exact(alone(tmp_path).geometry, tolerance=0)
    assert said[0] == (f"{str(path)!r}: its model space has no outline curve or hatch on "
                       f"the layers read, so its paper-space layout 'Sheet1' is read instead "
                       f"(layout= chooses one of 'Model', 'Sheet1')")
    assert all("VIEWPORT" not in message for message in said)
    left_out = [message for message in said if "left out the sheet format" in message]
    assert len(left_out) == 1 and "paper-space layout 'Sheet1'" in left_out[0]
    if format == "layer":
        assert "entities of layer 'FORMAT'" in left_out[0]
    elif format == "block":
        assert "entities of block 'SheetFormat1'" in left_out[0]
    else:
        border = PAPER[0] - 2 * MARGIN, PAPER[1] - 2 * MARGIN
        size = PAPER if format == "trimmed" else border
        assert f"the sheet border ({size[0]:.6g} x {size[1]:.6g})" in left_out[0]
        assert f"{4 + 4 + (format == 'trimmed')} curves; 1 HATCH in its title block" \
            in left_out[0]
        assert any("ignored 3 TEXT" in message for message in said)


def test_the_layout_is_chosen_by_name_and_an_unknown_one_lists_them(tmp_path):
    path, _ = sheet(tmp_path, plates=2, holes=5)
    region, said = read(path, layout="sheet1")               # case-insensitive, as in CAD
    assert region.betti == (2, 5)
    assert not any("is read instead" in message for message in said)
    with pytest.raises(RegionError, match="no outline curve.*in its model space"):
        load_dxf(path, layout="Model")
    with pytest.raises(ArgumentError, match=r"no layout 'Sheet2'; its layouts are 'Model', "
                                            r"'Sheet1' \('Model' is the model space\)"):
        load_dxf(path, layout="Sheet2")
    with pytest.raises(ArgumentError, match="layout must be the name of a layout"):
        load_dxf(path, layout=1)


def test_model_space_wins_over_a_sheet_without_a_word(tmp_path):
    path, area = sheet(tmp_path, plates=3, holes=11, model=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        region = load_dxf(path)
    assert region.geometry.equals_exact(alone(tmp_path, 3, 11).geometry, tolerance=0)
    with pytest.raises(RegionError, match="no outline curve.*paper-space layout 'Sheet1'"), \
            pytest.warns(UserWarning, match="left out the sheet format"):
        load_dxf(path, layout="Sheet1")                      # only the sheet format there


def test_a_lone_plate_in_paper_space_is_not_taken_for_a_border(tmp_path):
    """A rectangle enclosing everything else is a part unless it has the paper's size or
    a title block drawn against it (a face holding nothing): this plate is divided by a
    bend line, and both faces hold a hole. It reads as it does from model space."""
    def plate(space):
        space.add_lwpolyline([(100, 100), (400, 100), (400, 300), (100, 300)], close=True)
        space.add_line((250, 100), (250, 300))               # a bend line, edge to edge
        space.add_circle((150, 200), 10)
        space.add_circle((350, 200), 10)

    doc = ezdxf.new("R2010", units=4)
    paper = doc.layouts.get("Layout1")
    paper.page_setup(size=PAPER, margins=(0, 0, 0, 0), units="mm")
    plate(paper)
    doc.saveas(tmp_path / "paper.dxf")
    model = ezdxf.new("R2010", units=4)
    plate(model.modelspace())
    model.saveas(tmp_path / "model.dxf")
    region, said = read(tmp_path / "paper.dxf")
    assert region.geometry.equals_exact(load_dxf(tmp_path / "model.dxf").geometry, 0)
    assert not any("left out" in message for message in said)


def test_a_layer_named_like_a_sheet_format_is_read_when_asked_for(tmp_path):
    doc = ezdxf.new("R2010", units=4)
    paper = doc.layouts.get("Layout1")
    paper.add_circle((0, 0), 5, dxfattribs={"layer": "Border"})
    paper.add_circle((20, 0), 5)
    path = tmp_path / "named.dxf"
    doc.saveas(path)
    region, said = read(path)
    assert region.betti == (1, 0) and region.bounds[0] > 10
    assert any("1 entities of layer 'Border'" in message for message in said)
    both, _ = read(path, layers=["border", "0"])
    assert both.betti == (2, 0)


def test_nothing_but_a_sheet_anywhere_is_a_region_error(tmp_path):
    doc = ezdxf.new("R2010", units=4)
    paper = doc.layouts.get("Layout1")
    paper.page_setup(size=PAPER, margins=(0, 0, 0, 0), units="mm")
    draw_sheet_format(paper)
    path = tmp_path / "empty.dxf"
    doc.saveas(path)
    with pytest.raises(RegionError, match=r"model space nor, once viewports, sheet borders "
                                          r"and title blocks are left out, in its paper-space "
                                          r"layouts 'Layout1'"):
        load_dxf(path)


def test_a_small_sheet_meshes_with_an_ok_certificate(tmp_path):
    path, _ = sheet(tmp_path, plates=2, holes=3)
    region, _ = read(path)
    assert region.betti == (2, 3)
    mesh = pds.mesh_region(region, "auto")
    assert mesh.certificate().ok
    assert mesh.betti == region.betti


def test_the_same_sheet_reads_the_same_bit_for_bit(tmp_path):
    path, _ = sheet(tmp_path, plates=3, holes=20, format="lines")
    first, _ = read(path)
    again, _ = read(path)
    assert first.geometry.equals_exact(again.geometry, tolerance=0)
    assert np.array_equal(first.rings[0], again.rings[0])


def test_the_command_line_reads_the_sheet_and_chooses_the_layout(tmp_path, capsys):
    import json

    from pds_plugin.cli import main

    path, _ = sheet(tmp_path, plates=2, holes=3)
    report = tmp_path / "r.json"
    assert main([path, "-o", tmp_path / "sheet.ply", "--alpha", "auto",
                 "--report", report]) == 0
    printed = capsys.readouterr()
    assert "paper-space layout 'Sheet1' is read instead" in printed.out + printed.err
    [entry] = json.loads(report.read_text())["sections"]
    assert entry["region"]["betti"] == [2, 3] and entry["certificate"]["ok"]
    assert main([path, "-o", tmp_path / "model.ply", "--alpha", "1", "--layout", "Model"]) == 1
    assert "no outline curve" in capsys.readouterr().err
    svg = tmp_path / "square.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 4 4">'
                   '<rect width="4" height="4"/></svg>')
    assert main([svg, "-o", tmp_path / "s.ply", "--alpha", "1", "--layout", "Sheet1"]) == 1
    assert "--layout selects a layout of a DXF drawing" in capsys.readouterr().err


def test_the_limits_count_the_layout_read(tmp_path):
    """The paper-space layout's entities are counted before it is expanded, each INSERT
    with its block's entities (the model space, empty, would count nothing)."""
    path, _ = sheet(tmp_path, plates=2, holes=10)
    doc = ezdxf.readfile(path)
    count = sum(1 + (len(doc.blocks.get(entity.dxf.name)) if entity.dxftype() == "INSERT"
                     else 0) for entity in doc.layouts.get("Sheet1"))
    with pytest.raises(pds.SourceError, match=f"more than {count - 1} entities"):
        load_dxf(path, max_entities=count - 1)
    region, _ = read(path, max_entities=count)
    assert region.betti == (2, 10)
