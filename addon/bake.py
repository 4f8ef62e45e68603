# SPDX-License-Identifier: GPL-3.0-or-later
"""The source's lost detail baked into a tangent-space normal map on each LOD (issue 22 §3).

Cycles bakes the source onto the LOD (selected to active, as artists do by hand). The
rays start from a cage pushed out by the LOD's measured distance to the source, so they
reach the detail the LOD cut through without catching far-away parts. The image goes
into copies of the LOD's materials (the source keeps its own), through a Normal Map node
into every Principled BSDF whose Normal input is free; it is packed, so the .blend and
the glTF exporter carry it. Main thread only, after the LODs are linked (lod.commit).

Every material and image made here carries the custom property BAKED_PROP (the LOD's
name), so that replacing the LODs can remove exactly these once nothing uses them
(:func:`remove_unused`) and never a material the artist made. A LOD whose bake fails
gets its materials back and keeps no copy or image (a warning says why).
"""
from __future__ import annotations

import contextlib

import bpy

CAGE_MARGIN = 1.25  # the cage: this times the LOD's measured Hausdorff distance
CAGE_FALLBACK = 0.01  # of the bounding-box diagonal, when the LOD was not measured
BAKE_MARGIN_PIXELS = 8  # texels grown past each UV island (mip-mapping needs them)
# Custom property on every material copy and image a bake makes: the LOD's name. It
# marks them as ours: a replaced LOD's copies are removed only when they carry it.
BAKED_PROP = "lqlod_baked_for"


@contextlib.contextmanager
def _bake_scene(scene, view_layer, objects):
    """Cycles at one sample, the given objects visible and selectable, the rest as it was."""
    saved = {
        "engine": scene.render.engine,
        # (A view layer can list None for an object removed in the same call, such as the
        # LODs a new run replaces, until the next update.)
        "selected": [ob for ob in view_layer.objects if ob is not None and ob.select_get(view_layer=view_layer)],
        "active": view_layer.objects.active,
        "hidden": {ob.name: (ob.hide_get(view_layer=view_layer), ob.hide_select, ob.hide_render) for ob in objects},
    }
    try:
        scene.render.engine = 'CYCLES'
        scene.cycles.samples = 1
        for ob in objects:
            ob.hide_set(False, view_layer=view_layer)
            ob.hide_select = False
            ob.hide_render = False
        yield
    finally:
        for ob in objects:
            hidden, no_select, no_render = saved["hidden"][ob.name]
            ob.hide_set(hidden, view_layer=view_layer)
            ob.hide_select, ob.hide_render = no_select, no_render
        for ob in view_layer.objects:
            if ob is not None:
                ob.select_set(False, view_layer=view_layer)
        for ob in saved["selected"]:
            ob.select_set(True, view_layer=view_layer)
        view_layer.objects.active = saved["active"]
        scene.render.engine = saved["engine"]


def _own_materials(lod) -> tuple:
    """Fill every material slot of the LOD with a copy of its material (node-based), or a
    new material where the slot is empty, so the source's materials stay untouched.

    Slots linked to the object get the copy on the object: Cycles bakes into the
    material a slot shows, and an object-linked slot hides the mesh's. Returns (the
    distinct materials now in the slots, :func:`_restore`'s record of what was there)."""
    mesh = lod.data
    added_slot = not lod.material_slots
    if added_slot:
        mesh.materials.append(None)
    originals = [slot.material for slot in lod.material_slots]
    copies = {}
    for slot, mat in zip(lod.material_slots, originals):
        key = None if mat is None else mat.name
        if key not in copies:
            copy = bpy.data.materials.new(f"{lod.name}_Material") if mat is None else mat.copy()
            if mat is not None:
                copy.name = f"{mat.name}_{lod.name}"
            copy.use_nodes = True
            copy[BAKED_PROP] = lod.name
            copies[key] = copy
        slot.material = copies[key]  # on the object or the mesh, as the slot is linked
    return list(copies.values()), (originals, added_slot)


def _restore(lod, record, materials, image) -> None:
    """Undo :func:`_own_materials` and the image for a LOD whose bake failed: its slots
    get their materials back, and the copies and the image (ours, unused now) go."""
    originals, added_slot = record
    for slot, mat in zip(lod.material_slots, originals):
        slot.material = mat
    if added_slot:
        lod.data.materials.pop()
    for mat in materials:
        if mat.users == 0:
            bpy.data.materials.remove(mat)
    if image is not None and image.users == 0:
        bpy.data.images.remove(image)


def baked_materials(ob) -> list:
    """The materials a bake made for ``ob`` (BAKED_PROP set) in its slots, object- or
    mesh-linked; read them before the object goes, for :func:`remove_unused`."""
    found = [slot.material for slot in ob.material_slots]
    if ob.type == 'MESH':
        found += list(ob.data.materials)
    return list({m.as_pointer(): m for m in found if m is not None and BAKED_PROP in m}.values())


