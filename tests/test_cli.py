"""The pds-mesh command, run as a user runs it (a subprocess) and through main(argv).

Inputs: the built-in demo part (its section area is known in closed form) written as an
STL, small hand-made broken inputs, and ../shared/data when present.
"""

import json
import subprocess
import sys

import numpy as np
import pytest
import trimesh

from conftest import shared_file
from pds_plugin.cli import main
from pds_plugin.sources.demo import THICKNESS, demo_part, demo_section_area
from pds_plugin.analysis.quality import ASPECT_BOUND

PREFIX = "pds-mesh: error: "


def run(*args, cwd=None):
    """``python -m pds_plugin.cli ARGS`` in a subprocess (what the pds-mesh script runs)."""
    return subprocess.run([sys.executable, "-m", "pds_plugin.cli", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, timeout=120)


@pytest.fixture(scope="module")
def part_stl(tmp_path_factory):
    mesh = demo_part().to_mesh64()
    path = tmp_path_factory.mktemp("part") / "part.stl"
    trimesh.Trimesh(mesh.vert_properties[:, :3], mesh.tri_verts).export(path)
    return path


@pytest.fixture(scope="module")
def open_stl(tmp_path_factory):
    """A box with its +x side removed: not watertight where a z plane cuts it."""
    box = trimesh.creation.box(extents=(2, 2, 2))
    path = tmp_path_factory.mktemp("open") / "open.stl"
    box.update_faces(box.face_normals[:, 0] < 0.5)
    box.export(path)
    return path


def load_report(path):
    return json.loads(path.read_text())["sections"]


def read_ply_quality(path):
    mesh = trimesh.load_mesh(path, process=False)
    return mesh, mesh.metadata["_ply_raw"]["face"]["data"]["quality"]


def one_error_line(stderr):
    lines = stderr.strip().splitlines()
    assert len(lines) == 1, stderr
    assert lines[0].startswith(PREFIX), stderr
    return lines[0]


# --- as a user runs it ---------------------------------------------------------------

def test_help_explains_the_options_with_examples():
    result = run("--help")
    assert result.returncode == 0
    for text in ("--alpha", "--plane-origin", "--slices", "--jobs", "examples:",
                 "pds-mesh demo", "OUT_000.ply"):
        assert text in result.stdout


def test_demo_writes_a_certified_mesh_report_and_picture(tmp_path):
    out = tmp_path / "demo"
    result = run("demo", "-o", out)
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""
    assert "certificate  ok" in result.stdout and "4√3" in result.stdout
    [entry, graded] = load_report(out / "report.json")
    certificate = entry["certificate"]
    assert certificate["ok"] and certificate["topology_ok"]
    assert graded["certificate"]["ok"] and graded["certificate"]["grading"] == 0.2
    assert "graded " in result.stdout
    assert (out / "section_graded.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert certificate["max_aspect_ratio"] <= ASPECT_BOUND
    assert entry["region"]["area"] == pytest.approx(demo_section_area(), rel=1e-9)
    mesh, quality = read_ply_quality(out / "section.ply")
    assert len(mesh.faces) == entry["triangles"] and len(mesh.vertices) == entry["samples"]
    assert quality.max() <= ASPECT_BOUND
    # the file's triangles cover the section as the certificate measured
    assert mesh.area / demo_section_area() == pytest.approx(certificate["area_ratio"], rel=1e-9)
    assert (out / "section.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    solid = trimesh.load_mesh(out / "part.stl")
    assert solid.is_watertight and solid.volume == pytest.approx(
        demo_section_area() * THICKNESS, rel=1e-6)


def test_section_of_a_mesh_file_end_to_end(part_stl, tmp_path):
    out, report, picture = tmp_path / "cut.ply", tmp_path / "r.json", tmp_path / "cut.png"
    result = run(part_stl, "-o", out, "--axis", "z", "--at", "0.1", "--alpha", "0.15",
                 "--report", report, "--plot", picture, "--discs")
    assert result.returncode == 0, result.stderr
    assert "cut.ply" in result.stdout
    [entry] = load_report(report)
    # an STL stores float32 coordinates: the area is exact to about 1e-7
    assert entry["region"]["area"] == pytest.approx(demo_section_area(), rel=1e-6)
    assert entry["plane"] == {"origin": [0.0, 0.0, 0.1], "normal": [0.0, 0.0, 1.0]}
    certificate = entry["certificate"]
    assert certificate["min_separation"] >= 1 - 1e-12
    assert certificate["coverage_gap"] <= 1 + 1e-9
    assert certificate["max_aspect_ratio"] <= certificate["aspect_bound"] == ASPECT_BOUND
    assert entry["quality"]["aspect_max"] == certificate["max_aspect_ratio"]
    mesh, quality = read_ply_quality(out)
    np.testing.assert_allclose(mesh.vertices[:, 2], 0.1, atol=1e-12)    # in the plane
    assert quality.max() == pytest.approx(certificate["max_aspect_ratio"], rel=1e-12)
    assert picture.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("args, code, words", [
    (["missing.stl", "-o", "out.ply", "--axis", "z", "--alpha", "0.1"], 1, "no such file"),
    (["missing.stl", "-o", "out.ply", "--axis", "z", "--alpha", "-1"], 2, "alpha"),
])
def test_errors_are_one_line_without_traceback(tmp_path, args, code, words):
    result = run(*args, cwd=tmp_path)
    assert result.returncode == code
    assert words in one_error_line(result.stderr)
    assert result.stdout == ""


# --- through main(argv) ----------------------------------------------------------

def test_slices_are_numbered_and_evenly_spaced(part_stl, tmp_path, capsys):
    out, report = tmp_path / "slice.ply", tmp_path / "r.json"
    assert main([part_stl, "-o", out, "--plane-normal", "-2,0,0", "--slices", "3",
                 "--alpha", "0.12", "--report", report]) == 0
    assert capsys.readouterr().err == ""                 # no progress bar off a terminal
    entries = load_report(report)
    assert [e["output"] for e in entries] == [str(tmp_path / f"slice_{i:03d}.ply")
                                              for i in range(3)]
    # the middles of three equal slabs of the plate's extent [-2, 2] along the unit normal
    assert all(e["plane"]["normal"] == [-1.0, 0.0, 0.0] for e in entries)
    offsets = [np.dot(e["plane"]["origin"], e["plane"]["normal"]) for e in entries]
    np.testing.assert_allclose(offsets, [-4 / 3, 0, 4 / 3], atol=1e-12)
    for entry in entries:
        mesh = trimesh.load_mesh(entry["output"], process=False)
        assert len(mesh.faces) == entry["triangles"]
        np.testing.assert_allclose(mesh.vertices[:, 0], np.dot(entry["plane"]["origin"],
                                                               [1, 0, 0]), atol=1e-12)
        assert entry["certificate"]["quality_ok"]


def test_parallel_jobs_give_identical_files_and_reports(part_stl, tmp_path, capsys):
    reports = {}
    for jobs in (1, 2):
        folder = tmp_path / f"jobs{jobs}"
        folder.mkdir()
        assert main([part_stl, "-o", folder / "s.obj", "--axis", "y", "--at", "-0.4,0,0.7",
                     "--alpha", "0.1", "--jobs", jobs, "--report", folder / "r.json",
                     "--quiet"]) == 0
        reports[jobs] = load_report(folder / "r.json")
    assert capsys.readouterr().out == ""                 # --quiet
    for one, two in zip(reports[1], reports[2]):
        assert open(one["output"], "rb").read() == open(two["output"], "rb").read()
        one.pop("output"), two.pop("output")
        assert one == two
    assert len(reports[1]) == 3


def test_auto_alpha_keeps_every_hole(part_stl, tmp_path, capsys):
    report = tmp_path / "r.json"
    assert main([part_stl, "-o", tmp_path / "m.ply", "--axis", "z", "--alpha", "auto",
                 "--uniform", "--report", report]) == 0
    [entry] = load_report(report)
    assert entry["alpha_mode"] == "auto"
    assert entry["certificate"]["topology_ok"]
    assert entry["certificate"]["betti_mesh"] == entry["region"]["betti"] == [1, 3]
    assert entry["alpha"] <= entry["feature_size"]["value"] / 4
    assert "(auto)" in capsys.readouterr().out


def test_graded_featuretype_section_keeps_its_topology_with_fewer_vertices(tmp_path, capsys):
    stl = shared_file("featuretype.STL")
    reports = tmp_path / "uniform.json", tmp_path / "graded.json"
    assert main([stl, "-o", tmp_path / "u.ply", "--axis", "z", "--alpha", "auto", "--uniform",
                 "--report", reports[0]]) == 0
    assert main([stl, "-o", tmp_path / "g.ply", "--axis", "z", "--alpha", "auto",
                 "--grading", "0.25", "--report", reports[1]]) == 0     # implies --graded
    [uniform], [graded] = (load_report(r) for r in reports)
    certificate = graded["certificate"]
    assert certificate["ok"] and certificate["grading"] == 0.25
    assert certificate["betti_mesh"] == graded["region"]["betti"] == [2, 8]
    assert certificate["min_angle"] >= certificate["proven_angle"] > 22
    assert graded["samples"] < uniform["samples"] / 2
    assert "graded L=0.25" in capsys.readouterr().out


def test_auto_alpha_is_graded_unless_uniform_is_asked(part_stl, tmp_path, capsys):
    reports = tmp_path / "auto.json", tmp_path / "uniform.json"
    assert main([part_stl, "-o", tmp_path / "a.ply", "--axis", "z", "--alpha", "auto",
                 "--report", reports[0]]) == 0
    assert main([part_stl, "-o", tmp_path / "u.ply", "--axis", "z", "--alpha", "auto",
                 "--uniform", "--report", reports[1]]) == 0
    [auto], [uniform] = (load_report(r) for r in reports)
    assert auto["certificate"]["ok"] and auto["certificate"]["grading"] == 0.2
    assert auto["certificate"]["betti_mesh"] == auto["region"]["betti"] == [1, 3]
    assert "grading" not in uniform["certificate"] and uniform["certificate"]["ok"]
    out = capsys.readouterr().out.splitlines()
    assert "graded L=0.2" in out[0] and "graded L=" not in out[2]


def test_a_drawing_without_alpha_gets_a_certified_graded_mesh(tmp_path):
    """``pds-mesh drawing.svg -o out.ply``: --alpha defaults to auto, a graded mesh."""
    svg = tmp_path / "ring.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 20 20">'
                   '<path fill-rule="evenodd" d="M0 0H20V20H0Z M5 5H15V15H5Z"/></svg>')
    out, report = tmp_path / "ring.ply", tmp_path / "r.json"
    assert main([svg, "-o", out, "--report", report, "-q"]) == 0
    [entry] = load_report(report)
    assert entry["alpha_mode"] == "auto" and entry["certificate"]["grading"] == 0.2
    assert entry["certificate"]["ok"] and entry["certificate"]["betti_mesh"] == [1, 1]
    assert entry["region"]["area"] == pytest.approx(300.0, rel=1e-9)
    mesh, _ = read_ply_quality(out)
    assert len(mesh.faces) == entry["triangles"]


def test_demo_without_matplotlib_skips_the_pictures_in_one_line(tmp_path):
    """A plain install (no [plot] extra): the meshes and report, no picture, one line."""
    out = tmp_path / "demo"
    blocked = ("import sys; sys.modules['matplotlib'] = None; "
               "from pds_plugin.cli import main; sys.exit(main(sys.argv[1:]))")
    result = subprocess.run([sys.executable, "-c", blocked, "demo", "-o", str(out)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    skipped = [line for line in result.stdout.splitlines() if "pictures skipped" in line]
    assert len(skipped) == 1 and 'pip install "pds_plugin[plot]"' in skipped[0]
    assert not list(out.glob("*.png"))
    [entry, graded] = load_report(out / "report.json")
    assert entry["certificate"]["ok"] and graded["certificate"]["ok"]
    assert entry["plot"] is None and (out / "section_graded.ply").exists()


@pytest.mark.parametrize("options", [["--graded"], ["--grading", "0.3"]])
def test_uniform_with_graded_is_refused(part_stl, tmp_path, capsys, options):
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", "--alpha", "auto",
                 "--uniform", *options]) == 1
    assert "--uniform and --graded/--grading" in one_error_line(capsys.readouterr().err)
    assert not (tmp_path / "o.ply").exists()


@pytest.mark.parametrize("grading", ["0", "1", "abc"])
def test_bad_grading_is_a_usage_error(part_stl, tmp_path, capsys, grading):
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", "--alpha", "auto",
                 "--graded", f"--grading={grading}"]) == 2
    assert "grading must be a number in (0, 1)" in one_error_line(capsys.readouterr().err)


