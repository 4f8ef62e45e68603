"""Speed and convergence of addon/pure/measure.py's surface_deviation at several sample counts.

    .venv/bin/python bench/measure_speed.py [--mesh PATH] [--ratio 0.1] [--samples 200000 500000 1000000]

Measures the input mesh against Blender's Decimate output at ``ratio`` (default: ogre.obj,
124k faces, at 10 %): seconds per direction, Hausdorff and mean distance for each count of
area-uniform samples per surface. Prints a markdown table; bench/README.md quotes it.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import tables

from addon.pure.measure import surface_deviation
from blender_reference import decimate, load_mesh


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mesh", type=Path, default=_bootstrap.DEFAULT_MESH_DIR / "ogre.obj")
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--samples", type=int, nargs="+", default=[200_000, 500_000, 1_000_000])
    args = ap.parse_args(argv)
    mesh = load_mesh(args.mesh)
    out = decimate(mesh.vertices, mesh.faces, args.ratio)
    load = os.getloadavg()[0]
    print(f"{mesh.name} ({len(mesh.faces):,} faces) vs Blender Decimate {args.ratio:g} "
          f"({len(out.faces):,} faces); load average {load:.2f} on {os.cpu_count()} cores")
    print()
    print(tables.header(
        "samples per surface", "query points in -> out", "s, in -> out", "s, out -> in", "Hausdorff %", "mean %"))
    for n in args.samples:
        r = surface_deviation(mesh.vertices, mesh.faces, out.vertices, out.faces, n_samples=n)
        print(tables.row(f"{n:,}", f"{r['points_src']:,}", f"{r['seconds_src_to_dst']:.2f}",
                         f"{r['seconds_dst_to_src']:.2f}", f"{r['hausdorff_percent']:.4f}", f"{r['mean_percent']:.5f}"),
              flush=True)
    print()
    print(f"load average at the end: {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
