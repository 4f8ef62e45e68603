"""Shape keys (issue 34) through the installed add-on: a sphere (5,120 triangles) whose key
"Crown" raises a ridged crown on its top cap (z > 0.5) and whose key "Still" moves
nothing, simplified to 10 % and 5 % with no importance and with Source Shape Keys;
Importance from Shape Keys; and an object without keys, for the errors
(tests/test_addon_shape_keys.py checks what this returns)."""
import importlib
import json
from types import SimpleNamespace

import bpy
import numpy as np
from scene_tools import array, extension_module, remove_all_objects, select_only

CAP = 0.5  # the crown key moves the vertices above this height


def keyed_sphere():
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=5, radius=1.0)
    ob = bpy.context.active_object
    ob.name = "Ball"
    co = array(ob.data.vertices, "co", 3).reshape(-1, 3).astype(np.float64)
    height = np.clip((co[:, 2] - CAP) / (1.0 - CAP), 0.0, 1.0)
    ridges = 1.0 + 0.5 * np.sin(8.0 * np.arctan2(co[:, 1], co[:, 0]))
    crown = co * (1.0 + 0.3 * height ** 2 * ridges)[:, None]
    ob.shape_key_add(name="Basis", from_mix=False)
    ob.shape_key_add(name="Crown", from_mix=False).data.foreach_set("co", crown.astype(np.float32).ravel())
    ob.shape_key_add(name="Still", from_mix=False)
    return ob


REPORTS = []  # every generate_lods report, for the panel's Last Run box


def lods(ob, source: str, measure: bool = True) -> dict:
    lod = extension_module("addon.lod")
    report = lod.generate_lods(bpy.context, ob, lod.LodSettings(
        ratios=(0.1, 0.05), importance_source=source, measure_deviation=measure))
    REPORTS.append(report)
    levels = []
    for entry in report["levels"]:
        lod_ob = bpy.data.objects[entry["name"]]
        co = array(lod_ob.data.vertices, "co", 3).reshape(-1, 3)
        keys = lod_ob.data.shape_keys
        levels.append({"entry": entry, "vertices": len(co), "cap_vertices": int(np.count_nonzero(co[:, 2] > CAP)),
                       "keys": [b.name for b in keys.key_blocks] if keys else []})
    return {"levels": levels, "warnings": report["warnings"]}


def errors(plain) -> dict:
    """Source Shape Keys on an object without keys: through the API, the operator, the
    bake's poll, and the command line's choice (a note, not a failure)."""
    lod = extension_module("addon.lod")
    out = {}
    try:
        lod.generate_lods(bpy.context, plain, lod.LodSettings(ratio=0.5, levels=1, importance_source='SHAPE_KEYS'))
        out["api"] = None
    except lod.LodError as ex:
        out["api"] = str(ex)
    select_only(plain)
    try:
        bpy.ops.object.line_quadric_lod(ratio=0.5, levels=1, importance_source='SHAPE_KEYS')
        out["operator"] = None
    except RuntimeError as ex:
        out["operator"] = str(ex)
    out["bake_poll"] = bpy.ops.object.line_quadric_lod_from_shape_keys.poll()
    out["lods_made"] = sorted(ob.name for ob in bpy.data.objects if ob.name.startswith("Plain_LOD"))
    return out


def choices(objects) -> list:
    sources = extension_module("addon.headless.sources")
    args = SimpleNamespace(importance_group=None, from_armature=None, from_shape_keys=True)
    return [list(c) for c in sources.importance_choice(objects, args)]


def bake(ob) -> dict:
    """Importance from Shape Keys: the group it writes against the function it uses."""
    importance = extension_module("addon.pure.importance")
    key_deviation = extension_module("addon.pure.key_deviation")
    mesh_io = extension_module("addon.mesh_io")
    vertex_groups = extension_module("addon.vertex_groups")
    select_only(ob)
    panel = bpy.context.scene.line_quadric_lod
    panel.importance_source = 'SHAPE_KEYS'
    poll = bpy.ops.object.line_quadric_lod_from_shape_keys.poll()
    result = sorted(bpy.ops.object.line_quadric_lod_from_shape_keys())
    written = vertex_groups.read_weights(ob.data, ["LOD_Importance"])[:, 0]
    _, use_relative, keys = mesh_io.read_shape_keys(ob.data)
    expected = importance.shape_key_importance(key_deviation.key_offsets(keys, use_relative))
    co = array(ob.data.vertices, "co", 3).reshape(-1, 3)
    return {"poll": poll, "result": result, "source": panel.importance_source, "group": panel.importance_group,
            "largest_difference": float(np.abs(written - expected).max()),
            "below_cap_max": float(written[co[:, 2] < CAP - 1e-6].max()), "top": float(written.max())}


