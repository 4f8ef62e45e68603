"""The collapse engine: passes of many independent edge collapses.

One pass (cf. meshoptimizer's pipeline, vectorised):
  1. connectivity  - edges and incidences of the live faces (topology.build)
  2. classify      - boundary, seam and locked vertices; which edges may collapse
  3. cost          - optimal position and quadric error of every candidate edge
  4. select        - edges cheapest in their two-ring neighbourhoods (independent)
  5. validate      - link condition, no flips, no degenerate or UV-flipped faces
  6. apply         - relabel faces, drop the dead ones, sum quadrics, carry attributes
When no collapse passes the rules, the quality rules relax one step (core.guards) and the
passes go on; only the loosest step's failure stops the run short of its target.
Python loops run over passes only; every step is a bulk NumPy operation.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from . import components, features, kinds, quadrics, selection, shape_keys, slivers, topology, uv_poles, validation
from . import vertex_quadrics
from .tracked_distance import TrackedDistance
from .guards import relaxation_ladder
from .heartbeat import Heartbeat
from .prepare import Problem
from .result import (
    STOP_LIMIT,
    STOP_MAX_ERROR,
    STOP_TARGET,
    STOP_TOPOLOGY,
    SimplifyResult,
    SimplifyStats,
)
from .wedges import Wedges
from .geometry import edge_parameter, face_frames, index_of, rows
from .metrics import triangle_quality

# Selection rounds per pass: more rounds, more collapses per connectivity update.
SELECTION_ROUNDS = 4
LIMITED_SELECTION_ROUNDS = 32  # with edges a painted limit holds (_choose)
# Share of the cheapest candidates a pass may collapse: lower follows the sequential
# greedy order more closely, higher needs fewer passes. The share narrows as the target
# nears (half the share of faces still to go, within these bounds): early on the costs
# are tiny and alike and order hardly matters; the last collapses are the costly ones,
# where taking them out of order shows in distance and triangle shape.
COST_QUANTILE_MAX = 0.15
COST_QUANTILE_MIN = 0.05
# Share of a pass's eligible candidates (the cheapest part) that selection rounds after
# the first may still take. A later round finds local minima among what the first left
# unblocked, so it takes edges whose cheaper neighbours are only waiting for their new
# cost: out of greedy order. That is harmless for the cheap collapses and not for the
# costly end of the share: with every round taking the whole share, the ogre's sharp tip
# went out of order and its Hausdorff distance was 1.3x the sequential greedy's.
# (On the skinned-arm test at 3 % the mean distance rises by 4 %: the one-at-a-time greedy
# order is itself 12 % further there than the unlimited rounds, see docs/method.md.)
LATER_ROUND_SHARE = 0.25
# Below this cost (a mean squared distance, in units of the bounding-box diagonal: RMS
# 0.003 %) order cannot show, and later rounds take such collapses regardless of the
# share. On the 2M-face bench mesh, mostly flat subdivided triangles at first, it takes
# 45 passes (49 without this exception, 42 with no limit at all) and about the time it
# took before. At 1e-8 (0.01 %), beast's Hausdorff distance grew by a sixth: small
# features hide below a small mean.
ORDER_FREE_COST = 1e-9
# A part leaves the LOD before a collapse whose RMS distance to the surface's planes is
# more than its bounding-box diagonal times this (_drop_smaller_than): removed, the part is
# at most about its size from the rest. The quadric distance is a mean, and on a smooth
# hull ran at half the measured Hausdorff distance; on a low-poly robot at twice it, where
# (checked after each pass, before the crawl relaxation) its shoulders left at LOD1. Since
# the drop comes before the collapse and the rules relax when passes crawl, 1 keeps the
# robot's, the engine's and the Kenney character's levels as close as 0.5 did.
DROP_SIZE_SHARE = 1.0
# Feature corners (Options.feature_angle) crowding a level (more than CORNER_SHARE of the
# vertices it will have) and nearer to another corner than CORNER_SIZE_SHARE times the
# largest collapse distance so far move like other vertices (_release_small_corners). A
# CAD export's small holes and coarse cylinders turn at every facet: the engine's body_8
# has 224 corners (170 of them border turns), and its 10 % LOD (585 faces, about 290
# vertices) kept them all at 1.28x Decimate's Hausdorff distance, 1.40x its mean and 39 %
# slivers; now 0.84x, 0.98x and 28 % (bench/messy.py; body_4 1.00x, 1.07x, 33 % -> 0.76x,
# 0.88x, 25 %). Held while there is room, corners change nothing else measured there.
CORNER_SHARE = 0.5
CORNER_SIZE_SHARE = 2.0
# The rules relax a step (as when nothing passes them at all) once CRAWL_PASSES passes in a
# row each took less than CRAWL_SHARE of the faces the target still needs: where seams
# and hard edges hold most collapses back (a CAD engine's 67 parts in one run), the strict
# steps let a handful through a pass, and the passes crawled: 400 of 451 for the last
# third of the engine's LOD3, 3 s, before the step that let it through anyway.
CRAWL_SHARE = 0.005
CRAWL_PASSES = 5
# ... as long as the target still needs this many faces: a small mesh's last passes take a
# collapse or two by nature (and are cheap), and its rules relax when nothing passes.
CRAWL_MIN_NEED = 1_000
# Under a max_error bound with every rule relaxed, a level ends once this many passes in a
# row each took fewer than this share of the faces left (_crawling_under_bound).
# At 0.03 % over five passes the CAD engine's tight search runs (0.065 % and 0.26 % of
# its size) took 27 -> 20 s for +0.02 % / -0.4 % triangles, at 0.7 % / 2.1 % 13 -> 11.5 s
# for +0.6 % / -0.3 %; at 0.1 % the second level kept 8.5 % more.
BOUND_CRAWL_PASSES = 5
BOUND_CRAWL_SHARE = 0.0003
# Once a pass's validation lets fewer than SCREEN_BELOW of the collapses it tried through,
# every later pass first drops those of its cheapest SCREEN_SHARE of candidates that fail
# the rules judging a collapse by itself (validation.screened: link condition, turn,
# sliver), before choosing (_screened). In the tail of a CAD part most of the cheapest
# candidates fail them, and each pass tried the next few local minima, where a sequential
# greedy queue skips such a collapse at once: the engine's body_3 at 10 % took 224 passes,
# 165 of them for its last 550 faces (2,691 of the 3,879 collapses they tried failing the
# link condition). Screening, it takes 109 (0.33 -> 0.19 s). Taking more collapses a pass
# takes them further out of the greedy order, which in such a tail shows: screening from
# an acceptance of 0.5 (body_3 64 passes) made the engine parts' mean distance 9 % larger
# at 25 % and 10 %, from 0.1 3 %. Meshes whose passes never get that low (the shared
# organic meshes, fandisk, the Fox) are not screened and do not change. Nor is a run under
# a distance bound or painted limits: there the tail's rejections are mostly the bound's,
# which screening cannot catch, and screened it only took other collapses (the CAD
# engine's --max-error 1% 3%: 8,259 triangles at LOD1 instead of 8,053, 24.8 s instead
# of 20.8).
SCREEN_BELOW = 0.1
SCREEN_SHARE = COST_QUANTILE_MIN
# After this many passes in a row took nothing, a pass screens every candidate, not only
# its cheapest share: the run was crawling through them, the next few rejected each pass
# until none was left and the rules relaxed. On its own at 10 %, the engine's body_5 spent
# 140 of its 250 passes so (its screened share of a few dozen candidates, one or two
# rejected a pass), body_12 and body_17 as many: 248 -> 142 passes (0.163 -> 0.117 s),
# 238 -> 132 and 226 -> 91 (0.103 -> 0.055 s). After two such passes, screening everything
# also came in the tails of the largest parts, where a pass that takes nothing is the
# sliver floor's pause, not a crawl: body_3 took 123 passes for 109, body_8 93 for 88.
SCREEN_ALL_AFTER = 3
# In a run of several parts, a part with no candidate left relaxes the rules (one step) once
# the collapses taken elsewhere cost this many times the most its own ever cost
# (_part_held_back).
PART_HELD_BACK = 2.0
# Parts the target did not need are looked at again once the error has grown by this factor.
DROP_RECHECK_GROWTH = 1.25


@dataclass
class InputSlivers:
    """The input's triangle shapes, which the sliver rule measures against (core.slivers)."""

    quality: np.ndarray  # (run faces,) triangle quality of each input face, by face_origin
    worst: np.ndarray  # (n,) the worst input face merged into each vertex so far
    allowance: object  # the share of slivers the LOD may have (sliver_allowance); per part (parts,) in a run of several
    floor_off: object = False  # this pass: fewer slivers than the allowance, the floor is off (by part too)
    stalled: bool = False  # the last pass took nothing


