"""Graded ``"auto"`` vertices against the grading L, beside Triangle (issue 21's vertex
targets): how many vertices the proven angle bound θ_L = arcsin((1 - L) / 2) costs.

    python bench/grading_vertices.py             # 20 sections per shared STL part (~1 min)
    python bench/grading_vertices.py --write     # into docs/benchmarks.md

For each case (the shared STL parts' sections at evenly spaced heights, the 373-hole
drawing of bench/speed_targets.py): the mean vertex count of pds_plugin's graded
``"auto"`` mesh at L = 0.1 ... 0.4 (the default is 0.2), its ratio to Triangle ``pq30``
(no area bound, the speed targets' peer), Triangle at the same proven angle ``pq<θ_L>``,
and the 1st percentile of the triangles' smallest angles in pds_plugin's meshes. The field grows from each
feature's size at slope L (docs/graded.md, section 3), so the vertex count of a section
whose size is set by a few small features falls about as 1 / L²: that, not the sampler,
is the gap to Triangle, whose sizes follow the local feature size at a slope near 1.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

import pds_plugin as pds                                   # noqa: E402
from pds_plugin.sizing import DEFAULT_GRADING, angle_bound  # noqa: E402

from _environment import machine                           # noqa: E402
from _runners import _pslg                                 # noqa: E402
from _sections import write_section                        # noqa: E402
from speed_targets import PARTS, drawing_region, part_sections  # noqa: E402

GRADINGS = (0.1, 0.2, 0.3, 0.4)


def triangle_vertices(region, angle: float) -> int:
    import triangle

    return len(triangle.triangulate(_pslg(region), f"pq{angle:.2f}Q")["vertices"])


def pds_mesh(region, grading):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return pds.mesh_region(region, "auto", grading=grading)


def row(name, regions) -> str:
    """One table line: the case's mean vertex counts at every grading."""
    peer = np.mean([triangle_vertices(region, 30) for region in regions])
    cells = [name, f"{peer:,.0f}"]
    for grading in GRADINGS:
        meshes = [pds_mesh(region, grading) for region in regions]
        vertices = np.mean([len(mesh.vertices) for mesh in meshes])
        low = np.percentile(np.concatenate([mesh.quality().min_angle for mesh in meshes]), 1)
        same = np.mean([triangle_vertices(region, angle_bound(grading)) for region in regions])
        cells.append(f"{vertices:,.0f} ({vertices / peer:.2f}×; pq{angle_bound(grading):.1f} "
                     f"{same:,.0f}; 1 % under {low:.1f}°)")
    return "| " + " | ".join(cells) + " |"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--planes", type=int, default=20, help="sections per STL part")
    parser.add_argument("--write", action="store_true",
                        help="write the section 'graded vertices' of docs/benchmarks.md")
    args = parser.parse_args(argv)
    start = machine()
    head = ["| case | Triangle pq30 | " + " | ".join(
                f"L = {g}{' (default)' if g == DEFAULT_GRADING else ''}, θ_L = "
                f"{angle_bound(g):.1f}°" for g in GRADINGS) + " |",
            "|---|---|" + "---|" * len(GRADINGS)]
    print("\n".join(head), flush=True)
    lines = []
    cases = [(f"{part}, {args.planes} sections", part_sections(part, args.planes))
             for part in PARTS]
    cases.append(("drawing, 373 holes", [drawing_region()]))
    for name, regions in cases:
        if regions:
            lines.append(row(name, regions))
            print(lines[-1], flush=True)
    if args.write:
        write_section("graded vertices", "Graded vertices against the grading "
                      "(bench/grading_vertices.py, issue 21)",
                      f"on {start['date']} (commit `{start['commit']}`). Mean vertices of "
                      "graded `\"auto\"` meshes per case at each grading L, their ratio to "
                      "Triangle `pq30` (no area bound), Triangle at the same proven angle "
                      "`pq<θ_L>`, and the 1st percentile of the smallest angles of "
                      "pds_plugin's triangles. The vertex misses of the speed targets come "
                      "from L: docs/engine.md, \"Issue 21: the misses\".", [*head, *lines])
        print("wrote the section 'graded vertices' of docs/benchmarks.md")


if __name__ == "__main__":
    main()
