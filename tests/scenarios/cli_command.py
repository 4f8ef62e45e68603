"""``blender -c line_quadric_lod`` through the handler the installed extension registers
(tests/test_cli_command.py checks what this returns).

The bpy module has no command line of its own, so this records what the add-on hands to
``bpy.utils.register_cli_command`` when it is enabled, and then calls that handler with
arguments, as Blender does for ``-c``. The steps run in order in the folder ``work``;
later steps use the files earlier ones wrote.
"""
import contextlib
import hashlib
import io
import json
import os

import addon_utils
import bpy
from bpy_harness import EXT_MODULE
from scene_tools import describe_objects, empty_scene, extension_module


def record_registration(result: dict):
    """What register()/unregister() give Blender: disable and enable the extension twice,
    recording every call; returns the command's handler."""
    handles, events, handlers = [], [], []
    real_register, real_unregister = bpy.utils.register_cli_command, bpy.utils.unregister_cli_command

    def register(command_id, handler):
        handle = real_register(command_id, handler)
        handles.append(handle)
        events.append(("register", command_id, handler.__module__, handler.__name__))
        handlers.append(handler)
        return handle

    def unregister(handle):
        events.append(("unregister", any(handle is h for h in handles)))
        return real_unregister(handle)

    bpy.utils.register_cli_command, bpy.utils.unregister_cli_command = register, unregister
    try:
        addon_utils.disable(EXT_MODULE)  # the start-up registration goes
        addon_utils.enable(EXT_MODULE)  # ... and comes back through register()
        addon_utils.disable(EXT_MODULE)  # unregister() hands back that handle
        addon_utils.enable(EXT_MODULE)
    finally:
        bpy.utils.register_cli_command, bpy.utils.unregister_cli_command = real_register, real_unregister
    result["events"] = events
    return handlers[-1]


def caller(handler):
    """``call(*argv)``: the handler run on argv, as {"code", "stdout", "stderr"}."""
    def call(*argv):
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = handler(list(argv))
        return {"code": code, "stdout": out.getvalue(), "stderr": err.getvalue()}
    return call


def meshes() -> dict:
    """{mesh object: {"triangles", "parent"}} of the scene."""
    return {name: {"triangles": ob["triangles"], "parent": ob["parent"]}
            for name, ob in describe_objects().items() if ob["type"] == 'MESH'}


def digest(path: str) -> str:
    with open(path, "rb") as fh:
        return hashlib.sha256(fh.read()).hexdigest()


def write_inputs(work: str) -> str:
    """scene.blend (Rock, Slab with a "Detail" group, a camera) and a UV-less STL;
    returns the .blend's path."""
    empty_scene()
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=4)
    bpy.context.active_object.name = "Rock"
    bpy.ops.mesh.primitive_uv_sphere_add(location=(3, 0, 0))
    slab = bpy.context.active_object
    slab.name = "Slab"
    slab.vertex_groups.new(name="Detail").add(list(range(0, len(slab.data.vertices), 2)), 1.0, 'REPLACE')
    bpy.ops.object.camera_add()
    blend = os.path.join(work, "scene.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    empty_scene()
    bpy.ops.mesh.primitive_torus_add(major_segments=40, minor_segments=16)
    bpy.ops.wm.stl_export(filepath=os.path.join(work, "part.stl"))
    return blend


def blend_to_fbx(call, work: str, blend: str, result: dict) -> None:
    """A .blend input to FBX with an Unreal LOD group."""
    fbx = os.path.join(work, "rock.fbx")
    report = os.path.join(work, "rock.json")
    result["fbx_run"] = call("--input", blend, "--objects", "Rock", "--faces", "600", "200", "--output", fbx,
                             "--lod-group", "--report", report, "--quiet")
    with open(report, encoding="utf-8") as fh:
        result["fbx_report"] = json.load(fh)
    with open(fbx, "rb") as fh:
        result["fbx_has_lodgroup"] = b"LodGroup" in fh.read()
    empty_scene()
    bpy.ops.import_scene.fbx(filepath=fbx)
    result["fbx_meshes"] = meshes()
    result["fbx_empties"] = {ob.name: [c.name for c in ob.children]
                             for ob in bpy.context.scene.objects if ob.type == 'EMPTY'}


def open_file_to_gltf(call, work: str, blend: str, result: dict) -> None:
    """The open file (no --input) to glTF, importance where the group exists."""
    bpy.ops.wm.open_mainfile(filepath=blend)
    gltf = os.path.join(work, "open.gltf")
    result["gltf_run"] = call("--ratios", "0.5", "--importance-group", "Detail", "--output", gltf)
    result["gltf_files"] = sorted(os.listdir(work))
    empty_scene()
    bpy.ops.import_scene.gltf(filepath=gltf)
    result["gltf_meshes"] = meshes()


def stl_to_obj(call, work: str, result: dict) -> None:
    """A UV-less STL to OBJ."""
    obj = os.path.join(work, "part.obj")
    result["stl_run"] = call("--input", os.path.join(work, "part.stl"), "--ratios", "0.5", "0.25", "--output", obj,
                             "--quiet")
    empty_scene()
    if os.path.exists(obj):
        bpy.ops.wm.obj_import(filepath=obj)
    result["obj_meshes"] = meshes()


def failures(call, work: str, blend: str, result: dict) -> str:
    """Bad objects, an impossible target and a failing exporter: none may leave a partial
    file or touch a good one. Returns the good file's path."""
    good = os.path.join(work, "good.blend")
    result["good_run"] = call("--input", blend, "--ratios", "0.5", "--output", good, "--quiet")
    before = digest(good)
    result["bad_objects"] = call("--input", blend, "--objects", "Nope", "Camera", "--output", good)
    result["impossible"] = call("--input", blend, "--faces", "5000", "--output", good)
    scene_files = extension_module("addon.headless.scene_files")
    real_export = scene_files.export_scene

    def failing_export(path):
        with open(path, "wb") as fh:
            fh.write(b"half a file")
        raise RuntimeError("Error: No space left on device\n")

    scene_files.export_scene = failing_export
    try:
        # --force: the same command as the good run, whose output is up to date.
        result["export_fails"] = call("--input", blend, "--ratios", "0.5", "--output", good, "--force")
    finally:
        scene_files.export_scene = real_export
    result["good_unchanged"] = digest(good) == before
    return good


def rerun_on_own_output(call, work: str, good: str, result: dict) -> None:
    """A re-run on its own output replaces the LODs instead of making LODs of LODs."""
    again = os.path.join(work, "again.blend")
    result["rerun"] = call("--input", good, "--ratios", "0.25", "--output", again, "--lod-group", "--quiet")
    bpy.ops.wm.open_mainfile(filepath=again)
    result["rerun_objects"] = sorted(ob.name for ob in bpy.context.scene.objects)
    result["rerun_meshes"] = meshes()


def run(work: str) -> dict:
    result = {}
    call = caller(record_registration(result))
    blend = write_inputs(work)
    blend_to_fbx(call, work, blend, result)
    open_file_to_gltf(call, work, blend, result)
    stl_to_obj(call, work, result)
    good = failures(call, work, blend, result)
    rerun_on_own_output(call, work, good, result)
    result["leftovers"] = sorted(n for n in os.listdir(work) if n.startswith(".") and not n.endswith(".lqlod.json"))
    # after every fresh scene
    result["still_enabled"] = EXT_MODULE in {a.module for a in bpy.context.preferences.addons}
    result["bogus"] = call("--bogus")
    result["help"] = call("--help")
    return result
