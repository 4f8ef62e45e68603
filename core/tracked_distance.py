"""A measured bound on how far the LOD is from its source, kept collapse by collapse.

``max_error`` promises a distance an artist can check (issue 22), not a quadric's
area-weighted RMS, so when it is given every collapse is also measured:

- Source to LOD. Tracked points, every input vertex and the midpoints of every input
  face's edges, each belong to one live face (named by the input face that face descends
  from, an id that survives the engine's compaction), and carry an upper bound on their
  distance to it. A collapse replaces the faces around its two ends (the old fan) with
  the faces around the new vertex (the new fan), over the same patch of surface.
- LOD to source. Every live face, and every vertex that moved, carries an upper bound
  on its distance to the source.

A face one of whose corners moves by m moves none of its points by more than m, so a
collapse first adds m to the bounds it touches; only where a bound then passes
CLOSE_ENOUGH of the limit is it measured: points against the new faces (and moved to
the nearest), the new vertex and points of the new faces (centroid, new edges'
midpoints) against the input triangles under the old fan. A collapse that takes any of
them beyond the limit is rejected. The vertices' bounds are sure; the points are the
tracked ones, and a face's bound is its sampled points', so the two-sided Hausdorff
distance addon/pure/measure.py samples over the areas can come out somewhat above the limit
(up to 1.44x on the meshes measured); callers that must be sure measure the result.

All in the engine's normalised units (unit bounding-box diagonal). Every collapse is
measured near the limit, so this is for deviation targets, not for every run.
"""
from __future__ import annotations

import numpy as np

from .geometry import closest_on_triangles, rows


# Points inside each input face: a barycentric grid of this many steps a side, corners
# left out (the vertices are tracked once each). 2, the edges' midpoints: against 3 (7
# points a face) the sampled distance came out as close to the bound (1.17-1.44x against
# 1.19-1.41x on the Fox and homer at 0.05-1 %), a third faster.
FACE_GRID = 2
LIMIT_GRID = 3  # painted limits: a finer grid (7 points a face; docs/method.md#painted-limits)
# Bounds under this share of the limit are trusted as they are; above it they are
# measured (and a point farther than it from the face its face becomes looks for the
# nearest new face).
CLOSE_ENOUGH = 0.8


def _barycentric_grid(steps: int) -> np.ndarray:
    """(g, 3) barycentric coordinates of a triangle grid with ``steps`` a side, without
    the three corners."""
    ij = [(i, j) for i in range(steps + 1) for j in range(steps + 1 - i)]
    grid = np.array([(steps - i - j, i, j) for i, j in ij], dtype=float) / steps
    return grid[grid.max(axis=1) < 1.0]


