"""Custom split normals carried to the LODs (issue 22 §3): a foliage-style sphere whose
normals all point up, and a cube whose flat faces come from custom normals alone
(tests/test_addon_custom_normals.py checks what this returns)."""
import bpy
import numpy as np
from scene_tools import extension_module, remove_all_objects


def corner_normals(mesh) -> np.ndarray:
    out = np.empty(3 * len(mesh.loops))
    mesh.corner_normals.foreach_get("vector", out)
    return out.reshape(-1, 3)


def lod_of(ob, **settings):
    lod = extension_module("addon.lod")
    report = lod.generate_lods(bpy.context, ob, lod.LodSettings(levels=1, measure_deviation=False, **settings))
    return bpy.data.objects[report["levels"][0]["name"]]


def run() -> dict:
    result = {}
    remove_all_objects()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16)
    sphere = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    # Foliage cards and tree crowns are lit with normals pointing up, not their own.
    sphere.data.normals_split_custom_set([(0.0, 0.0, 1.0)] * len(sphere.data.loops))
    lod = lod_of(sphere, ratio=0.25)
    normals = corner_normals(lod.data)
    result["up"] = {"has_custom": lod.data.has_custom_normals, "triangles": len(lod.data.polygons),
                    "largest_angle": float(np.degrees(np.arccos(np.clip(normals[:, 2], -1, 1))).max())}

    remove_all_objects()
    bpy.ops.mesh.primitive_cube_add()
    bpy.ops.object.modifier_add(type='SUBSURF')
    cube = bpy.context.active_object
    cube.modifiers[0].subdivision_type = 'SIMPLE'
    cube.modifiers[0].levels = 3
    bpy.ops.object.modifier_apply(modifier=cube.modifiers[0].name)
    bpy.ops.object.shade_smooth()
    mesh = cube.data
    # Flat shading from custom normals only: each corner gets its face's normal, no sharp edges.
    face_normals = np.empty(3 * len(mesh.polygons))
    mesh.polygons.foreach_get("normal", face_normals)
    loop_face = np.repeat(np.arange(len(mesh.polygons)), [p.loop_total for p in mesh.polygons])
    mesh.normals_split_custom_set(face_normals.reshape(-1, 3)[loop_face].tolist())
    lod = lod_of(cube, ratio=0.1, feature_angle=0.0)
    lod_mesh = lod.data
    lod_normals = corner_normals(lod_mesh)
    tri_normals = np.empty(3 * len(lod_mesh.polygons))
    lod_mesh.polygons.foreach_get("normal", tri_normals)
    lod_loop_face = np.repeat(np.arange(len(lod_mesh.polygons)), [p.loop_total for p in lod_mesh.polygons])
    # Each LOD corner's normal against its own triangle's: flat shading kept means ~0 degrees.
    cos = np.einsum("ij,ij->i", lod_normals, tri_normals.reshape(-1, 3)[lod_loop_face])
    angles = np.degrees(np.arccos(np.clip(cos, -1, 1)))
    result["flat"] = {"has_custom": lod_mesh.has_custom_normals, "triangles": len(lod_mesh.polygons),
                      "mean_angle": float(angles.mean()), "largest_angle": float(angles.max())}

    # Hard Edges: a smooth-shaded cube without sharp edges or custom normals.
    remove_all_objects()
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    bpy.ops.object.modifier_add(type='SUBSURF')
    cube.modifiers[0].subdivision_type = 'SIMPLE'
    cube.modifiers[0].levels = 3
    bpy.ops.object.modifier_apply(modifier=cube.modifiers[0].name)
    bpy.ops.object.shade_smooth()
    for angle in (0.0, 30.0):
        lod_mesh = lod_of(cube, ratio=0.2, hard_edge_angle=angle).data
        attr = lod_mesh.attributes.get("sharp_edge")
        sharp = np.zeros(len(lod_mesh.edges), dtype=bool)
        if attr is not None:
            attr.data.foreach_get("value", sharp)
        ends = np.empty(2 * len(lod_mesh.edges), dtype=np.int64)
        lod_mesh.edges.foreach_get("vertices", ends)
        co = np.empty(3 * len(lod_mesh.vertices))
        lod_mesh.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)[ends.reshape(-1, 2)[sharp]]  # (k, 2, 3)
        on_cube_edge = (np.abs(np.abs(co) - 1.0) < 1e-5).sum(axis=2) >= 2  # two coordinates at +-1
        result[f"hard_{angle:g}"] = {"sharp": int(sharp.sum()), "on_cube_edges": int(on_cube_edge.all(axis=1).sum())}
    return result
