"""The graded certificate's fixed cost per call, and its text before and after a change
(issue 24: the remesh certifies every copied patch; docs/remesh.md "Session 21, fixed
costs").

    python bench/certificate_fixed_cost.py --dump before.txt   # every certificate's text
    python bench/certificate_fixed_cost.py --time              # CPU ms a call, base vs head
    python bench/certificate_fixed_cost.py --compare           # base and head: the same text?

Meshes: every patch mesh of the nine remesh bench parts (graded; with the meshes
certified during the remesh: the copies and the patches at spikes), and graded meshes of
the shared drawings (SVG, DXF) and of featuretype's and angle_block's mid-height
sections. ``--dump`` writes, per mesh, ``str(cert)`` and ``repr(cert.as_dict())`` (every
number in full) of a fresh certificate. ``--time`` certifies fresh copies of the small
patch meshes (as the remesh does its copies) with this tree's ``certify_graded`` and with
the one of ``--base`` (a git revision; its analysis modules loaded from git beside this
tree's), in turns, CPU time (``time.process_time``) per call, and checks that both give
the same text.
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np                                          # noqa: E402
import trimesh                                              # noqa: E402

import pds_plugin as pds                                    # noqa: E402
import pds_plugin.analysis.graded_certificate as graded_certificate  # noqa: E402
from pds_plugin.mesh import PlanarMesh                      # noqa: E402

from remesh_vs_meshlab import DATA, SHARED, generated_parts  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DRAWINGS = ("MIL.svg", "polygon.svg", "insert.dxf", "sliding-base.dxf", "spline.DXF",
            "wrench.dxf")
SECTIONS = ("featuretype.STL", "angle_block.STL")


def remesh_meshes(folder, graded=True):
    """(name, mesh) of each remesh bench part's patch meshes and of the meshes certified
    during its remesh (uniform ones with ``graded=False``)."""
    seen = []
    original = graded_certificate.certify_graded

    def recording(mesh):
        seen.append(mesh)
        return original(mesh)

    out = []
    parts = [DATA / name for name in SHARED if (DATA / name).exists()] + generated_parts(folder)
    for path in parts:
        seen.clear()
        graded_certificate.certify_graded = recording
        try:
            result = pds.remesh(trimesh.load_mesh(path), seed=0, graded=graded)
        finally:
            graded_certificate.certify_graded = original
        meshes = {id(m): m for m in list(seen) + list(result.patch_meshes)}
        out += [(f"{path.name}#{k}", m) for k, m in enumerate(meshes.values())
                if (m.field is not None) == graded]
    return out


def region_meshes(graded=True):
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name in DRAWINGS:
            if not (DATA / name).exists():
                continue
            region = (pds.load_svg if name.endswith(".svg") else pds.load_dxf)(DATA / name)
            out.append((name, pds.mesh_region(region, "auto", graded=graded, seed=0)))
        for name in SECTIONS:
            if not (DATA / name).exists():
                continue
            lo, hi = trimesh.load_mesh(DATA / name).bounds
            region = pds.section(DATA / name, plane_origin=(lo + hi) / 2,
                                 plane_normal=(0.0, 0.0, 1.0))
            out.append((f"{name} section", pds.mesh_region(region, "auto", graded=graded, seed=0)))
    return out


def fresh(mesh) -> PlanarMesh:
    """A copy with nothing cached (the remesh's copies share only the patch's region)."""
    return PlanarMesh(mesh.vertices, mesh.faces, mesh.on_boundary, mesh.region, mesh.alpha,
                      mesh.conforming, field=mesh.field)


def base_certify(revision):
    """``certify_graded`` of ``revision``: its analysis modules loaded beside this tree's
    (as pds_plugin.analysis._base_*), importing each other."""
    names = ("conformity", "small_features", "certificate", "graded_certificate")
    loaded = None
    for name in names:
        text = subprocess.run(["git", "show", f"{revision}:src/pds_plugin/analysis/{name}.py"],
                              cwd=ROOT, check=True, capture_output=True, text=True).stdout
        for other in names:
            text = text.replace(f"from .{other} import", f"from ._base_{other} import")
        full = f"pds_plugin.analysis._base_{name}"
        spec = importlib.util.spec_from_loader(full, loader=None)
        module = importlib.util.module_from_spec(spec)
        module.__package__ = "pds_plugin.analysis"
        sys.modules[full] = module
        exec(compile(text, f"<{revision}:{name}.py>", "exec"), module.__dict__)
        loaded = module
    return loaded.certify_graded, sys.modules["pds_plugin.analysis._base_certificate"].certify


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dump", type=Path)
    parser.add_argument("--time", action="store_true")
    parser.add_argument("--compare", action="store_true",
                        help="every certificate (graded and uniform meshes) of --base and of "
                             "this tree, in one process: the same text and numbers?")
    parser.add_argument("--base", default="main")
    parser.add_argument("--calls", type=int, default=20)
    parser.add_argument("--max-vertices", type=int, default=600)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        meshes = remesh_meshes(Path(folder))
    if args.dump:
        meshes += region_meshes()
        with open(args.dump, "w") as out:
            for name, mesh in meshes:
                cert = graded_certificate.certify_graded(fresh(mesh))
                out.write(f"== {name} ({len(mesh.vertices)} vertices)\n{cert}\n"
                          f"{cert.as_dict()!r}\n")
        print(f"{len(meshes)} certificates written to {args.dump}")
    if args.compare:
        from pds_plugin.analysis.certificate import certify
        graded_base, uniform_base = base_certify(args.base)
        with tempfile.TemporaryDirectory() as folder:
            uniform = remesh_meshes(Path(folder), graded=False) + region_meshes(graded=False)
        cases = [(n, m, graded_base, graded_certificate.certify_graded)
                 for n, m in meshes + region_meshes()]
        cases += [(n, m, uniform_base, certify) for n, m in uniform]
        different = 0
        for name, mesh, before, after in cases:
            a, b = before(fresh(mesh)), after(fresh(mesh))
            if str(a) != str(b) or repr(a.as_dict()) != repr(b.as_dict()):
                different += 1
                print(f"DIFFERENT: {name}")
        print(f"{len(cases)} certificates ({len(uniform)} uniform) compared with {args.base}: "
              f"{different} different")
    if args.time:
        small = [(n, m) for n, m in meshes if len(m.vertices) <= args.max_vertices]
        base = base_certify(args.base)[0]
        head = graded_certificate.certify_graded
        for name, mesh in small:
            a, b = base(fresh(mesh)), head(fresh(mesh))
            if str(a) != str(b) or repr(a.as_dict()) != repr(b.as_dict()):
                print(f"DIFFERENT: {name}")
        totals = {"base": [], "head": []}
        for _ in range(3):
            for label, certifier in (("base", base), ("head", head)):
                copies = [fresh(m) for _, m in small for _ in range(args.calls)]
                start = time.process_time()
                for copy in copies:
                    certifier(copy)
                totals[label].append((time.process_time() - start) / len(copies) * 1e3)
        vertices = np.mean([len(m.vertices) for _, m in small])
        print(f"{len(small)} meshes of at most {args.max_vertices} vertices (mean "
              f"{vertices:.0f}), {args.calls} fresh copies each, 3 rounds in turns")
        for label, values in totals.items():
            print(f"  {label}: CPU ms a call " + " / ".join(f"{v:.3f}" for v in values))
        print(f"  head / base (best): {min(totals['head']) / min(totals['base']):.3f}")


if __name__ == "__main__":
    main()
