# SPDX-License-Identifier: GPL-3.0-or-later
"""The sidebar panel (View3D > Sidebar > LOD), laid out in workflow order:
Target, Uniformity, Importance, Preserve, Generate, then the last run's report."""
from __future__ import annotations

import bpy

from . import mesh_io
from .pure.settings import PRESERVE_PAIRS, LodSettings
from .pure.importance import expected_gain, pose_weight
from .operators import (
    OBJECT_OT_line_quadric_lod,
    OBJECT_OT_line_quadric_lod_deviation_back,
    OBJECT_OT_line_quadric_lod_from_armature,
    OBJECT_OT_line_quadric_lod_from_shape_keys,
    OBJECT_OT_line_quadric_lod_paint,
    OBJECT_OT_line_quadric_lod_paint_limit,
    OBJECT_OT_line_quadric_lod_preview_importance,
    has_shape_keys,
    OBJECT_OT_line_quadric_lod_show_deviation,
)



def chain_preview(settings) -> str:
    """What the Target settings will make, e.g. "50% · 25% · 12.5%" (LodSettings.chain)."""
    kind, values = LodSettings.from_properties(settings).chain()
    if kind == "deviations":
        return " · ".join(f"≤{v}" for v in values) + " of the size"
    if kind == "triangles":
        return " · ".join(f"{c:,}" for c in values) + " triangles"
    return " · ".join(f"{100 * r:.3g}%" for r in values)


def breakdown_lines(level: dict) -> list:
    """The Last Run box's lines for one level beyond its row: the largest distance per
    material (when there are several) and per painted region, and the posed distance over
    the rig's actions (addon/pure/level_deviation.py, addon/posed_deviation.py)."""
    lines = []
    name = f"LOD{level['level']}"
    materials = level.get("materials") or {}
    if len(materials) > 1:
        lines.append(f"{name} max % by material: " + ", ".join(
            f"{m} {s['max_percent']:.3f}" for m, s in materials.items() if s["max_percent"] is not None))
    regions = level.get("regions") or {}
    if regions:
        lines.append(f"{name} max % by region: " + ", ".join(
            f"{r} {s['max_percent']:.3f}" if s["max_percent"] is not None else f"{r} -" for r, s in regions.items()))
    posed = level.get("posed")
    if posed and posed.get("frames"):
        lines.append(f"{name} posed, {posed['frames']} frames: max {posed['hausdorff_percent']['max']:.3f} %, "
                     f"mean {posed['mean_percent']['mean']:.4f} %")
    elif posed and posed.get("note") and level["level"] == 1:  # (the same for every level)
        lines.append(f"{name} posed: {posed['note']}")
    return lines


