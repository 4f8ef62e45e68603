"""Curves, text, surfaces and metaballs are parts of an asset (issue 32 §1): Blender draws
them as meshes and the exporters write them as meshes, so an asset's levels hold their
LODs too (tests/test_addon_curve_parts.py checks what this returns; the checkout's addon,
no install).

The scene: a monkey (Subdivision Surface applied once), a bevelled Bézier circle "Cable"
with a material "Rubber", an extruded text "Logo" with a material "Paint", and a Bézier
curve "Guide" with neither bevel nor extrusion (it draws no faces). All four are selected
and go to LodJob as the panel's Generate LODs gives them. ``blend_out``: the scene is
saved there first, for the command line (tests/test_cli_instances.py).
"""
import hashlib

import bpy
import numpy as np

from addon import job as job_mod
from addon import lod
from addon import operators
from scene_tools import drawn_triangles, remove_all_objects, select_only

RATIOS = (0.5, 0.25)


def curve_hash(curve) -> str:
    """The curve's control points, bevel and extrusion, hashed (the source must not change)."""
    h = hashlib.sha256()
    for spline in curve.splines:
        for point in spline.bezier_points:
            h.update(np.array([*point.co, *point.handle_left, *point.handle_right], np.float64).tobytes())
    h.update(np.array([curve.bevel_depth, curve.extrude], np.float64).tobytes())
    return h.hexdigest()


def build() -> dict:
    remove_all_objects()
    bpy.ops.mesh.primitive_monkey_add()
    monkey = bpy.context.active_object
    monkey.name = "Monkey"
    monkey.modifiers.new("Subdivision", 'SUBSURF').levels = 1
    bpy.ops.curve.primitive_bezier_circle_add(radius=1.5, location=(3.0, 0.0, 0.0))
    cable = bpy.context.active_object
    cable.name = "Cable"
    cable.data.bevel_depth, cable.data.bevel_resolution = 0.1, 3
    cable.data.materials.append(bpy.data.materials.new("Rubber"))
    bpy.ops.object.text_add(location=(-1.0, 2.0, 0.0))
    logo = bpy.context.active_object
    logo.name = "Logo"
    logo.data.body, logo.data.extrude = "LOD", 0.1
    logo.data.materials.append(bpy.data.materials.new("Paint"))
    bpy.ops.curve.primitive_bezier_curve_add(location=(0.0, -3.0, 0.0))
    guide = bpy.context.active_object
    guide.name = "Guide"
    return {"Monkey": monkey, "Cable": cable, "Logo": logo, "Guide": guide}


def chains(reports) -> dict:
    bpy.context.view_layer.update()  # the new objects' world matrices
    out = {}
    for r in reports:
        levels = []
        for lev in r["levels"]:
            ob = bpy.data.objects[lev["name"]]
            ob.data.calc_loop_triangles()
            levels.append({"type": ob.type, "triangles": len(ob.data.loop_triangles),
                           "materials": [m.name for m in ob.data.materials if m is not None],
                           "matrix_world": [list(row) for row in ob.matrix_world]})
        out[r["object"]] = levels
    return out


def run(blend_out: str = "") -> dict:
    objects = build()
    if blend_out:
        bpy.ops.wm.save_as_mainfile(filepath=blend_out, copy=True)
    select_only(*objects.values())
    selected = operators.selected_meshes(bpy.context)
    hashes = {n: curve_hash(objects[n].data) for n in ("Cable", "Guide")}
    drawn = {n: drawn_triangles(ob) for n, ob in objects.items()}
    job = job_mod.LodJob(bpy.context, selected, lod.LodSettings(ratios=RATIOS, measure_deviation=False))
    job.run()
    reports = job.commit(bpy.context)
    out = {"selected": sorted(ob.name for ob in selected), "skipped": job.skipped, "drawn": drawn,
           "asset": job.asset_report, "chains": chains(reports),
           "sources": {n: bpy.data.objects[n].type for n in objects},
           "unchanged": all(curve_hash(bpy.data.objects[n].data) == h for n, h in hashes.items()),
           "source_matrix": {n: [list(row) for row in bpy.data.objects[n].matrix_world] for n in objects}}
    # The text alone, as Generate LODs on it alone.
    alone = job_mod.LodJob(bpy.context, [bpy.data.objects["Logo"]],
                           lod.LodSettings(ratios=RATIOS, measure_deviation=False))
    alone.run()
    out["alone"] = chains(alone.commit(bpy.context))
    # The curve without faces alone: a message that says why.
    try:
        job_mod.LodJob(bpy.context, [bpy.data.objects["Guide"]], lod.LodSettings(ratios=RATIOS))
    except lod.LodError as ex:
        out["guide_alone"] = str(ex)
    return out
