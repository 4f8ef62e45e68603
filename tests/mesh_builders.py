"""Meshes the tests build, in NumPy: procedural inputs with known structure.

Every builder returns float64 vertices (n, 3) and int64 faces (m, 3) with outward
(counter-clockwise seen from outside) orientation; some also return corner UVs
(m, 3, 2) indexed like the faces, or per-face material indices. Nothing here imports
the core, so the tests' checks (mesh_checks.py) judge its output independently.
"""
from __future__ import annotations

import numpy as np

from bench.synthetic_meshes import shuffled  # noqa: F401  (tests renumber meshes with it)


def grid(nx: int = 10, ny: int = None, size=1.0, jitter: float = 0.0, seed: int = 0,
         height=None, alternate: bool = True):
    """A rectangle [0, sx] x [0, sy] of nx x ny quads, two triangles each, normal +z.

    jitter: interior vertices move in-plane by up to ``jitter`` cells in x and in y
    (<= 0.25 keeps every triangle positively oriented). height: optional f(x, y) -> z for a bumpy sheet.
    alternate: alternate the quad diagonals (a less biased triangulation).
    """
    ny = nx if ny is None else ny
    sx, sy = (size, size) if np.isscalar(size) else size
    x, y = np.meshgrid(np.linspace(0.0, sx, nx + 1), np.linspace(0.0, sy, ny + 1), indexing="xy")
    if jitter:
        rng = np.random.default_rng(seed)
        inner = np.zeros_like(x, dtype=bool)
        inner[1:-1, 1:-1] = True
        x = x + inner * rng.uniform(-jitter, jitter, x.shape) * (sx / nx)
        y = y + inner * rng.uniform(-jitter, jitter, y.shape) * (sy / ny)
    z = np.zeros_like(x) if height is None else height(x, y)
    v = np.c_[x.ravel(), y.ravel(), z.ravel()]
    j, i = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    a = (j * (nx + 1) + i).ravel()
    b, c, d = a + 1, a + nx + 2, a + nx + 1  # (i+1, j), (i+1, j+1), (i, j+1)
    flip = ((i + j) % 2 == 1).ravel() if alternate else np.zeros(a.size, dtype=bool)
    t1 = np.where(flip[:, None], np.c_[a, b, d], np.c_[a, b, c])
    t2 = np.where(flip[:, None], np.c_[b, c, d], np.c_[a, c, d])
    return v, np.concatenate([t1, t2]).astype(np.int64)


def bumps(amplitude: float = 0.15, freq: float = 2.0):
    """A smooth height field for :func:`grid`."""
    return lambda x, y: amplitude * np.sin(freq * np.pi * x) * np.cos(freq * np.pi * y)


def uv_sphere(n_lon: int = 16, n_lat: int = 10, radius: float = 1.0, pole_uv: str = "shared"):
    """A UV sphere: poles on z, n_lat bands, n_lon segments. Returns (V, F, UV).

    One vertex per position (the seam is in the corner UVs only): the meridian at u = 0
    has u = 0 on one side and u = 1 on the other. pole_uv: "shared" gives every pole
    corner the UV (0.5, v_pole), so the only seam is the meridian from pole to pole;
    "fan" gives each pole triangle its own u (as Blender's UV sphere does), so every
    pole edge is a seam too.
    """
    lon = np.arange(n_lon)
    rings = np.arange(1, n_lat)
    theta = np.pi * rings / n_lat
    phi = 2.0 * np.pi * lon / n_lon
    ring_v = np.stack([
        np.outer(np.sin(theta), np.cos(phi)),
        np.outer(np.sin(theta), np.sin(phi)),
        np.repeat(np.cos(theta)[:, None], n_lon, axis=1),
    ], axis=-1).reshape(-1, 3)
    north, south = 0, 1 + len(ring_v)
    v = np.concatenate([[[0.0, 0.0, 1.0]], ring_v, [[0.0, 0.0, -1.0]]]) * radius

    def rid(j, i):  # ring j in 1..n_lat-1, longitude i (wraps)
        return 1 + (j - 1) * n_lon + (i % n_lon)

    def ruv(j, i):  # i in 0..n_lon, not wrapped: u = 1 at the far side of the seam
        return np.stack([i / n_lon, np.full(len(i), 1.0 - j / n_lat)], axis=-1).astype(np.float64)

    faces, uvs = [], []
    i = lon
    pole_u = np.full(n_lon, 0.5) if pole_uv == "shared" else (i + 0.5) / n_lon
    # North cap: (pole, ring1[i], ring1[i+1]) is counter-clockwise from outside.
    faces.append(np.c_[np.full(n_lon, north), rid(1, i), rid(1, i + 1)])
    uvs.append(np.stack([np.c_[pole_u, np.ones(n_lon)], ruv(1, i), ruv(1, i + 1)], axis=1))
    for j in range(1, n_lat - 1):
        a, b, c, d = rid(j, i), rid(j + 1, i), rid(j + 1, i + 1), rid(j, i + 1)
        ua, ub, uc, ud = ruv(j, i), ruv(j + 1, i), ruv(j + 1, i + 1), ruv(j, i + 1)
        faces += [np.c_[a, b, c], np.c_[a, c, d]]
        uvs += [np.stack([ua, ub, uc], axis=1), np.stack([ua, uc, ud], axis=1)]
    j = n_lat - 1
    faces.append(np.c_[rid(j, i), np.full(n_lon, south), rid(j, i + 1)])
    uvs.append(np.stack([ruv(j, i), np.c_[pole_u, np.zeros(n_lon)], ruv(j, i + 1)], axis=1))
    return v, np.concatenate(faces).astype(np.int64), np.concatenate(uvs)