def test_a_spike_thinner_than_alpha_is_an_exception_with_its_bound(tmp_path, capsys):
    """A 20-unit square with a 20° spike 6 long at alpha 3: its sides are too short to
    split beside the tip's clearance and too long for one chord. They are halved (before,
    the spike's samples were left unjoined), so the mesh conforms; the halves' samples,
    alpha from the tip, face each other across it closer than alpha, which the
    certificate now proves (before, it called them unexplained and FAILED): the warning
    names the exception and its bound, and nothing failed."""
    drawing = tmp_path / "spike.svg"
    drawing.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 40 40">'
                       '<path d="M0 0H20V8.942L26 10L20 11.058V20H0Z"/></svg>')
    assert main([drawing, "-o", tmp_path / "u.ply", "--alpha", "3"]) == 0
    warning, = capsys.readouterr().err.splitlines()
    assert warning.startswith(f"pds-mesh: warning: {tmp_path / 'u.ply'}: 2 triangles below "
                              "Theorem 1 at small features, each within its proven bound")
    assert "sharp corner at (26, 30)" in warning and "FAILED" not in warning


def test_too_large_alpha_warns_which_hole_is_lost_and_the_alpha_to_keep_it(part_stl,
                                                                           tmp_path, capsys):
    assert main([part_stl, "-o", tmp_path / "m.ply", "--axis", "z", "--alpha", "0.4",
                 "--no-conforming"]) == 0         # a conforming mesh keeps every hole
    failed, *problems = capsys.readouterr().err.splitlines()
    assert failed == f"pds-mesh: warning: {tmp_path / 'm.ply'}: certificate FAILED (topology)"
    assert problems and all(p.startswith("pds-mesh: warning: ") for p in problems)
    assert any("hole" in p and "alpha <=" in p for p in problems)


