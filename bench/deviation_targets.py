"""Deviation targets on real meshes (issue 22): requested against measured distance.

    .venv/bin/python bench/deviation_targets.py [MESH ...] [--percent 0.05 0.2 1]

For each mesh (default: every mesh of ../shared/meshes) one progressive run snapshots the
ladder of addon/deviation_targets.py, and the bisection picks, per requested deviation
(percent of the bounding-box diagonal), the coarsest rung whose two-sided Hausdorff
distance (addon/measure.py, 500k samples a side) is within it. Prints a markdown table:
requested, measured, their ratio (must be <= 1, and >= 0.5 to count as close), triangles
kept, and the seconds of the run and of the measurements.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)

import core
from addon import deviation_targets
from addon.measure import surface_deviation
from blender_reference import load_mesh
from tables import header, row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="*", type=Path)
    ap.add_argument("--percent", type=float, nargs="+", default=[0.05, 0.2, 1.0])
    args = ap.parse_args(argv)
    meshes = args.meshes or sorted(p for p in _bootstrap.DEFAULT_MESH_DIR.iterdir()
                                   if p.suffix in (".obj", ".gltf", ".glb"))
    print(header("mesh", "requested %", "measured %", "measured / requested", "triangles",
                 "run s", "measure s", "rungs estimated + measured"))
    for path in meshes:
        mesh = load_mesh(path)
        v, f = mesh.vertices, mesh.faces
        rungs = deviation_targets.ladder(len(f))
        t0 = time.perf_counter()
        levels = core.simplify_chain(v, f, rungs)
        run_s = time.perf_counter() - t0
        diagonal = None
        seconds = [0.0]

        def measurer(**samples):
            def measure(i):
                nonlocal diagonal
                t = time.perf_counter()
                report = surface_deviation(v, f, levels[i].vertices, levels[i].faces, **samples)
                seconds[0] += time.perf_counter() - t
                diagonal = report["diagonal"]
                return report["hausdorff"]
            return measure

        search = deviation_targets.Search(measurer(n_samples=deviation_targets.QUICK_SAMPLES), measurer())
        search.hausdorff(0)  # also gives the diagonal
        requested = [p / 100.0 * diagonal for p in args.percent]
        below = -1
        for percent, deviation in zip(args.percent, requested):
            choice = search.coarsest_within(deviation, len(levels), below)
            if choice.level is None:
                print(row(path.name, f"{percent:g}", "-", "-", "none within", f"{run_s:.2f}", "", ""))
                continue
            below = choice.level
            measured = choice.hausdorff / diagonal * 100.0
            print(row(path.name, f"{percent:g}", f"{measured:.4f}", f"{measured / percent:.2f}",
                      f"{len(levels[choice.level].faces):,}", f"{run_s:.2f}", f"{seconds[0]:.1f}",
                      f"{len(search.measured)} + {len(search.confirmed)}"), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
