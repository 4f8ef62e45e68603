"""Paper Fig. 9: distance against triangle quality over a weight sweep, ours versus peers.

    .venv/bin/python bench/figures/fig_pareto.py [--samples N]  ->  docs/images/fig_pareto.png

stanford-bunny (a procedural bumpy sphere when absent) to 10 %:
  * ours: core.simplify over a sweep of the line-quadric weight w;
  * MeshLab's quadric edge collapse (pymeshlab, optional: skipped with a note when not
    importable) without and with its planar quadric, sweeping its planar weight. MeshLab
    gets the mesh scaled to a unit bounding-box diagonal (its planar weight depends on
    scale, core's w does not) and its own defaults otherwise (its quality threshold 0.3
    penalises badly shaped triangles in every MeshLab run, optimal placement on, autoclean on);
  * the probabilistic-quadric regulariser (Trettner & Kobbelt 2020) in place of ours:
    core.simplify(line_weight=0, probabilistic_sigma=sigma) over a sweep of sigma;
  * Blender's Decimate (one point: it has no such weight).
Each run is measured the same way (addon/pure/measure.py: two-sided Hausdorff and mean
distance in % of the bounding-box diagonal; core.quality_summary for q). Points further
right (better triangles) and lower (closer to the input) are better.
"""
from __future__ import annotations

import argparse
import time

import fig_common as fc
import tables  # in bench/, which fig_common put on sys.path
import bpy  # noqa: F401  (before pymeshlab: pymeshlab's embree breaks a later bpy import)
import matplotlib.pyplot as plt
from matplotlib.ticker import FormatStrFormatter

import core
from addon.pure.measure import mesh_report
from blender_reference import decimate
from fig_weight_sweep import RATIO, load_input
from peers import meshlab_or_none, meshlab_simplify

OUR_WEIGHTS = (0.0, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1)
MESHLAB_WEIGHTS = (1e-5, 1e-4, 3e-4, 1e-3, 1e-2)

# Trettner & Kobbelt's normal noise sigma (dimensionless, sigma^2 ~ w), with w = 0; the
# paper sweeps [1e-4, 1e1], past 1 the point term flattens the shape into blobs.
PROBABILISTIC_SIGMAS = (1e-3, 1e-2, 3e-2, 0.1, 0.3, 1.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, default=200_000, help="distance samples per surface")
    args = ap.parse_args()

    name, V, F = load_input()
    target = int(round(RATIO * len(F)))
    series = {}

    def measure(key, label, v, f, seconds):
        rep = mesh_report(V, F, v, f, n_samples=args.samples)
        series.setdefault(key, []).append(dict(label=label, faces=len(f), time=seconds, **rep))

    for w in OUR_WEIGHTS:
        fc.log(f"ours w = {w:g}")
        t0 = time.perf_counter()
        res = core.simplify(V, F, ratio=RATIO, line_weight=w)
        measure("ours", f"w = {w:g}", res.vertices, res.faces, time.perf_counter() - t0)

    pymeshlab = meshlab_or_none()
    notes = []
    for sigma in PROBABILISTIC_SIGMAS:
        fc.log(f"probabilistic sigma = {sigma:g}")
        t0 = time.perf_counter()
        res = core.simplify(V, F, ratio=RATIO, line_weight=0.0, probabilistic_sigma=sigma)
        measure("probabilistic", f"sigma = {sigma:g}", res.vertices, res.faces, time.perf_counter() - t0)
    if pymeshlab is None:
        notes.append("MeshLab skipped: pymeshlab is not importable (.venv/bin/python -m pip install pymeshlab)")
    else:
        fc.log("MeshLab, no planar quadric")
        measure("meshlab", "no planar quadric", *meshlab_simplify(pymeshlab, V, F, target, None))
        for pw in MESHLAB_WEIGHTS:
            fc.log(f"MeshLab planar weight {pw:g}")
            measure("meshlab_planar", f"planar weight {pw:g}", *meshlab_simplify(pymeshlab, V, F, target, pw))

    dec = decimate(V, F, RATIO)
    measure("blender", "Blender Decimate", dec.vertices, dec.faces, dec.seconds)

    style = {
        "ours": ("ours (core.simplify), w sweep", "o-", "C0"),
        "probabilistic": ("probabilistic quadric (TK20, in core), sigma sweep", "^-", "C4"),
        "meshlab": ("MeshLab QEC, no planar quadric", "D", "C2"),
        "meshlab_planar": ("MeshLab QEC + planar quadric, weight sweep", "s-", "C1"),
        "blender": ("Blender Decimate", "*", "C3"),
    }
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), layout="constrained")
    for ax, key, ylabel in zip(axes, ("hausdorff_percent", "mean_percent"),
                               ("Hausdorff distance, % of diagonal", "mean distance, % of diagonal")):
        for s, rows in series.items():
            label, marker, color = style[s]
            ax.plot([r["mean_quality"] for r in rows], [r[key] for r in rows], marker, color=color,
                    label=label, ms=9 if s == "blender" else 5)
            if s in ("ours", "meshlab_planar", "probabilistic"):
                for r in rows:
                    ax.annotate(r["label"].split()[-1], (r["mean_quality"], r[key]), textcoords="offset points",
                                xytext=(4, 3), fontsize=7, color=color)
        ax.set_xlabel("mean triangle quality q (higher is better)")
        ax.set_ylabel(f"{ylabel} (lower is better)")
        ax.set_yscale("log")
        for axis in (ax.yaxis.set_major_formatter, ax.yaxis.set_minor_formatter):
            axis(FormatStrFormatter("%g"))
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=8)
    fig.suptitle(f"{name} -> {RATIO:.0%} ({target:,} triangles): distance vs triangle quality", fontsize=11)
    fc.save(fig, "fig_pareto.png")

    ours = series["ours"]
    best_q_at_blender_h = max((r for r in ours if r["hausdorff_percent"] <= series["blender"][0]["hausdorff_percent"]),
                              key=lambda r: r["mean_quality"], default=None)
    sentence = (f"On {name} at {RATIO:.0%}, sweeping w moves our results along a curve from mean q "
                f"{ours[0]['mean_quality']:.3f} to {ours[-1]['mean_quality']:.3f}")
    if best_q_at_blender_h is not None:
        sentence += (f"; the best quality still within Blender Decimate's Hausdorff distance "
                     f"({series['blender'][0]['hausdorff_percent']:.3f} %) is q = "
                     f"{best_q_at_blender_h['mean_quality']:.3f} at {best_q_at_blender_h['label']}, against "
                     f"Blender's {series['blender'][0]['mean_quality']:.3f}")
    print(sentence + ".")
    print(tables.header(
        "method", "setting", "faces", "mean q", "min q", f"q<{core.SLIVER_QUALITY:g} %", "Hausdorff %", "mean %", "s"))
    for s, rows in series.items():
        for r in rows:
            print(tables.row(style[s][0], r['label'], r['faces'], *fc.report_cells(r), f"{r['time']:.2f}"))
    for note in notes:
        print(f"Note: {note}.")


if __name__ == "__main__":
    main()
