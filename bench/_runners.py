"""The peers: how each mesher is run on a region, as a user of it would.

Every runner takes ``(region, alpha, target, options)`` -- ``target`` is pds_plugin's
vertex count on the same region, ``options`` the :class:`Options` of the run -- and returns
a :class:`Run`. Each runner times only its own work (``perf_counter`` around the library
calls) and reads the process's peak resident memory when its meshing is done, so the
caller can run it in a fresh process and compare like with like.
"""

from __future__ import annotations

import math
import resource
import sys
from dataclasses import dataclass, field
from time import perf_counter
from typing import Callable

import numpy as np
import shapely


@dataclass(frozen=True)
class Options:
    seed: int = 0
    scipy_points: int = 10_000   # largest sample count scipy's PoissonDisk is asked for


@dataclass
class Run:
    """What one peer made, and what it cost."""

    vertices: np.ndarray            # (N, 2)
    faces: np.ndarray               # (M, 3) int
    alpha: float                    # the radius the metrics are relative to
    times: dict                     # seconds; "total" is the peer's end-to-end time
    peak_mb: float                  # peak resident memory of the process, MiB
    samples: np.ndarray | None = None   # the point set a sampler made (its coverage is measured)
    info: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Peer:
    key: str                     # command-line name (``--peers``)
    label: str                   # shown in the table
    run: Callable
    needs: tuple = ()            # modules that must be importable
    install: str = 'pip install "pds_plugin[bench]"'
    env: dict = field(default_factory=dict)   # environment of its child process

    @property
    def ours(self) -> bool:
        """True for pds_plugin itself (in any thread setting, conforming or not)."""
        return self.key.startswith("pds")


def peak_rss_mb() -> float:
    """Peak resident set size of this process's address space so far, in MiB.

    Linux: ``VmHWM`` of /proc/self/status. Not ``ru_maxrss``: the kernel carries it over
    from the forking parent through exec, so a child of a 500 MB parent reports at least
    500 MB whatever it does itself. Elsewhere ``ru_maxrss`` (KiB; bytes on macOS).
    """
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 2**10
    except OSError:
        pass
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return rss / 2**20 if sys.platform == "darwin" else rss / 2**10


def alpha_faces(points: np.ndarray, alpha: float, region) -> np.ndarray:
    """The 2D alpha filter a user builds from scipy: Delaunay triangles of circumradius
    at most ``alpha`` whose centroid lies in the region (an alpha larger than a concave
    notch would otherwise bridge it)."""
    from scipy.spatial import Delaunay

    if len(points) < 3:
        return np.empty((0, 3), np.int64)
    faces = Delaunay(points).simplices
    a, b, c = (points[faces[:, k]] for k in range(3))
    ab, ac, bc = b - a, c - a, c - b
    twice_area = np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    lengths = np.hypot(*ab.T) * np.hypot(*ac.T) * np.hypot(*bc.T)
    with np.errstate(divide="ignore", invalid="ignore"):
        small = lengths <= 2 * alpha * twice_area        # circumradius = abc / (4 * area)
    centroid = (a + b + c) / 3
    inside = shapely.contains_xy(region.geometry, centroid[:, 0], centroid[:, 1])
    return faces[small & inside].astype(np.int64)


def boundary_seeds(region, spacing: float) -> np.ndarray:
    """Points every ``spacing`` along each boundary ring, from its first vertex."""
    seeds = []
    for ring in map(shapely.LinearRing, region.rings):
        at = np.arange(0, ring.length, spacing)
        seeds.append(shapely.get_coordinates(shapely.line_interpolate_point(ring, at)))
    return np.concatenate(seeds)


# ----------------------------------------------------------------------------- pds_plugin

