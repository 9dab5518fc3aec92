"""Certified mesh of a section of a CAD solid read with trimesh (a mesh file or a Trimesh).

Cuts ../shared/data/featuretype.STL at mid-height when present (else a built-in trimesh
part: a plate with a round hole holding an island, and a square pocket through it),
meshes the section at the alpha its feature size suggests, prints the certificate and
the quality, checks that the mesh lies in the cutting plane in 3D, and cuts a stack of
five sections.

    python examples/section_trimesh.py [OUTPUT_DIR]
"""

import sys
from pathlib import Path

import numpy as np
import trimesh

import pds_plugin as pds

STL = Path(__file__).resolve().parents[2] / "shared" / "data" / "featuretype.STL"


def builtin_part() -> trimesh.Trimesh:
    """A 6 x 3 x 1 plate, a round hole with an island in it, and a square pocket."""
    def cylinder(x, radius, height):
        shape = trimesh.creation.cylinder(radius=radius, height=height, sections=96)
        return shape.apply_translation([x, 0, 0])

    plate = trimesh.creation.box(extents=(6, 3, 1))
    pocket = trimesh.creation.box(extents=(1, 1, 2)).apply_translation([1.5, 0, 0])
    return plate.difference(cylinder(-1.5, 1.0, 2)).union(cylinder(-1.5, 0.5, 1)).difference(pocket)


def print_mesh(mesh) -> None:
    print(f"  {mesh}")
    print("  " + str(mesh.certificate()).replace("\n", "\n  "))
    stats = mesh.quality().stats()
    print(f"  aspect ratio L²/A: mean {stats['aspect_mean']:.3f}, max {stats['aspect_max']:.3f} "
          f"(bound 4√3 = {4 * np.sqrt(3):.3f}); angles in [{stats['angle_min']:.1f}°, "
          f"{stats['angle_max']:.1f}°]")


def main(out_dir: Path) -> None:
    solid = STL if STL.exists() else builtin_part()
    bounds = (trimesh.load_mesh(solid) if isinstance(solid, Path) else solid).bounds
    middle = float(bounds[:, 2].mean())
    print(f"solid: {solid.name if isinstance(solid, Path) else 'built-in plate'}")

    region = pds.section(solid, plane_origin=(0, 0, middle), plane_normal=(0, 0, 1))
    print(f"section at z = {middle:.4g}: {region}")
    alpha = pds.suggest_alpha(region)
    print(f"suggested alpha (from the feature size): {alpha:.4g}")
    mesh = pds.mesh_region(region, alpha, seed=0)
    print_mesh(mesh)
    off_plane = np.abs(mesh.vertices_3d[:, 2] - middle).max()
    print(f"  vertices in 3D lie on the plane z = {middle:.4g} to {off_plane:.1e}")

    print("a stack of 5 sections, one in the middle of each fifth of the height:")
    for stacked in pds.sections(solid, plane_normal=(0, 0, 1), count=5):
        print(f"  z = {stacked.frame[2, 3]:8.4g}: components, holes = {stacked.betti}, "
              f"area = {stacked.area:.6g}")

    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "section_trimesh.ply"
    mesh.export(path)
    print(f"saved {path}: binary PLY, face quality = aspect ratio")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out"))
