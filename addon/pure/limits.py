# SPDX-License-Identifier: GPL-3.0-or-later
"""Painted limits (issue 34 §1): a vertex group that says how far each LOD may move.

Where the group's weight is 1 the LOD stays within the limit L of the source; at 0 the
region is free; a weight w in between allows L / w, so the limit grows smoothly to
"free" as the paint fades (and 1 / limit, what the core interpolates inside faces,
follows the paint linearly). The core holds it collapse by collapse (core option
``vertex_max_error``, core.tracked_distance) and meets the count target elsewhere; where
the limits make the count unreachable it stops above it (core.STOP_LIMIT), which the
LOD's notes and report say.

L is in scene units or in percent of the object's bounding-box diagonal (of the whole
asset's when the object is part of one), as ``--max-error`` is, or in pixels at each
LOD's switch distance. A LOD switches in where its largest measured error ε_k shows
Pixel Error (τ) pixels (addon/pure/switch_distances.py), so P pixels there are P · ε_k / τ
scene units: a limit relative to the LOD's own error, one per level
(``pixel_limits``). ε_k is measured on a first run without the limit (the run with it
keeps the region and gives the rest more error, so its ε_k is seldom smaller). With a
chain by deviation (or screen size) ε_k is the requested deviation, known before the
run: the search holds each level's own limit (deviation_search.by_deviation). Where a
level's measured error comes out below that ε_k, it switches in where its region shows P
pixels instead (``pixel_switch``), so the region shows at most P pixels wherever the LOD
is drawn. Each LOD's report
measures it with the report's own samples (measure.Sampled): at every sample of both
surfaces in the group, its distance over the limit there (``limit_used``: at most 1 when
the limit holds), and the region's largest distance.

Free of bpy: arrays in and out, and the runs that hold a chain to its limit
(``held_to_limit``, ``with_pixel_limit``: compute.py's simplify passed in).
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from . import deviation_search, deviation_targets, measure
from .level_deviation import at_samples
from .mesh_data import shading_normals
from .rebuild import lod_mesh

# The core holds the limit at its tracked points (the source's vertices and a grid inside
# its faces; the LOD's vertices and points of its faces): the report's area samples fall
# between them, up to 1.42x the core's bound on the test sphere's chain in pixels
# (tests/scenarios/addon_limits.py, before reruns). So the core is given this share of
# the limit, and a level the report's sampler still finds beyond is rerun tighter
# (held_to_limit, RERUN_AIM).
CORE_SHARE = 0.85
# A level measured beyond its limit (the report's limit_used above 1) runs again with its
# core limits times RERUN_AIM / limit_used, at most RERUNS times (held_to_limit).
RERUN_AIM = 0.9
RERUNS = 2
# Weights below this count as unpainted: a limit of L / 1e-6 is no limit at all, and
# float noise in a group should not constrain the LOD.
MIN_WEIGHT = 1e-6


def limit_in_mesh_units(value: float, percent: bool, diagonal: float, scale: float) -> float:
    """The limit L in the object's own (mesh) units: ``value`` percent of ``diagonal``
    (the object's or the asset's bounding-box diagonal, mesh units), or ``value`` scene
    units through the object's world ``scale`` (its largest axis scale; 1 for a single
    object, whose numbers are in its own units as --max-error's are)."""
    return value * diagonal / 100.0 if percent else value / scale


def pixel_limits(deviations, pixels: float, pixel_error: float) -> np.ndarray:
    """(k,) per-level limits (the units of ``deviations``) for ``pixels`` at each LOD's
    switch distance: pixels / pixel_error of its largest error ε_k, ``deviations`` (k,)
    made non-decreasing along the chain (as the switch distances are, and as the core
    wants a chain's limits)."""
    eps = np.maximum.accumulate(np.asarray(deviations, dtype=np.float64))
    return np.maximum(eps, 1e-12) * (float(pixels) / float(pixel_error))


def rerun_scales(used) -> "np.ndarray | None":
    """(k,) factors on each level's core limits for a rerun, from each level's measured
    ``used`` (limit_used), or None when every level is within (<= 1). A level within
    keeps its limits (factor 1)."""
    used = np.asarray(used, dtype=np.float64)
    if not (used > 1.0).any():
        return None
    return np.where(used > 1.0, RERUN_AIM / np.maximum(used, 1e-12), 1.0)


