# SPDX-License-Identifier: GPL-3.0-or-later
"""Generate a LOD chain for a mesh object: read, simplify with the core, write, link.

No UI here (operators, the command line and tests all call it). Bad input raises
:class:`LodError` with a message meant for the user; a cancelled run raises
:class:`LodCancelled`. Either way the scene is left as it was: all LOD meshes and
objects are built first and linked into the scene only when every one of them exists.

Three phases, so a caller can run the expensive middle one in a worker thread:
    prepare(context, obj, settings) -> LodInput      main thread: reads Blender data
    compute(lod_input, progress)    -> LodOutput     any thread: NumPy and the core only
    commit(context, [outputs])      -> [report]      main thread: writes Blender data
                                                     (an output given for several objects
                                                     sharing a mesh: LOD meshes made once)
:func:`generate_lods` chains them for one object.
"""
from __future__ import annotations

import dataclasses
from typing import Callable, Optional

import numpy as np

import bpy

from .pure._core import core
from . import asset as asset_set
from . import bake
from .pure import deviation_targets
from .pure import key_deviation
from .pure import limits
from .pure import measure
from . import mesh_io
from . import object_importance
from . import posed_deviation
from . import rig
from .pure import switch_distances
from . import vertex_groups
from .pure.compute import compute
from .pure.options import mesh_options
from .pure.phases import LodInput
from .pure.settings import LodError, LodSettings
from .pure.skin_fit import CHECK_POSES

SOURCE_PROP = "lod_source"  # custom property on a LOD: the name of the object it was made from
LEVEL_PROP = "lod_level"  # custom property on a LOD: 1..n (the source is LOD0)
# Custom properties on every object of a measured chain (the source too), one per key of
# switch_distances.PER_LEVEL_KEYS: "lqlod_switch_distance", "lqlod_unity_transition_height", ...
# The FBX exporter writes them (Custom Properties), the glTF hook (gltf_lod.py) reads them.
SWITCH_PROP_PREFIX = "lqlod_"
# ----------------------------------------------------------------------------- prepare


def check_source(source) -> None:
    """LodError unless ``source`` is a mesh object in Object Mode (prepare's first checks)."""
    if source is None or getattr(source, "type", None) != 'MESH':
        name = getattr(source, "name", source)
        raise LodError(f'"{name}" is not a mesh object')
    if source.mode == 'EDIT':
        raise LodError(f'"{source.name}" is in Edit Mode: switch to Object Mode first')


def shared_mesh_key(source, settings: LodSettings):
    """What objects whose LODs would be identical have in common (their mesh datablock's
    pointer), or None for an object whose LODs must be made on their own.

    Two objects with the same key and equal settings give prepare() equal inputs, so one
    compute() serves both and commit() can give both the same LOD meshes: prepare reads
    such an object through its mesh datablock alone (mesh_io.read_object without the
    modifier stack: its vertices, faces, attributes, vertex groups and shape keys are the
    mesh's, whichever object uses it), and nothing else it reads belongs to the object.
    Kept apart, because the object itself shapes the input or its LODs:
      * geometry modifiers that the settings evaluate (Use Modifiers): the input is the
        object's evaluated mesh, which its own stack makes;
      * an armature (modifier or parent): the skin columns, Source Armature's sample poses
        (placed by the object's matrix relative to the rig) and the LOD's own Armature
        modifier come from the object;
      * Bake Normals: each LOD gets its own baked material copies, made on its mesh.
    """
    if getattr(source, "type", None) != 'MESH' or source.data is None:
        return None
    if settings.use_modifiers and mesh_io.has_geometry_modifiers(source):
        return None
    if rig.armature_of(source) is not None or settings.importance_source in ('ARMATURE', 'ARMATURE_PAPER'):
        return None
    if settings.bake_normals:
        return None
    return source.data.as_pointer()


