"""Sources: CAD solids cut by planes, and 2D drawings, turned into a :class:`~pds_plugin.Region`.

- :mod:`.solids`: :func:`section` and :func:`sections` cut a ``trimesh.Trimesh``, a
  ``manifold3d.Manifold`` or a mesh file with planes (backends :mod:`.trimesh`,
  :mod:`.manifold`);
- :mod:`.svg`: :func:`load_svg` reads the filled shapes, or the outline drawing, of an
  SVG file; :mod:`.dxf`: :func:`load_dxf` the hatches, or the outline drawing, of a DXF
  file; :mod:`.drawing`: :func:`load_drawing` either, by the file's suffix;
- :mod:`.curves`: what the drawing readers share (chords to a tolerance, open ends);
- :mod:`.polygons`: the exact assembly of curves into polygons they and the solids share;
- :mod:`.demo`: the built-in CAD part of ``pds-mesh demo``.
"""

from .drawing import load_drawing
from .dxf import load_dxf
from .solids import section, sections
from .svg import load_svg

__all__ = ["section", "sections", "load_svg", "load_dxf", "load_drawing"]
