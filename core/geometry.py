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


def closest_on_triangles(p, a, b, c) -> tuple:
    """The point of each triangle (a[i], b[i], c[i]) closest to p[i], all (k, 3): its
    barycentric weights of a, b, c (k, 3) and its squared distance to p (k,).

    Inside the triangle's prism it is the projection on the plane; elsewhere it lies on
    an edge the projection is beyond (the opposite barycentric coordinate is negative),
    so only those edges are measured, as clamped segments. A degenerate triangle (no
    area) is measured as its three edges."""
    p, a, b, c = (np.asarray(x, dtype=np.float64) for x in (p, a, b, c))
    ab, ac, ap = b - a, c - a, p - a
    d00, d01, d11 = dot_rows(ab, ab), dot_rows(ab, ac), dot_rows(ac, ac)
    d20, d21 = dot_rows(ap, ab), dot_rows(ap, ac)
    denom = d00 * d11 - d01 * d01
    # Nearly collinear corners (sin^2 of the angle at a below 1e-12): as three edges.
    flat = denom <= 1e-12 * np.maximum(d00 * d11, 1e-300)
    safe = np.where(flat, 1.0, denom)
    v = (d11 * d20 - d01 * d21) / safe
    w = (d00 * d21 - d01 * d20) / safe
    u = 1.0 - v - w
    q = ap - v[:, None] * ab - w[:, None] * ac
    inside = (u >= 0) & (v >= 0) & (w >= 0) & ~flat
    d2 = np.where(inside, dot_rows(q, q), np.inf)
    bary = np.stack([u, v, w], axis=1)
    for beyond, i, j in ((w < 0, 0, 1), (u < 0, 1, 2), (v < 0, 2, 0)):
        at = np.flatnonzero((beyond | flat) & ~inside)
        if len(at) == 0:
            continue
        start, end = (a, b, c)[i][at], (a, b, c)[j][at]
        e = end - start
        ee = dot_rows(e, e)
        t = np.clip(dot_rows(p[at] - start, e) / np.where(ee > 0, ee, 1.0), 0.0, 1.0)
        r = p[at] - start - t[:, None] * e
        dist = dot_rows(r, r)
        closer = dist < d2[at]
        rows_ = at[closer]
        d2[rows_] = dist[closer]
        bary[rows_] = 0.0
        bary[rows_, i] = 1.0 - t[closer]
        bary[rows_, j] = t[closer]
    return bary, d2


def dot_rows(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Row-wise dot products of (k, d) arrays."""
    return np.einsum("ij,ij->i", x, y)


def _row_keys(values: np.ndarray) -> np.ndarray:
    """(k,) one opaque key per row of a (k, w) array, equal exactly where the rows are
    equal bit for bit (for floats -0.0 and 0.0 differ: rows compared are copies, not
    results)."""
    values = np.ascontiguousarray(values)
    return values.view(np.dtype((np.void, values.dtype.itemsize * values.shape[1]))).ravel()


def _find(keys_a: np.ndarray, keys_b: np.ndarray) -> np.ndarray:
    """(ka,) the index in keys_b of each of keys_a, or -1."""
    if len(keys_b) == 0 or len(keys_a) == 0:
        return np.full(len(keys_a), -1, dtype=np.int64)
    order = np.argsort(keys_b, kind="stable")
    at = np.minimum(np.searchsorted(keys_b[order], keys_a), len(keys_b) - 1)
    found = order[at]
    return np.where(keys_b[found] == keys_a, found, -1)


def same_points(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(ka,) for each point of a (ka, 3), the index of a point of b (kb, 3) at the very
    same position (bit for bit), or -1."""
    return _find(_row_keys(np.asarray(a, dtype=np.float64)), _row_keys(np.asarray(b, dtype=np.float64)))


def distinct_points(points: np.ndarray) -> tuple:
    """The distinct positions among ``points`` (k, 3), bit for bit: ((u,) the index of one
    point at each position, (k,) which of those u each point is at), so that
    ``points[first][inverse]`` is ``points``."""
    keys = _row_keys(np.asarray(points, dtype=np.float64))
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    return first, inverse.reshape(-1)


def position_ids(*point_sets) -> list:
    """One id per position over several point sets, each (k_i, 3): [(k_i,) int64], equal
    exactly where two points are at the very same position (bit for bit), whichever sets
    they are in. The ids follow one sorted order of the positions, so np.unique of one
    set's ids gives its distinct positions in distinct_points' order. One sort serves
    every comparison between the sets (measuring a LOD against its source compared them
    eight times, a sort each)."""
    sizes = [len(p) for p in point_sets]
    points = np.concatenate([np.asarray(p, dtype=np.float64).reshape(-1, 3) for p in point_sets])
    _, inverse = np.unique(_row_keys(points), return_inverse=True)
    return np.split(inverse.reshape(-1).astype(np.int64), np.cumsum(sizes)[:-1])


def index_of(keys_a: np.ndarray, keys_b: np.ndarray) -> np.ndarray:
    """(ka,) the index in keys_b (1-D, sortable) of each of keys_a, the first where
    several are equal, or -1."""
    return _find(keys_a, keys_b)


def same_triangles(va, fa, vb, fb) -> tuple:
    """Which triangles of mesh a are triangles of mesh b, corner for corner: ((ma,) the
    index of a triangle of b on vertices at the very same positions (bit for bit), either
    winding, or -1; (ma, 3) which corner of that triangle each of a's corners is).

    A LOD keeps its source's unmoved vertices exactly (core.simplify returns them as
    given), so where no collapse reached, its triangles are the source's: the distance
    between the two surfaces there is zero, with no search (addon/pure/measure.py)."""
    ids_a, ids_b = position_ids(va, vb)
    return triangles_at_same_positions(ids_a, fa, ids_b, fb)


def triangles_at_same_positions(ids_a, fa, ids_b, fb) -> tuple:
    """same_triangles from the vertices' position_ids (``ids_a``, ``ids_b``): whichever
    copies of a position (a UV seam's, a hard edge's) the two triangles use."""
    fa, fb = np.asarray(fa, dtype=np.int64), np.asarray(fb, dtype=np.int64)
    match = np.full(len(fa), -1, dtype=np.int64)
    corner = np.zeros((len(fa), 3), dtype=np.int64)
    if len(fa) == 0 or len(fb) == 0:
        return match, corner
    at_a, at_b = ids_a[fa], ids_b[fb]
    # A triangle is its three positions in order, whatever its rotation and winding.
    top = int(max(at_a.max(), at_b.max())) + 1
    found = _find(_triple_keys(np.sort(at_a, axis=1), top), _triple_keys(np.sort(at_b, axis=1), top))
    hit = np.flatnonzero(found >= 0)
    match[hit] = found[hit]
    # Which corner of b's triangle holds each of a's corners' position.
    corner[hit] = np.argmax(at_b[found[hit]][:, None, :] == at_a[hit][:, :, None], axis=2)
    return match, corner


def _triple_keys(rows_: np.ndarray, top: int) -> np.ndarray:
    """(k,) one sortable key per row of a (k, 3) array of ids in 0 .. top - 1: an int64
    (21 bits an id) while they fit, else the rows' bytes."""
    if top <= 1 << 21:
        return (rows_[:, 0] << 42) | (rows_[:, 1] << 21) | rows_[:, 2]
    return _row_keys(rows_)
