# SPDX-License-Identifier: GPL-3.0-or-later
"""A batch's assets on an executor (executors.py), one task each (asset_task.run_asset),
by the same rules on threads here and on a Dask cluster:

* a task that raises (its Blender process crashed or was killed, on a cluster also a
  lost worker) is submitted again, up to ``retries`` more times, to whichever thread or
  worker is free; after the last attempt its entry says why and how many attempts;
* an asset the child rejects cleanly is an entry with ``ok`` False, not an exception,
  so it is never retried;
* ``on_result(entry)`` as each asset ends, in finishing order (streamed reports, progress);
* the entries come back in the order the assets were given.

An interruption (Ctrl-C) leaves :func:`run` as the exception it is; closing the
executor (executors.open_executor) then cancels what has not started and stops the
running children. No Dask here.
"""
from __future__ import annotations

import concurrent.futures
import queue
from typing import Callable, Optional

from .asset_task import failed_entry, run_asset


def run(executor: concurrent.futures.Executor, assets: list, *, retries: int = 2,
        on_result: Optional[Callable[[dict], object]] = None) -> list:
    """Every asset's report entry, in the order given."""
    finished = queue.Queue()  # futures as they end: one wait per asset, not one per pending one
    pending = {}
    attempts = [0] * len(assets)

    def submit(i: int) -> None:
        future = executor.submit(run_asset, assets[i])
        pending[future] = i
        future.add_done_callback(finished.put)

    for i in range(len(assets)):
        submit(i)
    entries = [None] * len(assets)
    while pending:
        future = _next(finished)
        i = pending.pop(future)
        attempts[i] += 1
        error = _failure(future)
        if error is not None and attempts[i] <= retries and not future.cancelled():
            submit(i)
            continue
        entries[i] = future.result() if error is None else failed_entry(assets[i], _reason(error, attempts[i]))
        if on_result is not None:
            on_result(entries[i])
    return entries


# How often the wait for the next finished task wakes (seconds), only to let a Ctrl-C in.
WAKE_SECONDS = 0.25


def _next(finished: queue.Queue) -> concurrent.futures.Future:
    """The next future to end. The wait wakes every WAKE_SECONDS: the kernel may deliver
    Ctrl-C's SIGINT to any of the process's threads, and Python raises it in the main
    thread only when that thread next runs. A wait with no timeout then lasted until a
    running child ended (tests/test_batch.py sends the signal to another thread)."""
    while True:
        try:
            return finished.get(timeout=WAKE_SECONDS)
        except queue.Empty:
            pass


def _failure(future: concurrent.futures.Future) -> Optional[BaseException]:
    if future.cancelled():
        return concurrent.futures.CancelledError("the task was cancelled")
    return future.exception()


def _reason(error: BaseException, attempts: int) -> str:
    """One line for a task that never returned an entry, with its number of attempts."""
    reason = str(error) or type(error).__name__
    if type(error).__name__ == "KilledWorker":  # Dask: the workers running it kept dying
        reason = "the worker running it died repeatedly"
    return reason + (f" ({attempts} attempts)" if attempts > 1 else "")
