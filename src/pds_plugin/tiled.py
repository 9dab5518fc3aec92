"""Tiled meshing: one region cut into tiles, sampled phase by phase, stitched exactly.

:func:`mesh_tiled` meshes a region too large for one process (or worth spreading over
workers) as a grid of tiles, each task holding one tile and a halo around it:

1. **Phases.** Tiles are coloured by the parity of their column and row, four colours;
   tiles of one colour are at least one tile apart, and a tile is more than ``2 alpha``
   wide, so tiles of one phase never interact and run at once.
2. **Sampling** is done in three sweeps, corners, boundary and interior, as the
   uniform sampler does them (:func:`pds_plugin.poisson_disc`), each sweep over the four
   phases. A task samples its own closed tile with the sampler's own kernels, after
   placing as fixed samples the halo: every sample already made within ``2 alpha`` of
   its tile (its own earlier sweeps, its neighbours' earlier sweeps and phases). A new
   sample is refused within alpha of any sample, and the tile is covered to the
   sampler's resolution, so the stitched sampling is alpha-separated and maximal across
   the seams.
3. **Global ids** follow the tiles row by row, and in a tile the sweeps in order.
4. **Complex.** Each triangle belongs to the tile holding its circumcentre (the tiles
   of the first and last rows and columns reach to infinity). A tile computes the
   complex of its samples and its neighbours' within ``2 alpha``, which holds every
   point the empty-circle test of an owned triangle can need, with the points ordered
   by global id (the tie-break of :func:`pds_plugin.solid_alpha_complex` depends only on
   that order), at a radius a little above alpha; then it keeps the triangles whose
   circumradius test, evaluated exactly as the non-tiled complex of all the samples
   evaluates it (the same floating-point expression from the same vertex), passes. The
   stitched triangles are therefore the non-tiled complex of the stitched samples,
   triangle for triangle.
5. **Blocks.** Inside a task, the interior sweep and the complex go block by block
   (:data:`BLOCK_SAMPLES`), each block to its tile as a tile to the region (its own
   2 alpha halo, the blocks before it fixed), so a task's scratch is one block's and its
   memory the tile's samples and triangles plus that.

Everything lives in the ``store`` folder, one file per array (``.npy``: the same inputs
give the same bytes), and the driver keeps only the tile index (counts and id offsets).
Tasks are plain functions of small arguments, so any ``concurrent.futures`` executor
runs them (a process pool, ``dask.distributed``'s ``Client.get_executor()``); on a
cluster the store must be on a file system every worker sees. A rerun with the same
arguments and store skips the files already written (a killed task's file is never
half written: it is written under a temporary name and renamed).

Supported: uniform, non-conforming meshes (the paper's construction). Conforming
boundaries and graded fields need the boundary sampled along whole rings and a
radius field known across tiles; both are refused with an :class:`ArgumentError`
naming :func:`pds_plugin.mesh_region` (docs/tiled.md).
"""

from __future__ import annotations

import json
import math
import os
import secrets
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import MultiPolygon, box

from . import _sampling_kernels as kern
from ._atomic import atomic_path
from ._checks import check_alpha, check_positive, check_seed
from .analysis.certificate import Certificate
from .complex import solid_alpha_complex
from .errors import ArgumentError, ArgumentTypeError
from .region import Region, require_region, turning_angles
from .boundary_sampling import RESOLUTION
from .sampling import _MAX_GRID_CELLS, _Sampler

__all__ = ["mesh_tiled", "TiledMesh", "TiledCertificate", "Tiling"]

STAGES = ("corners", "boundary", "interior")
"""The sampling sweeps, in order; each runs over the four phases."""

HALO = 2.0
"""Halo width / alpha: the samples a task sees around its tile."""

BLOCK_SAMPLES = 2**13
"""About how many samples a task's scratch covers at once: a tile's interior is sampled,
and its complex computed, block by block (a grid of equal blocks over the tile, each
with its own 2 alpha halo), so a task's memory is its tile's samples and triangles plus
the scratch of one block (docs/tiled.md, "Memory per worker")."""

_RELAXED = 1e-9         # the tile's complex is computed at alpha (1 + this), then filtered
_FORMAT = 2             # the store's layout version (2: blocks)


@dataclass(frozen=True)
class Tiling:
    """A grid of ``nx`` by ``ny`` equal tiles over the box ``(x0, y0, x1, y1)``.

    Tile ``(i, j)`` is column ``i``, row ``j``; its closed box is :meth:`box`. The
    tiles of the first and last columns and rows own everything beyond the box too
    (:meth:`owner`), so every point of the plane has exactly one owner.

    Examples
    --------
    >>> tiling = Tiling(0.0, 0.0, 4.0, 2.0, 4, 2)
    >>> tiling.box(1, 0), tiling.phase(1, 0), tiling.owner([[1.5, 5.0], [-3.0, 0.2]]).tolist()
    ((1.0, 0.0, 2.0, 1.0), 1, [[1, 1], [0, 0]])
    """

    x0: float
    y0: float
    x1: float
    y1: float
    nx: int
    ny: int

    @property
    def width(self) -> float:
        """The tiles' width."""
        return (self.x1 - self.x0) / self.nx

    @property
    def height(self) -> float:
        """The tiles' height."""
        return (self.y1 - self.y0) / self.ny

    def _edge_x(self, i: int) -> float:
        return self.x1 if i == self.nx else self.x0 + i * self.width

    def _edge_y(self, j: int) -> float:
        return self.y1 if j == self.ny else self.y0 + j * self.height

    def box(self, i: int, j: int) -> tuple[float, float, float, float]:
        """The closed box of tile ``(i, j)``: ``(xmin, ymin, xmax, ymax)``."""
        return self._edge_x(i), self._edge_y(j), self._edge_x(i + 1), self._edge_y(j + 1)

    def reach(self, i: int, j: int) -> tuple[float, float, float, float]:
        """The box of tile ``(i, j)`` as it owns triangles: infinite on outer sides."""
        xmin, ymin, xmax, ymax = self.box(i, j)
        return (-math.inf if i == 0 else xmin, -math.inf if j == 0 else ymin,
                math.inf if i == self.nx - 1 else xmax, math.inf if j == self.ny - 1 else ymax)

    def phase(self, i: int, j: int) -> int:
        """The phase (colour) 0-3 of tile ``(i, j)``: the parities of its column and row."""
        return i % 2 + 2 * (j % 2)

    def owner(self, xy) -> np.ndarray:
        """(n, 2) the tile ``(i, j)`` owning each point of ``xy``."""
        xy = np.asarray(xy, dtype=float).reshape(-1, 2)
        i = np.clip(np.floor((xy[:, 0] - self.x0) / self.width), 0, self.nx - 1)
        j = np.clip(np.floor((xy[:, 1] - self.y0) / self.height), 0, self.ny - 1)
        return np.column_stack([i, j]).astype(np.int64)

    def tiles(self):
        """Every tile ``(i, j)``, row by row: the order of the global ids."""
        return [(i, j) for j in range(self.ny) for i in range(self.nx)]

    def neighbours(self, i: int, j: int):
        """The tiles of the 3 x 3 block around ``(i, j)`` (itself included), row by row."""
        return [(a, b) for b in range(j - 1, j + 2) for a in range(i - 1, i + 2)
                if 0 <= a < self.nx and 0 <= b < self.ny]


