"""Meshes the benchmarks make themselves (pure NumPy)."""
from __future__ import annotations

import numpy as np


def subdivide_midpoint(vertices, faces):
    """One 1->4 midpoint subdivision: every edge gets its midpoint, every triangle four
    children with the parent's orientation. Shared edges share their midpoint, so a
    manifold input stays manifold. Returns (V (n + edges, 3) f64, F (4m, 3) i64)."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    n, m = len(v), len(f)
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    e.sort(axis=1)
    # A scalar key per undirected edge: np.unique on int64 is much faster than on rows.
    key = e[:, 0] * n + e[:, 1]
    uniq, inv = np.unique(key, return_inverse=True)
    mid = 0.5 * (v[uniq // n] + v[uniq % n])
    a, b, c = (n + inv.reshape(3, m)).astype(np.int64)  # midpoints of edges 01, 12, 20
    f0, f1, f2 = f[:, 0], f[:, 1], f[:, 2]
    new_f = np.concatenate([np.stack([f0, a, c], 1), np.stack([a, f1, b], 1),
                            np.stack([c, b, f2], 1), np.stack([a, b, c], 1)])
    return np.concatenate([v, mid]), new_f


def arm_tube(around: int = 48, rings: int = 64):
    """The capped tube of tests/test_addon_skinned.py (an arm 2.6 long along z, radius
    about 0.2 with a narrowing at the elbow, z = 1), as triangles: each quad split along
    its first diagonal, each cap a fan. Returns (V (around*rings, 3) f64, F (k, 3) i64)."""
    z = np.linspace(0.02, 2.58, rings)
    radius = 0.22 + 0.05 * np.sin(z * np.pi / 1.3) ** 2 - 0.04 * np.exp(-((z - 1.0) / 0.12) ** 2)
    t = np.linspace(0, 2 * np.pi, around, endpoint=False)
    V = np.stack([np.outer(radius, np.cos(t)), np.outer(radius, np.sin(t)),
                  np.repeat(z[:, None], around, 1)], -1).reshape(-1, 3)
    idx = np.arange(rings * around).reshape(rings, around)
    q = np.stack([idx[:-1], np.roll(idx[:-1], -1, 1), np.roll(idx[1:], -1, 1), idx[1:]], -1).reshape(-1, 4)
    bottom, top = idx[0][::-1], idx[-1]
    caps = [np.stack([np.full(around - 2, c[0]), c[1:-1], c[2:]], 1) for c in (bottom, top)]
    return V, np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]], *caps]).astype(np.int64)
