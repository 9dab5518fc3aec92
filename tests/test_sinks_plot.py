"""Pictures: the right artists with the right number of elements, and real image files."""

import sys

import numpy as np
import pytest
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.analysis.quality import ASPECT_BOUND, ASPECT_EQUILATERAL

matplotlib = pytest.importorskip("matplotlib")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import (  # noqa: E402
    EllipseCollection, LineCollection, PathCollection, PolyCollection)

from pds_plugin.sinks.plot import (  # noqa: E402
    plot_histogram, plot_mesh, plot_multiresolution, plot_report, plot_samples)


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def region():
    plate = box(0, 0, 3, 2).difference(Point(1.0, 1.0).buffer(0.5)).union(Point(4, 1).buffer(0.7))
    return pds.Region.from_shapely(plate)


@pytest.fixture(scope="module")
def mesh(region):
    return pds.mesh_region(region, alpha=0.12, seed=5)


def collections_of(ax, kind):
    return [c for c in ax.collections if type(c) is kind]


def sliver_mesh(region):
    """A hand-made mesh with one triangle far above the Theorem 1 bound."""
    vertices = np.array([[0, 0], [1, 0], [0.5, 0.05], [0.5, 1.0]])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    return pds.PlanarMesh(vertices, faces, np.zeros(4, bool), region, 1.0)


def test_plot_samples_draws_outline_samples_and_discs(mesh, region):
    ax = plot_samples(mesh, discs=True)
    (outline,) = collections_of(ax, LineCollection)
    assert len(outline.get_segments()) == len(region.rings) == 3
    interior, boundary = collections_of(ax, PathCollection)
    assert len(interior.get_offsets()) == np.count_nonzero(~mesh.on_boundary)
    assert len(boundary.get_offsets()) == np.count_nonzero(mesh.on_boundary)
    np.testing.assert_array_equal(boundary.get_offsets(), mesh.vertices[mesh.on_boundary])
    (discs,) = collections_of(ax, EllipseCollection)
    np.testing.assert_array_equal(discs.get_offsets(), mesh.vertices)
    np.testing.assert_allclose(discs.get_widths(), 2 * mesh.alpha)   # diameters: radius alpha
    assert len(ax.get_legend().get_texts()) == 4
    plain = plot_samples(mesh, markersize=30)
    assert not collections_of(plain, EllipseCollection)
    assert all((c.get_sizes() == 30).all() for c in collections_of(plain, PathCollection))


def test_plot_mesh_colours_every_triangle_by_aspect_ratio(mesh):
    fig, ax = plt.subplots()
    assert plot_mesh(mesh, ax=ax) is ax
    (triangles,) = collections_of(ax, PolyCollection)
    assert len(triangles.get_paths()) == len(mesh.faces)
    np.testing.assert_array_equal(triangles.get_array(), mesh.quality().aspect_ratio)
    assert triangles.get_clim() == (ASPECT_EQUILATERAL, ASPECT_BOUND)
    assert len(fig.axes) == 2                      # the axes and its colorbar
    assert fig.axes[1].get_ylim() == pytest.approx((ASPECT_EQUILATERAL, ASPECT_BOUND))


def test_plot_histogram_counts_every_triangle_and_marks_the_bounds(mesh):
    ax = plot_histogram(mesh, bins=15)
    heights = [bar.get_height() for bar in ax.patches]
    assert len(heights) == 15 and sum(heights) == len(mesh.faces)
    assert [line.get_xdata()[0] for line in ax.lines] == [ASPECT_EQUILATERAL, ASPECT_BOUND]
    aspect = mesh.quality().aspect_ratio
    title = ax.get_title()
    for value in (aspect.mean(), aspect.std(), aspect.min(), aspect.max()):
        assert f"{value:.3f}" in title


def test_a_violation_of_the_bound_stays_visible(region):
    sliver = sliver_mesh(region)
    assert sliver.quality().aspect_ratio.max() > ASPECT_BOUND
    ax = plot_histogram(sliver)
    assert ax.patches[-1].get_x() + ax.patches[-1].get_width() == pytest.approx(
        sliver.quality().aspect_ratio.max())
    assert ax.patches[-1].get_height() == 1
    fig, ax = plt.subplots()
    plot_mesh(sliver, ax=ax)
    assert fig.axes[1].get_label() == "<colorbar>"
    assert any(patch.get_facecolor()[:3] == matplotlib.colors.to_rgb("red")
               for patch in fig.axes[1].patches)   # the colorbar's "over" arrow


