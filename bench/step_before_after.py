"""pds.section of the bench's STEP parts before and after a change, in one process: the
STEP reader and Region.from_shapely of a git revision (``main`` by default) loaded as
second modules beside this tree's, each section timed against the Booleans it runs
(bench/step_vs_stl.py's "its Booleans"), the calls taking turns; and whether the two
give the same rings (a hash of them).

    python bench/step_before_after.py            # against main
    python bench/step_before_after.py --ref c0829aa
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import types
from pathlib import Path

import pds_plugin as pds
from pds_plugin.sources import step
from pds_plugin.sources.planes import checked_on_face, checked_plane

sys.path.insert(0, str(Path(__file__).resolve().parent))
import step_stages as stages  # noqa: E402
import step_vs_stl as bench  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def _source(ref, path):
    return subprocess.run(["git", "-C", str(ROOT), "show", f"{ref}:{path}"], check=True,
                          capture_output=True, text=True).stdout


def _module(name, text, package):
    module = types.ModuleType(name)
    module.__package__ = package
    module.__file__ = f"<{name}>"
    sys.modules[name] = module
    exec(compile(text, module.__file__, "exec"), module.__dict__)
    return module


def old_reader(ref):
    """The revision's ``sources/step.py``, its Region that revision's ``region.py``."""
    _module("pds_plugin._region_before", _source(ref, "src/pds_plugin/region.py"),
            "pds_plugin")
    text = _source(ref, "src/pds_plugin/sources/step.py").replace(
        "from ..region import Region", "from .._region_before import Region")
    return _module("pds_plugin.sources._step_before", text, "pds_plugin.sources")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--ref", default="main")
    parser.add_argument("--rounds", type=int, default=40)
    args = parser.parse_args()
    before = old_reader(args.ref)

    def section(module, shape, origin, normal):
        origin, normal = checked_plane(origin, normal)
        return module.StepSolid(shape).cut(origin, normal, checked_on_face(None))

    print(f"| part | its Booleans (ms) | {args.ref} (ms) | / its Booleans | now (ms) | "
          f"/ its Booleans | now / {args.ref} | after the Booleans, {args.ref} (ms) | now (ms) "
          f"| same rings |")
    print("|---" * 10 + "|")
    with tempfile.TemporaryDirectory() as folder:
        for name, shape, origin, normal in stages.cases(folder):
            old = section(before, shape, origin, normal)
            new = pds.section(shape, origin, normal)
            same = stages.ring_hash(old) == stages.ring_hash(new)
            own, was, now = stages.interleaved(
                bench.own_booleans(shape, origin, normal),
                lambda: section(before, shape, origin, normal),
                lambda: section(step, shape, origin, normal),
                rounds=args.rounds, budget=30.0)
            print(f"| {name} | {1e3 * own:.2f} | {1e3 * was:.2f} | {was / own:.2f} | "
                  f"{1e3 * now:.2f} | **{now / own:.2f}** | {now / was:.2f} | "
                  f"{1e3 * (was - own):.2f} | {1e3 * (now - own):.2f} | "
                  f"{'yes' if same else 'NO'} |", flush=True)


if __name__ == "__main__":
    main()
