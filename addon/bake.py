# SPDX-License-Identifier: GPL-3.0-or-later
"""The source's lost detail baked into a tangent-space normal map on each LOD (issue 22 §3).

Cycles bakes the source onto the LOD (selected to active, as artists do by hand). The
rays start from a cage pushed out by the LOD's measured distance to the source, so they
reach the detail the LOD cut through without catching far-away parts. The image goes
into copies of the LOD's materials (the source keeps its own), through a Normal Map node
into every Principled BSDF whose Normal input is free; it is packed, so the .blend and
the glTF exporter carry it. Main thread only, after the LODs are linked (lod.commit).
"""
from __future__ import annotations

import contextlib

import bpy

CAGE_MARGIN = 1.25  # the cage: this times the LOD's measured Hausdorff distance
CAGE_FALLBACK = 0.01  # of the bounding-box diagonal, when the LOD was not measured
BAKE_MARGIN_PIXELS = 8  # texels grown past each UV island (mip-mapping needs them)


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


def _own_materials(lod) -> list:
    """The LOD's material slots filled with copies of its materials (node-based), or a new
    material where a slot is empty, so the source's materials stay untouched."""
    mesh = lod.data
    if not mesh.materials:
        mesh.materials.append(None)
    copies = {}
    for i, mat in enumerate(mesh.materials):
        if mat is None:
            mat = bpy.data.materials.new(f"{lod.name}_Material")
        else:
            if mat.name not in copies:
                copies[mat.name] = mat.copy()
                copies[mat.name].name = f"{mat.name}_{lod.name}"
            mat = copies[mat.name]
        mat.use_nodes = True
        mesh.materials[i] = mat
    return list(dict.fromkeys(mesh.materials))


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


def bake_chain(context, source, lods: list, levels: list, resolution: int, diagonal: float) -> list:
    """Bake ``source`` onto each of ``lods`` (their report ``levels`` give the measured
    distance); returns warnings (a LOD without UVs is skipped, a material whose normal
    input is taken keeps it)."""
    warnings = []
    scene, view_layer = context.scene, context.view_layer
    with _bake_scene(scene, view_layer, [source, *lods]):
        for lod, level in zip(lods, levels):
            mesh = lod.data
            if not mesh.uv_layers:
                warnings.append(f"{lod.name}: no UV map, no normal map baked (unwrap the source)")
                continue
            hausdorff = level.get("hausdorff_percent")
            distance = (hausdorff / 100.0 * diagonal * CAGE_MARGIN) if hausdorff else CAGE_FALLBACK * diagonal
            distance = max(distance, 1e-4 * diagonal)
            image = bpy.data.images.new(f"{lod.name}_normal", resolution, resolution, alpha=False)
            image.colorspace_settings.name = 'Non-Color'
            materials = _own_materials(lod)
            nodes = _image_nodes(materials, image)
            for ob in view_layer.objects:
                if ob is not None:
                    ob.select_set(False, view_layer=view_layer)
            source.select_set(True, view_layer=view_layer)
            lod.select_set(True, view_layer=view_layer)
            view_layer.objects.active = lod
            bpy.ops.object.bake(type='NORMAL', use_selected_to_active=True, cage_extrusion=distance,
                                max_ray_distance=2.0 * distance, normal_space='TANGENT',
                                margin=BAKE_MARGIN_PIXELS, uv_layer=mesh.uv_layers.active.name)
            image.pack()
            busy = _use_normal_map(materials, nodes, mesh.uv_layers.active.name)
            if busy:
                warnings.append(f"{lod.name}: {', '.join(busy)} already had a normal input; the baked map "
                                f"({image.name}) is in the material but not linked")
    return warnings
