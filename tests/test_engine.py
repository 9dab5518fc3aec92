"""The compiled kernels: thread count setting, and results independent of it."""

import os
import subprocess
import sys

import numpy as np
import pytest
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin import _parallel


@pytest.fixture
def threads():
    """Restore the thread setting after the test."""
    previous = _parallel.get_threads()
    yield _parallel
    _parallel.set_threads(previous)


def test_default_is_the_available_cores_when_built_with_openmp(threads):
    threads.set_threads(None)
    expected = int(os.environ.get("PDS_THREADS") or threads.available_cores())
    assert threads.get_threads() == (expected if threads.openmp else 1)


@pytest.mark.parametrize("bad", [0, -2, "two", 1.5j])
def test_bad_thread_counts_are_refused(threads, bad):
    with pytest.raises(ValueError, match="positive integer"):
        threads.set_threads(bad)


def test_environment_variable_sets_the_threads():
    code = "from pds_plugin import _parallel; print(_parallel.get_threads(), _parallel.openmp)"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            env={**os.environ, "PDS_THREADS": "3"}, check=True)
    threads, openmp = result.stdout.split()
    assert int(threads) == (3 if openmp == "True" else 1)


@pytest.mark.parametrize("conforming", [True, False])
@pytest.mark.parametrize("n", [2_000, 60_000])
def test_same_mesh_bit_for_bit_with_one_thread_or_many(threads, n, conforming):
    region = pds.Region.from_shapely(box(0, 0, 2, 1).difference(Point(1, 0.5).buffer(0.3)))
    alpha = float(np.sqrt(0.7 * region.area / n))
    meshes = []
    for count in (1, 2, 4):
        threads.set_threads(count)
        mesh = pds.mesh_region(region, alpha, seed=5, conforming=conforming)
        meshes.append((mesh.vertices.tobytes(), mesh.faces.tobytes(),
                       mesh.quality().angles.tobytes()))
    assert meshes[0] == meshes[1] == meshes[2]


def test_same_graded_mesh_bit_for_bit_with_one_thread_or_many(threads):
    # about 8,000 samples: the field's and the refinement boxes' parallel loops run on
    # several threads (they start at 4,096 iterations)
    region = pds.Region.from_shapely(box(0, 0, 4, 2).difference(Point(1, 1).buffer(0.3)))
    meshes = []
    for count in (1, 2, 4):
        threads.set_threads(count)
        mesh = pds.mesh_region(region, 0.03, seed=5, graded=True)
        meshes.append((mesh.vertices.tobytes(), mesh.faces.tobytes()))
    assert len(mesh.vertices) > 4096
    assert meshes[0] == meshes[1] == meshes[2]
