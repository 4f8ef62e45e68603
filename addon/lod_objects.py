# SPDX-License-Identifier: GPL-3.0-or-later
"""How LOD objects are marked and found again: the custom properties naming a LOD's
source and level, and holding each level's switch numbers (which the FBX exporter
writes and the glTF hook reads); an earlier run's LODs of a source; whether a
collection is in a scene.
"""
from __future__ import annotations

import bpy

SOURCE_PROP = "lod_source"  # custom property on a LOD: the name of the object it was made from
LEVEL_PROP = "lod_level"  # custom property on a LOD: 1..n (the source is LOD0)
# Custom properties on every object of a measured chain (the source too), one per key of
# switch_distances.PER_LEVEL_KEYS: "lqlod_switch_distance", "lqlod_unity_transition_height", ...
# The FBX exporter writes them (Custom Properties), the glTF hook (gltf_lod.py) reads them.
SWITCH_PROP_PREFIX = "lqlod_"


def switch_prop(key: str) -> str:
    """The custom property holding one level's switch_distances number ``key``."""
    return SWITCH_PROP_PREFIX + key


def set_switch_props(ob, numbers) -> None:
    """Give ``ob`` one custom property per switch number in ``numbers`` (none: remove them)."""
    for key in [k for k in ob.keys() if k.startswith(SWITCH_PROP_PREFIX)]:
        del ob[key]
    for key, value in (numbers or {}).items():
        ob[switch_prop(key)] = float(value)


def lods_by_source() -> dict:
    """{source object's name: the LOD objects made from it}, every LOD object of the file
    in one scan (a scan per source was quadratic: 600 parts, 0.6 s)."""
    found = {}
    for ob in bpy.data.objects:
        source = ob.get(SOURCE_PROP)
        if source is not None and LEVEL_PROP in ob:
            found.setdefault(source, []).append(ob)
    return found


def in_scene(collection, scene) -> bool:
    """Whether ``collection`` is the scene's own collection or one nested in it."""
    return collection == scene.collection or collection in scene.collection.children_recursive[:]
