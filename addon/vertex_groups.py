# SPDX-License-Identifier: GPL-3.0-or-later
"""Vertex-group weights in bulk, both ways.

Vertex groups have no ``foreach_get``/``foreach_set`` (the weights live in per-vertex
lists, ``MeshVertex.groups``), and ``mesh.attributes`` does not list them.

Operators are avoided where they would run once per small thing: a ``bpy.ops`` call from
Python runs ``view_layer.update()`` before and after the operator, and creating,
renaming or removing a vertex group, an object or a node group tags the depsgraph
relations, so that update rebuilds them for every object in the scene (about 1 ms
with 65 objects, 8-18 ms with 245, below). Writing through one operator call per group cost 11.4 s
on a 59-part rigged character (issue 32); the operators themselves are cheap.

Measured with bpy 4.5 on this machine (2 shared cores), old and new route in one process:
60 unlinked meshes of 1,000 vertices, each given 20 skin-weight-like groups (1-4 per
vertex, rows summing to 1; 142,582 nonzero weights), and one 60,000-vertex mesh (142,832),
in scenes of 65 and 245 objects; ranges over two runs of each.
tests/test_addon_vertex_groups.py checks that the routes give the same weights.

Writing (``write_weights``)
  * ``VertexGroup.add(indices, weight, 'REPLACE')``, one call per distinct (group,
    float32 weight) pair, the pairs found by one NumPy sort: no operator and nothing
    temporary, about 1-1.5 us a pair whatever the scene. Interpolated weights are nearly
    all distinct (1.0 is the usual repeat; 126,704 pairs of 142,483 weights on the big
    mesh), so the cost is linear in the weights written. 60 parts: 0.12-0.19 s in either
    scene; the same into 60 linked meshes replacing their groups 0.16-0.29 s; the
    60,000-vertex mesh 0.16-0.27 s.
  * Former route, kept as method="convert": ``geometry.attribute_convert`` per group
    (a float attribute filled by ``foreach_set``, converted): 60 parts 2.1-3.3 s with 65
    objects, 10-22 s with 245 (replacing linked groups 2.9-5.4 s and 21-35 s); the
    60,000-vertex mesh 0.07-0.19 s and 0.28-0.63 s.
  * Measured and not taken: one Geometry Nodes modifier per object storing every weight
    into its (existing) group and applied once, 17-27 ms a part (building a node tree
    through Python costs about 0.2 ms a node, and the apply still updates the view layer;
    the VertexGroup objects taken before the apply dangle after it and crash Blender when
    used); a ``bmesh`` deform layer set weight by weight, 0.06-0.13 s for either size,
    but per-weight Python and a round trip of the whole mesh; 'ADD' calls per binary digit
    of the weights, fewer calls on big groups but more on small ones, no faster
    overall; quantising to 1/65535 is up to 7.6e-6 off and leaves 118,399 of the
    126,704 pairs.
Reading (``read_weights``)
  * Python over ``v.groups`` (``numpy.fromiter``): about 2 us a vertex (2.4 weights
    each) and no operator: 60 parts 0.12-0.25 s in either scene; the 60,000-vertex mesh
    0.12-0.19 s.
  * Geometry Nodes on a throw-away copy of the mesh ("Named Attribute" reads a vertex
    group by name, "Store Named Attribute" makes it a float attribute, the modifier is
    applied by one operator call, ``foreach_get`` reads the attributes): about 10 ms a mesh
    plus the two view-layer updates, then about 0.5 us a vertex. 60 parts 0.9-1.6 s with
    65 objects and 2.4-4.1 s with 245; the 60,000-vertex mesh 0.04-0.15 s. "Named
    Attribute" finds attributes before vertex groups, so a mesh with a group called
    "position" or like a UV map is read in Python (applying the modifier to such a mesh
    crashes Blender 5.2).
  "auto" reads meshes of NODES_MIN_VERTICES (20,000) vertices or more through Geometry
  Nodes, where the per-mesh cost is below Python's (the crossover is 7,000 vertices in an
  empty scene and about 30,000 with 245 objects), and smaller ones in Python, so many
  small parts no longer pay an operator each.
Every route works on objects that are not linked to any scene (checked), so no scene is
touched.
"""
from __future__ import annotations

import numpy as np

import bpy

_TMP_PREFIX = "__lqlod_vg_"
# read_weights("auto") reads meshes with at least this many vertices through Geometry
# Nodes (one operator call) and smaller ones in Python; see the module docstring.
NODES_MIN_VERTICES = 20_000


