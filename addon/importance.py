# SPDX-License-Identifier: GPL-3.0-or-later
"""What the Importance settings mean, as numbers the core understands.

An artist gives importance as a value g_i in [0, 1] per vertex: a painted vertex group,
or the skin-derived weight of the paper (Sec. 5.3) divided by its cap 0.1, which is also
what "Importance from Armature" bakes into the LOD_Importance group so it can be seen
and repainted. The Strength slider (0..1) then says how much g counts:

Soft (paper Eq. 16, the default). Vertex i gets the line-quadric weight
    w_i = line_weight + strength * 0.1 * g_i.
Strength 1 gives a fully painted vertex w = 0.1, the largest weight the paper
recommends before shape fidelity suffers (Sec. 4.2); for an armature that is exactly
the paper's w_i = min(0.15 (1 - s_i), 0.1). Soft importance keeps a region denser
through the simplification without freezing it, and never trades away shape.

Strong (paper Sec. 4.4.1, extreme weights). The painted vertices get the small added
line quadric the paper recommends (0.01 at full paint), then their whole quadric is
multiplied by
    1 + importance_i = 1000 ** (strength * g_i).
The slider is exponential because what an artist sees is density, which follows the
factor's logarithm: strength 1 makes a fully painted vertex's error count 1000x, 0.5
makes it 32x, 0 changes nothing, and each step of the slider multiplies the density by
about the same amount.

What it does, measured: tests/test_addon_importance.py checks that the painted region's
vertex density rises with strength in both modes while the target is met and the region
is still simplified (soft, not frozen); docs/figures.md (Fig. 1 and 5) gives the densities
bench/fig_importance.py measures on a flat grid with a painted disc.
"""
from __future__ import annotations

import numpy as np

from ._core import core

SOFT_MAX_WEIGHT = 0.1  # w of a fully painted vertex at strength 1 (paper's recommended maximum)
STRONG_LINE_WEIGHT = 0.01  # the paper's "small amount of line quadrics" before scaling
STRONG_MAX_FACTOR = 1000.0  # error factor of a fully painted vertex at strength 1
SKIN_CAP = core.weights.SKIN_WEIGHT_MAX  # 0.1: skin weights are baked as w / cap in [0, 1]


def skin_importance(skin_weights: np.ndarray) -> np.ndarray:
    """Paper Sec. 5.3 weights from (n, bones) deform weights, normalised to [0, 1] (w / 0.1)."""
    return core.importance_from_skin_weights(skin_weights) / SKIN_CAP


def controls(g: np.ndarray, line_weight: float, strength: float, mode: str) -> dict:
    """Core keyword arguments (vertex_weights, importance) for importance g in [0, 1].

    mode: 'SOFT' or 'STRONG' (see the module docstring for what strength means).
    """
    g = np.clip(np.asarray(g, dtype=np.float64), 0.0, 1.0)
    s = float(strength)
    if mode == 'SOFT':
        return {"vertex_weights": line_weight + s * SOFT_MAX_WEIGHT * g}
    if mode == 'STRONG':
        return {
            "vertex_weights": line_weight + (STRONG_LINE_WEIGHT if s > 0 else 0.0) * g,
            "importance": np.power(STRONG_MAX_FACTOR, s * g) - 1.0,
        }
    raise ValueError(f"importance mode must be 'SOFT' or 'STRONG', got {mode!r}")
