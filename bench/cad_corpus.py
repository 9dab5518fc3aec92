"""Certify meshes of real CAD exports (issue 20): every section of the corpus of
``bench/_cad_corpus.py`` meshed three ways, and what the certificate says about each.

    python bench/cad_corpus.py                  # the whole corpus (about 10 minutes)
    python bench/cad_corpus.py --quick          # a slice: 2 planes per shared part, 5 generated
    python bench/cad_corpus.py --only teapot.stl --only "g03-flange p2" --verbose
    python bench/cad_corpus.py --jobs 2 --write # two worker processes; write docs/benchmarks.md
    python bench/cad_corpus.py --source occt --seed 5  # OpenCASCADE's exports (the [step] extra)
    python bench/cad_corpus.py --grading 0.45   # the graded mode only, at a steep grading

Each section is meshed uniform at ``alpha="auto"``, graded at ``alpha="auto"`` and uniform
at alpha = its extent / 150 (``_cad_corpus.MODES``), then certified. A mesh is **ok**
(``certificate.ok``), **ok with exceptions** (``ok_with_exceptions``: every breach at a
small feature explained and within its proven bound), **FAILED**, an **error** (the
section or the mesher raised; the exception's type is kept) or **refused**: ``pds.section``
refused the plane with a SectionError, because the part is open where the plane cuts it
(``teapot.stl`` is not watertight) or the plane passes through a gap between bodies
(``multibody.stl``): a clean refusal of a plane with no valid section, counted apart and
left out of the *certified* share. For every mesh that is not certified the reasons
are read off its certificate (:func:`reasons`). The script prints
the verdict counts per mode and source, the reasons, the failing cases (each with the
name that reproduces it: ``--only NAME --verbose`` prints its certificates) and the
times of meshing and of the certificate; ``--write`` puts the same tables into the
section ``cad-corpus`` of docs/benchmarks.md (which peers.py keeps).
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import statistics
import sys
import time
import traceback
import warnings
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from functools import partial
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import _cad_corpus  # noqa: E402
from _cad_corpus import DATA, MODES, all_cases, case, mesh, occt_cases  # noqa: E402
from _environment import machine                             # noqa: E402
from _sections import put_section                            # noqa: E402

VERDICTS = ("ok", "ok with exceptions", "FAILED", "error", "refused")
REPORT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks.md"
LISTED_IN_REPORT = 60     # lines of failing meshes in docs/benchmarks.md (all are printed)

# (words in a topology problem, the failure class it belongs to)
_TOPOLOGY = (("has no triangle", "topology: component lost"),
             ("is broken into", "topology: component broken"),
             ("are joined by", "topology: components joined"),
             ("is filled by", "topology: hole filled"),
             ("is merged with", "topology: holes merged"),
             ("opened to the outside", "topology: hole opened to the outside"),
             ("uncovered hole inside", "topology: uncovered hole inside a component"),
             ("is split into", "topology: hole split"),
             ("closed off into a hole", "topology: notch closed into a hole"))
# (words in a boundary problem, the failure class it belongs to)
_BOUNDARY = (("bends both ways", "boundary bends both ways between consecutive samples"),
             ("not joined by a mesh edge", "consecutive boundary samples not joined"),
             ("end at interior samples", "mesh-boundary edges end at interior samples"),
             ("too few to be a ring", "a ring with too few boundary samples"),
             ("alpha off it", "boundary samples off the boundary"),
             ("are not chords", "mesh-boundary edges that are not chords"),
             ("clockwise or flat", "clockwise or flat triangles"),
             ("triangles overlap", "triangles overlap"),
             ("not the polygon through", "outline is not the sampled polygon"),
             ("not the slivers", "chords cross other boundary"))


def reasons(cert) -> list[str]:
    """The failure classes of a certificate that is not ``ok_with_exceptions`` (empty
    for one that is): which of its checks fail, in words that group alike failures.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> reasons(pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2).certificate())
    []
    """
    from pds_plugin.analysis.certificate import COVERAGE_TOL, SEPARATION_TOL

    if cert.ok_with_exceptions:
        return []
    found = []
    if cert.coverage_gap > 1 + COVERAGE_TOL:
        found.append("coverage above alpha")
    for text in cert.unexplained:
        found.append("unexplained close pairs" if "pairs of samples" in text
                     else "unexplained triangles below the angle bound")
    if any(not e.meets_bound for e in cert.exceptions):
        found.append("exception beyond its proven bound")
    excused = cert.exceptions or cert.excused_pairs or cert.unexplained
    if cert.min_separation < 1 - SEPARATION_TOL and not excused:
        found.append("separation below alpha, no small feature named")
    if not cert.quality_ok and not excused:
        found.append("triangles below the angle bound, no small feature named")
    if not cert.topology_ok:
        named = [label for text in cert.topology.problems
                 for words, label in _TOPOLOGY if words in text]
        found += named or ["topology: Betti numbers differ"]
    if cert.isolated_samples:
        found.append("isolated samples")
    if cert.nonmanifold_vertices:
        found.append("non-manifold vertices")
    if cert.claims_conforming and not cert.boundary_ok:
        named = [label for text in cert.boundary_problems
                 for words, label in _BOUNDARY if words in text]
        found += named or ["boundary: not conforming (unnamed)"]
    return list(dict.fromkeys(found)) or ["unclassified"]


def run_case(name: str, modes=MODES, verbose=False) -> list[dict]:
    """Mesh and certify one case in every mode: one record per mode."""
    from pds_plugin.errors import SectionError   # (and pds_plugin, before the clock starts)

    found = case(name)
    base = {"name": name, "source": found.source, "part": found.part}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            region = found.region()
    except Exception as error:
        outcome = _error("section", error, refused=isinstance(error, SectionError))
        return [{**base, "mode": mode, **outcome} for mode in modes]
    base["tolerance_s"] = _tolerance_pass_seconds(region)
    records = []
    for mode in modes:
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                start = time.perf_counter()
                result = mesh(region, mode)
                meshed = time.perf_counter()
                cert = result.certificate()
                certified = time.perf_counter()
        except Exception as error:
            records.append({**base, "mode": mode, **_error("mesh", error)})
            continue
        said = list(dict.fromkeys(_warning_class(str(w.message)) for w in caught))
        verdict = ("ok" if cert.ok else "ok with exceptions" if cert.ok_with_exceptions
                   else "FAILED")
        records.append({**base, "mode": mode, "verdict": verdict, "reasons": reasons(cert),
                        "alpha": float(result.alpha), "samples": len(result.vertices),
                        "mesh_s": meshed - start, "cert_s": certified - meshed,
                        "coverage": float(cert.coverage_gap),
                        "separation": float(cert.min_separation), "warnings": said,
                        **({"certificate": str(cert)} if verbose and verdict == "FAILED" else {})})
    return records


def _tolerance_pass_seconds(region) -> float:
    """What the tolerance pass adds to making the region (the simplification, the pinches
    opened, the deviation measured): ``Region.from_shapely`` of the cut with the region's
    tolerance less the same without one, the fastest of three each."""
    from pds_plugin import Region

    def fastest(tolerance):
        times = []
        for _ in range(3):
            start = time.perf_counter()
            Region.from_shapely(region.source, region.frame, tolerance=tolerance).source_deviation
            times.append(time.perf_counter() - start)
        return min(times)

    return max(0.0, fastest(region.tolerance) - fastest(0.0)) if region.tolerance else 0.0


_WARNINGS = (("over the budget", "alpha kept above a feature by the sample budget"),
             ("beyond its limit", "alpha kept above a feature by the sampling grid's limit"),
             ("times below the region's inradius",
              "uniform alpha set by one feature far below the inradius (graded advised)"))


def _warning_class(message: str) -> str:
    """A warning's class: a known one by its words, else its first words."""
    for words, label in _WARNINGS:
        if words in message:
            return label
    return " ".join(message.split()[:8]) + " ..."


