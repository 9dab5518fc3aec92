"""How long ``certificate()`` takes against the meshing it certifies (issue 13's target:
at most 0.5x), region by region, and where its time goes.

Each round meshes the region with ``mesh_region`` (timed), then certifies a fresh copy of
the mesh (timed: nothing cached, so the certificate pays for the mesh's edges, quality
and outline as a first call of ``mesh.certificate()`` does). Meshing and certificate
alternate, so both see the same machine load; the table gives medians of wall time and
of CPU time (``time.process_time``, all threads: much less sensitive to a busy machine).

    python bench/certificate_time.py                     # every region, 3 rounds
    python bench/certificate_time.py --regions plate,square --square-sizes 1e6
    python bench/certificate_time.py --profile           # + the stages of certify()

Regions: unit squares (``--square-sizes``), a perforated plate (20 x 10 with 200 round
holes, ``--plate-size`` samples), and bench/_regions.py's others at ``--region-size``
samples (the shared CAD parts' mid-height sections when ../shared/data is present).
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import statistics
import time
import warnings

import shapely
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin import _parallel
from _regions import FIXED, alpha_for, cases

STAGES = {             # function name in the profile -> what the table calls it
    "triangle_quality": "triangle quality",
    "mesh_edges": "mesh edges",
    "mesh_betti": "mesh components, Betti",
    "mesh_union": "mesh outline",
    "closest_distance": "separation (closest pair)",
    "_visible_separation": "separation (visibility)",
    "_coverage_gap": "coverage gap",
    "_boundary_gap": "· along the boundary",
    "_missing_delaunay_circles": "· missing Delaunay triangles",
    "_delaunay_triangles_outside": "· missing Delaunay triangles (before c30a0b0)",
    "__init__": "sampled boundary (chords)",
    "boundary_report": "boundary report (conformity)",
    "_deviation": "· boundary deviation",
    "_areas_off": "· areas outside / missing",
    "topology_report": "topology report",
}


def perforated_plate() -> pds.Region:
    """A 20 x 10 plate with 200 round holes of radius 0.3 on a unit grid."""
    holes = shapely.union_all([Point(0.5 + i, 0.5 + j).buffer(0.3, quad_segs=16)
                               for i in range(20) for j in range(10)])
    return pds.Region.from_shapely(box(0, 0, 20, 10).difference(holes))


def regions(args):
    """(name, region, alpha) of every case asked for."""
    keys = args.regions.split(",")
    found = []
    square = pds.Region.from_shapely(box(0, 0, 1, 1))
    if "square" in keys:
        found += [(f"unit square {n:.0e}", square, alpha_for(square, n)) for n in args.square_sizes]
    if "plate" in keys:
        plate = perforated_plate()
        found.append(("perforated plate, 200 holes", plate, alpha_for(plate, args.plate_size)))
    fixed = [k for k in keys if k in FIXED]
    if fixed:
        chosen, missing = cases([], args.region_size, keys=fixed)
        found += [(case.name, case.region, case.alpha) for case in chosen]
        for note in missing:
            print(f"skipped: {note}")
    return found


def fresh(mesh) -> pds.PlanarMesh:
    """The same mesh with nothing cached."""
    return pds.PlanarMesh(mesh.vertices, mesh.faces, mesh.on_boundary, mesh.region,
                          mesh.alpha, conforming=mesh.conforming)


def _timed(run) -> tuple[float, float]:
    """Wall and CPU seconds of ``run()``."""
    wall, cpu = time.perf_counter(), time.process_time()
    run()
    return time.perf_counter() - wall, time.process_time() - cpu


def stage_times(mesh) -> dict[str, float]:
    """Cumulative seconds of the certificate's stages (cProfile, so somewhat slowed)."""
    profile = cProfile.Profile()
    profile.enable()
    fresh(mesh).certificate()
    profile.disable()
    total = 0.0
    times = {}
    for (path, _, name), row in pstats.Stats(profile).stats.items():
        cumulative = row[3]
        if name == "certify":
            total = cumulative
        label = STAGES.get(name)
        if name == "__init__" and not path.endswith("conformity.py"):
            label = None
        if label:
            times[label] = times.get(label, 0.0) + cumulative
    return {"certify (total)": total, **times}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--regions", default="square,plate," + ",".join(FIXED))
    parser.add_argument("--square-sizes", type=float, nargs="*", default=[1e4, 1e5, 1e6])
    parser.add_argument("--plate-size", type=float, default=1e5)
    parser.add_argument("--region-size", type=float, default=5e4)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--profile", action="store_true")
    args = parser.parse_args()
    print(f"threads {_parallel.get_threads()}, load {os.getloadavg()[0]:.1f} at the start\n")
    print("| region | vertices | mesh_region s | certificate() s | certificate / mesh | "
          "CPU: mesh_region s | certificate() s | certificate / mesh | CPU ≤ 0.5 |")
    print("|---|---|---|---|---|---|---|---|---|")
    profiles = []
    for name, region, alpha in regions(args):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mesh = pds.mesh_region(region, alpha)                # warm, and the mesh certified
            fresh(mesh).certificate()
        meshing, certifying = [], []
        for _ in range(args.rounds):
            meshing.append(_timed(lambda: pds.mesh_region(region, alpha)))
            copy = fresh(mesh)
            certifying.append(_timed(copy.certificate))
        (m, m_cpu), (c, c_cpu) = (tuple(map(statistics.median, zip(*times)))
                                  for times in (meshing, certifying))
        print(f"| {name} | {len(mesh.vertices):,} | {m:.3f} | {c:.3f} | {c / m:.2f} | "
              f"{m_cpu:.3f} | {c_cpu:.3f} | {c_cpu / m_cpu:.2f} | "
              f"{'yes' if c_cpu <= 0.5 * m_cpu else 'no'} |", flush=True)
        if args.profile:
            profiles.append((name, stage_times(mesh)))
    print(f"\nload {os.getloadavg()[0]:.1f} at the end")
    if profiles:
        found = {label for _, times in profiles for label in times}
        labels = [label for label in ("certify (total)", *STAGES.values()) if label in found]
        print("\nStages of certify() (cProfile, cumulative s; '·' rows are parts of the row above)\n")
        print("| stage | " + " | ".join(name for name, _ in profiles) + " |")
        print("|---|" + "---|" * len(profiles))
        for label in labels:
            print(f"| {label} | " + " | ".join(f"{times.get(label, 0.0):.3f}" for _, times in profiles)
                  + " |")


if __name__ == "__main__":
    main()
