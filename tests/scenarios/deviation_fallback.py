"""LODs by deviation when the core's tracked bound finds nothing (issue 22): the ladder
takes over (tests/test_deviation_fallback.py checks what this returns)."""
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
    return out
