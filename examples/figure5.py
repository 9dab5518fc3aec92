"""The paper's Figure 5: two independent Poisson disc samplings of one rectangle with the
same alpha, their meshes and their aspect-ratio histograms with mean, standard deviation,
minimum and maximum. Theorem 1: every aspect ratio L²/A lies in [4/√3, 4√3].

    python examples/figure5.py [OUTPUT_DIR]      # default: docs/figures

Writes figure5.png and prints the statistics of both meshes.
"""

import sys
from pathlib import Path

from matplotlib.figure import Figure
from shapely.geometry import box

import pds_plugin as pds
from pds_plugin.sinks.plot import plot_histogram, plot_mesh

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"


def main(out_dir: Path = OUT, alpha: float = 0.06, seeds=(1, 2)) -> dict:
    region = pds.Region.from_shapely(box(0, 0, 2, 1))
    meshes = [pds.mesh_region(region, alpha, seed=seed, conforming=False) for seed in seeds]
    figure = Figure(figsize=(12, 8), layout="constrained")
    axes = figure.subplots(2, len(meshes), height_ratios=[1, 1.1])
    stats = []
    for column, (seed, mesh) in enumerate(zip(seeds, meshes)):
        plot_mesh(mesh, ax=axes[0, column])
        axes[0, column].set_title(f"seed {seed}: {len(mesh.vertices)} samples, "
                                  f"{len(mesh.faces)} triangles, α = {alpha}")
        plot_histogram(mesh, ax=axes[1, column])
        stats.append(mesh.quality().stats())
        s = stats[-1]
        print(f"seed {seed}: {s['triangles']} triangles, aspect ratio mean {s['aspect_mean']:.4f}, "
              f"std {s['aspect_std']:.4f}, min {s['aspect_min']:.4f}, max {s['aspect_max']:.4f}")
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "figure5.png"
    figure.savefig(path, dpi=70)
    return {"path": path, "meshes": meshes, "stats": stats}


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
