"""Try every class of bad and hostile input and write docs/reliability.md.

    python bench/reliability.py                      # every class (about 5 minutes)
    python bench/reliability.py --classes "SVG files,point sets" --time-limit 10

Each class's inputs (bench/_corpus.py lists the classes) run one after the other in a worker process,
under a time limit and a memory limit per input (the resident memory of the worker and
all its children, polled): an input over either limit is a *hang*, its worker is killed
with its whole process group, and a fresh worker goes on with the next input. A worker
that dies is an *other exception* for the input it was running. Every input ends as one
of:

- **clean error**: the package's error type (``PdsError`` and ``OSError`` for files;
  ``ValueError``/``TypeError`` before the error type existed), or for the command line
  exit status 1 or 2 with one ``pds-mesh: error:`` line and no file left behind;
- **other exception**: any other exception, a traceback, a crash;
- **hang**: over the time or memory limit, or processes left running;
- **silent wrong**: accepted, but the oracle (shapely, KD-tree, Qhull, re-reading the
  files; never the certificate) finds the result wrong;
- **right**: accepted and right.

Independently, **mutated** counts the inputs (objects or files) whose digest changed.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import select
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from datetime import datetime, timezone
from pathlib import Path

BENCH = Path(__file__).resolve().parent
REPORT = BENCH.parent / "docs" / "reliability.md"
COLUMNS = ("tried", "clean", "other", "hang", "wrong", "mutated", "right")


def parse(argv=None):
    from _corpus import CLASSES

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--classes", type=lambda t: [c.strip() for c in t.split(",")],
                        default=list(CLASSES), help="comma-separated classes (default: all): "
                        + "; ".join(CLASSES))
    parser.add_argument("--time-limit", type=float, default=30.0,
                        help="seconds per input (default 30)")
    parser.add_argument("--memory-limit", type=float, default=2048.0,
                        help="MiB of resident memory per input, children included (default 2048)")
    parser.add_argument("--output", type=Path, default=REPORT,
                        help=f"the Markdown report (default {REPORT.relative_to(BENCH.parent)})")
    parser.add_argument("--worker", nargs=2, metavar=("CLASS", "FIRST"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    unknown = set(args.classes) - set(CLASSES)
    if unknown:
        parser.error(f"unknown classes {sorted(unknown)}; choose from {list(CLASSES)}")
    return args


# --- the worker: runs a class's inputs from FIRST on, one JSON line per input ----------

def _clean_errors():
    try:
        from pds_plugin.errors import PdsError
    except ImportError:                       # before the package had its own error type
        return (ValueError, TypeError, OSError)
    return (PdsError, OSError)


def worker(name: str, first: int) -> None:
    import warnings

    from _corpus import CLASSES
    from _hostile import digest

    warnings.simplefilter("ignore")
    clean = _clean_errors()
    cases = CLASSES[name]()
    _warm_up()
    for index in range(first, len(cases)):
        print(json.dumps({"index": index, "start": cases[index].name}), flush=True)
        with tempfile.TemporaryDirectory(prefix="pds_reliability_") as folder:
            outcome = _try(cases[index], Path(folder), clean, digest)
        print(json.dumps({"index": index, **outcome}), flush=True)


def _warm_up() -> None:
    """Load (or compile) the numba kernels before any input's clock starts."""
    import pds_plugin as pds
    from shapely.geometry import box

    pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.3).certificate()


def _try(case, folder, clean, digest) -> dict:
    try:
        trial = case.make(folder)
    except Exception as error:                # the harness's own bug: say so loudly
        return {"verdict": "other", "message": f"building the input failed: {error!r}"}
    before = digest(*trial.inputs)
    try:
        result = trial.call()
    except clean as error:
        verdict, message = "clean", f"{type(error).__name__}: {error}"
    except Exception as error:
        frame = traceback.extract_tb(error.__traceback__)[-1]
        verdict, message = "other", (f"{type(error).__name__}: {error} "
                                     f"({Path(frame.filename).name}:{frame.lineno})")
    else:
        try:
            judged = trial.check(result)
        except Exception as error:
            judged = ("other", f"the result could not be checked: {error!r}")
        verdict, message = judged if judged is not None else ("right", "")
    mutated = digest(*trial.inputs) != before
    message = " ".join(str(message).split())[:300]     # undecodable bytes of a file, escaped:
    message = message.encode("utf-8", "backslashreplace").decode("utf-8")
    return {"verdict": verdict, "message": message, "mutated": mutated}


# --- the parent: limits, restarts, the table -----------------------------------------

def _descendants(pid: int) -> list[int]:
    found, todo = [], [pid]
    while todo:
        current = todo.pop()
        found.append(current)
        try:
            todo += [int(p) for p in Path(f"/proc/{current}/task/{current}/children")
                     .read_text().split()]
        except OSError:
            pass
    return found


