"""One-off check that the compiled kernels give the numba kernels' results bit for bit.

The numba kernels are read from git (``--numba-commit``, the last commit that had them)
into a temporary folder and put in place of the compiled modules in a child process;
another child runs the compiled kernels, once with one thread and once with the default
thread count. Every case's outputs (samples, faces, quality, edges, certificate, and the
kernels called directly on hard inputs: cocircular grids, 3D triangles) are saved and
compared byte for byte. Needs numba installed (``pip install numba``); it is not a test
because the project no longer depends on numba.

    python bench/engine_compare_numba.py            # prints one line per case
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
from _swap import KERNELS  # noqa: E402


def _use_numba_kernels(folder: Path):
    """Register the numba kernel modules of ``folder`` as pds_plugin's."""
    for name in KERNELS:
        spec = importlib.util.spec_from_file_location(f"pds_plugin.{name}", folder / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = module
        spec.loader.exec_module(module)


def _cases():
    """(name, thunk returning a dict of arrays) for every compared input."""
    from shapely.geometry import box

    import pds_plugin as pds
    import _regions
    from pds_plugin import _complex_kernels, _geometry_kernels, complex as cx

    def mesh_outputs(region, alpha, seed):
        def run():
            mesh = pds.mesh_region(region, alpha, seed=seed)
            quality = mesh.quality()
            edges, boundary = mesh.edges
            certificate = mesh.certificate().as_dict()
            return {"vertices": mesh.vertices, "faces": mesh.faces,
                    "on_boundary": mesh.on_boundary, "alpha": np.float64(mesh.alpha),
                    "aspect": quality.aspect_ratio, "angles": quality.angles,
                    "lengths": quality.edge_lengths, "area": quality.area, "edges": edges,
                    "boundary": boundary,
                    "certificate": np.frombuffer(json.dumps(certificate, sort_keys=True,
                                                            default=str).encode(), np.uint8)}
        return run

    square = pds.Region.from_shapely(box(0, 0, 1, 1))
    for n in (1e3, 1e4, 1e5):
        for seed in (0, 1, 2):
            yield f"square {n:.0e} seed {seed}", mesh_outputs(square, _regions.alpha_for(square, n), seed)
    yield "square 1e6 seed 0", mesh_outputs(square, _regions.alpha_for(square, 1e6), 0)
    for key, (label, build, needs) in _regions.FIXED.items():
        if needs and not (_regions.DATA / needs).exists():
            continue
        region = build()
        alpha = min(pds.suggest_alpha(region), _regions.alpha_for(region, 2e4))
        for seed in (0, 3):
            yield f"{key} seed {seed}", mesh_outputs(region, alpha, seed)
        yield f"{key} auto", mesh_outputs(region, "auto", 0)

    def cocircular(n, jitter):
        def run():
            # integer grids: every unit square is cocircular, so the exact fallback and
            # the simulation of simplicity decide every diagonal
            rng = np.random.default_rng(n)
            xy = np.stack(np.meshgrid(np.arange(n), np.arange(n)), -1).reshape(-1, 2).astype(float)
            xy = xy[rng.permutation(len(xy))] + jitter * rng.standard_normal(xy.shape)
            faces = cx.solid_alpha_complex(xy, 0.75)
            order, start = _complex_kernels.bin_points(xy, 0.0, 0.0, 0.75, n + 2, n + 2)
            return {"faces": faces, "order": order, "start": start,
                    "circumcircles": np.concatenate(_geometry_kernels.circumcircles(xy, faces),
                                                    axis=None)}
        return run

    for n, jitter in ((30, 0.0), (200, 0.0), (200, 1e-14), (300, 1e-9)):
        yield f"cocircular grid {n}x{n} jitter {jitter:g}", cocircular(n, jitter)

    def triangles_3d():
        rng = np.random.default_rng(7)
        vertices = rng.standard_normal((5000, 3))
        faces = rng.integers(0, 5000, (20000, 3))
        faces[:10, 1] = faces[:10, 0]                  # degenerate: zero-length edges
        return dict(zip(("lengths", "area", "angles"),
                        _geometry_kernels.triangle_measures(vertices, faces)))
    yield "triangle_measures 3D", triangles_3d


def _child(kind: str, numba_folder: str, out: str):
    if kind == "numba":
        _use_numba_kernels(Path(numba_folder))
    results = {}
    for name, run in _cases():
        for key, value in run().items():
            results[f"{name}|{key}"] = np.asarray(value)
    np.savez(out, **results)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--numba-commit", default="16c20ab")
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _child(*args.child)
        return
    with tempfile.TemporaryDirectory(prefix="pds_compare_") as tmp:
        tmp = Path(tmp)
        for name in KERNELS:
            source = subprocess.run(["git", "show", f"{args.numba_commit}:src/pds_plugin/{name}.py"],
                                    cwd=ROOT, check=True, capture_output=True, text=True).stdout
            (tmp / f"{name}.py").write_text(source)
        runs = {"numba": ("numba", {}), "compiled": ("compiled", {}),
                "compiled, 1 thread": ("compiled", {"PDS_THREADS": "1"})}
        outputs = {}
        for label, (kind, env) in runs.items():
            out = tmp / f"{label.replace(' ', '_').replace(',', '')}.npz"
            subprocess.run([sys.executable, __file__, "--child", kind, str(tmp), str(out)],
                           check=True, env={**os.environ, **env, "NUMBA_CACHE_DIR": str(tmp / "cache")})
            outputs[label] = dict(np.load(out))
        reference = outputs.pop("numba")
        failures = 0
        for label, result in outputs.items():
            different = 0
            assert result.keys() == reference.keys(), (label, result.keys() ^ reference.keys())
            for key in reference:
                a, b = reference[key], result[key]
                same = a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
                if not same:
                    different += 1
                    print(f"DIFFERENT  {label}: {key} {a.dtype}{a.shape} vs {b.dtype}{b.shape}")
            cases = sorted({key.split("|")[0] for key in reference})
            failures += different
            print(f"{label}: {len(reference) - different} of {len(reference)} arrays bit-identical "
                  f"to numba over {len(cases)} cases")
        for case in sorted({key.split("|")[0] for key in reference}):
            print(f"  {case}: {reference[case + '|faces'].shape[0] if case + '|faces' in reference else '-'} faces")
        sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
