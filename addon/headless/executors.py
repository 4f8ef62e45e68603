# SPDX-License-Identifier: GPL-3.0-or-later
"""Where a batch's tasks run: threads of this process (--jobs N) or a Dask cluster
(--scheduler ADDRESS). Both are a ``concurrent.futures.Executor``, so the batch has one
task function (asset_task.py) and one set of rules (task_runner.py) wherever it runs.

--jobs N is the standard library's ThreadPoolExecutor with N threads, so a stock
Blender (or the ``bpy`` module) runs batches with nothing installed. Threads, not
processes: a task only starts its Blender process and waits, so a thread isolates a
crash as well as a process would, starts at once, and needs no re-import of the main
module (which multiprocessing's spawn would do, inside Blender too). Dask's in-process
LocalCluster did the same with more machinery, and its dashboard was off.

--scheduler ADDRESS is ``distributed.Client(ADDRESS).get_executor()``: the only place
Dask is imported, and only then. Remote workers do not have this package, so each task
function is sent by value (cloudpickle).

Closing the executor after an interruption or an error cancels the tasks not started
yet; local children that are running are stopped (a cluster's workers' children are
theirs to end).
"""
from __future__ import annotations

import concurrent.futures
import contextlib
import functools
import sys

from .asset_task import SCHEDULER_ENV, accept_new_children, stop_running_children

SCHEDULER_NEEDS_DASK = (f"--scheduler (or ${SCHEDULER_ENV}) needs Dask, which this Python does not have: "
                        "pip install 'dask[distributed]' (./lod.sh provisions it); --jobs N needs nothing")
CONNECT_TIMEOUT = "20s"


class SchedulerError(RuntimeError):
    """The cluster named by --scheduler cannot be used; the message says why."""


def dask_available() -> bool:
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


@contextlib.contextmanager
def open_executor(jobs: int, scheduler=None):
    """(executor, dashboard address or None): the Dask cluster of ``scheduler`` if given,
    else ``jobs`` threads here. Raises SchedulerError when the cluster cannot be used."""
    if scheduler:
        with _cluster_executor(scheduler) as opened:
            yield opened
    else:
        with _thread_executor(jobs) as executor:
            yield executor, None


@contextlib.contextmanager
def _thread_executor(jobs: int):
    accept_new_children()  # after an earlier batch of this process was stopped
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=jobs, thread_name_prefix="lqlod-asset")
    try:
        yield pool
    except BaseException:
        # Ctrl-C or an error: queued inputs never start, running Blender processes end,
        # so the threads are free to be joined below.
        pool.shutdown(wait=False, cancel_futures=True)
        stop_running_children()
        raise
    finally:
        pool.shutdown(wait=True)


@contextlib.contextmanager
def _cluster_executor(scheduler: str):
    distributed = _import_dask()
    try:
        client = distributed.Client(scheduler, timeout=CONNECT_TIMEOUT)
    except (OSError, ValueError, TimeoutError) as ex:
        raise SchedulerError(f"cannot reach the Dask scheduler at {scheduler}: {ex}") from None
    try:
        executor = _ByValueExecutor(client.get_executor(pure=False))
        try:
            yield executor, _dashboard(client)
        except BaseException:
            executor.shutdown(wait=False)  # cancels the batch's tasks, one message to the scheduler
            raise
    finally:
        client.close()


def _import_dask():
    try:
        import distributed
    except ImportError:
        raise SchedulerError(SCHEDULER_NEEDS_DASK) from None
    return distributed


def _dashboard(client):
    """The dashboard's address, or None: dashboard_link is a template even when the
    scheduler serves no dashboard."""
    served = "dashboard" in client.scheduler_info().get("services", {})
    return client.dashboard_link if served else None


class _ByValueExecutor(concurrent.futures.Executor):
    """A Dask cluster's executor whose tasks travel by value: Dask pickles a task with
    plain pickle when it can, which names functions by module, and a remote worker does
    not have this package."""

    def __init__(self, executor):
        self.executor = executor

    def submit(self, fn, /, *args, **kwargs):
        import cloudpickle

        cloudpickle.register_pickle_by_value(sys.modules[fn.__module__])
        return self.executor.submit(_ByValue(functools.partial(fn, *args, **kwargs)))

    def shutdown(self, wait=True, *, cancel_futures=False):
        self.executor.shutdown(wait=wait)


class _ByValue:
    """A call that unpickles as itself on any worker: it reduces to cloudpickle's copy
    of the function (its module registered to go by value)."""

    def __init__(self, call: functools.partial):
        self.call = call
        self.__name__ = call.func.__name__  # Dask names the task's key after it

    def __call__(self):
        return self.call()

    def __reduce__(self):
        import cloudpickle

        return cloudpickle.loads, (cloudpickle.dumps(self.call),)
