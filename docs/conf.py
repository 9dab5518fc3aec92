"""Sphinx configuration of the pds_plugin documentation site.

Build it (warnings are errors) with::

    python -m pip install -e ".[docs]"
    python -m sphinx -W --keep-going -b html docs docs/_build/html

The pages: docs/index.md (the entry), the guide (which.md), the gallery (generated
below from examples/*.py, with the pictures the examples write into docs/figures), the
theory pages (docs/*.md, Markdown through MyST) and the API reference (api.rst, from the
numpydoc docstrings).
"""

import ast
from pathlib import Path

import pds_plugin

DOCS = Path(__file__).resolve().parent
EXAMPLES = DOCS.parent / "examples"

project = "pds_plugin"
author = "pds_plugin contributors"
copyright = "pds_plugin contributors (MIT)"
release = version = pds_plugin.__version__

extensions = ["sphinx.ext.autodoc", "sphinx.ext.viewcode", "numpydoc", "myst_parser"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build"]
myst_heading_anchors = 4            # the theory pages link to their own sections (#warm-times)

autodoc_member_order = "bysource"
numpydoc_show_class_members = False      # the class docstrings list their attributes
numpydoc_class_members_toctree = False

html_theme = "pydata_sphinx_theme"
html_title = f"pds_plugin {release}"
html_theme_options = {"navigation_depth": 2, "show_toc_level": 2}
html_static_path = []


# --- the gallery: one page per example, its docstring, its pictures, its source -----------

def _gallery_page(script: Path) -> str:
    """The Markdown page of one example."""
    doc = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8"))) or script.stem
    first, _, rest = doc.partition("\n\n")
    first = " ".join(first.split())
    cut = min((k for k in map(first.find, (": ", ". ", " (")) if k > 0), default=len(first))
    title, lead = first[:cut].rstrip("."), first[cut:].lstrip(":. ")
    pictures = sorted((DOCS / "figures").glob(f"{script.stem}*.png"))
    lines = [f"# {title}", "", lead[:1].upper() + lead[1:], "", rest.strip(), ""]
    lines += [f"![{p.stem}](../figures/{p.name})\n" for p in pictures]
    lines += ["```{literalinclude} " + f"../../examples/{script.name}", ":language: python",
              "```", ""]
    return "\n".join(lines)


def write_gallery(app=None) -> None:
    """docs/gallery/*.md from examples/*.py (regenerated on every build, not committed)."""
    folder = DOCS / "gallery"
    folder.mkdir(exist_ok=True)
    scripts = sorted(EXAMPLES.glob("*.py"))
    pages = []
    for script in scripts:
        page = folder / f"{script.stem}.md"
        text = _gallery_page(script)
        if not page.exists() or page.read_text(encoding="utf-8") != text:
            page.write_text(text, encoding="utf-8")      # unchanged pages keep their time
        pages.append(script.stem)
    index = ["# Gallery", "",
             "The scripts in `examples/`, each runnable as `python examples/NAME.py`; the "
             "paper's figures are written into `docs/figures` (their default output). "
             "`pds-mesh demo` draws the picture below.", "",
             "![pds-mesh demo](../demo.png)", "",
             "```{toctree}", ":maxdepth: 1", "", *pages, "```", ""]
    text = "\n".join(index)
    path = folder / "index.md"
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def setup(app):
    app.connect("builder-inited", write_gallery)
    return {"parallel_read_safe": True}

