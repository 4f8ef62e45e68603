"""Batch throughput of the command line (issue 21): inputs per minute with --jobs 1 and 2.

    .venv/bin/python bench/batch_throughput.py [--small 12] [--large 4] [--jobs 1 2]

Writes two libraries of OBJ spheres into a temporary folder, small assets (about 5k
triangles, the bulk of a game's library) and large ones (about 180k), and runs
``python <checkout> --input LIB --output-dir OUT --format glb --force`` on each with every
--jobs value, the deviation measured as by default. --jobs 1 runs in one Blender process;
--jobs 2 runs a Blender process per input (two at a time, from threads of the parent), so
each input pays a process start.
Prints a markdown table (docs/headless.md quotes it). Run it alone: the machine's cores
are what it measures.
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs)
from synthetic_meshes import uv_sphere
from tables import header, row


def write_obj(path: Path, vertices, faces) -> None:
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")


def library(folder: Path, count: int, rings: int) -> int:
    folder.mkdir(parents=True)
    vertices, faces = uv_sphere(rings)
    for i in range(count):
        # Distinct content per file (a scale), so nothing is shared or skipped.
        write_obj(folder / f"asset_{i:03d}.obj", vertices * (1.0 + 0.01 * i), faces)
    return len(faces)


def run(folder: Path, out: Path, jobs: int) -> float:
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, str(_bootstrap.REPO_ROOT), "--input", str(folder), "--output-dir",
                           str(out), "--format", "glb", "--force", "--quiet", "--jobs", str(jobs)],
                          capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"--jobs {jobs} on {folder.name} failed:\n{proc.stderr[-2000:]}")
    return seconds


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", type=int, default=12, help="small assets (default 12)")
    ap.add_argument("--large", type=int, default=4, help="large assets (default 4)")
    ap.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="lqlod-throughput-") as tmp:
        root = Path(tmp)
        sizes = {"small": (args.small, 50), "large": (args.large, 300)}
        print(header("assets", "triangles each", "--jobs", "seconds", "inputs per minute"))
        for kind, (count, rings) in sizes.items():
            if not count:
                continue
            triangles = library(root / kind, count, rings)
            for jobs in args.jobs:
                seconds = run(root / kind, root / f"out_{kind}_{jobs}", jobs)
                print(row(f"{count} {kind}", f"{triangles:,}", jobs, f"{seconds:.1f}",
                          f"{count / seconds * 60.0:.0f}"), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
