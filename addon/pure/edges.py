# SPDX-License-Identifier: GPL-3.0-or-later
"""Edge bookkeeping for triangle meshes in plain NumPy (no bpy).

The add-on needs edges in three places: feature edges handed to the core (material
borders found between triangles), and the sharp edges and seams written onto a LOD,
which are found between output triangles and then matched against the edges Blender
built for the new mesh. All of it is sorting integer keys, so it lives here, testable
without Blender.
"""
from __future__ import annotations

import numpy as np

from ._core import core


def edge_keys(pairs: np.ndarray, n_vertices: int) -> np.ndarray:
    """One int64 per undirected edge: min * n + max (same key for (a, b) and (b, a))."""
    p = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    lo = p.min(axis=1)
    hi = p.max(axis=1)
    return lo * np.int64(max(n_vertices, 1)) + hi


def adjacent_triangle_pairs(faces: np.ndarray):
    """Pairs of triangles sharing an edge.

    Returns (edges (k, 2) vertex pairs, face_a (k,), face_b (k,)). A manifold interior
    edge gives one pair; an edge shared by t > 2 triangles gives t - 1 consecutive pairs
    (enough to detect any difference between the triangles around it); open boundary
    edges give none.
    """
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    m = len(f)
    if m == 0:
        empty = np.empty(0, dtype=np.int64)
        return np.empty((0, 2), dtype=np.int64), empty, empty
    a = f.ravel()
    b = f[:, [1, 2, 0]].ravel()
    face = np.repeat(np.arange(m, dtype=np.int64), 3)
    n = int(f.max()) + 1
    keys = edge_keys(np.stack([a, b], axis=1), n)
    order = np.argsort(keys, kind="stable")
    ks = keys[order]
    same = np.flatnonzero(ks[1:] == ks[:-1])
    first, second = order[same], order[same + 1]
    edges = np.stack([a[first], b[first]], axis=1)
    return edges, face[first], face[second]


def differing_edges(faces: np.ndarray, face_values: np.ndarray) -> np.ndarray:
    """Edges between two triangles whose ``face_values`` differ (material borders,
    smoothing-group borders), (k, 2) vertex pairs, each edge once."""
    edges, fa, fb = adjacent_triangle_pairs(faces)
    vals = np.asarray(face_values)
    return unique_edges(edges[vals[fa] != vals[fb]])


def corner_discontinuous_edges(faces: np.ndarray, corner_values: np.ndarray, tol: float = 1e-6) -> np.ndarray:
    """Edges across which a per-corner attribute jumps (UV seams), (k, 2) vertex pairs.

    corner_values: (m, 3, c), indexed like ``faces``. An edge is discontinuous when, at
    either of its two vertices, the values in the two triangles differ by more than tol.
    """
    edges, jump = _corner_jumps(faces, corner_values, tol)
    return unique_edges(edges[jump])


def welded_faces(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """``faces`` (m, 3) with each vertex replaced by the first vertex at its exact position,
    as the core welds before simplifying (core.weld.weld_map): an exported mesh is split
    into copies along its UV seams and hard edges, so its triangles there are neighbours,
    and its attributes' jumps between them seen, only once welded."""
    rep = core.weld.weld_map(np.asarray(vertices, dtype=np.float64), None)
    return rep[np.asarray(faces, dtype=np.int64)]


def faceted(faces: np.ndarray, corner_values: np.ndarray, tol: float = 1e-6) -> bool:
    """Whether a per-corner attribute jumps across more than half of the triangle pairs
    of ``faces``: a value per face (a colour per facet, as low-poly exports paint them),
    whose every vertex would be a seam junction, rather than regions with seams between."""
    edges, jump = _corner_jumps(faces, corner_values, tol)
    return len(edges) > 0 and len(unique_edges(edges[jump])) > 0.5 * len(edges)


def _corner_jumps(faces, corner_values, tol) -> tuple:
    """(the triangle pairs' shared edges (k, 2), whether the values jump across each (k,))."""
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    cv = np.asarray(corner_values, dtype=np.float64)
    cv = cv.reshape(len(f), 3, -1)
    edges, fa, fb = adjacent_triangle_pairs(f)
    jump = np.zeros(len(edges), dtype=bool)
    if len(edges) == 0:
        return edges, jump

    def corner_of(face_idx, vert):
        # Local corner (0..2) at which ``vert`` sits in each triangle of ``face_idx``.
        return np.argmax(f[face_idx] == vert[:, None], axis=1)

    for end in (0, 1):
        v = edges[:, end]
        va = cv[fa, corner_of(fa, v)]
        vb = cv[fb, corner_of(fb, v)]
        jump |= np.abs(va - vb).max(axis=1) > tol
    return edges, jump


def edge_index(mesh_edges: np.ndarray, pairs: np.ndarray, n_vertices: int) -> np.ndarray:
    """(E,) for each edge of ``mesh_edges`` (E, 2), the row of ``pairs`` (k, 2) that is the
    same undirected edge (the last such row), or -1."""
    me = np.asarray(mesh_edges, dtype=np.int64).reshape(-1, 2)
    if len(me) == 0 or len(pairs) == 0:
        return np.full(len(me), -1, dtype=np.int64)
    keys = edge_keys(pairs, n_vertices)
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]
    wanted = edge_keys(me, n_vertices)
    at = np.minimum(np.searchsorted(sorted_keys, wanted, side="right") - 1, len(keys) - 1)
    hit = (at >= 0) & (sorted_keys[np.maximum(at, 0)] == wanted)
    return np.where(hit, order[np.maximum(at, 0)], -1)