def subdivided_uv_sphere(levels: int = 1, n_lon: int = 32, n_lat: int = 16):
    """uv_sphere(pole_uv="fan") subdivided ``levels`` times (1->4 midpoints, pushed back
    onto the sphere), each face's UVs interpolated within that face, as a Subdivision
    Surface modifier gives Blender's UV sphere: the pole edges' midpoints have one UV per
    side, half the pole's jump. Returns (V, F, UV)."""
    v, f, uv = uv_sphere(n_lon, n_lat, pole_uv="fan")
    for _ in range(levels):
        m = len(f)
        v, f_new = subdivide(v, f)
        v = v / np.linalg.norm(v, axis=1, keepdims=True)
        mid = 0.5 * (uv + uv[:, [1, 2, 0]])  # midpoints of corners 01, 12, 20
        c0, c1, c2, a, b, c = uv[:, 0], uv[:, 1], uv[:, 2], mid[:, 0], mid[:, 1], mid[:, 2]
        uv = np.concatenate([np.stack([c0, a, c], axis=1), np.stack([a, c1, b], axis=1),
                             np.stack([c, b, c2], axis=1), np.stack([a, b, c], axis=1)])
        assert len(f_new) == 4 * m
        f = f_new
    return v, f, uv


def cube(k: int = 4, split: bool = False, half: float = 1.0, ticks=None):
    """A cube [-half, half]^3, each side a k x k grid of quads with its own UV island.

    Returns (V, F, UV). split=False: one vertex per position, the islands' borders are
    seams in the corner UVs. split=True: every side has its own vertices (as exported
    game assets arrive), coincident along the cube's edges, same UVs. ``ticks``: the
    grid's coordinates along each axis (increasing, from -half to half) instead of k
    even steps.
    """
    t = np.linspace(-half, half, k + 1) if ticks is None else np.asarray(ticks, dtype=np.float64)
    k = len(t) - 1
    # (normal axis, sign, u axis, v axis) with u x v = outward normal.
    sides = [(0, 1, 1, 2), (0, -1, 2, 1), (1, 1, 2, 0), (1, -1, 0, 2), (2, 1, 0, 1), (2, -1, 1, 0)]
    s_idx, r_idx = np.meshgrid(np.arange(k + 1), np.arange(k + 1), indexing="xy")
    V, F, UV = [], [], []
    base = 0
    for n_side, (axis, sign, ua, va) in enumerate(sides):
        p = np.zeros((k + 1, k + 1, 3))
        p[..., axis] = sign * half
        p[..., ua] = t[s_idx]
        p[..., va] = t[r_idx]
        col, row = n_side % 3, n_side // 3
        uv = np.stack([(col + 0.05 + 0.9 * s_idx / k) / 3.0, (row + 0.05 + 0.9 * r_idx / k) / 2.0], axis=-1)
        jj, ii = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")
        a = (jj * (k + 1) + ii).ravel()
        b, c, d = a + 1, a + k + 2, a + k + 1
        f = np.concatenate([np.c_[a, b, c], np.c_[a, c, d]])
        flat_uv = uv.reshape(-1, 2)
        V.append(p.reshape(-1, 3))
        F.append(f + base)
        UV.append(flat_uv[f])
        base += (k + 1) ** 2
    V, F, UV = np.concatenate(V), np.concatenate(F).astype(np.int64), np.concatenate(UV)
    if not split:
        V, F = weld_exact(V, F)
    return V, F, UV


