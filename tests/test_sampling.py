"""poisson_disc: the Poisson condition, exact maximality, boundary first, determinism."""

import numpy as np
import pytest
import shapely
from hypothesis import given, settings, strategies as st
from scipy import stats
from shapely.geometry import box

import pds_plugin as pds
from conftest import min_distance, probe_gap
from regions import regions, slotted_plate, wedge


def assert_maximal_poisson(region, samples, alpha):
    points = samples.points
    assert min_distance(points) >= alpha * (1 - 1e-12)
    # every sample in the (closed) region, boundary samples on the boundary
    assert shapely.distance(region.geometry, shapely.points(points)).max() <= 1e-9 * alpha
    on_edge = shapely.distance(region.geometry.boundary, shapely.points(points[samples.on_boundary]))
    assert on_edge.max(initial=0) <= 1e-9 * alpha
    assert probe_gap(region.geometry, points, alpha / 50) <= alpha * (1 + 1e-9)


@settings(max_examples=30, deadline=None)
@given(region=regions, alpha=st.floats(0.04, 0.2), seed=st.integers(0, 2**32 - 1))
def test_maximal_poisson_on_generated_regions(region, alpha, seed):
    assert_maximal_poisson(region, pds.poisson_disc(region, alpha, seed=seed), alpha)


@pytest.mark.parametrize("angle", [10, 29, 31, 59, 61, 90])
def test_sharp_corners_are_sampled_first(angle):
    region = pds.Region.from_shapely(wedge(angle))
    alpha = 0.05
    samples = pds.poisson_disc(region, alpha, seed=angle)
    assert_maximal_poisson(region, samples, alpha)
    assert (np.abs(samples.points) < 1e-15).all(axis=1).any(), "the apex is a sample"


@pytest.mark.parametrize("width", [0.1, 0.5, 0.9])
def test_slot_narrower_than_alpha_keeps_samples_apart(width):
    alpha = 0.1
    region = pds.Region.from_shapely(slotted_plate(width * alpha))
    for seed in range(3):
        assert_maximal_poisson(region, pds.poisson_disc(region, alpha, seed=seed), alpha)


def test_component_smaller_than_alpha_gets_a_sample():
    alpha = 0.2
    tiny = box(5, 5, 5 + 0.3 * alpha, 5 + 0.2 * alpha)
    region = pds.Region.from_shapely(shapely.MultiPolygon([box(0, 0, 1, 1), tiny]))
    samples = pds.poisson_disc(region, alpha, seed=3)
    assert_maximal_poisson(region, samples, alpha)
    assert shapely.intersects_xy(tiny, *samples.points.T).any()


def test_same_seed_same_bits_other_seed_other_samples():
    region = pds.Region.from_shapely(box(0, 0, 1, 1).difference(box(0.4, 0.4, 0.6, 0.6)))
    a = pds.poisson_disc(region, 0.03, seed=7)
    b = pds.poisson_disc(region, 0.03, seed=7)
    c = pds.poisson_disc(region, 0.03, seed=8)
    assert np.array_equal(a.points, b.points) and np.array_equal(a.on_boundary, b.on_boundary)
    assert len(a.points) != len(c.points) or not np.array_equal(a.points, c.points)


def test_no_grid_pattern():
    """Dart throwing is unbiased: positions inside the sampler's grid cells are uniform."""
    alpha = 0.01
    samples = pds.poisson_disc(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha, seed=0)
    cell = alpha / np.sqrt(2)
    inner = samples.points[~samples.on_boundary]
    for axis in range(2):
        phase = np.mod(inner[:, axis] / cell, 1.0)
        assert stats.kstest(phase, "uniform").pvalue > 1e-3


def test_sample_count_matches_the_estimate():
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    n = len(pds.poisson_disc(region, 0.01))
    assert 0.8 < n / pds.sampling.estimate_samples(region, 0.01) < 1.2


@pytest.mark.parametrize("alpha", [0, -1.0, float("nan"), float("inf")])
def test_bad_alpha_is_refused(alpha):
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    with pytest.raises(ValueError, match="alpha must be a positive finite number"):
        pds.poisson_disc(region, alpha)


