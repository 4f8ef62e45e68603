"""``blender -c line_quadric_lod``: the command the installed extension registers.

The bpy module has no command line of its own, so one Blender child (built extension
installed and enabled) records what the add-on hands to ``bpy.utils.register_cli_command``
when it is enabled, and then calls that registered handler with arguments, as Blender
does for ``-c``: on a .blend input (FBX with an Unreal LOD group), on the open file
(glTF), on a UV-less STL (OBJ out), and with bad inputs, a failing exporter and an
impossible target next to a good output file that must survive.
"""
import os

import pytest

from bpy_harness import run_in_blender

SNIPPET = r'''
import addon_utils, contextlib, hashlib, importlib, io, json, os
import numpy as np

W = os.environ["LQLOD_TEST_DIR"]
R = RESULT

# --- what register()/unregister() give Blender
handles, events = [], []
real_register, real_unregister = bpy.utils.register_cli_command, bpy.utils.unregister_cli_command

def register(command_id, handler):
    handle = real_register(command_id, handler)
    handles.append(handle)
    events.append(("register", command_id, handler.__module__, handler.__name__))
    R["handler"] = handler
    return handle

def unregister(handle):
    events.append(("unregister", any(handle is h for h in handles)))
    return real_unregister(handle)

bpy.utils.register_cli_command, bpy.utils.unregister_cli_command = register, unregister
try:
    addon_utils.disable(EXT)   # the start-up registration goes
    addon_utils.enable(EXT)    # ... and comes back through register()
    addon_utils.disable(EXT)   # unregister() hands back that handle
    addon_utils.enable(EXT)
finally:
    bpy.utils.register_cli_command, bpy.utils.unregister_cli_command = real_register, real_unregister
handler = R.pop("handler")
R["events"] = events
scene_files = importlib.import_module(handler.__module__.rsplit(".", 1)[0] + ".headless.scene_files")

def call(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = handler(list(argv))
    return {"code": code, "stdout": out.getvalue(), "stderr": err.getvalue()}

def fresh():
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)

def meshes():
    out = {}
    for ob in bpy.context.scene.objects:
        if ob.type == 'MESH':
            ob.data.calc_loop_triangles()
            out[ob.name] = {"triangles": len(ob.data.loop_triangles),
                            "parent": ob.parent.name if ob.parent else None}
    return out

def digest(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()

# --- inputs: scene.blend (Rock, Slab with a "Detail" group, a camera) and a UV-less STL
fresh()
bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=4)
bpy.context.active_object.name = "Rock"
bpy.ops.mesh.primitive_uv_sphere_add(location=(3, 0, 0))
slab = bpy.context.active_object
slab.name = "Slab"
slab.vertex_groups.new(name="Detail").add(list(range(0, len(slab.data.vertices), 2)), 1.0, 'REPLACE')
bpy.ops.object.camera_add()
blend = os.path.join(W, "scene.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)
fresh()
bpy.ops.mesh.primitive_torus_add(major_segments=40, minor_segments=16)
bpy.ops.wm.stl_export(filepath=os.path.join(W, "part.stl"))

# --- a .blend input to FBX with an Unreal LOD group
fbx = os.path.join(W, "rock.fbx")
R["fbx_run"] = call("--input", blend, "--objects", "Rock", "--faces", "600", "200", "--output", fbx,
                    "--lod-group", "--report", os.path.join(W, "rock.json"), "--quiet")
R["fbx_report"] = json.load(open(os.path.join(W, "rock.json")))
R["fbx_has_lodgroup"] = b"LodGroup" in open(fbx, "rb").read()
fresh()
bpy.ops.import_scene.fbx(filepath=fbx)
R["fbx_meshes"] = meshes()
R["fbx_empties"] = {ob.name: [c.name for c in ob.children] for ob in bpy.context.scene.objects if ob.type == 'EMPTY'}

# --- the open file (no --input) to glTF, importance where the group exists
bpy.ops.wm.open_mainfile(filepath=blend)
gltf = os.path.join(W, "open.gltf")
R["gltf_run"] = call("--ratios", "0.5", "--importance-group", "Detail", "--output", gltf)
R["gltf_files"] = sorted(os.listdir(W))
fresh()
bpy.ops.import_scene.gltf(filepath=gltf)
R["gltf_meshes"] = meshes()

# --- a UV-less STL to OBJ
obj = os.path.join(W, "part.obj")
R["stl_run"] = call("--input", os.path.join(W, "part.stl"), "--ratios", "0.5", "0.25", "--output", obj, "--quiet")
fresh()
if os.path.exists(obj):
    bpy.ops.wm.obj_import(filepath=obj)
R["obj_meshes"] = meshes()

# --- failures: none may leave a partial file or touch a good one
good = os.path.join(W, "good.blend")
R["good_run"] = call("--input", blend, "--ratios", "0.5", "--output", good, "--quiet")
before = digest(good)
R["bad_objects"] = call("--input", blend, "--objects", "Nope", "Camera", "--output", good)
R["impossible"] = call("--input", blend, "--faces", "5000", "--output", good)
real_export = scene_files.export_scene

def failing_export(path):
    open(path, "wb").write(b"half a file")
    raise RuntimeError("Error: No space left on device\n")

scene_files.export_scene = failing_export
try:
    R["export_fails"] = call("--input", blend, "--ratios", "0.5", "--output", good)
finally:
    scene_files.export_scene = real_export
R["good_unchanged"] = digest(good) == before
# a re-run on its own output replaces the LODs instead of making LODs of LODs
again = os.path.join(W, "again.blend")
R["rerun"] = call("--input", good, "--ratios", "0.25", "--output", again, "--lod-group", "--quiet")
bpy.ops.wm.open_mainfile(filepath=again)
R["rerun_objects"] = sorted(ob.name for ob in bpy.context.scene.objects)
R["rerun_meshes"] = meshes()
R["leftovers"] = sorted(n for n in os.listdir(W) if n.startswith("."))
R["still_enabled"] = EXT in {a.module for a in bpy.context.preferences.addons}  # after every fresh scene
R["bogus"] = call("--bogus")
R["help"] = call("--help")
'''


