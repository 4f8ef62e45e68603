"""Steps 2-4 of a pass: which edges may collapse, at what cost, and which of them can
collapse together in one pass."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import kinds, quadrics, shape_keys, topology
from .geometry import closest_on_triangles, edge_parameter, rows
from .heartbeat import chunks

_NO_RANK = np.iinfo(np.int64).max


@dataclass
class Candidates:
    """Collapsible edges: ``edge`` indexes conn.edges; ``remove`` merges into ``keep``,
    which moves to ``position``. ``cost`` is the quadric error there divided by the area
    the two quadrics stand for: a mean squared distance, comparable between dense and
    coarse regions (the raw area-weighted error would let small, densely tessellated
    features go first, which is what worst-case distance punishes). Without line
    quadrics (w = 0) the cost is the raw error: the paper's fallback to plain
    Garland-Heckbert, order included, which is what the fidelity end of the controls
    (line_weight 0, min_quality 0) asks for; measured on fandisk at 10 % (feature angle
    off), the raw order gives 0.95x Decimate's Hausdorff distance where the per-area order
    gives 1.57x.

    With the per-area ranking a seam pair's cost is at least the squared distance its
    collapse sweeps (swept_distance): its merged vertex is held on the segment between its
    ends, where on a curved surface it cuts a chord the quadric, averaged over the pair's
    area, underrates. (The raw error of w = 0 stays the paper's plain Garland-Heckbert.)"""

    edge: np.ndarray
    keep: np.ndarray
    remove: np.ndarray
    position: np.ndarray
    cost: np.ndarray

    def subset(self, mask) -> "Candidates":
        return Candidates(self.edge[mask], self.keep[mask], self.remove[mask], self.position[mask], self.cost[mask])


@dataclass
class CostCache:
    """Last pass's candidates: ``keep``, ``position`` (k, 3) and ``cost`` of each, and
    ``slot`` (edges,) the row of each edge among them, or -1 (core.selection reuses a
    row where neither end changed), ``pass_no`` the pass they were the candidates of."""

    keep: np.ndarray
    position: np.ndarray
    cost: np.ndarray
    slot: np.ndarray
    pass_no: int


def candidates(s, conn, kind, pass_no) -> Candidates:
    """Every edge allowed to collapse now, with its optimal position and cost."""
    n = len(s.V)
    a, b = conn.edges[:, 0], conn.edges[:, 1]
    faces_on_edge = conn.edge_faces

    ka, kb = kind[a], kind[b]
    swap = kinds.RANK[kb] > kinds.RANK[ka]  # the more constrained end survives
    keep = np.where(swap, b, a)
    remove = np.where(swap, a, b)
    k_keep = np.where(swap, kb, ka)
    k_remove = np.where(swap, ka, kb)

    # The collapse table (core.kinds), then its rules by edge: manifold_edges ...
    ok = kinds.allowed(k_remove, k_keep, conn.seam_edge)
    ok &= (faces_on_edge == 1) | (faces_on_edge == 2)
    # ... and boundaries_stay: an inner edge joining two border vertices would pinch.
    ok &= ~((faces_on_edge == 2) & conn.border_vertex[a] & conn.border_vertex[b])
    once_rejected = np.flatnonzero(ok & (s.rejected_pass > 0))
    ok[once_rejected[still_rejected(s, once_rejected, a[once_rejected], b[once_rejected])]] = False
    idx = np.flatnonzero(ok)
    keep, remove = keep[idx], remove[idx]
    k_keep, k_remove = k_keep[idx], k_remove[idx]

    # Reuse last pass's position and cost where neither end changed (quadric, position
    # or kind): most of the mesh is untouched by any one pass.
    if s.cache is not None:
        ckeep, cpos, ccost = s.cache.keep, s.cache.position, s.cache.cost
        at = s.cache.slot[idx]
        cached = at >= 0
        at = np.where(cached, at, 0)
        reuse = cached & (ckeep[at] == keep) & ~s.changed[keep] & ~s.changed[remove]
        if s.cost_per_area:
            # A seam pair's swept distance also reads its neighbours: not reused once one moved.
            on_seam = kinds.PLACE[k_remove, k_keep] == kinds.ON_SEAM
            reuse &= ~(on_seam & (np.maximum(s.touched[keep], s.touched[remove]) >= s.cache.pass_no))
        # Gather every row and overwrite the fresh minority: cheaper than masked copies.
        position = rows(cpos, at)
        cost = ccost[at]
        fresh = np.flatnonzero(~reuse)
    else:
        position = np.empty((len(idx), 3))
        cost = np.empty(len(idx))
        fresh = np.arange(len(idx))
    for part in chunks(len(fresh)):
        # In chunks, each row on its own: the same numbers, and a heartbeat between.
        rows_ = fresh[part]
        position[rows_], cost[rows_] = _optimal(s, keep[rows_], remove[rows_], k_keep[rows_], k_remove[rows_])
        s.heartbeat.beat()
    slot = np.full(len(conn.edges), -1, dtype=np.int64)
    slot[idx] = np.arange(len(idx))
    s.cache = CostCache(keep, position, cost, slot, pass_no)
    return Candidates(idx, keep, remove, position, cost)


def _optimal(s, keep, remove, k_keep, k_remove):
    """Position and quadric error of collapsing each remove into its keep."""
    q = quadrics.pair_sums(s.Q, keep, remove)
    v_keep, v_remove = s.V[keep], s.V[remove]
    pair_area = s.area[keep] + s.area[remove]  # what the pair's quadric stands for
    position = quadrics.minimize(q, 0.5 * (v_keep + v_remove), s.area_scale)
    place = kinds.PLACE[k_remove, k_keep]
    fixed = place == kinds.AT_KEEP
    position[fixed] = v_keep[fixed]
    free = exact_end_rows(s, place, keep, remove)
    if len(free):
        geometric = q[free] - quadrics.pair_sums(s.line_part, keep[free], remove[free])
        if s.plane_placement:
            position[free] = plane_optimum(q[free], geometric, v_keep[free], v_remove[free], s.area_scale)
        position[free] = exact_end(geometric, pair_area[free], v_keep[free], v_remove[free], position[free])
    along_seam = place == kinds.ON_SEAM
    if along_seam.any():
        position[along_seam], _ = quadrics.minimize_on_segment(q[along_seam], v_keep[along_seam], v_remove[along_seam])
    error = quadrics.evaluate(q, position)
    if s.keys is not None:
        # At each shape key's full value (and in each sample pose, core.skinning) the
        # merged vertex moves by its interpolated offset.
        t = edge_parameter(v_keep, v_remove, position)[:, None]
        # Every key's columns gathered at once (k, 3K), then laid out key by key (K, k, 3).
        keys = s.keys
        x_keep, x_remove = s.X[keep[:, None], keys.index], s.X[remove[:, None], keys.index]
        merged = ((x_keep + t * (x_remove - x_keep)) * keys.scale).reshape(len(keep), -1, 3).transpose(1, 0, 2)
        error = error + shape_keys.collapse_error(keys.quadrics, keep, remove, position, merged, keys.weights)
    if not s.cost_per_area:
        return position, error
    cost = error / np.maximum(pair_area, 1e-300)
    if along_seam.any():
        on_seam = np.flatnonzero(along_seam)
        swept = swept_distance(s.V, s.F, keep[on_seam], remove[on_seam], position[on_seam])
        cost[on_seam] = np.maximum(cost[on_seam], swept)
    return position, cost


# An end of an edge is exact where the root mean square distance of the pair's planes
# there is at most this share of the edge's length. On the bevelled cube such ends
# measured 1e-7 to 6e-4 of it (the planes a merged vertex's quadric remembers from earlier
# merges), the quadric's optimum of the same pairs 1e-3 to 1.2e-2.
EXACT_END = 1e-3


# Options.plane_placement: the share of the line quadrics kept in the placement's quadric,
# enough to make every solve well conditioned (a flat pair's planes alone leave a plane of
# optima), little enough to leave the planes in charge where they decide. On Blender's
# bevelled cylinder under 0.9 of 0.05 % of its diagonal a hundredth and a tenth gave
# 1,044 and 1,076 triangles, the whole quadric 1,162; applied only to the pairs whose
# planes leave a direction free (a cap, the wall) 1,044, only to the others 1,162: the
# merges that matter there are the ones the line quadrics place alone (scratch, session 34).
PLANE_PLACEMENT_LINE_SHARE = 0.01


def plane_optimum(q, geometric, v_keep, v_remove, area_scale: float) -> np.ndarray:
    """(k, 3) the optimum of each pair's planes ``geometric`` (k, 10) with
    PLANE_PLACEMENT_LINE_SHARE of its line quadrics (``q`` minus ``geometric``), solved as
    quadrics.minimize solves (regularised towards the edge's midpoint)."""
    placing = geometric + PLANE_PLACEMENT_LINE_SHARE * (q - geometric)
    return quadrics.minimize(placing, 0.5 * (v_keep + v_remove), area_scale)


def exact_end_rows(s, place, keep, remove) -> np.ndarray:
    """Indices of the rows (pairs ``keep``, ``remove`` placed by ``place``, core.kinds)
    whose merged vertex may go to an exact end (and is placed by its planes under
    Options.plane_placement): those placed at the optimum where a distance bound holds,
    everywhere under max_error, only at painted limits' vertices under limits alone
    (elsewhere a count target ranks, and count targets keep the optimum:
    docs/method.md)."""
    if s.line_part is None:
        return np.zeros(0, dtype=np.int64)
    rows_ = place == kinds.OPTIMAL
    if not s.bound.global_bound:
        rows_ &= s.bound.limited[keep] | s.bound.limited[remove]
    return np.flatnonzero(rows_)


def exact_end(geometric, area, v_keep, v_remove, position) -> np.ndarray:
    """(k, 3) ``position``, or an end of the edge where that end lies on every plane of
    the pair's faces and ``position`` does not.

    geometric: (k, 10) the pair's quadric without its line quadrics (planes of faces,
    boundaries, feature edges; the probabilistic planes' term when it is on, which no
    end is exact for); area: (k,) the area it stands for; v_keep, v_remove,
    position: (k, 3). Why: the line quadric pulls a merged vertex towards both ends'
    normal lines. Where one end is on a crease the other lies on (a flat side's vertex
    next to a bevel's foot, a foot vertex next to its corner) the merge is exact at that
    end, but the optimum of the whole quadric leaves the crease: the faces there are
    thin and weigh little against the flat side's line quadric (paper Eq. 16 weighs it
    by the vertex's area). Such merges moved the surface, and a distance bound refused
    them: the bevelled cube kept all of its flat sides' triangles at 0.05 % of its
    diagonal (docs/method.md, "Props as Blender makes them").
    """
    edge = v_keep - v_remove
    limit = np.maximum(area, 1e-300) * EXACT_END ** 2 * np.einsum("ij,ij->i", edge, edge)
    at_keep, at_remove = quadrics.evaluate(geometric, v_keep), quadrics.evaluate(geometric, v_remove)
    off = quadrics.evaluate(geometric, position) > limit
    to_keep = off & (at_keep <= limit) & (at_keep <= at_remove)
    to_remove = off & (at_remove <= limit) & ~to_keep
    out = position.copy()
    out[to_keep] = v_keep[to_keep]
    out[to_remove] = v_remove[to_remove]
    return out


def swept_distance(V, F, keep, remove, position) -> np.ndarray:
    """(k,) squared distance from the farther of each collapse's two ends (rows of V,
    where they are now) to the faces of F left around its merged vertex at ``position``
    (k, 3): the largest distance the collapse moves the surface away from them.

    Why seam pairs need it: a seam vertex slides only along its seam (core.kinds), so a
    pair merges on the segment between its ends. Where the seam follows a curve (a UV cut
    along the foot of a fillet), that segment is a chord inside the surface. The quadric,
    summed over the pair's faces and divided by their area (the ranking's mean squared
    distance), averages the chord's distance with the flat faces beside it: on BoomBox's
    knob it saw a chord 2.3-2.7x shorter than it is, and a few such merges made its 50 %
    LOD 1.58x Decimate's Hausdorff distance. Measuring what the merge cuts off is the
    one-sided distance of Hausdorff's, for the few rows that need it (docs/method.md).
    """
    k = len(keep)
    ends = np.concatenate([keep, remove])
    owner, corner = topology.gather_corners_of_each(F, ends, len(V))  # an end may be listed twice
    flat = F.ravel()
    nb_next, nb_prev = flat[topology.next_corner(corner)], flat[topology.previous_corner(corner)]
    collapse = owner % k
    other = np.where(owner < k, remove[collapse], keep[collapse])
    left = (nb_next != other) & (nb_prev != other)  # the faces on the edge itself go
    collapse, nb_next, nb_prev = collapse[left], nb_next[left], nb_prev[left]
    a, b, c = position[collapse], V[nb_next], V[nb_prev]
    farthest = np.zeros(k)
    for end in (keep, remove):
        nearest = np.full(k, np.inf)
        np.minimum.at(nearest, collapse, closest_on_triangles(V[end[collapse]], a, b, c)[1])
        farthest = np.maximum(farthest, np.where(np.isfinite(nearest), nearest, 0.0))
    return farthest


def still_rejected(s, edges, a, b) -> np.ndarray:
    """Which of ``edges`` (ends a, b) were found invalid in an earlier pass and have not
    had their neighbourhood changed since."""
    last_change = np.maximum(s.touched[a], s.touched[b])
    return last_change < s.rejected_pass[edges]


def independent_set(cand: Candidates, conn, n, seed, eligible=None) -> np.ndarray:
    """Indices into ``cand`` of edges cheapest among all eligible candidate edges
    touching the faces around both their ends.

    Two chosen edges then never share a face, nor is an end of one a neighbour of an end
    of the other, so one collapse cannot invalidate another's checks and a whole pass can
    be validated and applied at once; taking local minima approximates the greedy
    cheapest-first order. ``eligible`` (len(cand),) bool restricts the choice.
    """
    idx = np.arange(len(cand.edge)) if eligible is None else np.flatnonzero(eligible)
    rank = order_keys(cand.cost[idx], cand.edge[idx], seed)
    keep, remove = cand.keep[idx], cand.remove[idx]
    # The vertices sharing a face with v are exactly its edge neighbours, so "cheapest
    # among the edges around the faces of v" is a minimum over v's edges, then over its
    # neighbours: two scatter-minimums over edges, none over face corners.
    cheapest_at_vertex = np.full(n, _NO_RANK, dtype=np.int64)
    np.minimum.at(cheapest_at_vertex, keep, rank)
    np.minimum.at(cheapest_at_vertex, remove, rank)
    # Only edges between two ranked vertices can lower a minimum that is read later (at
    # ranked vertices): after the first round that is a small share of the mesh.
    ranked = cheapest_at_vertex != _NO_RANK
    a, b = conn.edges[:, 0], conn.edges[:, 1]
    between = np.flatnonzero(ranked[a] & ranked[b])
    a, b = a[between], b[between]
    cheapest_in_ring = cheapest_at_vertex.copy()
    np.minimum.at(cheapest_in_ring, a, cheapest_at_vertex[b])
    np.minimum.at(cheapest_in_ring, b, cheapest_at_vertex[a])
    return idx[(rank == cheapest_in_ring[keep]) & (rank == cheapest_in_ring[remove])]


def order_keys(cost: np.ndarray, edges: np.ndarray, seed: int) -> np.ndarray:
    """Distinct int64 keys ordered like ``cost``, without sorting.

    The bits of a non-negative float32 grow with its value, so they make the high half of
    the key (costs within float32 precision of each other are taken as equal); the low
    half, a bijective scramble of the edge index by the seed, breaks ties and makes every
    key distinct - which the local-minimum selection relies on.
    """
    high = np.minimum(cost, np.finfo(np.float32).max).astype(np.float32).view(np.int32).astype(np.int64)
    # The seed is mixed in before the odd multiplier (a bijection of 32-bit values), so
    # each seed orders tied edges differently; added after it, it would only rotate them.
    mask = np.uint64(0xFFFFFFFF)
    mixed_seed = (np.uint64(int(seed) & 0xFFFFFFFF) * np.uint64(0x85EBCA6B)) & mask
    low = ((edges.astype(np.uint64) ^ mixed_seed) * np.uint64(0x9E3779B1)) & mask
    return (high << np.int64(32)) | low.astype(np.int64)


def closed_rings(conn, F, vertices, n) -> np.ndarray:
    """(n,) bool: ``vertices`` and every vertex sharing a face with one of them."""
    hit = np.zeros(n, dtype=bool)
    hit[vertices] = True
    hit[np.compress(topology.faces_touching(F, vertices, n), F, axis=0).ravel()] = True
    return hit
