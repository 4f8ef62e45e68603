"""Normal maps baked onto the LODs (issue 22 §3): a bumpy UV sphere with one material,
its LODs with Bake Normals on (tests/test_addon_bake.py checks what this returns).

Also what a bake leaves behind: a second run replaces the first's LODs, and must take
their material copies and images along unless something else uses them; a bake that
fails or is interrupted must leave no copy either; an object-linked slot gets its copy."""
import bpy
import numpy as np
from scene_tools import extension_module, remove_all_objects


def bumpy_sphere(name: str, material_name: str, object_link: bool = False):
    """A smooth bumpy UV sphere (UVs from the primitive) with one node material."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32)
    src = bpy.context.active_object
    src.name = name
    bumps = src.modifiers.new("bumps", 'DISPLACE')
    bumps.texture = bpy.data.textures.new("bumps", 'CLOUDS')
    bumps.texture.noise_scale = 0.25
    bumps.strength = 0.15
    bpy.ops.object.modifier_apply(modifier="bumps")
    bpy.ops.object.shade_smooth()
    material = bpy.data.materials.new(material_name)
    material.use_nodes = True
    src.data.materials.append(material)
    if object_link:
        src.material_slots[0].link = 'OBJECT'
        src.material_slots[0].material = material
    return src, material


def describe_lod(ob) -> dict:
    """The material the LOD's first slot shows, its baked image and whether it is used."""
    mat = ob.material_slots[0].material
    images = [n.image for n in mat.node_tree.nodes if n.type == 'TEX_IMAGE' and n.image]
    bsdf = next(n for n in mat.node_tree.nodes if n.type == 'BSDF_PRINCIPLED')
    linked = bsdf.inputs["Normal"].is_linked and bsdf.inputs["Normal"].links[0].from_node.type == 'NORMAL_MAP'
    pixels = np.array(images[0].pixels[:]).reshape(-1, 4)[:, :3] if images else np.zeros((1, 3))
    return {"material": mat.name, "images": [i.name for i in images],
            "size": list(images[0].size) if images else None,
            "packed": bool(images and images[0].packed_file), "slot_link": ob.material_slots[0].link,
            "normal_linked": linked, "pixel_std": float(pixels.std(axis=0)[:2].mean()),
            "mean_blue": float(pixels[:, 2].mean())}


def unused() -> dict:
    """Names of the materials and images nothing uses (what File > Clean Up would purge)."""
    return {"materials": sorted(m.name for m in bpy.data.materials if m.users == 0),
            "images": sorted(i.name for i in bpy.data.images if i.users == 0)}


def marked(bake) -> dict:
    """Names of the materials and images a bake made (they carry bake.BAKED_PROP)."""
    return {"materials": sorted(m.name for m in bpy.data.materials if bake.BAKED_PROP in m),
            "images": sorted(i.name for i in bpy.data.images if bake.BAKED_PROP in i)}


def rebake(lod, bake, settings) -> dict:
    """Two runs on one source; between them the artist puts LOD1's baked copy on an
    object of their own and makes a material nothing uses yet."""
    src, material = bumpy_sphere("Sphere", "Stone")
    nodes_before = len(material.node_tree.nodes)
    first = lod.generate_lods(bpy.context, src, settings)
    first_lods = [describe_lod(bpy.data.objects[level["name"]]) for level in first["levels"]]
    bpy.ops.mesh.primitive_cube_add(location=(5, 0, 0))
    bpy.context.active_object.data.materials.append(bpy.data.materials[first_lods[0]["material"]])
    bpy.data.materials.new("Spare")  # the artist's, no users yet: never ours to remove
    # The second run replaces the first's LODs, removed in the same call as the bake.
    report = lod.generate_lods(bpy.context, src, settings)
    return {"warnings": report["warnings"], "source_material": src.data.materials[0].name,
            "source_nodes_unchanged": len(material.node_tree.nodes) == nodes_before,
            "first_lods": first_lods, "lods": [describe_lod(bpy.data.objects[level["name"]])
                                               for level in report["levels"]],
            "materials": sorted(m.name for m in bpy.data.materials),
            "images": sorted(i.name for i in bpy.data.images), "unused": unused(), "marked": marked(bake)}


def failing(lod, bake, settings) -> dict:
    """Bakes Blender refuses (one ends CANCELLED, one raises its error), then one stopped
    by Ctrl-C: each LOD keeps the source's material, no copy or image stays."""
    src, _ = bumpy_sphere("Failing", "Clay")
    real, outcomes = bake._cycles_bake, iter([{'CANCELLED'}, RuntimeError("Error: simulated failure\n")])

    def refused(ob, distance):
        outcome = next(outcomes)
        if isinstance(outcome, Exception):
            raise outcome
        return outcome

    def interrupted(ob, distance):
        raise KeyboardInterrupt

    try:
        bake._cycles_bake = refused
        report = lod.generate_lods(bpy.context, src, settings)
        after_refused = {"warnings": report["warnings"], "unused": unused(), "marked": marked(bake),
                         "lod_materials": [bpy.data.objects[level["name"]].material_slots[0].material.name
                                           for level in report["levels"]]}
        bake._cycles_bake = interrupted
        try:
            lod.generate_lods(bpy.context, src, settings)
            raised = False
        except KeyboardInterrupt:
            raised = True
    finally:
        bake._cycles_bake = real
    return {"refused": after_refused, "interrupted_raised": raised,
            "interrupted": {"unused": unused(), "marked": marked(bake)}}


def object_linked(lod, bake, settings) -> dict:
    """A source whose slot is linked to the object: the LOD's object slot gets the copy
    (Cycles bakes into the material a slot shows), the source's material is untouched."""
    src, material = bumpy_sphere("Linked", "Moss", object_link=True)
    nodes_before = len(material.node_tree.nodes)
    report = lod.generate_lods(bpy.context, src, settings)
    return {"warnings": report["warnings"], "source_nodes_unchanged": len(material.node_tree.nodes) == nodes_before,
            "lods": [describe_lod(bpy.data.objects[level["name"]]) for level in report["levels"]]}


def run(resolution: int = 64) -> dict:
    remove_all_objects()
    bpy.data.orphans_purge(do_recursive=True)  # the start-up file's unused data is not ours to check
    lod = extension_module("addon.lod")
    bake = extension_module("addon.bake")
    settings = lod.LodSettings(levels=2, ratio=0.1, bake_normals=True, bake_resolution=resolution)
    result = rebake(lod, bake, settings)
    remove_all_objects()  # each case on its own: then its unused and marked data are its own
    bpy.data.orphans_purge(do_recursive=True)
    result["failing"] = failing(lod, bake, settings)
    result["object_linked"] = object_linked(lod, bake, settings)
    return result