class VIEW3D_PT_line_quadric_lod(bpy.types.Panel):
    bl_label = "Line Quadric LOD"
    bl_idname = "VIEW3D_PT_line_quadric_lod"
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "LOD"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.line_quadric_lod
        ob = context.active_object
        is_mesh = ob is not None and ob.type == 'MESH'
        if not mesh_io.draws_geometry(ob):  # curves, text and the like draw a mesh, and get LODs
            layout.label(text="Select a mesh object", icon='INFO')

        box = layout.box()
        box.label(text="Target", icon='MOD_DECIM')
        box.row().prop(settings, "target_by", expand=True)
        col = box.column(align=True)
        if settings.target_by == 'DEVIATION':
            col.prop(settings, "max_deviation")
        elif settings.target_by == 'SCREEN':
            col.prop(settings, "pixel_error")
            col.prop(settings, "screen_height")
        else:
            col.prop(settings, "target_triangles")
            row = col.row(align=True)
            row.active = settings.target_triangles == 0
            row.prop(settings, "ratio")
        col.prop(settings, "levels")
        col.prop(settings, "level_factor")
        box.label(text="LOD1..%d: %s" % (settings.levels, chain_preview(settings)))
        if len(context.selected_objects) > 1:
            box.prop(settings, "asset_budget")
        box.prop(settings, "remove_small_components")

        box = layout.box()
        box.label(text="Shape", icon='MESH_GRID')
        col = box.column(align=True)
        col.prop(settings, "line_weight")
        col.prop(settings, "min_quality")
        col.prop(settings, "feature_angle")

        box = layout.box()
        box.label(text="Importance", icon='WPAINT_HLT')
        box.prop(settings, "importance_source", text="Source")
        if settings.importance_source == 'VERTEX_GROUP':
            if is_mesh:
                box.prop_search(settings, "importance_group", ob, "vertex_groups", text="Group")
                if settings.importance_group and settings.importance_group not in ob.vertex_groups:
                    box.label(text=f'"{ob.name}" has no group "{settings.importance_group}"', icon='ERROR')
            else:
                box.prop(settings, "importance_group", text="Group")
        if settings.importance_source == 'SHAPE_KEYS' and is_mesh and not has_shape_keys(ob):
            box.label(text=f'"{ob.name}" has no shape keys', icon='ERROR')
        if settings.importance_source == 'ARMATURE':
            box.prop(settings, "importance_strength")
            # Not a density: the rig's sample poses count in the error (addon/pure/importance.py).
            box.label(text=f"Sample poses count {pose_weight(settings.importance_strength):g}x the rest shape")
        elif settings.importance_source != 'NONE':
            box.prop(settings, "importance_strength")
            # What the strength buys, from the calibration (addon/pure/importance.py).
            box.label(text=f"Importance 1: about {expected_gain(settings.importance_strength):.1f}x "
                           f"as dense as the rest")
        row = box.row(align=True)
        row.operator(OBJECT_OT_line_quadric_lod_paint.bl_idname, icon='BRUSH_DATA')
        row.operator(OBJECT_OT_line_quadric_lod_from_armature.bl_idname, icon='ARMATURE_DATA')
        # Only where it can do something (its poll explains otherwise).
        if (is_mesh and has_shape_keys(ob)) or settings.importance_source == 'SHAPE_KEYS':
            box.operator(OBJECT_OT_line_quadric_lod_from_shape_keys.bl_idname, icon='SHAPEKEY_DATA')
        if settings.importance_source not in ('NONE', 'ARMATURE'):  # ARMATURE has no per-vertex g
            box.operator(OBJECT_OT_line_quadric_lod_preview_importance.bl_idname, icon='HIDE_OFF')

        box = layout.box()
        box.label(text="Limit", icon='CON_DISTLIMIT')
        if is_mesh:
            box.prop_search(settings, "limit_group", ob, "vertex_groups", text="Group")
        else:
            box.prop(settings, "limit_group", text="Group")
        if settings.limit_group:
            if is_mesh and settings.limit_group not in ob.vertex_groups:
                box.label(text=f'"{ob.name}" has no group "{settings.limit_group}"', icon='ERROR')
            row = box.row(align=True)
            row.prop(settings, "limit_distance")
            row.prop(settings, "limit_unit", text="")
        box.operator(OBJECT_OT_line_quadric_lod_paint_limit.bl_idname, icon='BRUSH_DATA')

        box = layout.box()
        box.label(text="Preserve", icon='LOCKED')
        col = box.column(align=True)
        for flag, strength in PRESERVE_PAIRS:
            row = col.row(align=True)
            row.prop(settings, flag)
            sub = row.row(align=True)
            sub.active = getattr(settings, flag)
            sub.prop(settings, strength, text="")

        col = layout.column(align=True)
        col.prop(settings, "use_modifiers")
        col.prop(settings, "measure_deviation")
        col.prop(settings, "deviation_colors")
        col.prop(settings, "hard_edge_angle")
        row = col.row(align=True)
        row.prop(settings, "bake_normals")
        sub = row.row(align=True)
        sub.active = settings.bake_normals
        sub.prop(settings, "bake_resolution", text="")
        # The button carries the panel's settings (the operator remembers none itself), so
        # Adjust Last Operation afterwards starts from exactly what the panel showed.
        op = layout.operator(OBJECT_OT_line_quadric_lod.bl_idname, icon='MOD_DECIM')
        for name in LodSettings.names():
            setattr(op, name, getattr(settings, name))
        # The active LOD's distance to its source as colours (addon/deviation_view.py), and back.
        row = layout.row(align=True)
        row.operator(OBJECT_OT_line_quadric_lod_show_deviation.bl_idname, icon='MOD_VERTEX_WEIGHT')
        if settings.deviation_view:
            row.operator(OBJECT_OT_line_quadric_lod_deviation_back.bl_idname, icon='LOOP_BACK')

        self.draw_report(layout, settings)

    @staticmethod
    def draw_report(layout, settings):
        reports = settings.report_list()
        if not reports:
            return
        box = layout.box()
        box.label(text="Last Run", icon='INFO')
        for rep in reports:
            box.label(text=f"{rep['object']}: {rep['source_triangles']:,} triangles, {rep['seconds']:.2f} s")
            grid = box.grid_flow(row_major=True, columns=6, even_columns=False, align=True)
            for title in ("LOD", "Triangles", "Max %", "Mean %", "Normals °", "Quality"):
                grid.label(text=title)
            for level in rep["levels"]:
                grid.label(text=f"LOD{level['level']}")
                grid.label(text=f"{level['triangles']:,}")
                grid.label(text=f"{level['hausdorff_percent']:.3f}" if "hausdorff_percent" in level else "-")
                grid.label(text=f"{level['mean_percent']:.4f}" if "mean_percent" in level else "-")
                # The shading normals' mean angle to the source's (measure.normal_deviation).
                grid.label(text=f"{level['normal_mean_degrees']:.1f}" if "normal_mean_degrees" in level else "-")
                grid.label(text=f"{level['mean_quality']:.2f}")
            for level in rep["levels"]:
                # Each shape key's deviation (the LOD and the source with the key at 1): the worst.
                if level.get("shape_keys"):
                    worst = max(level["shape_keys"], key=lambda entry: entry["hausdorff_percent"])
                    mean = sum(entry["mean_percent"] for entry in level["shape_keys"]) / len(level["shape_keys"])
                    # The mean over each key's own region (key_deviation.py), where a blink shows.
                    regions = [entry["region_mean_percent"] for entry in level["shape_keys"]
                               if "region_mean_percent" in entry]
                    where = f" (in their regions {sum(regions) / len(regions):.4f} %)" if regions else ""
                    box.label(text=f"LOD{level['level']} keys at 1: mean {mean:.4f} %{where}, worst "
                                   f"\"{worst['name']}\" {worst['hausdorff_percent']:.3f} % max")
            for level in rep["levels"]:
                if "importance" in level:
                    imp = level["importance"]
                    # "keyed region" for Source Shape Keys: nobody painted it.
                    box.label(text=f"LOD{level['level']}: {imp.get('region', 'painted')} region kept "
                                   f"{imp['painted_kept_percent']:.0f} %, "
                                   f"the rest {imp['rest_kept_percent']:.0f} % "
                                   f"({imp['painted_density']:.1f}x as dense)")
            for level in rep["levels"]:
                # The painted limit, measured (addon/pure/limits.py): 1 = at the limit.
                if level.get("limit"):
                    kept = level["limit"]
                    box.label(text=f"LOD{level['level']} limit \"{kept['group']}\": {100 * kept['limit_used']:.0f} % "
                                   f"of it used, region max {kept['region_hausdorff_percent']:.3f} %",
                              icon='CHECKMARK' if kept["within"] else 'ERROR')
            for level in rep["levels"]:
                for line in breakdown_lines(level):
                    box.label(text=line)
            for warning in rep.get("warnings", []):
                box.label(text=warning, icon='ERROR')


classes = (VIEW3D_PT_line_quadric_lod,)
