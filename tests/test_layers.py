"""The package's imports only go down its layers, and never in a cycle.

Every import in src/pds_plugin is read with ast, function-level ones included (only the
``if TYPE_CHECKING:`` blocks, which never run, are left out), and checked against the
layers of the README's Layout section:

    kernels, errors, checks -> region, boundary curves -> the stages' shared modules
    (boundary sampling, local complex, disc tile) -> boundary rules -> sampling, complex, sizing ->
    graded sampling and complex -> mesh -> analysis, tags, quadratic
    -> pipeline -> sources, sinks, partition -> workflows, batch, remeshing -> cli
    -> the package's lazy names
"""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "pds_plugin"

# (rank, module name or package prefix); a module takes the rank of its longest match
LAYERS = [
    (-1, "pds_plugin._visibility_kernels"),     # shared by the sampling and complex kernels
    (0, "pds_plugin._sampling_kernels"), (0, "pds_plugin._complex_kernels"),
    (0, "pds_plugin._geometry_kernels"), (0, "pds_plugin._mesh_kernels"),
    (0, "pds_plugin._certificate_kernels"), (0, "pds_plugin._sizing_kernels"),
    (0, "pds_plugin._graded_kernels"), (0, "pds_plugin._feature_kernels"),
    (0, "pds_plugin._parallel"),
    (0, "pds_plugin._version"),
    (1, "pds_plugin.errors"), (1, "pds_plugin.silence"), (1, "pds_plugin._atomic"),
    (2, "pds_plugin._checks"),
    (3, "pds_plugin.region"), (3, "pds_plugin.boundary_curves"),
    (4, "pds_plugin.boundary_sampling"), (4, "pds_plugin.local_complex"),
    (4, "pds_plugin.disc_tile"),                # the graded sampler's periodic tile
    (4.5, "pds_plugin.boundary_rules"),         # the uniform sampler's boundary rules
    (5, "pds_plugin.sampling"), (5, "pds_plugin.complex"), (5, "pds_plugin.sizing"),
    (6, "pds_plugin.graded_sampling"), (6, "pds_plugin.graded_complex"),
    (7, "pds_plugin.mesh"),
    (8, "pds_plugin.analysis"), (8, "pds_plugin.tags"), (8, "pds_plugin.quadratic"),
    (9, "pds_plugin.pipeline"),
    (10, "pds_plugin.sources"), (10, "pds_plugin.sinks"), (10, "pds_plugin.partition"),
    (11, "pds_plugin.workflows"), (11, "pds_plugin.batch"), (11, "pds_plugin.remeshing"),
    (12, "pds_plugin.cli"),
    (13, "pds_plugin"),
]
# Packages whose modules may import each other (without cycles); sources and sinks,
# on the same layer, may not import each other.
SIBLINGS = ("pds_plugin.analysis", "pds_plugin.sources", "pds_plugin.sinks", "pds_plugin.batch",
            "pds_plugin.cli")
# PlanarMesh's methods quality(), certificate(), to_trimesh(), to_meshset() and export()
# are the public shortcuts of the README's Layout section: they import their layer when called. These
# are the only imports allowed to go up, and they still may not close a cycle.
SHORTCUTS = {
    ("pds_plugin.mesh", "pds_plugin.analysis.quality"),
    ("pds_plugin.mesh", "pds_plugin.analysis.certificate"),
    ("pds_plugin.mesh", "pds_plugin.analysis.graded_certificate"),
    ("pds_plugin.mesh", "pds_plugin.sinks.files"),
    ("pds_plugin.mesh", "pds_plugin.sinks.meshlab"),
    ("pds_plugin.mesh", "pds_plugin.tags"),             # region_tags, boundary_tags
    ("pds_plugin.mesh", "pds_plugin.quadratic"),        # quadratic()
    ("pds_plugin.mesh", "pds_plugin.sinks.fem"),        # to_meshio(), to_skfem()
}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES = {module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}
KNOWN = {prefix for _, prefix in LAYERS}      # e.g. kernels that may be compiled modules


def is_type_checking(node) -> bool:
    test = node.test
    return (isinstance(node, ast.If)
            and (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING"
                 or isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"))


def imports(name: str) -> set[str]:
    """The pds_plugin modules that module ``name`` imports, anywhere in its code."""
    path = MODULES[name]
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()

    def visit(node):
        if isinstance(node, ast.If) and is_type_checking(node):
            for child in node.orelse:
                visit(child)
            return
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")[:len(package.split(".")) - node.level + 1] \
                if node.level else []
            target = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:       # `from . import x` may import module x
                sub = f"{target}.{alias.name}"  # (a .py file, or a compiled kernel module)
                found.add(sub if sub in MODULES or sub in KNOWN else target)
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(ast.parse(path.read_text(encoding="utf-8")))
    return {m for m in found if m == "pds_plugin" or m.startswith("pds_plugin.")}


GRAPH = {name: imports(name) for name in MODULES}


def rank(name: str) -> int:
    matches = [(len(prefix), r) for r, prefix in LAYERS
               if name == prefix or name.startswith(prefix + ".")]
    assert matches, f"{name} is in no layer: add it to LAYERS and to the README's Layout"
    return max(matches)[1]


def sibling_package(a: str, b: str) -> bool:
    def within(name, package):
        return name == package or name.startswith(package + ".")
    return any(within(a, p) and within(b, p) for p in SIBLINGS)


def test_the_graph_is_read():
    # a few known edges, so that a broken parser cannot pass silently
    assert "pds_plugin.region" in GRAPH["pds_plugin.sampling"]
    assert "pds_plugin._sampling_kernels" in GRAPH["pds_plugin.sampling"]
    assert "pds_plugin.analysis.certificate" in GRAPH["pds_plugin.mesh"]      # function-level
    assert "pds_plugin.sources.trimesh" in GRAPH["pds_plugin.sources.solids"]
    assert "pds_plugin.analysis.quality" not in GRAPH["pds_plugin.sinks.meshlab"]  # TYPE_CHECKING


@pytest.mark.parametrize("name", sorted(MODULES))
def test_imports_go_down(name):
    upward = [target for target in sorted(GRAPH[name])
              if (name, target) not in SHORTCUTS
              and not (rank(target) < rank(name)
                       or rank(target) == rank(name) and sibling_package(name, target))]
    assert not upward, f"{name} (layer {rank(name)}) imports " + ", ".join(
        f"{t} (layer {rank(t)})" for t in upward)


def test_no_import_cycle():
    seen, stack, cycles = set(), [], []

    def walk(name):
        if name in stack:
            cycles.append(stack[stack.index(name):] + [name])
            return
        if name in seen:
            return
        seen.add(name)
        stack.append(name)
        for target in sorted(GRAPH[name] & set(MODULES)):
            walk(target)
        stack.pop()

    for name in sorted(MODULES):
        walk(name)
    assert not cycles, "import cycles: " + "; ".join(" -> ".join(c) for c in cycles)


def test_kernels_import_nothing_of_the_package_but_kernels():
    """The sampling and complex kernels share the visibility kernels; nothing else."""
    for name in MODULES:
        if name.rpartition(".")[2].endswith("_kernels"):
            others = {t for t in GRAPH[name] if not t.rpartition(".")[2].endswith("_kernels")}
            assert not others, f"{name} imports {sorted(others)}"
