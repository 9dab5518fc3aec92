"""``pds-mesh demo``: the whole product on the built-in CAD part, every output written:
the uniform mesh with the automatic alpha, the graded mesh, and one picture with the two
side by side. Without matplotlib (the ``[plot]`` extra) the pictures are skipped, with
one line saying how to get them."""

from __future__ import annotations

from importlib.util import find_spec
from pathlib import Path

import numpy as np

from .._atomic import atomic_path
from ..analysis.quality import ASPECT_BOUND
from ..sinks.plot import plot_mesh
from ..sources.demo import demo_part
from ..sources.solids import section
from .mesh import Task, mesh_and_report
from .output import warn_about, write_report

__all__ = ["run"]

NO_PICTURES = ('pictures skipped: matplotlib is not installed (pip install "pds_plugin[plot]" '
               'to get them)')


def run(args) -> int:
    """Run ``pds-mesh demo`` with parsed arguments; return the exit status.

    Parameters
    ----------
    args : argparse.Namespace
        ``output`` (the directory, created) and ``seed``.

    Returns
    -------
    int
        0.

    Examples
    --------
    >>> import tempfile
    >>> from pds_plugin.cli.arguments import parser
    >>> run(parser().parse_args(["demo", "-o", tempfile.mkdtemp()]))   # doctest: +ELLIPSIS
    pds-mesh demo: a 4 x 2 x 0.5 plate with two holes, a slot and a sharp notch (manifold3d),
    ...
      certificate  ok
    ...
    0
    """
    out = args.output
    out.mkdir(parents=True, exist_ok=True)
    part = demo_part()
    solid = out / "part.stl"
    _write_stl(part, solid)
    region = section(part, plane_origin=(0.0, 0.0, 0.0), plane_normal=(0.0, 0.0, 1.0))
    pictures = find_spec("matplotlib") is not None

    def picture(name):
        return out / name if pictures else None
    task = Task(region, "auto", args.seed, None, out / "section.ply", picture("section.png"),
                discs=True)
    uniform_mesh, entry = mesh_and_report(task)
    warn_about(entry)
    graded_task = Task(region, "auto", args.seed, None, out / "section_graded.ply",
                       picture("section_graded.png"), discs=False, graded=True)
    graded_mesh, graded = mesh_and_report(graded_task)
    warn_about(graded)
    both = picture("uniform_and_graded.png")
    if pictures:
        _side_by_side(uniform_mesh, graded_mesh, both)
    report = out / "report.json"
    write_report(report, "pds_plugin.demo_part()", [entry, graded])
    c, g = entry["certificate"], graded["certificate"]

    def verdict(ok):
        return "ok" if ok else "FAILED"
    print("\n".join([
        "pds-mesh demo: a 4 x 2 x 0.5 plate with two holes, a slot and a sharp notch "
        "(manifold3d),",
        "cut at mid-thickness (z = 0) and meshed with the automatic alpha.",
        "",
        f"  section      {region.betti[0]} component(s), {region.betti[1]} hole(s), area "
        f"{region.area:.6g}",
        f"  alpha        {entry['alpha']:.6g}, from the narrowest feature: "
        f"{entry['feature_size']['where']}",
        f"  mesh         {entry['samples']} samples, {entry['triangles']} triangles",
        f"  certificate  {verdict(c['ok'])}",
        f"    sampling   {verdict(c['sampling_ok'])}: samples >= {c['min_separation']:.6f} "
        f"alpha apart, every point within {c['coverage_gap']:.6f} alpha of one",
        f"    quality    {verdict(c['quality_ok'])}: max aspect ratio "
        f"{c['max_aspect_ratio']:.4f} <= 4√3 = {ASPECT_BOUND:.4f}, angles "
        f"{c['min_angle']:.2f}° to {c['max_angle']:.2f}°",
        f"    topology   {verdict(c['topology_ok'])}: mesh (b0, b1) = "
        f"{tuple(c['betti_mesh'])}, section {tuple(c['betti_region'])}",
        f"  graded       {graded['samples']} samples, {graded['triangles']} triangles: sizes "
        f"follow the section (grading L = {g['grading']:g}), angles {g['min_angle']:.2f}° to "
        f"{g['max_angle']:.2f}° (proven >= {g['proven_angle']:.2f}°), certificate "
        f"{verdict(g['ok'])}",
        "",
        f"  {solid}  the solid (try the command on it)",
        f"  {task.output}  the mesh: binary PLY, face quality = aspect ratio",
        f"  {report}  quality statistics and certificate",
        *([f"  {task.plot}  samples with discs, mesh by aspect ratio, histogram",
           f"  {graded_task.output}, {graded_task.plot}  the graded mesh and its picture",
           f"  {both}  the uniform and the graded mesh side by side"] if pictures else
          [f"  {graded_task.output}  the graded mesh", f"  {NO_PICTURES}"]),
        "",
        "next, a finer mesh, and one too coarse (its certificate says which holes it lost):",
        f"  pds-mesh {solid} -o {out / 'fine.ply'} --axis z --alpha 0.03",
        f"  pds-mesh {solid} -o {out / 'coarse.ply'} --axis z --alpha 0.3",
    ]))
    return 0


def _side_by_side(uniform, graded, path: Path) -> None:
    """One picture: the uniform mesh left, the graded mesh right, each coloured by
    aspect ratio, with its triangle count and smallest angle."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(12, 4.2), layout="constrained")
    left, right = figure.subplots(1, 2)
    for ax, mesh, name in ((left, uniform, f"uniform, alpha = {uniform.alpha:.3g}"),
                           (right, graded, f"graded, L = {graded.field.grading:g}")):
        plot_mesh(mesh, ax=ax)
        ax.set_title(f"{name}\n{len(mesh.vertices)} samples, {len(mesh.faces)} triangles, "
                     f"angles >= {mesh.quality().angles.min():.1f}°")
    with atomic_path(path) as partial:          # never a half-written picture
        figure.savefig(partial, dpi=120)


def _write_stl(part, path: Path) -> None:
    import trimesh

    mesh = part.to_mesh64()
    trimesh.Trimesh(np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts),
                    process=False).export(path)
