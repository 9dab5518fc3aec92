"""The same section by two routes: the exact B-rep (STEP, through OpenCASCADE) and the
tessellated mesh (STL, through trimesh), for featuretype.STEP against featuretype.STL and
for parts made here with OCP (bench/_step_parts.py: plate with holes, fillets, pocket,
bolt, overlapping bodies), each written as STEP and tessellated to STL.

    python bench/step_vs_stl.py            # prints markdown tables (docs/step.md)

Per part: the section's area by each route against OpenCASCADE's own exact section area
(GProp of the common of the solid and the plane, 1e-10 relative), the Hausdorff distance
between the two sections' boundaries, the vertices of each, and the certificate of a
uniform and a graded ``alpha="auto"`` mesh of each. Then the times: OpenCASCADE's
Boolean (``BRepAlgoAPI_Section`` on the loaded shape) against ``pds.section`` of the
same loaded shape, and reading the file, best of 10.
"""

from __future__ import annotations

import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import shapely
import shapely.affinity

import pds_plugin as pds
from pds_plugin.sources import step

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _step_parts as parts  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
INCH = 25.4          # featuretype.STL is in inches, the STEP reader gives millimetres
REPEATS = 10


def exact_area(shape, origin, normal) -> float:
    """OpenCASCADE's area of the section: GProp of the common of the (fused) solids and
    a large planar face."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common, BRepAlgoAPI_Fuse
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepGProp import BRepGProp
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt
    from OCP.GProp import GProp_GProps

    solids = step._explore(shape, "SOLID")
    body = solids[0]
    for other in solids[1:]:
        body = BRepAlgoAPI_Fuse(body, other).Shape()
    face = BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(*origin), gp_Dir(*normal)),
                                   -1e4, 1e4, -1e4, 1e4).Face()
    properties = GProp_GProps()
    BRepGProp.SurfaceProperties_s(BRepAlgoAPI_Common(body, face).Shape(), properties, 1e-10)
    return properties.Mass()


def boolean_times(shape, origin, normal) -> tuple[float, float]:
    """Best times of OpenCASCADE's own cuts of the loaded shape, the Booleans alone: its
    Section by the plane, and its Common with a large face of the plane."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common, BRepAlgoAPI_Section
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt

    plane = gp_Pln(gp_Pnt(*origin), gp_Dir(*normal))

    def section():
        cut = BRepAlgoAPI_Section(shape, plane, False)
        cut.Approximation(True)
        cut.Build()
        return cut.Shape()

    def common():
        face = BRepBuilderAPI_MakeFace(plane, -1e3, 1e3, -1e3, 1e3).Face()
        return BRepAlgoAPI_Common(shape, face).Shape()
    return best_time(section), best_time(common)


def best_time(call) -> float:
    """The best of ``REPEATS`` runs, or of fewer when they take more than 10 s in all."""
    times = []
    while len(times) < REPEATS and sum(times) < 10:
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return min(times)


def verdict(region, graded) -> str:
    try:
        certificate = pds.mesh_region(region, "auto", graded=graded, seed=0).certificate()
    except pds.PdsError as error:
        return f"error: {type(error).__name__}"
    if certificate.ok:
        return "ok"
    return "ok with exceptions" if certificate.ok_with_exceptions else "FAILED"


