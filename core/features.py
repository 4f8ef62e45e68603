"""Sharp features found from the geometry: the edges and corners of hard-surface parts.

A CAD part or a bevelled prop carries its shape in a few creases. The face planes alone
keep them only as long as the collapses around them happen to be cheap in the right
order; the paper's dihedral-plane quadrics (Sec. 4.4.2, Eq. 18-19) on the crease edges
hold them softly, and the corners where three or more creases meet (a box corner, a
fandisk's tip) are kept exactly, since one moved corner bends every crease through it.
"""
from __future__ import annotations

import numpy as np

from . import grid
from .quadrics import scatter_sum
from .topology import Connectivity, connected_labels, next_corner

# The default feature angle, in degrees. Right angles are what hard-surface parts are made
# of (boxes, panels, a logo's outline), and 80 catches them with room for imprecise
# modelling, while organic meshes have few creases that sharp. Measured at 10 % (the Fox
# at 25 %) against feature angles off: on spot, the bunny, the ogre and the Fox every
# Hausdorff and mean distance stayed within 1.05x or improved (the Fox 0.45x -> 0.33x of
# Decimate's Hausdorff), beast's Hausdorff went from 1.12x to 1.00x of Decimate's, homer's
# from 0.78x to 0.95x; at 60 degrees beast's mean triangle quality lost 0.013, at 30
# degrees beast's Hausdorff distance grew 4.5x (docs/parameters.md).
DEFAULT_FEATURE_ANGLE = 80.0
# An open border is a silhouette against whatever is behind it, and its corners are the
# outline of a flat part (a logo, a decal, a card): a border turning by half the feature
# angle at one vertex is a corner. At the default that keeps a star's inner corners (72
# degrees) and a hexagon's (60) while a circle tessellated in 12 or more segments stays
# free. Measured at 10 %: the bunny's jagged scan holes get 107 such corners among their
# 223 border vertices and its Hausdorff distance went from 0.95x to 0.68x of Decimate's,
# mean distance and quality unchanged; the ogre's 200 border edges have none.
BORDER_ANGLE_SHARE = 0.5


def crease_edges(face_normals: np.ndarray, conn: Connectivity, angle_degrees: float) -> np.ndarray:
    """(k,) indices into conn.edges of the interior manifold edges whose two faces' unit
    normals (m, 3) differ by more than ``angle_degrees`` (the dihedral angle's supplement,
    as Blender's Auto Smooth measures it)."""
    normals = face_normals
    inner = np.flatnonzero(conn.edge_faces == 2)
    n0 = normals[conn.edge_face0[inner]]
    n1 = normals[conn.edge_face1[inner]]
    cosine = np.einsum("ij,ij->i", n0, n1)
    return inner[cosine < np.cos(np.radians(angle_degrees))]


def corners(edges: np.ndarray, n_vertices: int) -> np.ndarray:
    """(n,) bool: vertices where three or more of ``edges`` (k, 2) meet."""
    if len(edges) == 0:
        return np.zeros(n_vertices, dtype=bool)
    return np.bincount(np.asarray(edges).ravel(), minlength=n_vertices) >= 3