def _pds(conforming: bool):
    def run(region, alpha, target, options):
        """mesh_region end to end; then its certificate; then sampling and complex again,
        each timed apart (same seed, so the same samples)."""
        import pds_plugin as pds

        start = perf_counter()
        mesh = pds.mesh_region(region, alpha, seed=options.seed, conforming=conforming)
        meshed = perf_counter()
        peak = peak_rss_mb()
        certificate = mesh.certificate()
        certified = perf_counter()
        peak_certified = peak_rss_mb()
        samples = pds.poisson_disc(region, alpha, seed=options.seed, conforming=conforming)
        sampled = perf_counter()
        pds.solid_alpha_complex(samples.points, alpha, boundary=samples.rings)
        done = perf_counter()
        return Run(mesh.vertices, mesh.faces, alpha, samples=mesh.vertices, peak_mb=peak,
                   times={"total": meshed - start, "certificate": certified - meshed,
                          "sampling": sampled - certified, "complex": done - sampled},
                   info={"certificate_ok": certificate.ok,
                         "certificate_gap": certificate.coverage_gap,
                         "peak_mb_with_certificate": peak_certified})
    return run


# ----------------------------------------------------------------------------- scipy

def run_scipy(region, alpha, target, options):
    """scipy.stats.qmc.PoissonDisk (Bridson) over the bounding box at radius alpha,
    clipped to the region, then the 2D alpha filter. Above ``options.scipy_points``
    samples it is run at a coarser alpha (same region) and its time is extrapolated
    linearly to ``target`` samples by the caller."""
    from scipy.stats import qmc

    asked = min(target, options.scipy_points)
    used_alpha = alpha * math.sqrt(target / asked)
    xmin, ymin, xmax, ymax = region.bounds
    start = perf_counter()
    engine = qmc.PoissonDisk(2, radius=used_alpha, l_bounds=[xmin, ymin], u_bounds=[xmax, ymax],
                             rng=options.seed)
    points = engine.fill_space()
    sampled = perf_counter()
    in_box = len(points)
    points = points[shapely.contains_xy(region.geometry, points[:, 0], points[:, 1])]
    faces = alpha_faces(points, used_alpha, region)
    done = perf_counter()
    return Run(points, faces, used_alpha, samples=points, peak_mb=peak_rss_mb(),
               times={"total": done - start, "sampling": sampled - start},
               info={"bridson_points": in_box})


# ----------------------------------------------------------------------------- MeshLab

def _meshlab_samples(region, alpha, seeded: bool):
    """The region triangulated (trimesh, engine manifold), MeshLab's Poisson-disk
    sampling at radius alpha, optionally seeded with boundary points every alpha.

    Returns the MeshSet (current mesh: the samples) and the times of the steps.
    """
    import pymeshlab as pm
    import trimesh

    from pds_plugin.silence import silenced

    start = perf_counter()
    parts = [trimesh.creation.triangulate_polygon(polygon, engine="manifold")
             for polygon in region.geometry.geoms]
    offsets = np.cumsum([0] + [len(v) for v, _ in parts[:-1]])
    vertices = np.concatenate([v for v, _ in parts])
    faces = np.concatenate([f + o for (_, f), o in zip(parts, offsets)])
    with silenced():
        meshset = pm.MeshSet()
        meshset.add_mesh(pm.Mesh(vertex_matrix=np.column_stack([vertices, np.zeros(len(vertices))]),
                                 face_matrix=faces), "region")
        triangulated = perf_counter()
        seeding = {}
        if seeded:
            seeds = boundary_seeds(region, alpha)
            meshset.add_mesh(pm.Mesh(np.column_stack([seeds, np.zeros(len(seeds))])), "seeds")
            meshset.set_current_mesh(0)
            seeding = {"refineflag": True, "refinemesh": 1}
        meshset.generate_sampling_poisson_disk(radius=pm.PureValue(alpha), **seeding)
    sampled = perf_counter()
    return meshset, {"triangulate": triangulated - start, "sampling": sampled - triangulated}


