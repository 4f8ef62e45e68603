"""Props as a Blender artist makes them (issue 33 § 3): bevelled primitives, ours against
Decimate at count targets and, with ``--equal-error``, at equal error.

    .venv/bin/python bench/blender_props.py [--ratios 0.5 0.25 0.125] [--equal-error] [--only NAME ...]

Each prop is built in this process from Blender's own primitives and modifiers (Bevel,
Subdivision Surface), applied and triangulated, UVs as Blender makes them:
  bevel_cube      a cube, edges bevelled (4 segments), its sides cut once (Simple subdivision)
  bevel_cylinder  a 64-sided cylinder, its rims bevelled (4 segments)
  knob            a 48-sided cylinder, bevelled (3 segments), subdivided once
  bevel_box_long  a 3 x 0.6 x 0.3 box, edges bevelled (5 segments)
  cone_bevel      a 64-sided truncated cone, bevelled (3 segments)
  uv_sphere, torus, monkey_sub (Suzanne, subdivided twice): the organic baselines

Count targets: ours is the add-on's chain at the panel's defaults (``lod.prepare`` and
``lod.compute``: UV seams kept), Decimate a modifier on the same object; both measured by
one sampler (addon/pure/measure.py, 100,000 samples a side, two-sided, in % of the prop's
bounding-box diagonal). Equal error: bench/equal_error.py's two searches on the prop's
triangles (no UVs) at 0.05, 0.2 and 1 %. Prints markdown tables with the processor;
docs/method.md quotes them.
"""
from __future__ import annotations

import argparse
import sys

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import bpy
import numpy as np

import core
import equal_error
from addon import lod
from addon.pure import measure
from addon.pure.settings import LodSettings
from blender_reference import mesh_arrays
from run import environment
from tables import header, row

SAMPLES = 100_000
SEED = 7


def _bevel(ob, width, segments, by_angle=False):
    m = ob.modifiers.new("Bevel", "BEVEL")
    m.width, m.segments = width, segments
    if by_angle:
        m.limit_method = "ANGLE"


def _subdivide(ob, levels, simple=False):
    m = ob.modifiers.new("Subdivision", "SUBSURF")
    m.levels = levels
    if simple:
        m.subdivision_type = "SIMPLE"


def _bevel_cube():
    bpy.ops.mesh.primitive_cube_add(size=2)
    ob = bpy.context.object
    _bevel(ob, 0.15, 4)
    _subdivide(ob, 1, simple=True)
    return ob


def _bevel_cylinder():
    bpy.ops.mesh.primitive_cylinder_add(vertices=64, radius=1, depth=0.4)
    ob = bpy.context.object
    _bevel(ob, 0.05, 4, by_angle=True)
    return ob


def _knob():
    bpy.ops.mesh.primitive_cylinder_add(vertices=48, radius=0.3, depth=0.6)
    ob = bpy.context.object
    _bevel(ob, 0.06, 3, by_angle=True)
    _subdivide(ob, 1)
    return ob


def _bevel_box_long():
    bpy.ops.mesh.primitive_cube_add(size=1)
    ob = bpy.context.object
    ob.scale = (3, 0.6, 0.3)
    bpy.ops.object.transform_apply(scale=True)
    _bevel(ob, 0.05, 5)
    return ob


def _cone_bevel():
    bpy.ops.mesh.primitive_cone_add(vertices=64, radius1=1, radius2=0.3, depth=1.5)
    ob = bpy.context.object
    _bevel(ob, 0.04, 3, by_angle=True)
    return ob


def _uv_sphere():
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24)
    return bpy.context.object


def _torus():
    bpy.ops.mesh.primitive_torus_add(major_segments=64, minor_segments=24)
    return bpy.context.object


def _monkey_sub():
    bpy.ops.mesh.primitive_monkey_add()
    ob = bpy.context.object
    _subdivide(ob, 2)
    return ob


PROPS = {"bevel_cube": _bevel_cube, "bevel_cylinder": _bevel_cylinder, "knob": _knob,
         "bevel_box_long": _bevel_box_long, "cone_bevel": _cone_bevel, "uv_sphere": _uv_sphere,
         "torus": _torus, "monkey_sub": _monkey_sub}


