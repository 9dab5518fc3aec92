"""A fast slice of the real-CAD corpus of issue 20 (``bench/_cad_corpus.py``).

Sections of CAD-exported STL parts in ``../shared/data`` (skipped when absent) meshed
the corpus's three ways must be certified (``ok`` or ``ok_with_exceptions``), and the
union of the triangles must have the section's components and holes (shapely,
independently of the certificate). The whole corpus runs in ``bench/cad_corpus.py``;
the fuzz suite (tests/test_fuzz.py) draws from the rest of it.
"""

import io
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from conftest import shared_file

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
from _cad_corpus import FAST_SLICE, GENERATED_PARTS, case, generated_stl, mesh  # noqa: E402
from _hostile import betti, mesh_union  # noqa: E402

@pytest.mark.parametrize("name, mode", FAST_SLICE)
def test_sections_of_cad_exports_are_certified(name, mode):
    shared_file(name.rsplit(" ", 1)[0])
    assert_certified(name, mode)


def assert_certified(name, mode):
    """The corpus case ``name`` meshed the ``mode`` way is certified, and the union of its
    triangles has the section's components and holes."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # what the section repaired, what "auto" gave up
        region = case(name).region()
        result = mesh(region, mode)
    cert = result.certificate()
    assert cert.ok_with_exceptions, f"{name} / {mode}:\n{cert}"
    assert betti(mesh_union(result.vertices, result.faces)) == betti(region.geometry)


@pytest.mark.parametrize("name, mode", [
    # a kink (a tessellation seam) 1.25 alpha after the inflection of a long segment: the
    # kink was dropped for the inflection, and the region just past it, hidden from the
    # chord end before it, was 1.195 alpha from any sample it sees
    ("g05-torus-ring p0", "uniform auto"),
    # 35° and 17° spikes, one side a drilled hole's arc: the tip's triangle (its chords
    # opened to 51° by the arc, or its legs long beside a small r at the tip) was larger
    # than the graded complex keeps, leaving the tip sample isolated
    ("g18-cross-drilled-block p2", "graded auto"), ("g18-cross-drilled-block p4", "graded auto")])
def test_generated_sections_that_failed_are_certified(name, mode):
    assert_certified(name, mode)


def test_a_sliver_with_a_spike_by_a_pinch_is_certified():
    """shared.STL (two boxes sharing an edge) at a random plane: a sliver component 2.7
    alpha long with a 16° tip at the pinch. Its short side, too short for both corners'
    clearances, was halved after the spike's ladder had run, so its middle had no mirror
    image: the tip's triangle was too large to keep and the tip isolated."""
    import pds_plugin as pds

    path = shared_file("shared.STL")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        region = pds.section(path, (0.548614419967193, 0.5404287856088315, 0.38235093038291357),
                             (0.9712230536671947, 0.22903962138461267, -0.06531946005106569),
                             on_face="above")
        cert = mesh(region, "uniform fine").certificate()
    assert cert.ok_with_exceptions, str(cert)


