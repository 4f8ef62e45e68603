"""Several objects as one asset (issue 32 §1) through LodJob, the checkout's addon
(tests/test_addon_asset.py checks what this returns; runs without the extension installed).

The asset: a hull (a UV sphere of radius 2), two instances of one dense bolt (an ico
sphere of radius 0.05, 1,280 triangles) on it, and a decal (one quad, 2 triangles). Each
run starts from that scene; ``job`` names what it ran.
"""
import bpy
import numpy as np

from addon import job as job_mod
from addon import lod
from addon.pure._core import core
from scene_tools import drawn_triangles, mesh_hash, remove_all_objects


def build(painted: bool = False, masked: bool = False, helpers: bool = False) -> list:
    """The asset's objects; ``painted``: the hull's top (z > 1) painted 1 in a vertex group
    "Face", fading to 0 at z = 0.4 (a region a painted limit holds); ``masked``: also a cube
    "Masked" whose Mask modifier (an empty vertex group) leaves no faces; ``helpers``: also
    what a hard-surface or engine file keeps beside its parts, all selected: a cylinder
    "Cutter" that a Boolean modifier of the hull cuts a hole with (shown as a wire, as
    cutters are, but not disabled in renders), a box "Proxy" disabled in renders, a box
    "UCX_Hull" (a collision mesh by Unreal's naming) and "Hull_LOD1", the file's own
    coarser hull (by the _LOD<k> naming of engines and asset stores)."""
    remove_all_objects()
    for me in list(bpy.data.meshes):
        bpy.data.meshes.remove(me)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=2.0)
    hull = bpy.context.active_object
    hull.name = "Hull"
    if painted:
        co = np.array([v.co for v in hull.data.vertices])
        weight = np.clip((co[:, 2] - 0.4) / 0.6, 0.0, 1.0)
        group = hull.vertex_groups.new(name="Face")
        for value in np.unique(weight[weight > 0]):  # one call per distinct weight
            group.add([int(i) for i in np.flatnonzero(weight == value)], float(value), 'REPLACE')
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=4, radius=0.05, location=(2.0, 0.0, 0.3))
    bolt = bpy.context.active_object
    bolt.name = "Bolt"
    bolt.data.name = "BoltMesh"
    other = bpy.data.objects.new("Bolt2", bolt.data)
    other.location = (-2.0, 0.0, 0.3)
    bpy.context.scene.collection.objects.link(other)
    bpy.ops.mesh.primitive_plane_add(size=0.3, location=(0.0, 2.05, 0.0))
    decal = bpy.context.active_object
    decal.name = "Decal"
    if helpers:
        bpy.ops.mesh.primitive_cylinder_add(vertices=16, radius=0.3, depth=6.0)
        cutter = bpy.context.active_object
        cutter.name, cutter.display_type = "Cutter", 'WIRE'
        hole = hull.modifiers.new("Hole", 'BOOLEAN')
        hole.object, hole.operation = cutter, 'DIFFERENCE'
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, -4.0, 0.0))
        proxy = bpy.context.active_object
        proxy.name, proxy.hide_render = "Proxy", True
        bpy.ops.mesh.primitive_cube_add(size=4.0)
        collision = bpy.context.active_object
        collision.name = "UCX_Hull"
        bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8, radius=2.0)
        bpy.context.active_object.name = "Hull_LOD1"
        return [hull, bolt, other, decal, cutter, proxy, collision, bpy.context.active_object]
    if not masked:
        return [hull, bolt, other, decal]
    bpy.ops.mesh.primitive_cube_add(size=0.5, location=(0.0, -3.0, 0.0))
    cube = bpy.context.active_object
    cube.name = "Masked"
    cube.vertex_groups.new(name="Nothing")
    cube.modifiers.new("Mask", 'MASK').vertex_group = "Nothing"
    return [hull, bolt, other, decal, cube]


def triangles(ob) -> int:
    ob.data.calc_loop_triangles()
    return len(ob.data.loop_triangles)


