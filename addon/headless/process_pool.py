# SPDX-License-Identifier: GPL-3.0-or-later
"""--jobs N: each input in its own Blender process, N at a time.

bpy holds one scene per process, so inputs run side by side only in separate
processes. Each child is this same command line on one input with the parent's options
and a report of its own, which the parent reads back as that input's entry.
"""
from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from .arguments import option_argv
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


def run_parallel(jobs: list, args, parser, console: Console) -> list:
    """Each input in its own process (the same command on one input), ``args.jobs`` at a time."""
    base = child_command() + option_argv(
        parser, args, {"input", "sample", "output", "output_dir", "format", "report", "jobs"})
    files = [None] * len(jobs)
    pending = list(enumerate(jobs))
    running = {}
    tmp = Path(tempfile.mkdtemp(prefix="lqlod-jobs-"))
    t0 = time.perf_counter()
    finished = 0
    try:
        while pending or running:
            while pending and len(running) < args.jobs:
                i, job = pending.pop(0)
                report = tmp / f"{i}.json"
                argv = base + ["--input", str(job.path), "--report", str(report)]
                if job.outputs:
                    out_dir = job.outputs[0].parent
                    argv += ["--output-dir", str(out_dir), "--format", *(o.suffix[1:] for o in job.outputs)]
                proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                        stderr=subprocess.PIPE, text=True, errors="replace")
                lines = []
                pump = threading.Thread(target=_pump, args=(proc.stderr, lines, console), daemon=True)
                pump.start()
                running[i] = (job, proc, pump, lines, report)
            time.sleep(0.05)
            for i in [i for i, r in running.items() if r[1].poll() is not None]:
                job, proc, pump, lines, report = running.pop(i)
                pump.join()
                files[i] = _child_entry(job, proc.returncode, lines, report)
                finished += 1
                if not files[i]["ok"]:
                    console.error(f"{job.label}: {files[i]['error']}")
                elapsed = time.perf_counter() - t0
                left = len(jobs) - finished
                estimate = elapsed / finished * left / min(args.jobs, max(left, 1)) if left else 0.0
                console.progress(f"[{job.label}] {'done' if files[i]['ok'] else 'failed'} "
                                 f"({finished} of {len(jobs)} inputs, about {duration(estimate)} left)")
    finally:
        for job, proc, *_ in running.values():
            if proc.poll() is None:
                proc.terminate()
        for job, proc, *_ in running.values():
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
        shutil.rmtree(tmp, ignore_errors=True)
    return files


def _pump(stream, lines: list, console: Console) -> None:
    # A child's progress goes straight through; its error lines are kept for the
    # summary (the parent prints each failure once).
    for raw in stream:
        line = raw.rstrip("\n")
        lines.append(line)
        if line and not line.startswith("error:"):
            console.progress(line)


def _child_entry(job: InputJob, code: int, lines: list, report: Path) -> dict:
    try:
        data = json.loads(report.read_text(encoding="utf-8"))
        entry = data["files"][0]
        entry["label"] = job.label
        return entry
    except (OSError, ValueError, KeyError, IndexError):
        pass
    errors = [line[len("error: "):] for line in lines if line.startswith("error:")]
    reason = errors[-1] if errors else (
        f"the process exited with status {code}" + (f": {lines[-1]}" if lines else ""))
    return {"input": str(job.path), "label": job.label, "ok": False, "error": reason,
            "outputs": [], "objects": [], "warnings": [], "seconds": 0.0}
