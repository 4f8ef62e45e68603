"""Shape keys through modifiers, for the command line (tests/test_cli_keyed_modifiers.py).

``make``: ``blend`` gets "Face", half a monkey (x >= 0) with a Mirror modifier and a key
"Smile" that lifts its lower half in proportion to |x|, as faces are modelled; and a
UV sphere "Ball" with no keys. ``inspect``: imports ``fbx`` (or opens ``blend``) and
returns each mesh object's triangles, modifiers, key names, and for its last key how
many vertices it moves and their x range."""
import bpy
import bmesh
import numpy as np

from scene_tools import empty_scene


def make(blend: str) -> dict:
    empty_scene()
    bpy.ops.mesh.primitive_monkey_add()
    face = bpy.context.active_object
    face.name = "Face"
    bm = bmesh.new()
    bm.from_mesh(face.data)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=1, use_grid_fill=True)
    bmesh.ops.delete(bm, geom=[v for v in bm.verts if v.co.x < -1e-4], context='VERTS')
    bm.to_mesh(face.data)
    bm.free()
    mirror = face.modifiers.new("Mirror", 'MIRROR')
    mirror.use_clip = mirror.use_mirror_merge = True
    face.shape_key_add(name="Basis")
    smile = face.shape_key_add(name="Smile", from_mix=False)
    for point in smile.data:
        if point.co.y < -0.5:
            point.co.z += 0.2 * abs(point.co.x)
    bpy.ops.mesh.primitive_uv_sphere_add(location=(3.0, 0.0, 0.0))
    bpy.context.active_object.name = "Ball"
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    return {}


def inspect(fbx: str = "", blend: str = "") -> dict:
    if blend:
        bpy.ops.wm.open_mainfile(filepath=blend)
    else:
        empty_scene()
        bpy.ops.import_scene.fbx(filepath=fbx)
    out = {}
    for ob in bpy.context.scene.objects:
        if ob.type != 'MESH':
            continue
        keys = ob.data.shape_keys
        entry = {"triangles": sum(len(p.vertices) - 2 for p in ob.data.polygons),
                 "modifiers": [md.type for md in ob.modifiers],
                 "keys": [k.name for k in keys.key_blocks] if keys else []}
        if keys and len(keys.key_blocks) > 1:
            n = len(ob.data.vertices)
            basis, last = np.empty(3 * n), np.empty(3 * n)
            keys.key_blocks[0].data.foreach_get("co", basis)
            keys.key_blocks[-1].data.foreach_get("co", last)
            basis, last = basis.reshape(-1, 3), last.reshape(-1, 3)
            moved = np.linalg.norm(last - basis, axis=1) > 1e-4
            entry["moved"] = int(moved.sum())
            entry["moved_x"] = [float(basis[moved, 0].min()), float(basis[moved, 0].max())] if moved.any() else None
        out[ob.name] = entry
    return out


def run(mode: str, blend: str = "", fbx: str = "") -> dict:
    return make(blend) if mode == "make" else inspect(fbx, blend)
