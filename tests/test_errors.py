"""Every bad input gets a PdsError (a ValueError) of the kind it is; files stay OSError."""

import io

import numpy as np
import pytest
import trimesh
from shapely.geometry import Point, Polygon, box

import pds_plugin as pds
from pds_plugin import errors


def test_the_hierarchy():
    for name in errors.__all__:
        kind = getattr(errors, name)
        assert issubclass(kind, pds.PdsError) and issubclass(kind, ValueError), name
        assert getattr(pds, name) is kind                      # public through the package
    assert issubclass(pds.ArgumentTypeError, TypeError)         # wrong-typed arguments
    assert issubclass(pds.MissingDependencyError, ImportError)  # missing optional extras
    assert issubclass(pds.SectionError, pds.SourceError)


@pytest.fixture(scope="module")
def square():
    return pds.Region.from_shapely(box(0, 0, 1, 1))


@pytest.mark.parametrize("make, kind", [
    (lambda r: pds.Region.from_shapely(Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])),
     pds.RegionError),
    (lambda r: pds.Region.from_shapely("a square"), pds.ArgumentTypeError),
    (lambda r: pds.poisson_disc(r, -1.0), pds.ArgumentError),
    (lambda r: pds.poisson_disc(r, "big"), pds.ArgumentTypeError),
    (lambda r: pds.poisson_disc(r, 1e-4, max_samples=1000), pds.BudgetError),
    # a bad seed named as such (numpy's "expected non-negative integer" and SeedSequence's
    # TypeError before)
    (lambda r: pds.poisson_disc(r, 0.1, seed=-1), pds.ArgumentError),
    (lambda r: pds.poisson_disc(r, 0.1, seed=1.5), pds.ArgumentError),
    (lambda r: pds.section_report(None, seed=0), pds.ArgumentTypeError),   # AttributeError
    # an alpha far too small: refused before anything is allocated (graded, a remesh's
    # patches: numpy's MemoryError for 119 GiB at 1e-9 before)
    (lambda r: pds.mesh_region(r, 1e-9, graded=True), pds.BudgetError),
    (lambda r: pds.remesh(trimesh.creation.box(), 1e-9), pds.BudgetError),
    (lambda r: pds.mesh_regions([r, box(1, 0, 2, 1)], 1e-9), pds.BudgetError),  # was killed
    (lambda r: pds.mesh_regions([r, box(1, 0, 2, 1)], 1e-9, graded=True), pds.BudgetError),
    # a user's sizing far below the budget's radii: its rings' densification stops
    (lambda r: pds.mesh_region(r, 0.1, sizing=lambda x, y: 0 * x + 1e-9, max_samples=1000),
     pds.BudgetError),
    # sizes float64 or trimesh's reading cannot hold (numpy's ValueError before)
    (lambda r: pds.remesh(trimesh.creation.box((1e-9, 1e-9, 1e-9))), pds.SourceError),
    (lambda r: pds.remesh(trimesh.creation.box((1e12, 1e12, 1e12))), pds.SourceError),
    (lambda r: pds.section(trimesh.load_mesh(io.BytesIO(trimesh.creation.box(
        (1e-9,) * 3).export(file_type="stl")), file_type="stl"), (0, 0, 0), (0, 0, 1)),
     pds.SourceError),
    (lambda r: pds.section(trimesh.creation.box((1e-300,) * 3), (0, 0, 0), (0, 0, 1)),
     pds.SourceError),
    (lambda r: pds.remesh(trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, np.nan, 0], [0, 0, 1]],
                                          [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
                                          process=False)), pds.SourceError),
    (lambda r: pds.solid_alpha_complex([[0, 0], [0, 0], [1, 0]], 1.0), pds.ArgumentError),
    (lambda r: pds.section(trimesh.creation.box(), (0, 0, 5), (0, 0, 1)), pds.SectionError),
    (lambda r: pds.sections(trimesh.creation.box(), (0, 0, 1), count=0), pds.ArgumentError),
    # the paper's construction loses corners and small holes at a coarse alpha (a
    # conforming mesh keeps them: docs/conforming.md)
    (lambda r: pds.mesh_region(r, 10.0, conforming=False).export("empty.ply"), pds.EmptyMeshError),
    (lambda r: pds.auto_mesh(pds.Region.from_shapely(
        Point(0, 0).buffer(1).difference(Point(0.5, 0).buffer(0.01))), max_samples=200,
        conforming=False), pds.TopologyError),
])
def test_each_bad_input_raises_its_kind(square, make, kind):
    with pytest.raises(kind):
        make(square)


def test_a_missing_directory_stays_an_oserror(square, tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        pds.mesh_region(square, 0.2).export(tmp_path / "nowhere" / "out.ply")


def test_inputs_are_never_modified(square):
    frame = np.eye(4)
    region = pds.Region.from_shapely(box(0, 0, 1, 1), frame=frame)
    assert frame.flags.writeable and not region.frame.flags.writeable
    vertices = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    on_boundary = np.ones(4, bool)
    mesh = pds.PlanarMesh(vertices, faces, on_boundary, region, 0.75)
    for given, kept in ((vertices, mesh.vertices), (faces, mesh.faces),
                        (on_boundary, mesh.on_boundary)):
        assert given.flags.writeable and not kept.flags.writeable
        assert kept is not given and np.array_equal(kept, given)
    listed = pds.PlanarMesh(vertices.tolist(), faces.tolist(), on_boundary.tolist(), region, 0.75)
    assert np.array_equal(listed.faces, mesh.faces) and listed.faces.dtype == np.int64
