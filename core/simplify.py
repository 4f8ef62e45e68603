"""Public entry points: argument checking, then the engine."""
from __future__ import annotations

from typing import Callable, Mapping, Optional, Sequence

import numpy as np

from .features import DEFAULT_FEATURE_ANGLE
from .guards import SLIVER_QUALITY
from .result import SimplifyResult
from . import engine, prepare


def simplify(
    vertices,
    faces,
    *,
    target_faces: Optional[int] = None,
    ratio: Optional[float] = None,
    max_error: Optional[float] = None,
    line_weight: float = 1e-3,
    vertex_weights=None,
    importance=None,
    boundary_weight: float = 1.0,
    locked=None,
    progress: Optional[Callable[[float], object]] = None,
    seed: int = 0,
    vertex_attributes: Optional[Mapping[str, np.ndarray]] = None,
    normalize_attributes: Sequence[str] = (),
    corner_attributes: Optional[Mapping[str, np.ndarray]] = None,
    uv_attributes: Sequence[str] = (),
    preserve_seams: bool = True,
    feature_edges=None,
    feature_weight: float = 1.0,
    edge_weights=None,
    weld_distance: Optional[float] = None,
    probabilistic_sigma: float = 0.0,
    feature_angle: Optional[float] = DEFAULT_FEATURE_ANGLE,
    min_quality: float = SLIVER_QUALITY,
    remove_small_components: bool = False,
    shape_attributes: Sequence[str] = (),
) -> SimplifyResult:
    """Simplify a triangle mesh by edge collapse under quadric + line-quadric error.

    vertices: (n, 3) float, faces: (m, 3) int. Lengths are in mesh units.

    Target: ``target_faces`` (an int) or ``ratio`` (of the input face count, in (0, 1]),
    optionally with ``max_error`` (an RMS distance in mesh units: no collapse whose
    quadric error, divided by the area it stands for, exceeds max_error**2); the run stops
    at whichever comes first. With only ``max_error`` it simplifies as far as that allows.

    Controls (paper Eq. 16 and Sec. 4.4):
      line_weight: w for every vertex (1e-3 by default; 0 gives plain Garland-Heckbert).
      vertex_weights: (n,) per-vertex w_i >= 0, replaces line_weight where given.
      importance: (n,) >= 0, the extreme-weight variant: the augmented quadric of vertex i
        is scaled by (1 + importance_i), so flat regions are controllable too.
      boundary_weight: weight of the planes through open boundary edges (0 turns them off).
      locked: (n,) bool, vertices that never move and are never removed.
      feature_edges: (k, 2) vertex pairs kept softly by dihedral-plane quadrics (Eq. 18-19)
        weighted by ``feature_weight`` or by per-edge ``edge_weights`` (k,).
      feature_angle: degrees in [0, 180) (80 by default), or None/0 (off): interior edges
        whose faces' normals differ by more than this are creases, kept softly like
        ``feature_edges`` (weighted by ``feature_weight``); vertices where three or more
        creases or feature edges meet, and open-boundary vertices where the boundary
        turns by more than half the angle, are corners and stay put (unless the target
        cannot be reached otherwise).
      min_quality: in [0, 1], the triangle quality (4 sqrt(3) area / sum of squared edges;
        1 for equilateral) below which no collapse may turn a face (0.3 by default, 0 turns
        the rule off): lower it for closer hard-surface shapes at the cost of slivers.
      remove_small_components: when no collapse is possible short of the target, delete
        whole parts, smallest area first (never the largest, never one with a locked
        vertex), instead of stopping above the target.
      probabilistic_sigma: >= 0, the alternative regulariser the paper compares with
        (Trettner & Kobbelt 2020): the standard deviation of isotropic noise on the unit
        face normals (dimensionless; sigma^2 plays the part of w). 0 (default) leaves it
        off; combine with line_weight=0 to compare the two.

    Carried data:
      vertex_attributes: {name: (n, k)} interpolated along each collapsed edge.
      normalize_attributes: names among vertex_attributes whose rows summed to one and must
        keep doing so (skin weights).
      corner_attributes: {name: (m, 3, k)} per face corner (UVs, corner colours); an edge
        across which one of them is discontinuous is a seam, kept when preserve_seams.
      uv_attributes: names among corner_attributes (k = 2) whose triangles must not flip.
      shape_attributes: names among vertex_attributes (k = 3) that are shape-key offsets
        (mesh units): the LOD is kept close at each key's full value too, not only at rest
        (the strongest 16 count; core.shape_keys).
      weld_distance: weld vertices closer than this before simplifying (split vertices of
        exported assets); None welds only exactly coincident ones, a negative value none.

    Stopping: when no collapse passes the quality rules (normal turn, slivers, seams, UV
    area and flips), they relax step by step for the remaining collapses (core.guards),
    so every target the topology allows is reached; ``stats.stop_reason`` is
    ``"topology_limit"`` when even the loosest step cannot go on.

    progress(fraction) is called once per pass; returning False raises SimplifyCancelled.
    The same input and seed give bit-identical output.
    """
    return simplify_chain(
        vertices,
        faces,
        targets=[_single_target(faces, target_faces, ratio, max_error)],
        max_error=max_error,
        line_weight=line_weight,
        vertex_weights=vertex_weights,
        importance=importance,
        boundary_weight=boundary_weight,
        locked=locked,
        progress=progress,
        seed=seed,
        vertex_attributes=vertex_attributes,
        normalize_attributes=normalize_attributes,
        corner_attributes=corner_attributes,
        uv_attributes=uv_attributes,
        preserve_seams=preserve_seams,
        feature_edges=feature_edges,
        feature_weight=feature_weight,
        edge_weights=edge_weights,
        weld_distance=weld_distance,
        probabilistic_sigma=probabilistic_sigma,
        feature_angle=feature_angle,
        min_quality=min_quality,
        remove_small_components=remove_small_components,
        shape_attributes=shape_attributes,
    )[0]


def simplify_chain(vertices, faces, targets: Sequence[int], **options) -> list:
    """One simplification run that snapshots a LOD at each face count in ``targets``.

    targets: decreasing face counts. Returns one SimplifyResult per target, in order; each
    level is a coarsening of the previous one (edge collapse is progressive). Takes every
    option of :func:`simplify` except target_faces/ratio.
    """
    problem = prepare.validate_and_prepare(vertices, faces, targets, options)
    return engine.run(problem)


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
