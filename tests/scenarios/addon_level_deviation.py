"""Where each LOD differs (issue 34 §3), on meshes built here: the heat map Deviation
Colors writes, the report's distance per material and painted region, Show Deviation and
Back, and the posed distance over the rig's own actions
(tests/test_addon_level_deviation.py checks what this returns)."""
import json
import math

import bpy
import numpy as np
from scene_tools import (array, capped_tube, empty_scene, extension_module, mesh_hash, parent_with_automatic_weights,
                         posed_triangles, select_only, three_bone_rig)

HILL = (0.5, 0.0)  # where the bump stands on the grid
HILL_RADIUS = 0.25  # the painted group "Hill": vertices this close to it


def bump_grid(n: int = 60):
    """A grid over [-1, 1]^2 with a narrow bump at HILL; faces right of x = 0.2 use the
    material "Bumpy", the others "Flat"; the vertex group "Hill" paints the bump (weight 1)."""
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n))
    z = 0.4 * np.exp(-((x - HILL[0]) ** 2 + (y - HILL[1]) ** 2) / 0.02)
    V = np.stack([x, y, z], -1).reshape(-1, 3)
    idx = np.arange(n * n).reshape(n, n)
    quads = np.stack([idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]], -1).reshape(-1, 4)
    me = bpy.data.meshes.new("Bump")
    me.from_pydata(V.tolist(), [], quads.tolist())
    me.update()
    ob = bpy.data.objects.new("Bump", me)
    bpy.context.scene.collection.objects.link(ob)
    for name in ("Flat", "Bumpy"):
        me.materials.append(bpy.data.materials.new(name))
    me.polygons.foreach_set("material_index", (V[quads].mean(1)[:, 0] > 0.2).astype(np.int32))
    ob.vertex_groups.new(name="Hill").add(
        np.flatnonzero(np.hypot(V[:, 0] - HILL[0], V[:, 1] - HILL[1]) < HILL_RADIUS).tolist(), 1.0, 'REPLACE')
    ob.vertex_groups.new(name="Unused")
    ob["note"] = "the source's own property"
    return ob


def state(ob) -> dict:
    """What must not change on a source: its geometry, attributes, groups, materials, props."""
    me = ob.data
    return {"hash": mesh_hash(me), "attributes": sorted(a.name for a in me.attributes),
            "colors": sorted(a.name for a in me.color_attributes), "active_color": me.color_attributes.active_color_name,
            "groups": [g.name for g in ob.vertex_groups], "materials": [m.name for m in me.materials],
            # (generating gives the source its switch numbers, lqlod_*: lod.commit, as always)
            "props": sorted(k for k in ob.keys() if not k.startswith("lqlod_")), "mesh_props": sorted(me.keys()), "modifiers": [m.type for m in ob.modifiers]}


def heat_of(mesh) -> dict:
    """The heat map a LOD mesh carries: its colour and distance attributes as arrays."""
    ld = extension_module("addon.pure.level_deviation")
    color = mesh.color_attributes.get(ld.HEAT_ATTRIBUTE)
    dist = mesh.attributes.get(ld.DISTANCE_ATTRIBUTE)
    out = {"color": None if color is None else (color.domain, color.data_type, len(color.data)),
           "distance": None if dist is None else (dist.domain, dist.data_type, len(dist.data)),
           "scale": mesh.get(ld.SCALE_PROPERTY)}
    if color is not None and dist is not None:
        out["rgba"] = array(color.data, "color", 4).reshape(-1, 4)
        out["d"] = array(dist.data, "value", 1)
    return out


