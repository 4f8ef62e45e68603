"""Normal maps baked onto the LODs (issue 22 §3): a bumpy UV sphere with one material,
its LODs with Bake Normals on (tests/test_addon_bake.py checks what this returns)."""
import bpy
import numpy as np
from scene_tools import extension_module, remove_all_objects


def run(resolution: int = 64) -> dict:
    remove_all_objects()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32)
    src = bpy.context.active_object
    bumps = src.modifiers.new("bumps", 'DISPLACE')
    bumps.texture = bpy.data.textures.new("bumps", 'CLOUDS')
    bumps.texture.noise_scale = 0.25
    bumps.strength = 0.15
    bpy.ops.object.modifier_apply(modifier="bumps")
    bpy.ops.object.shade_smooth()
    material = bpy.data.materials.new("Stone")
    material.use_nodes = True
    src.data.materials.append(material)
    nodes_before = len(material.node_tree.nodes)

    lod = extension_module("addon.lod")
    settings = lod.LodSettings(levels=2, ratio=0.1, bake_normals=True, bake_resolution=resolution)
    # Twice: the second run replaces the first's LODs, removed in the same call as the bake.
    lod.generate_lods(bpy.context, src, settings)
    report = lod.generate_lods(bpy.context, src, settings)
    result = {"warnings": report["warnings"], "source_material": src.data.materials[0].name,
              "source_nodes_unchanged": len(material.node_tree.nodes) == nodes_before, "lods": []}
    for level in report["levels"]:
        ob = bpy.data.objects[level["name"]]
        mat = ob.data.materials[0]
        images = [n.image for n in mat.node_tree.nodes if n.type == 'TEX_IMAGE' and n.image]
        bsdf = next(n for n in mat.node_tree.nodes if n.type == 'BSDF_PRINCIPLED')
        linked = bsdf.inputs["Normal"].is_linked and bsdf.inputs["Normal"].links[0].from_node.type == 'NORMAL_MAP'
        pixels = np.array(images[0].pixels[:]).reshape(-1, 4)[:, :3] if images else np.zeros((1, 3))
        result["lods"].append({"material": mat.name, "images": [i.name for i in images],
                               "size": list(images[0].size) if images else None,
                               "packed": bool(images and images[0].packed_file),
                               "normal_linked": linked, "pixel_std": float(pixels.std(axis=0)[:2].mean()),
                               "mean_blue": float(pixels[:, 2].mean())})
    return result
