"""How addon/mesh_io.py reads meshes as importers bring them (tests/test_addon_reading.py
checks what this returns; the checkout's addon, no install): a flat-shaded monkey
(Subdivision Surface applied once) written to FBX and read back, whose importer marks
sharp every edge but those between coplanar faces, and a cube with four edges marked.
"""
import os
import tempfile

import bpy
import numpy as np

from addon import mesh_io
from addon.headless import scene_files
from pathlib import Path
from scene_tools import empty_scene


def read(ob) -> dict:
    data, _ = mesh_io.read_object(ob, bpy.context.evaluated_depsgraph_get(), True)
    return {"edges": len(ob.data.edges), "sharp": len(data.sharp_edges), "for_shading": data.sharp_for_shading}


def run() -> dict:
    empty_scene()
    bpy.ops.mesh.primitive_monkey_add()
    monkey = bpy.context.active_object
    monkey.modifiers.new("Subdivision", 'SUBSURF').levels = 1
    bpy.ops.object.modifier_apply(modifier="Subdivision")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "monkey.fbx"
        bpy.ops.export_scene.fbx(filepath=str(path))
        empty_scene()
        with scene_files.blender_output(False):
            scene_files.import_file(path)
        out = {"fbx_monkey": read(next(ob for ob in bpy.context.scene.objects if ob.type == 'MESH'))}
    empty_scene()
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    sharp = np.zeros(len(cube.data.edges), dtype=bool)
    sharp[:4] = True
    cube.data.attributes.new("sharp_edge", 'BOOLEAN', 'EDGE').data.foreach_set("value", sharp)
    out["cube"] = read(cube)
    out["triangles"] = triangles_as_blender_makes_them()
    return out


def triangles_as_blender_makes_them() -> dict:
    """mesh_io.triangles and positions against Blender's own loop triangles and vertex
    coordinates: a triangulated monkey (the one-block read), the monkey as modelled
    (quads and triangles) and a cylinder whose caps are n-gons (Blender triangulates)."""
    out = {}
    empty_scene()
    bpy.ops.mesh.primitive_monkey_add()
    monkey = bpy.context.active_object
    tri = monkey.data.copy()
    tri.name = "triangulated"
    import bmesh
    bm = bmesh.new()
    bm.from_mesh(tri)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    bm.to_mesh(tri)
    bm.free()
    bpy.ops.mesh.primitive_cylinder_add(vertices=12)
    for name, mesh in (("triangulated", tri), ("quads", monkey.data), ("ngons", bpy.context.active_object.data)):
        mesh.calc_loop_triangles()
        m = len(mesh.loop_triangles)
        expected = {prop: np.zeros(m * width, dtype=np.int64) for prop, width in
                    (("vertices", 3), ("loops", 3), ("polygon_index", 1))}
        for prop, array in expected.items():
            mesh.loop_triangles.foreach_get(prop, array)
        co = np.zeros(3 * len(mesh.vertices), dtype=np.float32)
        mesh.vertices.foreach_get("co", co)
        tris, loops, poly = mesh_io.triangles(mesh)
        out[name] = {
            "all_triangles": len(mesh.loops) == 3 * len(mesh.polygons),
            "triangles": m,
            "same": bool(np.array_equal(tris.ravel(), expected["vertices"])
                         and np.array_equal(loops.ravel(), expected["loops"])
                         and np.array_equal(poly, expected["polygon_index"])),
            "positions": bool(np.array_equal(mesh_io.positions(mesh), co.reshape(-1, 3).astype(np.float64))),
        }
    return out