def _error(stage, error, refused=False) -> dict:
    frame = traceback.extract_tb(error.__traceback__)[-1]
    message = " ".join(str(error).split())[:200]
    what = f"refused by {stage}" if refused else f"error in {stage}"
    return {"verdict": "refused" if refused else "error",
            "reasons": [f"{what}: {type(error).__name__}"],
            "error": f"{type(error).__name__}: {message} ({Path(frame.filename).name}:"
                     f"{frame.lineno})"}


def run(names, jobs=1, verbose=False, modes=MODES) -> list[dict]:
    """Every case's records, in the order of ``names``."""
    records = []
    one = partial(run_case, modes=modes, verbose=verbose)
    if jobs > 1:
        os.environ.setdefault("PDS_THREADS", "1")     # the workers share the cores
        with ProcessPoolExecutor(jobs) as pool:
            outcomes = pool.map(one, names)
    else:
        outcomes = map(one, names)
    for k, found in enumerate(outcomes):
        records += found
        if sys.stderr.isatty():
            print(f"\r{k + 1}/{len(names)} {names[k][:60]:<60}", end="", file=sys.stderr,
                  flush=True)
    if sys.stderr.isatty():
        print("\r" + " " * 79 + "\r", end="", file=sys.stderr)
    return records


# --- tables ------------------------------------------------------------------------------

