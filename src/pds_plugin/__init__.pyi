"""Type stub of pds_plugin: the public names that ``__getattr__`` imports on first use."""

from ._version import __version__ as __version__
from .region import Region as Region
from .sampling import Samples as Samples, poisson_disc as poisson_disc
from .complex import solid_alpha_complex as solid_alpha_complex
from .mesh import PlanarMesh as PlanarMesh
from .analysis.quality import Quality as Quality, triangle_quality as triangle_quality
from .analysis.feature import FeatureSize as FeatureSize, feature_size as feature_size
from .analysis.topology import (
    TopologyReport as TopologyReport,
    topology_report as topology_report,
)
from .analysis.certificate import Certificate as Certificate
from .analysis.graded_certificate import GradedCertificate as GradedCertificate
from .analysis import certify as certify
from .sizing import RadiusField as RadiusField
from .quadratic import QuadraticMesh as QuadraticMesh
from .pipeline import (
    Resolution as Resolution,
    auto_mesh as auto_mesh,
    mesh_region as mesh_region,
    multiresolution as multiresolution,
    section_report as section_report,
    suggest_alpha as suggest_alpha,
)
from .partition import (
    CompositeMesh as CompositeMesh,
    PartitionCertificate as PartitionCertificate,
    mesh_regions as mesh_regions,
)
from .remeshing import RemeshResult as RemeshResult, remesh as remesh
from .sources.solids import mesh_tolerance as mesh_tolerance, section as section, sections as sections
from .sources.svg import load_svg as load_svg
from .sources.dxf import load_dxf as load_dxf
from .sources.drawing import load_drawing as load_drawing
from .sources.demo import demo_part as demo_part
from .sinks.meshlab import meshlab_quality as meshlab_quality
from .workflows import add_section_meshes as add_section_meshes
from .batch import mesh_batch as mesh_batch
from .tiled import (
    TiledCertificate as TiledCertificate,
    TiledMesh as TiledMesh,
    mesh_tiled as mesh_tiled,
)
from .silence import silenced as silenced
from .errors import (
    ArgumentError as ArgumentError,
    ArgumentTypeError as ArgumentTypeError,
    BudgetError as BudgetError,
    EmptyMeshError as EmptyMeshError,
    MissingDependencyError as MissingDependencyError,
    PdsError as PdsError,
    RegionError as RegionError,
    SectionError as SectionError,
    SourceError as SourceError,
    TopologyError as TopologyError,
)

__all__ = [
    "ArgumentError",
    "ArgumentTypeError",
    "BudgetError",
    "Certificate",
    "CompositeMesh",
    "EmptyMeshError",
    "FeatureSize",
    "GradedCertificate",
    "MissingDependencyError",
    "PartitionCertificate",
    "PdsError",
    "PlanarMesh",
    "QuadraticMesh",
    "Quality",
    "RadiusField",
    "Region",
    "RegionError",
    "RemeshResult",
    "Resolution",
    "Samples",
    "SectionError",
    "SourceError",
    "TiledCertificate",
    "TiledMesh",
    "TopologyError",
    "TopologyReport",
    "add_section_meshes",
    "auto_mesh",
    "certify",
    "demo_part",
    "feature_size",
    "load_drawing",
    "load_dxf",
    "load_svg",
    "mesh_batch",
    "mesh_region",
    "mesh_regions",
    "mesh_tiled",
    "mesh_tolerance",
    "meshlab_quality",
    "multiresolution",
    "poisson_disc",
    "remesh",
    "section",
    "section_report",
    "sections",
    "silenced",
    "solid_alpha_complex",
    "suggest_alpha",
    "topology_report",
    "triangle_quality",
]
