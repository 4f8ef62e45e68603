# SPDX-License-Identifier: GPL-3.0-or-later
"""The built-in sample scene of ``--sample``: made from nothing, so the README's demo
needs no input file.

Two objects that show what the controls are for:
  * "Monkey": Suzanne subdivided twice (the modifier applied, so every exporter sees the
    same dense mesh), two materials (face / fur, a material border to keep) and a
    painted importance region around the eyes in the vertex group "LOD_Importance".
  * "Character": a small humanoid grown from a stick skeleton by the Skin modifier and
    smoothed (applied), rigged to the armature "Rig" whose bones follow the same
    skeleton, with procedural skin weights (normalised, at most 3 bones per vertex,
    blended across every joint), so "importance from armature" (paper Sec. 5.3) has
    joints to protect.

Procedural weights rather than Parent > With Automatic Weights: bone-heat weighting
can fail on a mesh ("failed to find solution for one or more bones") and its result
depends on solver details; the demo must work and give the same LODs every time.
"""
from __future__ import annotations

import numpy as np

import bpy

from . import vertex_groups
from .pure.settings import IMPORTANCE_GROUP
SAMPLE_NAME = "sample"

# The character's skeleton: joint positions (metres, Z up, facing -Y) and bones as
# (name, head joint, tail joint, parent bone). The mesh grows around the same sticks.
_JOINTS = {
    "pelvis": (0.0, 0.0, 0.95), "spine": (0.0, 0.0, 1.2), "chest": (0.0, 0.0, 1.42),
    "neck": (0.0, 0.0, 1.55), "head": (0.0, 0.0, 1.68), "crown": (0.0, 0.0, 1.9),
    "shoulder.L": (0.19, 0.0, 1.42), "elbow.L": (0.45, 0.0, 1.4), "wrist.L": (0.7, 0.0, 1.38),
    "hand.L": (0.8, 0.0, 1.37),
    "shoulder.R": (-0.19, 0.0, 1.42), "elbow.R": (-0.45, 0.0, 1.4), "wrist.R": (-0.7, 0.0, 1.38),
    "hand.R": (-0.8, 0.0, 1.37),
    "hip.L": (0.11, 0.0, 0.92), "knee.L": (0.13, -0.02, 0.5), "ankle.L": (0.14, 0.0, 0.09),
    "toe.L": (0.14, -0.16, 0.04),
    "hip.R": (-0.11, 0.0, 0.92), "knee.R": (-0.13, -0.02, 0.5), "ankle.R": (-0.14, 0.0, 0.09),
    "toe.R": (-0.14, -0.16, 0.04),
}
_RADII = {
    "pelvis": 0.14, "spine": 0.13, "chest": 0.15, "neck": 0.06, "head": 0.1, "crown": 0.09,
    "shoulder": 0.06, "elbow": 0.045, "wrist": 0.035, "hand": 0.04,
    "hip": 0.08, "knee": 0.06, "ankle": 0.045, "toe": 0.035,
}
_BONES = [
    ("Spine", "pelvis", "spine", None), ("Chest", "spine", "chest", "Spine"),
    ("Neck", "chest", "neck", "Chest"), ("Head", "neck", "crown", "Neck"),
]
for _side in ("L", "R"):
    _BONES += [
        (f"Clavicle.{_side}", "chest", f"shoulder.{_side}", "Chest"),
        (f"UpperArm.{_side}", f"shoulder.{_side}", f"elbow.{_side}", f"Clavicle.{_side}"),
        (f"Forearm.{_side}", f"elbow.{_side}", f"wrist.{_side}", f"UpperArm.{_side}"),
        (f"Hand.{_side}", f"wrist.{_side}", f"hand.{_side}", f"Forearm.{_side}"),
        (f"Hip.{_side}", "pelvis", f"hip.{_side}", "Spine"),
        (f"Thigh.{_side}", f"hip.{_side}", f"knee.{_side}", f"Hip.{_side}"),
        (f"Shin.{_side}", f"knee.{_side}", f"ankle.{_side}", f"Thigh.{_side}"),
        (f"Foot.{_side}", f"ankle.{_side}", f"toe.{_side}", f"Shin.{_side}"),
    ]
# The head joint of the skeleton mesh has no edge of its own ("neck" -> "crown" is one
# bone); the skin mesh still gets it as a vertex so the head is round.
_SKIN_EDGES = [("pelvis", "spine"), ("spine", "chest"), ("chest", "neck"), ("neck", "head"), ("head", "crown")] + [
    (a, b) for _, a, b, _p in _BONES[4:]]


