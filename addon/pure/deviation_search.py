# SPDX-License-Identifier: GPL-3.0-or-later
"""LOD levels chosen by measured deviation: for each requested deviation, the fewest
triangles whose measured distance to the source stays within it.

The core's tracked distance bound first (deviation_targets.by_tracked_bounds), with the
artist's controls and then the lean run and the planes' placement (fewer triangles at
the same distance: deviation_targets.alternatives); for a deviation none meets, the
ladder of rungs (deviation_targets.choose_levels), the coarsest rung measured within it
refined between rungs (a second run). Every level kept is measured as the report
measures it, with a harder climb (``search_report``, at ``report_samples``), and that
report is the level's: its number is the one the search compared with the bound.

compute.py calls in here with the run's phases.LodInput and its ways of running the
core; this module does not import compute.py (which imports it).
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from ._core import core
from . import deviation_targets
from . import measure
from .settings import LodError

# Area samples per surface for the report's deviation (see measure.py): 8 a triangle, at
# least 4,000 and at most 25,000 (report_samples), the source's side SOURCE_SHARE of that.
# Measuring is a Python loop of BVH queries, and the samples are the mean's; the largest
# distance comes from every vertex (queried on top) and the climb from the farthest points
# (measure._climb). At 50,000 a side without the climb the report's Hausdorff distance was
# 5 % under a million samples' on average, and 30 % under at worst (homer at 50 %); now
# 1.5 % over on average and 9 % under at worst (a CAD part where it was 15 % under), the
# mean within 1.4 %, in 54 % of the time (bench/measure_accuracy.py, 36 LODs).
DEVIATION_SAMPLES = 25_000
DEVIATION_SAMPLES_PER_TRIANGLE = 8
DEVIATION_SAMPLES_MIN = 4_000
# The source's side gets this share of its report_samples: every source vertex is queried,
# and a LOD's distance to its source peaks at the source's corners and creases, which the
# vertices are; the LOD's large triangles are where its own samples are needed. A quarter
# of the samples on the source's side moved the Hausdorff distance by 0.5 % on average.
SOURCE_SHARE = 0.5
# A level the deviation search keeps is measured with this many climb seeds of each kind
# a direction (measure._climb; the report's are one per 1,500 points, at most 16): the
# search keeps levels close to their bound (deviation_targets.STRETCH_SHARE), and a peak
# between samples is what takes one beyond. Against one measurement of a million samples
# and 2,048 seeds, three random seeds each, on 15 LODs of the shared meshes at 0.05-1 %:
# 256 seeds came out at 0.85-1.00 of it (homer at 0.05 %: a peak on a LOD triangle a fifth of the
# median's area, which the report's samples seldom hit and no seed near the largest
# samples climbs to; the level was kept at 7,226 triangles and measured 0.055 % by
# bench/equal_error.py), 1,024 at 0.98-1.00, measuring in 1.5-2.8x the time (0.1 -> 0.27
# s on homer's level), a search in 1.03-1.3x (session 34, docs/method.md). That many for
# a surface measured with DEVIATION_SAMPLES, one per 24 samples: a surface measured with
# fewer (a small mesh, a part of an asset, part_samples) climbs from as many fewer, at
# least the report's 16 (search_report). An engine's 29 parts with 1,024 each took its
# search at --max-error 1% 3% from 36.5 to 47.6 s.
SEARCH_CLIMB_SEEDS = 1024


# A part of an asset is sampled as much as its share of the asset's area would be if the
# asset were measured as one surface (report_samples of all it draws), with at least this
# many (and never more than report_samples gives a mesh of its size): an engine's hundred
# bolts each paid 8,000 samples a side a level, seven times what the block they sit on got
# per unit of area, and measuring took three times the simplification. A part of fewer
# triangles gets one a triangle at least (its vertices are queried on top, and it climbs
# to its own largest distance): a 300-part character of 96,000 triangles takes 0.81
# million queries for its report (0.91 million with a floor of 1,000, 1.95 million with
# 8,000 a part; the same surface as one mesh 0.30 million), and the 59-part character of
# bench/many_parts.py 3.0 s from scene to .glb (3.35 s with 1,000). Over the engine's 87
# part levels the report's Hausdorff distance is 0.948 of 100,000 samples' on average
# (0.961 with 1,000), its mean within 0.91-1.12 of theirs for 90 % of them (0.92-1.05).
ASSET_PART_SAMPLES_MIN = 250


def report_samples(triangles: int, part_samples: Optional[int] = None) -> int:
    """Area samples the report measures a surface of ``triangles`` triangles with;
    ``part_samples``: for a part of an asset, what part_samples gave it."""
    own = int(min(DEVIATION_SAMPLES, max(DEVIATION_SAMPLES_MIN, DEVIATION_SAMPLES_PER_TRIANGLE * triangles)))
    return own if part_samples is None else min(own, int(part_samples))


def part_samples(area_share: float, asset_triangles: int, part_triangles: int) -> int:
    """The area samples a side of a part of ``part_triangles`` triangles in an asset: its
    share of the asset's area (0 to 1) of what the asset would get as one surface of
    ``asset_triangles`` triangles, at least ASSET_PART_SAMPLES_MIN or one a triangle,
    whichever is fewer."""
    floor = min(ASSET_PART_SAMPLES_MIN, max(int(part_triangles), 1))
    return int(max(floor, np.ceil(report_samples(asset_triangles) * area_share)))


def search_report(data, level, part_samples: Optional[int] = None) -> dict:
    """deviation_report of a level the search keeps: climbing from SEARCH_CLIMB_SEEDS in
    proportion to the level's samples (report_samples) against DEVIATION_SAMPLES."""
    samples = report_samples(len(level.faces), part_samples)
    seeds = max(measure.CLIMB_SEEDS, int(np.ceil(SEARCH_CLIMB_SEEDS * samples / DEVIATION_SAMPLES)))
    return deviation_report(data, level, part_samples=part_samples, climb_seeds=seeds)


