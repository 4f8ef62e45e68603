"""Whole parts of a mesh (connected components) and which of them a target can spare.

Edge collapse never deletes a part (rule no_bare_vertex in core.guards): a bolt, a leaf
card or a piece of debris keeps at least one triangle, a closed one four. At the far
LODs of a game asset engines prefer such parts gone rather than left as shapeless
fragments, so with ``remove_small_components`` the engine, once no collapse is possible,
drops the smallest parts instead. Before that, a part smaller than the error the LOD
already has leaves it (:func:`smaller_than`): its removal costs less than keeping it
costs the rest of the mesh (issue 33: 500 bolts of 12 triangles held a CAD part's LOD
at 2,000 triangles, and a bolt kept as a tetrahedron looks like nothing).
"""
from __future__ import annotations

import numpy as np

from .geometry import face_frames
from .topology import connected_labels


def vertex_labels(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """(n,) int64: a label per vertex, equal for the vertices of one part (faces sharing
    vertices); an unused vertex is a part of its own."""
    if len(faces) == 0:
        return np.arange(n_vertices, dtype=np.int64)
    return connected_labels(n_vertices, np.r_[faces[:, 0], faces[:, 1]], np.r_[faces[:, 1], faces[:, 2]])


def face_labels(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """(m,) int64: a label per face, equal for faces of one part (sharing vertices)."""
    if len(faces) == 0:
        return np.zeros(0, dtype=np.int64)
    return vertex_labels(faces, n_vertices)[faces[:, 0]]


def _parts(faces: np.ndarray, vertices: np.ndarray, locked: np.ndarray, face_weight=None) -> tuple:
    """(the part of each face (m,) in 0..k-1, and per part: its surface area (k,), its
    faces (k,) counted with ``face_weight``, whether it has a locked vertex (k,)).
    ``faces`` not empty."""
    label = vertex_labels(faces, len(vertices))
    parts, part_of_face = np.unique(label[faces[:, 0]], return_inverse=True)
    k = len(parts)
    _, area = face_frames(vertices, faces)
    part_area = np.bincount(part_of_face, weights=area, minlength=k)
    part_faces = np.bincount(part_of_face, weights=face_weight, minlength=k)
    has_lock = np.bincount(part_of_face, weights=locked[faces].any(axis=1), minlength=k) > 0
    return part_of_face, part_area, part_faces, has_lock


def smallest_to_drop(faces: np.ndarray, vertices: np.ndarray, locked: np.ndarray, need: int,
                     face_weight=None):
    """((m,) bool of the faces to delete, how many parts they are), or None when no part
    can go.

    Parts go smallest surface area first, as many as it takes to remove ``need`` faces,
    but the largest part always stays and so does every part with a locked vertex (what
    the artist locked is never removed). ``face_weight``: (m,) what each face counts
    toward ``need`` (Options.part_copies), default 1.
    """
    if len(faces) == 0 or need <= 0:
        return None
    part_of_face, part_area, part_faces, has_lock = _parts(faces, vertices, locked, face_weight)
    if len(part_area) < 2:
        return None
    order = np.argsort(part_area, kind="stable")
    spare = order[:-1]  # the largest part stays
    spare = spare[~has_lock[spare]]
    if len(spare) == 0:
        return None
    upto = int(np.searchsorted(np.cumsum(part_faces[spare]), need, side="left")) + 1
    drop = np.zeros(len(part_area), dtype=bool)
    drop[spare[:upto]] = True
    return drop[part_of_face], int(drop.sum())


def smaller_than(faces: np.ndarray, vertices: np.ndarray, locked: np.ndarray, size: float, need: float,
                 face_weight=None, at_least_one: bool = False) -> tuple:
    """(faces to delete (m,) bool or None, how many parts, the size of the smallest part
    that may still go (inf: none)): the parts whose bounding-box diagonal is below
    ``size``, smallest first, no more than it takes to remove ``need`` faces (counted
    with ``face_weight`` (m,), default 1), or the smallest alone when that is more and
    ``at_least_one``. Never the largest part (by area) nor one with a locked vertex."""
    if len(faces) == 0:
        return None, 0, np.inf
    part_of_face, part_area, part_faces, has_lock = _parts(faces, vertices, locked, face_weight)
    k = len(part_area)
    if k < 2:
        return None, 0, np.inf
    # Each part's bounding box from its vertices (parts are joined by shared vertices, so
    # every corner of a vertex is in one part): a sixth of the corners' updates.
    part_of_vertex = np.full(len(vertices), -1, dtype=np.int64)
    part_of_vertex[faces.ravel()] = np.repeat(part_of_face, 3)
    used = np.flatnonzero(part_of_vertex >= 0)
    part_of_used, used_at = part_of_vertex[used], vertices[used]
    lo = np.full((k, 3), np.inf)
    hi = np.full((k, 3), -np.inf)
    np.minimum.at(lo, part_of_used, used_at)
    np.maximum.at(hi, part_of_used, used_at)
    diagonal = np.linalg.norm(hi - lo, axis=1)
    may_go = ~has_lock
    may_go[int(np.argmax(part_area))] = False
    spare = np.flatnonzero(may_go & (diagonal < size))
    spare = spare[np.argsort(diagonal[spare], kind="stable")]
    upto = int(np.searchsorted(np.cumsum(part_faces[spare]), need, side="right")) if need > 0 else 0
    if at_least_one and need > 0:
        upto = max(upto, min(1, len(spare)))
    drop = np.zeros(k, dtype=bool)
    drop[spare[:upto]] = True
    rest = diagonal[may_go & ~drop]
    smallest = float(rest.min()) if len(rest) else np.inf
    if upto == 0:
        return None, 0, smallest
    return drop[part_of_face], upto, smallest
