"""A part placed by constraints rather than a parent (tests/test_addon_constraints.py): a
monkey "Placed" that a Child Of constraint puts on the animated empty "Anchor" (moved and
turned between frames 1 and 12) and a Copy Scale constraint sizes like "Sizer", through
LodJob of the installed extension with a UV sphere "Ground" as the asset's other part."""
import bpy

from scene_tools import empty_scene, extension_module

job_mod = extension_module("addon.job")
lod = extension_module("addon.lod")

FRAMES = (1, 12)


def run() -> dict:
    empty_scene()
    anchor = bpy.data.objects.new("Anchor", None)
    bpy.context.scene.collection.objects.link(anchor)
    for frame, location, turn in ((1, (4.0, 0.0, 0.0), 0.0), (12, (4.0, 3.0, 1.0), 1.2)):
        anchor.location, anchor.rotation_euler = location, (0.0, 0.0, turn)
        anchor.keyframe_insert("location", frame=frame)
        anchor.keyframe_insert("rotation_euler", frame=frame)
    sizer = bpy.data.objects.new("Sizer", None)
    bpy.context.scene.collection.objects.link(sizer)
    sizer.scale = (2.0, 2.0, 2.0)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, location=(0.0, 0.0, -2.0))
    bpy.context.active_object.name = "Ground"
    bpy.ops.mesh.primitive_monkey_add()
    placed = bpy.context.active_object
    placed.name = "Placed"
    placed.modifiers.new("Subdivision", 'SUBSURF').levels = 1
    child_of = placed.constraints.new('CHILD_OF')
    child_of.target = anchor
    child_of.set_inverse_pending = False
    placed.constraints.new('COPY_SCALE').target = sizer
    objects = [placed, bpy.data.objects["Ground"]]
    job = job_mod.LodJob(bpy.context, objects, lod.LodSettings(ratios=(0.5, 0.25)))
    job.run()
    reports = job.commit(bpy.context)
    lods = {r["object"]: [level["name"] for level in r["levels"]] for r in reports}
    names = [name for source, chain in lods.items() for name in [source] + chain]
    out = {"lods": lods, "constraints": {name: [(c.type, c.target.name) for c in bpy.data.objects[name].constraints]
                                         for name in names}, "matrices": {}}
    for frame in FRAMES:
        bpy.context.scene.frame_set(frame)
        out["matrices"][frame] = {name: [list(row) for row in bpy.data.objects[name].matrix_world] for name in names}
    return out
