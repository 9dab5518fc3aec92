"""The paper's Figure 1: a two-component region (tragedy and comedy masks) sampled
coarse and fine, and a zoom on the samples with their Poisson discs.

    python examples/figure1.py [OUTPUT_DIR]      # default: docs/figures

Writes figure1.png. Every sample's disc of radius alpha contains no other sample
(Poisson condition) and the discs cover the region (maximality).
"""

import sys
from pathlib import Path

import shapely
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle
from shapely import affinity
from shapely.geometry import Point

import pds_plugin as pds
from pds_plugin.sinks.plot import plot_samples

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"


def mask(x: float, smile: bool):
    """An oval face with two eye holes and a crescent mouth hole, centred at (x, 0)."""
    face = affinity.scale(Point(0, 0).buffer(1.0, quad_segs=32), 0.8, 1.0)
    eyes = [affinity.scale(Point(dx, 0.3).buffer(0.17, quad_segs=16), 1.3, 0.8) for dx in (-0.3, 0.3)]
    # the mouth: a crescent between two circles, a smile (comedy) or a frown (tragedy)
    bend = 1 if smile else -1
    outer = Point(0, 0.15 * bend).buffer(0.5, quad_segs=32)
    inner = Point(0, 0.35 * bend).buffer(0.5, quad_segs=32)
    mouth = outer.difference(inner).intersection(shapely.box(-0.38, -1, 0.38, 1))
    mouth = affinity.translate(mouth, 0, -0.5 + 0.15 * bend)
    return affinity.translate(face.difference(shapely.union_all([*eyes, mouth])), x, 0)


def draw_region(ax, region):
    """The region filled, holes left white."""
    for polygon in region.geometry.geoms:
        ax.fill(*polygon.exterior.xy, color="0.75", linewidth=0.8, edgecolor="black")
        for ring in polygon.interiors:
            ax.fill(*ring.xy, color="white", linewidth=0.8, edgecolor="black")
    ax.set_aspect("equal")
    ax.set_axis_off()


def main(out_dir: Path = OUT, coarse: float = 0.12, fine: float = 0.03) -> dict:
    region = pds.Region.from_shapely(shapely.union_all([mask(-0.95, smile=False),
                                                        mask(0.95, smile=True)]))
    meshes = {alpha: pds.mesh_region(region, alpha, seed=1, conforming=False) for alpha in (coarse, fine)}
    figure = Figure(figsize=(16, 4.6), layout="constrained")
    axes = figure.subplots(1, 4)
    draw_region(axes[0], region)
    axes[0].set_title(f"(a) region: {region.betti[0]} components, {region.betti[1]} holes")
    plot_samples(meshes[coarse], ax=axes[1])
    axes[1].set_title(f"(b) coarse: α = {coarse}, {len(meshes[coarse].vertices)} samples")
    plot_samples(meshes[fine], ax=axes[2])
    axes[2].set_title(f"(c) fine: α = {fine}, {len(meshes[fine].vertices)} samples")
    plot_samples(meshes[fine], discs=True, ax=axes[3], markersize=25)
    # zoom on the lower edge of the comedy mask's left eye, eight discs across
    (x, y), half = (0.65, 0.16), 4 * fine
    axes[3].set_xlim(x - half, x + half)
    axes[3].set_ylim(y - half, y + half)
    axes[3].set_title("(d) zoom on the red square: Poisson discs")
    axes[2].add_patch(Rectangle((x - half, y - half), 2 * half, 2 * half, fill=False,
                                edgecolor="tab:red", linewidth=1.5, zorder=6))
    for ax in axes[1:3]:
        ax.get_legend().remove()
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "figure1.png"
    figure.savefig(path, dpi=80)
    for alpha, mesh in meshes.items():
        print(f"alpha {alpha}: {len(mesh.vertices)} samples, {len(mesh.faces)} triangles, "
              f"{pds.topology_report(mesh)}")
    return {"path": path, "region": region, "meshes": meshes}


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