@dataclass
class KeyOffsets:
    """Shape keys and sample poses in the error (core.shape_keys, core.skinning): offsets
    the merged vertex follows by interpolation, carried in columns of State.X."""

    quadrics: np.ndarray  # (K, n, 10) each key's quadrics
    columns: tuple  # slice of X holding each key's offsets
    index: np.ndarray  # (3K,) those columns of X, key by key
    weights: np.ndarray  # (K,) what each key's error counts (shape_keys.key_weights)
    scale: float  # offsets are in input units, positions normalised: this converts


@dataclass
class DistanceBound:
    """``max_error`` or painted limits in force (core.tracked_distance)."""

    tracker: TrackedDistance
    limit: float  # the bound, normalised units (inf: only painted limits)
    far_rejected: np.ndarray  # (edges,) int8: last rejected by the bound (BY_BOUND) or only by a painted limit (BY_LIMIT)
    limited: np.ndarray  # (n,) bool: vertices under a painted limit (their parts are never removed)

    @property
    def global_bound(self) -> bool:
        return bool(np.isfinite(self.limit))


BY_BOUND, BY_LIMIT = 1, 2  # DistanceBound.far_rejected


@dataclass
class State:
    """The mesh while it is being simplified. Vertex rows are never compacted during
    the run (removed vertices simply stop being referenced), so vertex stamps stay valid
    from pass to pass; per-edge memory (rejections, cost-cache slots) follows the edges
    through ``topology.after_collapses`` in ``_apply``."""

    V: np.ndarray
    Q: np.ndarray  # (n, 10) column-major: see quadrics.pair_sums
    area: np.ndarray
    F: np.ndarray
    face_origin: np.ndarray
    locked: np.ndarray  # (n,) locked by the artist
    complex: np.ndarray  # (n,) pinched or on an edge of 3+ faces (core.kinds.COMPLEX)
    corners: np.ndarray  # (n,) feature corners: locked while the rule feature_corners holds
    X: np.ndarray  # stacked vertex attributes (n, K)
    wedges: object  # core.wedges.Wedges of the corner attributes that make seams, or None
    touched: np.ndarray  # pass in which each vertex's neighbourhood last changed
    conn: object  # connectivity of F
    rejected_pass: np.ndarray  # (k,) per edge: pass of its last rejection, 0 never
    area_scale: float = 1.0
    cache: object = None  # core.selection.CostCache of the last pass's candidates, or None
    changed: object = None  # (n,) vertices whose quadric, position or kind changed
    kind: object = None  # last pass's vertex kinds (core.kinds)
    moved: object = None  # (n,) vertices that were ever given a new position
    face_count: object = None  # (n,) faces around each vertex (validation: no vertex loses its last)
    source_normals: object = None  # (run faces, 3) unit normal of every input face
    max_error_seen: float = 0.0
    ladder: tuple = ()  # core.guards.relaxation_ladder of this run
    guards: object = None  # the ladder step in force
    removed_components: int = 0
    copies: object = None  # (n,) how many times each vertex's part is drawn (Problem.copies), or None
    drop_at: float = np.inf  # the error (normalised) at which the smallest part that may go is smaller
    part: object = None  # (n,) the part of each vertex when several share the run (Options.vertex_part)
    part_cost: object = None  # (parts,) the largest RMS cost of a collapse taken in each part so far
    part_area_floor: object = None  # (parts,) rule no_degenerate_face's floor per part (validation.part_area_floors)
    corner_size: object = None  # (n,) a feature corner's distance to the nearest other corner (inf elsewhere)
    crawl: int = 0  # passes in a row that took less than CRAWL_SHARE of what the target needs
    bound_crawl: int = 0  # the same under a distance bound with every rule relaxed (_crawling_under_bound)
    idle: int = 0  # passes in a row that took nothing (SCREEN_ALL_AFTER)
    accepted_share: float = 1.0  # of the collapses the last pass's validation tried, the share it accepted
    face_quality: object = None  # (m,) each face's triangle_quality, kept up to date once asked (_face_quality)
    screening: bool = False  # the passes screen their candidates first (_screened), from the first that needed it on
    passed_screen: object = None  # (k,) per edge: pass in which it last passed the screening, 0 never
    surface_error: float = 0.0  # the largest RMS distance of a collapse to the rest surface's planes (normalised)
    slivers: object = None  # InputSlivers
    line_part: object = None  # (n, 10) column-major: the line quadrics' share of Q under a bound, else None
    plane_placement: bool = False  # Options.plane_placement (read where line_part is kept)
    cost_per_area: bool = True  # rank by mean squared distance; raw error without line quadrics
    keys: object = None  # KeyOffsets, when shape keys or sample poses are in the error
    bound: object = None  # DistanceBound, when max_error or painted limits bound the distance
    collapses: int = 0  # edge collapses applied so far
    seamless: object = None  # Wedges of Options.seamless_attributes (custom normals), or None
    close_holes: bool = False  # rule small_holes_stay relaxed (_unstick): holes of three edges may close
    heartbeat: Heartbeat = field(default_factory=lambda: Heartbeat(None))  # progress and cancelling (core.heartbeat)


