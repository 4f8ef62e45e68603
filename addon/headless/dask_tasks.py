# SPDX-License-Identifier: GPL-3.0-or-later
"""Many input files on Dask: one asset, one task, each task one Blender process.

Why a process per asset: bpy holds one scene per process and is not thread-safe, and an
importer can crash (a crafted PLY header aborts Blender) or run out of memory. The Dask
worker only starts the child and waits, so a crash fails that asset alone; the task then
raises, and Dask runs it again (``retries``) on whichever worker is free. An asset the
child rejects cleanly (unreadable file, no mesh, a missing group) comes back as a report
entry with ``ok`` False and is not retried: running it again would say the same.

One code path for one machine and many: ``jobs=N`` starts an in-process LocalCluster
running N tasks at a time, ``scheduler="tcp://host:8786"`` submits the same
tasks to a running cluster (workers started with ``dask worker``). Remote workers need
the same paths as this machine (shared storage for inputs, outputs and the checkout or
Blender binary in the child command); they need no copy of this package, because the
task functions travel by value.

No bpy here, and Dask is imported only when a batch runs, so the extension inside
Blender never needs it.
"""
from __future__ import annotations

import functools
import json
import logging
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from typing import Callable, Optional

DASK_MISSING = ("batch work on several processes or a cluster needs Dask: "
                "pip install 'dask[distributed]' (./lod.sh provisions it), or use --jobs 1")
SCHEDULER_ENV = "LQLOD_SCHEDULER"  # the cluster to use when --scheduler is not given
USAGE_STATUS = 2  # the command line's exit status for input it refuses (cli.EXIT_USAGE)
STDERR_LINES_KEPT = 20


@dataclass
class Asset:
    """One input file's task: the child command that makes its LODs (without --report)."""

    label: str
    input: str
    command: list


class SchedulerError(RuntimeError):
    """The cluster named by --scheduler cannot be used; the message says why."""


class AssetCrashed(RuntimeError):
    """The child process ended without a report: a crash, a kill or out of memory."""


# The children running in this process's worker threads, so that a cancelled or
# interrupted local batch stops them instead of leaving Blender running on its own.
_running: set = set()
_running_lock = threading.Lock()
_stopping = {"now": False}  # set by stop_running_children: no new child starts after it


def _children_registry() -> tuple:
    # Looked up through sys.modules, not as globals: run_asset travels by value to remote
    # workers, where a lock cannot go (nor is there anything to stop from here).
    module = sys.modules.get(__name__)
    if module is None or not hasattr(module, "_running"):
        return set(), threading.Lock(), {"now": False}
    return module._running, module._running_lock, module._stopping


def run_asset(asset: Asset) -> dict:
    """Run one asset's child process (on a worker); its report entry, or AssetCrashed."""
    fd, report = tempfile.mkstemp(prefix="lqlod-asset-", suffix=".json")
    os.close(fd)
    os.unlink(report)  # the child writes it atomically; no file means no report
    try:
        # Without the scheduler variable: the child runs its one input itself instead of
        # submitting it to the cluster again.
        env = {key: value for key, value in os.environ.items() if key != SCHEDULER_ENV}
        running, lock, stopping = _children_registry()
        with lock:  # started and registered at once, so a stop cannot miss it
            if stopping["now"]:
                raise AssetCrashed("the batch was stopped before this input started")
            proc = subprocess.Popen(
                asset.command + ["--report", report], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.PIPE, text=True, errors="replace", env=env)
            running.add(proc)
        try:
            _, stderr = proc.communicate()
        finally:
            with lock:
                running.discard(proc)
        lines = stderr.splitlines()[-STDERR_LINES_KEPT:]
        try:
            with open(report, encoding="utf-8") as fh:
                entry = json.load(fh)["files"][0]
        except (OSError, ValueError, KeyError, IndexError):
            if proc.returncode == USAGE_STATUS:  # the command line refused the input: no retry
                return {"input": asset.input, "label": asset.label, "ok": False,
                        "error": _crash_reason(proc.returncode, lines), "outputs": [], "objects": [],
                        "warnings": [], "seconds": 0.0}
            raise AssetCrashed(_crash_reason(proc.returncode, lines)) from None
        entry["label"] = asset.label
        return entry
    finally:
        if os.path.exists(report):
            os.unlink(report)


def stop_running_children(timeout: float = 10.0) -> None:
    """Terminate the children this process started (then kill those that linger)."""
    with _running_lock:
        _stopping["now"] = True
        procs = list(_running)
    for proc in procs:
        if proc.poll() is None:
            proc.terminate()
    for proc in procs:
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def _crash_reason(code: int, lines: list) -> str:
    errors = [line[len("error: "):] for line in lines if line.startswith("error: ")]
    if errors:
        return errors[-1]
    if code < 0:
        try:
            how = f"was killed by {signal.Signals(-code).name}"
        except ValueError:
            how = f"was killed by signal {-code}"
    else:
        how = f"exited with status {code}"
    last = next((line for line in reversed(lines) if line.strip()), "")
    return f"the Blender process {how}" + (f": {last.strip()}" if last else "")