@pytest.mark.parametrize("seed, name, mode", [
    # held out: a run of kinks 1.2 alpha apart lost every other one (1.075 alpha)
    (22, "g05-torus-ring p3", "uniform auto"),
    # two cracks 1e-7 wide where the bracket's fillet met its legs: alpha 1/5000 of the
    # part, 23 GB of refinement boxes along the cracks, FAILED (tests/test_tolerance.py)
    (24, "g14-bracket p1", "uniform auto"),
    # read into a Trimesh, the export's float32 noise was taken for float64: every plane
    # bent both ways between samples (tests/test_tolerance.py)
    (24, "g18-cross-drilled-block p0", "graded auto"),
    # a chord end just before a reflex vertex (a tessellation's zigzag) does not see the
    # ring just past it, beyond the chord: 1.05-1.5 r from every sample that sees it,
    # until the end moves onto the vertex (boundary_sampling.unhidden)
    (23, "g09-tube-with-bosses p2", "graded auto"), (23, "g05-torus-ring p0", "graded auto"),
    (24, "g05-torus-ring p2", "graded auto"), (24, "g13-flange p0", "graded auto"),
    # a 2.4 r side from a reflex corner to a 37° corner, too short for both clearances:
    # its one sample divides it in their ratio, and the pair across the 37° corner it
    # leaves closer than r was "unexplained"
    (24, "g07-housing p0", "graded auto"),
    # a step 0.07 alpha deep with a 37° corner, and a fold of two 4° tips 0.6 alpha
    # apart: the corner's triangle was too large to keep (its far neighbour at the
    # clearance), the tip samples isolated and their chords not mesh edges
    (24, "g07-housing p0", "uniform fine"), (24, "g07-housing p2", "uniform fine"),
    # a 9° tip whose neighbours' legs the graded sampler shortened to keep its triangle:
    # the pair across it, closer than its clearance, was "unexplained"
    (25, "g17-housing p0", "graded auto"),
    # a zigzag of kinks 0.3 alpha apart: thinning kept a convex kink and dropped the
    # reflex one beside it, which hid the ring past it (1.007 alpha); reflex kinks first
    (22, "g15-torus-ring p0", "uniform auto"),
    # a boss 0.05 alpha from a tube's 20° reflex bends: the bends' chords crossed the
    # boss, the chord polygons overlapped, samples were isolated and chords unjoined
    (28, "g09-tube-with-bosses p3", "uniform auto"),
    # a chord end 0.42 alpha before a 1.8° reflex vertex, the far end 1.025 alpha from it:
    # the wedge past the vertex was uncovered; the vertex is now a sample
    (24, "g05-torus-ring p3", "uniform auto"),
    # a wall 0.33 alpha thin between a bolt hole and the plate's edge: the hole's chord
    # of 1.7 alpha had the edge's sample across its middle, in its lens, and was not
    # joined; it now gets a rung across from that sample
    (28, "g00-bolted-plate p4", "uniform fine"),
    # a tessellation bump just past a chord end: its reflex run hid the sliver beyond the
    # chord (1.26 alpha from the far end); the end could not move along the run without
    # hiding the edge below, so the vertex ending the run is now a sample
    (31, "g10-bolted-plate p0", "uniform auto"),
    # closing a zigzag's tips as cracks, vertex by vertex, added their widths up to the
    # whole tolerance and left nothing for the simplification: the zigzag stayed and hid
    # the ring past it (1.18 alpha, 1.6 r); the simplification now keeps half of it
    (30, "g19-tube-with-bosses p4", "uniform auto"), (30, "g19-tube-with-bosses p4", "graded auto"),
    # a 1.6° reflex bend 0.2 r from a chord end hid the arc past it (1.12 r, 1.52 r from
    # every sample seen in a straight line); the end could not move onto it without
    # hiding the next chord's bend: the path around the bend is measured now
    (35, "g05-torus-ring p1", "graded auto"), (37, "g05-torus-ring p1", "graded auto"),
    # a tooth of the tessellation beyond a chord between two crossings, the arc on Q's
    # side around it (1.18 alpha in straight lines): reached along the chord now; and a
    # cut of a piece meeting the chord at an arc vertex on it made a zero-length edge
    # that no point was on the inner side of (1.47 r)
    (39, "g05-torus-ring p4", "uniform auto"), (39, "g05-torus-ring p3", "graded auto"),
    # a shaft's spike 0.66 r thin: the discs of its tip's shoulders suspended the wall
    # rule along it, r stayed the tip's, and the arc past the tip was 1.08 r from every
    # sample (tests/test_sizing.py)
    (32, "g06-shaft p4", "graded auto"),
    # a 3° tip 0.08 long beside a reflex notch (a switchback of the section): a sample
    # 0.005 across the tip from the notch's vertex was "unexplained" (its two segments
    # meet at the tip, so their distance was 0): a thin wall now, as thick as the sample
    # is from the other segment
    (39, "g07-housing p1", "uniform fine"), (44, "g17-housing p4", "uniform fine"),
    # an 11.7° tip of a bracket's sliver 0.8 alpha wide: its 1.85 alpha chord had every
    # guard blocked and was halved, which put a sample inside the tip's clearance and
    # made the tip's triangle obtuse (R = 2 alpha), the tip isolated; the chord is the
    # tip triangle's edge and is left whole
    (44, "g14-bracket p1", "uniform auto"),
    # ... but only at a convex tip: a reflex corner's triangle with its neighbours lies
    # outside the region (a shaft's notch, seed 34: the chord was left unjoined)
    (34, "g16-shaft p3", "uniform fine"),
    # a notch's vertex, the piece's only arc vertex, was its only cut: the edge from it
    # to the far chord end was that end's (1.26 alpha); cuts inside edges now
    (46, "g13-flange p2", "uniform auto"),
    # a 29° tip of a pocket: its triangle 2 % too large for the complex, the tip sample
    # isolated; the field's walls beyond the tip's disc (above) made its neighbours' r
    # smaller and its triangle one the complex keeps
    (38, "g02-pocketed-block p2", "graded auto"),
    # a fold of a hole's ring (a tip, then back 0.03 alpha, 1.4 tolerances across): the
    # chord from the crack's tip cut the fold's tip off and crossed the chord along it;
    # both tips were isolated and a dart fell 0.06 alpha from them. Chords that cross
    # their own ring now get the arc's vertex beside the crossing
    (49, "g17-housing p3", "uniform auto"), (49, "g17-housing p3", "uniform fine"),
    # a needle component with a 4° spike at each end: the second spike's ladder rewrote
    # the side both share and took the first tip's mirror pairs away; the tip's triangle
    # was too large to keep, the tip isolated. A ladder now stops short of another's rungs
    (60, "g14-bracket p3", "uniform auto"),
    # a sliver component 1.3 wide between a 35° and a 49° tip beside a flange's
    # section: every pair across it is across a spike, so "auto" took alpha 3.2 from the
    # flange's walls and two samples across the sliver were 0.39 alpha apart. A
    # component with a tip whose widest inscribed disc is narrower than every wall
    # found counts by its width now
    (72, "g13-flange p0", "uniform auto")])
