# SPDX-License-Identifier: GPL-3.0-or-later
"""--jobs N or --scheduler ADDRESS: the inputs as tasks (asset_task.py), each this same
command line on one input in its own Blender process, run on N threads here or on a Dask
cluster (executors.py) by the same rules (task_runner.py).

The child gets the parent's options, one input and its own report, which comes back as
that input's entry; a child that crashes is retried (--retries), one that fails cleanly
is reported once. Progress: a bar with count, rate and time left on a terminal, nothing
but failures in a log.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

from . import executors, task_runner
from .arguments import RUN_OPTIONS, option_argv
from .asset_task import Asset
from .console import Console, duration
from .inputs import InputJob

# The file a child runs as a script (its bootstrap loads the package around it).
ENTRY_SCRIPT = Path(__file__).resolve().parent.parent / "cli.py"


def child_command() -> list:
    """How to start this same command line in a new process."""
    import bpy

    script = str(ENTRY_SCRIPT)
    binary = bpy.app.binary_path
    if binary:  # inside Blender: a background Blender running the entry script
        return [binary, "--background", "--python-exit-code", "1", "--python", script, "--"]
    return [sys.executable, script]  # the bpy module: the same interpreter


def asset_for(job: InputJob, args, base: list) -> Asset:
    """The task of one input: ``base`` (the command and the shared options) plus its input,
    where its outputs go, and --force (the parent's up-to-date check already ran)."""
    argv = list(base)
    argv += ["--sample"] if job.kind == "sample" else ["--input", str(job.path)]
    if args.output is not None:
        argv += ["--output", str(job.outputs[0])]
    elif job.outputs:
        argv += ["--output-dir", str(job.outputs[0].parent), "--format", *(o.suffix[1:] for o in job.outputs)]
    if args.force:
        argv.append("--force")
    if args.debug:  # the child's traceback, not only the parent's "--debug shows details"
        argv.append("--debug")
    return Asset(job.label, str(job.path) if job.path else job.label, argv, echo_stderr=args.debug)


class ProgressBar:
    """One line redrawn in place on a terminal; silent when stderr is a log file."""

    def __init__(self, console: Console, total: int):
        self.console, self.total = console, total
        self.done = self.failed = 0
        self.t0 = time.perf_counter()
        self.live = not console.quiet and sys.stderr.isatty()

    def update(self, entry: dict) -> None:
        self.done += 1
        if not entry["ok"]:
            self.failed += 1
            self.clear()
            self.console.error(f"{entry['label']}: {entry['error']}")
        if self.live:
            elapsed = time.perf_counter() - self.t0
            rate = self.done / elapsed * 60.0 if elapsed > 0 else 0.0
            left = elapsed / self.done * (self.total - self.done)
            failed = f", {self.failed} failed" if self.failed else ""
            self.console.redraw(f"[{self.done}/{self.total}{failed}] {rate:.1f} inputs/min, "
                                f"about {duration(left)} left")

    def clear(self) -> None:
        if self.live:
            self.console.redraw("")


def run_batch(jobs: list, args, parser, console: Console, on_result) -> list:
    """Every job's report entry, in the order given; ``on_result(entry)`` as each ends."""
    base = child_command() + option_argv(parser, args, set(RUN_OPTIONS))
    assets = [asset_for(job, args, base) for job in jobs]
    bar = ProgressBar(console, len(assets))

    def finished(entry):
        bar.update(entry)
        on_result(entry)

    with executors.open_executor(args.jobs, args.scheduler) as (executor, dashboard):
        if dashboard:
            console.progress(f"Dask dashboard: {dashboard}")
        try:
            return task_runner.run(executor, assets, retries=args.retries, on_result=finished)
        finally:
            bar.clear()
