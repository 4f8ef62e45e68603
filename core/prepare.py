"""Step 0: check every argument and clean the input into a Problem for the engine.

Positions are normalised (centred, unit bounding-box diagonal) because quadric sums of
large coordinates lose precision to cancellation; coincident vertices are welded and
faces that became degenerate or duplicate, or have zero area, are dropped, since they
cannot be simplified and would break the manifold checks. Then the faults of exported
tessellations are repaired for the run: T-junction cracks closed (core.stitching) and
every part wound one way (core.orientation); the LOD comes back with the input's
windings and face origins (core.engine._snapshot).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Optional

import numpy as np

from . import checks, repair
from .metrics import triangle_quality
from .options import Options
from .weld import weld_map
from . import locality


# Below this triangle quality (core.metrics: 1 equilateral, about 1.7 height / longest
# edge) a face's corners lie on one line as far as float32 positions can tell.
ZERO_AREA_QUALITY = 1e-6


@dataclass
class Problem:
    """What the engine runs on: the Options it came from (checked: ``options``) and the
    arrays derived from them and the input, in normalised units."""

    options: Options  # as given, checked (feature_angle 0 is None: off)
    vertices: np.ndarray  # normalised: centred on the bounding box, unit diagonal
    input_positions: np.ndarray  # as given: vertices that never move come back bit-exact
    faces: np.ndarray  # engine.run takes them over and sets this to None (memory, see there)
    face_origin: np.ndarray
    vertex_origin: np.ndarray
    targets: list
    max_error: object  # one bound per target, normalised units, or None
    vertex_limits: object  # (targets, n) Options.vertex_max_error, normalised units (inf: free), or None
    line_weights: np.ndarray  # w_i of Eq. 16, per vertex
    quadric_scale: object  # (n,) >= 1 (Sec. 4.4.1), or None
    locked: np.ndarray  # (n,) bool
    progress: object
    vertex_attributes: dict  # options.vertex_attributes plus the sample poses' offsets
    corner_attributes: dict
    feature_edges: np.ndarray  # (k, 2), welded
    feature_edge_weights: np.ndarray  # (k,)
    pose_attributes: tuple  # names of the vertex attributes that hold pose_offsets (error only)
    center: np.ndarray
    scale: float
    input_vertices: int
    input_faces: int
    welded: int = 0
    flipped_origin: object = None  # (run faces,) bool: turned over by core.orientation, or None
    run_faces: int = 0  # face ids of the run (face_origin's range): input_faces unless stitched
    face_source: object = None  # (run faces,) the input face of each run face id, or None: the same
    unsplit_faces: object = None  # (run faces, 3) the face each run face was split from, or None
    connectivity: object = None  # topology.build of ``faces`` when prepare had it (engine.run reuses it)
    renumbered: bool = False  # vertices and faces in core.locality's order, not the input's
    copies: object = None  # (n,) how many times each vertex's part is drawn (Options.part_copies), or None


@dataclass
class Checked:
    """Every argument checked (core.checks), as arrays, in the input's units."""

    options: Options
    vertices: np.ndarray
    faces: np.ndarray
    targets: list
    max_error: object
    vertex_limits: object
    line_weights: np.ndarray
    quadric_scale: object
    locked: np.ndarray
    vertex_attributes: dict
    corner_attributes: dict
    feature_edges: np.ndarray
    feature_edge_weights: np.ndarray
    pose_attributes: tuple
    vertex_part: object = None  # (n,) int64 Options.vertex_part, or None
    copies: object = None  # (n,) Options.part_copies per vertex, or None


