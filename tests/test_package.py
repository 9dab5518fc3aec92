"""The package's public names: all importable, imported lazily, and listed in the stub."""

import ast
import subprocess
import sys
from pathlib import Path

import pds_plugin as pds

STUB = Path(pds.__file__).with_suffix(".pyi")


def test_every_public_name_resolves():
    for name in pds.__all__:
        assert getattr(pds, name) is not None, name


def test_the_stub_lists_exactly_the_public_names():
    tree = ast.parse(STUB.read_text(encoding="utf-8"))
    imported = {alias.asname for node in tree.body if isinstance(node, ast.ImportFrom)
                for alias in node.names}
    assert imported == set(pds.__all__) | {"__version__"}
    [listed] = [node.value for node in tree.body if isinstance(node, ast.Assign)
                and node.targets[0].id == "__all__"]
    assert ast.literal_eval(listed) == pds.__all__
    for node in tree.body:              # each stub import names the module that defines it
        if isinstance(node, ast.ImportFrom) and node.module != "_version":
            for alias in node.names:
                assert getattr(pds, alias.name).__module__ == f"pds_plugin.{node.module}"


def test_import_is_lazy():
    code = ("import sys, pds_plugin; heavy = {'numba', 'scipy', 'shapely', 'trimesh', "
            "'matplotlib', 'pymeshlab'} & set(sys.modules); print(sorted(heavy))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "[]"


def test_dir_shows_the_public_names_and_no_helpers():
    code = "import pds_plugin; print(' '.join(dir(pds_plugin)))"
    shown = set(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                               check=True).stdout.split())
    assert {"os", "import_module", "_os", "_import_module", "_PUBLIC"}.isdisjoint(shown)
    assert set(pds.__all__) <= shown
    assert {name for name in shown if not name.startswith("__")} <= set(pds.__all__)


def test_the_graded_and_composite_types_are_public():
    from pds_plugin.analysis.graded_certificate import GradedCertificate
    from pds_plugin.sizing import RadiusField
    assert pds.GradedCertificate is GradedCertificate and pds.RadiusField is RadiusField
    assert issubclass(pds.GradedCertificate, pds.Certificate)
    for name in ("GradedCertificate", "RadiusField", "PartitionCertificate", "QuadraticMesh"):
        assert name in pds.__all__
