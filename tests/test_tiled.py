"""mesh_tiled: the stitched sampling and complex are what the paper's construction makes
of the whole region, exactly, across the seams; and the same bytes on any executor."""

from __future__ import annotations

import itertools
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from multiprocessing import get_context
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree
from shapely.geometry import MultiPolygon, Point, Polygon, box

import pds_plugin as pds
from pds_plugin.errors import ArgumentError
from pds_plugin.tiled import HALO, Tiling, _canonical

PLATE = box(0, 0, 4, 2).difference(Point(2, 1).buffer(0.5))          # the hole on a tile corner
PARTS = MultiPolygon([box(0, 0, 3, 3).difference(box(1.2, 0.9, 1.8, 2.1)),  # a hole across a seam
                      Polygon([(3.4, 0), (5, 0), (5, 3), (3.4, 2.5)])])      # a second part
FRAME = box(-1.5, -1.5, 1.5, 1.5).difference(box(-0.55, -0.55, 0.55, 0.55))  # no region in the
CASES = [(PLATE, 0.06, (4, 2)), (PARTS, 0.07, (3, 3)), (box(0, 0, 1, 1), 0.05, (3, 2)),  # middle
         (FRAME, 0.1, (3, 3))]                                 # tile, which owns triangles


def _files(store: Path) -> dict:
    return {str(p.relative_to(store)): p.read_bytes() for p in sorted(store.rglob("*"))
            if p.is_file()}


@pytest.fixture(scope="module", params=range(len(CASES)), ids=["plate", "parts", "square", "frame"])
def case(request, tmp_path_factory):
    geometry, alpha, tiles = CASES[request.param]
    region = pds.Region.from_shapely(geometry)
    store = tmp_path_factory.mktemp("tiled")
    tiled = pds.mesh_tiled(region, alpha, tiles=tiles, store=store, seed=3)
    return region, alpha, tiled, tiled.to_mesh()


def test_stitched_sampling_is_separated_and_maximal(case):
    region, alpha, tiled, mesh = case
    distance = cKDTree(mesh.vertices).query(mesh.vertices, k=2)[0][:, 1]
    assert distance.min() >= alpha * (1 - 1e-12)              # every pair, seams included
    cert = mesh.certificate()                                   # the non-tiled certificate
    assert cert.coverage_gap <= 1 + 1e-9 and cert.ok, str(cert)
    assert cert.betti_mesh == region.betti


def test_seams_are_crossed(case):
    """The checks are not vacuous: samples of different tiles share triangles."""
    _, _, tiled, mesh = case
    tile_of = np.concatenate([np.full(len(tiled.tile(i, j)[0]), k)
                              for k, (i, j) in enumerate(tiled.tiling.tiles())])
    across = (tile_of[mesh.faces] != tile_of[mesh.faces[:, :1]]).any(axis=1)
    assert across.sum() > 20


def test_each_triangle_owned_by_one_tile(case):
    _, _, tiled, mesh = case
    per_tile = [tiled.tile(i, j)[3] for i, j in tiled.tiling.tiles()]
    faces = np.concatenate(per_tile)
    assert len(np.unique(np.sort(faces, axis=1), axis=0)) == len(faces) == len(mesh.faces)


def test_stitched_complex_is_the_non_tiled_complex(case):
    _, alpha, _, mesh = case
    whole = pds.solid_alpha_complex(mesh.vertices, alpha)
    assert np.array_equal(_canonical(whole), _canonical(mesh.faces))   # orientation too


def test_tiled_certificate_equals_the_whole_mesh_certificate(case):
    region, _, tiled, mesh = case
    tiles, whole = tiled.certificate(), mesh.certificate()
    assert tiles.ok and whole.ok
    assert (tiles.samples, tiles.triangles) == (whole.samples, whole.triangles)
    assert tiles.min_separation == whole.min_separation
    assert tiles.coverage_gap == pytest.approx(whole.coverage_gap, rel=1e-9)
    assert tiles.max_aspect_ratio == pytest.approx(whole.max_aspect_ratio, rel=1e-12)
    assert (tiles.min_angle, tiles.max_angle) == pytest.approx((whole.min_angle, whole.max_angle))
    assert tiles.area_ratio == pytest.approx(whole.area_ratio, rel=1e-9)
    assert tiles.betti_mesh == whole.betti_mesh == region.betti
    assert (tiles.isolated_samples, tiles.nonmanifold_vertices) == (0, 0)


def test_certificate_sees_a_broken_seam(tmp_path):
    """Drop the triangles of one tile: the tiled certificate notices (not a rubber stamp)."""
    region = pds.Region.from_shapely(PLATE)
    tiled = pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path)
    faces = tmp_path / "tiles" / "1_0_faces.npy"
    np.save(faces, np.load(faces)[:-5])
    cert = pds.TiledMesh(tmp_path).certificate()
    assert not cert.ok and cert.triangles == len(tiled.to_mesh().faces)