def mesh_tiled(region: Region, alpha: float, *, tiles=None, tile_size=None, store,
               executor=None, seed: int = 0, conforming: bool = False, graded: bool = False,
               feature_angle: float = 30.0) -> TiledMesh:
    """Mesh ``region`` tile by tile: a maximal Poisson disc sampling of radius ``alpha``
    and its solid alpha-complex, exact across the seams, written to ``store``.

    The result is the same kind of mesh as ``mesh_region(region, alpha,
    conforming=False)`` (the paper's construction): every pair of samples at least
    alpha apart, every point of the region within alpha of one, and the triangles
    exactly the solid alpha-complex of all the samples. The samples themselves differ
    from mesh_region's (the random choices are drawn tile by tile). See the module
    documentation and docs/tiled.md for how.

    Parameters
    ----------
    region : Region
    alpha : float
    tiles : (int, int), optional
        Columns and rows of tiles over the region's bounding box.
    tile_size : float or (float, float), optional
        The largest tile width and height instead; exactly one of ``tiles`` and
        ``tile_size`` is given. Tiles must be more than ``2 alpha`` wide and high.
    store : str or os.PathLike
        The folder the tiles are written to (created; on a cluster, one every worker
        reads and writes). A store holding the same mesh is resumed: finished tiles
        are kept.
    executor : concurrent.futures.Executor, optional
        Runs the tile tasks, e.g. ``dask.distributed.Client(...).get_executor()`` or a
        process pool; by default they run here, one after the other. The result is the
        same bytes either way.
    seed : int
        Seed of the random choices; each tile draws from its own generator seeded by
        ``(seed, sweep, column, row)``.
    conforming, graded : bool
        Not supported across tiles yet: ``True`` raises an :class:`ArgumentError`
        naming what to use instead (the default, False, is the paper's construction;
        ``mesh_region`` defaults to conforming meshes).
    feature_angle : float
        Boundary vertices turning by at least this many degrees are sampled first, as
        in :func:`pds_plugin.poisson_disc`.

    Returns
    -------
    TiledMesh

    Raises
    ------
    ArgumentTypeError, ArgumentError
        If ``region`` is not a Region, ``alpha`` not a positive number, the tiling not
        given exactly once or its tiles not wider than ``2 alpha``, ``conforming`` or
        ``graded`` asked for, or ``store`` holds a different mesh.

    Examples
    --------
    >>> import tempfile
    >>> from shapely.geometry import Point, box
    >>> import pds_plugin as pds
    >>> plate = pds.Region.from_shapely(box(0, 0, 4, 2).difference(Point(2, 1).buffer(0.5)))
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     tiled = pds.mesh_tiled(plate, 0.1, tiles=(4, 2), store=folder)
    ...     cert = tiled.certificate()
    ...     mesh = tiled.to_mesh()
    >>> cert.ok, cert.betti_mesh, len(mesh.vertices) == cert.samples
    (True, (1, 1), True)
    >>> faces = pds.solid_alpha_complex(mesh.vertices, 0.1)       # the non-tiled complex
    >>> def triangles(f):
    ...     return sorted(map(tuple, np.sort(f, axis=1)))
    >>> triangles(faces) == triangles(mesh.faces)
    True
    """
    require_region(region, "mesh_tiled")
    if isinstance(alpha, str):
        raise ArgumentError(f"mesh_tiled takes alpha as a number, got {alpha!r}; choose it "
                            "with pds.suggest_alpha(region) (alpha='auto' meshes the region "
                            "more than once, which tiles do not)")
    alpha = check_alpha(alpha)
    seed = check_seed(seed)
    if graded:
        raise ArgumentError("mesh_tiled makes uniform meshes only: a graded radius field is "
                            "not stitched across tiles yet; use mesh_region(region, alpha, "
                            "graded=True) for a region that fits one process")
    if conforming:
        raise ArgumentError("mesh_tiled makes the paper's (non-conforming) mesh only: "
                            "conforming boundaries are sampled along whole rings and are not "
                            "split across tiles yet; leave conforming=False, or use "
                            "mesh_region(region, alpha) (conforming) for a region that fits "
                            "one process")
    feature_angle = check_positive(feature_angle, "feature_angle")
    tiling = _tiling(region, alpha, tiles, tile_size)
    store = Path(os.path.abspath(store))     # the workers may run elsewhere
    params = {"format": _FORMAT, "alpha": alpha, "seed": seed, "feature_angle": feature_angle,
              "tiling": [tiling.x0, tiling.y0, tiling.x1, tiling.y1, tiling.nx, tiling.ny],
              "region": shapely.to_wkb(region.geometry, hex=True),
              "frame": region.frame.tolist(), "blocks": list(_blocks_per_tile(tiling, alpha))}
    _open_store(store, params)
    run = secrets.token_hex(8)     # keeps an executor that caches by arguments honest
    shapely.prepare(region.geometry)
    near = {}
    for i, j in tiling.tiles():
        xmin, ymin, xmax, ymax = tiling.box(i, j)
        grown = box(xmin - HALO * alpha, ymin - HALO * alpha, xmax + HALO * alpha,
                    ymax + HALO * alpha)
        # a tile within 2 alpha of the region may own triangles (a circumcentre lies
        # outside the region, up to alpha from it) even if it samples nothing
        if region.geometry.intersects(grown):
            near[i, j] = shapely.to_wkb(region.geometry.intersection(grown))
    counts = {}
    for stage in range(len(STAGES)):
        for phase in range(4):
            specs = [_Task(str(store), tiling, i, j, stage, alpha, seed, feature_angle,
                           near[i, j], run, tuple(t for t in tiling.neighbours(i, j) if t in near),
                           tuple(params["blocks"]))
                     for (i, j) in near if tiling.phase(i, j) == phase]
            for spec, made in zip(specs, _run(_sample_task, specs, executor)):
                counts[spec.i, spec.j, stage] = made
    index = _index(tiling, counts, near)
    with atomic_path(store / "index.json") as partial:
        partial.write_text(json.dumps(index), encoding="utf-8")
    specs = [_Task(str(store), tiling, i, j, -1, alpha, seed, feature_angle, near[i, j], run,
                   blocks=tuple(params["blocks"])) for (i, j) in near]
    list(_run(_complex_task, specs, executor))
    return TiledMesh(store)


