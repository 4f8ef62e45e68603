"""Small vectorised geometry shared by the engine's steps."""
from __future__ import annotations

import numpy as np


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross products of (k, 3) arrays: the same arithmetic as np.cross, which
    spends most of its time in generic axis handling (5x slower at 50k rows)."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    ax, ay, az = a[:, 0], a[:, 1], a[:, 2]
    bx, by, bz = b[:, 0], b[:, 1], b[:, 2]
    np.subtract(ay * bz, az * by, out=out[:, 0])
    np.subtract(az * bx, ax * bz, out=out[:, 1])
    np.subtract(ax * by, ay * bx, out=out[:, 2])
    return out


def rows(a: np.ndarray, index: np.ndarray) -> np.ndarray:
    """a[index] for a 2-D ``a``: np.take along axis 0 is about 4x faster than fancy
    indexing of rows in NumPy 1.26."""
    return np.take(a, index, axis=0)


def face_frames(vertices: np.ndarray, faces: np.ndarray) -> tuple:
    """Unit normals (m, 3) (zero for degenerate faces) and areas (m,) of triangles."""
    p0 = rows(vertices, faces[:, 0])
    normal = cross(rows(vertices, faces[:, 1]) - p0, rows(vertices, faces[:, 2]) - p0)
    double_area = np.linalg.norm(normal, axis=1)
    normals = np.zeros_like(normal)
    ok = double_area > 0
    normals[ok] = normal[ok] / double_area[ok, None]
    return normals, 0.5 * double_area


def edge_parameter(a: np.ndarray, b: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Where each p (k, 3) projects on segment a->b, clamped to [0, 1]: the weight of b
    when interpolating data for a collapsed edge."""
    d = b - a
    dd = np.einsum("ij,ij->i", d, d)
    t = np.einsum("ij,ij->i", p - a, d) / np.where(dd > 0, dd, 1.0)
    return np.clip(np.where(dd > 0, t, 0.0), 0.0, 1.0)
