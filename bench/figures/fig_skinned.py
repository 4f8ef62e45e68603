"""Paper Fig. 13: a skinned character, posed; how far the posed LOD is from the posed original.

    .venv/bin/python bench/figures/fig_skinned.py [--samples N]  ->  docs/images/fig_skinned.png

The character is Fox.gltf from ../shared/meshes (Khronos sample, CC-BY 4.0: 576 triangles,
24 bones), imported with Blender's glTF importer. Its triangles come with split vertices,
so the script welds them (bmesh remove_doubles) and adds a Subdivision Surface modifier
(level 2) before the Armature modifier, which makes a smooth 13,824-triangle character
whose vertex groups Blender interpolates. Without Fox.gltf the figure is skipped (the
bench never builds a stand-in character; tests do that).

Compared at the same triangle count (10 % of the subdivided character), all through the
bpy module, each LOD posed by the same armature at 10 frames of the Fox's "Run" and
"Survey" animations:
  * ours, Armature (sample poses): the add-on's own path (addon.lod.generate_lods with
    importance source ARMATURE at the default strength: the rig's sample poses in the
    error and the LOD's weights fitted to them, core/skinning.py, docs/armature.md); the
    LOD object gets its vertex groups and its own Armature modifier. Every other setting
    is the add-on's default (UV seams, sharp edges, boundaries kept);
  * ours, Armature (Paper): source ARMATURE_PAPER, the paper's w_i = min(0.15 (1 - s_i), 0.1)
    over its cap as the importance g, acting like painted importance (addon/pure/importance.py);
  * ours, no importance: the same with importance source NONE;
  * both again with UV Seams off, because Blender's Decimate does not keep seams either;
  * Blender's Decimate (Collapse, default settings) inserted between the Subdivision
    Surface and the Armature modifier, so Blender's LOD is skinned by its own weights.
Deviation: two-sided Hausdorff and mean distance (addon/pure/measure.py) between each posed LOD
and the posed original, in % of the posed original's bounding-box diagonal; the same at
rest for reference.
"""
from __future__ import annotations

import argparse
import sys

import fig_common as fc
import tables  # in bench/, which fig_common put on sys.path
import bpy
import bmesh  # after bpy: it is one of bpy's modules
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PolyCollection
from mathutils.bvhtree import BVHTree

import core
from addon import lod, rig
from addon.lod_objects import SOURCE_PROP
from addon.pure.measure import surface_deviation
from addon.pure.settings import LodSettings
from blender_reference import mesh_arrays, stdout_to_stderr

RATIO = 0.1
SUBDIV_LEVELS = 2


def load_fox(path):
    with stdout_to_stderr():
        bpy.ops.import_scene.gltf(filepath=str(path))
    fox = next(ob for ob in bpy.data.objects if ob.type == "MESH" and rig.armature_of(ob) is not None)
    for ob in list(bpy.data.objects):  # the importer's camera, light and bone-shape helpers
        if ob.type in ("MESH", "CAMERA", "LIGHT") and ob != fox:
            bpy.data.objects.remove(ob, do_unlink=True)
    bm = bmesh.new()
    bm.from_mesh(fox.data)
    bmesh.ops.remove_doubles(bm, verts=bm.verts, dist=1e-4 * max(fox.dimensions))
    bm.to_mesh(fox.data)
    bm.free()
    sub = fox.modifiers.new("Subdivision", "SUBSURF")
    sub.levels = sub.render_levels = SUBDIV_LEVELS
    fox.modifiers.move(len(fox.modifiers) - 1, 0)  # before the Armature modifier
    return fox, rig.armature_of(fox)


def world_arrays(ob):
    """Evaluated (modifiers, pose) triangles of ``ob`` in world space."""
    dg = bpy.context.evaluated_depsgraph_get()
    ev = ob.evaluated_get(dg)
    me = ev.to_mesh()
    try:
        v, f, _, _ = mesh_arrays(me)
    finally:
        ev.to_mesh_clear()
    mw = np.array(ev.matrix_world, dtype=np.float64)
    return v @ mw[:3, :3].T + mw[:3, 3], f


def set_pose(arm, posed: bool):
    arm.data.pose_position = "POSE" if posed else "REST"
    bpy.context.view_layer.update()


def face_distances(v, f, ref_v, ref_f):
    """Distance from each face centroid of (v, f) to the surface (ref_v, ref_f)."""
    tree = BVHTree.FromPolygons(ref_v.tolist(), ref_f.tolist())
    c = v[f].mean(axis=1)
    return np.array([tree.find_nearest(p)[3] for p in c.tolist()])


