"""silenced(): output that C and C++ code writes straight to the descriptors stays off the
terminal, shown here with MeshLab's own chatter (qhull's report)."""

import ctypes
import os
import sys

import numpy as np
import pytest

pymeshlab = pytest.importorskip("pymeshlab")
from pds_plugin.silence import silenced  # noqa: E402


def _qhull_chatter():
    """A real MeshLab call that prints from C++ (qhull's report on stderr)."""
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(np.random.default_rng(0).random((10, 3))), "cloud")
    ms.generate_alpha_shape()
    ctypes.CDLL(None).fflush(None)


@pytest.mark.skipif(sys.platform == "win32", reason="C stdio flush through ctypes")
def test_silenced_keeps_meshlab_chatter_off_the_terminal(capfd):
    _qhull_chatter()
    out, err = capfd.readouterr()
    assert "facets" in out + err                   # the chatter is real ...
    with silenced():
        _qhull_chatter()
        os.write(1, b"fd 1 inside\n")
        os.write(2, b"fd 2 inside\n")
    assert capfd.readouterr() == ("", "")          # ... and silenced
    print("after")
    os.write(2, b"fd 2 after\n")
    assert capfd.readouterr() == ("after\n", "fd 2 after\n")   # and restored


def test_silenced_restores_the_descriptors_after_an_error(capfd):
    with pytest.raises(RuntimeError):
        with silenced():
            raise RuntimeError("inside")
    os.write(1, b"still here\n")
    assert capfd.readouterr().out == "still here\n"