def panel(ball, plain) -> dict:
    """What the panel draws (bench/figures/ui_recorder.py, as tests/scenarios/addon_monkey.py
    records it): {state: [[kind, property or operator, text], ...]}."""
    ui_recorder = importlib.import_module("bench.figures.ui_recorder")
    panel_cls = extension_module("addon.panel").VIEW3D_PT_line_quadric_lod
    settings = bpy.context.scene.line_quadric_lod
    settings.last_report = json.dumps([REPORTS[1]])  # the Source Shape Keys run
    out = {}
    for tag, ob, source in (("ball_none", ball, 'NONE'), ("ball_keys", ball, 'SHAPE_KEYS'),
                            ("plain_none", plain, 'NONE'), ("plain_keys", plain, 'SHAPE_KEYS')):
        select_only(ob)
        settings.importance_source = source
        root = ui_recorder.record_panel(panel_cls, bpy.context)
        out[tag] = [[it["kind"], it.get("prop") or it.get("idname"), it["text"]]
                    for it, _active, _enabled in ui_recorder.walk(root.to_dict())]
    settings.importance_source = 'NONE'
    return out


def pebble(scale: float):
    """A small sphere whose key "Crown" (the Ball's key name) shifts it by 0.01: a part the
    keys barely move."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=0.3, location=(0, 4, 0))
    ob = bpy.context.active_object
    ob.name = "Pebble"
    ob.scale = (scale, scale, scale)
    co = array(ob.data.vertices, "co", 3).reshape(-1, 3).astype(np.float64)
    ob.shape_key_add(name="Basis", from_mix=False)
    shifted = (co + [0.0, 0.0, 0.01]).astype(np.float32).ravel()
    ob.shape_key_add(name="Crown", from_mix=False).data.foreach_set("co", shifted)
    bpy.context.view_layer.update()
    return ob


def several(ball, plain) -> dict:
    """Source Shape Keys on several objects (one asset): a part without keys gets no
    importance and a note; none with keys is an error; the importance is the asset's."""
    lod = extension_module("addon.lod")
    job_mod = extension_module("addon.job")
    out = {}
    # None of them has keys: through the API and the operator (the panel's path).
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=1.0, location=(-4, 0, 0))
    plain2 = bpy.context.active_object
    plain2.name = "Plain2"
    settings = lod.LodSettings(ratios=(0.1,), importance_source='SHAPE_KEYS', measure_deviation=False)
    try:
        job_mod.LodJob(bpy.context, [plain, plain2], settings)
        out["none_api"] = None
    except lod.LodError as ex:
        out["none_api"] = str(ex)
    select_only(plain, plain2)
    try:
        bpy.ops.object.line_quadric_lod(ratio=0.1, levels=1, importance_source='SHAPE_KEYS', measure_deviation=False)
        out["none_operator"] = None
    except RuntimeError as ex:
        out["none_operator"] = str(ex)
    out["none_lods"] = sorted(ob.name for ob in bpy.data.objects if "_LOD" in ob.name and "Plain" in ob.name)
    # One keyed part, one without keys: through the operator, as the panel runs it.
    select_only(ball, plain)
    out["mixed_result"] = sorted(bpy.ops.object.line_quadric_lod(
        ratio=0.1, levels=1, importance_source='SHAPE_KEYS', measure_deviation=False))
    reports = {rep["object"]: rep for rep in json.loads(bpy.context.scene.line_quadric_lod.last_report)}
    out["mixed"] = {name: {"importance": [lv.get("importance") for lv in rep["levels"]],
                           "warnings": rep["warnings"], "triangles": [lv["triangles"] for lv in rep["levels"]],
                           "asset": bpy.data.objects[rep["levels"][0]["name"]].get("lqlod_asset")}
                    for name, rep in reports.items()}
    job = job_mod.LodJob(bpy.context, [ball, plain], settings)
    out["mixed_inputs"] = [None if i.importance is None else float(np.max(i.importance)) for i in job.inputs]
    # The asset's reference: a part the keys move by 0.01 (at scale 1 and 2) next to the
    # Ball's crown, and the same without it (each mesh its own reference).
    out["pebble"] = {}
    for scale in (1.0, 2.0):
        small = pebble(scale)
        for shared in (True, False):
            job_mod.ASSET_KEY_REFERENCE = shared
            try:
                job = job_mod.LodJob(bpy.context, [ball, small], settings)
            finally:
                job_mod.ASSET_KEY_REFERENCE = True
            g_ball, g_small = job.inputs[0].importance, job.inputs[1].importance
            quadric = job.inputs[1].core_options.quadric_scale
            out["pebble"][f"{scale:g} {'asset' if shared else 'mesh'}"] = {
                "ball_max": float(g_ball.max()), "max": float(g_small.max()), "min": float(g_small.min()),
                "quadric_max": float(np.max(quadric))}
        bpy.data.objects.remove(small)
    return out


