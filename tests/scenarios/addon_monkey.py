"""The add-on on a subdivided monkey, step by step in one scene: the LOD chain, re-running,
cancelling, the vertex-group routes, bad inputs, the panel, Paint Importance, invoke and
the modal operator, undo (tests/test_addon_monkey.py checks what this returns).

The steps run in order and each starts from the scene the previous one left.
"""
import json
import types

import bpy
import numpy as np
from scene_tools import array, commit_after_cancel, diff, mesh_hash, extension_module, remove_all_objects, select_only

lod = extension_module("addon.lod")
job_mod = extension_module("addon.job")
LodCancelled = extension_module("addon.pure.settings").LodCancelled


def source_state(ob) -> dict:
    return {"mesh": mesh_hash(ob.data), "mods": [(m.name, m.type, m.show_viewport) for m in ob.modifiers],
            "matrix": [list(r) for r in ob.matrix_basis], "shape_index": ob.active_shape_key_index,
            "show_only": ob.show_only_shape_key, "groups": ob.vertex_groups.keys(),
            "keys": ob.data.shape_keys.key_blocks.keys() if ob.data.shape_keys else []}


def data_state() -> dict:
    return {name: sorted(x.name for x in getattr(bpy.data, name))
            for name in ("objects", "meshes", "collections", "node_groups", "shape_keys", "materials")}


def scene_state(src) -> dict:
    """What must not change when a run is cancelled: every data-block's name and the source."""
    return {**data_state(), **source_state(src)}


def monkey_lods() -> list:
    return sorted(o.name for o in bpy.data.objects if o.get("lod_source") == "Monkey")


def build_source(result: dict):
    """A subdivided monkey with two materials, UVs, colours, a group, a shape key, sharp edges and seams."""
    remove_all_objects()
    bpy.ops.mesh.primitive_monkey_add()
    src = bpy.context.active_object
    src.name = "Monkey"
    src.modifiers.new("Subdivision", 'SUBSURF').levels = 2
    for name in ("Skin", "Eyes"):
        src.data.materials.append(bpy.data.materials.new(name))
    n_poly = len(src.data.polygons)
    centers = array(src.data.polygons, "center", 3).reshape(-1, 3)
    src.data.polygons.foreach_set("material_index", (centers[:, 2] > 0.2).astype(np.int32))
    src.data.polygons.foreach_set("use_smooth", np.ones(n_poly, bool))
    edges_v = array(src.data.edges, "vertices", 2, np.int32).reshape(-1, 2)
    co = array(src.data.vertices, "co", 3).reshape(-1, 3)
    sharp = (co[edges_v[:, 0], 0] > 0.6) & (co[edges_v[:, 1], 0] > 0.6)  # the right ear's rim
    attr = src.data.attributes.new("sharp_edge", 'BOOLEAN', 'EDGE')
    attr.data.foreach_set("value", sharp)
    tint = src.data.color_attributes.new("Tint", 'BYTE_COLOR', 'CORNER')
    tint.data.foreach_set("color", np.tile([1.0, 0.5, 0.25, 1.0], len(src.data.loops)).astype(np.float32))
    heat = src.data.color_attributes.new("Heat", 'FLOAT_COLOR', 'POINT')
    heat.data.foreach_set("color", np.c_[np.clip(co[:, 2], 0, 1), np.zeros((len(co), 2)),
                                         np.ones(len(co))].astype(np.float32).ravel())
    group = src.vertex_groups.new(name="Top")
    group.add(np.flatnonzero(co[:, 2] > 0.3).tolist(), 0.75, 'REPLACE')
    src.shape_key_add(name="Basis")
    smile = src.shape_key_add(name="Smile")
    kco = co.copy()
    kco[:, 2] += 0.1
    smile.data.foreach_set("co", kco.ravel())
    smile.slider_max = 3.0
    smile.slider_min = 1.5
    smile.value = 1.7
    src["game_id"] = 42
    src.location = (1.0, 2.0, 3.0)
    src.rotation_euler = (0.1, 0.2, 0.3)
    result["sharp_input"] = int(sharp.sum())
    seam = (np.abs(co[edges_v[:, 0], 0]) < 1e-5) & (np.abs(co[edges_v[:, 1], 0]) < 1e-5)  # the mid line
    src.data.edges.foreach_set("use_seam", seam)
    result["seams_input"] = int(seam.sum())
    return src


