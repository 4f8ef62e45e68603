# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender meshes <-> NumPy arrays, in bulk (foreach_get / foreach_set, no per-vertex loops).

Reading gives a :class:`MeshData`: the mesh triangulated through its loop triangles, with
everything an artist expects on a LOD as arrays indexed by vertex or by triangle corner.
Writing makes a new mesh (and its object's vertex groups and shape keys) from a MeshData.
"""
from __future__ import annotations

import contextlib

import numpy as np

import bpy

from .pure import edges as edge_util
from . import vertex_groups
# The arrays themselves are bpy-free (mesh_data.py); named here as always.
from .pure.mesh_data import ATTRIBUTE_TYPES, AttributeLayer, ColorLayer, MeshData, ShapeKeyData  # noqa: F401

# Attributes that MeshData's own fields carry (positions, materials, smoothing, sharp
# edges, custom normals), besides UV maps and colour attributes (read by name); names
# starting with "." are Blender's internal ones (selection, hiding, UV pins).
_OWN_ATTRIBUTES = frozenset({"position", "material_index", "sharp_face", "sharp_edge", "custom_normal"})
_DOMAINS = ('POINT', 'EDGE', 'FACE', 'CORNER')


def _get(collection, prop, count, dtype, width=1):
    out = np.empty(count * width, dtype=dtype)
    if count:
        collection.foreach_get(prop, out)
    return out.reshape(-1, width) if width > 1 else out


def positions(mesh: bpy.types.Mesh) -> np.ndarray:
    """(n, 3) float64 the vertices' positions: the "position" attribute read as one block
    (3x faster than the vertices' "co", which goes through each vertex's RNA)."""
    n = len(mesh.vertices)
    attr = mesh.attributes.get("position")
    source = (attr.data, "vector") if attr is not None and attr.domain == 'POINT' else (mesh.vertices, "co")
    return _get(*source, n, np.float32, 3).astype(np.float64).reshape(n, 3)


def triangles(mesh: bpy.types.Mesh) -> tuple:
    """(vertices (m, 3), loops (m, 3), polygon (m,)) of the mesh's triangles as
    ``loop_triangles`` gives them, int64. A mesh of triangles only (a LOD, a glTF or
    triangulated import) is its corners in order, read as one block from the internal
    ".corner_vert" attribute: 20x faster than triangulating it and reading the loop
    triangles (the posed distance reads 944 evaluated meshes for a 59-part character)."""
    n_poly, n_loops = len(mesh.polygons), len(mesh.loops)
    corner_vert = mesh.attributes.get(".corner_vert")
    if n_loops == 3 * n_poly and corner_vert is not None and corner_vert.domain == 'CORNER':
        # (Every face has at least 3 corners, so 3 per face means every face a triangle,
        # its corners 3 f .. 3 f + 2: the triangle loop_triangles makes of it.)
        tris = _get(corner_vert.data, "value", n_loops, np.int32).astype(np.int64).reshape(n_poly, 3)
        return tris, np.arange(n_loops, dtype=np.int64).reshape(n_poly, 3), np.arange(n_poly, dtype=np.int64)
    mesh.calc_loop_triangles()
    m = len(mesh.loop_triangles)
    return (_get(mesh.loop_triangles, "vertices", m, np.int32, 3).astype(np.int64).reshape(m, 3),
            _get(mesh.loop_triangles, "loops", m, np.int32, 3).astype(np.int64).reshape(m, 3),
            _get(mesh.loop_triangles, "polygon_index", m, np.int32).astype(np.int64))


def read_mesh(mesh: bpy.types.Mesh, *, group_method: str = "auto", group_names=None) -> MeshData:
    """Everything :class:`MeshData` holds, read from ``mesh`` (not modified);
    ``group_names``: its vertex groups' names in index order when the caller has them
    (an object using the mesh lists them), else vertex_groups.group_names finds them."""
    n = len(mesh.vertices)
    verts = positions(mesh)
    tris, tri_loops, tri_poly = triangles(mesh)
    m = len(tris)
    n_poly = len(mesh.polygons)
    poly_mat = _get(mesh.polygons, "material_index", n_poly, np.int32)
    poly_smooth = _get(mesh.polygons, "use_smooth", n_poly, bool)
    if n_poly:
        # Smoothing regions bounded by sharp edges, computed in C (one int per polygon).
        poly_group = np.asarray(mesh.calc_smooth_groups(use_bitflags=False)[0], dtype=np.int64)
    else:
        poly_group = np.zeros(0, dtype=np.int64)

    n_loops = len(mesh.loops)
    uv_maps = {}
    for layer in mesh.uv_layers:
        uv = _get(layer.uv, "vector", n_loops, np.float32, 2).astype(np.float64).reshape(n_loops, 2)
        uv_maps[layer.name] = uv[tri_loops]
    uv_active = mesh.uv_layers.active.name if mesh.uv_layers.active else None
    uv_render = next((layer.name for layer in mesh.uv_layers if layer.active_render), None)

    colors = []
    for attr in mesh.color_attributes:
        if attr.domain == 'POINT':
            data = _get(attr.data, "color", n, np.float32, 4).astype(np.float64).reshape(n, 4)
        elif attr.domain == 'CORNER':
            data = _get(attr.data, "color", n_loops, np.float32, 4).astype(np.float64).reshape(n_loops, 4)[tri_loops]
        else:  # colour attributes live on points or corners only
            continue
        colors.append(ColorLayer(attr.name, attr.domain, attr.data_type, data))

    # corner_normals (Blender 4.1+) are the split normals as shaded, custom ones included.
    corner_normals = _get(mesh.corner_normals, "vector", n_loops, np.float32, 3).astype(np.float64)
    corner_normals = corner_normals.reshape(n_loops, 3)[tri_loops]
    custom_normals = corner_normals if mesh.has_custom_normals and n_loops else None

    n_edges = len(mesh.edges)
    edge_verts = _get(mesh.edges, "vertices", n_edges, np.int32, 2).astype(np.int64).reshape(n_edges, 2)
    sharp_attr = mesh.attributes.get("sharp_edge")
    if sharp_attr is not None and sharp_attr.domain == 'EDGE' and n_edges:
        sharp = _get(sharp_attr.data, "value", n_edges, bool)
    else:
        sharp = np.zeros(n_edges, dtype=bool)
    seam = _get(mesh.edges, "use_seam", n_edges, bool)

    seam_edges = edge_verts[seam]
    seam_region = edge_util.face_regions(tris, seam_edges) if len(seam_edges) else None

    attributes = _read_attributes(mesh, tri_poly, tri_loops, edge_verts)

    names = vertex_groups.group_names(mesh) if group_names is None else list(group_names)
    weights = vertex_groups.read_weights(mesh, names, method=group_method, all_names=names) \
        if names else np.zeros((n, 0))

    return MeshData(
        custom_normals=custom_normals,
        corner_normals=corner_normals,
        vertices=verts,
        faces=tris,
        material_index=poly_mat[tri_poly].astype(np.int64),
        smooth=poly_smooth[tri_poly],
        smooth_group=poly_group[tri_poly] if len(poly_group) else np.zeros(m, np.int64),
        uv_maps=uv_maps,
        uv_active=uv_active,
        uv_render=uv_render,
        colors=colors,
        attributes=attributes,
        color_active=mesh.color_attributes.active_color_name or None,
        color_render=getattr(mesh.color_attributes, "default_color_name", None) or None,
        group_names=names,
        group_weights=weights,
        sharp_edges=edge_verts[sharp],
        sharp_for_shading=bool(n_edges and np.count_nonzero(sharp) > 0.5 * n_edges),
        seam_edges=seam_edges,
        seam_region=seam_region,
    )


def _read_attributes(mesh, tri_poly, tri_loops, edge_verts) -> list:
    """The mesh's generic attributes (AttributeLayer): every attribute of a type
    ATTRIBUTE_TYPES knows that is not one of MeshData's own fields, a UV map, a colour
    attribute or Blender's internal; per triangle and per triangle corner as MeshData
    holds its faces."""
    own = _OWN_ATTRIBUTES | set(mesh.uv_layers.keys()) | {
        a.name for a in mesh.color_attributes if a.domain in ('POINT', 'CORNER')}
    layers = []
    for attr in mesh.attributes:
        kind = ATTRIBUTE_TYPES.get(attr.data_type)
        if attr.name.startswith(".") or attr.name in own or kind is None or attr.domain not in _DOMAINS:
            continue
        prop, width, dtype, _ = kind
        count = len(attr.data)
        values = _get(attr.data, prop, count, dtype, width).reshape(count, width)
        if attr.domain == 'FACE':
            values = values[tri_poly]
        elif attr.domain == 'CORNER':
            values = values[tri_loops]
        layers.append(AttributeLayer(attr.name, attr.domain, attr.data_type, values,
                                     edge_verts if attr.domain == 'EDGE' else None))
    return layers


def write_attributes(mesh: bpy.types.Mesh, layers: list) -> None:
    """``layers`` (AttributeLayer, as MeshData holds them) onto ``mesh``, made by
    build_mesh: one polygon a triangle, its loops in triangle-corner order, its edges
    computed. An edge layer's values go to the mesh's edges between its pairs of
    vertices, the rest get zero. A layer whose name the mesh already uses is left out."""
    edge_verts = None
    for layer in layers:
        if layer.name in mesh.attributes:
            continue
        prop, width, dtype, _ = ATTRIBUTE_TYPES[layer.data_type]
        values = np.asarray(layer.data).reshape(-1, width)
        if layer.domain == 'EDGE':
            if edge_verts is None:
                edge_verts = _get(mesh.edges, "vertices", len(mesh.edges), np.int32, 2).reshape(-1, 2)
            row = edge_util.edge_index(edge_verts, layer.edges, len(mesh.vertices))
            full = np.zeros((len(edge_verts), width), dtype=values.dtype)
            full[row >= 0] = values[row[row >= 0]]
            values = full
        attr = mesh.attributes.new(layer.name, layer.data_type, layer.domain)
        attr.data.foreach_set(prop, values.astype(dtype).reshape(-1))


def _shape_key_meta(block, offsets) -> ShapeKeyData:
    return ShapeKeyData(
        name=block.name,
        offsets=offsets,
        value=float(block.value),
        slider_min=float(block.slider_min),
        slider_max=float(block.slider_max),
        mute=bool(block.mute),
        relative_key=block.relative_key.name if block.relative_key else "",
        vertex_group=block.vertex_group,
        interpolation=block.interpolation,
    )


def read_shape_keys(mesh: bpy.types.Mesh) -> tuple:
    """(basis name, use_relative, [ShapeKeyData]) of ``mesh``'s own shape keys, offsets
    from its vertices (the basis); ("Basis", True, []) without keys."""
    key = mesh.shape_keys
    if key is None or len(key.key_blocks) < 2:
        return "Basis", True, []
    n = len(mesh.vertices)
    basis = _get(mesh.vertices, "co", n, np.float32, 3).astype(np.float64).reshape(n, 3)
    keys = []
    for block in key.key_blocks[1:]:
        co = _get(block.data, "co", n, np.float32, 3).astype(np.float64).reshape(n, 3)
        keys.append(_shape_key_meta(block, co - basis))
    return key.key_blocks[0].name, bool(key.use_relative), keys


def _base_shape_keys(mesh, data: MeshData) -> None:
    if mesh.shape_keys is None or len(mesh.shape_keys.key_blocks) < 2:
        return
    data.basis_name, data.shape_use_relative, data.shape_keys = read_shape_keys(mesh)


# Object types Blender draws as a mesh: curves with a bevel or extrusion (cables, pipes,
# trims), text, NURBS surfaces and metaballs evaluate to one, and the glTF and FBX
# exporters write them as meshes. A LOD of one is a mesh object.
GEOMETRY_TYPES = frozenset({'MESH', 'CURVE', 'FONT', 'SURFACE', 'META'})


def draws_geometry(obj) -> bool:
    """Whether ``obj`` is a mesh object or one that evaluates to a mesh (GEOMETRY_TYPES)."""
    return getattr(obj, "type", None) in GEOMETRY_TYPES


def evaluated_faces(obj, depsgraph) -> int:
    """The faces of ``obj``'s evaluated mesh (a curve without bevel or extrusion has none;
    a metaball's family is drawn by its first object alone)."""
    evaluated = obj.evaluated_get(depsgraph)
    if obj.type == 'MESH':
        return len(evaluated.data.polygons)
    mesh = evaluated.to_mesh()
    try:
        return len(mesh.polygons) if mesh is not None else 0
    finally:
        evaluated.to_mesh_clear()


def drawn_instances(obj, depsgraph) -> int:
    """How many instances ``obj``'s evaluated geometry draws (geometry nodes' Instance on
    Points, say): they are not in its evaluated mesh."""
    if not any(md.type == 'NODES' and md.show_viewport for md in getattr(obj, "modifiers", ())):
        return 0
    return sum(1 for inst in depsgraph.object_instances
               if inst.is_instance and inst.parent is not None and inst.parent.original == obj)


def deforming_armature_modifiers(obj) -> list:
    """The object's enabled Armature modifiers that point at an armature."""
    return [md for md in obj.modifiers if md.type == 'ARMATURE' and md.object is not None and md.show_viewport]


def has_geometry_modifiers(obj) -> bool:
    """True when the viewport modifier stack does more than skinning."""
    return any(md.show_viewport and md.type != 'ARMATURE' for md in obj.modifiers)


@contextlib.contextmanager
def _rest_state(obj):
    """Temporarily evaluate ``obj`` unposed and without shape-key mixing.

    The LOD gets its own Armature modifier and shape keys, so the geometry read must be
    the rest shape: Armature modifiers are switched off and only the basis key is shown.
    Every switch is restored, whatever happens.
    """
    saved_mods = [(md, md.show_viewport) for md in obj.modifiers if md.type == 'ARMATURE']
    saved_only = obj.show_only_shape_key
    saved_index = obj.active_shape_key_index
    try:
        for md, _ in saved_mods:
            md.show_viewport = False
        if getattr(obj.data, "shape_keys", None) is not None:
            obj.show_only_shape_key = True
            obj.active_shape_key_index = 0
        yield
    finally:
        for md, shown in saved_mods:
            md.show_viewport = shown
        obj.show_only_shape_key = saved_only
        obj.active_shape_key_index = saved_index


def read_object(obj: bpy.types.Object, depsgraph, use_modifiers: bool = True,
                group_method: str = "auto") -> tuple:
    """Read a mesh object's rest geometry. Returns (MeshData, warnings).

    use_modifiers: the modifier stack as the viewport evaluates it (minus Armature
    modifiers: the LOD is skinned again by its own); False reads the base mesh. Shape
    keys are carried as offsets; through modifiers each key is evaluated on its own, so
    they survive topology-changing modifiers such as Subdivision Surface.
    A curve, text, surface or metaball object (GEOMETRY_TYPES) is read as it evaluates,
    its modifiers included whatever ``use_modifiers`` says (it has no mesh of its own);
    its shape keys move curve points, not the mesh's vertices, and are not carried.
    """
    warnings = []
    if obj.type == 'MESH' and (not use_modifiers or not has_geometry_modifiers(obj)):
        data = read_mesh(obj.data, group_method=group_method, group_names=obj.vertex_groups.keys())
        _base_shape_keys(obj.data, data)
        return data, warnings
    if obj.type != 'MESH' and getattr(obj.data, "shape_keys", None) is not None:
        warnings.append("its shape keys are not carried: they move the curve's points, not a mesh's vertices")

    with _rest_state(obj):
        depsgraph.update()
        evaluated = obj.evaluated_get(depsgraph)
        # The evaluated object's own temporary mesh, and its group names (those of the
        # evaluated mesh): a mesh made in bpy.data and removed, or a throw-away object
        # to list the names, would tag the depsgraph relations, and the next update would
        # re-evaluate every object in the scene (24 ms a part with 300 objects).
        mesh = evaluated.to_mesh(preserve_all_data_layers=True, depsgraph=depsgraph)
        try:
            data = read_mesh(mesh, group_method=group_method, group_names=evaluated.vertex_groups.keys())
        finally:
            evaluated.to_mesh_clear()
        key = obj.data.shape_keys if obj.type == 'MESH' else None
        if key is not None and len(key.key_blocks) > 1:
            data.basis_name = key.key_blocks[0].name
            data.shape_use_relative = bool(key.use_relative)
            n = len(data.vertices)
            for index, block in enumerate(key.key_blocks):
                if index == 0:
                    continue
                obj.active_shape_key_index = index
                depsgraph.update()
                ev_mesh = obj.evaluated_get(depsgraph).data
                if len(ev_mesh.vertices) != n:
                    warnings.append(f'shape key "{block.name}" dropped: the modifiers give it a different topology')
                    continue
                co = _get(ev_mesh.vertices, "co", n, np.float32, 3).astype(np.float64).reshape(n, 3)
                data.shape_keys.append(_shape_key_meta(block, co - data.vertices))
    depsgraph.update()
    return data, warnings


# --------------------------------------------------------------------------- writing


def build_mesh(name: str, data: MeshData) -> bpy.types.Mesh:
    """A new mesh datablock (not linked to any object) from ``data``.

    Vertex groups and shape keys belong to an object in Blender's API: see
    :func:`add_vertex_groups` and :func:`add_shape_keys`.
    """
    v = np.ascontiguousarray(data.vertices, dtype=np.float32)
    f = np.ascontiguousarray(data.faces, dtype=np.int32).reshape(-1, 3)
    n, m = len(v), len(f)
    mesh = bpy.data.meshes.new(name)
    try:
        mesh.vertices.add(n)
        mesh.vertices.foreach_set("co", v.ravel())
        mesh.loops.add(3 * m)
        mesh.loops.foreach_set("vertex_index", f.ravel())
        mesh.polygons.add(m)
        mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * m, 3, dtype=np.int32))
        mesh.update(calc_edges=True)

        mesh.polygons.foreach_set("material_index", np.asarray(data.material_index, dtype=np.int32))
        mesh.polygons.foreach_set("use_smooth", np.asarray(data.smooth, dtype=bool))

        for uv_name, corners in data.uv_maps.items():
            layer = mesh.uv_layers.new(name=uv_name, do_init=False)
            layer.uv.foreach_set("vector", np.asarray(corners, dtype=np.float32).reshape(-1))
        # Names may be None (a mesh without UV maps); the collection only takes strings.
        if data.uv_active and data.uv_active in mesh.uv_layers:
            mesh.uv_layers.active = mesh.uv_layers[data.uv_active]
        if data.uv_render and data.uv_render in mesh.uv_layers:
            mesh.uv_layers[data.uv_render].active_render = True

        for layer in data.colors:
            attr = mesh.color_attributes.new(layer.name, layer.data_type, layer.domain)
            attr.data.foreach_set("color", np.asarray(layer.data, dtype=np.float32).reshape(-1))
        if data.color_active and data.color_active in mesh.color_attributes:
            mesh.color_attributes.active_color_name = data.color_active
        if data.color_render and data.color_render in mesh.color_attributes and hasattr(
                mesh.color_attributes, "default_color_name"):
            mesh.color_attributes.default_color_name = data.color_render
        write_attributes(mesh, data.attributes)
        write_point_floats(mesh, data.point_floats)
        for key, value in data.mesh_properties.items():
            mesh[key] = value

        n_edges = len(mesh.edges)
        edge_verts = _get(mesh.edges, "vertices", n_edges, np.int32, 2).reshape(n_edges, 2)
        if len(data.sharp_edges):
            sharp = edge_util.mark_edges(edge_verts, data.sharp_edges, n)
            if sharp.any():
                attr = mesh.attributes.new("sharp_edge", 'BOOLEAN', 'EDGE')
                attr.data.foreach_set("value", sharp)
        if len(data.seam_edges):
            mesh.edges.foreach_set("use_seam", edge_util.mark_edges(edge_verts, data.seam_edges, n))
        mesh.update()
        if data.custom_normals is not None:
            # Loops were written in triangle-corner order, so corner k is loop k.
            mesh.normals_split_custom_set(np.asarray(data.custom_normals, dtype=np.float64).reshape(-1, 3))
    except Exception:
        vertex_groups.remove_mesh(mesh)
        raise
    return mesh


