"""Renumbering a large mesh so that neighbours sit near each other in memory.

Every pass gathers per-vertex rows (positions, quadrics, flags) through the faces and
edges. When a mesh's numbering scatters neighbours over the whole array (a subdivided or
re-exported mesh appends new vertices at the end; a scan may come in any order), those
gathers miss the cache once the arrays outgrow it, and the time per face grows with the
mesh. Sorting the vertices along a Z-order (Morton) curve and the faces by their smallest
corner keeps neighbours close: on the ogre subdivided to 2M faces the run took 17 % less
time, at 7.9M faces 15 % less (single runs; repeats vary by about 10 %); below about a
million faces the arrays fit the cache and nothing changes, so small meshes keep their
own numbering (and their outputs).

The engine works on the renumbered mesh; ``engine._snapshot`` gives the LOD back in the
input's order (vertices by ``vertex_origin``, faces by ``face_origin``).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from .geometry import rows

# Vertices from which renumbering pays (measured: no gain on the ogre, 62k vertices, nor on
# its 248k-vertex subdivision; 17 % on its 1M-vertex one); it costs about 0.25 s per
# million vertices.
MIN_VERTICES = 400_000
_BITS = 10  # per axis: a 1024^3 grid, finer than any pass needs


def reorder(p):
    """The Problem ``p`` with vertices in Z-order and faces by their smallest corner, or
    ``p`` itself when it is too small to gain (MIN_VERTICES)."""
    n = len(p.vertices)
    if n < max(MIN_VERTICES, 1):
        return p
    order = np.argsort(morton_codes(p.vertices))
    new_id = np.empty(n, dtype=np.int64)
    new_id[order] = np.arange(n)
    faces = new_id[p.faces]
    face_order = np.argsort(np.minimum(np.minimum(faces[:, 0], faces[:, 1]), faces[:, 2]))
    return dataclasses.replace(
        p,
        vertices=rows(p.vertices, order),
        input_positions=rows(p.input_positions, order),
        faces=rows(faces, face_order),
        face_origin=p.face_origin[face_order],
        vertex_origin=p.vertex_origin[order],
        line_weights=p.line_weights[order],
        quadric_scale=None if p.quadric_scale is None else p.quadric_scale[order],
        locked=p.locked[order],
        copies=None if p.copies is None else p.copies[order],
        vertex_limits=None if p.vertex_limits is None else p.vertex_limits[:, order],
        vertex_attributes={k: rows(a, order) for k, a in p.vertex_attributes.items()},
        corner_attributes={k: rows(a, face_order) for k, a in p.corner_attributes.items()},
        feature_edges=new_id[p.feature_edges] if len(p.feature_edges) else p.feature_edges,
        renumbered=True,
    )


def morton_codes(points: np.ndarray) -> np.ndarray:
    """(n,) uint64 Z-order keys of (n, 3) points in their bounding box."""
    lo = points.min(axis=0)
    extent = float(np.ptp(points, axis=0).max()) or 1.0
    cells = ((points - lo) * ((2 ** _BITS - 1) / extent)).astype(np.uint64)
    return _spread(cells[:, 0]) | (_spread(cells[:, 1]) << np.uint64(1)) | (_spread(cells[:, 2]) << np.uint64(2))


def _spread(x: np.ndarray) -> np.ndarray:
    """The 10 low bits of x moved to every third bit (bit i to bit 3i)."""
    x = x & np.uint64(0x3FF)
    x = (x | (x << np.uint64(16))) & np.uint64(0x030000FF)
    x = (x | (x << np.uint64(8))) & np.uint64(0x0300F00F)
    x = (x | (x << np.uint64(4))) & np.uint64(0x030C30C3)
    return (x | (x << np.uint64(2))) & np.uint64(0x09249249)
