"""One triangle budget for a set of meshes (the parts of an asset), spread over them by error.

An asset is many parts: a body, clothes and eyes; a hull and its bolts. Given the same
ratio each, a bolt keeps half its triangles while the hull loses detail it needed, and a
two-triangle decal cannot be halved at all. Game LOD tools instead reduce the scene as a
whole (Simplygon's "scene-wide reduction"): a part keeps triangles in proportion to the
error its collapses would add.

The quadric error already ranks collapses that way (Garland & Heckbert 1997), across
separate surfaces as well as within one. So the split is one run of the core over every
part at once, in one frame of reference: the run takes the asset to each level's total,
and each part keeps what the run left of it (``face_origin`` says whose a face was).
The parts are then simplified one by one to those counts, each with its own attributes
(UVs, skin, shape keys), which this geometric run need not carry.
"""
from __future__ import annotations

from typing import Callable, Optional, Sequence

import numpy as np

from .options import Options
from .simplify import simplify_chain

# Per-vertex controls (core.Options) a part may bring; concatenated over the parts, each
# filled where a part has none with the value that means "as the options say".
_VERTEX_CONTROLS = ("quadric_scale", "line_weights")


def merged(parts: Sequence[tuple]) -> tuple:
    """(vertices (N, 3), faces (M, 3), face offsets (P + 1,)): the parts as one mesh, part
    p's faces at rows offsets[p]:offsets[p+1]. ``parts``: (vertices (n_p, 3), faces
    (m_p, 3)) each, in one frame."""
    vertex_counts = [len(v) for v, _ in parts]
    vertex_offsets = np.concatenate([[0], np.cumsum(vertex_counts)]).astype(np.int64)
    vertices = np.concatenate([np.asarray(v, dtype=np.float64).reshape(-1, 3) for v, _ in parts])
    faces = np.concatenate([np.asarray(f, dtype=np.int64).reshape(-1, 3) + vertex_offsets[p]
                            for p, (_, f) in enumerate(parts)])
    face_offsets = np.concatenate([[0], np.cumsum([len(f) for _, f in parts])]).astype(np.int64)
    return vertices, faces, face_offsets


def _merged_controls(parts: Sequence[tuple], controls: Optional[Sequence[Optional[dict]]], o: Options) -> dict:
    """The per-vertex controls of ``controls`` (one dict or None per part) as whole-asset
    arrays, plus the first line_scale_exponent given; {} when no part has any."""
    if not controls or not any(controls):
        return {}
    out = {}
    defaults = {"quadric_scale": 1.0, "line_weights": o.line_weight}
    for key in _VERTEX_CONTROLS:
        if any(c and c.get(key) is not None for c in controls):
            out[key] = np.concatenate([
                np.asarray(c[key], dtype=np.float64) if c and c.get(key) is not None
                else np.full(len(v), defaults[key]) for (v, _), c in zip(parts, controls)])
    exponents = [c["line_scale_exponent"] for c in controls if c and "line_scale_exponent" in c]
    if exponents and "quadric_scale" in out:
        out["line_scale_exponent"] = float(exponents[0])
    return out


def split_by_error(parts: Sequence[tuple], targets: Sequence[int], options: Optional[Options] = None, *,
                   controls: Optional[Sequence[Optional[dict]]] = None,
                   progress: Optional[Callable[[float], object]] = None) -> np.ndarray:
    """How many triangles each part keeps at each level when the parts are simplified
    together to the level's total.

    parts: (vertices (n_p, 3) float, faces (m_p, 3) int) per part, all in one frame and
      unit (the asset's), so that their errors compare.
    targets: the asset's triangle count per level, non-increasing, at most the sum of m_p.
    options: how to simplify (core.Options); per-vertex controls in it are ignored, give
      them per part in ``controls`` ({"quadric_scale": (n_p,), "line_weights": (n_p,),
      "line_scale_exponent": float}, or None for a part without).
    Returns (levels, P) int64: part p's triangles at each level. Each column is
    non-increasing; a row sums to the level's target unless the run stopped above it
    (then to what it reached). A 0 means the part was removed at that level
    (``remove_small_components``). Raises ValueError for parts without faces.
    """
    if not parts:
        raise ValueError("give at least one part")
    empty = [p for p, (_, f) in enumerate(parts) if len(f) == 0]
    if empty:
        raise ValueError(f"part {empty[0]} has no faces")
    o = Options() if options is None else options
    o = Options.of(o, max_error=None, locked=None, line_weights=None, quadric_scale=None, pose_offsets=None, pose_weight=0.0,
                   vertex_attributes={}, corner_attributes={}, normalize_attributes=(), uv_attributes=(),
                   shape_attributes=(), feature_edges=None, edge_weights=None)
    vertices, faces, face_offsets = merged(parts)
    extra = _merged_controls(parts, controls, o)
    if extra:
        o = Options.of(o, **extra)
    results = simplify_chain(vertices, faces, list(targets), o, progress=progress)
    counts = np.empty((len(results), len(parts)), dtype=np.int64)
    for level, result in enumerate(results):
        owner = np.searchsorted(face_offsets, result.face_origin, side="right") - 1
        counts[level] = np.bincount(owner, minlength=len(parts))
    return counts