def run(p: Problem) -> list:
    t_start = time.perf_counter()
    heartbeat = Heartbeat(p.progress)
    n = len(p.vertices)
    F = p.faces
    conn = topology.build(F, n) if p.connectivity is None else p.connectivity
    p.connectivity = None
    heartbeat.beat()
    face_normals, face_areas = face_frames(p.vertices, F)
    feature_edges, feature_weights, corners = _features(p, conn, face_normals, face_areas)
    heartbeat.beat()
    Q, area, line_part = vertex_quadrics.build(
        p.vertices, F, conn, p.line_weights, p.quadric_scale, p.options.boundary_weight,
        feature_edges, feature_weights, p.options.probabilistic_sigma, p.options.line_scale_exponent,
        line_part=True,
    )
    heartbeat.beat()
    # Vertices on non-manifold edges, or pinched (several fans), are left alone.
    complex_ = _non_manifold_vertices(conn, F, n)
    heartbeat.beat()
    names = list(p.vertex_attributes)
    X = np.concatenate([p.vertex_attributes[k] for k in names], axis=1) if names else np.zeros((n, 0))
    seamed = {k: a for k, a in p.corner_attributes.items() if k not in p.options.seamless_attributes}
    seamless = {k: a for k, a in p.corner_attributes.items() if k in p.options.seamless_attributes}
    # The UV rules (flips, areas) are the seamed maps': a seamless one (a map with an island
    # per face) is carried like custom normals, each side of a collapse its own values.
    wedges = Wedges.build(F, seamed, [a for a in p.options.uv_attributes if a in seamed]) if seamed else None
    s = State(
        V=p.vertices.copy(), Q=np.asfortranarray(Q), area=area, F=F, face_origin=p.face_origin, locked=p.locked, complex=complex_, corners=corners,
        X=X, wedges=wedges, touched=np.zeros(n, dtype=np.int64),
        conn=conn,
        corner_size=_corner_sizes(p.vertices, corners),
        rejected_pass=np.zeros(len(conn.edges), dtype=np.int64),
        changed=np.zeros(n, dtype=bool),
        moved=np.zeros(n, dtype=bool),
        face_count=np.bincount(F.ravel(), minlength=n),
        source_normals=_source_normals(p, face_normals),
        ladder=relaxation_ladder(p.options.min_quality),
    )
    s.guards = s.ladder[0]
    s.seamless = Wedges.build(F, seamless, ()) if seamless else None
    s.heartbeat = heartbeat
    s.copies = p.copies
    if p.options.vertex_part is not None:  # several parts in one run (core.assembly)
        s.part = np.asarray(p.options.vertex_part, dtype=np.int64)[p.vertex_origin]
        s.part_cost = np.zeros(int(s.part.max(initial=-1)) + 1)
        s.part_area_floor = validation.part_area_floors(s.V, s.part)
    # (Limits only grow along a chain: the first level's limited vertices are all there are.)
    limited = np.zeros(n, dtype=bool) if p.vertex_limits is None else np.isfinite(p.vertex_limits[0])
    if not limited.any():
        p.vertex_limits = None
    if p.max_error is not None or p.vertex_limits is not None:
        tracker = TrackedDistance(p.vertices, F, p.face_origin, p.run_faces,
                                  None if p.vertex_limits is None else p.vertex_limits[0],
                                  everywhere=p.max_error is not None)
        s.bound = DistanceBound(tracker, np.inf if p.max_error is None else p.max_error[0],
                                np.zeros(len(conn.edges), dtype=np.int8), limited)
    if s.bound is not None and line_part is not None:
        # Placement at an exact end and by the planes (core.selection.exact_end,
        # plane_optimum) reads the quadric without its line quadrics: under a bound only.
        s.line_part = np.asfortranarray(line_part)
        s.plane_placement = p.options.plane_placement
    del line_part
    if p.options.remove_small_components and (s.bound is None or not s.bound.global_bound):
        s.drop_at = components.smaller_than(s.F, s.V, _kept_parts(s), 0.0, 0)[2]
    if p.options.shape_attributes or p.pose_attributes:
        _shape_keys(s, p, names, X, area)
    input_quality = np.ones(p.run_faces)
    # A face core.stitching split is judged by the face it was split from: the fan's thin
    # triangles are no sliver of the input's, nor are their normals (nearly degenerate) a
    # reference for rule no_turn_over.
    input_quality[p.face_origin] = triangle_quality(s.V, s.F if p.unsplit_faces is None else p.unsplit_faces)
    s.slivers = InputSlivers(input_quality, slivers.worst_input_quality(s.F, n, input_quality[p.face_origin]),
                             slivers.sliver_allowance(input_quality[p.face_origin]) if s.part is None else
                             slivers.part_allowances(input_quality[p.face_origin], s.part[s.F[:, 0]], len(s.part_cost)))
    s.cost_per_area = bool(np.any(p.line_weights > 0)) or (p.quadric_scale is not None and bool(np.any(p.quadric_scale > 1)))
    s.area_scale = float(area.mean()) if n else 1.0

    # The passes own the faces and their connectivity from here (s.F and s.conn, rebuilt as
    # faces die), and the face frames were for the setup only. Holding any of them here
    # would keep it through the first pass, which on a large mesh is the run's peak of
    # memory (the 2M-face ogre: 1,546 -> 1,246 MB), and the first connectivity after it.
    del face_normals, face_areas, F, conn
    p.faces = None

    results = []
    start_faces = _drawn(s)
    final_target = p.targets[-1]
    passes = 0
    stop = STOP_TARGET
    level = 0
    while level < len(p.targets):
        target = p.targets[level]
        if _drawn(s) <= target or stop != STOP_TARGET:
            results.append(_snapshot(p, s, target, passes, time.perf_counter() - t_start, stop, names))
            level += 1
            if s.bound is not None and level < len(p.targets) and _loosen(s, p, level):
                if stop in (STOP_MAX_ERROR, STOP_LIMIT):  # (waiting edges may pass now)
                    stop = STOP_TARGET
            continue
        passes += 1
        before = _drawn(s)
        outcome = _one_pass(s, passes, target, p.options.seed, p.options.preserve_seams)
        if outcome is None and _crawling(s, before - _drawn(s), before - target):
            _relax(s)
        if outcome is None and _crawling_under_bound(s, before - _drawn(s), before):
            outcome = STOP_MAX_ERROR
        if outcome == STOP_TOPOLOGY:
            outcome = _unstick(s, p, target)
        if outcome is not None:
            stop = outcome
        heartbeat.report((start_faces - _drawn(s)) / max(start_faces - final_target, 1))
    return results


def _surface_errors(s: State, cand, chosen) -> np.ndarray:
    """(len(chosen),) the RMS distance (normalised) of each of the ``chosen`` collapses to
    the planes of the surface at rest: their cost without the shape keys' and poses'
    error, which would make a part that only moves in a key look farther than it is."""
    keep, remove = cand.keep[chosen], cand.remove[chosen]
    error = quadrics.evaluate(quadrics.pair_sums(s.Q, keep, remove), cand.position[chosen])
    error = error / np.maximum(s.area[keep] + s.area[remove], 1e-300)
    return np.sqrt(np.maximum(error, 0.0))


def _kept_parts(s: State) -> np.ndarray:
    """(n,) bool: vertices whose part may not be removed (locked, or under a painted limit)."""
    return s.locked if s.bound is None else s.locked | s.bound.limited


