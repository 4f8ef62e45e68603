"""The add-on in real Blender (bpy module, built extension installed and enabled):
a subdivided monkey's LOD chain, replacement on re-run, cancel, undo, bad inputs and the
panel. One Blender child runs every scenario of this file (module fixture); the tests
then check its RESULT."""
import pytest

from bpy_harness import run_in_blender

SNIPPET = r'''
import hashlib, importlib, json, types
import numpy as np

lod = importlib.import_module(EXT + ".addon.lod")
job_mod = importlib.import_module(EXT + ".addon.job")
vgroups = importlib.import_module(EXT + ".addon.vertex_groups")
panel_mod = importlib.import_module(EXT + ".addon.panel")
R = RESULT

for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
scene = bpy.context.scene

def arr(coll, prop, width, dtype=np.float32):
    a = np.empty(len(coll) * width, dtype=dtype)
    coll.foreach_get(prop, a)
    return a

def mesh_hash(me):
    h = hashlib.sha256()
    for coll, prop, w, dt in ((me.vertices, "co", 3, np.float32), (me.loops, "vertex_index", 1, np.int32),
                              (me.polygons, "material_index", 1, np.int32)):
        h.update(arr(coll, prop, w, dt).tobytes())
    return h.hexdigest()

def source_state(ob):
    return {"mesh": mesh_hash(ob.data), "mods": [(m.name, m.type, m.show_viewport) for m in ob.modifiers],
            "matrix": [list(r) for r in ob.matrix_basis], "shape_index": ob.active_shape_key_index,
            "show_only": ob.show_only_shape_key, "groups": ob.vertex_groups.keys(),
            "keys": ob.data.shape_keys.key_blocks.keys() if ob.data.shape_keys else []}

def data_state():
    return {name: sorted(x.name for x in getattr(bpy.data, name))
            for name in ("objects", "meshes", "collections", "node_groups", "shape_keys", "materials")}

def diff(a, b):
    return {k: [a.get(k), b.get(k)] for k in set(a) | set(b) if a.get(k) != b.get(k)}

def select_only(*obs):
    for o in bpy.context.selected_objects:
        o.select_set(False)
    for o in obs:
        o.select_set(True)
    if obs:
        bpy.context.view_layer.objects.active = obs[0]

# --- the source: subdivided monkey, two materials, UVs, colours, a group, a shape key, sharp edges
bpy.ops.mesh.primitive_monkey_add()
src = bpy.context.active_object
src.name = "Monkey"
src.modifiers.new("Subdivision", 'SUBSURF').levels = 2
for name in ("Skin", "Eyes"):
    src.data.materials.append(bpy.data.materials.new(name))
n_poly = len(src.data.polygons)
centers = arr(src.data.polygons, "center", 3).reshape(-1, 3)
src.data.polygons.foreach_set("material_index", (centers[:, 2] > 0.2).astype(np.int32))
src.data.polygons.foreach_set("use_smooth", np.ones(n_poly, bool))
edges_v = arr(src.data.edges, "vertices", 2, np.int32).reshape(-1, 2)
co = arr(src.data.vertices, "co", 3).reshape(-1, 3)
sharp = (co[edges_v[:, 0], 0] > 0.6) & (co[edges_v[:, 1], 0] > 0.6)  # the right ear's rim
attr = src.data.attributes.new("sharp_edge", 'BOOLEAN', 'EDGE')
attr.data.foreach_set("value", sharp)
col = src.data.color_attributes.new("Tint", 'BYTE_COLOR', 'CORNER')
col.data.foreach_set("color", np.tile([1.0, 0.5, 0.25, 1.0], len(src.data.loops)).astype(np.float32))
heat = src.data.color_attributes.new("Heat", 'FLOAT_COLOR', 'POINT')
heat.data.foreach_set("color", np.c_[np.clip(co[:, 2], 0, 1), np.zeros((len(co), 2)), np.ones(len(co))].astype(np.float32).ravel())
group = src.vertex_groups.new(name="Top")
group.add(np.flatnonzero(co[:, 2] > 0.3).tolist(), 0.75, 'REPLACE')
src.shape_key_add(name="Basis")
smile = src.shape_key_add(name="Smile")
kco = co.copy(); kco[:, 2] += 0.1
smile.data.foreach_set("co", kco.ravel())
smile.slider_max = 3.0
smile.slider_min = 1.5
smile.value = 1.7
src["game_id"] = 42
src.location = (1.0, 2.0, 3.0)
src.rotation_euler = (0.1, 0.2, 0.3)
R["sharp_input"] = int(sharp.sum())
seam = (np.abs(co[edges_v[:, 0], 0]) < 1e-5) & (np.abs(co[edges_v[:, 1], 0]) < 1e-5)  # the mid line
src.data.edges.foreach_set("use_seam", seam)
R["seams_input"] = int(seam.sum())

before_source = source_state(src)
before_data = data_state()
select_only(src)

# --- 1. Generate through the operator, as a script would
r = bpy.ops.object.line_quadric_lod(ratio=0.5, levels=3, level_factor=0.5)
R["op_result"] = sorted(r)
R["report"] = json.loads(scene.line_quadric_lod.last_report)
coll = bpy.data.collections.get("Monkey_LODs")
R["collection_objects"] = sorted(o.name for o in coll.objects) if coll else None
R["collection_in_scene"] = coll is not None and coll.name in [c.name for c in scene.collection.children_recursive]
lods = []
for k in (1, 2, 3):
    o = bpy.data.objects.get(f"Monkey_LOD{k}")
    if o is None:
        lods.append(None)
        continue
    me = o.data
    uv = arr(me.uv_layers["UVMap"].uv, "vector", 2).reshape(-1, 2) if "UVMap" in me.uv_layers else None
    w = np.array([o.vertex_groups["Top"].weight(i) if any(g.group == o.vertex_groups["Top"].index for g in v.groups) else 0.0
                  for i, v in enumerate(me.vertices)]) if "Top" in o.vertex_groups else None
    sk = me.shape_keys.key_blocks if me.shape_keys else None
    sharp_attr = me.attributes.get("sharp_edge")
    lods.append({
        "triangles": len(me.polygons),
        "all_triangles": bool(np.all(arr(me.polygons, "loop_total", 1, np.int32) == 3)),
        "materials": [m.name for m in me.materials],
        "material_indices": sorted(set(arr(me.polygons, "material_index", 1, np.int32).tolist())),
        "uv_maps": me.uv_layers.keys(),
        "uv_range": [float(uv.min()), float(uv.max())] if uv is not None else None,
        "colors": [(c.name, c.domain, c.data_type) for c in me.color_attributes],
        "color_mean": arr(me.color_attributes["Tint"].data, "color", 4).reshape(-1, 4).mean(0).tolist() if "Tint" in me.color_attributes else None,
        "groups": o.vertex_groups.keys(),
        "top_weights": sorted(set(np.round(w, 3).tolist())) if w is not None else None,
        "shape_keys": sk.keys() if sk else [],
        "smile_value": [sk["Smile"].value, sk["Smile"].slider_min, sk["Smile"].slider_max] if sk and "Smile" in sk else None,
        "smile_offset": float(np.median(arr(sk["Smile"].data, "co", 3).reshape(-1, 3)[:, 2] - arr(me.vertices, "co", 3).reshape(-1, 3)[:, 2])) if sk else None,
        "game_id": o.get("game_id"),
        "lod_level": o.get("lod_level"),
        "matrix_same": bool(np.allclose(np.array(o.matrix_world), np.array(src.matrix_world))),
        "smooth": bool(arr(me.polygons, "use_smooth", 1, bool).all()),
        "sharp_edges": int(arr(sharp_attr.data, "value", 1, bool).sum()) if sharp_attr else 0,
        "seam_edges": int(arr(me.edges, "use_seam", 1, bool).sum()),
        "seam_x": float(np.abs(arr(me.vertices, "co", 3).reshape(-1, 3)[arr(me.edges, "vertices", 2, np.int32).reshape(-1, 2)[arr(me.edges, "use_seam", 1, bool)], 0]).max()) if arr(me.edges, "use_seam", 1, bool).any() else None,
        "heat_range": [float(x) for x in (lambda h: (h[:, 0].min(), h[:, 0].max(), np.abs(h[:, 1:3]).max()))(
            arr(me.color_attributes["Heat"].data, "color", 4).reshape(-1, 4))] if "Heat" in me.color_attributes else None,
        "in_collection": [c.name for c in o.users_collection],
        "modifiers": [m.type for m in o.modifiers],
    })
R["lods"] = lods
R["source_diff"] = diff(before_source, source_state(src))

# --- 2. Re-running replaces the previous LODs of that source
select_only(src)
bpy.ops.object.line_quadric_lod(ratio=0.3, levels=2, level_factor=0.5)
R["rerun_objects"] = sorted(o.name for o in bpy.data.objects if o.get("lod_source") == "Monkey")
R["rerun_meshes"] = sorted(m.name for m in bpy.data.meshes if m.name.startswith("Monkey_LOD"))
R["rerun_triangles"] = [len(bpy.data.objects[f"Monkey_LOD{k}"].data.polygons) for k in (1, 2)]
R["rerun_report_targets"] = [lv["target"] for lv in json.loads(scene.line_quadric_lod.last_report)[0]["levels"]]

# --- 2b. Source and its LODs selected together: the LODs are skipped, then replaced
select_only(src, *[o for o in bpy.data.objects if o.get("lod_source") == "Monkey"])
r = bpy.ops.object.line_quadric_lod(ratio=0.3, levels=2, level_factor=0.5, measure_deviation=False)
R["with_lods_selected"] = [sorted(r), [rep["object"] for rep in json.loads(scene.line_quadric_lod.last_report)],
                           sorted(o.name for o in bpy.data.objects if o.get("lod_source") == "Monkey")]

# --- 3. Cancel: through the progress callback, and through a threaded job
state = data_state(); srcst = source_state(src)
calls = []
def stop_after_two(fraction):
    calls.append(fraction)
    return len(calls) < 2
try:
    lod.generate_lods(bpy.context, src, lod.LodSettings(ratio=0.2), progress=stop_after_two)
    R["cancel_raised"] = False
except lod.LodCancelled:
    R["cancel_raised"] = True
R["cancel_calls"] = len(calls)
R["cancel_unchanged"] = data_state() == state and source_state(src) == srcst

job = job_mod.LodJob(bpy.context, [src], lod.LodSettings(ratio=0.2))
job.start(); job.cancel(); job.wait(60)
try:
    job.commit(bpy.context)
    R["job_cancel_raised"] = False
except lod.LodCancelled:
    R["job_cancel_raised"] = True
R["job_cancel_unchanged"] = data_state() == state and source_state(src) == srcst

job = job_mod.LodJob(bpy.context, [src], lod.LodSettings(ratio=0.2, levels=1))
job.start(); job.wait(120)
reports = job.commit(bpy.context)
R["job_threaded_triangles"] = [lv["triangles"] for lv in reports[0]["levels"]]
R["job_threaded_objects"] = sorted(o.name for o in bpy.data.objects if o.get("lod_source") == "Monkey")

# --- 4. Vertex-group routes agree (fast C-side and per-vertex fallback)
names = vgroups.group_names(src.data)
fast = vgroups.read_weights(src.data, names, method="nodes")
slow = vgroups.read_weights(src.data, names, method="python")
R["vg_read_same"] = bool(np.array_equal(fast, slow)) and fast.shape == (len(src.data.vertices), len(names))
tmp_a = bpy.data.objects.new("tmp_a", src.data.copy()); tmp_b = bpy.data.objects.new("tmp_b", src.data.copy())
for t in (tmp_a, tmp_b):
    bpy.data.batch_remove([t.data.shape_keys])
    for g in list(t.vertex_groups):
        t.vertex_groups.remove(g)
W = np.random.default_rng(1).random((len(src.data.vertices), 2)) * (np.random.default_rng(2).random((len(src.data.vertices), 2)) > 0.5)
vgroups.write_weights(tmp_a, ["position", "g2"], W, method="convert")
vgroups.write_weights(tmp_b, ["position", "g2"], W, method="add")
ra = vgroups.read_weights(tmp_a.data, ["position", "g2"], method="python")
rb = vgroups.read_weights(tmp_b.data, ["position", "g2"], method="python")
R["vg_write_names"] = tmp_a.vertex_groups.keys()
R["vg_write_err"] = float(max(np.abs(ra - W).max(), np.abs(rb - W).max()))
R["vg_write_members"] = [int(sum(len(v.groups) for v in t.data.vertices)) for t in (tmp_a, tmp_b)]
R["vg_nonzero"] = int(np.count_nonzero(W))
for t in (tmp_a, tmp_b):
    me = t.data; bpy.data.objects.remove(t); bpy.data.meshes.remove(me)

# --- 5. Bad inputs: a clear report each, no traceback, nothing changed
def op_error(**kw):
    try:
        bpy.ops.object.line_quadric_lod(**kw)
    except RuntimeError as ex:
        return str(ex)
    return None

state = data_state()
errors = {}
select_only()
errors["no_mesh_selected"] = op_error()
select_only(bpy.data.objects["Monkey_LOD1"])
errors["only_lods_selected"] = op_error()
empty = bpy.data.objects.new("Empty Mesh", bpy.data.meshes.new("empty"))
scene.collection.objects.link(empty)
select_only(empty)
errors["empty_mesh"] = op_error()
edges_only = bpy.data.meshes.new("edges_only")
edges_only.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0)], [(0, 1), (1, 2)], [])
wire = bpy.data.objects.new("Wire", edges_only)
scene.collection.objects.link(wire)
select_only(wire)
errors["no_faces"] = op_error()
select_only(src)
errors["missing_group"] = op_error(importance_source='VERTEX_GROUP', importance_group="Nope")
errors["not_skinned"] = op_error(importance_source='ARMATURE')
arm_data = bpy.data.armatures.new("Rig")
arm = bpy.data.objects.new("Rig", arm_data)
scene.collection.objects.link(arm)
select_only(arm)
bpy.ops.object.mode_set(mode='EDIT')
b = arm_data.edit_bones.new("Bone"); b.head = (0, 0, 0); b.tail = (0, 0, 1); b.use_deform = False
bpy.ops.object.mode_set(mode='OBJECT')
src.modifiers.new("Armature", 'ARMATURE').object = arm
select_only(src)
errors["no_deform_bones"] = op_error(importance_source='ARMATURE')
try:
    bpy.ops.object.line_quadric_lod_from_armature()
    errors["from_armature_no_deform"] = None
except RuntimeError as ex:
    errors["from_armature_no_deform"] = str(ex)
src.modifiers.remove(src.modifiers["Armature"])
errors["target_not_smaller"] = op_error(ratio=1.0)
errors["too_many_levels"] = op_error(target_triangles=4, levels=4, level_factor=0.5)
bpy.ops.object.mode_set(mode='EDIT')
errors["edit_mode"] = op_error()
try:
    lod.generate_lods(bpy.context, src, lod.LodSettings())
    errors["edit_mode_api"] = None
except lod.LodError as ex:
    errors["edit_mode_api"] = "Error: " + str(ex)
bpy.ops.object.mode_set(mode='OBJECT')
R["errors"] = errors
for o in (empty, wire, arm):
    d = o.data; bpy.data.objects.remove(o)
    (bpy.data.meshes if d.__class__.__name__ == "Mesh" else bpy.data.armatures).remove(d)
R["errors_diff"] = diff(state, data_state())

# --- 6. The panel draws for every state, referencing only real properties and operators.
# bench/ui_recorder.py stands in for UILayout (bench/fig_panel.py draws the same recording
# as the docs' picture of the panel): it raises on an unknown property or operator.
ui_recorder = importlib.import_module("bench.ui_recorder")
panel_cls = panel_mod.VIEW3D_PT_line_quadric_lod
settings = scene.line_quadric_lod
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
settings.importance_source = 'VERTEX_GROUP'; settings.importance_group = "Missing"
draw("missing_group")
settings.importance_source = 'NONE'
settings.target_triangles = 20000; settings.preserve_seams = False
draw("greyed")
settings.target_triangles = 0; settings.preserve_seams = True
R["draw_items"] = draw_items
R["draws"] = draws
R["draw_settings"] = draw_settings
R["panel_registered"] = hasattr(bpy.types, "VIEW3D_PT_line_quadric_lod")
R["panel_category"] = panel_cls.bl_category

# --- 7. Paint Importance
select_only(src)
r = bpy.ops.object.line_quadric_lod_paint()
R["paint"] = {"result": sorted(r), "mode": src.mode, "active_group": src.vertex_groups.active.name,
              "source": settings.importance_source, "group": settings.importance_group}
bpy.ops.object.mode_set(mode='OBJECT')
r = bpy.ops.object.line_quadric_lod_paint()  # reuses the group
R["paint_groups"] = [g.name for g in src.vertex_groups]
bpy.ops.object.mode_set(mode='OBJECT')

# --- 7b. Started from the panel or F3, invoke takes the panel's settings for every
# property the caller did not set. (The bpy module never calls invoke, even for
# 'INVOKE_DEFAULT', so it is called directly with a stand-in operator.)
settings.levels = 2; settings.ratio = 0.2; settings.importance_strength = 0.3
fake = types.SimpleNamespace(**{n: getattr(lod.LodSettings(), n) for n in lod.LodSettings.names()})
fake.properties = types.SimpleNamespace(is_property_set=lambda name: name == "levels")
fake.levels = 1
fake.execute = lambda context: {"EXECUTED"}
R["invoke_result"] = sorted(bpy.types.OBJECT_OT_line_quadric_lod.invoke(fake, bpy.context, None))
R["invoke_settings"] = [fake.levels, fake.ratio, fake.importance_strength]
settings.levels = 3; settings.ratio = 0.5; settings.importance_strength = 1.0

# --- 7c. The modal operator's event handling, driven with stand-in events: Esc cancels a
# running job and changes nothing; a timer tick after the job is done commits it.
op_cls = bpy.types.OBJECT_OT_line_quadric_lod
def fake_operator(job):
    ns = types.SimpleNamespace(_job=job, _timer=None, messages=[])
    ns.report = lambda kind, text: ns.messages.append((sorted(kind), text))
    for name in ("_end_modal", "_commit", "_unexpected"):
        setattr(ns, name, types.MethodType(getattr(op_cls, name), ns))
    return ns
def event(kind, value='NOTHING'):
    return types.SimpleNamespace(type=kind, value=value)
state = data_state(); srcst = source_state(src)
ns = fake_operator(job_mod.LodJob(bpy.context, [src], lod.LodSettings(ratio=0.1, levels=3)))
ns._job.start()
R["modal_running"] = sorted(op_cls.modal(ns, bpy.context, event('A', 'PRESS')))
R["modal_navigation"] = sorted(op_cls.modal(ns, bpy.context, event('WHEELUPMOUSE', 'PRESS')))
R["modal_esc"] = sorted(op_cls.modal(ns, bpy.context, event('ESC', 'PRESS')))
R["modal_esc_messages"] = ns.messages
R["modal_esc_unchanged"] = data_state() == state and source_state(src) == srcst
ns = fake_operator(job_mod.LodJob(bpy.context, [src], lod.LodSettings(ratio=0.1, levels=1)))
ns._job.start(); ns._job.wait(120)
R["modal_timer"] = sorted(op_cls.modal(ns, bpy.context, event('TIMER')))
R["modal_timer_objects"] = sorted(o.name for o in bpy.data.objects if o.get("lod_source") == "Monkey")

# --- 8. Undo: one step per run
settings.importance_source = 'NONE'
select_only(src)
bpy.ops.ed.undo_push(message="before LODs")
state = data_state()
# The positional True asks bpy.ops for the undo push the UI makes after an operator
# with 'UNDO' in bl_options (scripts get none by default).
R["undo_flag"] = "UNDO" in bpy.types.OBJECT_OT_line_quadric_lod.bl_options
bpy.ops.object.line_quadric_lod('EXEC_DEFAULT', True, ratio=0.25, levels=3, level_factor=0.5)
R["undo_after_run"] = sorted(o.name for o in bpy.data.objects if o.get("lod_source") == "Monkey")
bpy.ops.ed.undo()
R["undo_restored"] = data_state() == state
R["undo_after_undo"] = sorted(o.name for o in bpy.data.objects if o.get("lod_source") == "Monkey")
bpy.ops.ed.redo()
R["redo_objects"] = sorted(o.name for o in bpy.data.objects if o.get("lod_source") == "Monkey")
'''


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_in_blender(SNIPPET, user_dir=blender_user_dir, timeout=600)


