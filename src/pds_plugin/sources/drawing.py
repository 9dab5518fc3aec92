"""2D drawings read by the reader their file suffix names (SVG, DXF)."""

from __future__ import annotations

import os

from .._checks import check_path
from ..errors import SourceError
from .dxf import load_dxf
from .svg import load_svg

__all__ = ["load_drawing", "is_drawing", "READERS"]

READERS = {".svg": load_svg, ".dxf": load_dxf}
"""The drawing reader of each file suffix (compared in lower case)."""


def load_drawing(path, **options):
    """Read a 2D drawing as a :class:`~pds_plugin.Region`, with the reader its suffix names.

    ``.svg`` is read by :func:`~pds_plugin.load_svg`, ``.dxf`` by
    :func:`~pds_plugin.load_dxf`; ``options`` go to the reader.

    Parameters
    ----------
    path : str or os.PathLike
    **options
        Keyword arguments of the reader (``tolerance``, ``units``, ``mode``, and
        ``layers`` and ``layout`` for DXF).

    Returns
    -------
    Region

    Raises
    ------
    SourceError
        If the suffix is not one of a drawing (the message lists them); or as the reader.

    Examples
    --------
    >>> import pathlib, tempfile, pds_plugin as pds
    >>> svg = pathlib.Path(tempfile.mkdtemp()) / "square.svg"
    >>> _ = svg.write_text('<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 4 4">'
    ...                    '<rect width="4" height="4"/></svg>')
    >>> pds.load_drawing(svg).area
    16.0
    """
    name = check_path(path)
    if not is_drawing(name):
        raise SourceError(f"cannot read {name!r} as a drawing: the suffix must be "
                          f"one of {', '.join(READERS)}")
    return READERS[os.path.splitext(name)[1].lower()](path, **options)


def is_drawing(path) -> bool:
    """Whether ``path`` names a 2D drawing, read by :func:`load_drawing`, rather than a
    solid to cut (a mesh or a B-rep file): by its suffix, in any case. The one place the
    command line (``pds-mesh``) and batch jobs decide which an input is.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    bool

    Examples
    --------
    >>> is_drawing("sheet.DXF"), is_drawing("part.svg"), is_drawing("part.stl")
    (True, True, False)
    """
    return os.path.splitext(os.fspath(path))[1].lower() in READERS
