# SPDX-License-Identifier: GPL-3.0-or-later
"""Generate a LOD chain for a mesh object: read, simplify with the core, write, link.

The orchestrator of a LOD run, in three phases, so a caller can run the expensive middle
one in a worker thread:
    prepare(context, obj, settings) -> LodInput      main thread: reads Blender data (here,
                                                     with rig.py, object_importance.py,
                                                     mesh_io.py and pure/options.py)
    compute(lod_input, progress)    -> LodOutput     any thread: NumPy and the core only
                                                     (pure/compute.py)
    commit(context, [outputs])      -> [report]      main thread: writes Blender data
                                                     (commit.py; an output given for several
                                                     objects sharing a mesh: LOD meshes made once)
:func:`generate_lods` chains them for one object; LodJob (job.py) runs them for several.

No UI here (operators, the command line and tests all call it). Bad input raises
:class:`LodError` with a message meant for the user; a cancelled run raises
:class:`LodCancelled`. Either way the scene is left as it was: all LOD meshes and
objects are built first and linked into the scene only when every one of them exists.
"""
from __future__ import annotations

import dataclasses
import re
from typing import Callable, Optional

import numpy as np

from . import asset as asset_set
from . import lod_objects
from . import mesh_io
from . import object_importance
from . import rig
from .commit import commit
from .pure import deviation_targets
from .pure import importance as imp
from .pure import key_deviation
from .pure import limits
from .pure import measure
from .pure._core import core
from .pure.compute import compute
from .pure.mesh_data import MeshData
from .pure.options import mesh_options
from .pure.phases import LodInput
from .pure.settings import LodError, LodSettings
from .pure.skin_fit import CHECK_POSES


def check_source(source) -> None:
    """LodError unless ``source`` is a mesh object, or one that evaluates to a mesh (a
    curve, text, surface or metaball: mesh_io.GEOMETRY_TYPES), in Object Mode
    (prepare's first checks)."""
    if source is None or not mesh_io.draws_geometry(source):
        name = getattr(source, "name", source)
        raise LodError(f'"{name}" is not a mesh object (nor a curve, text, surface or metaball)')
    if source.mode == 'EDIT':
        raise LodError(f'"{source.name}" is in Edit Mode: switch to Object Mode first')


def faces_to_read(source, depsgraph, use_modifiers: bool) -> int:
    """The faces prepare() would read from the object ``source``: its evaluated mesh's,
    through its modifiers (a Mask or Boolean can leave none), or its own mesh's with
    ``use_modifiers`` off; a curve's, text's, surface's or metaball's as it evaluates.
    Cheap for a mesh: nothing is read."""
    if source.type == 'MESH' and (not use_modifiers or not mesh_io.has_geometry_modifiers(source)):
        return len(source.data.polygons)
    return mesh_io.evaluated_faces(source, depsgraph)


def nothing_to_simplify(source, depsgraph, use_modifiers: bool) -> Optional[str]:
    """Why the mesh object ``source`` has nothing to simplify ("skipped: ..." follows its
    name in the notes of an asset that goes on without it), or None."""
    if faces_to_read(source, depsgraph, use_modifiers):
        return None
    if source.type in ('CURVE', 'FONT'):
        return "its curve makes no faces (no bevel, extrusion or fill)"
    if source.type == 'META':
        return "no faces (a metaball's family is drawn by its first object)"
    if use_modifiers and mesh_io.drawn_instances(source, depsgraph):
        # (the command line makes them objects first: sources.make_node_instances_real)
        return "its geometry nodes draw only instances (Object > Convert > Mesh makes them faces)"
    if use_modifiers and mesh_io.has_geometry_modifiers(source) and len(source.data.polygons):
        return "its modifiers leave no faces"
    return "no faces"


# Unreal's names for the collision meshes an FBX carries beside its render meshes (convex
# hulls, boxes, spheres, capsules): the engine takes them as they are, and LODs of them
# would be render meshes named like collision.
COLLISION_PREFIXES = ("UCX_", "UBX_", "USP_", "UCP_")


