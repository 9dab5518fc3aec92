"""Certified mesh of an exact section of a STEP part (needs the [step] extra: OCP).

Cuts ../shared/data/featuretype.STEP at mid-height when present, else a part made here
with OCP and written as STEP (a 100 x 60 x 10 plate with four bolt holes and a bore).
Prints the curves OpenCASCADE reports (lines, circles, B-splines: kept exact until they
are flattened), meshes the section at alpha="auto" (graded), prints the certificate,
checks that the mesh lies in the cutting plane in 3D, and writes it as PLY.

    python examples/section_step.py [OUTPUT_DIR]
"""

import sys
import tempfile
from collections import Counter
from pathlib import Path

import numpy as np

import pds_plugin as pds
from pds_plugin.sources.step import section_curves

STEP = Path(__file__).resolve().parents[2] / "shared" / "data" / "featuretype.STEP"


def plate_step(path: Path) -> Path:
    """Make the plate with OCP and write it as STEP."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    from OCP.STEPControl import STEPControl_StepModelType, STEPControl_Writer

    plate = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 100, 60, 10).Shape()
    for x, y, radius in [(12, 12, 5), (88, 12, 5), (12, 48, 5), (88, 48, 5), (50, 30, 12)]:
        hole = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, -1), gp_Dir(0, 0, 1)), radius, 12)
        plate = BRepAlgoAPI_Cut(plate, hole.Shape()).Shape()
    writer = STEPControl_Writer()
    with pds.silenced():                     # OCCT reports the transfer on stdout
        writer.Transfer(plate, STEPControl_StepModelType.STEPControl_AsIs)
        writer.Write(str(path))
    return path


def main(out_dir: Path) -> None:
    path = STEP if STEP.exists() else plate_step(out_dir / "plate.step")
    middle = 34.925 / 2 if path == STEP else 5.0
    origin, normal = (0.0, 0.0, middle), (0.0, 0.0, 1.0)
    curves = Counter(curve.kind for curve in section_curves(path, origin, normal))
    print(f"part: {path.name}; the plane z = {middle:g} cuts "
          + ", ".join(f"{count} {kind}(s)" for kind, count in sorted(curves.items())))

    region = pds.section(path, plane_origin=origin, plane_normal=normal)
    print(f"section: {region}")
    mesh = pds.mesh_region(region, "auto", graded=True, seed=0)
    print(f"mesh: {mesh}")
    print(mesh.certificate())
    height = mesh.vertices_3d[:, 2]
    print(f"3D vertices in the plane z = {middle:g}: {bool(np.allclose(height, middle))}")
    out = out_dir / "section_step.ply"
    mesh.export(out)
    print(f"wrote {out}")


if __name__ == "__main__":
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    folder.mkdir(parents=True, exist_ok=True)
    main(folder)