def lod_info(o, src) -> dict:
    """What one LOD object carries over from the source."""
    me = o.data
    uv = array(me.uv_layers["UVMap"].uv, "vector", 2).reshape(-1, 2) if "UVMap" in me.uv_layers else None
    top = o.vertex_groups.get("Top")
    w = np.array([top.weight(i) if any(g.group == top.index for g in v.groups) else 0.0
                  for i, v in enumerate(me.vertices)]) if top else None
    sk = me.shape_keys.key_blocks if me.shape_keys else None
    sharp_attr = me.attributes.get("sharp_edge")
    co = array(me.vertices, "co", 3).reshape(-1, 3)
    seam = array(me.edges, "use_seam", 1, bool)
    edges_v = array(me.edges, "vertices", 2, np.int32).reshape(-1, 2)
    heat = array(me.color_attributes["Heat"].data, "color", 4).reshape(-1, 4) if "Heat" in me.color_attributes else None
    return {
        "triangles": len(me.polygons),
        "corner_counts": sorted(set(array(me.polygons, "loop_total", 1, np.int32).tolist())),
        "materials": [m.name for m in me.materials],
        "material_indices": sorted(set(array(me.polygons, "material_index", 1, np.int32).tolist())),
        "uv_maps": me.uv_layers.keys(),
        "uv_range": [float(uv.min()), float(uv.max())] if uv is not None else None,
        "colors": [(c.name, c.domain, c.data_type) for c in me.color_attributes],
        "color_mean": (array(me.color_attributes["Tint"].data, "color", 4).reshape(-1, 4).mean(0).tolist()
                       if "Tint" in me.color_attributes else None),
        "groups": o.vertex_groups.keys(),
        "top_weights": sorted(set(np.round(w, 3).tolist())) if w is not None else None,
        "shape_keys": sk.keys() if sk else [],
        "smile_value": [sk["Smile"].value, sk["Smile"].slider_min, sk["Smile"].slider_max]
        if sk and "Smile" in sk else None,
        "smile_offset": float(np.median(array(sk["Smile"].data, "co", 3).reshape(-1, 3)[:, 2] - co[:, 2]))
        if sk else None,
        "game_id": o.get("game_id"),
        "lod_level": o.get("lod_level"),
        "matrix_same": bool(np.allclose(np.array(o.matrix_world), np.array(src.matrix_world))),
        "flat_faces": int(np.count_nonzero(~array(me.polygons, "use_smooth", 1, bool))),
        "sharp_edges": int(array(sharp_attr.data, "value", 1, bool).sum()) if sharp_attr else 0,
        "seam_edges": int(seam.sum()),
        "seam_x": float(np.abs(co[edges_v[seam], 0]).max()) if seam.any() else None,
        "heat_range": [float(heat[:, 0].min()), float(heat[:, 0].max()), float(np.abs(heat[:, 1:3]).max())]
        if heat is not None else None,
        "in_collection": [c.name for c in o.users_collection],
        "modifiers": [m.type for m in o.modifiers],
    }


def generate_through_the_operator(src, result: dict) -> None:
    """1. Generate through the operator, as a script would."""
    before = source_state(src)
    select_only(src)
    outcome = bpy.ops.object.line_quadric_lod(ratio=0.5, levels=3, level_factor=0.5)
    scene = bpy.context.scene
    result["op_result"] = sorted(outcome)
    result["report"] = json.loads(scene.line_quadric_lod.last_report)
    coll = bpy.data.collections.get("Monkey_LODs")
    result["collection_objects"] = sorted(o.name for o in coll.objects) if coll else None
    result["collection_in_scene"] = coll is not None and coll.name in [
        c.name for c in scene.collection.children_recursive]
    result["lods"] = [lod_info(o, src) if o is not None else None
                      for o in (bpy.data.objects.get(f"Monkey_LOD{k}") for k in (1, 2, 3))]
    result["source_diff"] = diff(before, source_state(src))


def rerun_replaces(src, result: dict) -> None:
    """2. Re-running replaces the previous LODs of that source; 2b. with the source and its
    LODs selected together, the LODs are skipped, then replaced."""
    select_only(src)
    bpy.ops.object.line_quadric_lod(ratio=0.3, levels=2, level_factor=0.5)
    result["rerun_objects"] = monkey_lods()
    result["rerun_meshes"] = sorted(m.name for m in bpy.data.meshes if m.name.startswith("Monkey_LOD"))
    result["rerun_triangles"] = [len(bpy.data.objects[f"Monkey_LOD{k}"].data.polygons) for k in (1, 2)]
    report = json.loads(bpy.context.scene.line_quadric_lod.last_report)
    result["rerun_report_targets"] = [lv["target"] for lv in report[0]["levels"]]

    select_only(src, *[o for o in bpy.data.objects if o.get("lod_source") == "Monkey"])
    outcome = bpy.ops.object.line_quadric_lod(ratio=0.3, levels=2, level_factor=0.5, measure_deviation=False)
    report = json.loads(bpy.context.scene.line_quadric_lod.last_report)
    result["with_lods_selected"] = [sorted(outcome), [rep["object"] for rep in report], monkey_lods()]


