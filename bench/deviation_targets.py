"""Deviation targets on real meshes (issue 22): requested against measured distance.

    .venv/bin/python bench/deviation_targets.py [MESH ...] [--percent 0.05 0.2 1]

For each mesh (default: every mesh of ../shared/meshes) the add-on's own path makes one
LOD per requested deviation (percent of the bounding-box diagonal), as the panel and
``--max-error`` do: the core's tracked distance bound first, the ladder where that
misses (addon/pure/deviation_targets.py). Prints a markdown table: requested, measured
(the report's two-sided Hausdorff distance, 500k samples a side), their ratio (must be
<= 1, and >= 0.5 to count as close), triangles, and the seconds of the whole search.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)

import bpy

from addon import lod
from addon.pure.settings import LodSettings
from blender_reference import load_mesh, mesh_from_arrays
from tables import header, row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="*", type=Path)
    ap.add_argument("--percent", type=float, nargs="+", default=[0.05, 0.2, 1.0])
    args = ap.parse_args(argv)
    meshes = args.meshes or sorted(p for p in _bootstrap.DEFAULT_MESH_DIR.iterdir()
                                   if p.suffix in (".obj", ".gltf", ".glb"))
    print(header("mesh", "triangles in", "requested %", "measured %", "measured / requested", "triangles",
                 "search s"))
    for path in meshes:
        mesh = load_mesh(path)
        source = bpy.data.objects.new(path.stem, mesh_from_arrays(path.stem, mesh.vertices, mesh.faces))
        bpy.context.scene.collection.objects.link(source)
        settings = LodSettings(max_deviations=tuple((p, True) for p in args.percent))
        t0 = time.perf_counter()
        lod_input = lod.prepare(bpy.context.scene, source, settings)
        output = lod.compute(lod_input)
        seconds = time.perf_counter() - t0
        by_request = {round(r["requested_deviation_percent"], 9): r for r in output.reports}
        for percent in args.percent:
            r = by_request.get(round(percent, 9))
            if r is None:
                print(row(path.name, f"{len(mesh.faces):,}", f"{percent:g}", "-", "-", "none within", f"{seconds:.1f}"))
                continue
            measured = r["hausdorff_percent"]
            print(row(path.name, f"{len(mesh.faces):,}", f"{percent:g}", f"{measured:.4f}",
                      f"{measured / percent:.2f}", f"{r['triangles']:,}", f"{seconds:.1f}"), flush=True)
        bpy.data.objects.remove(source)
    return 0


if __name__ == "__main__":
    sys.exit(main())
