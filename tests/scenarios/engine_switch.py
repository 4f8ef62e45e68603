"""Switch data for the engines through the installed extension (tests/test_engine_switch.py):
a measured chain's custom properties, the Unreal LOD group's screen sizes, a .glb written
by Blender's own glTF exporter (the extension's hooks add MSFT_lod) and an .fbx whose
custom properties come back through Blender's FBX importer."""
from pathlib import Path

import bpy
from scene_tools import (capped_tube, empty_scene, extension_module, parent_with_automatic_weights,
                         remove_all_objects, three_bone_rig)

lod = extension_module("addon.lod")
switch_prop = extension_module("addon.lod_objects").switch_prop
lod_group = extension_module("addon.lod_group")
scene_files = extension_module("addon.headless.scene_files")

SWITCH_KEYS = ("deviation", "switch_distance", "msft_screen_coverage", "unreal_screen_size",
               "unity_transition_height", "godot_visibility_range_begin", "godot_visibility_range_end")


def switch_props(ob) -> dict:
    return {key: ob[switch_prop(key)] for key in SWITCH_KEYS if switch_prop(key) in ob}


def animated_skin_exports(paused_glb: str, plain_glb: str) -> dict:
    """A skinned tube, its LOD chain and an action bending the elbow over 20 frames,
    written by the command line's export (Armature modifiers paused while the exporter
    samples the action) and by the exporter called directly."""
    empty_scene()
    rig = three_bone_rig()
    tube, _, _ = capped_tube("Arm", lambda z: 0.3 + 0.0 * z, 16, 24)
    parent_with_automatic_weights(rig, tube)
    lod.generate_lods(bpy.context, tube, lod.LodSettings(ratio=0.5, levels=2))
    bone = rig.pose.bones["Lower"]
    bone.rotation_mode = 'XYZ'
    for frame, angle in ((1, 0.0), (10, 1.2), (20, 0.3)):
        bone.rotation_euler = (angle, 0.0, 0.0)
        bone.keyframe_insert("rotation_euler", frame=frame)
    bpy.context.scene.frame_start, bpy.context.scene.frame_end = 1, 20
    mods = [m for ob in bpy.data.objects if ob.type == 'MESH' for m in ob.modifiers if m.type == 'ARMATURE']
    scene_files.export_scene(Path(paused_glb))
    shown_after = [m.show_viewport for m in mods]
    with scene_files.gltf_hooks_visible():
        bpy.ops.export_scene.gltf(filepath=plain_glb, export_format='GLB', use_selection=False, export_apply=True)
    return {"armature_modifiers": len(mods), "shown_after": shown_after}


def run(glb: str, fbx: str, unmeasured_glb: str, paused_glb: str, plain_glb: str) -> dict:
    empty_scene()
    bpy.ops.mesh.primitive_monkey_add(size=2.0, location=(1.0, 0.0, 0.0))
    src = bpy.context.active_object
    src.name = "Monkey"
    src.scale = (2.0, 2.0, 2.0)
    mod = src.modifiers.new("sub", 'SUBSURF')
    mod.levels = 2
    report = lod.generate_lods(bpy.context, src, lod.LodSettings(ratio=0.5, levels=3))
    chain = [src] + [bpy.data.objects[level["name"]] for level in report["levels"]]
    result = {"report": report, "props": {ob.name: switch_props(ob) for ob in chain}}

    # The command line's naming: LOD0 renamed, the chain under an Unreal LOD group.
    lod_group.rename_as_lod0(src)
    empty = lod_group.group_chain(bpy.context, "Monkey", chain)
    result["group_props"] = {k: empty[k] for k in empty.keys()}
    result["names"] = [ob.name for ob in chain]

    bpy.ops.export_scene.gltf(filepath=glb, export_format='GLB', use_selection=False, export_apply=True)
    bpy.ops.export_scene.fbx(filepath=fbx, use_selection=False, use_mesh_modifiers=True,
                             use_custom_props=True, add_leaf_bones=False)
    remove_all_objects()
    bpy.ops.import_scene.fbx(filepath=fbx)
    result["fbx_props"] = {ob.name: {k: ob[k] for k in ob.keys() if k.startswith("lqlod_")}
                           for ob in bpy.data.objects}

    # Unmeasured: no switch data, no MSFT_lod, and no stale properties left on the source.
    empty_scene()
    bpy.ops.mesh.primitive_monkey_add()
    src = bpy.context.active_object
    lod.generate_lods(bpy.context, src, lod.LodSettings(ratio=0.5, levels=2))
    assert switch_prop("switch_distance") in src
    unmeasured = lod.generate_lods(bpy.context, src, lod.LodSettings(ratio=0.5, levels=2, measure_deviation=False))
    result["unmeasured"] = {"switch": unmeasured["switch"],
                            "props": [k for ob in bpy.data.objects for k in ob.keys() if k.startswith("lqlod_")]}
    bpy.ops.export_scene.gltf(filepath=unmeasured_glb, export_format='GLB', use_selection=False)
    result["animated_skin"] = animated_skin_exports(paused_glb, plain_glb)
    return result