def cancel(src, result: dict) -> None:
    """3. Cancel: through the progress callback, and through a threaded job."""
    before = scene_state(src)
    calls = []

    def stop_after_two(fraction):
        calls.append(fraction)
        return len(calls) < 2

    try:
        lod.generate_lods(bpy.context, src, lod.LodSettings(ratio=0.2), progress=stop_after_two)
        result["cancel_raised"] = False
    except LodCancelled:
        result["cancel_raised"] = True
    result["cancel_calls"] = len(calls)
    result["cancel_changes"] = diff(before, scene_state(src))

    job = job_mod.LodJob(bpy.context, [src], lod.LodSettings(ratio=0.2))
    result["job_cancel_raised"] = commit_after_cancel(job, LodCancelled, 60)
    result["job_cancel_changes"] = diff(before, scene_state(src))

    job = job_mod.LodJob(bpy.context, [src], lod.LodSettings(ratio=0.2, levels=1))
    job.start()
    job.wait(120)
    reports = job.commit(bpy.context)
    result["job_threaded_triangles"] = [lv["triangles"] for lv in reports[0]["levels"]]
    result["job_threaded_objects"] = monkey_lods()


def vertex_group_routes(src, result: dict) -> None:
    """4. Vertex-group routes agree (fast C-side and per-vertex fallback)."""
    vgroups = extension_module("addon.vertex_groups")
    names = vgroups.group_names(src.data)
    fast = vgroups.read_weights(src.data, names, method="nodes")
    slow = vgroups.read_weights(src.data, names, method="python")
    result["vg_read_shapes"] = [list(fast.shape), list(slow.shape), [len(src.data.vertices), len(names)]]
    result["vg_read_max_difference"] = float(np.abs(fast - slow).max()) if fast.shape == slow.shape else None
    tmp_a = bpy.data.objects.new("tmp_a", src.data.copy())
    tmp_b = bpy.data.objects.new("tmp_b", src.data.copy())
    for t in (tmp_a, tmp_b):
        bpy.data.batch_remove([t.data.shape_keys])
        for g in list(t.vertex_groups):
            t.vertex_groups.remove(g)
    n = len(src.data.vertices)
    W = np.random.default_rng(1).random((n, 2)) * (np.random.default_rng(2).random((n, 2)) > 0.5)
    vgroups.write_weights(tmp_a, ["position", "g2"], W, method="convert")
    vgroups.write_weights(tmp_b, ["position", "g2"], W, method="add")
    ra = vgroups.read_weights(tmp_a.data, ["position", "g2"], method="python")
    rb = vgroups.read_weights(tmp_b.data, ["position", "g2"], method="python")
    result["vg_write_names"] = tmp_a.vertex_groups.keys()
    result["vg_write_err"] = float(max(np.abs(ra - W).max(), np.abs(rb - W).max()))
    result["vg_write_members"] = [int(sum(len(v.groups) for v in t.data.vertices)) for t in (tmp_a, tmp_b)]
    result["vg_nonzero"] = int(np.count_nonzero(W))
    for t in (tmp_a, tmp_b):
        me = t.data
        bpy.data.objects.remove(t)
        bpy.data.meshes.remove(me)


def operator_error(**kwargs):
    """The operator's error message, or None when it ran."""
    try:
        bpy.ops.object.line_quadric_lod(**kwargs)
    except RuntimeError as ex:
        return str(ex)
    return None