def test_three_lods_with_the_right_counts(res):
    assert res["op_result"] == ["FINISHED"]
    rep = res["report"][0]
    assert rep["object"] == "Monkey" and rep["source_triangles"] == 15744
    assert [lv["target"] for lv in rep["levels"]] == [7872, 3936, 1968]
    for lv, info in zip(rep["levels"], res["lods"]):
        assert info is not None
        assert abs(info["triangles"] - lv["target"]) <= 1
        assert info["triangles"] == lv["triangles"] and info["all_triangles"]
        assert 0 < lv["hausdorff_percent"] < 5 and 0 < lv["mean_percent"] < lv["hausdorff_percent"]
        assert 0.3 < lv["mean_quality"] <= 1


def test_objects_and_collection(res):
    assert res["collection_objects"] == ["Monkey_LOD1", "Monkey_LOD2", "Monkey_LOD3"]
    assert res["collection_in_scene"]
    for k, info in enumerate(res["lods"], start=1):
        assert info["in_collection"] == ["Monkey_LODs"]
        assert info["lod_level"] == k
        assert info["matrix_same"]
        assert info["game_id"] == 42  # custom properties copied
        assert info["modifiers"] == []  # the subdivision is applied, not copied


def test_materials_uvs_colours_groups_shape_keys_carried(res):
    for info in res["lods"]:
        assert info["materials"] == ["Skin", "Eyes"]
        assert info["material_indices"] == [0, 1]
        assert info["uv_maps"] == ["UVMap"]
        assert 0.0 <= info["uv_range"][0] < info["uv_range"][1] <= 1.0
        assert ["Tint", "CORNER", "BYTE_COLOR"] in info["colors"]
        assert ["Heat", "POINT", "FLOAT_COLOR"] in info["colors"]
        lo, hi, other = info["heat_range"]
        assert 0.0 <= lo < 0.1 and 0.9 < hi <= 1.0 and other == 0.0  # interpolated, in range
        assert info["color_mean"] == pytest.approx([1.0, 0.5, 0.25, 1.0], abs=0.02)
        assert info["groups"] == ["Top"]
        assert max(info["top_weights"]) == pytest.approx(0.75, abs=1e-3)
        assert info["shape_keys"] == ["Basis", "Smile"]
        assert info["smile_value"] == pytest.approx([1.7, 1.5, 3.0])
        assert info["smile_offset"] == pytest.approx(0.1, abs=1e-3)
        assert info["smooth"]
        assert info["sharp_edges"] > 0  # the ear's sharp rim still splits normals
        assert info["seam_edges"] > 0  # seams are marked where the source had them
        assert info["seam_x"] < 0.05  # on the mid line (held softly: within 2 % of the width)


