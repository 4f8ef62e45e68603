"""Issue 19 § 2, what each part of Source Armature does: the rows of
bench/figures/skinned_poses.py (the Fox, the procedural humanoid) through the core, one
part at a time.

    .venv/bin/python bench/skinned_ablation.py [--rows A,B,C,D,H1,H2,H3,H4] [--poses 16] [--seed 0]
        [--pose-weight 4] [--oracle] [--samples 30000]

Each row (skinned_poses.ROWS) is read once through the add-on's own reading
(addon.lod.prepare, every setting the default), its evaluation poses (the rows' random
poses or clip frames) are taken from Blender as bone matrices, and then, in NumPy:
  none        core.simplify with the add-on's options;
  fit only    that LOD with its weights fitted to the sample poses (core.skinning.fit_weights);
  poses only  the sample poses in the error (core.Options.pose_offsets), weights interpolated;
  both        poses in the error and weights fitted: what Source Armature does;
  oracle      (--oracle) density from the measured posed error itself: importance g from
              each source vertex's posed distance to the "none" LOD over the evaluation
              poses, through the calibrated slider at Strength 0.5. No artist has it; it
              bounds what any density-only mapping (the paper's among them) could do.
Posed: two-sided mean distance (addon/pure/measure.py) between the posed source and the posed
LOD, linear blend skinning of both in NumPy (checked here against Blender's own posed
source), % of the bounding-box diagonal, averaged over the row's poses; ratios over none.
--poses, --seed and --pose-weight change the sample poses (core.skinning.random_poses) and
what they count (core.Options.pose_weight; the add-on's default Strength 0.5 gives 4).
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "figures"))
import fig_common as fc  # noqa: E402  (first: _bootstrap before bpy)
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import core  # noqa: E402
import skinned_poses as sp  # noqa: E402
from addon.pure import importance as imp  # noqa: E402
from addon.pure import skin_fit  # noqa: E402
from addon import lod, rig  # noqa: E402
from addon.pure.measure import surface_deviation  # noqa: E402
from addon.pure.settings import LodSettings  # noqa: E402
from fig_skinned import world_arrays  # noqa: E402

skin = core.skinning.skin


def read_row(key, poses, seed):
    """Everything a row needs, read from Blender once."""
    row = sp.ROWS[key]
    fox, arm = sp.load_row(fc.find_mesh("Fox"), row)
    if arm.animation_data is None:
        arm.animation_data_create()
    sp.rest(arm)
    inp = lod.prepare(bpy.context.scene, fox, LodSettings(ratio=row["ratio"], levels=1, measure_deviation=False))
    sample = rig.sample_poses(fox, inp.data.group_names, poses, seed)
    names, rest, parents, to_armature = rig.rig_arrays(fox, arm)
    columns = [names.index(inp.data.group_names[c]) for c in inp.names["skin"]]
    evaluation = {"random": sp.random_poses(arm, sp.RANDOM_POSES), "clips": sp.clip_poses(arm, sp.clip_frames(5)),
                  "fig": sp.clip_poses(arm, sp.FIG_POSES)}[row["poses"]]
    world = np.array(fox.matrix_world)
    skin_w = inp.data.group_weights[:, inp.names["skin"]]
    mats, worst = [], 0.0
    for _, apply in evaluation:
        apply()
        turns = np.array([np.array(arm.pose.bones[n].matrix_basis) for n in names])
        m = core.skinning.change_of_space(core.skinning.pose_matrices(rest, parents, turns), to_armature)[columns]
        mats.append(m)
        blender = world_arrays(fox)[0]
        ours = skin(inp.data.vertices, skin_w, m) @ world[:3, :3].T + world[:3, 3]
        if len(ours) == len(blender):
            worst = max(worst, float(np.abs(ours - blender).max() / np.ptp(blender, axis=0).max()))
    sp.rest(arm)
    fc.log(f"row {key}: {len(inp.data.faces):,} faces, {len(mats)} evaluation poses, "
           f"skinning against Blender's: {worst:.1e} of the size")
    return inp, skin_w, sample, np.array(mats), world


def posed_distance(inp, skin_w, mats, world, result, weights, samples):
    """(rest, mean over the evaluation poses) two-sided mean distance, % of the diagonal."""
    def w(p):
        return p @ world[:3, :3].T + world[:3, 3]
    sv, sf = inp.data.vertices, inp.data.faces
    rest = surface_deviation(w(sv), sf, w(result.vertices), result.faces, n_samples=samples)["mean_percent"]
    posed = [surface_deviation(w(skin(sv, skin_w, m)), sf, w(skin(result.vertices, weights, m)), result.faces,
                               n_samples=samples)["mean_percent"] for m in mats]
    return rest, float(np.mean(posed))


def fitted(inp, sample, result):
    """The LOD's weights fitted to the sample poses, as Source Armature fits them."""
    return skin_fit.fit_skin(dataclasses.replace(inp, poses=sample), result)[0].vertex_attributes["skin"]


