"""Progress and cancelling between, and inside, the long steps of a run.

A pass over a scan of millions of triangles takes seconds, and the set-up before the
first pass longer still; an artist's Esc and a pipeline's Ctrl-C must not wait for it.
The engine calls :meth:`Heartbeat.beat` between steps and between chunks of its bulk
work; the caller's progress callback runs at most every ``interval`` seconds, with the
fraction done so far, and returning False from it cancels the run there.
"""
from __future__ import annotations

import time
from typing import Callable, Optional

from .result import SimplifyCancelled

BEAT_INTERVAL = 0.25  # seconds between progress calls inside a pass
# Rows per chunk of per-edge bulk work (positions and costs): about 0.1-0.3 s each on one
# core, large enough that the chunking costs nothing measurable.
CHUNK_ROWS = 1 << 19


class Heartbeat:
    def __init__(self, progress: Optional[Callable[[float], object]], interval: Optional[float] = None):
        self.progress = progress
        self.interval = BEAT_INTERVAL if interval is None else interval
        self.fraction = 0.0
        self.last = time.perf_counter()

    def report(self, fraction: float) -> None:
        """A pass ended at ``fraction`` done: always tell the caller."""
        self.fraction = min(max(fraction, 0.0), 1.0)
        self._call()

    def beat(self) -> None:
        """Between steps: tell the caller (the same fraction) if it has waited long enough."""
        if self.progress is not None and time.perf_counter() - self.last >= self.interval:
            self._call()

    def _call(self) -> None:
        if self.progress is None:
            return
        self.last = time.perf_counter()
        if self.progress(self.fraction) is False:
            raise SimplifyCancelled("simplification cancelled")


def chunks(count: int, size: Optional[int] = None):
    """Slices covering range(count) in order, ``size`` (CHUNK_ROWS) rows each, the last
    one shorter."""
    size = CHUNK_ROWS if size is None else size
    for start in range(0, count, size):
        yield slice(start, min(start + size, count))