def test_input_had_features(res):
    assert res["sharp_input"] > 0 and res["seams_input"] > 0


def test_source_unchanged(res):
    assert res["source_diff"] == {}


def test_rerun_replaces_previous_lods(res):
    assert res["rerun_objects"] == ["Monkey_LOD1", "Monkey_LOD2"]
    assert res["rerun_meshes"] == ["Monkey_LOD1", "Monkey_LOD2"]
    assert res["rerun_report_targets"] == [4723, 2362]
    assert all(abs(t - g) <= 1 for t, g in zip(res["rerun_triangles"], res["rerun_report_targets"]))


def test_source_selected_with_its_lods(res):
    assert res["with_lods_selected"] == [["FINISHED"], ["Monkey"], ["Monkey_LOD1", "Monkey_LOD2"]]


def test_cancel_leaves_the_scene_as_it_was(res):
    assert res["cancel_raised"] and res["cancel_calls"] == 2
    assert res["cancel_unchanged"]
    assert res["job_cancel_raised"] and res["job_cancel_unchanged"]
    assert abs(res["job_threaded_triangles"][0] - 3149) <= 1
    assert res["job_threaded_objects"] == ["Monkey_LOD1"]


def test_vertex_group_routes_agree(res):
    assert res["vg_read_same"]
    assert res["vg_write_names"] == ["position", "g2"]  # a group may share an attribute's name
    assert res["vg_write_err"] < 1e-6
    assert res["vg_write_members"] == [res["vg_nonzero"]] * 2