def _link(context, ob):
    context.scene.collection.objects.link(ob)
    return ob


def _applied(context, ob) -> None:
    """Replace ``ob``'s mesh by its evaluated mesh and drop the modifiers."""
    depsgraph = context.evaluated_depsgraph_get()
    mesh = bpy.data.meshes.new_from_object(ob.evaluated_get(depsgraph), preserve_all_data_layers=True,
                                           depsgraph=depsgraph)
    old = ob.data
    mesh.name = old.name
    ob.modifiers.clear()
    ob.data = mesh
    bpy.data.meshes.remove(old)


def _co(mesh) -> np.ndarray:
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def _material(name, color):
    mat = bpy.data.materials.new(name)
    mat.diffuse_color = (*color, 1.0)
    return mat


def add_monkey(context, location=(-1.4, 0.0, 1.0)):
    """Suzanne subdivided twice, two materials, and the painted importance region."""
    bpy.ops.mesh.primitive_monkey_add(size=1.6, location=location, calc_uvs=True)
    ob = context.active_object
    ob.name = ob.data.name = "Monkey"
    sub = ob.modifiers.new("Subdivision", 'SUBSURF')
    sub.levels = sub.render_levels = 2
    _applied(context, ob)
    mesh = ob.data
    mesh.materials.append(_material("Monkey_Fur", (0.45, 0.28, 0.15)))
    mesh.materials.append(_material("Monkey_Face", (0.85, 0.65, 0.5)))
    n_poly = len(mesh.polygons)
    centers = np.empty(n_poly * 3, dtype=np.float32)
    mesh.polygons.foreach_get("center", centers)
    centers = centers.reshape(-1, 3)
    co = _co(mesh)
    lo, hi = co.min(axis=0), co.max(axis=0)
    size = float(np.max(hi - lo))
    # Suzanne faces -Y: the front third of her depth is the face.
    face = centers[:, 1] < lo[1] + 0.3 * (hi[1] - lo[1])
    mesh.polygons.foreach_set("material_index", face.astype(np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(n_poly, dtype=bool))
    # Importance painted as a soft disc on the eyes and brow: 1 at the centre, 0 beyond.
    centre = np.array([0.0, lo[1], lo[2] + 0.62 * (hi[2] - lo[2])])
    d = np.linalg.norm((co - centre) * np.array([1.0, 0.6, 1.0]), axis=1) / (0.2 * size)
    weight = np.clip(1.0 - d * d, 0.0, 1.0) ** 2
    vertex_groups.write_weights(ob, [IMPORTANCE_GROUP], weight[:, None])
    return ob


def _segment_distances(points: np.ndarray, heads: np.ndarray, tails: np.ndarray) -> np.ndarray:
    """(n, b) distance from every point to every bone segment."""
    axis = tails - heads  # (b, 3)
    rel = points[:, None, :] - heads[None, :, :]  # (n, b, 3)
    t = np.clip(np.einsum("nbk,bk->nb", rel, axis) / np.maximum((axis * axis).sum(axis=1), 1e-12), 0.0, 1.0)
    closest = heads[None] + t[..., None] * axis[None]
    return np.linalg.norm(points[:, None, :] - closest, axis=2)


def skin_weights(points: np.ndarray, heads: np.ndarray, tails: np.ndarray, keep: int = 3) -> np.ndarray:
    """Procedural skin weights (n, b): inverse-distance falloff to the bone segments,
    the ``keep`` largest per vertex, normalised to sum 1 (smooth blends at the joints)."""
    d = _segment_distances(points, heads, tails)
    w = 1.0 / np.maximum(d, 1e-4) ** 6
    if w.shape[1] > keep:
        cut = np.partition(w, -keep, axis=1)[:, -keep][:, None]
        w = np.where(w >= cut, w, 0.0)
    w /= w.sum(axis=1, keepdims=True)
    w[w < 1e-3] = 0.0
    return w / w.sum(axis=1, keepdims=True)


def _cylinder_uvs(mesh) -> None:
    """A cylindrical UV map around Z with its seam down the back (+Y), as a game
    character's unwrap usually has one."""
    co = _co(mesh)
    n_loops, n_poly = len(mesh.loops), len(mesh.polygons)
    loop_vert = np.empty(n_loops, dtype=np.int32)
    mesh.loops.foreach_get("vertex_index", loop_vert)
    totals = np.empty(n_poly, dtype=np.int32)
    mesh.polygons.foreach_get("loop_total", totals)
    loop_poly = np.repeat(np.arange(n_poly), totals)  # loops are stored polygon by polygon
    p = co[loop_vert]
    u = np.arctan2(p[:, 0], -p[:, 1]) / (2.0 * np.pi) + 0.5  # 0 and 1 meet at the back
    # A polygon straddling the back gets its low side moved past 1: a seam, not a smear.
    span = np.zeros(n_poly)
    np.maximum.at(span, loop_poly, u)
    low = np.ones(n_poly)
    np.minimum.at(low, loop_poly, u)
    wraps = (span - low)[loop_poly] > 0.5
    u = np.where(wraps & (u < 0.5), u + 1.0, u)
    v = (p[:, 2] - co[:, 2].min()) / max(float(np.ptp(co[:, 2])), 1e-9)
    layer = mesh.uv_layers.new(name="UVMap")
    layer.uv.foreach_set("vector", np.column_stack([u, v]).astype(np.float32).ravel())


def add_character(context, location=(1.2, 0.0, 0.0)):
    """A small skinned humanoid: (mesh object "Character", armature object "Rig")."""
    names = list(_JOINTS)
    index = {name: i for i, name in enumerate(names)}
    joints = np.array([_JOINTS[n] for n in names], dtype=np.float64)
    mesh = bpy.data.meshes.new("Character")
    mesh.from_pydata(joints.tolist(), [(index[a], index[b]) for a, b in _SKIN_EDGES], [])
    ob = _link(context, bpy.data.objects.new("Character", mesh))
    ob.location = location
    ob.modifiers.new("Skin", 'SKIN')
    radii = np.array([_RADII[n.split(".")[0]] for n in names], dtype=np.float32)
    skin = mesh.skin_vertices[0].data
    skin.foreach_set("radius", np.repeat(radii, 2))
    roots = np.zeros(len(names), dtype=bool)
    roots[index["pelvis"]] = True
    skin.foreach_set("use_root", roots)
    sub = ob.modifiers.new("Subdivision", 'SUBSURF')
    sub.levels = sub.render_levels = 2
    _applied(context, ob)
    ob.data.materials.append(_material("Character_Skin", (0.3, 0.5, 0.8)))
    _cylinder_uvs(ob.data)
    ob.data.polygons.foreach_set("use_smooth", np.ones(len(ob.data.polygons), dtype=bool))

    arm_data = bpy.data.armatures.new("Rig")
    rig = _link(context, bpy.data.objects.new("Rig", arm_data))
    rig.location = location
    for other in context.view_layer.objects:
        other.select_set(False)
    context.view_layer.objects.active = rig
    rig.select_set(True)
    bpy.ops.object.mode_set(mode='EDIT')
    try:
        for name, head, tail, parent in _BONES:
            bone = arm_data.edit_bones.new(name)
            bone.head, bone.tail = _JOINTS[head], _JOINTS[tail]
            if parent is not None:
                bone.parent = arm_data.edit_bones[parent]
                bone.use_connect = tuple(bone.parent.tail) == tuple(bone.head)
    finally:
        bpy.ops.object.mode_set(mode='OBJECT')

    heads = np.array([_JOINTS[h] for _, h, _t, _p in _BONES], dtype=np.float64)
    tails = np.array([_JOINTS[t] for _, _h, t, _p in _BONES], dtype=np.float64)
    weights = skin_weights(_co(ob.data), heads, tails)
    vertex_groups.write_weights(ob, [b[0] for b in _BONES], weights)
    ob.parent = rig
    md = ob.modifiers.new("Armature", 'ARMATURE')
    md.object = rig
    ob.location = (0.0, 0.0, 0.0)  # now relative to the rig
    return ob, rig


def build(context=None) -> dict:
    """Add the sample objects to the current scene; returns {name: object}."""
    context = context or bpy.context
    if context.mode != 'OBJECT':
        bpy.ops.object.mode_set(mode='OBJECT')
    monkey = add_monkey(context)
    character, rig = add_character(context)
    for ob in context.view_layer.objects:
        ob.select_set(False)
    context.view_layer.objects.active = monkey
    return {"Monkey": monkey, "Character": character, "Rig": rig}
