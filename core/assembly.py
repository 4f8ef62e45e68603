"""Many parts, one run: the meshes of an asset simplified together (issue 32).

An asset is many meshes (a body, clothes and eyes; an engine block and its bolts). Run
one by one, each part pays the engine's per-pass cost on its own (a pure-NumPy pass
costs about a millisecond whatever its size, and a run takes a few hundred), and its
share of the asset's budget has to be found beforehand (core.budget's error curves: a
second run of every part). Run together, the parts share every pass, and the greedy
order spends the budget where it costs least error across the whole asset, which is
Simplygon's "scene-wide reduction" and what core.budget approximates part by part.

:func:`combine` puts the parts into one mesh and one Options: each part's positions in
the asset's units (its ``scale``: a mesh drawn at several sizes takes the largest), its
options' per-vertex and per-corner arrays side by side, attributes a part lacks padded
with zeros (a key that does not move a part is a zero offset there; a part without UVs
has one flat UV, which no rule reads as a flip), and Options.vertex_part so that no
weld joins two parts that touch. Options.part_copies makes the targets count what the
asset draws: an instanced mesh is simplified once and counts once per object.

:func:`split` takes a result of the combined run back to one SimplifyResult per part,
in the part's own units, with the part's own attributes only. A part with no face left
(removed as a small part, Options.remove_small_components) comes back as None.

What the parts must share, because the run has one value of it: every scalar option
(rules, seed, ...; the line weight is per vertex), but the exponents of importance, which
only the parts with importance must share (SCALED_ONLY). Painted limits and max_error are
not combined: the tracked distance finds the closest source point, which may lie on
another part.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from .options import Options
from .result import STOP_TARGET, SimplifyResult


@dataclass
class Part:
    """One part: its mesh (vertices (n, 3), faces (m, 3)) and options in its own units,
    ``scale`` from its units to the asset's (> 0), and how many times it is drawn."""

    vertices: np.ndarray
    faces: np.ndarray
    options: Options
    scale: float = 1.0
    copies: int = 1


@dataclass
class Layout:
    """Where each part lies in the combined run, to split its results."""

    vertex_offsets: np.ndarray  # (parts + 1,)
    face_offsets: np.ndarray  # (parts + 1,)
    scales: np.ndarray  # (parts,)
    vertex_part: np.ndarray  # (n,) the part of each combined vertex
    vertex_attributes: list  # per part: {name: width} of its own vertex attributes
    corner_attributes: list  # per part: {name: width} of its own corner attributes
    shape_attributes: frozenset  # names whose values are offsets (scaled with positions)
    given: list  # per part: its (n_i, 3) vertices as given (float64), for the unmoved ones


# Options every part must give alike: the run has one of each.
SHARED = ("boundary_weight", "seed", "preserve_seams", "weld_distance",
          "stitch_cracks", "probabilistic_sigma", "feature_angle", "min_quality", "plane_placement",
          "remove_small_components", "pose_weight")
# Options that act only through a part's quadric_scale (importance, raised to them): a
# part without one, or whose scale is 1 everywhere, is the same under any value. So only
# the parts with importance must agree, and the run takes theirs: an asset whose head
# alone is painted, or whose face alone has shape keys, is still one run.
SCALED_ONLY = ("line_scale_exponent", "key_scale_exponent")
# Options that cannot be combined (see the module's docstring).
NOT_COMBINED = ("max_error", "vertex_max_error", "vertex_part", "part_copies")


