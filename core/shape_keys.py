"""Shape keys in the error: a LOD must stay close at every key's full value, not only at rest.

Shape keys are carried as per-vertex offsets, interpolated along each collapse like any
other vertex attribute. Measured on a sphere with a bulge and a crease as keys, the LOD's
mean distance at a key's full value was 1.1-1.3x its distance at rest: the collapses
were chosen for the rest shape only. So each vertex also accumulates the planes of its
faces in every key's deformed shape (the same area-weighted quadrics as at rest, Eq. 7-8),
and a candidate collapse is charged, per key, the squared distance of its merged vertex
moved by its interpolated offset to those planes: the mean over the keys, counted like
the rest error.

Shapes: K keys, n vertices; offsets (K, n, 3); quadrics (K, n, 10).
"""
from __future__ import annotations

import numpy as np

from . import quadrics
from .geometry import face_frames

# Keys in the error at most, the ones that move the surface most: every key costs a
# quadric per vertex (80 bytes) and an evaluation per candidate edge, and a face rig can
# have a hundred keys, most of them small.
MAX_KEYS = 16


def strongest(offsets: np.ndarray, areas: np.ndarray, count: int = MAX_KEYS) -> np.ndarray:
    """Indices of the ``count`` keys (K, n, 3) that move the surface most (area-weighted
    squared offset), in their given order."""
    if len(offsets) <= count:
        return np.arange(len(offsets))
    size = np.einsum("knj,knj,n->k", offsets, offsets, areas)
    return np.sort(np.argsort(-size, kind="stable")[:count])


def vertex_quadrics(vertices: np.ndarray, faces: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """(K, n, 10): every vertex's area-weighted face planes in every key's shape."""
    n = len(vertices)
    out = np.empty((len(offsets), n, quadrics.QUADRIC_SIZE))
    for k, offset in enumerate(offsets):  # a loop over keys (at most MAX_KEYS), not elements
        shape = vertices + offset
        normals, areas = face_frames(shape, faces)
        plane = quadrics.plane_quadrics(normals, shape[faces[:, 0]], areas / 3.0)
        out[k] = quadrics.accumulate(faces, plane, n)
    return out


def key_weights(shape_keys: int, poses: int, pose_weight: float) -> np.ndarray:
    """(K,) what each key's error counts: the mean over the shape keys, plus
    ``pose_weight`` times the mean over the sample poses (core.skinning)."""
    return np.concatenate([np.full(shape_keys, 1.0 / max(shape_keys, 1)),
                           np.full(poses, pose_weight / max(poses, 1))])


def collapse_error(key_quadrics: np.ndarray, keep: np.ndarray, remove: np.ndarray, position: np.ndarray,
                   merged_offsets: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """(k,) weighted sum over the keys (``weights`` (K,), key_weights) of the squared
    distance of each merged vertex, at ``position`` plus its interpolated offset (K, k, 3),
    to both ends' planes in that key."""
    total = np.zeros(len(keep))
    for k in range(len(key_quadrics)):  # key by key: each gather stays in cache
        q = quadrics.pair_sums(key_quadrics[k], keep, remove)
        total += weights[k] * quadrics.evaluate(q, position + merged_offsets[k])
    return total