def _tiling(region: Region, alpha: float, tiles, tile_size) -> Tiling:
    """The tiling asked for, checked: tiles more than 2 alpha wide and high."""
    if (tiles is None) == (tile_size is None):
        raise ArgumentError("give exactly one of tiles=(columns, rows) and tile_size")
    xmin, ymin, xmax, ymax = region.bounds
    if tiles is not None:
        try:
            nx, ny = (int(n) for n in tiles)
        except (TypeError, ValueError):
            raise ArgumentTypeError(f"tiles must be two integers (columns, rows), got "
                                    f"{tiles!r}") from None
        if nx < 1 or ny < 1 or (nx, ny) != tuple(tiles):
            raise ArgumentError(f"tiles must be two positive integers, got {tiles!r}")
    else:
        try:
            size = np.broadcast_to(np.asarray(tile_size, dtype=float), (2,))
        except (TypeError, ValueError):
            raise ArgumentTypeError(f"tile_size must be a number or two, got "
                                    f"{tile_size!r}") from None
        if not (np.isfinite(size).all() and (size > 0).all()):
            raise ArgumentError(f"tile_size must be positive, got {tile_size!r}")
        nx, ny = (max(1, math.ceil(span / s)) for span, s in zip((xmax - xmin, ymax - ymin), size))
    tiling = Tiling(float(xmin), float(ymin), float(xmax), float(ymax), nx, ny)
    narrowest = min(tiling.width if nx > 1 else math.inf, tiling.height if ny > 1 else math.inf)
    if narrowest <= HALO * alpha * (1 + 1e-6):
        most = [max(1, math.ceil(span / (HALO * alpha * (1 + 1e-6))) - 1)
                for span in (xmax - xmin, ymax - ymin)]
        raise ArgumentError(f"tiles of {tiling.width:.6g} x {tiling.height:.6g} are not wider "
                            f"than 2 alpha = {2 * alpha:.6g}: tiles of one phase would "
                            f"interact; use at most {most[0]} x {most[1]} tiles (or a larger "
                            "tile_size)")
    side = alpha / math.sqrt(2)                  # the sampler's cells, as in _Sampler
    cells = (((tiling.width + 2 * HALO * alpha) / side + 3)
             * ((tiling.height + 2 * HALO * alpha) / side + 3))
    if cells > _MAX_GRID_CELLS:
        need = [math.ceil(span / (math.sqrt(_MAX_GRID_CELLS) * side * 0.9))
                for span in (xmax - xmin, ymax - ymin)]
        raise ArgumentError(f"tiles of {tiling.width:.6g} x {tiling.height:.6g} hold about "
                            f"{0.7 * tiling.width * tiling.height / alpha ** 2:.3g} samples "
                            f"each at alpha={alpha:.6g}, more than one "
                            f"task's sampling grid allows; use at least {need[0]} x {need[1]} "
                            "tiles (or a smaller tile_size)")
    return tiling


def _blocks_per_tile(tiling: Tiling, alpha: float) -> tuple[int, int]:
    """Columns and rows of blocks in a tile: blocks of at most about
    :data:`BLOCK_SAMPLES` samples (at the uniform sampler's density, 0.7 per alpha
    squared), and at least 8 alpha wide and high."""
    side = alpha * math.sqrt(BLOCK_SAMPLES / 0.7)
    return tuple(max(1, min(math.ceil(span / side), math.floor(span / (8 * alpha))))
                 for span in (tiling.width, tiling.height))


def _block_reach(blocks: Tiling, a: int, b: int, reach) -> tuple:
    """The part of the plane block ``(a, b)`` owns within the tile's ``reach``: its box,
    infinite on the sides where it meets an infinite side of the reach."""
    xmin, ymin, xmax, ymax = blocks.box(a, b)
    return (reach[0] if a == 0 else xmin, reach[1] if b == 0 else ymin,
            reach[2] if a == blocks.nx - 1 else xmax, reach[3] if b == blocks.ny - 1 else ymax)


def _open_store(store: Path, params: dict) -> None:
    """Create the store, or check that the one there holds the same mesh (a resume)."""
    record = store / "params.json"
    if record.exists():
        if json.loads(record.read_text(encoding="utf-8")) != params:
            raise ArgumentError(f"the store {store} holds a different tiled mesh (other region, "
                                "alpha, seed or tiling); give a new folder or remove it")
        return
    if store.exists() and any(store.iterdir()):
        raise ArgumentError(f"the store {store} is a folder that is not empty and holds no "
                            "tiled mesh; give a new or empty folder")
    (store / "samples").mkdir(parents=True, exist_ok=True)
    (store / "tiles").mkdir(exist_ok=True)
    with atomic_path(record) as partial:
        partial.write_text(json.dumps(params), encoding="utf-8")


def _run(function, specs, executor):
    """``function`` over ``specs``, in order: here, or on ``executor``."""
    if executor is None:
        return [function(spec) for spec in specs]
    futures = [executor.submit(function, spec) for spec in specs]
    return [future.result() for future in futures]


def _index(tiling: Tiling, counts: dict, near: dict) -> dict:
    """The tile index: samples per tile and sweep, each tile's first global id, and the
    bounding box of all samples (the grid of the non-tiled complex)."""
    tiles, first, low, high = {}, 0, [math.inf, math.inf], [-math.inf, -math.inf]
    for i, j in tiling.tiles():
        if (i, j) not in near:
            continue
        made = [counts[i, j, stage] for stage in range(len(STAGES))]
        tiles[f"{i},{j}"] = {"first": first, "counts": [m["count"] for m in made]}
        first += sum(m["count"] for m in made)
        for m in made:
            if m["count"]:
                low = [min(a, b) for a, b in zip(low, m["low"])]
                high = [max(a, b) for a, b in zip(high, m["high"])]
    return {"tiles": tiles, "samples": first, "low": low, "high": high}


@dataclass(frozen=True)
class _Task:
    """One tile's task: everything it needs, small enough to ship to a worker."""

    store: str
    tiling: Tiling
    i: int
    j: int
    stage: int
    alpha: float
    seed: int
    feature_angle: float
    near: bytes         # WKB of the region within 2 alpha of the tile
    run: str
    neighbours: tuple = ()  # the tiles of the 3 x 3 block around it that have a task
    blocks: tuple = (1, 1)  # columns and rows of blocks in the tile (BLOCK_SAMPLES)

    def block_grid(self) -> Tiling:
        """The blocks of the tile, as a tiling of its box."""
        return Tiling(*self.tiling.box(self.i, self.j), *self.blocks)


