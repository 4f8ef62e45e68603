# SPDX-License-Identifier: GPL-3.0-or-later
"""The LOD settings as Blender properties, derived from the table in settings.py.

``settings_properties()`` gives fresh property definitions named exactly like the fields
of :class:`settings.LodSettings`; the Generate operator and the scene's settings group
(which the panel edits and the operator starts from) both take their annotations from it.
"""
from __future__ import annotations

import json

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from .pure.settings import SETTINGS

_PROPERTY = {bool: BoolProperty, int: IntProperty, float: FloatProperty, str: StringProperty}


def settings_properties(operator: bool = False) -> dict:
    """Fresh bpy property definitions for every setting of settings.SETTINGS (same names,
    defaults, ranges, labels and tooltips).

    operator=True marks them SKIP_SAVE: the operator must not remember its last values,
    because started from the panel it takes the panel's settings for every property the
    caller did not set (Blender would otherwise pre-set remembered values).
    """
    opts = {"options": {'SKIP_SAVE'}} if operator else {}
    props = {}
    for s in SETTINGS:
        kw = dict(name=s.label, default=s.default, description=s.tooltip, **opts)
        if s.low is not None:
            kw["min"] = s.low
        if s.high is not None:
            kw["max"] = s.high
        kw.update(s.blender)
        props[s.name] = (EnumProperty(items=list(s.items), **kw) if s.items else _PROPERTY[s.kind](**kw))
    return props


class LineQuadricLodSettings(bpy.types.PropertyGroup):
    """The panel's settings (scene-wide) and the last run's report."""

    __annotations__ = {
        **settings_properties(),
        "last_report": StringProperty(
            name="Last Report", default="", options={'HIDDEN'},
            description="JSON list of the last run's per-object reports"),
        "deviation_view": StringProperty(
            name="Deviation View", default="", options={'HIDDEN'},
            description="JSON: what the viewports and LOD meshes showed before Show Deviation "
                        "(addon/deviation_view.py), for Back"),
    }

    def report_list(self) -> list:
        try:
            value = json.loads(self.last_report) if self.last_report else []
        except ValueError:
            return []
        return value if isinstance(value, list) else []
