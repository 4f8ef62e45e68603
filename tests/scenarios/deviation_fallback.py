"""LODs by deviation when the core's tracked bound finds nothing (issue 22): the ladder
takes over; where the level it finds measures far under the bound, a run by count probes
below it; and an alternative run's smaller saving is kept where it costs no slivers
(tests/test_deviation_fallback.py checks what this returns)."""
import bpy
from scene_tools import extension_module, remove_all_objects


def run() -> dict:
    remove_all_objects()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12)
    ob = bpy.context.active_object
    lod = extension_module("addon.lod")
    targets = extension_module("addon.pure.deviation_targets")
    tracked = targets.by_tracked_bounds
    calls = []

    def nothing_within(deviations, run, exact):
        calls.append(len(deviations))
        return [targets.Found(d, None, float("nan")) for d in deviations]

    out = {}
    for name, search in (("tracked", tracked), ("ladder", nothing_within)):
        targets.by_tracked_bounds = search
        try:
            settings = lod.LodSettings(max_deviations=((0.5, True), (2.0, True)))
            output = lod.compute(lod.prepare(bpy.context.scene, ob, settings))
        finally:
            targets.by_tracked_bounds = tracked
        out[name] = [{key: r[key] for key in ("triangles", "hausdorff_percent", "requested_deviation_percent")}
                     for r in output.reports]
    out["fallback_calls"] = calls
    out["source_triangles"] = sum(len(p.vertices) - 2 for p in ob.data.polygons)
    out["probe"] = _bevelled_box_at_one_percent(lod, targets)
    out["free_saving"] = _bevelled_cylinder_at_one_percent(lod, targets)
    return out


def _bevelled_cylinder_at_one_percent(lod, targets) -> dict:
    """A 64-sided cylinder with bevelled rims (bench/blender_props.py's bevel_cylinder) by
    deviation at 1 %, with the alternatives' smaller savings refused and kept."""
    core = extension_module("core")
    remove_all_objects()
    bpy.ops.mesh.primitive_cylinder_add(vertices=64, radius=1, depth=0.4)
    ob = bpy.context.active_object
    bevel = ob.modifiers.new("Bevel", "BEVEL")
    bevel.width, bevel.segments, bevel.limit_method = 0.05, 4, "ANGLE"
    bpy.ops.object.modifier_apply(modifier=bevel.name)
    while ob.data.uv_layers:
        ob.data.uv_layers.remove(ob.data.uv_layers[0])
    out = {"stretch_within": targets.STRETCH_WITHIN, "min_saving": targets.LEAN_MIN_SAVING}
    free = targets._free_saving
    for name, rule in (("off", lambda mine, theirs, slivers: False), ("on", free)):
        targets._free_saving = rule
        try:
            output = lod.compute(lod.prepare(bpy.context.scene, ob, lod.LodSettings(max_deviations=((1.0, True),))))
        finally:
            targets._free_saving = free
        (report,), (level,) = output.reports, output.levels
        out[name] = {"triangles": report["triangles"], "hausdorff_percent": report["hausdorff_percent"],
                     "requested_deviation_percent": report["requested_deviation_percent"],
                     "sliver_percent": core.quality_summary(level.vertices, level.faces)["sliver_percent"]}
    return out


def _bevelled_box_at_one_percent(lod, targets) -> dict:
    """A long box with bevelled edges (bench/blender_props.py's bevel_box_long) by
    deviation at 1 %, without the probe below the tracked level (PROBE_BELOW 0) and with it."""
    remove_all_objects()
    bpy.ops.mesh.primitive_cube_add(size=1)
    ob = bpy.context.active_object
    ob.scale = (3, 0.6, 0.3)
    bpy.ops.object.transform_apply(scale=True)
    bevel = ob.modifiers.new("Bevel", "BEVEL")
    bevel.width, bevel.segments = 0.05, 5
    bpy.ops.object.modifier_apply(modifier=bevel.name)
    while ob.data.uv_layers:  # (as bench/equal_error.py has it: its seams would hold the box at 16)
        ob.data.uv_layers.remove(ob.data.uv_layers[0])
    out = {"source_triangles": sum(len(p.vertices) - 2 for p in ob.data.polygons),
           "probe_below": targets.PROBE_BELOW, "stretch_within": targets.STRETCH_WITHIN}
    default = targets.PROBE_BELOW
    for name, below in (("off", 0.0), ("on", default)):
        targets.PROBE_BELOW = below
        try:
            output = lod.compute(lod.prepare(bpy.context.scene, ob, lod.LodSettings(max_deviations=((1.0, True),))))
        finally:
            targets.PROBE_BELOW = default
        (report,) = output.reports
        out[name] = {key: report[key] for key in ("triangles", "hausdorff_percent", "requested_deviation_percent")}
    return out
