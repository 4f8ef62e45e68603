"""Small vectorised geometry shared by the engine's steps."""
from __future__ import annotations

import numpy as np


def face_frames(vertices: np.ndarray, faces: np.ndarray) -> tuple:
    """Unit normals (m, 3) (zero for degenerate faces) and areas (m,) of triangles."""
    p0 = vertices[faces[:, 0]]
    cross = np.cross(vertices[faces[:, 1]] - p0, vertices[faces[:, 2]] - p0)
    double_area = np.linalg.norm(cross, axis=1)
    normals = np.zeros_like(cross)
    ok = double_area > 0
    normals[ok] = cross[ok] / double_area[ok, None]
    return normals, 0.5 * double_area


def edge_parameter(a: np.ndarray, b: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Where each p (k, 3) projects on segment a->b, clamped to [0, 1]: the weight of b
    when interpolating data for a collapsed edge."""
    d = b - a
    dd = np.einsum("ij,ij->i", d, d)
    t = np.einsum("ij,ij->i", p - a, d) / np.where(dd > 0, dd, 1.0)
    return np.clip(np.where(dd > 0, t, 0.0), 0.0, 1.0)