def bevelled_box(flat: int = 2, segments: int = 4, bevel: float = 0.15):
    """A cube [-1, 1]^3 with every edge bevelled round, as Blender's Bevel modifier and a
    simple subdivision make a prop: each side's flat part a ``flat`` x ``flat`` grid,
    each bevel ``segments`` rows of a quarter circle of radius ``bevel``, spherical
    corners. Returns (V, F)."""
    inner = 1.0 - bevel
    ticks = np.concatenate([np.linspace(-1.0, -inner, segments + 1), np.linspace(-inner, inner, flat + 1)[1:-1],
                            np.linspace(inner, 1.0, segments + 1)])
    V, F, _ = cube(ticks=ticks)
    # Each grid point goes onto the rounded box: the nearest point of the inner box plus
    # ``bevel`` along the way out (a quarter circle's rows at even angles, not even steps).
    core_point = np.clip(V, -inner, inner)
    out = V - core_point
    length = np.linalg.norm(out, axis=1, keepdims=True)
    V = core_point + bevel * out / np.maximum(length, 1e-300)
    return V, F


def weld_exact(V, F, return_map=False):
    """Merge exactly coincident vertices (keeps the first of each position, in order).

    return_map: also return (n,) the welded index of every input vertex.
    """
    _, first, inverse = np.unique(V, axis=0, return_index=True, return_inverse=True)
    order = np.sort(first)
    new_of_first = np.empty(len(V), dtype=np.int64)
    new_of_first[order] = np.arange(len(order))
    index = new_of_first[first[inverse.reshape(-1)]]
    return (V[order], index[F], index) if return_map else (V[order], index[F])


def torus(nu: int = 16, nv: int = 8, R: float = 1.0, r: float = 0.35):
    """A closed torus around z (Euler characteristic 0)."""
    u = 2.0 * np.pi * np.arange(nu) / nu
    w = 2.0 * np.pi * np.arange(nv) / nv
    U, W = np.meshgrid(u, w, indexing="ij")
    v = np.stack([(R + r * np.cos(W)) * np.cos(U), (R + r * np.cos(W)) * np.sin(U), r * np.sin(W)], -1).reshape(-1, 3)
    I, J = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a = (I * nv + J).ravel()
    b = (((I + 1) % nu) * nv + J).ravel()
    c = (((I + 1) % nu) * nv + (J + 1) % nv).ravel()
    d = (I * nv + (J + 1) % nv).ravel()
    return v, np.concatenate([np.c_[a, b, c], np.c_[a, c, d]]).astype(np.int64)


def tube(n_around: int = 16, n_height: int = 8, radius: float = 0.5, height: float = 2.0):
    """An open cylinder along z: two boundary loops."""
    ang = 2.0 * np.pi * np.arange(n_around) / n_around
    zs = np.linspace(0.0, height, n_height + 1)
    A, Z = np.meshgrid(ang, zs, indexing="ij")
    v = np.stack([radius * np.cos(A), radius * np.sin(A), Z], -1).reshape(-1, 3)
    I, J = np.meshgrid(np.arange(n_around), np.arange(n_height), indexing="ij")
    h = n_height + 1
    a = (I * h + J).ravel()
    b = (((I + 1) % n_around) * h + J).ravel()
    c = b + 1
    d = a + 1
    return v, np.concatenate([np.c_[a, b, c], np.c_[a, c, d]]).astype(np.int64)


