"""Messages that used to mislead (issue 10): each bad input gets the package's error type
and a message that names the real problem and what to do."""

import gzip
import math
import subprocess
import sys

import numpy as np
import pytest
import trimesh
from shapely.geometry import box

import pds_plugin as pds

SVG = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10">{}</svg>'
PNG = b"\x89PNG\r\n\x1a\n" + bytes(200)
DXF_TEXT = "0\nSECTION\n2\nENTITIES\n0\nENDSEC\n0\nEOF\n"


@pytest.fixture(scope="module")
def square():
    return pds.Region.from_shapely(box(0, 0, 1, 1))


def write(folder, name, content):
    path = folder / name
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    return path


@pytest.mark.parametrize("name, content, read, words", [
    # was "not well-formed (invalid token): line 1, column 0"
    ("logo.svg", PNG, pds.load_svg, ["is a PNG image, not an SVG drawing", "no geometry"]),
    # was "File ... is not a DXF file."
    ("logo.dxf", PNG, pds.load_dxf, ["is a PNG image, not a DXF drawing"]),
    # was "... nor plain text (trimesh: No module named 'charset_normalizer')"
    ("logo.stl", PNG, lambda p: pds.section(p, (0, 0, 0), (0, 0, 1)),
     ["is a PNG image, not a mesh file"]),
    # was "syntax error: line 1, column 0"
    ("plate.svg", DXF_TEXT, pds.load_svg, ["is a DXF drawing, not an SVG", "load_dxf",
                                           "name it .dxf"]),
    ("plate.dxf", SVG.format('<rect width="5" height="5"/>'), pds.load_dxf,
     ["is an SVG drawing, not a DXF", "load_svg"]),
    # was "not well-formed (invalid token)"
    ("plate.svg", gzip.compress(SVG.format('<rect width="5" height="5"/>').encode()),
     pds.load_svg, ["gzip-compressed", "decompress it first"]),
    ("part.stl", SVG.format('<rect width="5" height="5"/>'),
     lambda p: pds.section(p, (0, 0, 0), (0, 0, 1)), ["is an SVG drawing, not a mesh file"]),
])
def test_a_file_of_another_kind_is_named_for_what_it_is(tmp_path, name, content, read, words):
    path = write(tmp_path, name, content)
    with pytest.raises(pds.SourceError) as caught:
        read(path)
    message = str(caught.value)
    assert "charset_normalizer" not in message and "invalid token" not in message
    for word in words:
        assert word in message


def test_an_unknown_binary_file_does_not_blame_a_missing_module(tmp_path):
    path = write(tmp_path, "part.stl", b"solid-ish?\x00\xff\xfe" + bytes(range(256)) * 2)
    with pytest.raises(pds.SourceError, match="cannot read .* as a mesh") as caught:
        pds.section(path, (0, 0, 0), (0, 0, 1))
    assert "No module named" not in str(caught.value)


def test_an_empty_binary_mesh_has_no_triangles_and_is_not_called_unreadable(tmp_path):
    """Binary meshes have NUL bytes too: only bytes no mesh format has are 'unreadable'
    (trimesh reads any bytes as text when charset_normalizer is installed)."""
    import numpy as np
    import trimesh
    empty = write(tmp_path, "empty.stl", bytes(80) + (0).to_bytes(4, "little"))
    cloud = tmp_path / "cloud.ply"
    trimesh.PointCloud(np.eye(3)).export(cloud, encoding="binary")
    for path in (empty, cloud):
        with pytest.raises(pds.SourceError, match="has no triangles") as caught:
            pds.section(path, (0, 0, 0), (0, 0, 1))
        assert "neither a valid binary mesh" not in str(caught.value)