EXPECTED_ERRORS = {
    "no_mesh_selected": "Select one or more mesh objects",
    "only_lods_selected": "Only LOD objects are selected: select their source mesh",
    "empty_mesh": '"Empty Mesh" has an empty mesh',
    "no_faces": '"Wire" has no faces',
    "missing_group": '"Monkey" has no vertex group "Nope"',
    "not_skinned": '"Monkey" is not skinned',
    "no_deform_bones": 'armature "Rig" has no deform bones',
    "from_armature_no_deform": 'armature "Rig" has no deform bones',
    "target_not_smaller": "is not smaller than the mesh",
    "too_many_levels": "use fewer levels",
    "edit_mode": "Switch to Object Mode",
    "edit_mode_api": "is in Edit Mode",
}


@pytest.mark.parametrize("case", sorted(EXPECTED_ERRORS))
def test_bad_input_gives_a_clear_report(res, case):
    message = res["errors"][case]
    assert message is not None, f"{case}: no error reported"
    assert EXPECTED_ERRORS[case] in message
    assert "Traceback" not in message and "Python:" not in message


def test_bad_inputs_change_nothing(res):
    assert res["errors_diff"] == {}


def test_panel_draws_in_every_state(res):
    assert res["panel_registered"] and res["panel_category"] == "LOD"
    draws = res["draws"]
    assert ["label", "Select a mesh object"] in draws["no_object"]
    ops = [x[1] for x in draws["NONE"] if x[0] == "operator"]
    assert ops == ["object.line_quadric_lod_paint", "object.line_quadric_lod_from_armature", "object.line_quadric_lod"]
    props = {x[1] for x in draws["NONE"] if x[0] == "prop"}
    assert {"ratio", "levels", "level_factor", "target_triangles", "line_weight", "importance_source",
            "preserve_boundaries", "preserve_seams", "preserve_sharp", "preserve_materials",
            "boundary_strength", "seam_strength", "sharp_strength", "material_strength"} <= props
    assert ["prop_search", "importance_group"] in draws["VERTEX_GROUP"]
    armature_props = {x[1] for x in draws["ARMATURE"] if x[0] == "prop"}
    assert "importance_strength" in armature_props and "importance_mode" not in armature_props  # one mode
    assert "object.line_quadric_lod_preview_importance" in [x[1] for x in draws["ARMATURE"] if x[0] == "operator"]
    assert any("has no group" in x[1] for x in draws["missing_group"] if x[0] == "label")
    # The last run's report is shown: one row per LOD.
    assert ["label", "LOD2"] in draws["NONE"]