def test_featuretype_auto_mid_section_has_2_components_and_8_holes(tmp_path, capsys):
    stl = shared_file("featuretype.STL")
    report = tmp_path / "r.json"
    assert main([stl, "-o", tmp_path / "ft.ply", "--axis", "z", "--alpha", "auto",
                 "--report", report]) == 0
    [entry] = load_report(report)
    assert entry["region"]["betti"] == [2, 8]            # ../shared/data/README.md
    assert entry["certificate"]["ok"]
    assert entry["certificate"]["betti_mesh"] == [2, 8]


def test_mil_svg_needs_no_plane_and_reports_lost_holes(tmp_path, capsys):
    svg = shared_file("MIL.svg")
    report = tmp_path / "r.json"
    assert main([svg, "-o", tmp_path / "mil.ply", "--alpha", "40", "--report", report]) == 0
    [entry] = load_report(report)
    assert entry["region"]["betti"] == [1, 8]            # ../shared/data/README.md
    assert entry["plane"] == {"origin": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]}
    certificate = entry["certificate"]
    # certified at this coarse alpha: the S-shaped sides of the small holes (about 1.6
    # alpha across) get samples where a chord end does not see the region beyond its
    # chord, each pair closer than alpha an itemised exception (docs/conforming.md,
    # "Fixed alphas"); a conforming mesh keeps the holes
    assert certificate["ok_with_exceptions"] and certificate["topology_ok"]
    # the paper's complex: 40 is too coarse for the small holes
    assert main([svg, "-o", tmp_path / "mil.ply", "--alpha", "40", "--report", report,
                 "--no-conforming"]) == 0
    [entry] = load_report(report)
    assert entry["certificate"]["sampling_ok"] and entry["certificate"]["quality_ok"]
    assert not entry["certificate"]["topology_ok"]
    assert "keep it with alpha <=" in capsys.readouterr().err