POSES = [("Run", f) for f in (0, 4, 8, 12, 16, 20, 24)] + [("Survey", f) for f in (20, 40, 60)]
SHOWN_POSE = ("Run", 8)


def make_lod(fox, arm, label, source, **overrides):
    """The add-on's LOD of ``fox`` (rest shape), kept out of the add-on's re-run cleanup."""
    settings = LodSettings(ratio=RATIO, levels=1, importance_source=source, measure_deviation=False, **overrides)
    set_pose(arm, False)
    report = lod.generate_lods(bpy.context.scene, fox, settings)
    level = report["levels"][0]
    if level["stop_reason"] != core.STOP_TARGET:
        sys.exit(f"{label}: the add-on stopped early: {report['warnings']}")
    ob = bpy.data.objects[level["name"]]
    if rig.armature_of(ob) is not arm:
        sys.exit(f"{ob.name} is not deformed by {arm.name}: the add-on did not copy the Armature modifier")
    del ob[SOURCE_PROP]  # so the next generate_lods run does not replace this LOD
    ob.name = label
    return ob, level["triangles"]


def decimated_copy(fox, triangles, m):
    """A copy of ``fox`` with Decimate between its Subdivision and Armature modifiers."""
    ob = fox.copy()  # shares the mesh, copies the modifier stack
    bpy.context.scene.collection.objects.link(ob)
    dec = ob.modifiers.new("Decimate", "DECIMATE")
    dec.decimate_type = "COLLAPSE"
    dec.ratio = triangles / m
    dec.use_collapse_triangulate = True
    ob.modifiers.move(len(ob.modifiers) - 1, 1)
    return ob