# What the docs' picture of the panel (bench/fig_panel.py) shows with the default settings:
# each field's label (RNA name or the panel's text override) and value as Blender formats it.
PANEL_DEFAULTS = {
    "target_triangles": ["Triangles", "0"], "ratio": ["Ratio", "0.50"], "levels": ["Levels", "3"],
    "level_factor": ["Factor", "0.50"], "remove_small_components": ["Remove Small Parts", ""],
    "line_weight": ["Uniformity", "0.0010"], "min_quality": ["Min Quality", "0.30"],
    "feature_angle": ["Feature Angle", "80.0"],
    "importance_source": ["Source", "None"],
    "preserve_boundaries": ["Boundaries", ""], "boundary_strength": ["", "1.00"],
    "preserve_seams": ["UV Seams", ""], "seam_strength": ["", "1.00"],
    "preserve_sharp": ["Sharp Edges", ""], "sharp_strength": ["", "1.00"],
    "preserve_materials": ["Material Borders", ""], "material_strength": ["", "1.00"],
    "use_modifiers": ["Apply Modifiers", ""], "measure_deviation": ["Measure Deviation", ""],
}


def test_panel_recording_names_values_and_greys_out(res):
    items = res["draw_items"]
    shown = {i[1]: i[2:4] for i in items["NONE"] if i[0] == "prop"}
    assert shown == PANEL_DEFAULTS
    assert [i[2] for i in items["NONE"] if i[0] == "operator"] == [
        "Paint Importance", "Importance from Armature", "Generate LODs"]
    assert all(i[4] for i in items["NONE"])  # nothing greyed out by default
    assert ["label", None, "LOD1..3: 50% · 25% · 12.5%", None, True] in items["NONE"]
    group = {i[1]: i[2:4] for i in items["VERTEX_GROUP"] if i[0] in ("prop", "prop_search")}
    assert group["importance_group"] == ["Group", "Top"]
    assert "importance_mode" not in group and group["importance_strength"] == ["Strength", "0.50"]
    # Triangles > 0 greys out the Ratio, an option that is off greys out its strength.
    assert sorted(i[1] for i in items["greyed"] if not i[4]) == ["ratio", "seam_strength"]
    assert ["label", None, "LOD1..3: 20,000 · 10,000 · 5,000 triangles", None, True] in items["greyed"]


