"""Switch data for the engines through the installed extension (tests/test_engine_switch.py):
a measured chain's custom properties, the Unreal LOD group's screen sizes, a .glb written
by Blender's own glTF exporter (the extension's hooks add MSFT_lod) and an .fbx whose
custom properties come back through Blender's FBX importer."""
import bpy
from scene_tools import empty_scene, extension_module, remove_all_objects

lod = extension_module("addon.lod")
switch_prop = extension_module("addon.lod_objects").switch_prop
lod_group = extension_module("addon.lod_group")

SWITCH_KEYS = ("deviation", "switch_distance", "msft_screen_coverage", "unreal_screen_size",
               "unity_transition_height", "godot_visibility_range_begin", "godot_visibility_range_end")


def switch_props(ob) -> dict:
    return {key: ob[switch_prop(key)] for key in SWITCH_KEYS if switch_prop(key) in ob}


def run(glb: str, fbx: str, unmeasured_glb: str) -> dict:
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
    return result