def unique_edges(pairs: np.ndarray) -> np.ndarray:
    """Undirected edges, each once, as (min, max) rows sorted by key."""
    p = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    if len(p) == 0:
        return p
    p = np.sort(p, axis=1)
    return np.unique(p, axis=0)


def merge_weighted_edges(groups) -> tuple:
    """Union of several edge sets, each with one weight: an edge in several sets keeps
    its largest weight. groups: iterable of ((k, 2) pairs, weight). Returns (edges, weights)."""
    pairs, weights = [], []
    for edges, weight in groups:
        e = unique_edges(edges)
        if len(e):
            pairs.append(e)
            weights.append(np.full(len(e), float(weight)))
    if not pairs:
        return np.empty((0, 2), dtype=np.int64), np.empty(0)
    p = np.concatenate(pairs)
    w = np.concatenate(weights)
    n = int(p.max()) + 1
    keys = edge_keys(p, n)
    # Sort by key, then by descending weight, and keep the first of each key.
    order = np.lexsort((-w, keys))
    keys, p, w = keys[order], p[order], w[order]
    keep = np.ones(len(keys), dtype=bool)
    keep[1:] = keys[1:] != keys[:-1]
    return p[keep], w[keep]


def face_regions(faces: np.ndarray, cut_edges: np.ndarray) -> np.ndarray:
    """Connected regions of triangles that meet across edges not in ``cut_edges``.

    Returns (m,) int64 labels (the smallest triangle index of each region). Used for
    seam islands: regions bounded by the artist's seams.
    """
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    m = len(f)
    if m == 0:
        return np.arange(0, dtype=np.int64)
    edges, fa, fb = adjacent_triangle_pairs(f)
    n = int(f.max()) + 1
    cut = np.asarray(cut_edges, dtype=np.int64).reshape(-1, 2)
    if len(cut):
        keep = ~np.isin(edge_keys(edges, n), edge_keys(cut, n))
        fa, fb = fa[keep], fb[keep]
    return core.topology.connected_labels(m, fa, fb)


def chains_through(edges: np.ndarray, kept: np.ndarray, with_edges: bool = False):
    """Where chains of ``edges`` (k, 2) run between ``kept`` vertices ((n,) bool) through
    vertices that are gone: (j, 2) pairs of kept vertices, each pair once; with
    ``with_edges`` also (j,) the index into ``edges`` of a chain's first edge.

    A LOD keeps a source's sharp edge chain as an edge between two of its surviving
    vertices after the ones between them collapsed; following each chain from a kept
    vertex through the removed ones (of two chain edges each: a removed junction or end
    ends the chain) finds the kept vertex at its other end. Pointer doubling over the
    directed edges, so no loop runs per edge."""
    e = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    if len(e) == 0:
        return (e, np.empty(0, dtype=np.int64)) if with_edges else e
    kept = np.asarray(kept, dtype=bool)
    tail, head = np.concatenate([e[:, 0], e[:, 1]]), np.concatenate([e[:, 1], e[:, 0]])
    h = len(tail)
    degree = np.bincount(e.ravel(), minlength=len(kept))
    through = ~kept[head] & (degree[head] == 2)  # the chain goes on past the head
    # The two directed edges leaving each vertex, by tail: next(u->v) = v->w with w != u.
    order = np.argsort(tail, kind="stable")
    start = np.searchsorted(tail[order], head)
    first = order[np.minimum(start, h - 1)]
    second = order[np.minimum(start + 1, h - 1)]
    nxt = np.where(head[first] != tail, first, second)
    ptr = np.where(through, nxt, np.arange(h))
    for _ in range(int(np.ceil(np.log2(h))) + 1):
        ptr = ptr[ptr]
    end = head[ptr]
    ok = kept[tail] & kept[end] & ~through[ptr] & (end != tail)
    if not with_edges:
        return unique_edges(np.stack([tail[ok], end[ok]], axis=1))
    pairs = np.sort(np.stack([tail[ok], end[ok]], axis=1), axis=1)
    pairs, first = np.unique(pairs, axis=0, return_index=True)
    return pairs, np.flatnonzero(ok)[first] % len(e)


def mark_edges(mesh_edges: np.ndarray, wanted: np.ndarray, n_vertices: int) -> np.ndarray:
    """Boolean mask over ``mesh_edges`` (E, 2): True where the edge is in ``wanted``."""
    return edge_index(mesh_edges, np.asarray(wanted, dtype=np.int64).reshape(-1, 2), n_vertices) >= 0
