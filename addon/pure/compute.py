# SPDX-License-Identifier: GPL-3.0-or-later
"""The compute phase of a LOD run (addon/lod.py): simplify and measure a LodInput into a
LodOutput with NumPy and the core alone, so it can run in a worker thread.

Which way the levels are made follows the input: by triangle targets (one core run),
under a painted limit (limits.held_to_limit), by deviation (deviation_search), or as an
asset's core run left them (LodInput.chain); with the rig's sample poses their skin
weights are fitted (skin_fit). Each level's mesh is rebuilt from the core's result
(rebuild.lod_mesh) and gets its report entry: counts, why the core stopped, and when
measuring the deviation, per material and region (level_deviation), per shape key
(key_deviation) and how dense the painted region stayed (importance).
"""
from __future__ import annotations

import time
from typing import Callable, Optional

from ._core import core
from . import deviation_search
from . import importance as imp
from . import key_deviation
from . import level_deviation
from . import limits
from . import measure
from . import mesh_data
from . import rebuild
from . import skin_fit
from .deviation_search import report_samples
from .mesh_data import MeshData
from .phases import LodInput, LodOutput
from .settings import LodCancelled, LodError

# What a measured LOD's report entry takes from measure.mesh_report: distances in % of the
# source's bounding-box diagonal, the shading normals' angle to the source's in degrees
# (measure.normal_deviation), triangle quality.
NORMAL_KEYS = ("normal_mean_degrees", "normal_p95_degrees", "normal_max_degrees")
REPORT_KEYS = ("hausdorff_percent", "mean_percent") + NORMAL_KEYS + ("mean_quality", "min_quality",
                                                                     "sliver_percent")
# compute() reports simplification as this share of its progress and the deviation
# measurement (when on) as the rest; progress_share() is what callers estimating time use.
SIMPLIFY_SHARE = 0.8


def progress_share(measuring: bool) -> float:
    """The share of compute()'s progress fraction that simplification takes."""
    return SIMPLIFY_SHARE if measuring else 1.0