def boundary_corners(vertices: np.ndarray, faces: np.ndarray, face_normals: np.ndarray, face_areas: np.ndarray,
                     conn: Connectivity, feature_angle: float) -> np.ndarray:
    """(n,) bool: open-boundary vertices where the outline has a corner (a flat logo's, a
    cut-out panel's), and those where more than two boundary edges meet.

    A corner is a turn within the surface by the feature angle or more, or by
    BORDER_ANGLE_SHARE of it beyond what either border neighbour turns the same way: a
    bend spread over consecutive vertices is a rounded corner, which the boundary planes
    keep in shape, while locking the vertices of it that happen to turn most keeps some
    and lets the rest go (the 576 rounded patches of a subdivided triangle soup lost 40 %
    of their area at 10 %, against 16 % with no border corners). A border loop that turns
    the same way by that much at every vertex is a polygon (a hexagonal cap), not a bend:
    all its vertices are corners.
    The turn is measured in the vertex's tangent plane (area-weighted normal, from the
    faces' unit normals and areas), so a border that only wobbles out of the surface
    (noise on a scanned sheet) has no corners; its direction follows the faces'
    orientation along the border, so it does not depend on how vertices are numbered."""
    n = len(vertices)
    border = conn.edge_faces == 1
    corner = np.zeros(n, dtype=bool)
    if not border.any():
        return corner
    # Each border edge in the direction of its one face's half-edge: from a to b.
    h = conn.edge_he0[border]
    a = faces.ravel()[h]
    b = faces.ravel()[next_corner(h)]
    count = np.bincount(a, minlength=n) + np.bincount(b, minlength=n)
    corner[count > 2] = True
    before = np.full(n, -1, dtype=np.int64)
    after = np.full(n, -1, dtype=np.int64)
    before[b] = a
    after[a] = b
    # Two border edges, one in and one out (faces oriented alike on both sides).
    v = np.flatnonzero((count == 2) & (before >= 0) & (after >= 0))
    into = vertices[v] - vertices[before[v]]
    out = vertices[after[v]] - vertices[v]
    normal = scatter_sum(faces, face_normals * face_areas[:, None], n)[v]
    normal /= np.maximum(np.linalg.norm(normal, axis=1), 1e-300)[:, None]
    into -= normal * np.einsum("ij,ij->i", into, normal)[:, None]
    out -= normal * np.einsum("ij,ij->i", out, normal)[:, None]
    length = np.linalg.norm(into, axis=1) * np.linalg.norm(out, axis=1)
    cosine = np.einsum("ij,ij->i", into, out) / np.maximum(length, 1e-300)
    angle = np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))
    # Signed turn: positive one way round the surface normal, negative the other, so the
    # inner corners of a star (turning against its tips) stand on their own.
    side = np.sign(np.einsum("ij,ij->i", np.cross(into, out), normal))
    turn = np.zeros(n)
    turn[v] = side * angle
    half = feature_angle * BORDER_ANGLE_SHARE
    # What the neighbours turn the same way is part of the same bend, not this corner's.
    along = np.maximum(np.maximum(turn[before[v]] * side, turn[after[v]] * side), 0.0)
    corner[v[(angle >= feature_angle) | (angle - along >= half)]] = True
    # A loop turning the same way by half the angle at every vertex: a polygon. Loops are
    # found among the border vertices only (numbered 0..k-1), not over the whole mesh.
    on_border = np.flatnonzero(count > 0)
    ia, ib = np.searchsorted(on_border, a), np.searchsorted(on_border, b)
    loop = connected_labels(len(on_border), ia, ib)
    off = (np.abs(turn[a]) < half) | (np.sign(turn[a]) != np.sign(turn[b]))  # leaves a run of same-way turns
    broken = np.zeros(len(on_border), dtype=bool)
    broken[loop[ia[off]]] = True
    corner[on_border[~broken[loop]]] = True
    return corner


def sharp_edges(vertices: np.ndarray, faces: np.ndarray, angle_degrees: float) -> np.ndarray:
    """(k, 2) vertex pairs of the interior edges of ``faces`` (m, 3) whose faces' normals
    differ by more than ``angle_degrees``: where a mesh shaded by angle (Blender's Smooth by
    Angle) shows a hard edge."""
    from .geometry import face_frames
    from .topology import build

    conn = build(np.asarray(faces, dtype=np.int64), len(vertices))
    normals, _ = face_frames(np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64))
    return conn.edges[crease_edges(normals, conn, angle_degrees)]


def nearest_other(points: np.ndarray, brute_force_below: int = 512) -> np.ndarray:
    """(k,) distance from each of ``points`` (k, 3) to the nearest other one (inf for a
    lone point): a corner's feature size, how far the next corner of its shape is (a bolt
    hole's eight border turns lie a facet apart, a box's corners an edge).

    Exact. Below ``brute_force_below`` points, all pairs; above, the points are hashed to
    a grid and each looks in the 27 cells around its own: a neighbour found within one
    cell's size is the nearest (any nearer one is in those cells), and the points that
    found none that near look again in a grid of cells three times as large, starting
    fine so that a dense cluster's cells hold a few points each."""
    p = np.asarray(points, dtype=np.float64)
    k = len(p)
    out = np.full(k, np.inf)
    if k < 2:
        return out
    if k < brute_force_below:
        d2 = np.einsum("ijk,ijk->ij", p[:, None] - p[None], p[:, None] - p[None])
        np.fill_diagonal(d2, np.inf)
        return np.sqrt(d2.min(axis=1))
    lo = p.min(axis=0)
    diagonal = float(np.linalg.norm(p.max(axis=0) - lo))
    if diagonal == 0.0:
        return np.zeros(k)
    cell = diagonal / np.cbrt(k) / 4.0
    todo = np.arange(k)
    while len(todo):
        best = _nearest_in_cells(p, lo, cell, todo)
        found = best <= cell * cell
        out[todo[found]] = np.sqrt(best[found])
        if cell > diagonal:  # every other point was in the 27 cells
            out[todo[~found]] = np.sqrt(best[~found])
            break
        todo = todo[~found]
        cell *= 3.0
    return out


def _nearest_in_cells(p, lo, cell, queries) -> np.ndarray:
    """(len(queries),) the squared distance from each query point to the nearest other
    point of ``p`` in the 27 grid cells (size ``cell``, from ``lo``) around its own (inf
    when none)."""
    c = grid.cells(p, lo, cell)
    stride = grid.strides(c)
    key = c @ stride
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    best = np.full(len(queries), np.inf)
    mine = key[queries]
    for offset in grid.NEIGHBOURS @ stride:
        q, at = grid.in_cells(sorted_key, mine + offset)
        them = order[at]
        other = them != queries[q]
        q, them = q[other], them[other]
        diff = p[queries[q]] - p[them]
        np.minimum.at(best, q, np.einsum("ij,ij->i", diff, diff))
    return best
