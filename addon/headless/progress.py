# SPDX-License-Identifier: GPL-3.0-or-later
"""An input's progress lines while its LodJob runs: each object's chain, each LOD as it
is simplified, each object when done, with the time left for the input and the inputs
after it.
"""
from __future__ import annotations

import time

from ..job import ObjectObserver
from ..pure.compute import progress_share
from .console import Console, duration


class TimeLeft:
    """Time-left estimate for the objects of one input.

    Simplifying and measuring cost very differently (measuring a LOD is a fixed number
    of point queries, about the same for a small and a large LOD), so each has its own
    rate: seconds per triangle removed and seconds per LOD measured, taken from what
    this run has done so far (the current object's live progress before anything has
    finished), with rough priors before that. ``later`` adds the inputs still waiting.
    """

    PRIOR_SIMPLIFY = 5e-5  # s per triangle removed (2-core machine, bpy 4.5)
    PRIOR_MEASURE = 0.5  # s per LOD measured at deviation_search.DEVIATION_SAMPLES samples (fewer on small meshes)

    def __init__(self, inputs, later: float):
        # (An asset's parts get their targets when its budget is split: until then, all.)
        self.simplify_left = sum(len(i.data.faces) - (i.targets[-1] if i.targets else 0) for i in inputs)
        # LODs to measure (a chain by deviation: its bounds; its targets are the search's rungs).
        self.measure_left = sum(len(i.targets) if i.deviations is None else len(i.deviations)
                                for i in inputs if i.settings.measure_deviation or i.deviations is not None)
        self.simplify_done = self.simplify_seconds = 0.0
        self.measure_done = self.measure_seconds = 0.0
        self.later = later

    def rate(self, done, seconds, live_done, live_seconds, prior) -> float:
        if done > 0:
            return (seconds + live_seconds) / (done + live_done)
        if live_done > 0:
            return live_seconds / live_done
        return prior

    def left(self, live_simplify=0.0, live_simplify_s=0.0, live_measure=0.0, live_measure_s=0.0) -> float:
        rs = self.rate(self.simplify_done, self.simplify_seconds, live_simplify, live_simplify_s, self.PRIOR_SIMPLIFY)
        rm = self.rate(self.measure_done, self.measure_seconds, live_measure, live_measure_s, self.PRIOR_MEASURE)
        return (rs * max(self.simplify_left - live_simplify, 0.0) + rm * max(self.measure_left - live_measure, 0.0)
                + self.later)

    def record(self, removed, simplify_s, measured, measure_s) -> None:
        self.simplify_done += removed
        self.simplify_seconds += simplify_s
        self.simplify_left -= removed
        self.measure_done += measured
        self.measure_seconds += measure_s
        self.measure_left -= measured



class ProgressLines(ObjectObserver):
    """The lines of one input's LodJob run: each object's chain as it starts, each LOD as
    it is simplified, each object when it is done, all with the time left."""

    def __init__(self, console: Console, label: str, inputs: list, later: float):
        self.console = console
        self.label = label
        self.estimate = TimeLeft(inputs, later)

    def splitting(self, parts: int, targets: list) -> None:
        self.console.progress(f"[{self.label}] one asset of {parts} meshes: its budget ("
                              + ", ".join(f"LOD{k} {t:,}" for k, t in enumerate(targets, start=1))
                              + " triangles) goes to them by error")

    def started(self, lod_input) -> None:
        self.input = lod_input
        m = len(lod_input.data.faces)
        targets = lod_input.targets
        self.removed = max(m - (targets[-1] if targets else m), 1)
        if lod_input.deviations is not None:
            # A chain by deviation: the targets are the search's rungs, not LODs; the LODs
            # are known when it is done.
            self.console.progress(f"[{self.label}] {lod_input.source_name}: {m:,} triangles -> LODs within "
                                  + ", ".join(f"{d:.4g}" for d in lod_input.deviations) + " (measured)")
            self.marks = []
        else:
            self.console.progress(f"[{self.label}] {lod_input.source_name}: {m:,} triangles -> "
                                  + ", ".join(f"LOD{k} {t:,}" for k, t in enumerate(targets, start=1)))
            # The engine reports (faces removed) / (faces to remove down to the last target).
            self.marks = [(m - t) / self.removed for t in targets]
        self.measuring = lod_input.settings.measure_deviation or lod_input.deviations is not None
        self.share = progress_share(self.measuring)  # how lod.compute splits its fraction
        self.next = 0
        self.t0 = time.perf_counter()
        self.t_simplified = None

    def _left(self, chain: float, measured: float) -> str:
        now = time.perf_counter()
        if self.t_simplified is None:
            left = self.estimate.left(chain * self.removed, now - self.t0)
        else:
            left = self.estimate.left(self.removed, self.t_simplified - self.t0, measured, now - self.t_simplified)
        return f"about {duration(left)} left"

    def progress(self, fraction: float) -> None:
        chain = min(fraction / self.share, 1.0)
        if chain >= 1.0 and self.t_simplified is None:
            self.t_simplified = time.perf_counter()
        while self.next < len(self.marks) and chain >= self.marks[self.next] - 1e-9:
            self._announce(self.next, chain)
            self.next += 1

    def _announce(self, index: int, chain: float) -> None:
        name = self.input.source_name
        self.console.progress(f"[{self.label}] {name}: LOD{index + 1} simplified, target "
                              f"{self.input.targets[index]:,} triangles ({self._left(chain, 0.0)})")

    def finished(self, lod_output) -> None:
        while self.next < len(self.marks):  # levels that stopped early
            self._announce(self.next, 1.0)
            self.next += 1
        now = time.perf_counter()
        simplified = self.t_simplified or now
        measured = len(lod_output.levels) if self.measuring else 0
        self.estimate.record(self.removed, simplified - self.t0, measured, now - simplified)
        self.console.progress(f"[{self.label}] {self.input.source_name}: done in {now - self.t0:.1f} s "
                              f"(about {duration(self.estimate.left())} left)")
