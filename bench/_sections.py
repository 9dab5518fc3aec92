"""Sections of docs/benchmarks.md that other scripts than peers.py write.

A script puts its section between ``<!-- section: NAME -->`` and ``<!-- /section: NAME -->``
(:func:`put_section`); peers.py rewrites the whole file but keeps those sections
(:func:`kept_sections`), so every number in the file still comes from a script.
"""

from __future__ import annotations

import re
from pathlib import Path

_SECTION = re.compile(r"<!-- section: (?P<name>[\w./-]+) -->\n.*?<!-- /section: (?P=name) -->\n",
                      re.DOTALL)


def put_section(path: Path, name: str, text: str) -> None:
    """Replace section ``name`` of the file at ``path`` by ``text`` (append it if new)."""
    block = f"<!-- section: {name} -->\n{text.rstrip()}\n<!-- /section: {name} -->\n"
    old = path.read_text() if path.exists() else ""
    current = {m.group("name"): m for m in _SECTION.finditer(old)}
    if name in current:
        match = current[name]
        new = old[:match.start()] + block + old[match.end():]
    else:
        new = old.rstrip("\n") + ("\n\n" if old else "") + block
    path.write_text(new)


def kept_sections(path: Path) -> str:
    """The sections other scripts wrote into the file at ``path``, as one text."""
    if not path.exists():
        return ""
    return "\n".join(m.group(0) for m in _SECTION.finditer(path.read_text()))