def test_held_out_sections_that_failed_are_certified(monkeypatch, seed, name, mode):
    import _cad_corpus

    def forget():
        _cad_corpus.generated_stl.cache_clear()
        _cad_corpus._generated_solid.cache_clear()

    monkeypatch.setattr(_cad_corpus, "GENERATED_SEED", seed)
    forget()
    try:
        assert_certified(name, mode)
    finally:
        forget()


@pytest.mark.parametrize("alpha", [1.2, 1.4, 1.6, 2.1, 2.5, 3.0])
def test_a_needles_second_tip_keeps_its_ladder_at_fixed_alphas(monkeypatch, alpha):
    """Held-out bracket seed 60 p3: a needle with 4° and 5° tips, their shorter sides
    meeting at its blunt top, its longer side one concave arc between the tips. Each tip
    mirrored its whole shorter side onto the arc by its angle alone (as if its sides
    were straight, thinner than alpha for 28 alpha), so the first ladder reached almost
    to the second tip and left it no room: its first samples, 3.1 and 3.5 alpha away on
    its two sides, made a triangle too large to keep, the tip isolated at 30 of 50
    alphas in [0.8, 3]. A ladder stops where its spike is alpha wide."""
    import pds_plugin as pds
    import _cad_corpus

    monkeypatch.setattr(_cad_corpus, "GENERATED_SEED", 60)
    _cad_corpus.generated_stl.cache_clear()
    _cad_corpus._generated_solid.cache_clear()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            region = case("g14-bracket p3").region()
    finally:
        _cad_corpus.generated_stl.cache_clear()
        _cad_corpus._generated_solid.cache_clear()
    cert = pds.mesh_region(region, alpha, seed=0).certificate()
    assert cert.ok_with_exceptions and cert.isolated_samples == 0, str(cert)


