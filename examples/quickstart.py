"""Quick start: from a shapely polygon to a certified triangle mesh in three lines.

A 4 x 2 plate with a round hole is sampled with a maximal Poisson disc sampling of
radius alpha = 0.1 and meshed with the solid alpha-complex. The certificate measures
what the paper proves (samples >= alpha apart, every point within alpha of a sample,
aspect ratio L²/A <= 4√3, the region's holes kept), then the quality statistics follow.

    python examples/quickstart.py
"""

from shapely.geometry import Point, box

import pds_plugin as pds

plate = box(0, 0, 4, 2).difference(Point(1, 1).buffer(0.5))

region = pds.Region.from_shapely(plate)
mesh = pds.mesh_region(region, alpha=0.1, seed=0)
print(mesh.certificate())

print("quality statistics:")
for name, value in mesh.quality().stats().items():
    print(f"  {name:<12} {value:.6g}")