def prepare(context_or_scene, source, settings: LodSettings, chain_labels: tuple = (),
            asset: Optional[asset_set.Asset] = None, keys_optional: bool = False) -> LodInput:
    """Check the input and read everything the run needs from Blender (main thread).
    ``chain_labels``: how a message about the explicit chain names its ratios and triangle
    counts (LodSettings.targets; the command line: "--ratios", "--faces"). ``asset``: the
    asset ``source`` is a part of (addon/asset.py): a chain by triangles gets its targets
    from the asset's budget later (LodJob), deviations are relative to the asset.
    ``keys_optional``: ``source`` is one of several objects (LodJob): with Source Shape
    Keys, a mesh without shape keys is made without importance and gets NO_KEYS_NOTE
    rather than an error (LodJob raises one when none of the objects has keys)."""
    check_source(source)
    settings.validate()
    _, depsgraph = mesh_io.scene_and_depsgraph(context_or_scene)
    data, warnings = mesh_io.read_object(source, depsgraph, settings.use_modifiers)
    if len(data.vertices) == 0:
        raise LodError(f'"{source.name}" has an empty mesh')
    if len(data.faces) == 0:
        raise LodError(f'"{source.name}" has no faces, only vertices or edges: there is nothing to simplify')
    deviations = reference = None
    if asset is not None:
        # Scene units through the object's scale into its own: the same distance for every part.
        scale = asset_set.world_scale(source)
        if scale <= 0:
            raise LodError(f'"{source.name}" has a zero scale')
        reference = asset.diagonal / scale
        targets = []  # a chain by triangles: the asset budget's share, set by LodJob
        if settings.deviation_chain() is not None:
            deviations = [d / scale for d in settings.deviations(asset.diagonal)]
            # The search's rungs; none for a part too small to search (kept whole).
            targets = deviation_targets.ladder(len(data.faces))
    else:
        targets = settings.targets(len(data.faces), *chain_labels)
        if settings.deviation_chain() is not None:
            deviations = settings.deviations(measure.bbox_diagonal(data.vertices, data.faces))
    if keys_optional and settings.importance_source == 'SHAPE_KEYS' and not data.shape_keys:
        g = None
        warnings.append(object_importance.NO_KEYS_NOTE)
    else:
        g = object_importance.importance_of(source, settings, data.group_names, data.group_weights,
                        lambda: key_deviation.offsets_of(data))
    if g is not None and settings.importance_source == 'SHAPE_KEYS' and not np.any(g > 0):
        warnings.append("no shape key moves any vertex: Source Shape Keys has nothing to keep")
    poses = check_poses = None
    if settings.importance_source == 'ARMATURE' and settings.importance_strength > 0:
        every = rig.sample_poses(source, data.group_names, core.skinning.SAMPLE_POSES + CHECK_POSES)
        poses, check_poses = every[:core.skinning.SAMPLE_POSES], every[core.skinning.SAMPLE_POSES:]
    skin_columns = rig.deform_columns(source, data.group_names)[1] if data.group_names else []
    options, names = mesh_options(settings, data, skin_columns, g, poses)
    limit = painted_limit(source, settings, data, reference, asset is not None, warnings)
    if limit is not None and limit[1] is not None:  # (pixels: per level, from a first run: compute)
        column, value, _ = limit
        options = core.Options.of(options, vertex_max_error=limits.vertex_limits(data.group_weights[:, column], value))
    return LodInput(source.name, dataclasses.replace(settings), data, targets, options, names, warnings,
                    importance=None if g is None or settings.importance_strength <= 0 else np.asarray(g),
                    deviations=deviations, poses=poses, check_poses=check_poses, in_asset=asset is not None,
                    reference_diagonal=reference,
                    material_names=[s.material.name if s.material else None for s in source.material_slots],
                    limit=limit)


def painted_limit(source, settings: LodSettings, data: mesh_io.MeshData, reference: Optional[float],
                  in_asset: bool, warnings: list) -> Optional[tuple]:
    """The settings' painted limit for ``source`` (addon/pure/limits.py): (column, L in the
    object's units or None for pixels, object to scene units), or None without a Limit
    Group. A group the object lacks is a LodError, or for a part of an asset a note (the
    part is free); ``reference``: the asset's diagonal in the object's units (None: its
    own)."""
    name = settings.limit_group
    if not name:
        return None
    if settings.limit_unit == 'PIXELS' and settings.deviation_chain() is not None:
        raise LodError("a Limit in pixels goes with triangle targets (each LOD's switch distance comes "
                       "from its measured error); with Deviation or Screen Size targets give it in % "
                       "or scene units")
    if name not in data.group_names:
        if in_asset:
            warnings.append(f'no vertex group "{name}": no painted limit on this part')
            return None
        raise LodError(f'"{source.name}" has no vertex group "{name}" (Limit Group)')
    column = list(data.group_names).index(name)
    if not np.any(data.group_weights[:, column] > limits.MIN_WEIGHT):
        warnings.append(f'the Limit Group "{name}" is empty: no painted limit')
        return None
    scale = asset_set.world_scale(source) if in_asset else 1.0
    if settings.limit_unit == 'PIXELS':
        return column, None, scale
    diagonal = reference if reference is not None else measure.bbox_diagonal(data.vertices, data.faces)
    value = limits.limit_in_mesh_units(settings.limit_distance, settings.limit_unit == 'PERCENT', diagonal, scale)
    return column, value, scale


# ----------------------------------------------------------------------------- compute


# ----------------------------------------------------------------------------- commit


_TRANSFORM_PROPS = ("rotation_mode", "location", "rotation_euler", "rotation_quaternion",
                    "rotation_axis_angle", "scale", "delta_location", "delta_rotation_euler",
                    "delta_rotation_quaternion", "delta_scale")
