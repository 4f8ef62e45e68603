# SPDX-License-Identifier: GPL-3.0-or-later
"""Which objects of an input's scene get LODs, and with which importance.

In a batch of mixed assets only some have the painted group, a rig or shape keys: an
object without what was asked for is simplified without importance and gets a note,
rather than failing its input.
"""
from __future__ import annotations

from .. import lod
from .. import lod_objects
from .. import mesh_io
from .. import rig
from .errors import InputError
from ..pure.wording import quoted_names


# Collection instances inside instanced collections are made real too, this many deep.
INSTANCE_DEPTH = 8


def _place_under(parent, ob, basis) -> None:
    """Link the new object ``ob`` where ``parent`` is linked, as its child at ``basis``
    (a Matrix in the parent's space, no parent inverse)."""
    from mathutils import Matrix

    ob.parent = parent
    ob.matrix_parent_inverse = Matrix.Identity(4)
    ob.matrix_basis = basis
    for target in parent.users_collection:
        target.objects.link(ob)


def make_instances_real(scene, view_layer) -> list:
    """Every collection instance the view layer draws becomes objects: for each empty
    that instances a collection, a copy of every object of that collection (sharing its
    mesh, modifiers and materials, as Alt+D does) parented to the empty where the
    instance draws it; the empty then instances nothing. Returns a note per empty.

    Instanced, a part and its LODs are drawn by every empty at once: each instance of a
    bolt showed all four levels on top of each other, in Blender and in the .glb, and the
    asset's budget counted the bolt once. As objects sharing one mesh, a part is
    simplified once and drawn, counted and switched per copy, as the glTF importer's
    shared meshes are (core.assembly). The copies are flattened under their empty: a
    hierarchy inside the instanced collection becomes its world placement.

    One note per collection and round, naming its empties: a kitbash scene instances one
    collection dozens of times."""
    from mathutils import Matrix

    notes = []
    for _ in range(INSTANCE_DEPTH):
        instancers = [ob for ob in view_layer.objects
                      if ob.instance_type == 'COLLECTION' and ob.instance_collection is not None]
        if not instancers:
            break
        made_of = {}  # collection name -> (its empties' names, objects made per instance)
        for empty in instancers:
            coll = empty.instance_collection
            into_collection_space = Matrix.Translation(-coll.instance_offset)
            made = 0
            for src in coll.all_objects:
                _place_under(empty, src.copy(), into_collection_space @ src.matrix_world)
                made += 1
            empty.instance_type = 'NONE'
            made_of.setdefault(coll.name, ([], made))[0].append(empty.name)
        for name, (empties, made) in made_of.items():
            empties = sorted(empties)
            at = f"its instance by {quoted_names(empties)}" if len(empties) == 1 else \
                f"its {len(empties)} instances by {quoted_names(empties)}"
            notes.append(f'collection "{name}": {at} made real ({made} object{"s" if made != 1 else ""} '
                         f'each, sharing their meshes)')
        view_layer.update()  # (the view layer lists newly linked objects once updated)
    return notes


