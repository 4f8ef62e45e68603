# SPDX-License-Identifier: GPL-3.0-or-later
"""Everything that touches bpy: the panel, the operators, mesh I/O and LOD objects.

Modules (one idea each):
    _core           where ``core`` is imported from (extension vs. top-level layout)
    edges           edge bookkeeping in plain NumPy (feature edges, sharp edges, seams)
    vertex_groups   vertex-group weights in bulk (no per-vertex loops)
    mesh_data       MeshData, the arrays a mesh is read into and written from (no bpy)
    mesh_io         Blender meshes <-> NumPy arrays (foreach_get / foreach_set)
    settings        SETTINGS, the one table of the settings, and what derives from it: LodSettings,
                    the command line's options; LodError, LodCancelled (no bpy)
    importance      what the Importance settings mean as core parameters
    lod             generate_lods(): read, simplify, write, link (no UI)
    deviation_search  LOD levels by measured deviation: the core's tracked bound, the lean
                    run, then the ladder of rungs refined between rungs
    skin_fit        LOD skin weights fitted to the rig's sample poses; coarse levels checked
                    against a run without the poses
    job             LodJob: the LOD run of the panel and the command line (worker thread, Esc cancel)
    lod_group       the chain named for game engines: source "<name>_LOD0", the Unreal LOD group
    props           the settings as Blender properties (operator and scene share them)
    operators       Generate LODs, Paint Importance, Importance from Armature, Show Deviation
    panel           the sidebar panel
    measure         surface deviation and the LOD report numbers
    bvh             the closest-point trees (Blender's mathutils) measure queries
    level_deviation where a LOD differs: per vertex (the heat map), per material and painted
                    region (the report), the posed numbers' summary (no bpy)
    posed_deviation the posed distance of skinned LODs over the armature's own actions
    deviation_view  Show Deviation: a LOD's heat map in the viewport, and back
    cli             the command line's entry point (blender -c line_quadric_lod, -P, python <checkout>)
    headless/       the command line's parts (its __init__ lists them)

The submodules that need bpy are imported inside register(), so the pure-NumPy parts
(edges, settings, importance, mesh_data, level_deviation) import without Blender.
"""
from . import bvh as _bvh
from .measure import set_tree_builder as _set_tree_builder

# The deviation measurement queries Blender's closest-point trees (mathutils, imported
# only when a tree is built): wherever the package is imported, measure.py has them.
_set_tree_builder(_bvh.build_tree)

_classes = []
_cli_commands = []  # handles from bpy.utils.register_cli_command


def register():
    import bpy

    from . import cli, operators, panel, props

    _classes[:] = [props.LineQuadricLodSettings, *operators.classes, *panel.classes]
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.line_quadric_lod = bpy.props.PointerProperty(type=props.LineQuadricLodSettings)
    # `blender -b scene.blend -c line_quadric_lod [options]` (Blender 4.2+).
    _cli_commands.append(bpy.utils.register_cli_command(cli.COMMAND_ID, cli.cli_command))


def unregister():
    import bpy

    while _cli_commands:
        bpy.utils.unregister_cli_command(_cli_commands.pop())
    if hasattr(bpy.types.Scene, "line_quadric_lod"):
        del bpy.types.Scene.line_quadric_lod
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
    _classes.clear()
