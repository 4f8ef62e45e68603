# SPDX-License-Identifier: GPL-3.0-or-later
"""Show Deviation: a LOD's heat map in the 3D viewport, in one click, and back.

The active LOD object (one Generate LODs made: it names its source in ``lod_source``)
gets the heat map of addon/pure/level_deviation.py if its mesh does not carry it yet
(measured now, as the report measures it: the source read as Generate reads it, with
the panel's Apply Modifiers), the colour attribute is made its mesh's active one, and
the 3D viewports switch to Solid shading coloured by the active attribute. What the
viewports and meshes showed before is kept in the scene's settings (``deviation_view``,
JSON) until Back puts it back. The source object is only read.
"""
from __future__ import annotations

import json

import bpy

from .pure import deviation_search
from .pure import level_deviation
from . import mesh_io
from .lod_objects import LEVEL_PROP, SOURCE_PROP


def source_of(ob):
    """The object ``ob`` is a LOD of, or None (not a LOD, or its source is gone)."""
    if ob is None or ob.type != 'MESH' or LEVEL_PROP not in ob:
        return None
    source = bpy.data.objects.get(ob.get(SOURCE_PROP, ""))
    return source if mesh_io.draws_geometry(source) else None


def blocker(context):
    """Why Show Deviation cannot run, or None."""
    ob = context.active_object
    if ob is None or ob.type != 'MESH' or LEVEL_PROP not in ob:
        return "Make a LOD object active (one that Generate LODs made)"
    if source_of(ob) is None:
        return f'The source of "{ob.name}" ("{ob.get(SOURCE_PROP, "")}") is no longer in the file'
    if context.mode != 'OBJECT':
        return "Switch to Object Mode first"
    return None


def has_heat(mesh) -> bool:
    return (level_deviation.HEAT_ATTRIBUTE in mesh.color_attributes
            and level_deviation.DISTANCE_ATTRIBUTE in mesh.attributes)


def paint(context, lod_ob, use_modifiers: bool = True) -> float:
    """Measure ``lod_ob`` against its source and write the heat map onto its mesh (the
    colour and distance attributes and the scale, as Deviation Colors does at
    generation); returns the scale (the distance shown red, mesh units)."""
    source = source_of(lod_ob)
    _, depsgraph = mesh_io.scene_and_depsgraph(context)
    data, _ = mesh_io.read_object(source, depsgraph, use_modifiers)
    level = mesh_io.read_mesh(lod_ob.data, group_names=lod_ob.vertex_groups.keys())
    report = deviation_search.deviation_report(data, level)
    distances, colors, scale = level_deviation.heat_layer(level, report["sampled"])
    write_heat(lod_ob.data, distances, colors, scale)
    return scale


def write_heat(mesh, distances, colors, scale: float) -> None:
    """The heat map's attributes and scale on ``mesh``, replacing earlier ones."""
    import numpy as np

    old = mesh.color_attributes.get(level_deviation.HEAT_ATTRIBUTE)
    if old is not None:
        mesh.color_attributes.remove(old)
    attr = mesh.color_attributes.new(level_deviation.HEAT_ATTRIBUTE, 'FLOAT_COLOR', 'POINT')
    attr.data.foreach_set("color", np.asarray(colors, dtype=np.float32).reshape(-1))
    mesh_io.write_point_floats(mesh, {level_deviation.DISTANCE_ATTRIBUTE: distances})
    mesh[level_deviation.SCALE_PROPERTY] = float(scale)
    mesh.update()


def view_spaces(context) -> list:
    """The 3D viewports to switch: the one the button was pressed in, else every one of
    the window's screen."""
    space = context.space_data
    if space is not None and space.type == 'VIEW_3D':
        return [space]
    screen = context.screen
    if screen is None:
        return []
    return [area.spaces.active for area in screen.areas if area.type == 'VIEW_3D']


def _space_key(space) -> str:
    """How a viewport is found again: its screen's name and its area's index there."""
    for screen in bpy.data.screens:
        for i, area in enumerate(screen.areas):
            if area.spaces.active == space:
                return f"{screen.name}\t{i}"
    return ""


def _space_of(key: str):
    name, _, index = key.partition("\t")
    screen = bpy.data.screens.get(name)
    if screen is None or not index.isdigit() or int(index) >= len(screen.areas):
        return None
    area = screen.areas[int(index)]
    return area.spaces.active if area.type == 'VIEW_3D' else None


def saved(settings) -> dict:
    try:
        value = json.loads(settings.deviation_view) if settings.deviation_view else {}
    except ValueError:
        return {}
    return value if isinstance(value, dict) else {}


def show(context, settings, lod_ob) -> int:
    """Solid shading by attribute colour in the viewports, the heat map the LOD's active
    colour; what they showed before kept in ``settings.deviation_view`` (the first time
    only: Back returns to what was there before the first Show). Returns how many
    viewports were switched."""
    state = saved(settings)
    spaces = state.setdefault("spaces", {})
    meshes = state.setdefault("meshes", {})
    switched = 0
    for space in view_spaces(context):
        key = _space_key(space)
        if key and key not in spaces:
            spaces[key] = {"type": space.shading.type, "color_type": space.shading.color_type}
        space.shading.type = 'SOLID'
        space.shading.color_type = 'VERTEX'
        switched += 1
    mesh = lod_ob.data
    if mesh.name not in meshes:
        meshes[mesh.name] = mesh.color_attributes.active_color_name or ""
    mesh.color_attributes.active_color_name = level_deviation.HEAT_ATTRIBUTE
    settings.deviation_view = json.dumps(state)
    return switched


def back(settings) -> int:
    """Put back what the viewports and meshes showed before Show Deviation; returns how
    many viewports were put back."""
    state = saved(settings)
    restored = 0
    for key, shading in state.get("spaces", {}).items():
        space = _space_of(key)
        if space is not None:
            space.shading.type = shading["type"]
            space.shading.color_type = shading["color_type"]
            restored += 1
    for name, active in state.get("meshes", {}).items():
        mesh = bpy.data.meshes.get(name)
        if mesh is not None and active in mesh.color_attributes:
            mesh.color_attributes.active_color_name = active
    settings.deviation_view = ""
    return restored