def _stage_path(store, i, j, stage, what="points") -> str:
    return os.path.join(store, "samples", f"{i}_{j}_{STAGES[stage]}_{what}.npy")


def _save(path: Path, array) -> None:
    with atomic_path(path) as partial, open(partial, "wb") as file:
        np.save(file, np.ascontiguousarray(array), allow_pickle=False)


def _distance_to_box(xy, rect) -> np.ndarray:
    """Distance of each point to the closed box ``rect`` (its sides may be infinite)."""
    xmin, ymin, xmax, ymax = rect
    with np.errstate(invalid="ignore"):
        dx = np.maximum(np.maximum(xmin - xy[:, 0], xy[:, 0] - xmax), 0.0)
        dy = np.maximum(np.maximum(ymin - xy[:, 1], xy[:, 1] - ymax), 0.0)
    return np.hypot(dx, dy)


def _rim(xy, rect, width) -> np.ndarray:
    """Indices of the points of a tile within ``width`` of its box's sides."""
    xmin, ymin, xmax, ymax = rect
    inner = ((xy[:, 0] >= xmin + width) & (xy[:, 0] <= xmax - width)
             & (xy[:, 1] >= ymin + width) & (xy[:, 1] <= ymax - width))
    return np.flatnonzero(~inner)


def _halo(task: _Task) -> np.ndarray:
    """The samples fixed before this task within 2 alpha of its tile: its own earlier
    sweeps whole, its neighbours' rims from earlier sweeps and, in this sweep, earlier
    phases; in a fixed order."""
    tiling, here = task.tiling, (task.i, task.j)
    parts = []
    for a, b in tiling.neighbours(task.i, task.j):
        for stage in range(task.stage + 1):
            if stage == task.stage and tiling.phase(a, b) >= tiling.phase(*here):
                continue
            if (a, b) not in task.neighbours:          # a tile with no region in it
                continue
            parts.append(np.load(_stage_path(task.store, a, b, stage)) if (a, b) == here
                         else np.load(_stage_path(task.store, a, b, stage, "rim"))[:, :2])
    xy = np.concatenate(parts) if parts else np.empty((0, 2))
    return xy[_distance_to_box(xy, tiling.box(task.i, task.j)) <= HALO * task.alpha]


def _sample_task(task: _Task) -> dict:
    """Run one sweep of the sampler on one tile, its halo fixed; write its new samples
    and their rim. Returns their count and bounding box."""
    path = _stage_path(task.store, task.i, task.j, task.stage)
    if not os.path.exists(path):
        new = _sample_tile(task)
        rim = _rim(new, task.tiling.box(task.i, task.j), HALO * task.alpha)
        # the rim: x, y and the index in the sweep's samples (exact as a float)
        _save(_stage_path(task.store, task.i, task.j, task.stage, "rim"),
              np.column_stack([new[rim], rim.astype(float)]))
        _save(path, new)              # last: its presence says the sweep is done
    new = np.load(path)
    if not len(new):
        return {"count": 0}
    return {"count": len(new), "low": new.min(axis=0).tolist(), "high": new.max(axis=0).tolist()}


def _sample_tile(task: _Task) -> np.ndarray:
    """The new samples of one sweep in one tile, by the uniform sampler's kernels."""
    alpha, rect = task.alpha, task.tiling.box(task.i, task.j)
    near = shapely.from_wkb(task.near)
    inside = _polygons(shapely.intersection(near, box(*rect)))
    if inside is None:
        return np.empty((0, 2))
    halo = _halo(task)
    rng = np.random.default_rng([task.seed, task.stage, task.i, task.j])
    stage = STAGES[task.stage]
    if stage == "interior":
        return _sample_interior(task, inside, halo, rng)
    sampler = _fixed_sampler(inside, rect, halo, alpha)
    fixed = sampler.count
    if stage == "corners":
        sampler._insert(_corners(near, rect, task.feature_angle))
    else:
        start, direction, length = _boundary_pieces(near, rect, sampler.s)
        order = rng.permutation(len(start))
        u = rng.random(len(start))
        sampler._reserve(len(start))
        sampler.count = kern.sample_boundary_pieces(
            start, direction, length, order, u, sampler.grid, sampler.nxt, sampler.covered,
            sampler.points, sampler.count, alpha, RESOLUTION * alpha, sampler.x0,
            sampler.y0, sampler.s, sampler.vis)
    return sampler.points[fixed:sampler.count].copy()


def _fixed_sampler(inside, rect, fixed, alpha: float) -> _Sampler:
    """The uniform sampler's state over ``inside`` (polygons in the box ``rect``), its
    grid widened by the halo, the samples ``fixed`` placed (and what they cover marked)."""
    reach = HALO * alpha * (1 + 1e-9)
    sampler = _Sampler(Region(inside, np.eye(4)), alpha,
                       bounds=(rect[0] - reach, rect[1] - reach, rect[2] + reach, rect[3] + reach))
    sampler._reserve(len(fixed))
    kern.place_all(np.ascontiguousarray(fixed), sampler.grid, sampler.nxt, sampler.covered,
                   sampler.points, 0, alpha, sampler.x0, sampler.y0, sampler.s, sampler.vis)
    sampler.count = len(fixed)
    return sampler


def _sample_interior(task: _Task, inside, halo, rng) -> np.ndarray:
    """The interior sweep of a tile, block by block (row by row): each block's sampler
    holds the block and its halo (the tile's halo and the blocks sampled before it,
    within 2 alpha), so the scratch is one block's; the tile's samples are the blocks'
    in order."""
    alpha, blocks = task.alpha, task.block_grid()
    made = []
    for a, b in blocks.tiles():
        rect = blocks.box(a, b)
        part = inside if blocks.nx * blocks.ny == 1 else \
            _polygons(shapely.intersection(inside, box(*rect)))
        if part is None:
            continue
        fixed = [xy[_distance_to_box(xy, rect) <= HALO * alpha] for xy in (halo, *made)]
        fixed = np.concatenate(fixed)
        sampler = _fixed_sampler(part, rect, fixed, alpha)
        sampler.add_interior(rng)
        made.append(sampler.points[len(fixed):sampler.count].copy())
        del sampler, fixed
    return np.concatenate(made) if made else np.empty((0, 2))


def _polygons(geometry) -> MultiPolygon | None:
    """The polygons of a shapely result with area, as a MultiPolygon; None if none."""
    parts = [g for g in shapely.get_parts(geometry) if g.geom_type in ("Polygon", "MultiPolygon")]
    polygons = [p for g in parts for p in shapely.get_parts(g) if p.area > 0]
    return MultiPolygon(polygons) if polygons else None


