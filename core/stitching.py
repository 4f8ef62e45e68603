"""Closing T-junction cracks: border vertices that lie on another border's edge split it.

CAD exporters tessellate each face of a solid on its own, so where two faces meet their
shared curve is cut at different points on either side: after welding the coincident
ends, the seam is a slit of zero width, two border chains on one curve (T-junctions).
On the largest part of the 2CylinderEngine sample 86 % of the 2,172 border vertices lie
within 1e-4 of the part's size from a border edge of the other side (median 1.5e-6).
Each chain can then only slide along itself (rule boundaries_stay), the slit's ends are
border corners, and a LOD stops far above its target (1,144 faces for 922) or opens the
slits into holes.

The repair (cf. MeshLab's "snap mismatched borders", Botsch et al., Polygon Mesh
Processing, Sec. 3.4 on gaps and T-junctions): every border vertex within a small
distance of a border edge of its own part (the parts joined by shared vertices, which the
exact weld gives every face of one exported solid) that it is not on, strictly between
the edge's ends, is inserted
into that edge: the edge's face (a, b, c) becomes the fan (a, p1, c), (p1, p2, c), ...,
(pk, b, c) over the points in order along a -> b. With both chains' vertices in both
sides' edges the two sides share every edge and the slit is an ordinary interior seam.
Vertices are not moved: a point of a curved seam sits off the other side's chord by the
chord's sagitta, a fraction of the tolerance. But where that puts it beyond the apex of
the other side's thin face, so that the split would turn a face over, the point moves
onto the edge it goes into (by that sagitta: 1e-5 of the part's size on the engine's
parts), as long as none of its own faces turns (``_snapped``); such splits were undone,
and 268 of the 322 T-junctions they left open on the engine's parts close this way.

The new faces descend from the face they split (engine._snapshot gives them its index);
their corner values are interpolated along the split edge.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import components, grid, topology
from .geometry import edge_parameter, face_frames

# A border vertex joins a border edge when it is this close to it, relative to the
# edge's length (a chord's sagitta is length^2 / 8r: up to 1 % means a curve sampled at
# up to about 9 degrees a segment) ...
RELATIVE_TOLERANCE = 1e-2
# ... and no farther than this, in units of the mesh's bounding-box diagonal: separate
# parts that only come close are left alone.
ABSOLUTE_TOLERANCE = 1e-3
# Inserted points must lie strictly inside the edge (an end is a weld, not a split).
END_MARGIN = 1e-6
# Splitting rounds: a face with several split edges has one split per round.
ROUNDS = 3


def stitch(vertices: np.ndarray, faces: np.ndarray, conn=None, fixed=None):
    """(faces (m', 3), parent (m',), rows (k,), weights (k, 3, 3), connectivity of the new
    faces, vertices (n, 3)) with T-junction cracks closed, or None when nothing is to be
    stitched (the common case). The vertices are ``vertices`` but where a point moved onto
    the edge it went into (_snapped); ``fixed`` (n,) bool: vertices that may not move.

    vertices (n, 3) in normalised units (unit diagonal), faces (m, 3) int64 without
    degenerate or duplicate rows. parent: the row of ``faces`` each output face comes
    from; rows: the output faces made by splits, and weights: where each of their corners
    lies on its parent, as barycentric weights over the parent's corners (for
    interpolating corner values; every other face has its parent's corners). conn:
    ``topology.build(faces, n)`` if the caller has it."""
    n = len(vertices)
    fixed = np.zeros(n, dtype=bool) if fixed is None else np.asarray(fixed, dtype=bool)
    part = components.vertex_labels(faces, n)
    parent = np.arange(len(faces))
    rows, weights = np.zeros(0, dtype=np.int64), np.zeros((0, 3, 3))
    current = faces
    for _ in range(ROUNDS):
        splits = _border_splits(vertices, current, n, part, conn)
        if splits is None:
            break
        before = current
        points = _points_on_edges(vertices, before, *splits)
        current, step_parent, step_rows, step_weights = _split_faces(current, *splits)
        vertices = _snapped(vertices, before, current, step_parent, step_rows, points, fixed)
        current, step_parent, step_rows, step_weights, conn = _undo_bad_splits(
            vertices, before, current, step_parent, step_rows, step_weights, n)
        vertices = _unsnapped(vertices, points, current[step_rows])
        # Composed even when every split of the round was undone: the undone faces come
        # back in another order, and a parent left as it was named the wrong face for
        # most rows (an engine part: 1,753 of 1,932, each judged by another face's
        # normal, quality and corner values for the whole run).
        rows, weights = _composed(len(before), rows, weights, step_parent, step_rows, step_weights)
        parent = parent[step_parent]
        if len(current) == len(before):
            break
    if len(current) == len(faces):
        return None
    return current, parent, rows, weights, conn, vertices


class _Points(NamedTuple):
    """The points a round inserts: vertex ids (k,), the face of ``before`` each goes into
    (k,), its place on that face's edge (k, 3) and where it was (k, 3)."""

    vertex: np.ndarray
    face: np.ndarray
    on_edge: np.ndarray
    was: np.ndarray


