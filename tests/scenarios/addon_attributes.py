"""Generic attributes on a LOD (tests/test_addon_attributes.py checks what this returns;
the checkout's addon, no install): a cube (8 cuts a side) carrying, as an artist's
shader or a Geometry Nodes setup would read them,
  * "wear"   POINT FLOAT, the linear field x + 2y + 3z (interpolated);
  * "top"    POINT BOOLEAN, z > 0 (each LOD vertex's from its source vertex);
  * "side"   FACE INT, which of the six sides the face is on;
  * "corner_side" CORNER INT, the same per face corner;
  * "crease_edge" EDGE FLOAT, 1 on the cube's twelve edges, 0 elsewhere;
  * "tint"   FACE FLOAT_COLOR (a colour on faces is no colour attribute in Blender);
  * "bevel_weight_edge" EDGE FLOAT, all zero (Blender makes it when a tool touches it);
  * "turn"   POINT QUATERNION, a rotation per vertex (taken, not interpolated).
LodJob makes two LODs (0.5, 0.25); each LOD's attributes are returned with its vertices,
triangles and edges.
"""
import bpy
import numpy as np

from addon import job as job_mod
from addon import lod
from scene_tools import array as flat, mesh_hash, remove_all_objects


def array(collection, prop: str, width: int, dtype=np.float32) -> np.ndarray:
    return flat(collection, prop, width, dtype).reshape(-1, width)


def values(attr, width: int = 1):
    prop = {'FLOAT_COLOR': "color", 'FLOAT_VECTOR': "vector"}.get(attr.data_type, "value")
    dtype = bool if attr.data_type == 'BOOLEAN' else (np.int32 if attr.data_type == 'INT' else np.float32)
    out = np.empty(len(attr.data) * width, dtype=dtype)
    attr.data.foreach_get(prop, out)
    return out.reshape(-1, width).squeeze(-1) if width == 1 else out.reshape(-1, width)


def describe(me) -> dict:
    me.calc_loop_triangles()
    co = array(me.vertices, "co", 3).astype(np.float64)
    loops = array(me.loops, "vertex_index", 1, np.int32).ravel()
    starts = array(me.polygons, "loop_start", 1, np.int32).ravel()
    sizes = array(me.polygons, "loop_total", 1, np.int32).ravel()
    normals = array(me.polygons, "normal", 3).astype(np.float64)
    out = {"vertices": co.tolist(), "edges": array(me.edges, "vertices", 2, np.int32).tolist(),
           "face_normals": normals.tolist(), "loop_face": np.repeat(np.arange(len(starts)), sizes).tolist(),
           "loop_vertex": loops.tolist(), "attributes": {}}
    for attr in me.attributes:
        if attr.name in ("wear", "top", "side", "corner_side", "crease_edge", "tint", "bevel_weight_edge", "turn"):
            width = 4 if attr.data_type in ('FLOAT_COLOR', 'QUATERNION') else 1
            out["attributes"][attr.name] = {"domain": attr.domain, "type": attr.data_type,
                                            "values": values(attr, width).tolist()}
    return out


def side_of(normals: np.ndarray) -> np.ndarray:
    axis = np.abs(normals).argmax(axis=1)
    return 2 * axis + (normals[np.arange(len(normals)), axis] > 0)


def run() -> dict:
    remove_all_objects()
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    ob = bpy.context.active_object
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.subdivide(number_cuts=8)
    bpy.ops.object.mode_set(mode='OBJECT')
    me = ob.data
    co = array(me.vertices, "co", 3).astype(np.float64)
    normals = array(me.polygons, "normal", 3).astype(np.float64)
    me.attributes.new("wear", 'FLOAT', 'POINT').data.foreach_set("value", co @ np.array([1.0, 2.0, 3.0]))
    me.attributes.new("top", 'BOOLEAN', 'POINT').data.foreach_set("value", co[:, 2] > 0)
    side = side_of(normals)
    me.attributes.new("side", 'INT', 'FACE').data.foreach_set("value", side)
    sizes = array(me.polygons, "loop_total", 1, np.int32).ravel()
    me.attributes.new("corner_side", 'INT', 'CORNER').data.foreach_set("value", np.repeat(side, sizes))
    edges = array(me.edges, "vertices", 2, np.int32)
    a, b = co[edges[:, 0]], co[edges[:, 1]]  # both ends on one edge of the cube:
    on_rim = ((np.abs(a) > 0.999) & (np.abs(b) > 0.999) & (np.sign(a) == np.sign(b))).sum(axis=1) >= 2
    me.attributes.new("crease_edge", 'FLOAT', 'EDGE').data.foreach_set("value", on_rim.astype(np.float32))
    tint = np.zeros((len(side), 4), np.float32)
    tint[:, 0], tint[:, 3] = side / 5.0, 1.0
    me.attributes.new("tint", 'FLOAT_COLOR', 'FACE').data.foreach_set("color", tint.ravel())
    me.attributes.new("bevel_weight_edge", 'FLOAT', 'EDGE')
    angle = np.arctan2(co[:, 1], co[:, 0])  # a turn about z by each vertex's angle
    turn = np.column_stack([np.cos(angle / 2), np.zeros(len(co)), np.zeros(len(co)), np.sin(angle / 2)])
    me.attributes.new("turn", 'QUATERNION', 'POINT').data.foreach_set("value", turn.astype(np.float32).ravel())
    before = mesh_hash(me)
    job = job_mod.LodJob(bpy.context, [ob], lod.LodSettings(ratios=(0.5, 0.25), measure_deviation=False))
    job.run()
    reports = job.commit(bpy.context)
    return {"source": describe(me), "unchanged": mesh_hash(me) == before,
            "lods": [describe(bpy.data.objects[lev["name"]].data) for lev in reports[0]["levels"][1:]]}