def _corners(near, rect, feature_angle) -> np.ndarray:
    """The region's vertices in the closed tile turning by at least ``feature_angle``,
    sharpest first (the uniform sampler's first sweep, restricted to the tile). ``near``
    is the region within 2 alpha of the tile, so every vertex in the tile keeps both its
    edges' directions."""
    corners, turns = [np.empty((0, 2))], [np.empty(0)]
    for polygon in shapely.get_parts(near):
        if polygon.geom_type != "Polygon":
            continue
        for ring in (polygon.exterior, *polygon.interiors):
            xy = shapely.get_coordinates(ring)[:-1]
            xy = xy[np.any(xy != np.roll(xy, 1, axis=0), axis=1)]
            if len(xy) < 3:
                continue
            turn = np.abs(turning_angles(xy))
            keep = (turn >= np.radians(feature_angle)) & (_distance_to_box(xy, rect) == 0)
            corners.append(xy[keep])
            turns.append(turn[keep])
    corners, turns = np.concatenate(corners), np.concatenate(turns)
    return np.ascontiguousarray(corners[np.argsort(-turns, kind="stable")])


def _boundary_pieces(near, rect, max_length):
    """The region's boundary within the closed tile, cut into straight pieces no longer
    than ``max_length`` as :meth:`Region.boundary_pieces` cuts it."""
    lines = shapely.intersection(near.boundary, box(*rect))
    segments = []
    for line in shapely.get_parts(lines):
        if line.geom_type not in ("LineString", "LinearRing", "MultiLineString"):
            continue
        for part in shapely.get_parts(line):
            xy = shapely.get_coordinates(part)
            if len(xy) >= 2:
                segments.append(np.stack([xy[:-1], xy[1:]], axis=1))
    if not segments:
        return np.empty((0, 2)), np.empty((0, 2)), np.empty(0)
    seg = np.concatenate(segments)
    vec = seg[:, 1] - seg[:, 0]
    seg_len = np.hypot(vec[:, 0], vec[:, 1])
    seg, vec, seg_len = seg[seg_len > 0], vec[seg_len > 0], seg_len[seg_len > 0]
    count = np.maximum(np.ceil(seg_len / max_length), 1).astype(np.int64)
    owner = np.repeat(np.arange(len(seg)), count)
    step = np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count)
    start = seg[owner, 0] + (step / count[owner])[:, None] * vec[owner]
    return (np.ascontiguousarray(start), np.ascontiguousarray(vec[owner] / seg_len[owner, None]),
            np.ascontiguousarray(seg_len[owner] / count[owner]))


def _index_of(store) -> dict:
    return json.loads((Path(store) / "index.json").read_text(encoding="utf-8"))


def _tile_samples(store, index: dict, i: int, j: int):
    """A tile's samples in global id order, its first id and each sweep's count."""
    record = index["tiles"].get(f"{i},{j}")
    if record is None:
        return np.empty((0, 2)), 0, [0] * len(STAGES)
    parts = [np.load(_stage_path(store, i, j, stage)) for stage in range(len(STAGES))]
    return np.concatenate(parts), record["first"], record["counts"]


def _gathered(task: _Task, index: dict):
    """The tile's own samples and its neighbours' within 2 alpha of the part of the
    plane it owns, sorted by global id: (points, ids, own)."""
    tiling = task.tiling
    reach = tiling.reach(task.i, task.j)
    own_xy, first, _ = _tile_samples(task.store, index, task.i, task.j)
    points, ids = [own_xy], [first + np.arange(len(own_xy))]
    for a, b in tiling.neighbours(task.i, task.j):
        record = index["tiles"].get(f"{a},{b}")
        if (a, b) == (task.i, task.j) or record is None:
            continue
        start = record["first"]
        for stage, count in enumerate(record["counts"]):
            rim = np.load(_stage_path(task.store, a, b, stage, "rim"))
            xy, rim = np.ascontiguousarray(rim[:, :2]), rim[:, 2].astype(np.int64)
            near = _distance_to_box(xy, reach) <= HALO * task.alpha
            points.append(xy[near])
            ids.append(start + rim[near])
            start += count
    points, ids = np.concatenate(points), np.concatenate(ids)
    order = np.argsort(ids, kind="stable")
    own = (ids[order] >= first) & (ids[order] < first + len(own_xy))
    return np.ascontiguousarray(points[order]), ids[order], own


def _exact_complex(points, ids, alpha: float, low, high) -> np.ndarray:
    """The solid alpha-complex of ``points`` (sorted by global id ``ids``) as the
    non-tiled :func:`pds_plugin.solid_alpha_complex` of all the samples decides it.

    The empty-circle test is exact, and its ties are broken by the points' order, which
    is the global ids' here. The one floating-point decision, circumradius <= alpha, is
    evaluated by the complex's kernel from the triangle's first vertex in the order of
    the kernel's grid of cells of side alpha from the corner ``low`` of all the samples
    (cell row by row, then index). The complex is computed at a radius a little above
    alpha and that decision redone here, from the same vertex, by the same expression."""
    faces = solid_alpha_complex(points, alpha * (1 + _RELAXED))
    if not len(faces):
        return faces
    h = alpha
    nx = int((high[0] - low[0]) / h) + 1
    ny = int((high[1] - low[1]) / h) + 1
    cell = (np.minimum(((points[:, 1] - low[1]) / h).astype(np.int64), ny - 1) * nx
            + np.minimum(((points[:, 0] - low[0]) / h).astype(np.int64), nx - 1))
    rank = np.empty(len(points), np.int64)
    rank[np.argsort(cell, kind="stable")] = np.arange(len(points))     # ids ascend already
    by_rank = np.take_along_axis(faces, np.argsort(rank[faces], axis=1), axis=1)
    corner = points[by_rank]                     # (M, 3, 2): the kernel's i, j, k
    bx, by = corner[:, 1, 0] - corner[:, 0, 0], corner[:, 1, 1] - corner[:, 0, 1]
    cx, cy = corner[:, 2, 0] - corner[:, 0, 0], corner[:, 2, 1] - corner[:, 0, 1]
    cross = bx * cy - by * cx
    b2 = bx * bx + by * by
    c2 = cx * cx + cy * cy
    d2 = (cx - bx) * (cx - bx) + (cy - by) * (cy - by)
    alpha2 = alpha * alpha
    keep = ~((cross == 0.0) | (b2 * c2 * d2 > 4.0 * alpha2 * cross * cross))
    return faces[keep]


