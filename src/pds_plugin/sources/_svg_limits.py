"""Limits on an SVG file, checked before svgelements expands it.

A few kilobytes of ``<use>`` references can stand for 10^8 shapes, one path can hold a
million segments and a file can be mostly comment: svgelements would build them all in
memory. :func:`check_svg_limits` reads the file's XML tree once (no entity is expanded,
no reference followed) and counts what the drawing *expands to* (every ``<use>`` counted
as the element it copies), refusing before any of it is built.
"""

from __future__ import annotations

import math
import os
import re
import xml.etree.ElementTree as ElementTree

import numpy as np

from .._checks import check_positive_int
from ..errors import SourceError

__all__ = ["MAX_BYTES", "MAX_ELEMENTS", "MAX_SEGMENTS", "check_svg_limits"]

MAX_BYTES = 20_000_000
"""Largest SVG file read by default (``max_bytes``)."""
MAX_ELEMENTS = 100_000
"""Most elements a drawing may expand to, ``<use>`` copies included (``max_elements``)."""
MAX_SEGMENTS = 100_000
"""Most path and polygon segments a drawing may expand to (``max_segments``); svgelements
holds each in several kilobytes."""

_NUMBER = re.compile(rb"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_LINK = ("href", "{http://www.w3.org/1999/xlink}href")
_GEOMETRY = frozenset({"d", "points", "transform", "x", "y", "width", "height", "r", "rx", "ry",
                       "cx", "cy", "x1", "y1", "x2", "y2", "viewBox"})


def check_svg_limits(path, max_elements=MAX_ELEMENTS, max_segments=MAX_SEGMENTS) -> None:
    """Refuse an SVG file that expands to too many elements or segments (its size is
    checked by :func:`.curves.checked_file`, with ``MAX_BYTES``).

    Parameters
    ----------
    path : str or os.PathLike
    max_elements, max_segments : int
        The limits; each error names the keyword of :func:`pds_plugin.load_svg` that
        raises it.

    Raises
    ------
    SourceError
        If a limit is exceeded, a shape has a negative size (an error in SVG), or a
        geometric attribute holds NaN, infinity or a number beyond float64.
    ArgumentError
        If a limit is not a positive integer.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> bomb = pathlib.Path(tempfile.mkdtemp()) / "bomb.svg"
    >>> groups = "".join(f'<g id="g{i}">' + f'<use href="#g{i - 1}"/>' * 10 + '</g>'
    ...                  for i in range(1, 9))
    >>> _ = bomb.write_text('<svg xmlns="http://www.w3.org/2000/svg"><defs><g id="g0">'
    ...                     f'<rect width="1" height="1"/></g>{groups}</defs>'
    ...                     '<use href="#g8"/></svg>')
    >>> check_svg_limits(bomb)
    Traceback (most recent call last):
    ...
    pds_plugin.errors.SourceError: ... expands to more than 100,000 elements (its <use> copies counted); pass a larger max_elements to read it
    """
    name = os.fspath(path)
    max_elements = check_positive_int(max_elements, "max_elements")
    max_segments = check_positive_int(max_segments, "max_segments")
    with open(name, "rb") as file:
        data = file.read()
    try:
        root = ElementTree.fromstring(data)
    except (ElementTree.ParseError, ValueError):
        return                             # not XML: svgelements says what is wrong
    by_id = {element.get("id"): element for element in root.iter() if element.get("id")}
    elements, segments = _expanded(root, by_id, max_elements, max_segments, name)
    if elements > max_elements:
        raise SourceError(f"{name!r} expands to more than {max_elements:,} elements (its <use> "
                          f"copies counted); pass a larger max_elements to read it")
    if segments > max_segments:
        raise SourceError(f"{name!r} expands to more than {max_segments:,} path segments; "
                          f"pass a larger max_segments to read it")
    for element in root.iter():
        tag = element.tag.rsplit("}", 1)[-1]
        for attribute in _GEOMETRY.intersection(element.keys()):
            value = element.get(attribute)
            if _non_finite(value):
                shown = value if len(value) <= 40 else value[:37] + "..."
                raise SourceError(f"{name!r} has a <{tag}> with {attribute}=\"{shown}\": NaN, "
                                  f"infinite and out-of-range numbers (beyond ±1.8e308) cannot "
                                  f"be drawn; fix the drawing")
        for size_name in {"circle": ("r",), "ellipse": ("rx", "ry"),
                          "rect": ("width", "height")}.get(tag, ()):
            value = element.get(size_name, "").strip()
            if value.startswith("-") and _NUMBER.fullmatch(value.encode()) and float(value):
                raise SourceError(f"{name!r} has a <{tag}> with {size_name}={value}: a "
                                  f"negative size is an error in SVG; fix the drawing")


def _expanded(root, by_id, max_elements, max_segments, name) -> tuple[int, int]:
    """Elements and segments of ``root`` with every ``<use>`` replaced by what it copies,
    counted without recursion and capped past the limits; a ``<use>`` cycle is refused."""
    cost, visiting = {}, set()             # element -> (elements, segments), when done
    stack = [(root, False)]
    while stack:
        element, children_done = stack.pop()
        if element in cost:
            continue
        if element in visiting and not children_done:     # reached again from inside it
            raise SourceError(f"{name!r} has a <use> cycle through the element with id "
                              f"{element.get('id')!r}: it would never end; fix the drawing")
        parts = list(element) + [by_id[ref] for ref in _references(element) if ref in by_id]
        if not children_done:
            visiting.add(element)
            stack.append((element, True))
            stack += [(part, False) for part in parts if part not in cost]
            continue
        visiting.discard(element)
        own = sum(_count_numbers(element.get(name, "")) // 2 for name in ("d", "points"))
        counted = [cost.get(part, (1, 0)) for part in parts]
        cost[element] = (min(1 + sum(c[0] for c in counted), max_elements + 1),
                         min(own + sum(c[1] for c in counted), max_segments + 1))
    return cost[root]


def _non_finite(text: str) -> bool:
    """Whether ``text`` holds NaN, infinity or a number float64 cannot hold (svgelements
    would drop the attribute, or the shape, without a word). No SVG keyword of a
    geometric attribute contains "nan" or "inf"."""
    lowered = text.lower()
    if "nan" in lowered or "inf" in lowered:
        return True
    return any(not math.isfinite(float(number)) for number in _NUMBER.findall(text.encode())
               if len(number) > 300 or b"e" in number.lower())


def _count_numbers(text: str) -> int:
    """About how many numbers ``text`` holds: its runs of number characters."""
    if not text:
        return 0
    codes = np.frombuffer(text.encode("ascii", "replace"), np.uint8)
    digit = np.isin(codes, np.frombuffer(b"0123456789.eE+-", np.uint8))
    return int(digit[0]) + int(np.count_nonzero(digit[1:] & ~digit[:-1]))


def _references(element) -> list[str]:
    if element.tag.rsplit("}", 1)[-1] != "use":
        return []
    return [element.get(key)[1:] for key in _LINK if (element.get(key) or "").startswith("#")]