def test_svg_with_holes_through_main(tmp_path, capsys):
    svg = tmp_path / "ring.svg"
    svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 20 20">'
                   '<path fill-rule="evenodd" d="M0 0H20V20H0Z M5 5H15V15H5Z"/></svg>')
    report = tmp_path / "r.json"
    assert main([svg, "-o", tmp_path / "ring.ply", "--alpha", "1", "--report", report]) == 0
    [entry] = load_report(report)
    assert entry["region"]["area"] == 300.0 and entry["region"]["betti"] == [1, 1]
    assert entry["certificate"]["ok"]


def test_dxf_drawing_needs_no_plane_and_reads_the_layers_asked(tmp_path):
    import ezdxf

    doc = ezdxf.new(units=4)
    doc.layers.add("PLATE")
    doc.layers.add("HOLE")
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (20, 0), (20, 10), (0, 10)], close=True,
                       dxfattribs={"layer": "PLATE"})
    msp.add_lwpolyline([(5, 3), (9, 3), (9, 7), (5, 7)], close=True, dxfattribs={"layer": "HOLE"})
    drawing = tmp_path / "plate.dxf"
    doc.saveas(drawing)
    report = tmp_path / "r.json"
    assert main([drawing, "-o", tmp_path / "plate.ply", "--alpha", "auto",
                 "--report", report]) == 0
    [entry] = load_report(report)
    assert entry["region"]["area"] == 184.0 and entry["region"]["betti"] == [1, 1]
    assert entry["certificate"]["ok"] and entry["certificate"]["betti_mesh"] == [1, 1]
    assert main([drawing, "-o", tmp_path / "solid.ply", "--alpha", "1", "--layer", "plate",
                 "--report", report]) == 0
    [entry] = load_report(report)
    assert entry["region"]["area"] == 200.0 and entry["region"]["betti"] == [1, 0]


