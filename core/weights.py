"""Per-vertex line-quadric weights derived from data the artist already has."""
from __future__ import annotations

import numpy as np

# Paper Sec. 5.3: w_i = c (1 - s_i) with c = 0.15, kept at or below 0.1.
SKIN_WEIGHT_SCALE = 0.15
SKIN_WEIGHT_MAX = 0.1


def skin_line_weights(
    skin_weights: np.ndarray, scale: float = SKIN_WEIGHT_SCALE, cap: float = SKIN_WEIGHT_MAX
) -> np.ndarray:
    """Per-vertex line-quadric weights w_i that favour joints, from skinning weights
    (pass them as ``line_weights``).

    skin_weights: (n, b) float, the weight of each of b deform bones at each vertex.
    Returns (n,) float64 w_i = min(scale * (1 - s_i), cap), s_i the largest bone weight at
    vertex i: vertices shared by several bones (near joints) get high weights, vertices
    driven by a single bone get none. Unweighted vertices (all zeros) get the cap.
    """
    s = np.asarray(skin_weights, dtype=np.float64)
    if s.ndim != 2:
        raise ValueError(f"skin_weights must be (n, bones), got shape {s.shape}")
    if s.shape[1] == 0:
        return np.full(s.shape[0], float(cap))
    largest = np.clip(s.max(axis=1), 0.0, 1.0)
    return np.minimum(scale * (1.0 - largest), cap)
