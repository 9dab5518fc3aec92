"""docs/benchmarks.md: the machine, the targets, the tables, and how each number was
obtained."""

from __future__ import annotations

import math
from pathlib import Path

from _metrics import PROBES_PER_ALPHA
from _rows import Row, sampling_rate
from _sections import kept_sections
from _targets import Target

COLUMNS = ("peer", "time (s)", "× pds", "peak MiB", "vertices", "triangles", "min ∠", "max ∠",
           "max L²/A", "mean L²/A", "> 4√3", "gap / α", "Betti (b0, b1)", "area ratio",
           "Hausdorff / α", "notes")


def write(path: Path, *, command: str, machine: dict, load_end, load_peak: float,
          versions: dict, startup,
          targets: list[Target], rows: list[Row], missing: list[str], figures: list[Path],
          timeout: float) -> Path:
    parts = [
        "# Benchmarks: pds_plugin against the meshers users pick today\n",
        f"Written by `{command}` on {machine['date']} (commit `{machine['commit']}`). "
        "Do not edit by hand: run the command again to refresh every number.\n",
        _machine(machine, load_end, load_peak, versions),
        _targets(targets),
        *(_region(rows, name, timeout) for name in dict.fromkeys(row.case.name for row in rows)),
        _parts(rows),
        _startup(startup) if startup else "",
        _figures(path, figures),
        _method(timeout),
        ("## Regions left out\n\n" + "".join(f"- {m}\n" for m in missing)) if missing else "",
        kept_sections(path),             # e.g. bench/batch.py's, which it writes itself
    ]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(part for part in parts if part))
    return path


def _machine(machine, load_end, load_peak, versions) -> str:
    load = " ".join(f"{v:.2f}" for v in machine["load"])
    load_after = " ".join(f"{v:.2f}" for v in load_end)
    # the run keeps about one core busy itself (two in the parallel kernels): a
    # 1-minute load above 1 before it starts, or above 2 while it runs, is other work
    busy = machine["load"][0] > 1 or load_peak > 2
    lines = [
        "## Machine\n",
        f"- CPU: {machine['cpu']}, {machine['cores']} logical cores; "
        f"RAM {machine['ram_gb']:.1f} GiB; {machine['os']}; Python {machine['python']}",
        f"- Load average (1, 5, 15 min) at the start: {load}; at the end: {load_after}; "
        f"highest 1-min load read after each peer: {load_peak:.2f} (this run itself keeps "
        "about one core busy)."
        + (" **Other work shared the cores during this run**: absolute times are inflated; "
           "ratios within a region are fairer, as its peers ran back to back." if busy else ""),
        "- Versions: " + ", ".join(f"{name} {version or 'not installed'}"
                                   for name, version in versions.items()),
        "",
    ]
    return "\n".join(lines)


def _targets(targets) -> str:
    if not targets:
        return ""
    mark = {True: "**holds**", False: "**misses**", None: "not measured"}
    lines = ["## Targets (issues 2, 5 and 13)\n", "| target | measured | verdict |", "|---|---|---|"]
    lines += [f"| {t.goal} | {t.measured} | {mark[t.holds]} |" for t in targets]
    return "\n".join(lines) + "\n"


