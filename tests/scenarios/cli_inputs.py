"""The inputs of tests/test_cli.py, written into one folder by factory Blender:
a.obj (a UV sphere "Ball"), rig.glb (a UV-mapped tube "Arm" skinned to two bones) and
scene.blend ("Rock", "Slab" with the vertex group "Detail" on one half, and a camera).
"""
import os

import bpy
import numpy as np
from scene_tools import array, empty_scene


def write_obj(out: str) -> None:
    """a.obj: a UV sphere (UVs, no materials)."""
    empty_scene()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=1.0)
    bpy.context.active_object.name = "Ball"
    bpy.ops.wm.obj_export(filepath=os.path.join(out, "a.obj"), export_materials=False)


def write_skinned_glb(out: str) -> None:
    """rig.glb: a UV-mapped tube skinned to two bones that meet at its middle."""
    empty_scene()
    ring, rows, r, h = 32, 41, 0.25, 2.0
    t = np.linspace(0, 2 * np.pi, ring, endpoint=False)
    z = np.linspace(0, h, rows)
    V = np.column_stack([np.tile(r * np.cos(t), rows), np.tile(r * np.sin(t), rows), np.repeat(z, ring)])
    i, j = np.meshgrid(np.arange(rows - 1), np.arange(ring), indexing="ij")
    a = (i * ring + j).ravel()
    b = (i * ring + (j + 1) % ring).ravel()
    quads = np.stack([a, b, b + ring, a + ring], -1)
    me = bpy.data.meshes.new("Arm")
    me.from_pydata(V.tolist(), [], quads.tolist())
    cj, ci = quads % ring, quads // ring
    u = cj / ring
    u = np.where((cj == 0) & (cj.max(1, keepdims=True) == ring - 1), 1.0, u)
    me.uv_layers.new(name="UVMap").uv.foreach_set(
        "vector", np.stack([u, ci / (rows - 1)], -1).astype(np.float32).ravel())
    arm_ob = bpy.data.objects.new("Arm", me)
    bpy.context.scene.collection.objects.link(arm_ob)
    ad = bpy.data.armatures.new("Skeleton")
    rig = bpy.data.objects.new("Skeleton", ad)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode='EDIT')
    lower = ad.edit_bones.new("Lower")
    lower.head, lower.tail = (0, 0, 0), (0, 0, 1)
    upper = ad.edit_bones.new("Upper")
    upper.head, upper.tail = (0, 0, 1), (0, 0, 2)
    upper.parent, upper.use_connect = lower, True
    bpy.ops.object.mode_set(mode='OBJECT')
    s = np.clip((V[:, 2] - 0.8) / 0.4, 0, 1)
    for name, w in (("Lower", 1 - s), ("Upper", s)):
        g = arm_ob.vertex_groups.new(name=name)
        for val in np.unique(w[w > 0]):
            g.add(np.flatnonzero(w == val).tolist(), float(val), 'REPLACE')
    arm_ob.parent = rig
    arm_ob.modifiers.new("Armature", 'ARMATURE').object = rig
    bpy.ops.export_scene.gltf(filepath=os.path.join(out, "rig.glb"), export_format='GLB')


def write_blend(out: str) -> None:
    """scene.blend: "Rock" (an icosphere of 320 triangles under a Subdivision Surface
    modifier: 1,280 evaluated, which its LOD0 in a .glb must have too), "Slab" (a wavy
    sheet with the vertex group "Detail" on one half), and a camera, which is not a mesh;
    a second scene "Storyboard" holds a cube "Spare" (the file opens on the first)."""
    empty_scene()
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2)
    bpy.context.active_object.name = "Rock"
    bpy.context.active_object.modifiers.new("Subdivision", 'SUBSURF').levels = 1
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=24, y_subdivisions=24, size=2, location=(3, 0, 0))
    slab = bpy.context.active_object
    slab.name = "Slab"
    co = array(slab.data.vertices, "co", 3).reshape(-1, 3)
    co[:, 2] = 0.15 * np.sin(3 * co[:, 0]) * np.cos(2 * co[:, 1])
    slab.data.vertices.foreach_set("co", co.ravel())
    slab.vertex_groups.new(name="Detail").add(np.flatnonzero(co[:, 0] < 0).tolist(), 1.0, 'REPLACE')
    bpy.ops.object.camera_add(location=(0, -5, 2))
    storyboard = bpy.data.scenes.new("Storyboard")
    spare = bpy.data.meshes.new("Spare")
    spare.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    storyboard.collection.objects.link(bpy.data.objects.new("Spare", spare))
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, "scene.blend"))


def run(out: str) -> dict:
    write_obj(out)
    write_skinned_glb(out)
    write_blend(out)
    return {"written": sorted(os.listdir(out))}
