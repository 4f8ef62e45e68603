"""Peak memory of one core.simplify run, measured in a process of its own.

Usage: python bench/core_memory.py MESH.npz RATIO [LINE_WEIGHT]
(MESH.npz holds arrays ``vertices`` (n, 3) and ``faces`` (m, 3)). Prints one JSON line:
  peak_rss_mb        the process's peak resident set size (VmHWM in /proc/self/status):
                     interpreter + NumPy + the input arrays + everything core.simplify
                     allocates. This is what a user's machine must hold, so it is the number
                     the bench compares with its budget.
  before_rss_mb      the same high-water mark just before simplify (interpreter, NumPy
                     and the loaded input), so peak - before is simplify's own share.
  seconds            simplify's wall time here (informational: the bench times core in
                     the same process as Blender).
  source             "VmHWM", or "ru_maxrss" where /proc is missing.
The process never imports bpy, so Blender's own memory is not counted. Why VmHWM and not
getrusage's ru_maxrss: on Linux ru_maxrss survives exec, so a child started from the
bench (which holds Blender and the big mesh) would report the parent's peak instead of
its own; VmHWM belongs to the process's own address space, which exec creates afresh.
"""
from __future__ import annotations

import json
import resource
import sys
import time

import _bootstrap  # noqa: F401  (repository root on sys.path)
import numpy as np


def _peak_rss_mb() -> tuple:
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0, "VmHWM"  # kB
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, "ru_maxrss"


def main(argv) -> None:
    if len(argv) not in (2, 3):
        raise SystemExit(__doc__)
    import core

    data = np.load(argv[0])
    vertices, faces = data["vertices"], data["faces"]
    ratio = float(argv[1])
    line_weight = float(argv[2]) if len(argv) > 2 else core.DEFAULT_LINE_WEIGHT
    before, _ = _peak_rss_mb()
    t0 = time.perf_counter()
    res = core.simplify(vertices, faces, ratio=ratio, line_weight=line_weight)
    seconds = time.perf_counter() - t0
    peak, source = _peak_rss_mb()
    print(json.dumps({
        "peak_rss_mb": peak,
        "before_rss_mb": before,
        "source": source,
        "seconds": seconds,
        "input_faces": int(len(faces)),
        "output_faces": int(len(res.faces)),
    }))


if __name__ == "__main__":
    main(sys.argv[1:])