def run_colors() -> dict:
    lod = extension_module("addon.lod")
    ld = extension_module("addon.pure.level_deviation")
    measure = extension_module("addon.pure.measure")
    empty_scene()
    ob = bump_grid()
    before = state(ob)
    result = {"vertices_source": len(ob.data.vertices)}

    # Generate through the operator, as the panel's button does, with Deviation Colors on.
    select_only(ob)
    result["generate"] = sorted(bpy.ops.object.line_quadric_lod(ratio=0.05, levels=2, deviation_colors=True))
    rep = json.loads(bpy.context.scene.line_quadric_lod.last_report)[0]
    generated = state(ob)
    result["levels"] = [{k: lv.get(k) for k in ("name", "triangles", "hausdorff_percent", "mean_percent",
                                                  "materials", "regions", "deviation_colors")}
                        for lv in rep["levels"]]
    V = array(ob.data.vertices, "co", 3).reshape(-1, 3).astype(float)
    ob.data.calc_loop_triangles()
    F = array(ob.data.loop_triangles, "vertices", 3, np.int32).reshape(-1, 3).astype(np.int64)
    diagonal = measure.bbox_diagonal(V, F)
    checks = []
    for lv in rep["levels"]:
        lod_ob = bpy.data.objects[lv["name"]]
        heat = heat_of(lod_ob.data)
        v = array(lod_ob.data.vertices, "co", 3).reshape(-1, 3).astype(float)
        lod_ob.data.calc_loop_triangles()
        f = array(lod_ob.data.loop_triangles, "vertices", 3, np.int32).reshape(-1, 3).astype(np.int64)
        d = heat["d"].astype(float)
        # Each vertex's own distance to the source surface (measure.closest_points).
        tri, bary = measure.closest_points(V, F, v)
        own = np.linalg.norm(np.einsum("kc,kcj->kj", bary, V[F[tri]]) - v, axis=1)
        r = np.hypot(v[:, 0] - HILL[0], v[:, 1] - HILL[1])
        expected_rgba = ld.heat_colors(d, heat["scale"])
        checks.append({
            "name": lv["name"], "vertices": len(lod_ob.data.vertices), "color": heat["color"],
            "distance": heat["distance"], "scale": heat["scale"], "max_d": float(d.max()),
            "below_own": float((own - d).max()),  # > 0: a vertex painted closer than it is
            # Far from the bump the LOD lies on the source: nothing raises those vertices.
            "far_equal_own": float(np.mean(np.abs(d - own)[r > 0.6] <= 1e-5 * diagonal)),
            "far_raise": float(np.max((d - own)[r > 0.6]) / heat["scale"]),
            "raised": float(np.mean(d > own + 1e-5 * diagonal)),
            "rgba_error": float(np.abs(heat["rgba"] - expected_rgba).max()),
            "hill_mean": float(d[r < HILL_RADIUS].mean()), "far_mean": float(d[r > 0.6].mean()),
            "hausdorff": lv["hausdorff_percent"] * diagonal / 100.0,
            "active_color": lod_ob.data.color_attributes.active_color_name,
        })
    result["checks"] = checks

    # The measurement's own points (keep_samples) change none of its numbers and are consistent.
    lod1 = bpy.data.objects[rep["levels"][0]["name"]]
    v1 = array(lod1.data.vertices, "co", 3).reshape(-1, 3).astype(float)
    f1 = array(lod1.data.loop_triangles, "vertices", 3, np.int32).reshape(-1, 3).astype(np.int64)
    plain = measure.surface_deviation(V, F, v1, f1, n_samples=(20_000, 5_000))
    kept = measure.surface_deviation(V, F, v1, f1, n_samples=(20_000, 5_000), keep_samples=True)
    s = kept.pop("sampled")
    same = {k: plain[k] == kept[k] for k in plain if not k.startswith("seconds")}
    src_points = np.einsum("kc,kcj->kj", s.src_bary, V[F[s.src_triangle]])
    on_lod = np.einsum("kc,kcj->kj", s.src_nearest_bary, v1[f1[s.src_nearest]])
    result["keep_samples"] = {
        "same": same, "mean_src": abs(float(s.src_distance.mean()) - kept["mean_src_to_dst"]),
        "mean_dst": abs(float(s.dst_distance.mean()) - kept["mean_dst_to_src"]),
        "closest": float(np.abs(np.linalg.norm(src_points - on_lod, axis=1) - s.src_distance).max()) / diagonal,
        "counts": [len(s.src_distance), len(s.dst_distance), len(s.dst_vertices)]}

    # Show Deviation on a LOD without the heat map: measured now, then shown.
    lod2 = bpy.data.objects[rep["levels"][1]["name"]]
    written = heat_of(lod2.data)
    lod2.data.color_attributes.remove(lod2.data.color_attributes[ld.HEAT_ATTRIBUTE])
    lod2.data.attributes.remove(lod2.data.attributes[ld.DISTANCE_ATTRIBUTE])
    del lod2.data[ld.SCALE_PROPERTY]
    spaces = [a.spaces.active for a in bpy.context.screen.areas if a.type == 'VIEW_3D']
    for space in spaces:
        space.shading.type, space.shading.color_type = 'MATERIAL', 'TEXTURE'
    select_only(ob)
    result["poll_on_source"] = bpy.ops.object.line_quadric_lod_show_deviation.poll()
    result["back_poll_before"] = bpy.ops.object.line_quadric_lod_deviation_back.poll()
    select_only(lod2)
    result["show"] = sorted(bpy.ops.object.line_quadric_lod_show_deviation())
    again = heat_of(lod2.data)
    result["show_heat"] = {"color": again["color"], "distance": again["distance"],
                           "median_diff": float(np.median(np.abs(again["d"] - written["d"]))) / written["scale"],
                           "scale_ratio": again["scale"] / written["scale"],
                           "corr": float(np.corrcoef(again["d"], written["d"])[0, 1])}
    result["shown"] = [(s.shading.type, s.shading.color_type) for s in spaces]
    result["active_after_show"] = lod2.data.color_attributes.active_color_name
    result["back_poll_after"] = bpy.ops.object.line_quadric_lod_deviation_back.poll()
    result["back"] = sorted(bpy.ops.object.line_quadric_lod_deviation_back())
    result["after_back"] = [(s.shading.type, s.shading.color_type) for s in spaces]
    result["source_changed_by_view"] = {k: [generated[k], v] for k, v in state(ob).items() if generated[k] != v}

    # The defaults (the command line's and the panel's): no heat map, the breakdown still there.
    result["default_setting"] = extension_module("addon.pure.settings").LodSettings().deviation_colors
    plain_rep = lod.generate_lods(bpy.context.scene, ob, extension_module("addon.pure.settings").LodSettings(
        ratio=0.05, levels=1))
    plain_lod = bpy.data.objects[plain_rep["levels"][0]["name"]]
    result["default_heat"] = heat_of(plain_lod.data)["color"]
    result["default_breakdown"] = sorted(k for k in ("materials", "regions", "deviation_colors")
                                         if k in plain_rep["levels"][0])
    # Two objects are one asset: a level's heat maps share one scale in scene units.
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.3, location=(3, 0, 0))
    ball = bpy.context.active_object
    ball.scale = (2.0, 2.0, 2.0)
    select_only(ob, ball)
    result["asset_generate"] = sorted(bpy.ops.object.line_quadric_lod(ratio=0.05, levels=2, deviation_colors=True))
    reps = json.loads(bpy.context.scene.line_quadric_lod.last_report)
    result["asset"] = [[{"world_scale": lv["deviation_colors"]["scale"] * max(bpy.data.objects[lv["name"]].scale),
                         "mesh_scale": bpy.data.objects[lv["name"]].data[ld.SCALE_PROPERTY],
                         "own_max": float(heat_of(bpy.data.objects[lv["name"]].data)["d"].max()),
                         "shared": lv["deviation_colors"].get("shared")} for lv in r["levels"]] for r in reps]
    result["source_changed"] = {k: [before[k], v] for k, v in state(ob).items() if before[k] != v}
    return result


