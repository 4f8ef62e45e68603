"""A procedural humanoid for the skinned benches: a second character beside the Fox.

A stick figure of 20 joints (spine, neck and head, two arms to the hands, two legs to
the toes) given a body by Blender's Skin modifier and Subdivision Surface, both applied,
and an armature of 19 bones along its limbs, parented *With Automatic Weights* (Blender's
bone heat). Built in the current (empty) scene; ``build`` returns (body, armature).
Level 2 gives 3,008 quads (6,016 triangles).
"""
from __future__ import annotations

import bpy

JOINTS = {
    "pelvis": (0, 0, 1.0), "chest": (0, 0, 1.35), "neck": (0, 0, 1.55), "head": (0, 0, 1.85),
    "shoulder.L": (0.2, 0, 1.5), "elbow.L": (0.5, 0, 1.45), "wrist.L": (0.78, 0, 1.4), "hand.L": (0.9, 0, 1.38),
    "shoulder.R": (-0.2, 0, 1.5), "elbow.R": (-0.5, 0, 1.45), "wrist.R": (-0.78, 0, 1.4), "hand.R": (-0.9, 0, 1.38),
    "hip.L": (0.12, 0, 0.95), "knee.L": (0.13, 0, 0.52), "ankle.L": (0.13, 0, 0.1), "toe.L": (0.13, -0.18, 0.03),
    "hip.R": (-0.12, 0, 0.95), "knee.R": (-0.13, 0, 0.52), "ankle.R": (-0.13, 0, 0.1), "toe.R": (-0.13, -0.18, 0.03),
}
RADIUS = {"pelvis": .16, "chest": .2, "neck": .07, "head": .13, "shoulder": .07, "elbow": .05, "wrist": .04,
          "hand": .05, "hip": .09, "knee": .065, "ankle": .05, "toe": .04}
# Each bone runs from its parent joint to the joint it is named after.
LIMBS = [("pelvis", "chest"), ("chest", "neck"), ("neck", "head")] + [
    pair for side in ("L", "R") for pair in (
        ("chest", f"shoulder.{side}"), (f"shoulder.{side}", f"elbow.{side}"), (f"elbow.{side}", f"wrist.{side}"),
        (f"wrist.{side}", f"hand.{side}"), ("pelvis", f"hip.{side}"), (f"hip.{side}", f"knee.{side}"),
        (f"knee.{side}", f"ankle.{side}"), (f"ankle.{side}", f"toe.{side}"))]


def build(subdivision: int = 2):
    names = list(JOINTS)
    mesh = bpy.data.meshes.new("Humanoid")
    mesh.from_pydata([JOINTS[n] for n in names], [(names.index(a), names.index(b)) for a, b in LIMBS], [])
    body = bpy.data.objects.new("Humanoid", mesh)
    bpy.context.scene.collection.objects.link(body)
    body.modifiers.new("Skin", "SKIN")
    for i, name in enumerate(names):
        r = RADIUS[name.split(".")[0]]
        mesh.skin_vertices[0].data[i].radius = (r, r)
    mesh.skin_vertices[0].data[0].use_root = True
    body.modifiers.new("Subdivision", "SUBSURF").levels = subdivision
    bpy.context.view_layer.objects.active = body
    for modifier in list(body.modifiers):
        bpy.ops.object.modifier_apply(modifier=modifier.name)

    rig = bpy.data.objects.new("Rig", bpy.data.armatures.new("Rig"))
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    bones = {}
    for parent, joint in LIMBS:
        bone = rig.data.edit_bones.new(joint)
        bone.head, bone.tail = JOINTS[parent], JOINTS[joint]
        bone.parent = bones.get(parent)
        bones[joint] = bone
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.object.select_all(action="DESELECT")
    body.select_set(True)
    rig.select_set(True)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.parent_set(type="ARMATURE_AUTO")
    return body, rig
