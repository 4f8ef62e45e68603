"""Public entry points: argument checking, then the engine."""
from __future__ import annotations

from typing import Callable, Optional, Sequence

import numpy as np

from .options import Options
from .result import SimplifyResult
from . import allocation, engine, prepare


def simplify(
    vertices,
    faces,
    *,
    target_faces: Optional[int] = None,
    ratio: Optional[float] = None,
    options: Optional[Options] = None,
    progress: Optional[Callable[[float], object]] = None,
    **option_values,
) -> SimplifyResult:
    """Simplify a triangle mesh by edge collapse under quadric + line-quadric error.

    vertices: (n, 3) float, faces: (m, 3) int. Lengths are in mesh units.

    Target: ``target_faces`` (an int) or ``ratio`` (of the input face count, in (0, 1]),
    optionally with the option ``max_error``; the run stops at whichever comes first.
    With only ``max_error`` it simplifies as far as that allows.

    How: ``options`` (a :class:`core.Options`, which documents every field) and/or its
    fields as keywords (``line_weight=0.01``), the keywords taking precedence.

    Stopping: when no collapse passes the quality rules (normal turn, slivers, seams, UV
    area and flips), they relax step by step for the remaining collapses (core.guards),
    so every target the topology allows is reached; ``stats.stop_reason`` is
    ``"topology_limit"`` when even the loosest step cannot go on, and
    ``"max_error_reached"`` when the distance bound holds collapses back (then no rule
    relaxes), and ``"limit_reached"`` when the painted limits (``vertex_max_error``) do,
    after every rule relaxed elsewhere.

    progress(fraction) is called after every pass and, in long ones, every quarter second
    between their steps (core.heartbeat); returning False raises SimplifyCancelled.
    The same input and seed give bit-identical output.
    """
    opts = Options.of(options, **option_values)
    target = _single_target(faces, target_faces, ratio, opts.max_error)
    return simplify_chain(vertices, faces, [target], opts, progress=progress)[0]


def simplify_chain(vertices, faces, targets: Sequence[int], options: Optional[Options] = None, *,
                   progress: Optional[Callable[[float], object]] = None, **option_values) -> list:
    """One simplification run that snapshots a LOD at each face count in ``targets``.

    targets: decreasing face counts. Returns one SimplifyResult per target, in order; each
    level is a coarsening of the previous one (edge collapse is progressive). Options as
    for :func:`simplify`.
    """
    opts = Options.of(options, **option_values)
    with allocation.reused_memory(len(faces) if hasattr(faces, "__len__") else 0):
        return engine.run(prepare.validate_and_prepare(vertices, faces, targets, opts, progress))


def _single_target(faces, target_faces, ratio, max_error) -> int:
    m = _face_count(faces)
    if target_faces is not None and ratio is not None:
        raise ValueError("give either target_faces or ratio, not both")
    if ratio is not None:
        ratio = float(ratio)
        if not np.isfinite(ratio) or not (0.0 < ratio <= 1.0):
            raise ValueError(f"ratio must be in (0, 1], got {ratio}")
        return max(int(round(ratio * m)), 0)
    if target_faces is not None:
        if isinstance(target_faces, bool) or int(target_faces) != target_faces:
            raise ValueError(f"target_faces must be a whole number, got {target_faces!r}")
        if target_faces < 0:
            raise ValueError(f"target_faces must be >= 0, got {target_faces}")
        return int(target_faces)
    if max_error is None:
        raise ValueError("give a target: target_faces, ratio or max_error")
    return 0


def _face_count(faces) -> int:
    shape = np.shape(faces)
    if len(shape) != 2 or shape[1] != 3:
        raise ValueError(f"faces must be an (m, 3) array of triangles, got shape {shape}")
    return shape[0]
