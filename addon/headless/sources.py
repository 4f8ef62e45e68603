# SPDX-License-Identifier: GPL-3.0-or-later
"""Which objects of an input's scene get LODs, and with which importance.

In a batch of mixed assets only some have the painted group, a rig or shape keys: an
object without what was asked for is simplified without importance and gets a note,
rather than failing its input.
"""
from __future__ import annotations

from .. import lod_objects
from .. import rig
from .errors import InputError


def select_objects(scene, names) -> tuple:
    """(objects, skipped) to simplify: ``names`` or every mesh object that is not a LOD."""
    # Meshes drawn as bone shapes (rig widgets) are display helpers, not assets.
    widgets = {pb.custom_shape for ob in scene.objects if ob.type == 'ARMATURE' and ob.pose
               for pb in ob.pose.bones if pb.custom_shape is not None}
    meshes = [ob for ob in scene.objects if ob.type == 'MESH' and lod_objects.LEVEL_PROP not in ob and ob not in widgets]
    if names:
        problems, picked = [], []
        for name in dict.fromkeys(names):
            ob = scene.objects.get(name)
            if ob is None:
                available = ", ".join(sorted(o.name for o in meshes)[:12]) or "none"
                problems.append(f'object "{name}" not found (mesh objects: {available})')
            elif ob.type != 'MESH':
                problems.append(f'"{name}" is not a mesh object (its type is {ob.type})')
            elif lod_objects.LEVEL_PROP in ob:
                problems.append(f'"{name}" is a LOD made by an earlier run, not a source')
            else:
                picked.append(ob)
        if problems:
            raise InputError("; ".join(problems))
        return picked, []
    with_faces = [ob for ob in meshes if len(ob.data.polygons)]
    if not with_faces:
        raise InputError("no mesh objects with faces" if meshes else "no mesh objects")
    skipped = [f'"{ob.name}" skipped: no faces' for ob in meshes if not len(ob.data.polygons)]
    return with_faces, skipped


def importance_choice(objects, args) -> list:
    """Per object: (importance_source, group, note or None); the note goes into the
    report and after the table. The painted group wins, then the rig (--from-armature),
    then the shape keys (--from-shape-keys): one source per object."""
    group = args.importance_group
    choices = []
    for ob in objects:
        if group and group in ob.vertex_groups:
            choices.append(('VERTEX_GROUP', group, None))
        elif args.from_armature and rig.armature_of(ob) is not None:
            choices.append(('ARMATURE_PAPER' if args.from_armature == "paper" else 'ARMATURE', "", None))
        elif getattr(args, "from_shape_keys", False) and has_shape_keys(ob):
            choices.append(('SHAPE_KEYS', "", None))
        else:
            wanted = [w for w, on in ((f'no vertex group "{group}"', bool(group)),
                                      ("not skinned", args.from_armature),
                                      ("no shape keys", getattr(args, "from_shape_keys", False))) if on]
            note = f"no importance ({' and '.join(wanted)})" if wanted else None
            choices.append(('NONE', "", note))
    return choices


def limit_choice(objects, args) -> list:
    """Per object: (limit group or "", note or None): --limit-group on the objects that
    have it; the others are free, with a note."""
    group = getattr(args, "limit_group", None)
    if not group:
        return [("", None)] * len(objects)
    return [(group, None) if group in ob.vertex_groups else ("", f'no painted limit (no vertex group "{group}")')
            for ob in objects]


def has_shape_keys(ob) -> bool:
    """Whether the mesh object ``ob`` has shape keys besides its basis."""
    keys = ob.data.shape_keys
    return keys is not None and len(keys.key_blocks) > 1


def importance_label(source: str, group: str) -> str:
    """How the report names an importance choice: NONE, ARMATURE, ARMATURE_PAPER,
    SHAPE_KEYS or VERTEX_GROUP:<group>."""
    return source if source != 'VERTEX_GROUP' else f"VERTEX_GROUP:{group}"