@pytest.fixture
def bad_inputs(tmp_path, part_stl, open_stl):
    (tmp_path / "garbage.stl").write_text("this is not a mesh\n")
    (tmp_path / "notes.txt").write_text("hello\n")
    (tmp_path / "empty.svg").write_text('<svg xmlns="http://www.w3.org/2000/svg" '
                                        'viewBox="0 0 10 10"></svg>')
    (tmp_path / "text.dxf").write_text("this is not a drawing\n")
    return {"part": part_stl, "open": open_stl, "dir": tmp_path, "dxf": tmp_path / "text.dxf",
            "garbage": tmp_path / "garbage.stl", "txt": tmp_path / "notes.txt",
            "svg": tmp_path / "empty.svg", "missing": tmp_path / "missing.stl"}


@pytest.mark.parametrize("what, args, code, words", [
    ("missing file", ["{missing}", "--axis", "z"], 1, "no such file"),
    ("a directory", ["{dir}", "--axis", "z"], 1, "is a directory"),
    ("unreadable mesh", ["{garbage}", "--axis", "z"], 1, "no triangles"),
    ("unknown format", ["{txt}", "--axis", "z"], 1, "not supported"),
    ("zero normal", ["{part}", "--plane-normal", "0,0,0"], 2, "zero vector"),
    ("unparsable plane", ["{part}", "--plane-normal", "0,a,1"], 2, "comma-separated"),
    ("two numbers", ["{part}", "--plane-origin", "0,1", "--axis", "z"], 2, "three"),
    ("no plane", ["{part}"], 1, "--axis or --plane-normal"),
    ("plane misses", ["{part}", "--axis", "z", "--at", "3"], 1, "misses the solid"),
    ("open mesh", ["{open}", "--axis", "z"], 1, "not watertight"),
    ("empty svg", ["{svg}"], 1, "nothing to mesh"),
    ("svg and plane", ["{svg}", "--axis", "z"], 1, "already planar"),
    ("dxf and plane", ["{dxf}", "--at", "1"], 1, "DXF drawing, which is already planar"),
    ("not a dxf", ["{dxf}"], 1, "cannot read"),
    ("layer of an svg", ["{svg}", "--layer", "0"], 1, "--layer selects layers of a DXF"),
    ("slices and origin", ["{part}", "--axis", "z", "--slices", "2", "--plane-origin",
                           "0,0,0"], 1, "--slices"),
    ("slices and at", ["{part}", "--axis", "z", "--slices", "2", "--at", "0"], 2,
     "not allowed with"),
    ("zero slices", ["{part}", "--axis", "z", "--slices", "0"], 2, "positive integer"),
])
def test_bad_inputs_get_one_clear_line(bad_inputs, capsys, what, args, code, words):
    args = [a.format(**bad_inputs) for a in args]
    out = bad_inputs["dir"] / "out.ply"
    assert main([*args, "-o", out, "--alpha", "0.2"]) == code, what
    captured = capsys.readouterr()
    assert words in one_error_line(captured.err), what
    assert not out.exists()


