"""Step 5 of a pass: reject collapses that would break the mesh.

Checked in bulk over the corners around both ends of every chosen edge:
- link condition (manifold in, manifold out): the ends share exactly the neighbours
  opposite the edge, and do not both keep a face on those two neighbours (a closed
  tetrahedron, or one hanging off a pinch, would fold into two faces on the same
  corners);
- no vertex loses its last face (the kept end, or a corner opposite the edge), so no
  part of the mesh disappears, and no locked vertex with it;
- no face turns over (new.old normal below the step's min_normal_cosine, or facing away
  from the input face it descends from) or collapses to zero area,
  and none becomes a sliver (quality below the step's min_quality) worse than it was;
- no UV triangle flips (delegated to the wedges, when corner data is carried);
- with ``max_error``, the LOD stays within it of the source (core.tracked_distance).
core.guards states every rule and which of them relax (the thresholds in ``s.guards``).
"""
from __future__ import annotations

import numpy as np

from . import topology
from .geometry import cross, rows
from . import slivers
from .guards import SLIVER_QUALITY, SLIVER_SLACK, relaxation_ladder
from .metrics import quality_from

STRICT = relaxation_ladder()[0]
# Rule no_degenerate_face: a face's doubled area may not fall to this, in units of its
# mesh's bounding-box diagonal squared; in a run of several parts (core.assembly), of its
# part's (part_area_floors): a part 10^7 times smaller than the asset's largest had every
# face below the asset's floor, every collapse of it was refused, and a search by
# deviation made nothing of the whole asset.
MIN_DOUBLE_AREA = 1e-14


def part_area_floors(vertices: np.ndarray, part: np.ndarray) -> np.ndarray:
    """(parts,) MIN_DOUBLE_AREA in the units of ``vertices`` (n, 3) for each part (n,)
    labels: times the square of the part's bounding-box diagonal in those units."""
    parts = int(part.max(initial=-1)) + 1
    low = np.full((parts, 3), np.inf)
    high = np.full((parts, 3), -np.inf)
    np.minimum.at(low, part, vertices)
    np.maximum.at(high, part, vertices)
    diagonal_sq = np.where(np.isfinite(low).all(axis=1), np.einsum("ij,ij->i", high - low, high - low), 1.0)
    return MIN_DOUBLE_AREA * diagonal_sq
FLAT_RING_AGREEMENT = 0.85  # |sum of ring normals| / sum of their lengths: "nearly flat"


