"""Importance from the armature measured posed: a 5 % LOD without and with it, each posed
by the rig in four random poses and measured against the posed source
(tests/test_addon_skinned_poses.py checks what this returns)."""
import math

import bpy
import numpy as np
from scene_tools import (capped_tube, extension_module, parent_with_automatic_weights, posed_triangles,
                         remove_all_objects, three_bone_rig)

POSE_SEEDS = (11, 12, 13, 14)


def tube_radius(z):
    return 0.2 + 0.03 * np.sin(z * 2.1) ** 2


def set_pose(rig, seed) -> None:
    """The rest pose (seed None), or every bone turned by 20 to 50 degrees about a random axis."""
    rng = np.random.default_rng(seed)
    for pb in rig.pose.bones:
        pb.rotation_mode = 'QUATERNION'
        if seed is None:
            pb.rotation_quaternion = (1, 0, 0, 0)
            continue
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        angle = math.radians(rng.uniform(20.0, 50.0))
        pb.rotation_quaternion = (math.cos(angle / 2), *(math.sin(angle / 2) * axis))
    bpy.context.view_layer.update()


def run() -> dict:
    lod = extension_module("addon.lod")
    measure = extension_module("addon.pure.measure")
    LodSettings = extension_module("addon.pure.settings").LodSettings
    SOURCE_PROP = extension_module("addon.lod_objects").SOURCE_PROP
    result = {}
    remove_all_objects()
    rig = three_bone_rig()
    ob, V, _faces = capped_tube("Tube", tube_radius, around=48, rings=80)
    result["parent"] = parent_with_automatic_weights(rig, ob)

    lods = {}
    # 5 %, and a coarse 0.6 % (15 triangles a bone, where Source Armature checks the
    # level against one made without the poses: addon/pure/skin_fit.py, skinned_levels).
    for source, ratio, key in (('NONE', 0.05, 'NONE'), ('ARMATURE', 0.05, 'ARMATURE'),
                               ('ARMATURE_PAPER', 0.05, 'ARMATURE_PAPER'),
                               ('NONE', 0.006, 'NONE_COARSE'), ('ARMATURE', 0.006, 'ARMATURE_COARSE')):
        set_pose(rig, None)
        report = lod.generate_lods(bpy.context.scene, ob, LodSettings(
            ratio=ratio, levels=1, importance_source=source, measure_deviation=False))
        lod_ob = bpy.data.objects[report["levels"][0]["name"]]
        del lod_ob[SOURCE_PROP]  # keep it out of the next run's cleanup
        lod_ob.name = key
        lods[key] = lod_ob
    result["triangles"] = {k: len(posed_triangles(L)[1]) for k, L in lods.items()}
    result["modifiers"] = [m.type for m in lods['ARMATURE'].modifiers]
    result["rest"], result["posed"] = {}, {k: [] for k in lods}
    set_pose(rig, None)
    source = posed_triangles(ob)
    for k, lod_ob in lods.items():
        result["rest"][k] = measure.surface_deviation(*source, *posed_triangles(lod_ob), n_samples=40_000)["mean_percent"]
    moved = []
    for seed in POSE_SEEDS:
        set_pose(rig, seed)
        source = posed_triangles(ob)
        moved.append(float(np.abs(source[0] - V).max()))
        for k, lod_ob in lods.items():
            result["posed"][k].append(
                measure.surface_deviation(*source, *posed_triangles(lod_ob), n_samples=40_000)["mean_percent"])
    result["moved"] = min(moved)
    set_pose(rig, None)
    result["forward_kinematics"] = forward_kinematics_check(rig, ob)
    return result


def forward_kinematics_check(rig, ob) -> list:
    """The sample poses' maths (core.skinning) against Blender's own Armature deformation,
    with the armature moved, turned and scaled and the mesh given its own transform: the
    largest distance between the two posed meshes, relative to the mesh's size, per pose."""
    skinning = extension_module("addon.pure._core").core.skinning
    rig_arrays = extension_module("addon.rig").rig_arrays
    vertex_groups = extension_module("addon.vertex_groups")
    rig.location, rig.rotation_euler, rig.scale = (0.4, -1.2, 0.3), (0.3, -0.5, 1.1), (1.7, 1.7, 1.7)
    ob.matrix_parent_inverse = ob.matrix_parent_inverse @ mathutils_matrix((0.2, 0.1, -0.3), (0.0, 0.0, 0.4))
    bpy.context.view_layer.update()
    rest_v = np.array([v.co for v in ob.data.vertices], dtype=np.float64)
    names, rest, parents, to_armature = rig_arrays(ob, rig)
    weights = vertex_groups.read_weights(ob.data, names)  # columns in the bones' order
    out = []
    for seed in (21, 22):
        set_pose(rig, seed)
        turns = np.array([np.array(rig.pose.bones[name].matrix_basis) for name in names])
        deform = skinning.change_of_space(skinning.pose_matrices(rest, parents, turns), to_armature)
        mw = np.array(ob.matrix_world)
        ours = skinning.skin(rest_v, weights, deform) @ mw[:3, :3].T + mw[:3, 3]
        blender = posed_triangles(ob)[0]
        size = float(np.ptp(blender, axis=0).max())
        out.append(float(np.abs(ours - blender).max()) / size)
    set_pose(rig, None)
    return out


def mathutils_matrix(location, euler):
    from mathutils import Euler, Matrix
    return Matrix.Translation(location) @ Euler(euler).to_matrix().to_4x4()
