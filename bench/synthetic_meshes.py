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


def grid(n: int, jitter: float = 0.0, seed: int = 0, size: float = 1.0, start: float = 0.0):
    """A flat n x n vertex grid on [start, start + size]^2 (z = 0), each quad split into two
    triangles along the same diagonal.

    Interior vertices move in the plane by up to ``jitter`` grid spacings (uniform), so the
    triangulation is irregular but the surface stays exactly flat.
    Returns V (n*n, 3) f64, F (2 (n-1)^2, 3) i64, counter-clockwise seen from +z.
    """
    xs = np.linspace(start, start + size, n)
    X, Y = np.meshgrid(xs, xs, indexing="xy")
    V = np.stack([X.ravel(), Y.ravel(), np.zeros(n * n)], axis=1)
    if jitter > 0:
        h = size / (n - 1)
        x, y = V[:, 0], V[:, 1]
        inner = (x > start) & (x < start + size) & (y > start) & (y < start + size)
        rng = np.random.default_rng(seed)
        V[inner, :2] += rng.uniform(-jitter * h, jitter * h, (int(inner.sum()), 2))
    r, c = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (r * n + c).ravel()
    b, d = a + 1, a + n
    e = d + 1
    F = np.concatenate([np.stack([a, b, e], 1), np.stack([a, e, d], 1)]).astype(np.int64)
    return V, F


def icosahedron():
    """The regular icosahedron (not on the unit sphere: vertices at (0, +-1, +-phi) and
    their cyclic turns), faces wound outward. Returns (V (12, 3) f64, F (20, 3) i64)."""
    t = (1.0 + 5 ** 0.5) / 2
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
                  [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
                  [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]], np.int64)
    return V, F


def bumpy_sphere(subdivisions: int = 5, amplitude: float = 0.08):
    """A procedural stand-in for a scanned mesh: an icosphere with smooth bumps."""
    V, F = icosahedron()
    for _ in range(subdivisions):
        V, F = subdivide_midpoint(V, F)
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    x, y, z = V.T
    r = 1.0 + amplitude * (np.sin(5 * x) * np.sin(4 * y) * np.sin(6 * z) + 0.5 * np.sin(11 * x + 3 * z))
    return V * r[:, None], F


def scan_like(subdivisions: int = 9, noise: float = 0.0005, seed: int = 0):
    """A stand-in for a photogrammetry scan: ``bumpy_sphere`` with fine noise along the
    normal (``noise`` of the radius, what a scanner adds) and its vertices and faces in a
    random order (scans come out of reconstruction in no useful order, so nothing of the
    input's numbering helps the cache). 9 subdivisions: 5,242,880 faces."""
    V, F = bumpy_sphere(subdivisions)
    rng = np.random.default_rng(seed)
    V = V * (1.0 + noise * rng.standard_normal(len(V)))[:, None]
    return shuffled(V, F, rng)


def shuffled(V, F, seed=0):
    """The same surface with its vertices and faces numbered at random (the order a scan
    or a careless exporter may give). seed: an int or a numpy Generator."""
    rng = np.random.default_rng(seed)
    order = rng.permutation(len(V))
    new_id = np.empty(len(V), dtype=np.int64)
    new_id[order] = np.arange(len(V))
    return V[order], new_id[F][rng.permutation(len(F))]


def uv_sphere(rings: int):
    """A closed unit UV sphere, faces wound outward: ``rings`` bands from pole to pole,
    ``2 * rings`` segments. Returns (vertices (n, 3) float64, faces (4 * rings * (rings - 1), 3) int64)."""
    theta = np.linspace(0.0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0.0, 2.0 * np.pi, 2 * rings, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    vertices = np.c_[(np.sin(t) * np.cos(p)).ravel(), (np.sin(t) * np.sin(p)).ravel(), np.cos(t).ravel()]
    vertices = np.r_[vertices, [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]]]
    bands, around = t.shape
    r, c = np.meshgrid(np.arange(bands - 1), np.arange(around), indexing="ij")
    a, b = (r * around + c).ravel(), (r * around + (c + 1) % around).ravel()
    top, bottom = len(vertices) - 2, len(vertices) - 1
    first, last = np.arange(around), (bands - 1) * around + np.arange(around)
    faces = np.r_[np.c_[a, a + around, b + around], np.c_[a, b + around, b],
                  np.c_[np.full(around, top), first, (first + 1) % around],
                  np.c_[np.full(around, bottom), (bands - 1) * around + (first + 1) % around, last]]
    return vertices, faces.astype(np.int64)
