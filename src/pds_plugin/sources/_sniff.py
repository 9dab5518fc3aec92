"""What a file really holds, from its first bytes, for the readers' error messages.

A PNG renamed ``.svg``, a DXF saved as ``.stl`` or a gzip-compressed ``.svgz`` makes the
parser fail with "not well-formed (invalid token)" or "not a DXF file", which does not
say what is wrong. :func:`misnamed` recognises the common formats by their signatures so
that the reader can say "it is a PNG image" and what to do instead.
"""

from __future__ import annotations

import re

__all__ = ["MESH_KINDS", "misnamed"]

_MAGIC = [(b"\x89PNG\r\n\x1a\n", "png"), (b"\xff\xd8\xff", "jpeg"), (b"GIF87a", "gif"),
          (b"GIF89a", "gif"), (b"II*\x00", "tiff"), (b"MM\x00*", "tiff"), (b"%PDF-", "pdf"),
          (b"\x1f\x8b", "gzip"), (b"PK\x03\x04", "zip"), (b"AutoCAD Binary DXF", "dxf"),
          (b"glTF", "glb")]
_TEXT = [(re.compile(rb"0[ \t]*\r?\n[ \t]*SECTION\b"), "dxf"),
         (re.compile(rb"<\?xml[^>]*>\s*(<!--.*?-->\s*|<!DOCTYPE[^>]*>\s*)*<svg\b|<svg\b",
                     re.S | re.I), "svg"),
         (re.compile(rb"solid\b"), "stl"), (re.compile(rb"ply\r?\n"), "ply"),
         (re.compile(rb"OFF\b"), "off")]
_NAMES = {"png": "a PNG image", "jpeg": "a JPEG image", "gif": "a GIF image",
          "tiff": "a TIFF image", "pdf": "a PDF document", "gzip": "gzip-compressed (as .svgz "
          "and .gz files are)", "zip": "a ZIP archive", "dxf": "a DXF drawing",
          "svg": "an SVG drawing", "stl": "an STL mesh", "ply": "a PLY mesh",
          "off": "an OFF mesh", "glb": "a GLB model"}
_ADVICE = {**dict.fromkeys(("png", "jpeg", "gif", "tiff", "pdf"),
                           "a picture holds no geometry to read; give the drawing (SVG, DXF) "
                           "or the mesh (STL, OBJ, PLY, ...) itself"),
           "gzip": "decompress it first (e.g. gunzip)",
           "zip": "extract the file it holds first",
           "dxf": "read it with pds_plugin.load_dxf (pds-mesh: name it .dxf)",
           "svg": "read it with pds_plugin.load_svg (pds-mesh: name it .svg)",
           **dict.fromkeys(("stl", "ply", "off", "glb"),
                           "cut it with pds_plugin.section (pds-mesh: give it its own suffix "
                           "and --axis)")}
MESH_KINDS = frozenset({"stl", "ply", "off", "glb", "zip"})
"""What trimesh reads (3MF is a ZIP archive)."""


def misnamed(path, expected: str, readable=frozenset()) -> str | None:
    """Why ``path`` is not a file of the ``expected`` kind, if its first bytes tell.

    Parameters
    ----------
    path : str
    expected : str
        What the reader wanted, for the message ("an SVG drawing").
    readable : set of str
        The kinds this reader reads (their signatures say nothing against the file).

    Returns
    -------
    str or None
        "it is <kind>, not <expected>; <what to do>", or None when the bytes match no
        known format, or one the reader reads.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> picture = pathlib.Path(tempfile.mkdtemp()) / "logo.svg"
    >>> _ = picture.write_bytes(b"\\x89PNG\\r\\n\\x1a\\n" + bytes(100))
    >>> print(misnamed(picture, "an SVG drawing", {"svg"}))
    it is a PNG image, not an SVG drawing; a picture holds no geometry to read; give the drawing (SVG, DXF) or the mesh (STL, OBJ, PLY, ...) itself
    """
    try:
        with open(path, "rb") as file:
            head = file.read(4096)
    except OSError:
        return None
    text = head.lstrip(b"\xef\xbb\xbf \t\r\n")
    kind = next((kind for magic, kind in _MAGIC if head.startswith(magic)), None) or next(
        (kind for pattern, kind in _TEXT if pattern.match(text)), None)
    if kind is None or kind in readable:
        return None
    return f"it is {_NAMES[kind]}, not {expected}; {_ADVICE[kind]}"
