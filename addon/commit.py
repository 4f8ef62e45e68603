# SPDX-License-Identifier: GPL-3.0-or-later
"""The commit phase of a LOD run (addon/lod.py): write each LodOutput's LOD meshes and
objects into the scene (main thread).

Everything is built unlinked first and removed again if anything fails, so the scene is
either untouched or has the whole result; then each source's earlier LODs are replaced,
the new ones named and linked into "<source>_LODs", their switch numbers set, normals
baked if asked for, and skinned chains measured posed over the rig's actions.
"""
from __future__ import annotations

from typing import Optional

import bpy

from . import animation
from . import asset as asset_set
from . import bake
from . import lod_objects
from . import mesh_io
from . import posed_deviation
from . import vertex_groups
from .pure import limits
from .pure import measure
from .pure import switch_distances
from .pure.settings import LodError
from .rig import armature_of

_TRANSFORM_PROPS = ("rotation_mode", "location", "rotation_euler", "rotation_quaternion",
                    "rotation_axis_angle", "scale", "delta_location", "delta_rotation_euler",
                    "delta_rotation_quaternion", "delta_scale")
_ARMATURE_MOD_PROPS = ("object", "use_vertex_groups", "use_bone_envelopes", "use_deform_preserve_volume",
                       "use_multi_modifier", "vertex_group", "invert_vertex_group", "show_viewport",
                       "show_render")


def commit(context_or_scene, outputs: list, sources: Optional[list] = None,
           switch: Optional[dict] = None) -> list:
    """Write the LOD objects of each output and link them (main thread).

    ``sources``: the object (or its name) each output is for; by default each output's own
    source (``out.input.source_name``). An output given for several objects (the very same
    LodOutput, e.g. LodJob's for objects sharing one mesh) is written once: its LOD meshes
    are built for the first of them and every one of them gets LOD objects of its own
    (names, transform, parent, collection, object-linked materials, custom properties as
    for any source) that use those meshes.

    Everything is built unlinked first; if anything fails, what was built is removed
    and the scene is untouched. Then each source's earlier LODs are replaced.
    ``switch``: one set of switch numbers (switch_distances.switch_data) for every chain,
    an asset's (addon/asset.py), instead of each chain's own.
    Returns one report dict per entry of ``outputs``; the report of an object sharing
    another's LOD meshes names them (``levels[i]["mesh"]``, ``shared_with``), says whose
    entry has the time (``shares``) and has ``seconds`` 0 (levels' too), so times add up.
    """
    scene, _ = mesh_io.scene_and_depsgraph(context_or_scene)
    if sources is None:
        names = [out.input.source_name for out in outputs]
    else:
        if len(sources) != len(outputs):
            raise ValueError(f"{len(sources)} sources for {len(outputs)} outputs")
        names = [getattr(s, "name", s) for s in sources]
    group_names = {}  # id(output) -> names of the objects it is written for, in order
    for out, name in zip(outputs, names):
        group_names.setdefault(id(out), []).append(name)
    built = _build(outputs, names, group_names)
    _remove_earlier(built)
    reports = []
    posed = []  # measured skinned chains (posed_deviation.Chain)
    for source, out, objects, leader in built:
        group = group_names[id(out)]
        coll = _link(scene, source, objects, leader, len(group))
        levels = [dict(entry, name=lod.name, mesh=lod.data.name) for entry, lod in zip(out.reports, objects)]
        if leader is not None:  # computed once, for the group's first object: its entry has the time
            for entry in levels:
                entry["seconds"] = 0.0
        data = out.input.data
        warnings = list(out.input.warnings)
        chain_switch = _switch_numbers(source, out, objects, levels, switch, warnings)
        if out.input.settings.bake_normals and leader is None:
            # (Into copies of the LOD's materials: the objects sharing its meshes show the
            # mesh-linked ones; LodJob does not share meshes when baking.)
            warnings.extend(bake.bake_chain(
                bpy.context, source, objects, levels, out.input.settings.bake_resolution,
                measure.bbox_diagonal(data.vertices, data.faces)))
        rep = {
            "object": source.name,
            "collection": coll.name,
            "source_mesh": source.data.name,
            "source_triangles": int(len(data.faces)),
            "source_vertices": int(len(data.vertices)),
            "seconds": float(out.seconds) if leader is None else 0.0,
            "levels": levels,
            "switch": chain_switch,
            "warnings": warnings,
            # The other objects whose LOD objects use the same LOD meshes (made once).
            "shared_with": [name for name in group if name != source.name],
        }
        if leader is not None:
            rep["shares"] = leader  # whose LOD meshes these are, and whose entry has the time
        elif out.input.settings.measuring() and armature_of(source) is not None:
            posed.append(posed_deviation.Chain(
                source, objects, levels, measure.bbox_diagonal(data.vertices, data.faces), out.input.part_samples,
                [(data.vertices, data.faces)] + [(level.vertices, level.faces) for level in out.levels]))
        reports.append(rep)
    if posed:  # over the rig's own actions (addon/posed_deviation.py), once the LODs are in the scene
        try:
            posed_deviation.measure_chains(scene, lambda: mesh_io.scene_and_depsgraph(context_or_scene)[1], posed)
        except Exception as ex:  # the LODs are made: a failed extra measurement is a note
            for source, *_ in posed:
                next(r for r in reports if r["object"] == source.name)["warnings"].append(
                    f"the posed distance was not measured ({type(ex).__name__}: {ex})")
    return reports


