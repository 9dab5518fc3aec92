"""Where one ``pds.remesh`` call goes, stage by stage (issue 24's time target, issue 21
item 1; docs/remesh.md "Where the time goes").

    python bench/remesh_profile.py                          # the four parts slower than MeshLab
    python bench/remesh_profile.py --parts shared.STL --repeat 5
    python bench/remesh_profile.py --hashes                 # the output meshes' SHA-256 only
    python bench/remesh_profile.py --cprofile 25            # and cProfile's top functions

Per part: CPU time of the process (``time.process_time``) per call, warm (one untimed
call first), averaged over ``--repeat`` calls; then the time of each stage (CPU time of
the process in the wrapped function, the shared machine's load disturbs it less than wall
time; nested stages included in their parents, so the column does not add up), its calls per remesh, and per remeshed patch. Stages: the radius fields, the
chains and their agreement (``partition``), the copies of repeated faces (``_translates``
picks them, ``_translated`` makes and certifies each), the meshing of the patches (the graded
sampler's boundary, leaves, dart passes and refinement levels, the complex, the exact
tie-break), and the assembly (placing interior samples on the input, splitting kept
faces, the solid's checks, the interface report). Patch finding (``_as_trimesh``,
``_coplanar_patches``, ``_usable_patches`` with its ``_plane_rings`` and ``_patch``), the
copies' matching (``_rolled``) and the certificates measured during the remesh
(``certify_graded``: the copies' and the patches' at spikes) are stages too.

``--hashes`` prints, per part (graded and uniform), the SHA-256 of the remesh (its
vertices, faces, patch indices and the patches' 2D meshes) and its verdicts: the same
seed must give the same hashes bit for bit; ``--cprofile N`` adds cProfile's N functions
of most own time (over the ``--repeat`` calls).
"""

from __future__ import annotations

import argparse
import collections
import cProfile
import hashlib
import io
import pstats
import sys
import tempfile
import time
from pathlib import Path

import trimesh

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np                                         # noqa: E402
import pds_plugin as pds                                   # noqa: E402
import pds_plugin.analysis.graded_certificate as graded_certificate  # noqa: E402
import pds_plugin.graded_complex as graded_complex         # noqa: E402
import pds_plugin.graded_sampling as graded_sampling       # noqa: E402
import pds_plugin.local_complex as local_complex           # noqa: E402
import pds_plugin.remeshing as remeshing                   # noqa: E402
import pds_plugin.sizing as sizing                         # noqa: E402

from remesh_vs_meshlab import DATA, generated_parts        # noqa: E402

SLOW = ("7_8ths_cube.stl", "shared.STL", "20mm-xyz-cube.stl", "g-block-pockets.stl")

STAGES = [
    (remeshing, "_as_trimesh"), (remeshing, "_coplanar_patches"), (remeshing, "_usable_patches"),
    (remeshing, "_plane_rings"), (remeshing, "_patches"), (remeshing, "_manifold_patches"),
    (sizing, "radius_field"), (sizing, "radius_fields"),
    (remeshing, "partition_topology"), (remeshing, "junction_fields"), (remeshing, "agreeing_fields"),
    (remeshing, "graded_sample_chains"), (remeshing, "chain_sample_radii"),
    (remeshing, "_agreeing_sizes"),
    (remeshing, "_patch_meshes"), (remeshing, "_meshed_together"),
    (remeshing, "_translates"), (remeshing, "_rolled"), (remeshing, "_translated"),
    (graded_certificate, "certify_graded"),
    (graded_sampling, "graded_poisson_disc"),
    (graded_sampling._GradedSampler, "add_boundary"),
    (graded_sampling._GradedSampler, "_leaves"),
    (graded_sampling._GradedSampler, "_open"),
    (graded_sampling._GradedSampler, "_throw"),
    (graded_sampling.kern, "split_open"),
    (graded_complex, "graded_alpha_complex"), (graded_complex, "local_faces"),
    (local_complex, "_exactly_empty"),
    (remeshing, "_cut_apart"), (remeshing, "_assemble"), (remeshing, "_on_input"),
    (remeshing, "_triangle_of"), (remeshing, "_volume_kept"),
    (remeshing, "_split_kept"), (remeshing, "_surface_facts"),
    (remeshing, "interface_report"),
]


