# SPDX-License-Identifier: GPL-3.0-or-later
"""Where a LOD differs from its source (issue 34 §3): per vertex for the heat map, per
material and painted region for the report, and over the rig's frames for a skinned LOD.
Free of bpy: functions of arrays (and of phases.LodInput and MeshData, read as arrays).

Everything here reuses the points the level report already measures
(measure.surface_deviation(keep_samples=True): a :class:`measure.Sampled`); nothing is
queried again.

Per LOD vertex (``vertex_distances``): its own distance to the source surface, raised to
the largest distance of the source samples that stand for it, so that what the LOD lost
(a cut-off horn, a hole filled, a limb grown thinner) shows where the LOD is, not only
where its vertices stray. A source sample stands for the LOD vertex nearest its closest
LOD point in barycentric terms (the corner of the LOD triangle it lands on with the
largest coordinate). The heat map (``heat_colors``) maps 0 to blue and ``scale`` to red
through cyan, green and yellow, the colours of Blender's weight paint.

Per material and per painted region (``level_breakdown``): every area sample of both
surfaces is given to what it lies on. A source sample belongs to the material of its
source triangle and to each region (vertex group) whose weight, interpolated at the
sample, is at least REGION_WEIGHT; a LOD sample to the material of its LOD triangle and
to the regions by the LOD's own (carried) weights. Per group the two directions are
pooled as the level report pools them (``two_sided``): each direction's samples weigh
half, so the mean is the mean of the two directional means (with one group holding
everything: the report's ``mean_percent``), the 95th percentile is that weighted
distribution's, and the max is the largest sample or vertex of the group (the vertices
of its faces, or painted at least REGION_WEIGHT), as in the Hausdorff distance: the
largest of the materials' max is the report's ``hausdorff_percent``.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from .settings import PREVIEW_GROUP

HEAT_ATTRIBUTE = "LOD_Deviation"  # FLOAT_COLOR, POINT: the heat map
DISTANCE_ATTRIBUTE = "LOD_Deviation_Distance"  # FLOAT, POINT: the distance itself, mesh units
SCALE_PROPERTY = "lod_deviation_scale"  # on the LOD's mesh: the distance that is red, mesh units
REGION_WEIGHT = 0.5  # a sample is in a painted region where the group's weight is at least this
NO_MATERIAL = "(no material)"
PERCENTILE = 95.0
# A posed source and LOD whose every vertex lies within RIGID_TOLERANCE of the source's
# diagonal of one rigid motion of their rest shapes take their rest distances
# (moved_rigidly). Blender skins in float32, which leaves a part about a step of its
# coordinates off any exact motion (the 59 one-bone parts of bench/many_parts.py: up to
# 1.7 steps, 1.2e-6 of their diagonals), so RIGID_ROUNDING steps of the largest
# coordinate are allowed too, but never more than RIGID_MOST of the diagonal: a small part
# far from its origin, where float32 cannot tell a rigid motion from a bend that small,
# is measured. A distance then moves by at most twice the allowance: 2e-4 % of the
# diagonal, 2e-3 % where float32's steps set it.
RIGID_TOLERANCE = 1e-6
RIGID_ROUNDING = 8
RIGID_MOST = 1e-5

# The heat ramp in display (sRGB) colours, evenly spaced from 0 to 1: Blender's weight
# paint colours (blue, cyan, green, yellow, red).
_RAMP_SRGB = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 0.0]])


# ----------------------------------------------------------------------------- per vertex


def vertex_distances(n_vertices: int, faces: np.ndarray, sampled) -> np.ndarray:
    """(n_vertices,) each LOD vertex's distance for the heat map: its own distance to the
    source, or more where source samples whose closest LOD point is nearest to it lie
    further away. ``faces``: the LOD's (m, 3); ``sampled``: measure.Sampled of the source
    (src) against this LOD (dst). A vertex no face uses gets 0."""
    out = np.zeros(int(n_vertices), dtype=np.float64)
    out[np.asarray(sampled.dst_vertices, dtype=np.int64)] = sampled.dst_vertex_distance
    nearest = np.asarray(sampled.src_nearest, dtype=np.int64)
    if len(nearest):
        corner = np.argmax(np.asarray(sampled.src_nearest_bary), axis=1)
        np.maximum.at(out, np.asarray(faces, dtype=np.int64)[nearest, corner], sampled.src_distance)
    return out


def srgb_to_linear(c: np.ndarray) -> np.ndarray:
    """Display (sRGB) colour components to scene-linear ones (FLOAT_COLOR attributes hold
    linear values; the viewport shows them through the display transform)."""
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def heat_colors(distances: np.ndarray, scale: float) -> np.ndarray:
    """(n, 4) linear RGBA: 0 blue, ``scale`` and beyond red (cyan, green, yellow between,
    evenly); a scale of 0 (a LOD that lies on its source) is all blue."""
    d = np.asarray(distances, dtype=np.float64)
    t = np.clip(d / scale, 0.0, 1.0) if scale > 0 else np.zeros_like(d)
    x = t * (len(_RAMP_SRGB) - 1)
    i = np.minimum(x.astype(np.int64), len(_RAMP_SRGB) - 2)
    f = (x - i)[:, None]
    srgb = _RAMP_SRGB[i] * (1.0 - f) + _RAMP_SRGB[i + 1] * f
    return np.concatenate([srgb_to_linear(srgb), np.ones((len(d), 1))], axis=1)


def heat_layer(level, sampled) -> tuple:
    """(distances per vertex, linear colours, scale) of ``level`` (a MeshData) for the heat
    map: vertex_distances, coloured from 0 to their largest (the scale, mesh units)."""
    distances = vertex_distances(len(level.vertices), level.faces, sampled)
    scale = float(distances.max(initial=0.0))
    return distances, heat_colors(distances, scale), scale


# ----------------------------------------------------------------------------- statistics


def weighted_quantile(values: np.ndarray, weights: np.ndarray, q: float) -> float:
    """The smallest value whose share of the total weight at or below it is at least ``q``
    (0 to 1): the inverted CDF of the weighted sample (unweighted: numpy's
    "inverted_cdf" percentile). NaN for no values."""
    values = np.asarray(values, dtype=np.float64)
    weights = np.asarray(weights, dtype=np.float64)
    if len(values) == 0:
        return float("nan")
    order = np.argsort(values, kind="stable")
    cumulative = np.cumsum(weights[order])
    # (a relative tolerance: cumulative sums of equal weights may fall a rounding short)
    index = np.searchsorted(cumulative, q * cumulative[-1] * (1.0 - 1e-12), side="left")
    return float(values[order][min(index, len(values) - 1)])


def two_sided(src: np.ndarray, dst: np.ndarray, scale: float = 1.0, vertex_max: Optional[float] = None) -> dict:
    """{mean, p95, max, samples} of the distances of one group's samples, ``src`` on the
    source and ``dst`` on the LOD, pooled as the two-sided report pools them: each
    direction's samples together weigh half (all of it when the other has none), so the
    mean is the mean of the directional means. Distances times ``scale`` (100 / the
    diagonal gives percent); mean, p95 and max None when there are no samples.
    ``vertex_max``: the largest distance of the group's vertices, which counts in the max
    as vertices count in the Hausdorff distance (the mean and percentile are the area
    samples' alone, as the report's mean is)."""
    src = np.asarray(src, dtype=np.float64)
    dst = np.asarray(dst, dtype=np.float64)
    count = len(src) + len(dst)
    if count == 0:
        return {"mean": None, "p95": None, "max": None, "samples": 0}
    parts = [(d, 1.0 / len(d)) for d in (src, dst) if len(d)]
    values = np.concatenate([d for d, _ in parts])
    weights = np.concatenate([np.full(len(d), w / len(parts)) for d, w in parts])
    return {"mean": float(np.mean([d.mean() for d, _ in parts])) * scale,
            "p95": weighted_quantile(values, weights, PERCENTILE / 100.0) * scale,
            "max": max(float(values.max()), -np.inf if vertex_max is None else vertex_max) * scale,
            "samples": int(count)}


def at_samples(vertex_values: np.ndarray, faces: np.ndarray, triangle: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """Per-vertex values (n,) or (n, c) interpolated at points given by their triangle (k,)
    and barycentric coordinates (k, 3): (k,) or (k, c)."""
    values = np.asarray(vertex_values, dtype=np.float64)
    corners = values[np.asarray(faces, dtype=np.int64)[np.asarray(triangle, dtype=np.int64)]]  # (k, 3[, c])
    return np.einsum("kj,kj...->k...", np.asarray(bary, dtype=np.float64), corners)


def grouped(src_d, src_member, dst_d, dst_member, names, scale: float = 1.0, vertices=None) -> dict:
    """{name: two_sided of the samples that are members}: ``src_member`` (k, g) and
    ``dst_member`` (k', g) say per sample whether it is in each of the g groups ``names``
    (one sample may be in several, or none). ``vertices``: optional (distances (j,),
    membership (j, g)) of both surfaces' vertices, for each group's max."""
    src_member = np.asarray(src_member, dtype=bool).reshape(len(src_d), len(names))
    dst_member = np.asarray(dst_member, dtype=bool).reshape(len(dst_d), len(names))
    if vertices is not None:
        v_d = np.asarray(vertices[0], dtype=np.float64)
        v_in = np.asarray(vertices[1], dtype=bool).reshape(len(v_d), len(names))
        v_max = np.where(v_in, v_d[:, None], -np.inf).max(axis=0, initial=-np.inf)
    out = {}
    for j, name in enumerate(names):  # a loop over groups (materials, regions): a handful
        extra = None if vertices is None or not np.isfinite(v_max[j]) else float(v_max[j])
        out[name] = two_sided(np.asarray(src_d)[src_member[:, j]], np.asarray(dst_d)[dst_member[:, j]], scale, extra)
    return out


def vertices_in(face_member: np.ndarray, faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """(n_vertices, g): whether a vertex is on a face in each group (``face_member`` (m, g))."""
    face_member = np.asarray(face_member, dtype=bool)
    out = np.zeros((int(n_vertices), face_member.shape[1]), dtype=bool)
    faces = np.asarray(faces, dtype=np.int64)
    for corner in range(3):
        np.logical_or.at(out, faces[:, corner], face_member)
    return out


def material_groups(material_index: np.ndarray, material_names: list) -> tuple:
    """(material names, each once in slot order, and (m,) each triangle's index into
    them): ``material_names`` per slot (None for an empty slot); slots of the same
    material are one, an empty slot or an index past the slots is NO_MATERIAL."""
    labels = [name if name else NO_MATERIAL for name in material_names] + [NO_MATERIAL]
    names = list(dict.fromkeys(labels))
    slot_group = np.array([names.index(label) for label in labels], dtype=np.int64)  # a handful of slots
    index = np.asarray(material_index, dtype=np.int64)
    return names, slot_group[np.where((index >= 0) & (index < len(material_names)), index, len(material_names))]


def membership(group: np.ndarray, groups: int) -> np.ndarray:
    """(k, groups) bool from (k,) group indices."""
    return np.asarray(group, dtype=np.int64)[:, None] == np.arange(groups)


def region_columns(group_names: list, skin_columns, importance_group: Optional[str] = None) -> list:
    """[(name, column)] of the painted regions among a mesh's vertex groups: every group
    that is not a deform-bone (skin) group, without the importance preview, plus the
    importance group when one is used (even if it is a deform group)."""
    skin = set(skin_columns or ())
    out = [(name, j) for j, name in enumerate(group_names) if j not in skin and name != PREVIEW_GROUP]
    if importance_group and importance_group in group_names and all(n != importance_group for n, _ in out):
        out.append((importance_group, list(group_names).index(importance_group)))
    return out


def _percent(stats: dict) -> dict:
    return {"mean_percent": stats["mean"], "p95_percent": stats["p95"], "max_percent": stats["max"],
            "samples": stats["samples"]}


def _climbed(sampled, side: str) -> tuple:
    """(triangles (c,), barycentric coordinates (c, 3), distances (c,)) of the points the
    measurement's climb tried on ``side`` ("src" or "dst") of ``sampled``; none if it kept none."""
    triangle = getattr(sampled, f"{side}_climbed_triangle")
    if triangle is None:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 3)), np.zeros(0)
    return (np.asarray(triangle, dtype=np.int64), np.asarray(getattr(sampled, f"{side}_climbed_bary")),
            np.asarray(getattr(sampled, f"{side}_climbed_distance"), dtype=np.float64))


