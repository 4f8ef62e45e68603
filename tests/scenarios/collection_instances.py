"""Two .blends for the command line (tests/test_cli_instances.py). ``blend_out``: bolts
that are collection instances: a cube "Base" with a Subdivision Surface, the collection
"Bolts" (excluded from the view layer, as a kitbash library is) holding the UV sphere
"Bolt", and three empties instancing it at their own places, one of them scaled.
``shared_out``: one monkey mesh drawn by three objects: "Right", "Left" mirrored (scale
x -1) and "Tall" (scale z 4), a cube "Masked" whose Mask modifier leaves no faces, a
cylinder "Cutter" its Boolean modifier cuts with, a box "UCX_Right" (a collision mesh) and
"Right_LOD1", the file's own coarser monkey (a Decimate applied to a copy)."""
import bpy

from scene_tools import remove_all_objects

PLACES = ((-1.5, 0.0, 1.2), (0.0, 0.0, 1.2), (1.5, 0.0, 1.2))


def run(blend_out: str, shared_out: str = "") -> dict:
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
    made = {"bolt_triangles": len(bolt.data.loop_triangles)}
    if shared_out:
        remove_all_objects()
        bpy.ops.mesh.primitive_monkey_add(location=(1.5, 0.0, 0.0))
        right = bpy.context.active_object
        right.name = "Right"
        for name, location, scale in (("Left", (-1.5, 0.0, 0.0), (-1.0, 1.0, 1.0)),
                                      ("Tall", (0.0, 3.0, 0.0), (1.0, 1.0, 4.0))):
            ob = bpy.data.objects.new(name, right.data)
            ob.location, ob.scale = location, scale
            scene.collection.objects.link(ob)
        right.data.calc_loop_triangles()
        made["monkey_triangles"] = len(right.data.loop_triangles)
        bpy.ops.mesh.primitive_cube_add(size=0.5, location=(0.0, -3.0, 0.0))
        cube = bpy.context.active_object
        cube.name = "Masked"
        cube.vertex_groups.new(name="Nothing")
        cube.modifiers.new("Mask", 'MASK').vertex_group = "Nothing"
        # What a hard-surface or engine file keeps beside its parts: a Boolean cutter (of
        # the cube: the monkeys stay one mesh drawn three times) and a collision box.
        bpy.ops.mesh.primitive_cylinder_add(radius=0.1, depth=1.0, location=(0.0, -3.0, 0.0))
        cutter = bpy.context.active_object
        cutter.name, cutter.display_type = "Cutter", 'WIRE'
        hole = cube.modifiers.new("Hole", 'BOOLEAN')
        hole.object = cutter
        bpy.ops.mesh.primitive_cube_add(size=3.0, location=(1.5, 0.0, 0.0))
        bpy.context.active_object.name = "UCX_Right"
        # And the file's own coarser "Right", as an asset store ships it.
        own = bpy.data.objects.new("Right_LOD1", right.data.copy())
        own.location = right.location
        scene.collection.objects.link(own)
        own.modifiers.new("Decimate", 'DECIMATE').ratio = 0.5
        bpy.context.view_layer.objects.active = own
        bpy.ops.object.modifier_apply(modifier="Decimate")
        bpy.ops.wm.save_as_mainfile(filepath=shared_out)
    return made