def validate_and_prepare(vertices, faces, targets, o: Optional[Options] = None, progress=None) -> Problem:
    """Check every argument (ValueError naming the problem), normalise the positions,
    clean the input (weld, drop what cannot be simplified), renumber a large mesh for
    locality and repair what exporters write (core.repair): the steps below, in order."""
    c = checked(vertices, faces, targets, Options() if o is None else o, progress)
    center, scale = _frame(c.vertices)
    vn = (c.vertices - center) / scale
    rep, keep, twin = _cleaned(vn, c.faces, c.options.weld_distance, scale, c.vertex_part)
    n, m = len(vn), len(c.faces)
    welded = int(np.count_nonzero(rep != np.arange(n)))
    locked, line_weights, quadric_scale = c.locked, c.line_weights, c.quadric_scale
    tightness = None if c.vertex_limits is None else scale / c.vertex_limits  # 1 / limit, normalised
    if welded:  # welded vertices pool their locks, weights, scales and limits: the strongest wins
        locked = np.bincount(rep, weights=locked, minlength=n)[rep] > 0
        line_weights = _max_by_group(line_weights, rep, n)
        if quadric_scale is not None:
            quadric_scale = _max_by_group(quadric_scale, rep, n)
        if tightness is not None:
            tightness = np.stack([_max_by_group(row, rep, n) for row in tightness])
    problem = locality.reorder(Problem(
        options=c.options,
        vertices=vn,
        input_positions=c.vertices,
        faces=rep[c.faces][keep] if m else c.faces,
        face_origin=np.flatnonzero(keep),
        vertex_origin=np.arange(n),
        targets=c.targets,
        max_error=None if c.max_error is None else [e / scale for e in c.max_error],
        vertex_limits=None if tightness is None else _inverse(tightness),
        line_weights=line_weights,
        quadric_scale=quadric_scale,
        locked=locked,
        progress=progress,
        vertex_attributes=c.vertex_attributes,
        corner_attributes={k: a[keep] for k, a in c.corner_attributes.items()},
        feature_edges=rep[c.feature_edges] if len(c.feature_edges) else c.feature_edges,
        feature_edge_weights=c.feature_edge_weights,
        pose_attributes=c.pose_attributes,
        center=center,
        scale=scale,
        input_vertices=n,
        input_faces=m,
        welded=welded,
        run_faces=m,
        copies=c.copies,
    ))
    return repair.repaired(problem, twin, stitch=bool(c.options.stitch_cracks))