# A file's own levels of detail, by the naming of Unreal, Unity and asset stores:
# "Chair_LOD1" (or "Chair LOD1", "Chair.lod1", "ChairLOD1") beside "Chair_LOD0" or "Chair".
_LOD_NAME = re.compile(r"^(?P<base>.*?)[_. -]?LOD(?P<level>\d+)$", re.IGNORECASE)


def scene_helpers(objects) -> dict:
    """{name: why} of those of ``objects`` (a scene's) that serve another object rather
    than being a part of what the file draws, found from the objects together:
      * the operands of Boolean modifiers (an operand object, or every object of an operand
        collection; enabled or not): what they cut is in the LODs of what they cut;
      * a file's own lower levels of detail (_LOD_NAME, level 1 and up beside its level 0
        or its base name): the file's LOD0 is the source, and LODs of its LOD1 beside it
        would draw the asset twice at every level (an asset-store FBX ships LOD0-LOD3).
    helper_role adds what an object says of itself."""
    helpers = {}
    for ob in objects:
        for mod in getattr(ob, "modifiers", ()):
            if mod.type != 'BOOLEAN':
                continue
            if getattr(mod, "operand_type", 'OBJECT') == 'COLLECTION':
                operands = list(mod.collection.all_objects) if mod.collection is not None else []
            else:
                operands = [mod.object] if mod.object is not None else []
            for operand in operands:
                helpers[operand.name] = ("a Boolean modifier's operand (its shape is already in the object whose "
                                         "modifier uses it)")
    for name, (first, level) in own_lods(objects).items():
        helpers.setdefault(name, f'an existing LOD{level} of "{first}" (by its name): "{first}" is the source')
    return helpers


def own_lods(objects) -> dict:
    """{name: (its level 0's name, its level)} of those of ``objects`` that are a file's
    own lower levels of detail by their names (_LOD_NAME: level 1 and up beside a level 0
    or the base name), among those that draw geometry (an FBX's LOD group empty named
    "Rock" is no level 0 of "Rock_LOD1"). LODs an earlier run made (marked) are not the
    file's own."""
    named = {}  # (base, level) -> name
    for ob in objects:
        if lod_objects.LEVEL_PROP in ob or not mesh_io.draws_geometry(ob):
            continue
        match = _LOD_NAME.match(ob.name)
        if match:
            named[(match["base"].lower(), int(match["level"]))] = ob.name
        else:
            named.setdefault((ob.name.lower(), 0), ob.name)
    return {name: (named[(base, 0)], level) for (base, level), name in named.items()
            if level > 0 and (base, 0) in named}


def helper_role(source, helpers: dict) -> Optional[str]:
    """Why the object ``source`` is a helper of the asset rather than a part of what it
    draws ("skipped: ..." follows its name in the notes), or None. ``helpers``: the
    scene's scene_helpers.

    A hard-surface file keeps its Boolean cutters beside the objects they cut, a file made
    for an engine its collision meshes and its own LODs: none is a part of the asset's
    first level, and as parts they took a share of every level's triangle budget, were
    measured into the asset's distance and got LODs of their own, drawn solid in the
    written file."""
    if source.name in helpers:
        return helpers[source.name]
    if source.hide_render:
        return "disabled in renders"
    if source.name.upper().startswith(COLLISION_PREFIXES):
        return "a collision mesh (Unreal's UCX_ naming), which engines take as it is"
    return None


