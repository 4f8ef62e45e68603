"""A .blend whose bolts are collection instances (tests/test_cli_instances.py runs the
command line on it): a cube "Base" with a Subdivision Surface, the collection "Bolts"
(excluded from the view layer, as a kitbash library is) holding the UV sphere "Bolt",
and three empties instancing it at their own places, one of them scaled."""
import bpy

from scene_tools import remove_all_objects

PLACES = ((-1.5, 0.0, 1.2), (0.0, 0.0, 1.2), (1.5, 0.0, 1.2))


def run(blend_out: str) -> dict:
    remove_all_objects()
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    base = bpy.context.active_object
    base.name = "Base"
    base.modifiers.new("Subdivision", 'SUBSURF').levels = 2
    bolts = bpy.data.collections.new("Bolts")
    scene.collection.children.link(bolts)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=0.3)
    bolt = bpy.context.active_object
    bolt.name = "Bolt"
    for coll in list(bolt.users_collection):
        coll.objects.unlink(bolt)
    bolts.objects.link(bolt)
    bpy.context.view_layer.layer_collection.children["Bolts"].exclude = True
    for i, place in enumerate(PLACES):
        empty = bpy.data.objects.new(f"BoltInstance{i}", None)
        empty.instance_type = 'COLLECTION'
        empty.instance_collection = bolts
        empty.location = place
        if i == 2:
            empty.scale = (2.0, 2.0, 2.0)
        scene.collection.objects.link(empty)
    bpy.ops.wm.save_as_mainfile(filepath=blend_out)
    bolt.data.calc_loop_triangles()
    return {"bolt_triangles": len(bolt.data.loop_triangles)}