def combine(parts: Sequence[Part]) -> tuple:
    """(vertices (N, 3), faces (M, 3), Options, Layout) of ``parts`` as one run.
    ValueError naming what differs when the parts cannot share a run."""
    if not parts:
        raise ValueError("give at least one part")
    first = parts[0].options
    for name in NOT_COMBINED:
        if any(getattr(p.options, name) is not None for p in parts):
            raise ValueError(f"parts with {name} cannot share a run: simplify them one by one")
    shared = shared_options([p.options for p in parts])
    for p in parts:
        if not p.scale > 0:
            raise ValueError(f"a part's scale must be > 0, got {p.scale}")
        if int(p.copies) != p.copies or p.copies < 1:
            raise ValueError(f"a part's copies must be a whole number >= 1, got {p.copies}")
    n = np.array([len(p.vertices) for p in parts])
    m = np.array([len(p.faces) for p in parts])
    v_off = np.concatenate([[0], np.cumsum(n)])
    f_off = np.concatenate([[0], np.cumsum(m)])
    shapes = frozenset(name for p in parts for name in p.options.shape_attributes)

    given = [np.asarray(p.vertices, dtype=np.float64) for p in parts]
    vertices = np.concatenate([v * p.scale for v, p in zip(given, parts)])
    faces = np.concatenate([np.asarray(p.faces, dtype=np.int64).reshape(-1, 3) + v_off[i]
                            for i, p in enumerate(parts)])
    vattrs, vwidths = _side_by_side([p.options.vertex_attributes or {} for p in parts], n, shapes,
                                    [p.scale for p in parts])
    cattrs, cwidths = _side_by_side([p.options.corner_attributes or {} for p in parts], m, frozenset(),
                                    [p.scale for p in parts], corner=True)
    line_weights = np.concatenate([np.full(k, p.options.line_weight, dtype=np.float64)
                                   if p.options.line_weights is None else np.asarray(p.options.line_weights, float)
                                   for k, p in zip(n, parts)])
    scaled = any(p.options.quadric_scale is not None for p in parts)
    quadric_scale = np.concatenate([np.ones(k) if p.options.quadric_scale is None
                                    else np.asarray(p.options.quadric_scale, float)
                                    for k, p in zip(n, parts)]) if scaled else None
    locked = np.concatenate([np.zeros(k, bool) if p.options.locked is None else np.asarray(p.options.locked, bool)
                             for k, p in zip(n, parts)])
    edges, weights = [], []
    for i, p in enumerate(parts):
        fe = p.options.feature_edges
        if fe is not None and len(fe):
            fe = np.asarray(fe, dtype=np.int64).reshape(-1, 2)
            edges.append(fe + v_off[i])
            weights.append(np.full(len(fe), p.options.feature_weight) if p.options.edge_weights is None
                           else np.asarray(p.options.edge_weights, dtype=np.float64))
    poses = _poses(parts, n)
    labels = np.repeat(np.arange(len(parts)), n)
    options = dataclasses.replace(
        first, **shared,
        line_weight=0.0, line_weights=line_weights, quadric_scale=quadric_scale, locked=locked,
        vertex_attributes=vattrs, corner_attributes=cattrs,
        normalize_attributes=tuple(sorted({a for p in parts for a in p.options.normalize_attributes})),
        uv_attributes=tuple(sorted({a for p in parts for a in p.options.uv_attributes})),
        seamless_attributes=tuple(sorted({a for p in parts for a in p.options.seamless_attributes})),
        shape_attributes=tuple(sorted(shapes)),
        feature_edges=np.concatenate(edges) if edges else None,
        edge_weights=np.concatenate(weights) if edges else None,
        pose_offsets=poses,
        vertex_part=labels, part_copies=np.array([int(p.copies) for p in parts]))
    layout = Layout(v_off, f_off, np.array([float(p.scale) for p in parts]), labels, vwidths, cwidths, shapes,
                    given)
    return vertices, faces, options, layout


def shared_options(options: Sequence[Options]) -> dict:
    """{name: the one value a run of parts with ``options`` has} for SHARED and
    SCALED_ONLY; ValueError naming the option when the parts differ in it."""
    scaled = [o for o in options if _has_importance(o)]
    out = {}
    for names, among in ((SHARED, options), (SCALED_ONLY, scaled or options[:1])):
        for name in names:
            values = {repr(getattr(o, name)) for o in among}
            if len(values) > 1:
                raise ValueError(f"the parts differ in {name} ({', '.join(sorted(values))}): one run has one")
            out[name] = getattr(among[0], name)
    return out


def _has_importance(options: Options) -> bool:
    """Whether ``options`` scales some vertex's quadric (quadric_scale not 1 everywhere)."""
    scale = options.quadric_scale
    return scale is not None and bool(np.any(np.asarray(scale, dtype=np.float64) != 1.0))