def _region(rows, name, timeout) -> str:
    mine = [row for row in rows if row.case.name == name]
    case = mine[0].case
    pds = next((row for row in mine if row.peer.key == "pds" and row.ok), None)
    lines = [f"### {name}\n",
             f"alpha = {case.alpha:.6g}; region Betti numbers (components, holes) = "
             f"{case.region.betti}; area {case.region.area:.6g}.\n",
             "| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(_cells(row, pds, timeout)) + " |" for row in mine]
    return "\n".join(lines) + "\n"


def _cells(row: Row, pds: Row | None, timeout: float) -> list[str]:
    label = f"**{row.peer.label}**" if row.peer.key == "pds" else row.peer.label
    if row.status == "timeout":
        ratio = f"> {timeout / pds.time:.3g}" if pds else "—"
        return [label, f"> {timeout:g} (timeout)", ratio] + ["—"] * 12 + [row.message]
    if not row.ok:
        return [label, row.status] + ["—"] * 13 + [row.message]
    m = row.metric
    betti = m("betti", None)
    topology = "—" if betti is None else f"{betti} {'✓' if m('topology_ok') else '✗'}"
    time = _g(row.time) + (" ‡" if row.scale != 1 else "")
    return [label, time, _g(row.time / pds.time) if pds else "—", f"{row.peak_mb:.0f}",
            f"{m('vertices'):,}", f"{m('triangles'):,}", _f(m("min_angle"), 1),
            _f(m("max_angle"), 1), _f(m("max_aspect"), 2), _f(m("mean_aspect"), 2),
            _share(m("above_bound")), _f(m("coverage_gap"), 3), topology, _f(m("area_ratio"), 4),
            _f(m("hausdorff"), 2), _notes(row)]


def _notes(row: Row) -> str:
    notes = []
    if row.scale != 1:
        notes.append(f"‡ measured {row.times['total']:.3g} s for {row.measured_points:,} samples "
                     f"at {row.alpha / row.case.alpha:.3g}α, scaled ×{row.scale:.3g} (linear)")
    if row.peer.ours:
        notes.append(f"certificate {'ok' if row.info.get('certificate_ok') else 'FAILED'} "
                     f"(gap {row.info.get('certificate_gap', math.nan):.6f})")
    if "switches" in row.info:
        notes.append(f"`{row.info['switches']}`")
    if "meshlab_nonmanifold_edges" in row.info:
        count = row.info["meshlab_nonmanifold_edges"]
        notes.append(f"MeshLab reports {count:,} non-manifold edges")
    elif row.metric("nonmanifold_edges", 0):
        notes.append(f"{row.metric('nonmanifold_edges'):,} non-manifold edges")
    if row.message:
        notes.append(row.message)
    return "; ".join(notes)


def _parts(rows) -> str:
    pds_rows = [row for row in rows if row.peer.ours and row.ok]
    if not pds_rows:
        return ""
    scipy = {row.case.name: row for row in rows if row.peer.key == "scipy" and row.ok}
    lines = ["## pds_plugin's parts, timed apart\n",
             "mesh_region = poisson_disc + solid_alpha_complex; the parts are timed in a "
             "second call in the same process (same seed, same samples).\n",
             "| region | threads | samples | mesh_region (s) | sampling (s) | samples/s | "
             "complex (s) | certificate (s) | certificate / mesh | peak MiB meshing / with "
             "certificate | scipy PoissonDisk points/s | throughput × scipy |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in pds_rows:
        other = scipy.get(row.case.name)
        rate, other_rate = sampling_rate(row), sampling_rate(other) if other else math.nan
        lines.append(
            f"| {row.case.name} | {row.peer.env.get('PDS_THREADS', 'default')} | "
            f"{row.metric('vertices'):,} | {_g(row.time)} | "
            f"{_g(row.times['sampling'])} | {rate:,.0f} | {_g(row.times['complex'])} | "
            f"{_g(row.times['certificate'])} | {_g(row.times['certificate'] / row.time)} | "
            f"{row.peak_mb:.0f} / {row.info.get('peak_mb_with_certificate', math.nan):.0f} | "
            f"{_f(other_rate, 0)} | {_g(rate / other_rate)} |")
    return "\n".join(lines) + "\n"


def _startup(startup) -> str:
    return "\n".join([
        "## Start-up\n",
        "| measure | seconds |", "|---|---|",
        f"| `import pds_plugin`, fresh process (median / max of 5) | "
        f"{startup['import_median']:.3f} / {startup['import_max']:.3f} |",
        f"| then reaching `pds_plugin.mesh_region` (lazy imports: numpy, scipy, shapely, "
        f"kernels; median) | {startup['first_use']:.3f} |",
        f"| first mesh_region + certificate of a fresh process | "
        f"{startup['cold_first_call']:.2f} |",
        f"| the same in a second fresh process | "
        f"{startup['warm_first_call']:.2f} |",
        f"| the same call again in that process | {startup['in_process']:.3f} |",
        "",
        "The call is a unit square of about 10k samples (issue 13's cold-start size). The "
        "kernels are compiled at install: nothing is compiled at run time.\n"])


def _figures(path: Path, figures) -> str:
    if not figures:
        return ""
    lines = ["## Figures\n"]
    lines += [f"![{figure.stem}]({Path(figure).relative_to(path.parent)})\n" for figure in figures]
    return "\n".join(lines)


def _method(timeout) -> str:
    return f"""## How each number is obtained

- **One run, fresh processes.** Every peer runs on every region in its own fresh Python
  process (`bench/_isolate.py`), peers of a region back to back, pds_plugin first. The
  child first runs the peer once on a tiny square (imports, extension loading, library
  start-up: not timed; start-up is measured separately above), then on the region. A
  peer that crashes or exceeds the {timeout:g} s limit (`--timeout`) gets a row saying so
  and the run goes on. pds_plugin's child gets three times the limit: it meshes,
  certifies, then samples and meshes again to time the parts apart. A run shorter than
  1 s is repeated (up to 3 runs, every peer alike) and the fastest kept, as `timeit`
  does: on a shared machine the slowest runs measure the neighbours.
- **Time** is wall time (`time.perf_counter`) of the peer's own work: building its input
  from the region's rings, meshing, and reading the mesh back as arrays. **× pds** is
  that time over pds_plugin's `mesh_region` time on the same region. pds_plugin runs
  some kernels in parallel (OpenMP threads sized to the loop and the cores available);
  the "1 thread" row is the same code with `PDS_THREADS=1`. Triangle, gmsh
  (`General.NumThreads` left at 1), MeshLab and scipy run on one core.
- **‡ scipy's PoissonDisk** is pure-Python Bridson (a few thousand points/s), so above
  `--scipy-points` samples it runs on the same region at a coarser alpha
  (alpha·√(target/cap)); its time is scaled **linearly** in the sample count to
  pds_plugin's count on that region. Its gap, quality and topology are measured at the
  alpha it ran at. Its sampling throughput counts every point it made in the bounding box.
- **Peak MiB** is the child process's peak resident set (`VmHWM` of /proc/self/status),
  read right after the peer's meshing, so it includes the interpreter and the libraries
  (C allocations too, which `tracemalloc` would miss). Not `ru_maxrss`: Linux carries it
  over from the forking parent through exec, so every child would report at least the
  parent's size. For pds_plugin it is read before the certificate; the figure with the
  certificate is in the parts table.
- **Triangle** gets `pq30` / `pq33` with the max-area switch (`a`, written in fixed
  point: `a4e-05` would read as `a4` + `e`) tuned by untimed trial runs to pds_plugin's
  vertex count; hole points are one per piece of (convex hull − region).
- **gmsh** meshes a geo model of the region's rings with mesh size alpha at every point
  and `Mesh.MeshSizeMax` alpha, `Mesh.MeshSizeExtendFromBoundary` 0 (so short polygon
  edges do not shrink the interior); boundary segments shorter than alpha stay as they
  are, which is where its small angles come from.
- **MeshLab**: the region triangulated by `trimesh.creation.triangulate_polygon`
  (engine manifold), `generate_sampling_poisson_disk(radius=alpha)` (the seeded variant
  adds boundary points every alpha as `refinemesh` with `refineflag`), then the **2D
  alpha filter** every non-pds sampler gets: scipy Delaunay triangles with circumradius
  ≤ alpha whose centroid is in the region. The `generate_alpha_shape` row is what a
  MeshLab user tries instead: qhull in 3D on planar points.
- **Quality** (`pds_plugin.analysis.quality.triangle_quality`): angles in degrees, aspect ratio
  L²/A (longest edge squared over area; 4/√3 ≈ 2.31 equilateral, Theorem 1 bound
  4√3 ≈ 6.93); "> 4√3" is the share of triangles above the bound (+1e-9 relative).
- **gap / α** (samplers only): the largest distance from the region to the samples,
  computed independently of pds_plugin's certificate: circumradii of scipy Delaunay
  triangles whose circumcentre is in the region (Voronoi vertices) and nearest-sample
  distances of boundary probes every α/{PROBES_PER_ALPHA} (exact to α/{2 * PROBES_PER_ALPHA}).
  It must be ≤ 1 for the alpha-complex to have no pinholes.
- **Betti (b0, b1)**: components and holes of the mesh from its Euler characteristic
  (`pds_plugin.mesh.mesh_betti`); ✓ when equal to the region's. With overlapping
  triangles (MeshLab's alpha shape) the Euler count is meaningless: b1 goes negative.
- **area ratio**: mesh area / region area. **Hausdorff / α**: between the region's
  boundary and the mesh's boundary edges (pinholes included), both probed every
  α/{PROBES_PER_ALPHA} with exact point-to-segment distances (shapely STRtree).
- **Targets** are checked on the largest unit square of the run, with the ratios
  above; a peer over the time limit gives a lower bound on the ratio.
"""


def _g(value) -> str:
    if value is None or not math.isfinite(value):
        return "—"
    return f"{value:.3g}" if abs(value) < 1e4 else f"{value:,.0f}"


def _f(value, digits: int) -> str:
    if value is None or not math.isfinite(value):
        return "—"
    return f"{value:,.{digits}f}"


def _share(value) -> str:
    if value is None or not math.isfinite(value):
        return "—"
    return "0" if value == 0 else f"{100 * value:.2g} %"
