"""Painted limits (issue 34 §1) through the installed add-on: a bumpy sphere (5,120
triangles) whose vertex group "Face" is painted 1 on its top cap (z > 0.4) and fades to 0
below it, simplified to 50 / 25 / 10 % with and without a limit; a limit no count can
keep; a missing group; Paint Limit; the command line's choice per object
(tests/test_addon_limits.py checks what this returns)."""
from types import SimpleNamespace

import bpy
import numpy as np
from scene_tools import array, extension_module, remove_all_objects, select_only

CAP = 0.4  # weight 1 above this height, fading to 0 at CAP - FADE
FADE = 0.3
LIMIT_PERCENT = 0.25


def painted_sphere():
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=4, radius=1.0)
    ob = bpy.context.active_object
    ob.name = "Head"
    co = array(ob.data.vertices, "co", 3).reshape(-1, 3).astype(np.float64)
    bumps = 1.0 + 0.06 * np.sin(9 * co[:, 0]) * np.sin(7 * co[:, 1]) + 0.03 * np.sin(13 * co[:, 2])
    co = co * bumps[:, None]
    ob.data.vertices.foreach_set("co", co.astype(np.float32).ravel())
    ob.data.update()
    weight = np.clip((co[:, 2] - (CAP - FADE)) / FADE, 0.0, 1.0)
    group = ob.vertex_groups.new(name="Face")
    for value in np.unique(weight[weight > 0]):  # a few distinct weights: one call each
        group.add([int(i) for i in np.flatnonzero(weight == value)], float(value), 'REPLACE')
    return ob, weight


def lods(ob, **settings) -> dict:
    lod = extension_module("addon.lod")
    settings.setdefault("ratios", (0.5, 0.25, 0.1))
    report = lod.generate_lods(bpy.context, ob, lod.LodSettings(**settings))
    return {"levels": report["levels"], "warnings": report["warnings"]}


def errors(head, plain) -> dict:
    lod = extension_module("addon.lod")
    out = {}
    for tag, ob, extra in (("missing", plain, {}),):
        try:
            lod.generate_lods(bpy.context, ob, lod.LodSettings(ratio=0.5, levels=1, limit_group="Face", **extra))
            out[tag] = None
        except lod.LodError as ex:
            out[tag] = str(ex)
    select_only(plain)
    try:
        bpy.ops.object.line_quadric_lod(ratio=0.5, levels=1, limit_group="Face")
        out["operator"] = None
    except RuntimeError as ex:
        out["operator"] = str(ex)
    out["lods_made"] = sorted(ob.name for ob in bpy.data.objects if ob.name.startswith("Plain_LOD"))
    return out


def paint_limit(ob) -> dict:
    select_only(ob)
    panel = bpy.context.scene.line_quadric_lod
    panel.limit_group = ""
    result = sorted(bpy.ops.object.line_quadric_lod_paint_limit())
    out = {"result": result, "panel_group": panel.limit_group, "mode": ob.mode,
           "groups": [g.name for g in ob.vertex_groups]}
    bpy.ops.object.mode_set(mode='OBJECT')
    panel.limit_group = ""
    return out


def command_line(objects) -> dict:
    sources = extension_module("addon.headless.sources")
    arguments = extension_module("addon.headless.arguments")
    parser = arguments.build_parser()
    args = SimpleNamespace(limit_group="Face")
    out = {"choice": [list(c) for c in sources.limit_choice(objects, args)]}
    parsed = parser.parse_args(["--limit-group", "Face", "--limit", "0.2%", "--report", "r.json"])
    s = arguments.lod_settings(parsed, limit_group="Face")
    out["settings"] = [s.limit_group, s.limit_distance, s.limit_unit]
    parsed = parser.parse_args(["--limit", "0.5px", "--report", "r.json"])
    out["pixels"] = arguments.lod_settings(parsed).limit_unit
    parsed = parser.parse_args(["--limit", "0.02", "--report", "r.json"])
    out["units"] = arguments.lod_settings(parsed).limit_unit
    out["problems"] = arguments.check_args(parsed)
    return out


def run() -> dict:
    remove_all_objects()
    head, weight = painted_sphere()
    before = array(head.data.vertices, "co", 3).copy()
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=1.0, location=(4, 0, 0))
    plain = bpy.context.active_object
    plain.name = "Plain"
    free = lods(head)
    held = lods(head, limit_group="Face", limit_distance=LIMIT_PERCENT)
    tight = lods(head, limit_group="Face", limit_distance=0.005)
    pixels = lods(head, limit_group="Face", limit_distance=0.25, limit_unit='PIXELS')
    pixels_by_deviation = lods(head, ratios=None, max_deviations=((0.5, True), (1.0, True), (2.0, True)),
                               limit_group="Face", limit_distance=0.25, limit_unit='PIXELS')
    unmeasured = lods(head, limit_group="Face", limit_distance=LIMIT_PERCENT, measure_deviation=False)
    return {
        "input": {"triangles": len(head.data.polygons), "painted": int(np.count_nonzero(weight > 0))},
        "free": free,
        "held": held,
        "tight": tight,
        "pixels": pixels,
        "pixels_by_deviation": pixels_by_deviation,
        "unmeasured": unmeasured,
        "source_unchanged": bool(np.array_equal(before, array(head.data.vertices, "co", 3))),
        "errors": errors(head, plain),
        "paint": paint_limit(plain),
        "command_line": command_line([head, plain]),
    }
