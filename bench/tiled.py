"""mesh_tiled against mesh_region: CPU time, wall time and memory, in process and on 2
Dask workers; and a CAD section at about 3 million samples checked by independent oracles.

    python bench/tiled.py                      # 1e5 and 1e6 samples, the CAD section at 3e6
    python bench/tiled.py --sizes 1e5 --cad 0  # a smoke run
    python bench/tiled.py --sizes --cad 3e6    # the CAD section only

Each region is meshed with the paper's construction (conforming=False, the only one
mesh_tiled makes) at the alpha that gives about the number of samples asked for, 4 x 4
tiles:

1. ``mesh_region`` in a fresh process;
2. ``mesh_tiled`` in a fresh process, its tasks run there one after the other;
3. ``mesh_tiled`` from a fresh driver process on a Dask ``LocalCluster`` of 2 worker
   processes (one thread each), warmed up by a tiny tiled mesh first.

Every run uses one kernel thread (``PDS_THREADS=1``), so CPU time is the work. Times are
CPU seconds (``time.process_time``; for the cluster, the driver's plus both workers'
increase over the run), and wall seconds: the machine is shared, mesh_region runs in the
same invocation.

**Memory.** A worker is a Python process with numpy, scipy, shapely, pds_plugin and Dask
loaded before any tile arrives: that *baseline* (its resident size when idle, after the
warm-up) is printed apart, and the *increment* is the worker's peak resident size over
the run (``VmHWM``, reset when the run starts) minus that baseline: what the tiles
themselves took. "tile mesh" is the largest tile's own share of the mesh (its samples
and triangles as arrays: 16 bytes per sample, 24 per triangle); the issue's target reads
increment <= 3 x tile mesh.

**Checks.** "same bytes" compares every file of the serial and the cluster store;
"= complex" checks that the stitched triangles equal ``solid_alpha_complex`` of all the
stitched samples, "cert" the tiled certificate. The CAD section is checked further by
oracles that share no code with pds_plugin: separation by a k-d tree (scipy), coverage
exactly (the largest distance from the region to the samples is at a Voronoi vertex in
the region, a crossing of a Voronoi edge with the boundary, or a boundary vertex: the
Delaunay circumcentres of scipy's Qhull, and along every boundary piece the lower
envelope of the squared distances to the samples near it), the faces equal to Qhull's
Delaunay triangles of circumradius <= alpha, the Betti numbers from the faces'
components and Euler characteristic against the region's. Run it under ``ulimit -v 12000000``.
"""

from __future__ import annotations

import os

os.environ.setdefault("PDS_THREADS", "1")

import argparse                                                     # noqa: E402
import hashlib                                                      # noqa: E402
import json                                                         # noqa: E402
import math                                                         # noqa: E402
import subprocess                                                   # noqa: E402
import sys                                                          # noqa: E402
import tempfile                                                     # noqa: E402
import time                                                         # noqa: E402
from pathlib import Path                                            # noqa: E402

TILES = (4, 4)