def test_alpha_of_the_wrong_type_is_refused():
    with pytest.raises(TypeError, match="alpha must be a positive number"):
        pds.poisson_disc(pds.Region.from_shapely(box(0, 0, 1, 1)), "big")


def test_too_many_samples_is_refused_with_the_estimate_and_a_usable_alpha():
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    with pytest.raises(ValueError, match=r"about 7(\.\d+)?e\+0?7 samples.*use alpha >= 0\.0") as info:
        pds.poisson_disc(region, 1e-4, max_samples=1000)
    usable = float(info.value.args[0].split("use alpha >= ")[1].split()[0])
    assert pds.sampling.estimate_samples(region, usable) <= 1000 * 1.001
    assert len(pds.poisson_disc(region, usable, max_samples=1000)) > 0


def test_a_polygon_is_not_a_region():
    with pytest.raises(TypeError, match="Region.from_shapely"):
        pds.poisson_disc(box(0, 0, 1, 1), 0.1)


@pytest.mark.parametrize("seed", range(3))
def test_conforming_boundary_spacing_and_visible_separation(seed):
    """Consecutive boundary samples are alpha to √3 alpha apart along pieces longer than
    2 alpha, and samples closer than alpha never see each other (slot of 0.3 alpha)."""
    alpha = 0.05
    geometry = slotted_plate(0.3 * alpha)
    samples = pds.poisson_disc(pds.Region.from_shapely(geometry), alpha, seed=seed, conforming=True)
    points = samples.points
    for ring in samples.rings:
        spacing = np.linalg.norm(points[ring] - points[np.roll(ring, -1)], axis=1)
        short = spacing < alpha * (1 - 1e-12)
        assert spacing.max() <= np.sqrt(3) * alpha * (1 + 1e-12)
        assert short.sum() <= 2                   # the slot's end, 0.3 alpha wide
    from scipy.spatial import cKDTree
    pairs = cKDTree(points).query_pairs(alpha * (1 - 1e-12), output_type="ndarray")
    lines = shapely.linestrings(np.stack([points[pairs[:, 0]], points[pairs[:, 1]]], axis=1))
    seen = pairs[shapely.covers(geometry.buffer(1e-9 * alpha), lines)]
    consecutive = {tuple(sorted(e)) for ring in samples.rings
                   for e in zip(ring.tolist(), np.roll(ring, -1).tolist())}
    assert len(pairs) > len(seen)                 # close pairs across the slot exist...
    assert {tuple(sorted(e)) for e in seen.tolist()} <= consecutive   # ...only the slot's end sees
    assert shapely.distance(geometry, shapely.points(points)).max() <= 1e-9 * alpha


def test_a_runaway_refinement_stops(monkeypatch):
    """If the coverage test never certified a box (as where a conservative visibility
    test fails over a whole area), the boxes would multiply by four per level: the
    conforming sampler stops at twice the region's cells instead."""
    from pds_plugin import sampling

    counts = []

    def all_open(parent, sub_x, sub_y, size, status, domain, grid, nxt, points, alpha, vis,
                 x0, y0, s, bx, by, work):
        bx[:] = x0 + (parent % grid.shape[1]) * s + sub_x * size
        by[:] = y0 + (parent // grid.shape[1]) * s + sub_y * size
        return len(parent)

    def split_all(parent, sub_x, sub_y, bx, by, size, first, grid, nxt, points, alpha, vis,
                  child_parent, child_sub_x, child_sub_y, work):
        counts.append(len(parent))
        corner = np.arange(4 * len(parent)) % 4
        child_parent[:] = np.repeat(parent, 4)
        child_sub_x[:] = 2 * np.repeat(sub_x, 4) + corner % 2
        child_sub_y[:] = 2 * np.repeat(sub_y, 4) + corner // 2
        return len(parent)

    monkeypatch.setattr(sampling.kern, "open_boxes", all_open)
    monkeypatch.setattr(sampling.kern, "split_uncovered", split_all)
    region = pds.Region.from_shapely(box(0, 0, 1, 1))
    samples = pds.poisson_disc(region, 0.05, conforming=True)
    cells = (1 / (0.05 / np.sqrt(2)) + 3) ** 2
    assert len(samples) > 0 and max(counts) <= 4 * 2 * cells
