"""pds_plugin: certified triangle meshes of planar sections.

A region (from shapely, a trimesh/manifold3d solid cut by a plane, or an SVG or DXF
drawing) is sampled with a maximal Poisson disc sampling of radius ``alpha`` and meshed
with the solid alpha-complex of the samples; every triangle then has aspect ratio L²/A ≤ 4√3.

>>> import pds_plugin as pds
>>> from shapely.geometry import Point
>>> mesh = pds.mesh_region(pds.Region.from_shapely(Point(0, 0).buffer(1)), alpha=0.2)
>>> mesh.certificate().ok
True

Every public name is imported on first use, so ``import pds_plugin`` stays fast.
"""

import os as _os
from importlib import import_module as _import_module

# Idle OpenMP threads of the kernels sleep rather than spin: on a busy machine a spinning
# thread takes the core the working one needs (docs/engine.md). Read when the kernels
# load OpenMP, so it is set before any of them is imported; a user's setting wins.
_os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

from ._version import __version__

_PUBLIC = {
    "Region": "region",
    "Samples": "sampling",
    "poisson_disc": "sampling",
    "solid_alpha_complex": "complex",
    "PlanarMesh": "mesh",
    "Quality": "analysis.quality",
    "triangle_quality": "analysis.quality",
    "feature_size": "analysis.feature",
    "FeatureSize": "analysis.feature",
    "topology_report": "analysis.topology",
    "TopologyReport": "analysis.topology",
    "Certificate": "analysis.certificate",
    "GradedCertificate": "analysis.graded_certificate",
    "certify": "analysis",
    "RadiusField": "sizing",
    "mesh_region": "pipeline",
    "suggest_alpha": "pipeline",
    "auto_mesh": "pipeline",
    "multiresolution": "pipeline",
    "Resolution": "pipeline",
    "section_report": "pipeline",
    "mesh_regions": "partition",
    "CompositeMesh": "partition",
    "PartitionCertificate": "partition",
    "QuadraticMesh": "quadratic",
    "remesh": "remeshing",
    "RemeshResult": "remeshing",
    "section": "sources.solids",
    "sections": "sources.solids",
    "mesh_tolerance": "sources.solids",
    "load_svg": "sources.svg",
    "load_dxf": "sources.dxf",
    "load_drawing": "sources.drawing",
    "demo_part": "sources.demo",
    "meshlab_quality": "sinks.meshlab",
    "add_section_meshes": "workflows",
    "silenced": "silence",
    **{name: "errors" for name in ("PdsError", "ArgumentError", "ArgumentTypeError",
                                   "RegionError", "SourceError", "SectionError", "BudgetError",
                                   "TopologyError", "EmptyMeshError",
                                   "MissingDependencyError")},
    "mesh_batch": "batch",
    "mesh_tiled": "tiled",
    "TiledMesh": "tiled",
    "TiledCertificate": "tiled",
}

__all__ = sorted(_PUBLIC)


def __getattr__(name):
    module = _PUBLIC.get(name)
    if module is None:
        raise AttributeError(f"module 'pds_plugin' has no attribute {name!r}")
    value = getattr(_import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    """The public names and the module's own dunders (not its private helpers)."""
    return sorted({name for name in globals() if not name.startswith("_") or
                   name.startswith("__")} | set(_PUBLIC))
