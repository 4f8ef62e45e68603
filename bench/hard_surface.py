"""The shape-versus-fidelity table (issue 18): one mesh, several settings, beside Decimate.

    .venv/bin/python bench/hard_surface.py [MESH] [--ratio 0.1] [--samples 200000]

MESH defaults to fandisk.obj in ../shared/meshes. Every row is core.simplify with the
given settings at the ratio, measured like bench/run.py (Hausdorff and mean distance in %
of the bounding diagonal, both directions; mean quality; slivers, quality below 0.3),
after Blender's Decimate on the same (welded) triangles in the same process. Prints a
markdown table; docs/troubleshooting.md quotes it.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import tables

import core
from addon.pure.measure import mesh_report
from blender_reference import decimate, load_mesh
from run import welded

SETTINGS = (
    {},
    {"feature_angle": 0},
    {"min_quality": 0.0},
    {"line_weight": 0.0},
    {"line_weight": 0.0, "feature_angle": 0},
    {"line_weight": 0.0, "min_quality": 0.0},
)


def row(label, report, decimate_report=None, seconds=None) -> str:
    if decimate_report is not None:
        ratios = (f"{report['hausdorff_percent'] / decimate_report['hausdorff_percent']:.2f}x",
                  f"{report['mean_percent'] / decimate_report['mean_percent']:.2f}x")
    else:
        ratios = (1, 1)
    return tables.row(label, f"{report['hausdorff_percent']:.4f}", f"{report['mean_percent']:.5f}", *ratios,
                      f"{report['mean_quality']:.3f}", f"{report['sliver_percent']:.2f}", f"{seconds:.3f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh", nargs="?", type=Path, default=_bootstrap.DEFAULT_MESH_DIR / "fandisk.obj")
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--samples", type=int, default=200_000)
    ap.add_argument("--settings", type=json.loads, default=None,
                    help="a JSON list of core.simplify option dicts (default: the docs' table)")
    args = ap.parse_args(argv)
    mesh = load_mesh(args.mesh)
    v, f = mesh.vertices, mesh.faces
    wv, wf, _ = welded(v, f)
    dec = decimate(wv, wf, args.ratio)
    base = mesh_report(v, f, dec.vertices, dec.faces, n_samples=args.samples)
    print(f"{args.mesh.name} at {args.ratio:g} ({len(dec.faces):,} of {len(f):,} triangles)\n")
    print(tables.header(
        "settings", "Hausdorff %", "mean %", "Hausdorff / Decimate", "mean / Decimate", "mean quality", "slivers %",
        "seconds"))
    print(row("Blender's Decimate", base, seconds=dec.seconds))
    for options in args.settings or SETTINGS:
        t0 = time.perf_counter()
        r = core.simplify(v, f, ratio=args.ratio, **options)
        seconds = time.perf_counter() - t0
        rep = mesh_report(v, f, r.vertices, r.faces, n_samples=args.samples)
        label = ", ".join(f"{k} {val:g}" for k, val in options.items()) or "defaults"
        print(row(label, rep, base, seconds), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