def deviation_report(data, level, normals=None, part_samples: Optional[int] = None,
                     climb_seeds: Optional[int] = None) -> dict:
    """measure.mesh_report of ``level`` against the source, as the report measures it
    (``normals``: (source's, level's) corner normals, for the shading deviation too), with
    its points kept (``sampled``: the report's breakdown per material and region and the
    heat map use them, addon/pure/level_deviation.py); ``climb_seeds``: measure.
    surface_deviation's (None: the report's)."""
    return measure.mesh_report(data.vertices, data.faces, level.vertices, level.faces,
                               n_samples=(int(SOURCE_SHARE * report_samples(len(data.faces), part_samples)),
                                          report_samples(len(level.faces), part_samples)),
                               normals=normals, keep_samples=True, climb_seeds=climb_seeds)


def by_deviation(lod_input, simplify, report_progress, simplify_share, simplify_with_progress) -> tuple:
    """(the levels kept, each one's requested deviation, their measurements by id).

    First the core's tracked distance bound (deviation_targets.by_tracked_bounds), with
    the artist's controls, lean and the planes' placement (the fewer triangles win,
    deviation_targets.alternatives); for a deviation it does not meet, the ladder: per
    requested deviation the coarsest rung measured within it (deviation_targets.
    choose_levels), refined between rungs. A level measured far under its deviation is
    probed by count below it (probe_below). Neither that nor a smaller saving of an
    alternative is taken under a painted limit. A deviation none meets is left out with a
    warning, and none met is a LodError.

    ``simplify(targets, **options)``: the core run on ``lod_input`` (compute.py's, which
    moves the progress bar); ``simplify_with_progress(lod_input, targets, progress)``:
    the same with a progress callback of its own (compute.simplify_chain; the refinement's run)."""
    data = lod_input.data
    measured = {}

    def exact(level):
        report_progress(simplify_share)
        measured[id(level)] = search_report(data, level)
        return measured[id(level)]["hausdorff"]

    per_level = _level_limits(lod_input)

    def rows(requested):  # the per-level settings of the levels a run makes
        return {key: value[requested] for key, value in per_level.items()}

    def tracked(variant):  # by_tracked_bounds with the controls, ``variant`` replacing some
        return deviation_targets.by_tracked_bounds(
            lod_input.deviations,
            lambda bounds, requested: simplify([0] * len(bounds), max_error=bounds, **variant, **rows(requested)),
            exact)

    found = tracked({})
    options = lod_input.core_options
    # Under a painted limit neither a smaller saving of an alternative nor a run by count
    # (probe_below) is taken: the first took the Face region of tests/test_addon_limits.py
    # (limits in pixels, by deviation) to 1.17 of its limit, and a run by count holds a
    # limit only with limits.held_to_limit's measuring, which the probe does not do.
    slivers = sliver_share if lod_input.limit is None else None
    if options.line_weights is None and options.pose_offsets is None:
        # Lean, then the planes' placement (deviation_targets.alternatives): fewer
        # triangles at the same distance, each kept where it saves LEAN_MIN_SAVING, or
        # less with no larger share of slivers (deviation_targets.fewest_each; not under
        # a painted limit).
        for variant in deviation_targets.alternatives({"line_weight": options.line_weight}, options.min_quality):
            found = deviation_targets.fewest_each(found, tracked(variant), slivers=slivers)
    if any(f.level is None for f in found):
        ladder = _by_ladder(lod_input, simplify(lod_input.targets), report_progress, simplify_share,
                            simplify_with_progress)
        for f in found:
            other = ladder.get(f.deviation)
            if other is not None and (f.level is None or len(other[0].faces) < len(f.level.faces)):
                f.level, f.hausdorff = other[0], other[1]["hausdorff"]
                measured[id(other[0])] = other[1]
        deviation_targets.coarser_each(found)

    def quick(level):
        report_progress(simplify_share)
        return quick_hausdorff(data, level)

    if lod_input.limit is None:
        probe_below(found, lambda counts: simplify_with_progress(
            lod_input, counts, lambda _: report_progress(simplify_share) is None), quick, exact)
    kept = [f for f in found if f.level is not None]
    for f in found:
        if f.level is None and lod_input.in_asset:
            k = found.index(f) + 1
            lod_input.warnings.append(repeat_note(k, f.deviation))
        elif f.level is None:
            lod_input.warnings.append(
                f"no LOD within {f.deviation:.4g} (the object's units): no level coarser than the "
                f"one before is measured within it")
    if lod_input.in_asset and len(kept) < len(found):
        # A part of an asset is in every level: where nothing coarser is within the bound,
        # the level before repeats (at LOD1, the whole part).
        previous = None
        for f in found:
            if f.level is None:
                f.level = previous or whole(lod_input, simplify, measured)
            previous = f.level
        kept = found
    if not kept:
        raise LodError(f'"{lod_input.source_name}": no LOD is within the requested deviation '
                       f"{found[0].deviation:.4g}: ask for a larger one")
    lod_input.targets = [len(f.level.faces) for f in kept]
    if per_level:  # each kept level's own limit (the report's entry), as the levels left
        column, value, scale = lod_input.limit
        lod_input.limit = (column, tuple(value[found.index(f)] for f in kept), scale)
    return [f.level for f in kept], [f.deviation for f in kept], {id(f.level): measured[id(f.level)] for f in kept}