class TrackedDistance:
    """Points of the source on the LOD's faces; see the module docstring.

    vertices (n, 3), faces (m, 3) and face_ids (m,): the prepared input (normalised) and
    the input face id of each row, as the engine's face_origin starts; input_faces: the
    number of input face ids."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, face_ids: np.ndarray, input_faces: int,
                 vertex_limits=None, everywhere: bool = True):
        m = len(faces)
        self.triangles = np.zeros((input_faces, 3, 3))
        self.triangles[face_ids] = vertices[faces]
        used = np.zeros(len(vertices), dtype=bool)
        used[faces.ravel()] = True
        vertex_points = np.flatnonzero(used)
        # Each used vertex starts on one of its faces (any will do: it lies on all of them).
        first_face = np.full(len(vertices), -1, dtype=np.int64)
        first_face[faces.ravel()[::-1]] = np.repeat(np.arange(m), 3)[::-1]
        # Inside the faces, a barycentric grid: the distance to the LOD can peak between
        # the corners (on the Fox at 0.2 %, twice what the corners and centroids say).
        grid = _barycentric_grid(FACE_GRID if everywhere else LIMIT_GRID)
        inner = np.einsum("gk,fkj->fgj", grid, self.triangles[face_ids]).reshape(-1, 3)
        self.points = np.concatenate([vertices[vertex_points], inner])
        on_face = np.repeat(face_ids, len(grid))
        self.face_of_point = np.concatenate([face_ids[first_face[vertex_points]], on_face]).astype(np.int64)
        # The input face a point lies inside (-1 for vertices): the LOD-to-source side
        # measures against the faces the fan holds.
        self.source_face = np.concatenate([np.full(len(vertex_points), -1, dtype=np.int64), on_face])
        self.input_faces = input_faces
        # (Kept only under painted limits: F is large, and the engine lets go of its own.)
        self._limit_frame = None if vertex_limits is None else (vertex_points, faces, face_ids, grid)
        self._kept = None
        self.point_tightness = np.zeros(len(self.points))
        self.face_tightness = np.zeros(input_faces)
        if vertex_limits is not None:
            self.set_limits(vertex_limits)
        if not everywhere:
            # Only the limits bound the distance: a free point never needs measuring (nor
            # later, as limits only grow along a chain).
            self._kept = self.point_tightness > 0
            self.points, self.face_of_point = self.points[self._kept], self.face_of_point[self._kept]
            self.source_face, self.point_tightness = self.source_face[self._kept], self.point_tightness[self._kept]
        self.distance = np.zeros(len(self.points))
        # Per input face id: a bound on the distance from the live face that descends from
        # it to the source (0 while it is the input face itself; sampled once measured).
        self.face_far = np.zeros(input_faces)
        # Per vertex: an upper bound on its distance to the source (0 where it has not moved).
        self.vertex_far = np.zeros(len(vertices))
        self.rejected_edges = np.zeros(0, dtype=np.int64)  # those the last ``within`` rejected
        self.limit_rejected = np.zeros(0, dtype=np.int64)  # among them, those only a painted limit rejected
        self._pending = []
        self._index()

    def set_limits(self, vertex_limits):
        """Painted limits (Options.vertex_max_error, (n,) normalised, inf: free; given
        at construction too), kept as tightness, 1 / limit (0: free): a point inside a
        face takes its corners' barycentric mean, so a painted weight over a limit
        interpolates as the weight does; an input face, its tightest corner."""
        vertex_points, faces, face_ids, grid = self._limit_frame
        tight = _inverse(vertex_limits)
        self.point_tightness = np.concatenate([tight[vertex_points],
                                               np.einsum("gk,fk->fg", grid, tight[faces]).ravel()])
        self.face_tightness = np.zeros(self.input_faces)
        self.face_tightness[face_ids] = tight[faces].max(axis=1)
        if self._kept is not None:
            self.point_tightness = self.point_tightness[self._kept]

    def _index(self):
        """Points grouped by face id (CSR), after the assignments changed."""
        self.order = np.argsort(self.face_of_point, kind="stable")
        self.starts = np.searchsorted(self.face_of_point[self.order], np.arange(self.input_faces + 1))

    def largest(self) -> float:
        """The bound so far: the farthest point, or face, from the other surface."""
        return max(float(self.distance.max()) if len(self.distance) else 0.0,
                   float(self.face_far.max()) if len(self.face_far) else 0.0)

    def within(self, bound: float, face_origin, fan_faces, collapse, new_tri, is_new, ring, moving, moved,
               keep, edges) -> np.ndarray:
        """(c,) bool: the collapses whose new fan keeps every point of their old fan, and
        itself, within ``bound`` of the other surface.

        fan_faces (k,): live face rows around either end of each collapse, each once;
        collapse (k,): which of the c collapses; new_tri (k, 3, 3): the face each row
        becomes (rows where is_new (k,) is False die with the edge); ring (k, 2): the
        row's two corners that stay (vertex ids; on a dying row, the other end and the
        corner opposite the edge); moving (k,): the row's moving corner (vertex id) and
        moved (k,) how far it goes; keep (c,): the vertex each collapse keeps (at the
        new position); edges (c,): the collapses' edge ids, to recognise them when they
        are applied (``commit``).

        A face whose one corner moves by m moves none of its points by more than m, so
        a point's (or a face's) distance grows by at most m: where that bound stays
        under CLOSE_ENOUGH of ``bound`` nothing is measured (early on, nearly
        everywhere); elsewhere the distances are measured and replace the bounds."""
        c = len(edges)
        ids = face_origin[fan_faces]
        # Every point of the old fans, with the fan row it lies on.
        counts = self.starts[ids + 1] - self.starts[ids]
        home = np.repeat(np.arange(len(ids)), counts)
        point = self.order[_ranges(self.starts[ids], counts)]
        owner = collapse[home]
        # What bounds each point, and each collapse's new fan: ``bound`` or a painted
        # limit, whichever is smaller (a collapse: the tightest limit of its old fan's
        # faces and points).
        if self._limit_frame is None:  # max_error alone: one bound (and no per-point arrays to build)
            point_bound = np.full(len(point), float(bound))
            collapse_bound = np.full(c, float(bound))
            local_bound = np.full(c, np.inf)
        else:
            point_limit = _inverse(self.point_tightness[point])
            point_bound = np.minimum(bound, point_limit)
            fan_tightness = np.zeros(c)
            np.maximum.at(fan_tightness, collapse, self.face_tightness[ids])
            np.maximum.at(fan_tightness, owner, self.point_tightness[point])
            local_bound = _inverse(fan_tightness)
            collapse_bound = np.minimum(bound, local_bound)
        limit = CLOSE_ENOUGH * point_bound

        # Source to LOD: the bound on the face its face becomes; where that is too loose
        # (or the face dies), measured against that face (a dying face's points: the two
        # new faces on its opposite corner), and where that is still far, against every
        # new face of the collapse.
        d = self.distance[point] + moved[home]
        new_face = np.where(is_new[home], home, -1)
        loose = np.flatnonzero((d > limit) | (new_face < 0))
        if len(loose):
            xyz = rows(self.points, point[loose])
            limit_sq = limit[loose] ** 2
            first, second = _next_faces(collapse, is_new, ring)
            d2 = np.full(len(loose), np.inf)
            face_of = np.full(len(loose), -1, dtype=np.int64)
            for candidate in (first, second):
                face = candidate[home[loose]]
                has = np.flatnonzero(face >= 0)
                t = new_tri[face[has]]
                d2_here = _distance_sq(xyz[has], t[:, 0], t[:, 1], t[:, 2])
                closer = d2_here < d2[has]
                d2[has[closer]] = d2_here[closer]
                face_of[has[closer]] = face[has[closer]]
            far = np.flatnonzero(d2 > limit_sq)
            if len(far):
                new_rows = np.flatnonzero(is_new)
                groups = _Groups(collapse[new_rows], c)

                def search(which):
                    d2_far, row = groups.nearest(xyz[which], owner[loose[which]], lambda m: new_tri[new_rows[m]])
                    better = d2_far < d2[which]
                    d2[which[better]] = d2_far[better]
                    face_of[which[better]] = new_rows[row[better]]

                # Under max_error alone, the farthest of each collapse's far points first:
                # where even its nearest new face is beyond the bound, the collapse is
                # rejected and its other points need no search (in a tight bound's tail,
                # most collapses tried). (Painted limits search them all: which limit
                # rejects a collapse needs every point's distance.)
                if self._limit_frame is not None:
                    search(far)
                else:
                    far_owner = owner[loose[far]]
                    order = np.lexsort((d2[far], far_owner))
                    last = np.ones(len(far), dtype=bool)
                    last[:-1] = far_owner[order[1:]] != far_owner[order[:-1]]
                    farthest = far[order[last]]
                    search(farthest)
                    out = np.zeros(c, dtype=bool)
                    out[owner[loose[farthest]]] = d2[farthest] > point_bound[loose[farthest]] ** 2
                    rest = far[order[~last]]
                    search(rest[~out[owner[loose[rest]]]])
            d[loose] = np.sqrt(d2)
            new_face[loose] = face_of
        beyond = np.bincount(owner[d > point_bound], minlength=c) > 0
        beyond_limit = False if self._limit_frame is None else np.bincount(owner[d > point_limit], minlength=c) > 0

        face_far, lod_worst, vertex = self._lod_to_source_of(~beyond, new_tri, is_new, collapse, ids, point, home,
                                                             new_face, moved, moving, ring,
                                                             CLOSE_ENOUGH * collapse_bound, c)
        ok = ~beyond & (lod_worst <= collapse_bound)
        present = np.zeros(c, dtype=bool)
        present[collapse] = True
        self.rejected_edges = edges[present & ~ok]
        # Those a painted limit rejects whatever ``bound`` is: no larger bound lets them pass.
        self.limit_rejected = edges[present & ~ok & (beyond_limit | (lod_worst > local_bound))]
        # Remember where the points of the accepted collapses go, and their faces' and new
        # vertices' bounds.
        # (A dying face's bound goes with it: face_far is 0 on dying rows.)
        mine, rows_ok = ok[owner], np.flatnonzero(ok[collapse])
        self._pending.append((edges[owner[mine]], point[mine], ids[new_face[mine]], d[mine],
                              edges[collapse[rows_ok]], ids[rows_ok], face_far[rows_ok],
                              edges[ok], keep[ok], vertex[ok]))
        return ok

    def _lod_to_source_of(self, wanted, new_tri, is_new, collapse, ids, point, home, new_face, moved, moving, ring,
                          limit, c) -> tuple:
        """_lod_to_source for the collapses ``wanted`` (c,) bool says (those the source's
        points already put beyond the bound need no more: in a tight bound's tail nearly
        every collapse tried is, and measuring the LOD's side of each was most of a pass).
        Under painted limits every collapse is measured: which limit rejects it (the bound
        or its region's) needs both sides."""
        if self._limit_frame is not None or wanted.all():
            return self._lod_to_source(new_tri, is_new, collapse, ids, point, home, new_face, moved, moving, ring,
                                       limit, c)
        rows_kept = np.flatnonzero(wanted[collapse])
        renumber = np.full(len(collapse), -1, dtype=np.int64)
        renumber[rows_kept] = np.arange(len(rows_kept))
        points_kept = np.flatnonzero(wanted[collapse[home]])
        kept_face = new_face[points_kept]
        face_far_kept, worst, vertex = self._lod_to_source(
            new_tri[rows_kept], is_new[rows_kept], collapse[rows_kept], ids[rows_kept], point[points_kept],
            renumber[home[points_kept]], np.where(kept_face >= 0, renumber[kept_face], -1), moved[rows_kept],
            moving[rows_kept], ring[rows_kept], limit, c)
        face_far = np.zeros(len(collapse))
        face_far[rows_kept] = face_far_kept
        return face_far, worst, vertex

    def _lod_to_source(self, new_tri, is_new, collapse, ids, point, home, new_face, moved, moving, ring, limit,
                       c) -> tuple:
        """((k,), (c,), (c,)): upper bounds on each new face's distance to the source (0 on
        dying rows), the largest per collapse, and the new vertex's.

        The new vertex: no farther than either end's bound plus how far that end moves,
        and where that passes its collapse's ``limit`` (c,), measured against the input
        triangles under the old fan (those its faces descend from, or whose points they hold). A face: its
        bound from before plus how far its corner moved, and where that passes
        ``limit``, its corners' bounds and its points measured (centroid and new edges'
        midpoints) against the input triangles under the face, or under the whole old
        fan where those are beyond ``limit`` too. Vertices' bounds are sure; between the
        measured points a face can stray a little further."""
        source = self.source_face[point]
        has = (source >= 0) & (new_face >= 0)
        under_fan = None

        def nearest_under_fan(queries, owner):
            nonlocal under_fan
            if under_fan is None:
                under_fan = _Groups.of_pairs(np.concatenate([collapse, collapse[new_face[has]]]),
                                             np.concatenate([ids, source[has]]), c, self.input_faces)
            return under_fan.nearest(queries, owner, lambda m: self.triangles[m])[0]

        vertex = np.full(c, np.inf)
        np.minimum.at(vertex, collapse, self.vertex_far[moving] + moved)
        loose_vertex = np.unique(collapse[vertex[collapse] > limit[collapse]])  # (collapses without rows are rejected)
        if len(loose_vertex):
            at = np.zeros(c, dtype=np.int64)
            at[collapse[::-1]] = np.arange(len(collapse))[::-1]  # a row of each collapse: its x
            x = new_tri[at, 0]
            # First the input triangle of the fan's nearest point inside a face (cheap
            # distances to points); only where that one is too far, all under the fan.
            inside = np.flatnonzero(source >= 0)
            owner_in = collapse[home[inside]]
            gap = np.einsum("ij,ij->i", self.points[point[inside]] - x[owner_in], self.points[point[inside]] - x[owner_in])
            nearest_point = np.full(c, np.inf)
            np.minimum.at(nearest_point, owner_in, gap)
            hit = np.flatnonzero(gap == nearest_point[owner_in])
            tri_of = np.full(c, -1, dtype=np.int64)
            tri_of[owner_in[hit]] = source[inside[hit]]
            measured = np.full(len(loose_vertex), np.inf)
            known = np.flatnonzero(tri_of[loose_vertex] >= 0)
            t = self.triangles[tri_of[loose_vertex[known]]]
            measured[known] = _distance_sq(x[loose_vertex[known]], t[:, 0], t[:, 1], t[:, 2])
            again = np.flatnonzero(measured > limit[loose_vertex] ** 2)
            if len(again):
                measured[again] = np.minimum(measured[again],
                                             nearest_under_fan(x[loose_vertex[again]], loose_vertex[again]))
            vertex[loose_vertex] = np.minimum(vertex[loose_vertex], np.sqrt(measured))

        face_far = np.where(is_new, self.face_far[ids] + moved, 0.0)
        loose = np.flatnonzero(is_new & (face_far > limit[collapse]))
        if len(loose):
            t = new_tri[loose]
            # (The far edge's points are as far from the source as before: it does not move.)
            samples = np.stack([t.mean(axis=1), 0.5 * (t[:, 0] + t[:, 1]), 0.5 * (t[:, 0] + t[:, 2])],
                               axis=1).reshape(-1, 3)
            per_face = samples.shape[0] // len(loose)
            sample_row = np.repeat(loose, per_face)
            # First the input triangle of the face's nearest point inside an input face
            # (cheap distances to points); where that one is too far, all under the face.
            inside = np.flatnonzero(has)
            by_row = _Groups(new_face[inside], len(ids), inside)
            _, nearest_point = by_row.nearest(samples, sample_row, points_of=lambda m: self.points[point[m]])
            d2 = np.full(len(samples), np.inf)
            known = np.flatnonzero(nearest_point >= 0)
            t = self.triangles[source[nearest_point[known]]]
            d2[known] = _distance_sq(samples[known], t[:, 0], t[:, 1], t[:, 2])
            limit_sq = limit[collapse[sample_row]] ** 2
            again = np.flatnonzero(d2 > limit_sq)
            if len(again):
                under_row = _Groups.of_pairs(np.concatenate([np.arange(len(ids)), new_face[has]]),
                                             np.concatenate([ids, source[has]]), len(ids), self.input_faces)
                d2[again] = np.minimum(d2[again], under_row.nearest(samples[again], sample_row[again],
                                                                    lambda m: self.triangles[m])[0])
            far = np.flatnonzero(d2 > limit_sq)
            if len(far):
                d2[far] = np.minimum(d2[far], nearest_under_fan(samples[far], collapse[sample_row[far]]))
            corners = np.maximum(vertex[collapse[loose]], self.vertex_far[ring[loose]].max(axis=1))
            face_far[loose] = np.maximum(np.sqrt(d2).reshape(-1, per_face).max(axis=1), corners)
        worst = np.zeros(c)
        np.maximum.at(worst, collapse, face_far)
        return face_far, np.maximum(worst, vertex), vertex

    def commit(self, applied_edges: np.ndarray):
        """Move the points of the collapses applied (by edge id) to their new faces, and
        keep their new faces' bounds; drop what was measured for collapses not applied."""
        if self._pending:
            (edge, point, face, dist, face_edge, face_id, far,
             vertex_edge, vertex_id, vertex_far) = (np.concatenate(parts) for parts in zip(*self._pending))
            keep = np.isin(edge, applied_edges)
            self.face_of_point[point[keep]] = face[keep]
            self.distance[point[keep]] = dist[keep]
            applied = np.isin(face_edge, applied_edges)
            self.face_far[face_id[applied]] = far[applied]
            applied = np.isin(vertex_edge, applied_edges)
            self.vertex_far[vertex_id[applied]] = vertex_far[applied]
            self._pending = []
            self._index()


def _next_faces(collapse, is_new, ring) -> tuple:
    """((k,), (k,)): for each fan row, the new faces its points are first measured
    against: a surviving row, itself (and -1); a dying row, the (up to) two new faces of
    its collapse on its corner opposite the edge (its neighbours across the two edges
    that merge)."""
    k = len(collapse)
    first = np.where(is_new, np.arange(k), -1)
    second = np.full(k, -1, dtype=np.int64)
    dying = np.flatnonzero(~is_new)
    alive = np.flatnonzero(is_new)
    if len(dying) == 0 or len(alive) == 0:
        return first, second
    span = np.int64(ring.max()) + 1
    key = np.concatenate([collapse[alive] * span + ring[alive, 0], collapse[alive] * span + ring[alive, 1]])
    row = np.concatenate([alive, alive])
    order = np.argsort(key, kind="stable")
    key, row = key[order], row[order]
    # On a dying row, the corner that is not the collapse's other end is the second.
    wanted = collapse[dying] * span + ring[dying, 1]
    at = np.searchsorted(key, wanted)
    for out, offset in ((first, 0), (second, 1)):
        i = np.minimum(at + offset, len(key) - 1)
        hit = (at + offset < len(key)) & (key[i] == wanted)
        out[dying[hit]] = row[i[hit]]
    return first, second


class _Groups:
    """Members (triangles or points) grouped by an owner (a collapse, a fan row):
    ``members`` sorted by owner, ``start`` (owners + 1,) their offsets."""

    def __init__(self, owner_of_member: np.ndarray, owners: int, members=None):
        order = np.argsort(owner_of_member, kind="stable")
        self.members = order if members is None else members[order]
        self.start = np.searchsorted(owner_of_member[order], np.arange(owners + 1))

    @classmethod
    def of_pairs(cls, owner, member, owners, members):
        """Distinct (owner, member) pairs, grouped by owner."""
        code = np.unique(owner * np.int64(members) + member)
        return cls(code // members, owners, code % members)

    def nearest(self, queries: np.ndarray, query_owner: np.ndarray, triangles_of=None, points_of=None) -> tuple:
        """For each query point (q, 3) the squared distance to the nearest member of its
        owner's group, and that member (-1, and inf, for an empty group). The members
        are triangles (``triangles_of`` maps members (k,) to (k, 3, 3)) or points
        (``points_of`` maps them to (k, 3))."""
        count = (self.start[1:] - self.start[:-1])[query_owner]
        pair = np.repeat(np.arange(len(queries)), count)
        member = self.members[_ranges(self.start[query_owner], count)]
        if points_of is not None:
            gap = rows(queries, pair) - points_of(member)
            d2 = np.einsum("ij,ij->i", gap, gap)
        else:
            tri = triangles_of(member) if len(member) else np.zeros((0, 3, 3))
            d2 = _distance_sq(rows(queries, pair), tri[:, 0], tri[:, 1], tri[:, 2])
        best = np.full(len(queries), np.inf)
        np.minimum.at(best, pair, d2)
        hit = np.flatnonzero(d2 == best[pair])
        which = np.full(len(queries), -1, dtype=np.int64)
        which[pair[hit[::-1]]] = member[hit[::-1]]  # the first nearest
        return best, which


def _inverse(values: np.ndarray) -> np.ndarray:
    """1 / values: 0 where a value is infinite, infinite where it is 0."""
    with np.errstate(divide="ignore"):
        return 1.0 / np.asarray(values, dtype=np.float64)


def _ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Concatenated aranges starts[i] .. starts[i] + counts[i] - 1."""
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    offsets = np.repeat(starts - np.concatenate([[0], np.cumsum(counts)[:-1]]), counts)
    return np.arange(total) + offsets


def _distance_sq(p, a, b, c) -> np.ndarray:
    """(k,) squared distance from each point p (k, 3) to its triangle (a, b, c)."""
    return closest_on_triangles(p, a, b, c)[1]
