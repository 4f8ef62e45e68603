"""Objects sharing one mesh (instances) through LodJob, the checkout's addon.job and
addon.lod (tests/test_addon_instances.py checks what this returns; runs without the
extension installed).

The scene: the mesh "Part" (a UV sphere with two materials, a UV map, a vertex group and
a shape key) used by A, B (scaled, an object-linked material), C (parented to an Empty,
in a collection of its own), F (a Subdivision modifier switched off in the viewport: the
same evaluated input), D (a Subdivision modifier on: its own input) and E (other
settings); Solo has its own mesh, a copy of Part (equal geometry, another datablock).
Before anything else the scene without D, E, F and B's object material is saved as a
.blend for the command-line test (``blend_out``).

Steps: a cancelled job, a job run but never committed and a commit that fails midway
change nothing; then the job is run and committed (counting lod.compute and
core.simplify_chain calls, and the observer's groups); then run again (replacing).
"""

import bpy
import numpy as np

from addon import job as job_mod
from addon import lod
from addon.pure._core import core
from addon.pure.settings import LodCancelled
from scene_tools import array, commit_after_cancel, diff, mesh_hash

RATIOS = (0.5, 0.25)
OTHER_RATIOS = (0.4, 0.2)
ORDER = ["A", "Solo", "B", "D", "C", "E", "F"]


def data_state() -> dict:
    """Every data-block's name, and what the sources are and use."""
    state = {name: sorted(x.name for x in getattr(bpy.data, name))
             for name in ("objects", "meshes", "collections", "shape_keys", "materials")}
    state["sources"] = {name: {"mesh": ob.data.name, "users": ob.data.users, "hash": mesh_hash(ob.data),
                               "matrix": [list(r) for r in ob.matrix_world],
                               "slots": [(s.link, s.material.name if s.material else None) for s in ob.material_slots],
                               # (commit writes its switch numbers on a measured chain's source, "lqlod_*")
                               "props": sorted(k for k in ob.keys() if not k.startswith("lqlod_"))}
                        for name, ob in bpy.data.objects.items() if ob.type == 'MESH' and "lod_level" not in ob}
    return state


def build_scene(blend_out: str):
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    for me in list(bpy.data.meshes):
        bpy.data.meshes.remove(me)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1.0)
    a = bpy.context.active_object
    a.name = "A"
    part = a.data
    part.name = "Part"
    for name in ("Grey", "Blue"):
        part.materials.append(bpy.data.materials.new(name))
    centers = array(part.polygons, "center", 3).reshape(-1, 3)
    part.polygons.foreach_set("material_index", (centers[:, 2] > 0.3).astype(np.int32))
    co = array(part.vertices, "co", 3).reshape(-1, 3)
    a.vertex_groups.new(name="Top").add(np.flatnonzero(co[:, 2] > 0.5).tolist(), 0.75, 'REPLACE')
    a.shape_key_add(name="Basis")
    bulge = a.shape_key_add(name="Bulge")
    bulge.data.foreach_set("co", (co * 1.1).astype(np.float32).ravel())
    a["asset_id"] = 7

    def instance(name, location, mesh=None):
        ob = bpy.data.objects.new(name, mesh or part)
        ob.location = location
        scene.collection.objects.link(ob)
        return ob

    b = instance("B", (4.0, 0.0, 0.0))
    b.rotation_euler = (0.3, 0.0, 1.2)
    b.scale = (2.0, 2.0, 2.0)
    b["asset_id"] = 8
    holder = bpy.data.objects.new("Holder", None)
    holder.location = (0.0, 6.0, 1.0)
    holder.rotation_euler = (0.0, 0.0, 0.5)
    parts = bpy.data.collections.new("Parts")
    scene.collection.children.link(parts)
    parts.objects.link(holder)
    c = bpy.data.objects.new("C", part)
    parts.objects.link(c)
    c.parent = holder
    c.location = (1.0, 1.0, 1.0)
    c.scale = (0.5, 0.5, 0.5)
    solo_mesh = part.copy()
    solo_mesh.name = "SoloMesh"
    instance("Solo", (-4.0, 0.0, 0.0), solo_mesh)
    bpy.context.view_layer.update()
    if blend_out:
        bpy.ops.wm.save_as_mainfile(filepath=blend_out, copy=True)

    red = bpy.data.materials.new("Red")
    b.material_slots[0].link = 'OBJECT'
    b.material_slots[0].material = red
    d = instance("D", (0.0, -4.0, 0.0))
    d.modifiers.new("Subdivision", 'SUBSURF').levels = 1
    instance("E", (0.0, 0.0, 4.0))
    f = instance("F", (0.0, 0.0, -4.0))
    off = f.modifiers.new("Subdivision", 'SUBSURF')
    off.levels = 1
    off.show_viewport = False
    bpy.context.view_layer.update()


class Counting(job_mod.ObjectObserver):
    def __init__(self):
        self.started_names, self.finished_count = [], 0

    def started(self, lod_input):
        self.started_names.append(lod_input.source_name)

    def finished(self, lod_output):
        self.finished_count += 1


def objects_and_settings():
    objects = [bpy.data.objects[name] for name in ORDER]
    settings = [lod.LodSettings(ratios=OTHER_RATIOS if ob.name == "E" else RATIOS) for ob in objects]
    return objects, settings


def parent_of(collection) -> str:
    """The name of the collection ``collection`` is a child of ("Scene Collection" for the scene's)."""
    if collection.name in bpy.context.scene.collection.children:
        return "Scene Collection"
    return next((p.name for p in bpy.data.collections if collection.name in p.children), None)