def bad_inputs(src, result: dict) -> None:
    """5. Bad inputs: a clear report each, no traceback, nothing changed."""
    scene = bpy.context.scene
    before = data_state()
    errors = {}
    select_only()
    errors["no_mesh_selected"] = operator_error()
    select_only(bpy.data.objects["Monkey_LOD1"])
    errors["only_lods_selected"] = operator_error()
    empty = bpy.data.objects.new("Empty Mesh", bpy.data.meshes.new("empty"))
    scene.collection.objects.link(empty)
    select_only(empty)
    errors["empty_mesh"] = operator_error()
    edges_only = bpy.data.meshes.new("edges_only")
    edges_only.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0)], [(0, 1), (1, 2)], [])
    wire = bpy.data.objects.new("Wire", edges_only)
    scene.collection.objects.link(wire)
    select_only(wire)
    errors["no_faces"] = operator_error()
    select_only(src)
    errors["missing_group"] = operator_error(importance_source='VERTEX_GROUP', importance_group="Nope")
    errors["not_skinned"] = operator_error(importance_source='ARMATURE')
    arm_data = bpy.data.armatures.new("Rig")
    arm = bpy.data.objects.new("Rig", arm_data)
    scene.collection.objects.link(arm)
    select_only(arm)
    bpy.ops.object.mode_set(mode='EDIT')
    bone = arm_data.edit_bones.new("Bone")
    bone.head, bone.tail, bone.use_deform = (0, 0, 0), (0, 0, 1), False
    bpy.ops.object.mode_set(mode='OBJECT')
    src.modifiers.new("Armature", 'ARMATURE').object = arm
    select_only(src)
    errors["no_deform_bones"] = operator_error(importance_source='ARMATURE')
    try:
        bpy.ops.object.line_quadric_lod_from_armature()
        errors["from_armature_no_deform"] = None
    except RuntimeError as ex:
        errors["from_armature_no_deform"] = str(ex)
    src.modifiers.remove(src.modifiers["Armature"])
    errors["target_not_smaller"] = operator_error(ratio=1.0)
    errors["too_many_levels"] = operator_error(target_triangles=4, levels=4, level_factor=0.5)
    bpy.ops.object.mode_set(mode='EDIT')
    errors["edit_mode"] = operator_error()
    try:
        lod.generate_lods(bpy.context, src, lod.LodSettings())
        errors["edit_mode_api"] = None
    except lod.LodError as ex:
        errors["edit_mode_api"] = "Error: " + str(ex)
    bpy.ops.object.mode_set(mode='OBJECT')
    result["errors"] = errors
    for o in (empty, wire, arm):
        data = o.data
        bpy.data.objects.remove(o)
        (bpy.data.meshes if data.__class__.__name__ == "Mesh" else bpy.data.armatures).remove(data)
    result["errors_diff"] = diff(before, data_state())


def panel_draws(src, result: dict) -> None:
    """6. The panel draws for every state, referencing only real properties and operators.
    bench/figures/ui_recorder.py stands in for UILayout (bench/figures/fig_panel.py draws the same
    recording as the docs' picture of the panel): it raises on an unknown property or operator."""
    import importlib

    ui_recorder = importlib.import_module("bench.figures.ui_recorder")
    panel_cls = extension_module("addon.panel").VIEW3D_PT_line_quadric_lod
    settings = bpy.context.scene.line_quadric_lod
    draws, draw_settings, draw_items = {}, {}, {}

    def draw(tag):
        root = ui_recorder.record_panel(panel_cls, bpy.context)
        draws[tag] = root.log
        draw_items[tag] = [[it["kind"], it.get("prop") or it.get("idname"), it["text"], it.get("display"), active]
                           for it, active, _enabled in ui_recorder.walk(root.to_dict())]
        draw_settings[tag] = {name: getattr(settings, name) for name in lod.LodSettings.names()}

    select_only()
    bpy.context.view_layer.objects.active = None
    draw("no_object")
    select_only(src)
    for source in ('NONE', 'VERTEX_GROUP', 'ARMATURE'):
        settings.importance_source = source
        settings.importance_group = "Top" if source == 'VERTEX_GROUP' else ""
        draw(source)
    settings.importance_source = 'VERTEX_GROUP'
    settings.importance_group = "Missing"
    draw("missing_group")
    settings.importance_source = 'NONE'
    settings.target_triangles = 20000
    settings.preserve_seams = False
    draw("greyed")
    settings.target_triangles = 0
    settings.preserve_seams = True
    for by in ('DEVIATION', 'SCREEN'):
        settings.target_by = by
        draw(f"by_{by.lower()}")
    settings.target_by = 'COUNT'
    result["draw_items"] = draw_items
    result["draws"] = draws
    result["draw_settings"] = draw_settings
    result["panel_registered"] = hasattr(bpy.types, "VIEW3D_PT_line_quadric_lod")
    result["panel_category"] = panel_cls.bl_category