def read_weights(mesh: bpy.types.Mesh, names, method: str = "auto", all_names=None) -> np.ndarray:
    """Weights of the vertex groups ``names`` of ``mesh`` as an (n, len(names)) float64
    matrix (0 where a vertex is not in a group). The mesh is not modified.

    method: "auto" (Python below NODES_MIN_VERTICES vertices, else Geometry Nodes
    falling back to Python), "nodes" or "python". ``all_names``: every group of the mesh
    in index order when the caller has them (group_names), or None.
    """
    if method not in ("auto", "nodes", "python"):
        raise ValueError(f"unknown method {method!r}")
    names = list(names)
    n = len(mesh.vertices)
    if not names or n == 0:
        return np.zeros((n, len(names)))
    use_nodes = method == "nodes" or (method == "auto" and n >= NODES_MIN_VERTICES)
    # "Named Attribute" finds built-in and other attributes before vertex groups, so a mesh
    # with a group called like one ("position", a UV map) is read in Python: renaming the
    # group on the copy read it right in Blender 4.5, and on such a mesh Blender 5.2's
    # modifier_apply crashes whatever the node tree reads.
    if all_names is None:
        all_names = group_names(mesh)
    if use_nodes and any(name in mesh.attributes for name in all_names):
        use_nodes = False
    if use_nodes:
        try:
            return _read_via_nodes(mesh, names)
        except RuntimeError:
            if method == "nodes":
                raise
    return _read_via_python(mesh, names, all_names)


def _read_via_python(mesh, names, all_names) -> np.ndarray:
    n = len(mesh.vertices)
    # The mesh's own group indices -> our columns (groups not asked for are dropped).
    column = np.full(max(len(all_names), 1), -1, dtype=np.int64)
    for col, name in enumerate(names):
        if name in all_names:
            column[all_names.index(name)] = col
    count = np.fromiter((len(v.groups) for v in mesh.vertices), dtype=np.int64, count=n)
    total = int(count.sum())
    out = np.zeros((n, len(names)))
    if total == 0:
        return out
    flat = np.fromiter((x for v in mesh.vertices for g in v.groups for x in (g.group, g.weight)),
                       dtype=np.float64, count=2 * total).reshape(-1, 2)
    rows = np.repeat(np.arange(n), count)
    grp = flat[:, 0].astype(np.int64)
    ok = grp < len(column)
    cols = np.where(ok, column[np.minimum(grp, len(column) - 1)], -1)
    keep = cols >= 0
    out[rows[keep], cols[keep]] = flat[keep, 1]
    return out


def group_names(mesh) -> list:
    """The vertex-group names of ``mesh`` in index order. A caller with an object using
    the mesh reads them from it (``ob.vertex_groups.keys()``) instead."""
    # Since Blender 3.0 the names are stored on the mesh and any object using it lists
    # them. Without one, a throw-away object, never linked; but making and removing it
    # tags the depsgraph relations, and the next evaluated depsgraph rebuilds them for
    # every object in the scene: 14-18 ms with 300 objects, once per part read.
    tmp = bpy.data.objects.new(_TMP_PREFIX + "names", mesh)
    try:
        return [g.name for g in tmp.vertex_groups]
    finally:
        bpy.data.objects.remove(tmp)


def _read_via_nodes(mesh, names) -> np.ndarray:
    n = len(mesh.vertices)
    tmp_mesh = mesh.copy()
    tmp_obj = bpy.data.objects.new(_TMP_PREFIX + "read", tmp_mesh)
    tree = None
    try:
        if tmp_mesh.shape_keys is not None:
            # Modifiers cannot be applied to a mesh with shape keys; the copy does not need them.
            remove_shape_keys(tmp_mesh)
        # Columns of groups the mesh lacks stay 0.
        present = set(tmp_obj.vertex_groups.keys())
        sources = {col: name for col, name in enumerate(names) if name in present}
        tree = _store_groups_tree(sources)
        mod = tmp_obj.modifiers.new(_TMP_PREFIX + "mod", 'NODES')
        mod.node_group = tree
        with bpy.context.temp_override(object=tmp_obj, active_object=tmp_obj):
            result = bpy.ops.object.modifier_apply(modifier=mod.name)
        if result != {'FINISHED'}:
            raise RuntimeError(f"applying the temporary Geometry Nodes modifier returned {result}")
        out = np.zeros((len(names), n), dtype=np.float32)
        for col in sources:
            attr = tmp_mesh.attributes.get(f"{_TMP_PREFIX}{col}")
            if attr is None or len(attr.data) != n:
                raise RuntimeError("the temporary Geometry Nodes modifier did not store the weights")
            attr.data.foreach_get("value", out[col])
        return out.T.astype(np.float64)
    finally:
        bpy.data.objects.remove(tmp_obj)
        remove_mesh(tmp_mesh)
        if tree is not None:
            bpy.data.node_groups.remove(tree)


def remove_shape_keys(mesh) -> None:
    """Delete the mesh's Key datablock. (Object.shape_key_clear on an object that is not
    in a scene detaches the Key but leaves it in bpy.data, and removing a mesh can leave
    its Key behind, which Blender then reports as broken at the next load.)"""
    if mesh.shape_keys is not None:
        bpy.data.batch_remove([mesh.shape_keys])


def remove_mesh(mesh) -> None:
    """Remove a mesh datablock and its shape keys."""
    remove_shape_keys(mesh)
    bpy.data.meshes.remove(mesh)


