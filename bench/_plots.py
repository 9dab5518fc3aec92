"""The benchmark's figures: time against vertex count, and aspect-ratio tails."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pds_plugin.analysis.quality import ASPECT_BOUND, ASPECT_EQUILATERAL

MAX_POINTS = 200_000   # aspect ratios drawn per curve (a random subset beyond this)


def _pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def time_vs_vertices(rows, path: Path) -> Path | None:
    """Log-log wall time against vertex count on the unit squares, one line per peer;
    pds_plugin's parts in thin grey; extrapolated times (scipy) as open markers."""
    squares = [row for row in rows if row.case.key == "square" and row.ok and row.metrics]
    if not squares:
        return None
    plt = _pyplot()
    figure, ax = plt.subplots(figsize=(11, 5.5))
    for key in dict.fromkeys(row.peer.key for row in squares):
        mine = sorted((row for row in squares if row.peer.key == key), key=_plotted_count)
        x, y = [_plotted_count(row) for row in mine], [row.time for row in mine]
        scaled = [row.scale != 1 for row in mine]
        line, = ax.plot(x, y, marker="o", **_style(key), label=mine[0].peer.label
                        + (" (open marker: extrapolated)" if any(scaled) else ""))
        ax.plot(np.compress(scaled, x), np.compress(scaled, y), "o", mfc="white",
                color=line.get_color(), zorder=line.get_zorder())
        if key == "pds":
            for part, style in (("sampling", ":"), ("complex", "--"), ("certificate", "-.")):
                ax.plot(x, [row.times[part] for row in mine], style, color="0.4", lw=1,
                        label=f"pds_plugin {part}")
    ax.set(xscale="log", yscale="log", xlabel="mesh vertices", ylabel="wall time (s)",
           title="Unit square: time against vertex count (one run, each peer in a fresh process)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path


def aspect_tails(rows, case_names, path: Path) -> Path | None:
    """For each named case, the share of each peer's triangles with aspect ratio L²/A
    above x (log scale), with Theorem 1's bound 4√3 marked. Rows that only change a
    peer's environment (pds_plugin on 1 thread: the same mesh) are left out."""
    panels = [[row for row in rows if row.case.name == name and row.ok and row.peer.env == {}
               and len(row.metric("aspect", ())) > 0] for name in case_names]
    panels = [panel for panel in panels if panel]
    if not panels:
        return None
    plt = _pyplot()
    figure, axes = plt.subplots(1, len(panels), figsize=(max(6.5 * len(panels), 11), 5),
                                squeeze=False)
    for ax, panel in zip(axes[0], panels):
        floor = 0.5 / max(len(row.metric("aspect")) for row in panel)
        for row in panel:
            values = np.sort(_subsample(row.metric("aspect")))
            values = values[np.isfinite(values)]
            share = 1 - np.arange(len(values)) / len(values)
            ax.step(values, share, where="post", label=row.peer.label, **_style(row.peer.key))
        ax.axvline(ASPECT_BOUND, color="k", ls="--", lw=1)
        ax.text(ASPECT_BOUND, 1.5 * floor, " 4√3 (Theorem 1)", fontsize="small")
        ax.set(xscale="log", yscale="log", xlim=(ASPECT_EQUILATERAL, None), ylim=(floor, 1.1),
               xlabel="aspect ratio L²/A", ylabel="share of triangles with L²/A > x",
               title=panel[0].case.name)
        ax.grid(True, which="both", alpha=0.3)
    handles, labels = axes[0][0].get_legend_handles_labels()
    figure.legend(handles, labels, loc="lower center", ncol=3, fontsize="small")
    figure.tight_layout(rect=(0, 0.14, 1, 1))
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path


def _plotted_count(row) -> float:
    """The vertex count a row's time belongs to: an extrapolated time belongs to the
    count it was extrapolated to."""
    return row.measured_points * row.scale if row.scale != 1 else row.metric("vertices")


COLOURS = {"scipy": "tab:blue", "meshlab": "tab:orange", "meshlab-seeded": "tab:green",
           "meshlab-alpha-shape": "tab:red", "triangle-pq30": "tab:purple",
           "triangle-pq33": "tab:brown", "gmsh-delaunay": "tab:pink", "gmsh-frontal": "tab:olive"}


def _style(key: str) -> dict:
    """pds_plugin black, thick and on top (1 thread: grey, dashed); each peer its colour."""
    if key == "pds":
        return {"color": "k", "lw": 2.5, "zorder": 10}
    if key == "pds-1thread":
        return {"color": "0.5", "lw": 1.5, "ls": "--", "zorder": 9}
    return {"color": COLOURS.get(key)}


def _subsample(values, size: int = MAX_POINTS) -> np.ndarray:
    values = np.asarray(values)
    if len(values) <= size:
        return values
    return np.random.default_rng(0).choice(values, size, replace=False)
