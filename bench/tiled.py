"""mesh_tiled against mesh_region: CPU time and peak memory, serial and on 2 Dask workers.

    python bench/tiled.py                    # 1e5, 3e5 and 1e6 samples (~3-5 min on 2 loaded cores)
    python bench/tiled.py --sizes 1e5        # a smoke run

Each region is meshed with the paper's construction (conforming=False, the only one
mesh_tiled makes) at the alpha that gives about the number of samples asked for:

1. ``mesh_region`` in a fresh process;
2. ``mesh_tiled`` in a fresh process, its tasks run there one after the other;
3. ``mesh_tiled`` from a fresh driver process on a Dask ``LocalCluster`` of 2 worker
   processes (one thread each), warmed up by a tiny tiled mesh first.

Every run uses one kernel thread (``PDS_THREADS=1``), so CPU time is the work. Times are
CPU seconds (``time.process_time``; for the cluster, the driver's plus both workers'
increase over the run), and wall seconds for the record: the machine is shared. Peak
memory is ``VmHWM`` of the process (for the cluster, of the larger worker, after the
warm-up and after the run: the difference is what the tiles added). "tile mesh"
is one tile's own share of the mesh (its samples and triangles as arrays: 16 bytes per
sample, 24 per triangle). "same bytes" compares every file of the serial and the
cluster store; "= complex" checks that the stitched triangles equal
``solid_alpha_complex`` of all the stitched samples, and "cert" the tiled certificate.
Run it under ``ulimit -v 6000000``.
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
from pathlib import Path                                            # noqa: E402

TILES = (4, 4)

CHILD = r"""
import json, os, sys, time, math, resource
import numpy as np
import shapely
import pds_plugin as pds

def hwm():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM"):
            return int(line.split()[1]) / 1024

spec = json.loads(sys.argv[1])
region = pds.Region.from_shapely(shapely.from_wkt(spec["wkt"]))
alpha, mode = spec["alpha"], spec["mode"]
small = pds.Region.from_shapely(shapely.box(0, 0, 1, 1))
pds.mesh_region(small, 0.1, conforming=False)                  # imports, kernels loaded
out = {}
if mode == "region":
    cpu, wall = time.process_time(), time.perf_counter()
    mesh = pds.mesh_region(region, alpha, conforming=False)
    out.update(cpu=time.process_time() - cpu, wall=time.perf_counter() - wall,
               samples=len(mesh.vertices), peak=hwm())
elif mode == "serial":
    cpu, wall = time.process_time(), time.perf_counter()
    tiled = pds.mesh_tiled(region, alpha, tiles=spec["tiles"], store=spec["store"])
    out.update(cpu=time.process_time() - cpu, wall=time.perf_counter() - wall,
               samples=tiled.samples, peak=hwm())
else:
    from distributed import Client, LocalCluster

    def usage():
        for line in open("/proc/self/status"):
            if line.startswith("VmHWM"):
                peak = int(line.split()[1]) / 1024
        return time.process_time(), peak

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None, env={"PDS_THREADS": "1"}) as cluster, \
            Client(cluster) as client:
        executor = client.get_executor()
        pds.mesh_tiled(small, 0.05, tiles=(4, 4), store=spec["store"] + "-warm",
                       executor=executor)
        before = client.run(usage)
        cpu, wall = time.process_time(), time.perf_counter()
        tiled = pds.mesh_tiled(region, alpha, tiles=spec["tiles"], store=spec["store"],
                               executor=executor)
        driver, wall = time.process_time() - cpu, time.perf_counter() - wall
        after = client.run(usage)
    workers = sum(after[w][0] - before[w][0] for w in after)
    out.update(cpu=driver + workers, driver_cpu=driver, wall=wall, samples=tiled.samples,
               peak=max(after[w][1] for w in after), warm=max(before[w][1] for w in before),
               driver_peak=hwm())
print(json.dumps(out))
"""


def regions(samples: float):
    """(name, WKT, alpha) for about ``samples`` samples: a unit square and a plate with
    holes on the seams of the 4 x 4 tiling."""
    from shapely.geometry import Point, box

    square = box(0, 0, 1, 1)
    plate = box(0, 0, 2, 1)
    for x in (0.25, 0.5, 1.0, 1.5, 1.75):
        for y in (0.25, 0.5, 0.75):
            plate = plate.difference(Point(x, y).buffer(0.06))
    for name, geometry in (("square", square), ("plate, 15 holes", plate)):
        alpha = math.sqrt(0.7 * geometry.area / samples)
        yield name, geometry.wkt, alpha


def run(mode: str, wkt: str, alpha: float, store: str) -> dict:
    spec = json.dumps({"mode": mode, "wkt": wkt, "alpha": alpha, "store": store,
                       "tiles": TILES})
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


def checks(store: Path, alpha: float) -> tuple[bool, bool, int]:
    """Stitched faces = the non-tiled complex of the stitched samples; the tiled
    certificate; the largest tile's own mesh in bytes."""
    import numpy as np

    import pds_plugin as pds
    from pds_plugin.tiled import _canonical

    tiled = pds.TiledMesh(store)
    mesh = tiled.to_mesh()
    equal = bool(np.array_equal(_canonical(pds.solid_alpha_complex(mesh.vertices, alpha)),
                                _canonical(mesh.faces)))
    del mesh
    largest = max(16 * len(v) + 24 * len(f) for v, _, _, f in
                  (tiled.tile(i, j) for i, j in tiled.tiling.tiles()))
    return equal, tiled.certificate().ok, largest


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[1e5, 3e5, 1e6])
    args = parser.parse_args()
    print(f"load average at start: {os.getloadavg()}", flush=True)
    header = ("| region | samples | mesh_region CPU s / wall s / peak MiB | tiled 4x4 serial "
              "CPU s / wall s / peak MiB | tiled 4x4 on 2 Dask workers CPU s / wall s / worker "
              "peak MiB (warmed up → after) | tile mesh MiB | serial / region CPU | same bytes "
              "| = complex | cert |")
    print(header)
    print("|" + "---|" * 10)
    for size in args.sizes:
        for name, wkt, alpha in regions(size):
            with tempfile.TemporaryDirectory() as folder:
                serial_store, cluster_store = Path(folder, "serial"), Path(folder, "cluster")
                whole = run("region", wkt, alpha, "")
                serial = run("serial", wkt, alpha, str(serial_store))
                cluster = run("cluster", wkt, alpha, str(cluster_store))
                same = digest(serial_store) == digest(cluster_store)
                equal, ok, tile_bytes = checks(serial_store, alpha)
            print(f"| {name} | {serial['samples']:,} | {whole['cpu']:.2f} / {whole['wall']:.2f} / "
                  f"{whole['peak']:.0f} | {serial['cpu']:.2f} / {serial['wall']:.2f} / "
                  f"{serial['peak']:.0f} | {cluster['cpu']:.2f} / {cluster['wall']:.2f} / "
                  f"{cluster['warm']:.0f} → {cluster['peak']:.0f} | {tile_bytes / 2**20:.1f} | "
                  f"{serial['cpu'] / whole['cpu']:.2f} | {'yes' if same else 'NO'} | "
                  f"{'yes' if equal else 'NO'} | {'ok' if ok else 'FAILED'} |", flush=True)
    print(f"load average at end: {os.getloadavg()}")


if __name__ == "__main__":
    main()
