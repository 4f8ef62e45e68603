"""Blender's own primitives taken to the low counts of a game's last LODs, and six separate
cubes with and without Remove Small Parts (tests/test_addon_low_targets.py checks what
this returns)."""
import bpy
from scene_tools import extension_module, remove_all_objects


def fresh(add_primitive, **kwargs):
    """The scene with only the primitive that ``add_primitive`` adds."""
    remove_all_objects()
    add_primitive(**kwargs)
    return bpy.context.active_object


def one_level(ob, **settings) -> dict:
    lod = extension_module("addon.lod")
    report = lod.generate_lods(bpy.context, ob, lod.LodSettings(levels=1, measure_deviation=False, **settings))
    level = report["levels"][0]
    lod_ob = bpy.data.objects[level["name"]]
    return {"target": level["target"], "triangles": level["triangles"], "stop": level["stop_reason"],
            "step": level["relaxation_step"], "removed": level["removed_components"],
            "warnings": report["warnings"], "uv_layers": len(lod_ob.data.uv_layers),
            "polygons": len(lod_ob.data.polygons)}


def run() -> dict:
    result = {}
    sphere = fresh(bpy.ops.mesh.primitive_uv_sphere_add, segments=20, ring_count=10)
    result["sphere"] = one_level(sphere, target_triangles=36)
    sphere = fresh(bpy.ops.mesh.primitive_uv_sphere_add, segments=60, ring_count=40)
    result["big_sphere"] = one_level(sphere, target_triangles=46)
    monkey = fresh(bpy.ops.mesh.primitive_monkey_add)
    result["monkey"] = one_level(monkey, target_triangles=9)
    monkey = fresh(bpy.ops.mesh.primitive_monkey_add)
    result["monkey_20"] = one_level(monkey, target_triangles=20)
    # Six separate cubes: together they cannot go below 6 x 4 triangles without losing parts.
    remove_all_objects()
    for i in range(6):
        bpy.ops.mesh.primitive_cube_add(size=0.2 + 0.1 * i, location=(i, 0, 0))
    bpy.ops.object.select_all(action='SELECT')
    bpy.ops.object.join()
    cubes = bpy.context.active_object
    result["cubes_kept"] = one_level(cubes, target_triangles=10, remove_small_components=False)
    result["cubes_removed"] = one_level(cubes, target_triangles=10)
    monkey = fresh(bpy.ops.mesh.primitive_monkey_add)
    result["monkey_kept"] = one_level(monkey, target_triangles=9, remove_small_components=False)
    return result
