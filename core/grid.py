"""A uniform grid over points, for neighbour searches without a tree: each point's cell
as one int64 key, and for query keys every point in that cell (core.stitching's
T-junction search, core.features.nearest_other's corner spacing).

Cells are numbered from 1 so that a query one cell beyond the points' box (an offset of
NEIGHBOURS) never wraps onto a key in use.
"""
from __future__ import annotations

import numpy as np

# The 27 cell offsets around (and including) a cell, (27, 3).
NEIGHBOURS = np.stack(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1], indexing="ij"), -1).reshape(-1, 3)


def cells(points: np.ndarray, lo: np.ndarray, size: float) -> np.ndarray:
    """(k, 3) int64 the cell of each point of a grid of cubes of ``size`` from ``lo``."""
    return np.floor((points - lo) / size).astype(np.int64) + 1


def strides(*cell_arrays: np.ndarray) -> np.ndarray:
    """(3,) int64: a cell's key is its cell @ strides, unique over the cells given and
    their neighbours."""
    extent = np.max([c.max(axis=0) for c in cell_arrays], axis=0) + 2
    return np.array([1, extent[0], extent[0] * extent[1]], dtype=np.int64)


def in_cells(sorted_keys: np.ndarray, keys: np.ndarray) -> tuple:
    """Every entry of ``sorted_keys`` equal to each of ``keys``: (rows (p,), the index of
    its query in ``keys``; at (p,), its index in ``sorted_keys``), query by query."""
    first = np.searchsorted(sorted_keys, keys, side="left")
    count = np.searchsorted(sorted_keys, keys, side="right") - first
    total = int(count.sum())
    rows = np.repeat(np.arange(len(keys)), count)
    at = np.repeat(first, count) + np.arange(total) - np.repeat(np.cumsum(count) - count, count)
    return rows, at