def make_node_instances_real(view_layer) -> tuple:
    """Every instance that an object's geometry nodes draw (Instance on Points, a scatter)
    becomes an object: one mesh per distinct instanced geometry, shared by a copy per
    instance parented to the instancer where the instance draws it; the instancer keeps
    the mesh its stack makes besides the instances (its geometry-nodes modifier and the
    others but Armature applied). Returns (notes, names of the instancers that keep no
    faces: nothing of their own to simplify, and no note needed).

    The instances were in no LOD: the evaluated mesh of a scatter holds no faces (they
    are instances), so the file failed with '"Scatter": its modifiers leave no faces', or
    an object with faces of its own lost its instances in every level. Made objects
    sharing their meshes, as collection instances are (make_instances_real), each
    instanced geometry is simplified once and drawn, counted and switched per copy.
    The input file is not touched: the command line works on its own copy."""
    import bpy

    instancers = {ob.name: ob for ob in view_layer.objects if ob.type == 'MESH'
                  and any(md.type == 'NODES' and md.show_viewport for md in ob.modifiers)}
    if not instancers:
        return [], []
    depsgraph = view_layer.depsgraph
    placed = {}  # instancer name -> [(mesh, world matrix)] in the depsgraph's order
    meshes = {}  # instanced geometry (its evaluated data) -> the mesh made of it
    for inst in depsgraph.object_instances:
        if not inst.is_instance or inst.parent is None or inst.parent.original.name not in instancers:
            continue
        data = inst.object.data
        if inst.object.type != 'MESH' or data is None or not len(data.polygons):
            continue  # (a light, a curve's points, an instanced point cloud)
        key = data.as_pointer()
        if key not in meshes:
            meshes[key] = data.copy()  # (the evaluated data is the depsgraph's, gone after the loop)
            meshes[key].name = f"{inst.parent.original.name} instance"
        placed.setdefault(inst.parent.original.name, []).append((meshes[key], inst.matrix_world.copy()))
    notes, faceless = [], []
    for name, copies in placed.items():
        ob = instancers[name]
        own = bpy.data.meshes.new_from_object(ob.evaluated_get(depsgraph), preserve_all_data_layers=True,
                                              depsgraph=depsgraph)
        mesh_name = ob.data.name
        ob.data.name = f"{mesh_name} (with geometry nodes)"  # (the loaded copy's; freed unused)
        own.name = mesh_name
        ob.data = own
        for md in [md for md in ob.modifiers if md.type != 'ARMATURE']:
            ob.modifiers.remove(md)
        into_parent = ob.matrix_world.inverted_safe()
        for i, (mesh, world) in enumerate(copies):
            _place_under(ob, bpy.data.objects.new(f"{name}.{i:03d}", mesh), into_parent @ world)
        distinct = len({id(mesh) for mesh, _ in copies})
        notes.append(f'"{name}": the {len(copies)} instance{"s" if len(copies) != 1 else ""} its geometry nodes '
                     f'draw made real ({distinct} mesh{"es" if distinct != 1 else ""}, shared), its modifiers applied')
        if not len(own.polygons):
            faceless.append(name)
    if placed:
        view_layer.update()
    return notes, faceless


def make_linked_local(view_layer) -> list:
    """Every object the view layer draws that is linked from another .blend becomes a
    local object in its place, under its own name where no local object has it (its
    mesh, materials and rig stay linked, and the library is not touched). Returns a note
    per object.

    A linked object cannot be renamed (its source becomes "<name>_LOD0", lod_group.py),
    and its name is only unique within its library: beside a local object of the same
    name, say a copy that make_instances_real made of the library's collection, the
    chains were looked up by name and the file failed with 'cannot rename "Rock" to
    "Rock_LOD0": an object of that name exists'."""
    from pathlib import Path

    notes = []
    for ob in [o for o in view_layer.objects if o.library is not None]:
        name, library = ob.name, Path(ob.library.filepath.replace("//", "", 1)).name
        local = ob.make_local()
        if local.name != name:
            local.name = name  # (Blender keeps another name if a local object has this one)
        notes.append(f'"{local.name}": linked from {library}, made a local object in the output '
                     f'(its mesh stays linked)')
    if notes:
        view_layer.update()
    return notes


def keys_the_export_drops(objects, inputs) -> list:
    """(object, its MeshData) for each mesh object whose shape keys an export that applies
    modifiers would drop (glTF, FBX): keys and a modifier beyond Armature. ``inputs``: the
    job's LodInput per object (its ``data`` read through the stack, each key on its own)."""
    from .. import mesh_io

    return [(ob, lod_input.data) for ob, lod_input in zip(objects, inputs)
            if ob.type == 'MESH' and ob.data.shape_keys is not None and lod_input.data.shape_keys
            and mesh_io.has_geometry_modifiers(ob)]


def bake_keyed_sources(pairs) -> list:
    """Give each (object, MeshData) of keys_the_export_drops the mesh its stack makes,
    with its shape keys (and their animation), in place of its mesh and modifiers (but
    Armature). Returns a note per object.

    The glTF and FBX exporters apply a mesh's modifiers and then write it without its
    keys: a face modelled with a Mirror modifier came out with its smile on LOD1-3 (read
    through the stack, like every LOD) and none on LOD0. Only the loaded copy changes,
    and only for those formats (one_input.process writes a .blend first)."""
    from .. import animation, mesh_io

    notes = []
    names = {}  # the mesh's name before, per mesh (objects with modifiers may share one)
    for ob, data in pairs:
        old = ob.data
        name = names.setdefault(old.as_pointer(), old.name)
        old.name = f"{name} (with modifiers)"
        mesh = mesh_io.build_mesh(name, data)
        ob.data = mesh
        mesh_io.add_vertex_groups(ob, data)
        mesh_io.add_shape_keys(ob, data)
        animation.copy_animation(old.shape_keys, mesh.shape_keys)
        for md in [md for md in ob.modifiers if md.type != 'ARMATURE']:
            ob.modifiers.remove(md)
        notes.append(f'"{ob.name}": LOD0 written as its modifiers make it, with its shape keys (an export '
                     f'that applies modifiers drops the keys)')
    return notes


