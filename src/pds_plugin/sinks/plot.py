"""Pictures of a PlanarMesh with matplotlib: samples and discs, the mesh coloured by
aspect ratio, the aspect-ratio histogram (the paper's Figure 5), a one-file report and
a multiresolution strip.

Triangles are coloured on the scale of the mesh's own quality bound: 4√3 (Theorem 1)
for a uniform mesh, 4 cot θ_L for a graded one (θ_L = arcsin((1 - L)/2), docs/graded.md),
so the valid triangles of a graded mesh are not drawn as violations.

Each drawing function takes an optional matplotlib ``ax`` and returns the Axes it drew
on; without ``ax`` it opens a new pyplot figure (matplotlib picks the non-interactive
Agg backend by itself when there is no display). The functions that write a file draw on
a standalone ``matplotlib.figure.Figure``, so scripts that write thousands of reports do
not accumulate open pyplot figures.

matplotlib is an optional dependency: ``pip install "pds_plugin[plot]"``.
"""

from __future__ import annotations

import math

import numpy as np

from .._atomic import atomic_path
from .._checks import check_has_triangles, check_output_directory, import_optional
from ..analysis.quality import ASPECT_BOUND, ASPECT_EQUILATERAL
from ..errors import ArgumentError

__all__ = ["plot_samples", "plot_mesh", "plot_histogram", "plot_report",
           "plot_multiresolution"]

_CMAP = "viridis"
_OVER = "red"          # triangles above the Theorem 1 bound (none on a certified mesh)


def _matplotlib():
    return import_optional("matplotlib", "plot", "pds_plugin.sinks.plot")


def aspect_bound(mesh) -> tuple[float, str]:
    """The aspect ratio L²/A that ``mesh``'s triangles are proven to stay under, and its
    name: 4√3 for a uniform mesh (Theorem 1), 4 cot θ_L for a graded one whose radius
    field is L-Lipschitz (θ_L = arcsin((1 - L)/2)).

    Parameters
    ----------
    mesh : PlanarMesh

    Returns
    -------
    (float, str)

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> square = pds.Region.from_shapely(box(0, 0, 1, 1))
    >>> aspect_bound(pds.mesh_region(square, 0.2))[1]
    '4√3'
    >>> bound, name = aspect_bound(pds.mesh_region(square, 0.2, graded=True, grading=0.2))
    >>> round(bound, 2), name
    (9.17, '4 cot θ_L')
    """
    field = getattr(mesh, "field", None)
    if field is None:
        return ASPECT_BOUND, "4√3"
    from ..sizing import angle_bound
    return 4 / math.tan(math.radians(angle_bound(field.grading))), "4 cot θ_L"


def _new_axes(ax):
    if ax is not None:
        return ax
    _matplotlib()
    import matplotlib.pyplot as plt
    return plt.subplots(figsize=(6, 6), layout="constrained")[1]


def _figure(**kwargs):
    """A standalone Figure (not registered with pyplot) for functions that write files."""
    _matplotlib()
    from matplotlib.figure import Figure
    return Figure(layout="constrained", **kwargs)


def _panel_size(region, panels: int, extra_width: float = 0.0, width: float = 4.5):
    """figsize for ``panels`` equal-aspect views of ``region`` side by side."""
    x0, y0, x1, y1 = region.bounds
    height = float(np.clip(width * (y1 - y0) / (x1 - x0), 0.4 * width, 2.0 * width)) + 1.3
    return (width * panels + extra_width, height)


def _draw_outline(ax, region):
    from matplotlib.collections import LineCollection

    rings = [np.vstack([ring, ring[:1]]) for ring in region.rings]
    outline = LineCollection(rings, colors="black", linewidths=1.0, zorder=3,
                             label="region boundary")
    ax.add_collection(outline)
    return outline


def _square_view(ax, region):
    x0, y0, x1, y1 = region.bounds
    pad = 0.03 * max(x1 - x0, y1 - y0)
    ax.set_xlim(x0 - pad, x1 + pad)
    ax.set_ylim(y0 - pad, y1 + pad)
    ax.set_aspect("equal")