def set_frame(arm, action, frame):
    arm.animation_data.action = bpy.data.actions[action]
    bpy.context.scene.frame_set(frame)
    set_pose(arm, True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--samples", type=int, default=100_000, help="distance samples per surface")
    args = ap.parse_args()
    path = fc.find_mesh("Fox")
    if path is None:
        print("Skipped: Fox.gltf is not in ../shared/meshes (the figure needs a rigged character).")
        return
    fox, arm = load_fox(path)
    if arm.animation_data is None:
        arm.animation_data_create()
    set_pose(arm, False)
    m = len(world_arrays(fox)[1])

    objects = {}
    objects["ours, Armature (sample poses)"], faces = make_lod(fox, arm, "ours, Armature (sample poses)", "ARMATURE")
    objects["ours, no importance"], _ = make_lod(fox, arm, "ours, no importance", "NONE")
    objects["ours, Armature (Paper)"], _ = make_lod(fox, arm, "ours, Armature (Paper)", "ARMATURE_PAPER")
    # Blender's Decimate ignores UV seams; these two show ours on geometry alone as well.
    for label, source in (("ours, Armature (sample poses), seams off", "ARMATURE"),
                          ("ours, no importance, seams off", "NONE")):
        objects[label], _ = make_lod(fox, arm, label, source, preserve_seams=False)
    objects["Blender Decimate"] = decimated_copy(fox, faces, m)
    labels = list(objects)

    def measure_state():
        ov, of = world_arrays(fox)
        out = {"original": (ov, of)}
        for label, ob in objects.items():
            lv, lf = world_arrays(ob)
            out[label] = (lv, lf, surface_deviation(ov, of, lv, lf, n_samples=args.samples))
        return out

    set_pose(arm, False)
    rest = measure_state()
    posed = {}
    for action, frame in POSES:
        fc.log(f"pose {action} frame {frame}")
        set_frame(arm, action, frame)
        posed[action, frame] = measure_state()

    # Top: side views at one pose, LOD faces coloured by distance to the posed original.
    # Bottom: Hausdorff and mean distance at every pose.
    shown = posed[SHOWN_POSE]
    ov, of = shown["original"]
    diag = float(np.linalg.norm(ov.max(0) - ov.min(0)))
    extent = np.ptp(ov, axis=0)
    a = int(np.argmax(extent[:2]))  # the long horizontal axis; z is up after the glTF import
    b = 2
    fig = plt.figure(figsize=(16, 7.2), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[0.75, 1.0])
    axes = top.subplots(1, 4)
    pictured = [labels[0], labels[1], "Blender Decimate"]
    face_d = {label: 100.0 * face_distances(shown[label][0], shown[label][1], ov, of) / diag for label in pictured}
    vmax = float(np.quantile(np.concatenate(list(face_d.values())), 0.99))
    coll = None
    for ax, label in zip(axes, ["original"] + pictured):
        if label == "original":
            v, f = ov, of
            title = f"posed original, {len(f):,} triangles"
        else:
            v, f, d = shown[label]
            title = (f"{label}, {len(f):,} triangles\nHausdorff {d['hausdorff_percent']:.3f} %, "
                     f"mean {d['mean_percent']:.4f} %")
        pc = PolyCollection(v[f][:, :, [a, b]], edgecolors="black", linewidths=0.12 if label == "original" else 0.3)
        if label == "original":
            pc.set_facecolor("#dde6f0")
        else:
            pc.set_array(face_d[label])
            pc.set_cmap("magma_r")
            pc.set_clim(0.0, vmax)
            coll = pc
        ax.add_collection(pc)
        ax.set_xlim(ov[:, a].min(), ov[:, a].max())
        ax.set_ylim(ov[:, b].min(), ov[:, b].max())
        ax.set_aspect("equal")
        ax.set_axis_off()
        ax.set_title(title, fontsize=9)
    top.colorbar(coll, ax=axes, shrink=0.8, label="face distance to posed original, % of diagonal")
    top.suptitle(f"Fox (subdivided, {m:,} triangles) -> {RATIO:.0%}, posed by its armature "
                 f"('{SHOWN_POSE[0]}' frame {SHOWN_POSE[1]}), side view", fontsize=11)
    x = np.arange(len(POSES))
    ticks = [f"{act} {fr}" for act, fr in POSES]
    for ax, key, ylabel in zip(bottom.subplots(1, 2), ("hausdorff_percent", "mean_percent"),
                               ("Hausdorff, % of diagonal", "mean distance, % of diagonal")):
        for i, label in enumerate(labels):
            ax.plot(x, [posed[p][label][2][key] for p in POSES], "o-" if "seams off" not in label else "^--",
                    color=f"C{i}", label=label, ms=5)
            ax.axhline(rest[label][2][key], color=f"C{i}", ls=":", lw=0.8)
        ax.set_xticks(x, ticks, rotation=45, fontsize=8)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    ax.legend(fontsize=8, title="dotted: at rest", title_fontsize=8)
    bottom.suptitle("deviation of each posed LOD from the posed original, per pose", fontsize=10)
    fc.save(fig, "fig_skinned.png")

    def avg(label, key):
        return float(np.mean([posed[p][label][2][key] for p in POSES]))

    ours, plain, paper, blender = labels[0], labels[1], labels[2], "Blender Decimate"
    print(f"Over {len(POSES)} poses of the Fox's Run and Survey animations at {RATIO:.0%}, the posed LOD's mean "
          f"deviation from the posed original averages {avg(ours, 'mean_percent'):.4f} % with Source Armature "
          f"(sample poses), {avg(paper, 'mean_percent'):.4f} % with the paper's skin importance, "
          f"{avg(plain, 'mean_percent'):.4f} % without importance and "
          f"{avg(blender, 'mean_percent'):.4f} % for Blender's Decimate (Hausdorff {avg(ours, 'hausdorff_percent'):.3f} / "
          f"{avg(plain, 'hausdorff_percent'):.3f} / {avg(blender, 'hausdorff_percent'):.3f} %).")
    print(tables.header("method", "triangles", "rest Hausdorff %", "rest mean %",
                        "posed Hausdorff %, mean over poses (max)", "posed mean %, mean over poses (max)"))
    for label in labels:
        hs = [posed[p][label][2]["hausdorff_percent"] for p in POSES]
        ms = [posed[p][label][2]["mean_percent"] for p in POSES]
        r = rest[label][2]
        print(tables.row(label, f"{len(rest[label][1]):,}", f"{r['hausdorff_percent']:.4f}", f"{r['mean_percent']:.5f}",
                         f"{np.mean(hs):.4f} ({max(hs):.4f})", f"{np.mean(ms):.5f} ({max(ms):.5f})"))
    print("Posing adds to the mean deviation (mean over poses minus rest): " + ", ".join(
        f"{label} +{avg(label, 'mean_percent') - rest[label][2]['mean_percent']:.4f} %" for label in labels) + ".")
    wins = {label: sum(posed[p][label][2]["mean_percent"] < posed[p][blender][2]["mean_percent"] for p in POSES)
            for label in labels if label != blender}
    print("Poses where the mean deviation is below Blender's: "
          + ", ".join(f"{label} {n}/{len(POSES)}" for label, n in wins.items()) + ".")
    q = {label: core.quality_summary(rest[label][0], rest[label][1]) for label in labels}
    print("Mean triangle quality at rest: " + ", ".join(f"{k} {v['mean_quality']:.3f}" for k, v in q.items()) + ".")


if __name__ == "__main__":
    main()
