"""Painted importance on a flat 120 x 120 grid with a painted disc, taken to 10 % at each
strength; Preview Importance; Blender's Decimate with the same group for contrast
(tests/test_addon_importance.py checks what this returns)."""
import math

import bpy
import numpy as np
from scene_tools import array, extension_module, remove_all_objects, select_only

CENTER, RADIUS = np.array([0.3, 0.2]), 0.35
DISC_AREA = math.pi * RADIUS ** 2
REST_AREA = 4.0 - DISC_AREA


def in_disc(points):
    return np.linalg.norm(points[:, :2] - CENTER, axis=1) < RADIUS


def densities(mesh):
    """(vertices in the disc, their density, the density outside, all vertices)."""
    P = array(mesh.vertices, "co", 3).reshape(-1, 3)
    inside = in_disc(P)
    return int(inside.sum()), float(inside.sum() / DISC_AREA), float((~inside).sum() / REST_AREA), len(P)


def lods_at_each_strength(ob, strengths) -> list:
    lod = extension_module("addon.lod")
    runs = []
    for s in strengths:
        report = lod.generate_lods(bpy.context, ob, lod.LodSettings(
            ratio=0.1, levels=1, importance_source='VERTEX_GROUP', importance_group="LOD_Importance",
            importance_strength=s, measure_deviation=False))
        lod_ob = bpy.data.objects[ob.name + "_LOD1"]
        disc, d_in, d_out, nv = densities(lod_ob.data)
        P = array(lod_ob.data.vertices, "co", 3)
        runs.append({"strength": s, "triangles": len(lod_ob.data.polygons),
                     "target": report["levels"][0]["target"], "vertices": nv, "disc_vertices": disc,
                     "density_ratio": d_in / d_out, "quality": report["levels"][0]["mean_quality"],
                     "report": report["levels"][0].get("importance"),
                     "flat": float(np.abs(P.reshape(-1, 3)[:, 2]).max())})
    return runs


def preview(ob, inside) -> dict:
    """Preview Importance with the panel's settings (default strength): a vertex group with
    the effective importance, shown in Weight Paint mode; the painted group is untouched."""
    panel = bpy.context.scene.line_quadric_lod
    panel.importance_source = 'VERTEX_GROUP'
    panel.importance_group = "LOD_Importance"
    select_only(ob)
    outcome = bpy.ops.object.line_quadric_lod_preview_importance()
    vertex_groups = extension_module("addon.vertex_groups")
    importance = extension_module("addon.pure.importance")
    w = vertex_groups.read_weights(ob.data, ["LOD_Importance_Preview", "LOD_Importance"])
    shown = {"result": sorted(outcome), "mode": ob.mode, "active": ob.vertex_groups.active.name,
             "inside": [float(w[inside, 0].min()), float(w[inside, 0].max())],
             "outside_max": float(w[~inside, 0].max()),
             "painted_changed": int(np.count_nonzero((w[:, 1] > 0) != inside)),
             "expected": float(importance.effective(np.array([1.0]), panel.importance_strength)[0]),
             "strength": float(panel.importance_strength)}
    bpy.ops.object.mode_set(mode='OBJECT')
    return shown


def decimate_contrast(ob) -> dict:
    """Blender's Decimate with the same group, plain and inverted (the issue's numbers)."""
    dec = ob.modifiers.new("Decimate", 'DECIMATE')
    dec.ratio = 0.1
    dec.vertex_group = "LOD_Importance"
    contrast = {}
    for invert in (False, True):
        dec.invert_vertex_group = invert
        depsgraph = bpy.context.evaluated_depsgraph_get()
        depsgraph.update()
        mesh = ob.evaluated_get(depsgraph).to_mesh()
        disc, _d_in, _d_out, nv = densities(mesh)
        contrast["inverted" if invert else "plain"] = {"vertices": nv, "disc_vertices": disc}
        ob.evaluated_get(depsgraph).to_mesh_clear()
    ob.modifiers.remove(dec)
    return contrast


def run(strengths: list) -> dict:
    remove_all_objects()
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=120, y_subdivisions=120, size=2)
    ob = bpy.context.active_object
    co = array(ob.data.vertices, "co", 3).reshape(-1, 3)
    inside = in_disc(co)
    ob.vertex_groups.new(name="LOD_Importance").add(np.flatnonzero(inside).tolist(), 1.0, 'REPLACE')
    return {"input": {"vertices": len(co), "disc_vertices": int(inside.sum())},
            "runs": lods_at_each_strength(ob, strengths),
            "preview": preview(ob, inside),
            "decimate": decimate_contrast(ob)}
