"""Paper Fig. 4: the line-quadric weight w trades shape fidelity for triangle quality.

    .venv/bin/python bench/figures/fig_weight_sweep.py [--samples N]  ->  docs/images/fig_weight_sweep.png

stanford-bunny from ../shared/meshes (a procedural bumpy sphere when it is absent) taken
to 10 % by core.simplify for w in {0, 1e-4, 1e-3, 1e-2, 1e-1}; for each: mean and minimum
triangle quality, slivers, and the two-sided Hausdorff and mean surface distance to the
input (addon/pure/measure.py, Blender's BVH, in % of the bounding-box diagonal). Blender's
Decimate at the same ratio is drawn as a reference line.
"""
from __future__ import annotations

import argparse

import fig_common as fc
import tables  # in bench/, which fig_common put on sys.path
import bpy  # noqa: F401  (imported early: nothing else may load first, see _bootstrap)
import matplotlib.pyplot as plt
import numpy as np

import core
from addon.pure.measure import mesh_report
from blender_reference import decimate, load_mesh
from synthetic_meshes import bumpy_sphere

RATIO = 0.1
WEIGHTS = (0.0, 1e-4, 1e-3, 1e-2, 1e-1)


def load_input():
    path = fc.find_mesh("stanford-bunny")
    if path is not None:
        m = load_mesh(path)
        return "stanford-bunny", m.vertices, m.faces
    fc.log("stanford-bunny not found in ../shared/meshes: using a procedural bumpy sphere")
    V, F = bumpy_sphere()
    return "bumpy sphere", V, F


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, default=200_000, help="distance samples per surface")
    args = ap.parse_args()

    name, V, F = load_input()
    rows = []
    for w in WEIGHTS:
        fc.log(f"{name}: w = {w:g}")
        res = core.simplify(V, F, ratio=RATIO, line_weight=w)
        rep = mesh_report(V, F, res.vertices, res.faces, n_samples=args.samples)
        rows.append(dict(label=f"w = {w:g}", w=w, faces=len(res.faces), **rep, core_seconds=res.stats.seconds))
    dec = decimate(V, F, RATIO)
    ref = dict(label="Blender Decimate", faces=len(dec.faces),
               **mesh_report(V, F, dec.vertices, dec.faces, n_samples=args.samples))

    x = np.arange(len(WEIGHTS))
    ticks = ["0"] + [f"1e{int(np.log10(w))}" for w in WEIGHTS[1:]]
    panels = (
        ("mean_quality", "mean triangle quality q", "quality rises with w", "{:.3f}"),
        ("hausdorff_percent", "Hausdorff distance, % of diagonal", "worst-case distance", "{:.3f}"),
        ("mean_percent", "mean distance, % of diagonal", "mean distance", "{:.4f}"),
    )
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), layout="constrained")
    for ax, (key, ylabel, title, fmt) in zip(axes, panels):
        ax.plot(x, [r[key] for r in rows], "o-", color="C0", label="ours (core.simplify)")
        ax.axhline(ref[key], color="C3", ls="--", label=f"Blender Decimate ({fmt.format(ref[key])})")
        for xi, r in zip(x, rows):
            ax.annotate(fmt.format(r[key]), (xi, r[key]), textcoords="offset points", xytext=(0, 6),
                        ha="center", fontsize=7)
        ax.set_xticks(x, ticks)
        ax.set_xlabel("line-quadric weight w")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.margins(y=0.15)
        ax.legend(fontsize=8, loc="upper left")
    fig.suptitle(f"{name}, {len(F):,} triangles -> {RATIO:.0%}", fontsize=11)
    fc.save(fig, "fig_weight_sweep.png")

    q = [r["mean_quality"] for r in rows]
    mono = all(b >= a for a, b in zip(q, q[1:]))
    print(f"On {name} at {RATIO:.0%}, raising w from 0 to 0.1 takes mean triangle quality from "
          f"{q[0]:.3f} to {q[-1]:.3f} ({'monotonically' if mono else 'NOT monotonically'}) while the mean "
          f"distance goes from {rows[0]['mean_percent']:.4f} % to {rows[-1]['mean_percent']:.4f} % of the diagonal.")
    print(tables.header("method", "faces", "mean q", "min q", f"q<{core.SLIVER_QUALITY:g} %", "Hausdorff %", "mean %",
                        "core s"))
    for r in rows + [ref]:
        secs = f"{r['core_seconds']:.2f}" if "w" in r else "-"
        print(tables.row(r['label'], r['faces'], *fc.report_cells(r), secs))


if __name__ == "__main__":
    main()