def _drop_smaller_than(s: State, target: int, size: float, at_least_one: bool = False) -> bool:
    """Drop the parts whose bounding-box diagonal is below ``size`` (normalised), as many
    as the target still needs (Options.remove_small_components, core.components.
    smaller_than): removed, such a part is no farther from the LOD than the collapse it
    spares would move the surface, and its triangles go to the rest. Returns whether any
    went; parts the target did not need are asked again once the error has grown."""
    faces, parts, smallest = components.smaller_than(s.F, s.V, _kept_parts(s), size, _drawn(s) - target,
                                                     None if s.copies is None else s.copies[s.F[:, 0]],
                                                     at_least_one)
    if faces is None:
        s.drop_at = max(smallest, size * DROP_RECHECK_GROWTH)
        return False
    s.drop_at = smallest
    _drop_faces(s, ~faces)
    s.removed_components += parts
    return True


def _drawn(s: State):
    """The faces left, as the targets count them: each as many times as its part is
    drawn (Options.part_copies)."""
    return len(s.F) if s.copies is None else int(round(float(s.copies[s.F[:, 0]].sum())))


def _removed_by(s: State, conn, cand, chosen) -> np.ndarray:
    """(k,) the faces each chosen collapse removes, as the targets count them."""
    edges = cand.edge[chosen]
    faces = conn.edge_faces[edges]
    return faces if s.copies is None else faces * s.copies[conn.edges[edges, 0]]


def _loosen(s: State, p: Problem, level: int) -> bool:
    """The next level's bounds, when larger (a chain: each level under its own): what the
    last ones rejected gets a new chance (and, as in _unstick, the pass may have found
    no candidate: no cost to reuse). Whether any bound grew."""
    grew = False
    if s.bound.global_bound and p.max_error[level] > s.bound.limit:
        s.bound.limit = p.max_error[level]
        grew = True
    if p.vertex_limits is not None and (p.vertex_limits[level] > p.vertex_limits[level - 1]).any():
        s.bound.tracker.set_limits(p.vertex_limits[level])
        grew = True
    if grew:
        _forget_rejections(s)
        s.bound_crawl = 0
    return grew


def _rejections_to_new_edges(s: State, old_ends: np.ndarray) -> None:
    """Connectivity built afresh (s.conn) after collapses that ``old_ends`` (k, 2) gives
    each old edge's ends after: each surviving edge keeps what was remembered of it
    (rejections, with the distance bound's kind), as the carried update does; merged or
    new edges start afresh, and no cached cost is reused. Forgetting every rejection at
    every pass made a part whose last collapses close holes (rule small_holes_stay
    relaxed) try its 400 rejected edges again after each collapse, 16 a pass: the
    engine's body_22 at 10 % took 817 passes."""
    rejected_pass = s.rejected_pass
    held = None if s.bound is None else s.bound.far_rejected.copy()
    _forget_rejections(s)
    n = np.int64(len(s.V))
    lo, hi = old_ends.min(axis=1), old_ends.max(axis=1)
    was = (rejected_pass > 0) & (lo != hi)
    if not was.any():
        return
    new_key = s.conn.edges[:, 0] * n + s.conn.edges[:, 1]
    at = index_of(new_key, (lo * n + hi)[was])
    found = at >= 0
    s.rejected_pass[found] = rejected_pass[was][at[found]]
    if held is not None:
        s.bound.far_rejected[found] = held[was][at[found]]


def _forget_rejections(s: State, keep_limits: bool = False):
    """Per-edge memory of the current connectivity, empty: every edge gets a new chance
    (after a rule relaxed or the bound grew, or when the edges were rebuilt), and no
    cached cost is reused. ``keep_limits``: a quality rule relaxed, which changes nothing
    for what a painted limit rejected (a collapse's position and distance do not depend
    on the rules): those stay rejected until their neighbourhood changes, or every pass
    after a relaxation would first reject them all again."""
    held = None
    if keep_limits and s.bound is not None and not s.bound.global_bound:
        held = np.flatnonzero(s.bound.far_rejected == BY_LIMIT)
    rejected_pass = s.rejected_pass
    s.rejected_pass = np.zeros(len(s.conn.edges), dtype=np.int64)
    s.passed_screen = None
    s.cache = None
    if s.bound is not None:
        s.bound.far_rejected = np.zeros(len(s.conn.edges), dtype=np.int8)
        if held is not None and len(held):
            s.rejected_pass[held] = rejected_pass[held]
            s.bound.far_rejected[held] = BY_LIMIT


def _distance_blocks(s: State):
    """The stop reason when an edge the distance bound rejected is still waiting (its
    neighbourhood unchanged since), else None: then the bound, not a quality rule, is
    what stops the run: STOP_LIMIT where painted limits hold back most of the waiting
    edges (no larger max_error would let those pass), else STOP_MAX_ERROR."""
    far = np.flatnonzero(s.bound.far_rejected)
    if len(far) == 0:
        return None
    ends = s.conn.edges[far]
    waiting = far[selection.still_rejected(s, far, ends[:, 0], ends[:, 1])]
    if len(waiting) == 0:
        return None
    by_limit = int(np.count_nonzero(s.bound.far_rejected[waiting] == BY_LIMIT))
    return STOP_LIMIT if 2 * by_limit >= len(waiting) else STOP_MAX_ERROR


def _shape_keys(s: State, p: Problem, names, X, area):
    """Put the strongest shape keys and every sample pose in the error (core.shape_keys,
    core.skinning): both are offsets the merged vertex follows by interpolation."""
    starts = np.cumsum([0] + [p.vertex_attributes[k].shape[1] for k in names])

    def columns(group):
        return [slice(starts[names.index(k)], starts[names.index(k)] + 3) for k in group]
    scale = 1.0 / p.scale
    key_columns, pose_columns = columns(p.options.shape_attributes), columns(p.pose_attributes)
    if key_columns:
        offsets = np.stack([X[:, c] for c in key_columns]) * scale
        key_columns = [key_columns[i] for i in shape_keys.strongest(offsets, area)]
    all_columns = tuple(key_columns + pose_columns)
    offsets = np.stack([X[:, c] for c in all_columns]) * scale
    key_quadrics = shape_keys.vertex_quadrics(s.V, s.F, offsets)
    if p.quadric_scale is not None:
        # Importance scales a vertex's whole error (Sec. 4.4.1): its planes in every key's
        # shape as at rest, or a region the keys move, where the keys' error sets the cost,
        # would hardly feel it.
        key_quadrics *= p.quadric_scale[None, :, None]
        if key_columns and p.options.key_scale_exponent != 1.0:
            # The keys' own weight where the importance is (Options.key_scale_exponent).
            key_quadrics[:len(key_columns)] *= (p.quadric_scale ** (p.options.key_scale_exponent - 1.0))[None, :, None]
    s.keys = KeyOffsets(
        quadrics=key_quadrics,
        columns=all_columns,
        index=np.concatenate([np.arange(c.start, c.stop) for c in all_columns]),
        weights=shape_keys.key_weights(len(key_columns), len(pose_columns), p.options.pose_weight),
        scale=scale,
    )


