"""Connectivity of a triangle soup, rebuilt in bulk once per pass.

Edges are found by sorting half-edge keys (lo * n + hi) rather than by walking a
half-edge structure: sorting is one vectorised call, and a pass changes too much of the
mesh for incremental bookkeeping in Python to pay off.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Connectivity:
    """Edges and incidences of the live faces.

    edges: (k, 2) int64 with edges[:, 0] < edges[:, 1]; edge_faces: (k,) number of faces
    on each edge (1 boundary, 2 interior, more non-manifold); half_edge_order: the
    half-edges sorted by edge key, which the next pass reuses as a nearly sorted
    starting order.
    """

    edges: np.ndarray
    edge_keys: np.ndarray
    edge_faces: np.ndarray
    edge_he0: np.ndarray  # a half-edge (flat corner index f*3+s) of each edge
    edge_he1: np.ndarray  # the other half-edge of an interior edge, else -1
    half_edge_order: np.ndarray
    border_vertex: np.ndarray  # (n,) bool: on an edge with a single face

    @property
    def edge_face0(self) -> np.ndarray:
        """(k,) a face on each edge."""
        return self.edge_he0 // 3

    @property
    def edge_face1(self) -> np.ndarray:
        """(k,) the other face of an interior edge, else -1."""
        return np.where(self.edge_he1 >= 0, self.edge_he1 // 3, -1)


def build(faces: np.ndarray, n_vertices: int, order_hint=None) -> Connectivity:
    """Connectivity of ``faces``. order_hint: a permutation of the half-edges that is
    already nearly sorted by edge key (the previous pass's order carried over): a stable
    sort finishes it several times faster than sorting from scratch."""
    a = faces.ravel()
    b = np.roll(a, -1)  # the corner each half-edge ends at: the next, or the face's first
    b[2::3] = a[0::3]
    lo = np.minimum(a, b)
    hi = np.maximum(a, b)
    keys = lo * np.int64(n_vertices) + hi
    if order_hint is None:
        order = np.argsort(keys)
    else:
        order = order_hint[np.argsort(keys[order_hint], kind="stable")]
    sorted_keys = keys[order]
    new_group = np.empty(len(sorted_keys), dtype=bool)
    new_group[:1] = True
    np.not_equal(sorted_keys[1:], sorted_keys[:-1], out=new_group[1:])
    group_start = np.flatnonzero(new_group)
    edge_faces = np.diff(np.append(group_start, len(sorted_keys)))
    edge_keys = sorted_keys[group_start]

    first_he = order[group_start]
    edges = np.empty((len(group_start), 2), dtype=np.int64)
    np.take(lo, first_he, out=edges[:, 0])
    np.take(hi, first_he, out=edges[:, 1])
    # The second half-edge of a group, where there is one (interior or non-manifold edge).
    after_first = order.take(np.minimum(group_start + 1, len(order) - 1)) if len(order) else order
    second_he = np.where(edge_faces >= 2, after_first, -1)
    border_vertex = np.zeros(n_vertices, dtype=bool)
    border_vertex[np.compress(edge_faces == 1, edges, axis=0).ravel()] = True

    return Connectivity(
        edges=edges,
        edge_keys=edge_keys,
        edge_faces=edge_faces,
        edge_he0=first_he,
        edge_he1=second_he,
        half_edge_order=order,
        border_vertex=border_vertex,
    )


def carry_order(order: np.ndarray, alive_half_edges: np.ndarray) -> np.ndarray:
    """The half-edge order of the previous pass, renumbered after dead faces are dropped
    (alive_half_edges: (3m,) bool, each face's flag repeated for its three corners)."""
    new_index = np.cumsum(alive_half_edges) - 1
    kept = order.compress(alive_half_edges[order])
    return new_index[kept]


def set_on_half_edges(per_half_edge: np.ndarray, conn: Connectivity, edges: np.ndarray, values) -> None:
    """per_half_edge[h] = value for both half-edges h of each of ``edges`` (k,).

    Per-half-edge memory outlives the pass: a face's slots keep their order when faces
    are relabelled and compacted, so an edge whose ends did not change is found again
    under the same half-edges (compressed with the surviving faces), without a search."""
    values = np.broadcast_to(values, edges.shape)
    per_half_edge[conn.edge_he0[edges]] = values
    second = conn.edge_he1[edges]
    has_second = second >= 0
    per_half_edge[second[has_second]] = values[has_second]


def any_corner(flags: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(m,) whether any corner of each face has a set per-vertex flag. Three gathers and
    two ors: reductions along a length-3 axis are several times slower in NumPy."""
    return flags[faces[:, 0]] | flags[faces[:, 1]] | flags[faces[:, 2]]


def next_corner(corner: np.ndarray) -> np.ndarray:
    """The corner after ``corner`` (flat f*3+s) in its face: where its half-edge ends."""
    return corner - corner % 3 + (corner % 3 + 1) % 3


def gather_vertex_corners(faces: np.ndarray, vertices: np.ndarray, n_vertices: int) -> tuple:
    """All corners of each of ``vertices`` (k,), distinct. Returns (owner (c,), corners (c,)):
    owner[i] is the position in ``vertices`` whose corner corners[i] is (flat f*3+s).
    One scan over all corners: cheaper than keeping a vertex-to-corner index up to date."""
    owner_of = np.full(n_vertices, -1, dtype=np.int32)  # int32: half the bytes to scan
    owner_of[vertices] = np.arange(len(vertices), dtype=np.int32)
    per_corner = owner_of[faces.ravel()]
    corners = np.flatnonzero(per_corner >= 0)
    return per_corner[corners].astype(np.int64), corners


def connected_labels(n_nodes: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Connected components of the graph with edges a[i]-b[i] over nodes 0..n_nodes-1.

    Returns (n_nodes,) int64: the smallest node of each node's component. Hook and
    compress: each round every root hooks onto the smallest root across an edge, then
    labels jump to their roots, so rounds grow like log(n) on meshes rather than like
    their diameter; all in bulk.
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    label = np.arange(n_nodes, dtype=np.int64)
    while len(a):
        la, lb = label[a], label[b]
        low = np.minimum(la, lb)
        new = label.copy()
        np.minimum.at(new, la, low)
        np.minimum.at(new, lb, low)
        while True:
            jumped = new[new]
            if np.array_equal(jumped, new):
                break
            new = jumped
        if np.array_equal(new, label):
            break
        label = new
    return label