def test_a_face_beyond_the_vertices_of_a_mesh_file_is_named(tmp_path):
    path = write(tmp_path, "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(pds.SourceError, match="a face refers to a vertex the file does not have"):
        pds.section(path, (0, 0, 0.5), (0, 0, 1))


@pytest.mark.parametrize("call", [pds.load_svg, pds.load_dxf, pds.load_drawing,
                                  lambda p: pds.mesh_region(
                                      pds.Region.from_shapely(box(0, 0, 1, 1)), 0.3).export(p)])
@pytest.mark.parametrize("path", [None, 3, b"bytes.svg"])
def test_a_path_that_is_not_a_file_name_is_a_type_error(call, path):
    # was TypeError: expected str, bytes or os.PathLike object, not NoneType
    with pytest.raises(pds.ArgumentTypeError, match="must be a file name"):
        call(path)


@pytest.mark.parametrize("frame, kind, words", [
    (np.full((4, 4), np.nan), pds.ArgumentError, "NaN or infinite"),   # was "got shape (4, 4)"
    ("xy", pds.ArgumentTypeError, "4x4 matrix of numbers"),           # was float('xy') ValueError
    (np.eye(3), pds.ArgumentError, "got shape (3, 3)"),
])
def test_a_bad_frame_says_what_is_wrong_with_it(frame, kind, words):
    with pytest.raises(kind) as caught:
        pds.Region.from_shapely(box(0, 0, 1, 1), frame=frame)
    assert words in str(caught.value)


@pytest.mark.parametrize("repair", ["yes", "no", 1, None])
def test_repair_must_be_a_bool(repair):
    # "no" used to repair (a non-empty string is truthy)
    with pytest.raises(pds.ArgumentTypeError, match="repair must be True or False"):
        pds.Region.from_shapely(box(0, 0, 1, 1), repair=repair)


def test_a_plane_touching_an_apex_is_not_said_to_miss_the_solid():
    tetrahedron = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
                                  [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    assert tetrahedron.is_watertight
    # was "the plane misses the solid: it is at normal·x = 1 but the solid spans [0, 1]"
    with pytest.raises(pds.SectionError) as caught:
        pds.section(tetrahedron, (0, 0, 1), (0, 0, 1))
    message = str(caught.value)
    assert "only touches the solid" in message and "misses" not in message
    assert "[0, 1]" in message and "strictly inside" in message
    with pytest.raises(pds.SectionError, match="misses the solid"):
        pds.section(tetrahedron, (0, 0, 1.5), (0, 0, 1))


def test_too_many_sections_are_refused_before_cutting():
    # count=10**9 used to run until memory ran out
    with pytest.raises(pds.BudgetError, match="more than 10,000"):
        pds.sections(trimesh.creation.box(), (0, 0, 1), count=10**9)
    with pytest.raises(pds.BudgetError, match="more than 10,000 sections"):
        pds.sections(trimesh.creation.box(), (0, 0, 1), np.zeros(10_001))


@pytest.mark.parametrize("faces", [[[0, 1, 5]], [[0, 1, -1]]])
def test_faces_beyond_the_vertices_are_refused(square, faces):
    vertices = np.array([[0.0, 0], [1, 0], [0, 1]])
    # triangle_quality used to read memory past the vertex array and return its garbage
    with pytest.raises(pds.ArgumentError, match=r"face 0 refers to vertex -?\d, but there are 3"):
        pds.triangle_quality(vertices, faces)
    with pytest.raises(pds.ArgumentError, match="refers to vertex"):
        pds.PlanarMesh(vertices, faces, [True] * 3, square, 0.5)


def test_a_planar_mesh_checks_its_other_arguments(square):
    vertices, faces = np.array([[0.0, 0], [1, 0], [0, 1]]), [[0, 1, 2]]
    with pytest.raises(pds.ArgumentError, match="on_boundary has 2 flags for 3 vertices"):
        pds.PlanarMesh(vertices, faces, [True] * 2, square, 0.5)
    with pytest.raises(pds.ArgumentError, match="alpha must be a positive"):
        pds.PlanarMesh(vertices, faces, [True] * 3, square, -1.0)
    with pytest.raises(pds.ArgumentTypeError, match="PlanarMesh needs a pds_plugin.Region"):
        pds.PlanarMesh(vertices, faces, [True] * 3, box(0, 0, 1, 1), 0.5)


@pytest.mark.parametrize("call, who", [(pds.topology_report, "topology_report"),
                                       (pds.meshlab_quality, "meshlab_quality"),
                                       (pds.certify, "certify")])
def test_analyses_of_something_that_is_not_a_mesh_say_so(call, who):
    # was AttributeError: 'NoneType' object has no attribute 'region'
    with pytest.raises(pds.ArgumentTypeError, match=f"{who} needs a pds_plugin.PlanarMesh, "
                                                    f"got NoneType"):
        call(None)


def test_add_section_meshes_needs_a_meshset():
    with pytest.raises(pds.ArgumentTypeError, match="needs a pymeshlab.MeshSet, got str"):
        pds.add_section_meshes("part.stl", 0.1, count=2)


def test_a_temporary_file_error_is_raised_about_the_final_name(tmp_path):
    from pds_plugin._atomic import atomic_path

    folder = tmp_path / "gone"
    folder.mkdir()
    target = folder / "report.json"
    # was "[Errno 2] No such file or directory: '.../gone/.report.3160b63fa9ca43f1.tmp.json'"
    with pytest.raises(FileNotFoundError) as caught:
        with atomic_path(target) as partial:
            folder.rmdir()                      # the folder goes away while writing
            partial.write_text("{}")
    assert f"cannot write {target}" in str(caught.value) and ".tmp" not in str(caught.value)


def test_export_to_a_folder_or_under_a_file_says_so(square, tmp_path):
    mesh = pds.mesh_region(square, 0.3)
    # was "cannot export to a path without a suffix"
    with pytest.raises(IsADirectoryError, match="it is a directory; give a file name"):
        mesh.export(tmp_path)
    afile = write(tmp_path, "notes.txt", "x")
    # was "directory .../notes.txt does not exist; create it first"
    with pytest.raises(NotADirectoryError, match="notes.txt is a file, not a directory"):
        mesh.export(afile / "out.ply")


def test_a_mesh_without_triangles_says_how_big_the_region_is(tmp_path):
    region = pds.Region.from_shapely(box(0, 0, 20, 10))
    mesh = pds.mesh_region(region, 500.0, conforming=False)    # a conforming mesh keeps the corners
    # was "PlanarMesh(vertices=1, faces=0, alpha=500) has no triangles to export (...)"
    with pytest.raises(pds.EmptyMeshError, match=r"the mesh has 1 sample and no triangles to "
                                                 r"export: alpha=500 is probably too large "
                                                 r"for the region \(it spans 20 x 10\)"):
        mesh.export(tmp_path / "never.ply")
    assert not (tmp_path / "never.ply").exists()


@pytest.mark.parametrize("body, attribute", [
    ('<rect width="5" height="5" transform="matrix(nan 0 0 1 0 0)"/>', "transform"),  # IndexError
    ('<rect width="5" height="5" transform="translate(inf 0)"/>', "transform"),  # was dropped
    ('<rect x="nan" width="5" height="5"/>', "x"),                              # was x = 0
    ('<rect width="nan" height="5"/>', "width"),                   # was "no visible shapes"
    ('<path d="M0 0 L nan 5 L 5 5 Z"/>', "d"),                     # was "zero size"
    ('<polygon points="0,0 5,inf 5,5"/>', "points"),               # was "no closed loop"
    ('<rect width="1e309" height="5"/>', "width"),                 # was "zero size"
])
def test_non_finite_svg_numbers_name_the_element_and_attribute(tmp_path, body, attribute):
    path = write(tmp_path, "drawing.svg", SVG.format(body))
    with pytest.raises(pds.SourceError, match=rf"has a <\w+> with {attribute}=.*NaN, infinite"):
        pds.load_svg(path)


def test_an_svg_transform_that_overflows_is_not_called_zero_size(tmp_path):
    path = write(tmp_path, "drawing.svg",
                 SVG.format('<rect width="5" height="5" transform="scale(1e308)"/>'))
    with pytest.raises(pds.RegionError, match="coordinates overflow float64"):
        pds.load_svg(path)


def test_the_cli_does_not_call_a_text_file_a_solid(tmp_path):
    write(tmp_path, "notes.txt", "hello")
    process = subprocess.run([sys.executable, "-m", "pds_plugin.cli", "notes.txt", "-o",
                              "out.ply", "--alpha", "0.1"], cwd=tmp_path, capture_output=True,
                             text=True)
    assert process.returncode == 1 and "Traceback" not in process.stderr
    assert "notes.txt is not a drawing (.svg, .dxf)" in process.stderr
    assert "is a solid" not in process.stderr


def test_svg_limits_are_documented_as_they_are():
    from pds_plugin.sources import _svg_limits

    doc = pds.load_svg.__doc__
    assert f"({_svg_limits.MAX_ELEMENTS:,})" in doc and f"({_svg_limits.MAX_SEGMENTS:,})" in doc
    assert math.isclose(_svg_limits.MAX_BYTES, 20e6) and "(20 MB)" in doc


@pytest.mark.parametrize("text, words", [
    # each was "... has no <svg> element: it is not an SVG drawing"
    ('<svg xmlns="http://example.com/x" viewBox="0 0 10 10"><rect width="10" height="10"/>'
     '</svg>', "in the namespace 'http://example.com/x', not SVG's"),
    ('<SVG xmlns="http://www.w3.org/2000/svg"><RECT width="10" height="10"/></SVG>',
     "element names are lower case"),
    ("<html><body>hi</body></html>", "root element is <html>, not <svg>"),
    # was "maximum recursion depth exceeded while calling a Python object"
    (SVG.format("<g>" * 10_000 + '<rect width="5" height="5"/>' + "</g>" * 10_000),
     "nested too deep"),
])
def test_an_xml_file_that_is_not_svg_says_why(tmp_path, text, words):
    with pytest.raises(pds.SourceError, match="cannot read .* as SVG") as caught:
        pds.load_svg(write(tmp_path, "drawing.svg", text))
    assert words in str(caught.value) and "recursion" not in str(caught.value)


def test_the_cli_says_an_output_that_is_a_folder_is_one(tmp_path):
    write(tmp_path, "drawing.svg", SVG.format('<rect width="10" height="10"/>'))
    (tmp_path / "meshes").mkdir()
    process = subprocess.run([sys.executable, "-m", "pds_plugin.cli", "drawing.svg", "-o",
                              "meshes", "--alpha", "1"], cwd=tmp_path, capture_output=True,
                             text=True)
    # was "cannot write meshes: the output suffix must be one of .3mf, ..."
    assert process.returncode == 1
    assert "cannot write meshes: it is a directory; give a file name" in process.stderr


@pytest.mark.parametrize("alpha", [0.1, "auto"])
def test_a_misspelt_sampling_option_is_named_with_the_nearest(square, alpha):
    # was: "poisson_disc() got an unexpected keyword argument 'maxsamples'"
    with pytest.raises(pds.ArgumentTypeError, match="no option 'maxsamples'; did you mean "
                                                    "'max_samples'"):
        pds.mesh_region(square, alpha, maxsamples=3)


def test_an_alpha_string_other_than_auto_names_auto(square):
    # was: "alpha must be a positive number", silent about 'auto'
    with pytest.raises(pds.ArgumentError, match="positive number or 'auto', got 'AUTO'"):
        pds.mesh_region(square, "AUTO")


def test_section_report_checks_its_seed(square):
    # was: accepted, and written into the report
    with pytest.raises(pds.ArgumentError, match="seed must be an integer"):
        pds.section_report(pds.mesh_region(square, 0.2), seed="x")


def test_pds_mesh_version(capsys):
    from pds_plugin.cli import main
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"pds-mesh {pds.__version__}"