CHILD = r"""
import json, os, sys, time
import numpy as np
import shapely
import pds_plugin as pds

def status(key):
    for line in open("/proc/self/status"):
        if line.startswith(key):
            return int(line.split()[1]) / 1024

def idle():
    # the resident size now, and the peak reset to it (Linux: clear_refs 5)
    with open("/proc/self/clear_refs", "w") as file:
        file.write("5")
    return status("VmRSS")

def peak():
    return time.process_time(), status("VmHWM")

spec = json.loads(sys.argv[1])
region = pds.Region.from_shapely(shapely.from_wkb(bytes.fromhex(spec["wkb"])))
alpha, mode = spec["alpha"], spec["mode"]
small = pds.Region.from_shapely(shapely.box(0, 0, 1, 1))
out = {}
if mode == "baseline":
    out["import"] = status("VmRSS")
    pds.mesh_region(small, 0.1, conforming=False)
    out["warm"] = status("VmRSS")
elif mode == "region":
    pds.mesh_region(small, 0.1, conforming=False)                  # imports, kernels loaded
    base = idle()
    cpu, wall = time.process_time(), time.perf_counter()
    mesh = pds.mesh_region(region, alpha, conforming=False)
    out.update(cpu=time.process_time() - cpu, wall=time.perf_counter() - wall,
               samples=len(mesh.vertices), base=base, peak=status("VmHWM"))
elif mode == "serial":
    pds.mesh_tiled(small, 0.05, tiles=(4, 4), store=spec["store"] + "-warm")
    base = idle()
    cpu, wall = time.process_time(), time.perf_counter()
    tiled = pds.mesh_tiled(region, alpha, tiles=spec["tiles"], store=spec["store"])
    out.update(cpu=time.process_time() - cpu, wall=time.perf_counter() - wall,
               samples=tiled.samples, base=base, peak=status("VmHWM"))
elif mode == "pool":
    import resource
    from concurrent.futures import ProcessPoolExecutor
    from multiprocessing import get_context

    def children():
        usage = resource.getrusage(resource.RUSAGE_CHILDREN)
        return usage.ru_utime + usage.ru_stime

    # the processes' start and warm-up, measured apart: a pool that does only that
    with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
        pds.mesh_tiled(small, 0.05, tiles=(4, 4), store=spec["store"] + "-warm0", executor=pool)
    start = children()
    with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
        pds.mesh_tiled(small, 0.05, tiles=(4, 4), store=spec["store"] + "-warm", executor=pool)
        cpu, wall = time.process_time(), time.perf_counter()
        tiled = pds.mesh_tiled(region, alpha, tiles=spec["tiles"], store=spec["store"],
                               executor=pool)
        driver, wall = time.process_time() - cpu, time.perf_counter() - wall
    out.update(cpu=driver + children() - 2 * start, wall=wall, samples=tiled.samples)
else:
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None, env={"PDS_THREADS": "1"}) as cluster, \
            Client(cluster) as client:
        executor = client.get_executor()
        fresh = client.run(status, "VmRSS")
        pds.mesh_tiled(small, 0.05, tiles=(4, 4), store=spec["store"] + "-warm",
                       executor=executor)
        time.sleep(1.0)
        base = client.run(idle)
        before = client.run(peak)
        cpu, wall = time.process_time(), time.perf_counter()
        tiled = pds.mesh_tiled(region, alpha, tiles=spec["tiles"], store=spec["store"],
                               executor=executor)
        driver, wall = time.process_time() - cpu, time.perf_counter() - wall
        after = client.run(peak)
        base = client.run(idle) if spec.get("certificate") else base
        cpu, cert_wall = time.process_time(), time.perf_counter()
        if spec.get("certificate"):
            cert = pds.TiledMesh(spec["store"]).certificate(executor=executor)
            cert_after = client.run(peak)
            out.update(cert_ok=cert.ok, cert_wall=time.perf_counter() - cert_wall,
                       cert_increment=max(cert_after[w][1] - base[w] for w in base))
    out.update(cpu=driver + sum(after[w][0] - before[w][0] for w in after), driver_cpu=driver,
               wall=wall, samples=tiled.samples, fresh=max(fresh.values()),
               base=max(base.values()), increment=max(after[w][1] - base[w] for w in after),
               driver_peak=status("VmHWM"))
print(json.dumps(out))
"""


def synthetic(samples: float):
    """(name, geometry, alpha) for about ``samples`` samples: a unit square and a plate
    with holes on the seams of the 4 x 4 tiling."""
    from shapely.geometry import Point, box

    square = box(0, 0, 1, 1)
    plate = box(0, 0, 2, 1)
    for x in (0.25, 0.5, 1.0, 1.5, 1.75):
        for y in (0.25, 0.5, 0.75):
            plate = plate.difference(Point(x, y).buffer(0.06))
    for name, geometry in (("square", square), ("plate, 15 holes", plate)):
        yield name, geometry, math.sqrt(0.7 * geometry.area / samples)


