"""Welding coincident vertices, so split vertices of exported assets (one copy per UV or
normal) become one surface that can be simplified as the closed shape it is."""
from __future__ import annotations

import numpy as np


def weld_map(vertices: np.ndarray, distance) -> np.ndarray:
    """(n,) index of the representative each vertex is welded to (itself if none).

    distance: None welds exactly coincident positions; a positive value snaps positions
    to a grid of that size first (vertices closer than it usually share a cell; pairs
    straddling a cell border are left apart); negative disables welding.
    """
    n = len(vertices)
    if n == 0 or (distance is not None and distance < 0):
        return np.arange(n)
    key = vertices if not distance else np.floor(vertices / float(distance))
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    return first[inverse.reshape(-1)]
