# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's operators: Generate LODs, Paint Importance, Importance from Armature,
Importance from Shape Keys, Preview Importance, Paint Limit, Show Deviation and its way back.

Every failure reaches the user as a ``self.report`` line (and {'CANCELLED'}), never as
a Python traceback; unexpected errors are printed to the console for bug reports.
"""
from __future__ import annotations

import json
import traceback

import numpy as np

import bpy

from . import deviation_view, lod_objects, mesh_io, object_importance, vertex_groups
from .pure.importance import expected_gain, key_strength_note
from .headless.report import noted_names, object_notes
from .job import LodJob
from .pure.settings import LodCancelled, LodError, LodSettings
from .props import settings_properties
from .pure.settings import IMPORTANCE_GROUP, LIMIT_GROUP, PREVIEW_GROUP
_PROGRESS_STEPS = 1000
# Events a running generation lets through: looking around changes no data.
_NAVIGATION = {'MIDDLEMOUSE', 'WHEELUPMOUSE', 'WHEELDOWNMOUSE', 'TRACKPADPAN', 'TRACKPADZOOM',
               'NDOF_MOTION', 'MOUSEMOVE', 'INBETWEEN_MOUSEMOVE'}


def scene_settings(context):
    return getattr(context.scene, "line_quadric_lod", None)


def selected_meshes(context) -> list:
    """Selected mesh objects (and curves, text, surfaces and metaballs, which draw one:
    mesh_io.GEOMETRY_TYPES), except LODs made by an earlier run (they would be replaced
    while being read; a source selected together with its LODs is the usual case)."""
    return [ob for ob in context.selected_objects
            if mesh_io.draws_geometry(ob) and lod_objects.LEVEL_PROP not in ob]


def _generate_blocker(context):
    """Why Generate LODs cannot run in this context, or None."""
    if context.mode != 'OBJECT':
        return "Switch to Object Mode to generate LODs"
    if not selected_meshes(context):
        if any(ob.type == 'MESH' for ob in context.selected_objects):
            return "Only LOD objects are selected: select their source mesh"
        return "Select one or more mesh objects"
    return None


def _summary(reports) -> str:
    parts = []
    for rep in reports:
        counts = " / ".join(f"{lv['triangles']:,}" for lv in rep["levels"])
        made = f"sharing {rep['shares']}'s LOD meshes" if rep.get("shares") else f"in {rep['seconds']:.1f} s"
        text = f"{rep['object']}: {len(rep['levels'])} LODs ({counts} triangles) {made}"
        importance = [lv["importance"] for lv in rep["levels"] if "importance" in lv]
        if importance:
            text += (f", {importance[0].get('region', 'painted')} region "
                     + " / ".join(f"{imp['painted_density']:.1f}x" for imp in importance) + " as dense as the rest")
        parts.append(text)
    return "; ".join(parts)


class OBJECT_OT_line_quadric_lod(bpy.types.Operator):
    """Make a chain of LODs of every selected mesh object (line-quadric simplification)"""

    bl_idname = "object.line_quadric_lod"
    bl_label = "Generate LODs"
    bl_options = {'REGISTER', 'UNDO'}

    __annotations__ = settings_properties(operator=True)

    _job = None
    _timer = None

    @classmethod
    def poll(cls, context):
        blocker = _generate_blocker(context)
        if blocker:
            cls.poll_message_set(blocker)
            return False
        return True

    def _settings(self) -> LodSettings:
        return LodSettings.from_properties(self)

    def invoke(self, context, event):
        # Started from the panel: take the panel's settings, except any the caller set.
        panel = scene_settings(context)
        if panel is not None:
            for name in LodSettings.names():
                if not self.properties.is_property_set(name):
                    setattr(self, name, getattr(panel, name))
        if bpy.app.background or context.window is None:
            return self.execute(context)  # no event loop to drive a modal run
        blocker = _generate_blocker(context)
        if blocker:
            self.report({'ERROR'}, blocker)
            return {'CANCELLED'}
        try:
            self._job = LodJob(context, selected_meshes(context), self._settings())
        except LodError as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        except Exception as ex:
            return self._unexpected(ex)
        self._job.start()
        wm = context.window_manager
        wm.progress_begin(0, _PROGRESS_STEPS)
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        context.workspace.status_text_set("Generating LODs: Esc to cancel")
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        job = self._job
        if event.type == 'ESC' and event.value == 'PRESS':
            job.cancel()
            job.wait()
            self._end_modal(context)
            self.report({'WARNING'}, "LOD generation cancelled: nothing was changed")
            return {'CANCELLED'}
        if event.type == 'TIMER':
            context.window_manager.progress_update(int(job.fraction * _PROGRESS_STEPS))
            context.workspace.status_text_set(f"Generating LODs {job.fraction:.0%}: Esc to cancel")
            if job.done:
                self._end_modal(context)
                return self._commit(context, job)
        if event.type in _NAVIGATION:
            return {'PASS_THROUGH'}
        return {'RUNNING_MODAL'}

    def _end_modal(self, context):
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        context.workspace.status_text_set(None)

    def cancel(self, context):
        # Blender ends a modal operator this way when its window closes.
        if self._job is not None:
            self._job.cancel()
            self._job.wait()
        self._end_modal(context)

    def execute(self, context):
        blocker = _generate_blocker(context)
        if blocker:
            self.report({'ERROR'}, blocker)
            return {'CANCELLED'}
        wm = context.window_manager
        wm.progress_begin(0, _PROGRESS_STEPS)
        try:
            job = LodJob(context, selected_meshes(context), self._settings())
            job.run(progress=lambda f: wm.progress_update(int(f * _PROGRESS_STEPS)))
            return self._commit(context, job)
        except LodError as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        except LodCancelled:
            self.report({'WARNING'}, "LOD generation cancelled: nothing was changed")
            return {'CANCELLED'}
        except Exception as ex:
            return self._unexpected(ex)
        finally:
            wm.progress_end()

    def _commit(self, context, job):
        try:
            reports = job.commit(context)
        except LodError as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        except LodCancelled:
            self.report({'WARNING'}, "LOD generation cancelled: nothing was changed")
            return {'CANCELLED'}
        except Exception as ex:
            return self._unexpected(ex)
        panel = scene_settings(context)
        if panel is not None:
            panel.last_report = json.dumps(reports)
        for note in job.skipped + job.asset_notes:
            self.report({'WARNING'}, note)
        # A note the copies of a shared mesh (or several parts) have alike: once, naming them.
        for warning, names in object_notes(reports).items():
            self.report({'WARNING'}, f"{noted_names(names)}: {warning}")
        self.report({'INFO'}, _summary(reports))
        return {'FINISHED'}

    def _unexpected(self, ex):
        traceback.print_exc()
        self.report({'ERROR'}, f"LOD generation failed unexpectedly ({type(ex).__name__}: {ex}); "
                               f"details in the system console")
        return {'CANCELLED'}


def _importance_blocker(context):
    ob = context.active_object
    if ob is None or ob.type != 'MESH':
        return "Make a mesh object active"
    if context.mode not in ('OBJECT', 'PAINT_WEIGHT'):
        return "Switch to Object Mode or Weight Paint mode first"
    return None


def _use_importance_group(context, ob, group):
    ob.vertex_groups.active_index = group.index
    panel = scene_settings(context)
    if panel is not None:
        panel.importance_source = 'VERTEX_GROUP'
        panel.importance_group = group.name


class _Blocked:
    """An operator whose ``blocker(context)`` says why it cannot run (or None): poll()
    explains it, execute() reports it (``report_blocker``)."""

    blocker = staticmethod(lambda context: None)

    @classmethod
    def poll(cls, context):
        blocker = cls.blocker(context)
        if blocker:
            if hasattr(cls, "poll_message_set"):
                cls.poll_message_set(blocker)
            return False
        return True

    def report_blocker(self, context) -> bool:
        blocker = self.blocker(context)
        if blocker:
            self.report({'ERROR'}, blocker)
        return bool(blocker)


class _ImportanceOperator(_Blocked):
    """Shared checks of the importance and painting helpers: an active mesh object in
    Object or Weight Paint mode."""

    blocker = staticmethod(_importance_blocker)

    def write_group(self, ob, group: str, compute):
        """``compute()`` -> (per-vertex values in [0, 1], anything else), written into the
        vertex group ``group``; returns compute's result, or None after reporting why not
        (an expected problem in its own words, anything else with its type)."""
        try:
            result = compute()
            vertex_groups.write_weights(ob, [group], result[0][:, None])
        except LodError as ex:
            self.report({'ERROR'}, str(ex))
            return None
        except Exception as ex:
            traceback.print_exc()
            self.report({'ERROR'}, f"{self.bl_label} failed ({type(ex).__name__}: {ex})")
            return None
        return result


class _PaintGroupOperator(_ImportanceOperator):
    """Make (or reuse) a vertex group, make it the panel's, and enter Weight Paint mode on it."""

    group_name = ""
    hint = ""

    def use_group(self, context, ob, group):
        raise NotImplementedError

    def execute(self, context):
        if self.report_blocker(context):
            return {'CANCELLED'}
        ob = context.active_object
        group = ob.vertex_groups.get(self.group_name) or ob.vertex_groups.new(name=self.group_name)
        self.use_group(context, ob, group)
        if ob.mode != 'WEIGHT_PAINT':
            try:
                bpy.ops.object.mode_set(mode='WEIGHT_PAINT')
            except RuntimeError as ex:
                self.report({'ERROR'}, f'Could not enter Weight Paint mode on "{ob.name}": {ex}')
                return {'CANCELLED'}
        self.report({'INFO'}, f'Painting "{self.group_name}": {self.hint}')
        return {'FINISHED'}


