"""A skinned arm in real Blender: Importance from Armature, LODs that deform with the rig,
and the posed LOD against Blender's Decimate at the same triangle count.

The test builds its own character: a 3-bone armature and a capped tube "arm" (48 x 64
vertices, with a narrowing at the elbow), parented with Automatic Weights. One Blender
child runs everything (module fixture); the tests check its RESULT.
"""
import statistics

import pytest

from bpy_harness import run_in_blender

SNIPPET = r'''
import importlib, json, math
import numpy as np

lod = importlib.import_module(EXT + ".addon.lod")
measure = importlib.import_module(EXT + ".addon.measure")
R = RESULT
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
scene = bpy.context.scene

def select_only(*obs):
    for o in bpy.context.view_layer.objects:
        o.select_set(False)
    for o in obs:
        o.select_set(True)
    bpy.context.view_layer.objects.active = obs[0] if obs else None

bpy.ops.object.armature_add(enter_editmode=True, location=(0, 0, 0))
arm = bpy.context.active_object
arm.name = "Rig"
eb = arm.data.edit_bones
b0 = eb[0]; b0.name = "Upper"; b0.head = (0, 0, 0); b0.tail = (0, 0, 1.0)
b1 = eb.new("Lower"); b1.head = (0, 0, 1.0); b1.tail = (0, 0, 2.0); b1.parent = b0; b1.use_connect = True
b2 = eb.new("Hand"); b2.head = (0, 0, 2.0); b2.tail = (0, 0, 2.6); b2.parent = b1; b2.use_connect = True
bpy.ops.object.mode_set(mode='OBJECT')

around, rings = 48, 64
z = np.linspace(0.02, 2.58, rings)
radius = 0.22 + 0.05 * np.sin(z * math.pi / 1.3) ** 2 - 0.04 * np.exp(-((z - 1.0) / 0.12) ** 2)
t = np.linspace(0, 2 * math.pi, around, endpoint=False)
V = np.stack([np.outer(radius, np.cos(t)), np.outer(radius, np.sin(t)), np.repeat(z[:, None], around, 1)], -1).reshape(-1, 3)
idx = np.arange(rings * around).reshape(rings, around)
quads = np.stack([idx[:-1], np.roll(idx[:-1], -1, 1), np.roll(idx[1:], -1, 1), idx[1:]], -1).reshape(-1, 4)
faces = [tuple(q) for q in quads.tolist()] + [tuple(idx[0][::-1].tolist()), tuple(idx[-1].tolist())]
me = bpy.data.meshes.new("Arm")
me.from_pydata(V.tolist(), [], faces)
me.update()
ob = bpy.data.objects.new("Arm", me)
scene.collection.objects.link(ob)
select_only(arm, ob)  # armature active, mesh selected
bpy.context.view_layer.objects.active = arm
R["parent"] = sorted(bpy.ops.object.parent_set(type='ARMATURE_AUTO'))
R["groups"] = ob.vertex_groups.keys()

def weights(o, names):
    W = np.zeros((len(o.data.vertices), len(names)))
    index = {o.vertex_groups[nm].index: c for c, nm in enumerate(names) if nm in o.vertex_groups}
    for v in o.data.vertices:
        for g in v.groups:
            if g.group in index:
                W[v.index, index[g.group]] = g.weight
    return W

bones = ["Upper", "Lower", "Hand"]
select_only(ob)
R["from_armature"] = sorted(bpy.ops.object.line_quadric_lod_from_armature())
skin = weights(ob, bones)
baked = weights(ob, ["LOD_Importance"])[:, 0]
paper = np.minimum(0.15 * (1.0 - skin.max(axis=1)), 0.1)  # paper Sec. 5.3
R["baked_error"] = float(np.abs(baked - paper / 0.1).max())
R["baked_range"] = [float(baked.min()), float(baked.max())]
R["baked_nonzero"] = int(np.count_nonzero(baked))
# Vertices near the elbow (z = 1, shared by Upper and Lower) matter more than mid-bone ones.
zc = V[:, 2]
R["baked_elbow_vs_mid"] = [float(baked[np.abs(zc - 1.0) < 0.1].mean()), float(baked[np.abs(zc - 0.5) < 0.1].mean())]
R["settings_after_bake"] = [scene.line_quadric_lod.importance_source, scene.line_quadric_lod.importance_group]

def posed(o):
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    e = o.evaluated_get(dg)
    m = e.to_mesh()
    m.calc_loop_triangles()
    P = np.empty(len(m.vertices) * 3, np.float32); m.vertices.foreach_get("co", P)
    F = np.empty(len(m.loop_triangles) * 3, np.int32); m.loop_triangles.foreach_get("vertices", F)
    M = np.array(e.matrix_world)
    P = P.reshape(-1, 3).astype(float) @ M[:3, :3].T + M[:3, 3]
    e.to_mesh_clear()
    return P, F.reshape(-1, 3)

def pose(on):
    for b in arm.pose.bones:
        b.rotation_mode = 'XYZ'
        b.rotation_euler = (0, 0, 0)
    if on:
        arm.pose.bones["Lower"].rotation_euler = (math.radians(80), 0, 0)
        arm.pose.bones["Hand"].rotation_euler = (math.radians(-50), 0, math.radians(30))

src_tris = len(posed(ob)[1])
R["source_triangles"] = src_tris
# The tube is symmetric, so many collapses tie exactly and the seed decides between them:
# each asserted case runs with three seeds (the add-on always passes seed 0).
core_module = importlib.import_module(EXT + ".addon._core").core
simplify_chain = core_module.simplify_chain
SEED = [0]
core_module.simplify_chain = lambda *args, **kwargs: simplify_chain(*args, seed=SEED[0], **kwargs)
runs = {}
for source in ('ARMATURE', 'VERTEX_GROUP', 'NONE'):
    for ratio in (0.1, 0.03):
        info = {"triangles": [], "ours": []}
        for seed in ((0, 1, 2) if source != 'NONE' else (0,)):
            SEED[0] = seed
            pose(False)
            select_only(ob)
            bpy.ops.object.line_quadric_lod(ratio=ratio, levels=1, importance_source=source,
                                            importance_group="LOD_Importance", measure_deviation=False)
            L = bpy.data.objects["Arm_LOD1"]
            tris = len(L.data.polygons)
            info["triangles"].append(tris)
            if seed == 0:
                dup = bpy.data.objects.get("Arm_Decimate")
                if dup is not None:
                    d = dup.data; bpy.data.objects.remove(dup); bpy.data.meshes.remove(d)
                dup = ob.copy(); dup.data = ob.data.copy(); dup.name = "Arm_Decimate"
                scene.collection.objects.link(dup)
                dec = dup.modifiers.new("Decimate", 'DECIMATE')
                dec.ratio = tris / src_tris
                dup.modifiers.move(len(dup.modifiers) - 1, 0)  # decimate the rest shape, then skin
            if source == 'ARMATURE' and ratio == 0.1 and seed == 0:
                lw = weights(L, bones)
                info["modifiers"] = [(m.type, m.object.name if m.object else None) for m in L.modifiers]
                info["parent"] = L.parent.name if L.parent else None
                info["groups"] = L.vertex_groups.keys()
                info["weight_range"] = [float(lw.min()), float(lw.max())]
                info["weight_sum_range"] = [float(lw.sum(1).min()), float(lw.sum(1).max())]
                info["source_sum_range"] = [float(skin.sum(1).min()), float(skin.sum(1).max())]
                info["bones_used"] = int((lw.max(0) > 0.5).sum())
            pose(True)
            Ps, Fs = posed(ob)
            Pl, Fl = posed(L)
            ours = measure.surface_deviation(Ps, Fs, Pl, Fl, n_samples=50_000)
            info["ours"].append([ours["hausdorff_percent"], ours["mean_percent"]])
            if seed == 0:
                Pd, Fd = posed(dup)
                theirs = measure.surface_deviation(Ps, Fs, Pd, Fd, n_samples=50_000)
                info.update(decimate_triangles=len(Fd), decimate=[theirs["hausdorff_percent"], theirs["mean_percent"]],
                            moved=float(np.abs(Ps - V).max()))
        runs[f"{source}_{ratio}"] = info
core_module.simplify_chain = simplify_chain
pose(False)
R["runs"] = runs

# Generating while posed, through a modifier stack (Subdivision after the Armature): the
# LOD is built from the rest shape (it gets its own Armature modifier), and the source's
# modifiers are left exactly as they were.
sub = ob.modifiers.new("Subdivision", 'SUBSURF')
sub.levels = 1
pose(True)
mods_before = [(m.name, m.show_viewport) for m in ob.modifiers]
select_only(ob)
bpy.ops.object.line_quadric_lod(ratio=0.05, levels=1, importance_source='ARMATURE', measure_deviation=False)
L = bpy.data.objects["Arm_LOD1"]
P = np.empty(len(L.data.vertices) * 3, np.float32); L.data.vertices.foreach_get("co", P)
F = np.array([p.vertices[:] for p in L.data.polygons])
rest = measure.surface_deviation(V, np.array([t for f in faces for t in [(f[0], f[i], f[i + 1]) for i in range(1, len(f) - 1)]]),
                                 P.reshape(-1, 3), F)
R["posed_run"] = {"rest_hausdorff": rest["hausdorff_percent"], "mods_after": [(m.name, m.show_viewport) for m in ob.modifiers],
                  "mods_before": mods_before, "lod_mods": [m.type for m in L.modifiers],
                  "triangles": len(F), "report": json.loads(scene.line_quadric_lod.last_report)[0]}
pose(False)
'''


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_in_blender(SNIPPET, user_dir=blender_user_dir, timeout=600)


