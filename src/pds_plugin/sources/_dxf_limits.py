"""Limits on a DXF drawing, checked before its blocks are expanded.

A few kilobytes of nested INSERTs (a block inserting another ten times, nine levels
deep, or one MINSERT array of 10^4 x 10^4 copies) stand for 10^8 entities, and one
polyline can hold millions of vertices: expanding them would take hours and gigabytes.
:func:`check_dxf_limits` counts what the layout read *expands to* from the block
definitions alone (every INSERT counted as all the copies it places), refusing before
any of it is built. The twin of :mod:`._svg_limits`; the file size is checked by
:func:`.curves.checked_file` before ezdxf reads anything.
"""

from __future__ import annotations

from .._checks import check_positive_int
from ..errors import SourceError

__all__ = ["MAX_BYTES", "MAX_ENTITIES", "MAX_SEGMENTS", "check_dxf_limits"]

MAX_BYTES = 50_000_000
"""Largest DXF file read by default (``max_bytes``): ezdxf holds about 15 times the file
in memory, and reads some 2 MB a second."""
MAX_ENTITIES = 100_000
"""Most entities a drawing may expand to, every INSERT copy included (``max_entities``)."""
MAX_SEGMENTS = 1_000_000
"""Most polyline vertices, spline control points and hatch boundary edges a drawing may
expand to (``max_segments``)."""


def check_dxf_limits(document, name: str, max_entities=MAX_ENTITIES,
                     max_segments=MAX_SEGMENTS, layout=None) -> None:
    """Refuse a DXF layout that expands to too many entities or segments.

    Parameters
    ----------
    document : ezdxf.document.Drawing
    name : str
        The file, for messages.
    max_entities, max_segments : int
        The limits; each error names the keyword of :func:`pds_plugin.load_dxf` that
        raises it.
    layout : ezdxf.layouts.Layout, optional
        The layout read; default: the model space.

    Raises
    ------
    SourceError
        If a limit is exceeded.
    ArgumentError
        If a limit is not a positive integer.

    Examples
    --------
    >>> import ezdxf
    >>> doc = ezdxf.new()
    >>> _ = doc.blocks.new("B0").add_line((0, 0), (1, 0))
    >>> for level in range(1, 9):                      # B8 holds 10^8 lines
    ...     block = doc.blocks.new(f"B{level}")
    ...     for copy in range(10):
    ...         _ = block.add_blockref(f"B{level - 1}", (copy, 0))
    >>> _ = doc.modelspace().add_blockref("B8", (0, 0))
    >>> check_dxf_limits(doc, "'bomb.dxf'")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.SourceError: 'bomb.dxf' expands to more than 100,000 entities (every block INSERT counted with all its copies); pass a larger max_entities to read it
    """
    max_entities = check_positive_int(max_entities, "max_entities")
    max_segments = check_positive_int(max_segments, "max_segments")
    entities, segments = _expanded(document, layout, max_entities, max_segments)
    if entities > max_entities:
        raise SourceError(f"{name} expands to more than {max_entities:,} entities (every "
                          f"block INSERT counted with all its copies); pass a larger "
                          f"max_entities to read it")
    if segments > max_segments:
        raise SourceError(f"{name} expands to more than {max_segments:,} polyline vertices, "
                          f"spline control points and hatch edges; pass a larger "
                          f"max_segments to read it")


def _expanded(document, layout, max_entities, max_segments) -> tuple[int, int]:
    """Entities and segments of the layout (None: the model space) with every INSERT
    replaced by its copies of the block, counted without recursion and capped past the
    limits. A block that inserts itself counts nothing for that INSERT (the reader
    refuses it)."""
    def inserted(space):
        return {entity.dxf.name for entity in space if entity.dxftype() == "INSERT"
                and document.blocks.get(entity.dxf.name) is not None}

    cost, visiting = {}, set()             # block name (None: the layout) -> (entities, segments)
    stack = [(None, False)]
    while stack:
        block, children_done = stack.pop()
        if block in cost or (block in visiting and not children_done):
            continue
        if block is not None:
            space = document.blocks.get(block)
        else:
            space = document.modelspace() if layout is None else layout
        if not children_done:
            visiting.add(block)
            stack.append((block, True))
            stack += [(name, False) for name in inserted(space)
                      if name not in cost and name not in visiting]
            continue
        visiting.discard(block)
        entities = segments = 0
        for entity in space:
            entities, segments = entities + 1, segments + _segments(entity)
            if entity.dxftype() == "INSERT":
                copies = max(1, entity.mcount)
                inner_entities, inner_segments = cost.get(entity.dxf.name, (0, 0))
                entities += copies * inner_entities
                segments += copies * inner_segments
        cost[block] = (min(entities, max_entities + 1), min(segments, max_segments + 1))
    return cost[None]


def _segments(entity) -> int:
    """The vertices, control points or boundary edges the reader turns into pieces."""
    kind = entity.dxftype()
    if kind == "LWPOLYLINE":
        return len(entity)
    if kind == "POLYLINE":
        return len(entity.vertices)
    if kind == "SPLINE":
        return entity.control_point_count() + entity.fit_point_count()
    if kind == "HATCH":
        return sum(len(getattr(path, "vertices", ())) + len(getattr(path, "edges", ()))
                   for path in entity.paths)
    return 0
