"""Issue 21's speed targets, pds_plugin against Triangle in the same run, with verdicts.

    python bench/speed_targets.py               # every target (the 1M square takes ~1 min)
    python bench/speed_targets.py --quick       # without the 1M square
    python bench/speed_targets.py --only drawing --profile   # one case, cProfile of pds
    python bench/speed_targets.py --write       # and the section of docs/benchmarks.md

Every pds_plugin time is warm (one untimed call first), the best of ``--repeat`` calls,
as wall time and as CPU time of the process (``time.process_time``: all threads), which
the shared machine's load disturbs far less; Triangle (Shewchuk's, the ``triangle``
package: bench only) meshes the same polygons in the same run, ``pq30`` and ``pq33`` with
no area bound beside graded meshes (their vertex counts are the comparison) and with the
area chosen (untimed) for pds_plugin's vertex count beside uniform ones. Ratios are
pds / Triangle; a verdict compares the ratio the issue names with its bound.

Cases (issue 21, "Targets"):

- ``drawing``: a laser-cut drawing of 10 plates and 373 round holes, written as DXF with
  ezdxf (LINE and ARC outlines, CIRCLE holes, as tests/test_dxf_layouts.py draws it) and
  read with :func:`pds_plugin.load_dxf`; graded ``"auto"``;
- ``laser``: bench/graded.py's laser sheet (400 holes, 1.5-unit walls); graded ``"auto"``;
- ``sections``: the shared STL parts (featuretype, angle_block, ADIS16480) cut at 60
  planes each; graded ``"auto"`` per section;
- ``uniform-auto``: uniform ``"auto"`` on the ~1k-vertex section (angle_block.STL z-mid);
- ``squares``: uniform unit squares of 10k, 100k (and 1M unless ``--quick``) vertices;
- ``demo``: the demo part, graded ``"auto"`` vertices against uniform ``"auto"``.
"""

from __future__ import annotations

import argparse
import cProfile
import io
import math
import pstats
import sys
import tempfile
import warnings
from pathlib import Path
from time import perf_counter, process_time

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

import pds_plugin as pds                                   # noqa: E402

from _drawings import rounded_plate                        # noqa: E402
from _environment import machine                           # noqa: E402
from _regions import DATA                                  # noqa: E402
from _runners import _area_for_vertices, _pslg             # noqa: E402
from _sections import write_section                        # noqa: E402

PARTS = ("featuretype.STL", "angle_block.STL", "ADIS16480.STL")
PLANES = 60
CASES = ("drawing", "laser", "sections", "uniform-auto", "squares", "demo")


# --------------------------------------------------------------------------- regions