def plot_samples(mesh, discs: bool = False, ax=None, markersize: float | None = None):
    """Draw the region's outline and the samples, boundary samples marked.

    With ``discs=True`` every sample also gets its disc of radius ``alpha`` (its own
    radius r(p) on a graded mesh; one
    EllipseCollection, fast for 10⁵ samples): by maximality the discs cover the region,
    and by the Poisson condition no disc contains another sample. ``markersize`` is the
    scatter size in points² (by default smaller for many samples; raise it for a zoom).

    Parameters
    ----------
    mesh : PlanarMesh
    discs : bool
    ax : matplotlib.axes.Axes, optional
        Draw there; a new pyplot figure otherwise.
    markersize : float, optional

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.2)
    >>> ax = plot_samples(mesh, discs=True)
    """
    ax = _new_axes(ax)
    from matplotlib.collections import EllipseCollection

    from matplotlib.patches import Circle

    points, on_boundary = np.asarray(mesh.vertices), np.asarray(mesh.on_boundary, dtype=bool)
    handles = [_draw_outline(ax, mesh.region)]
    size = markersize if markersize is not None else (12 if len(points) < 2000 else 3)
    for where, colour, name in ((~on_boundary, "tab:blue", "interior"),
                                (on_boundary, "tab:orange", "boundary")):
        handles.append(ax.scatter(*points[where].T, s=size, c=colour, linewidths=0, zorder=4,
                                  label=f"{name} samples ({np.count_nonzero(where)})"))
    if discs:
        style = dict(facecolor="tab:blue", edgecolor="tab:blue", alpha=0.12, linewidth=0.5)
        field = getattr(mesh, "field", None)
        if field is None:
            diameter, label = np.full(len(points), 2 * mesh.alpha), f"α = {mesh.alpha:.3g}"
        else:                                   # graded: each sample's own radius r(p)
            diameter, label = 2 * field(points), f"r(p) ≤ α = {mesh.alpha:.3g}"
        ax.add_collection(EllipseCollection(diameter, diameter, 0.0, units="xy", offsets=points,
                                            offset_transform=ax.transData, **style))
        # legends cannot draw an EllipseCollection: show one disc instead
        handles.append(Circle((0, 0), 1, label=f"discs of radius {label}", **style))
    _square_view(ax, mesh.region)
    ax.set_title(f"{len(points)} samples, α = {mesh.alpha:.3g}")
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.06), ncols=2,
              fontsize="small", frameon=False)
    return ax


def _draw_mesh(ax, mesh, bound: float):
    """The triangles as one PolyCollection coloured by L²/A on [4/√3, bound]."""
    import matplotlib
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize

    check_has_triangles(mesh, "to plot")
    aspect = mesh.quality().aspect_ratio
    cmap = matplotlib.colormaps[_CMAP].with_extremes(over=_OVER)
    triangles = PolyCollection(np.asarray(mesh.vertices)[np.asarray(mesh.faces)],
                               array=aspect, cmap=cmap,
                               norm=Normalize(ASPECT_EQUILATERAL, bound),
                               edgecolors="black", linewidths=0.15 if len(aspect) < 20000 else 0.0)
    ax.add_collection(triangles)
    _draw_outline(ax, mesh.region)
    _square_view(ax, mesh.region)
    return triangles


def _colorbar(figure, mappable, axes, meshes, bound: float, name: str):
    above = any(mesh.quality().aspect_ratio.max() > bound for mesh in meshes)
    bar = figure.colorbar(mappable, ax=axes, extend="max" if above else "neither")
    step = 1 if bound < 8 else 2
    between = [v for v in range(3, math.ceil(bound), step) if bound - v > 0.4 * step]
    bar.set_ticks([ASPECT_EQUILATERAL, *between, bound],
                  labels=["4/√3", *map(str, between), name])
    bar.set_label("aspect ratio L²/A")
    return bar


def plot_mesh(mesh, ax=None):
    """Draw the triangles coloured by aspect ratio L²/A over [4/√3, bound], with a colorbar.

    The bound is the mesh's own (:func:`aspect_bound`: 4√3, or 4 cot θ_L for a graded
    mesh); triangles above it (none on a certified mesh) are drawn in red. The
    region's outline is drawn on top, so lost holes or bridged gaps show.

    Parameters
    ----------
    mesh : PlanarMesh
    ax : matplotlib.axes.Axes, optional
        Draw there; a new pyplot figure otherwise.

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.2)
    >>> ax = plot_mesh(mesh)
    """
    ax = _new_axes(ax)
    bound, name = aspect_bound(mesh)
    triangles = _draw_mesh(ax, mesh, bound)
    _colorbar(ax.figure, triangles, ax, [mesh], bound, name)
    ax.set_title(f"{len(mesh.faces)} triangles, α = {mesh.alpha:.3g}")
    return ax