def verdict_table(records) -> list[str]:
    """Verdict counts per source and mode, and for all sources."""
    lines = ["| source | mode | meshes | ok | ok with exceptions | FAILED | error | refused "
             "| certified |", "|---|---|--:|--:|--:|--:|--:|--:|--:|"]
    for source in ("shared", "generated", "occt", "all"):
        for mode in MODES:
            mine = [r for r in records if r["mode"] == mode and source in ("all", r["source"])]
            if not mine:
                continue
            count = Counter(r["verdict"] for r in mine)
            certified = count["ok"] + count["ok with exceptions"]
            meshable = len(mine) - count["refused"]
            bold = "**" if source == "all" else ""
            lines.append(f"| {bold}{source}{bold} | {mode} | {len(mine)} | "
                         + " | ".join(str(count[v]) for v in VERDICTS)
                         + f" | {100 * certified / max(meshable, 1):.1f} % |")
    return lines


def _modes(records) -> list[str]:
    """The modes of :data:`MODES` that ``records`` hold (``--grading``: the graded one)."""
    return [mode for mode in MODES if any(r["mode"] == mode for r in records)]


def reason_table(records) -> list[str]:
    """How many meshes of each mode fail for each reason (a mesh can have several)."""
    modes = _modes(records)
    count = Counter((reason, r["mode"]) for r in records for reason in r["reasons"])
    names = sorted({reason for reason, _ in count}, key=lambda n: -sum(
        count[n, mode] for mode in modes))
    if not names:
        return ["Every mesh is certified."]
    lines = ["| failure class | " + " | ".join(modes) + " | all |",
             "|---|" + "--:|" * (len(modes) + 1)]
    for name in names:
        row = [count[name, mode] for mode in modes]
        lines.append(f"| {name} | " + " | ".join(map(str, row)) + f" | {sum(row)} |")
    return lines


def warning_table(records) -> list[str]:
    """How many meshes of each mode warned, by the warning's class."""
    modes = _modes(records)
    count = Counter((said, r["mode"]) for r in records for said in r.get("warnings", ()))
    names = sorted({said for said, _ in count}, key=lambda n: -sum(count[n, m] for m in modes))
    if not names:
        return ["No mesh warned."]
    lines = ["| warning | " + " | ".join(modes) + " | all |", "|---|" + "--:|" * (len(modes) + 1)]
    for name in names:
        row = [count[name, mode] for mode in modes]
        lines.append(f"| {name} | " + " | ".join(map(str, row)) + f" | {sum(row)} |")
    return lines


