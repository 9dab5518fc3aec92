"""The paper's Figure 6: multiresolution meshes of two regions, and what their topology
certificates say.

(a)-(c) A disc with two circular holes whose radii differ by a factor of four. With alpha
half the larger radius the mesh has only the larger hole; with alpha half the smaller
radius it has both (Theorem 2).

(d)-(f) A disc with one hole made of two equal circles joined by a thin rectangular pipe.
With alpha half the circles' radius the mesh has the two circles but closes the pipe, so
the certificate reports the hole split in two and where; with alpha half the pipe's height
the whole hole is recovered.

    python examples/figure6.py [OUTPUT_DIR]      # default: docs/figures

Writes figure6_two_holes.png and figure6_pipe.png.
"""

import sys
from pathlib import Path

import matplotlib.pyplot as plt
import shapely
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.sinks.plot import plot_multiresolution

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"

BIG, SMALL = 0.4, 0.1                  # hole radii, a factor of four apart
CIRCLE, PIPE = 0.25, 0.06              # the second hole: circle radius, pipe height


def two_holes():
    disc = Point(0, 0).buffer(1, quad_segs=64)
    holes = Point(-0.35, 0).buffer(BIG, quad_segs=64).union(Point(0.5, 0).buffer(SMALL, quad_segs=32))
    return pds.Region.from_shapely(disc.difference(holes))


def pipe_hole():
    disc = Point(0, 0).buffer(1, quad_segs=64)
    hole = shapely.union_all([Point(-0.5, 0).buffer(CIRCLE, quad_segs=64),
                              Point(0.5, 0).buffer(CIRCLE, quad_segs=64),
                              box(-0.5, -PIPE / 2, 0.5, PIPE / 2)])
    return pds.Region.from_shapely(disc.difference(hole))


def draw(name, region, alphas, out_dir, seed=0):
    """Mesh at each alpha, print the topology reports, write the strip; return reports."""
    meshes = [pds.mesh_region(region, alpha, seed=seed, conforming=False) for alpha in alphas]
    reports = [pds.topology_report(mesh) for mesh in meshes]
    figure = plot_multiresolution(meshes)
    for ax, mesh, report in zip(figure.axes, meshes, reports):
        verdict = "topology ok" if report.topology_ok else "topology lost"
        ax.set_title(f"{ax.get_title()}\nmesh (b0, b1) = {report.betti_mesh}, "
                     f"region {report.betti_region}: {verdict}", fontsize="medium")
    path = out_dir / f"figure6_{name}.png"
    figure.savefig(path, dpi=70)
    plt.close(figure)
    for alpha, report in zip(alphas, reports):
        print(f"{name}, alpha {alpha:.4g}: {report}")
    return path, reports


def main(out_dir: Path = OUT) -> dict:
    out_dir.mkdir(parents=True, exist_ok=True)
    results = {}
    results["two_holes"] = draw("two_holes", two_holes(), [BIG / 2, SMALL / 2], out_dir)
    results["pipe"] = draw("pipe", pipe_hole(), [CIRCLE / 2, PIPE / 2], out_dir)
    return results


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