def _part_held_back(s: State, cand, chosen, rms) -> bool:
    """Several parts in one run: whether a part that has no candidate left under the rules
    in force (the rest of the run goes on) would, alone, have had its rules relaxed by now:
    this pass's collapses cost more than PART_HELD_BACK times the most its own collapses
    ever cost. One run relaxes its rules only once no part has a candidate; run alone, a
    part relaxes as soon as it has none. Without this, the parts that still had valid but
    costly collapses paid for the held-back ones (a six-part character's torso went from
    31 to 10 triangles while its arms, waiting for the loosest step, kept 28). Also
    records what each part's collapses cost when the pass goes ahead."""
    if s.guards.step + 1 < len(s.ladder):
        parts = len(s.part_cost)
        alive = np.bincount(s.part[s.F[:, 0]], minlength=parts) > 0
        waiting = alive & (np.bincount(s.part[cand.keep], minlength=parts) == 0) & (s.part_cost > 0)
        if np.any(waiting & (float(rms[chosen].max()) > PART_HELD_BACK * s.part_cost)):
            return True
    np.maximum.at(s.part_cost, s.part[cand.keep[chosen]], rms[chosen])
    return False


def _crawling(s: State, removed: int, needed: int) -> bool:
    """Whether the passes have been crawling: CRAWL_PASSES in a row, each taking less than
    CRAWL_SHARE of what the target still needs (at least CRAWL_MIN_NEED), while a looser
    step of the rules is left."""
    if s.guards.step + 1 >= len(s.ladder) or needed < CRAWL_MIN_NEED or removed >= CRAWL_SHARE * needed:
        s.crawl = 0
        return False
    s.crawl += 1
    return s.crawl >= CRAWL_PASSES


def _crawling_under_bound(s: State, removed: int, faces: int) -> bool:
    """Under max_error with every rule relaxed: whether BOUND_CRAWL_PASSES passes in a row
    each took fewer than BOUND_CRAWL_SHARE of the faces left, which ends the level (at most
    that share times those passes above where the crawl would have ended). In the tail of
    a tight bound nearly every collapse the passes try is beyond it, and each pass
    measures a new batch of them: the CAD engine at 0.065 % of its size spent 30 passes of
    150 ms on its last 1 % of faces, and 50 on 3.5 % at 0.26 %."""
    if s.bound is None or not s.bound.global_bound or s.guards.step + 1 < len(s.ladder):
        return False
    if removed >= BOUND_CRAWL_SHARE * faces:
        s.bound_crawl = 0
        return False
    s.bound_crawl += 1
    return s.bound_crawl >= BOUND_CRAWL_PASSES


def _corner_sizes(vertices, corners) -> np.ndarray:
    """(n,) each feature corner's distance to the nearest other corner (its feature's
    size, core.features.nearest_other), inf for the other vertices."""
    size = np.full(len(vertices), np.inf)
    if corners.any():
        size[corners] = features.nearest_other(vertices[corners])
    return size


def _release_small_corners(s: State, target: int) -> None:
    """Feature corners stay put (rule feature_corners) while they are at most
    CORNER_SHARE of the vertices the level will have (a closed mesh has about half as
    many vertices as faces). Once they crowd it, those nearer to another corner than
    CORNER_SIZE_SHARE times the largest collapse distance so far move like other vertices:
    their feature (a bolt hole's rim, a coarse cylinder's facets) is below what the LOD
    resolves, as a part smaller than the error may go (_drop_smaller_than), and held they
    spent the level on themselves. A polygon whose LOD is its corners keeps them: they are
    far apart. A true corner's quadric (three planes) still holds it where it is."""
    if s.max_error_seen <= 0 or not s.corners.any():
        return
    alive = s.corners & (s.face_count > 0)
    if np.count_nonzero(alive) <= CORNER_SHARE * 0.5 * target:
        return
    small = alive & (s.corner_size < CORNER_SIZE_SHARE * s.max_error_seen)
    if small.any():
        s.corners = s.corners & ~small


def _relax(s: State) -> None:
    """The quality rules one step looser (core.guards.relaxation_ladder); edges the stricter
    step rejected get a new chance."""
    s.guards = s.ladder[s.guards.step + 1]
    s.crawl = 0
    _forget_rejections(s, keep_limits=True)


def _unstick(s: State, p: Problem, target: int):
    """Nothing passes the rules in force: relax the quality rules one step, or (when the
    artist allows it and every rule is already relaxed) drop the smallest parts the
    target cannot keep. Returns None to go on, or STOP_TOPOLOGY."""
    if s.guards.step + 1 < len(s.ladder):
        # (The cost cache of a pass that found no candidate has nothing to reuse.)
        _relax(s)
        return None
    # Rule small_holes_stay, last: a hole of three border edges closes by collapsing one of
    # them (core.validation). Blender's Decimate closes them too; a CAD part's cracks and
    # pin holes end as such triangles, and each holds three vertices on the border (a
    # 1,654-triangle engine part, body_12, stopped at 279 for 165 with 45 holes, 35 of
    # them down to three edges). Only here, so no run that reaches its target changes.
    if not s.close_holes and topology.has_triangular_holes(s.conn):
        s.close_holes = True
        _forget_rejections(s, keep_limits=True)
        return None
    # A removed part is as far from the LOD as can be: not under max_error, nor where a
    # painted limit holds.
    if p.options.remove_small_components and (s.bound is None or not s.bound.global_bound):
        dropped = components.smallest_to_drop(s.F, s.V, _kept_parts(s), _drawn(s) - target,
                                              None if s.copies is None else s.copies[s.F[:, 0]])
        if dropped is not None:
            faces, parts = dropped
            _drop_faces(s, ~faces)
            s.removed_components += parts
            return None
    # Under painted limits the rules relax as for a count target; once nothing is left to
    # relax, a limit that still holds an edge back is what stops the run.
    if s.bound is not None:
        return _distance_blocks(s) or STOP_TOPOLOGY
    return STOP_TOPOLOGY


