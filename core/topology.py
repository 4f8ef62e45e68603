"""Connectivity of a triangle soup: built once by sorting, then carried through each
pass of collapses.

Edges are found by sorting half-edge keys (lo * n + hi) rather than by walking a
half-edge structure: sorting is one vectorised call. After a pass the connectivity is
updated, not rebuilt: a collapse only relabels the removed vertex's edges and merges the
two edges of each face that dies, and those faces say exactly which edges they are.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Connectivity:
    """Edges and incidences of the live faces.

    edges: (k, 2) int64 with edges[:, 0] < edges[:, 1] (column-major: the passes read
    the two ends as separate columns); edge_faces: (k,) number of faces on each edge
    (1 boundary, 2 interior, more non-manifold); edge_he0/edge_he1: half-edges (flat
    corner index f*3+s) on each edge, the second -1 on a boundary (a non-manifold edge
    lists two of its half-edges); he_edge: (3m,) the edge of every half-edge.
    edge_keys: the sorted keys lo * n + hi, from ``build`` only (None once updated:
    edges then keep their slots, not their key order).
    """

    edges: np.ndarray
    edge_faces: np.ndarray
    edge_he0: np.ndarray
    edge_he1: np.ndarray
    he_edge: np.ndarray
    border_vertex: np.ndarray  # (n,) bool: on an edge with a single face
    edge_keys: np.ndarray = None

    @property
    def edge_face0(self) -> np.ndarray:
        """(k,) a face on each edge."""
        return self.edge_he0 // 3

    @property
    def edge_face1(self) -> np.ndarray:
        """(k,) the other face of an interior edge, else -1."""
        return np.where(self.edge_he1 >= 0, self.edge_he1 // 3, -1)


def build(faces: np.ndarray, n_vertices: int) -> Connectivity:
    """Connectivity of ``faces`` (m, 3), from scratch."""
    a = faces.ravel()
    b = np.roll(a, -1)  # the corner each half-edge ends at: the next, or the face's first
    b[2::3] = a[0::3]
    lo = np.minimum(a, b)
    hi = np.maximum(a, b)
    keys = lo * np.int64(n_vertices) + hi
    order = np.argsort(keys)
    sorted_keys = keys[order]
    new_group = np.empty(len(sorted_keys), dtype=bool)
    new_group[:1] = True
    np.not_equal(sorted_keys[1:], sorted_keys[:-1], out=new_group[1:])
    group_start = np.flatnonzero(new_group)
    edge_faces = np.diff(np.append(group_start, len(sorted_keys)))
    he_edge = np.empty(len(order), dtype=np.int64)
    he_edge[order] = np.cumsum(new_group) - 1

    first_he = order[group_start]
    # The second half-edge of a group, where there is one (interior or non-manifold edge).
    after_first = order.take(np.minimum(group_start + 1, len(order) - 1)) if len(order) else order
    second_he = np.where(edge_faces >= 2, after_first, -1)
    return _connectivity(lo.take(first_he), hi.take(first_he), edge_faces, first_he, second_he, he_edge,
                         n_vertices, sorted_keys[group_start])


def after_collapses(conn: Connectivity, alive: np.ndarray, remap: np.ndarray, removed: np.ndarray) -> tuple:
    """The connectivity after a pass of independent collapses, and which old edges live on.

    alive: (m,) bool, the faces that survive (the others died with a collapsed edge);
    remap: (n,) vertex relabelling (each removed vertex to its kept one, others to
    themselves); removed: the removed vertices. Returns (connectivity of the surviving
    faces, numbered as they will be after compaction; (k,) bool over the old edges, those
    that keep a slot), or None if the collapses were not independent. A dying face (keep,
    remove, x) takes the collapsed edge with it and merges (remove, x) into (keep, x),
    which keeps its slot; every other edge at most has an end relabelled. Per-edge memory
    compressed by the returned mask follows the edges, merged ones included.
    """
    n = len(remap)
    a, b = remap[conn.edges[:, 0]], remap[conn.edges[:, 1]]
    collapsed = a == b
    merging = _merging_edges(conn, alive, collapsed, removed, n)
    if merging is None:
        return None
    gone, kept = merging
    alive_he = np.repeat(alive, 3)
    merged_he0, merged_he1 = _merged_half_edges(conn, gone, kept, alive_he)
    merged_faces = conn.edge_faces[kept] + conn.edge_faces[gone] - 2  # each loses its dying face
    stays = merged_faces > 0  # a lone triangle's last edges leave with it

    survive = ~collapsed
    survive[gone] = False
    survive[kept[~stays]] = False
    new_edge = np.cumsum(survive) - 1
    he0, he1 = conn.edge_he0.compress(survive), conn.edge_he1.compress(survive)
    edge_faces = conn.edge_faces.compress(survive)
    at = new_edge[kept[stays]]
    he0[at], he1[at], edge_faces[at] = merged_he0[stays], merged_he1[stays], merged_faces[stays]
    new_edge[gone] = new_edge[kept]  # a gone edge's half-edges now belong to its merge
    new_he = np.cumsum(alive_he) - 1
    he0 = new_he[he0]
    he1 = np.where(he1 >= 0, new_he[he1], -1)
    he_edge = new_edge[conn.he_edge.compress(alive_he)]
    # A non-manifold edge lists two of its half-edges only: where one merged, take them
    # from the full per-half-edge map (rare: such vertices are locked).
    was_non_manifold = (conn.edge_faces[kept] > 2) | (conn.edge_faces[gone] > 2)
    if was_non_manifold.any():
        _relist(new_edge[kept[was_non_manifold]], he_edge, he0, he1)
    lo, hi = np.minimum(a, b).compress(survive), np.maximum(a, b).compress(survive)
    return _connectivity(lo, hi, edge_faces, he0, he1, he_edge, n), survive


def _merging_edges(conn, alive, collapsed, removed, n):
    """(gone, kept): for every dying face, its edge to the removed vertex and its edge to
    the kept one, which the first merges into; None unless every dying face lies on
    exactly one collapsed edge and no edge takes two merges."""
    is_removed = np.zeros(n, dtype=bool)
    is_removed[removed] = True
    dying = np.flatnonzero(~alive)
    edge_of = conn.he_edge[(3 * dying[:, None] + np.arange(3)).ravel()].reshape(-1, 3)
    to_removed = is_removed[conn.edges[:, 0][edge_of]] | is_removed[conn.edges[:, 1][edge_of]]
    gone_side = to_removed & ~collapsed[edge_of]
    kept_side = ~to_removed
    gone, kept = edge_of[gone_side], edge_of[kept_side]
    if not (len(gone) == len(kept) == len(dying) and np.all(gone_side.any(axis=1))
            and np.all(kept_side.any(axis=1)) and len(np.unique(kept)) == len(kept)):
        return None
    return gone, kept


def _merged_half_edges(conn, gone, kept, alive_he):
    """(he0, he1) of each kept edge after its merge: the live half-edge of itself and of
    the edge merging into it (one each, on manifold edges), the second -1 if none."""
    def live(h):
        return np.where((h >= 0) & alive_he[h], h, -1)

    own = live(conn.edge_he0[kept])
    own = np.where(own >= 0, own, live(conn.edge_he1[kept]))
    joining = live(conn.edge_he0[gone])
    joining = np.where(joining >= 0, joining, live(conn.edge_he1[gone]))
    return np.where(own >= 0, own, joining), np.where(own >= 0, joining, -1)


def _relist(edges, he_edge, he0, he1) -> None:
    """Set he0/he1 of ``edges`` to their first two half-edges in ``he_edge``, in place."""
    half_edges = np.flatnonzero(np.isin(he_edge, edges))
    half_edges = half_edges[np.argsort(he_edge[half_edges], kind="stable")]
    owner = he_edge[half_edges]
    first = np.flatnonzero(np.concatenate([[True], owner[1:] != owner[:-1]]))
    he0[owner[first]] = half_edges[first]
    has_second = (first + 1 < len(owner)) & (owner[np.minimum(first + 1, len(owner) - 1)] == owner[first])
    he1[owner[first]] = np.where(has_second, half_edges[np.minimum(first + 1, len(owner) - 1)], -1)


def _connectivity(lo, hi, edge_faces, he0, he1, he_edge, n_vertices, edge_keys=None) -> Connectivity:
    ends = np.empty((2, len(lo)), dtype=np.int64)
    ends[0], ends[1] = lo, hi
    border = edge_faces == 1
    border_vertex = np.zeros(n_vertices, dtype=bool)
    border_vertex[lo[border]] = True
    border_vertex[hi[border]] = True
    return Connectivity(edges=ends.T, edge_faces=edge_faces, edge_he0=he0, edge_he1=he1, he_edge=he_edge,
                        border_vertex=border_vertex, edge_keys=edge_keys)


def has_triangular_holes(conn: Connectivity) -> bool:
    """Whether some open border runs around a hole of three edges (a, b, c): the
    border edges of a vertex with two of them, whose other ends share a border edge."""
    border = conn.edges[conn.edge_faces == 1]
    if len(border) < 3:
        return False
    ends = border.ravel()
    other = border[:, ::-1].ravel()
    order = np.argsort(ends, kind="stable")
    ends, other = ends[order], other[order]
    first = np.flatnonzero(np.concatenate([[True], ends[1:] != ends[:-1]]))
    count = np.diff(np.append(first, len(ends)))
    pairs = first[count == 2]
    lo = np.minimum(other[pairs], other[pairs + 1])
    hi = np.maximum(other[pairs], other[pairs + 1])
    n = np.int64(len(conn.border_vertex))
    keys = np.minimum(border[:, 0], border[:, 1]) * n + np.maximum(border[:, 0], border[:, 1])
    return bool(np.isin(lo * n + hi, keys).any())


def faces_touching(faces: np.ndarray, vertices: np.ndarray, n_vertices: int) -> np.ndarray:
    """(m,) bool: the faces with a corner among ``vertices``."""
    flags = np.zeros(n_vertices, dtype=bool)
    flags[vertices] = True
    return any_corner(flags, faces)


def any_corner(flags: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(m,) whether any corner of each face has a set per-vertex flag. Three gathers and
    two ors: reductions along a length-3 axis are several times slower in NumPy."""
    return flags[faces[:, 0]] | flags[faces[:, 1]] | flags[faces[:, 2]]