def valid_collapses(s, conn, cand, chosen, opposite, faces_taken, window=None) -> np.ndarray:
    """(len(chosen),) bool: which chosen collapses are safe to apply.

    opposite: ``opposite_corners`` of the chosen edges. faces_taken: (n,) the faces each
    vertex loses as a corner opposite the edge of collapses of this pass: those accepted
    in earlier rounds and every one chosen now (a pinched vertex can be opposite several
    independent collapses, one per fan). window: see topology.gather_vertex_corners."""
    c = len(chosen)
    if c == 0:
        return np.zeros(0, dtype=bool)
    n = len(s.V)
    keep, remove, pos = cand.keep[chosen], cand.remove[chosen], cand.position[chosen]
    fans = _rings(s, cand, chosen, *topology.gather_vertex_corners(s.F, np.concatenate([keep, remove]), n, window))
    collapse, from_keep, faces, moving, nb_next, nb_prev, other_end, dying = fans
    edge = cand.edge[chosen]
    ok = _link_condition(conn, edge, nb_next, nb_prev, _open_fan(s, conn, moving), other_end, from_keep, collapse, c, n,
                         s.close_holes)
    opposite0, opposite1 = opposite
    ok &= _no_vertex_left_bare(s.face_count, faces_taken, keep, remove, conn.edge_faces[edge], opposite0, opposite1)
    ok &= _no_fold_onto_opposite_edge(opposite0, opposite1, nb_next, nb_prev, dying, from_keep, collapse, c)
    ok &= _corners_kept(s, conn, keep, remove, pos, fans, c)
    guards = s.guards
    if s.wedges is not None:
        ok &= s.wedges.valid_uv(s.F, conn, edge, keep, remove, pos, s.V, faces, collapse, dying, c,
                                guards.min_uv_area_kept, guards.uv_flip)
    if s.bound is not None:
        s.bound.tracker.rejected_edges = np.zeros(0, dtype=np.int64)
    if s.bound is not None and ok.any():
        # Rule max_error: only for what passed the rest (the measuring is the dear part).
        # Each face of the old fans once: a face on the edge is gathered from both ends.
        fan = ok[collapse] & (from_keep | ~dying)
        new_tri = np.stack([rows(pos, collapse[fan]), rows(s.V, nb_next[fan]), rows(s.V, nb_prev[fan])], axis=1)
        # A dying row's second ring corner is the one opposite the edge.
        ring = np.stack([nb_next[fan], nb_prev[fan]], axis=1)
        swap = dying[fan] & (ring[:, 1] == other_end[fan])
        ring[swap] = ring[swap][:, ::-1]
        moved = np.linalg.norm(new_tri[:, 0] - rows(s.V, moving[fan]), axis=1)
        ok &= s.bound.tracker.within(s.bound.limit, s.face_origin, faces[fan], collapse[fan], new_tri, ~dying[fan], ring,
                               moving[fan], moved, keep, edge)
    return ok


def screened(s, conn, cand, idx) -> np.ndarray:
    """(len(idx),) bool: which of the candidates ``idx`` (indices into ``cand``, not
    necessarily independent) pass the rules that judge a collapse by itself on the mesh
    as it is: the link condition and the corner rules (turn, fold-over, degenerate,
    sliver; corner_breaks). A collapse either of them rejects is rejected in any
    independent set of a pass too, so a pass may drop it before choosing (engine's
    screening, where most of the cheapest candidates fail them). The rules that depend
    on the other collapses of the pass (vertices left bare, UV wedges) or are costly
    (max_error) wait for valid_collapses."""
    c = len(idx)
    if c == 0:
        return np.zeros(0, dtype=bool)
    n = len(s.V)
    keep, remove = cand.keep[idx], cand.remove[idx]
    fans = _rings(s, cand, idx, *topology.gather_corners_of_each(s.F, np.concatenate([keep, remove]), n))
    collapse, from_keep, _, moving, nb_next, nb_prev, other_end, _ = fans
    ok = _link_condition(conn, cand.edge[idx], nb_next, nb_prev, _open_fan(s, conn, moving), other_end, from_keep,
                         collapse, c, n, s.close_holes)
    return ok & _corners_kept(s, conn, keep, remove, cand.position[idx], fans, c)


def _rings(s, cand, chosen, owner, corners) -> tuple:
    """Per gathered corner of both ends of the ``chosen`` collapses (owner: the position
    in keep + remove whose corner it is): (collapse it belongs to, whether of the kept
    end, its face, the moving vertex, the face's next and previous corners' vertices,
    the collapse's other end, whether the face dies with the edge)."""
    c = len(chosen)
    keep, remove = cand.keep[chosen], cand.remove[chosen]
    from_keep = owner < c
    collapse = np.where(from_keep, owner, owner - c)
    corner_vertex = s.F.ravel()
    # Each gathered corner is the moving end itself; its face's other two corners stay put
    # (or one of them is the other end, and the face dies with the edge).
    nb_next = corner_vertex[topology.next_corner(corners)]
    nb_prev = corner_vertex[topology.previous_corner(corners)]
    other_end = np.where(from_keep, remove[collapse], keep[collapse])
    dying = (nb_next == other_end) | (nb_prev == other_end)
    return collapse, from_keep, corners // 3, corner_vertex[corners], nb_next, nb_prev, other_end, dying