def test_plot_report_writes_a_png(mesh, tmp_path):
    path = tmp_path / "report.png"
    figure = plot_report(mesh, path, discs=True, dpi=80)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20_000
    image = matplotlib.image.imread(path)
    width, height = figure.get_size_inches() * 80
    assert image.shape[:2] == (round(height), round(width))
    assert image.shape[1] > 2 * image.shape[0]     # three panels side by side
    assert len(np.unique(image.reshape(-1, image.shape[2]), axis=0)) > 100   # not blank
    assert len(figure.axes) == 4                   # samples, mesh, histogram, colorbar
    assert figure not in map(plt.figure, plt.get_fignums())   # not left open in pyplot


def test_plot_multiresolution_strip(region, tmp_path):
    meshes = [pds.mesh_region(region, alpha, seed=0) for alpha in (0.1, 0.4, 0.2)]
    figure = plot_multiresolution(meshes, tmp_path / "strip.png", dpi=60)
    assert (tmp_path / "strip.png").stat().st_size > 10_000
    panels = figure.axes[:3]
    assert [ax.get_title().split("\n")[0] for ax in panels] == ["α = 0.1", "α = 0.4", "α = 0.2"]
    counts = [len(collections_of(ax, PolyCollection)[0].get_paths()) for ax in panels]
    assert counts == [len(m.faces) for m in meshes]       # figure.axes[i] shows meshes[i]
    assert len(figure.axes) == 4                   # one shared colorbar
    interactive = plot_multiresolution(meshes[:1])
    assert plt.fignum_exists(interactive.number)


def test_plot_errors(mesh, region, tmp_path):
    empty = pds.PlanarMesh(np.array(mesh.vertices[:3]), np.empty((0, 3), dtype=np.int64),
                           np.array(mesh.on_boundary[:3]), region, mesh.alpha)
    for draw in (plot_mesh, plot_histogram):
        with pytest.raises(ValueError, match="no triangles"):
            draw(empty)
    with pytest.raises(ValueError, match="no triangles"):
        plot_report(empty, tmp_path / "r.png")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        plot_report(mesh, tmp_path / "missing" / "r.png")
    with pytest.raises(ValueError, match="at least one mesh"):
        plot_multiresolution([])


def test_missing_matplotlib_names_the_extra(mesh, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    with pytest.raises(ImportError, match=r'pip install "pds_plugin\[plot\]"'):
        plot_report(mesh, "report.png")


# --- graded meshes: drawn on their own bound -----------------------------------------

@pytest.fixture(scope="module")
def graded(region):
    return pds.mesh_region(region, alpha=0.4, seed=5, graded=True, grading=0.3)


def graded_bound(grading):
    """4 cot θ_L with θ_L = arcsin((1 - L)/2), docs/graded.md section 2."""
    return 4 / np.tan(np.arcsin((1 - grading) / 2))


def test_graded_mesh_is_coloured_up_to_its_own_bound(graded):
    bound = graded_bound(0.3)
    assert graded.certificate().ok and bound > ASPECT_BOUND
    fig, ax = plt.subplots()
    plot_mesh(graded, ax=ax)
    (triangles,) = collections_of(ax, PolyCollection)
    assert triangles.get_clim() == pytest.approx((ASPECT_EQUILATERAL, bound))
    bar = fig.axes[1]
    assert bar.get_ylim() == pytest.approx((ASPECT_EQUILATERAL, bound))
    assert bar.get_yticklabels()[-1].get_text() == "4 cot θ_L"
    assert not any(patch.get_facecolor()[:3] == matplotlib.colors.to_rgb("red")
                   for patch in bar.patches)   # a certified graded mesh has no "over" arrow


def test_graded_histogram_marks_the_graded_bound(graded):
    ax = plot_histogram(graded)
    assert [line.get_xdata()[0] for line in ax.lines] == pytest.approx(
        [ASPECT_EQUILATERAL, graded_bound(0.3)])
    assert "graded bound, L = 0.3" in ax.get_legend().get_texts()[1].get_text()


def test_graded_discs_have_each_sample_its_own_radius(graded):
    ax = plot_samples(graded, discs=True)
    (discs,) = collections_of(ax, EllipseCollection)
    radius = graded.field(graded.vertices)
    np.testing.assert_allclose(discs._widths * 2, 2 * radius)   # half-widths, in data units
    assert radius.min() < 0.5 * graded.alpha          # the radius does follow the section


def test_multiresolution_of_mixed_meshes_uses_the_largest_bound(mesh, graded):
    figure = plot_multiresolution([mesh, graded])
    clims = [c.get_clim() for ax in figure.axes[:2] for c in collections_of(ax, PolyCollection)]
    assert clims == [pytest.approx((ASPECT_EQUILATERAL, graded_bound(0.3)))] * 2