@pytest.mark.parametrize("alpha", ["0", "-0.5", "abc", "nan", "inf"])
def test_bad_alpha_is_a_usage_error(part_stl, tmp_path, capsys, alpha):
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", f"--alpha={alpha}"]) == 2
    assert "positive number or 'auto'" in one_error_line(capsys.readouterr().err)


def test_too_many_samples_passes_the_estimate_and_the_largest_alpha(part_stl, tmp_path,
                                                                    capsys):
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", "--alpha", "1e-6"]) == 1
    line = one_error_line(capsys.readouterr().err)
    assert "samples" in line and "alpha >=" in line
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", "--alpha", "0.05",
                 "--max-samples", "100"]) == 1
    assert "max_samples=100" in one_error_line(capsys.readouterr().err)


@pytest.mark.parametrize("output, plot, words", [
    ("out.xyz", None, "output suffix"),
    ("nowhere/out.ply", None, "does not exist"),
    ("out.ply", "picture.xyz", "picture suffix"),
])
def test_bad_outputs_are_refused_before_meshing(part_stl, tmp_path, capsys, output, plot,
                                                words):
    args = [part_stl, "-o", tmp_path / output, "--axis", "z", "--alpha", "0.1"]
    assert main(args + (["--plot", tmp_path / plot] if plot else [])) == 1
    assert words in one_error_line(capsys.readouterr().err)


def test_an_alpha_too_large_for_any_triangle_names_the_section(part_stl, tmp_path, capsys):
    out = tmp_path / "s.ply"
    # the paper's construction (a conforming mesh keeps the corners, so it has triangles)
    assert main([part_stl, "-o", out, "--axis", "z", "--at", "-0.1,0.1", "--alpha", "50",
                 "--no-conforming"]) == 1
    line = one_error_line(capsys.readouterr().err)
    assert str(tmp_path / "s_000.ply") in line and "no triangles" in line


def test_the_input_is_never_overwritten(tmp_path, capsys):
    box = tmp_path / "box.ply"
    trimesh.creation.box().export(box)
    before = box.read_bytes()
    assert main([box, "-o", box, "--axis", "z", "--alpha", "0.1"]) == 1
    assert "overwrite the input" in one_error_line(capsys.readouterr().err)
    assert box.read_bytes() == before


