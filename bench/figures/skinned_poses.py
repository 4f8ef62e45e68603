"""Issue 19 § 2: does importance from the armature make posed LODs closer? The table.

    .venv/bin/python bench/figures/skinned_poses.py [--rows A,B,C,D,H1,H2,H3,H4] [--samples N] [--strength S]

For each row, LODs at the same triangle count through the add-on (addon.lod.generate_lods,
every other setting the default) with
  * none:   importance source None;
  * paper:  source Armature (the paper's mapping), w_i = min(0.15 (1 - s_i), 0.1) as
            painted importance through the calibrated Strength slider (addon/pure/importance.py);
and Blender's Decimate (Collapse) inserted just before the Armature modifier, so it is
skinned by Blender's own interpolated weights. Each is posed by the rig and measured
against the posed original: two-sided mean distance (addon/pure/measure.py), % of the posed
original's bounding-box diagonal, averaged over the row's poses; "rest" is the same at
the rest pose. The ratios are with / without importance.

Rows (the Fox of the glTF sample models, ../shared/meshes/Fox.gltf, 576 triangles, 24
bones, clips Survey / Walk / Run):
  A  imported as is, 25 %, 5 random poses
  B  imported as is, Subdivision Surface level 2 before the Armature modifier, 10 %, 5 random poses
  C  as B, 15 frames of its three clips (5 evenly spaced in each)
  D  docs/figures.md's setup (welded, then subdivided; bench/figures/fig_skinned.py), 10 %, its
     10 frames of Run and Survey
and a second character, made here (bench/figures/humanoid.py: Skin modifier, automatic
weights, 6,016 triangles, 19 bones):
  H1 25 %, 5 random poses
  H2 10 %, 5 random poses
  H3, H4  the same at Subdivision level 1 (1,504 triangles), 25 % and 10 %: 20 and 8
          triangles a bone, where the poses need checking (addon/pure/skin_fit.py)
Random poses: every bone turned about a random axis by an angle uniform in [0, 40 deg]
(pose-bone quaternions, seeds 101..105). Without Fox.gltf only the humanoid's rows run.
--sources takes further add-on importance sources by their enum name (e.g. a new
method under test) besides none and paper.
"""
from __future__ import annotations

import argparse
import math

import fig_common as fc
import tables  # in bench/, which fig_common put on sys.path
import bpy
import humanoid
import numpy as np

from addon import lod, rig
from addon.lod_objects import SOURCE_PROP
from addon.pure.measure import surface_deviation
from addon.pure.settings import LodSettings
from fig_skinned import load_fox, world_arrays
from blender_reference import stdout_to_stderr

RANDOM_POSES = 5
MAX_ANGLE_DEG = 40.0
SOURCES = {"none": "NONE", "paper": "ARMATURE_PAPER", "poses": "ARMATURE"}
FIG_POSES = [("Run", f) for f in (0, 4, 8, 12, 16, 20, 24)] + [("Survey", f) for f in (20, 40, 60)]


def fresh_scene():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def import_fox(path, subdivide: bool, weld: bool):
    if weld:
        fox, arm = load_fox(path)  # welded + level-2 subdivision before the Armature modifier
        if not subdivide:
            fox.modifiers.remove(fox.modifiers["Subdivision"])
        return fox, arm
    with stdout_to_stderr():
        bpy.ops.import_scene.gltf(filepath=str(path))
    fox = next(ob for ob in bpy.data.objects if ob.type == "MESH" and rig.armature_of(ob) is not None)
    for ob in list(bpy.data.objects):
        if ob.type in ("MESH", "CAMERA", "LIGHT") and ob != fox:
            bpy.data.objects.remove(ob, do_unlink=True)
    if subdivide:
        sub = fox.modifiers.new("Subdivision", "SUBSURF")
        sub.levels = sub.render_levels = 2
        fox.modifiers.move(len(fox.modifiers) - 1, 0)
    return fox, rig.armature_of(fox)


