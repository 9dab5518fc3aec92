"""The pipeline: suggest_alpha and auto_mesh (alpha from the feature size, topology
verified), multiresolution (one certified mesh per alpha, the paper's Figure 6 claims),
mesh_region("auto") and section_report."""

import math
import runpy
import warnings
from pathlib import Path

import pytest
import shapely
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin import Region, feature_size, suggest_alpha
from pds_plugin.analysis.topology import topology_report
from pds_plugin.pipeline import Resolution, auto_mesh
from pds_plugin.sampling import estimate_samples

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def disc_with_hole(radius=0.15):
    return pds.Region.from_shapely(Point(0, 0).buffer(1).difference(Point(0.5, 0).buffer(radius)))


def test_levels_follow_the_alphas_and_carry_their_certificates():
    region = disc_with_hole()
    # the paper's construction: Theorem 1 at every level (a conforming mesh of a hole
    # smaller than alpha has the exceptions of docs/conforming.md)
    levels = pds.multiresolution(region, [0.4, 0.1, 0.05], seed=3, conforming=False)
    assert [level.alpha for level in levels] == [0.4, 0.1, 0.05]
    for level in levels:
        assert isinstance(level, Resolution)
        alpha, mesh, certificate = level
        assert mesh.alpha == alpha and mesh.region is region
        assert certificate is mesh.certificate()
        assert certificate.quality_ok            # Theorem 1 at every level
    assert len(levels[0].mesh.vertices) < len(levels[1].mesh.vertices) < len(levels[2].mesh.vertices)


def test_coarse_levels_lose_the_hole_fine_levels_keep_it():
    # a hole of radius r closes near alpha = r and is kept with alpha <= r/2 (Theorem 2,
    # the paper's construction; a conforming mesh keeps holes at any alpha)
    r = 0.15
    coarse, fine = pds.multiresolution(disc_with_hole(r), [2 * r, r / 2], conforming=False)
    assert coarse.certificate.betti_mesh == (1, 0) and not coarse.certificate.topology_ok
    assert "hole 0 of component 0" in coarse.certificate.topology.problems[0]
    assert fine.certificate.betti_mesh == (1, 1) and fine.certificate.topology_ok
    assert "topology lost" in str(coarse) and "topology ok" in str(fine)


def test_same_seed_same_levels():
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    a, b = (pds.multiresolution(region, [0.3, 0.1], seed=7) for _ in range(2))
    assert all((x.mesh.vertices == y.mesh.vertices).all() for x, y in zip(a, b))


@pytest.mark.parametrize("alphas, error, match", [
    ([], ValueError, "empty"),
    ([0.1, -0.2], ValueError, "positive finite"),
    ([0.1, float("nan")], ValueError, "positive finite"),
    (0.1, TypeError, "iterable"),
    (["coarse"], TypeError, "iterable"),
])
def test_bad_alphas(alphas, error, match):
    with pytest.raises(error, match=match):
        pds.multiresolution(disc_with_hole(), alphas)


def test_the_budget_is_checked_before_any_meshing():
    with pytest.raises(ValueError, match="alpha 0.0001"):
        pds.multiresolution(disc_with_hole(), [0.5, 1e-4], max_samples=10_000)


def test_bad_region():
    with pytest.raises(TypeError, match="Region"):
        pds.multiresolution(box(0, 0, 1, 1), [0.1])


def test_figure6_example_reproduces_the_paper(tmp_path):
    results = runpy.run_path(str(EXAMPLES / "figure6.py"))["main"](tmp_path)
    (holes_png, (coarse, fine)) = results["two_holes"]
    # alpha = half the larger radius: only the larger hole; half the smaller: both
    assert coarse.betti_mesh == (1, 1) and fine.betti_mesh == (1, 2) and fine.topology_ok
    assert "hole 1 of component 0" in coarse.problems[0] and "filled" in coarse.problems[0]
    (pipe_png, (coarse, fine)) = results["pipe"]
    # alpha = half the circles' radius: the pipe closes and splits the hole in two
    assert coarse.betti_mesh == (1, 2) and "split into 2" in coarse.problems[0]
    assert fine.betti_mesh == (1, 1) and fine.topology_ok
    for png in (holes_png, pipe_png):
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# --- section_report: the per-section report the CLI writes, for library users -----------