def failed_entry(asset: Asset, reason: str) -> dict:
    """A report entry for an asset that never produced one (same keys as the child's)."""
    return {"input": asset.input, "label": asset.label, "ok": False, "error": reason,
            "outputs": [], "objects": [], "warnings": [], "seconds": 0.0}


def dask_available() -> bool:
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


class _ByValue:
    """A task function that unpickles as itself on any worker: Dask pickles a task graph
    with plain pickle when it can, which names functions by module, and a remote worker
    does not have this package; this reduces to cloudpickle's copy of the function."""

    def __init__(self, function):
        self.function = function

    def __call__(self):
        return self.function()

    def __reduce__(self):
        import cloudpickle

        return cloudpickle.loads, (cloudpickle.dumps(self.function),)


def _dask():
    try:
        import distributed
    except ImportError:
        raise RuntimeError(DASK_MISSING) from None
    import cloudpickle

    # Remote workers do not have this package: the task functions travel by value.
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    return distributed


def open_client(jobs: int, scheduler: Optional[str]):
    """(client, cluster or None, dashboard address or None) for ``scheduler`` if given,
    else an in-process LocalCluster running ``jobs`` tasks at a time."""
    distributed = _dask()
    # A failed task is reported once, in the batch's own words; an in-process worker
    # would also log each attempt with a traceback.
    logging.getLogger("distributed.worker").setLevel(logging.CRITICAL)
    if scheduler:
        try:
            client = distributed.Client(scheduler, timeout="20s")
        except (OSError, ValueError, TimeoutError) as ex:
            raise SchedulerError(f"cannot reach the Dask scheduler at {scheduler}: {ex}") from None
        # dashboard_link is a template even when the scheduler serves no dashboard.
        try:
            served = "dashboard" in client.scheduler_info().get("services", {})
        except BaseException:
            client.close()
            raise
        return client, None, client.dashboard_link if served else None
    # Worker threads, not processes: a task only starts its Blender process and waits,
    # so threads isolate crashes just as well, start at once, and need no re-import of
    # the main module (which multiprocessing's spawn would do, inside Blender too).
    cluster = distributed.LocalCluster(
        n_workers=1, threads_per_worker=jobs, processes=False, dashboard_address=None,
        silence_logs=logging.ERROR)
    try:
        return distributed.Client(cluster), cluster, None
    except BaseException:
        cluster.close()
        raise


def close_client(client, cluster) -> None:
    """Close what open_client opened; a local cluster's running children are stopped."""
    if cluster is not None:
        stop_running_children()  # the local workers' children live in this process
    client.close()
    if cluster is not None:
        cluster.close()


def run(assets: list, *, jobs: int = 1, scheduler: Optional[str] = None, retries: int = 2,
        on_result: Optional[Callable[[dict], object]] = None) -> list:
    """Every asset's report entry, in the order given. ``on_result(entry)`` is called as each
    finishes (in finishing order), for streaming reports and progress."""
    client, cluster, _ = open_client(jobs, scheduler)
    try:
        return run_on(client, assets, retries=retries, on_result=on_result)
    finally:
        close_client(client, cluster)


def run_on(client, assets: list, *, retries: int = 2,
           on_result: Optional[Callable[[dict], object]] = None) -> list:
    distributed = _dask()
    with _running_lock:
        _stopping["now"] = False  # a new batch in this process
    stamp = f"{time.time_ns():x}"
    futures = [client.submit(_ByValue(functools.partial(run_asset, asset)), key=f"lod-{stamp}-{i}",
                             retries=retries, pure=False)
               for i, asset in enumerate(assets)]
    index = {future.key: i for i, future in enumerate(futures)}
    entries = [None] * len(assets)
    try:
        for future in distributed.as_completed(futures):
            i = index[future.key]
            if future.status == "finished":
                entry = future.result()
            else:
                error = future.exception()
                reason = str(error) or type(error).__name__
                if type(error).__name__ == "KilledWorker":
                    reason = "the worker running it died repeatedly"
                tries = f" ({retries + 1} attempts)" if retries else ""
                entry = failed_entry(assets[i], reason + tries)
            entries[i] = entry
            if on_result is not None:
                on_result(entry)
    finally:
        pending = [future for future in futures if not future.done()]
        if pending:
            client.cancel(pending)  # one message to the scheduler, not one per future
    return entries