def cases(folder: Path):
    """(name, STEP path, STL path, STL scale, plane origin, normal) of every part; the
    STL of the M6 screw (which has none) is its STEP tessellated at 0.01."""
    if (DATA / "featuretype.STEP").exists() and (DATA / "featuretype.STL").exists():
        yield ("featuretype", DATA / "featuretype.STEP", DATA / "featuretype.STL", INCH,
               (0.0, 0.0, 34.925 / 2), (0.0, 0.0, 1.0))
    if (DATA / "M6-1x12-countersunk-screw.step").exists():     # a modelled thread
        screw = DATA / "M6-1x12-countersunk-screw.step"
        stl = parts.write_stl(step.load(screw), folder / "screw.stl", deflection=0.01)
        yield "M6 screw, across the thread", screw, stl, 1.0, (0.0, 0.0, -6.0), (0.0, 0.0, 1.0)
        yield "M6 screw, along its axis", screw, stl, 1.0, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0)
    for name, (build, height) in parts.PARTS.items():
        shape = build()
        path = parts.write(shape, folder / f"{name}.step")
        stl = parts.write_stl(shape, folder / f"{name}.stl", deflection=0.01)
        yield name, path, stl, 1.0, (0.0, 0.0, height), (0.0, 0.0, 1.0)
    shape = parts.plate_with_holes()                 # a tilted plane: ellipses
    yield ("plate_with_holes tilted", folder / "plate_with_holes.step",
           folder / "plate_with_holes.stl", 1.0, (50.0, 30.0, 5.0),
           tuple(np.array([0.05, 0.0, 1.0]) / np.hypot(1, 0.05)))


def row(name, path, stl, scale, origin, normal):
    shape = step.load(path)
    exact = exact_area(shape, origin, normal)
    region = pds.section(shape, origin, normal)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh_region = pds.section(stl, np.asarray(origin) / scale, normal)
    tessellated = shapely.affinity.scale(mesh_region.geometry, scale, scale, origin=(0, 0))
    hausdorff = shapely.hausdorff_distance(region.geometry.boundary, tessellated.boundary,
                                           densify=0.01)
    curves = step.section_curves(shape, origin, normal)
    kinds = ", ".join(f"{sum(c.kind == k for c in curves)} {k}" for k in
                      ("line", "circle", "ellipse", "bspline", "adaptive")
                      if any(c.kind == k for c in curves))
    vertices = sum(len(r) for r in region.rings), sum(len(r) for r in mesh_region.rings)
    quality = (f"| {name} | {kinds} | {(region.area - exact) / exact:+.2e} | "
               f"{(tessellated.area - exact) / exact:+.2e} | {hausdorff:.3g} | "
               f"{vertices[0]} / {vertices[1]} | {verdict(region, False)} / "
               f"{verdict(region, True)} | "
               f"{verdict(mesh_region, False)} / {verdict(mesh_region, True)} |")
    section, common = boolean_times(shape, origin, normal)
    ours = best_time(lambda: pds.section(shape, origin, normal))
    reading = best_time(lambda: step.load(path))
    timing = (f"| {name} | {1e3 * section:.1f} | {1e3 * common:.1f} | {1e3 * ours:.1f} | "
              f"{ours / section:.2f} | {ours / common:.2f} | {1e3 * reading:.1f} |")
    return quality, timing


def main() -> None:
    quality = ["| part | curves of the cut | STEP area error | STL area error | "
               "Hausdorff STEP-STL | vertices STEP / STL | STEP uniform / graded | "
               "STL uniform / graded |", "|---" * 8 + "|"]
    timing = ["| part | OCCT Section (ms) | OCCT Common (ms) | pds.section (ms) | "
              "/ Section | / Common | read STEP (ms) |", "|---" * 7 + "|"]
    with tempfile.TemporaryDirectory() as folder:
        for case in cases(Path(folder)):
            q, t = row(*case)
            quality.append(q)
            timing.append(t)
            print(q, file=sys.stderr)
    print(f"Areas against OpenCASCADE's exact section area (GProp, 1e-10); the STEP route "
          f"at its default tolerance ({step.RELATIVE_TOLERANCE:g} of the part's diagonal); "
          f"STL tessellated at 0.01 deflection (featuretype.STL as exported, in inches, "
          f"scaled by 25.4). Certificates of alpha=\"auto\" meshes, seed 0.\n")
    print("\n".join(quality))
    print(f"\nTimes on the loaded shape, best of {REPEATS} (or of the runs that fit in 10 s), "
          f"after one warm-up cut: OpenCASCADE's BRepAlgoAPI_Section and BRepAlgoAPI_Common "
          f"alone against pds.section (its Common, the exact curves flattened, the polygons, "
          f"the Region).\n")
    print("\n".join(timing))


if __name__ == "__main__":
    main()
