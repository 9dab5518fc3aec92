"""Graded meshes against Triangle pq30 (no area bound) and gmsh with a size field from the
distance to the boundary, on the same polygons (issue 12).

    python bench/graded.py                 # the table, default grading
    python bench/graded.py --grading-table # vertices and angles for L = 0.05 ... 0.3
    python bench/graded.py --quick         # without the laser-cut sheet
    python bench/graded.py --no-gmsh       # without gmsh
    python bench/graded.py --gmsh-everywhere  # gmsh on the sheet too (over 9 min there)

The table, with issue 12's targets checked on it, is printed and written as a section of
docs/benchmarks.md (``--out``), which peers.py keeps when it rewrites the file.

Every column is measured the same way for every mesher: vertices, min/max angle from
:func:`pds_plugin.triangle_quality`, Betti numbers from the Euler characteristic
(bench/_metrics.py) against the region's, time of the meshing call (pds_plugin: warm,
the faster of 2 after one untimed run; its certificate is not timed), as wall time and as
CPU time of the process (all threads), which the shared machine's load disturbs less.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys
from pathlib import Path
from time import perf_counter, process_time

import numpy as np
import shapely
from shapely.geometry import Point, box

sys.path.insert(0, str(Path(__file__).parent))

import pds_plugin as pds                                   # noqa: E402
from pds_plugin.analysis.quality import triangle_quality   # noqa: E402
from pds_plugin.sizing import DEFAULT_GRADING, angle_bound # noqa: E402

from _environment import machine                           # noqa: E402
from _metrics import betti_numbers                          # noqa: E402
from _sections import put_section                           # noqa: E402
from _regions import DATA, cad_plate, stl_section, svg_drawing  # noqa: E402
from _runners import _gmsh_geometry, _pslg                  # noqa: E402


def laser_sheet() -> pds.Region:
    """A laser-cut-like sheet: 1,300 x 1,300 units, a 20 x 20 grid of 400 holes at
    pitch 65 (rounded rectangles and circles of random size, seed 0), the material
    between neighbouring holes 1.5 units wide where the holes are largest."""
    rng = np.random.default_rng(0)
    pitch, wall = 65.0, 1.5
    holes = []
    for i in range(20):
        for j in range(20):
            cx, cy = 20 + pitch * (i + 0.5), 20 + pitch * (j + 0.5)
            if rng.random() < 0.5:
                half = 0.5 * (pitch - wall) if rng.random() < 0.6 else rng.uniform(8, 28)
                rounding = min(rng.uniform(0.5, 6), half / 2)
                holes.append(box(cx - half + rounding, cy - half + rounding,
                                 cx + half - rounding, cy + half - rounding).buffer(rounding, 4))
            else:
                radius = 0.5 * (pitch - wall) if rng.random() < 0.5 else rng.uniform(5, 28)
                holes.append(Point(cx, cy).buffer(radius, 16))
    sheet = box(0, 0, 1340, 1340).difference(shapely.union_all(holes))
    return pds.Region.from_shapely(sheet)


REGIONS = {
    "laser sheet (400 holes, 1.5 walls)": (laser_sheet, None),
    "MIL.svg": (svg_drawing, "MIL.svg"),
    "featuretype.STL z-mid": (stl_section("featuretype.STL"), "featuretype.STL"),
    "angle_block.STL z-mid": (stl_section("angle_block.STL"), "angle_block.STL"),
    "CAD plate (manifold3d)": (cad_plate, None),
}


SLOW_FOR_GMSH = {"laser sheet (400 holes, 1.5 walls)"}
"""Regions gmsh takes minutes on, left out unless ``--gmsh-everywhere``."""


def timed(run):
    """(result, wall seconds, CPU seconds of the process, all threads) of ``run()``."""
    wall, cpu = perf_counter(), process_time()
    result = run()
    return result, perf_counter() - wall, process_time() - cpu


def run_pds(region, grading):
    def mesh():
        return pds.mesh_region(region, "auto", graded=True, grading=grading)
    mesh()                                                   # warm: imports, caches
    runs = [timed(mesh) for _ in range(2)]
    result, wall, cpu = min(runs, key=lambda r: r[1])
    return result.vertices, result.faces, (wall, min(r[2] for r in runs)), result


def run_triangle(region):
    import triangle
    pslg = _pslg(region)
    out, wall, cpu = timed(lambda: triangle.triangulate(pslg, "pq30Q"))
    return out["vertices"], out["triangles"].astype(np.int64), (wall, cpu)


def run_gmsh(region, smallest, grading):
    """gmsh Frontal-Delaunay with the size field min(cap, smallest + L * distance to the
    boundary) (Distance + MathEval fields), the smallest size and cap from pds_plugin's
    field so the two grade alike."""
    import gmsh
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.model.add("region")
        start, cpu = perf_counter(), process_time()
        _gmsh_geometry(gmsh.model.geo, region, smallest)
        gmsh.model.geo.synchronize()
        curves = [tag for _, tag in gmsh.model.getEntities(1)]
        distance = gmsh.model.mesh.field.add("Distance")
        gmsh.model.mesh.field.setNumbers(distance, "CurvesList", curves)
        gmsh.model.mesh.field.setNumber(distance, "Sampling", 20)
        size = gmsh.model.mesh.field.add("MathEval")
        gmsh.model.mesh.field.setString(size, "F", f"{smallest} + {grading} * F{distance}")
        gmsh.model.mesh.field.setAsBackgroundMesh(size)
        gmsh.model.mesh.generate(2)
        tags, coordinates, _ = gmsh.model.mesh.getNodes()
        _, nodes = gmsh.model.mesh.getElementsByType(2)
        elapsed = perf_counter() - start, process_time() - cpu
    finally:
        gmsh.finalize()
    order = np.argsort(tags)
    faces = order[np.searchsorted(tags, nodes.reshape(-1, 3), sorter=order)]
    return coordinates.reshape(-1, 3)[:, :2], faces.astype(np.int64), elapsed


def measure(region, vertices, faces, seconds) -> dict:
    quality = triangle_quality(np.asarray(vertices, float), faces)
    return {"vertices": len(vertices), "min_angle": quality.angles.min(),
            "max_angle": quality.angles.max(),
            "exact": tuple(betti_numbers(faces, len(vertices))) == tuple(region.betti),
            "wall": seconds[0], "cpu": seconds[1]}


def row(name, mesher, m, note="") -> str:
    return (f"| {name} | {mesher} | {m['vertices']:,} | {m['min_angle']:.1f}° | "
            f"{m['max_angle']:.1f}° | {'exact' if m['exact'] else 'WRONG'} | {m['wall']:.3f} s | "
            f"{m['cpu']:.3f} s | {note} |")


def table(names, grading, gmsh=True) -> list[str]:
    """Print the table row by row; return its lines and the targets' verdicts."""
    lines = [f"grading L = {grading}, proven min angle {angle_bound(grading):.2f}°; load "
             f"average before: {os.getloadavg()[0]:.1f} (2 cores; CPU time, all threads, is "
             "the estimate of a quiet machine's wall time)\n",
             "| region | mesher | vertices | min angle | max angle | topology | wall | CPU | "
             "certificate |", "|---|---|---|---|---|---|---|---|---|"]
    print("\n".join(lines))
    pairs = []
    for name in names:
        build, data = REGIONS[name]
        if data and not (DATA / data).exists():
            lines.append(f"| {name} | (skipped: {data} absent) | | | | | | | |")
            print(lines[-1])
            continue
        region = build()
        v, f, t, mesh = run_pds(region, grading)
        cert = mesh.certificate()
        ours = measure(region, v, f, t)
        ours["ok"] = cert.ok
        lines.append(row(name, "pds graded", ours, f"{'ok' if cert.ok else 'FAILED'} "
                         f"(separation {cert.min_separation:.4f}, coverage "
                         f"{cert.coverage_gap:.4f})"))
        print(lines[-1])
        theirs = measure(region, *run_triangle(region))
        lines.append(row(name, "Triangle pq30", theirs))
        print(lines[-1])
        pairs.append((name, ours, theirs))
        if gmsh and name in SLOW_FOR_GMSH and gmsh != "everywhere":
            lines.append(f"| {name} | gmsh distance field | (not run: over 9 minutes here; "
                         "`--gmsh-everywhere` runs it) | | | | | | |")
            print(lines[-1])
        elif gmsh:
            v, f, t = run_gmsh(region, cert.smallest_radius, grading)
            lines.append(row(name, "gmsh distance field", measure(region, v, f, t)))
            print(lines[-1])
        sys.stdout.flush()
    verdicts = targets(pairs, grading)
    print("\n" + "\n".join(verdicts))
    return lines + [""] + verdicts