def _points_on_edges(V, F, corner, vertex, t) -> _Points:
    """_Points of the splits (corner, vertex, t) _border_splits gives on the faces ``F``."""
    flat = F.ravel()
    a, b = V[flat[corner]], V[flat[topology.next_corner(corner)]]
    return _Points(vertex, corner // 3, a + t[:, None] * (b - a), V[vertex])


def _snapped(V, before, faces, parent, rows, points: _Points, fixed) -> np.ndarray:
    """``V`` with the points of the splits that would turn a face over moved onto the edges
    they go into, each only where none of the faces around it turns (its own side's, as
    ``faces`` has them); a split still turned after that is undone (_undo_bad_splits)."""
    turned_parents, parent_normals = _turned_splits(V, before, faces, parent, rows)
    move = np.isin(points.face, turned_parents) & ~fixed[points.vertex]
    if not move.any():
        return V
    moved = V.copy()
    moved[points.vertex[move]] = points.on_edge[move]
    # Each face as it must keep facing: one not split this round as it did, a split one as
    # the face it was split from did (before anything moved).
    was = face_frames(V, faces)[0]
    was[rows] = parent_normals
    for _ in range(int(move.sum())):
        # (A vertex put back can turn a face another one moved shares: look again.)
        around = np.flatnonzero(np.isin(faces, points.vertex[move]).any(axis=1))
        now, area = face_frames(moved, faces[around])
        bad = around[(np.einsum("ij,ij->i", was[around], now) <= 0) | (area <= 0)]
        if len(bad) == 0:
            break
        back = move & np.isin(points.vertex, faces[bad].ravel())
        moved[points.vertex[back]] = points.was[back]
        move &= ~back
    return moved


def _unsnapped(V, points: _Points, split_faces) -> np.ndarray:
    """``V`` with the points whose splits were all undone back where they were."""
    gone = ~np.isin(points.vertex, split_faces.ravel()) & np.any(V[points.vertex] != points.was, axis=1)
    if not gone.any():
        return V
    V = V.copy()
    V[points.vertex[gone]] = points.was[gone]
    return V


def _composed(m_before, rows, weights, step_parent, step_rows, step_weights):
    """(rows, weights) over a round's output faces, from the earlier rounds' (rows,
    weights) over its input faces and the round's own: a face split twice has its corners
    on its first parent by the product of the two."""
    earlier = np.full(m_before, -1, dtype=np.int64)
    earlier[rows] = np.arange(len(rows))
    inherited = earlier[step_parent]  # each output face's parent's earlier weights, or -1
    split = np.zeros(len(step_parent), dtype=bool)
    split[step_rows] = True
    keep = np.flatnonzero(~split & (inherited >= 0))
    own = inherited[step_rows]
    prior = np.broadcast_to(np.eye(3), (len(step_rows), 3, 3)).copy()
    prior[own >= 0] = weights[own[own >= 0]]
    return (np.concatenate([keep, step_rows]),
            np.concatenate([weights[inherited[keep]], np.einsum("fij,fjk->fik", step_weights, prior)]))


def _border_splits(V, F, n, part, conn=None):
    """(face, corner, vertex, t) of every split: border half-edge ``corner`` (flat index
    3 f + s, from F[f, s] to the next corner) gets ``vertex`` at parameter t; or None."""
    conn = topology.build(F, n) if conn is None else conn
    border = np.flatnonzero(conn.edge_faces == 1)
    if len(border) == 0:
        return None
    he = conn.edge_he0[border]
    flat = F.ravel()
    a = flat[he]
    b = flat[topology.next_corner(he)]
    c = flat[topology.previous_corner(he)]
    points = np.unique(np.concatenate([a, b]))
    edge_i, point_i = _near_pairs(V, a, b, points)
    if len(edge_i) == 0:
        return None
    v = points[point_i]
    pa, pb, pv = V[a[edge_i]], V[b[edge_i]], V[v]
    t = edge_parameter(pa, pb, pv)  # clamped: a point beyond an end fails END_MARGIN
    dist = np.linalg.norm(pa + t[:, None] * (pb - pa) - pv, axis=1)
    tol = np.minimum(RELATIVE_TOLERANCE * np.linalg.norm(pb - pa, axis=1), ABSOLUTE_TOLERANCE)
    ok = (dist <= tol) & (t > END_MARGIN) & (t < 1 - END_MARGIN)
    ok &= (v != a[edge_i]) & (v != b[edge_i]) & (v != c[edge_i])
    # Cracks are within one part's surface: separate parts that touch stay separate.
    ok &= part[v] == part[a[edge_i]]
    edge_i, v, t, dist = edge_i[ok], v[ok], t[ok], dist[ok]
    if len(edge_i) == 0:
        return None
    # A vertex goes into its nearest edge only.
    order = np.lexsort((dist, v))
    first = np.concatenate([[True], v[order][1:] != v[order][:-1]])
    pick = order[first]
    edge_i, v, t = edge_i[pick], v[pick], t[pick]
    # One split edge per face and round (a face's other edges wait for the next round).
    f = he[edge_i] // 3
    face_first = np.zeros(len(F), dtype=np.int64) - 1
    np.maximum.at(face_first, f, he[edge_i])  # any one border half-edge of the face
    keep = he[edge_i] == face_first[f]
    return he[edge_i][keep], v[keep], t[keep]


def _near_pairs(V, a, b, points):
    """(edge, point) index pairs whose point may lie within tolerance of the edge a-b:
    points hashed to a grid, edges sampled along their length at half a cell, each
    sample looking in the cells its reach overlaps (of the 27 around it). Exact
    distances are the caller's.

    A point within tolerance of an edge is within half the sample spacing plus the
    tolerance of a sample, under half a cell: each sample needs only the cells that
    distance reaches into, three or four on average rather than 27 (the CAD engine's
    first round: 500,000 pairs to measure; see _reach)."""
    pa, pb = V[a], V[b]
    length = np.linalg.norm(pb - pa, axis=1)
    cell = max(float(np.median(length)), 1e-9)
    samples = np.ceil(length / (0.5 * cell)).astype(np.int64) + 1
    edge_of = np.repeat(np.arange(len(a)), samples)
    start = np.cumsum(samples) - samples
    t = (np.arange(len(edge_of)) - start[edge_of]) / np.maximum(samples[edge_of] - 1, 1)
    sample_pos = pa[edge_of] + t[:, None] * (pb - pa)[edge_of]
    lo = np.minimum(sample_pos.min(axis=0), V[points].min(axis=0))
    scaled = (sample_pos - lo) / cell
    sample_cell = np.floor(scaled).astype(np.int64) + 1
    point_cell = grid.cells(V[points], lo, cell)
    stride = grid.strides(sample_cell, point_cell)
    point_key = point_cell @ stride
    by_key = np.argsort(point_key, kind="stable")
    sorted_keys = point_key[by_key]
    # Where in its cell each sample lies (0 to 1 per axis), and how far it must look.
    within = scaled - (sample_cell - 1)
    reach = _reach(length, samples, cell)[edge_of]
    edges_out, points_out = [], []
    sample_key = sample_cell @ stride
    for off in grid.NEIGHBOURS:
        looks = np.ones(len(sample_key), dtype=bool)
        for axis, o in enumerate(off):
            if o < 0:
                looks &= within[:, axis] < reach
            elif o > 0:
                looks &= within[:, axis] > 1.0 - reach
        rows = np.flatnonzero(looks)
        if len(rows) == 0:
            continue
        rep, at = grid.in_cells(sorted_keys, sample_key[rows] + off @ stride)
        if len(rep) == 0:
            continue
        edges_out.append(edge_of[rows[rep]])
        points_out.append(by_key[at])
    if not edges_out:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    # One int64 key per pair: np.unique on rows (axis=0) sorts them as bytes, far slower.
    key = np.unique(np.concatenate(edges_out) * np.int64(len(points)) + np.concatenate(points_out))
    return key // len(points), key % len(points)


def _reach(length, samples, cell) -> np.ndarray:
    """(edges,) how far, in cells, a sample of each edge must look: half its samples'
    spacing plus the edge's tolerance (a point within tolerance of the edge is that near
    a sample), with a margin for rounding."""
    spacing = length / np.maximum(samples - 1, 1)
    tolerance = np.minimum(RELATIVE_TOLERANCE * length, ABSOLUTE_TOLERANCE)
    return (0.5 * spacing + tolerance) / cell * (1.0 + 1e-6) + 1e-9


def _split_faces(F, corner, vertex, t):
    """Faces with the split half-edges fanned out. corner: flat half-edge index per
    inserted point (several points may share one), vertex: the point, t: its parameter.
    Returns (faces, parent row, the rows of the new faces, (k, 3, 3) barycentric weights
    of each new face's corners over its parent's corners)."""
    m = len(F)
    order = np.lexsort((t, corner))
    corner, vertex, t = corner[order], vertex[order], t[order]
    face = corner // 3
    side = corner % 3
    split_faces, first_of = np.unique(face, return_index=True)
    count = np.diff(np.append(first_of, len(face)))
    # Each split face becomes count + 1 faces: consecutive pairs of [a, p1..pk, b], with c.
    a_side = side[first_of]
    fs = split_faces
    a = F[fs, a_side]
    b = F[fs, (a_side + 1) % 3]
    c = F[fs, (a_side + 2) % 3]
    chain_len = count + 2
    chain_start = np.cumsum(chain_len) - chain_len
    chain = np.empty(int(chain_len.sum()), dtype=np.int64)
    chain_t = np.empty(len(chain))
    chain[chain_start] = a
    chain_t[chain_start] = 0.0
    chain[chain_start + chain_len - 1] = b
    chain_t[chain_start + chain_len - 1] = 1.0
    inner = np.repeat(chain_start, count) + 1 + (np.arange(len(vertex)) - np.repeat(first_of, count))
    chain[inner] = vertex
    chain_t[inner] = t
    group = np.repeat(np.arange(len(fs)), chain_len)
    pair_first = np.flatnonzero(np.diff(group) == 0)  # every position with a successor in its chain
    g = group[pair_first]
    new_faces = np.stack([chain[pair_first], chain[pair_first + 1], c[g]], axis=1)
    # Keep the parent's corner order: (a, b, c) sits at sides (s, s+1, s+2).
    s0 = a_side[g]
    rolled = np.empty_like(new_faces)
    rows_ = np.arange(len(g))
    for k in range(3):
        rolled[rows_, (s0 + k) % 3] = new_faces[:, k]
    w = np.zeros((len(g), 3, 3))
    t0, t1 = chain_t[pair_first], chain_t[pair_first + 1]
    w[rows_, s0, s0] = 1 - t0
    w[rows_, s0, (s0 + 1) % 3] = t0
    w[rows_, (s0 + 1) % 3, s0] = 1 - t1
    w[rows_, (s0 + 1) % 3, (s0 + 1) % 3] = t1
    w[rows_, (s0 + 2) % 3, (s0 + 2) % 3] = 1.0
    untouched = np.ones(m, dtype=bool)
    untouched[fs] = False
    keep_rows = np.flatnonzero(untouched)
    faces = np.concatenate([F[keep_rows], rolled])
    parent = np.concatenate([keep_rows, fs[g]])
    return faces, parent, len(keep_rows) + np.arange(len(rolled)), w


def _turned_splits(V, before, faces, parent, rows) -> tuple:
    """(the faces of ``before`` whose split turned a new face against them, the normals
    of every split face's parent (len(rows), 3))."""
    normals, _ = face_frames(V, faces[rows])
    parent_normals, _ = face_frames(V, before[parent[rows]])
    return np.unique(parent[rows][np.einsum("ij,ij->i", normals, parent_normals) <= 0]), parent_normals


def _folded(V, faces, conn) -> np.ndarray:
    """(edges,) bool: edges of two faces that run them the same way and face the same way
    (one lies on the other; two faces wound against each other face opposite ways, and
    core.orientation turns one of them)."""
    flat = faces.ravel()
    two = np.flatnonzero((conn.edge_faces == 2) & (conn.edge_he1 >= 0))
    same_way = flat[conn.edge_he0[two]] == flat[conn.edge_he1[two]]
    two = two[same_way]
    normals, _ = face_frames(V, faces[np.concatenate([conn.edge_he0[two], conn.edge_he1[two]]) // 3])
    folded = np.zeros(len(conn.edge_faces), dtype=bool)
    folded[two] = np.einsum("ij,ij->i", normals[:len(two)], normals[len(two):]) > 0
    return folded


def _undo_bad_splits(V, before, faces, parent, rows, weights, n):
    """The split faces back as they were where a split went wrong:
    - a new face turned against the face it was split from (a point beside a thin
      triangle's edge can fall on the wrong side of its other edges): rule no_turn_over
      would then freeze its corners for the whole run;
    - an edge with three or more faces among the new ones (a seam where three sheets
      meet, a vertex that fitted an edge of its own side), or two faces on one side of an
      edge (both run it the same way and face the same way: a fold, as a moved point at
      a thin face's foot made one): the repair must not make a manifold mesh non-manifold.
    rows, weights: the split faces and their corners' weights, as _split_faces gives.
    Returns them with the faces and parents kept, and the connectivity of those faces
    (the next round's, and core.repair's, so it is built once)."""
    split = np.zeros(len(faces), dtype=bool)
    split[rows] = True
    bad = _turned_splits(V, before, faces, parent, rows)[0]
    for _ in range(ROUNDS + 1):
        if len(bad):
            undo = np.isin(parent, bad)
            new_index = np.cumsum(~undo) - 1
            kept = ~undo[rows]
            rows, weights = new_index[rows[kept]], weights[kept]
            faces = np.concatenate([faces[~undo], before[bad]])
            parent = np.concatenate([parent[~undo], bad])
            split = np.zeros(len(faces), dtype=bool)
            split[rows] = True
        conn = topology.build(faces, n)
        crowded = np.flatnonzero((conn.edge_faces > 2) | _folded(V, faces, conn))
        if len(crowded) == 0:
            break
        on_crowded = np.flatnonzero(np.isin(conn.he_edge, crowded)) // 3
        bad = np.unique(parent[on_crowded[split[on_crowded]]])
        if len(bad) == 0:
            break  # those edges were non-manifold in the input
    return faces, parent, rows, weights, conn
