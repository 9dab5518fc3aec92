"""``bench/remesh_profile.py`` with the fixed costs of a base revision swapped in: its
graded certificate (analysis modules loaded from git, ``certificate_fixed_cost.base_certify``)
and its ``partition.interface_report``; the rest of the remesh is this tree's. Base and
head run in turns in separate processes, so both see the same machine load
(docs/remesh.md "Session 21, fixed costs").

    python bench/remesh_fixed_costs.py --rounds 2 -- --parts 7_8ths_cube.stl g-block-pockets.stl
    python bench/remesh_fixed_costs.py --as-base main -- --parts 7_8ths_cube.stl   # base only
    python bench/remesh_fixed_costs.py --script remesh_vs_meshlab.py --rounds 1    # the ratios
"""

from __future__ import annotations

import argparse
import importlib.util
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

ROOT = Path(__file__).resolve().parents[1]


def swap_in(revision: str) -> None:
    import pds_plugin.analysis.graded_certificate as graded_certificate
    import pds_plugin.remeshing as remeshing
    from certificate_fixed_cost import base_certify

    graded_certificate.certify_graded = base_certify(revision)[0]
    text = subprocess.run(["git", "show", f"{revision}:src/pds_plugin/partition.py"], cwd=ROOT,
                          check=True, capture_output=True, text=True).stdout
    name = "pds_plugin._base_partition"
    module = importlib.util.module_from_spec(importlib.util.spec_from_loader(name, loader=None))
    module.__package__ = "pds_plugin"
    sys.modules[name] = module
    exec(compile(text, f"<{revision}:partition.py>", "exec"), module.__dict__)
    remeshing.interface_report = module.interface_report


def main() -> None:
    argv = sys.argv[1:]
    rest = argv[argv.index("--") + 1:] if "--" in argv else []
    own = argv[:argv.index("--")] if "--" in argv else argv
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--as-base", default=None, help="run once with this revision's costs")
    parser.add_argument("--base", default="main")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--script", default="remesh_profile.py",
                        help="the bench script run (its main(argv) or its __main__)")
    args = parser.parse_args(own)
    if args.as_base:
        swap_in(args.as_base)
        import runpy
        sys.argv = [args.script, *rest]
        runpy.run_path(str(ROOT / "bench" / args.script), run_name="__main__")
        return
    for k in range(args.rounds):
        for label, extra in (("base", ["--as-base", args.base, "--script", args.script]),
                             ("head", [])):
            print(f"\n=== round {k + 1}, {label}", flush=True)
            if extra:
                subprocess.run([sys.executable, __file__, *extra, "--", *rest], check=True)
            else:
                subprocess.run([sys.executable, str(ROOT / "bench" / args.script), *rest],
                               check=True)


if __name__ == "__main__":
    main()
