"""What the tests measure on a mesh and assert about a simplify result, in NumPy.

Measurements (edge tables, boundaries, components, seams, UV islands, distances) return
values; the ``assert_*`` functions raise AssertionError with a message saying what was
wrong. Nothing here imports the core, so these checks judge its output independently.
"""
from __future__ import annotations

import numpy as np


def edge_table(F):
    """Undirected edges (e, 2) sorted, and the number of faces on each."""
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    return uniq, count


def directed_edges(F):
    return np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])


def boundary_edges(F):
    e, c = edge_table(F)
    return e[c == 1]


def euler_characteristic(F):
    used = np.unique(F)
    e, _ = edge_table(F)
    return len(used) - len(e) + len(F)


def component_labels(n, edges):
    """Connected-component label of each of n nodes under ``edges`` (min-label
    propagation; iterations scale with the diameter, fine for test meshes)."""
    label = np.arange(n)
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    if len(edges) == 0:
        return label
    while True:
        m = np.minimum(label[edges[:, 0]], label[edges[:, 1]])
        new = label.copy()
        np.minimum.at(new, edges[:, 0], m)
        np.minimum.at(new, edges[:, 1], m)
        new = new[new]  # pointer jumping
        if np.array_equal(new, label):
            return label
        label = new


def count_components(n, edges, nodes=None):
    """Number of connected components among ``nodes`` (default: nodes touched by edges)."""
    label = component_labels(n, edges)
    if nodes is None:
        nodes = np.unique(np.asarray(edges).ravel())
    return len(np.unique(label[nodes]))


def boundary_loops(F):
    """Number of boundary loops (components of the boundary-edge graph)."""
    b = boundary_edges(F)
    if len(b) == 0:
        return 0
    return count_components(int(F.max()) + 1, b)


def face_normals(V, F):
    return np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])


def uv_signed_area(UV):
    """Twice the signed area of each UV triangle (m, 3, 2)."""
    d1 = UV[:, 1] - UV[:, 0]
    d2 = UV[:, 2] - UV[:, 0]
    return d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]


def _uv_changes_by_end(F, UV, tol):
    """The interior edges, (s, 2) sorted vertex pairs (lo, hi), and per edge whether its
    two faces' UVs differ at lo and at hi, (s,) bool each.

    For each directed half-edge (a -> b) of a face, the UVs at a and b in that face,
    sorted so that the two half-edges of an interior edge lie side by side."""
    he = directed_edges(F)
    uv_a = np.concatenate([UV[:, 0], UV[:, 1], UV[:, 2]])
    uv_b = np.concatenate([UV[:, 1], UV[:, 2], UV[:, 0]])
    lo_first = he[:, 0] < he[:, 1]
    key = np.sort(he, axis=1)
    uv_lo = np.where(lo_first[:, None], uv_a, uv_b)
    uv_hi = np.where(lo_first[:, None], uv_b, uv_a)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, uv_lo, uv_hi = key[order], uv_lo[order], uv_hi[order]
    pair = np.flatnonzero(np.all(key[1:] == key[:-1], axis=1))  # half-edges (pair, pair + 1)
    at_lo = np.abs(uv_lo[pair] - uv_lo[pair + 1]).max(1) > tol
    at_hi = np.abs(uv_hi[pair] - uv_hi[pair + 1]).max(1) > tol
    return key[pair], at_lo, at_hi


def seam_edges(F, UV, tol=0.0):
    """Interior edges across which the corner UVs differ: (s, 2) sorted vertex pairs; an
    interior edge is a seam when its two faces disagree at either end."""
    edges, at_lo, at_hi = _uv_changes_by_end(F, UV, tol)
    return edges[at_lo | at_hi]


def uv_change_counts(F, UV, n=None, tol=0.0):
    """(n,) for each vertex, the interior edges at it across which its own corner UV
    differs between the edge's two faces: 0 where the vertex has one UV (also at the end
    of a seam edge whose UVs differ only at the other end: a cut's tip, the ring around a
    pole whose triangles each have their own UV), 2 along a seam, else an end or a
    junction of seams."""
    n = int(F.max()) + 1 if n is None else n
    edges, at_lo, at_hi = _uv_changes_by_end(F, UV, tol)
    return np.bincount(np.r_[edges[at_lo, 0], edges[at_hi, 1]], minlength=n)


def uv_islands(F, UV):
    """Island label (0..k-1) of each face: faces joined across edges that are not seams."""
    he = directed_edges(F)
    m = len(F)
    face_of = np.tile(np.arange(m), 3)
    key = np.sort(he, axis=1)
    seams = seam_edges(F, UV)
    n = int(F.max()) + 1
    seam_keys = seams[:, 0] * n + seams[:, 1]
    k = key[:, 0] * n + key[:, 1]
    order = np.argsort(k, kind="stable")
    ks, fs = k[order], face_of[order]
    pair = np.flatnonzero(ks[1:] == ks[:-1])
    not_seam = ~np.isin(ks[pair], seam_keys)
    links = np.c_[fs[pair[not_seam]], fs[pair[not_seam] + 1]]
    return np.unique(component_labels(m, links), return_inverse=True)[1].reshape(-1)


def point_segment_distance(P, A, B):
    """(p, s) distances from points P (p, 3) to segments A-B (s, 3)."""
    d = B - A
    dd = np.einsum("ij,ij->i", d, d)
    t = np.einsum("psk,sk->ps", P[:, None, :] - A[None, :, :], d) / np.where(dd > 0, dd, 1.0)
    t = np.clip(t, 0.0, 1.0)
    closest = A[None] + t[..., None] * d[None]
    return np.linalg.norm(P[:, None, :] - closest, axis=2)