def bend_rig(rig, name: str, angle: float, frames=(1, 12, 24)):
    """A new action ``name`` on ``rig``: Lower and Hand turn about x by 0, ``angle``, -angle/2."""
    action = bpy.data.actions.new(name)
    rig.animation_data.action = action
    for frame, a in zip(frames, (0.0, angle, -angle / 2)):
        for pb in rig.pose.bones[1:]:
            pb.rotation_mode = 'XYZ'
            pb.rotation_euler = (math.radians(a), 0.0, 0.0)
            pb.keyframe_insert("rotation_euler", frame=frame)
    return action


def run_posed() -> dict:
    lod = extension_module("addon.lod")
    measure = extension_module("addon.pure.measure")
    posed_deviation = extension_module("addon.posed_deviation")
    LodSettings = extension_module("addon.pure.settings").LodSettings
    empty_scene()
    rig = three_bone_rig()
    ob, _, _ = capped_tube("Tube", lambda z: 0.2 + 0.03 * np.sin(z * 2.1) ** 2, around=32, rings=60)
    result = {"parent": parent_with_automatic_weights(rig, ob)}
    settings = LodSettings(ratio=0.1, levels=2)

    rep = lod.generate_lods(bpy.context.scene, ob, settings)
    result["no_actions"] = [lv.get("posed") for lv in rep["levels"]]

    rig.animation_data_create()
    wave = bend_rig(rig, "Wave", -50.0, frames=(1, 6, 10))
    track = rig.animation_data.nla_tracks.new()
    track.strips.new("Wave", 1, wave)
    bend_rig(rig, "Bend", 70.0)
    scene = bpy.context.scene
    scene.frame_set(7)
    pose_before = [tuple(pb.rotation_euler) for pb in rig.pose.bones]
    before = {"frame": scene.frame_current, "action": rig.animation_data.action.name,
              "use_nla": rig.animation_data.use_nla, "tracks": len(rig.animation_data.nla_tracks)}
    rep = lod.generate_lods(bpy.context.scene, ob, settings)
    result["warnings"] = rep["warnings"]
    result["posed"] = [lv["posed"] for lv in rep["levels"]]
    result["rest"] = [lv["hausdorff_percent"] for lv in rep["levels"]]
    result["restored"] = {
        "frame": [before["frame"], scene.frame_current],
        "action": [before["action"], rig.animation_data.action.name],
        "use_nla": [before["use_nla"], rig.animation_data.use_nla],
        "tracks": [before["tracks"], len(rig.animation_data.nla_tracks)],
        "pose": float(np.abs(np.array(pose_before) - np.array([tuple(pb.rotation_euler)
                                                                for pb in rig.pose.bones])).max())}

    # An independent measurement of the largest "Bend" frame of LOD2: posed by hand.
    lod_ob = bpy.data.objects[rep["levels"][1]["name"]]
    rows = [r for r in rep["levels"][1]["posed"]["per_frame"] if r["action"] == "Bend"]
    worst = max(rows, key=lambda r: r["hausdorff_percent"])
    rig.animation_data.use_nla = False
    scene.frame_set(worst["frame"])
    src, low = posed_triangles(ob), posed_triangles(lod_ob)
    # 16 frames in all (8 of each action): each frame samples a 16th of the report's.
    n = (posed_deviation.posed_samples(len(src[1]), frames=16), posed_deviation.posed_samples(len(low[1]), frames=16))
    again = measure.surface_deviation(*src, *low, n_samples=n, vertex_limit=max(n))
    rest_v = array(ob.data.vertices, "co", 3).reshape(-1, 3).astype(float)
    ob.data.calc_loop_triangles()
    rest_f = array(ob.data.loop_triangles, "vertices", 3, np.int32).reshape(-1, 3)
    result["independent"] = {"reported": worst["hausdorff_percent"],
                             "measured": again["hausdorff"] * 100.0 / measure.bbox_diagonal(rest_v, rest_f),
                             "moved": float(np.abs(src[0] - rest_v).max())}
    rig.animation_data.use_nla = True
    result["rigid"] = rigid_part()
    return result