def level_breakdown(source, level, sampled, material_names: Optional[list], regions: list,
                    diagonal: float) -> dict:
    """The level's distance per material and per painted region, in percent of
    ``diagonal``: {"materials": {name: {mean_percent, p95_percent, max_percent, samples}},
    "regions": {...}}, each key only when there is something to break down (materials:
    the object has material slots; regions: ``regions`` is not empty).

    ``source`` and ``level``: MeshData (vertices, faces, material_index, group_weights);
    ``sampled``: measure.Sampled of source (src) against level (dst); ``material_names``:
    per slot; ``regions``: [(name, column of group_weights)] (region_columns).

    Each group's max also takes its vertices' distances (the vertices of its faces; for a
    region those whose weight is at least REGION_WEIGHT) and the points the measurement's
    climb tried on its faces (measure._climb), as the Hausdorff distance does: the largest
    max over the materials is the level's Hausdorff distance."""
    scale = 100.0 / diagonal if diagonal > 0 else float("nan")
    src_d, dst_d = sampled.src_distance, sampled.dst_distance
    src_v, dst_v = np.asarray(sampled.src_vertices), np.asarray(sampled.dst_vertices)
    src_c, dst_c = _climbed(sampled, "src"), _climbed(sampled, "dst")
    # (the vertices' and the climbed points' distances: each group's max only)
    vertex_d = np.concatenate([sampled.src_vertex_distance, sampled.dst_vertex_distance, src_c[2], dst_c[2]])
    out = {}
    if material_names:
        names, src_group = material_groups(source.material_index, material_names)
        _, dst_group = material_groups(level.material_index, material_names)
        src_faces, dst_faces = membership(src_group, len(names)), membership(dst_group, len(names))
        vertex_in = np.concatenate([vertices_in(src_faces, source.faces, len(source.vertices))[src_v],
                                    vertices_in(dst_faces, level.faces, len(level.vertices))[dst_v],
                                    src_faces[src_c[0]], dst_faces[dst_c[0]]])
        stats = grouped(src_d, src_faces[sampled.src_triangle], dst_d, dst_faces[sampled.dst_triangle], names,
                        scale, (vertex_d, vertex_in))
        out["materials"] = {name: _percent(s) for name, s in stats.items() if s["samples"]}
    if regions:
        columns = [j for _, j in regions]
        src_w = np.asarray(source.group_weights, dtype=np.float64)[:, columns]
        dst_w = np.asarray(level.group_weights, dtype=np.float64)[:, columns]
        # (the tolerance: a weight painted at exactly 0.5 interpolates to 0.5 give or take a rounding)
        threshold = REGION_WEIGHT - 1e-9
        at_src = at_samples(src_w, source.faces, sampled.src_triangle, sampled.src_bary).reshape(len(src_d), -1)
        at_dst = at_samples(dst_w, level.faces, sampled.dst_triangle, sampled.dst_bary).reshape(len(dst_d), -1)
        vertex_in = np.concatenate([src_w[src_v], dst_w[dst_v],
                                    at_samples(src_w, source.faces, src_c[0], src_c[1]).reshape(len(src_c[0]),
                                                                                                 len(columns)),
                                    at_samples(dst_w, level.faces, dst_c[0], dst_c[1]).reshape(len(dst_c[0]),
                                                                                              len(columns))]
                                   ) >= threshold
        stats = grouped(src_d, at_src >= threshold, dst_d, at_dst >= threshold, [n for n, _ in regions], scale,
                        (vertex_d, vertex_in))
        out["regions"] = {name: _percent(s) for name, s in stats.items()}
    return out


