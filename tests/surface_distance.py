"""Brute-force point-to-surface distances for the tests' small meshes, on core's own
closest-point primitive (core.geometry.closest_on_triangles, itself checked against
sampled triangles in tests/test_core_tracked_distance.py)."""
from __future__ import annotations

import numpy as np

from core.geometry import closest_on_triangles


def nearest_faces(points, V, F):
    """For each point, the triangle of (V, F) nearest to it, its barycentric coordinates
    of the closest point there and the distance: brute force (small meshes)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    tri = np.empty(len(points), np.int64)
    for i in range(0, len(points), 256):
        p = points[i:i + 256]
        k = len(p)
        _, d2 = closest_on_triangles(np.repeat(p, len(F), 0), np.tile(a, (k, 1)), np.tile(b, (k, 1)),
                                     np.tile(c, (k, 1)))
        tri[i:i + k] = d2.reshape(k, len(F)).argmin(axis=1)
    bary, d2 = closest_on_triangles(points, a[tri], b[tri], c[tri])
    return tri, bary, np.sqrt(d2)


def mean_distance(points, V, F):
    """Mean distance from points to the mesh (V, F)."""
    return float(distance_to_mesh(points, V, F).mean())


def distance_to_mesh(points, V, F) -> np.ndarray:
    """(p,) distance from each point to the nearest triangle of (V, F)."""
    return nearest_faces(points, V, F)[2]