# --- commands: pds-mesh mesh / demo, the mesh command by default ----------------------

def test_mesh_command_is_the_default(part_stl, tmp_path, capsys):
    args = ["-o", None, "--axis", "z", "--alpha", "0.2", "-q"]
    explicit, implicit = tmp_path / "explicit.ply", tmp_path / "implicit.ply"
    assert main(["mesh", part_stl, *[explicit if a is None else a for a in args]]) == 0
    assert main([part_stl, *[implicit if a is None else a for a in args]]) == 0
    assert explicit.read_bytes() == implicit.read_bytes()


def test_a_file_named_demo_is_an_input_of_the_mesh_command(part_stl, tmp_path, capsys,
                                                            monkeypatch):
    (tmp_path / "demo").write_bytes(part_stl.read_bytes())
    monkeypatch.chdir(tmp_path)
    # the file is read as the input (trimesh needs a suffix to know an STL, so it says
    # so), not taken for the demo command
    assert main(["mesh", "demo", "-o", "cut.ply", "--axis", "z", "--alpha", "0.2"]) == 1
    assert "cannot read 'demo' as a mesh" in one_error_line(capsys.readouterr().err)
    assert not (tmp_path / "pds-demo").exists()


def test_each_command_has_its_help(capsys):
    assert main(["mesh", "--help"]) == 0
    assert "--plane-normal" in capsys.readouterr().out
    assert main(["demo", "--help"]) == 0
    out = capsys.readouterr().out
    assert "built-in CAD part" in out and "--alpha" not in out
    assert main(["demo", "--alpha", "1"]) == 2
    assert "unrecognized arguments: --alpha" in capsys.readouterr().err


def test_a_bug_keeps_its_traceback(part_stl, tmp_path, monkeypatch):
    from pds_plugin.cli import mesh as mesh_command

    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug, not bad input")
    monkeypatch.setattr(mesh_command, "mesh_region", broken)
    with pytest.raises(ZeroDivisionError, match="a bug"):
        main([part_stl, "-o", tmp_path / "x.ply", "--axis", "z", "--alpha", "0.2"])


def two_slabs(folder):
    """Two 2x2x1 slabs with nothing between z = 1 and z = 2."""
    slabs = trimesh.util.concatenate([trimesh.creation.box(extents=(2, 2, 1)).apply_translation(
        (0, 0, z)) for z in (0.5, 2.5)])
    path = folder / "slabs.stl"
    slabs.export(path)
    return path


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_failing_later_section_leaves_no_file(tmp_path, capsys, jobs):
    """The plane z = 1.5 cuts no material: the run fails and writes none of the sections
    (not part_000.ply), nor the pictures or the report."""
    slabs = two_slabs(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    status = main([slabs, "-o", out / "part.ply", "--axis", "z", "--at", "0.5,1.5,2.5",
                   "--alpha", "0.2", "--plot", out / "part.png", "--report", out / "r.json",
                   "--jobs", jobs])
    assert status == 1
    assert "cuts no material" in one_error_line(capsys.readouterr().err)
    assert list(out.iterdir()) == []


def test_a_report_path_that_is_a_folder_fails_before_any_mesh(part_stl, tmp_path, capsys):
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", "--alpha", "0.1",
                 "--report", tmp_path]) == 1
    assert "is a directory" in one_error_line(capsys.readouterr().err)
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_an_output_that_is_a_folder_is_named(part_stl, tmp_path, capsys):
    (tmp_path / "o.ply").mkdir()
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", "--alpha", "0.1"]) == 1
    assert "is a directory" in one_error_line(capsys.readouterr().err)


def test_a_negative_seed_is_a_usage_error(part_stl, tmp_path, capsys):
    """Was a ValueError traceback from numpy."""
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", "--alpha", "0.1",
                 "--seed", "-1"]) == 2
    assert "integer >= 0" in capsys.readouterr().err