def distance_to_polyline(P, V, edges):
    """Distance from each point to the nearest of the segments V[edges]."""
    if len(P) == 0:
        return np.zeros(0)
    return point_segment_distance(P, V[edges[:, 0]], V[edges[:, 1]]).min(axis=1)


def max_sagitta(v, f, radius=1.0) -> float:
    """Largest depth below the sphere of a face's circumcentre: R - sqrt(R^2 - rho^2)."""
    a = np.linalg.norm(v[f[:, 1]] - v[f[:, 2]], axis=1)
    b = np.linalg.norm(v[f[:, 2]] - v[f[:, 0]], axis=1)
    c = np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1)
    area = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)
    rho = a * b * c / (4.0 * area)
    return float((radius - np.sqrt(radius ** 2 - rho ** 2)).max())


def material_border_edges(F, material):
    """Edges between two faces of different material: (k, 2) sorted vertex pairs."""
    he = directed_edges(F)
    face = np.tile(np.arange(len(F)), 3)
    key = np.sort(he, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, face = key[order], face[order]
    pair = np.flatnonzero(np.all(key[1:] == key[:-1], axis=1))
    differ = material[face[pair]] != material[face[pair + 1]]
    return key[pair[differ]]


def seam_branches(n, seams):
    """Split a seam graph into branches: chains between its special vertices (ends and
    junctions, degree != 2). Returns (vertex, branch) incidence pairs, one per branch a
    vertex lies on (junctions and ends lie on several)."""
    deg = np.bincount(seams.ravel(), minlength=n)
    plain = deg == 2
    inner = seams[plain[seams[:, 0]] & plain[seams[:, 1]]]
    comp = component_labels(n, inner)
    a, b = seams[:, 0], seams[:, 1]
    label = np.where(plain[a], comp[a], np.where(plain[b], comp[b], n + np.arange(len(seams))))
    pairs = np.unique(np.c_[np.r_[a, b], np.r_[label, label]], axis=0)
    return pairs[:, 0], pairs[:, 1]


def edges_along_branches(edges, inc_vertex, inc_branch):
    """(k,) bool: whether both ends of each edge (in input vertex numbers) lie on one
    common seam branch, i.e. the edge follows a single input seam polyline."""
    big = np.int64(inc_branch.max() + 1) if len(inc_branch) else np.int64(1)
    keys = inc_vertex * big + inc_branch
    order = np.argsort(inc_vertex, kind="stable")
    sv, sb = inc_vertex[order], inc_branch[order]
    start = np.searchsorted(sv, edges[:, 0], side="left")
    stop = np.searchsorted(sv, edges[:, 0], side="right")
    count = stop - start
    owner = np.repeat(np.arange(len(edges)), count)
    rows = np.repeat(start, count) + (np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count))
    hit = np.isin(edges[owner, 1] * big + sb[rows], keys)
    return np.bincount(owner[hit], minlength=len(edges)) > 0


# ---------------------------------------------------------------- result checks


def assert_valid_mesh(V, F, manifold=True):
    """Structural checks of a triangle mesh (V (n, 3), F (m, 3)) any simplifier must pass.

    manifold: the input was manifold, so the output must be too (each undirected edge on
    at most two faces, each directed edge at most once: consistently oriented).
    """
    assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == 3
    assert np.issubdtype(F.dtype, np.integer) and F.ndim == 2 and F.shape[1] == 3
    assert np.isfinite(V).all()
    if len(F):
        assert F.min() >= 0 and F.max() < len(V), "face index out of range"
    # Every output vertex is used (isolated ones are dropped, removed ones compacted away).
    assert np.array_equal(np.unique(F), np.arange(len(V))), "unreferenced output vertices"
    assert np.all((F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])), "degenerate face"
    assert len(np.unique(np.sort(F, axis=1), axis=0)) == len(F), "duplicate faces"
    if manifold and len(F):
        _, count = edge_table(F)
        assert count.max() <= 2, "non-manifold edge created"
        _, dcount = np.unique(directed_edges(F), axis=0, return_counts=True)
        assert dcount.max() == 1, "inconsistent orientation (a directed edge used twice)"


def assert_valid_result(r, V_in, F_in, manifold=True, split=False):
    """assert_valid_mesh on a simplify result, plus its origins and stats.

    split: the input had T-junction cracks that core.stitching closes by splitting faces,
    so several output faces may descend from one input face."""
    V, F = r.vertices, r.faces
    assert_valid_mesh(V, F, manifold)
    fo, vo = np.asarray(r.face_origin), np.asarray(r.vertex_origin)
    assert fo.shape == (len(F),) and vo.shape == (len(V),)
    if len(F):
        assert fo.min() >= 0 and fo.max() < len(F_in), "face_origin out of range"
        # Collapse only relabels and deletes faces: one output face per surviving input face.
        assert split or len(np.unique(fo)) == len(fo), "two output faces claim the same input face"
        assert vo.min() >= 0 and vo.max() < len(V_in)
        assert len(np.unique(vo)) == len(vo), "two output vertices claim the same input vertex"
    s = r.stats
    assert s.output_faces == len(F) and s.output_vertices == len(V)
    assert s.input_faces == len(F_in) and s.input_vertices == len(V_in)


def assert_target_respected(r, target):
    """Within 1 of the target when the stats say it was reached; above it otherwise."""
    m = len(r.faces)
    if r.stats.stop_reason == "target_reached":
        assert target - 1 <= m <= target, (m, target)
    else:
        assert r.stats.stop_reason in ("topology_limit", "max_error_reached")
        assert m > target, (m, target, r.stats.stop_reason)