def test_section_report_is_json_ready_and_agrees_with_the_mesh():
    import json

    region = disc_with_hole()
    mesh = pds.mesh_region(region, 0.1, seed=4)
    report = pds.section_report(mesh, seed=4, output="out.ply", warnings=["careful"])
    text = json.dumps(report)                                 # plain values only
    assert json.dumps(json.loads(text)) == text
    assert report["output"] == "out.ply" and report["plot"] is None
    assert report["samples"] == len(mesh.vertices) and report["triangles"] == len(mesh.faces)
    assert report["alpha"] == 0.1 and report["alpha_mode"] == "given" and report["seed"] == 4
    assert report["region"]["betti"] == [1, 1]
    assert report["region"]["area"] == pytest.approx(region.area, rel=1e-15)
    assert report["plane"] == {"origin": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}
    assert report["feature_size"]["value"] == pds.feature_size(region).value
    assert report["quality"]["aspect_max"] <= report["certificate"]["aspect_bound"]
    assert list(report["certificate"]["betti_mesh"]) == [1, 1] and report["warnings"] == ["careful"]


def test_section_report_refuses_an_unknown_alpha_mode():
    mesh = pds.mesh_region(disc_with_hole(), 0.2)
    with pytest.raises(pds.ArgumentError, match="alpha_mode"):
        pds.section_report(mesh, seed=0, alpha_mode="guessed")


def test_mesh_region_auto_is_auto_mesh():
    region = disc_with_hole(0.3)
    auto = pds.mesh_region(region, "auto", seed=1)
    direct = pds.auto_mesh(region, seed=1)
    assert auto.alpha == direct.alpha
    assert (auto.vertices == direct.vertices).all() and (auto.faces == direct.faces).all()


# --- suggest_alpha -------------------------------------------------------------------

def region(geometry):
    return Region.from_shapely(geometry)


def test_suggest_alpha_is_half_the_lfs_and_respects_the_budget():
    plate = region(box(0, 0, 4, 3).difference(box(1.5, 0.5, 1.8, 4)))
    assert suggest_alpha(plate, conforming=False) == pytest.approx(0.3 / 4, rel=1e-12)
    budget = int(estimate_samples(plate, 0.3 / 4) / 10)
    with pytest.warns(UserWarning, match="gap of width 0.3"):
        capped = suggest_alpha(plate, max_samples=budget, conforming=False)
    assert capped > 0.3 / 4
    assert estimate_samples(plate, capped) == pytest.approx(budget, rel=1e-9)
    # the slot stays open in a conforming mesh; the thinnest wall, 0.5 under it, counts
    assert suggest_alpha(plate) == pytest.approx(0.5 / 4, rel=1e-12)


def test_auto_keeps_the_sampling_grid_within_its_limit():
    """Two thin strips far apart across a wide, tall box (a tilted plane through a
    plate): the feature size asks for an alpha whose sampling grid over the bounding box
    has more cells than the limit. "auto" used to raise BudgetError there (a held-out
    corpus section); now it takes the smallest alpha the grid allows, says so, and
    meshes."""
    from pds_plugin.sampling import _MAX_GRID_CELLS, DEFAULT_MAX_SAMPLES

    strips = region(box(0, 0, 2000, 0.02).union(box(0, 1999.98, 2000, 2000)))
    assert estimate_samples(strips, 0.005) < DEFAULT_MAX_SAMPLES
    with pytest.warns(UserWarning, match="sampling grid .* beyond its limit"):
        alpha = suggest_alpha(strips)
    assert alpha > 0.005
    cells = (2000 / (alpha / math.sqrt(2)) + 3) ** 2
    assert 0.98 * _MAX_GRID_CELLS < cells <= _MAX_GRID_CELLS


def test_no_warning_within_the_budget():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        suggest_alpha(region(box(0, 0, 1, 1)))


# --- auto_mesh ----------------------------------------------------------------------

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def test_auto_mesh_refines_a_coarse_start_until_the_topology_is_right():
    # the paper's construction closes the hole at a coarse alpha (a conforming mesh keeps it)
    disc = region(Point(0, 0).buffer(1).difference(Point(0.4, 0).buffer(0.15)))
    mesh = auto_mesh(disc, max_alpha=1.0, seed=2, conforming=False)
    assert mesh.certificate().topology_ok
    steps = math.log(mesh.alpha) / math.log(0.7)
    assert steps == pytest.approx(round(steps)) and round(steps) >= 1
    # the level before it still lost the hole
    coarser = topology_report(pds.mesh_region(disc, mesh.alpha / 0.7, seed=2, conforming=False))
    assert not coarser.topology_ok