def test_character_is_skinned(res):
    assert res["parent"] == ["FINISHED"]
    assert res["groups"] == ["Upper", "Lower", "Hand"]


def test_importance_from_armature_is_the_papers_formula(res):
    assert res["from_armature"] == ["FINISHED"]
    # Baked as w_i / 0.1 so the group reads 0..1 in Weight Paint mode.
    assert res["baked_error"] < 1e-6
    lo, hi = res["baked_range"]
    assert 0.0 <= lo and hi <= 1.0 and hi > 0.5
    elbow, mid = res["baked_elbow_vs_mid"]
    assert elbow > 2 * mid
    assert res["settings_after_bake"] == ["VERTEX_GROUP", "LOD_Importance"]


def test_lods_deform_with_the_rig(res):
    info = res["runs"]["ARMATURE_0.1"]
    assert info["modifiers"] == [["ARMATURE", "Rig"]]
    assert info["parent"] == "Rig"
    assert info["groups"][:3] == ["Upper", "Lower", "Hand"] and "LOD_Importance" in info["groups"]
    lo, hi = info["weight_range"]
    assert lo >= 0.0 and hi <= 1.0
    assert info["bones_used"] == 3
    # Interpolated weights stay within the source's range of weight sums.
    src_lo, src_hi = info["source_sum_range"]
    lo, hi = info["weight_sum_range"]
    assert lo >= src_lo - 1e-3 and hi <= src_hi + 1e-3