def targets(pairs, grading) -> list[str]:
    """Issue 12's targets on the pairs (name, pds graded, Triangle pq30) of one run."""
    if not pairs:
        return []
    mark = {True: "**holds**", False: "**misses**"}
    ratios = [(ours["vertices"] / theirs["vertices"], name) for name, ours, theirs in pairs]
    angle = min((ours["min_angle"], name) for name, ours, _ in pairs)
    bound = angle_bound(grading)
    per_30k = max((30_000 * ours["wall"] / ours["vertices"], name) for name, ours, _ in pairs
                  if ours["vertices"] >= 10_000) if any(
        ours["vertices"] >= 10_000 for _, ours, _ in pairs) else None
    lines = ["| target (issue 12) | measured | verdict |", "|---|---|---|",
             f"| vertices ≤ 3× Triangle pq30's (aim 1.5×) | worst {max(ratios)[0]:.2f}× "
             f"({max(ratios)[1]}), best {min(ratios)[0]:.2f}× ({min(ratios)[1]}) | "
             f"{mark[max(ratios)[0] <= 3]} |",
             f"| min angle ≥ 20° at the default L, never below the proven {bound:.2f}° | "
             f"smallest {angle[0]:.2f}° ({angle[1]}) | {mark[angle[0] >= max(20, bound)]} |",
             f"| topology exact | {sum(o['exact'] for _, o, _ in pairs)} of {len(pairs)} "
             f"regions | {mark[all(o['exact'] for _, o, _ in pairs)]} |",
             f"| certificate ok | {sum(o['ok'] for _, o, _ in pairs)} of {len(pairs)} regions | "
             f"{mark[all(o['ok'] for _, o, _ in pairs)]} |"]
    if per_30k is not None:
        lines.append(f"| ≤ 1 s warm per 30k graded vertices (wall) | {per_30k[0]:.2f} s per 30k "
                     f"({per_30k[1]}) | {mark[per_30k[0] <= 1]} |")
    return lines