def _one_pass(s: State, pass_no: int, target: int, seed, preserve_seams):
    """One pass; returns a stop reason when nothing more can be collapsed, else None."""
    n = len(s.V)
    conn = s.conn
    _release_small_corners(s, target)
    kind = _classify(s, conn, n, preserve_seams)
    if s.kind is not None:
        s.changed |= kind != s.kind
    s.kind = kind
    cand = selection.candidates(s, conn, kind, pass_no)
    s.heartbeat.beat()
    if len(cand.edge) == 0:
        # What is left was rejected. Where the distance bound still holds an edge back, it
        # is what stops the run: relaxing the quality rules would only buy slivers under
        # the same bound. Otherwise the rules relax (_unstick) as for a face target.
        # (Painted limits alone hold back only their regions: the rules relax elsewhere,
        # and _unstick says STOP_LIMIT once nothing is left to relax.)
        if s.bound is not None and s.bound.global_bound:
            return _distance_blocks(s) or STOP_TOPOLOGY
        return STOP_TOPOLOGY
    # The floor is off while the LOD has fewer slivers than its input's share, and for a
    # pass after one that took nothing: a LOD that hovers at the share would otherwise
    # crawl on a few collapses a pass (a CAD part took 590 passes for its last 250 faces).
    s.slivers.floor_off = _sliver_floor_off(s)
    s.screening |= s.accepted_share < SCREEN_BELOW and s.bound is None
    failed = _screened(s, conn, cand, pass_no) if s.screening else None
    mean_sq = cand.cost if s.cost_per_area else cand.cost / np.maximum(s.area[cand.keep] + s.area[cand.remove], 1e-300)
    cand = _input_slivers_first(s, conn, cand)
    drawn = _drawn(s)
    share = min(max(0.5 * (drawn - target) / drawn, COST_QUANTILE_MIN), COST_QUANTILE_MAX)
    if s.slivers.stalled and s.bound is not None and not s.bound.global_bound:
        # A pass that took nothing under painted limits: every candidate may go, in
        # every round, or the passes crawl through the few cheapest around the last
        # change, each rejected in turn (a sphere half painted: 1,346 passes).
        share = 1.0
    chosen = _choose(s, conn, cand, n, seed, pass_no, share, failed)
    # Stop exactly at the target: only the cheapest collapses the target still needs.
    need = drawn - target
    removed = _removed_by(s, conn, cand, chosen)
    if removed.sum() > need:
        order = np.argsort(cand.cost[chosen], kind="stable")
        chosen = chosen[order]
        upto = int(np.searchsorted(np.cumsum(removed[order]), need, side="left")) + 1
        chosen = chosen[:upto]
    s.slivers.stalled = len(chosen) == 0
    s.idle = s.idle + 1 if s.slivers.stalled else 0
    if len(chosen):
        if s.part is not None and _part_held_back(s, cand, chosen, np.sqrt(mean_sq)):
            _relax(s)
            return None
        if s.drop_at < np.inf:
            errors = _surface_errors(s, cand, chosen)
            largest = float(errors.max())
            # A part smaller than what this pass would cost goes first (when the target
            # needs it): its removal is the cheaper step; the pass is then chosen again.
            # When even the pass's cheapest collapse costs more, the part goes even if
            # the level ends under its budget by the part's triangles.
            if largest * DROP_SIZE_SHARE >= s.drop_at and _drop_smaller_than(
                    s, target, largest * DROP_SIZE_SHARE, float(errors.min()) * DROP_SIZE_SHARE >= s.drop_at):
                return None
            s.surface_error = max(s.surface_error, largest)
        s.max_error_seen = max(s.max_error_seen, float(np.sqrt(mean_sq[chosen].max())))
        if s.bound is not None:
            s.bound.tracker.commit(cand.edge[chosen])
        _apply(s, conn, cand, chosen, pass_no)
    return None


def _screened(s: State, conn, cand, pass_no):
    """(len(cand.edge),) bool: the candidates among the cheapest SCREEN_SHARE (all of them
    after SCREEN_ALL_AFTER passes that took nothing) that validation.screened rejects
    (remembered as rejected, like any other: they wait for their neighbourhood to
    change); the pass does not choose them. They still count in
    the share of the candidates a pass may take (_choose), so that the pass takes the
    collapses it would have taken had it tried them in turn. (Tried first: the share
    taken of what the screening left, which ran far up the costs in a CAD part's tail,
    body_3 at 10 % 2.6x the Hausdorff distance.) One that passed is screened again only
    once its neighbourhood changed. Runs under a distance bound are not screened
    (SCREEN_BELOW), so nothing here is the bound's rejection."""
    if s.passed_screen is None:
        s.passed_screen = np.zeros(len(conn.edges), dtype=np.int64)
    if s.idle >= SCREEN_ALL_AFTER:
        tried = np.arange(len(cand.edge))
    else:
        limit = _cost_quantiles(cand.cost, (SCREEN_SHARE,))[0]
        tried = np.flatnonzero(cand.cost <= limit)
    last_change = np.maximum(s.touched[cand.keep[tried]], s.touched[cand.remove[tried]])
    tried = tried[last_change >= s.passed_screen[cand.edge[tried]]]
    ok = validation.screened(s, conn, cand, tried)
    s.passed_screen[cand.edge[tried[ok]]] = pass_no
    failed = np.zeros(len(cand.edge), dtype=bool)
    failed[tried[~ok]] = True
    _remember_rejections(s, conn, cand, tried[~ok], pass_no)
    return failed


def _sliver_floor_off(s: State):
    """InputSlivers.floor_off for this pass: a sliver-rich input (or, in a run of several,
    each sliver-rich part: an array by part) may make slivers while it has fewer than its
    allowance, or after a pass that took nothing."""
    allowance = s.slivers.allowance
    if np.ndim(allowance) == 0:
        return allowance > 0 and (s.slivers.stalled or slivers.within_allowance(_face_quality(s), allowance))
    if not allowance.any():
        return False
    within = slivers.parts_within_allowance(_face_quality(s), s.part[s.F[:, 0]], allowance)
    return (allowance > 0) & (s.slivers.stalled | within)


def _face_quality(s: State) -> np.ndarray:
    """(m,) the quality of every face of s.F. Computed once, then kept up to date by
    _apply for the faces around the moved vertices only: a sliver-rich run counts its
    slivers every pass, and measuring all its faces each time was 0.07 s of the CAD
    engine's 0.9 s run (55 passes)."""
    if s.face_quality is None:
        s.face_quality = triangle_quality(s.V, s.F)
    return s.face_quality


def _input_slivers_first(s: State, conn, cand):
    """``cand`` with the input's slivers ranked first (slivers.ranked_first) where they are
    faults: in an input, or a part of a run of several, that is not sliver-rich (in one
    that is they are its shape)."""
    allowance = s.slivers.allowance
    if np.ndim(allowance) == 0:
        if allowance:
            return cand
        return slivers.ranked_first(s.V, s.F, s.face_origin, s.slivers.quality, s.guards.min_quality, conn, cand)
    if allowance.all():
        return cand
    ranked = slivers.ranked_first(s.V, s.F, s.face_origin, s.slivers.quality, s.guards.min_quality, conn, cand)
    if ranked is cand or not allowance.any():
        return ranked
    plain = allowance[s.part[cand.keep]] == 0
    cost = np.where(plain, ranked.cost, cand.cost)
    return selection.Candidates(cand.edge, cand.keep, cand.remove, cand.position, cost)


def _features(p: Problem, conn, face_normals, face_areas) -> tuple:
    """The given feature edges plus the creases sharper than ``feature_angle`` (each
    edge once, the given weight winning), their weights, and the (n,) corners: where
    three or more of them meet, and where an open boundary has a corner (features.boundary_corners)."""
    edges, weights = p.feature_edges, p.feature_edge_weights
    if p.options.feature_angle:
        crease = conn.edges[features.crease_edges(face_normals, conn, p.options.feature_angle)]
        given = np.sort(edges, axis=1) if len(edges) else edges
        n = len(p.vertices)
        new = ~np.isin(crease[:, 0] * np.int64(n) + crease[:, 1], given[:, 0] * np.int64(n) + given[:, 1]) \
            if len(given) else np.ones(len(crease), dtype=bool)
        edges = np.concatenate([edges.reshape(-1, 2), crease[new]])
        weights = np.concatenate([weights, np.full(int(new.sum()), p.options.feature_weight)])
        corners = features.corners(edges, n) | features.boundary_corners(
            p.vertices, p.faces, face_normals, face_areas, conn, p.options.feature_angle)
        return edges, weights, corners
    return edges, weights, np.zeros(len(p.vertices), dtype=bool)


def _source_normals(p: Problem, face_normals) -> np.ndarray:
    """Unit normals of the input faces, indexed like face_origin."""
    normals = np.zeros((p.run_faces, 3))
    normals[p.face_origin] = face_normals if p.unsplit_faces is None else face_frames(p.vertices, p.unsplit_faces)[0]
    return normals