def failing_list(records, limit=None) -> list[str]:
    """The meshes that are not certified, one line per case and outcome (the modes that
    share it named together), by case name; with a ``limit``, the first ``limit`` lines
    with the rarest failure classes first, so that each class is shown."""
    groups = {}
    for r in records:
        if r["verdict"] in ("FAILED", "error", "refused"):
            said = "; ".join(r["reasons"]) if r["verdict"] == "FAILED" else r["error"]
            groups.setdefault((r["name"], r["verdict"], said), []).append(r)
    order = list(groups)
    if limit is not None:
        share = Counter("; ".join(mine[0]["reasons"]) for mine in groups.values())
        order.sort(key=lambda key: share["; ".join(groups[key][0]["reasons"])])
    lines = []
    for name, verdict, said in order[:limit]:
        mine = groups[name, verdict, said]
        numbers = "".join(f" ({r['mode']}: coverage {r['coverage']:.3g}, separation "
                          f"{r['separation']:.3g})" for r in mine if verdict == "FAILED")
        modes = ", ".join(r["mode"] for r in mine)
        lines.append(f"- `{name}` / {modes}: **{verdict}** — {said}{numbers}")
    if limit is not None and len(groups) > limit:
        lines.append(f"- ... {len(groups) - limit} more: run the script for the whole list")
    return lines or ["None."]


def time_table(records) -> list[str]:
    """Per mode: meshes timed, total, median and largest time of meshing and of the
    certificate, in seconds."""
    lines = ["| mode | meshes | meshing total | median | max | certificate total | median | "
             "max | certificate / meshing |", "|---|--:|--:|--:|--:|--:|--:|--:|--:|"]
    for mode in MODES:
        timed = [r for r in records if r["mode"] == mode and "mesh_s" in r]
        if not timed:
            continue
        m, c = [r["mesh_s"] for r in timed], [r["cert_s"] for r in timed]
        lines.append(f"| {mode} | {len(timed)} | {sum(m):.1f} | {statistics.median(m):.3f} | "
                     f"{max(m):.2f} | {sum(c):.1f} | {statistics.median(c):.3f} | {max(c):.2f} "
                     f"| {sum(c) / sum(m):.2f} |")
    passes = {r["name"]: r["tolerance_s"] for r in records if "tolerance_s" in r}
    meshing = sum(r["mesh_s"] for r in records if "mesh_s" in r)
    if passes and meshing:
        lines.append(f"\nTolerance pass: {sum(passes.values()):.2f} s over {len(passes)} sections, "
                     f"{100 * sum(passes.values()) / meshing:.1f} % of the meshing time of the "
                     f"{len(_modes(records))} modes (issue 20's target: at most 10 %); at most "
                     f"{max(passes.values()) * 1e3:.1f} ms for one section.")
    slow = max((r for r in records if "mesh_s" in r), key=lambda r: r["mesh_s"] + r["cert_s"],
               default=None)
    if slow:
        lines.append(f"\nSlowest: `{slow['name']}` / {slow['mode']}, {slow['mesh_s']:.2f} s "
                     f"meshing + {slow['cert_s']:.2f} s certificate ({slow['samples']:,} samples).")
    return lines


def report(records, seconds, jobs, limit=None) -> list[str]:
    sections = len({r["name"] for r in records})
    return ["### Verdicts", "", *verdict_table(records), "",
            "### Why the others are not certified", "", *reason_table(records), "",
            "### Warnings while meshing", "", *warning_table(records), "",
            "### Time (seconds)", "", *time_table(records), "",
            f"{sections} section{'s' * (sections != 1)}, {len(records)} meshes in {seconds / 60:.1f} min "
            f"({jobs} process{'es' if jobs > 1 else ''}).", "",
            "### Meshes not certified (reproduce: `python bench/cad_corpus.py --only NAME "
            "--verbose`)", "", *failing_list(records, limit)]


# --- command line ------------------------------------------------------------------------

