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