def test_paint_importance(res):
    p = res["paint"]
    assert p["result"] == ["FINISHED"] and p["mode"] == "WEIGHT_PAINT"
    assert p["active_group"] == "LOD_Importance"
    assert p["source"] == "VERTEX_GROUP" and p["group"] == "LOD_Importance"
    assert res["paint_groups"].count("LOD_Importance") == 1


def test_generate_button_uses_panel_settings(res):
    for state in ("NONE", "VERTEX_GROUP", "ARMATURE"):
        sets = {x[2]: x[3] for x in res["draws"][state] if x[0] == "set" and x[1] == "object.line_quadric_lod"}
        assert sets == res["draw_settings"][state]
    assert res["invoke_result"] == ["EXECUTED"]
    assert res["invoke_settings"] == [1, pytest.approx(0.2), pytest.approx(0.3)]


def test_modal_esc_cancels_and_timer_commits(res):
    assert res["modal_running"] == ["RUNNING_MODAL"]  # editing is blocked while it runs
    assert res["modal_navigation"] == ["PASS_THROUGH"]  # looking around is not
    assert res["modal_esc"] == ["CANCELLED"]
    assert res["modal_esc_messages"] == [[["WARNING"], "LOD generation cancelled: nothing was changed"]]
    assert res["modal_esc_unchanged"]
    assert res["modal_timer"] == ["FINISHED"]
    assert res["modal_timer_objects"] == ["Monkey_LOD1"]


def test_undo_is_one_step(res):
    assert res["undo_flag"]
    assert res["undo_after_run"] == ["Monkey_LOD1", "Monkey_LOD2", "Monkey_LOD3"]
    assert res["undo_restored"]
    assert res["undo_after_undo"] == ["Monkey_LOD1"]  # the threaded job's LOD from before
    assert res["redo_objects"] == ["Monkey_LOD1", "Monkey_LOD2", "Monkey_LOD3"]
