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
asset's when the object is part of one), as ``--max-error`` is. Each LOD's report
measures it with the report's own samples (measure.Sampled): at every sample of both
surfaces in the group, its distance over the limit there (``limit_used``: at most 1 when
the limit holds), and the region's largest distance.

Free of bpy: arrays in and out.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from .level_deviation import at_samples

# The core holds the limit at its tracked points (the source's vertices and a grid inside
# its faces; the LOD's vertices and points of its faces): the report's area samples fall
# between them and came out up to 1.08x the core's bound on the test sphere
# (tests/scenarios/addon_limits.py), so the core is given this share of the limit.
CORE_SHARE = 0.85
# Weights below this count as unpainted: a limit of L / 1e-6 is no limit at all, and
# float noise in a group should not constrain the LOD.
MIN_WEIGHT = 1e-6


def limit_in_mesh_units(value: float, percent: bool, diagonal: float, scale: float) -> float:
    """The limit L in the object's own (mesh) units: ``value`` percent of ``diagonal``
    (the object's or the asset's bounding-box diagonal, mesh units), or ``value`` scene
    units through the object's world ``scale`` (its largest axis scale; 1 for a single
    object, whose numbers are in its own units as --max-error's are)."""
    return value * diagonal / 100.0 if percent else value / scale


def vertex_limits(weights: np.ndarray, limit: float) -> np.ndarray:
    """(n,) per-vertex limits for the core, mesh units: CORE_SHARE of limit / weight
    where the weight is above MIN_WEIGHT, inf (free) elsewhere. ``weights``: (n,) the
    group's, in [0, 1]."""
    w = np.clip(np.asarray(weights, dtype=np.float64), 0.0, 1.0)
    out = np.full(len(w), np.inf)
    painted = w > MIN_WEIGHT
    out[painted] = CORE_SHARE * limit / w[painted]
    return out


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
    used = float((distance * np.clip(weight, 0.0, 1.0)).max()) / limit
    half = weight >= 0.5 - 1e-9
    region = float(distance[half].max()) if half.any() else 0.0
    percent = 100.0 / diagonal if diagonal > 0 else float("nan")
    return {
        "limit": limit * scene_scale,
        "limit_percent": limit * percent,
        "limit_used": used,
        "within": bool(used <= 1.0),
        "region_hausdorff": region * scene_scale,
        "region_hausdorff_percent": region * percent,
        "samples": int(np.count_nonzero(weight > MIN_WEIGHT)),
    }
