"""pds_plugin inside a MeshLab workflow.

Load a CAD solid into a pymeshlab MeshSet, add certified meshes of three horizontal
sections to the same MeshSet with one call, check their quality with MeshLab's own
filters, and save one section as a PLY with per-face quality (open it in MeshLab and
colour by quality: Filters > Color Creation > Colorize by face quality).

Uses ../shared/data/featuretype.STL when present, else the demo part (a plate with
holes, a slot and a notch made with manifold3d).

    python examples/meshlab_workflow.py [OUTPUT_DIR]
"""

import sys
from pathlib import Path

import numpy as np
import pymeshlab

import pds_plugin as pds
from pds_plugin.sinks.meshlab import RADIUS_RATIO_BOUND, meshlab_quality
from pds_plugin.workflows import add_section_meshes

STL = Path(__file__).resolve().parents[2] / "shared" / "data" / "featuretype.STL"


def builtin_part() -> pymeshlab.Mesh:
    """The part of ``pds-mesh demo`` (:func:`pds_plugin.demo_part`) as a pymeshlab mesh."""
    mesh = pds.demo_part().to_mesh64()
    return pymeshlab.Mesh(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts))


def main(out_dir: Path) -> None:
    ms = pymeshlab.MeshSet()
    if STL.exists():
        ms.load_new_mesh(str(STL))
        alpha = 0.04
    else:
        ms.add_mesh(builtin_part(), "built-in plate")
        alpha = 0.05
    solid = ms.current_mesh()
    print(f"solid: {solid.label()!r}, {solid.face_number()} faces")

    # one call: cut with 3 evenly spaced horizontal planes, mesh, add to the MeshSet
    added = add_section_meshes(ms, alpha, plane_normal=(0, 0, 1), count=3)

    print(f"{'mesh id':>7}  {'name':<32} {'b0,b1':>6} {'samples':>8} {'triangles':>9}"
          f"  {'MeshLab 2r/R min / mean':>23}")
    for s in added:
        ms.set_current_mesh(s.mesh_id)
        measured = meshlab_quality(ms)        # MeshLab's own aspect-ratio filter on the layer
        stats = measured.statistics
        print(f"{s.mesh_id:>7}  {s.name:<32} {str(s.mesh.region.betti):>6} "
              f"{len(s.mesh.vertices):>8} {len(s.mesh.faces):>9}"
              f"  {stats['min']:>11.4f} / {stats['avg']:.4f}")
        assert measured.certified, "Theorem 1 violated?"
    print(f"Theorem 1 in MeshLab's terms: every 2r/R >= 2*sqrt(3) - 3 = {RADIUS_RATIO_BOUND:.4f}")

    middle = added[len(added) // 2]
    counts = meshlab_quality(middle.mesh, bins=8, range=(RADIUS_RATIO_BOUND, 1.0)).counts
    print(f"histogram of 2r/R over [{RADIUS_RATIO_BOUND:.3f}, 1] for {middle.name!r}: "
          f"{counts.tolist()}")

    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "meshlab_section.ply"
    ms.set_current_mesh(middle.mesh_id)
    ms.save_current_mesh(str(path), binary=True, save_face_quality=True,
                         save_vertex_quality=True, save_vertex_color=False)
    print(f"saved {path} ({path.stat().st_size} bytes): face quality = aspect ratio L²/A, "
          f"vertex quality = 1 on boundary samples")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out"))