def paint_importance(src, result: dict) -> None:
    """7. Paint Importance, twice: the second run reuses the group."""
    settings = bpy.context.scene.line_quadric_lod
    select_only(src)
    outcome = bpy.ops.object.line_quadric_lod_paint()
    result["paint"] = {"result": sorted(outcome), "mode": src.mode, "active_group": src.vertex_groups.active.name,
                       "source": settings.importance_source, "group": settings.importance_group}
    bpy.ops.object.mode_set(mode='OBJECT')
    bpy.ops.object.line_quadric_lod_paint()
    result["paint_groups"] = [g.name for g in src.vertex_groups]
    bpy.ops.object.mode_set(mode='OBJECT')


def invoke_takes_panel_settings(result: dict) -> None:
    """7b. Started from the panel or F3, invoke takes the panel's settings for every
    property the caller did not set. (The bpy module never calls invoke, even for
    'INVOKE_DEFAULT', so it is called directly with a stand-in operator.)"""
    settings = bpy.context.scene.line_quadric_lod
    settings.levels = 2
    settings.ratio = 0.2
    settings.importance_strength = 0.3
    fake = types.SimpleNamespace(**{n: getattr(lod.LodSettings(), n) for n in lod.LodSettings.names()})
    fake.properties = types.SimpleNamespace(is_property_set=lambda name: name == "levels")
    fake.levels = 1
    fake.execute = lambda context: {"EXECUTED"}
    result["invoke_result"] = sorted(bpy.types.OBJECT_OT_line_quadric_lod.invoke(fake, bpy.context, None))
    result["invoke_settings"] = [fake.levels, fake.ratio, fake.importance_strength]
    settings.levels = 3
    settings.ratio = 0.5
    settings.importance_strength = 1.0


def modal_events(src, result: dict) -> None:
    """7c. The modal operator's event handling, driven with stand-in events: Esc cancels a
    running job and changes nothing; a timer tick after the job is done commits it."""
    op_cls = bpy.types.OBJECT_OT_line_quadric_lod

    def fake_operator(job):
        ns = types.SimpleNamespace(_job=job, _timer=None, messages=[])
        ns.report = lambda kind, text: ns.messages.append((sorted(kind), text))
        for name in ("_end_modal", "_commit", "_unexpected"):
            setattr(ns, name, types.MethodType(getattr(op_cls, name), ns))
        return ns

    def event(kind, value='NOTHING'):
        return types.SimpleNamespace(type=kind, value=value)

    before = scene_state(src)
    ns = fake_operator(job_mod.LodJob(bpy.context, [src], lod.LodSettings(ratio=0.1, levels=3)))
    ns._job.start()
    result["modal_running"] = sorted(op_cls.modal(ns, bpy.context, event('A', 'PRESS')))
    result["modal_navigation"] = sorted(op_cls.modal(ns, bpy.context, event('WHEELUPMOUSE', 'PRESS')))
    result["modal_esc"] = sorted(op_cls.modal(ns, bpy.context, event('ESC', 'PRESS')))
    result["modal_esc_messages"] = ns.messages
    result["modal_esc_changes"] = diff(before, scene_state(src))
    ns = fake_operator(job_mod.LodJob(bpy.context, [src], lod.LodSettings(ratio=0.1, levels=1)))
    ns._job.start()
    ns._job.wait(120)
    result["modal_timer"] = sorted(op_cls.modal(ns, bpy.context, event('TIMER')))
    result["modal_timer_objects"] = monkey_lods()


def undo_is_one_step(src, result: dict) -> None:
    """8. Undo: one step per run."""
    bpy.context.scene.line_quadric_lod.importance_source = 'NONE'
    select_only(src)
    bpy.ops.ed.undo_push(message="before LODs")
    before = data_state()
    # The positional True asks bpy.ops for the undo push the UI makes after an operator
    # with 'UNDO' in bl_options (scripts get none by default).
    result["undo_flag"] = "UNDO" in bpy.types.OBJECT_OT_line_quadric_lod.bl_options
    bpy.ops.object.line_quadric_lod('EXEC_DEFAULT', True, ratio=0.25, levels=3, level_factor=0.5)
    result["undo_after_run"] = monkey_lods()
    bpy.ops.ed.undo()
    result["undo_changes"] = diff(before, data_state())
    result["undo_after_undo"] = monkey_lods()
    bpy.ops.ed.redo()
    result["redo_objects"] = monkey_lods()


def run() -> dict:
    result = {}
    src = build_source(result)
    generate_through_the_operator(src, result)
    rerun_replaces(src, result)
    cancel(src, result)
    vertex_group_routes(src, result)
    bad_inputs(src, result)
    panel_draws(src, result)
    paint_importance(src, result)
    invoke_takes_panel_settings(result)
    modal_events(src, result)
    undo_is_one_step(src, result)
    return result