def _meshlab_filtered(seeded: bool):
    def run(region, alpha, target, options):
        start = perf_counter()
        meshset, times = _meshlab_samples(region, alpha, seeded)
        points = np.ascontiguousarray(meshset.current_mesh().vertex_matrix()[:, :2])
        faces = alpha_faces(points, alpha, region)
        done = perf_counter()
        return Run(points, faces, alpha, samples=points, peak_mb=peak_rss_mb(),
                   times={"total": done - start, **times})
    return run


def run_meshlab_alpha_shape(region, alpha, target, options):
    """What a MeshLab user tries next: ``generate_alpha_shape`` on the boundary-seeded
    samples. It is qhull in 3D (with joggle) on planar points: overlapping triangles."""
    import pymeshlab as pm

    from pds_plugin.silence import silenced

    start = perf_counter()
    meshset, times = _meshlab_samples(region, alpha, seeded=True)
    with silenced():
        meshset.generate_alpha_shape(alpha=pm.PureValue(alpha), filtering="Alpha Complex")
    shape = meshset.current_mesh()
    done = perf_counter()
    with silenced():
        measures = meshset.get_topological_measures()
    total = done - start
    return Run(np.asarray(shape.vertex_matrix()[:, :2], float),
               shape.face_matrix().astype(np.int64), alpha, peak_mb=peak_rss_mb(),
               times={"total": total, **times, "alpha_shape": total - sum(times.values())},
               info={"meshlab_nonmanifold_edges": int(measures["non_two_manifold_edges"])})


# ----------------------------------------------------------------------------- Triangle

def _pslg(region) -> dict:
    """The region as Triangle's planar straight line graph, with one hole point in each
    connected piece of (convex hull - region)."""
    rings = region.rings
    vertices = np.concatenate(rings)
    first = np.cumsum([0] + [len(r) for r in rings[:-1]])
    corner = [np.arange(len(ring)) for ring in rings]
    segments = np.concatenate([f + np.column_stack([i, np.roll(i, -1)])
                               for f, i in zip(first, corner)])
    pslg = {"vertices": vertices, "segments": segments}
    empty = shapely.get_parts(region.geometry.convex_hull.difference(region.geometry))
    empty = empty[~shapely.is_empty(empty)]
    if len(empty):
        pslg["holes"] = shapely.get_coordinates(shapely.point_on_surface(empty))
    return pslg


def _triangle(min_angle: int):
    def run(region, alpha, target, options):
        """``pq<angle>a<area>Q``, the area chosen (untimed) for about ``target`` vertices."""
        import triangle

        area = _area_for_vertices(_pslg(region), f"pq{min_angle}", target, region.area)
        switches = f"pq{min_angle}a{area:.20f}Q"     # fixed point: 'a4e-05' reads as a4 + e
        start = perf_counter()
        mesh = triangle.triangulate(_pslg(region), switches)
        done = perf_counter()
        return Run(mesh["vertices"], mesh["triangles"].astype(np.int64), alpha,
                   peak_mb=peak_rss_mb(), times={"total": done - start},
                   info={"switches": switches.rstrip("0")})
    return run


def _area_for_vertices(pslg, prefix: str, target: int, region_area: float) -> float:
    """The max-area switch that gives about ``target`` vertices: the vertex count is
    modelled as ``n0 + c / area`` (boundary plus interior), refitted on the last two
    trial runs until within 2 % of the target; the best area tried is returned."""
    import triangle

    def vertices(area):
        return len(triangle.triangulate(pslg, f"{prefix}a{area:.20f}Q")["vertices"])

    a1 = 2.5 * region_area / max(target / 8, 10)
    a2 = a1 / 2
    n1, n2 = vertices(a1), vertices(a2)
    tried = [(abs(n1 - target), a1), (abs(n2 - target), a2)]
    for _ in range(4):
        c = (n2 - n1) / (1 / a2 - 1 / a1)
        n0 = n2 - c / a2
        if min(tried)[0] <= 0.02 * target or c <= 0 or target <= n0:
            break
        a1, n1, a2 = a2, n2, c / (target - n0)
        n2 = vertices(a2)
        tried.append((abs(n2 - target), a2))
    return min(tried)[1]