def run_job(painted: bool = False, masked: bool = False, helpers: bool = False, **settings) -> dict:
    objects = build(painted, masked, helpers)
    names = [ob.name for ob in objects]
    hashes = {ob.name: mesh_hash(ob.data) for ob in objects}
    source_triangles = {ob.name: triangles(ob) for ob in objects}
    out = {"names": names, "source_triangles": source_triangles,
           "drawn_triangles": {ob.name: drawn_triangles(ob) for ob in objects}}
    try:
        job = job_mod.LodJob(bpy.context, objects, lod.LodSettings(**settings))
        out["together"] = job.together()
        out["skipped"] = job.skipped
        fractions = []
        # How many core runs over how many meshes the job makes (one run for the asset,
        # or one per part).
        runs = out["core_runs"] = []
        real = core.simplify_chain

        def counted(vertices, faces, *args, **kwargs):
            runs.append(len(faces))
            return real(vertices, faces, *args, **kwargs)
        core.simplify_chain = counted
        try:
            job.run(progress=fractions.append)
        finally:
            core.simplify_chain = real
        reports = job.commit(bpy.context)
    except lod.LodError as ex:
        out["error"] = str(ex)
        return out
    out["fraction_monotonic"] = all(b >= a for a, b in zip(fractions, fractions[1:]))
    out["asset"] = job.asset_report
    out["unchanged"] = all(mesh_hash(bpy.data.objects[n].data) == h for n, h in hashes.items())
    out["reports"] = {r["object"]: {"levels": [{k: v for k, v in lev.items() if k != "importance"}
                                              for lev in r["levels"]],
                                    "warnings": r["warnings"], "switch": r["switch"]} for r in reports}
    out["lods"] = {}
    for r in reports:
        chain = []
        for lev in r["levels"]:
            ob = bpy.data.objects[lev["name"]]
            chain.append({"triangles": triangles(ob), "mesh": ob.data.name,
                          "switch": ob.get("lqlod_switch_distance"), "scale": max(ob.matrix_world.to_scale())})
        out["lods"][r["object"]] = chain
    out["source_switch"] = {n: bpy.data.objects[n].get("lqlod_switch_distance") for n in names}
    corners = np.concatenate([np.array([bpy.data.objects[n].matrix_world @ __import__("mathutils").Vector(c)
                                        for c in bpy.data.objects[n].bound_box]) for n in names])
    out["asset_diagonal"] = float(np.linalg.norm(corners.max(0) - corners.min(0)))
    out["world_scale"] = {n: float(max(bpy.data.objects[n].matrix_world.to_scale())) for n in names}
    return out


def split_by_curves(**settings) -> dict:
    """run_job with the budget split by each part's error curve, each part run alone (the
    way painted limits and Source Armature take)."""
    job_mod.ONE_RUN = False
    try:
        return run_job(**settings)
    finally:
        job_mod.ONE_RUN = True


# Far levels: at the last the hull has about 20 triangles and its collapses cost more
# than twice a bolt's size (core: a part leaves before such a collapse).
FAR = (0.5, 0.05, 0.015, 0.006)


def run() -> dict:
    return {
        "asset": run_job(ratios=(0.5, 0.25, 0.125)),
        "asset_split": split_by_curves(ratios=(0.5, 0.25, 0.125)),
        "far_split": split_by_curves(ratios=FAR, measure_deviation=False),
        "asset_unmeasured": run_job(ratios=(0.5, 0.25, 0.125), measure_deviation=False),
        "per_part": run_job(ratios=(0.5, 0.25, 0.125), asset_budget=False),
        "deviation": run_job(max_deviations=((1.0, True), (4.0, True))),
        # A bound nothing coarser than the asset meets: a note on the asset, not on a part.
        "deviation_tight": run_job(max_deviations=((0.0001, True),)),
        "deviation_per_part": run_job(max_deviations=((1.0, True), (4.0, True)), asset_budget=False,
                                      measure_deviation=False),
        "too_small": run_job(triangle_counts=(10_000,)),
        "far": run_job(ratios=FAR, measure_deviation=False),
        "far_kept": run_job(ratios=FAR, measure_deviation=False, remove_small_components=False),
        # The hull's top held to 0.1 px where each level switches in: the split by error
        # curves sees the limit, so the asset still draws its budget.
        "limit_pixels": run_job(painted=True, ratios=(0.5, 0.25, 0.125), limit_group="Face",
                                limit_distance=0.1, limit_unit='PIXELS'),
        # Importance painted on the hull alone (the other parts have no such group): still
        # one run for the asset, by ratios and by deviation.
        "importance_one_part": run_job(painted=True, ratios=(0.5, 0.25, 0.125), importance_source='VERTEX_GROUP',
                                       importance_group="Face", measure_deviation=False),
        "importance_one_part_deviation": run_job(painted=True, max_deviations=((1.0, True), (4.0, True)),
                                                 importance_source='VERTEX_GROUP', importance_group="Face"),
        "importance_no_part_painted": run_job(ratios=(0.5,), importance_source='VERTEX_GROUP',
                                              importance_group="Face", measure_deviation=False),
        # A cube whose Mask modifier leaves no faces: the asset goes on without it.
        "masked": run_job(masked=True, ratios=(0.5, 0.25, 0.125), measure_deviation=False),
        # A Boolean cutter, a box disabled in renders and a collision box, selected with
        # the parts: the asset goes on without them.
        "helpers": run_job(helpers=True, ratios=(0.5, 0.25, 0.125), measure_deviation=False),
        "named_lods": named_lods(),
    }


def named_lods() -> dict:
    """lod.scene_helpers' reasons for objects named as engines and asset stores name their
    levels (stand-ins with a name, a type, no modifiers and no custom properties), one a
    run made ("Gear_LOD1", marked) beside its source, and an empty "Rock"."""
    class Named(dict):
        def __init__(self, name, kind='MESH', **props):
            super().__init__(props)
            self.name, self.type, self.modifiers = name, kind, ()

    names = ["Chair", "Chair_LOD1", "Chair LOD2", "chair.lod3", "Rock_LOD1", "Tree_LOD0", "TreeLOD1",
             "Tree_LOD2", "Gear_LOD0", "Cup_LOD10"]
    made = Named("Gear_LOD1", **{lod.lod_objects.LEVEL_PROP: 1})
    group = Named("Rock", 'EMPTY')  # an FBX's LOD group: no level 0 of Rock_LOD1
    return lod.scene_helpers([Named(n) for n in names] + [made, group])
