"""What the Blender-side scenarios share: the installed extension's modules, the scene,
mesh data as NumPy arrays, a description of a scene's objects, and the skinned test rig
(three bones along z and a capped tube).

Runs inside a Blender child (tests/blender_child.py puts this folder on sys.path).
"""
import hashlib
import importlib
import math

import bpy
import numpy as np
from bpy_harness import EXT_MODULE


def extension_module(name: str):
    """A module of the installed extension, e.g. ``extension_module("addon.lod")``."""
    return importlib.import_module(f"{EXT_MODULE}.{name}")


def empty_scene() -> None:
    """A new empty scene from the factory start-up file (enabled add-ons stay enabled)."""
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)


def remove_all_objects() -> None:
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)


def drawn_triangles(ob) -> int:
    """The triangles of ``ob``'s evaluated mesh (through its modifiers; a curve's or a
    text's as it evaluates)."""
    evaluated = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        return len(mesh.loop_triangles)
    finally:
        evaluated.to_mesh_clear()


def select_only(*obs) -> None:
    """Select exactly ``obs``; the first becomes active (with none, the active one stays)."""
    for ob in list(bpy.context.selected_objects):
        ob.select_set(False)
    for ob in obs:
        ob.select_set(True)
    if obs:
        bpy.context.view_layer.objects.active = obs[0]


def mesh_hash(me) -> str:
    """A digest of a mesh's positions, corners and material indices (did it change?)."""
    h = hashlib.sha256()
    for coll, prop, width, dtype in ((me.vertices, "co", 3, np.float32), (me.loops, "vertex_index", 1, np.int32),
                                     (me.polygons, "material_index", 1, np.int32)):
        h.update(array(coll, prop, width, dtype).tobytes())
    return h.hexdigest()


def diff(before: dict, after: dict) -> dict:
    """{key: [before, after]} for every key whose value changed."""
    return {k: [before.get(k), after.get(k)] for k in set(before) | set(after) if before.get(k) != after.get(k)}


def value_errors(calls: dict) -> dict:
    """{name: the ValueError's message, or None if it raised none} for {name: call}."""
    errors = {}
    for name, call in calls.items():
        try:
            call()
            errors[name] = None
        except ValueError as ex:
            errors[name] = str(ex)
    return errors


def commit_after_cancel(job, cancelled, seconds: float = 120) -> bool:
    """Start ``job`` (a LodJob), cancel it, wait, and commit: whether the commit raised
    ``cancelled`` (the LodCancelled of the package the job came from)."""
    job.start()
    job.cancel()
    job.wait(seconds)
    try:
        job.commit(bpy.context)
    except cancelled:
        return True
    return False


def array(collection, prop: str, width: int, dtype=np.float32):
    """``collection.foreach_get(prop)`` as a flat NumPy array (width values per item)."""
    values = np.empty(len(collection) * width, dtype=dtype)
    collection.foreach_get(prop, values)
    return values


def describe_objects() -> dict:
    """{name: what it is} for every object of the scene: type and parent; for an Empty its
    "fbx_type"; for a mesh its triangles and vertices, a hash of its geometry, its vertex
    groups, the armature that deforms it, its number of UV maps and its "lod_level"; with
    a modifier other than Armature, its "evaluated_triangles"."""
    objects = {}
    for ob in bpy.context.scene.objects:
        entry = {"type": ob.type, "parent": ob.parent.name if ob.parent else None}
        if ob.type == 'EMPTY':
            entry["fbx_type"] = ob.get("fbx_type")
        if ob.type == 'MESH':
            me = ob.data
            me.calc_loop_triangles()
            co = array(me.vertices, "co", 3)
            tri = array(me.loop_triangles, "vertices", 3, np.int32)
            entry.update(
                triangles=len(me.loop_triangles), vertices=len(me.vertices),
                geometry=hashlib.sha256(co.tobytes() + tri.tobytes()).hexdigest(),
                groups=sorted(g.name for g in ob.vertex_groups),
                armature=next((md.object.name for md in ob.modifiers
                               if md.type == 'ARMATURE' and md.object is not None), None),
                uv_maps=len(me.uv_layers), lod_level=ob.get("lod_level"))
            if any(md.type != 'ARMATURE' for md in ob.modifiers):
                # (as the viewport evaluates it: what a LOD of it was made from)
                evaluated = ob.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
                evaluated.calc_loop_triangles()
                entry["evaluated_triangles"] = len(evaluated.loop_triangles)
        objects[ob.name] = entry
    return objects


def posed_triangles(ob):
    """The object as evaluated now (modifiers, pose), triangulated, in world space:
    (V (n, 3) float64, F (m, 3) int32)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    depsgraph.update()
    evaluated = ob.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    mesh.calc_loop_triangles()
    points = array(mesh.vertices, "co", 3).reshape(-1, 3).astype(float)
    faces = array(mesh.loop_triangles, "vertices", 3, np.int32).reshape(-1, 3)
    matrix = np.array(evaluated.matrix_world)
    evaluated.to_mesh_clear()
    return points @ matrix[:3, :3].T + matrix[:3, 3], faces


def three_bone_rig(name: str = "Armature"):
    """An armature along z: Upper 0-1 (the elbow at z = 1), Lower 1-2, Hand 2-2.6."""
    bpy.ops.object.armature_add(enter_editmode=True, location=(0, 0, 0))
    rig = bpy.context.active_object
    rig.name = name
    bones = rig.data.edit_bones
    upper = bones[0]
    upper.name, upper.head, upper.tail = "Upper", (0, 0, 0), (0, 0, 1.0)
    parent = upper
    for bone_name, head, tail in (("Lower", 1.0, 2.0), ("Hand", 2.0, 2.6)):
        bone = bones.new(bone_name)
        bone.head, bone.tail = (0, 0, head), (0, 0, tail)
        bone.parent, bone.use_connect = parent, True
        parent = bone
    bpy.ops.object.mode_set(mode='OBJECT')
    return rig


def capped_tube(name: str, radius_at, around: int, rings: int):
    """A tube along z from 0.02 to 2.58 (``rings`` rings of ``around`` vertices, radius
    ``radius_at(z)``), quads and two n-gon caps, linked to the scene.
    Returns (object, V (rings * around, 3), faces as vertex tuples)."""
    z = np.linspace(0.02, 2.58, rings)
    radius = radius_at(z)
    t = np.linspace(0, 2 * math.pi, around, endpoint=False)
    V = np.stack([np.outer(radius, np.cos(t)), np.outer(radius, np.sin(t)),
                  np.repeat(z[:, None], around, 1)], -1).reshape(-1, 3)
    idx = np.arange(rings * around).reshape(rings, around)
    quads = np.stack([idx[:-1], np.roll(idx[:-1], -1, 1), np.roll(idx[1:], -1, 1), idx[1:]], -1).reshape(-1, 4)
    faces = [tuple(q) for q in quads.tolist()] + [tuple(idx[0][::-1].tolist()), tuple(idx[-1].tolist())]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(V.tolist(), [], faces)
    mesh.update()
    ob = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(ob)
    return ob, V, faces


def parent_with_automatic_weights(rig, ob) -> list:
    """Parent ``ob`` to ``rig`` with Automatic Weights, as an artist would; the operator's result."""
    select_only(rig, ob)
    return sorted(bpy.ops.object.parent_set(type='ARMATURE_AUTO'))
