"""Collapse order on the skinned-arm test's tube, at rest: the engine as it is, the engine
with unlimited later selection rounds (as before the limit), and the one-at-a-time
greedy order (bench/sequential.py, per-area cost). docs/method.md quotes it.

    .venv/bin/python bench/arm_order.py [--ratios 0.03 0.1] [--samples 200000]

Prints faces, Hausdorff and mean distance (% of the bounding-box diagonal) per ratio.
"""
from __future__ import annotations

import argparse

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import tables
import bpy  # noqa: F401  (brings mathutils, which the distance measure uses)

from addon.pure.measure import surface_deviation
from core import engine, simplify
from synthetic_meshes import arm_tube
from sequential import simplify_sequential


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.03, 0.1])
    ap.add_argument("--samples", type=int, default=200_000)
    args = ap.parse_args(argv)
    V, F = arm_tube()
    limited = engine.LATER_ROUND_SHARE
    print(f"arm tube: {len(F)} triangles")
    print(tables.header("ratio", "order", "faces", "Hausdorff %", "mean %"))
    for ratio in args.ratios:
        target = int(round(ratio * len(F)))
        outputs = {}
        for label, share in ((f"engine (later rounds {limited:g} of the share)", limited),
                             ("engine, later rounds unlimited", 1.0)):
            engine.LATER_ROUND_SHARE = share
            try:
                r = simplify(V, F, target_faces=target)
            finally:
                engine.LATER_ROUND_SHARE = limited
            outputs[label] = (r.vertices, r.faces)
        sV, sF, _ = simplify_sequential(V, F, target_faces=target, cost="per_area")
        outputs["one at a time (per-area cost)"] = (sV, sF)
        for label, (v, f) in outputs.items():
            d = surface_deviation(V, F, v, f, n_samples=args.samples)
            print(tables.row(f"{ratio:g}", label, len(f), f"{d['hausdorff_percent']:.4f}", f"{d['mean_percent']:.5f}"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
