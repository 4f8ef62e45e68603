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
(lod_objects.py's custom properties, switch_distances.py's numbers), per the MSFT_lod README
(KhronosGroup/glTF extensions/2.0/Vendor/MSFT_lod):
    LOD0's node  extensions.MSFT_lod = {"ids": [node of LOD1, ..., node of LODn]}
                 extras.MSFT_screencoverage = [c_0, ..., c_n] (c_n: below it, nothing)
    every level  extras.visibility_range_begin / visibility_range_end (Godot 4's
                 GeometryInstance3D properties, scene units; docs/engines.md)
and "MSFT_lod" in extensionsUsed (not extensionsRequired: a reader without it shows LOD0).
The LOD nodes stay where the exporter put them, in the scene, so readers that do not
know MSFT_lod (Blender, Godot) still get every level as a node of its own.

An asset (addon/asset.py: its objects carry ``lqlod_asset``, its name) switches as one:
    before the exporter numbers the nodes (gather_gltf_hook), each level k >= 1 becomes
    a node "<asset>_LODk" at the scene's root whose children are that level's nodes,
    moved there with their world transforms; LOD0 is the smallest subtree holding every
    source's node (a new root "<asset>_LOD0" over the roots holding them when they have
    no common ancestor). MSFT_lod and MSFT_screencoverage go on LOD0's node, the level
    nodes as its ids: each level a whole subtree, switched at the asset's distances.
    An asset with a skinned part keeps one MSFT_lod per chain instead: its skins' joints
    live in LOD0's subtree, which a reader swapping whole subtrees would take away. So
    does an asset an animation moves (a node-animated character: its parts' channels,
    which every level's node has, animation.copy_animation, are relative to their parents).
"""
from __future__ import annotations

import bpy

import numpy as np

from . import lod_objects
from .asset import ASSET_PROP  # on an asset's objects: its name
from .lod_group import base_name

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
    if any(lod_objects.switch_prop(name) not in ob for name in needed):
        return None  # not a measured chain member (or a hand-edited one missing its numbers)
    if lod_objects.LEVEL_PROP in ob and lod_objects.SOURCE_PROP in ob:
        return ob[lod_objects.SOURCE_PROP], int(ob[lod_objects.LEVEL_PROP])
    return base_name(ob), 0


class glTF2ExportUserExtension:
    """The glTF exporter's user extension (see the module docstring)."""

    def __init__(self):
        self.chains = {}  # source name -> {level: glTF node}
        self.coverage = {}  # source name -> {level: MSFT screen coverage}
        self.asset_of = {}  # source name -> its asset's name
        self.assets = {}  # asset name -> its root node (LOD0) and level nodes, once made whole
        self.mesh_nodes = {}  # a mesh object's name (a renamed LOD0's before renaming) -> its node
        self.lod_nodes = []  # (its source's name, node) of every LOD object's node
        self.active = True

    def _claim(self, export_settings) -> bool:
        self.active = export_settings.setdefault(OWNER_KEY, id(self)) == id(self)
        return self.active

    def gather_node_hook(self, gltf2_node, blender_object, export_settings):
        if blender_object is None or not self._claim(export_settings):
            return
        if blender_object.type == 'MESH':  # every LOD and source, measured or not (_share_morph_channels)
            self.mesh_nodes[base_name(blender_object)] = gltf2_node
            source = blender_object.get(lod_objects.SOURCE_PROP)
            if isinstance(source, str):
                self.lod_nodes.append((source, gltf2_node))
        key = chain_key(blender_object)
        if key is None:
            return
        self.chains.setdefault(key[0], {})[key[1]] = gltf2_node
        asset = blender_object.get(ASSET_PROP)
        if isinstance(asset, str) and asset:
            self.asset_of[key[0]] = asset
        self.coverage.setdefault(key[0], {})[key[1]] = float(
            blender_object[lod_objects.switch_prop("msft_screen_coverage")])
        extras = gltf2_node.extras if isinstance(gltf2_node.extras, dict) else {}
        for extra, prop in GODOT_EXTRAS.items():
            extras[extra] = float(blender_object[lod_objects.switch_prop(prop)])
        gltf2_node.extras = extras

    def gather_gltf_hook(self, active_scene_idx, scenes, animations, export_settings):
        """LOD nodes get their LOD0's morph-weight channels (_share_morph_channels), and each
        asset's levels become whole subtrees (module docstring), while the nodes are still
        objects: the exporter numbers them after this."""
        if not self.active:
            return
        _share_morph_channels(self.lod_nodes, self.mesh_nodes, animations)
        if not self.asset_of:
            return
        members = {}  # asset -> {level: [nodes]}
        for base, asset in self.asset_of.items():
            for level, node in self.chains.get(base, {}).items():
                members.setdefault(asset, {}).setdefault(level, []).append(node)
        animated = _transform_animated(animations)
        for scene in scenes:
            tree = _Tree(scene)
            for asset, levels in members.items():
                made = _asset_levels(tree, asset, levels, animated, export_settings)
                if made is not None:
                    self.assets[asset] = made

    def gather_gltf_extensions_hook(self, gltf2_plan, export_settings):
        if not self.chains or not self.active:
            return
        index = {id(node): i for i, node in enumerate(gltf2_plan.nodes)}
        written = 0
        for asset, (top, levels) in self.assets.items():
            if id(top) not in index or any(id(node) not in index for node in levels):
                continue
            coverage = [self._asset_coverage(asset, level) for level in range(len(levels) + 1)]
            top.extensions = top.extensions or {}
            top.extensions[EXTENSION_NAME] = {"ids": [index[id(node)] for node in levels]}
            top.extras = top.extras if isinstance(top.extras, dict) else {}
            top.extras[COVERAGE_EXTRA] = coverage
            written += 1
        in_assets = {base for base, asset in self.asset_of.items() if asset in self.assets}
        lods = lod_objects.lods_by_source()
        for base, nodes in self.chains.items():
            if base in in_assets:
                continue  # its asset switches as a whole
            n_lods = len(lods.get(base, []))
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

    def _asset_coverage(self, asset: str, level: int) -> float:
        """The asset's MSFT screen coverage at ``level`` (every part has the same)."""
        return next(self.coverage[base][level] for base, a in self.asset_of.items()
                    if a == asset and level in self.coverage.get(base, {}))


def _local_matrix(node) -> np.ndarray:
    """A glTF node's transform as a 4x4 matrix (its matrix, or T * R * S)."""
    from mathutils import Matrix, Quaternion, Vector

    if node.matrix:  # (the exporter leaves [] or None for none)
        return np.array(node.matrix, dtype=np.float64).reshape(4, 4).T  # column-major
    x, y, z, w = node.rotation or (0.0, 0.0, 0.0, 1.0)  # glTF quaternions are x, y, z, w
    trs = Matrix.LocRotScale(Vector(node.translation or (0.0, 0.0, 0.0)), Quaternion((w, x, y, z)),
                             Vector(node.scale or (1.0, 1.0, 1.0)))
    return np.array(trs, dtype=np.float64)


def _set_transform(node, matrix: np.ndarray) -> None:
    """Give ``node`` the 4x4 ``matrix``: as translation, rotation and scale when it is one
    (no shear: Blender's decomposition gives it back), else as its matrix."""
    from mathutils import Matrix

    location, rotation, scale = Matrix([list(row) for row in matrix]).decompose()
    node.matrix = None
    node.translation = list(location) if location.length > 0 else None
    node.rotation = [rotation.x, rotation.y, rotation.z, rotation.w] if rotation.angle > 1e-9 else None
    node.scale = list(scale) if any(abs(c - 1.0) > 1e-9 for c in scale) else None
    if np.allclose(_local_matrix(node), matrix, atol=1e-5 * max(1.0, np.abs(matrix).max())):
        return
    node.translation = node.rotation = node.scale = None
    node.matrix = [float(v) for v in matrix.T.reshape(-1)]


class _Tree:
    """A gathered glTF scene's hierarchy (nodes still objects): each node's parent (None
    at the root) and world matrix, by id."""

    def __init__(self, scene):
        self.scene = scene
        self.parent, self.world = {}, {}
        stack = [(node, None, np.eye(4)) for node in scene.nodes]
        while stack:
            node, parent, above = stack.pop()
            self.parent[id(node)] = parent
            self.world[id(node)] = above @ _local_matrix(node)
            stack.extend((child, node, self.world[id(node)]) for child in (node.children or []))

    def holds(self, node) -> bool:
        return id(node) in self.parent

    def ancestors(self, node) -> list:
        """``node`` and its ancestors, up to its root."""
        out = []
        while node is not None:
            out.append(node)
            node = self.parent[id(node)]
        return out

    def detach(self, node) -> None:
        parent = self.parent[id(node)]
        siblings = self.scene.nodes if parent is None else parent.children
        siblings[:] = [n for n in siblings if n is not node]
        if parent is not None and not parent.children:
            parent.children = None

    def add_root(self, node) -> None:
        self.scene.nodes.append(node)
        self.parent[id(node)] = None
        self.world[id(node)] = np.eye(4)


def _new_node(name: str, children: list):
    from io_scene_gltf2.io.com import gltf2_io

    return gltf2_io.Node(camera=None, children=children, extensions=None, extras=None, matrix=None, mesh=None,
                         name=name, rotation=None, scale=None, skin=None, translation=None, weights=None)


def _common_ancestor(tree: _Tree, nodes: list):
    """The deepest node above (or among) all ``nodes``, or None when they have different roots."""
    paths = [tree.ancestors(node)[::-1] for node in nodes]  # root first
    common = None
    for step in zip(*paths):
        if any(n is not step[0] for n in step):
            break
        common = step[0]
    return common


def _morph_targets(node) -> int:
    mesh = node.mesh
    if mesh is None or not getattr(mesh, "primitives", None):
        return 0
    return len(mesh.primitives[0].targets or [])


def _share_morph_channels(lod_nodes: list, mesh_nodes: dict, animations) -> int:
    """Each LOD node with no morph-weight channel of its own in an animation gets its
    source's node's there, the same sampler, when its mesh has as many morph targets (a
    LOD keeps every shape key, in order). animation.key_copies_paused kept the exporter
    from sampling each level's copy of the source's shape-key actions, the same values
    (a LOD whose keys the exporter did sample keeps its own channels). Returns the
    channels added."""
    from io_scene_gltf2.io.com import gltf2_io

    followers = {}  # id(source node) -> [LOD nodes with as many morph targets]
    for source, node in lod_nodes:
        top = mesh_nodes.get(source)
        if top is not None and top is not node and _morph_targets(top) and _morph_targets(node) == _morph_targets(top):
            followers.setdefault(id(top), []).append(node)
    added = 0
    for animation in animations or []:
        channels = animation.channels or []
        weighted = {id(c.target.node) for c in channels if c.target is not None and c.target.path == "weights"}
        for channel in list(channels):
            target = channel.target
            if target is None or target.path != "weights" or id(target.node) not in followers:
                continue
            for node in followers[id(target.node)]:
                if id(node) in weighted:
                    continue
                channels.append(gltf2_io.AnimationChannel(
                    extensions=None, extras=None, sampler=channel.sampler,
                    target=gltf2_io.AnimationChannelTarget(extensions=None, extras=None, node=node, path="weights")))
                weighted.add(id(node))
                added += 1
    return added


def _transform_animated(animations) -> set:
    """The ids of the gathered nodes an animation channel moves (translation, rotation or
    scale; morph weights move no node)."""
    moved = set()
    for animation in animations or []:
        for channel in animation.channels or []:
            target = channel.target
            if target is not None and target.node is not None and target.path in ("translation", "rotation", "scale"):
                moved.add(id(target.node))
    return moved


def _asset_levels(tree: _Tree, asset: str, levels: dict, animated: set, export_settings):
    """Make the asset's levels whole subtrees in ``tree`` (module docstring); returns
    (LOD0's node, [level nodes]) or None (not in this scene, a level missing, skinned, or
    moved by an animation: ``animated``, the ids of animated nodes)."""
    count = max(levels) if levels else 0
    if count == 0 or sorted(levels) != list(range(count + 1)):
        return None
    if not all(tree.holds(node) for nodes in levels.values() for node in nodes):
        return None
    if any(node.skin is not None for nodes in levels.values() for node in nodes):
        export_settings['log'].info(
            f"{EXTENSION_NAME}: the asset {asset!r} has skinned parts: one {EXTENSION_NAME} per part")
        return None
    if any(id(above) in animated for nodes in levels.values() for node in nodes for above in tree.ancestors(node)):
        # A level moved to a root of its own, in world space, would lose what moves its
        # parts: their own channels are relative to their parents, and an animated
        # ancestor would no longer be theirs. Each part keeps its place and its channels.
        export_settings['log'].info(
            f"{EXTENSION_NAME}: the asset {asset!r} has animated nodes: one {EXTENSION_NAME} per part")
        return None
    level_nodes = []
    for level in range(1, count + 1):
        moved = levels[level]
        for node in moved:  # to the new level root, where it stays put in the world
            world = tree.world[id(node)]
            tree.detach(node)
            if not np.allclose(world, _local_matrix(node), atol=1e-9):
                _set_transform(node, world)
        root = _new_node(f"{asset}_LOD{level}", list(moved))
        tree.add_root(root)
        for node in moved:
            tree.parent[id(node)] = root
        level_nodes.append(root)
    top = _common_ancestor(tree, levels[0])
    if top is None:  # several roots: one new root above those holding the sources
        roots = []
        for node in levels[0]:
            root = tree.ancestors(node)[-1]
            if all(root is not r for r in roots):
                roots.append(root)
        for root in roots:
            tree.detach(root)
        top = _new_node(f"{asset}_LOD0", roots)
        tree.add_root(top)
        tree.scene.nodes.remove(top)
        tree.scene.nodes.insert(0, top)
    return top, level_nodes