def test_auto_mesh_names_the_feature_when_the_budget_runs_out():
    # a hole 0.001 from the outline: material thinner than any alpha the budget allows.
    # The warning names it; the conforming mesh at the budget's alpha keeps the wall with
    # rungs across it, each thin triangle an itemised exception (tests/test_fixed_alpha.py)
    hairline = region(box(0, 0, 10, 5).difference(box(1, 1, 9, 4.999)))
    with pytest.warns(UserWarning, match=r"alpha 0.00025 needed for the wall of width 0.001 "
                                         r"between vertex 0 of the hole 0 of component 0"):
        mesh = auto_mesh(hairline, max_samples=2000)
    assert mesh.certificate().ok_with_exceptions and mesh.certificate().topology_ok
    # two parts 0.001 apart: the paper's complex joins them below alpha 0.00025
    hairline = region(box(0, 0, 5, 5).union(box(5.001, 0, 10.001, 5)))
    with pytest.raises(ValueError, match=r"gap of width 0.001 .* needs alpha <= 0.00025.*"
                                         r"components 0 and 1 are joined"):
        auto_mesh(hairline, max_samples=2000, conforming=False)   # conforming keeps the gap


@pytest.mark.parametrize("bad", [0, -1, float("inf"), float("nan")])
def test_auto_mesh_rejects_bad_max_alpha(bad):
    with pytest.raises(ValueError, match="max_alpha"):
        auto_mesh(region(box(0, 0, 1, 1)), max_alpha=bad)


def data_section(name):
    path = DATA / name
    if not path.exists():
        pytest.skip(f"{path} is not available")
    if name.endswith(".svg"):
        return pds.load_svg(path)
    import trimesh
    solid = trimesh.load(path)
    middle = solid.bounds.mean(axis=0)
    return pds.section(solid, plane_origin=middle, plane_normal=[0, 0, 1])


@pytest.mark.parametrize("name, betti", [("featuretype.STL", (2, 8)), ("MIL.svg", (1, 8))])
def test_auto_mesh_recovers_the_topology_of_real_parts(name, betti):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # the SVG has two open strokes, reported
        reg = data_section(name)
    assert reg.betti == betti
    mesh = auto_mesh(reg)
    certificate = mesh.certificate()
    assert certificate.topology_ok and certificate.betti_mesh == betti
    # Theorem 1 wherever samples are alpha apart: the parts' boundary pieces shorter than
    # alpha are kept, with the exceptions of docs/conforming.md
    quality = mesh.quality()
    regular = (quality.edge_lengths >= mesh.alpha * (1 - 1e-9)).all(axis=1)
    assert quality.aspect_ratio[regular].max() <= 4 * math.sqrt(3) * (1 + 1e-9)
    assert mesh.alpha == pytest.approx(feature_size(reg).value / 4)


@pytest.mark.parametrize("bad", [0, -3, 2.5, "many", True])
def test_bad_sample_budgets(bad):
    square = region(box(0, 0, 1, 1))
    with pytest.raises(ValueError, match="max_samples must be a positive integer"):
        suggest_alpha(square, max_samples=bad)
    with pytest.raises(ValueError, match="max_samples must be a positive integer"):
        auto_mesh(square, max_samples=bad)


def test_an_alpha_below_the_coordinates_resolution_is_refused_at_once():
    """A unit square at 1e15 (float spacing 0.125): alpha 0.02 used to run for minutes
    past 8 GB; 0.1 gave overlapping triangles."""
    import time

    far = pds.Region.from_shapely(box(1e15, 1e15, 1e15 + 1, 1e15 + 1))
    for alpha in (0.02, 0.05, 0.1):
        started = time.monotonic()
        with pytest.raises(pds.PdsError, match="translate the region towards the origin"):
            pds.mesh_region(far, alpha)
        assert time.monotonic() - started < 5


def test_a_region_far_from_the_origin_meshes_like_one_at_it():
    near = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.1)
    far = pds.mesh_region(pds.Region.from_shapely(box(1e8, 1e8, 1e8 + 1, 1e8 + 1)), 0.1)
    assert far.certificate().ok and abs(len(far.vertices) - len(near.vertices)) < 20


@pytest.mark.parametrize("keywords, words", [
    ({"alpha": True}, "alpha must be a positive number"),
    ({"alpha": 1e-300}, "translate"),
    ({"alpha": 0.1, "max_samples": 0}, "max_samples"),
    ({"alpha": 0.1, "max_samples": float("nan")}, "max_samples"),
    ({"alpha": 0.1, "seed": -1}, "seed"),
])
def test_bad_numbers_get_the_package_error(keywords, words):
    with pytest.raises(pds.PdsError, match=words):
        pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), **keywords)