class OBJECT_OT_line_quadric_lod_paint(_PaintGroupOperator, bpy.types.Operator):
    """Paint where detail matters: creates (or reuses) the vertex group "LOD_Importance" and enters Weight Paint mode on it"""

    bl_idname = "object.line_quadric_lod_paint"
    bl_label = "Paint Importance"
    bl_options = {'REGISTER', 'UNDO'}
    group_name = IMPORTANCE_GROUP
    hint = "weight 1 = keep most detail"

    def use_group(self, context, ob, group):
        _use_importance_group(context, ob, group)


class OBJECT_OT_line_quadric_lod_paint_limit(_PaintGroupOperator, bpy.types.Operator):
    """Paint how far the LODs may move: creates (or reuses) the vertex group "LOD_Limit", makes it the Limit Group and enters Weight Paint mode on it (weight 1 = within Limit, 0 = free)"""

    bl_idname = "object.line_quadric_lod_paint_limit"
    bl_label = "Paint Limit"
    bl_options = {'REGISTER', 'UNDO'}
    group_name = LIMIT_GROUP
    hint = "weight 1 = the LODs stay within Limit, 0 = free"

    def use_group(self, context, ob, group):
        ob.vertex_groups.active_index = group.index
        panel = scene_settings(context)
        if panel is not None:
            panel.limit_group = group.name


