# SPDX-License-Identifier: GPL-3.0-or-later
"""The Blender side: the panel, the operators, mesh I/O, LOD objects and the command line.

What needs no Blender lives in ``pure/`` (its __init__ lists its modules; tests keep it free
of Blender, tests/test_core_purity.py). Modules here (one idea each):
    vertex_groups   vertex-group weights in bulk (no per-vertex loops)
    mesh_io         Blender meshes <-> NumPy arrays (foreach_get / foreach_set)
    lod             the LOD run's orchestrator: prepare (read), compute, commit; generate_lods()
    commit          the commit phase: LOD meshes and objects written and linked, switch
                    numbers set, normals baked, skinned chains measured posed
    lod_objects     how LOD objects are marked (source, level, switch numbers) and found
    rig             reading the rig: the deforming armature, its skin columns, sample poses
    object_importance  an object's importance g from the settings' source, and its preview
    asset           several objects as one asset: its bounds, budget split and report
    job             LodJob: the LOD run of the panel and the command line (worker thread, Esc cancel)
    lod_group       the chain named for game engines: source "<name>_LOD0", the Unreal LOD group
    gltf_lod        the glTF exporter's hook: MSFT_lod and the switch numbers
    bake            Bake Normals: each LOD's lost detail baked into a normal map
    props           the settings as Blender properties (operator and scene share them)
    operators       Generate LODs, Paint Importance, Importance from Armature, Show Deviation
    panel           the sidebar panel
    sample          the built-in sample (a mesh with painted importance)
    bvh             the closest-point trees (Blender's mathutils) pure/measure.py queries
    posed_deviation the posed distance of skinned LODs over the armature's own actions
    deviation_view  Show Deviation: a LOD's heat map in the viewport, and back
    cli             the command line's entry point (blender -c line_quadric_lod, -P, python <checkout>)
    headless/       the command line's parts (its __init__ lists them)

The submodules that need bpy are imported inside register(), so ``pure/`` imports
without Blender.
"""
from . import bvh as _bvh
from .pure.measure import set_tree_builder as _set_tree_builder

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