def _circumcentres(points, faces) -> np.ndarray:
    """(m, 2) the circumcentres of ``faces``, computed from their vertices in global id
    order (the same numbers in every tile, so every tile finds the same owner)."""
    corner = points[np.sort(faces, axis=1)]
    a, b, c = corner[:, 0], corner[:, 1], corner[:, 2]
    bx, by, cx, cy = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1], c[:, 0] - a[:, 0], c[:, 1] - a[:, 1]
    cross = 2.0 * (bx * cy - by * cx)
    ux = a[:, 0] + (cy * (bx * bx + by * by) - by * (cx * cx + cy * cy)) / cross
    uy = a[:, 1] + (bx * (cx * cx + cy * cy) - cx * (bx * bx + by * by)) / cross
    return np.column_stack([ux, uy])


def _canonical(faces, sort: bool = True) -> np.ndarray:
    """Faces rotated to start at their smallest id (orientation kept), and the rows
    sorted unless ``sort`` is False."""
    faces = np.asarray(faces, np.int64).reshape(-1, 3)
    shift = np.argmin(faces, axis=1)
    faces = np.take_along_axis(faces, (shift[:, None] + np.arange(3)) % 3, axis=1)
    return faces[np.lexsort(faces.T[::-1])] if sort else faces


def _faces_path(store, i, j) -> str:
    return os.path.join(store, "tiles", f"{i}_{j}_faces.npy")


def _complex_task(task: _Task) -> int:
    """Write the triangles tile ``(i, j)`` owns, in global ids; return their count.

    The tile's part of the plane is done block by block (the blocks of its interior
    sweep): each block's complex is computed on the points within 2 alpha of the part
    the block owns, and keeps the triangles whose circumcentre the tile and the block
    own."""
    path = _faces_path(task.store, task.i, task.j)
    if not os.path.exists(path):
        index = _index_of(task.store)
        points, ids, _ = _gathered(task, index)
        reach, blocks = task.tiling.reach(task.i, task.j), task.block_grid()
        parts = []
        for a, b in blocks.tiles():
            near = np.flatnonzero(_distance_to_box(points, _block_reach(blocks, a, b, reach))
                                  <= HALO * task.alpha)
            local = np.ascontiguousarray(points[near])
            faces = _exact_complex(local, ids[near], task.alpha, index["low"], index["high"])
            centre = _circumcentres(local, faces)
            tile, block = task.tiling.owner(centre), blocks.owner(centre)
            owned = faces[(tile[:, 0] == task.i) & (tile[:, 1] == task.j)
                          & (block[:, 0] == a) & (block[:, 1] == b)]
            parts.append(_canonical(ids[near][owned], sort=False))   # in the kernel's order
            del local, faces, centre, tile, block, owned
        _save_parts(path, parts)
    return int(np.load(path, mmap_mode="r").shape[0])


def _save_parts(path, parts) -> None:
    """Save the (m, 3) int64 arrays ``parts`` as one ``.npy`` array, one part after the
    other, without joining them in memory (the bytes of ``np.save`` of their join)."""
    shape = (sum(len(p) for p in parts), 3)
    header = {"descr": np.lib.format.dtype_to_descr(np.dtype(np.int64)),
              "fortran_order": False, "shape": shape}
    with atomic_path(path) as partial, open(partial, "wb") as file:
        np.lib.format.write_array_header_1_0(file, header)
        for part in parts:
            file.write(np.ascontiguousarray(part, np.int64).tobytes())


class TiledMesh:
    """A mesh written tile by tile to a store folder by :func:`mesh_tiled`.

    Only the tile index is held in memory; :meth:`to_mesh` assembles the whole mesh,
    :meth:`certificate` measures it tile by tile and :meth:`export` streams it to PLY.

    Parameters
    ----------
    store : str or os.PathLike
        A folder :func:`mesh_tiled` finished writing.

    Attributes
    ----------
    store : pathlib.Path
    alpha : float
    seed : int
    tiling : Tiling
    samples : int
        How many samples (vertices) in all.

    Examples
    --------
    >>> import tempfile
    >>> from shapely.geometry import box
    >>> import pds_plugin as pds
    >>> square = pds.Region.from_shapely(box(0, 0, 1, 1))
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     tiled = pds.mesh_tiled(square, 0.1, tile_size=0.5, store=folder)
    ...     again = pds.TiledMesh(folder)                 # opened from the store
    ...     mesh = again.to_mesh()
    ...     same = np.array_equal(mesh.faces, tiled.to_mesh().faces)
    >>> tiled.tiling.nx, tiled.tiling.ny, same, tiled.samples == len(mesh.vertices)
    (2, 2, True, True)
    """

    def __init__(self, store):
        self.store = Path(store)
        if not (self.store / "index.json").exists():
            raise ArgumentError(f"{self.store} holds no finished tiled mesh (no index.json); "
                                "run mesh_tiled with this store")
        params = json.loads((self.store / "params.json").read_text(encoding="utf-8"))
        self._params = params
        self._index = _index_of(self.store)
        self.alpha = float(params["alpha"])
        self.seed = int(params["seed"])
        x0, y0, x1, y1, nx, ny = params["tiling"]
        self.tiling = Tiling(x0, y0, x1, y1, int(nx), int(ny))
        self.samples = int(self._index["samples"])

    @property
    def region(self) -> Region:
        """The region meshed (read from the store)."""
        return Region(shapely.from_wkb(self._params["region"]), np.array(self._params["frame"]))

    @property
    def triangles(self) -> int:
        """How many triangles in all (read from the files' headers)."""
        return sum(int(np.load(_faces_path(self.store, i, j), mmap_mode="r").shape[0])
                   for i, j in self._tiles())

    def _tiles(self):
        return [(i, j) for i, j in self.tiling.tiles() if f"{i},{j}" in self._index["tiles"]]

    def tile(self, i: int, j: int):
        """Tile ``(i, j)``: its samples, their global ids, which are on the boundary, and
        the triangles it owns (global ids).

        Returns
        -------
        vertices : (n, 2) float ndarray
        ids : (n,) int64 ndarray
        on_boundary : (n,) bool ndarray
        faces : (m, 3) int64 ndarray
        """
        if f"{i},{j}" not in self._index["tiles"]:
            return np.empty((0, 2)), np.empty(0, np.int64), np.empty(0, bool), \
                np.empty((0, 3), np.int64)
        vertices, first, counts = _tile_samples(self.store, self._index, i, j)
        on_boundary = np.repeat([stage != "interior" for stage in STAGES], counts)
        return (vertices, first + np.arange(len(vertices)), on_boundary,
                np.load(_faces_path(self.store, i, j)))

    def to_mesh(self):
        """The whole mesh as one :class:`~pds_plugin.PlanarMesh` (when it fits in memory).

        Returns
        -------
        PlanarMesh
            Vertices in global id order, the tiles' triangles one tile after another;
            not conforming (the paper's construction).
        """
        from .mesh import PlanarMesh

        parts = [self.tile(i, j) for i, j in self._tiles()]
        vertices = np.concatenate([p[0] for p in parts]) if parts else np.empty((0, 2))
        on_boundary = np.concatenate([p[2] for p in parts]) if parts else np.empty(0, bool)
        faces = np.concatenate([p[3] for p in parts]) if parts else np.empty((0, 3), np.int64)
        return PlanarMesh(vertices, faces, on_boundary, self.region, self.alpha, False)

    def export(self, path) -> None:
        """Write the mesh to a binary PLY file, tile by tile (vertices lifted to 3D by
        the region's frame; faces as 32-bit indices).

        Parameters
        ----------
        path : str or os.PathLike
        """
        frame, tiles = np.array(self._params["frame"]), self._tiles()
        kind = "int" if self.samples < 2**31 else "uint"
        header = ("ply\nformat binary_little_endian 1.0\n"
                  f"element vertex {self.samples}\nproperty double x\nproperty double y\n"
                  f"property double z\nelement face {self.triangles}\n"
                  f"property list uchar {kind} vertex_indices\nend_header\n")
        face_type = np.dtype([("n", "u1"), ("v", "<i4" if kind == "int" else "<u4", (3,))])
        with atomic_path(path) as partial, open(partial, "wb") as file:
            file.write(header.encode("ascii"))
            for i, j in tiles:
                xy, _, _ = _tile_samples(self.store, self._index, i, j)
                file.write(np.ascontiguousarray(_lift(xy, frame), "<f8").tobytes())
            for i, j in tiles:
                faces = np.load(_faces_path(self.store, i, j))
                record = np.empty(len(faces), face_type)
                record["n"] = 3
                record["v"] = faces
                file.write(record.tobytes())

    def certificate(self, executor=None) -> TiledCertificate:
        """Measure the mesh tile by tile, the seams included: separation, coverage,
        Theorem 1, isolated and non-manifold vertices, and the Betti numbers.

        Each task holds one tile and its neighbours' samples within 2 alpha, so its
        distances and its triangles' stars are those of the whole mesh; the driver adds
        up counts and joins the components that cross seams.

        Parameters
        ----------
        executor : concurrent.futures.Executor, optional
            Runs the tile tasks (by default here).

        Returns
        -------
        TiledCertificate
        """
        run = secrets.token_hex(8)
        params = self._params
        blocks = tuple(params.get("blocks", (1, 1)))      # stores before blocks: (1, 1)
        specs = [_Task(str(self.store), self.tiling, i, j, -1, self.alpha, self.seed,
                       float(params["feature_angle"]), b"", run, blocks=blocks)
                 for i, j in self._tiles()]
        return _reduced(_run(_certificate_task, specs, executor), self)