def rest(arm):
    arm.data.pose_position = "REST"
    bpy.context.view_layer.update()


def make_lod(fox, arm, source, ratio, strength):
    rest(arm)
    settings = LodSettings(ratio=ratio, levels=1, importance_source=source, importance_strength=strength,
                           measure_deviation=False)
    report = lod.generate_lods(bpy.context.scene, fox, settings)
    level = report["levels"][0]
    ob = bpy.data.objects[level["name"]]
    del ob[SOURCE_PROP]  # keep it out of the next run's cleanup
    ob.name = f"LOD {source}"
    return ob, level["triangles"]


def decimated(fox, triangles):
    rest(rig.armature_of(fox))
    m = len(world_arrays(fox)[1])
    ob = fox.copy()
    bpy.context.scene.collection.objects.link(ob)
    dec = ob.modifiers.new("Decimate", "DECIMATE")
    dec.decimate_type = "COLLAPSE"
    dec.ratio = triangles / m
    dec.use_collapse_triangulate = True
    at = next(i for i, md in enumerate(ob.modifiers) if md.type == "ARMATURE")
    ob.modifiers.move(len(ob.modifiers) - 1, at)  # just before the Armature modifier
    return ob


def random_poses(arm, count):
    """Setters for ``count`` random poses (every pose bone, random axis, angle <= 40 deg)."""
    def setter(seed):
        def apply():
            if arm.animation_data is not None:
                arm.animation_data.action = None
            rng = np.random.default_rng(seed)
            for pb in arm.pose.bones:
                axis = rng.normal(size=3)
                axis /= np.linalg.norm(axis)
                angle = math.radians(rng.uniform(0.0, MAX_ANGLE_DEG))
                pb.rotation_mode = "QUATERNION"
                pb.location = (0, 0, 0)
                pb.scale = (1, 1, 1)
                pb.rotation_quaternion = (math.cos(angle / 2), *(math.sin(angle / 2) * axis))
            arm.data.pose_position = "POSE"
            bpy.context.view_layer.update()
        return apply
    return [(f"random {100 + k + 1}", setter(100 + k + 1)) for k in range(count)]


def clip_poses(arm, frames):
    def setter(action, frame):
        def apply():
            if arm.animation_data is None:
                arm.animation_data_create()
            arm.animation_data.action = bpy.data.actions[action]
            bpy.context.scene.frame_set(frame)
            arm.data.pose_position = "POSE"
            bpy.context.view_layer.update()
        return apply
    return [(f"{a} {f}", setter(a, f)) for a, f in frames]


def clip_frames(per_clip):
    out = []
    for action in sorted(bpy.data.actions, key=lambda a: a.name):
        lo, hi = action.frame_range
        out += [(action.name, int(round(f))) for f in np.linspace(lo, hi, per_clip, endpoint=False)]
    return out


ROWS = {
    "A": dict(title="Fox as imported, 25 %, 5 random poses", subdivide=False, weld=False, ratio=0.25, poses="random"),
    "B": dict(title="Fox subdivided twice, 10 %, 5 random poses", subdivide=True, weld=False, ratio=0.1, poses="random"),
    "C": dict(title="Fox subdivided twice, 10 %, 15 frames of its 3 clips", subdivide=True, weld=False, ratio=0.1,
              poses="clips"),
    "D": dict(title="figures.md: Fox welded + subdivided, 10 %, Run and Survey (10 frames)", subdivide=True,
              weld=True, ratio=0.1, poses="fig"),
    "H1": dict(title="procedural humanoid, 25 %, 5 random poses", humanoid=True, ratio=0.25, poses="random"),
    "H2": dict(title="procedural humanoid, 10 %, 5 random poses", humanoid=True, ratio=0.1, poses="random"),
    "H3": dict(title="procedural humanoid at level 1 (1,504 triangles), 25 %, 5 random poses", humanoid=True,
               subdivision=1, ratio=0.25, poses="random"),
    "H4": dict(title="procedural humanoid at level 1, 10 %, 5 random poses", humanoid=True, subdivision=1,
               ratio=0.1, poses="random"),
}