def _side_by_side(per_part: list, counts: np.ndarray, offsets: frozenset, scales: list,
                  corner: bool = False) -> tuple:
    """({name: the parts' values stacked, zeros where a part has none, as wide as the
    widest}, per part {name: its own width}). Values named in ``offsets`` are lengths:
    multiplied by the part's scale."""
    names = sorted({name for attrs in per_part for name in attrs})
    widths = [{name: np.asarray(a[name]).shape[-1] for name in a} for a in per_part]
    out = {}
    for name in names:
        width = max(w[name] for w in widths if name in w)
        blocks = []
        for attrs, k, scale in zip(per_part, counts, scales):
            shape = (k, 3, width) if corner else (k, width)
            block = np.zeros(shape)
            if name in attrs:
                a = np.asarray(attrs[name], dtype=np.float64)
                block[..., :a.shape[-1]] = a * scale if name in offsets else a
            blocks.append(block)
        out[name] = np.concatenate(blocks)
    return out, widths


def _poses(parts: Sequence[Part], n: np.ndarray) -> Optional[np.ndarray]:
    """The parts' pose_offsets side by side, in the asset's units (zeros for a part with
    none: it does not move), or None when no part has any."""
    given = [p.options.pose_offsets for p in parts if p.options.pose_offsets is not None]
    if not given:
        return None
    counts = {np.asarray(g).shape[0] for g in given}
    if len(counts) > 1:
        raise ValueError(f"the parts have different numbers of sample poses ({sorted(counts)})")
    count = counts.pop()
    return np.concatenate([np.zeros((count, k, 3)) if p.options.pose_offsets is None
                           else np.asarray(p.options.pose_offsets, dtype=np.float64) * p.scale
                           for k, p in zip(n, parts)], axis=1)


def split(result: SimplifyResult, layout: Layout) -> list:
    """Per part, its share of ``result`` (a run on combine's mesh) as a SimplifyResult in
    the part's own units and indices, or None when the part has no face left."""
    part_of_vertex = layout.vertex_part[result.vertex_origin]
    part_of_face = part_of_vertex[result.faces[:, 0]] if len(result.faces) else np.zeros(0, dtype=np.int64)
    local = np.empty(len(result.vertices), dtype=np.int64)
    out = []
    for i, scale in enumerate(layout.scales):
        face_rows = np.flatnonzero(part_of_face == i)
        if len(face_rows) == 0:
            out.append(None)
            continue
        vertex_rows = np.flatnonzero(part_of_vertex == i)
        local[vertex_rows] = np.arange(len(vertex_rows))
        vattrs = {}
        for name, width in layout.vertex_attributes[i].items():
            values = result.vertex_attributes[name][vertex_rows, :width]
            vattrs[name] = values / scale if name in layout.shape_attributes else values
        cattrs = {name: result.corner_attributes[name][face_rows][..., :width]
                  for name, width in layout.corner_attributes[i].items()}
        stats = result.stats
        own_faces = int(layout.face_offsets[i + 1] - layout.face_offsets[i])
        # A vertex no collapse moved comes back as given, bit for bit (x * s / s need not
        # be x): as for one mesh, where unmoved vertices skip the normalisation.
        origin = result.vertex_origin[vertex_rows] - layout.vertex_offsets[i]
        given = layout.given[i][origin]
        vertices = result.vertices[vertex_rows]
        unmoved = np.all(vertices == given * scale, axis=1)
        vertices = np.where(unmoved[:, None], given, vertices / scale)
        out.append(SimplifyResult(
            vertices=vertices,
            faces=local[result.faces[face_rows]],
            face_origin=result.face_origin[face_rows] - layout.face_offsets[i],
            vertex_origin=origin,
            stats=dataclasses.replace(
                stats, input_vertices=int(layout.vertex_offsets[i + 1] - layout.vertex_offsets[i]),
                input_faces=own_faces, output_vertices=len(vertex_rows), output_faces=len(face_rows),
                # A part's share is what the asset's run gave it: its target, reached. Why
                # the run itself stopped is the combined result's (stats.stop_reason).
                target_faces=len(face_rows), max_error=stats.max_error / scale, stop_reason=STOP_TARGET,
                welded_vertices=0, removed_components=0),
            vertex_attributes=vattrs,
            corner_attributes=cattrs,
        ))
    return out