def _lift(xy, frame) -> np.ndarray:
    from .region import lift

    return lift(xy, frame) if len(xy) else np.empty((0, 3))


@dataclass(frozen=True)
class TiledCertificate:
    """The certificate of a :class:`TiledMesh`, measured tile by tile.

    Distances are ratios to alpha, as in :class:`~pds_plugin.Certificate`, whose
    fields of the same names these equal; the topology is the Betti numbers (b0 from the
    components joined across seams, b1 from the Euler characteristic), not the
    per-hole report of :func:`pds_plugin.topology_report`.

    Attributes
    ----------
    alpha : float
    samples, triangles : int
    min_separation, coverage_gap : float
    coverage_gap_at : tuple of float
    max_aspect_ratio, min_angle, max_angle : float
    isolated_samples, nonmanifold_vertices : int
    stray_triangles : int
        Stored triangles with a vertex farther than 2 alpha from the tile that owns them
        (no triangle of circumradius <= alpha has one); 0 on a correct mesh.
    area_ratio : float
    betti_mesh, betti_region : tuple of int
    """

    alpha: float
    samples: int
    triangles: int
    min_separation: float
    coverage_gap: float
    coverage_gap_at: tuple
    max_aspect_ratio: float
    min_angle: float
    max_angle: float
    isolated_samples: int
    nonmanifold_vertices: int
    stray_triangles: int
    area_ratio: float
    betti_mesh: tuple
    betti_region: tuple

    # the verdicts of a whole mesh's certificate, on the same fields
    aspect_bound, angle_range = Certificate.aspect_bound, Certificate.angle_range
    sampling_ok, quality_ok = Certificate.sampling_ok, Certificate.quality_ok

    @property
    def ok(self) -> bool:
        """Sampling, quality, the region's Betti numbers, no isolated sample, manifold,
        no stray triangle."""
        return (self.sampling_ok and self.quality_ok and self.betti_mesh == self.betti_region
                and self.isolated_samples == 0 and self.nonmanifold_vertices == 0
                and self.stray_triangles == 0)


