"""Custom split normals carried to the LODs (issue 22 §3): a foliage-style sphere whose
normals all point up, and a cube whose flat faces come from custom normals alone; and
the report's shading-normal deviation, against the same LODs with their normals
dropped and against Blender's own normals of the LODs
(tests/test_addon_custom_normals.py checks what this returns)."""
import bpy
import numpy as np
from scene_tools import extension_module, remove_all_objects


def corner_normals(mesh) -> np.ndarray:
    out = np.empty(3 * len(mesh.loops))
    mesh.corner_normals.foreach_get("vector", out)
    return out.reshape(-1, 3)


def sharp_edge_ends(mesh) -> np.ndarray:
    """(k, 2, 3) the end positions of the mesh's edges marked sharp."""
    attr = mesh.attributes.get("sharp_edge")
    sharp = np.zeros(len(mesh.edges), dtype=bool)
    if attr is not None:
        attr.data.foreach_get("value", sharp)
    ends = np.empty(2 * len(mesh.edges), dtype=np.int64)
    mesh.edges.foreach_get("vertices", ends)
    co = np.empty(3 * len(mesh.vertices))
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)[ends.reshape(-1, 2)[sharp]]


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

    result["deviation"] = normal_deviations()
    result["dangling"] = dangling_sharp_chain()

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
        co = sharp_edge_ends(lod_of(cube, ratio=0.2, hard_edge_angle=angle).data)
        on_cube_edge = (np.abs(np.abs(co) - 1.0) < 1e-5).sum(axis=2) >= 2  # two coordinates at +-1
        result[f"hard_{angle:g}"] = {"sharp": len(co), "on_cube_edges": int(on_cube_edge.all(axis=1).sum())}
    return result


def dangling_sharp_chain() -> dict:
    """A smooth sphere with sharp edges along half a meridian, from the pole to the
    equator: a crease that ends inside its smoothing region. The LOD's sharp edges, and
    how many lie on that meridian's half plane."""
    remove_all_objects()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16)
    ob = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    mesh = ob.data
    co = np.empty(3 * len(mesh.vertices))
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    ends = np.empty(2 * len(mesh.edges), dtype=np.int64)
    mesh.edges.foreach_get("vertices", ends)
    ends = ends.reshape(-1, 2)
    on_half = (np.abs(co[:, 1]) < 1e-6) & (co[:, 0] > -1e-6) & (co[:, 2] > -1e-6)
    mesh.edges.foreach_set("use_edge_sharp", on_half[ends].all(axis=1))
    source_sharp = int(on_half[ends].all(axis=1).sum())
    co = sharp_edge_ends(lod_of(ob, ratio=0.5).data)
    on_plane = (np.abs(co[:, :, 1]) < 0.05).all(axis=1)  # the sphere's segments are 0.2 apart
    return {"source_sharp": source_sharp, "sharp": len(co), "on_meridian": int(on_plane.sum())}


def normal_deviations() -> dict:
    """Per source: the report's normal deviation of its 25 % LOD, the same measured with
    Blender's corner normals of the LOD as built, and with the LOD's custom normals
    dropped (reset to what Blender computes from its smooth flags and sharp edges)."""
    lod_module = extension_module("addon.lod")
    mesh_io = extension_module("addon.mesh_io")
    measure = extension_module("addon.pure.measure")
    deviation_search = extension_module("addon.pure.deviation_search")
    out = {}
    for name in ("up", "weighted", "by_angle", "split"):
        remove_all_objects()
        if name == "split":  # faceted by split vertices, as exported assets are: no sharp edges, no custom normals
            bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)
            ob = bpy.context.active_object
            bpy.ops.object.shade_smooth()
            split = ob.modifiers.new("split", 'EDGE_SPLIT')
            split.split_angle = 0.0
            bpy.ops.object.modifier_apply(modifier="split")
        elif name == "up":  # the foliage sphere
            bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16)
            ob = bpy.context.active_object
            bpy.ops.object.shade_smooth()
            ob.data.normals_split_custom_set([(0.0, 0.0, 1.0)] * len(ob.data.loops))
        else:  # a bevelled box: Weighted Normal shading, or smooth with hard edges by angle
            bpy.ops.mesh.primitive_cube_add()
            ob = bpy.context.active_object
            ob.scale = (1.0, 0.6, 0.4)
            bpy.ops.object.transform_apply(scale=True)
            bevel = ob.modifiers.new("bevel", 'BEVEL')
            bevel.width, bevel.segments = 0.08, 3
            bpy.ops.object.modifier_apply(modifier="bevel")
            sub = ob.modifiers.new("sub", 'SUBSURF')
            sub.subdivision_type, sub.levels = 'SIMPLE', 2
            bpy.ops.object.modifier_apply(modifier="sub")
            if name == "weighted":
                bpy.ops.object.shade_smooth()
                weighted = ob.modifiers.new("weighted", 'WEIGHTED_NORMAL')
                weighted.keep_sharp = True
                bpy.ops.object.modifier_apply(modifier="weighted")
            else:
                bpy.ops.object.shade_smooth_by_angle(angle=np.radians(30.0))
        report = lod_module.generate_lods(bpy.context, ob, lod_module.LodSettings(levels=1, ratio=0.25))
        level = report["levels"][0]
        lod_mesh = bpy.data.objects[level["name"]].data
        source, lod = mesh_io.read_mesh(ob.data), mesh_io.read_mesh(lod_mesh)

        def against_source(normals):
            return measure.normal_deviation(source.vertices, source.faces, source.corner_normals,
                                            lod.vertices, lod.faces, normals,
                                            n_samples=int(deviation_search.SOURCE_SHARE
                                                          * deviation_search.report_samples(len(source.faces))))

        entry = {"has_custom": lod_mesh.has_custom_normals,
                 "report": [level[k] for k in ("normal_mean_degrees", "normal_p95_degrees")],
                 "blender": [against_source(lod.corner_normals)[k] for k in ("normal_mean_degrees",
                                                                            "normal_p95_degrees")]}
        if lod_mesh.has_custom_normals:
            lod_object = bpy.data.objects[level["name"]]
            with bpy.context.temp_override(object=lod_object, active_object=lod_object):
                bpy.ops.mesh.customdata_custom_splitnormals_clear()
            dropped = mesh_io.read_mesh(lod_mesh)
            entry["dropped_has_custom"] = lod_mesh.has_custom_normals
            entry["dropped"] = [against_source(dropped.corner_normals)[k] for k in ("normal_mean_degrees",
                                                                                   "normal_p95_degrees")]
        if name == "split":  # faceted like the source: each corner's normal is its face's
            face_normals = np.empty(3 * len(lod_mesh.polygons))
            lod_mesh.polygons.foreach_get("normal", face_normals)
            loop_face = np.repeat(np.arange(len(lod_mesh.polygons)), [p.loop_total for p in lod_mesh.polygons])
            cos = np.einsum("ij,ij->i", corner_normals(lod_mesh), face_normals.reshape(-1, 3)[loop_face])
            entry["facet_angle"] = float(np.degrees(np.arccos(np.clip(cos, -1, 1))).max())
        out[name] = entry
    return out