@pytest.mark.parametrize("ratio", [0.1, 0.03])
def test_posed_lod_beats_decimate(res, ratio):
    for source in ("ARMATURE", "VERTEX_GROUP"):
        info = res["runs"][f"{source}_{ratio}"]
        assert info["moved"] > 0.5  # the pose really bends the arm
        for tris in info["triangles"]:
            assert abs(tris - round(ratio * res["source_triangles"])) <= 1
        assert abs(info["decimate_triangles"] - info["triangles"][0]) <= 0.02 * info["triangles"][0]
        hausdorff = [h for h, _ in info["ours"]]
        mean = [m for _, m in info["ours"]]
        dec_h, dec_mean = info["decimate"]
        # The median of the three seeds: on this symmetric tube the tie-breaking seed moves
        # a single LOD's distances a lot. Over eight seeds, the posed mean at 3 % ranged
        # 0.98-1.12x Decimate's and the Hausdorff distance at 10 % 0.68-1.33x.
        assert max(hausdorff) < (2.0 if ratio == 0.1 else 3.0)  # bounded, % of the bbox diagonal
        # At 3 % the joints decide the worst spot, and protecting them wins clearly. At 10 %
        # the worst spot is a single vertex somewhere on the arm: only "as close, within
        # that scatter" holds.
        assert statistics.median(hausdorff) < (dec_h if ratio < 0.1 else 1.2 * dec_h)
        # On average as close at 10 %. At 3 % (184 triangles) the greedy cheapest-first
        # order itself is a little further on average on this tube (bench/arm_order.py).
        assert statistics.median(mean) < (1.05 if ratio >= 0.1 else 1.1) * dec_mean


def test_posed_source_is_read_at_rest(res):
    run = res["posed_run"]
    assert run["mods_after"] == run["mods_before"]  # Armature modifier switched back on
    assert run["lod_mods"] == ["ARMATURE"]  # Subdivision applied, skinning kept live
    rep = run["report"]
    assert rep["source_triangles"] == 63 * 48 * 8 + 2 * 48 * 2  # the subdivided arm was read
    assert abs(run["triangles"] - rep["levels"][0]["target"]) <= 1
    # Against the unposed, unsubdivided arm: close (a bent arm would be ~20 % off).
    assert run["rest_hausdorff"] < 2.0