class OBJECT_OT_line_quadric_lod_from_armature(_ImportanceOperator, bpy.types.Operator):
    """Bake importance from the skin weights into the vertex group "LOD_Importance" (paper Sec. 5.3: vertices near joints matter), so it can be seen and repainted"""

    bl_idname = "object.line_quadric_lod_from_armature"
    bl_label = "Importance from Armature"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        if self.report_blocker(context):
            return {'CANCELLED'}
        ob = context.active_object

        def skin_importance():
            names = ob.vertex_groups.keys()
            weights = vertex_groups.read_weights(ob.data, names, all_names=names)
            return object_importance.skin_importance_of(ob, names, weights), None

        written = self.write_group(ob, IMPORTANCE_GROUP, skin_importance)
        if written is None:
            return {'CANCELLED'}
        g = written[0]
        _use_importance_group(context, ob, ob.vertex_groups[IMPORTANCE_GROUP])
        joints = int(np.count_nonzero(g > 0))
        self.report({'INFO'}, f'"{IMPORTANCE_GROUP}": importance from the skin weights on {joints:,} of '
                              f'{len(g):,} vertices (1 = w 0.1, the paper\'s cap)')
        return {'FINISHED'}


def has_shape_keys(ob) -> bool:
    """Whether the object ``ob`` (a mesh) has shape keys besides its basis."""
    keys = getattr(ob.data, "shape_keys", None)
    return keys is not None and len(keys.key_blocks) > 1


class OBJECT_OT_line_quadric_lod_from_shape_keys(_ImportanceOperator, bpy.types.Operator):
    """Bake importance from the shape keys into the vertex group "LOD_Importance" (vertices the keys move matter, the more the farther they move), so it can be seen and repainted"""

    bl_idname = "object.line_quadric_lod_from_shape_keys"
    bl_label = "Importance from Shape Keys"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        if not super().poll(context):
            return False
        ob = context.active_object
        if not has_shape_keys(ob):
            cls.poll_message_set(f'"{ob.name}" has no shape keys')
            return False
        return True

    def execute(self, context):
        if self.report_blocker(context):
            return {'CANCELLED'}
        ob = context.active_object
        written = self.write_group(ob, IMPORTANCE_GROUP, lambda: (object_importance.shape_key_importance_of(ob), None))
        if written is None:
            return {'CANCELLED'}
        g = written[0]
        _use_importance_group(context, ob, ob.vertex_groups[IMPORTANCE_GROUP])
        keys = len(ob.data.shape_keys.key_blocks) - 1
        self.report({'INFO'}, f'"{IMPORTANCE_GROUP}": importance from {keys} shape key{"s" if keys != 1 else ""} '
                              f'on {int(np.count_nonzero(g > 0)):,} of {len(g):,} vertices '
                              f'(1 = moved as far as the keys move most)')
        return {'FINISHED'}


