# SPDX-License-Identifier: GPL-3.0-or-later
"""What moves a LOD as its source moves, besides the armature: the source object's own
animation and its shape keys' (actions, NLA tracks, drivers), copied onto every level at
commit; and, for the glTF export, the LOD shape keys' copy paused so the exporter does not
sample the same key values once per level (addon/gltf_lod.py gives each level's node its
LOD0's channels instead).

Many glTF files animate their parts by nodes (the Kenney character in ../shared/assets:
legs, arms and torso each an object action) and their faces by morph weights
(RobotExpressive's expressions): without these copies the LODs stood still, and a glTF
file's levels had no channels.
"""
from __future__ import annotations

import contextlib
import math

from . import lod_objects
from .lod_group import base_name

# What of an ID's animation data its LOD gets as the source has it (copy_animation).
# An NLA strip's timing goes last: setting its action range, scale or repeat moves its
# end, and the *_raw frames are set as they are, without moving the strip.
_ANIMATION_PROPS = ("action_extrapolation", "action_blend_type", "action_influence", "use_nla")
_STRIP_PROPS = ("extrapolation", "blend_type", "blend_in", "blend_out", "use_auto_blend", "influence",
                "use_animated_influence", "use_animated_time", "use_animated_time_cyclic", "mute",
                "use_reverse", "use_sync_length", "action_frame_start", "action_frame_end", "scale", "repeat",
                "frame_start_raw", "frame_end_raw")


def copy_animation(source, lod) -> None:
    """The animation of ``source`` (an object, or a mesh's shape keys) on ``lod`` (its LOD
    object, or the LOD mesh's shape keys): its action, NLA tracks and drivers. Actions
    are shared, not copied, each with its source's slot (Blender 4.4+: a slot may animate
    several IDs of its type); drivers keep their targets (a corrective key driven by a
    bone is driven by it on every level). Armature deformation is the Armature
    modifier's (commit._copy_setup); a parent's animation the LOD follows as its source
    does. Nothing to copy (None on either side, no animation data): nothing done."""
    src = source.animation_data if source is not None else None
    if src is None or lod is None:
        return
    dst = lod.animation_data_create()
    if src.action is not None:
        dst.action = src.action
        if getattr(src, "action_slot", None) is not None:
            dst.action_slot = src.action_slot
    for prop in _ANIMATION_PROPS:
        setattr(dst, prop, getattr(src, prop))
    below, solo = None, None
    for track in src.nla_tracks:
        new = dst.nla_tracks.new(prev=below)
        new.name, new.mute, new.lock = track.name, track.mute, track.lock
        solo = new if track.is_solo else solo
        free = None  # a whole frame after every strip copied into the track so far
        for strip in track.strips:
            # strips.new takes a whole frame and refuses one a strip already covers (two
            # strips that touch, a fractional start): each is made where the track is
            # free, then given its source's exact frames (_STRIP_PROPS' *_raw).
            start = math.ceil(strip.frame_start) if free is None else max(math.ceil(strip.frame_start), free)
            copy = new.strips.new(strip.name, int(start), strip.action)
            if getattr(strip, "action_slot", None) is not None:
                copy.action_slot = strip.action_slot
            for prop in _STRIP_PROPS:
                setattr(copy, prop, getattr(strip, prop))
            free = math.ceil(max(copy.frame_end, start)) + 1
        below = new
    if solo is not None:
        solo.is_solo = True
    for driver in src.drivers:
        dst.drivers.from_existing(src_driver=driver)


def signature(anim) -> tuple:
    """What copy_animation copies of ``anim`` (AnimData or None), as a comparable value."""
    if anim is None:
        return ()
    slot = getattr(anim, "action_slot", None)
    return (anim.action, slot.identifier if slot is not None else None,
            tuple(getattr(anim, p) for p in _ANIMATION_PROPS),
            tuple((t.name, t.mute, t.is_solo, tuple((s.action, tuple(getattr(s, p) for p in _STRIP_PROPS))
                                                    for s in t.strips))
                  for t in anim.nla_tracks),
            tuple((d.data_path, d.array_index) for d in anim.drivers))


def moved_by_animation(obj) -> bool:
    """Whether an animation moves ``obj``: an action, an NLA track or a driver on it or on
    an object above it (a node-animated character's parts). Such a part's LODs keep their
    places in the hierarchy: gathered under a new parent, a level would lose what moves it."""
    while obj is not None:
        anim = obj.animation_data
        if anim is not None and (anim.action is not None or len(anim.nla_tracks) or len(anim.drivers)):
            return True
        obj = obj.parent
    return False


def _key_copies(scene) -> list:
    """[(LOD mesh's shape keys, its source's)] for every LOD object in ``scene`` whose keys
    animate as a copy of its source's (copy_animation's, untouched since), each once."""
    by_base = {base_name(ob): ob for ob in scene.objects}  # a renamed LOD0 by its name before
    pairs, seen = [], set()
    for ob in scene.objects:
        if ob.type != 'MESH' or lod_objects.SOURCE_PROP not in ob or ob.data.shape_keys is None:
            continue
        key = ob.data.shape_keys
        source = by_base.get(ob[lod_objects.SOURCE_PROP])
        if key.animation_data is None or key.as_pointer() in seen or source is None or source.type != 'MESH':
            continue
        source_key = source.data.shape_keys
        if source_key is not None and signature(key.animation_data) == signature(source_key.animation_data):
            seen.add(key.as_pointer())
            pairs.append((key, source_key))
    return pairs


@contextlib.contextmanager
def key_copies_paused(scene):
    """Every LOD's copy of its source's shape-key animation off while the glTF exporter
    runs, then copied back (copy_animation). The exporter samples each mesh's shape-key
    actions frame by frame on its own (io_scene_gltf2 sampling_cache.get_cache_data, a
    scene evaluation per frame per mesh and action): on RobotExpressive, 14 actions and
    three faces at four levels, that took the export from 4 to 9 s, for the same values at
    every level. gltf_lod gives each level's node its LOD0's morph-weight channels instead,
    sharing their samplers. Yields the number of keys paused."""
    pairs = _key_copies(scene)
    for key, _ in pairs:
        key.animation_data_clear()
    try:
        yield len(pairs)
    finally:
        for key, source_key in pairs:
            copy_animation(source_key, key)
