"""One triangle budget for a set of meshes (the parts of an asset), spread over them by error.

An asset is many parts: a body, clothes and eyes; a hull and its bolts. Given the same
ratio each, a bolt keeps half its triangles while the hull loses detail it needed, and a
two-triangle decal cannot be halved at all. Game LOD tools instead reduce the scene as a
whole (Simplygon's "scene-wide reduction"): every part is taken to the same error, and
the error is whatever makes the whole asset meet its triangle budget.

Each part's own run says what its triangles cost: snapshotted down a ladder of counts,
it gives the part's error curve (:func:`error_curve`: the running largest RMS quadric
distance of an accepted collapse, core.SimplifyStats.max_error, Garland & Heckbert 1997,
with the part's own attributes, seams and features holding it back). For each level one
error eps is then found, by bisection, at which the parts' counts add up to the level's
budget (:func:`split_by_error`), every part weighted by how many times the asset draws
it. A part may also leave the asset (:func:`with_removal`) once the level's error is
larger than what its removal costs, as game LOD tools drop bolts from far LODs. Equal error is what minimises the largest error (the asset's Hausdorff distance is
the largest of its parts') for a given total. Measured on the shared assets
(bench/assets.py), this split beat both one merged geometry-only run, whose order did
not see the parts' custom normals and seams (2.5x the Hausdorff distance on a CAD
engine at 50 %), and the same ratio for every part.
"""
from __future__ import annotations

from typing import Callable, Optional, Sequence

import numpy as np

from .options import Options
from .simplify import simplify_chain

LADDER_FACTOR = 0.8  # each rung of an error curve has this share of the one before


def ladder(m: int, floor: int = 0, factor: float = LADDER_FACTOR) -> list:
    """Decreasing triangle counts from ``factor`` * m down to ``floor`` (included)."""
    rungs = []
    t = m * factor
    while t > max(floor, 1):
        rungs.append(int(t))
        t *= factor
    return sorted(set(rungs + [int(floor)]), reverse=True)


def error_curve(vertices, faces, options: Optional[Options] = None, *, floor: int = 0,
                factor: float = LADDER_FACTOR, progress: Optional[Callable[[float], object]] = None) -> tuple:
    """(counts, errors), both (k,) float64: the mesh simplified once down a ladder of
    counts to ``floor``, and the error each rung had reached, in mesh units. counts[0] is
    the mesh's own count at error 0; counts decrease, errors never do."""
    m = len(faces)
    results = simplify_chain(vertices, faces, ladder(m, floor, factor), options, progress=progress)
    counts = np.array([m] + [len(r.faces) for r in results], dtype=np.float64)
    errors = np.maximum.accumulate(np.array([0.0] + [float(r.stats.max_error) for r in results]))
    return counts, errors


def with_removal(curve: tuple, error: float) -> tuple:
    """``curve`` with the part's removal as its last step: at ``error`` (what leaving the
    asset costs, in the curve's unit) its count drops from the last rung's to 0. Unchanged
    when the curve already reaches that error (removing it would cost no less)."""
    counts, errors = curve
    if not error > errors[-1] or counts[-1] == 0:
        return curve
    step = np.nextafter(error, 0.0) if np.nextafter(error, 0.0) > errors[-1] else error
    return (np.concatenate([counts, [counts[-1], 0.0]]), np.concatenate([errors, [step, error]]))


def count_at(curve: tuple, eps: float) -> float:
    """A part's triangle count at error ``eps``: linear between the rungs around it (the
    last rung's count beyond the curve)."""
    counts, errors = curve
    if eps >= errors[-1]:
        return float(counts[-1])
    i = int(np.searchsorted(errors, eps, side="right"))  # errors[i-1] <= eps < errors[i]
    lo, hi = errors[i - 1], errors[i]
    f = 0.0 if hi <= lo else (eps - lo) / (hi - lo)
    return float(counts[i - 1] + f * (counts[i] - counts[i - 1]))


def split_by_error(curves: Sequence[tuple], targets: Sequence[int], weights: Optional[Sequence[float]] = None,
                   iterations: int = 60) -> np.ndarray:
    """How many triangles each part keeps at each level: every part at one error eps per
    level, the eps at which sum(weights * counts) meets the level's target.

    curves: per part its :func:`error_curve`, errors in one unit (the asset's).
    targets: the asset's triangle count per level (what it draws), non-increasing.
    weights: per part how many times the asset draws it (default 1).
    Returns (levels, parts) int64, each column non-increasing and at most the part's own
    count; 0 for a part whose curve ends in its removal (with_removal) past that error. A level the curves cannot reach (below every part's last rung) gets the last
    rungs. Where many collapses cost the same (flat regions: 0), the parts at that error
    share what the target leaves in proportion to what they could still give.
    """
    if not curves:
        raise ValueError("give at least one part")
    w = np.ones(len(curves)) if weights is None else np.asarray(weights, dtype=np.float64)
    if len(w) != len(curves):
        raise ValueError(f"{len(w)} weights for {len(curves)} parts")
    top = max(float(c[1][-1]) for c in curves)
    out = []
    for target in targets:
        lo, hi = 0.0, top
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            drawn = float(np.dot(w, [count_at(c, mid) for c in curves]))
            lo, hi = (mid, hi) if drawn > target else (lo, mid)
        above = np.array([count_at(c, lo) for c in curves])
        below = np.array([count_at(c, hi) for c in curves])
        jump = float(np.dot(w, above - below))
        f = 0.0 if jump <= 0 else min(max((target - float(np.dot(w, below))) / jump, 0.0), 1.0)
        level = below + f * (above - below)
        # A part leaving (with_removal) leaves whole: between its last rung and 0, the nearer.
        for p, (counts, _) in enumerate(curves):
            if counts[-1] == 0 and len(counts) > 1 and 0 < level[p] < counts[-2]:
                level[p] = counts[-2] if level[p] >= counts[-2] / 2 else 0.0
        out.append(np.rint(level))
    counts = np.asarray(out, dtype=np.int64).reshape(len(out), len(curves))
    return np.minimum.accumulate(counts, axis=0)
