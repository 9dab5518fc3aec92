"""Sources: CAD solids cut by planes, and SVG drawings, turned into a :class:`~pds_plugin.Region`.

- :mod:`.solids`: :func:`section` and :func:`sections` cut a ``trimesh.Trimesh``, a
  ``manifold3d.Manifold`` or a mesh file with planes (backends :mod:`.trimesh`,
  :mod:`.manifold`);
- :mod:`.svg`: :func:`load_svg` reads the filled shapes, or the outline drawing, of an
  SVG file;
- :mod:`.polygons`: the exact assembly of curves into polygons both share;
- :mod:`.demo`: the built-in CAD part of ``pds-mesh demo``.
"""

from .solids import section, sections
from .svg import load_svg

__all__ = ["section", "sections", "load_svg"]