def oracle_options(inp, skin_w, mats, result):
    from mathutils.bvhtree import BVHTree
    sv = inp.data.vertices

    def distances(v, f, points):
        tree = BVHTree.FromPolygons(v.tolist(), f.tolist(), all_triangles=True)
        return np.array([tree.find_nearest(p)[3] for p in points.tolist()])
    excess = -distances(result.vertices, result.faces, sv)
    for m in mats:
        excess += distances(skin(result.vertices, result.vertex_attributes["skin"], m), result.faces,
                            skin(sv, skin_w, m)) / len(mats)
    excess = np.maximum(excess, 0.0)
    g = np.clip(excess / np.percentile(excess, 90), 0.0, 1.0)
    return core.Options.of(inp.core_options, **imp.controls(g, inp.settings.line_weight, 0.5))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rows", default="A,B,C,D,H1,H2,H3,H4")
    ap.add_argument("--poses", type=int, default=core.skinning.SAMPLE_POSES)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--pose-weight", type=float, default=imp.pose_weight(imp.DEFAULT_STRENGTH))
    ap.add_argument("--oracle", action="store_true")
    ap.add_argument("--samples", type=int, default=30_000)
    args = ap.parse_args()
    rows = args.rows.split(",")
    if fc.find_mesh("Fox") is None:
        rows = [key for key in rows if sp.ROWS[key].get("humanoid")]
        print("Fox.gltf is not in ../shared/meshes: the humanoid's rows only.")
    print(f"{args.poses} sample poses (seed {args.seed}), pose weight {args.pose_weight:g}; "
          f"posed / rest mean distance, % of the diagonal, and over none")
    print("| row | none | fit only | poses only | both |" + (" oracle density |" if args.oracle else ""))
    print("|---|---|---|---|---|" + ("---|" if args.oracle else ""))
    for key in rows:
        inp, skin_w, sample, mats, world = read_row(key, args.poses, args.seed)
        target = inp.targets[0]

        def run(options):
            return core.simplify_chain(inp.data.vertices, inp.data.faces, [target], options)[0]
        plain = run(inp.core_options)
        offsets = core.skinning.pose_offsets(inp.data.vertices, skin_w, sample)
        posed = run(core.Options.of(inp.core_options, pose_offsets=offsets, pose_weight=args.pose_weight))
        cells = {
            "none": posed_distance(inp, skin_w, mats, world, plain, plain.vertex_attributes["skin"], args.samples),
            "fit": posed_distance(inp, skin_w, mats, world, plain, fitted(inp, sample, plain), args.samples),
            "poses": posed_distance(inp, skin_w, mats, world, posed, posed.vertex_attributes["skin"], args.samples),
            "both": posed_distance(inp, skin_w, mats, world, posed, fitted(inp, sample, posed), args.samples),
        }
        if args.oracle:
            density = run(oracle_options(inp, skin_w, mats, plain))
            cells["oracle"] = posed_distance(inp, skin_w, mats, world, density, density.vertex_attributes["skin"],
                                             args.samples)
        r0, p0 = cells["none"]
        text = [f"{p0:.4f} / {r0:.4f}"] + [f"{p:.4f} / {r:.4f} ({p / p0:.2f}x / {r / r0:.2f}x)"
                                           for label, (r, p) in cells.items() if label != "none"]
        print(f"| {key}: {sp.ROWS[key]['title']} | " + " | ".join(text) + " |", flush=True)


if __name__ == "__main__":
    main()