class OBJECT_OT_line_quadric_lod_preview_importance(_ImportanceOperator, bpy.types.Operator):
    """Show what the Importance settings will do: writes each vertex's effective importance (0 = simplified like the rest, 1 = the slider's top, nearly locked) into the vertex group "LOD_Importance_Preview" and shows it in Weight Paint mode"""

    bl_idname = "object.line_quadric_lod_preview_importance"
    bl_label = "Preview Importance"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        if self.report_blocker(context):
            return {'CANCELLED'}
        ob = context.active_object
        settings = scene_settings(context)
        settings = LodSettings.from_properties(settings) if settings is not None else LodSettings()
        written = self.write_group(ob, PREVIEW_GROUP, lambda: object_importance.importance_preview(ob, settings))
        if written is None:
            return {'CANCELLED'}
        effective, painted, strength = written
        # Shown, not selected for the LODs: the panel keeps reading the painted group.
        ob.vertex_groups.active_index = ob.vertex_groups[PREVIEW_GROUP].index
        if ob.mode != 'WEIGHT_PAINT':
            try:
                bpy.ops.object.mode_set(mode='WEIGHT_PAINT')
            except RuntimeError as ex:
                self.report({'WARNING'}, f'"{PREVIEW_GROUP}" written; Weight Paint mode failed: {ex}')
                return {'FINISHED'}
        scaled = key_strength_note(settings.importance_strength, strength)
        self.report({'INFO'}, f'"{PREVIEW_GROUP}": {painted:,} of {len(effective):,} vertices painted; at strength '
                              f'{strength:.2f} they should come out about '
                              f'{expected_gain(strength):.1f}x as dense as the rest '
                              + (f'({scaled})' if scaled else
                                 f'(preview only: paint "{settings.importance_group or IMPORTANCE_GROUP}")'))
        return {'FINISHED'}


class OBJECT_OT_line_quadric_lod_show_deviation(_Blocked, bpy.types.Operator):
    """Show where the active LOD differs from its source: its distance per vertex as colours (blue on the source, red at its largest), in Solid shading by attribute; measured now if the LOD does not carry it. The source is not changed"""

    bl_idname = "object.line_quadric_lod_show_deviation"
    bl_label = "Show Deviation"
    bl_options = {'REGISTER', 'UNDO'}
    blocker = staticmethod(deviation_view.blocker)

    def execute(self, context):
        if self.report_blocker(context):
            return {'CANCELLED'}
        ob = context.active_object
        settings = scene_settings(context)
        use_modifiers = settings.use_modifiers if settings is not None else True
        try:
            measured = not deviation_view.has_heat(ob.data)
            if measured:
                deviation_view.paint(context, ob, use_modifiers)
            switched = deviation_view.show(context, settings, ob) if settings is not None else 0
        except LodError as ex:
            self.report({'ERROR'}, str(ex))
            return {'CANCELLED'}
        except Exception as ex:
            traceback.print_exc()
            self.report({'ERROR'}, f"{self.bl_label} failed ({type(ex).__name__}: {ex})")
            return {'CANCELLED'}
        scale = ob.data.get(deviation_view.level_deviation.SCALE_PROPERTY, 0.0)
        source = deviation_view.source_of(ob)
        self.report({'INFO'}, f'"{ob.name}": {"measured, " if measured else ""}red = {scale:.4g} '
                              f'(its largest distance to "{source.name}", object units), blue = on it'
                              + ("" if switched else "; no 3D viewport to switch"))
        return {'FINISHED'}


def _not_switched(context):
    settings = scene_settings(context)
    return "Show Deviation has not switched the view" if settings is None or not settings.deviation_view else None


class OBJECT_OT_line_quadric_lod_deviation_back(_Blocked, bpy.types.Operator):
    """Put the viewport shading and the LODs' active colour back as they were before Show Deviation"""

    bl_idname = "object.line_quadric_lod_deviation_back"
    bl_label = "Back"
    bl_options = {'REGISTER', 'UNDO'}
    blocker = staticmethod(_not_switched)

    def execute(self, context):
        restored = deviation_view.back(scene_settings(context))
        self.report({'INFO'}, f"Shading put back in {restored} viewport{'s' if restored != 1 else ''}")
        return {'FINISHED'}


classes = (
    OBJECT_OT_line_quadric_lod,
    OBJECT_OT_line_quadric_lod_paint,
    OBJECT_OT_line_quadric_lod_paint_limit,
    OBJECT_OT_line_quadric_lod_from_armature,
    OBJECT_OT_line_quadric_lod_from_shape_keys,
    OBJECT_OT_line_quadric_lod_preview_importance,
    OBJECT_OT_line_quadric_lod_show_deviation,
    OBJECT_OT_line_quadric_lod_deviation_back,
)
