"""The graded remesh with facets of curved surfaces at alpha (the default since session
25) against the same remesh grading them (``remeshing._facets`` answering no: the
meshes of before, bit for bit), and the uniform remesh, in turns on held-out parts: CPU
ms, best of ``--repeats`` (docs/remesh.md, "Session 25").

    python bench/remesh_facets.py                      # the shafts and cross-drilled blocks
    python bench/remesh_facets.py --parts 4401/6 4302/8
"""

import argparse
import time

import numpy as np

import pds_plugin as pds
from pds_plugin import remeshing
from remesh_vs_meshlab import held_out_part

PARTS = ["4302/16", "4401/36", "4301/6", "4401/26", "4401/16", "4401/6", "4401/28", "4302/8",
         "4301/18"]


def graded_throughout(patches, *args):
    """``remeshing._facets`` of before session 25: no patch is a facet."""
    return np.zeros(len(patches), bool)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--parts", nargs="*", default=PARTS, help="held-out SEED/K")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    facets = remeshing._facets
    print("| part | graded before | graded now | now / before | uniform |\n|---|---|---|---|---|")
    for part in args.parts:
        seed, k = map(int, part.split("/"))
        name, source, _ = held_out_part(seed, k)
        best = {"before": np.inf, "now": np.inf, "uniform": np.inf}
        for _ in range(args.repeats):
            for mode in best:
                remeshing._facets = graded_throughout if mode == "before" else facets
                start = time.process_time()
                pds.remesh(source, "auto", graded=mode != "uniform", seed=k)
                best[mode] = min(best[mode], time.process_time() - start)
        remeshing._facets = facets
        before, now, uniform = (1e3 * best[m] for m in ("before", "now", "uniform"))
        print(f"| {name} {part} | {before:.0f} ms | {now:.0f} ms | {now / before:.2f} | "
              f"{uniform:.0f} ms |", flush=True)


if __name__ == "__main__":
    main()