def test_phases_are_more_than_2_alpha_apart():
    tiling = Tiling(0.0, 0.0, 10.0, 7.0, 5, 4)
    alpha = 0.99 * min(tiling.width, tiling.height) / HALO
    for (a, b), (c, d) in itertools.combinations(tiling.tiles(), 2):
        if tiling.phase(a, b) == tiling.phase(c, d):
            p, q = tiling.box(a, b), tiling.box(c, d)
            gap = np.hypot(max(q[0] - p[2], p[0] - q[2], 0), max(q[1] - p[3], p[1] - q[3], 0))
            assert gap > HALO * alpha


def test_same_bytes_serial_threads_processes(tmp_path):
    region = pds.Region.from_shapely(PLATE)
    runs = {}
    with ThreadPoolExecutor(2) as threads, \
            ProcessPoolExecutor(2, mp_context=get_context("spawn")) as processes:
        for name, executor in (("serial", None), ("threads", threads), ("processes", processes)):
            tiled = pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path / name,
                                   executor=executor, seed=7)
            tiled.export(tmp_path / f"{name}.ply")
            runs[name] = _files(tmp_path / name), (tmp_path / f"{name}.ply").read_bytes()
    assert runs["serial"] == runs["threads"] == runs["processes"]
    other = pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path / "other", seed=8)
    assert not np.array_equal(other.to_mesh().vertices, tiled.to_mesh().vertices)


def test_same_bytes_on_dask(tmp_path):
    distributed = pytest.importorskip("distributed")
    region = pds.Region.from_shapely(PLATE)
    serial = pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path / "serial", seed=7)
    with distributed.Client(processes=False, n_workers=2, threads_per_worker=1,
                            dashboard_address=None) as client:
        pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path / "dask",
                       executor=client.get_executor(), seed=7)
    assert _files(tmp_path / "serial") == _files(tmp_path / "dask")
    assert serial.certificate(executor=None).ok


def test_resume_recomputes_only_what_is_missing(tmp_path):
    region = pds.Region.from_shapely(PLATE)
    pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path / "a")
    before = _files(tmp_path / "a")
    for name in ("samples/2_1_interior_points.npy", "tiles/0_1_faces.npy", "index.json"):
        (tmp_path / "a" / name).unlink()            # as if their tasks had been killed
    pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path / "a")
    assert _files(tmp_path / "a") == before
    with pytest.raises(ArgumentError, match="different tiled mesh"):
        pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path / "a", seed=1)


def test_export_streams_the_mesh(case, tmp_path):
    _, _, tiled, mesh = case
    tiled.export(tmp_path / "mesh.ply")
    read = trimesh.load(tmp_path / "mesh.ply", process=False)
    assert np.array_equal(read.vertices, mesh.vertices_3d)
    assert np.array_equal(read.faces, mesh.faces)


@pytest.mark.parametrize("options, message", [
    ({"tiles": (2, 2), "conforming": True}, "mesh_region"),
    ({"tiles": (2, 2), "graded": True}, "graded=True"),
    ({"tiles": (40, 2)}, "not wider than 2 alpha"),
    ({"tiles": (2, 2), "tile_size": 0.5}, "exactly one"),
    ({}, "exactly one"),
    ({"tile_size": -1.0}, "positive"),
    ({"tiles": (1, 1), "alpha": 1e-4}, "use at least 3 x 3 tiles"),
    ({"tiles": (2, 2), "alpha": "auto"}, "suggest_alpha"),
])
def test_refusals(tmp_path, options, message):
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    options = {"alpha": 0.1, **options}
    with pytest.raises(ArgumentError, match=message):
        pds.mesh_tiled(region, store=tmp_path, **options)