def write_point_floats(mesh: bpy.types.Mesh, values: dict) -> None:
    """Float attributes on the points of ``mesh``, {name: (n,) values}, each replacing
    any attribute of that name."""
    for name, array in values.items():
        old = mesh.attributes.get(name)
        if old is not None:
            mesh.attributes.remove(old)
        attr = mesh.attributes.new(name, 'FLOAT', 'POINT')
        attr.data.foreach_set("value", np.asarray(array, dtype=np.float32).reshape(-1))


def add_vertex_groups(obj: bpy.types.Object, data: MeshData) -> None:
    if data.group_names:
        vertex_groups.write_weights(obj, data.group_names, data.group_weights)


def add_shape_keys(obj: bpy.types.Object, data: MeshData) -> None:
    """Shape keys on ``obj`` (a new object): the basis is the mesh, each key basis + offsets."""
    if not data.shape_keys:
        return
    basis = obj.shape_key_add(name=data.basis_name, from_mix=False)
    key = obj.data.shape_keys
    key.use_relative = data.shape_use_relative
    base = np.asarray(data.vertices, dtype=np.float64)
    blocks = {basis.name: basis}
    for sk in data.shape_keys:
        block = obj.shape_key_add(name=sk.name, from_mix=False)
        block.data.foreach_set("co", (base + sk.offsets).astype(np.float32).ravel())
        block.interpolation = sk.interpolation
        block.vertex_group = sk.vertex_group
        block.mute = sk.mute
        # Blender keeps slider_min < slider_max at every assignment: set them in an order
        # that never crosses the current range.
        if sk.slider_min < block.slider_max:
            block.slider_min, block.slider_max = sk.slider_min, sk.slider_max
        else:
            block.slider_max = sk.slider_max
            block.slider_min = sk.slider_min
        block.value = sk.value
        blocks[sk.name] = block
    for sk in data.shape_keys:
        if sk.relative_key in blocks:
            blocks[sk.name].relative_key = blocks[sk.relative_key]


def scene_and_depsgraph(context_or_scene) -> tuple:
    """(scene, evaluated depsgraph) of a context, or of a scene (its first view layer's
    when it is not the context's)."""
    if isinstance(context_or_scene, bpy.types.Scene):
        scene = context_or_scene
        if bpy.context.scene == scene and bpy.context.view_layer is not None:
            depsgraph = bpy.context.evaluated_depsgraph_get()
        else:
            depsgraph = scene.view_layers[0].depsgraph
            depsgraph.update()
        return scene, depsgraph
    return context_or_scene.scene, context_or_scene.evaluated_depsgraph_get()
