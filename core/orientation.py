"""Consistent winding: which faces to turn over so that every part is oriented one way.

Exporters often write parts of a surface wound the other way (a UV sphere's pole caps, a
CAD face whose loop was reversed). Across such an edge both faces run the edge in the
same direction, so the half-edge structure sees two fans where there is one surface: its
vertices count as pinched (core.topology.fans_per_vertex) and are locked, and the normal
rules (no_turn_over) compare faces that point opposite ways. A 360-triangle sphere with
flipped caps then stopped at 44 triangles for a target of 36.

The repair is the classic one (MeshLab's "re-orient coherently", Blender's Recalculate
Normals without the outside test): across every edge with exactly two faces, the faces
must agree, so the wanted flip bits satisfy x_f xor x_g = s_fg, where s_fg is 1 when the
two faces run the edge the same way. That is a two-colouring of the face graph with
signed edges, found here in bulk by union-find with parity (hook and compress, as
core.topology.connected_labels, with each node carrying its parity to its root). Each
part then keeps the winding of most of its area and the rest is turned over. A part that
cannot be oriented (a Moebius strip, a Klein bottle) keeps the edges that disagree.

The engine works on the repaired faces; core.engine._snapshot turns the faces that were
turned over back, so every LOD face keeps the winding its source face had.
"""
from __future__ import annotations

import numpy as np

from . import topology
from .geometry import face_frames


def faces_to_flip(vertices: np.ndarray, faces: np.ndarray, conn=None) -> np.ndarray:
    """(m,) bool: the faces to turn over so that each part is consistently wound.

    vertices (n, 3), faces (m, 3) int. Only edges with exactly two faces join faces
    (a non-manifold edge says nothing about which side is out). Of the two windings of a
    part, the one covering more of its area wins. conn: ``topology.build(faces, n)`` if
    the caller has it."""
    m = len(faces)
    if m == 0:
        return np.zeros(0, dtype=bool)
    if conn is None:
        conn = topology.build(faces, len(vertices))
    inner = np.flatnonzero(conn.edge_faces == 2)
    he0, he1 = conn.edge_he0[inner], conn.edge_he1[inner]
    starts = faces.ravel()
    disagree = starts[he0] == starts[he1]  # both half-edges start at the same vertex
    if not disagree.any():
        return np.zeros(m, dtype=bool)
    root, parity = parity_labels(m, he0 // 3, he1 // 3, disagree)
    _, area = face_frames(vertices, faces)
    # Area of each part wound like its root (parity 0) and the other way.
    area_flipped = np.bincount(root, weights=area * parity, minlength=m)
    area_total = np.bincount(root, weights=area, minlength=m)
    root_flips = area_flipped > 0.5 * area_total  # then the root's own winding is the minority
    return parity.astype(bool) != root_flips[root]


def parity_labels(n_nodes: int, a: np.ndarray, b: np.ndarray, differ: np.ndarray) -> tuple:
    """Components of the graph a[i]-b[i] with, for every node, its parity to its root.

    differ (k,) bool: edge i asks x[a] != x[b] (else x[a] == x[b]). Returns (root, parity):
    (n_nodes,) int64 the smallest node of each component, (n_nodes,) int8 the bit x of
    each node with x[root] = 0, satisfying every edge of a spanning forest (edges closing
    an odd cycle, where no bits satisfy all, are the ones left unsatisfied).

    Each round every root with an edge to a smaller root hooks onto the smallest of them,
    with the parity that edge implies; then nodes jump to their roots, composing parities
    on the way. Rounds grow like log(n) on meshes rather than like their diameter.
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    s = np.asarray(differ, dtype=np.int8)
    label = np.arange(n_nodes, dtype=np.int64)
    parity = np.zeros(n_nodes, dtype=np.int8)
    while len(a):
        la, lb = label[a], label[b]
        apart = la != lb
        if not apart.any():
            break
        a, b, s, la, lb = a[apart], b[apart], s[apart], la[apart], lb[apart]
        # x[la] ^ x[lb] = s ^ parity[a] ^ parity[b]: the roots' relative parity.
        relative = s ^ parity[a] ^ parity[b]
        high, low = np.maximum(la, lb), np.minimum(la, lb)
        # Each high root hooks onto its smallest low root, once.
        order = np.lexsort((low, high))
        first = np.concatenate([[True], high[order][1:] != high[order][:-1]])
        pick = order[first]
        parent = np.arange(n_nodes, dtype=np.int64)
        to_parent = np.zeros(n_nodes, dtype=np.int8)
        parent[high[pick]] = low[pick]
        to_parent[high[pick]] = relative[pick]
        # Pointer jumping: every hooked root to its new root, parities composed.
        while True:
            grand = parent[parent]
            if np.array_equal(grand, parent):
                break
            to_parent = to_parent ^ to_parent[parent]
            parent = grand
        parity = parity ^ to_parent[label]
        label = parent[label]
    return label, parity