@pytest.fixture(scope="module")
def result(blender_user_dir, tmp_path_factory):
    work = tmp_path_factory.mktemp("cli_command")
    os.environ["LQLOD_TEST_DIR"] = str(work)
    try:
        return run_in_blender(SNIPPET, user_dir=blender_user_dir)
    finally:
        del os.environ["LQLOD_TEST_DIR"]


def errors(run):
    return [line for line in run["stderr"].splitlines() if line.startswith("error:")]


def test_enabling_registers_the_command_and_disabling_unregisters_it(result):
    events = [tuple(e) for e in result["events"]]
    handler = ("register", "line_quadric_lod", events[1][2], "cli_command")
    assert events[1][2].endswith(".addon.cli")
    # disable (start-up handle), enable, disable (the handle register() returned), enable
    assert events == [("unregister", False), handler, ("unregister", True), handler]


def test_blend_to_fbx_with_an_unreal_lod_group(result):
    run = result["fbx_run"]
    assert run["code"] == 0 and run["stderr"] == "", run
    assert result["fbx_has_lodgroup"]
    rock = result["fbx_report"]["files"][0]["objects"]
    assert [o["object"] for o in rock] == ["Rock"]  # --objects: Slab is left alone
    assert [lv["triangles"] for lv in rock[0]["levels"]] == [1280, 600, 200]
    chain = ["Rock_LOD0", "Rock_LOD1", "Rock_LOD2"]
    assert result["fbx_empties"] == {"Rock_LODGroup": chain}
    meshes = result["fbx_meshes"]
    # The whole scene is written; only Rock got LODs.
    assert {n: m["triangles"] for n, m in meshes.items()} == {**dict(zip(chain, [1280, 600, 200])), "Slab": 960}
    assert [meshes[n]["parent"] for n in chain] == ["Rock_LODGroup"] * 3 and meshes["Slab"]["parent"] is None


def test_open_file_to_gltf(result):
    run = result["gltf_run"]
    assert run["code"] == 0, run
    assert "open.gltf" in result["gltf_files"] and "open.bin" in result["gltf_files"]
    meshes = result["gltf_meshes"]
    assert sorted(meshes) == ["Rock_LOD0", "Rock_LOD1", "Slab_LOD0", "Slab_LOD1"]
    assert meshes["Rock_LOD1"]["triangles"] == 640
    assert "[scene.blend] Slab: LOD1 simplified" in run["stderr"]  # progress without --quiet
    assert 'note: scene.blend: Rock: no importance (no vertex group "Detail")' in run["stdout"]


def test_uvless_stl_to_obj(result):
    run = result["stl_run"]
    assert run["code"] == 0, run
    tris = {n: m["triangles"] for n, m in result["obj_meshes"].items()}
    assert tris == {"part_LOD0": 1280, "part_LOD1": 640, "part_LOD2": 320}


def test_failures_are_one_line_and_never_touch_a_good_file(result):
    assert result["good_run"]["code"] == 0
    bad = result["bad_objects"]
    assert bad["code"] == 1 and errors(bad) == [
        'error: scene.blend: object "Nope" not found (mesh objects: Rock, Slab); '
        '"Camera" is not a mesh object (its type is CAMERA)']
    impossible = result["impossible"]
    assert impossible["code"] == 1 and errors(impossible) == [
        "error: scene.blend: \"Rock\": --faces 5000 is not fewer than the mesh's 1,280 triangles"]
    export = result["export_fails"]
    assert export["code"] == 1 and len(errors(export)) == 1
    assert errors(export)[0].endswith("good.blend: No space left on device") and "could not write" in errors(export)[0]
    assert result["good_unchanged"] and result["leftovers"] == []
    for run in (bad, impossible, export):
        assert "Traceback" not in run["stderr"] + run["stdout"]
        assert "FAILED" in run["stdout"]


def test_fresh_scenes_between_inputs_keep_the_extension_enabled(result):
    assert result["still_enabled"]


def test_bad_option_and_help_through_the_handler(result):
    assert result["bogus"]["code"] == 2
    assert errors(result["bogus"]) == [
        "error: unrecognized arguments: --bogus (see blender -b [scene.blend] -c line_quadric_lod --help)"]
    assert result["help"]["code"] == 0
    assert result["help"]["stdout"].startswith("usage: blender -b [scene.blend] -c line_quadric_lod")


def test_rerun_on_its_own_output_replaces_the_lods(result):
    assert result["rerun"]["code"] == 0, result["rerun"]
    assert result["rerun_objects"] == ["Camera", "Rock_LOD0", "Rock_LOD1", "Rock_LODGroup",
                                       "Slab_LOD0", "Slab_LOD1", "Slab_LODGroup"]
    meshes = result["rerun_meshes"]
    assert meshes["Rock_LOD1"]["triangles"] == 320 and meshes["Rock_LOD0"]["triangles"] == 1280
    assert meshes["Rock_LOD1"]["parent"] == "Rock_LODGroup"
