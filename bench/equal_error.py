"""Triangles at equal error (issue 33 § 3): how many each simplifier needs to stay within
a two-sided Hausdorff distance, ours against Blender's Decimate.

    .venv/bin/python bench/equal_error.py [--percent 0.05 0.2 1] [--parts 3] [--only NAME ...]

Ours: the add-on's own deviation search (``max_deviations``, as the panel's "By
Deviation" and ``--max-error``), which keeps the fewest triangles its report measures
within the bound. Decimate: its ratio on a geometric grid (0.8^k) and then bisected
(``--steps``) for the fewest triangles within the bound, on the welded triangles (Merge by Distance, as bench/run.py
gives it), judged by the independent sampler below. Both LODs are measured by that one
sampler (addon/pure/measure.py, ``--samples`` area samples a side plus the vertices, a seed of
its own): Decimate's is within it by construction, ours (found with the report's own
sampler) is marked where it comes out beyond. Meshes: every mesh of ../shared/meshes, BoomBox and the
``--parts`` largest meshes of the 2CylinderEngine. Prints a markdown table with the
processor; docs/method.md quotes it.
"""
from __future__ import annotations

import argparse
import sys
import time

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import bpy

from addon import lod
from addon.pure.measure import mesh_report
from addon.pure.settings import LodSettings
from blender_reference import decimate, load_mesh, mesh_from_arrays
from messy import ASSETS, gltf_meshes
from run import MESH_SUFFIXES, environment, welded

CHECK_SEED = 7  # the independent sampler's seed (the search measures with seed 0)
GRID_STEPS = 28  # Decimate's ratio grid: 0.8 ** k, down to 0.2 %


def meshes(args) -> list:
    out = []
    for path in sorted(_bootstrap.DEFAULT_MESH_DIR.iterdir()):
        if path.suffix.lower() in MESH_SUFFIXES:
            mesh = load_mesh(path)
            out.append((path.stem, mesh.vertices, mesh.faces))
    boombox = ASSETS / "BoomBox" / "BoomBox.gltf"
    if boombox.exists():
        out.append(("BoomBox", *gltf_meshes(boombox)[0][1:]))
    engine = ASSETS / "2CylinderEngine" / "2CylinderEngine.gltf"
    if engine.exists():
        parts = sorted(gltf_meshes(engine), key=lambda m: -len(m[2]))[:args.parts]
        out += [(f"engine {name}", v, f) for name, v, f in parts]
    if args.only:
        out = [m for m in out if m[0] in args.only]
    return out


def ours(name, V, F, percents) -> dict:
    """{percent: (triangles, V, F)} from the add-on's deviation search, one chain."""
    source = bpy.data.objects.new(name, mesh_from_arrays(name, V, F))
    bpy.context.scene.collection.objects.link(source)
    try:
        settings = LodSettings(max_deviations=tuple((p, True) for p in percents), measure_deviation=True)
        output = lod.compute(lod.prepare(bpy.context.scene, source, settings))
        found = {}
        for report, level in zip(output.reports, output.levels):
            found[round(report["requested_deviation_percent"], 9)] = (len(level.faces), level.vertices, level.faces)
        return found
    finally:
        bpy.data.objects.remove(source)


class DecimateRuns:
    """Blender's Decimate on one mesh's welded triangles, each ratio run and measured
    once (by the independent sampler) for all the bounds."""

    def __init__(self, V, F, samples):
        self.V, self.F, self.samples = V, F, samples
        self.wv, self.wf, _ = welded(V, F)
        self.runs = {}

    def run(self, ratio) -> tuple:
        """(Hausdorff %, the Decimated output) at ``ratio``."""
        if ratio not in self.runs:
            dec = decimate(self.wv, self.wf, ratio)
            h = float("inf") if len(dec.faces) == 0 else mesh_report(
                self.V, self.F, dec.vertices, dec.faces, n_samples=self.samples, seed=CHECK_SEED)["hausdorff_percent"]
            self.runs[ratio] = (h, dec)
        return self.runs[ratio]

    def coarsest_within(self, percent, steps) -> tuple:
        """(triangles, V, F) of the coarsest LOD found within ``percent``: ratios on a
        geometric grid from 1 down (its distance does not always grow as its ratio falls:
        a bisection alone can stop at a spike), then ``steps`` bisections between the
        coarsest grid ratio within and the next one down."""
        grid = [0.8 ** k for k in range(1, GRID_STEPS + 1)]
        ok = [r for r in grid if self.run(r)[0] <= percent]
        hi = min(ok) if ok else 1.0  # the input itself is within
        lower = [r for r in grid if r < hi]
        lo = max(lower) if lower else 0.0
        for _ in range(steps):
            mid = 0.5 * (lo + hi)
            if self.run(mid)[0] <= percent:
                hi = mid
            else:
                lo = mid
        if hi == 1.0:
            return len(self.F), self.V, self.F
        dec = self.run(hi)[1]
        return len(dec.faces), dec.vertices, dec.faces


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--percent", type=float, nargs="+", default=[0.05, 0.2, 1.0])
    ap.add_argument("--parts", type=int, default=3)
    ap.add_argument("--steps", type=int, default=6, help="Decimate ratio bisection steps after the grid")
    ap.add_argument("--samples", type=int, default=200_000)
    ap.add_argument("--only", nargs="+", metavar="NAME")
    args = ap.parse_args(argv)
    env = environment()
    lines = ["| mesh | triangles | bound % | ours | Decimate | ours / Decimate | ours measured % | Decimate measured % "
             "| ours slivers % | Decimate slivers % | search s |", "|" + "---|" * 11]
    for name, V, F in meshes(args):
        print(name, file=sys.stderr, flush=True)
        t0 = time.perf_counter()
        found = ours(name, V, F, args.percent)
        seconds = time.perf_counter() - t0
        decimate_runs = DecimateRuns(V, F, args.samples)
        for percent in args.percent:
            dec = decimate_runs.coarsest_within(percent, args.steps)
            ours_lod = found.get(round(percent, 9))
            d_rep = mesh_report(V, F, dec[1], dec[2], n_samples=args.samples, seed=CHECK_SEED)
            if ours_lod is None:
                lines.append(f"| {name} | {len(F):,} | {percent:g} | none within | {dec[0]:,} | | | "
                             f"{d_rep['hausdorff_percent']:.4f} | | {d_rep['sliver_percent']:.1f} | {seconds:.1f} |")
                continue
            o_rep = mesh_report(V, F, ours_lod[1], ours_lod[2], n_samples=args.samples, seed=CHECK_SEED)
            mark = lambda h: f"{h:.4f}" + (" (beyond)" if h > percent else "")  # noqa: E731
            lines.append(f"| {name} | {len(F):,} | {percent:g} | {ours_lod[0]:,} | {dec[0]:,} | "
                         f"**{ours_lod[0] / max(dec[0], 1):.2f}x** | {mark(o_rep['hausdorff_percent'])} | "
                         f"{mark(d_rep['hausdorff_percent'])} | {o_rep['sliver_percent']:.1f} | "
                         f"{d_rep['sliver_percent']:.1f} | {seconds:.1f} |")
            print(lines[-1], file=sys.stderr, flush=True)
    print(f"{env['cpu']}, {env['cpu_count']} cores; Blender {env['blender']}, NumPy {env['numpy']}; "
          f"commit {env['commit']}\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
