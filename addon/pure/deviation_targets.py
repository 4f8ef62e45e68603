# SPDX-License-Identifier: GPL-3.0-or-later
"""LODs asked for by deviation: the fewest triangles whose *measured* distance to the
source stays within a bound (issue 22).

First choice: the core's ``max_error``, a distance it tracks collapse by collapse
(core.tracked_distance), one run for the whole chain of bounds (``by_tracked_bounds``).
It checks points, so the area-sampled Hausdorff distance the report gives can come out
a little above it: each level is given TRACKED_SHARE of its deviation, measured as the
report measures it, and rerun with a rescaled bound where it came out beyond (or
needlessly close).

The tracked distance over-estimates across some collapses (a bevel flattened into its
side), so a level kept far under its deviation is probed by count below it
(``probe_counts``; deviation_search.probe_below keeps the coarsest measured within).

Fallback, for levels no tracked run brings within: one progressive run snapshots a ladder
of ever coarser levels (each ``LADDER_STEP`` times the triangles of the one before), and
a bisection over the ladder estimates the two-sided Hausdorff distance (addon/pure/measure.py
with fewer samples) of a few of them, and the coarsest within the bound is then measured
as the report measures it; should that say "beyond" after all, the next finer rung is.
Distance grows close to monotonically as triangles go, so about log2(levels) estimates
suffice; the kept level's reported number is within the bound by construction. Adjacent
levels differ by about 1/LADDER_STEP in distance, so the level kept is seldom needlessly
dense.

No bpy here: the measuring function is passed in (``measure.surface_deviation`` needs
Blender's mathutils when called).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np

LADDER_STEP = 0.85  # each rung keeps this share of the rung above's triangles
LADDER_FLOOR = 4  # no rung below this many triangles (a tetrahedron)
FIRST_RUNGS = (0.99, 0.97, 0.94, 0.9)  # shares of the source's triangles above the first step
# A level kept at less than this share of its bound is refined between its rung and the
# next (a second run; see deviation_search._refine): the "within a factor 2" of the request.
REFINE_BELOW = 0.5
REFINE_STEPS = 8  # counts tried between two rungs
# The first bound given to the core, as a share of the requested deviation: the sampled
# Hausdorff distance came out at 1.0-1.44x the tracked bound (Fox, homer, fandisk, bunny
# at 0.05-2 %), so at 0.7 one run is within and close (0.7-1.0x) nearly always: a second
# run costs as much as the first (28 s on the 124k-triangle ogre).
TRACKED_SHARE = 0.7
TRACKED_RUNS = 3  # at most: a level that came out beyond, or needlessly close, runs again
TRACKED_CLOSE = 0.6  # needlessly close: measured under this share of the deviation
TRACKED_AIM = 0.9  # a run again aims at this share of it
# The first run stops at each level a second time, at STRETCH_SHARE of its deviation (the
# same run goes on to it), and that coarser level is kept where it measures within
# STRETCH_WITHIN of the deviation: where the tracked distance is the sampled one (clean
# tessellations, props) the share of 0.7 above leaves 30 % of the bound unused, and a
# level measured just under its bound is the one measuring's luck most often flatters.
STRETCH_SHARE = 0.9
STRETCH_WITHIN = 0.95
# The tracked distance is an upper estimate: a run under it stops where the estimate, not
# the measured distance, reaches the bound. Where a level kept measures under PROBE_BELOW
# of its deviation, a run by count (the controls, no bound) snapshots counts below it, down
# to PROBE_SHARE of its triangles (probe_counts), and the coarsest measured within
# STRETCH_WITHIN of the deviation replaces it (deviation_search.probe_below). The long
# bevelled box of bench/blender_props.py at 1 %: the bound stopped at 20 triangles measured
# at 0.71 %, by count 12 measure 0.90 % (Decimate's 12). A run by count flattens the bevels
# first, so below a level measured close to its bound it finds nothing: probed from 0.85,
# no level of bench/equal_error.py's meshes came out coarser, and the searches took 5-15 %
# longer (ogre 98 -> 105 s). From 0.75 the engine's parts are probed (body_2 at 0.05 and
# 1 %), the finest count first (deviation_search.probe_below): body_2 24.9 -> 25.2-25.7 s.
PROBE_BELOW = 0.75
PROBE_SHARE = 0.5
# Area samples a side for the estimates that steer the search (the report uses
# measure.DEFAULT_SAMPLES); vertices are added either way.
QUICK_SAMPLES = 50_000
# A LOD asked for by deviation is judged by its triangles at that distance, as game
# pipelines judge one, so the tracked search runs twice: with the artist's controls, and
# "lean", with a tenth of the line weight and half the sliver floor; each level keeps the
# run with fewer triangles within its bound (``fewest_each``). Measured with
# bench/equal_error.py against Decimate bisected to the same two-sided Hausdorff distance
# (fandisk, 0.05 / 0.2 %): 1,054 / 370 triangles with the controls alone (1.08x / 0.98x
# Decimate's), 828 / 320 lean, with 17 / 13 % slivers against Decimate's 28 / 25 %. On
# organic meshes the two differ by 1-2 %. Not with importance or a rig (their own
# line weights are the artist's control, addon/pure/importance.py).
LEAN_LINE_WEIGHT = 0.1  # times the line weight
LEAN_MIN_QUALITY = 0.5  # times the sliver floor
# The lean level is kept only where it saves this share of the triangles: its thinner
# triangles are worth a real saving. On organic meshes it saved 1-9 % and had up to three
# times Decimate's slivers (beast and the bunny at 1 %: 9.6-9.8 % against 3.3-3.6 %).
LEAN_MIN_SAVING = 0.1
# A smaller saving is kept where it costs nothing (fewest_each with ``slivers``): the
# level has no larger share of slivers than the one it replaces, and measures within
# STRETCH_WITHIN of its deviation (a level measured just under its bound is the one
# measuring's luck most often flatters). bench/blender_props.py --equal-error: the
# bevelled cylinder at 1 % 72 -> 66 triangles (the planes' placement, 30.6 -> 28.8 %
# slivers), the cone at 1 % 46 -> 44.
# A third run places each merged vertex by its planes (core.Options.plane_placement), kept
# as lean is, where it saves LEAN_MIN_SAVING of the triangles: where the planes leave a
# direction free (a cap, a straight wall) the line quadrics place a merge, and on the
# bevelled cylinder of bench/blender_props.py those merges held the LOD at 1,162 triangles
# at 0.05 % of its diagonal (1.11x Decimate's) with either line weight; by its planes
# 1,044 (1.00x). Placed so in every run, smooth props lost (the knob at 0.05 %: 1,394 ->
# 1,976 triangles): a run of its own, so each level keeps the placement that did better
# (docs/method.md, "Props as Blender makes them").


def alternatives(line_weight: dict, min_quality: float) -> list:
    """The search's runs besides the artist's controls, as core options that replace
    theirs, in the order they are compared (fewest_each): lean, then the planes'
    placement. ``line_weight``: the controls' line weight as the core option that carries
    it, {"line_weight": w} or {"line_weights": (n,) array} (an asset's parts in one run);
    ``min_quality``: their sliver floor."""
    lean = {name: value * LEAN_LINE_WEIGHT for name, value in line_weight.items()}
    return [{**lean, "min_quality": min_quality * LEAN_MIN_QUALITY}, {"plane_placement": True}]


def ladder(triangles: int, step: float = LADDER_STEP, floor: int = LADDER_FLOOR) -> list:
    """Decreasing triangle counts below ``triangles``: first the fine rungs of FIRST_RUNGS
    (tight bounds on low-poly meshes allow only a few collapses), then
    round(triangles * step**k), k >= 1, down to ``floor``; distinct, so every rung
    removes something."""
    shares = [r for r in FIRST_RUNGS if r > step] + [step ** k for k in range(1, 200)]
    counts = []
    for share in shares:
        count = int(round(triangles * share))
        if count < floor:
            break
        if count < triangles and (not counts or count < counts[-1]):
            counts.append(count)
    return counts


@dataclass
class Choice:
    """For one requested deviation: the rung kept (None: not even the first rung is within
    it) and the Hausdorff distance measured there (mesh units)."""

    deviation: float
    level: Optional[int]
    hausdorff: float


@dataclass
class Search:
    """Measured distances by rung index, shared between the requested deviations.

    ``quick(i)`` steers the bisection (fewer samples); ``exact(i)`` is the report's own
    measurement, taken of the rung finally kept: if it says the rung is beyond the bound
    after all (a sampling miss), the next finer rung is confirmed instead.
    """

    quick: Callable[[int], float]
    exact: Optional[Callable[[int], float]] = None
    measured: dict = field(default_factory=dict)
    confirmed: dict = field(default_factory=dict)

    def hausdorff(self, level: int) -> float:
        if level not in self.measured:
            self.measured[level] = float(self.quick(level))
        return self.measured[level]

    def exact_hausdorff(self, level: int) -> float:
        if self.exact is None:
            return self.hausdorff(level)
        if level not in self.confirmed:
            self.confirmed[level] = float(self.exact(level))
        return self.confirmed[level]

    def coarsest_within(self, deviation: float, levels: int, below: int = -1) -> Choice:
        """The highest rung in (below, levels) measured within ``deviation``; bisection
        assuming distance grows with the rung (rung ``below`` is taken as within)."""
        lo, hi = below, levels  # lo: within (or the source), hi: beyond (or past the end)
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if self.hausdorff(mid) <= deviation:
                lo = mid
            else:
                hi = mid
        while lo > below and self.exact_hausdorff(lo) > deviation:
            lo -= 1
        if lo == below:
            return Choice(deviation, None, float("nan"))
        return Choice(deviation, lo, self.exact_hausdorff(lo))


def choose_levels(deviations: Sequence[float], levels: int, quick: Callable[[int], float],
                  exact: Optional[Callable[[int], float]] = None) -> list:
    """A Choice per requested deviation (increasing), each coarser than the one before.

    ``levels``: how many rungs the run produced; ``quick(i)`` / ``exact(i)``: the two-sided
    Hausdorff distance of rung i to the source, in the units of ``deviations``, estimated
    and as reported (``exact`` defaults to ``quick``).
    """
    deviations = [float(d) for d in deviations]
    if any(not np.isfinite(d) or d <= 0 for d in deviations):
        raise ValueError(f"deviations must be positive numbers, got {deviations}")
    if any(b <= a for a, b in zip(deviations, deviations[1:])):
        raise ValueError(f"deviations must increase (each LOD coarser than the one before), got {deviations}")
    search = Search(quick, exact)
    choices, below = [], -1
    for deviation in deviations:
        choice = search.coarsest_within(deviation, levels, below)
        if choice.level is not None:
            below = choice.level
        choices.append(choice)
    return choices


def between(finer: int, coarser: int, steps: int = REFINE_STEPS) -> list:
    """Up to ``steps`` decreasing triangle counts strictly between two rungs' counts."""
    counts = np.unique(np.round(np.linspace(finer, coarser, steps + 2)[1:-1]).astype(int))[::-1]
    return [int(c) for c in counts if coarser < c < finer]


def probe_counts(found: list, i: int) -> list:
    """The decreasing triangle counts a run by count tries below ``found[i]`` (Found, from
    by_tracked_bounds): REFINE_STEPS between its level and PROBE_SHARE of its triangles,
    then that share, none at or below the next level kept (each level stays coarser than
    the one before) nor below LADDER_FLOOR; none where its level measured at PROBE_BELOW
    of its deviation or more, or there is none."""
    f = found[i]
    if f.level is None or not f.hausdorff < PROBE_BELOW * f.deviation:
        return []
    n = len(f.level.faces)
    later = [len(g.level.faces) for g in found[i + 1:] if g.level is not None]
    floor = max(LADDER_FLOOR, int(np.ceil(n * PROBE_SHARE)), later[0] + 1 if later else 0)
    return between(n, floor) + [floor] if floor < n else []


@dataclass
class Found:
    """A level found for one requested deviation by the tracked bound: the core's result
    (None: no run gave one within) and its measured Hausdorff distance (mesh units)."""

    deviation: float
    level: object
    hausdorff: float


def by_tracked_bounds(deviations: Sequence[float], run: Callable[[list, list], list],
                      exact: Callable[[object], float]) -> list:
    """A Found per requested deviation (increasing), from runs of the core with
    ``max_error`` bounds.

    run(bounds, requested): the core's levels (core.SimplifyResult) for a non-decreasing
    list of bounds, one run, one level each; ``requested`` the index of the deviation
    each bound is for (per-level settings, painted limits, follow it); exact(level): its
    two-sided Hausdorff distance as reported. The first run also stops at STRETCH_SHARE
    of each deviation, and that level is kept where it measures within STRETCH_WITHIN of
    it. Each run rescales a level's bound by how its measurement missed the deviation (to
    TRACKED_AIM of it, by a factor in [0.5, 2]): smaller where it came out beyond, larger
    where it came out needlessly close (under TRACKED_CLOSE). The coarsest level measured
    within is kept; a level no collapse made is no LOD (its next bound is the whole
    deviation). A run again makes the levels up to the last one that needs it.
    """
    deviations = [float(d) for d in deviations]
    shares = [TRACKED_SHARE] * len(deviations)
    found = [Found(d, None, float("nan")) for d in deviations]
    levels = len(deviations)  # how many levels the next run makes
    for attempt in range(TRACKED_RUNS):
        # Each level's bounds in this run: its share, and on the first run also STRETCH_SHARE.
        per_level = [(share, max(share, STRETCH_SHARE)) if attempt == 0 else (share,) for share in shares[:levels]]
        step = len(per_level[0])
        asked = list(np.maximum.accumulate([s * d for level_shares, d in zip(per_level, deviations) for s in level_shares]))
        made = run(asked, [i for i, level_shares in enumerate(per_level) for _ in level_shares])
        bounds = asked[::step]
        again = -1  # the last level that runs again
        for i, level in enumerate(made[::step]):
            stretched = _stretched_within(made[step * i + 1], level, deviations[i], exact) if step == 2 else None
            if stretched is not None:
                found[i] = stretched
                continue
            if level.stats.collapses == 0:  # the bound allowed no collapse at all
                if shares[i] < 1.0:
                    shares[i], again = 1.0, i
                continue
            best = found[i].level
            if best is not None and len(level.faces) >= len(best.faces):
                continue  # no coarser than what is kept
            hausdorff = float(exact(level))
            if hausdorff <= deviations[i]:
                found[i] = Found(deviations[i], level, hausdorff)
            if not TRACKED_CLOSE <= hausdorff / deviations[i] <= 1.0:
                # Relative to the bound this level was given (the chain may have raised it).
                factor = TRACKED_AIM * deviations[i] / max(hausdorff, 1e-12 * deviations[i])
                shares[i] = bounds[i] / deviations[i] * min(max(factor, 0.5), 2.0)
                again = i
        if again < 0:
            break
        # A run again stops at the last level that needs it: the levels after it keep
        # what they have (the chain's levels need not come from one run), and a CAD
        # engine's run paid its whole tail for a first level run again.
        levels = again + 1
    return coarser_each(found)


def _stretched_within(far, level, deviation: float, exact) -> Optional[Found]:
    """The first run's stretched level ``far`` (at STRETCH_SHARE) as found for
    ``deviation`` where it is coarser than ``level`` and measures within STRETCH_WITHIN of
    the deviation, else None."""
    if far.stats.collapses == 0 or len(far.faces) >= len(level.faces):
        return None
    hausdorff = float(exact(far))
    return Found(deviation, far, hausdorff) if hausdorff <= STRETCH_WITHIN * deviation else None


def coarser_each(found: list) -> list:
    """``found`` (Found or Choice-like: ``.level`` with ``.faces``, or None) with every
    level that is no coarser than a kept one before it left out (level None)."""
    fewest = None
    for f in found:
        if f.level is None:
            continue
        if fewest is not None and len(f.level.faces) >= fewest:
            f.level, f.hausdorff = None, float("nan")
        else:
            fewest = len(f.level.faces)
    return found


def fewest_each(found: list, other: list, min_saving: float = LEAN_MIN_SAVING,
                slivers: Optional[Callable[[object], float]] = None) -> list:
    """``found`` with each level replaced by ``other``'s for the same deviation where that
    has at least ``min_saving`` fewer triangles (a share; both within their bound: Found
    from by_tracked_bounds), or where ``found`` has none, or (with ``slivers(level)``, a
    level's share of slivers) where it has fewer triangles at no cost (``_free_saving``);
    then each level coarser than the one before (coarser_each)."""
    for mine, theirs in zip(found, other):
        if theirs.level is not None and (
                mine.level is None or len(theirs.level.faces) <= (1.0 - min_saving) * len(mine.level.faces)
                or (slivers is not None and _free_saving(mine, theirs, slivers))):
            mine.level, mine.hausdorff = theirs.level, theirs.hausdorff
    return coarser_each(found)


def _free_saving(mine, theirs, slivers) -> bool:
    """Whether ``theirs`` (Found) has fewer triangles than ``mine`` with no larger share of
    slivers, measured within STRETCH_WITHIN of its deviation."""
    return (len(theirs.level.faces) < len(mine.level.faces)
            and theirs.hausdorff <= STRETCH_WITHIN * theirs.deviation
            and slivers(theirs.level) <= slivers(mine.level))