def lod_info(ob, pointer_ids: dict) -> dict:
    me = ob.data
    return {
        "name": ob.name,
        "mesh": me.name,
        "mesh_id": pointer_ids.setdefault(me.as_pointer(), len(pointer_ids)),
        "users": me.users,
        "triangles": sum(len(p.vertices) - 2 for p in me.polygons),
        "parent": ob.parent.name if ob.parent else None,
        "collections": [c.name for c in ob.users_collection],
        "collection_parents": [parent_of(c) for c in ob.users_collection],
        "lod_source": ob.get("lod_source"),
        "lod_level": ob.get("lod_level"),
        "asset_id": ob.get("asset_id"),
        "slots": [(s.link, s.material.name if s.material else None) for s in ob.material_slots],
        "mesh_materials": [m.name if m else None for m in me.materials],
        "groups": ob.vertex_groups.keys(),
        "shape_keys": me.shape_keys.key_blocks.keys() if me.shape_keys else [],
        "switch_distance": ob.get("lqlod_switch_distance"),
    }


def matrix_gap(a, b) -> float:
    return float(np.abs(np.array(a.matrix_world) - np.array(b.matrix_world)).max())


def run(blend_out: str = "") -> dict:
    result = {}
    build_scene(blend_out)
    compute_calls, simplify_calls = [], []
    real_compute, real_simplify = lod.compute, core.simplify_chain

    def counting_compute(lod_input, progress=None):
        compute_calls.append(lod_input.source_name)
        return real_compute(lod_input, progress)

    def counting_simplify(*args, **kwargs):
        simplify_calls.append(len(args[0]))
        return real_simplify(*args, **kwargs)

    lod.compute = counting_compute
    core.simplify_chain = counting_simplify
    try:
        before = data_state()

        # 1. Cancelled: commit raises before touching anything.
        objects, settings = objects_and_settings()
        job = job_mod.LodJob(bpy.context, objects, settings)
        result["groups"] = job.groups
        result["inputs"] = [i.source_name for i in job.inputs]
        result["cancel_raised"] = commit_after_cancel(job, LodCancelled)
        result["cancel_changes"] = diff(before, data_state())

        # 2. Run to the end but never committed.
        objects, settings = objects_and_settings()
        job = job_mod.LodJob(bpy.context, objects, settings)
        job.run()
        result["uncommitted_changes"] = diff(before, data_state())

        # 3. A commit failing midway (an instance renamed since the run): everything built goes.
        bpy.data.objects["C"].name = "C_moved"
        try:
            job.commit(bpy.context)
            result["failed_commit_raised"] = None
        except lod.LodError as ex:
            result["failed_commit_raised"] = str(ex)
        bpy.data.objects["C_moved"].name = "C"
        result["failed_commit_changes"] = diff(before, data_state())
        result["orphan_meshes_after_failure"] = [m.name for m in bpy.data.meshes if m.users == 0]

        # 4. Run and commit, counting the core runs.
        del compute_calls[:], simplify_calls[:]
        objects, settings = objects_and_settings()
        observer = Counting()
        fractions = []
        job = job_mod.LodJob(bpy.context, objects, settings)
        job.run(progress=fractions.append, observer=observer)
        reports = job.commit(bpy.context)
        bpy.context.view_layer.update()
        result["compute_calls"] = list(compute_calls)
        result["simplify_calls"] = list(simplify_calls)
        result["observer_started"] = observer.started_names
        result["observer_finished"] = observer.finished_count
        result["fraction_monotonic"] = all(b >= a for a, b in zip(fractions, fractions[1:]))
        result["fraction_end"] = job.fraction
        result["reports"] = [{key: rep.get(key) for key in ("object", "collection", "source_mesh", "seconds",
                                                            "shares", "shared_with", "warnings")}
                             | {"levels": [{key: lv.get(key) for key in ("name", "mesh", "seconds", "triangles",
                                                                           "switch_distance", "hausdorff_percent")}
                                           for lv in rep["levels"]]}
                             for rep in reports]
        pointer_ids = {}
        lods = {}
        for name in ORDER:
            source = bpy.data.objects[name]
            chain = sorted((ob for ob in bpy.data.objects if ob.get("lod_source") == name), key=lambda o: o["lod_level"])
            lods[name] = [dict(lod_info(ob, pointer_ids), matrix_gap=matrix_gap(ob, source),
                               source_collection=source.users_collection[0].name) for ob in chain]
        result["lods"] = lods
        result["source_mesh_ids"] = {name: pointer_ids.setdefault(bpy.data.objects[name].data.as_pointer(),
                                                                   len(pointer_ids)) for name in ORDER}
        after = data_state()
        result["sources_changed"] = {name: diff(before["sources"][name], after["sources"][name])
                                     for name in before["sources"]
                                     if before["sources"][name] != after["sources"].get(name)}
        result["new_meshes"] = sorted(set(after["meshes"]) - set(before["meshes"]))

        # 5. Again: the earlier LODs (and their shared meshes) are replaced, names kept.
        objects, settings = objects_and_settings()
        job = job_mod.LodJob(bpy.context, objects, settings)
        job.run()
        job.commit(bpy.context)
        result["rerun_meshes"] = sorted(m.name for m in bpy.data.meshes if "_LOD" in m.name)
        result["rerun_objects"] = sorted(ob.name for ob in bpy.data.objects if "lod_level" in ob)
        result["orphan_meshes"] = [m.name for m in bpy.data.meshes if m.users == 0]
        result["rerun_part_lod_users"] = [getattr(bpy.data.meshes.get(f"Part_LOD{k}"), "users", None)
                                          for k in (1, 2)]
    finally:
        lod.compute = real_compute
        core.simplify_chain = real_simplify
    return result