def _choose(s: State, conn, cand, n, seed, pass_no, share, failed=None) -> np.ndarray:
    """Valid, mutually independent collapses for this pass.

    Several selection rounds: each takes the local minima among candidates whose ends lie
    outside the closed one-rings of the collapses already taken, so later rounds never
    interfere with earlier ones and one connectivity update serves many more collapses.
    """
    taken = []
    # Greedy order, approximately: only the cheapest share of candidates may go this
    # pass, so costly regions wait for later passes as they would in a sequential queue.
    # Edges a painted limit rejected stay candidates but do not set the share: in a run
    # held back in its painted regions they are the cheapest, and would otherwise take
    # the pass from the free regions, a few collapses a pass (a quarter of a sphere
    # painted: 89 passes for 31).
    ranked = cand.cost
    free = None
    if s.bound is not None:
        free = s.bound.far_rejected[cand.edge] != BY_LIMIT
        if free.all() or not free.any():
            free = None
        else:
            ranked = cand.cost[free]
    pass_limit, later_limit = _cost_quantiles(ranked, (share, share * LATER_ROUND_SHARE if share < 1 else 1.0))
    eligible = cand.cost <= pass_limit
    if failed is not None:
        eligible &= ~failed
    if free is not None:
        eligible &= free
    window = None  # later rounds look only at the faces around what is still eligible
    # Faces the pass's collapses take from the corners opposite their edges.
    faces_taken = np.zeros(n, dtype=s.face_count.dtype)
    rounds = SELECTION_ROUNDS
    if free is not None or (share >= 1.0 and s.bound is not None):
        # Under painted limits the free candidates can be a handful around the last
        # change, one independent per round: more (cheap, windowed) rounds rather than
        # a pass each (a sphere half painted took 566 passes for one level, 195 this way).
        rounds = LIMITED_SELECTION_ROUNDS
    tried = tried_ok = 0
    for round_no in range(rounds):
        chosen = selection.independent_set(cand, conn, n, seed, eligible)
        if len(chosen) == 0:
            break
        # Count every chosen collapse's losses first (a pinched vertex can be opposite
        # several), then give back those of the rejected ones.
        opposite = validation.opposite_corners(s.F, conn, cand.edge[chosen])
        has1 = opposite[1] >= 0
        corners = np.concatenate([opposite[0], opposite[1].compress(has1)])
        np.add.at(faces_taken, corners, 1)
        ok = validation.valid_collapses(s, conn, cand, chosen, opposite, faces_taken, window)
        np.subtract.at(faces_taken, corners.compress(~np.concatenate([ok, ok.compress(has1)])), 1)
        _remember_rejections(s, conn, cand, chosen[~ok], pass_no)
        tried, tried_ok = tried + len(chosen), tried_ok + int(ok.sum())
        s.heartbeat.beat()
        eligible[chosen] = False
        chosen = chosen[ok]
        taken.append(chosen)
        if round_no == 0:
            # The raw error of a collapse is its mean squared distance times about two
            # vertex areas.
            order_free = ORDER_FREE_COST if s.cost_per_area else ORDER_FREE_COST * 2.0 * s.area_scale
            eligible &= cand.cost <= max(later_limit, order_free)
        if len(chosen) == 0:
            continue
        faces = s.F if window is None else window[1]
        blocked = selection.closed_rings(conn, faces, np.concatenate([cand.keep[chosen], cand.remove[chosen]]), n)
        eligible &= ~(blocked[cand.keep] | blocked[cand.remove])
        if not eligible.any():
            break
        if window is None:
            window = _faces_around(s.F, np.concatenate([cand.keep[eligible], cand.remove[eligible]]), n)
    s.accepted_share = tried_ok / tried if tried else 1.0
    return np.concatenate(taken) if taken else np.zeros(0, dtype=np.int64)


def _faces_around(F, vertices, n) -> tuple:
    """(face ids, their rows of F): the faces with a corner among ``vertices``."""
    ids = np.flatnonzero(topology.faces_touching(F, vertices, n))
    return ids, F[ids]


def _cost_quantiles(cost: np.ndarray, shares) -> list:
    """The costs below which the given shares (each in [0, 1]) of ``cost`` (k,) lie, from
    one partial sort."""
    last = len(cost) - 1
    ranks = [int(share * last) for share in shares]
    ordered = np.partition(cost, sorted(set(ranks)))
    return [ordered[r] for r in ranks]


def _non_manifold_vertices(conn, F, n) -> np.ndarray:
    """(n,) bool: vertices on a non-manifold edge, or pinched (more than one fan)."""
    bad = topology.fans_per_vertex(conn, F, n) > 1
    bad[conn.edges[conn.edge_faces > 2].ravel()] = True
    return bad


def _classify(s: State, conn, n, preserve_seams) -> np.ndarray:
    """Every vertex's kind (core.kinds) under the rules in force (rules seams and
    feature_corners, core.guards)."""
    locked = s.locked | s.corners if s.guards.corners_kept else s.locked
    kind = np.where(locked, kinds.LOCKED,
                    np.where(s.complex, kinds.COMPLEX,
                             np.where(conn.border_vertex, kinds.BORDER, kinds.FREE))).astype(np.int8)
    if s.wedges is not None and preserve_seams and s.guards.seams != "free":
        # (A UV pole's web of seams, which fades out within its island, is none: core.uv_poles.)
        change = uv_poles.pole_web_changes(conn.edges, s.wedges.value_changes(s.F, conn), n, conn.border_vertex)
        seam_edge = change.any(axis=1)
        # A vertex is on a seam where its own values change (core.wedges.value_changes),
        # as meshoptimizer classifies by a vertex's wedges: the ring around a pole whose
        # triangles each have their own UV ends every pole edge's seam but is continuous
        # itself. Counted by edge end, it was a seam end, locked: ten UV spheres stayed at
        # about 270 of their 960 triangles under the strict rules while the asset they
        # were part of took its 12.5 % level from a subdivided cube (34 of its 12,288
        # triangles kept; 1,126 now).
        seam_count = np.bincount(conn.edges[change], minlength=n)
        on_seam = seam_count > 0
        kind[on_seam & (kind <= kinds.BORDER)] = kinds.SEAM
        # Seam ends and junctions stay put so the seam keeps its shape and its corners,
        # until the rule relaxes to let them slide along one of their seams.
        if s.guards.seams == "kept":
            kind[on_seam & (seam_count != 2)] = kinds.LOCKED
        conn.seam_edge = seam_edge
    else:
        conn.seam_edge = np.zeros(len(conn.edges), dtype=bool)
    return kind


def _remember_rejections(s: State, conn, cand, rejected, pass_no):
    """Invalid collapses are skipped until their neighbourhood changes, so one bad edge
    does not block its neighbourhood pass after pass; the distance bound's rejections
    are also marked as such (_distance_blocks)."""
    if len(rejected) == 0:
        return
    s.rejected_pass[cand.edge[rejected]] = pass_no
    if s.bound is not None:
        edge = cand.edge[rejected]
        s.bound.far_rejected[edge] = np.where(np.isin(edge, s.bound.tracker.rejected_edges),
                                              np.where(np.isin(edge, s.bound.tracker.limit_rejected), BY_LIMIT, BY_BOUND),
                                              0)