def two_material_sheet(n: int = 20, curved: bool = True):
    """A square sheet, left half material 0, right half material 1, border on x = 0.5.

    curved: a gentle cylindrical bend (z depends on y only) so the border is a curve in
    3D but still exactly the polyline of grid line x = 0.5. Returns (V, F, material).
    """
    height = (lambda x, y: 0.25 * np.sin(np.pi * y)) if curved else None
    v, f = grid(n, size=1.0, height=height)
    cx = v[f, 0].mean(axis=1)
    return v, f, (cx > 0.5).astype(np.int64)


def components(meshes):
    """Concatenate (V, F) pairs into one mesh of disjoint components."""
    V, F, base = [], [], 0
    for v, f in meshes:
        V.append(v)
        F.append(f + base)
        base += len(v)
    return np.concatenate(V), np.concatenate(F).astype(np.int64)


def with_fin(n: int = 10, fin_rows: int = 3):
    """A flat grid with a vertical fin standing on its middle row of vertices: every
    edge along that row carries three or four faces (non-manifold)."""
    v, f = grid(n, alternate=False)
    row = n // 2
    base_ids = row * (n + 1) + np.arange(n + 1)  # vertices with y = 0.5
    zs = np.linspace(0.0, 0.5, fin_rows + 1)[1:]
    X, Z = np.meshgrid(v[base_ids, 0], zs, indexing="xy")
    fin_v = np.c_[X.ravel(), np.full(X.size, 0.5), Z.ravel()]
    ids = np.concatenate([base_ids[None, :], len(v) + np.arange(X.size).reshape(fin_rows, n + 1)])
    a, b = ids[:-1, :-1].ravel(), ids[:-1, 1:].ravel()
    c, d = ids[1:, 1:].ravel(), ids[1:, :-1].ravel()
    fin_f = np.concatenate([np.c_[a, b, c], np.c_[a, c, d]])
    return np.concatenate([v, fin_v]), np.concatenate([f, fin_f]).astype(np.int64)


def square_loop_edges(n: int, lo: int, hi: int):
    """The edges of :func:`grid` (n x n, any diagonals) along the square of grid lines
    lo..hi in both directions: a closed loop of 4 (hi - lo) edges."""
    def vid(i, j):
        return j * (n + 1) + i
    r = np.arange(lo, hi)
    bottom = np.c_[vid(r, lo), vid(r + 1, lo)]
    top = np.c_[vid(r, hi), vid(r + 1, hi)]
    left = np.c_[vid(lo, r), vid(lo, r + 1)]
    right = np.c_[vid(hi, r), vid(hi, r + 1)]
    return np.concatenate([bottom, right, top, left]).astype(np.int64)


def icosphere(level: int):
    """Unit icosphere (all vertices on the sphere) after ``level`` 1->4 subdivisions."""
    p = (1.0 + 5 ** 0.5) / 2.0
    v = np.array([[-1, p, 0], [1, p, 0], [-1, -p, 0], [1, -p, 0], [0, -1, p], [0, 1, p],
                  [0, -1, -p], [0, 1, -p], [p, 0, -1], [p, 0, 1], [-p, 0, -1], [-p, 0, 1]], float)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
                  [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
                  [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
                  [8, 6, 7], [9, 8, 1]], np.int64)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    for _ in range(level):
        v, f = subdivide(v, f)
        v /= np.linalg.norm(v, axis=1, keepdims=True)
    return v, f