def rigid_part() -> dict:
    """A bumpy tube skinned wholly to one bone ("Lower", weight 1), played by "Turn" (the
    bone turns 60 degrees: the tube moves as one rigid body) and "Grow" (it turns and
    grows 1.5 times at frame 11)."""
    lod = extension_module("addon.lod")
    LodSettings = extension_module("addon.pure.settings").LodSettings
    empty_scene()
    rig = three_bone_rig()
    ob, _, _ = capped_tube("Part", lambda z: 0.2 + 0.05 * np.sin(z * 7.0) ** 2, around=24, rings=40)
    group = ob.vertex_groups.new(name="Lower")
    group.add(list(range(len(ob.data.vertices))), 1.0, 'REPLACE')
    ob.modifiers.new("Armature", 'ARMATURE').object = rig
    ob.parent = rig
    rig.animation_data_create()
    pb = rig.pose.bones["Lower"]
    pb.rotation_mode = 'XYZ'
    for name, scale in (("Grow", 1.5), ("Turn", 1.0)):
        rig.animation_data.action = bpy.data.actions.new(name)
        for frame, angle, s in ((1, 0.0, 1.0), (11, 60.0, scale), (24, -30.0, 1.0)):
            pb.rotation_euler = (math.radians(angle), 0.0, 0.0)
            pb.scale = (s, s, s)
            pb.keyframe_insert("rotation_euler", frame=frame)
            pb.keyframe_insert("scale", frame=frame)
    track = rig.animation_data.nla_tracks.new()
    track.strips.new("Grow", 1, bpy.data.actions["Grow"])
    rep = lod.generate_lods(bpy.context.scene, ob, LodSettings(ratio=0.25, levels=2))
    return {"warnings": rep["warnings"],
            "rest": [{"hausdorff_percent": lv["hausdorff_percent"], "mean_percent": lv["mean_percent"]}
                     for lv in rep["levels"]],
            "posed": [lv["posed"] for lv in rep["levels"]]}


def run(which: str) -> dict:
    return run_colors() if which == "colors" else run_posed()
