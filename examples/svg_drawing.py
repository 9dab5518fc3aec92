"""Certified meshes of SVG drawings: a CAD outline drawing and a filled drawing.

Reads ../shared/data/MIL.svg (an outline drawing exported from CAD: loose stroked arcs and
lines, one of its slots is missing a side, which is reported) and polygon.svg when
present, and always a built-in filled drawing (a plate with a Bézier edge and two
evenodd holes, one round, one square with an elliptical island); meshes each at the
alpha its feature size suggests and prints the certificate.

    python examples/svg_drawing.py [OUTPUT_DIR]
"""

import sys
import warnings
from pathlib import Path

import pds_plugin as pds

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"

BUILTIN = """<svg xmlns="http://www.w3.org/2000/svg"
     width="120mm" height="80mm" viewBox="0 0 120 80">
  <g fill-rule="evenodd" transform="translate(10 10)">
    <path d="M 0 0 H 80 C 100 0 100 60 80 60 H 0 Z
             M 15 30 A 10 10 0 1 0 35 30 A 10 10 0 1 0 15 30 Z
             M 50 20 H 70 V 40 H 50 Z"/>
  </g>
  <ellipse cx="70" cy="40" rx="6" ry="3"/>
</svg>
"""


def mesh_and_report(name: str, region, out_dir: Path) -> None:
    alpha = pds.suggest_alpha(region)
    mesh = pds.mesh_region(region, alpha, seed=0)
    print(f"{name}: {region}")
    print(f"  alpha {alpha:.4g}: {mesh}")
    print("  " + str(mesh.certificate()).replace("\n", "\n  "))
    path = out_dir / f"{Path(name).stem}.ply"
    mesh.export(path)
    print(f"  saved {path}")


def main(out_dir: Path) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    builtin = out_dir / "builtin_drawing.svg"
    builtin.write_text(BUILTIN)
    # filled shapes, converted to millimetres (the page is 120 mm wide)
    mesh_and_report(builtin.name, pds.load_svg(builtin, units="mm"), out_dir)

    if (DATA / "MIL.svg").exists():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            region = pds.load_svg(DATA / "MIL.svg")     # outline drawing, read automatically
        for warning in caught:
            print(f"warning: {warning.message}")
        mesh_and_report("MIL.svg", region, out_dir)
    if (DATA / "polygon.svg").exists():
        mesh_and_report("polygon.svg", pds.load_svg(DATA / "polygon.svg"), out_dir)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out"))
