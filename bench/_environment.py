"""The machine, the library versions, and pds_plugin's start-up costs.

Start-up is measured in fresh subprocesses: ``import pds_plugin`` alone, and the first
``mesh_region`` + ``certificate()`` of a process (the kernels are compiled at install, so
this is imports and loading the extension modules; the first process after start-up
also reads them from disk).
"""

from __future__ import annotations

import json
import os
import platform
import statistics
import subprocess
import sys
from datetime import datetime, timezone
from importlib import metadata
from pathlib import Path

LIBRARIES = ("pds_plugin", "numpy", "scipy", "shapely", "Cython", "trimesh", "manifold3d",
             "pymeshlab", "triangle", "gmsh", "matplotlib")

_IMPORT = """
import json, time
start = time.perf_counter()
import pds_plugin
imported = time.perf_counter()
pds_plugin.mesh_region
print(json.dumps([imported - start, time.perf_counter() - imported]))
"""

SQUARE_10K_ALPHA = 0.00856899
"""The unit square's alpha for about 10,000 samples (``_regions.alpha_for``), the size of
issue 13's cold-start target."""

_FIRST_CALL = f"""
import json, time
from shapely.geometry import box
import pds_plugin as pds
region = pds.Region.from_shapely(box(0, 0, 1, 1))
times = []
for _ in range(2):
    start = time.perf_counter()
    pds.mesh_region(region, {SQUARE_10K_ALPHA}, seed=0).certificate()
    times.append(time.perf_counter() - start)
print(json.dumps(times))
"""


def machine() -> dict:
    """CPU model, cores, RAM, OS, Python, the load average now, the date and the
    repository commit."""
    return {
        "cpu": _cpu_model(),
        "cores": os.cpu_count(),
        "ram_gb": _ram_gb(),
        "os": f"{platform.system()} {platform.release()}",
        "python": platform.python_version(),
        "load": os.getloadavg(),
        "date": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "commit": _commit(),
    }


def versions() -> dict:
    """Installed version of every library the benchmark uses (None if absent)."""
    found = {}
    for name in LIBRARIES:
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            found[name] = None
    return found


def startup(repeats: int = 5) -> dict:
    """``import pds_plugin`` time (median and max of ``repeats`` fresh processes), the
    time to then reach ``mesh_region`` (the lazy import of numpy, scipy, shapely and the
    kernels' modules; median), and the first-call time of the first and of a second
    fresh process (a unit square of about 10k samples, mesh and certificate; ``in_process`` is the
    second call in that second process)."""
    imports = [json.loads(_python(_IMPORT)) for _ in range(repeats)]
    cold = json.loads(_python(_FIRST_CALL))
    warm = json.loads(_python(_FIRST_CALL))
    return {"import_median": statistics.median(first for first, _ in imports),
            "import_max": max(first for first, _ in imports),
            "first_use": statistics.median(then for _, then in imports),
            "cold_first_call": cold[0], "warm_first_call": warm[0], "in_process": warm[1]}


def _python(code: str, env: dict | None = None) -> str:
    """Run ``code`` in a fresh interpreter and return what it printed."""
    return subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True,
                          env={**os.environ, **(env or {})}).stdout.strip()


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def _ram_gb() -> float:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (ValueError, OSError, AttributeError):
        return float("nan")


def _commit() -> str:
    """``git describe`` of the repository the benchmark runs from, '-dirty' if edited."""
    try:
        return subprocess.run(["git", "describe", "--always", "--dirty"], capture_output=True,
                              text=True, check=True, cwd=Path(__file__).parent).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
