"""Seams that only a UV pole makes (core.engine's vertex kinds read them).

A UV sphere gives each triangle around a pole its own UV there: the pole's values change
across every edge around it, and each of those edges is a seam at the pole's end only.
The ring around the pole is continuous (core.wedges.value_changes counts a seam at a
vertex where its own values change), so the seams end there and hold nothing but the
pole. Subdivided, each such ray gets vertices of its own whose values change across it
(halfway to the pole, half the pole's jump): as seam vertices they may only slide along
their ray, into the pole, which a fan of 32 rays 11 degrees apart only allows by making
slivers. They held 57 vertices of a subdivided UV sphere's 3,968-triangle LOD chain at
its poles while the rest of the sphere went: at 150 triangles the LOD measured 7.8 % of
its size from the sphere (1.2 % with seams free), at 120, 20 %.

Such rays are not island boundaries: they fade out within the island. A seam path is a
pole ray when it starts at a vertex where at least POLE_RAYS seams start (a junction of
islands has three or four), runs through vertices on exactly two seam edges, and ends
where the values are continuous. Its vertices but the pole are then not on a seam; the
pole stays a junction. A relief cut that fades out from a border or from an ordinary
junction stays a seam.
"""
from __future__ import annotations

import numpy as np

# Seams starting at one vertex, at least, for it to be a UV pole (a UV sphere has 8-64).
POLE_RAYS = 6
# Seam vertices along one ray, at most (a UV sphere subdivided n times has 2^n - 1).
RAY_LENGTH = 16


def pole_ray_changes(edges: np.ndarray, change: np.ndarray, n: int) -> np.ndarray:
    """``change`` (k, 2) bool (core.wedges.value_changes: per edge of ``edges`` (k, 2) and
    end, whether the values change there) with the changes along pole rays cleared but
    at their poles."""
    at = edges[change]  # the vertex at each changing end
    seam_count = np.bincount(at, minlength=n)
    poles = np.flatnonzero(seam_count >= POLE_RAYS)
    if len(poles) == 0:
        return change
    # For every vertex on exactly two seam edges, those two edges (rows of ``edges``).
    edge_of_end = np.nonzero(change)[0]
    order = np.argsort(at, kind="stable")
    through = seam_count == 2
    pair = np.full((n, 2), -1, dtype=np.int64)
    sorted_at, sorted_edge = at[order], edge_of_end[order]
    two = through[sorted_at]
    firsts = np.flatnonzero(two & np.r_[True, sorted_at[1:] != sorted_at[:-1]])
    pair[sorted_at[firsts], 0] = sorted_edge[firsts]
    pair[sorted_at[firsts], 1] = sorted_edge[firsts + 1]
    # Walk every ray from its pole, all at once.
    is_pole = np.zeros(n, dtype=bool)
    is_pole[poles] = True
    start = np.flatnonzero((change[:, 0] & is_pole[edges[:, 0]]) | (change[:, 1] & is_pole[edges[:, 1]]))
    ray = np.arange(len(start))
    edge = start.copy()
    came_from = np.where(is_pole[edges[start, 0]] & change[start, 0], edges[start, 0], edges[start, 1])
    steps = [(ray, edge)]
    valid = np.zeros(len(start), dtype=bool)
    for _ in range(RAY_LENGTH + 1):
        far = np.where(edges[edge, 0] == came_from, edges[edge, 1], edges[edge, 0])
        far_end = (edges[edge, 1] == far).astype(np.int64)
        changes_there = change[edge, far_end]
        faded = ~changes_there  # the ray ends where the values are continuous
        valid[ray[faded]] = True
        go = changes_there & through[far]
        ray, edge, came_from, far = ray[go], edge[go], came_from[go], far[go]
        if len(ray) == 0:
            break
        nxt = np.where(pair[far, 0] == edge, pair[far, 1], pair[far, 0])
        ray, edge, came_from = ray, nxt, far
        steps.append((ray, edge))
    out = change.copy()
    for r, e in steps:
        keep = valid[r]
        e = e[keep]
        # Clear the changes at every end of a valid ray's edges but at a pole.
        out[e, 0] &= is_pole[edges[e, 0]]
        out[e, 1] &= is_pole[edges[e, 1]]
    return out