def _apply(s: State, conn, cand, chosen, pass_no):
    keep, remove, pos = cand.keep[chosen], cand.remove[chosen], cand.position[chosen]
    s.collapses += len(chosen)
    t = edge_parameter(rows(s.V, keep), rows(s.V, remove), pos)
    if s.X.shape[1]:
        s.X[keep] += t[:, None] * (s.X[remove] - s.X[keep])
    for corner_data in _corner_data(s):
        corner_data.collapse(s.F, conn, cand.edge[chosen], keep, remove, t)
    s.changed = np.zeros(len(s.V), dtype=bool)
    s.changed[keep] = True
    s.moved[keep] |= np.any(pos != s.V[keep], axis=1)
    s.V[keep] = pos
    quadrics.merge_rows(s.Q, keep, remove)
    if s.line_part is not None:
        quadrics.merge_rows(s.line_part, keep, remove)
    if s.keys is not None:
        s.keys.quadrics[:, keep] += s.keys.quadrics[:, remove]
    s.area[keep] += s.area[remove]
    s.slivers.worst[keep] = np.minimum(s.slivers.worst[keep], s.slivers.worst[remove])
    remap = np.arange(len(s.V))
    remap[remove] = keep
    F = remap[s.F]
    alive = (F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])
    # The faces that die (those on the collapsed edges) each take a face from their corners.
    np.subtract.at(s.face_count, np.compress(~alive, s.F, axis=0).ravel(), 1)
    s.face_count[keep] += s.face_count[remove]
    s.face_count[remove] = 0
    s.F = np.compress(alive, F, axis=0)  # 4x faster than F[alive] on rows
    s.face_origin = s.face_origin.compress(alive)
    # Closing a hole merges two border edges that no dying face names, which the carried
    # update does not do (rare: only once every rule is relaxed): the connectivity is built
    # afresh then, and what is remembered of each edge is carried over by its ends.
    carried = None if s.close_holes else topology.after_collapses(conn, alive, remap, remove)
    if carried is None:  # if the collapses were not independent, or holes may close: start afresh
        s.conn = topology.build(s.F, len(s.V))
        _rejections_to_new_edges(s, remap[conn.edges])
    else:
        s.conn, surviving_edges = carried
        s.rejected_pass = s.rejected_pass.compress(surviving_edges)
        if s.passed_screen is not None:
            s.passed_screen = s.passed_screen.compress(surviving_edges)
        if s.cache is not None:
            s.cache.slot = s.cache.slot.compress(surviving_edges)
        if s.bound is not None:
            s.bound.far_rejected = s.bound.far_rejected.compress(surviving_edges)
    for corner_data in _corner_data(s):
        corner_data.keep_faces(alive)
    around = topology.faces_touching(s.F, keep, len(s.V))
    s.touched[np.compress(around, s.F, axis=0).ravel()] = pass_no
    if s.face_quality is not None:
        # (Only the faces around a kept vertex moved; the others' quality is as it was.)
        s.face_quality = s.face_quality.compress(alive)
        s.face_quality[around] = triangle_quality(s.V, np.compress(around, s.F, axis=0))


def _corner_data(s: State) -> list:
    """The corner data the run carries: the wedges that make seams and the seamless ones
    (Options.seamless_attributes), those there are."""
    return [w for w in (s.wedges, s.seamless) if w is not None]


def _drop_faces(s: State, alive):
    """Delete the faces not ``alive`` (whole parts): their vertices stop being used."""
    np.subtract.at(s.face_count, np.compress(~alive, s.F, axis=0).ravel(), 1)
    s.F = np.compress(alive, s.F, axis=0)
    s.face_origin = s.face_origin.compress(alive)
    if s.face_quality is not None:
        s.face_quality = s.face_quality.compress(alive)
    for corner_data in _corner_data(s):
        corner_data.keep_faces(alive)
    s.conn = topology.build(s.F, len(s.V))
    _forget_rejections(s)


def _snapshot(p: Problem, s: State, target, passes, seconds, stop, names) -> SimplifyResult:
    """Compact copy of the current mesh in input units, as one LOD level, in the input's
    order (core.locality may have renumbered the mesh for the run)."""
    used = np.zeros(len(s.V), dtype=bool)
    used[s.F.ravel()] = True
    kept = np.flatnonzero(used)
    face_order = None
    if p.renumbered:
        kept = kept[np.argsort(p.vertex_origin[kept])]
        face_order = np.argsort(s.face_origin)
    new_index = np.empty(len(s.V), dtype=np.int64)
    new_index[kept] = np.arange(len(kept))
    # Unmoved vertices (locked ones among them) come back exactly as given, not through
    # the normalisation round trip.
    vertices = np.where(s.moved[kept, None], s.V[kept] * p.scale + p.center, p.input_positions[kept])
    faces = new_index[s.F if face_order is None else s.F[face_order]]
    face_origin = s.face_origin.copy() if face_order is None else s.face_origin[face_order]
    # Faces core.orientation turned over for the run get their input winding back.
    turned = None if p.flipped_origin is None else p.flipped_origin[face_origin]
    if turned is not None:
        faces[turned] = faces[turned][:, [0, 2, 1]]
    if p.face_source is not None:  # faces core.stitching split descend from the face they split
        face_origin = p.face_source[face_origin]
    vattrs = {}
    col = 0
    for name in names:
        k = p.vertex_attributes[name].shape[1]
        vals = s.X[kept, col:col + k].copy()
        col += k
        if name in p.pose_attributes:  # in the error only, not carried
            continue
        if name in p.options.normalize_attributes:
            vals = _renormalise(vals, p.vertex_attributes[name][kept])
        vattrs[name] = vals
    cattrs = {}
    for corner_data in _corner_data(s):
        cattrs.update(corner_data.corner_values())
    if face_order is not None:
        cattrs = {k: a[face_order] for k, a in cattrs.items()}
    if turned is not None:
        for values in cattrs.values():
            values[turned] = values[turned][:, [0, 2, 1]]
    stats = SimplifyStats(
        input_vertices=p.input_vertices,
        input_faces=p.input_faces,
        output_vertices=len(kept),
        output_faces=len(faces),
        target_faces=target,
        passes=passes,
        seconds=seconds,
        stop_reason=stop if _drawn(s) > target else STOP_TARGET,
        max_error=(s.bound.tracker.largest() if s.bound is not None and s.bound.global_bound
                   else s.max_error_seen) * p.scale,
        welded_vertices=p.welded,
        relaxation_step=s.guards.step,
        removed_components=s.removed_components,
        collapses=s.collapses,
    )
    return SimplifyResult(
        vertices=vertices,
        faces=faces,
        face_origin=face_origin,
        vertex_origin=p.vertex_origin[kept],
        stats=stats,
        vertex_attributes=vattrs,
        corner_attributes=cattrs,
    )


def _renormalise(values, original_rows):
    """Rows whose input summed to one (skin weights) sum to one again, exactly."""
    sums = values.sum(axis=1)
    was_unit = np.abs(original_rows.sum(axis=1) - 1.0) < 1e-6
    fix = was_unit & (sums > 0)
    values[fix] /= sums[fix, None]
    return values