def left_out(source, depsgraph, use_modifiers: bool, helpers: Optional[dict]) -> Optional[str]:
    """Why an object of several is not a part of their asset (helper_role, then
    nothing_to_simplify), or None. ``helpers`` None: no object is taken for a helper
    (the objects were named one by one)."""
    return (helpers is not None and helper_role(source, helpers)) or nothing_to_simplify(source, depsgraph,
                                                                                            use_modifiers)


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
            asset: Optional[asset_set.Asset] = None, importance_optional: bool = False) -> LodInput:
    """Check the input and read everything the run needs from Blender (main thread).
    ``chain_labels``: how a message about the explicit chain names its ratios and triangle
    counts (LodSettings.targets; the command line: "--ratios", "--faces"). ``asset``: the
    asset ``source`` is a part of (addon/asset.py): a chain by triangles gets its targets
    from the asset's budget later (LodJob), deviations are relative to the asset.
    ``importance_optional``: ``source`` is one of several objects (LodJob): one without
    the importance source (the painted group, the rig's skin, shape keys: object_importance.
    missing_source) is made without importance and gets a note rather than an error, as
    the command line does (LodJob raises one when none of the objects has it)."""
    check_source(source)
    settings.validate()
    _, depsgraph = mesh_io.scene_and_depsgraph(context_or_scene)
    data, warnings = mesh_io.read_object(source, depsgraph, settings.use_modifiers)
    instances = mesh_io.drawn_instances(source, depsgraph) if settings.use_modifiers else 0
    if instances and len(data.faces):
        # (the command line makes them objects first: sources.make_node_instances_real)
        warnings.append(f"the {instances} instance{'s' if instances != 1 else ''} its geometry nodes draw "
                        f"{'are' if instances != 1 else 'is'} not in its LODs (Object > Convert > Mesh makes "
                        f"them faces)")
    if len(data.faces) == 0 and source.type != 'MESH':  # a curve without bevel, a metaball of a family
        raise LodError(f'"{source.name}" has nothing to simplify: '
                       f'{nothing_to_simplify(source, depsgraph, settings.use_modifiers)}')
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
    missing = object_importance.missing_source(source, settings, data) if importance_optional else None
    if missing is not None:
        g = None
        warnings.append(object_importance.no_importance_note(missing))
        settings = dataclasses.replace(settings, importance_source='NONE')
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
    run_settings = settings
    if g is not None and settings.importance_source == 'SHAPE_KEYS' and asset is None:
        # An asset's parts are scaled by the asset's still surface (asset.key_importance).
        scaled = imp.key_strength(settings.importance_strength, *imp.still_share(g, data.vertices, data.faces))
        note = imp.key_strength_note(settings.importance_strength, scaled)
        if note is not None:
            warnings.append(note)
            run_settings = dataclasses.replace(settings, importance_strength=scaled)
    options, names = mesh_options(run_settings, data, skin_columns, g, poses)
    limit = painted_limit(source, settings, data, reference, asset is not None, warnings, deviations)
    if limit is not None and limit[1] is not None:  # (pixels by triangles: per level, from a first run: compute)
        column, value, _ = limit
        # Per level (pixels by deviation): the first, strictest, for every run but the
        # search's own chains, which get one per level (deviation_search.by_deviation).
        strictest = value[0] if isinstance(value, tuple) else value
        options = core.Options.of(options, vertex_max_error=limits.vertex_limits(data.group_weights[:, column],
                                                                                 strictest))
    return LodInput(source.name, dataclasses.replace(settings), data, targets, options, names, warnings,
                    importance=None if g is None or settings.importance_strength <= 0 else np.asarray(g),
                    deviations=deviations, poses=poses, check_poses=check_poses, in_asset=asset is not None,
                    reference_diagonal=reference,
                    material_names=[s.material.name if s.material else None for s in source.material_slots],
                    limit=limit)


def painted_limit(source, settings: LodSettings, data: MeshData, reference: Optional[float],
                  in_asset: bool, warnings: list, deviations: Optional[list] = None) -> Optional[tuple]:
    """The settings' painted limit for ``source`` (addon/pure/limits.py): (column, L in the
    object's units, or per level a tuple of them, or None for pixels by triangles (set
    after a first run: compute), object to scene units), or None without a Limit Group. A
    group the object lacks is a LodError, or for a part of an asset a note (the part is
    free); ``reference``: the asset's diagonal in the object's units (None: its own);
    ``deviations``: a chain by deviation's, the object's units (pixels are relative to
    them)."""
    name = settings.limit_group
    if not name:
        return None
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
    if settings.limit_unit == 'PIXELS' and deviations is not None:
        # Each LOD's requested deviation shows Pixel Error pixels at its switch distance.
        return column, tuple(float(v) for v in limits.pixel_limits(deviations, settings.limit_distance,
                                                                   settings.pixel_error)), scale
    if settings.limit_unit == 'PIXELS':
        return column, None, scale
    diagonal = reference if reference is not None else measure.bbox_diagonal(data.vertices, data.faces)
    value = limits.limit_in_mesh_units(settings.limit_distance, settings.limit_unit == 'PERCENT', diagonal, scale)
    return column, value, scale


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