@pytest.mark.parametrize("option, value", [("--slices", "1000000000"),
                                           ("--at", ",".join(["0.1"] * 10_001))])
def test_the_number_of_sections_is_bounded(part_stl, tmp_path, capsys, option, value):
    assert main([part_stl, "-o", tmp_path / "o.ply", "--axis", "z", "--alpha", "0.1", option,
                 value]) == 2
    assert "at most 10,000" in capsys.readouterr().err


def test_jobs_are_capped_at_the_cores_and_share_the_budget():
    import os
    from pds_plugin.cli.mesh import _workers

    cores = len(os.sched_getaffinity(0))
    assert _workers(1000, 50) == min(cores, 50)
    assert _workers(1000, 1) == 1 and _workers(1, 50) == 1


def process_tree(pid):
    """``pid`` and every process below it, from /proc."""
    from pathlib import Path
    found, todo = [], [pid]
    while todo:
        current = todo.pop()
        found.append(current)
        try:
            todo += map(int, Path(f"/proc/{current}/task/{current}/children").read_text().split())
        except OSError:
            pass
    return found


def alive(pid):
    from pathlib import Path
    try:
        return Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.parametrize("signum", ["SIGTERM", "SIGKILL", "SIGINT"])
def test_no_worker_outlives_pds_mesh(tmp_path, signum):
    """pds-mesh --jobs 2 stopped by a signal while meshing: its workers end too, and no
    file is left under a final name."""
    import os
    import signal
    import time

    block = tmp_path / "block.stl"
    trimesh.creation.box(extents=(4, 4, 4)).export(block)
    child = subprocess.Popen([sys.executable, "-m", "pds_plugin.cli", block, "-o", "s.ply",
                              "--axis", "z", "--slices", "4", "--alpha", "0.004", "--jobs", "2"],
                             cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    while len(process_tree(child.pid)) < 3 and time.monotonic() < deadline:
        time.sleep(0.2)
    workers = process_tree(child.pid)[1:]
    assert len(workers) >= 2, "the workers did not start"
    time.sleep(2.0)
    os.kill(child.pid, getattr(signal, signum))
    child.wait(timeout=60)
    deadline = time.monotonic() + 20
    while any(map(alive, workers)) and time.monotonic() < deadline:
        time.sleep(0.2)
    orphans = [pid for pid in workers if alive(pid)]
    for pid in orphans:
        os.kill(pid, signal.SIGKILL)
    assert orphans == []
    assert [p.name for p in tmp_path.iterdir() if not p.name.startswith(".")] == ["block.stl"]
    if signum != "SIGKILL":
        assert child.returncode == 130 and "interrupted" in child.stderr.read().decode()


def test_the_default_middle_plane_on_a_step_moves_off_it(tmp_path, capsys):
    """A stepped block has its step face at exactly half height: the automatic middle
    plane moves just above it (a warning says so); an explicit plane there needs
    --on-face."""
    import manifold3d as m3

    part = (m3.Manifold.cube((2, 2, 1)) + m3.Manifold.cube((1, 1, 1)).translate((0, 0, 1)))
    mesh = part.to_mesh64()
    block = tmp_path / "block.stl"
    trimesh.Trimesh(np.asarray(mesh.vert_properties)[:, :3], mesh.tri_verts).export(block)
    assert main([block, "-o", tmp_path / "mid.ply", "--axis", "z", "--alpha", "0.1"]) == 0
    assert "just above" in capsys.readouterr().err
    assert main([block, "-o", tmp_path / "at.ply", "--axis", "z", "--at", "1",
                 "--alpha", "0.1"]) == 1
    assert "on_face" in one_error_line(capsys.readouterr().err)
    assert main([block, "-o", tmp_path / "below.ply", "--axis", "z", "--at", "1",
                 "--alpha", "0.1", "--on-face", "below"]) == 0
    assert trimesh.load_mesh(tmp_path / "below.ply").area > 3.9     # the 2 x 2 base, not the step
