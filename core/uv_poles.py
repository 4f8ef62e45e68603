"""Seams that only a UV pole makes (core.engine's vertex kinds read them).

A UV sphere gives each triangle around a pole its own UV there: the pole's values change
across every edge around it, and each of those edges is a seam at the pole's end only.
The ring around the pole is continuous (core.wedges.value_changes counts a seam at a
vertex where its own values change), so the seams end there and hold nothing but the
pole. Subdivided, the pole's edges get vertices of their own whose values change
(halfway to the pole, half the pole's jump; Blender's Subdivision Surface also splits
them towards the face centres): as seam ends and junctions they were locked, or slid
only into the pole, which a fan of 32 rays 11 degrees apart allows only by making
slivers. They held the LOD's budget at the poles while the rest of the sphere went: at
5 % of its triangles, Blender's subdivided UV sphere measured 11.6 % of its size from
its source (1.1 % with seams free).

Such seams are no island boundaries: they fade out within the island. The seams between
seam vertices other than the poles make components; one is a pole's web when it joins
exactly one pole (a vertex where at least POLE_RAYS seams start: a junction of islands
has three or four), lies within WEB_DEPTH edges of a pole, has no border vertex, and
fades out: a seam edge of it ends at a vertex whose values are continuous. Its vertices are then
no seam vertices; the pole stays a junction. The meridian (two poles), a cap island's
outline (no fading edge: the edges leaving an outline into its island are no seams) and
a relief cut from a border or an ordinary junction stay seams.
"""

from __future__ import annotations

import numpy as np

from . import topology

# Seams starting at one vertex, at least, for it to be a UV pole (a UV sphere has 8-64).
POLE_RAYS = 6
# Edges from its pole, at most, to each vertex of a pole's web (a pole subdivided twice
# has its rays' vertices one, two and three edges out).
WEB_DEPTH = 3


def pole_web_changes(edges: np.ndarray, change: np.ndarray, n: int, border=None) -> np.ndarray:
    """``change`` (k, 2) bool (core.wedges.value_changes: per edge of ``edges`` (k, 2) and
    end, whether the values change there) with the changes at the vertices of pole webs
    cleared. ``border``: (n,) bool, the border vertices, or None."""
    seam_count = np.bincount(edges[change], minlength=n)
    is_pole = seam_count >= POLE_RAYS
    if not is_pole.any():
        return change
    a, b = edges[:, 0], edges[:, 1]
    on_seam = seam_count > 0
    seam_edge = change.any(axis=1)
    web = on_seam & ~is_pole
    nodes = np.flatnonzero(web)
    index = np.full(n, -1, dtype=np.int64)
    index[nodes] = np.arange(len(nodes))
    inner = seam_edge & web[a] & web[b]
    component = topology.connected_labels(len(nodes), index[a[inner]], index[b[inner]])
    near = is_pole.copy()  # within WEB_DEPTH edges of a pole
    for _ in range(WEB_DEPTH):
        grown = near.copy()
        grown[b[near[a]]] = True
        grown[a[near[b]]] = True
        near = grown
    far = np.bincount(component, weights=~near[nodes], minlength=len(nodes))
    # The poles each component joins (by a seam edge), counted once each.
    to_pole = seam_edge & ((is_pole[a] & web[b]) | (is_pole[b] & web[a]))
    member = index[np.where(is_pole[a], b, a)[to_pole]]
    pole = np.where(is_pole[a], a, b)[to_pole]
    joined = np.unique(component[member] * np.int64(n) + pole) // n
    poles = np.bincount(joined, minlength=len(nodes))
    # Fading: a seam edge from a component vertex to a vertex with continuous values.
    fade = seam_edge & ((web[a] & ~on_seam[b]) | (web[b] & ~on_seam[a]))
    fades = np.bincount(component[index[np.where(web[a], a, b)[fade]]], minlength=len(nodes))
    ok = (poles == 1) & (far == 0) & (fades > 0)
    if border is not None:
        ok &= np.bincount(component, weights=border[nodes], minlength=len(nodes)) == 0
    cleared = np.zeros(n, dtype=bool)
    cleared[nodes[ok[component]]] = True
    if not cleared.any():
        return change
    out = change.copy()
    out[:, 0] &= ~cleared[a]
    out[:, 1] &= ~cleared[b]
    return out
