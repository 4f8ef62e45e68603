"""A studio's .blend files for the command line (tests/test_cli_blend_files.py), and what
the command line wrote.

``make``: under ``root``, ``assets/rocks.blend`` holds the collection "Rocks" with the
sphere "Rock", textured with ``assets/textures/rock.png`` at a relative path;
``shots/shot.blend`` links "Rock" itself into its scene, instances "Rocks" with the empty
"RockInstance" (so a local copy named "Rock" comes beside the linked one) and has a local
textured cube "Crate" (``shots/textures/crate.png``, relative). ``inspect``: opens
``blend`` and returns its objects (name, whether linked, triangles), its images and
libraries (the path as stored and whether it exists)."""
import os

import bpy

from scene_tools import empty_scene


def _textured(ob, image_path: str) -> None:
    image = bpy.data.images.new(os.path.basename(image_path), 8, 8)
    image.filepath_raw = image_path
    image.file_format = 'PNG'
    image.save()
    material = bpy.data.materials.new(ob.name)
    material.use_nodes = True
    node = material.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = image
    material.node_tree.links.new(node.outputs[0], material.node_tree.nodes["Principled BSDF"].inputs[0])
    ob.data.materials.append(material)


def make(root: str) -> dict:
    assets, shots = os.path.join(root, "assets"), os.path.join(root, "shots")
    for folder in (os.path.join(assets, "textures"), os.path.join(shots, "textures")):
        os.makedirs(folder, exist_ok=True)
    empty_scene()
    rocks = bpy.data.collections.new("Rocks")
    bpy.context.scene.collection.children.link(rocks)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16)
    rock = bpy.context.active_object
    rock.name = "Rock"
    for coll in list(rock.users_collection):
        coll.objects.unlink(rock)
    rocks.objects.link(rock)
    _textured(rock, os.path.join(assets, "textures", "rock.png"))
    library = os.path.join(assets, "rocks.blend")
    bpy.ops.wm.save_as_mainfile(filepath=library, relative_remap=True)
    bpy.ops.file.make_paths_relative()
    bpy.ops.wm.save_mainfile()

    empty_scene()
    with bpy.data.libraries.load(library, link=True, relative=True) as (_, linked):
        linked.collections = ["Rocks"]
    rocks = linked.collections[0]
    bpy.context.scene.collection.objects.link(rocks.objects["Rock"])
    instance = bpy.data.objects.new("RockInstance", None)
    instance.instance_type = 'COLLECTION'
    instance.instance_collection = rocks
    instance.location = (3.0, 0.0, 0.0)
    bpy.context.scene.collection.objects.link(instance)
    bpy.ops.mesh.primitive_cube_add(location=(-3.0, 0.0, 0.0))
    crate = bpy.context.active_object
    crate.name = "Crate"
    crate.modifiers.new("Subdivision", 'SUBSURF').levels = 2
    _textured(crate, os.path.join(shots, "textures", "crate.png"))
    shot = os.path.join(shots, "shot.blend")
    bpy.ops.wm.save_as_mainfile(filepath=shot)
    bpy.ops.file.make_paths_relative()
    bpy.ops.wm.save_mainfile()
    return inspect(shot)


def inspect(blend: str) -> dict:
    bpy.ops.wm.open_mainfile(filepath=blend)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    objects = {}
    for ob in bpy.context.scene.objects:
        if ob.type == 'MESH':
            mesh = ob.evaluated_get(depsgraph).to_mesh()
            mesh.calc_loop_triangles()
            objects[ob.name] = {"linked": ob.library is not None, "triangles": len(mesh.loop_triangles)}
            ob.evaluated_get(depsgraph).to_mesh_clear()
    paths = lambda ids: {i.name: [i.filepath, os.path.exists(bpy.path.abspath(i.filepath, library=i.library))]
                         for i in ids if i.filepath}
    return {"objects": objects, "images": paths(bpy.data.images), "libraries": paths(bpy.data.libraries)}


def run(mode: str, root: str = "", blend: str = "") -> dict:
    return make(root) if mode == "make" else inspect(blend)