def test_store_must_be_new_or_a_tiled_mesh(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(ArgumentError, match="not empty"):
        pds.mesh_tiled(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.1, tiles=(2, 2),
                       store=tmp_path)
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_circumradius_ties_decided_as_the_non_tiled_complex():
    """At alpha equal to a triangle's own circumradius (and one ulp either side) the
    tile's complex keeps exactly the triangles the non-tiled complex keeps. (Computed
    naively, from another grid origin, one of these 30 cases differs.)"""
    from scipy.spatial import Delaunay

    from pds_plugin.tiled import _exact_complex

    rng = np.random.default_rng(5)
    points = rng.random((300, 2))
    low, high = points.min(axis=0).tolist(), points.max(axis=0).tolist()
    ids = np.arange(len(points))
    simplices = Delaunay(points).simplices
    a, b, c = (points[simplices[:, k]] for k in range(3))
    sides = [np.hypot(*(p - q).T) for p, q in ((a, b), (b, c), (c, a))]
    area = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]) / 2
    radius = sides[0] * sides[1] * sides[2] / (4 * area)
    checked = 0
    radius = np.sort(radius[radius < 0.08])       # within the points' spacing
    for r in radius[len(radius) // 4:: len(radius) // 12]:
        for alpha in (np.nextafter(r, 0), r, np.nextafter(r, 1)):
            whole = pds.solid_alpha_complex(points, alpha)
            tiles = _exact_complex(points, ids, float(alpha), low, high)
            assert np.array_equal(_canonical(whole), _canonical(tiles))
            checked += 1
    assert checked >= 30


def test_one_tile_and_a_relative_store(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    region = pds.Region.from_shapely(PLATE)
    tiled = pds.mesh_tiled(region, 0.1, tile_size=10.0, store="one")
    assert (tiled.tiling.nx, tiled.tiling.ny) == (1, 1) and tiled.store.is_absolute()
    mesh = tiled.to_mesh()
    assert tiled.certificate().ok and mesh.certificate().ok
    whole = pds.solid_alpha_complex(mesh.vertices, 0.1)
    assert np.array_equal(_canonical(whole), _canonical(mesh.faces))


def test_blocks_inside_tiles_keep_the_seams_exact(tmp_path, monkeypatch):
    """Tiles sampled and triangulated block by block (a task's scratch is one block's):
    the blocks' seams are as exact as the tiles', and the same bytes on threads."""
    import pds_plugin.tiled as tiled_module

    monkeypatch.setattr(tiled_module, "BLOCK_SAMPLES", 30)
    region = pds.Region.from_shapely(PARTS)
    tiled = pds.mesh_tiled(region, 0.07, tiles=(2, 2), store=tmp_path / "serial", seed=2)
    assert min(tiled._params["blocks"]) >= 2            # blocks meet inside every tile
    mesh = tiled.to_mesh()
    distance = cKDTree(mesh.vertices).query(mesh.vertices, k=2)[0][:, 1]
    assert distance.min() >= 0.07 * (1 - 1e-12)
    whole = pds.solid_alpha_complex(mesh.vertices, 0.07)
    assert np.array_equal(_canonical(whole), _canonical(mesh.faces))
    cert = mesh.certificate()
    assert cert.ok and cert.coverage_gap <= 1 + 1e-9 and cert.betti_mesh == region.betti
    assert tiled.certificate().ok
    with ThreadPoolExecutor(2) as threads:
        pds.mesh_tiled(region, 0.07, tiles=(2, 2), store=tmp_path / "threads", seed=2,
                       executor=threads)
    assert _files(tmp_path / "serial") == _files(tmp_path / "threads")


def _move_sample(store: Path, i: int, j: int, k: int, xy) -> None:
    """Move sample ``k`` of tile ``(i, j)``'s interior sweep to ``xy``, in its points
    file and its rim (as a bad sampler would have placed it)."""
    points_path = store / "samples" / f"{i}_{j}_interior_points.npy"
    rim_path = store / "samples" / f"{i}_{j}_interior_rim.npy"
    points, rim = np.load(points_path), np.load(rim_path)
    points[k] = xy
    rim[rim[:, 2] == k, :2] = xy
    np.save(points_path, points)
    np.save(rim_path, rim)


@pytest.fixture()
def plate_store(tmp_path):
    region = pds.Region.from_shapely(PLATE)
    tiled = pds.mesh_tiled(region, 0.1, tiles=(4, 2), store=tmp_path)
    interior = np.load(tmp_path / "samples" / "1_0_interior_points.npy")
    xmax = tiled.tiling.box(1, 0)[2]
    neighbour = np.load(tmp_path / "samples" / "2_0_interior_points.npy")
    return tmp_path, tiled, interior, xmax, neighbour


def test_tiled_certificate_sees_a_seam_too_close(plate_store):
    """Two samples of two tiles closer than alpha across their seam: the tile-by-tile
    separation sees it (each tile holds its neighbours' rim), as the whole mesh does."""
    store, tiled, interior, xmax, neighbour = plate_store
    k = int(np.argmax(interior[:, 0]))                  # the sample nearest the seam
    target = neighbour[np.argmin(np.hypot(*(neighbour - interior[k]).T))]
    _move_sample(store, 1, 0, k, target + [-0.4 * tiled.alpha, 0.0])
    cert, whole = pds.TiledMesh(store).certificate(), pds.TiledMesh(store).to_mesh().certificate()
    assert cert.min_separation == pytest.approx(0.4) == whole.min_separation
    assert not cert.ok


def test_tiled_certificate_sees_a_hole_at_a_seam(plate_store):
    """A sample next to a seam taken out of the region (5 alpha below it): the hole it
    leaves, across the seam, is seen tile by tile. (Its place is at least the distance
    to the nearest other sample from every sample; the certificate recomputes the
    complex, so the stored triangles, still joined to the moved sample, do not hide it.)"""
    store, tiled, interior, xmax, _ = plate_store
    k = int(np.argmax(interior[:, 0] - 10 * interior[:, 1]))   # low and at the seam
    hole = interior[k].copy()
    _move_sample(store, 1, 0, k, [hole[0], -0.5])
    cert = pds.TiledMesh(store).certificate()
    others = pds.TiledMesh(store).to_mesh().vertices
    assert xmax - hole[0] < tiled.alpha                   # the hole's disc crosses the seam
    assert cert.coverage_gap >= cKDTree(others).query(hole)[0] / tiled.alpha > 1
    assert not cert.ok
