# SPDX-License-Identifier: GPL-3.0-or-later
"""glTF export of LOD chains: ``MSFT_lod`` and ``MSFT_screencoverage`` through the glTF
exporter's own user-extension hooks.

How the exporter finds this (io_scene_gltf2, ExportGLTF2.execute, Blender 4.2-4.5): for
every name in ``bpy.context.preferences.addons`` it looks up ``sys.modules[name]`` and, if
that module has an attribute ``glTF2ExportUserExtension``, instantiates it once per
export and calls its hooks. For this extension the module is the package Blender
enabled, ``bl_ext.<repo>.line_quadric_lod`` (the checkout's top-level __init__.py, which
hands the class out lazily); the command line run through the pip ``bpy`` module is
not an enabled add-on, so headless/scene_files.py lists it for the length of its export.

What the hooks write, for each chain whose objects are all exported and were measured
(lod.py's custom properties, switch_distances.py's numbers), per the MSFT_lod README
(KhronosGroup/glTF extensions/2.0/Vendor/MSFT_lod):
    LOD0's node  extensions.MSFT_lod = {"ids": [node of LOD1, ..., node of LODn]}
                 extras.MSFT_screencoverage = [c_0, ..., c_n] (c_n: below it, nothing)
    every level  extras.visibility_range_begin / visibility_range_end (Godot 4's
                 GeometryInstance3D properties, scene units; docs/engines.md)
and "MSFT_lod" in extensionsUsed (not extensionsRequired: a reader without it shows LOD0).
The LOD nodes stay where the exporter put them, in the scene, so readers that do not
know MSFT_lod (Blender, Godot) still get every level as a node of its own.
"""
from __future__ import annotations

import bpy

from . import lod
from .lod_group import BASE_NAME_PROP

EXTENSION_NAME = "MSFT_lod"
COVERAGE_EXTRA = "MSFT_screencoverage"
GODOT_EXTRAS = {"visibility_range_begin": "godot_visibility_range_begin",
                "visibility_range_end": "godot_visibility_range_end"}
# export_settings key: the first of several instances of this class in one export (the
# installed extension and a checkout's copy, say) writes, the others stay out.
OWNER_KEY = "line_quadric_lod_gltf_owner"


def chain_key(ob):
    """(name of the chain's source before any renaming, level) of a measured chain member,
    or None for an object that is none."""
    needed = ("switch_distance", "msft_screen_coverage", *GODOT_EXTRAS.values())
    if any(lod.switch_prop(name) not in ob for name in needed):
        return None  # not a measured chain member (or a hand-edited one missing its numbers)
    if lod.LEVEL_PROP in ob and lod.SOURCE_PROP in ob:
        return ob[lod.SOURCE_PROP], int(ob[lod.LEVEL_PROP])
    base = ob.get(BASE_NAME_PROP)
    return (base if isinstance(base, str) else ob.name), 0


class glTF2ExportUserExtension:
    """The glTF exporter's user extension (see the module docstring)."""

    def __init__(self):
        self.chains = {}  # source name -> {level: glTF node}
        self.coverage = {}  # source name -> {level: MSFT screen coverage}
        self.active = True

    def _claim(self, export_settings) -> bool:
        self.active = export_settings.setdefault(OWNER_KEY, id(self)) == id(self)
        return self.active

    def gather_node_hook(self, gltf2_node, blender_object, export_settings):
        if blender_object is None or not self._claim(export_settings):
            return
        key = chain_key(blender_object)
        if key is None:
            return
        self.chains.setdefault(key[0], {})[key[1]] = gltf2_node
        self.coverage.setdefault(key[0], {})[key[1]] = float(
            blender_object[lod.switch_prop("msft_screen_coverage")])
        extras = gltf2_node.extras if isinstance(gltf2_node.extras, dict) else {}
        for extra, prop in GODOT_EXTRAS.items():
            extras[extra] = float(blender_object[lod.switch_prop(prop)])
        gltf2_node.extras = extras

    def gather_gltf_extensions_hook(self, gltf2_plan, export_settings):
        if not self.chains or not self.active:
            return
        index = {id(node): i for i, node in enumerate(gltf2_plan.nodes)}
        written = 0
        for base, nodes in self.chains.items():
            n_lods = len(lod.previous_lods(base))
            if n_lods == 0 or sorted(nodes) != list(range(n_lods + 1)) or \
                    any(id(node) not in index for node in nodes.values()):
                export_settings['log'].warning(
                    f"{EXTENSION_NAME}: the LOD chain of {base!r} is not exported whole "
                    f"(levels {sorted(nodes)} of 0..{n_lods}); no {EXTENSION_NAME} for it")
                continue
            coverage = [self.coverage[base][level] for level in range(n_lods + 1)]
            top = nodes[0]
            top.extensions = top.extensions or {}
            top.extensions[EXTENSION_NAME] = {"ids": [index[id(nodes[level])] for level in range(1, n_lods + 1)]}
            top.extras[COVERAGE_EXTRA] = coverage
            written += 1
        if written and EXTENSION_NAME not in gltf2_plan.extensions_used:
            gltf2_plan.extensions_used.append(EXTENSION_NAME)