def repeat_note(k: int, deviation: float) -> str:
    """What a part of an asset says when its LOD ``k`` (1-based) repeats the level before
    (at LOD1, the whole part): nothing coarser is within the asset's ``deviation`` (the
    object's units)."""
    return (f"LOD{k} repeats " + (f"LOD{k - 1}" if k > 1 else "the whole part")
            + f": nothing coarser is within the asset's deviation {deviation:.4g} (the object's units)")


def _level_limits(lod_input) -> dict:
    """{vertex_max_error: (levels, n)} for a chain of the search when the painted limit
    is one per level (pixels at each LOD's switch distance: limits.pixel_limits of the
    requested deviations), else {} (the core options have the limit, or none)."""
    if lod_input.limit is None or not isinstance(lod_input.limit[1], tuple):
        return {}
    from . import limits  # (limits builds on this module's measurements)

    column, value, _ = lod_input.limit
    return {"vertex_max_error": limits.level_rows(lod_input.data.group_weights[:, column], value)}


def whole(lod_input, simplify, measured: dict):
    """The part itself as a level (a run to its own triangle count), measured: 0 apart."""
    level = simplify([len(lod_input.data.faces)])[0]
    measured[id(level)] = deviation_report(lod_input.data, level)
    return level


def _by_ladder(lod_input, rungs: list, report_progress, simplify_share, simplify_with_progress) -> dict:
    """{deviation: (level, its report)} for the requested deviations some rung of the
    ladder meets: the coarsest rung measured within it, refined between rungs where
    it is under half the deviation (_refine)."""
    quick, exact, reports = _measurers(lod_input.data, rungs, lambda: report_progress(simplify_share))
    choices = deviation_targets.choose_levels(lod_input.deviations, len(rungs), quick, exact)
    chosen = {}
    for c in choices:
        if c.level is None:
            continue
        level, report = rungs[c.level], reports[c.level]
        if c.hausdorff < deviation_targets.REFINE_BELOW * c.deviation and c.level + 1 < len(rungs):
            level, report = _refine(lod_input, level, report, rungs[c.level + 1], c.deviation, report_progress,
                                    simplify_share, simplify_with_progress)
        chosen[c.deviation] = (level, report)
    return chosen