_ARMATURE_MOD_PROPS = ("object", "use_vertex_groups", "use_bone_envelopes", "use_deform_preserve_volume",
                       "use_multi_modifier", "vertex_group", "invert_vertex_group", "show_viewport",
                       "show_render")


def _copy_setup(source, lod, level: int, mesh_too: bool = True) -> None:
    """Give the new LOD object ``lod`` its source's place, materials, custom properties and
    Armature modifiers. ``mesh_too``: also fill its mesh's material list (False for a LOD
    mesh another instance's LOD object already set up: the list is the mesh's, shared)."""
    lod.parent = source.parent
    lod.parent_type = source.parent_type
    if source.parent_type == 'BONE':
        lod.parent_bone = source.parent_bone
    lod.matrix_parent_inverse = source.matrix_parent_inverse.copy()
    for prop in _TRANSFORM_PROPS:
        setattr(lod, prop, getattr(source, prop))

    materials = source.data.materials
    if mesh_too:
        for i in range(len(source.material_slots)):
            lod.data.materials.append(materials[i] if i < len(materials) else None)
    for i, slot in enumerate(source.material_slots):
        if slot.link == 'OBJECT':
            lod.material_slots[i].link = 'OBJECT'
            lod.material_slots[i].material = slot.material

    for key in source.keys():
        if key in (SOURCE_PROP, LEVEL_PROP) or key.startswith(SWITCH_PROP_PREFIX):
            continue
        value = source[key]
        lod[key] = value.to_dict() if hasattr(value, "to_dict") else (
            value.to_list() if hasattr(value, "to_list") else value)
        try:
            lod.id_properties_ui(key).update(**source.id_properties_ui(key).as_dict())
        except TypeError:  # values without UI data (groups, ID pointers)
            pass
    lod[SOURCE_PROP] = source.name
    lod[LEVEL_PROP] = level

    for md in source.modifiers:
        if md.type == 'ARMATURE' and md.object is not None:
            new = lod.modifiers.new(md.name, 'ARMATURE')
            for prop in _ARMATURE_MOD_PROPS:
                setattr(new, prop, getattr(md, prop))


def previous_lods(source_name: str) -> list:
    """LOD objects made from the object called ``source_name`` by an earlier run."""
    return [ob for ob in bpy.data.objects if ob.get(SOURCE_PROP) == source_name and LEVEL_PROP in ob]


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


def in_scene(collection, scene) -> bool:
    """Whether ``collection`` is the scene's own collection or one nested in it."""
    return collection == scene.collection or collection in scene.collection.children_recursive[:]


def _lod_collection(scene, source):
    name = f"{source.name}_LODs"
    coll = bpy.data.collections.get(name)
    if coll is None:
        coll = bpy.data.collections.new(name)
    if not in_scene(coll, scene):
        parent = next((c for c in source.users_collection if in_scene(c, scene)), scene.collection)
        parent.children.link(coll)
    return coll


def switch_prop(key: str) -> str:
    """The custom property holding one level's switch_distances number ``key``."""
    return SWITCH_PROP_PREFIX + key


world_scale = asset_set.world_scale  # (kept here too: callers name it lod.world_scale)


def _switch_data(source, out) -> tuple:
    """(switch_distances.chain_switch_data of the chain, or None, and why not)."""
    if not all("hausdorff_percent" in entry for entry in out.reports):
        return None, None  # nothing measured (Measure Deviation off), nothing to say
    try:
        percent = [0.0] + [entry["hausdorff_percent"] for entry in out.reports]
        data = out.input.data
        settings = out.input.settings
        return switch_distances.chain_switch_data(
            percent, data.vertices, data.faces, world_scale(source), pixel_error=settings.pixel_error,
            screen_height=settings.screen_height, vertical_fov_degrees=settings.vertical_fov), None
    except ValueError as ex:
        return None, f"no switch distances: {ex}"


