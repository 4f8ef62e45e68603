# SPDX-License-Identifier: GPL-3.0-or-later
"""One input's task: the command line on that one input, in a Blender process of its own.

Why a process per asset: bpy holds one scene per process and is not thread-safe, and an
importer can crash (a crafted PLY header aborts Blender) or run out of memory. The task
only starts the child and waits, so a crash fails that asset alone: the task raises
AssetCrashed and the runner (task_runner.py) may run it again. An asset the child
rejects cleanly (unreadable file, no mesh, a missing group) comes back as a report entry
with ``ok`` False and is not retried: running it again would say the same.

The same function runs in a thread of this process (--jobs N, executors.py) and on a
Dask worker of a cluster (--scheduler), which gets it by value (cloudpickle): so this
module imports nothing of ours, no Dask and no bpy, only the standard library.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
from dataclasses import dataclass

SCHEDULER_ENV = "LQLOD_SCHEDULER"  # the cluster to use when --scheduler is not given
USAGE_STATUS = 2  # the command line's exit status for input it refuses (cli.EXIT_USAGE)
STDERR_LINES_KEPT = 20


@dataclass
class Asset:
    """One input file's task: the child command that makes its LODs (without --report)."""

    label: str
    input: str
    command: list
    # --debug: the child's stderr (tracebacks, the importers' own output) is passed on
    # whole when it ends, instead of only its last error line being kept.
    echo_stderr: bool = False


class AssetCrashed(RuntimeError):
    """The child process ended without a report: a crash, a kill or out of memory."""


# The children running in this process's threads, so that a cancelled or interrupted
# local batch stops them instead of leaving Blender running on its own.
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
    """Run one asset's child process; its report entry, or AssetCrashed."""
    fd, report = tempfile.mkstemp(prefix="lqlod-asset-", suffix=".json")
    os.close(fd)
    os.unlink(report)  # the child writes it atomically; no file means no report
    try:
        code, lines = _run_child(asset.command + ["--report", report], asset.echo_stderr)
        try:
            with open(report, encoding="utf-8") as fh:
                entry = json.load(fh)["files"][0]
        except (OSError, ValueError, KeyError, IndexError):
            if code == USAGE_STATUS:  # the command line refused the input: no retry
                return failed_entry(asset, _crash_reason(code, lines))
            raise AssetCrashed(_crash_reason(code, lines)) from None
        entry["label"] = asset.label
        return entry
    finally:
        if os.path.exists(report):
            os.unlink(report)


def _run_child(command: list, echo_stderr: bool) -> tuple:
    """(exit status, the last lines of stderr) of ``command``, registered while it runs so
    that stop_running_children can end it."""
    # Without the scheduler variable: the child runs its one input itself instead of
    # submitting it to the cluster again.
    env = {key: value for key, value in os.environ.items() if key != SCHEDULER_ENV}
    running, lock, stopping = _children_registry()
    with lock:  # started and registered at once, so a stop cannot miss it
        if stopping["now"]:
            raise AssetCrashed("the batch was stopped before this input started")
        proc = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, text=True, errors="replace", env=env)
        running.add(proc)
    try:
        _, stderr = proc.communicate()
    finally:
        with lock:
            running.discard(proc)
    if echo_stderr and stderr:
        sys.stderr.write(stderr if stderr.endswith("\n") else stderr + "\n")  # one write: children do not interleave
        sys.stderr.flush()
    return proc.returncode, stderr.splitlines()[-STDERR_LINES_KEPT:]


def accept_new_children() -> None:
    """A new batch in this process: children may start again after an earlier stop."""
    with _running_lock:
        _stopping["now"] = False


def stop_running_children(timeout: float = 10.0) -> None:
    """Terminate the children this process started (then kill those that linger); no
    child starts after this until accept_new_children."""
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