def test_auto_alpha_warns_when_the_budget_caps_it_below_a_slot():
    """A 10 x 10 plate with a 1e-4-wide slot: 20,000 samples cannot resolve it, the
    bridged slot keeps the topology, so only a warning can tell."""
    plate = pds.Region.from_shapely(box(0, 0, 10, 10).difference(box(2, 5 - 5e-5, 10, 5 + 5e-5)))
    with pytest.warns(UserWarning, match=r"gap of width 0\.0001.*raise max_samples"):
        mesh = pds.mesh_region(plate, "auto", max_samples=20_000, conforming=False)
    assert mesh.alpha > 1e-4
    # a conforming mesh keeps the slot open at that alpha: nothing to warn about
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kept = pds.mesh_region(plate, "auto", max_samples=20_000)
    certificate = kept.certificate()
    assert certificate.boundary_ok and certificate.topology_ok
    assert certificate.outside_area_ratio == 0 and certificate.missing_area_ratio == 0
    # the slot's end is an edge 1e-4 long between two corners: an exception to Theorem 1
    # the certificate must not hide
    assert certificate.min_separation < 0.001 and not certificate.ok


def test_uniform_auto_says_when_one_thin_wall_makes_it_heavy_and_graded_is_light():
    """A hole 0.05 from the outline of a 12 x 8 plate (a tessellated bolt hole near a
    rim, cut obliquely): uniform "auto" takes alpha 0.0125 everywhere, about 400,000
    samples, and says so before sampling, naming the wall and graded=True; the graded
    mesh is certified with a few hundred vertices. A plate without such a wall is
    meshed without a word."""
    plate = Region.from_shapely(box(0, 0, 12, 8).difference(Point(10.95, 4).buffer(1.0, 64)))
    with warnings.catch_warnings():
        warnings.simplefilter("error")            # raised where it is said: no sampling
        with pytest.raises(UserWarning, match=r"set by the wall of width 0\.05 .* "
                           r"times below the region's inradius .*\(graded=True"):
            pds.mesh_region(plate, "auto")
        graded = pds.mesh_region(plate, "auto", graded=True)
        plain = pds.mesh_region(Region.from_shapely(box(0, 0, 12, 8).difference(
            Point(9, 4).buffer(1.0, 64))), "auto")
    assert graded.certificate().ok and len(graded.vertices) < 1000
    assert plain.certificate().ok


def test_auto_meshes_a_speck_over_the_budget_as_a_small_ring():
    """A square and, far from it, a speck whose altitude asks for alpha 5e-5 (a held-out
    gear section's triangle 0.007 across took the budget's 5 million samples and 18 s):
    over the sample budget, "auto" takes the alpha the other components ask for, meshes
    the speck whole as a small ring, says so, and the certificate lists its close pairs."""
    import warnings

    import shapely
    from shapely.geometry import Polygon, box

    speck = Polygon([(150, 0), (150.01, 0), (150.005, 0.0002)])
    region = pds.Region.from_shapely(shapely.MultiPolygon([box(0, 0, 100, 100), speck]))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = pds.mesh_region(region, "auto")
    assert mesh.alpha == pytest.approx(25.0)                    # the square's wall / 4
    assert any("small rings" in str(w.message) for w in caught)
    cert = mesh.certificate()
    assert cert.ok_with_exceptions and cert.betti_mesh == (2, 0), str(cert)
    assert cert.exceptions and len(mesh.vertices) < 100


def test_a_coarse_alpha_over_a_cluster_of_small_holes_points_to_the_graded_mesh():
    """100 holes of radius 0.05 in a 2 x 2 patch of a 10 x 10 plate, alpha 2: the
    conforming samples of the holes crowd the complex (309 points within 2 alpha of one,
    the laser sheets of bench/fixed_alpha.py at extent / 20 likewise), which refuses
    them; the message names the graded mesh with alpha as its cap, which is certified."""
    holes = shapely.union_all([Point(4 + 0.2 * (i % 10), 4 + 0.2 * (i // 10)).buffer(
        0.05, quad_segs=4) for i in range(100)])
    region = pds.Region.from_shapely(box(0, 0, 10, 10).difference(holes))
    with pytest.raises(pds.BudgetError, match=r"graded=True \(pds-mesh --graded\)"):
        pds.mesh_region(region, 2.0)
    mesh = pds.mesh_region(region, 2.0, graded=True)
    assert mesh.certificate().ok and mesh.certificate().betti_mesh == (1, 100)