def _build(outputs: list, names: list, group_names: dict) -> list:
    """Every output's LOD objects, built unlinked for the object of its name: [(source,
    output, its LOD objects, name of the group's first object or None)]. The LOD meshes of
    an output are built for the first object given it and used by the others' objects.
    If anything fails, what was built is removed and the error raised."""
    built = []  # (source, output, its LOD objects, name of the group's first object or None)
    lod_meshes = {}  # id(output) -> its LOD meshes, built for the first object given it
    made = []  # every mesh built, removed again if anything fails
    try:
        for out, name in zip(outputs, names):
            source = bpy.data.objects.get(name)
            if source is None:
                raise LodError(f'the object "{name}" no longer exists')
            meshes = lod_meshes.get(id(out))
            first = meshes is None
            if first:
                meshes = lod_meshes[id(out)] = []
            objects = []
            built.append((source, out, objects, None if first else group_names[id(out)][0]))
            for k, level in enumerate(out.levels, start=1):
                # (A level repeating the one before, an asset's part that cannot get
                # coarser, uses its mesh.)
                new = first and not (k > 1 and level is out.levels[k - 2])
                if new:
                    mesh = mesh_io.build_mesh(f"{source.name}_LOD{k}", level)
                    made.append(mesh)
                    meshes.append(mesh)
                elif first:
                    meshes.append(meshes[-1])
                mesh = meshes[k - 1]
                lod = bpy.data.objects.new(f"{source.name}_LOD{k}.tmp", mesh)
                objects.append(lod)
                if new:  # both are the mesh's (vertex group names too, since Blender 3.0)
                    mesh_io.add_vertex_groups(lod, level)
                    mesh_io.add_shape_keys(lod, level)
                    # (A curve's keys move its points, not the LOD's vertices: not carried.)
                    animation.copy_animation(source.data.shape_keys if source.type == 'MESH' else None,
                                             mesh.shape_keys)
                _copy_setup(source, lod, k, mesh_too=new)
                animation.copy_animation(source, lod)
    except BaseException:
        for _, _, objects, _ in built:
            for lod in objects:
                bpy.data.objects.remove(lod)
        for mesh in made:
            if mesh.users == 0:
                vertex_groups.remove_mesh(mesh)
        raise
    return built


def _remove_earlier(built: list) -> None:
    """Replace every source's earlier LODs (never an object being written for).

    Every source's earlier LODs go before any new one is named, so that a LOD mesh several
    of them shared is gone (no users left) when the new shared mesh takes its name."""
    keep = {ob.as_pointer() for _, _, objects, _ in built for ob in objects}
    keep |= {source.as_pointer() for source, _, _, _ in built}  # never remove an object being written for
    earlier = lod_objects.lods_by_source()
    for source, _, _, _ in built:
        for old in earlier.get(source.name, []):
            if old.as_pointer() not in keep:
                _replace_lod(old)


def _link(scene, source, objects: list, leader: Optional[str], group_size: int):
    """Name ``source``'s new LOD objects (and their meshes, when ``leader`` is None: they
    are this object's own) and link them into its LOD collection, which is returned."""
    coll = _lod_collection(scene, source)
    for k, lod in enumerate(objects, start=1):
        lod.name = f"{source.name}_LOD{k}"
        if leader is None and not (k > 1 and lod.data is objects[k - 2].data):
            # Named as its LOD object, or when several objects' LODs use it, after the
            # source mesh they all share: "<mesh>_LOD<k>".
            lod.data.name = lod.name if group_size == 1 else f"{source.data.name}_LOD{k}"
        coll.objects.link(lod)
    return coll


