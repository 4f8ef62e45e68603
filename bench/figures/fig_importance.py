"""Paper Fig. 1 and 5: painted importance on a flat region, ours versus Blender's Decimate.

    .venv/bin/python bench/figures/fig_importance.py   ->  docs/images/fig_importance.png

A flat grid of 120 x 120 quads (121 x 121 = 14,641 vertices, 28,800 triangles) with a disc painted at weight 1 (the rest
0), taken to 10 %:
  * ours at three strengths of the add-on's Importance slider: 0.1 (a subtle preference),
    the default 0.5 and 1 (the top, near locking); the painted vertices' quadrics are
    scaled by a factor calibrated on density (Sec. 4.4.1, addon/pure/importance.py);
  * hard lock: core's ``locked=`` on the painted vertices (they can never move or go);
  * Blender's Decimate (Collapse, ratio 0.1) with the same vertex group, plain and inverted.
The importance arrays come from addon/pure/importance.py, exactly as the panel computes them.
For each: the triangles left, the stop reason, and the vertex density (vertices per unit
area) inside and outside the disc.
"""
from __future__ import annotations

import fig_common as fc
import tables  # in bench/, which fig_common put on sys.path
import bpy
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Circle

import core
from addon.pure.importance import DEFAULT_STRENGTH, controls
from blender_reference import mesh_arrays, mesh_from_arrays, stdout_to_stderr
from synthetic_meshes import grid

N = 121  # vertices per side: 120 x 120 quads
RATIO = 0.1
CENTER = np.array([0.5, 0.5])
RADIUS = 0.2


def decimate_with_group(V, F, weights, ratio, invert):
    """Blender's Decimate (Collapse) with a vertex group holding ``weights`` (0 = not in it)."""
    me = mesh_from_arrays("grid", V, F)
    ob = bpy.data.objects.new("grid", me)
    bpy.context.scene.collection.objects.link(ob)
    try:
        vg = ob.vertex_groups.new(name="LOD_Importance")
        # One add() per distinct weight: here a painted disc, so a single call.
        for value in np.unique(weights[weights > 0]):
            vg.add(np.flatnonzero(weights == value).tolist(), float(value), "REPLACE")
        mod = ob.modifiers.new("Decimate", "DECIMATE")
        mod.decimate_type = "COLLAPSE"
        mod.ratio = ratio
        mod.use_collapse_triangulate = True
        mod.vertex_group = vg.name
        mod.invert_vertex_group = invert
        with stdout_to_stderr():
            ob_eval = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
            out = ob_eval.to_mesh()
        try:
            v, f, _, _ = mesh_arrays(out)
        finally:
            ob_eval.to_mesh_clear()
    finally:
        bpy.data.objects.remove(ob, do_unlink=True)
        bpy.data.meshes.remove(me)
    return v, f


def densities(V, F):
    """Vertices per unit area inside and outside the disc (of the vertices used by faces)."""
    used = V[np.unique(F)]
    inside = np.linalg.norm(used[:, :2] - CENTER, axis=1) <= RADIUS
    disc_area = np.pi * RADIUS ** 2
    return inside.sum() / disc_area, (~inside).sum() / (1.0 - disc_area), int(inside.sum()), int(len(used))


def main() -> None:
    V, F = grid(N)
    g = (np.linalg.norm(V[:, :2] - CENTER, axis=1) <= RADIUS).astype(np.float64)
    target = int(round(RATIO * len(F)))
    runs = []

    def ours(label, **kw):
        res = core.simplify(V, F, ratio=RATIO, **kw)
        runs.append(dict(label=label, V=res.vertices, F=res.faces, stop=res.stats.stop_reason))

    for strength, what in ((0.1, "subtle"), (DEFAULT_STRENGTH, "default"), (1.0, "top")):
        ours(f"ours, importance strength {strength:g} ({what})", **controls(g, core.DEFAULT_LINE_WEIGHT, strength))
    ours("hard lock of the painted vertices", line_weight=core.DEFAULT_LINE_WEIGHT, locked=g > 0)
    for invert in (False, True):
        v, f = decimate_with_group(V, F, g, RATIO, invert)
        stop = "target_reached" if abs(len(f) - target) <= 2 else "stopped early"
        runs.append(dict(label=f"Blender Decimate, vertex group{' inverted' if invert else ''}",
                         V=v, F=f, stop=stop))
    for r in runs:
        r["d_in"], r["d_out"], r["v_in"], r["v_all"] = densities(r["V"], r["F"])
        r.update(core.quality_summary(r["V"], r["F"]))
    d_in0, d_out0, v_in0, _ = densities(V, F)

    fig, axes = plt.subplots(2, 4, figsize=(16, 8.4), layout="constrained")
    axes = axes.ravel()
    axes[-1].set_axis_off()  # seven panels on a 2 x 4 grid
    fc.plot_mesh_2d(axes[0], V, F, f"input: {len(F):,} triangles, painted disc (weight 1)", linewidth=0.1)
    for ax, r in zip(axes[1:], runs):
        fc.plot_mesh_2d(ax, r["V"], r["F"],
                        f"{r['label']}\n{len(r['F']):,} triangles, density in/out "
                        f"{r['d_in'] / r['d_out']:.1f}x", linewidth=0.25)
    for ax in axes[:-1]:
        ax.add_patch(Circle(CENTER, RADIUS, fill=False, ec="red", lw=1.2, ls="--"))
    fig.suptitle(f"Painted importance on a flat {N - 1} x {N - 1} grid, target {RATIO:.0%} ({target:,} triangles)",
                 fontsize=11)
    fc.save(fig, "fig_importance.png")

    subtle, default, top, lock, dec, dec_inv = runs
    print(f"On a flat {N - 1}x{N - 1} grid taken to {RATIO:.0%} ({target:,} triangles) with a painted disc, our "
          f"importance reaches the target with {subtle['d_in'] / subtle['d_out']:.1f}x, "
          f"{default['d_in'] / default['d_out']:.1f}x and {top['d_in'] / top['d_out']:.1f}x the vertex density "
          f"inside the disc at strength 0.1, {DEFAULT_STRENGTH:g} (the default: the disc keeps "
          f"{default['v_in']:,} of its {v_in0:,} vertices) and 1, while Blender's "
          f"Decimate with the same vertex group stops at {len(dec['F']):,} triangles "
          f"({dec['v_all']:,} of {N * N:,} vertices) and, inverted, keeps "
          f"{dec_inv['v_in']:,} of the {v_in0:,} painted vertices like a hard lock "
          f"({lock['v_in']:,} kept by core's locked=).")
    print(tables.header(
        "method", "triangles", "stop", "vertices", "in disc", "density in", "density out", "in/out", "mean q"))
    print(tables.row("input", f"{len(F):,}", "-", f"{N * N:,}", f"{v_in0:,}", f"{d_in0:,.0f}", f"{d_out0:,.0f}",
                     f"{d_in0 / d_out0:.2f}", "-"))
    for r in runs:
        print(tables.row(r['label'], f"{len(r['F']):,}", r['stop'], f"{r['v_all']:,}", f"{r['v_in']:,}",
                         f"{r['d_in']:,.0f}", f"{r['d_out']:,.0f}", f"{r['d_in'] / r['d_out']:.2f}",
                         f"{r['mean_quality']:.3f}"))


if __name__ == "__main__":
    main()
