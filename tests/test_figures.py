"""The examples that reproduce the paper's Figures 1 and 5 run and show what the paper
says (Figure 6 is checked in test_multires.py)."""

import runpy
from pathlib import Path

import numpy as np

from pds_plugin.analysis.quality import ASPECT_BOUND, ASPECT_EQUILATERAL

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run(name, out_dir):
    return runpy.run_path(str(EXAMPLES / name))["main"](out_dir)


def is_png(path):
    return path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_figure1_two_masks_sampled_coarse_and_fine(tmp_path):
    result = run("figure1.py", tmp_path)
    assert is_png(result["path"])
    region = result["region"]
    assert region.betti == (2, 6)               # two masks, two eyes and a mouth each
    coarse, fine = result["meshes"].values()
    assert len(fine.vertices) > 10 * len(coarse.vertices)
    assert fine.certificate().topology_ok       # the fine sampling resolves both masks
    for mesh in (coarse, fine):
        assert mesh.certificate().sampling_ok   # Poisson discs, covering (panel d)


def test_figure5_two_samplings_of_a_rectangle_within_the_bounds(tmp_path):
    result = run("figure5.py", tmp_path)
    assert is_png(result["path"])
    first, second = result["meshes"]
    assert len(first.vertices) != len(second.vertices) or \
        not np.array_equal(first.vertices, second.vertices)       # independent samplings
    for stats in result["stats"]:
        assert ASPECT_EQUILATERAL - 1e-12 <= stats["aspect_min"]
        assert stats["aspect_max"] <= ASPECT_BOUND * (1 + 1e-9)   # Theorem 1
        assert stats["above_bound"] == 0
    # the two distributions agree: the quality does not depend on the sampling
    means = [s["aspect_mean"] for s in result["stats"]]
    stds = [s["aspect_std"] for s in result["stats"]]
    assert abs(means[0] - means[1]) < 0.1 * means[0] and abs(stds[0] - stds[1]) < 0.2 * stds[0]
