"""Certified meshes of DXF drawings: a built-in bracket, and the public test drawings.

Writes a small bracket drawing with ezdxf (inches: a plate with rounded corners drawn as
polyline bulges, a slot, and two holes placed by a mirrored block; a dimension on its own
layer), reads it in millimetres, meshes it at the alpha its feature size suggests and
prints the certificate. Then does the same for ../shared/data/wrench.dxf and
sliding-base.dxf when present.

    python examples/dxf_drawing.py [OUTPUT_DIR]
"""

import sys
import warnings
from pathlib import Path

import ezdxf

import pds_plugin as pds

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def bracket(path: Path) -> None:
    doc = ezdxf.new("R2010", units=1)                   # $INSUNITS = 1: inches
    doc.layers.add("PART")
    doc.layers.add("DIMENSIONS")
    msp = doc.modelspace()
    r = 0.25                                            # corner radius: bulge tan(90°/4)
    bulge = 0.41421356237309503
    msp.add_lwpolyline([(r, 0, 0), (4 - r, 0, bulge), (4, r, 0), (4, 2 - r, bulge),
                        (4 - r, 2, 0), (r, 2, bulge), (0, 2 - r, 0), (0, r, bulge)],
                       format="xyb", close=True, dxfattribs={"layer": "PART"})
    msp.add_lwpolyline([(1.5, 0.9, 0), (2.5, 0.9, 1), (2.5, 1.1, 0), (1.5, 1.1, 1)],
                       format="xyb", close=True, dxfattribs={"layer": "PART"})   # a slot
    hole = doc.blocks.new("HOLE")
    hole.add_circle((0.6, 0), radius=0.2)               # on layer 0: takes the INSERT's
    msp.add_blockref("HOLE", (0, 1), dxfattribs={"layer": "PART"})
    msp.add_blockref("HOLE", (4, 1), dxfattribs={"layer": "PART", "xscale": -1})  # mirrored
    msp.add_linear_dim(base=(0, -0.5), p1=(0, 0), p2=(4, 0),
                       dxfattribs={"layer": "DIMENSIONS"}).render()
    doc.saveas(path)


def main(out_dir: Path) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    drawings = [out_dir / "bracket.dxf"]
    bracket(drawings[0])
    drawings += [DATA / name for name in ("wrench.dxf", "sliding-base.dxf")
                 if (DATA / name).exists()]
    for drawing in drawings:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            # the bracket in millimetres (its DIMENSIONS layer holds only annotation, and is
            # left out); the others through load_drawing, which chooses by the suffix
            region = (pds.load_dxf(drawing, units="mm") if drawing.name == "bracket.dxf"
                      else pds.load_drawing(drawing))
        for warning in caught:
            print(f"warning: {warning.message}")
        alpha = pds.suggest_alpha(region)
        mesh = pds.mesh_region(region, alpha, seed=0)
        mesh.export(out_dir / f"{drawing.stem}.ply")
        print(f"{drawing.name}: {region}, alpha {alpha:.4g}: {mesh}")
        print("  " + str(mesh.certificate()).replace("\n", "\n  "))


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out"))