def _switch_numbers(source, out, objects: list, levels: list, asset_switch: Optional[dict],
                    warnings: list) -> Optional[dict]:
    """Set the chain's switch numbers on the source and its LOD objects and into each
    level's entry, and return the report's ``switch`` (LOD0's numbers as ``lod0``), or
    None; ``asset_switch``: the asset's one set, else the chain's own (why there are none
    goes into ``warnings``)."""
    if asset_switch is not None:  # one set for the asset, each part switching with it
        switch, why_not = asset_switch, None
    else:
        switch, why_not = _switch_data(source, out)  # per object: its world scale
    per_level = switch_distances.per_level(switch)[:len(objects) + 1] if switch else [None] * (len(objects) + 1)
    for ob, numbers in zip([source] + objects, per_level):
        lod_objects.set_switch_props(ob, numbers)
    if switch:
        for entry, numbers in zip(levels, per_level[1:]):
            entry.update(numbers)
        switch = {key: value for key, value in switch.items() if key not in switch_distances.PER_LEVEL_KEYS}
        switch["lod0"] = per_level[0]
    if why_not:
        warnings.append(why_not)
    return switch


def _copy_setup(source, lod, level: int, mesh_too: bool = True) -> None:
    """Give the new LOD object ``lod`` its source's place (its parent, transform and
    constraints), materials, custom properties and Armature modifiers. ``mesh_too``: also
    fill its mesh's material list (False for a LOD mesh another instance's LOD object
    already set up: the list is the mesh's, shared)."""
    lod.parent = source.parent
    lod.parent_type = source.parent_type
    if source.parent_type == 'BONE':
        lod.parent_bone = source.parent_bone
    lod.matrix_parent_inverse = source.matrix_parent_inverse.copy()
    for prop in _TRANSFORM_PROPS:
        setattr(lod, prop, getattr(source, prop))
    for constraint in source.constraints:  # a Child Of or Copy Transforms that places the source
        lod.constraints.copy(constraint)

    materials = source.data.materials
    if mesh_too:
        for i in range(len(source.material_slots)):
            lod.data.materials.append(materials[i] if i < len(materials) else None)
    for i, slot in enumerate(source.material_slots):
        if slot.link == 'OBJECT':
            lod.material_slots[i].link = 'OBJECT'
            lod.material_slots[i].material = slot.material

    for key in source.keys():
        if key in (lod_objects.SOURCE_PROP, lod_objects.LEVEL_PROP) or key.startswith(lod_objects.SWITCH_PROP_PREFIX):
            continue
        value = source[key]
        lod[key] = value.to_dict() if hasattr(value, "to_dict") else (
            value.to_list() if hasattr(value, "to_list") else value)
        try:
            lod.id_properties_ui(key).update(**source.id_properties_ui(key).as_dict())
        except TypeError:  # values without UI data (groups, ID pointers)
            pass
    lod[lod_objects.SOURCE_PROP] = source.name
    lod[lod_objects.LEVEL_PROP] = level

    for md in source.modifiers:
        if md.type == 'ARMATURE' and md.object is not None:
            new = lod.modifiers.new(md.name, 'ARMATURE')
            for prop in _ARMATURE_MOD_PROPS:
                setattr(new, prop, getattr(md, prop))


def _remove_object_and_mesh(ob) -> None:
    mesh = ob.data if ob.type == 'MESH' else None
    bpy.data.objects.remove(ob)
    if mesh is not None and mesh.users == 0:
        vertex_groups.remove_mesh(mesh)


def _replace_lod(ob) -> None:
    """Remove an earlier run's LOD, with the material copies and images its bake made
    once nothing uses them (they would stay behind as orphans, and push the new copies'
    names to .001); materials and images not made by a bake are never removed."""
    baked = bake.baked_materials(ob)  # read before the object and its mesh go
    _remove_object_and_mesh(ob)
    bake.remove_unused(baked)


def _lod_collection(scene, source):
    """The collection "<source>_LODs", made and linked into the scene (beside the source) if need be."""
    name = f"{source.name}_LODs"
    coll = bpy.data.collections.get(name)
    if coll is None:
        coll = bpy.data.collections.new(name)
    if not lod_objects.in_scene(coll, scene):
        parent = next((c for c in source.users_collection if lod_objects.in_scene(c, scene)), scene.collection)
        parent.children.link(coll)
    return coll


def _switch_data(source, out) -> tuple:
    """(switch_distances.chain_switch_data of the chain, or None, and why not)."""
    if not all("hausdorff_percent" in entry for entry in out.reports):
        return None, None  # nothing measured (Measure Deviation off), nothing to say
    try:
        percent = [0.0] + [limits.switch_percent(entry) for entry in out.reports]
        data = out.input.data
        settings = out.input.settings
        return switch_distances.chain_switch_data(
            percent, data.vertices, data.faces, asset_set.world_scale(source), pixel_error=settings.pixel_error,
            screen_height=settings.screen_height, vertical_fov_degrees=settings.vertical_fov), None
    except ValueError as ex:
        return None, f"no switch distances: {ex}"
