"""What is measured on a region or a mesh: triangle quality, the boundary's feature size,
the mesh's topology against the region's, and the certificate that gathers them.

- :mod:`.quality`: aspect ratio L²/A, angles, edge lengths (Theorem 1);
- :mod:`.feature`: the feature size of a region's boundary (Theorem 2's condition);
- :mod:`.topology`: Betti numbers of mesh and region, and what was lost where;
- :mod:`.conformity`: how the mesh's outline follows the region's boundary;
- :mod:`.small_features`: the exceptions to Theorem 1 at features smaller than alpha,
  located and bounded;
- :mod:`.certificate`: separation, coverage gap, quality and topology, measured.

Nothing here makes a mesh: that is :mod:`pds_plugin.pipeline`.
"""