# ----------------------------------------------------------------------------- posed


def sample_frames(start: float, end: float, count: int) -> list:
    """Up to ``count`` whole frames spread evenly from ``start`` to ``end`` (both in when
    count > 1; the middle one when count is 1), each once."""
    first, last = int(np.ceil(start - 1e-6)), int(np.floor(end + 1e-6))
    if last < first:
        return [int(round(start))]
    if count <= 1:
        return [int(round((first + last) / 2.0))]
    return sorted({int(round(f)) for f in np.linspace(first, last, min(count, last - first + 1))})


def frames_per_action(actions: int, per_action: int, total: int) -> int:
    """How many frames each of ``actions`` actions gets: ``per_action``, fewer when that
    would pass ``total`` in all, never below one."""
    return max(1, min(per_action, total // max(actions, 1)))


def moved_rigidly(rest: list, posed: list, diagonal: float) -> bool:
    """Whether the surfaces ``posed`` [(vertices (n, 3), faces (m, 3))] are the surfaces
    ``rest`` (the same faces, vertex for vertex) moved by one isometry, every vertex
    within RIGID_TOLERANCE of ``diagonal`` (the rest source's) or RIGID_ROUNDING float32
    steps of the largest coordinate, if those are at most RIGID_MOST of it: a part skinned
    to one bone, or a pose that is the rest pose. Distances between such surfaces are
    their rest distances: the posed distance of a source and LOD that moved so together
    is what the level report measured at rest (to twice the allowance), with the report's
    own samples, which are more than a frame's.

    The isometry is the orthogonal Procrustes fit of all the rest vertices to the posed
    ones (reflections allowed: they keep distances too); its residual is checked at
    every vertex, so a part that is flat or a line can only fail the test, not pass it
    wrongly."""
    if len(rest) != len(posed) or not rest:
        return False
    for (v0, f0), (v1, f1) in zip(rest, posed):
        if np.shape(v0) != np.shape(v1) or np.shape(f0) != np.shape(f1) or not np.array_equal(f0, f1):
            return False
    a = np.concatenate([np.asarray(v, dtype=np.float64) for v, _ in rest])
    b = np.concatenate([np.asarray(v, dtype=np.float64) for v, _ in posed])
    if len(a) == 0 or not (np.isfinite(a).all() and np.isfinite(b).all()):
        return False
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((a - ca).T @ (b - cb))
    moved = (a - ca) @ (u @ vt) + cb
    rounding = RIGID_ROUNDING * float(np.spacing(np.float32(max(np.abs(a).max(), np.abs(b).max()))))
    if not diagonal > 0 or rounding > RIGID_MOST * diagonal:
        return False
    allowance = max(RIGID_TOLERANCE * float(diagonal), rounding)
    return float(np.sqrt(np.einsum("ij,ij->i", moved - b, moved - b).max())) <= allowance


def posed_summary(hausdorff: list, mean: list) -> dict:
    """{hausdorff_percent: {mean, max}, mean_percent: {mean, max}} over frames: each
    frame's two-sided Hausdorff and mean distance (percent); the mean and the largest."""
    h, m = np.asarray(hausdorff, dtype=np.float64), np.asarray(mean, dtype=np.float64)
    if len(h) == 0:
        return {}
    return {"hausdorff_percent": {"mean": float(h.mean()), "max": float(h.max())},
            "mean_percent": {"mean": float(m.mean()), "max": float(m.max())}}


# ----------------------------------------------------------------------------- a level of a run


def measure_level(lod_input, level, report: dict, index: int = 0) -> tuple:
    """What the level report adds for a measured ``level`` (a MeshData) of ``lod_input``
    (phases.LodInput) whose measurement ``report`` kept its samples (``sampled``); ``index``:
    the level's place in the chain (0 for LOD1): (the level,
    with the heat map's attributes when the settings ask for them, and the entries for the
    report: materials, regions, deviation_colors). A report without samples adds nothing."""
    sampled = report.get("sampled")
    if sampled is None:
        return level, {}
    data, settings = lod_input.data, lod_input.settings
    diagonal = measure_diagonal(report)
    skin = (lod_input.names or {}).get("skin", ())
    group = settings.importance_group if settings.importance_source == 'VERTEX_GROUP' else None
    entry = level_breakdown(data, level, sampled, getattr(lod_input, "material_names", None),
                            region_columns(list(data.group_names), skin, group), diagonal)
    if lod_input.limit is not None:
        from . import limits  # (it builds on this module's sampling helpers)
        kept = limits.limit_entry(lod_input, report, index)
        if kept is not None:
            entry["limit"] = kept
    if settings.deviation_colors:
        level = with_heat(level, sampled)
        scale = level.mesh_properties[SCALE_PROPERTY]
        entry["deviation_colors"] = {"attribute": HEAT_ATTRIBUTE, "distance_attribute": DISTANCE_ATTRIBUTE,
                                     "scale": scale,
                                     "scale_percent": scale * 100.0 / diagonal if diagonal > 0 else None}
    return level, entry


def share_scales(chains: list) -> None:
    """One heat scale per level for the parts of an asset (a bolt's own largest distance
    is not red while the hull is further off): each level's heat map, on every part that
    has one, is coloured again from 0 to the largest distance, in scene units, of that
    level over all the parts; its report entry says so (``shared``: "asset").

    chains: [(phases.LodOutput, unit)], each output once (objects sharing its meshes share
    its colours), ``unit`` the scene units per unit of its object (asset.world_scale)."""
    largest = {}
    for out, unit in chains:
        for k, level in enumerate(out.levels):
            if SCALE_PROPERTY in level.mesh_properties:
                largest[k] = max(largest.get(k, 0.0), float(level.mesh_properties[SCALE_PROPERTY]) * unit)
    for out, unit in chains:
        diagonal = None
        done = set()
        for k, (level, entry) in enumerate(zip(out.levels, out.reports)):
            if k not in largest or DISTANCE_ATTRIBUTE not in level.point_floats or unit <= 0:
                continue
            scale = largest[k] / unit
            if id(level) not in done:  # (a level repeated in the chain is one mesh)
                done.add(id(level))
                colors = heat_colors(level.point_floats[DISTANCE_ATTRIBUTE], scale)
                level.colors[:] = [layer if layer.name != HEAT_ATTRIBUTE else
                                   type(layer)(layer.name, layer.domain, layer.data_type, colors)
                                   for layer in level.colors]
                level.mesh_properties[SCALE_PROPERTY] = scale
            if diagonal is None:
                v, f = out.input.data.vertices, out.input.data.faces
                used = np.asarray(v)[np.unique(f)]
                diagonal = float(np.linalg.norm(used.max(0) - used.min(0)))
            entry.get("deviation_colors", {}).update(
                scale=scale, scale_percent=scale * 100.0 / diagonal if diagonal > 0 else None, shared="asset")


def measure_diagonal(report: dict) -> float:
    """The diagonal a measurement's percentages are of (measure.surface_deviation's)."""
    return float(report.get("diagonal") or 0.0)


def with_heat(level, sampled):
    """A copy of ``level`` (MeshData) carrying the heat map: the colour attribute
    HEAT_ATTRIBUTE, the distance attribute DISTANCE_ATTRIBUTE and the scale as the mesh's
    SCALE_PROPERTY (replacing any layer of those names it carried from its source).
    ``level`` itself when it has them already (a level repeated in a chain: one mesh)."""
    import dataclasses

    from .mesh_data import ColorLayer

    if DISTANCE_ATTRIBUTE in level.point_floats:
        return level
    distances, colors, scale = heat_layer(level, sampled)
    layers = [c for c in level.colors if c.name != HEAT_ATTRIBUTE]
    layers.append(ColorLayer(HEAT_ATTRIBUTE, 'POINT', 'FLOAT_COLOR', colors))
    return dataclasses.replace(level, colors=layers,
                               point_floats={**level.point_floats, DISTANCE_ATTRIBUTE: distances},
                               mesh_properties={**level.mesh_properties, SCALE_PROPERTY: scale})