def checked(vertices, faces, targets, o: Options, progress=None) -> Checked:
    """Every argument checked, ValueError naming the first problem found."""
    v = checks.as_vertices(vertices)
    n = len(v)
    f = checks.as_faces(faces, n)
    m = len(f)
    vertex_part, copies = checks.parts(o.vertex_part, o.part_copies, n)
    drawn = None if copies is None else int(round(float(copies[f[:, 0]].sum()))) if m else 0
    tgt = checks.targets(targets, m, drawn)
    max_error = None if o.max_error is None else checks.max_errors(o.max_error, len(tgt))
    vertex_limits = None if o.vertex_max_error is None else checks.limits(o.vertex_max_error, n, len(tgt),
                                                                           "vertex_max_error")
    line_weight = checks.non_negative(o.line_weight, "line_weight")
    line_weights = (np.full(n, line_weight) if o.line_weights is None
                    else checks.per_vertex(o.line_weights, n, "line_weights"))
    quadric_scale = None
    if o.quadric_scale is not None:
        quadric_scale = checks.per_vertex(o.quadric_scale, n, "quadric_scale")
        if n and quadric_scale.min() < 1:
            raise ValueError(f"quadric_scale must be >= 1 (found {quadric_scale.min()}): "
                             f"it multiplies the error, 1 leaves it as it is")
    line_scale_exponent = checks.non_negative(o.line_scale_exponent, "line_scale_exponent")
    if line_scale_exponent == 0:
        raise ValueError("line_scale_exponent must be > 0: at 0 quadric_scale would leave the line quadric "
                         "unscaled and a flat region uncontrollable")
    boundary_weight = checks.non_negative(o.boundary_weight, "boundary_weight")
    probabilistic_sigma = checks.non_negative(o.probabilistic_sigma, "probabilistic_sigma")
    locked = np.zeros(n, dtype=bool) if o.locked is None else checks.per_vertex(o.locked, n, "locked", dtype=bool)
    if progress is not None and not callable(progress):
        raise ValueError("progress must be callable (fraction) -> bool")
    if isinstance(o.seed, bool) or not isinstance(o.seed, (int, np.integer)):
        raise ValueError(f"seed must be an integer, got {o.seed!r}")
    vattrs = checks.vertex_attributes(o.vertex_attributes, n)
    for name in o.normalize_attributes or ():
        if name not in vattrs:
            raise ValueError(f"normalize_attributes names {name!r}, which is not a vertex attribute")
    cattrs = checks.corner_attributes(o.corner_attributes, m)
    for name in o.uv_attributes or ():
        if name not in cattrs or cattrs[name].shape[2] != 2:
            raise ValueError(f"uv_attributes names {name!r}, which is not a 2-component corner attribute")
    for name in o.seamless_attributes or ():
        if name not in cattrs:
            raise ValueError(f"seamless_attributes names {name!r}, which is not a corner attribute")
    fe = checks.edge_list(o.feature_edges if o.feature_edges is not None else [], n, "feature_edges")
    feature_weight = checks.non_negative(o.feature_weight, "feature_weight")
    feature_angle = o.feature_angle
    if feature_angle is not None:
        feature_angle = checks.non_negative(feature_angle, "feature_angle")
        if feature_angle >= 180:
            raise ValueError(f"feature_angle is in degrees and must be below 180, got {feature_angle}")
        feature_angle = feature_angle or None  # 0 turns it off, like None
    min_quality = checks.non_negative(o.min_quality, "min_quality")
    if min_quality > 1:
        raise ValueError(f"min_quality is a triangle quality in [0, 1], got {min_quality}")
    ew = o.edge_weights
    if ew is None:
        few = np.full(len(fe), feature_weight)
    else:
        few = np.asarray(ew, dtype=np.float64)
        if few.shape != (len(fe),):
            raise ValueError(f"edge_weights must have one value per feature edge ({len(fe)}), got shape {few.shape}")
        if not np.isfinite(few).all() or (few < 0).any():
            raise ValueError("edge_weights must be finite and >= 0")
    for name in o.shape_attributes or ():
        if name not in vattrs or vattrs[name].shape[1] != 3:
            raise ValueError(f"shape_attributes names {name!r}, which is not a 3-component vertex attribute")
    pose_weight = checks.non_negative(o.pose_weight, "pose_weight")
    key_scale_exponent = checks.non_negative(o.key_scale_exponent, "key_scale_exponent")
    poses = ()
    if o.pose_offsets is not None and pose_weight > 0:
        offsets = np.asarray(o.pose_offsets, dtype=np.float64)
        if offsets.ndim != 3 or offsets.shape[1:] != (n, 3):
            raise ValueError(f"pose_offsets must be (poses, n, 3) with n = {n}, got shape {offsets.shape}")
        if not np.isfinite(offsets).all():
            raise ValueError("pose_offsets must be finite")
        # Carried through the run like vertex attributes (interpolated along collapses),
        # under names no caller can give, and left out of the result.
        vattrs = dict(vattrs)
        poses = tuple(f"\0pose{i}" for i in range(len(offsets)))
        for name, offset in zip(poses, offsets):
            vattrs[name] = offset
    options = dataclasses.replace(
        o, feature_angle=feature_angle, seed=int(o.seed), line_scale_exponent=line_scale_exponent,
        boundary_weight=boundary_weight, probabilistic_sigma=probabilistic_sigma, feature_weight=feature_weight,
        min_quality=min_quality, pose_weight=pose_weight, key_scale_exponent=key_scale_exponent,
        preserve_seams=bool(o.preserve_seams), plane_placement=bool(o.plane_placement),
        remove_small_components=bool(o.remove_small_components), normalize_attributes=tuple(o.normalize_attributes or ()),
        uv_attributes=tuple(o.uv_attributes or ()), seamless_attributes=tuple(o.seamless_attributes or ()),
        shape_attributes=tuple(o.shape_attributes or ()),
        weld_distance=None if o.weld_distance is None else float(o.weld_distance))
    return Checked(options, v, f, tgt, max_error, vertex_limits, line_weights, quadric_scale, locked, vattrs, cattrs, fe, few,
                   poses, vertex_part, copies)


def _frame(v: np.ndarray) -> tuple:
    """(center, scale) of the normalised frame: centred on the bounding box, unit
    diagonal. Quadric sums of large coordinates lose precision to cancellation."""
    if len(v) == 0:
        return np.zeros(3), 1.0
    lo, hi = v.min(axis=0), v.max(axis=0)
    return 0.5 * (lo + hi), float(np.linalg.norm(hi - lo)) or 1.0


