"""Sections of docs/benchmarks.md that other scripts than peers.py write.

A script puts its section between ``<!-- section: NAME -->`` and ``<!-- /section: NAME -->``
(:func:`put_section`); peers.py rewrites the whole file but keeps those sections
(:func:`kept_sections`), so every number in the file still comes from a script.
"""

from __future__ import annotations

import re
import shlex
import sys
from pathlib import Path

BENCHMARKS = Path(__file__).resolve().parents[1] / "docs" / "benchmarks.md"

# a name is one line of text without ">": "speed targets", "bench/batch.py"
_SECTION = re.compile(r"<!-- section: (?P<name>[^\n>]+?) -->\n.*?<!-- /section: (?P=name) -->\n",
                      re.DOTALL)


def put_section(path: Path, name: str, text: str) -> None:
    """Replace section ``name`` of the file at ``path`` by ``text`` (append it if new);
    further copies of the section, with the blank lines before them, are dropped."""
    if not _SECTION.fullmatch(f"<!-- section: {name} -->\n<!-- /section: {name} -->\n"):
        raise ValueError(f"a section name is one line without '>': {name!r}")
    block = f"<!-- section: {name} -->\n{text.rstrip()}\n<!-- /section: {name} -->\n"
    old = path.read_text() if path.exists() else ""
    copies = [m for m in _SECTION.finditer(old) if m.group("name") == name]
    if not copies:
        path.write_text(old.rstrip("\n") + ("\n\n" if old else "") + block)
        return
    new = old[:copies[0].start()] + block
    end = copies[0].end()
    for match in copies[1:]:
        new += old[end:match.start()].rstrip("\n") + "\n"
        end = match.end()
    path.write_text(new.rstrip("\n") + "\n" + old[end:])


def write_section(name: str, title: str, intro: str, lines) -> None:
    """Section ``name`` of docs/benchmarks.md: ``title``, then "Written by `python
    bench/SCRIPT ARGS`" (this process's command line) and ``intro``, then ``lines``."""
    command = shlex.join(["python", f"bench/{Path(sys.argv[0]).name}", *sys.argv[1:]])
    put_section(BENCHMARKS, name, "\n".join([f"## {title}\n", f"Written by `{command}` {intro}\n",
                                             *lines]))


def kept_sections(path: Path) -> str:
    """The sections other scripts wrote into the file at ``path``, as one text."""
    if not path.exists():
        return ""
    return "\n".join(m.group(0) for m in _SECTION.finditer(path.read_text()))
