"""Certified at the alpha the user gives (issue 20): drawings and CAD sections meshed
uniform at fixed alphas from extent / 20 to extent / 300, two seeds each, and what the
certificate says about every mesh.

At ``alpha="auto"`` the region's walls bound alpha; a user's alpha may be larger than a
wall, a band between holes, a fillet or a lobe. The mesh must then still be certified:
``ok``, or ``ok_with_exceptions`` with every close pair and thin triangle an itemised small
feature within its proven bound, never FAILED.

Inputs: the shared drawings (``../shared/data``: MIL.svg, polygon.svg, insert.dxf,
sliding-base.dxf, wrench.dxf, spline.DXF; left out when absent), generated laser-cut
sheets (``bench/_drawings.py``: 4 plates, 100-260 holes, slots and hexagons, walls down to
a tenth of a hole's radius), and sections of CAD exports (``bench/_cad_corpus.py``: the
shared STL parts at mid-height, generated float32 parts at random planes).

Usage::

    python bench/fixed_alpha.py                 # the whole table, a few minutes
    python bench/fixed_alpha.py --quick         # 2 alphas, 1 seed
    python bench/fixed_alpha.py --write         # into docs/benchmarks.md, section 'fixed-alpha'
    python bench/fixed_alpha.py --held-out 10   # sheets 10-13, generated parts of seed 10
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import pds_plugin as pds
from _cad_corpus import DATA, case
from _drawings import laser_drawing
from _environment import machine
from _sections import put_section
from cad_corpus import reasons

REPORT = Path(__file__).resolve().parents[1] / "docs" / "benchmarks.md"
FRACTIONS = (20, 30, 45, 60, 100, 150, 300)
"""alpha = the input's extent / each of these."""
SEEDS = (0, 1)
DRAWINGS = ("MIL.svg", "polygon.svg", "insert.dxf", "sliding-base.dxf", "wrench.dxf",
            "spline.DXF")
SHEETS = 4
SECTIONS = ("teapot.stl z4/7", "featuretype.STL z4/7", "angle_block.STL z4/7",
            "ADIS16480.STL z4/7", "7_8ths_cube.stl z4/7", "g00-bolted-plate p0",
            "g03-flange p1", "g05-torus-ring p2", "g07-housing p0", "g09-tube-with-bosses p3")


def inputs(first_sheet: int = 0) -> list[tuple[str, object]]:
    """``(name, make)`` for every input present: ``make()`` gives its region; the sheets
    from seed ``first_sheet`` on."""
    found = []
    for name in DRAWINGS:
        path = DATA / name
        if path.exists():
            load = pds.load_svg if name.endswith(".svg") else pds.load_dxf
            found.append((name, lambda load=load, path=path: load(path)))
    found += [(f"sheet-{seed}", lambda seed=seed: laser_drawing(seed))
              for seed in range(first_sheet, first_sheet + SHEETS)]
    for name in SECTIONS:
        if name.startswith("g") or (DATA / name.rsplit(" ", 1)[0]).exists():
            found.append((name, lambda name=name: case(name).region()))
    return found


def run(fractions=FRACTIONS, seeds=SEEDS, first_sheet=0) -> list[dict]:
    """One record per mesh: input, fraction, seed, verdict, reasons, samples, seconds."""
    records = []
    for name, make in inputs(first_sheet):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")       # stray strokes, texts, repaired sections
            region = make()
        extent = max(np.ptp(np.reshape(region.bounds, (2, 2)), axis=0))
        for fraction in fractions:
            for seed in seeds:
                record = dict(input=name, fraction=fraction, seed=seed)
                began = time.perf_counter()
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        mesh = pds.mesh_region(region, alpha=extent / fraction, seed=seed)
                    cert = mesh.certificate()
                    verdict = ("ok" if cert.ok else "ok with exceptions"
                               if cert.ok_with_exceptions else "FAILED")
                    record.update(verdict=verdict, samples=len(mesh.vertices),
                                  reasons=reasons(cert) if verdict == "FAILED" else [])
                except pds.BudgetError as error:       # a clean refusal: alpha far too large
                    record.update(verdict="refused", samples=0,
                                  reasons=[f"{type(error).__name__}: {error}"[:160]])
                except Exception as error:             # a bench counts errors, never stops
                    record.update(verdict="error", samples=0,
                                  reasons=[f"{type(error).__name__}: {error}"[:160]])
                record["seconds"] = time.perf_counter() - began
                print(f"{name} / {fraction} / seed {seed}: {record['verdict']}"
                      + (f" ({'; '.join(record['reasons'])})" if record["reasons"] else ""),
                      flush=True)
                records.append(record)
    return records