# ----------------------------------------------------------------------------- gmsh

def _gmsh(algorithm: int):
    def run(region, alpha, target, options):
        """The region's rings as a gmsh geo model, mesh size alpha at every point and
        inside (``MeshSizeExtendFromBoundary`` 0, so polygon edges shorter than alpha do
        not shrink the interior), ``Mesh.Algorithm`` 5 (Delaunay) or 6 (Frontal-Delaunay)."""
        import gmsh

        gmsh.initialize(readConfigFiles=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.option.setNumber("Mesh.Algorithm", algorithm)
            gmsh.option.setNumber("Mesh.MeshSizeMax", alpha)
            gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
            gmsh.model.add("region")
            start = perf_counter()
            _gmsh_geometry(gmsh.model.geo, region, alpha)
            gmsh.model.geo.synchronize()
            gmsh.model.mesh.generate(2)
            tags, coordinates, _ = gmsh.model.mesh.getNodes()
            _, nodes = gmsh.model.mesh.getElementsByType(2)
            done = perf_counter()
        finally:
            gmsh.finalize()
        order = np.argsort(tags)
        faces = order[np.searchsorted(tags, nodes.reshape(-1, 3), sorter=order)]
        return Run(coordinates.reshape(-1, 3)[:, :2], faces.astype(np.int64), alpha,
                   peak_mb=peak_rss_mb(), times={"total": done - start})
    return run


def _gmsh_geometry(geo, region, size: float) -> None:
    """One plane surface per component: its exterior and hole rings as curve loops
    (``region.rings`` lists each component's exterior, then its holes)."""
    def loop(ring):
        points = [geo.addPoint(x, y, 0.0, size) for x, y in ring]
        lines = [geo.addLine(a, b) for a, b in zip(points, points[1:] + points[:1])]
        return geo.addCurveLoop(lines)

    rings = iter(region.rings)
    for polygon in region.geometry.geoms:
        geo.addPlaneSurface([loop(next(rings)) for _ in range(1 + len(polygon.interiors))])


PEERS = {peer.key: peer for peer in [
    Peer("pds", "pds_plugin mesh_region", _pds(conforming=True), ("pds_plugin",)),
    Peer("pds-1thread", "pds_plugin mesh_region, 1 thread", _pds(conforming=True),
         ("pds_plugin",), env={"PDS_THREADS": "1"}),
    Peer("pds-pure", "pds_plugin mesh_region, conforming=False", _pds(conforming=False),
         ("pds_plugin",)),
    Peer("scipy", "scipy PoissonDisk + Delaunay α", run_scipy, ("scipy",)),
    Peer("meshlab", "MeshLab Poisson-disk + 2D α", _meshlab_filtered(seeded=False),
         ("pymeshlab", "trimesh")),
    Peer("meshlab-seeded", "MeshLab Poisson-disk, boundary-seeded + 2D α",
         _meshlab_filtered(seeded=True), ("pymeshlab", "trimesh")),
    Peer("meshlab-alpha-shape", "MeshLab seeded + generate_alpha_shape", run_meshlab_alpha_shape,
         ("pymeshlab", "trimesh")),
    Peer("triangle-pq30", "Triangle pq30 (equal vertex count)", _triangle(30), ("triangle",)),
    Peer("triangle-pq33", "Triangle pq33 (equal vertex count)", _triangle(33), ("triangle",)),
    Peer("gmsh-delaunay", "gmsh Delaunay (5), size α", _gmsh(5), ("gmsh",)),
    Peer("gmsh-frontal", "gmsh Frontal-Delaunay (6), size α", _gmsh(6), ("gmsh",)),
]}
"""Every peer, in table order. pds_plugin runs first on each region: its vertex count is
the target the others are sized for. Its 1-thread twin shows what the kernels' threads give
(or cost, on a busy machine)."""