def next_corner(corner: np.ndarray) -> np.ndarray:
    """The corner after ``corner`` (flat f*3+s) in its face: where its half-edge ends."""
    return corner - corner % 3 + (corner % 3 + 1) % 3


def previous_corner(corner: np.ndarray) -> np.ndarray:
    """The corner before ``corner`` (flat f*3+s) in its face: opposite its half-edge."""
    return corner - corner % 3 + (corner % 3 + 2) % 3


def gather_vertex_corners(faces: np.ndarray, vertices: np.ndarray, n_vertices: int, window=None) -> tuple:
    """All corners of each of ``vertices`` (k,), distinct. Returns (owner (c,), corners (c,)):
    owner[i] is the position in ``vertices`` whose corner corners[i] is (flat f*3+s).
    One scan over all corners: cheaper than keeping a vertex-to-corner index up to date.
    window: optional (face ids, their rows of faces) known to hold every face of
    ``vertices``; only those are scanned."""
    owner_of = np.full(n_vertices, -1, dtype=np.int32)  # int32: half the bytes to scan
    owner_of[vertices] = np.arange(len(vertices), dtype=np.int32)
    scanned = faces if window is None else window[1]
    per_corner = owner_of[scanned.ravel()]
    corners = np.flatnonzero(per_corner >= 0)
    owner = per_corner[corners].astype(np.int64)
    if window is not None:
        corners = 3 * window[0][corners // 3] + corners % 3
    return owner, corners


def gather_corners_of_each(faces: np.ndarray, vertices: np.ndarray, n_vertices: int) -> tuple:
    """gather_vertex_corners where a vertex may be listed more than once (collapses that
    are not independent): every listing gets all the vertex's corners. Returns (owner
    (c,), corners (c,)), owner in ascending order, each listing's corners ascending. One
    scan of the faces for the distinct vertices, then their corners grouped by vertex."""
    unique, listing = np.unique(vertices, return_inverse=True)
    unique_owner, unique_corner = gather_vertex_corners(faces, unique, n_vertices)
    by_vertex = np.argsort(unique_owner, kind="stable")
    per_vertex = np.bincount(unique_owner, minlength=len(unique))
    first_of_vertex = np.cumsum(per_vertex) - per_vertex
    count = per_vertex[listing]
    owner = np.repeat(np.arange(len(vertices), dtype=np.int64), count)
    offset = np.arange(len(owner)) - np.repeat(np.cumsum(count) - count, count)
    return owner, unique_corner[by_vertex[np.repeat(first_of_vertex[listing], count) + offset]]


def fans_per_vertex(conn: Connectivity, faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """(n,) the number of fans around each vertex: groups of its faces joined across
    interior edges at the vertex. A manifold vertex has one (zero if unused).

    Counting edges and faces cannot see a vertex pinched between two closed fans (each has
    as many edges as faces), so the fans are found: ``turn`` steps from a corner to the
    same vertex's corner across its outgoing edge, so each closed fan is a cycle of turns
    and each open one a path ending at a border corner (which turns onto itself). After
    k doublings of the step, with 2^k at least the vertex's face count, every corner of a
    cycle knows the cycle's smallest corner and every corner of a path its end: one
    representative per fan. Where orientation disagrees across an edge a fan may split in
    two and its vertex count as pinched, which only locks it.
    """
    flat = faces.ravel()
    # 32-bit corners where they fit: the doubling rounds are random gathers over every
    # corner, and half the bytes take ~40 % off them on a 2M-face mesh.
    index = np.int32 if len(flat) < 2**31 and n_vertices < 2**31 else np.int64
    corner = np.arange(len(flat), dtype=index)
    edge = conn.he_edge
    he0, he1 = conn.edge_he0.astype(index)[edge], conn.edge_he1.astype(index)[edge]
    interior = conn.edge_faces[edge] == 2
    across = np.where(interior, np.where(he0 == corner, he1, he0), corner)
    # Consistently oriented, the half-edge across ends at this vertex; if not, it starts
    # there. (A gather from a table of next corners beats next_corner's modulo here.)
    following = corner.reshape(-1, 3)[:, [1, 2, 0]].ravel()
    vertex = flat.astype(index)
    turn = np.where(vertex[across] == vertex, across, following[across])
    turn[~interior] = corner[~interior]
    faces_at = np.bincount(flat, minlength=n_vertices)
    smallest, reach = corner.copy(), turn
    for _ in range(int(np.ceil(np.log2(max(int(faces_at.max(initial=0)), 2))))):
        np.minimum(smallest, smallest[reach], out=smallest)
        reach = reach[reach]
    on_path = turn[reach] == reach
    representative = np.where(on_path, reach, smallest)
    return np.bincount(flat[representative == corner], minlength=n_vertices)


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