def plot_histogram(mesh, ax=None, bins: int = 20):
    """Histogram of the aspect ratio L²/A with its statistics (the paper's Figure 5).

    The bounds 4/√3 (equilateral) and the mesh's own (:func:`aspect_bound`: 4√3 by
    Theorem 1, 4 cot θ_L for a graded mesh) are marked; the mean, standard deviation,
    minimum and maximum are in the title. The bins span [4/√3, bound], widened
    to include any value outside it, so a violation of the bound is visible.

    Parameters
    ----------
    mesh : PlanarMesh
    ax : matplotlib.axes.Axes, optional
        Draw there; a new pyplot figure otherwise.
    bins : int

    Returns
    -------
    matplotlib.axes.Axes

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.2)
    >>> ax = plot_histogram(mesh)
    """
    check_has_triangles(mesh, "to plot")
    ax = _new_axes(ax)
    aspect = mesh.quality().aspect_ratio
    stats = mesh.quality().stats()
    bound, name = aspect_bound(mesh)
    lo = min(ASPECT_EQUILATERAL, stats["aspect_min"])
    hi = max(bound, stats["aspect_max"])
    ax.hist(aspect, bins=bins, range=(lo, hi), color="tab:blue", edgecolor="white")
    ax.axvline(ASPECT_EQUILATERAL, color="tab:green", linestyle="--",
               label=f"4/√3 ≈ {ASPECT_EQUILATERAL:.3f} (equilateral)")
    field = getattr(mesh, "field", None)
    proof = "Theorem 1 bound" if field is None else f"graded bound, L = {field.grading:g}"
    ax.axvline(bound, color="tab:red", linestyle="--", label=f"{name} ≈ {bound:.3f} ({proof})")
    ax.set_xlabel("aspect ratio L²/A")
    ax.set_ylabel("triangles")
    ax.set_title(f"{stats['triangles']} triangles: mean {stats['aspect_mean']:.3f}, "
                 f"std {stats['aspect_std']:.3f}\nmin {stats['aspect_min']:.3f}, "
                 f"max {stats['aspect_max']:.3f}")
    ax.legend(loc="upper right", fontsize="small")
    return ax


def plot_report(mesh, path, discs: bool = False, dpi: int = 120):
    """Write one image with the samples, the mesh and the histogram side by side.

    This is what ``pds-mesh --plot`` writes. The format follows the suffix of ``path``
    (PNG, SVG, PDF, … whatever matplotlib writes).

    Parameters
    ----------
    mesh : PlanarMesh
    path : str or os.PathLike
    discs : bool
        Also draw each sample's disc of radius alpha.
    dpi : int

    Returns
    -------
    matplotlib.figure.Figure
        The standalone figure that was saved.

    Raises
    ------
    FileNotFoundError
        If the parent directory of ``path`` does not exist.
    EmptyMeshError
        If the mesh has no triangles.

    Examples
    --------
    >>> import tempfile, pathlib, pds_plugin as pds
    >>> from shapely.geometry import box
    >>> mesh = pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), alpha=0.2)
    >>> figure = plot_report(mesh, pathlib.Path(tempfile.mkdtemp()) / "report.png")
    """
    path = check_output_directory(path)
    check_has_triangles(mesh, "to plot")
    figure = _figure(figsize=_panel_size(mesh.region, 3, extra_width=1.0, width=5.0))
    samples_ax, mesh_ax, histogram_ax = figure.subplots(1, 3, width_ratios=[1, 1.2, 1])
    plot_samples(mesh, discs=discs, ax=samples_ax)
    plot_mesh(mesh, ax=mesh_ax)
    plot_histogram(mesh, ax=histogram_ax)
    with atomic_path(path) as partial:          # never a half-written picture
        figure.savefig(partial, dpi=dpi)
    return figure


def plot_multiresolution(meshes, path=None, dpi: int = 120):
    """Draw several meshes of one region side by side, one colorbar for all.

    The paper's multiresolution view (Figure 6): each panel shows the mesh at its
    ``alpha``, coloured by aspect ratio, with the region's outline on top so that the
    holes and walls a coarse ``alpha`` loses stand out. The colour scale ends at the
    largest of the meshes' bounds (:func:`aspect_bound`).

    Parameters
    ----------
    meshes : sequence of PlanarMesh
        Drawn left to right in the order given (coarse to fine reads best), so
        ``figure.axes[i]`` shows ``meshes[i]``; the colorbar is the last Axes.
    path : str or Path, optional
        Write the image there (standalone figure); otherwise open a pyplot figure.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ArgumentError
        If ``meshes`` is empty.
    EmptyMeshError
        If a mesh has no triangles.
    FileNotFoundError
        If the parent directory of ``path`` does not exist.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> region = pds.Region.from_shapely(box(0, 0, 1, 1))
    >>> figure = plot_multiresolution([pds.mesh_region(region, a) for a in (0.3, 0.1)])
    """
    meshes = list(meshes)
    if not meshes:
        raise ArgumentError("plot_multiresolution needs at least one mesh")
    for mesh in meshes:
        check_has_triangles(mesh, "to plot")
    size = dict(figsize=_panel_size(meshes[0].region, len(meshes), extra_width=1.0))
    if path is None:
        _matplotlib()
        import matplotlib.pyplot as plt
        figure = plt.figure(layout="constrained", **size)
    else:
        path = check_output_directory(path)
        figure = _figure(**size)
    axes = np.atleast_1d(figure.subplots(1, len(meshes)))
    bound, name = max(aspect_bound(mesh) for mesh in meshes)
    for ax, mesh in zip(axes, meshes):
        triangles = _draw_mesh(ax, mesh, bound)
        ax.set_title(f"α = {mesh.alpha:.3g}\n{len(mesh.vertices)} samples, "
                     f"{len(mesh.faces)} triangles")
    _colorbar(figure, triangles, list(axes), meshes, bound, name)
    if path is not None:
        with atomic_path(path) as partial:          # never a half-written picture
            figure.savefig(partial, dpi=dpi)
    return figure