def compute(lod_input: LodInput, progress: Optional[Callable[[float], object]] = None) -> LodOutput:
    """Simplify and measure (no bpy data access: safe in a worker thread).

    progress(fraction in [0, 1]) is called during the run; returning False cancels it
    (LodCancelled). Simplification is the first SIMPLIFY_SHARE, the deviation report the rest.
    """
    t0 = time.perf_counter()
    measuring = lod_input.settings.measuring()
    simplify_share = progress_share(measuring or lod_input.deviations is not None)

    def report_progress(fraction):
        if progress is not None and progress(min(max(fraction, 0.0), 1.0)) is False:
            raise LodCancelled("cancelled")

    data = lod_input.data

    reached = [0.0]  # a search runs the core more than once: the bar never goes back

    def simplify(targets, **options):
        def step(f):
            reached[0] = max(reached[0], simplify_share * f)
            return progress is None or progress(reached[0]) is not False
        return simplify_chain(lod_input, targets, step, **options)

    built = {}  # output meshes already made (under a painted limit): {id(result): (result, mesh)}
    if lod_input.in_asset and not lod_input.targets and lod_input.deviations is not None:
        # A part too small to search (addon/asset.py): whole at every level of the asset.
        measured = {}
        whole = deviation_search.whole(lod_input, simplify, measured)
        results, requested = [whole] * len(lod_input.deviations), list(lod_input.deviations)
        lod_input.targets = [len(data.faces)] * len(results)
        lod_input.warnings.append(f"too small ({len(data.faces)} triangles) for a LOD by deviation: "
                                  f"kept whole at every level")
    elif lod_input.in_asset and not lod_input.targets:
        results, requested, measured = [], [], {}  # the asset's split removed it at LOD1
    elif lod_input.chain is not None:  # simplified with the rest of its asset (LodJob)
        results = list(lod_input.chain)
        requested = list(lod_input.chain_requested or [None] * len(results))
        measured = dict(lod_input.chain_measured or {})
    elif lod_input.deviations is not None:
        results, requested, measured = deviation_search.by_deviation(lod_input, simplify, report_progress,
                                                                     simplify_share, simplify_chain)
    elif lod_input.limit is not None:
        # Painted limits with triangle targets: measured as the report measures, rerun
        # tighter where a level came out beyond (addon/pure/limits.py).
        first = limits.with_pixel_limit(lod_input, simplify) if lod_input.limit[1] is None else None
        results, measured, built = limits.held_to_limit(lod_input, simplify, first)
        requested = [None] * len(results)
    else:
        results = simplify(lod_input.targets)
        requested = [None] * len(results)
        measured = {}
    levels, reports = [], []
    diagonal = own_diagonal = None
    if lod_input.deviations is not None:
        diagonal = lod_input.reference_diagonal or measure.bbox_diagonal(data.vertices, data.faces)
        if lod_input.reference_diagonal:
            own_diagonal = measure.bbox_diagonal(data.vertices, data.faces)
    if lod_input.poses is not None:
        results = skin_fit.skinned_levels(lod_input, results, simplify, lod_input.deviations is None,
                                          lambda: report_progress(simplify_share))
    previous = None  # the last level's measurement (a repeated level is not measured again)
    for k, (target, result) in enumerate(zip(lod_input.targets, results), start=1):
        report_progress(simplify_share + (1.0 - simplify_share) * (k - 1) / len(results))
        repeated = k > 1 and result is results[k - 2]
        if repeated:  # a level repeated (an asset's part): one mesh
            levels.append(levels[-1])
        elif id(result) in built and built[id(result)][0] is result:  # (measured under a limit)
            levels.append(built[id(result)][1])
        else:
            levels.append(rebuild.lod_mesh(data, result, lod_input.names, lod_input.settings.hard_edge_angle))
        stats = result.stats
        entry = {
            "level": k,
            "target": int(target) if requested[k - 1] is None else None,
            "triangles": int(len(result.faces)),
            "vertices": int(len(result.vertices)),
            "seconds": float(stats.seconds),
            "stop_reason": stats.stop_reason,
            "relaxation_step": int(stats.relaxation_step),
            "removed_components": int(stats.removed_components),
        }
        if requested[k - 1] is not None:
            entry["requested_deviation"] = requested[k - 1]
            entry["requested_deviation_percent"] = requested[k - 1] * 100.0 / diagonal
            if own_diagonal is not None and own_diagonal > 0:
                # A part's bound in % of its own diagonal, as its hausdorff_percent is
                # (requested_deviation_percent is the asset's, its reference).
                entry["requested_deviation_object_percent"] = requested[k - 1] * 100.0 / own_diagonal
        if measuring or requested[k - 1] is not None:
            rep = previous if repeated and previous is not None else \
                level_report(data, levels[-1], measured.get(id(result)), lod_input.part_samples)
            previous = rep
            entry.update({key: float(rep[key]) for key in REPORT_KEYS if key in rep})
            # Per material and painted region, and the heat map when asked for.
            levels[-1], more = level_deviation.measure_level(lod_input, levels[-1], rep, k - 1)
            entry.update(more)
        else:
            entry.update(core.quality_summary(result.vertices, result.faces))
            if lod_input.limit is not None and id(result) in measured:
                # Measuring off, but the chain was held to its painted limit as measured:
                # how it kept the limit costs nothing more to report.
                kept = limits.limit_entry(lod_input, measured[id(result)], k - 1)
                if kept is not None:
                    entry["limit"] = kept
        if measuring and data.shape_keys:
            # Each key's shape too: the LOD with the key at 1 against the source with it.
            entry["shape_keys"] = reports[-1]["shape_keys"] if repeated and "shape_keys" in reports[-1] \
                else key_deviation.level_key_deviations(data, levels[-1], part_samples=lod_input.part_samples)
        if lod_input.importance is not None:
            density = imp.importance_density(lod_input.importance, result.vertex_origin,
                                         imp.region_word(lod_input.settings.importance_source))
            if density is not None:
                entry["importance"] = density
        if stats.stop_reason != core.STOP_TARGET and requested[k - 1] is None:
            why = core.STOP_REASON_TEXT.get(stats.stop_reason, stats.stop_reason)
            hint = "" if lod_input.settings.remove_small_components else \
                " (Remove Small Parts lets it delete the smallest separate parts)"
            lod_input.warnings.append(
                f"LOD{k} stopped at {entry['triangles']} triangles (target {target}): {why}"
                + (hint if stats.stop_reason == core.STOP_TOPOLOGY else ""))
        reports.append(entry)
    report_progress(1.0)
    return LodOutput(lod_input, levels, reports, time.perf_counter() - t0)


def level_report(data: MeshData, level: MeshData, measured: Optional[dict],
                  part_samples: Optional[int] = None) -> dict:
    """The report's measurement of ``level`` against the source ``data``: mesh_report at
    report_samples, with the shading-normal deviation from the same closest points
    (the LOD's normals as Blender will shade it, mesh_data.shading_normals). ``measured``:
    the level's report if a deviation search already made one; it gets the normal
    deviation on its own (the search measured before the LOD's normals existed)."""
    normals = None if data.corner_normals is None else (data.corner_normals, mesh_data.shading_normals(level))
    if measured is None:
        return deviation_search.deviation_report(data, level, normals, part_samples)
    if normals is None or "normal_mean_degrees" in measured:
        return measured
    if "sampled" in measured:  # (the closest points it kept give the normals' angles: no query)
        return dict(measured, **measure.normal_keys_of(measured["sampled"], *normals))
    angles = measure.normal_deviation(data.vertices, data.faces, normals[0], level.vertices, level.faces, normals[1],
                                      n_samples=report_samples(len(data.faces), part_samples))
    return dict(measured, **{key: angles[key] for key in NORMAL_KEYS})


def simplify_chain(lod_input: LodInput, targets: list, progress, **options) -> list:
    """core.simplify_chain on the input, with the input's options (``options`` replacing
    some); cancelling and the core's ValueError become LodCancelled and LodError."""
    data = lod_input.data
    try:
        return core.simplify_chain(data.vertices, data.faces, targets,
                                   core.Options.of(lod_input.core_options, **options), progress=progress)
    except core.SimplifyCancelled as ex:
        raise LodCancelled("cancelled") from ex
    except ValueError as ex:
        raise LodError(f'"{lod_input.source_name}": {ex}') from ex
