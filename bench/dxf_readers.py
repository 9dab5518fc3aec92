"""Compare the two DXF readers pds_plugin could build on: ezdxf (through ``load_dxf``) and
trimesh's own (``trimesh.load_path(...).polygons_full``).

    python bench/dxf_readers.py            # prints a markdown table (docs/dxf_readers.md)

Rows: the public test drawings of ../shared/data (when present), and small drawings
written here with ezdxf whose areas are known in closed form, one per feature a CAD
export uses. Each reader gets (components, holes), the area's relative error (against
the closed form, or against the other reader on the public drawings) and its time.
"""

from __future__ import annotations

import math
import tempfile
import time
import warnings
from pathlib import Path

import ezdxf

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
TOLERANCE = 1e-5


def _drawing(build, units=0):
    doc = ezdxf.new("R2010", units=units)
    build(doc, doc.modelspace())
    return doc


def _square(msp, side=10):
    msp.add_lwpolyline([(0, 0), (side, 0), (side, side), (0, side)], close=True)


def _mirrored_arc(doc, msp):         # a half disc of radius 3, right of x = -20 mirrored
    msp.add_arc((20, 0), 3, -90, 90, dxfattribs={"extrusion": (0, 0, -1)})
    msp.add_line((-20, 3), (-20, -3))


def _mirrored_ellipse(doc, msp):     # a half ellipse 5 x 2 below y = 0
    msp.add_ellipse((0, 0), (5, 0, 0), 0.4, 0, math.pi, dxfattribs={"extrusion": (0, 0, -1)})
    msp.add_line((-5, 0), (5, 0))


def _bulges(doc, msp):               # 10 x 4, bottom bulging out (b 0.5), top in (b 0.25)
    msp.add_lwpolyline([(0, 0, 0.5), (10, 0, 0), (10, 4, -0.25), (0, 4, 0)], format="xyb",
                       close=True)


def _quadratic_spline(doc, msp):     # area under (0,0) (5,6) (10,0): 20 h / 3 with h = 3
    msp.add_open_spline([(0, 0), (5, 6), (10, 0)], degree=2)
    msp.add_line((0, 0), (10, 0))


def _nested_mirrored_blocks(doc, msp):   # a 2 x 1 rectangle, scaled 0.5 then -2 x 2
    doc.blocks.new("A").add_lwpolyline([(0, 0), (2, 0), (2, 1), (0, 1)], close=True)
    doc.blocks.new("B").add_blockref("A", (1, 0), dxfattribs={"xscale": 0.5, "yscale": 0.5})
    msp.add_blockref("B", (10, 10), dxfattribs={"xscale": -2, "yscale": 2, "rotation": 90})


def _stretched_circle_block(doc, msp):   # a unit circle in a block scaled 3 x 1
    doc.blocks.new("DOT").add_circle((0, 0), 1)
    msp.add_blockref("DOT", (0, 0), dxfattribs={"xscale": 3, "yscale": 1})


def _hatch_only(doc, msp):           # a hatched 20 x 20 square with a round hole r = 8
    hatch = msp.add_hatch()
    hatch.paths.add_polyline_path([(0, 0), (20, 0), (20, 20), (0, 20)])
    hatch.paths.add_edge_path().add_arc((10, 10), radius=8)


def _segment(chord, bulge):
    sweep = 4 * math.atan(bulge)
    radius = chord / (2 * math.sin(sweep / 2))
    return radius**2 / 2 * (sweep - math.sin(sweep))


CASES = [  # name, build, exact area, (components, holes), save options
    ("ARC in a mirrored OCS", _mirrored_arc, math.pi * 9 / 2, (1, 0), {}),
    ("ELLIPSE in a mirrored OCS", _mirrored_ellipse, math.pi * 5, (1, 0), {}),
    ("LWPOLYLINE bulges both ways", _bulges, 40 + _segment(10, 0.5) - _segment(10, 0.25),
     (1, 0), {}),
    ("SPLINE of degree 2", _quadratic_spline, 20.0, (1, 0), {}),
    ("nested mirrored INSERT", _nested_mirrored_blocks, 2.0, (1, 0), {}),
    ("INSERT scaled 3 x 1 (circle)", _stretched_circle_block, 3 * math.pi, (1, 0), {}),
    ("HATCH only", _hatch_only, 400 - 64 * math.pi, (1, 1), {}),
    ("binary DXF", lambda doc, msp: _square(msp), 100.0, (1, 0), {"fmt": "bin"}),
]


def read_pds(path):
    import pds_plugin as pds

    region = pds.load_dxf(path, tolerance=TOLERANCE)
    return region.betti, region.area


def read_trimesh(path):
    import trimesh

    polygons = trimesh.load_path(path).polygons_full
    return (len(polygons), sum(len(p.interiors) for p in polygons)), sum(p.area for p in polygons)


READERS = {"ezdxf (load_dxf)": read_pds, "trimesh.load_path": read_trimesh}


def measure(reader, path):
    """(betti, area, seconds) or the error's first line; the best of 3 runs."""
    best = math.inf
    for _ in range(3):
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                betti, area = reader(path)
        except Exception as error:  # a reader's failure is a result here
            return f"{type(error).__name__}: {str(error).splitlines()[0][:60]}"
        best = min(best, time.perf_counter() - start)
    return betti, area, best


def cell(result, exact, topology, reference=False):
    if isinstance(result, str):
        return f"fails ({result})"
    betti, area, seconds = result
    error = "reference area" if reference else f"area error {abs(area - exact) / exact:.1e}"
    mark = "" if topology is None or tuple(betti) == topology else " **wrong topology**"
    return f"{tuple(betti)}, {error}, {1e3 * seconds:.0f} ms{mark}"


def main() -> None:
    rows = []
    folder = Path(tempfile.mkdtemp())
    for name in ("wrench.dxf", "sliding-base.dxf", "insert.dxf", "spline.DXF"):
        path = DATA / name
        if not path.exists():
            continue
        results = {reader: measure(function, path) for reader, function in READERS.items()}
        reference = results["ezdxf (load_dxf)"]
        exact = reference[1] if not isinstance(reference, str) else float("nan")
        rows.append((name, {reader: cell(result, exact, None, reader == "ezdxf (load_dxf)")
                            for reader, result in results.items()}))
    for name, build, exact, topology, options in CASES:
        path = folder / f"{name.split()[0].lower()}_{len(rows)}.dxf"
        _drawing(build).saveas(path, **options)
        rows.append((name, {reader: cell(measure(function, path), exact, topology)
                            for reader, function in READERS.items()}))
    print(f"| drawing | {' | '.join(READERS)} |")
    print(f"|---|{'---|' * len(READERS)}")
    for name, cells in rows:
        print(f"| {name} | {' | '.join(cells[reader] for reader in READERS)} |")


if __name__ == "__main__":
    main()
