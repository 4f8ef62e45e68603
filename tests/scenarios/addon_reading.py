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
    return out
