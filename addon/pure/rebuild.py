# SPDX-License-Identifier: GPL-3.0-or-later
"""A LOD's mesh rebuilt from the core's result: the source's faces' materials, smoothing
and seams carried to the faces they became, the carried attributes back into vertex
groups, colours, UV maps, shape keys and custom normals, and the sharp edges and seams
that keep the LOD shading and unwrapped as its source does.
"""
from __future__ import annotations

import dataclasses
from typing import Optional

import numpy as np

from ._core import core
from . import edges as edge_util
from .mesh_data import AttributeLayer, ColorLayer, MeshData
from .options import interpolated_attributes


def sharp_chains(data: MeshData, result) -> np.ndarray:
    """(k, 2) LOD edges (LOD vertex ids) along which a chain of the source's sharp edges ran."""
    kept = np.zeros(len(data.vertices), dtype=bool)
    kept[result.vertex_origin] = True
    pairs = edge_util.chains_through(data.sharp_edges, kept)
    if len(pairs) == 0:
        return pairs
    lod_vertex = np.full(len(data.vertices), -1, dtype=np.int64)
    lod_vertex[result.vertex_origin] = np.arange(len(result.vertex_origin))
    pairs = lod_vertex[pairs]
    lod_edges = edge_util.unique_edges(np.concatenate([result.faces[:, [0, 1]], result.faces[:, [1, 2]],
                                                       result.faces[:, [2, 0]]]))
    return pairs[edge_util.mark_edges(pairs, lod_edges, len(result.vertices))]


def lod_mesh(data: MeshData, result, names, hard_edge_angle: float = 0.0) -> MeshData:
    """The LOD's MeshData from the core's ``result`` for the source ``data``: every face's
    material, smoothing and seam region from the face it came from; the attributes the
    core carried (``names``: the attribute keys given to the core -> what they stand for,
    as core_options made them) back into vertex groups, colours, UV maps, shape keys and
    custom normals; sharp edges and seams where the source had them (and, with
    ``hard_edge_angle``, where the LOD's faces meet sharper than it)."""
    fo = result.face_origin
    va, ca = result.vertex_attributes, result.corner_attributes
    n_out = len(result.vertices)
    weights = np.zeros((n_out, len(data.group_names)))
    for key in ("skin", "groups"):
        if key in names:
            weights[:, names[key]] = np.clip(va[key], 0.0, 1.0)
    colors = [
        ColorLayer(layer.name, layer.domain, layer.data_type,
                   va[f"color{i}"] if layer.domain == 'POINT' else ca[f"color{i}"])
        for i, layer in enumerate(data.colors)
    ]
    uv_maps = {uv_name: ca[f"uv{i}"] for i, uv_name in enumerate(data.uv_maps)}
    shape_keys = [dataclasses.replace(sk, offsets=va[f"shape{i}"]) for i, sk in enumerate(data.shape_keys)]
    carried = interpolated_attributes(data)
    attributes = [carried_attribute(data, result, layer, f"attr{i}" if f"attr{i}" in carried else None)
                  for i, layer in enumerate(data.attributes)]
    smooth_group = data.smooth_group[fo]
    faces = result.faces
    # Normals split where the source's did: between faces of different smoothing regions,
    # which sharp edges bound, and vertices split apart (an exported asset's hard edges;
    # every edge, where each triangle has its own vertices). The core welds such vertices,
    # so without this the LOD would shade smooth across them. Carried custom normals say
    # themselves how the LOD shades; with them only the sharp edges are marked.
    if len(data.sharp_edges) or "normal" not in ca:
        sharp = edge_util.differing_edges(faces, smooth_group)
    else:
        sharp = np.empty((0, 2), np.int64)
    if len(data.sharp_edges):
        # And along the source's sharp edges, also those that end inside a smoothing
        # region (a crease fading out), which the regions cannot say: where a chain of
        # them ran between two vertices the LOD kept, and the LOD has that edge.
        sharp = edge_util.unique_edges(np.concatenate([sharp, sharp_chains(data, result)]))
    if hard_edge_angle > 0 and "normal" not in ca:
        sharp = edge_util.unique_edges(np.concatenate(
            [sharp.reshape(-1, 2), core.features.sharp_edges(result.vertices, faces, hard_edge_angle)]))
    if len(data.seam_edges):
        # Seams where the source had them: between triangles from regions the seams
        # separated, and, for seams that cut into a region (a cylinder's), where the UVs
        # are split between two vertices that came from seam vertices.
        on_seam = np.zeros(len(data.vertices), dtype=bool)
        on_seam[data.seam_edges.ravel()] = True
        on_seam = on_seam[result.vertex_origin]
        parts = [edge_util.differing_edges(faces, data.seam_region[fo])]
        for uv in uv_maps.values():
            split = edge_util.corner_discontinuous_edges(faces, uv)
            parts.append(split[on_seam[split].all(axis=1)])
        seam = edge_util.unique_edges(np.concatenate(parts))
    else:
        seam = np.empty((0, 2), np.int64)
    return MeshData(
        vertices=result.vertices,
        faces=faces,
        material_index=data.material_index[fo],
        smooth=data.smooth[fo],
        smooth_group=smooth_group,
        uv_maps=uv_maps,
        uv_active=data.uv_active,
        uv_render=data.uv_render,
        colors=colors,
        attributes=attributes,
        color_active=data.color_active,
        color_render=data.color_render,
        group_names=list(data.group_names),
        group_weights=weights,
        basis_name=data.basis_name,
        shape_keys=shape_keys,
        shape_use_relative=data.shape_use_relative,
        sharp_edges=sharp,
        seam_edges=seam,
        seam_region=data.seam_region[fo] if data.seam_region is not None else None,
        custom_normals=_unit(ca["normal"]) if "normal" in ca else None,
    )


