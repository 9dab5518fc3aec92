"""What is measured on a region or a mesh: triangle quality, the boundary's feature size,
the mesh's topology against the region's, and the certificate that gathers them.

- :mod:`.quality`: aspect ratio L²/A, angles, edge lengths (Theorem 1);
- :mod:`.feature`: the feature size of a region's boundary (Theorem 2's condition);
- :mod:`.topology`: Betti numbers of mesh and region, and what was lost where;
- :mod:`.conformity`: how the mesh's outline follows the region's boundary;
- :mod:`.small_features`: the exceptions to Theorem 1 at features smaller than alpha,
  located and bounded;
- :mod:`.certificate`: separation, coverage gap, quality and topology, measured;
- :mod:`.graded_certificate`: the same, against a graded mesh's radius field;
- :func:`certify` (``pds_plugin.certify``): the certificate of any mesh, by its kind.

Nothing here makes a mesh: that is :mod:`pds_plugin.pipeline`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..mesh import PlanarMesh
    from ..partition import PartitionCertificate
    from ..quadratic import QuadraticMesh
    from .certificate import Certificate

__all__ = ["certify"]


def certify(mesh: PlanarMesh | QuadraticMesh) -> Certificate | PartitionCertificate:
    """The certificate of any mesh this package makes, chosen by the mesh's kind.

    - a uniform :class:`~pds_plugin.PlanarMesh`: a
      :class:`~pds_plugin.Certificate` (separation and coverage / alpha, Theorem 1's 4√3);
    - a graded one (``mesh.field`` is its :class:`~pds_plugin.RadiusField`): a
      :class:`~pds_plugin.GradedCertificate` (ratios to the local radius r, the bound
      θ_L of its grading L);
    - a :class:`~pds_plugin.CompositeMesh` from :func:`~pds_plugin.mesh_regions`: a
      :class:`~pds_plugin.PartitionCertificate` (each part's certificate, and the joins);
    - a :class:`~pds_plugin.QuadraticMesh` (``mesh.quadratic()``): its linear mesh's
      certificate with the curved triangles' Jacobian checks as ``quadratic``.

    It is always the mesh's own :meth:`~pds_plugin.PlanarMesh.certificate`: measured
    once per mesh, then cached.

    Parameters
    ----------
    mesh : PlanarMesh, CompositeMesh or QuadraticMesh

    Returns
    -------
    Certificate, GradedCertificate or PartitionCertificate

    Raises
    ------
    ArgumentTypeError
        If ``mesh`` is not a mesh (a :class:`~pds_plugin.RemeshResult` is named: its
        certificates are per patch, ``result.certificates``).

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> square = pds.Region.from_shapely(box(0, 0, 2, 1))
    >>> uniform, graded = pds.mesh_region(square, 0.1), pds.mesh_region(square, 0.1, graded=True)
    >>> type(pds.certify(uniform)).__name__, type(pds.certify(graded)).__name__
    ('Certificate', 'GradedCertificate')
    >>> pds.certify(graded).ok, pds.certify(graded) is graded.certificate()
    (True, True)
    """
    from .._checks import check_planar_mesh
    from ..errors import ArgumentTypeError

    if hasattr(mesh, "patch_meshes") and hasattr(mesh, "certificates"):
        raise ArgumentTypeError("certify needs one mesh; a RemeshResult has one certificate "
                                "per remeshed patch: use result.certificates (and result.ok)")
    if hasattr(mesh, "jacobian_report") and hasattr(mesh, "mesh"):   # a QuadraticMesh
        check_planar_mesh(mesh.mesh, "certify")
        return mesh.certificate()
    return check_planar_mesh(mesh, "certify").certificate()