def _open_fan(s, conn, moving) -> np.ndarray:
    """Around a closed fan every neighbour follows the moving corner exactly once, so the
    preceding neighbours add nothing; only open fans (borders) and pinched or locked
    vertices need both to see their whole ring."""
    return conn.border_vertex[moving] | s.locked[moving] | s.complex[moving]


def _corners_kept(s, conn, keep, remove, pos, fans, c) -> np.ndarray:
    """(c,) bool: collapses none of whose faces turns over, vanishes or becomes a sliver
    (corner_breaks, at the floors in force); fans: _rings of them."""
    collapse, _, faces, moving, nb_next, nb_prev, _, dying = fans
    source = rows(s.source_normals, s.face_origin[faces])
    guards = s.guards
    floor_off = s.slivers.floor_off  # core.slivers.sliver_allowance; per part in a run of several
    if np.ndim(floor_off) == 0:
        floor = 0.0 if floor_off else guards.min_quality
    else:
        floor = np.where(floor_off[s.part[keep]], 0.0, guards.min_quality)[collapse]
    if np.any(floor > 0) and conn.border_vertex.any():
        floor = slivers.border_floors(floor, s.slivers.worst, conn.border_vertex, keep, remove,
                                      nb_next, nb_prev, collapse)
    area_floor = MIN_DOUBLE_AREA if s.part_area_floor is None else s.part_area_floor[s.part[keep]][collapse]
    bad = corner_breaks(rows(s.V, moving), rows(s.V, nb_next), rows(s.V, nb_prev), rows(pos, collapse),
                        dying, collapse, c, source, guards.min_normal_cosine, floor, area_floor)
    return np.bincount(collapse[bad], minlength=c) == 0


def corner_breaks(p_a, p_b, p_c, x, dying, collapse, c, source,
                  min_normal_cosine=STRICT.min_normal_cosine, min_quality=SLIVER_QUALITY,
                  min_double_area=MIN_DOUBLE_AREA) -> np.ndarray:
    """(k,) bool: the corners whose face would turn over, vanish or become a sliver.

    One row per face corner around the ends of ``c`` collapses: p_a (k, 3) the moving
    corner, p_b and p_c (k, 3) the face's next and previous corners (which stay put), x
    (k, 3) the new position of its collapse, dying (k,) faces on the collapsed edge (never
    bad), collapse (k,) which collapse the corner belongs to, source (k, 3) the unit normal
    of the input face its face descends from. min_normal_cosine and min_quality: the
    relaxable rules' thresholds (core.guards); min_quality may be (k,), one per corner
    (core.slivers.border_floors); min_double_area (rule no_degenerate_face) may be (k,),
    one per corner (part_area_floors).
    """
    # Normals before and after moving the end to the new position: (b - a) x (c - a) in
    # the face's own cyclic order.
    ab_old, ac_old, ab_new, ac_new = p_b - p_a, p_c - p_a, p_b - x, p_c - x
    n_old = cross(ab_old, ac_old)
    n_new = cross(ab_new, ac_new)
    len_old = np.sqrt(np.einsum("ij,ij->i", n_old, n_old))
    len_new = np.sqrt(np.einsum("ij,ij->i", n_new, n_new))
    dot = np.einsum("ij,ij->i", n_old, n_new)
    # Rules normal_turn and no_turn_over (a negative cosine is never allowed), and
    # no_degenerate_face.
    min_cosine = max(min_normal_cosine, 0.0)
    bad = ~dying & ((dot < min_cosine * len_old * len_new) | (len_new <= min_double_area))
    # Nor may a face end up facing against a nearly flat surface around the collapse (a
    # fold-over that each single turn allowed). Only where the rings' normals agree: at
    # tips and sharp ridges their sum means little.
    ring = np.stack([np.bincount(collapse, weights=n_old[:, j], minlength=c) for j in range(3)], axis=1)
    spread = np.bincount(collapse, weights=len_old, minlength=c)
    flat = np.sqrt(np.einsum("ij,ij->i", ring, ring)) >= FLAT_RING_AGREEMENT * spread
    bad |= ~dying & flat[collapse] & (np.einsum("ij,ij->i", n_new, rows(ring, collapse)) < 0)
    # Small turns add up over passes: no face may end up facing away from the input face
    # it descends from.
    bad |= ~dying & (np.einsum("ij,ij->i", n_new, source) < 0)
    # Rule sliver: never turn a face into a sliver, so the output's worst triangles stay
    # up. A face that already is one may get somewhat worse (not below half its
    # quality), or the slivers of the input would freeze their whole neighbourhood.
    if np.any(min_quality > 0):
        bc = np.einsum("ij,ij->i", p_c - p_b, p_c - p_b)
        q_new = _quality(len_new, ab_new, ac_new, bc)
        q_old = _quality(len_old, ab_old, ac_old, bc)
        bad |= ~dying & (q_new < min_quality) & ((q_old >= min_quality) | (q_new < SLIVER_SLACK * q_old))
    return bad


