"""The input's own slivers go first.

The sliver rule (core.guards) keeps new slivers out, but it never removes the ones the
input has: the Fox kept two of its 70 to the 25 % LOD. So a candidate edge on a sliver
ranks cheaper, by (quality / floor)^4, and those collapses happen early, while they are
still cheap (at a square the Fox kept both of its last two; at the fourth power none are
left at 50, 25 and 10 %). Costs for max_error and the reported error stay undiscounted.
"""
from __future__ import annotations

import numpy as np

from .metrics import triangle_quality
from .selection import Candidates


def ranked_first(V, F, face_origin, input_quality, floor, conn, cand) -> Candidates:
    """``cand`` with the cost of every edge on a sliver (quality below ``floor``) scaled
    by (its worst face's quality / floor)^4.

    V, F: the current mesh; face_origin (m,) the input face of each; input_quality: the
    input faces' qualities. Only faces descending from an input sliver can be one now:
    the rule never lets a face drop below the floor, and a relaxed floor is only lower.
    """
    if floor <= 0 or len(cand.edge) == 0 or input_quality.min(initial=1.0) >= floor:
        return cand
    suspects = np.flatnonzero(np.take(input_quality, face_origin) < floor)
    quality = triangle_quality(V, np.take(F, suspects, axis=0))
    thin = quality < floor
    if not thin.any():
        return cand
    thin_faces, quality = suspects[thin], quality[thin]
    # The few sliver faces name their edges; every other candidate keeps its cost.
    edges = conn.he_edge[(3 * thin_faces[:, None] + np.arange(3)).ravel()]
    worst = np.ones(len(conn.edges))
    np.minimum.at(worst, edges, np.repeat(quality, 3))
    factor = (np.take(worst, cand.edge) / floor) ** 4
    return Candidates(cand.edge, cand.keep, cand.remove, cand.position, cand.cost * np.minimum(factor, 1.0))
