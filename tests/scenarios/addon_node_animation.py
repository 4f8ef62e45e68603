"""A character animated by its nodes, as glTF files often are (the Kenney character in
../shared/assets moves its legs, arms and torso by object actions; no armature), as one
asset through LodJob of the installed extension, then written by the command line's glTF export
(tests/test_node_animation.py checks what this returns).

The asset: "Body", a UV sphere under an empty "Root" whose action walks it along x, and
"Arm", an ico sphere parented to Body, swung by its own action "Swing" and holding a
second action "Wave" in an NLA track (muted, as the glTF importer leaves the others),
twice: the second strip touching the first and ending between frames.
Body has a shape key "Bulge" (its top pushed out) whose value an action "Breathe" plays,
with "Sigh" in an NLA track: morph weights, as RobotExpressive's faces have.
"""
from pathlib import Path

import bpy

from scene_tools import empty_scene, extension_module

job_mod = extension_module("addon.job")
lod = extension_module("addon.lod")
scene_files = extension_module("addon.headless.scene_files")
one_input = extension_module("addon.headless.one_input")

FRAMES = (1, 6, 12)


def _keyed(ob, prop: str, values: dict, action_name: str, owner=None):
    """``ob``'s ``prop`` keyed at {frame: value}; the action (of ``owner``, the ID the
    animation data is on, when ``ob`` is not one: a shape key's is its Key's) named."""
    for frame, value in values.items():
        setattr(ob, prop, value)
        ob.keyframe_insert(prop, frame=frame)
    action = (owner or ob).animation_data.action
    action.name = action_name
    return action


def build() -> list:
    empty_scene()
    root = bpy.data.objects.new("Root", None)
    bpy.context.scene.collection.objects.link(root)
    _keyed(root, "location", {1: (0.0, 0.0, 0.0), 12: (3.0, 0.0, 0.0)}, "Walk")
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1.0)
    body = bpy.context.active_object
    body.name = "Body"
    body.parent = root
    body.shape_key_add(name="Basis")
    bulge = body.shape_key_add(name="Bulge", from_mix=False)
    for point in bulge.data:
        if point.co.z > 0.3:
            point.co.z += 0.4
    keys = body.data.shape_keys
    sigh = _keyed(bulge, "value", {1: 0.0, 12: 1.0}, "Sigh", keys)
    keys.animation_data.action = None
    track = keys.animation_data.nla_tracks.new()
    track.name = "Sigh"
    track.strips.new("Sigh", 1, sigh)
    track.mute = True
    _keyed(bulge, "value", {1: 0.0, 6: 1.0, 12: 0.0}, "Breathe", keys)
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, radius=0.3, location=(1.3, 0.0, 0.0))
    arm = bpy.context.active_object
    arm.name = "Arm"
    arm.parent = body
    arm.rotation_mode = 'XYZ'
    wave = _keyed(arm, "rotation_euler", {1: (0.0, 0.0, 0.0), 12: (0.0, 0.0, 1.0)}, "Wave")
    arm.animation_data.action = None
    track = arm.animation_data.nla_tracks.new()
    track.name = "Wave"
    first = track.strips.new("Wave", 1, wave)
    first.frame_end_raw = 12.5
    # A second strip that starts between frames, where the first ends: strips.new takes
    # a whole frame and would refuse frame 12 there (animation.copy_animation).
    again = track.strips.new("Wave again", 20, wave)
    again.frame_start_raw, again.frame_end_raw = 12.5, 23.5
    track.mute = True
    _keyed(arm, "rotation_euler", {1: (0.0, 0.0, 0.0), 6: (0.9, 0.0, 0.0), 12: (0.0, 0.0, 0.0)}, "Swing")
    bpy.context.scene.frame_start, bpy.context.scene.frame_end = 1, 12
    return [body, arm]


def _animation(ob) -> dict:
    anim = ob.animation_data
    if anim is None:
        return {}
    slot = getattr(anim, "action_slot", None)
    return {"action": anim.action.name if anim.action else None,
            "slot": slot.identifier if slot is not None else None,
            "tracks": [(t.name, t.mute, [(s.action.name, s.frame_start, s.frame_end) for s in t.strips])
                       for t in anim.nla_tracks]}


def run(glb: str = "") -> dict:
    """``glb``: also write the scene there by the command line's export (not on Blender 4.2,
    whose glTF exporter crashes in its bpy module: .ci/run)."""
    objects = build()
    job = job_mod.LodJob(bpy.context, objects, lod.LodSettings(ratios=(0.5, 0.25)))
    job.run()
    reports = job.commit(bpy.context)
    lods = {r["object"]: [level["name"] for level in r["levels"]] for r in reports}
    out = {"lods": lods, "animation": {}, "parents": {}, "matrices": {}}
    chain_names = [name for source, names in lods.items() for name in [source] + names]
    out["key_animation"] = {}
    for name in chain_names:
        ob = bpy.data.objects[name]
        out["animation"][name] = _animation(ob)
        out["parents"][name] = ob.parent.name if ob.parent else None
        if ob.data.shape_keys is not None:
            out["key_animation"][name] = _animation(ob.data.shape_keys)
    scene = bpy.context.scene
    for frame in FRAMES:
        scene.frame_set(frame)
        out["matrices"][frame] = {name: [list(row) for row in bpy.data.objects[name].matrix_world]
                                  for name in chain_names}
        out.setdefault("bulge", {})[frame] = {name: bpy.data.objects[name].data.shape_keys.key_blocks["Bulge"].value
                                              for name in chain_names if name.startswith("Body")}
    # The command line's naming with --lod-group (Unreal's FBX LOD groups): one group per
    # chain, each where its LOD0 was in the hierarchy, so everything still moves.
    entries = [{"object": name, "levels": [{"name": name}] + [{"name": n} for n in names]}
               for name, names in lods.items()]
    asset = {"name": "Walker", "levels": [{} for _ in range(2)]}
    one_input.name_chains(entries, True, asset)
    out["groups"] = {e["object"]: e["lod_group"] for e in entries}
    out["asset_group"] = asset.get("lod_group")
    out["grouped"] = {}
    renamed = [[level["name"] for level in e["levels"]] for e in entries]
    for frame in FRAMES:
        scene.frame_set(frame)
        out["grouped"][frame] = [[[list(row) for row in bpy.data.objects[n].matrix_world] for n in chain]
                                 for chain in renamed]
    scene.frame_set(1)
    if glb:
        scene_files.export_scene(Path(glb))
        # The LODs' key animation was paused for the export (animation.key_copies_paused): back.
        out["key_animation_after"] = {e["object"]: [_animation(bpy.data.objects[level["name"]].data.shape_keys)
                                                    for level in e["levels"]] for e in entries if e["object"] == "Body"}
    return out
