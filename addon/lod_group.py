# SPDX-License-Identifier: GPL-3.0-or-later
"""A LOD chain named the way game engines pick it up.

Unity builds its LOD Group from the suffixes: the source is renamed "<name>_LOD0" next
to the LODs "<name>_LOD1" .. "<name>_LODn" that lod.py makes. Unreal reads an FBX LOD
group: an Empty "<name>_LODGroup" with the custom property fbx_type = "LodGroup", parent
of the whole chain, which the FBX exporter writes as such; with a measured chain it also
carries Unreal's screen size per level (docs/engines.md).

A renamed source keeps its name before in a custom property, so a later run on the
same file gives it back first: its earlier LODs (which record that name as their source)
are then replaced instead of the renamed source getting LODs of its own.
"""
from __future__ import annotations

import bpy

from . import lod_objects
from .pure.settings import LodError

BASE_NAME_PROP = "lod_base_name"  # on a source renamed "<name>_LOD0": its name before
LOD_GROUP_SUFFIX = "_LODGroup"
UNREAL_SCREEN_SIZE_PROP = "lqlod_unreal_screen_size_LOD"  # + level, on the LOD group


def base_name(ob) -> str:
    """An object's name, or for a source :func:`rename_as_lod0` renamed its name before
    (what its LODs record as their source)."""
    base = ob.get(BASE_NAME_PROP)
    return base if isinstance(base, str) else ob.name


def restore_base_names(scene) -> None:
    """Give every source that :func:`rename_as_lod0` renamed its name back."""
    for ob in scene.objects:
        base = ob.get(BASE_NAME_PROP)
        if isinstance(base, str) and ob.name == f"{base}_LOD0":
            ob.name = base
            del ob[BASE_NAME_PROP]


def rename_as_lod0(source) -> str:
    """Rename ``source`` "<name>_LOD0"; returns the new name. LodError if that name is taken."""
    base = source.name
    wanted = f"{base}_LOD0"
    if wanted in bpy.data.objects:
        raise LodError(f'cannot rename "{base}" to "{wanted}": an object of that name exists')
    source.name = wanted
    source[BASE_NAME_PROP] = base
    return source.name


def _empty(context, name: str, collection):
    """The Empty ``name`` (made in ``collection`` unless it exists)."""
    empty = bpy.data.objects.get(name)
    if empty is None or empty.type != 'EMPTY':
        empty = bpy.data.objects.new(name, None)
        collection.objects.link(empty)
    return empty


def _parent_keeping_place(obs: list, parent) -> None:
    for ob in obs:
        world = ob.matrix_world.copy()
        ob.parent = parent
        ob.parent_type = 'OBJECT'
        ob.matrix_parent_inverse.identity()
        ob.matrix_world = world


def _set_screen_sizes(empty, levels: list) -> None:
    """Unreal's screen size per level on the group, from each level's first object (when measured)."""
    for key in [k for k in empty.keys() if k.startswith(UNREAL_SCREEN_SIZE_PROP)]:
        del empty[key]
    sizes = [obs[0].get(lod_objects.switch_prop("unreal_screen_size")) if obs else None for obs in levels]
    if all(size is not None for size in sizes):
        for level, size in enumerate(sizes):
            empty[f"{UNREAL_SCREEN_SIZE_PROP}{level}"] = float(size)


def group_asset(context, name: str, levels: list):
    """One Unreal LOD group for a whole asset (addon/asset.py): the Empty
    "<name>_LODGroup" (fbx_type LodGroup, at the world's origin, in the scene's own
    collection) with one child Empty "<name>_LOD<k>" per level, parent of that level's
    objects (``levels[k]``, LOD0 the sources), each kept where it is in the world.
    Unreal's importer takes every mesh under a level's node as that LOD (Combine Meshes
    joins them). Returns the group Empty."""
    context.view_layer.update()
    collection = context.scene.collection
    group = _empty(context, name + LOD_GROUP_SUFFIX, collection)
    group["fbx_type"] = "LodGroup"
    group.parent = None
    group.matrix_world.identity()
    _set_screen_sizes(group, levels)
    for k, obs in enumerate(levels):
        level = _empty(context, f"{name}_LOD{k}", collection)
        level.parent = group
        level.matrix_parent_inverse.identity()
        level.matrix_world.identity()
        context.view_layer.update()
        _parent_keeping_place(obs, level)
    k = len(levels)  # levels an earlier run made that this one does not: gone once empty
    while (old := bpy.data.objects.get(f"{name}_LOD{k}")) is not None and old.type == 'EMPTY' and not old.children:
        bpy.data.objects.remove(old)
        k += 1
    return group


def group_chain(context, base: str, chain: list):
    """Parent ``chain`` (LOD0 first) to the Empty "<base>_LODGroup", made where LOD0 is
    unless it exists, keeping every object where it is in the world. Returns the Empty."""
    scene = context.scene
    source = chain[0]
    name = base + LOD_GROUP_SUFFIX
    # Where commit.py puts the LODs' collection: LOD0's first collection in this scene.
    collection = next((c for c in source.users_collection if lod_objects.in_scene(c, scene)), scene.collection)
    empty = _empty(context, name, collection)
    empty["fbx_type"] = "LodGroup"
    # Unreal's screen size per level (switch_distances.py), when the chain was measured:
    # "lqlod_unreal_screen_size_LOD0" .. "_LODn", written by the FBX exporter as custom properties.
    _set_screen_sizes(empty, [[ob] for ob in chain])
    # The group takes LOD0's place in the hierarchy (an armature or bone parent stays).
    empty.parent = source.parent
    if source.parent is not None and source.parent_type == 'BONE':
        empty.parent_type, empty.parent_bone = 'BONE', source.parent_bone
    empty.matrix_parent_inverse = source.matrix_parent_inverse.copy()
    context.view_layer.update()
    _parent_keeping_place(chain, empty)
    return empty