def selected(args) -> list[str]:
    cases = occt_cases() if args.source == "occt" else all_cases()
    if args.quick:
        cases = [c for c in cases if (c.source == "shared" and c.plane in ("z4/7", "tilt-x"))
                 or (c.source == "generated" and c.plane == "p0"
                     and int(c.part[1:3]) % 4 == 0)]
    if args.source:
        cases = [c for c in cases if c.source == args.source]
    if args.only:
        cases = [c for c in cases if any(word in c.name for word in args.only)]
    return [c.name for c in cases]


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="a slice: 2 planes of each shared part, 5 generated sections")
    parser.add_argument("--only", action="append", metavar="NAME",
                        help="cases whose name contains NAME (repeat for several), e.g. "
                        "'teapot.stl', 'teapot.stl z5/7', 'g03-flange'")
    parser.add_argument("--source", choices=("shared", "generated", "occt"),
                        help="only these parts; occt: OpenCASCADE's STL exports of random "
                        "B-rep parts (not in the default corpus; needs the [step] extra)")
    parser.add_argument("--seed", type=int,
                        help="the seed of the generated parts (default 20): another seed gives "
                        "held-out parts the corpus was never tuned on")
    parser.add_argument("--grading", type=float,
                        help="the graded mode's grading L (default 0.2); with it only the "
                        "graded mode runs, e.g. --grading 0.45 for a steep one")
    parser.add_argument("--jobs", type=int, default=1,
                        help="worker processes (default 1; each then runs the kernels on "
                        "one thread)")
    parser.add_argument("--verbose", action="store_true",
                        help="print the certificate of every FAILED mesh")
    parser.add_argument("--write", action="store_true",
                        help="write the tables into the section 'cad-corpus' of --out")
    parser.add_argument("--out", type=Path, default=REPORT,
                        help="the report (default docs/benchmarks.md)")
    parser.add_argument("--json", type=Path, metavar="PATH",
                        help="also write every mesh's record (verdict, reasons, alpha, samples, "
                        "times, error) to PATH as JSON")
    return parser.parse_args(argv)


def section(header, records, seconds, jobs) -> str:
    """The section 'cad-corpus' of docs/benchmarks.md."""
    return "\n".join([
        "## Real CAD exports (bench/cad_corpus.py)\n",
        f"Written by {header}. Each section of the corpus (`bench/_cad_corpus.py`: the shared "
        "STL parts at 7 z levels, 2 tilted planes and the planes of issue 20; 20 generated "
        "manifold3d/trimesh parts placed at random angles, written to binary STL (float32) "
        "and read back, at 5 random planes each) is meshed uniform `alpha=\"auto\"`, graded "
        "`alpha=\"auto\"` and uniform at alpha = extent / 150, and certified. *certified* = "
        "ok or ok with exceptions, out of the meshes not *refused* (planes `pds.section` "
        "refuses cleanly: through an open part of `teapot.stl`, through the gap between "
        "the bodies of `multibody.stl`); issue 20's target is ≥ 99.5 % in every mode.\n",
        *report(records, seconds, jobs, LISTED_IN_REPORT)])


def main(argv=None) -> list[dict]:
    args = parse(argv)
    if args.seed is not None:           # before the first generated part; workers inherit it
        os.environ["PDS_CORPUS_SEED"] = str(args.seed)
        _cad_corpus.GENERATED_SEED = args.seed
    modes = MODES
    if args.grading is not None:        # likewise: the workers read it when they start
        os.environ["PDS_CORPUS_GRADING"] = str(args.grading)
        _cad_corpus.GRADING = args.grading
        modes = ("graded auto",)
    names = selected(args)
    start = machine()
    command = shlex.join(["python", "bench/cad_corpus.py", *(sys.argv[1:] if argv is None
                                                             else argv)])
    header = (f"`{command}` on {start['date']} (commit `{start['commit']}`), {start['cores']} "
              f"cores, load {start['load'][0]:.1f}; shared parts "
              f"{'from' if DATA.exists() else 'absent:'} ../shared/data")
    print(header + "\n", flush=True)
    began = time.perf_counter()
    records = run(names, args.jobs, args.verbose, modes)
    seconds = time.perf_counter() - began
    print("\n".join(report(records, seconds, args.jobs)))
    if args.verbose:
        for r in records:
            if r.get("certificate"):
                print(f"\n{r['name']} / {r['mode']}:\n{r['certificate']}")
    if args.json:
        args.json.write_text(json.dumps(records, indent=1) + "\n")
    if args.write:
        put_section(args.out, "cad-corpus", section(header, records, seconds, args.jobs))
        print(f"\nwrote the section 'cad-corpus' of {args.out}")
    return records


if __name__ == "__main__":
    main()