def drop_replaced_lods(scene, sources) -> list:
    """Remove from the loaded scene the file's own LODs (lod.own_lods) of the objects in
    ``sources``, which get new levels; returns a note for each. The written file would
    draw them at every distance, on top of the new levels (an asset-store FBX's Chair_LOD1
    and Chair_LOD2 beside the Chair_LOD0 it was made from). The input file is not touched:
    the command line works on its own copy of the scene."""
    import bpy

    made = {ob.name for ob in sources}
    notes = []
    for name, (first, _) in lod.own_lods(list(scene.objects)).items():
        ob = scene.objects.get(name)
        if first in made and ob is not None and name not in made:
            bpy.data.objects.remove(ob)
            notes.append(f'"{name}" not written: the new levels of "{first}" replace it')
    return notes


def select_objects(scene, names, view_layer=None, depsgraph=None, use_modifiers: bool = True,
                   instancers_only=()) -> tuple:
    """(objects, skipped) to simplify: ``names``, or every object that draws a mesh
    (mesh_io.GEOMETRY_TYPES) and is not a LOD nor a helper (a Boolean cutter, disabled in
    renders, a collision mesh, the file's own LOD1 and up: lod.helper_role), of
    ``view_layer``'s objects when given (an excluded collection draws nothing), with faces
    to simplify (through its modifiers with ``use_modifiers``: a Mask or Boolean can leave
    none, and such an object failed its file). ``depsgraph``: the scene's evaluated one,
    found when not given. ``instancers_only``: names of objects whose geometry nodes drew
    only instances, made objects (make_node_instances_real): left out without a note."""
    # Meshes drawn as bone shapes (rig widgets) are display helpers, not assets.
    widgets = {pb.custom_shape for ob in scene.objects if ob.type == 'ARMATURE' and ob.pose
               for pb in ob.pose.bones if pb.custom_shape is not None}
    meshes = [ob for ob in scene.objects if mesh_io.draws_geometry(ob) and lod_objects.LEVEL_PROP not in ob
              and ob not in widgets and ob.name not in instancers_only]
    drawn = None if view_layer is None else set(view_layer.objects)
    if names:
        problems, picked = [], []
        for name in dict.fromkeys(names):
            ob = scene.objects.get(name)
            if ob is None:
                available = ", ".join(sorted(o.name for o in meshes)[:12]) or "none"
                problems.append(f'object "{name}" not found (mesh objects: {available})')
            elif not mesh_io.draws_geometry(ob):
                problems.append(f'"{name}" is not a mesh object (its type is {ob.type})')
            elif lod_objects.LEVEL_PROP in ob:
                problems.append(f'"{name}" is a LOD made by an earlier run, not a source')
            else:
                picked.append(ob)
        if problems:
            raise InputError("; ".join(problems))
        return picked, []
    skipped = []
    if drawn is not None:
        skipped = [f'"{ob.name}" skipped: not in the view layer (its collection is excluded)'
                   for ob in meshes if ob not in drawn]
        meshes = [ob for ob in meshes if ob in drawn]
    helpers = lod.scene_helpers(scene.objects)
    if depsgraph is None:
        depsgraph = mesh_io.scene_and_depsgraph(scene)[1]
    empty = {ob: why for ob in meshes if (why := lod.left_out(ob, depsgraph, use_modifiers, helpers))}
    with_faces = [ob for ob in meshes if ob not in empty]
    if not with_faces:
        if not meshes:
            raise InputError("no mesh objects")
        raise InputError("no mesh objects to simplify: "
                         + "; ".join(f'"{ob.name}": {why}' for ob, why in empty.items()))
    skipped += [f'"{ob.name}" skipped: {why}' for ob, why in empty.items()]
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