def carried_attribute(data: MeshData, result, layer: AttributeLayer, key: Optional[str]) -> AttributeLayer:
    """The LOD's values of the source's generic attribute ``layer``: what the core
    interpolated for it (``key``: its name in the result's attributes, or None), else the
    value of the element each LOD element came from: a face's from its source face, a
    vertex's from its source vertex, a corner's from origin_corners, an edge's from the
    source edge between its ends' source vertices, or else from the first edge of a chain
    of source edges with values that ran between them through vertices the LOD lost (a
    crease along a kept feature, as sharp_chains); other LOD edges get zero."""
    if key:
        values = (result.vertex_attributes if layer.domain == 'POINT' else result.corner_attributes)[key]
        return dataclasses.replace(layer, data=values)
    if layer.domain == 'FACE':
        return dataclasses.replace(layer, data=layer.data[result.face_origin])
    if layer.domain == 'POINT':
        return dataclasses.replace(layer, data=layer.data[result.vertex_origin])
    if layer.domain == 'CORNER':
        width = layer.data.shape[-1]
        return dataclasses.replace(layer, data=layer.data.reshape(-1, width)[origin_corners(data, result)])
    n = len(data.vertices)
    lod_edges = edge_util.unique_edges(result.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2))
    row = edge_util.edge_index(result.vertex_origin[lod_edges], layer.edges, n)
    marked = np.flatnonzero(np.any(layer.data != 0, axis=1))
    kept = np.zeros(n, dtype=bool)
    kept[result.vertex_origin] = True
    pairs, first = edge_util.chains_through(layer.edges[marked], kept, with_edges=True)
    chain = edge_util.edge_index(result.vertex_origin[lod_edges], pairs, n)
    along = (row < 0) & (chain >= 0)
    row[along] = marked[first[chain[along]]]
    return dataclasses.replace(layer, data=layer.data[row[row >= 0]], edges=lod_edges[row >= 0])


def origin_corners(data: MeshData, result) -> np.ndarray:
    """(m_out, 3) for each LOD triangle corner, the source triangle corner (an index into
    the flattened (m, 3) corners) it came from: the corner of the triangle its face came
    from (result.face_origin) at the vertex its vertex came from (result.vertex_origin),
    else that triangle's corner nearest to it."""
    source = np.asarray(data.faces)[result.face_origin]  # (m_out, 3) source vertex ids
    origin = result.vertex_origin[result.faces]  # (m_out, 3)
    gap = np.linalg.norm(np.asarray(data.vertices)[source][:, None, :, :]
                         - np.asarray(result.vertices)[result.faces][:, :, None, :], axis=-1)
    gap[source[:, None, :] == origin[:, :, None]] = -1.0
    return result.face_origin[:, None] * 3 + np.argmin(gap, axis=2)


def _unit(vectors: np.ndarray) -> np.ndarray:
    """Rows scaled to length 1 (an interpolated normal is shorter); zero rows stay zero."""
    length = np.linalg.norm(vectors, axis=-1, keepdims=True)
    return np.divide(vectors, length, out=np.zeros_like(vectors), where=length > 1e-12)