def load_row(path, row):
    """(mesh, armature) of a row, in a fresh scene: the Fox (path) or the humanoid."""
    fresh_scene()
    if row.get("humanoid"):
        return humanoid.build(row.get("subdivision", 2))
    return import_fox(path, row["subdivide"], row["weld"])


def run_row(path, row, samples, strength, sources):
    fox, arm = load_row(path, row)
    if arm.animation_data is None:
        arm.animation_data_create()
    objects = {}
    tris = {}
    for label in sources:
        objects[label], tris[label] = make_lod(fox, arm, SOURCES.get(label, label), row["ratio"], strength)
    objects["Decimate"] = decimated(fox, tris[sources[0]])
    if row["poses"] == "random":
        poses = random_poses(arm, RANDOM_POSES)
    elif row["poses"] == "clips":
        poses = clip_poses(arm, clip_frames(5))
    else:
        poses = clip_poses(arm, FIG_POSES)

    def measure():
        ov, of = world_arrays(fox)
        out = {}
        for label, ob in objects.items():
            lv, lf = world_arrays(ob)
            out[label] = surface_deviation(ov, of, lv, lf, n_samples=samples)["mean_percent"]
            tris.setdefault(label, len(lf))
        return out

    rest(arm)
    at_rest = measure()
    posed = []
    for name, apply in poses:
        apply()
        posed.append(measure())
    rest(arm)
    mean_posed = {label: float(np.mean([p[label] for p in posed])) for label in objects}
    return at_rest, mean_posed, tris, posed


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rows", default="A,B,C,D,H1,H2,H3,H4")
    ap.add_argument("--samples", type=int, default=50_000, help="distance samples per surface")
    ap.add_argument("--strength", type=float, default=0.5, help="importance strength (the add-on's default 0.5)")
    ap.add_argument("--sources", default="none,paper,poses")
    args = ap.parse_args()
    path = fc.find_mesh("Fox")
    rows = args.rows.split(",")
    if path is None:
        rows = [key for key in rows if ROWS[key].get("humanoid")]
        print("Fox.gltf is not in ../shared/meshes: the humanoid's rows only.")
    sources = args.sources.split(",")
    assert sources[0] == "none", "the ratios are against 'none', which goes first"
    print(f"strength {args.strength}, {args.samples:,} samples per surface; mean distance, % of the diagonal")
    labels = sources + ["Decimate"]
    print(tables.header("row", "tris",
                        "posed: " + labels[0], *labels[1:], "posed ratio over none: " + " / ".join(labels[1:]),
                        "rest: " + labels[0], *labels[1:], "rest ratio over none: " + " / ".join(sources[1:])))
    for key in rows:
        row = ROWS[key]
        fc.log(f"row {key}: {row['title']}")
        r, p, tris, per_pose = run_row(path, row, args.samples, args.strength, sources)
        cells = " | ".join(f"{p[lb]:.4f}" for lb in labels)
        ratios = " / ".join(f"{p[lb] / p['none']:.2f}x" for lb in labels[1:])
        rcells = " | ".join(f"{r[lb]:.4f}" for lb in labels)
        rratios = " / ".join(f"{r[lb] / r['none']:.2f}x" for lb in sources[1:])
        print(tables.row(f"{key}: {row['title']}", f"{tris['none']:,}", cells, ratios, rcells, rratios), flush=True)
        wins = {lb: sum(pp[lb] < pp["none"] for pp in per_pose) for lb in labels[1:]}
        fc.log(f"  poses where closer than none: {wins} of {len(per_pose)}")


if __name__ == "__main__":
    main()