def swelling(radius: float = 1.0, location=(0, -4, 0)):
    """An icosphere whose key "Swell" moves every vertex outwards, the top three times as
    far as the bottom: keys that leave no part of the surface still."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=radius, location=location)
    ob = bpy.context.active_object
    ob.name = "Swelling"
    co = array(ob.data.vertices, "co", 3).reshape(-1, 3).astype(np.float64)
    swell = co * (1.0 + 0.05 * (2.0 + co[:, 2] / radius))[:, None]
    ob.shape_key_add(name="Basis", from_mix=False)
    ob.shape_key_add(name="Swell", from_mix=False).data.foreach_set("co", swell.astype(np.float32).ravel())
    bpy.context.view_layer.update()
    return ob


def everywhere() -> dict:
    """Source Shape Keys where the keys move the whole surface: alone (the strength comes
    down to nothing, with a note: the LOD is the one without importance), beside a larger
    still part as one asset (the asset's still surface: full strength), and the preview."""
    lod = extension_module("addon.lod")
    job_mod = extension_module("addon.job")
    object_importance = extension_module("addon.object_importance")
    ob = swelling()
    out = {}
    for source in ('NONE', 'SHAPE_KEYS'):
        report = lod.generate_lods(bpy.context, ob, lod.LodSettings(
            ratios=(0.25,), importance_source=source, measure_deviation=False))
        lod_ob = bpy.data.objects[report["levels"][0]["name"]]
        out[source] = {"co": array(lod_ob.data.vertices, "co", 3).reshape(-1, 3).tolist(),
                       "warnings": report["warnings"]}
    effective, _, strength = object_importance.importance_preview(ob, lod.LodSettings(importance_source='SHAPE_KEYS'))
    out["preview"] = {"largest": float(np.max(effective)), "strength": strength}
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=3.0, location=(0, -12, 0))
    still = bpy.context.active_object
    still.name = "StillPart"
    job = job_mod.LodJob(bpy.context, [ob, still], lod.LodSettings(
        ratios=(0.25,), importance_source='SHAPE_KEYS', measure_deviation=False))
    out["asset"] = {"quadric_max": float(np.max(job.inputs[0].core_options.quadric_scale)),
                    "warnings": list(job.inputs[0].warnings)}
    for o in (ob, still):
        bpy.data.objects.remove(o)
    return out


def run() -> dict:
    remove_all_objects()
    ball = keyed_sphere()
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=1.0, location=(4, 0, 0))
    plain = bpy.context.active_object
    plain.name = "Plain"
    return {
        "input": {"triangles": len(ball.data.polygons), "vertices": len(ball.data.vertices),
                  "cap_vertices": int(np.count_nonzero(array(ball.data.vertices, "co", 3).reshape(-1, 3)[:, 2] > CAP))},
        "none": lods(ball, 'NONE'),
        "keys": lods(ball, 'SHAPE_KEYS'),
        "unmeasured": lods(ball, 'SHAPE_KEYS', measure=False),
        "errors": errors(plain),
        "choices": choices([ball, plain]),
        "panel": panel(ball, plain),
        "bake": bake(ball),
        "several": several(ball, plain),
        "everywhere": everywhere(),
    }