def cad_section(samples: float):
    """(name, Region, alpha): the mid-height section of featuretype.STL (the shared data
    folder; 2 parts, 8 holes), or of the manifold3d plate of bench/_regions.py without it,
    at the alpha giving about ``samples`` samples."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from _regions import DATA, alpha_for, cad_plate, stl_section

    if (DATA / "featuretype.STL").exists():
        name, region = "featuretype.STL z-mid section", stl_section("featuretype.STL")()
    else:
        name, region = "CAD plate section (manifold3d)", cad_plate()
    return name, region, alpha_for(region, samples)


def run(mode: str, geometry, alpha: float, store: str = "", **extra) -> dict:
    import shapely

    spec = json.dumps({"mode": mode, "wkb": shapely.to_wkb(geometry, hex=True), "alpha": alpha,
                       "store": store, "tiles": TILES, **extra})
    done = subprocess.run([sys.executable, "-c", CHILD, spec], capture_output=True, text=True,
                          env={**os.environ, "PDS_THREADS": "1"})
    if done.returncode:
        raise RuntimeError(f"{mode} failed:\n{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def digest(store: Path) -> str:
    h = hashlib.sha256()
    for path in sorted(p for p in store.rglob("*") if p.is_file()):
        h.update(str(path.relative_to(store)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def tile_mesh_bytes(tiled) -> int:
    """The largest tile's own mesh: 16 bytes per sample, 24 per triangle."""
    return max(16 * len(v) + 24 * len(f) for v, _, _, f in
               (tiled.tile(i, j) for i, j in tiled.tiling.tiles()))


def checks(store: Path, alpha: float) -> tuple[bool, bool]:
    """Stitched faces = the non-tiled complex of the stitched samples; the tiled
    certificate."""
    import numpy as np

    import pds_plugin as pds
    from pds_plugin.tiled import _canonical

    tiled = pds.TiledMesh(store)
    mesh = tiled.to_mesh()
    equal = bool(np.array_equal(_canonical(pds.solid_alpha_complex(mesh.vertices, alpha)),
                                _canonical(mesh.faces)))
    return equal, tiled.certificate().ok


def baseline() -> dict:
    """Resident sizes (MiB) of a bare interpreter, with numpy, scipy and shapely, and
    with pds_plugin imported and warmed up."""
    bare = subprocess.run([sys.executable, "-c", "import resource; print(open('/proc/self/status')"
                           ".read().split('VmRSS:')[1].split()[0])"], capture_output=True,
                          text=True).stdout
    libs = subprocess.run([sys.executable, "-c", "import numpy, scipy.sparse, scipy.spatial, "
                           "shapely; print(open('/proc/self/status').read().split('VmRSS:')[1]"
                           ".split()[0])"], capture_output=True, text=True).stdout
    from shapely.geometry import box

    package = run("baseline", box(0, 0, 1, 1), 0.1)
    return {"python": int(bare) / 1024, "libraries": int(libs) / 1024, **package}


# ---- the independent oracles (scipy and shapely only) -------------------------------

def oracle_separation(xy) -> float:
    from scipy.spatial import cKDTree

    return float(cKDTree(xy).query(xy, k=2)[0][:, 1].min())