def _refine(lod_input, within, within_report, beyond, deviation, report_progress, simplify_share,
            simplify_with_progress):
    """Between two adjacent rungs, ``within`` the bound at far less than it and ``beyond``
    it (a low-poly mesh, where one rung removes a large step of error): a second run
    snapshots counts between them and the coarsest measured within the bound is kept
    (else ``within``). Returns (level, its report)."""
    data = lod_input.data
    counts = deviation_targets.between(len(within.faces), len(beyond.faces))
    if not counts:
        return within, within_report
    levels = simplify_with_progress(lod_input, counts, lambda f: report_progress(simplify_share) is None)
    quick, exact, reports = _measurers(data, levels, lambda: report_progress(simplify_share))
    choice = deviation_targets.Search(quick, exact).coarsest_within(deviation, len(levels))
    if choice.level is None:
        return within, within_report
    return levels[choice.level], reports[choice.level]


def probe_below(found: list, run_counts, quick, exact) -> None:
    """Each level of ``found`` (Found, the searches' levels within their deviations, each
    coarser than the one before) that deviation_targets.probe_counts probes below:
    ``run_counts(counts)`` (a run by count, the controls' options) snapshots those
    counts, and the coarsest of them measured within STRETCH_WITHIN of the deviation
    replaces it. ``quick(level)`` steers the bisection, ``exact(level)`` is the report's
    measurement (deviation_targets.Search). The finest count is run and estimated first:
    where it is beyond, the coarser ones are not run (a run to half the triangles of a
    level near its source's count is most of a whole run: the engine's parts at 0.05 %)."""
    for i, f in enumerate(found):
        counts = deviation_targets.probe_counts(found, i)
        if not counts:
            continue
        bound = deviation_targets.STRETCH_WITHIN * f.deviation
        levels = run_counts(counts[:1])
        first = quick(levels[0])
        if first > bound:
            continue
        levels += run_counts(counts[1:]) if len(counts) > 1 else []
        choice = deviation_targets.Search(lambda k, at=levels: quick(at[k]), lambda k, at=levels: exact(at[k]),
                                          measured={0: first}).coarsest_within(bound, len(levels))
        if choice.level is not None and len(levels[choice.level].faces) < len(f.level.faces):
            f.level, f.hausdorff = levels[choice.level], choice.hausdorff


def sliver_share(level) -> float:
    """A level's share of slivers, in percent (core.quality_summary)."""
    return core.quality_summary(level.vertices, level.faces)["sliver_percent"]


def quick_hausdorff(data, level) -> float:
    """``level``'s two-sided Hausdorff distance to the source ``data``, estimated with
    QUICK_SAMPLES (what steers a bisection; the level kept is measured as reported)."""
    return measure.surface_deviation(data.vertices, data.faces, level.vertices, level.faces,
                                     n_samples=deviation_targets.QUICK_SAMPLES)["hausdorff"]


