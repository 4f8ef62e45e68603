# SPDX-License-Identifier: GPL-3.0-or-later
"""The arrays a mesh is read into and written from (mesh_io.py does both with bpy): a
triangulated mesh and what it carries. Free of bpy, so what works on them (compute.py,
level_deviation.py) can be used and tested without Blender."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ._core import core


@dataclass
class ColorLayer:
    """A colour attribute: data is (n, 4) for domain POINT, (m, 3, 4) for CORNER."""

    name: str
    domain: str  # 'POINT' or 'CORNER'
    data_type: str  # 'FLOAT_COLOR' or 'BYTE_COLOR'
    data: np.ndarray


@dataclass
class AttributeLayer:
    """A generic attribute of the mesh (an artist's, a Geometry Nodes output, a glTF
    importer's custom one; what the other fields hold is not one), carried to the LODs.

    ``domain`` and ``data_type`` are Blender's. ``data``, with the attribute's values
    last (width 1 for a single value): (n, w) per vertex for 'POINT', (m, w) per
    triangle for 'FACE', (m, 3, w) per triangle corner for 'CORNER', and for 'EDGE'
    (k, w) per edge of ``edges`` (k, 2) vertex pairs."""

    name: str
    domain: str
    data_type: str
    data: np.ndarray
    edges: Optional[np.ndarray] = None


# How each kind of attribute is read, written and carried: Blender's data type ->
# (the foreach_get/foreach_set property, values per element, NumPy type, interpolated).
# Interpolated values follow a collapse as UVs and shape keys do (a painted wear mask, a
# wind weight); the others (ids, flags, rotations and matrices, which a mean would not
# keep valid) take the value of the vertex, face or corner each LOD element came from.
ATTRIBUTE_TYPES = {
    'FLOAT': ("value", 1, np.float32, True),
    'FLOAT2': ("vector", 2, np.float32, True),
    'FLOAT_VECTOR': ("vector", 3, np.float32, True),
    'FLOAT_COLOR': ("color", 4, np.float32, True),
    'BYTE_COLOR': ("color", 4, np.float32, True),
    'QUATERNION': ("value", 4, np.float32, False),
    'FLOAT4X4': ("value", 16, np.float32, False),
    'INT': ("value", 1, np.int32, False),
    'INT8': ("value", 1, np.int32, False),
    'INT32_2D': ("value", 2, np.int32, False),
    'BOOLEAN': ("value", 1, bool, False),
}


def interpolated(layer: AttributeLayer) -> bool:
    """Whether ``layer``'s values are interpolated along collapses (ATTRIBUTE_TYPES)."""
    return ATTRIBUTE_TYPES[layer.data_type][3]


@dataclass
class ShapeKeyData:
    """A shape key as offsets from the basis, plus the settings the LOD copies."""

    name: str
    offsets: np.ndarray  # (n, 3)
    value: float = 0.0
    slider_min: float = 0.0
    slider_max: float = 1.0
    mute: bool = False
    relative_key: str = ""
    vertex_group: str = ""
    interpolation: str = 'KEY_LINEAR'


@dataclass
class MeshData:
    """A triangulated mesh and the data it carries, all as NumPy arrays.

    Per vertex: vertices (n, 3), group_weights (n, g), point colours, shape-key offsets.
    Per triangle: faces (m, 3), material_index, smooth, smooth_group (the input's
    smoothing region, so the LOD splits normals where the source did).
    Per triangle corner (m, 3, k): UV maps, corner colours.
    Any domain: ``attributes``, the mesh's other attributes (AttributeLayer).
    Edges as (k, 2) vertex pairs: sharp_edges, seam_edges; seam_region labels the
    triangles by the regions the seams cut the surface into (so the LOD's seams can be
    marked where the source's were).
    """

    vertices: np.ndarray
    faces: np.ndarray
    material_index: np.ndarray
    smooth: np.ndarray
    smooth_group: np.ndarray
    uv_maps: dict = field(default_factory=dict)
    uv_active: Optional[str] = None
    uv_render: Optional[str] = None
    colors: list = field(default_factory=list)
    attributes: list = field(default_factory=list)  # AttributeLayer
    color_active: Optional[str] = None
    color_render: Optional[str] = None
    group_names: list = field(default_factory=list)
    group_weights: Optional[np.ndarray] = None
    basis_name: str = "Basis"
    shape_keys: list = field(default_factory=list)
    shape_use_relative: bool = True
    sharp_edges: np.ndarray = field(default_factory=lambda: np.empty((0, 2), np.int64))
    # Most edges of the mesh (more than half) are marked sharp: shaded flat through its
    # edges (how the OBJ and FBX importers bring a flat-shaded mesh: every edge but those
    # between coplanar faces), the marks single out no crease.
    sharp_for_shading: bool = False
    seam_edges: np.ndarray = field(default_factory=lambda: np.empty((0, 2), np.int64))
    seam_region: Optional[np.ndarray] = None  # (m,) per triangle: the region between seams
    # (m, 3, 3) unit normal per triangle corner when the mesh has custom split normals
    # (an artist's or a Weighted Normal modifier's shading), else None.
    custom_normals: Optional[np.ndarray] = None
    # (m, 3, 3) the normal of each triangle corner as Blender shades the mesh (custom,
    # smooth or flat): what a LOD's shading is measured against. Set by read_mesh; None
    # on the LODs' data (core.shading.corner_normals gives theirs).
    corner_normals: Optional[np.ndarray] = None
    # Written onto the mesh build_mesh makes, not read back: float attributes on the
    # points, {name: (n,)}, and custom properties of the mesh datablock, {name: value}
    # (a LOD's heat map: addon/pure/level_deviation.py).
    point_floats: dict = field(default_factory=dict)
    mesh_properties: dict = field(default_factory=dict)

    @property
    def has_shape_keys(self) -> bool:
        return bool(self.shape_keys)


def shading_normals(data: MeshData) -> np.ndarray:
    """(m, 3, 3) the corner normals Blender gives the mesh addon/mesh_io.py's
    build_mesh(data) makes: the custom normals it writes, else the ones Blender computes
    from the smooth flags and sharp edges (core.shading.corner_normals), without building
    the mesh."""
    if data.custom_normals is not None:
        return np.asarray(data.custom_normals, dtype=np.float64)
    return core.shading.corner_normals(data.vertices, data.faces, data.smooth, data.sharp_edges)
