"""How close the report's deviation comes to the exact one (addon/pure/measure.py): the
report's sampler against uniform samples without the climb, both judged by a million.

    .venv/bin/python bench/measure_accuracy.py [--ratios 0.5 0.25 0.1] [--reference 1000000]

Every mesh of ../shared/meshes, BoomBox and the three largest meshes of the
2CylinderEngine, each simplified by the core at each ratio, then measured three ways:
  * reference  ``--reference`` area samples a side, a seed of its own, no climb;
  * uniform    50,000 a side, no climb (the report before the climb);
  * report     as the report measures (deviation_search.deviation_report's counts:
               report_samples, the source's side SOURCE_SHARE of it, every vertex and the
               climb towards the largest distance, measure._climb).
Prints, per mesh and ratio, each way's Hausdorff and mean distance over the reference's,
then their mean, least and largest ratio and the seconds each way took in all, with the
processor. A ratio under 1 is a distance the sampler missed.
"""
from __future__ import annotations

import argparse
import time

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import bpy  # noqa: F401  (the closest-point tree)
import numpy as np

import core
from addon.pure import deviation_search, measure
from assets import processor
from blender_reference import load_mesh
from messy import ASSETS, gltf_meshes
from run import MESH_SUFFIXES
from tables import header, row

UNIFORM = 50_000
REFERENCE_SEED = 11


def meshes() -> list:
    out = [(p.stem, *(lambda m: (m.vertices, m.faces))(load_mesh(p)))
           for p in sorted(_bootstrap.DEFAULT_MESH_DIR.iterdir()) if p.suffix.lower() in MESH_SUFFIXES]
    boombox = ASSETS / "BoomBox" / "BoomBox.gltf"
    if boombox.exists():
        out.append(("BoomBox", *gltf_meshes(boombox)[0][1:]))
    engine = ASSETS / "2CylinderEngine" / "2CylinderEngine.gltf"
    if engine.exists():
        out += [(f"engine {name}", v, f) for name, v, f in sorted(gltf_meshes(engine), key=lambda m: -len(m[2]))[:3]]
    return out


def without_climb(*args, **kwargs) -> dict:
    seeds = measure.CLIMB_SEEDS
    measure.CLIMB_SEEDS = 0
    try:
        return measure.surface_deviation(*args, **kwargs)
    finally:
        measure.CLIMB_SEEDS = seeds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ratios", nargs="+", type=float, default=[0.5, 0.25, 0.1])
    parser.add_argument("--reference", type=int, default=1_000_000)
    args = parser.parse_args()
    print(f"Processor: {processor()}; reference {args.reference:,} samples a side; "
          f"each cell: the way's distance over the reference's\n")
    print(header("mesh", "triangles", "ratio", "uniform Hausdorff", "report Hausdorff", "uniform mean", "report mean"))
    ratios = {"uniform": ([], []), "report": ([], [])}
    seconds = {"uniform": 0.0, "report": 0.0}
    for name, v, f in meshes():
        for ratio in args.ratios:
            lod = core.simplify(v, f, ratio=ratio)
            reference = without_climb(v, f, lod.vertices, lod.faces, n_samples=args.reference, seed=REFERENCE_SEED)
            t0 = time.perf_counter()
            uniform = without_climb(v, f, lod.vertices, lod.faces, n_samples=UNIFORM)
            t1 = time.perf_counter()
            report = measure.surface_deviation(
                v, f, lod.vertices, lod.faces,
                n_samples=(int(deviation_search.SOURCE_SHARE * deviation_search.report_samples(len(f))),
                           deviation_search.report_samples(len(lod.faces))))
            t2 = time.perf_counter()
            seconds["uniform"] += t1 - t0
            seconds["report"] += t2 - t1
            cells = []
            for way, d in (("uniform", uniform), ("report", report)):
                ratios[way][0].append(d["hausdorff"] / reference["hausdorff"])
                ratios[way][1].append(d["mean"] / reference["mean"])
            print(row(name, f"{len(f):,}", f"{ratio:g}", *(f"{ratios[w][0][-1]:.3f}" for w in ratios),
                      *(f"{ratios[w][1][-1]:.4f}" for w in ratios)), flush=True)
    print()
    print(header("way", "Hausdorff: mean", "least", "largest", "mean distance: least", "largest", "seconds"))
    for way, (h, m) in ratios.items():
        print(row(way, f"{np.mean(h):.3f}", f"{np.min(h):.3f}", f"{np.max(h):.3f}", f"{np.min(m):.4f}",
                  f"{np.max(m):.4f}", f"{seconds[way]:.2f}"))


if __name__ == "__main__":
    main()
