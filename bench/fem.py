"""Finite-element sinks (docs/fem.md): what tags, quadratic nodes and the meshio and
scikit-fem conversions cost beside meshing, and the P1/P2 convergence on the unit disc.

    python bench/fem.py              # alphas 0.02, 0.01, 0.005 (about 10 s)
    python bench/fem.py --alphas 0.01 0.004

Prints two tables: seconds per step on an SVG disc with a slot (arcs kept exact: its
certificate, the quadratic mesh's with the Jacobians, the files, dolfinx's pair), and
the L2 error of -Δu = 1 on the unit disc (u = (1 - r²)/4) with P1, P2 on the true circle,
and P2 with its boundary mid nodes left on the chords, with the rates between alphas.
Needs the fem extra (meshio, scikit-fem).
"""

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

import pds_plugin as pds
from pds_plugin.sinks.fem import write_dolfinx

SHAFT = ('<svg xmlns="http://www.w3.org/2000/svg" viewBox="-1 -1 2 2"><path id="shaft" '
         'fill-rule="evenodd" d="M1 0A1 1 0 0 0 -1 0A1 1 0 0 0 1 0Z M0.3 0.1H-0.3V-0.1H0.3Z"/>'
         '</svg>')
DISC = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="-1 -1 2 2"><circle r="1"/></svg>'


def timed(step):
    start = time.perf_counter()
    step()
    return time.perf_counter() - start


def costs(folder, alphas):
    path = Path(folder) / "shaft.svg"
    path.write_text(SHAFT)
    region = pds.load_svg(path)
    steps = ("mesh", "tags", "quadratic", "certificate", "P2 cert.", "to_meshio",
             "to_skfem(1)", "to_skfem(2)", ".msh", ".vtu", ".xdmf", "dolfinx")
    print(f"{'alpha':>7} {'vertices':>9} " + " ".join(f"{s:>11}" for s in steps))
    for alpha in alphas:
        box = {}
        row = [timed(lambda: box.setdefault("mesh", pds.mesh_region(region, alpha)))]
        mesh = box["mesh"]
        row.append(timed(lambda: (mesh.region_tags, mesh.boundary_tags)))
        row.append(timed(mesh.quadratic))
        row.append(timed(mesh.certificate))
        row.append(timed(lambda: mesh.quadratic().certificate()))   # + the Jacobians
        row.append(timed(mesh.to_meshio))
        row.append(timed(lambda: mesh.to_skfem(1)))
        row.append(timed(lambda: mesh.to_skfem(2)))
        for suffix in (".msh", ".vtu", ".xdmf"):
            row.append(timed(lambda: mesh.export(Path(folder) / f"shaft{suffix}")))
        row.append(timed(lambda: write_dolfinx(mesh, Path(folder) / "shaft_dolfinx.xdmf")))
        print(f"{alpha:>7.3g} {len(mesh.vertices):>9} " + " ".join(f"{t:>11.3f}" for t in row))


def l2_error(fem_mesh, element, intorder):
    from skfem import Basis, Functional, asm, condense, solve
    from skfem.models.poisson import laplace, unit_load

    basis = Basis(fem_mesh, element, intorder=intorder)
    u = solve(*condense(asm(laplace, basis), asm(unit_load, basis), D=basis.get_dofs()))

    @Functional
    def squared(w):
        return (w["u"] - (1 - w.x[0] ** 2 - w.x[1] ** 2) / 4) ** 2
    return float(np.sqrt(squared.assemble(basis, u=basis.interpolate(u))))


def convergence(folder, alphas):
    from skfem import ElementTriP1, ElementTriP2, MeshTri, MeshTri2

    path = Path(folder) / "disc.svg"
    path.write_text(DISC)
    region = pds.load_svg(path, tolerance=1e-6)
    kinds = ("P1", "P2 on the circle", "P2 on the chords")
    errors = {kind: [] for kind in kinds}
    for alpha in alphas:
        mesh = pds.mesh_region(region, alpha)
        errors["P1"].append(l2_error(mesh.to_skfem(1), ElementTriP1(), 4))
        errors["P2 on the circle"].append(l2_error(mesh.to_skfem(2), ElementTriP2(), 6))
        straight = MeshTri2.from_mesh(MeshTri(np.array(mesh.vertices.T), np.array(mesh.faces.T)))
        errors["P2 on the chords"].append(l2_error(straight, ElementTriP2(), 6))
    print(f"\n{'element':<18} " + " ".join(f"{'alpha ' + format(a, '.3g'):>12}" for a in alphas)
          + "   rates")
    for kind, values in errors.items():
        rates = np.log(np.array(values[:-1]) / values[1:]) / np.log(np.array(alphas[:-1]) /
                                                                   alphas[1:])
        print(f"{kind:<18} " + " ".join(f"{e:>12.3e}" for e in values) + "   "
              + ", ".join(f"{r:.2f}" for r in rates))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--alphas", type=float, nargs="+", default=[0.02, 0.01, 0.005])
    parser.add_argument("--rates", type=float, nargs="+", default=[0.2, 0.1, 0.05, 0.025])
    options = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        costs(folder, options.alphas)
        convergence(folder, options.rates)


if __name__ == "__main__":
    main()
