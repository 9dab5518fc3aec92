"""Sinks: where a PlanarMesh goes after it is made.

- :mod:`.files`: trimesh objects and files (binary PLY with quality, OBJ), through a
  registry of writers by suffix;
- :mod:`.plot`: matplotlib pictures (samples, mesh by aspect ratio, histogram);
- :mod:`.meshlab`: pymeshlab MeshSets and MeshLab's own quality measures.

Each imports its heavy library where it is used.
"""