def _certificate_task(task: _Task) -> dict:
    """One tile's share of the certificate (see :meth:`TiledMesh.certificate`)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from .analysis.certificate import _coverage_gap, _SampleGrid
    from .analysis.quality import triangle_quality
    from .mesh import PlanarMesh

    index = _index_of(task.store)
    points, ids, own = _gathered(task, index)
    alpha, out = task.alpha, {"own": int(own.sum())}
    if not len(points):
        return out
    params = json.loads((Path(task.store) / "params.json").read_text(encoding="utf-8"))
    region = shapely.from_wkb(params["region"])
    # separation and coverage block by block (the blocks of the tile's sampling), each
    # on the samples within 2 alpha of the part of the plane the block owns: every pair
    # closer than alpha, and every sample a point of the block within alpha of one
    # needs, is there
    reach, blocks = task.tiling.reach(task.i, task.j), task.block_grid()
    out["separation"] = math.inf
    for a, b in blocks.tiles():
        near = _distance_to_box(points, _block_reach(blocks, a, b, reach)) <= HALO * alpha
        local = np.ascontiguousarray(points[near])
        if not len(local):
            continue
        grid = _SampleGrid(local, 2 * alpha)
        out["separation"] = min(out["separation"], float(grid.closest_distance()))
        inside = _polygons(shapely.intersection(region, box(*blocks.box(a, b))))
        if inside is None:
            continue
        faces = _exact_complex(local, ids[near], alpha, index["low"], index["high"])
        mesh = PlanarMesh(local, faces, np.zeros(len(local), bool), Region(inside, np.eye(4)),
                          alpha)
        gap, at = _coverage_gap(mesh, mesh.faces, mesh.boundary_edges, grid)
        if gap > out.get("gap", -math.inf):
            out["gap"], out["gap_at"] = float(gap), [float(v) for v in at]
        del local, grid, faces, mesh
    # the rest measures the stored triangles: the tile's own, and those of the 3 x 3
    # tiles around it at an own vertex (its star: circumcentres within alpha of it)
    owned, star = _stored_faces(task, index, ids, own)
    out["triangles"] = len(owned)
    out["strays"] = int(np.count_nonzero((owned < 0).any(axis=1)))
    owned, star = owned[(owned >= 0).all(axis=1)], star[(star >= 0).all(axis=1)]
    if len(owned):
        measured = [triangle_quality(points, owned[k:k + 2**15])
                    for k in range(0, len(owned), 2**15)]
        out.update(aspect=max(float(q.aspect_ratio.max()) for q in measured),
                   low=min(float(q.angles.min()) for q in measured),
                   high=max(float(q.angles.max()) for q in measured),
                   area=float(sum(q.area.sum() for q in measured)))
        del measured
    # the edges with an own end are all in that star (one int64 key per edge)
    n = np.int64(len(points))                 # int64 keys from the int32 indices
    pairs = ((0, 1), (1, 2), (2, 0))
    keys = np.concatenate([np.minimum(star[:, p], star[:, q]) * n
                           + np.maximum(star[:, p], star[:, q]) for p, q in pairs])
    keys, uses = np.unique(keys, return_counts=True)
    edges = np.column_stack([keys // n, keys % n])
    del keys
    exact = own[edges[:, 0]] | own[edges[:, 1]]
    edges, uses = edges[exact], uses[exact]
    used = np.zeros(len(points), bool)
    used[star.ravel()] = True
    rim_count = np.bincount(edges[uses == 1].ravel(), minlength=len(points))
    out.update(isolated=int(np.count_nonzero(own & ~used)),
               nonmanifold=int(np.count_nonzero(own & (rim_count > 2))),
               used=int(np.count_nonzero(own & used)),
               edges=int(np.count_nonzero(own[edges[:, 0]])))     # the lower id is own
    graph = coo_matrix((np.ones(len(edges), np.int8), (edges[:, 0], edges[:, 1])),
                       shape=(len(points), len(points)))
    label = connected_components(graph, directed=False)[1]
    present = np.unique(label[own & used])
    first = np.full(label.max() + 1, np.iinfo(np.int64).max)
    np.minimum.at(first, label, ids)
    # the vertices another tile's graph may hold too: foreign ones, and own ones next to them
    crossing = edges[own[edges[:, 0]] != own[edges[:, 1]]]
    shared = np.unique(crossing.ravel())
    out["components"] = first[present].tolist()
    out["links"] = np.column_stack([first[label[shared]], ids[shared]]).tolist()
    return out


def _stored_faces(task: _Task, index: dict, ids, own):
    """The stored triangles of the tile, and those of the tiles around it with a vertex
    of the tile, as indices into ``ids`` (-1 for an id not among them: a triangle
    reaching farther than 2 alpha, which a correct mesh does not have). The files are
    read a chunk at a time, so only the kept triangles are held."""
    record = index["tiles"][f"{task.i},{task.j}"]
    first, last = record["first"], record["first"] + sum(record["counts"])

    def local(faces):        # int32: a tile's task holds far fewer than 2**31 samples
        at = np.minimum(np.searchsorted(ids, faces), len(ids) - 1)
        return np.where(ids[at] == faces, at, -1).astype(np.int32)
    owned, star = [np.empty((0, 3), np.int32)], [np.empty((0, 3), np.int32)]
    for a, b in task.tiling.neighbours(task.i, task.j):
        if f"{a},{b}" not in index["tiles"]:
            continue
        for faces in _face_chunks(_faces_path(task.store, a, b)):
            if (a, b) == (task.i, task.j):
                owned.append(local(faces))
            star.append(local(faces[((faces >= first) & (faces < last)).any(axis=1)]))
    return np.concatenate(owned), np.concatenate(star)


def _face_chunks(path, rows: int = 2**15):
    """The (m, 3) int64 array of a ``.npy`` file, ``rows`` rows at a time."""
    with open(path, "rb") as file:
        version = np.lib.format.read_magic(file)
        read = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                else np.lib.format.read_array_header_2_0)
        shape, _, _ = read(file)
        for start in range(0, shape[0], rows):
            count = min(rows, shape[0] - start)
            yield np.fromfile(file, np.int64, 3 * count).reshape(count, 3)


def _reduced(parts: list, mesh: TiledMesh) -> TiledCertificate:
    """The tiles' shares added up, and the components joined across the seams."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    alpha, region = mesh.alpha, mesh.region
    gaps = [(p["gap"], p["gap_at"]) for p in parts if "gap" in p]
    gap, gap_at = max(gaps, key=lambda g: g[0]) if gaps else (math.inf, (math.nan, math.nan))
    reps = [r for p in parts for r in p.get("components", [])]
    links = np.array([link for p in parts for link in p.get("links", [])],
                     np.int64).reshape(-1, 2)
    nodes, inverse = np.unique(np.concatenate([reps, links.ravel()]).astype(np.int64),
                               return_inverse=True)
    n_reps = len(reps)
    pairs = inverse[n_reps:].reshape(-1, 2)
    graph = coo_matrix((np.ones(len(pairs), np.int8), (pairs[:, 0], pairs[:, 1])),
                       shape=(len(nodes), len(nodes)))
    label = connected_components(graph, directed=False)[1]
    b0 = len(np.unique(label[inverse[:n_reps]]))
    triangles = sum(p.get("triangles", 0) for p in parts)
    chi = sum(p.get("used", 0) for p in parts) - sum(p.get("edges", 0) for p in parts) + triangles
    with_faces = [p for p in parts if p.get("triangles")]
    return TiledCertificate(
        alpha=alpha, samples=sum(p["own"] for p in parts), triangles=triangles,
        min_separation=min((p.get("separation", math.inf) for p in parts),
                           default=math.inf) / alpha,
        coverage_gap=gap / alpha, coverage_gap_at=tuple(gap_at),
        max_aspect_ratio=max((p["aspect"] for p in with_faces), default=0.0),
        min_angle=min((p["low"] for p in with_faces), default=180.0),
        max_angle=max((p["high"] for p in with_faces), default=0.0),
        isolated_samples=sum(p.get("isolated", 0) for p in parts),
        nonmanifold_vertices=sum(p.get("nonmanifold", 0) for p in parts),
        stray_triangles=sum(p.get("strays", 0) for p in parts),
        area_ratio=sum(p.get("area", 0.0) for p in with_faces) / region.area,
        betti_mesh=(b0, b0 - chi), betti_region=region.betti)
