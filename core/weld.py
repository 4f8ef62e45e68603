"""Welding coincident vertices, so split vertices of exported assets (one copy per UV or
normal) become one surface that can be simplified as the closed shape it is."""
from __future__ import annotations

import itertools

import numpy as np

from .topology import connected_labels

_NEIGHBOUR_OFFSETS = np.array(list(itertools.product((-1, 0, 1), repeat=3)), dtype=np.int64)


def weld_map(vertices: np.ndarray, distance) -> np.ndarray:
    """(n,) index of the representative each vertex is welded to (itself if none).

    distance: None welds exactly coincident positions; a positive value welds vertices
    closer than it (transitively); negative disables welding.
    """
    n = len(vertices)
    if n == 0 or (distance is not None and distance < 0):
        return np.arange(n)
    if not distance:
        return _weld_exact(vertices)
    return _weld_within(vertices, float(distance))


def _weld_exact(vertices: np.ndarray) -> np.ndarray:
    """Exactly coincident positions weld to their first occurrence.

    Sorting one 64-bit hash of each row's bits is several times faster than np.unique
    over rows (which compares rows field by field). Equal rows hash equally and, the sort
    being stable, come out as a run led by their first occurrence; a run that holds
    different rows (a hash collision) sends the whole call to np.unique instead.
    """
    bits = np.ascontiguousarray(vertices + 0.0).view(np.uint64)  # + 0.0: -0.0 == 0.0
    h = bits[:, 0] * np.uint64(0x9E3779B97F4A7C15)
    h = (h ^ (h >> np.uint64(29)) ^ bits[:, 1]) * np.uint64(0xBF58476D1CE4E5B9)
    h = (h ^ (h >> np.uint64(32)) ^ bits[:, 2]) * np.uint64(0x94D049BB133111EB)
    order = np.argsort(h, kind="stable")
    hs, vs = h[order], vertices[order]
    same_hash = hs[1:] == hs[:-1]
    same_row = same_hash & np.all(vs[1:] == vs[:-1], axis=1)
    if np.any(same_hash & ~same_row):
        _, first, inverse = np.unique(vertices, axis=0, return_index=True, return_inverse=True)
        return first[inverse.reshape(-1)]
    run_start = np.concatenate([[True], ~same_row])
    leader = order[np.flatnonzero(run_start)][np.cumsum(run_start) - 1]
    out = np.empty(len(vertices), dtype=np.int64)
    out[order] = leader
    return out


def _weld_within(vertices: np.ndarray, distance: float) -> np.ndarray:
    """Grid cells of size ``distance``: vertices in one cell weld; neighbouring cells
    (the 26 around) weld where their first vertices are within ``distance``, so pairs
    straddling a cell border are not missed. Joined cells form one weld group."""
    cells = np.floor(vertices / distance).astype(np.int64)
    cells -= cells.min(axis=0) - 1  # leave room for the -1 offsets
    extent = cells.max(axis=0) + 2
    if float(np.prod(extent.astype(np.float64))) >= 2.0**62:
        raise ValueError(f"weld_distance {distance} is too small for this mesh's extent")
    stride = np.array([extent[1] * extent[2], extent[2], 1], dtype=np.int64)
    keys = cells @ stride
    cell_keys, first, cell_of = np.unique(keys, return_index=True, return_inverse=True)
    cell_of = cell_of.reshape(-1)
    rep = vertices[first]

    pairs = []
    for offset in _NEIGHBOUR_OFFSETS @ stride:
        if offset <= 0:
            continue  # each neighbouring pair once
        at = np.searchsorted(cell_keys, cell_keys + offset)
        at = np.minimum(at, len(cell_keys) - 1)
        hit = np.flatnonzero(cell_keys[at] == cell_keys + offset)
        close = np.linalg.norm(rep[hit] - rep[at[hit]], axis=1) <= distance
        pairs.append(np.stack([hit[close], at[hit][close]], axis=1))
    pairs = np.concatenate(pairs) if pairs else np.zeros((0, 2), dtype=np.int64)

    label = connected_labels(len(cell_keys), pairs[:, 0], pairs[:, 1])
    return first[label[cell_of]]