def scaled_rows(rows: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """(k, n) per-level vertex limits times ``scale`` (k,), kept non-decreasing along the
    chain (the core's rule): a level's limits are at most the next level's."""
    out = np.asarray(rows, dtype=np.float64) * np.asarray(scale, dtype=np.float64)[:, None]
    return np.minimum.accumulate(out[::-1], axis=0)[::-1]


def level_rows(weights: np.ndarray, per_level) -> np.ndarray:
    """(levels, n) vertex_limits for each level's limit in ``per_level``: the core's
    vertex_max_error for a chain with one limit per level."""
    return np.stack([vertex_limits(weights, v) for v in per_level])


def vertex_limits(weights: np.ndarray, limit: float) -> np.ndarray:
    """(n,) per-vertex limits for the core, mesh units: CORE_SHARE of limit / weight
    where the weight is above MIN_WEIGHT, inf (free) elsewhere. ``weights``: (n,) the
    group's, in [0, 1]."""
    w = np.clip(np.asarray(weights, dtype=np.float64), 0.0, 1.0)
    out = np.full(len(w), np.inf)
    painted = w > MIN_WEIGHT
    out[painted] = CORE_SHARE * limit / w[painted]
    return out


def limit_entry(lod_input, report: dict, index: int) -> Optional[dict]:
    """The level report's ``limit`` entry of a level of ``lod_input`` (phases.LodInput, with a
    painted limit) from its measurement ``report`` (kept samples), ``index``: the level's
    place in the chain: level_report with the group's name (and the pixels asked for)."""
    settings = lod_input.settings
    column, value, scene_scale = lod_input.limit
    if isinstance(value, tuple):  # per level (pixels at each switch distance)
        value = value[min(index, len(value) - 1)]
    kept = level_report(lod_input.data, report["sampled"], column, value,
                        lod_input.reference_diagonal or float(report.get("diagonal") or 0.0), scene_scale)
    if kept is None:
        return None
    kept = dict(kept, group=settings.limit_group)
    if settings.limit_unit == 'PIXELS':
        kept["limit_pixels"] = settings.limit_distance
        switch = pixel_switch(report["hausdorff"], kept["limit_used"] * value, settings.limit_distance,
                              settings.pixel_error, report.get("diagonal") or 0.0)
        kept.update(switch, switch_deviation=switch["switch_deviation"] * scene_scale)  # (scene units, as "limit")
    return kept


def pixel_switch(hausdorff: float, region: float, pixels: float, pixel_error: float, diagonal: float) -> dict:
    """Where a level under a limit in pixels may switch in, as the error its switch
    distance is computed from (switch_distances.py): its own largest error, or, where its
    painted region would show more than ``pixels`` there, the error at whose switch
    distance it shows ``pixels``: region * pixel_error / pixels.

    Why: the chain's limits are P / Pixel Error of an error known before the run (the
    requested deviation, or the level's error without the limit), and the level's own
    measured error can come out below it (a deviation search keeps levels at 0.6-1.0 of
    their bound), which would bring the LOD in closer, where the region shows more than
    P pixels. Held this way, the region shows at most P pixels wherever the LOD is drawn,
    and the LOD comes in no later than its limit's error puts it (the region is within
    that limit). ``hausdorff``: the level's largest error, ``region``: the largest
    weight-scaled distance of its painted region (limit_used times the limit), both mesh
    units; ``diagonal``: what percent means (the source's own diagonal, as the level's
    hausdorff_percent). Returns {switch_deviation (mesh units), switch_deviation_percent, region_pixels (the region's largest distance in pixels where
    the level switches in, before the chain's and the asset's running maximum, which only
    bring it in later)}."""
    switch = max(float(hausdorff), float(region) * float(pixel_error) / float(pixels))
    return {"switch_deviation": switch,
            "switch_deviation_percent": switch * 100.0 / diagonal if diagonal > 0 else float("nan"),
            "region_pixels": float(region) / switch * float(pixel_error) if switch > 0 else 0.0}


def switch_percent(entry: dict) -> float:
    """The error (percent of the source's diagonal) a measured level's switch distance is
    computed from: its Hausdorff distance, or pixel_switch's where a limit in pixels asks
    for more."""
    return float((entry.get("limit") or {}).get("switch_deviation_percent", entry["hausdorff_percent"]))


def level_report(source, sampled, column: int, limit: float, diagonal: float,
                 scene_scale: float = 1.0) -> Optional[dict]:
    """How the level keeps its painted limit, from the report's samples.

    ``source``: MeshData (faces, group_weights); ``sampled``: measure.Sampled of the source (src) against the level
    (dst); ``column``: the limit group's column of group_weights; ``limit``: L, mesh
    units; ``diagonal``: what percent means (mesh units); ``scene_scale``: mesh to
    scene units.

    {limit, limit_percent, limit_used (the largest distance over the local limit, at
    the samples and vertices of both surfaces: <= 1 where the limit holds), within
    (limit_used <= 1), region_hausdorff and region_hausdorff_percent (the largest
    distance where the weight is at least 1/2), samples (in the painted region)}, or
    None when nothing is painted."""
    src_w = np.asarray(source.group_weights, dtype=np.float64)[:, column]
    if not (src_w > MIN_WEIGHT).any():
        return None
    # Distance over the local limit, d / (L / w) = d * w / L, at every sample and vertex
    # of both surfaces; the limit is painted on the source, so a LOD point's is the one at
    # its closest source point.
    weight = np.concatenate([
        at_samples(src_w, source.faces, sampled.src_triangle, sampled.src_bary),
        at_samples(src_w, source.faces, sampled.dst_nearest, sampled.dst_nearest_bary),
        src_w[np.asarray(sampled.src_vertices, dtype=np.int64)],
        at_samples(src_w, source.faces, sampled.dst_vertex_nearest, sampled.dst_vertex_nearest_bary),
    ])
    distance = np.concatenate([sampled.src_distance, sampled.dst_distance,
                               sampled.src_vertex_distance, sampled.dst_vertex_distance])
    ratio = distance * np.clip(weight, 0.0, 1.0) / limit
    k_src, k_dst = len(sampled.src_distance), len(sampled.dst_distance)
    k_src_v = len(sampled.src_vertex_distance)
    source_side = np.concatenate([ratio[:k_src], ratio[k_src + k_dst:k_src + k_dst + k_src_v]])
    lod_side = np.concatenate([ratio[k_src:k_src + k_dst], ratio[k_src + k_dst + k_src_v:]])
    used = float(ratio.max())
    half = weight >= 0.5 - 1e-9
    region = float(distance[half].max()) if half.any() else 0.0
    percent = 100.0 / diagonal if diagonal > 0 else float("nan")
    return {
        "limit": limit * scene_scale,
        "limit_percent": limit * percent,
        "limit_used": used,
        # (each way: the source's points to the LOD, the LOD's to the source)
        "limit_used_source_to_lod": float(source_side.max(initial=0.0)),
        "limit_used_lod_to_source": float(lod_side.max(initial=0.0)),
        "within": bool(used <= 1.0),
        "region_hausdorff": region * scene_scale,
        "region_hausdorff_percent": region * percent,
        "samples": int(np.count_nonzero(weight > MIN_WEIGHT)),
    }


def held_to_limit(lod_input, simplify, first: Optional[list] = None) -> tuple:
    """(the chain under its painted limit, each level's measurement by id of its result,
    and each level's output mesh: {id: (result, mesh)}).

    The core holds the limit at its tracked points, and is given CORE_SHARE of it;
    the report's area samples fall between those points. Each level is measured here as
    the report will measure it (the same output mesh, so the same samples: the report
    reuses these measurements), and where a level used more than its limit the chain runs
    again with that level's limits (and the ones before it) scaled down to
    RERUN_AIM of what was used, at most RERUNS times."""
    data, settings = lod_input.data, lod_input.settings
    column, value, _ = lod_input.limit
    weights = data.group_weights[:, column]
    per_level = np.asarray(value if isinstance(value, tuple) else [value] * len(lod_input.targets), dtype=float)
    rows = level_rows(weights, per_level)
    results = first if first is not None else simplify(lod_input.targets)
    for attempt in range(RERUNS + 1):
        measured, built, used = {}, {}, []
        for k, result in enumerate(results):
            level = lod_mesh(data, result, lod_input.names, settings.hard_edge_angle)
            built[id(result)] = (result, level)
            normals = None if data.corner_normals is None else (data.corner_normals, shading_normals(level))
            rep = deviation_search.deviation_report(data, level, normals, lod_input.part_samples)  # (as compute.level_report)
            measured[id(result)] = rep
            kept = level_report(data, rep["sampled"], column, per_level[k],
                                lod_input.reference_diagonal or rep["diagonal"])
            used.append(0.0 if kept is None else kept["limit_used"])
        lod_input.limit_rows = rows
        scale = rerun_scales(used)
        if scale is None or attempt == RERUNS:
            return results, measured, built
        rows = scaled_rows(rows, scale)
        results = simplify(lod_input.targets, vertex_max_error=rows)
    return results, measured, built


def with_pixel_limit(lod_input, simplify) -> list:
    """The chain under a painted limit in pixels at each LOD's switch distance
    (pixel_limits): a first run without it gives each level's largest error ε_k
    (measured, with the deviation search's quicker sampling), the limit is then
    P / Pixel Error of it per level, and the chain runs again under those limits. Sets
    the per-level limits into lod_input.limit."""
    data, settings = lod_input.data, lod_input.settings
    column, _, scale = lod_input.limit
    free = simplify(lod_input.targets)
    eps = [measure.surface_deviation(data.vertices, data.faces, r.vertices, r.faces,
                                     n_samples=deviation_targets.QUICK_SAMPLES)["hausdorff"] for r in free]
    per_level = pixel_limits(eps, settings.limit_distance, settings.pixel_error)
    weights = data.group_weights[:, column]
    lod_input.limit = (column, tuple(float(v) for v in per_level), scale)
    return simplify(lod_input.targets,
                    vertex_max_error=level_rows(weights, per_level))
