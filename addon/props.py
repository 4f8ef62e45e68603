# SPDX-License-Identifier: GPL-3.0-or-later
"""The LOD settings as Blender properties, defined once for the operator and the panel.

``settings_properties()`` gives fresh property definitions named exactly like the fields
of :class:`lod.LodSettings`; the Generate operator and the scene's settings group (which
the panel edits and the operator starts from) both take their annotations from it.
"""
from __future__ import annotations

import json

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from .settings import LodSettings

IMPORTANCE_SOURCES = [
    ('NONE', "None", "Every vertex counts the same"),
    ('VERTEX_GROUP', "Vertex Group",
     "A vertex group (e.g. painted in Weight Paint mode): weight 1 marks the most important vertices"),
    ('ARMATURE', "Armature",
     "From the skin weights (paper Sec. 5.3): vertices shared by several deform bones, "
     "near joints, are kept so the LOD still bends well"),
]
# Kept only so files and scripts that set it still load: both act alike since issue 19.
IMPORTANCE_MODES = [
    ('SOFT', "Soft", "No longer used: importance has one calibrated mode (see Strength)"),
    ('STRONG', "Strong", "No longer used: importance has one calibrated mode (see Strength)"),
]


def settings_properties(operator: bool = False) -> dict:
    """Fresh bpy property definitions for every LodSettings field (same names).

    operator=True marks them SKIP_SAVE: the operator must not remember its last values,
    because started from the panel it takes the panel's settings for every property the
    caller did not set (Blender would otherwise pre-set remembered values).
    """
    d = LodSettings()
    opts = {"options": {'SKIP_SAVE'}} if operator else {}
    props = {
        "ratio": FloatProperty(
            name="Ratio", default=d.ratio, min=0.0001, max=1.0, subtype='FACTOR',
            description="Triangles of the first LOD as a fraction of the source's "
                        "(used when Triangles is 0)", **opts),
        "levels": IntProperty(
            name="Levels", default=d.levels, min=1, max=16,
            description="Number of LODs to make (the source itself is LOD0)", **opts),
        "level_factor": FloatProperty(
            name="Factor", default=d.level_factor, min=0.01, max=0.99, subtype='FACTOR',
            description="Each LOD has this fraction of the previous LOD's triangles "
                        "(3 levels at 0.5 from ratio 0.5: 50 %, 25 %, 12.5 %)", **opts),
        "target_triangles": IntProperty(
            name="Triangles", default=d.target_triangles, min=0,
            description="Triangle count of the first LOD; 0 uses the Ratio instead", **opts),
        "line_weight": FloatProperty(
            name="Uniformity", default=d.line_weight, min=0.0, soft_max=0.1, max=10.0,
            precision=4, step=0.01,
            description="Line-quadric weight w for every vertex: higher gives more uniform, "
                        "better shaped triangles, lower follows the shape more faithfully "
                        "(paper default 0.001; above 0.1 the shape starts to suffer)", **opts),
        "min_quality": FloatProperty(
            name="Min Quality", default=d.min_quality, min=0.0, max=1.0, subtype='FACTOR',
            description="No collapse makes a triangle thinner than this quality (1 = equilateral): "
                        "lower it (even to 0) for hard-surface parts that need their shape more than "
                        "clean triangles. Relaxed automatically only when the target needs it", **opts),
        "feature_angle": FloatProperty(
            name="Feature Angle", default=d.feature_angle, min=0.0, max=179.0, precision=1,
            description="Degrees: edges whose faces' normals differ by more than this are kept "
                        "like sharp edges, and corners where three of them meet (or where an open "
                        "border turns by half as much) stay in place. 80 keeps the right angles of "
                        "hard-surface parts; below about 60 organic meshes suffer. 0 turns it off", **opts),
        "remove_small_components": BoolProperty(
            name="Remove Small Parts", default=d.remove_small_components,
            description="When the target needs it, delete the smallest separate parts (bolts, "
                        "leaf cards) instead of stopping above the target", **opts),
        "importance_source": EnumProperty(
            name="Importance", items=IMPORTANCE_SOURCES, default=d.importance_source,
            description="Where the per-vertex importance comes from", **opts),
        "importance_group": StringProperty(
            name="Group", default=d.importance_group,
            description="Vertex group holding the importance (0 = normal, 1 = most important)", **opts),
        "importance_strength": FloatProperty(
            name="Strength", default=d.importance_strength, min=0.0, max=1.0, subtype='FACTOR',
            description="How much denser important regions stay, on flat and curved surfaces alike "
                        "(measured at 10 %): 0.1 about 1.5x, 0.25 about 2.4x, 0.5 about 4.5x, "
                        "0.75 about 12x, 1 nearly locked. 0 = importance off", **opts),
        "importance_mode": EnumProperty(
            name="Mode", items=IMPORTANCE_MODES, default=d.importance_mode,
            description="No longer used (one calibrated mode); kept so older files load", **opts),
        "preserve_boundaries": BoolProperty(
            name="Boundaries", default=d.preserve_boundaries,
            description="Keep open boundaries (holes, borders) in place", **opts),
        "boundary_strength": FloatProperty(
            name="Strength", default=d.boundary_strength, min=0.0, soft_max=10.0, max=1000.0,
            description="Weight of the planes that hold open boundaries (1 = as strong as the surface)", **opts),
        "preserve_seams": BoolProperty(
            name="UV Seams", default=d.preserve_seams,
            description="Keep UV seams: seam vertices only slide along the seam, UVs never flip", **opts),
        "seam_strength": FloatProperty(
            name="Strength", default=d.seam_strength, min=0.0, soft_max=10.0, max=1000.0,
            description="Extra weight holding seam edges in place (paper Sec. 4.4.2)", **opts),
        "preserve_sharp": BoolProperty(
            name="Sharp Edges", default=d.preserve_sharp,
            description="Keep edges marked sharp (paper Sec. 4.4.2, dihedral-plane quadrics)", **opts),
        "sharp_strength": FloatProperty(
            name="Strength", default=d.sharp_strength, min=0.0, soft_max=10.0, max=1000.0,
            description="Weight holding sharp edges in place", **opts),
        "preserve_materials": BoolProperty(
            name="Material Borders", default=d.preserve_materials,
            description="Keep the borders between faces of different materials", **opts),
        "material_strength": FloatProperty(
            name="Strength", default=d.material_strength, min=0.0, soft_max=10.0, max=1000.0,
            description="Weight holding material borders in place", **opts),
        "use_modifiers": BoolProperty(
            name="Apply Modifiers", default=d.use_modifiers,
            description="Simplify the mesh as the modifiers make it (Armature modifiers excepted: "
                        "each LOD gets its own); off: the base mesh", **opts),
        "measure_deviation": BoolProperty(
            name="Measure Deviation", default=d.measure_deviation,
            description="Measure each LOD's distance to the source for the report "
                        "(takes about a second per LOD on large meshes)", **opts),
    }
    missing = set(LodSettings.names()) ^ set(props)
    if missing:  # a developer error: scripts rely on these names matching
        raise RuntimeError(f"operator properties and LodSettings disagree: {sorted(missing)}")
    return props


class LineQuadricLodSettings(bpy.types.PropertyGroup):
    """The panel's settings (scene-wide) and the last run's report."""

    __annotations__ = {
        **settings_properties(),
        "last_report": StringProperty(
            name="Last Report", default="", options={'HIDDEN'},
            description="JSON list of the last run's per-object reports"),
    }

    def report_list(self) -> list:
        try:
            value = json.loads(self.last_report) if self.last_report else []
        except ValueError:
            return []
        return value if isinstance(value, list) else []