def wrapped(times, calls):
    """Wrap every stage's function to add its wall time and calls up."""
    originals = []
    for owner, name in STAGES:
        function = getattr(owner, name, None)
        if function is None:                # a stage an older version does not have
            continue
        originals.append((owner, name, function))

        def timed(*args, _function=function, _name=name, **kwargs):
            start = time.process_time()
            try:
                return _function(*args, **kwargs)
            finally:
                times[_name] += time.process_time() - start
                calls[_name] += 1
        setattr(owner, name, timed)
    return originals


def digest(result) -> str:
    """The SHA-256 of a remesh: its mesh, patch indices and the patches' 2D meshes."""
    sha = hashlib.sha256()
    for array in [result.mesh.vertices, result.mesh.faces, result.patch] + [
            a for mesh in result.patch_meshes for a in (mesh.vertices, mesh.faces)]:
        sha.update(np.ascontiguousarray(array).tobytes())
    return sha.hexdigest()[:16]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--parts", nargs="*", default=None,
                        help="part file names (default: the four slowest against MeshLab; "
                             "every bench part with --hashes)")
    parser.add_argument("--repeat", type=int, default=3, help="timed calls per part")
    parser.add_argument("--hashes", action="store_true",
                        help="print the output meshes' hashes (graded and uniform) only")
    parser.add_argument("--cprofile", type=int, default=0, metavar="N",
                        help="also print cProfile's N functions of most own time")
    args = parser.parse_args(argv)
    paths = {path.name: path for path in generated_parts(Path(tempfile.mkdtemp()))}
    if args.hashes:
        from remesh_vs_meshlab import SHARED
        names = args.parts or [*SHARED, *paths]
        for name in names:
            mesh = trimesh.load(paths.get(name, DATA / name), process=False)
            for graded in (True, False):
                result = pds.remesh(mesh, graded=graded)
                print(f"{name} {'graded' if graded else 'uniform'} {digest(result)} "
                      f"ok={result.ok} ok_with_exceptions={result.ok_with_exceptions} "
                      f"solid_ok={result.solid_ok} volume_error={result.volume_error!r} "
                      f"vertices={len(result.mesh.vertices)}")
        return
    for name in args.parts or SLOW:
        mesh = trimesh.load(paths.get(name, DATA / name), process=False)
        result = pds.remesh(mesh)
        patches = len(result.patch_meshes)
        start = time.process_time()
        for _ in range(args.repeat):
            pds.remesh(mesh)
        total = (time.process_time() - start) / args.repeat
        times, calls = collections.defaultdict(float), collections.Counter()
        originals = wrapped(times, calls)
        try:
            for _ in range(args.repeat):
                pds.remesh(mesh)
        finally:
            for owner, stage, function in originals:
                setattr(owner, stage, function)
        print(f"\n{name}: {total * 1e3:.1f} ms CPU a call, {patches} patches remeshed, "
              f"{len(result.mesh.vertices)} vertices")
        print("| stage | ms a call | calls a call | ms a patch |")
        print("|---|---|---|---|")
        for stage, seconds in sorted(times.items(), key=lambda item: -item[1]):
            ms = seconds / args.repeat * 1e3
            print(f"| {stage} | {ms:.1f} | {calls[stage] / args.repeat:g} | "
                  f"{ms / max(patches, 1):.2f} |")
        if args.cprofile:
            profile = cProfile.Profile()
            profile.enable()
            for _ in range(args.repeat):
                pds.remesh(mesh)
            profile.disable()
            out = io.StringIO()
            pstats.Stats(profile, stream=out).sort_stats("tottime").print_stats(args.cprofile)
            print(out.getvalue())


if __name__ == "__main__":
    main()