def remove_unused(materials) -> None:
    """Remove those of ``materials`` (a bake's copies, from :func:`baked_materials`) that
    nothing uses any more, then their baked images that nothing uses any more.

    Only data carrying BAKED_PROP goes, and only at zero users: a copy the artist put on
    another object, or gave a fake user, stays, and so does every image of the artist's
    (the copies share the source material's textures)."""
    images = []
    for mat in materials:
        if BAKED_PROP not in mat or mat.users != 0:
            continue
        if mat.node_tree is not None:
            images += [n.image for n in mat.node_tree.nodes if n.type == 'TEX_IMAGE' and n.image is not None]
        bpy.data.materials.remove(mat)
    for image in {i.as_pointer(): i for i in images}.values():
        if BAKED_PROP in image and image.users == 0:
            bpy.data.images.remove(image)


def _image_nodes(materials, image) -> list:
    """An Image Texture node of ``image`` in each material, made active: Cycles bakes into
    the active image node of every material of the active object."""
    nodes = []
    for mat in materials:
        tree = mat.node_tree
        node = tree.nodes.new("ShaderNodeTexImage")
        node.image = image
        node.label = "Baked normals (Line Quadric LOD)"
        tree.nodes.active = node
        nodes.append(node)
    return nodes


def _use_normal_map(materials, nodes, uv_name) -> list:
    """Link each image node through a Normal Map node to the free Normal inputs; returns
    the materials whose Principled BSDF already had a normal input (left as they were)."""
    busy = []
    for mat, node in zip(materials, nodes):
        tree = mat.node_tree
        normal_map = tree.nodes.new("ShaderNodeNormalMap")
        normal_map.uv_map = uv_name or ""
        tree.links.new(node.outputs["Color"], normal_map.inputs["Color"])
        for bsdf in (n for n in tree.nodes if n.type == 'BSDF_PRINCIPLED'):
            if bsdf.inputs["Normal"].is_linked:
                busy.append(mat.name)
            else:
                tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    return busy


def _cycles_bake(lod, distance: float) -> set:
    """Cycles' bake of the selected source onto the active ``lod`` (Blender's operator
    result; a RuntimeError is an error it reported)."""
    uv_name = lod.data.uv_layers.active.name
    return bpy.ops.object.bake(type='NORMAL', use_selected_to_active=True, cage_extrusion=distance,
                               max_ray_distance=2.0 * distance, normal_space='TANGENT',
                               margin=BAKE_MARGIN_PIXELS, uv_layer=uv_name)


def _select_pair(view_layer, source, lod) -> None:
    """Source selected, LOD selected and active, nothing else: Cycles' selected to active."""
    for ob in view_layer.objects:
        if ob is not None:
            ob.select_set(False, view_layer=view_layer)
    source.select_set(True, view_layer=view_layer)
    lod.select_set(True, view_layer=view_layer)
    view_layer.objects.active = lod


def _bake_lod(view_layer, source, lod, distance: float, resolution: int) -> list:
    """Bake one LOD into a new packed image in copies of its materials; returns warnings.

    A bake Blender refuses (an error, or a result other than FINISHED: it then only
    prints why, e.g. "No active image found") leaves the LOD as it was, with a warning;
    any other exception (Ctrl-C) also undoes the copies, then goes on up."""
    image = bpy.data.images.new(f"{lod.name}_normal", resolution, resolution, alpha=False)
    image.colorspace_settings.name = 'Non-Color'
    image[BAKED_PROP] = lod.name
    materials, record = _own_materials(lod)
    try:
        nodes = _image_nodes(materials, image)
        _select_pair(view_layer, source, lod)
        try:
            result = _cycles_bake(lod, distance)
            why = None if 'FINISHED' in result else f"Blender's bake ended {', '.join(sorted(result))}"
        except RuntimeError as ex:
            why = str(ex).strip()
    except BaseException:
        _restore(lod, record, materials, image)
        raise
    if why is not None:
        _restore(lod, record, materials, image)
        return [f"{lod.name}: no normal map baked ({why}); it keeps its materials"]
    image.pack()
    uv_name = lod.data.uv_layers.active.name
    busy = _use_normal_map(materials, nodes, uv_name)
    if busy:
        return [f"{lod.name}: {', '.join(busy)} already had a normal input; the baked map "
                f"({image.name}) is in the material but not linked"]
    return []


def bake_chain(context, source, lods: list, levels: list, resolution: int, diagonal: float) -> list:
    """Bake ``source`` onto each of ``lods`` (their report ``levels`` give the measured
    distance); returns warnings (a LOD without UVs is skipped, a material whose normal
    input is taken keeps it, a failed bake leaves its LOD unbaked)."""
    warnings = []
    scene, view_layer = context.scene, context.view_layer
    with _bake_scene(scene, view_layer, [source, *lods]):
        for lod, level in zip(lods, levels):
            if not lod.data.uv_layers:
                warnings.append(f"{lod.name}: no UV map, no normal map baked (unwrap the source)")
                continue
            hausdorff = level.get("hausdorff_percent")
            distance = (hausdorff / 100.0 * diagonal * CAGE_MARGIN) if hausdorff else CAGE_FALLBACK * diagonal
            distance = max(distance, 1e-4 * diagonal)
            warnings.extend(_bake_lod(view_layer, source, lod, distance, resolution))
    return warnings
