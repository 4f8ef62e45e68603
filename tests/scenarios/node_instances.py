"""Geometry-nodes instances for the command line (tests/test_cli_node_instances.py).
``blend_out``: "Scatter", a grid whose geometry nodes draw an icosphere on each of its
points and nothing else; "Field", a coarser grid that draws itself and a cone on each of
its points; a plain UV sphere "Ball". Returns the triangles each draws and the panel's reason
for leaving "Scatter" out. ``check``: a written .blend instead: the instances each of its
objects still draws, and which objects have a geometry-nodes modifier."""
import bpy

from addon import lod, mesh_io
from addon.pure.settings import LodSettings
from scene_tools import remove_all_objects


def _tree(name: str, instance_node: str, keep_points: bool):
    tree = bpy.data.node_groups.new(name, 'GeometryNodeTree')
    tree.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
    tree.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
    given, out = tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")
    on_points = tree.nodes.new("GeometryNodeInstanceOnPoints")
    shape = tree.nodes.new(instance_node)
    tree.links.new(given.outputs[0], on_points.inputs["Points"])
    tree.links.new(shape.outputs["Mesh"], on_points.inputs["Instance"])
    if keep_points:
        join = tree.nodes.new("GeometryNodeJoinGeometry")
        tree.links.new(on_points.outputs["Instances"], join.inputs[0])
        tree.links.new(given.outputs[0], join.inputs[0])
        tree.links.new(join.outputs[0], out.inputs[0])
    else:
        tree.links.new(on_points.outputs["Instances"], out.inputs[0])
    return tree, shape


def _grid(name: str, cuts: int, size: float, location) -> bpy.types.Object:
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=cuts, y_subdivisions=cuts, size=size, location=location)
    ob = bpy.context.active_object
    ob.name = name
    return ob


def run(blend_out: str = "", check: str = "") -> dict:
    if check:
        bpy.ops.wm.open_mainfile(filepath=check)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        return {"instances": {ob.name: mesh_io.drawn_instances(ob, depsgraph) for ob in bpy.context.scene.objects},
                "with_nodes": sorted(ob.name for ob in bpy.context.scene.objects
                                     if any(md.type == 'NODES' for md in ob.modifiers))}
    remove_all_objects()
    scatter = _grid("Scatter", 3, 6.0, (0.0, 0.0, 0.0))
    tree, ico = _tree("Scatter", "GeometryNodeMeshIcoSphere", keep_points=False)
    ico.inputs["Subdivisions"].default_value = 2
    ico.inputs["Radius"].default_value = 0.5
    scatter.modifiers.new("Scatter", 'NODES').node_group = tree
    field = _grid("Field", 2, 4.0, (8.0, 0.0, 0.0))
    field.rotation_euler = (0.0, 0.0, 0.5)
    tree, cone = _tree("Field", "GeometryNodeMeshCone", keep_points=True)
    cone.inputs["Vertices"].default_value = 24
    field.modifiers.new("Cones", 'NODES').node_group = tree
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, location=(0.0, 8.0, 0.0))
    bpy.context.active_object.name = "Ball"
    depsgraph = bpy.context.evaluated_depsgraph_get()
    drawn = {}  # object name -> {"own": its mesh's triangles, "instances": each instance's}
    for inst in depsgraph.object_instances:
        mesh = inst.object.data
        if inst.object.type == 'MESH' and mesh is not None:
            mesh.calc_loop_triangles()
            name = (inst.parent.original if inst.is_instance else inst.object.original).name
            of = drawn.setdefault(name, {"own": 0, "instances": []})
            if inst.is_instance:
                of["instances"].append(len(mesh.loop_triangles))
            else:
                of["own"] = len(mesh.loop_triangles)
    reason = lod.nothing_to_simplify(scatter, depsgraph, True)
    field_notes = lod.prepare(bpy.context, field, LodSettings(ratios=(0.5,))).warnings
    bpy.ops.wm.save_as_mainfile(filepath=blend_out)
    return {"drawn": drawn, "scatter_reason": reason, "field_notes": field_notes}