def _measurers(data, levels: list, tick) -> tuple:
    """(quick(i), exact(i), reports): level i's two-sided Hausdorff distance to the source,
    estimated with fewer samples or measured as the report measures it (its full report
    kept in ``reports[i]``); ``tick()`` before each lets Esc in between the measurements."""
    reports = {}

    def quick(i):
        tick()
        return quick_hausdorff(data, levels[i])

    def exact(i):
        tick()
        reports[i] = search_report(data, levels[i])
        return reports[i]["hausdorff"]

    return quick, exact, reports


def by_deviation_together(inputs: list, scales: list, copies: list, deviations: list, notes: list,
                          progress=None, cancelled=lambda: False) -> Optional[list]:
    """An asset's chain by deviation in one core run over all its parts (core.assembly), as
    by_deviation does for one mesh: the tracked distance bound, with the controls, lean and
    the planes' placement, each level measured as the report measures it, part by part (its
    Hausdorff distance in scene units: the largest over the parts). Twenty-nine separate
    searches took the CAD engine two minutes at --max-error 1% 3%.

    ``inputs``: the parts' LodInputs (their ``part_samples`` set); ``scales``: each part's
    largest world scale, ``copies``: how many objects draw it; ``deviations``: per level,
    scene units; ``notes`` gets what the report should say about the asset. Returns per
    part (its levels, their measurements by id), or None where a part left a level (the
    caller then searches part by part)."""
    assembly = core.assembly
    parts = [assembly.Part(i.data.vertices, i.data.faces, i.core_options, s, c)
             for i, s, c in zip(inputs, scales, copies)]
    vertices, faces, options, layout = assembly.combine(parts)
    splits, measured = {}, {}

    def run(bounds, requested, **more):
        if cancelled():
            raise core.SimplifyCancelled("cancelled")
        return core.simplify_chain(vertices, faces, [0] * len(bounds),
                                   core.Options.of(options, max_error=list(bounds), **more), progress=progress)

    def exact(level):
        if cancelled():
            raise core.SimplifyCancelled("cancelled")
        split = assembly.split(level, layout)
        splits[id(level)] = split
        worst = 0.0
        for part, lod_input, scale in zip(split, inputs, scales):
            if part is None:
                continue
            report = search_report(lod_input.data, part, part_samples=lod_input.part_samples)
            measured[id(part)] = report
            worst = max(worst, report["hausdorff"] * scale)
        return worst

    found = deviation_targets.by_tracked_bounds(deviations, run, exact)
    if all(i.core_options.line_weights is None and i.core_options.pose_offsets is None for i in inputs):
        # As by_deviation: lean, then the planes' placement, each where it saves a tenth
        # (or less, with no larger share of slivers).
        for variant in deviation_targets.alternatives({"line_weights": options.line_weights}, options.min_quality):
            found = deviation_targets.fewest_each(found, deviation_targets.by_tracked_bounds(
                deviations, lambda bounds, requested, variant=variant: run(bounds, requested, **variant), exact),
                slivers=sliver_share)
    # A level no run met repeats the one before, the whole asset at LOD1, as a part of
    # an asset does in its own search (by_deviation): every part is in every level.
    previous = None
    for k, f in enumerate(found, start=1):
        if f.level is None:
            if previous is None:
                previous = core.simplify_chain(vertices, faces, [int(round(float(
                    np.dot([len(i.data.faces) for i in inputs], copies))))], options)[0]
                exact(previous)
            f.level = previous
            notes.append(f"the asset's LOD{k} repeats " + (f"its LOD{k - 1}" if k > 1 else "it whole")
                         + f": nothing coarser is within its deviation {f.deviation:.4g} (scene units)")
        previous = f.level
    out = []
    for p in range(len(inputs)):
        chain = [splits[id(f.level)][p] for f in found]
        if any(level is None for level in chain):
            return None
        out.append((chain, {id(level): measured[id(level)] for level in chain}))
    return out