def _store_groups_tree(sources: dict):
    """A node group storing the vertex group ``sources[col]`` as the float point
    attribute "<_TMP_PREFIX><col>", for each col."""
    tree = bpy.data.node_groups.new(_TMP_PREFIX + "store", 'GeometryNodeTree')
    tree.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
    tree.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
    node_in = tree.nodes.new("NodeGroupInput")
    node_out = tree.nodes.new("NodeGroupOutput")
    last = node_in.outputs[0]
    for col, name in sources.items():
        read = tree.nodes.new("GeometryNodeInputNamedAttribute")
        read.data_type = 'FLOAT'
        read.inputs["Name"].default_value = name
        store = tree.nodes.new("GeometryNodeStoreNamedAttribute")
        store.data_type = 'FLOAT'
        store.domain = 'POINT'
        store.inputs["Name"].default_value = f"{_TMP_PREFIX}{col}"
        tree.links.new(last, store.inputs["Geometry"])
        tree.links.new(read.outputs["Attribute"], store.inputs["Value"])
        last = store.outputs["Geometry"]
    tree.links.new(last, node_out.inputs[0])
    return tree


def write_weights(obj: bpy.types.Object, names, weights: np.ndarray, method: str = "auto") -> None:
    """Add one vertex group per name to mesh object ``obj`` with the given (n, g) weights.

    Weights are clipped to [0, 1] and stored as float32 (what a vertex group holds), so
    reading them back gives ``np.float32(np.clip(weights, 0, 1))`` exactly. Vertices whose
    float32 weight is 0 are left out of a group (as painting and Blender's own converter
    do). An existing group of the same name is replaced; the new groups follow the
    object's other groups in the order of ``names``. ``obj`` need not be linked to a
    scene, and nothing else in the scene is touched or updated.

    method: "auto" or "add" (``VertexGroup.add``, no operator), or "convert" (the former
    route: one ``geometry.attribute_convert`` call per group, raising RuntimeError if the
    operator refuses; kept as an independent reference for tests and timing).
    """
    if method not in ("auto", "add", "convert"):
        raise ValueError(f"unknown method {method!r}")
    names = list(names)
    if len(set(names)) != len(names):
        raise ValueError(f"duplicate vertex-group names in {names}")
    n = len(obj.data.vertices)
    w = np.clip(np.asarray(weights, dtype=np.float64).reshape(n, len(names)), 0.0, 1.0).astype(np.float32)
    if method == "convert":
        for col, name in enumerate(names):
            old = obj.vertex_groups.get(name)
            if old is not None:
                obj.vertex_groups.remove(old)
            _write_via_convert(obj, name, w[:, col])
    else:
        _write_via_add(obj, names, w)


def _write_via_add(obj, names, w: np.ndarray) -> None:
    """All groups of ``obj`` at once: one ``VertexGroup.add(indices, weight, 'REPLACE')``
    per distinct (group, float32 weight) pair, the indices found by one sort in NumPy."""
    groups = []
    for name in names:
        old = obj.vertex_groups.get(name)
        if old is not None:
            obj.vertex_groups.remove(old)
        groups.append(obj.vertex_groups.new(name=name))
    wt = w.T  # (g, n): np.nonzero walks it group by group, vertices ascending
    cols, rows = np.nonzero(wt > 0.0)
    if len(rows) == 0:
        return
    values = np.ascontiguousarray(wt[cols, rows], dtype=np.float32)
    # Equal (group, weight) pairs share a key: the group above the weight's 32 bits.
    key = (cols.astype(np.int64) << 32) | values.view(np.uint32).astype(np.int64)
    order = np.argsort(key, kind="stable")
    key = key[order]
    starts = np.flatnonzero(np.concatenate(([True], key[1:] != key[:-1])))
    ends = np.append(starts[1:], len(key))
    index = rows[order].tolist()  # one conversion; each call gets a slice of it
    adds = [group.add for group in groups]
    first = order[starts]
    # float32 -> Python float is exact, and VertexGroup.add stores it back as float32.
    for col, value, s, e in zip(cols[first].tolist(), values[first].tolist(), starts.tolist(), ends.tolist()):
        adds[col](index[s:e], value, 'REPLACE')


def _write_via_convert(obj, name, values):
    mesh = obj.data
    tmp_name = _TMP_PREFIX + "write"
    attr = mesh.attributes.new(tmp_name, 'FLOAT', 'POINT')
    try:
        attr.data.foreach_set("value", np.ascontiguousarray(values, dtype=np.float32))
        mesh.attributes.active = attr
        with bpy.context.temp_override(object=obj, active_object=obj):
            result = bpy.ops.geometry.attribute_convert(mode='VERTEX_GROUP')
        if result != {'FINISHED'}:
            raise RuntimeError(f"attribute_convert returned {result}")
    finally:
        leftover = mesh.attributes.get(tmp_name)
        if leftover is not None:
            mesh.attributes.remove(leftover)
    group = obj.vertex_groups.get(tmp_name)
    if group is None:
        raise RuntimeError("attribute_convert did not create the vertex group")
    # Renamed afterwards: vertex-group and attribute names share no namespace, so a group
    # may be called like an existing attribute (a UV map, "position"), which the
    # attribute route could not create directly.
    group.name = name
