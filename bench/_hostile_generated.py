"""Generated inputs for bench/reliability.py: sweeps of alpha, far and tiny coordinates,
degenerate polygons, seeded random regions and point sets, and random pds-mesh
invocations. Each has an oracle that does not trust the package (bench/_hostile.py's
:func:`mesh_problem`, :func:`complex_trial`, :func:`cli_verdict`); the certificate is
read only to know whether a topology change was reported to the user.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import subprocess

import numpy as np

from _hostile import (_SVG, Case, Trial, _mesh_check, _stl, betti, cli_verdict,
                      complex_trial, mesh_betti)

SEED = 20261130


def _shapes():
    """A square, a ring and an L of size 1 with their corner at the origin."""
    from shapely.geometry import Point, Polygon, box

    ring = Point(0.5, 0.5).buffer(0.5, quad_segs=16).difference(
        Point(0.5, 0.5).buffer(0.2, quad_segs=16))
    ell = Polygon([(0, 0), (1, 0), (1, 0.3), (0.3, 0.3), (0.3, 1), (0, 1)])
    return {"square": box(0, 0, 1, 1), "ring": ring, "L": ell}


def told_check(geometry, alpha):
    """The mesh checks of :func:`_hostile.mesh_problem`, the topology one only when the
    certificate claims it: at an alpha too large for a narrow part the mesh may lose a
    hole, and the certificate must say so (then the user was told, not misled)."""
    geometric = _mesh_check(geometry, alpha, topology=False)

    def check(mesh):
        problem = geometric(mesh)
        if problem is not None or len(mesh.faces) == 0:
            return problem
        found, drawn = mesh_betti(mesh.vertices, mesh.faces), betti(geometry)
        if found != drawn and mesh.certificate().topology_ok:
            return "wrong", f"Betti numbers {found} for a region with {drawn}, certificate ok"
        return None
    return check


def _mesh_case(name, geometry, alpha, **options):
    import pds_plugin as pds

    def make(folder):
        def run():
            return pds.mesh_region(pds.Region.from_shapely(geometry), alpha, **options)
        return Trial(run, [geometry], told_check(geometry, alpha))
    return Case(name, make)


def alpha_sweep_cases():
    """Every power of ten from 1e-320 to 1e320 (and a few between) on three shapes; the
    sample budget is 100,000, so small alphas must be refused by the budget."""
    alphas = [float(f"1e{k}") for k in range(-320, 321, 20)]          # 1e320 is inf + [0.3, 0.05, 0.012, 0.7, 1.4, 5e-324]
    return [_mesh_case(f"{shape} at alpha {alpha:g}", geometry, alpha, max_samples=100_000)
            for shape, geometry in _shapes().items() for alpha in alphas]


def coordinate_grid_cases():
    """The three shapes scaled to sizes 1e-6 .. 1e6 and moved to offsets 0 .. 1e15 in x, y
    or both, meshed at a tenth of their size: meshed right, or refused as beyond float64's
    resolution."""
    from shapely import affinity

    cases = []
    for shape, geometry in _shapes().items():
        for size in (1e-6, 1e-2, 1.0, 1e3, 1e6):
            for dx, dy in ((0, 0), (1e4, 0), (0, -1e8), (-1e12, 1e12), (1e14, 0), (0, 1e15)):
                moved = affinity.translate(affinity.scale(geometry, size, size, origin=(0, 0)),
                                           dx, dy)
                cases.append(_mesh_case(f"{shape} of size {size:g} at ({dx:g}, {dy:g})", moved,
                                        size / 10))
    return cases


def degenerate_polygons():
    """Polygons that are barely polygons: spikes, slivers, repeated and collinear
    vertices, holes touching the outline, near-coincident parts."""
    import shapely
    from shapely.geometry import MultiPolygon, Point, Polygon, box

    spike = Polygon([(0, 0), (1, 0), (1, 1), (0.5, 1), (0.5, 3), (0.5, 1), (0, 1)])
    return {
        "repeated vertices": Polygon([(0, 0), (0, 0), (1, 0), (1, 0), (1, 1), (0, 1), (0, 1)]),
        "collinear run": Polygon([(0, 0), (0.25, 0), (0.5, 0), (0.75, 0), (1, 0), (1, 1), (0, 1)]),
        "zero-width spike": spike,
        "sliver 1e-9 wide": box(0, 0, 1, 1e-9),
        "sliver 1e-6 wide on a square": box(0, 0, 1, 1).union(box(1, 0.5, 2, 0.5 + 1e-6)),
        "hole touching the outline at a point": Polygon(
            [(0, 0), (2, 0), (2, 2), (0, 2)], [[(0, 1), (1, 0.5), (1, 1.5)]]),
        "hole touching the outline along an edge": Polygon(
            [(0, 0), (2, 0), (2, 2), (0, 2)], [[(0, 0.5), (1, 0.5), (1, 1.5), (0, 1.5)]]),
        "hole equal to the outline": Polygon([(0, 0), (1, 0), (1, 1), (0, 1)],
                                             [[(0, 0), (1, 0), (1, 1), (0, 1)]]),
        "hole outside the outline": Polygon([(0, 0), (1, 0), (1, 1), (0, 1)],
                                            [[(2, 2), (3, 2), (3, 3)]]),
        "two squares touching at a corner": MultiPolygon([box(0, 0, 1, 1), box(1, 1, 2, 2)]),
        "two squares 1e-12 apart": MultiPolygon([box(0, 0, 1, 1), box(1 + 1e-12, 0, 2, 1)]),
        "two overlapping squares": MultiPolygon([box(0, 0, 2, 2), box(1, 1, 3, 3)]),
        "bowtie": Polygon([(0, 0), (2, 2), (2, 0), (0, 2)]),
        "self-touching ring": Polygon([(0, 0), (2, 0), (2, 2), (1, 0), (0, 2)]),
        "triangle near-collinear (1e-12)": Polygon([(0, 0), (1, 0), (0.5, 1e-12)]),
        "triangle near-collinear (1e-4)": Polygon([(0, 0), (1, 0), (0.5, 1e-4)]),
        "100,000-gon": Point(0, 0).buffer(1, quad_segs=25_000),
        "comb of 200 teeth": shapely.union_all([box(0, 0, 20, 1)] + [
            box(0.1 * i, 1, 0.1 * i + 0.05, 3) for i in range(200)]),
        "square with 400 pin holes": box(0, 0, 20, 20).difference(shapely.union_all(
            [Point(0.5 + i, 0.5 + j).buffer(0.1, quad_segs=4) for i in range(20)
             for j in range(20)])),
        "nested islands": shapely.union_all([
            box(0, 0, 10, 10).difference(box(1, 1, 9, 9)), box(2, 2, 8, 8).difference(
                box(3, 3, 7, 7)), box(4, 4, 6, 6)]),
        "hole 1e-9 from the outline": box(0, 0, 1, 1).difference(box(1e-9 * 1 + 0.0, 0.4,
                                                                      0.5, 0.6)),
        "empty polygon beside a square": shapely.GeometryCollection(
            [shapely.Polygon(), box(0, 0, 1, 1)]),
        "polygon with a NaN hole": Polygon([(0, 0), (1, 0), (1, 1), (0, 1)],
                                           [[(0.2, 0.2), (math.nan, 0.3), (0.4, 0.4)]]),
        "1e-300 square beside a unit square": MultiPolygon([box(0, 0, 1, 1),
                                                            box(5, 5, 5 + 1e-300, 5 + 1e-300)]),
        "square of side 1e90": box(0, 0, 1e90, 1e90),
        "square of side 1e-90": box(0, 0, 1e-90, 1e-90),
        "a point buffered by 0": Point(0, 0).buffer(0),
        "four vertices, zero area": Polygon([(0, 0), (1, 1), (2, 2), (3, 3)]),
        "long thin diagonal strip": Polygon([(0, 0), (100, 100), (100, 100.01), (0, 0.01)]),
        "star of 1,000 spikes": Polygon([((1 + (i % 2) * 4) * math.cos(i * math.pi / 1000),
                                          (1 + (i % 2) * 4) * math.sin(i * math.pi / 1000))
                                         for i in range(2000)]),
    }


def degenerate_polygon_cases():
    """Each degenerate polygon with repair off and on, meshed at a tenth of its size:
    a clean refusal, or a mesh right for the region made (separation, coverage, aspect,
    no overlap, the region's Betti numbers)."""
    import pds_plugin as pds

    def case(name, geometry, repair):
        def make(folder):
            def run():
                region = pds.Region.from_shapely(geometry, repair=repair)
                x0, y0, x1, y1 = region.bounds
                alpha = max(x1 - x0, y1 - y0) / 10
                return region, pds.mesh_region(region, alpha, max_samples=200_000), alpha

            def check(result):
                # repair off: the region is the polygon, but for the moves it reports
                # (components touching at a point moved apart, Region.source_deviation):
                # its boundary within that of the polygon's, its area within that times
                # the polygon's perimeter
                region, mesh, alpha = result
                moved = region.source_deviation * geometry.length
                if not repair and not math.isclose(region.area, geometry.area, rel_tol=1e-9,
                                                   abs_tol=moved):
                    return "wrong", (f"area {region.area:.9g} for a polygon of "
                                     f"{geometry.area:.9g} (moved {region.source_deviation:.3g})")
                return told_check(region.geometry, alpha)(mesh)
            return Trial(run, [geometry], check)
        return Case(f"{name}, repair={repair}", make)
    return [case(name, geometry, repair) for name, geometry in degenerate_polygons().items()
            for repair in (False, True)]


def random_region(rng):
    """A star-shaped polygon of 5 to 40 vertices with 0 to 3 round holes, size about 1."""
    import shapely
    from shapely.geometry import Point, Polygon

    count = int(rng.integers(5, 41))
    angles = np.sort(rng.uniform(0, 2 * np.pi, count))
    radii = rng.uniform(0.5, 1.0, count)
    outline = Polygon(np.column_stack([radii * np.cos(angles), radii * np.sin(angles)]))
    holes = [Point(rng.uniform(-0.3, 0.3, 2)).buffer(rng.uniform(0.03, 0.12), quad_segs=8)
             for _ in range(int(rng.integers(0, 4)))]
    return shapely.make_valid(outline.difference(shapely.union_all(holes))) if holes else outline


def random_region_cases(count=110):
    """Seeded random regions at random alphas (1/100 to 1/5 of their size) and seeds."""
    import shapely

    rng = np.random.default_rng(SEED)
    cases = []
    for index in range(count):
        geometry = random_region(rng)
        polygons = [p for p in shapely.get_parts(geometry) if p.area > 0]
        geometry = shapely.MultiPolygon(polygons) if len(polygons) > 1 else polygons[0]
        alpha = float(10 ** rng.uniform(-2, np.log10(0.2)))
        seed = int(rng.integers(0, 2**31))
        cases.append(_mesh_case(f"random region {index} (alpha {alpha:.4g}, seed {seed})",
                                geometry, alpha, seed=seed))
    return cases


def random_point_set_cases(count=80):
    """Seeded point sets of 3 to 3,000 points: uniform, clustered, jittered grids, nearly
    collinear, far from the origin, with alpha from 0.2 to 3 times their spacing."""
    rng = np.random.default_rng(SEED)
    cases = []
    for index in range(count):
        n = int(10 ** rng.uniform(np.log10(3), np.log10(3000)))
        kind = ["uniform", "clusters", "grid", "collinear", "far"][index % 5]
        if kind == "uniform":
            points = rng.random((n, 2))
        elif kind == "clusters":
            centres = rng.random((4, 2))
            points = centres[rng.integers(0, 4, n)] + rng.normal(0, 0.02, (n, 2))
        elif kind == "grid":
            side = max(2, int(math.sqrt(n)))
            grid = np.stack(np.meshgrid(np.arange(side), np.arange(side)), -1).reshape(-1, 2)
            points = (grid + rng.normal(0, 1e-3, grid.shape)) / side
        elif kind == "collinear":
            points = np.column_stack([rng.random(n), rng.normal(0, 1e-6, n)])
        else:
            points = rng.random((n, 2)) + 1e6
        points = np.unique(points, axis=0)
        spacing = 1 / math.sqrt(len(points))
        alpha = float(spacing * 10 ** rng.uniform(np.log10(0.2), np.log10(3)))
        cases.append(Case(f"{kind} {len(points)} points, alpha {alpha:.3g}",
                          lambda folder, p=points, a=alpha: complex_trial(p, a)))
    return cases


# --- pds-mesh invocations, run in this process (no interpreter start per run) -------------

_OPTIONS = {
    "input": ["part.stl", "drawing.svg", "plate.dxf", "missing.stl", "exists", "notes.txt",
              "part.STL"],
    "-o": ["out.ply", "out.obj", "out.stl", "out", "exists", "no/dir/out.ply", "out.PLY",
           "part.stl"],
    "--alpha": ["0.1", "0.3", "auto", "0", "-1", "nan", "inf", "1e-300", "1e300", "abc", ""],
    "--axis": ["z", "x", "w"],
    "--plane-normal": ["0,0,1", "0,0,0", "1,1", "nan,0,1", "1,2,3"],
    "--plane-origin": ["0,0,0.5", "0,0,9", "a,b,c"],
    "--at": ["0.5", "0.25,0.75", "5", "1", "", "a", "-0.5"],
    "--slices": ["0", "2", "-1", "1000000000", "x"],
    "--on-face": ["above", "below", "sideways"],
    "--jobs": ["1", "2", "0", "1000", "x"],
    "--seed": ["0", "-1", "1.5", "7"],
    "--max-samples": ["0", "100", "1e6", "20000"],
    "--report": ["r.json", "exists", "no/dir/r.json"],
    "--layer": ["OUTLINE", "NOPE"],
}


def _good_invocation(rng) -> list[str]:
    """A pds-mesh run that must succeed: a section of the 2 x 1 x 1 box, or a drawing,
    with good values of some other options."""
    source = str(rng.choice(["part.stl", "drawing.svg", "plate.dxf"]))
    argv = [source, "-o", str(rng.choice(["out.ply", "out.obj", "out.stl", "out.off"])),
            "--alpha", str(rng.choice(["0.1", "0.25", "auto"]))]
    if source == "part.stl":
        argv += ["--axis", str(rng.choice(["x", "y", "z"]))]
        where = rng.integers(0, 3)
        argv += [["--at", str(rng.choice(["0.3", "0.5,0.7", "0.61"]))], ["--slices", "3"],
                 []][int(where)]
    elif source == "plate.dxf" and rng.random() < 0.5:
        argv += ["--layer", "OUTLINE"]
    for option, values in (("--seed", ["0", "7", "123456789"]), ("--max-samples", ["20000"]),
                           ("--report", ["r.json"]), ("--jobs", ["1", "2"])):
        if rng.random() < 0.3:
            argv += [option, str(rng.choice(values))]
    return argv


def _run_cli(folder, argv):
    """``pds-mesh argv`` in ``folder`` in this process, as a CompletedProcess."""
    from pds_plugin.cli import main

    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    os.chdir(folder)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(argv)
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess(argv, code, out.getvalue(), err.getvalue())


def cli_fuzz_cases(count=140):
    """Seeded random pds-mesh invocations: half with good values only (which must
    succeed), half with an input, an output, alpha and up to four other options drawn
    from good and bad values; judged as bench/_hostile.py's command line class: exit 0
    with complete files, or one error line and no file left behind."""
    import ezdxf

    rng = np.random.default_rng(SEED)
    others = [key for key in _OPTIONS if key not in ("input", "-o", "--alpha")]
    invocations = []
    for index in range(count):
        if index % 2:                     # every other run: good values only
            invocations.append((_good_invocation(rng), True))
            continue
        argv = [str(rng.choice(_OPTIONS["input"]))]
        for key in ("-o", "--alpha"):
            if rng.random() < 0.95:
                argv += [key, str(rng.choice(_OPTIONS[key]))]
        for key in rng.choice(others, size=int(rng.integers(0, 5)), replace=False):
            argv += [str(key), str(rng.choice(_OPTIONS[str(key)]))]
        invocations.append((argv, False))

    def make_for(argv, good):
        def judge(process, folder, keep):
            verdict = cli_verdict(process, folder, keep)
            if good and verdict is not None and verdict[0] == "clean":
                return "wrong", f"a good invocation was refused: {verdict[1]}"
            return verdict

        def make(folder):
            stl = _stl(folder)
            (folder / "drawing.svg").write_text(_SVG.format(
                attributes='viewBox="0 0 10 10"', body='<rect width="10" height="10"/>'))
            doc = ezdxf.new(units=4)
            doc.modelspace().add_lwpolyline([(0, 0), (4, 0), (4, 2), (0, 2)], close=True,
                                            dxfattribs={"layer": "OUTLINE"})
            doc.saveas(folder / "plate.dxf")
            (folder / "notes.txt").write_text("hello")
            (folder / "exists").mkdir()
            keep = ("part.stl", "drawing.svg", "plate.dxf", "notes.txt", "exists")
            return Trial(lambda: _run_cli(folder, argv), [stl, folder / "plate.dxf"],
                         lambda process: judge(process, folder, keep))
        return make
    return [Case("pds-mesh " + " ".join(repr(a) if not a or " " in a else a for a in argv),
                 make_for(argv, good)) for argv, good in invocations]