def oracle_delaunay(xy, alpha):
    """Qhull's Delaunay triangles of ``xy``, their circumcentres and circumradii, and
    the (sorted) triangles of circumradius <= alpha."""
    import numpy as np
    from scipy.spatial import Delaunay

    simplices = Delaunay(xy).simplices
    a, b, c = (xy[simplices[:, k]] for k in range(3))
    bx, by, cx, cy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1], c[:, 0] - a[:, 0], c[:, 1] - a[:, 1]
    d = 2.0 * (bx * cy - by * cx)
    ux = (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / d
    uy = (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / d
    radius = np.hypot(ux, uy)
    centre = np.column_stack([a[:, 0] + ux, a[:, 1] + uy])
    return simplices, centre, radius


def oracle_coverage(xy, geometry, centre, radius, alpha) -> float:
    """The largest distance from the region to the samples ``xy``, exactly: the
    Voronoi vertices (Delaunay circumcentres) in the region, and along each boundary
    piece the maximum of the squared distance to its near samples (t^2 plus the lower
    envelope of lines, largest at a crossing of two lines or an end)."""
    import numpy as np
    import shapely
    from scipy.spatial import cKDTree

    shapely.prepare(geometry)
    big = radius > 0.5 * alpha
    inside = shapely.contains_xy(geometry, centre[big, 0], centre[big, 1]) | \
        shapely.intersects_xy(geometry.boundary, centre[big, 0], centre[big, 1])
    worst = float(radius[big][inside].max()) if inside.any() else 0.0
    # boundary pieces no longer than alpha / 2
    rings = [shapely.get_coordinates(r) for p in shapely.get_parts(geometry)
             for r in (p.exterior, *p.interiors)]
    seg = np.concatenate([np.stack([r[:-1], r[1:]], axis=1) for r in rings])
    vec = seg[:, 1] - seg[:, 0]
    length = np.hypot(vec[:, 0], vec[:, 1])
    seg, vec, length = seg[length > 0], vec[length > 0], length[length > 0]
    count = np.ceil(length / (0.5 * alpha)).astype(np.int64)
    owner = np.repeat(np.arange(len(seg)), count)
    step = np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count)
    start = seg[owner, 0] + (step / count[owner])[:, None] * vec[owner]
    unit = vec[owner] / length[owner, None]
    piece = length[owner] / count[owner]
    tree, k = cKDTree(xy), 16
    mid = start + 0.5 * piece[:, None] * unit
    while True:           # every sample within alpha + half a piece of each piece's middle
        dist, near = tree.query(mid, k=k, distance_upper_bound=alpha + 0.5 * piece.max())
        if not np.isfinite(dist[:, -1]).any():
            break
        k *= 2
    k = int(np.isfinite(dist).sum(axis=1).max())
    dist, near = dist[:, :k], near[:, :k]
    for chunk in range(0, len(start), 1024):
        sl = slice(chunk, chunk + 1024)
        p0, d, L, idx, ok = start[sl], unit[sl], piece[sl], near[sl], np.isfinite(dist[sl])
        s = xy[np.where(ok, idx, 0)]
        rel = p0[:, None, :] - s
        c = np.where(ok, (rel ** 2).sum(axis=2), np.inf)            # value at t = 0
        m = np.where(ok, 2.0 * (rel * d[:, None, :]).sum(axis=2), 0.0)   # slope in t
        with np.errstate(invalid="ignore", divide="ignore"):
            t = (c[:, None, :] - c[:, :, None]) / (m[:, :, None] - m[:, None, :])
        t = t.reshape(len(p0), -1)
        t = np.where(np.isfinite(t) & (t > 0) & (t < L[:, None]), t, 0.0)
        t = np.concatenate([t, np.zeros((len(p0), 1)), L[:, None]], axis=1)
        value = t ** 2 + (c[:, None, :] + m[:, None, :] * t[:, :, None]).min(axis=2)
        worst = max(worst, float(np.sqrt(np.max(value))))
    return worst


def oracle_betti(n_vertices, faces) -> tuple[int, int]:
    """b0 from the components of the triangles' edge graph, b1 = b0 - (V - E + F)."""
    import numpy as np
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    keys = np.unique(edges[:, 0] * np.int64(n_vertices) + edges[:, 1])
    a, b = keys // n_vertices, keys % n_vertices
    used = np.unique(faces)
    graph = coo_matrix((np.ones(len(keys), np.int8), (a, b)), shape=(n_vertices, n_vertices))
    label = connected_components(graph, directed=False)[1]
    b0 = len(np.unique(label[used]))
    chi = len(used) - len(keys) + len(faces)
    return b0, b0 - chi


def cad_row(samples: float) -> None:
    import numpy as np

    import pds_plugin as pds

    name, region, alpha = cad_section(samples)
    geometry = region.geometry
    print(f"\n### {name}: alpha = {alpha:.6g}, 4 x 4 tiles, 2 Dask workers\n", flush=True)
    with tempfile.TemporaryDirectory() as folder:
        serial_store, cluster_store = Path(folder, "serial"), Path(folder, "cluster")
        whole = run("region", geometry, alpha)
        serial = run("serial", geometry, alpha, str(serial_store))
        cluster = run("cluster", geometry, alpha, str(cluster_store), certificate=True)
        pool = run("pool", geometry, alpha, str(Path(folder, "pool")))
        same = digest(serial_store) == digest(cluster_store) == digest(Path(folder, "pool"))
        tiled = pds.TiledMesh(serial_store)
        tile_bytes = tile_mesh_bytes(tiled)
        started = time.perf_counter()
        cert = tiled.certificate()
        cert_wall = time.perf_counter() - started
        mesh = tiled.to_mesh()
    xy, faces = mesh.vertices, mesh.faces
    started = time.perf_counter()
    separation = oracle_separation(xy)
    simplices, centre, radius = oracle_delaunay(xy, alpha)
    small = np.sort(simplices[radius <= alpha], axis=1)
    same_faces = np.array_equal(np.unique(small, axis=0), np.unique(np.sort(faces, axis=1), axis=0))
    tie = np.abs(radius / alpha - 1)
    gap = oracle_coverage(xy, geometry, centre, radius, alpha)
    betti = oracle_betti(len(xy), faces)
    oracle_wall = time.perf_counter() - started
    exact = betti == tuple(region.betti) == tuple(cert.betti_mesh)
    ratio = cluster["increment"] * 2**20 / tile_bytes
    rows = [
        ("samples / triangles",
         f"{len(xy):,} / {len(faces):,} (Qhull: {int((radius <= alpha).sum()):,} of "
         f"circumradius <= alpha; the closest to alpha: {tie.min():.1e} relative)"),
        ("separation (k-d tree) / alpha",
         f"{separation / alpha:.9f} (>= 1: {'yes' if separation >= alpha else 'NO'})"),
        ("coverage (exact: Voronoi vertices + boundary envelope) / alpha",
         f"{gap / alpha:.9f} (<= 1: {'yes' if gap <= alpha else 'NO'}); tiled certificate "
         f"{cert.coverage_gap:.9f}"),
        ("faces = Qhull's alpha-complex", "yes" if same_faces else "NO"),
        ("Betti: faces / region / tiled certificate",
         f"{betti} / {region.betti} / {cert.betti_mesh} ({'exact' if exact else 'NO'})"),
        ("tiled certificate: in process; on the 2 workers",
         f"{'ok' if cert.ok else 'FAILED'} in {cert_wall:.1f} s wall; "
         f"{'ok' if cluster.get('cert_ok') else 'FAILED'} in {cluster['cert_wall']:.1f} s "
         f"wall, worker peak increment {cluster['cert_increment']:.1f} MiB"),
        ("same bytes in process, on the cluster and on the pool", "yes" if same else "NO"),
        ("mesh_region: CPU s / wall s / peak MiB (+ over its idle process)",
         f"{whole['cpu']:.2f} / {whole['wall']:.2f} / {whole['peak']:.0f} "
         f"(+{whole['peak'] - whole['base']:.0f})"),
        ("tiled in process: CPU s / wall s / peak MiB (+ over its idle process)",
         f"{serial['cpu']:.2f} / {serial['wall']:.2f} / {serial['peak']:.0f} "
         f"(+{serial['peak'] - serial['base']:.1f})"),
        ("tiled on 2 workers: CPU s (driver + workers) / wall s",
         f"{cluster['cpu']:.2f} / {cluster['wall']:.2f}"),
        ("tiled on a pool of 2 spawned processes: CPU s (driver + processes, less their "
         "start-up) / wall s", f"{pool['cpu']:.2f} / {pool['wall']:.2f}"),
        ("cluster wall / mesh_region wall (target <= 1.5)",
         f"{cluster['wall'] / whole['wall']:.2f}"),
        ("worker MiB: idle baseline / peak increment / largest tile mesh",
         f"{cluster['base']:.0f} / {cluster['increment']:.1f} / {tile_bytes / 2**20:.1f} "
         f"(increment {ratio:.2f} x tile mesh; target <= 3)"),
        ("oracles' wall s", f"{oracle_wall:.1f}"),
    ]
    print("| | |\n|---|---|")
    for key, value in rows:
        print(f"| {key} | {value} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="*", default=[1e5, 1e6])
    parser.add_argument("--cad", type=float, default=3e6,
                        help="samples of the CAD section (0: skip it)")
    args = parser.parse_args()
    print(f"load average at start: {os.getloadavg()}", flush=True)
    base = baseline()
    print(f"\nA worker's resident size before any tile: Python {base['python']:.0f} MiB, with "
          f"numpy, scipy and shapely {base['libraries']:.0f} MiB; with pds_plugin imported "
          f"(lazily: no scipy yet) {base['import']:.0f} MiB, after one small mesh (kernels, "
          f"scipy, shapely loaded) {base['warm']:.0f} MiB; a Dask worker process: \"fresh\" "
          "and \"idle\" (after a warm-up tiled mesh) below.\n", flush=True)
    if args.sizes:
        print("| region | samples | mesh_region CPU s / wall s / peak MiB (+ over idle) | tiled "
              "4x4 serial CPU s / wall s / peak MiB (+ over idle) | tiled 4x4 on 2 Dask workers "
              "CPU s / wall s | worker MiB: fresh / idle (warmed up) / peak increment | tile "
              "mesh MiB | increment / tile mesh | cluster / region wall | same bytes "
              "| = complex | cert |")
        print("|" + "---|" * 12)
    for size in args.sizes:
        for name, geometry, alpha in synthetic(size):
            with tempfile.TemporaryDirectory() as folder:
                serial_store, cluster_store = Path(folder, "serial"), Path(folder, "cluster")
                whole = run("region", geometry, alpha)
                serial = run("serial", geometry, alpha, str(serial_store))
                cluster = run("cluster", geometry, alpha, str(cluster_store))
                same = digest(serial_store) == digest(cluster_store)
                equal, ok = checks(serial_store, alpha)
                import pds_plugin as pds
                tile_bytes = tile_mesh_bytes(pds.TiledMesh(serial_store))
            print(f"| {name} | {serial['samples']:,} | {whole['cpu']:.2f} / {whole['wall']:.2f} / "
                  f"{whole['peak']:.0f} (+{whole['peak'] - whole['base']:.0f}) | "
                  f"{serial['cpu']:.2f} / {serial['wall']:.2f} / {serial['peak']:.0f} "
                  f"(+{serial['peak'] - serial['base']:.1f}) | {cluster['cpu']:.2f} / "
                  f"{cluster['wall']:.2f} | {cluster['fresh']:.0f} / {cluster['base']:.0f} / "
                  f"+{cluster['increment']:.1f} | {tile_bytes / 2**20:.1f} | "
                  f"{cluster['increment'] * 2**20 / tile_bytes:.2f} | "
                  f"{cluster['wall'] / whole['wall']:.2f} | {'yes' if same else 'NO'} | "
                  f"{'yes' if equal else 'NO'} | {'ok' if ok else 'FAILED'} |", flush=True)
    if args.cad:
        cad_row(args.cad)
    print(f"\nload average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