def test_graded_coverage_in_a_chords_lens_is_an_exception_within_its_bound():
    """featuretype.STL's tilted section has a spike whose tip triangle has its
    circumcentre in the lens of a chord, where the graded sampler places no sample (one
    there would drop the chord's triangle): 1.11 r from the nearest sample. On main the
    certificate said FAILED (coverage above 1); now it is an itemised exception, proven
    at most r(x) / (1 - L). Brute force: the nearest sample that sees the point (through
    the region) is as far as the certificate says, within that bound."""
    import shapely

    shared_file("featuretype.STL")
    region = case("featuretype.STL tilt-x").region()
    cert = mesh(region, "graded auto").certificate()
    assert not cert.ok and cert.ok_with_exceptions, cert
    assert 1 < cert.lens_coverage <= 1 / (1 - cert.grading) and cert.coverage_gap <= 1
    result = mesh(region, "graded auto")
    x = np.array(cert.lens_coverage_at)
    distance = np.hypot(*(result.vertices - x).T)
    seen = [k for k in np.argsort(distance)[:20] if region.geometry.buffer(1e-9).covers(
        shapely.LineString([x, result.vertices[k]]))]
    r = result.field(x[None])[0]
    assert distance[seen[0]] / r == pytest.approx(cert.lens_coverage, rel=1e-9)
    assert "in a chord's lens" in str(cert)


@pytest.mark.parametrize("part", [GENERATED_PARTS[0], GENERATED_PARTS[9]])
def test_generated_exports_are_float32_watertight_and_placed_at_random(part):
    import trimesh

    solid = trimesh.load(io.BytesIO(generated_stl(part)), file_type="stl")
    assert solid.is_watertight and solid.volume > 0
    assert np.array_equal(solid.vertices, solid.vertices.astype(np.float32))
    # rotated before the export: no face normal is along an axis
    assert np.abs(solid.face_normals).max() < 1 - 1e-6
    assert generated_stl.__wrapped__(part) == generated_stl(part)     # seeded: same bytes


def test_the_corpus_script_counts_and_writes_what_it_measured(tmp_path):
    import cad_corpus

    shared_file("cylinder.stl")
    out = tmp_path / "benchmarks.md"
    out.write_text("# Benchmarks\n")
    records = cad_corpus.main(["--only", "cylinder.stl z4/7", "--write", "--out", str(out)])
    assert [(r["name"], r["mode"]) for r in records] == [
        ("cylinder.stl z4/7", mode) for mode in cad_corpus.MODES]
    text = out.read_text()
    assert text.startswith("# Benchmarks\n") and "<!-- section: cad-corpus -->" in text
    for mode in cad_corpus.MODES:
        row = next(line for line in text.splitlines() if line.startswith(f"| **all** | {mode} |"))
        cells = [c.strip() for c in row.split("|")[3:-2]]
        assert cells == ["1"] + [str(sum(r["verdict"] == v for r in records if r["mode"] == mode))
                                 for v in cad_corpus.VERDICTS]


def test_failure_reasons_name_the_checks_that_fail():
    import cad_corpus
    import pds_plugin as pds
    from shapely.geometry import Point

    holed = Point(0, 0).buffer(1).difference(Point(0.3, 0).buffer(0.05))
    coarse = pds.mesh_region(pds.Region.from_shapely(holed), 0.5, conforming=False)
    assert "topology: hole filled" in cad_corpus.reasons(coarse.certificate())
    fine = pds.mesh_region(pds.Region.from_shapely(holed), 0.02)
    assert cad_corpus.reasons(fine.certificate()) == []


@pytest.mark.parametrize("name, grading", [("featuretype.STL tilt-x", 0.3),
                                           ("g18-cross-drilled-block p1", 0.45)])
def test_a_chords_own_points_count_in_its_lens_when_rounding_puts_them_outside(name, grading):
    """Coverage peaks on a chord, the edge of its lens, computed a rounding off the
    chord's line on the outer side: they were measured as plain coverage (1.046 r at
    L = 0.45, and on featuretype's tilted section at L = 0.3) and the certificate said
    FAILED. They are lens points within 1e-9 of the chord's length² across it."""
    import pds_plugin as pds

    part = name.rsplit(" ", 1)[0]
    if part not in GENERATED_PARTS:
        shared_file(part)                   # skips when ../shared/data is absent
    region = case(name).region()
    cert = pds.mesh_region(region, "auto", 0, graded=True, grading=grading).certificate()
    assert cert.ok_with_exceptions, str(cert)
    assert cert.coverage_gap <= 1 + 1e-9
    assert cert.lens_coverage <= 1 / (1 - grading)