def subdivide(v, f):
    """1->4 midpoint subdivision: (v', f'), the old vertices first, then one midpoint per
    edge. v may carry any columns (positions, barycentrics), all averaged."""
    e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    key = e[:, 0] * len(v) + e[:, 1]
    uniq, inv = np.unique(key, return_inverse=True)
    mid = 0.5 * (v[uniq // len(v)] + v[uniq % len(v)])
    m = len(f)
    a, b, c = (len(v) + inv.reshape(3, m)).astype(np.int64)  # midpoints of 01, 12, 20
    f = np.concatenate([np.c_[f[:, 0], a, c], np.c_[a, f[:, 1], b], np.c_[c, b, f[:, 2]], np.c_[a, b, c]])
    return np.concatenate([v, mid]), f


def thin_patches(count: int, seed: int = 0, levels: int = 2, bulge: float = 0.15):
    """``count`` separate curved patches, each a thin triangle (sides 1 and about 0.1,
    quality 0.1-0.2) subdivided ``levels`` times and bulged out of its plane by
    ``bulge`` x the sum of the barycentric products (so its border curves too), turned
    and placed at random: the patch soup a game export gives after Subdivision Surface."""
    rng = np.random.default_rng(seed)
    parts = []
    for _ in range(count):
        corners = np.array([[0.0, 0, 0], [1, 0, 0], [rng.uniform(0.2, 0.8), rng.uniform(0.06, 0.12), 0]])
        v, f = np.c_[corners, np.eye(3)], np.array([[0, 1, 2]])
        for _ in range(levels):
            v, f = subdivide(v, f)
        b = v[:, 3:]
        lift = bulge * (b[:, 0] * b[:, 1] + b[:, 1] * b[:, 2] + b[:, 2] * b[:, 0])
        turn = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        parts.append(((v[:, :3] + np.c_[0 * lift, 0 * lift, lift]) @ turn.T + rng.uniform(-3, 3, 3), f))
    return components(parts)



# ---------------------------------------------------------------- what exporters write (issue 33)

def flipped_caps(n_lon: int = 20, n_lat: int = 10):
    """A UV sphere whose two pole caps are wound the wrong way (some exporters write
    triangle fans so): (V, F, the rows of F turned over)."""
    V, F, _ = uv_sphere(n_lon, n_lat)
    F = F.copy()
    caps = np.r_[0:n_lon, len(F) - n_lon:len(F)]
    F[caps] = F[caps][:, ::-1]
    return V, F, caps


def with_bad_faces(V, F, seed: int = 0, share: float = 0.1):
    """(V, F') with faces no simplifier can use mixed in among F's, ``share`` of its count
    of each kind: exact duplicates, duplicates wound the other way, zero-area faces on
    three points of one line (the midpoint of an edge is added as a vertex) and faces
    with a repeated corner. Returns (V', F', (m',) bool: the rows no simplifier can use,
    the zero-area ones and those with a repeated corner; of two copies of a face either
    may serve)."""
    rng = np.random.default_rng(seed)
    k = max(int(share * len(F)), 1)
    dup = F[rng.choice(len(F), k, replace=False)]
    rev = F[rng.choice(len(F), k, replace=False)][:, ::-1]
    pick = F[rng.choice(len(F), k, replace=False)]
    mid = 0.5 * (V[pick[:, 0]] + V[pick[:, 1]])
    mid_ids = len(V) + np.arange(k)
    flat = np.c_[pick[:, 0], mid_ids, pick[:, 1]]
    repeated = F[rng.choice(len(F), k, replace=False)][:, [0, 0, 1]]
    bad = np.concatenate([dup, rev, flat, repeated])
    allF = np.concatenate([F, bad])
    order = rng.permutation(len(allF))
    is_bad = np.r_[np.zeros(len(F) + 2 * k, bool), np.ones(2 * k, bool)][order]
    return np.concatenate([V, mid]), allF[order].astype(np.int64), is_bad


def three_sheets(n: int = 10):
    """Three square sheets hinged on one shared edge (x = 0 .. 1, y = z = 0), at 0, 120
    and 240 degrees: every edge along the hinge has three faces."""
    sheets = []
    for angle in (0.0, 2 * np.pi / 3, 4 * np.pi / 3):
        v, f = grid(n)
        y = v[:, 1]
        sheets.append((np.c_[v[:, 0], y * np.cos(angle), y * np.sin(angle)], f))
    V, F = components(sheets)
    return weld_exact(V, F)


def bolts(count: int = 500, seed: int = 0, spread: float = 20.0):
    """``count`` separate closed boxes of 12 triangles each (bolts, rivets, screws of a CAD
    assembly) of random sizes 0.2-1 and turns, scattered over a cube of side ``spread``."""
    rng = np.random.default_rng(seed)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    quads = np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
    faces = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    meshes = []
    for _ in range(count):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        size = rng.uniform(0.1, 0.5, 3)
        meshes.append(((corners * size) @ q.T + rng.uniform(0, spread, 3), faces))
    return components(meshes)


def t_junction_slit(left: int = 12, right: int = 7, rows: int = 10):
    """One sheet tessellated in two halves that do not share their middle line: the left
    half cuts it into ``left`` segments, the right half into ``right`` (as CAD exporters
    tessellate each face of a solid alone). Only the line's two ends are shared, so the
    middle is a slit of zero width: two border chains on one line, T-junctions."""
    lv, lf = grid(rows, left, size=(1.0, 1.0), alternate=True)
    rv, rf = grid(rows, right, size=(1.0, 1.0), alternate=True)
    # Both halves in the plane z = 0; the left one for x in [-1, 0], the right one [0, 1],
    # the shared line at x = 0 (the left grid's last column, the right grid's first).
    lv = np.c_[lv[:, 0] - 1.0, lv[:, 1], lv[:, 2]]
    V, F = components([(lv, lf), (rv, rf)])
    return weld_exact(V, F)



def cracked_quadrants(divisions, seed: int = 0, jitter: float = 6e-4, sliver: float = 1e-4):
    """The sheet [-1, 1] x [-1, 1] (normal +z) as CAD exporters write a face they cut in
    four: each quadrant tessellated alone (``divisions``: its (nx, ny) quads, four pairs),
    so the lines x = 0 and y = 0 are cracks with T-junctions, only the origin and the
    lines' outer ends shared. Each quadrant's points on a line lie off it by up to
    ``jitter`` towards the other side (within core.stitching's tolerance), and its column
    and row of faces beside the lines are ``sliver`` wide, so that some of the splits that
    close the cracks would turn the other side's thin faces over and are undone; a face at
    the origin has a crack on two of its edges, split one round at a time."""
    rng = np.random.default_rng(seed)
    meshes = []
    for (sx, sy), (nx, ny) in zip(((-1, -1), (1, -1), (-1, 1), (1, 1)), divisions):
        v, f = grid(int(nx), int(ny), size=(1.0, 1.0))
        v = v.copy()
        v[np.isclose(v[:, 0], 1.0 / nx), 0] = sliver
        v[np.isclose(v[:, 1], 1.0 / ny), 1] = sliver
        on_x = np.isclose(v[:, 0], 0.0) & (v[:, 1] > 0) & (v[:, 1] < 1)
        on_y = np.isclose(v[:, 1], 0.0) & (v[:, 0] > 0) & (v[:, 0] < 1)
        v[on_x, 0] = -rng.uniform(0.0, jitter, int(on_x.sum()))
        v[on_y, 1] = -rng.uniform(0.0, jitter, int(on_y.sum()))
        v[:, 0] *= sx
        v[:, 1] *= sy
        meshes.append((v, f if sx * sy > 0 else f[:, ::-1]))  # (a mirror turns the faces over)
    return weld_exact(*components(meshes))


# cracked_quadrants' divisions and seeds in which a stitching round has every split undone
# (the faces come back in another order: core.stitching.stitch's parents must follow).
CRACKED_QUADRANTS = (
    (((4, 3), (7, 3), (7, 3), (5, 6)), 13),
    (((3, 7), (8, 3), (3, 5), (5, 7)), 14),
    (((7, 6), (7, 5), (8, 5), (3, 5)), 28),
    (((6, 5), (4, 4), (7, 8), (8, 8)), 29),
)


def _revolved(profile, n_around: int, first: int = 0):
    """A profile of (radius, height) points revolved about z in ``n_around`` steps: its
    rings' vertices (len(profile) * n_around, 3), ring i's ids starting at ``first`` + i *
    n_around, and a list of the strips' faces between consecutive rings (2 * n_around
    triangles each, wound outwards for a profile that runs down the outside)."""
    profile = np.asarray(profile, dtype=np.float64)
    t = 2 * np.pi * np.arange(n_around) / n_around
    V = np.concatenate([np.c_[r * np.cos(t), r * np.sin(t), np.full(n_around, z)] for r, z in profile])
    cur = np.arange(n_around)
    nxt = (cur + 1) % n_around
    strips = []
    for i in range(len(profile) - 1):
        a, b = first + i * n_around + cur, first + i * n_around + nxt
        c, d = first + (i + 1) * n_around + nxt, first + (i + 1) * n_around + cur
        strips.append(np.concatenate([np.c_[a, d, c], np.c_[a, c, b]]))
    return V, strips

def filleted_puck(n_around: int = 64, n_cap: int = 4, n_fillet: int = 4, radius: float = 1.0,
                  fillet: float = 0.05, height: float = 0.2):
    """A closed puck, as CAD tessellates one: a flat cap in rings, a quarter-round fillet of
    radius ``fillet`` down to a straight wall, a flat bottom. UVs in two islands, the cap
    with its fillet planar and the wall with the bottom cylindrical, so a UV seam runs
    round the fillet's foot on the wall (BoomBox's knobs are made this way).
    Returns (V, F, UV (m, 3, 2))."""
    cap = [(radius - fillet) * i / n_cap for i in range(1, n_cap + 1)]
    profile = [(r, height) for r in cap]
    for j in range(1, n_fillet + 1):
        a = 0.5 * np.pi * j / n_fillet
        profile.append((radius - fillet + fillet * np.sin(a), height - fillet + fillet * np.cos(a)))
    foot = len(profile) - 1
    profile += [(radius, (height - fillet) * (1 - j / 2)) for j in (1, 2)]
    profile += [(r, 0.0) for r in cap[::-1][1:]]
    profile = np.array(profile)
    rings, strips = _revolved(profile, n_around, first=1)
    V = np.concatenate([[[0.0, 0.0, height]], rings, [[0.0, 0.0, 0.0]]])
    cur = np.arange(n_around)
    nxt = (cur + 1) % n_around
    last = 1 + (len(profile) - 1) * n_around
    F = [np.c_[np.zeros(n_around, np.int64), 1 + cur, 1 + nxt], *strips,
         np.c_[np.full(n_around, len(V) - 1), last + nxt, last + cur]]
    island = [np.zeros(n_around, np.int64), *(np.full(2 * n_around, int(i >= foot)) for i in range(len(strips))),
              np.ones(n_around, np.int64)]
    F, island = np.concatenate(F), np.concatenate(island)
    P = V[F]
    planar = P[..., :2] * 0.2 + 0.3
    u = np.arctan2(P[..., 1], P[..., 0])
    u = np.where(u.max(axis=1, keepdims=True) - u > np.pi, u + 2 * np.pi, u)  # one side of the wrap
    cylindrical = np.stack([u, P[..., 2]], axis=-1) + 5.0
    return V, F, np.where(island[:, None, None] == 0, planar, cylindrical)


def bevelled_disc(n_around: int = 64, radius: float = 1.0, depth: float = 0.4, bevel: float = 0.05,
                  segments: int = 4):
    """A closed disc as Blender's cylinder with its rims bevelled: two flat caps, each an
    ``n_around``-gon triangulated as a fan from one rim vertex, a quarter-round bevel of
    radius ``bevel`` in ``segments`` rings at each rim, and the straight wall between.
    Returns (V, F)."""
    half = depth / 2
    quarter = 0.5 * np.pi * np.arange(segments + 1) / segments
    top = np.c_[radius - bevel + bevel * np.sin(quarter), half - bevel + bevel * np.cos(quarter)]
    bottom = np.c_[radius - bevel + bevel * np.cos(quarter), -half + bevel - bevel * np.sin(quarter)]
    V, F = _revolved(np.concatenate([top, bottom]), n_around)
    fan = np.arange(1, n_around - 1)
    last = len(V) - n_around
    F.append(np.c_[np.zeros(len(fan), np.int64), fan, fan + 1])
    F.append(np.c_[np.full(len(fan), last), last + fan + 1, last + fan])
    return V, np.concatenate(F)


def holed_sphere(level: int = 3, holes: int = 40, seed: int = 0):
    """An icosphere with up to ``holes`` faces removed, no two sharing a vertex or a
    neighbour (greedily, in a random order: 35 fit at level 3 with seed 0), so as many
    separate holes of three border edges. Returns (V, F, the holes made)."""
    V, F = icosphere(level)[:2]
    F = np.asarray(F)
    used = np.zeros(len(V), dtype=bool)
    removed = []
    for f in np.random.default_rng(seed).permutation(len(F)):  # (a builder: a loop is fine)
        ring = np.flatnonzero(np.isin(F, F[f]).any(axis=1))
        if not used[F[ring]].any():
            removed.append(f)
            used[F[ring]] = True
            if len(removed) == holes:
                break
    keep = np.ones(len(F), dtype=bool)
    keep[removed] = False
    return np.asarray(V, dtype=np.float64), F[keep], len(removed)