def grading_table(names):
    gradings = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3)
    print("| region | " + " | ".join(f"L={g}" for g in gradings) + " | Triangle pq30 |")
    print("|---|" + "---|" * (len(gradings) + 1))
    print("| proven min angle | " + " | ".join(f"{angle_bound(g):.2f}°" for g in gradings) + " | 30° (not proven for output) |")
    for name in names:
        build, data = REGIONS[name]
        if data and not (DATA / data).exists():
            continue
        region = build()
        cells = []
        for g in gradings:
            mesh = pds.mesh_region(region, "auto", graded=True, grading=g)
            cells.append(f"{len(mesh.vertices):,} / {mesh.quality().angles.min():.1f}°")
        v, f, _ = run_triangle(region)
        cells.append(f"{len(v):,} / {triangle_quality(v, f).angles.min():.1f}°")
        print(f"| {name} (vertices / min angle) | " + " | ".join(cells) + " |")
        sys.stdout.flush()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--grading", type=float, default=DEFAULT_GRADING)
    parser.add_argument("--grading-table", action="store_true")
    parser.add_argument("--quick", action="store_true", help="leave out the laser-cut sheet")
    parser.add_argument("--no-gmsh", dest="gmsh", action="store_false",
                        help="leave out gmsh (over 9 minutes on the laser-cut sheet)")
    parser.add_argument("--gmsh-everywhere", dest="gmsh", action="store_const",
                        const="everywhere", help="run gmsh on the laser-cut sheet too")
    parser.add_argument("--only", choices=list(REGIONS), action="append",
                        help="these regions only (repeat for several)")
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[1] / "docs"
                        / "benchmarks.md", help="the report whose section 'graded' is written "
                        "(default docs/benchmarks.md)")
    args = parser.parse_args()
    names = args.only or (list(REGIONS)[1:] if args.quick else list(REGIONS))
    if args.grading_table:
        grading_table(names)
        return
    start = machine()
    command = shlex.join(["python", "bench/graded.py", *sys.argv[1:]])
    lines = table(names, args.grading, args.gmsh)
    put_section(args.out, "graded", "\n".join([
        "## Graded meshes (bench/graded.py)\n",
        f"Written by `{command}` on {start['date']} (commit `{start['commit']}`); pds_plugin "
        f"`mesh_region(region, \"auto\", graded=True)` warm, the faster of 2; Triangle `pq30` "
        "with no area bound; gmsh Frontal-Delaunay with a size field from the distance to the "
        "boundary (docs/graded.md).\n", *lines]))
    print(f"wrote the section 'graded' of {args.out}")


if __name__ == "__main__":
    main()
