"""Region.from_shapely of a git revision (``main`` by default) against this tree's, on the
shared drawings and mesh sections (as MultiPolygons, their geometry and collections of
their parts) and on invalid input: the same geometry, source, tolerance and healing bit
for bit, the same errors word for word, and the same uniform and graded "auto" meshes.

    python bench/region_identity.py [REF]
"""
import glob
import os
import subprocess
import sys
import types
import warnings
from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import GeometryCollection, LineString, MultiPolygon, Polygon, box

import pds_plugin as pds
from pds_plugin import region as new

ROOT = Path(__file__).resolve().parents[1]
REF = sys.argv[1] if len(sys.argv) > 1 else "main"
src = subprocess.run(["git", "-C", str(ROOT), "show", f"{REF}:src/pds_plugin/region.py"],
                     check=True, capture_output=True, text=True).stdout
old = types.ModuleType("pds_plugin._region_before")
old.__package__ = "pds_plugin"
exec(compile(src, "region_before.py", "exec"), old.__dict__)
old_from = old.Region.from_shapely.__func__

def both(geometry, **kw):
    out = []
    for f in (old_from, new.Region.from_shapely.__func__):
        try:
            r = f(new.Region, geometry, **kw)
            out.append(("ok", r))
        except Exception as e:
            out.append(("err", f"{type(e).__name__}: {e}"))
    return out

def same(a, b):
    if a[0] != b[0]: return False
    if a[0] == "err": return a[1] == b[1]
    ra, rb = a[1], b[1]
    return (shapely.to_wkb(ra.geometry) == shapely.to_wkb(rb.geometry)
            and shapely.to_wkb(ra.source) == shapely.to_wkb(rb.source)
            and ra.tolerance == rb.tolerance and np.array_equal(ra.frame, rb.frame)
            and (ra._healed is None) == (rb._healed is None)
            and (ra._healed is None or (shapely.to_wkb(ra._healed[0]) == shapely.to_wkb(rb._healed[0]) and ra._healed[1] == rb._healed[1])))

cases = []
D = str(ROOT.parents[0] / "shared" / "data")
for f in sorted(glob.glob(D + "/*")):
    low = f.lower()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if low.endswith(".svg"): r = pds.load_svg(f)
            elif low.endswith(".dxf"): r = pds.load_dxf(f)
            elif low.endswith((".stl", ".step")):
                import trimesh  # noqa: F401
                if low.endswith(".stl"):
                    m = trimesh.load(f); lo, hi = m.bounds
                else:
                    from pds_plugin.sources import step; s = step.StepSolid(f); lo, hi = s.center - 1, s.center + 1
                mid = (lo + hi) / 2
                r = pds.section(f, mid + [0, 0, 1e-4 * (hi[2] - lo[2])], (0, 0, 1))
            else: continue
    except Exception as e:
        print("skip", os.path.basename(f), type(e).__name__, e); continue
    cases.append((os.path.basename(f), r.source, dict(tolerance=r.tolerance, frame=r.frame)))
    cases.append((os.path.basename(f) + " geometry", r.geometry, {}))
    # as a Polygon list / GeometryCollection / with an empty part
    cases.append((os.path.basename(f) + " collection", GeometryCollection(list(r.geometry.geoms)), {}))
bow = Polygon([(0, 0), (2, 2), (2, 0), (0, 2)])
cases += [("bowtie", bow, {}), ("bowtie repair", bow, dict(repair=True)),
          ("flat", Polygon([(0, 0), (1, 0), (2, 0)]), {}),
          ("flat repair", MultiPolygon([box(0, 0, 1, 1), Polygon([(2, 0), (3, 0), (4, 0)])]), dict(repair=True)),
          ("empty", Polygon(), {}), ("line", LineString([(0, 0), (1, 1)]), {}),
          ("nan", Polygon([(0, 0), (1, np.nan), (1, 1)]), {}),
          ("multi empty part", shapely.multipolygons([box(0, 0, 1, 1), Polygon()]), {}),
          ("touching", MultiPolygon([box(0, 0, 1, 1), box(1, 1, 2, 2)]), {}),
          ("hole touching", Polygon([(0, 0), (4, 0), (4, 4), (0, 4)], [[(0, 2), (2, 1), (2, 3)]]), {}),
          ("overlap", MultiPolygon([box(0, 0, 2, 2), box(1, 1, 3, 3)]), {}),
          ("overlap repair", MultiPolygon([box(0, 0, 2, 2), box(1, 1, 3, 3)]), dict(repair=True)),
          ("noisy tol", Polygon([(0, 0), (1, 1e-9), (2, 0), (2, 1), (0, 1)]), dict(tolerance=1e-6)),
          ("cw", Polygon([(0, 0), (0, 1), (1, 1), (1, 0)]), {}),
          ("tiny", box(0, 0, 1e-60, 1e-60), {}), ("not geometry", [(0, 0)], {}),
          ("bad frame", box(0, 0, 1, 1), dict(frame=np.zeros((4, 4)))),
          ("bad tol", box(0, 0, 1, 1), dict(tolerance=-1)), ("bad repair", box(0, 0, 1, 1), dict(repair="no"))]
bad = 0
for name, g, kw in cases:
    a, b = both(g, **kw)
    ok = same(a, b)
    bad += not ok
    print(("same " if ok else "DIFF ") + name, a[0], (a[1] if a[0] == "err" else ""))
print("differences:", bad, "of", len(cases))
# meshes of a few: identical arrays
for name, g, kw in [c for c in cases if c[0].split()[0].endswith(("svg", "dxf", "DXF", "STEP", "step", "STL")) and " " not in c[0]] + cases[-19:]:
    a, b = both(g, **kw)
    if a[0] != "ok": continue
    for graded in (False, True):
        ma = pds.mesh_region(a[1], "auto", graded=graded, seed=0); mb = pds.mesh_region(b[1], "auto", graded=graded, seed=0)
        equal = np.array_equal(ma.vertices, mb.vertices) and np.array_equal(ma.faces, mb.faces)
        print("mesh", name, "graded" if graded else "uniform", "same" if equal else "DIFFERENT")