def _link_condition(conn, edges, nb_next, nb_prev, open_fan, other_end, from_keep, collapse, c, n,
                    close_holes: bool = False) -> np.ndarray:
    """Link condition from the ring neighbours of both ends: they share exactly the
    corners opposite the edge. With ``close_holes`` (rule small_holes_stay relaxed) a
    border edge may also share the third corner of a hole of three edges, which the
    collapse closes (_closes_triangular_hole).

    Every (collapse, neighbour, side) becomes one integer; one sort of them all gives the
    distinct neighbours of each end and, where the same neighbour follows on the other
    side, the neighbours the two ends share. nb_prev counts only where open_fan."""
    nb = np.concatenate([nb_next, nb_prev.compress(open_fan)])
    owner = np.concatenate([collapse, collapse.compress(open_fan)])
    side = np.concatenate([~from_keep, (~from_keep).compress(open_fan)])
    useful = nb != np.concatenate([other_end, other_end.compress(open_fan)])
    code = np.sort(((owner * np.int64(n) + nb) * 2 + side).compress(useful))
    distinct = code.compress(np.concatenate([[True], code[1:] != code[:-1]])) if len(code) else code
    owner = distinct // (2 * n)
    from_remove = (distinct & 1).astype(bool)
    shared_here = np.zeros(len(distinct), dtype=bool)
    shared_here[:-1] = (distinct[1:] == distinct[:-1] + 1) & ~from_remove[:-1]
    shared = np.bincount(owner.compress(shared_here), minlength=c)
    ok = shared == conn.edge_faces[edges]
    if close_holes:
        maybe = (shared == 2) & (conn.edge_faces[edges] == 1)
        if maybe.any():
            common = (distinct // 2) % n
            ok |= _closes_triangular_hole(maybe, owner.compress(shared_here), common.compress(shared_here),
                                          nb_next, nb_prev, other_end, from_keep, collapse, c)
    return ok


def _closes_triangular_hole(maybe, shared_owner, shared_vertex, nb_next, nb_prev, other_end, from_keep, collapse,
                            c) -> np.ndarray:
    """(c,) bool: which border-edge collapses (a, b) whose ends share two neighbours
    (``maybe``) close a hole of three edges (a, b, h): the neighbour h that is not the
    corner opposite (a, b) lies on one face around a and one around b (so a-h and b-h are
    border edges too), and those faces' third corners differ. The collapse then merges
    a-h and b-h into one inner edge of two faces: the hole is gone and the surface stays
    manifold (with the same third corner the two faces would become one twice)."""
    # The corner opposite the edge: the other ring corner of a face on it.
    on_edge = (nb_next == other_end) | (nb_prev == other_end)
    opposite = np.full(c, -1, dtype=np.int64)
    opposite[collapse[on_edge]] = np.where(nb_next == other_end, nb_prev, nb_next)[on_edge]
    hole = np.full(c, -1, dtype=np.int64)
    pick = maybe[shared_owner] & (shared_vertex != opposite[shared_owner])
    hole[shared_owner[pick]] = shared_vertex[pick]
    h = hole[collapse]
    hits = (h >= 0) & ((nb_next == h) | (nb_prev == h))
    third = np.where(nb_next == h, nb_prev, nb_next)
    at_keep = np.bincount(collapse[hits & from_keep], minlength=c)
    at_remove = np.bincount(collapse[hits & ~from_keep], minlength=c)
    third_keep = np.full(c, -1, dtype=np.int64)
    third_remove = np.full(c, -2, dtype=np.int64)
    third_keep[collapse[hits & from_keep]] = third[hits & from_keep]
    third_remove[collapse[hits & ~from_keep]] = third[hits & ~from_keep]
    return maybe & (hole >= 0) & (at_keep == 1) & (at_remove == 1) & (third_keep != third_remove)


def opposite_corners(F, conn, edges) -> tuple:
    """((k,), (k,)): the vertex opposite each edge in each of its faces; -1 in the
    second where the edge has one face."""
    corner_vertex = F.ravel()
    he0, he1 = conn.edge_he0[edges], conn.edge_he1[edges]
    opposite0 = corner_vertex[topology.previous_corner(he0)]
    has1 = he1 >= 0
    opposite1 = np.where(has1, corner_vertex[topology.previous_corner(np.where(has1, he1, 0))], -1)
    return opposite0, opposite1


def _no_vertex_left_bare(face_count, faces_taken, keep, remove, faces_on_edge, opposite0, opposite1) -> np.ndarray:
    """(c,) bool: collapses after which every vertex they touch still has a face.

    A collapse deletes the faces on its edge (faces_on_edge, 1 or 2; opposite0/opposite1
    their corners opposite the edge, -1 for none). The kept end then has the faces of
    both ends but those; each opposite corner loses one. A lone triangle, or a fan
    hanging off a pinch, would otherwise vanish with its last collapse, taking even
    locked vertices along. faces_taken: see valid_collapses."""
    ok = face_count[keep] + face_count[remove] - 2 * faces_on_edge > 0
    ok &= face_count[opposite0] > faces_taken[opposite0]
    has1 = opposite1 >= 0
    second = np.where(has1, opposite1, 0)
    ok &= ~has1 | (face_count[second] > faces_taken[second])
    return ok


def _no_fold_onto_opposite_edge(opposite0, opposite1, nb_next, nb_prev, dying, from_keep, collapse, c):
    """(c,) bool: False where both ends have a surviving face on the two corners opposite
    an inner edge. Collapsing would turn those faces into two on the same three vertices:
    a closed tetrahedron folding flat, also where one end has other fans (a pinch), which
    a degree count cannot see. The ends share no other neighbour (link condition), so
    that is the only edge of their rings that both can have."""
    inner = (opposite1 >= 0) & (opposite1 != opposite0)
    o0, o1 = opposite0[collapse], opposite1[collapse]
    on_pair = ~dying & inner[collapse] & (((nb_next == o0) & (nb_prev == o1)) | ((nb_next == o1) & (nb_prev == o0)))
    at_keep = np.bincount(collapse.compress(on_pair & from_keep), minlength=c)
    at_remove = np.bincount(collapse.compress(on_pair & ~from_keep), minlength=c)
    return (at_keep == 0) | (at_remove == 0)


def _quality(double_area, ab, ac, bc_squared):
    """Triangle quality (core.metrics) from two edge vectors at a corner and the squared
    length of the third edge."""
    sq = np.einsum("ij,ij->i", ab, ab) + np.einsum("ij,ij->i", ac, ac) + bc_squared
    return quality_from(double_area, np.maximum(sq, 1e-300))
