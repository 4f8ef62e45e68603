"""The input's slivers: they go first, and where an open border forces thin faces, those
may stay.

The sliver rule (core.guards) keeps new slivers out, but it never removes the ones the
input has: the Fox kept two of its 70 to the 25 % LOD. So a candidate edge on a sliver
ranks cheaper, by (quality / floor)^4, and those collapses happen early, while they are
still cheap (at a square the Fox kept both of its last two; at the fourth power none are
left at 50, 25 and 10 %). Costs for max_error and the reported error stay undiscounted.

A face whose three corners all lie on open borders has the shape its border gives it:
no position of its corners makes a thin strip between two borders, or a thin patch
between its own corners, any fatter. The sliver rule would hold such faces at full
count instead, and spend the target elsewhere: on the Fox subdivided as imported (576
separate thin patches) that doubled the LOD's mean distance (0.0211 % against 0.0096 %)
and did not even lower its share of slivers (7.7 % against 4.9 %). So such a face may
be as thin as the rule lets an input sliver get, half the worst input sliver merged into
its corners (``border_floors``); every other face, and every border without an input
sliver, keeps the full floor.
"""
from __future__ import annotations

import numpy as np

from .guards import SLIVER_SLACK
from .metrics import SLIVER_QUALITY, triangle_quality
from .selection import Candidates

# An input with at least this share of slivers (one face in twenty) is a tessellation
# whose thin triangles are its shape, not its faults: CAD exports run cylinders and
# fillets in long strips (17-31 % on the 2CylinderEngine's parts, 7.2 % on BoomBox).
# Below it slivers are the odd bad face of a scan or a sculpt (the shared organic meshes:
# 0-4.2 %), which go first (ranked_first) and which the rule keeps out of the LOD; the
# rule then stays as it was and costs nothing per pass.
SLIVER_RICH_SHARE = 0.05


def sliver_allowance(input_quality) -> float:
    """The share of slivers a LOD of this input may have before the sliver rule applies:
    the input's own share where that is at least SLIVER_RICH_SHARE, else 0.

    A LOD is not asked to be better shaped than its source. On a CAD part whose input is
    a quarter slivers, holding every collapse to the floor cost up to 3.4x Blender
    Decimate's Hausdorff distance (the engine's body_1 at 25 %), and Decimate's LODs have
    about the input's share of slivers (20-37 % on those parts)."""
    quality = np.asarray(input_quality)
    return float(part_allowances(quality, np.zeros(len(quality), dtype=np.int64), 1)[0])


def part_allowances(input_quality, face_part, parts: int) -> np.ndarray:
    """(parts,) sliver_allowance of each part of a run of several (core.assembly), from
    its own faces: input_quality (m,) and face_part (m,) the part of each input face.

    Whether slivers are a part's shape or its faults is the part's own affair: a
    bevelled box (38 % strips) beside a monkey is 0.5 % slivers as one asset, and its
    bevels, taken for faults, went first (ranked_first) at LOD1, 0.55 % of its size from
    the source where the monkey's collapses cost 0.1 %."""
    part = np.asarray(face_part, dtype=np.int64)
    faces = np.bincount(part, minlength=parts)
    thin = np.bincount(part, weights=np.asarray(input_quality) < SLIVER_QUALITY, minlength=parts)
    share = thin / np.maximum(faces, 1)
    return np.where(share >= SLIVER_RICH_SHARE, share, 0.0)


def parts_within_allowance(quality, face_part, allowance: np.ndarray) -> np.ndarray:
    """(parts,) within_allowance of each part: fewer slivers among its faces (quality
    (m,) their triangle_quality, face_part (m,) the part of each) than its ``allowance``
    (parts,) share."""
    parts = len(allowance)
    faces = np.bincount(face_part, minlength=parts)
    thin = np.bincount(face_part, weights=quality < SLIVER_QUALITY, minlength=parts)
    return (allowance > 0) & (thin < allowance * faces)


def within_allowance(quality, allowance: float) -> bool:
    """Whether the mesh whose faces have triangle_quality ``quality`` (m,) has fewer
    slivers than ``allowance`` (a share): then this pass's collapses may make slivers
    (the floor is off)."""
    if allowance <= 0 or len(quality) == 0:
        return False
    return float(np.count_nonzero(quality < SLIVER_QUALITY)) < allowance * len(quality)


def worst_input_quality(F, n, quality) -> np.ndarray:
    """(n,) the worst quality of the input faces around each vertex (1 where none).

    F (m, 3) the input faces, quality (m,) theirs. A collapse's kept end takes the worse
    of its two ends' values (core.engine), so a vertex holds the worst input face
    merged into it."""
    worst = np.ones(n)
    np.minimum.at(worst, F.ravel(), np.repeat(quality, 3))
    return worst


def border_floors(min_quality, worst, border_vertex, keep, remove, nb_next, nb_prev, collapse):
    """(k,) the sliver rule's floor at each gathered corner (core.validation).

    min_quality: the step's floor; worst: ``worst_input_quality`` as carried so far;
    border_vertex (n,) bool; keep, remove (c,) the collapses' ends; nb_next, nb_prev (k,)
    the corner's face's two other corners, collapse (k,) its collapse. A face whose
    corners all end on open borders, with an input sliver merged into them, gets
    SLIVER_SLACK x the worst input quality merged into them; the rest, min_quality."""
    merged = np.minimum(worst[keep], worst[remove])[collapse]
    end_on_border = (border_vertex[keep] | border_vertex[remove])[collapse]
    bordered = end_on_border & border_vertex[nb_next] & border_vertex[nb_prev]
    input_worst = np.minimum(np.minimum(worst[nb_next], worst[nb_prev]), merged)
    return np.where(bordered & (input_worst < min_quality), SLIVER_SLACK * input_worst, min_quality)


def ranked_first(V, F, face_origin, input_quality, floor, conn, cand) -> Candidates:
    """``cand`` with the cost of every edge on a sliver (quality below ``floor``) scaled
    by (its worst face's quality / floor)^4.

    V, F: the current mesh; face_origin (m,) the input face of each; input_quality: the
    input faces' qualities. Only faces descending from an input sliver are looked at:
    the rule keeps every other face above the floor, but where the border forces it
    (``border_floors``), and those are not the input's.
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