def _cleaned(vn: np.ndarray, f: np.ndarray, weld_distance, scale: float, vertex_part=None) -> tuple:
    """(rep, keep, twin): each vertex's weld representative (n,), the faces kept (m,)
    bool, and each face's first copy wound the other way or -1 (m,) (None without faces).

    Coincident vertices (exported assets) are welded; then faces that became degenerate,
    repeat another face or have zero area are dropped: they cannot be simplified and would
    break the manifold checks. ``vertex_part``: (n,) labels, or None; vertices of
    different parts are not welded (the parts of an asset touch, and come back apart)."""
    n, m = len(vn), len(f)
    distance = None if weld_distance is None else (weld_distance / scale if weld_distance > 0 else weld_distance)
    rep = weld_map(vn, distance)
    if vertex_part is not None:
        rep = _within_parts(rep, vertex_part)
    if m == 0:
        return rep, np.zeros(0, dtype=bool), None
    fw = rep[f]
    keep = (fw[:, 0] != fw[:, 1]) & (fw[:, 1] != fw[:, 2]) & (fw[:, 0] != fw[:, 2])
    first, twin = _first_copies(fw, n)
    keep &= first
    # Faces whose corners lie on one line (to float32 precision) have no area to keep
    # and no normal; exporters write them where they bridge a T-junction, (a, m, b)
    # beside a face on (a, b), which puts three faces on that edge. Without them the
    # junction is an open slit, which core.stitching closes.
    keep[keep] &= triangle_quality(vn, fw[keep]) >= ZERO_AREA_QUALITY
    return rep, keep, twin


def _within_parts(rep: np.ndarray, part: np.ndarray) -> np.ndarray:
    """A weld map (n,) split by part: each vertex goes to the first vertex of its weld
    group that lies in its own part."""
    n = len(rep)
    key = rep * np.int64(int(part.max()) + 1) + part  # < n * parts: fits int64
    _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    return first[inverse.reshape(-1)]


def _first_copies(faces: np.ndarray, n: int) -> tuple:
    """((m,) bool: the first of the faces with each set of corners; (m,) int64: for each
    face, the first face of its set wound the other way, or -1). faces (m, 3).

    Two stable integer sorts, by the first two corners and then by that pair's rank and
    the third corner; a single key a*n^2 + b*n + c would overflow int64 from 2M vertices,
    and np.unique(axis=0) sorts the rows as raw bytes, 25 times slower (6 s at 8M faces)."""
    m = len(faces)
    sorted_faces = np.sort(faces, axis=1).astype(np.int64, copy=False)  # NumPy 1.x keeps int32 * np.int64(n) in int32
    pair = sorted_faces[:, 0] * np.int64(n) + sorted_faces[:, 1]
    by_pair = np.argsort(pair, kind="stable")
    ordered = pair[by_pair]
    rank = np.empty(m, dtype=np.int64)
    rank[by_pair] = np.cumsum(np.concatenate([[True], ordered[1:] != ordered[:-1]])) - 1
    triple = rank * np.int64(n) + sorted_faces[:, 2]  # < m * n: fits int64
    by_triple = np.argsort(triple, kind="stable")
    ordered = triple[by_triple]
    starts = np.concatenate([[True], ordered[1:] != ordered[:-1]])
    first = np.zeros(m, dtype=bool)
    first[by_triple[starts]] = True
    # A duplicate wound the other way: each face's winding is the parity of the rotation
    # that starts it at its smallest corner (a, b, c -> even where b < c).
    group = np.empty(m, dtype=np.int64)
    group[by_triple] = np.cumsum(starts) - 1
    smallest = np.argmin(faces, axis=1)
    after = faces[np.arange(m), (smallest + 1) % 3]
    before = faces[np.arange(m), (smallest + 2) % 3]
    odd = (after > before).astype(np.int64)
    first_of = np.full((int(group.max(initial=-1)) + 1, 2), m, dtype=np.int64)
    np.minimum.at(first_of, (group, odd), np.arange(m))
    twin = first_of[group, 1 - odd]
    return first, np.where(twin < m, twin, -1)


def _inverse(values: np.ndarray) -> np.ndarray:
    """1 / values, inf where a value is 0."""
    with np.errstate(divide="ignore"):
        return 1.0 / values


def _max_by_group(values, rep, n):
    out = np.zeros(n)
    order = np.argsort(values, kind="stable")
    out[rep[order]] = values[order]  # ascending writes: the largest lands last
    return out[rep]