def _set_switch_props(ob, numbers) -> None:
    for key in [k for k in ob.keys() if k.startswith(SWITCH_PROP_PREFIX)]:
        del ob[key]
    for key, value in (numbers or {}).items():
        ob[switch_prop(key)] = float(value)


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
                _copy_setup(source, lod, k, mesh_too=new)
    except BaseException:
        for _, _, objects, _ in built:
            for lod in objects:
                bpy.data.objects.remove(lod)
        for mesh in made:
            if mesh.users == 0:
                vertex_groups.remove_mesh(mesh)
        raise

    keep = {ob.as_pointer() for _, _, objects, _ in built for ob in objects}
    keep |= {source.as_pointer() for source, _, _, _ in built}  # never remove an object being written for
    # Every source's earlier LODs go before any new one is named, so that a LOD mesh several
    # of them shared is gone (no users left) when the new shared mesh takes its name.
    for source, _, _, _ in built:
        for old in previous_lods(source.name):
            if old.as_pointer() not in keep:
                _replace_lod(old)
    asset_switch = switch
    reports = []
    posed = []  # measured skinned chains: (source, LOD objects, level entries, diagonal, part samples)
    for source, out, objects, leader in built:
        group = group_names[id(out)]
        coll = _lod_collection(scene, source)
        for k, lod in enumerate(objects, start=1):
            lod.name = f"{source.name}_LOD{k}"
            if leader is None and not (k > 1 and lod.data is objects[k - 2].data):
                # Named as its LOD object, or when several objects' LODs use it, after the
                # source mesh they all share: "<mesh>_LOD<k>".
                lod.data.name = lod.name if len(group) == 1 else f"{source.data.name}_LOD{k}"
            coll.objects.link(lod)
        levels = [dict(entry, name=lod.name, mesh=lod.data.name) for entry, lod in zip(out.reports, objects)]
        if leader is not None:  # computed once, for the group's first object: its entry has the time
            for entry in levels:
                entry["seconds"] = 0.0
        data = out.input.data
        warnings = list(out.input.warnings)
        if asset_switch is not None:  # one set for the asset, each part switching with it
            switch, why_not = asset_switch, None
        else:
            switch, why_not = _switch_data(source, out)  # per object: its world scale
        per_level = switch_distances.per_level(switch)[:len(objects) + 1] if switch else [None] * (len(objects) + 1)
        for ob, numbers in zip([source] + objects, per_level):
            _set_switch_props(ob, numbers)
        if switch:
            for entry, numbers in zip(levels, per_level[1:]):
                entry.update(numbers)
            switch = {key: value for key, value in switch.items() if key not in switch_distances.PER_LEVEL_KEYS}
            switch["lod0"] = per_level[0]
        if why_not:
            warnings.append(why_not)
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
            "switch": switch,
            "warnings": warnings,
            # The other objects whose LOD objects use the same LOD meshes (made once).
            "shared_with": [name for name in group if name != source.name],
        }
        if leader is not None:
            rep["shares"] = leader  # whose LOD meshes these are, and whose entry has the time
        elif out.input.settings.measuring() and rig.armature_of(source) is not None:
            posed.append((source, objects, levels, measure.bbox_diagonal(data.vertices, data.faces),
                          out.input.part_samples))
        reports.append(rep)
    if posed:  # over the rig's own actions (addon/posed_deviation.py), once the LODs are in the scene
        try:
            posed_deviation.measure_chains(scene, lambda: mesh_io.scene_and_depsgraph(context_or_scene)[1], posed)
        except Exception as ex:  # the LODs are made: a failed extra measurement is a note
            for source, *_ in posed:
                next(r for r in reports if r["object"] == source.name)["warnings"].append(
                    f"the posed distance was not measured ({type(ex).__name__}: {ex})")
    return reports


def generate_lods(context_or_scene, source_obj, settings: LodSettings,
                  progress: Optional[Callable[[float], object]] = None) -> dict:
    """Make ``source_obj``'s LOD chain and link it into the scene. Returns its report:
    {object, collection, source_mesh, source_triangles, source_vertices, seconds, warnings,
     shared_with (other objects using the same LOD meshes: none here),
     levels: [{level, name, mesh, target, triangles, vertices, seconds, stop_reason,
               hausdorff_percent, mean_percent, normal_mean_degrees, normal_p95_degrees,
               normal_max_degrees (if measured), mean_quality, min_quality, sliver_percent,
               importance (with importance on: painted_vertices, painted_kept,
               painted_kept_percent, rest_kept_percent, painted_density, region: "painted",
               or "keyed" for Source Shape Keys),
               shape_keys (measured, with shape keys: per key {name, hausdorff, mean,
               hausdorff_percent, mean_percent, and for a key that moves the mesh
               region_mean, region_hausdorff, their _percent, region_area_percent}, the
               LOD and the source each with that key at 1; key_deviation.py),
               measured: materials, regions ({name: {mean_percent, p95_percent,
               max_percent, samples}}), deviation_colors (with Deviation Colors), posed
               (skinned: over the armature's actions; addon/pure/level_deviation.py,
               addon/posed_deviation.py),
               and measured: deviation, switch_distance, msft_screen_coverage, unreal_screen_size,
               unity_transition_height, godot_visibility_range_begin/_end (switch_distances.py)}],
     switch: None unmeasured, else {pixel_error, screen_height, vertical_fov_degrees,
             bounding_sphere_radius, bounding_box_size, cull_distance, lod0: LOD0's numbers}}.
    Raises LodError (bad input) or LodCancelled (progress returned False); in both
    cases the scene is unchanged.
    """
    lod_input = prepare(context_or_scene, source_obj, settings)
    output = compute(lod_input, progress)
    return commit(context_or_scene, [output])[0]
