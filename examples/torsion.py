"""The torsion constant of a section with scikit-fem, from a drawing (docs/fem.md).

Saint-Venant torsion through Prandtl's stress function: -Δφ = 2 in the section, φ = 0 on
its outline (named "outline 0" by the mesh's boundary tags), and the torsion constant
J = 2 ∫ φ dA. Two SVG drawings are meshed and solved with linear (P1) and quadratic (P2)
triangles; the quadratic mesh has its boundary nodes on the drawing's true circle.
J is checked against the closed forms:

- a circle of radius R: J = π R⁴ / 2;
- a rectangle a x b (a >= b): J = a b³ / 3 (1 - 192 b / (π⁵ a) Σ_{n odd} tanh(nπa / 2b) / n⁵).

Run: python examples/torsion.py (needs the fem extra: pip install "pds_plugin[fem]").
"""

import tempfile
from pathlib import Path

import numpy as np
from skfem import Basis, ElementTriP1, ElementTriP2, Functional, asm, condense, solve
from skfem.models.poisson import laplace, unit_load

import pds_plugin as pds

ALPHAS = (0.2, 0.1, 0.05)


def circle_j(radius):
    return np.pi * radius ** 4 / 2


def rectangle_j(a, b, terms=50):
    a, b = max(a, b), min(a, b)
    n = np.arange(1, 2 * terms, 2)
    return a * b ** 3 / 3 * (1 - 192 * b / (np.pi ** 5 * a) * np.sum(
        np.tanh(n * np.pi * a / (2 * b)) / n ** 5))


@Functional
def _integral(w):
    return w["phi"]


def torsion_constant(mesh, order):
    """J = 2 ∫ φ with -Δφ = 2 inside and φ = 0 on the outline, on P1 or P2 triangles."""
    fem_mesh = mesh.to_skfem(order=order)
    basis = Basis(fem_mesh, ElementTriP1() if order == 1 else ElementTriP2(),
                  intorder=2 * order + 2)
    stiffness, load = asm(laplace, basis), 2 * asm(unit_load, basis)
    phi = solve(*condense(stiffness, load, D=basis.get_dofs("outline 0")))
    return 2 * _integral.assemble(basis, phi=basis.interpolate(phi))


def drawing(folder, name, body, view):
    path = Path(folder) / name
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{view}">{body}</svg>')
    return path


def main():
    folder = tempfile.mkdtemp()
    sections = {
        "circle r=1": (drawing(folder, "circle.svg", '<circle id="shaft" r="1"/>',
                               "-1 -1 2 2"), circle_j(1.0)),
        "rectangle 2x1": (drawing(folder, "bar.svg", '<rect id="bar" width="2" height="1"/>',
                                  "0 0 2 1"), rectangle_j(2.0, 1.0)),
    }
    print(f"{'section':<14} {'alpha':>6} {'vertices':>8} {'J P1':>12} {'error P1':>9} "
          f"{'J P2':>12} {'error P2':>9}")
    for name, (path, exact) in sections.items():
        region = pds.load_svg(path, tolerance=1e-6)
        errors = {1: [], 2: []}
        for alpha in ALPHAS:
            mesh = pds.mesh_region(region, alpha)
            values = {order: torsion_constant(mesh, order) for order in (1, 2)}
            for order, value in values.items():
                errors[order].append(abs(value - exact) / exact)
            print(f"{name:<14} {alpha:>6.3g} {len(mesh.vertices):>8} {values[1]:>12.8f} "
                  f"{errors[1][-1]:>9.2e} {values[2]:>12.8f} {errors[2][-1]:>9.2e}")
        rates = {order: np.polyfit(np.log(ALPHAS), np.log(e), 1)[0]
                 for order, e in errors.items()}
        print(f"{name:<14} exact J = {exact:.8f}; rate of the error in alpha: "
              f"P1 {rates[1]:.2f}, P2 {rates[2]:.2f}")


if __name__ == "__main__":
    main()