def drawing_region() -> pds.Region:
    """10 plates with rounded corners (LINE + ARC) and 373 CIRCLE holes of radius 2.5 in
    grids of pitch 12, two rows of plates: a laser-cut drawing as CAD writes it."""
    import ezdxf

    doc = ezdxf.new("R2010", units=4)
    space = doc.modelspace()
    plates, holes, corner, radius = 10, 373, 4.0, 2.5
    counts = [holes // plates + (k < holes % plates) for k in range(plates)]
    for k, count in enumerate(counts):
        columns, rows = 7, math.ceil(count / 7)
        width, height = 8 + 12 * columns, 8 + 12 * rows
        x0, y0 = 40 + (k // 2) * 120.0, (90.0, 20.0)[k % 2] + 300.0 * (k % 2)
        rounded_plate(space, x0, y0, width, height, corner)
        for j in range(count):
            space.add_circle((x0 + 10 + 12 * (j % columns), y0 + 10 + 12 * (j // columns)), radius)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "plates.dxf"
        doc.saveas(path)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return pds.load_dxf(path)


def laser_region() -> pds.Region:
    from graded import laser_sheet
    return laser_sheet()


def part_sections(part: str, planes: int = PLANES) -> list[pds.Region]:
    """``planes`` sections of a shared STL part at evenly spaced heights (z), those that
    cut it; empty when the part is absent."""
    import trimesh

    if not (DATA / part).exists():
        return []
    solid = trimesh.load_mesh(DATA / part)
    lo, hi = solid.bounds
    centre = (lo + hi) / 2
    found = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for k in range(planes):
            z = lo[2] + (k + 0.5) / planes * (hi[2] - lo[2])
            try:
                region = pds.section(solid, plane_origin=(centre[0], centre[1], z),
                                     plane_normal=(0, 0, 1), on_face="above")
            except pds.PdsError:
                continue
            found.append(region)
    return found


# --------------------------------------------------------------------------- timing

def timed(run, repeat: int):
    """(result, best wall s, best CPU s) of ``run()`` warm: one untimed call, then
    ``repeat`` timed ones."""
    run()
    best_wall, best_cpu, result = math.inf, math.inf, None
    for _ in range(repeat):
        wall, cpu = perf_counter(), process_time()
        result = run()
        best_wall = min(best_wall, perf_counter() - wall)
        best_cpu = min(best_cpu, process_time() - cpu)
    return result, best_wall, best_cpu


def triangle_run(region, switches: str, repeat: int):
    """(vertices, wall s, CPU s) of Triangle on the region's polygons."""
    import triangle

    pslg = _pslg(region)
    out, wall, cpu = timed(lambda: triangle.triangulate(pslg, switches + "Q"), repeat)
    return len(out["vertices"]), wall, cpu


def triangle_at(region, target: int, angle: int, repeat: int):
    """Triangle pq<angle> with the area (chosen untimed) for about ``target`` vertices."""
    area = _area_for_vertices(_pslg(region), f"pq{angle}", target, region.area)
    return triangle_run(region, f"pq{angle}a{area:.20f}", repeat)


def graded(region):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return pds.mesh_region(region, "auto", graded=True)


def uniform_auto(region):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return pds.mesh_region(region, "auto")


# --------------------------------------------------------------------------- measures

class Row(dict):
    """One measured line: case, what, pds (vertices, wall, CPU), peers, ratios."""


def measure_graded(name, region, repeat, certify=True) -> Row:
    mesh, wall, cpu = timed(lambda: graded(region), repeat)
    row = Row(case=name, mode="graded auto", vertices=len(mesh.vertices), wall=wall, cpu=cpu)
    if certify:
        cert = mesh.certificate()
        row["certificate"] = "ok" if cert.ok else ("ok with exceptions"
                                                   if cert.ok_with_exceptions else "FAILED")
    for angle in (30, 33):
        row[f"pq{angle}"] = triangle_run(region, f"pq{angle}", repeat)
    return row


def measure_sections(part, regions, repeat) -> Row:
    """Graded auto on every section of the part: summed times and vertices, per section
    on average."""
    totals = np.zeros(3)
    peers = {30: np.zeros(3), 33: np.zeros(3)}
    certified = 0
    for region in regions:
        mesh, wall, cpu = timed(lambda: graded(region), repeat)
        totals += (len(mesh.vertices), wall, cpu)
        certified += bool(mesh.certificate().ok)
        for angle in peers:
            peers[angle] += triangle_run(region, f"pq{angle}", repeat)
    n = max(len(regions), 1)
    row = Row(case=f"{part}, {len(regions)} sections", mode="graded auto, per section",
              vertices=totals[0] / n, wall=totals[1] / n, cpu=totals[2] / n,
              certificate=f"{certified} of {len(regions)} ok")
    for angle, t in peers.items():
        row[f"pq{angle}"] = tuple(t / n)
    return row


def measure_uniform(name, region, mesher, repeat) -> Row:
    mesh, wall, cpu = timed(lambda: mesher(region), repeat)
    row = Row(case=name, mode="uniform", vertices=len(mesh.vertices), wall=wall, cpu=cpu)
    for angle in (30, 33):
        row[f"pq{angle}"] = triangle_at(region, len(mesh.vertices), angle, repeat)
    return row


def square_alpha(vertices: int) -> float:
    """The alpha at which the unit square gets about ``vertices`` samples."""
    from _regions import alpha_for
    from shapely.geometry import box
    return alpha_for(pds.Region.from_shapely(box(0, 0, 1, 1)), vertices)


# --------------------------------------------------------------------------- targets

def ratio(row, angle=30, what="cpu"):
    peer = row[f"pq{angle}"]
    index = {"vertices": 0, "wall": 1, "cpu": 2}[what]
    mine = row[what]
    return mine / peer[index] if peer[index] else math.inf


def verdict(holds: bool) -> str:
    return "**holds**" if holds else "**misses**"


def targets(rows: dict) -> list[str]:
    """Issue 21's targets, one line each, from the measured rows."""
    lines = ["| target (issue 21) | measured | verdict |", "|---|---|---|"]
    if "drawing" in rows:
        r = rows["drawing"]
        lines.append(f"| 373-hole drawing, graded auto: ≤ 0.5 s for the call (aim 0.2 s) | "
                     f"{r['wall']:.3f} s wall, {r['cpu']:.3f} s CPU (all threads) | "
                     f"{verdict(r['wall'] <= 0.5)} by wall, {verdict(r['cpu'] <= 0.5)} by CPU |")
        lines.append(f"| 373-hole drawing: ≤ 2× Triangle pq30's vertices (aim 1.5×) | "
                     f"{ratio(r, what='vertices'):.2f}× | {verdict(ratio(r, what='vertices') <= 2)} |")
    for key in [k for k in rows if k.startswith("sections ")]:
        r = rows[key]
        lines.append(f"| {r['case']}: ≤ 5× Triangle pq30's time per section (aim 2×) | "
                     f"{ratio(r):.1f}× CPU, {ratio(r, what='wall'):.1f}× wall | "
                     f"{verdict(ratio(r) <= 5)} |")
        lines.append(f"| {r['case']}: ≤ 2× Triangle pq30's vertices | "
                     f"{ratio(r, what='vertices'):.2f}× | {verdict(ratio(r, what='vertices') <= 2)} |")
    if "uniform-auto" in rows:
        r = rows["uniform-auto"]
        lines.append(f"| uniform auto, {r['vertices']:,}-vertex section: ≤ 5× Triangle pq30 | "
                     f"{ratio(r):.1f}× CPU, {ratio(r, what='wall'):.1f}× wall | "
                     f"{verdict(ratio(r) <= 5)} |")
    bounds = {10_000: 1.0, 100_000: 0.8, 1_000_000: 1.0}
    for size, bound in bounds.items():
        key = f"square {size}"
        if key in rows:
            r = rows[key]
            lines.append(f"| unit square {size:,}: ≤ {bound}× Triangle pq30 (pq33 beside) | "
                         f"{ratio(r):.2f}× CPU ({ratio(r, 33):.2f}× pq33), {ratio(r, what='wall'):.2f}× "
                         f"wall | {verdict(ratio(r) <= bound)} |")
    if "demo" in rows:
        r = rows["demo"]
        lines.append(f"| demo part: graded vertices < uniform auto's | {r['graded']:,} against "
                     f"{r['uniform']:,} | {verdict(r['graded'] < r['uniform'])} |")
    return lines


def table(rows: dict) -> list[str]:
    lines = ["| case | pds_plugin | vertices | wall s | CPU s | certificate | Triangle pq30: "
             "vertices / wall / CPU | pq33 | CPU ratio pq30 / pq33 | vertex ratio pq30 |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for key, r in rows.items():
        if key == "demo":
            continue
        p30, p33 = r["pq30"], r["pq33"]
        lines.append(f"| {r['case']} | {r['mode']} | {r['vertices']:,.0f} | {r['wall']:.4f} | "
                     f"{r['cpu']:.4f} | {r.get('certificate', '')} | {p30[0]:,.0f} / "
                     f"{p30[1]:.4f} / {p30[2]:.4f} | {p33[0]:,.0f} / {p33[1]:.4f} / {p33[2]:.4f} | "
                     f"{ratio(r):.1f}× / {ratio(r, 33):.1f}× | {ratio(r, what='vertices'):.2f}× |")
    return lines


# --------------------------------------------------------------------------- main

def run(cases, args) -> dict:
    rows = {}
    profile = cProfile.Profile() if args.profile else None

    def note(key, row):
        rows[key] = row
        print(table({key: row})[-1], flush=True)

    def maybe_profiled(call):
        if profile is None:
            return
        profile.enable()
        call()
        profile.disable()

    if "drawing" in cases:
        region = drawing_region()
        note("drawing", measure_graded("drawing, 10 plates, 373 holes (DXF)", region, args.repeat))
        maybe_profiled(lambda: graded(region))
    if "laser" in cases:
        region = laser_region()
        note("laser", measure_graded("laser sheet, 400 holes", region, max(1, args.repeat - 1)))
        maybe_profiled(lambda: graded(region))
    if "sections" in cases:
        for part in PARTS:
            regions = part_sections(part, args.planes)
            if regions:
                note(f"sections {part}", measure_sections(part, regions, args.repeat))
                maybe_profiled(lambda: [graded(r) for r in regions])
    if "uniform-auto" in cases and (DATA / "angle_block.STL").exists():
        from _regions import stl_section
        region = stl_section("angle_block.STL")()
        note("uniform-auto", measure_uniform("angle_block.STL z-mid", region, uniform_auto,
                                             args.repeat))
        maybe_profiled(lambda: uniform_auto(region))
    if "squares" in cases:
        from shapely.geometry import box
        square = pds.Region.from_shapely(box(0, 0, 1, 1))
        for size in args.sizes:
            alpha = square_alpha(size)
            note(f"square {size}", measure_uniform(
                f"unit square {size:,}", square,
                lambda region: pds.mesh_region(region, alpha), 1 if size >= 1e6 else args.repeat))
    if "demo" in cases:
        from pds_plugin.sources.demo import demo_part
        region = pds.section(demo_part(), plane_origin=(0, 0, 0), plane_normal=(0, 0, 1))
        rows["demo"] = {"graded": len(graded(region).vertices),
                        "uniform": len(uniform_auto(region).vertices)}
        print(f"demo: graded {rows['demo']['graded']} vertices, uniform auto "
              f"{rows['demo']['uniform']}", flush=True)
    if profile is not None:
        out = io.StringIO()
        pstats.Stats(profile, stream=out).sort_stats("cumulative").print_stats(args.profile_lines)
        print(out.getvalue())
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="without the 1M square")
    parser.add_argument("--only", choices=CASES, action="append", help="these cases only")
    parser.add_argument("--planes", type=int, default=PLANES, help="sections per STL part")
    parser.add_argument("--repeat", type=int, default=3, help="timed calls per case (best)")
    parser.add_argument("--profile", action="store_true",
                        help="cProfile one more pds call per case, print the cumulative table")
    parser.add_argument("--profile-lines", type=int, default=40)
    parser.add_argument("--write", action="store_true",
                        help="write the section 'speed targets' of docs/benchmarks.md")
    args = parser.parse_args(argv)
    args.sizes = [10_000, 100_000] + ([] if args.quick else [1_000_000])
    start = machine()
    print(f"{start['cpu']}, {start['cores']} cores, load {start['load'][0]:.1f}", flush=True)
    rows = run(args.only or CASES, args)
    lines = table(rows)
    verdicts = targets(rows)
    print("\n" + "\n".join(lines) + "\n\n" + "\n".join(verdicts))
    if args.write:
        write_section("speed targets", "Speed targets (bench/speed_targets.py, issue 21)",
                      f"on {start['date']} (commit `{start['commit']}`, load average "
                      f"{start['load'][0]:.1f} at the start; 2 shared cores: the CPU time of the "
                      "process, all threads, is the estimate of a quiet machine's wall time). "
                      "pds_plugin warm, best of the timed calls; Triangle in the same run, "
                      "`pq30`/`pq33` with no area bound beside graded meshes and at "
                      "pds_plugin's vertex count beside uniform ones. Ratios are pds / "
                      "Triangle. The misses are explained by the profiles below: "
                      "docs/engine.md, \"Issue 21: the misses\".", [*lines, "", *verdicts])
        print("wrote the section 'speed targets' of docs/benchmarks.md")


if __name__ == "__main__":
    main()
