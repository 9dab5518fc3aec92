"""``alpha="auto"`` on a ~1k-vertex CAD section against Triangle pq30 on the same polygon
(issue 13's target: at most 5× Triangle's time, warm).

The section is the mid-height cut of ``featuretype.STL`` from the shared data folder.
Both meshers run warm in this process: pds_plugin's ``mesh_region(region, "auto")`` (the
uniform automatic alpha, the Python API's default) after one untimed call, and Triangle
``pq30`` with the area switch that gives the same vertex count (chosen untimed). Each
time is the median of ``repeats`` runs, as wall time.
"""

from __future__ import annotations

import statistics
from time import perf_counter

import pds_plugin as pds
from _regions import DATA, stl_section
from _runners import _area_for_vertices, _pslg

PART = "featuretype.STL"


def auto_path(repeats: int = 5) -> dict | None:
    """Times and vertex counts of both meshers, or None without the part or Triangle."""
    try:
        import triangle
    except ImportError:
        return None
    if not (DATA / PART).exists():
        return None
    region = stl_section(PART)()
    mesh = pds.mesh_region(region, "auto")
    ours = _median(lambda: pds.mesh_region(region, "auto"), repeats)
    pslg = _pslg(region)
    switches = f"pq30a{_area_for_vertices(pslg, 'pq30', len(mesh.vertices), region.area):.20f}Q"
    theirs = _median(lambda: triangle.triangulate(pslg, switches), repeats)
    return {"region": f"{PART} z-mid", "boundary_vertices": sum(map(len, region.rings)),
            "vertices": len(mesh.vertices), "pds": ours,
            "triangle_vertices": len(triangle.triangulate(pslg, switches)["vertices"]),
            "triangle": theirs}


def _median(run, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = perf_counter()
        run()
        times.append(perf_counter() - start)
    return statistics.median(times)