def table(records) -> list[str]:
    lines = ["| input | meshes | ok | ok with exceptions | FAILED | error | refused | certified | "
             "samples (largest) | seconds |", "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|"]
    names = list(dict.fromkeys(r["input"] for r in records))
    for name in [*names, None]:
        rows = [r for r in records if name is None or r["input"] == name]
        count = {v: sum(r["verdict"] == v for r in rows)
                 for v in ("ok", "ok with exceptions", "FAILED", "error", "refused")}
        certified = count["ok"] + count["ok with exceptions"]
        meshed = max(len(rows) - count["refused"], 1)
        label = f"`{name}`" if name else "**all**"
        lines.append(f"| {label} | {len(rows)} | {count['ok']} | {count['ok with exceptions']} | "
                     f"{count['FAILED']} | {count['error']} | {count['refused']} | "
                     f"{100 * certified / meshed:.1f} % | {max(r['samples'] for r in rows):,} | "
                     f"{sum(r['seconds'] for r in rows):.1f} |")
    return lines


def failures(records) -> list[str]:
    bad = [r for r in records if r["verdict"] in ("FAILED", "error", "refused")]
    if not bad:
        return ["Every mesh is certified."]
    return ["Not certified (reproduce: `pds.mesh_region(region, alpha=extent / fraction, "
            "seed=seed).certificate()`):", ""] + [
        f"- `{r['input']}` at extent / {r['fraction']}, seed {r['seed']}: **{r['verdict']}** — "
        + "; ".join(r["reasons"]) for r in bad]


def section(header, records) -> str:
    return "\n".join([
        "## Fixed alphas (bench/fixed_alpha.py)\n",
        f"Written by {header}. Every input meshed uniform at alpha = its extent / "
        f"{', '.join(str(f) for f in sorted({r['fraction'] for r in records}))}, seeds "
        f"{', '.join(str(s) for s in sorted({r['seed'] for r in records}))}, and certified: "
        "*certified* = ok or ok with exceptions, of the meshes not *refused* (a clean "
        "`BudgetError`: alpha so large that hundreds of a sheet's hole samples fall within "
        "2 alpha of one point); issue 20: never FAILED. Inputs: the shared "
        "drawings, generated laser-cut sheets (`bench/_drawings.py`) and CAD sections "
        "(`bench/_cad_corpus.py`).\n",
        *table(records), "", *failures(records)])


def main(argv=None) -> list[dict]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="extent / 30 and / 150, seed 0")
    parser.add_argument("--write", action="store_true",
                        help="write the table into the section 'fixed-alpha' of --out")
    parser.add_argument("--out", type=Path, default=REPORT)
    parser.add_argument("--held-out", type=int, metavar="SEED",
                        help="inputs never tuned on: the sheets from this seed on, and the "
                        "generated sections of this corpus seed")
    args = parser.parse_args(argv)
    if args.held_out is not None:
        import _cad_corpus

        _cad_corpus.GENERATED_SEED = args.held_out
    start = machine()
    command = shlex.join(["python", "bench/fixed_alpha.py",
                          *(sys.argv[1:] if argv is None else argv)])
    header = (f"`{command}` on {start['date']} (commit `{start['commit']}`), "
              f"{start['cores']} cores, load {start['load'][0]:.1f}")
    print(header + "\n", flush=True)
    first_sheet = 0 if args.held_out is None else args.held_out
    records = (run((30, 150), (0,), first_sheet) if args.quick
               else run(first_sheet=first_sheet))
    text = section(header, records)
    print("\n" + text)
    if args.write:
        put_section(args.out, "fixed-alpha", text)
        print(f"\nwrote the section 'fixed-alpha' of {args.out}")
    return records


if __name__ == "__main__":
    main()