def _resident_mib(pids) -> float:
    total = 0
    for pid in pids:
        try:
            for line in Path(f"/proc/{pid}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    total += int(line.split()[1])
        except OSError:
            pass
    return total / 1024


def run_class(name: str, count: int, time_limit: float, memory_limit: float) -> list[dict]:
    outcomes, first = [], 0
    while first < count:
        child = subprocess.Popen([sys.executable, __file__, "--worker", name, str(first)],
                                 stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                                 start_new_session=True, cwd=BENCH)
        started, current, over = None, first, None              # no clock while warming up
        try:
            while over is None:
                ready, _, _ = select.select([child.stdout], [], [], 0.1)
                if ready:
                    line = child.stdout.readline()
                    if not line:
                        break                                    # the worker ended
                    record = json.loads(line)
                    if "start" in record:
                        current, started = record["index"], time.monotonic()
                        _progress(name, current, count, record["start"])
                    else:
                        outcomes.append(record)
                        current = record["index"] + 1
                    continue
                if started is not None and time.monotonic() - started > time_limit:
                    over = f"still running after {time_limit:g} s"
                elif (memory := _resident_mib(_descendants(child.pid))) > memory_limit:
                    over = f"over {memory_limit:g} MiB ({memory:.0f} MiB)"
        finally:
            for pid in reversed(_descendants(child.pid)):
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            try:
                os.killpg(child.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            child.wait()
        if current < count and (not outcomes or outcomes[-1]["index"] < current):
            outcomes.append({"index": current, "verdict": "hang" if over else "other",
                             "message": over or f"the worker died (exit {child.returncode})",
                             "mutated": False})
            current += 1
        first = current
    return outcomes


def _progress(name, index, count, what):
    if sys.stderr.isatty():
        print(f"\r{name}: {index + 1}/{count} {what[:60]:<60}", end="", file=sys.stderr,
              flush=True)


def summarize(outcomes) -> dict:
    row = dict.fromkeys(COLUMNS, 0)
    row["tried"] = len(outcomes)
    for outcome in outcomes:
        row[outcome["verdict"]] += 1
        row["mutated"] += bool(outcome.get("mutated"))
    return row


def report(results: dict, args, seconds: float) -> str:
    import pds_plugin
    from _corpus import TIME_LIMITS

    header = ("| class | inputs tried | clean errors | other exceptions | hangs | silent wrong "
              "| mutated | right results |")
    lines = ["# Reliability: bad and hostile inputs", "",
             f"Written by `python bench/reliability.py` on "
             f"{datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC, pds_plugin "
             f"{pds_plugin.__version__}, Python {platform.python_version()}, "
             f"{os.cpu_count()} cores, in {seconds / 60:.1f} min. Limits per input: "
             f"{args.time_limit:g} s (more for the classes that run pds-mesh: "
             f"{', '.join(f'{k} {v:g} s' for k, v in TIME_LIMITS.items())}) and "
             f"{args.memory_limit:g} MiB of resident memory (children included). The "
             "inputs and their oracles are in `bench/_hostile.py`, `bench/_hostile_files.py` and "
             "`bench/_hostile_generated.py` (classes listed in `bench/_corpus.py`); what each "
             "column means is in the docstring of `bench/reliability.py`. Every "
             "column but *inputs tried*, *clean errors* and *right results* should be 0.", "",
             header, "|---|--:|--:|--:|--:|--:|--:|--:|"]
    total = dict.fromkeys(COLUMNS, 0)
    for name, (cases, outcomes) in results.items():
        row = summarize(outcomes)
        total = {k: total[k] + row[k] for k in COLUMNS}
        lines.append(f"| {name} | " + " | ".join(str(row[k]) for k in COLUMNS) + " |")
    lines.append("| **all** | " + " | ".join(f"**{total[k]}**" for k in COLUMNS) + " |")
    problems = [(name, cases[o["index"]], o) for name, (cases, outcomes) in results.items()
                for o in outcomes if o["verdict"] in ("other", "hang", "wrong") or o["mutated"]]
    lines += ["", "## What is still wrong", ""]
    lines += [f"- {name}, *{case}*: **{o['verdict']}**{' (mutated)' if o['mutated'] else ''} "
              f"— {o['message']}" for name, case, o in problems] or ["Nothing."]
    lines += ["", "## Every input", ""]
    for name, (cases, outcomes) in results.items():
        lines += [f"### {name}", "", "| input | verdict | message |", "|---|---|---|"]
        lines += [f"| {cases[o['index']]} | {o['verdict']}{' (mutated)' if o['mutated'] else ''}"
                  f" | {o['message'].replace('|', '/')[:160]} |" for o in outcomes]
        lines.append("")
    return "\n".join(lines)


def main(argv=None) -> Path:
    sys.path.insert(0, str(BENCH))
    args = parse(argv)
    if args.worker:
        worker(args.worker[0], int(args.worker[1]))
        return None
    from _corpus import CLASSES, TIME_LIMITS

    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))    # kill the workers on the way out
    began, results = time.monotonic(), {}
    for name in args.classes:
        names = [case.name for case in CLASSES[name]()]
        limit = max(args.time_limit, TIME_LIMITS.get(name, 0.0))
        results[name] = (names, run_class(name, len(names), limit, args.memory_limit))
        row = summarize(results[name][1])
        print(f"\r{name}: " + ", ".join(f"{k} {row[k]}" for k in COLUMNS) + " " * 40,
              file=sys.stderr)
    args.output.write_text(report(results, args, time.monotonic() - began) + "\n",
                           encoding="utf-8")
    print(f"wrote {args.output}", file=sys.stderr)
    return args.output


if __name__ == "__main__":
    main()