def build(name):
    """The prop ``name`` alone in the scene, its modifiers applied, triangulated."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    ob = PROPS[name]()
    bpy.context.view_layer.objects.active = ob
    for m in list(ob.modifiers):
        bpy.ops.object.modifier_apply(modifier=m.name)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.mesh.quads_convert_to_tris()
    bpy.ops.object.mode_set(mode="OBJECT")
    return ob


def triangles(ob):
    """(vertices, faces) of the object's evaluated mesh (its own space)."""
    ev = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
    try:
        return mesh_arrays(ev.to_mesh())[:2]
    finally:
        ev.to_mesh_clear()


def decimated(ob, ratio):
    m = ob.modifiers.new("Decimate", "DECIMATE")
    m.ratio, m.use_collapse_triangulate = ratio, True
    try:
        return triangles(ob)
    finally:
        ob.modifiers.remove(m)


def count_rows(name, ratios) -> list:
    ob = build(name)
    V, F = triangles(ob)
    diag = float(np.linalg.norm(V.max(0) - V.min(0)))
    output = lod.compute(lod.prepare(bpy.context.scene, ob, LodSettings(ratios=tuple(ratios), measure_deviation=False)))
    out = []
    for ratio, level in zip(ratios, output.levels):
        dv, df = decimated(ob, ratio)
        ours = measure.surface_deviation(V, F, level.vertices, level.faces, n_samples=SAMPLES, seed=SEED)
        theirs = measure.surface_deviation(V, F, dv, df, n_samples=SAMPLES, seed=SEED)
        slivers = (core.quality_summary(level.vertices, level.faces)["sliver_percent"],
                   core.quality_summary(dv, df)["sliver_percent"])
        out.append(row(name, f"{len(F):,}", f"{ratio:g}", f"{len(level.faces):,} / {len(df):,}",
                       f"{100 * ours['hausdorff'] / diag:.4f} / {100 * theirs['hausdorff'] / diag:.4f}",
                       f"**{ours['hausdorff'] / theirs['hausdorff']:.2f}x**" if theirs["hausdorff"] > 0 else "-",
                       f"{100 * ours['mean'] / diag:.5f} / {100 * theirs['mean'] / diag:.5f}",
                       f"{ours['mean'] / theirs['mean']:.2f}x" if theirs["mean"] > 0 else "-",
                       f"{slivers[0]:.1f} / {slivers[1]:.1f}"))
    return out


def equal_error_rows(name, percents) -> list:
    V, F = triangles(build(name))
    ours = equal_error.ours(name, V, F, percents)
    theirs = equal_error.DecimateRuns(V, F, 200_000)
    out = []
    for percent in percents:
        n, dv, df = theirs.coarsest_within(percent, 6)
        found = ours.get(round(percent, 9))
        if found is None:
            out.append(row(name, f"{len(F):,}", f"{percent:g}", "none", f"{n:,}", "-", "-", "-"))
            continue
        h = measure.mesh_report(V, F, found[1], found[2], n_samples=200_000, seed=equal_error.CHECK_SEED)["hausdorff_percent"]
        out.append(row(name, f"{len(F):,}", f"{percent:g}", f"{found[0]:,}", f"{n:,}", f"**{found[0] / n:.2f}x**",
                       f"{h:.4f}" + (" (beyond)" if h > percent else ""),
                       f"{core.quality_summary(found[1], found[2])['sliver_percent']:.1f} / "
                       f"{core.quality_summary(dv, df)['sliver_percent']:.1f}"))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.5, 0.25, 0.125])
    ap.add_argument("--equal-error", action="store_true", help="also the triangles at 0.05, 0.2 and 1 %% (slow)")
    ap.add_argument("--only", nargs="+", choices=sorted(PROPS), metavar="NAME")
    args = ap.parse_args(argv)
    names = args.only or list(PROPS)
    env = environment()
    print(f"{env['cpu']}, {env['cpu_count']} cores; Blender {env['blender']}, NumPy {env['numpy']}; commit {env['commit']}\n")
    print(header("prop", "triangles", "ratio", "triangles, ours / Decimate", "Hausdorff %, ours / Decimate",
                 "Hausdorff ratio", "mean %, ours / Decimate", "mean ratio", "slivers %, ours / Decimate"))
    for name in names:
        print("\n".join(count_rows(name, args.ratios)), flush=True)
    if args.equal_error:
        print("\n" + header("prop", "triangles", "bound %", "ours", "Decimate", "ours / Decimate",
                            "ours measured %", "slivers %, ours / Decimate"))
        for name in names:
            print("\n".join(equal_error_rows(name, [0.05, 0.2, 1.0])), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
