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
    color_active: Optional[str] = None
    color_render: Optional[str] = None
    group_names: list = field(default_factory=list)
    group_weights: Optional[np.ndarray] = None
    basis_name: str = "Basis"
    shape_keys: list = field(default_factory=list)
    shape_use_relative: bool = True
    sharp_edges: np.ndarray = field(default_factory=lambda: np.empty((0, 2), np.int64))
    # Every edge of the mesh is marked sharp: shaded flat through its edges (how the OBJ
    # and FBX importers bring a flat-shaded mesh), the marks single out no crease.
    sharp_everywhere: bool = False
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
