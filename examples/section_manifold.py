"""Certified mesh of an oblique section of a manifold3d solid.

Takes the demo part (``pds_plugin.demo_part()``: a manifold3d plate with two round holes,
a slot and a sharp V notch), or reads ../shared/data/featuretype.STL into a Manifold (in float64,
through Mesh64) when present, cuts it with a tilted plane, meshes the section, prints
the certificate, and shows that the 2D frame is the plane's own: the same plane cut
from the same solid as a trimesh mesh gives the same coordinates, and the frame lifts
the mesh back into the plane.

    python examples/section_manifold.py [OUTPUT_DIR]
"""

import sys
from pathlib import Path

import manifold3d as m3
import numpy as np
import trimesh

import pds_plugin as pds

STL = Path(__file__).resolve().parents[2] / "shared" / "data" / "featuretype.STL"


def from_file(path: Path) -> m3.Manifold:
    mesh = trimesh.load_mesh(path)
    return m3.Manifold(m3.Mesh64(vert_properties=np.asarray(mesh.vertices, np.float64),
                                 tri_verts=np.asarray(mesh.faces, np.uint64)))


def main(out_dir: Path) -> None:
    solid = from_file(STL) if STL.exists() else pds.demo_part()
    print(f"solid: {STL.name if STL.exists() else 'built-in plate'}, {solid.num_tri()} triangles, "
          f"status {solid.status().name}")
    vertices = np.asarray(solid.to_mesh64().vert_properties)[:, :3]
    origin = vertices.min(axis=0) / 2 + vertices.max(axis=0) / 2
    normal = np.array([0.0, 1.0, 0.3])        # tilted: the section is not an axis slice

    region = pds.section(solid, plane_origin=origin, plane_normal=normal)
    print(f"section through {np.round(origin, 4).tolist()} with normal {normal.tolist()}: {region}")

    # the frame depends on the plane only: the same cut of the same mesh via trimesh agrees
    mesh64 = solid.to_mesh64()
    as_trimesh = trimesh.Trimesh(mesh64.vert_properties[:, :3], mesh64.tri_verts, process=False)
    twin = pds.section(as_trimesh, plane_origin=origin, plane_normal=normal)
    print(f"same plane via trimesh: same frame {np.array_equal(twin.frame, region.frame)}, "
          f"same geometry {twin.geometry.equals_exact(region.geometry, tolerance=0)}")

    alpha = pds.suggest_alpha(region)
    mesh = pds.mesh_region(region, alpha, seed=0)
    print(f"alpha {alpha:.4g}: {mesh}")
    print(mesh.certificate())
    unit = normal / np.linalg.norm(normal)
    distance = np.abs((mesh.vertices_3d - origin) @ unit).max()
    print(f"mesh vertices lifted by region.frame lie in the plane to {distance:.1e}")

    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "section_manifold.ply"
    mesh.export(path)
    print(f"saved {path}: binary PLY, face quality = aspect ratio")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out"))
