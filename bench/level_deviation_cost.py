"""What the report's breakdown per material and painted region, and the heat map, add to
the level report's measurement (issue 34 §3).

    .venv/bin/python bench/level_deviation_cost.py [--mesh PATH] [--repeats 3]

The source: a bumpy UV sphere of about 50,000 triangles made here (or ``--mesh``), with
two materials (its two halves) and a painted vertex group (a cap). Its default chain
(50 %, 25 %, 12.5 %) is made once without measuring; then each LOD is measured as the
report measures it (compute.level_report's measurement: mesh_report with the shading
normals, at report_samples) with and without keeping its points (alternately, the
fastest of ``--repeats`` kept), and the breakdown per material and region
(addon/pure/level_deviation.py: what every measured LOD now pays) and the heat map (Deviation
Colors) are timed on their own, the fastest of five times as many runs: a busy machine
slows a measurement of half a second by more than the breakdown costs. Prints a
markdown table; the extra columns are in percent of the measurement.
"""
from __future__ import annotations

import argparse
import time

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)

import bpy
import numpy as np

from addon.pure import deviation_search, level_deviation, measure, mesh_data
from addon import lod
from addon.pure.settings import LodSettings


def bumpy_sphere():
    bpy.ops.mesh.primitive_uv_sphere_add(segments=224, ring_count=113)
    ob = bpy.context.active_object
    me = ob.data
    v = np.empty(len(me.vertices) * 3, np.float32)
    me.vertices.foreach_get("co", v)
    v = v.reshape(-1, 3).astype(float)
    bumps = 1.0 + 0.05 * np.sin(9 * v[:, 0]) * np.sin(7 * v[:, 1]) * np.sin(8 * v[:, 2])
    me.vertices.foreach_set("co", (v * bumps[:, None]).astype(np.float32).ravel())
    return ob


def from_file(path):
    from blender_reference import load_mesh

    mesh = load_mesh(path)
    data = bpy.data.meshes.new("mesh")
    data.from_pydata(mesh.vertices.tolist(), [], mesh.faces.tolist())
    ob = bpy.data.objects.new("mesh", data)
    bpy.context.collection.objects.link(ob)
    return ob


def dress(ob):
    """Two materials (halves by x) and a painted group (a cap by z)."""
    me = ob.data
    for name in ("Left", "Right"):
        me.materials.append(bpy.data.materials.new(name))
    v = np.empty(len(me.vertices) * 3, np.float32)
    me.vertices.foreach_get("co", v)
    v = v.reshape(-1, 3)
    centre = np.empty(len(me.polygons) * 3, np.float32)
    me.polygons.foreach_get("center", centre)
    me.polygons.foreach_set("material_index", (centre.reshape(-1, 3)[:, 0] > np.median(v[:, 0])).astype(np.int32))
    cap = np.flatnonzero(v[:, 2] > np.quantile(v[:, 2], 0.8))
    ob.vertex_groups.new(name="Cap").add(cap.tolist(), 1.0, 'REPLACE')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mesh", help="an .obj/.gltf instead of the generated sphere")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)
    ob = from_file(args.mesh) if args.mesh else bumpy_sphere()
    dress(ob)
    settings = LodSettings(measure_deviation=False)
    lod_input = lod.prepare(bpy.context.scene, ob, settings)
    levels = lod.compute(lod_input).levels
    data = lod_input.data

    def measured(level, keep):
        normals = (data.corner_normals, mesh_data.shading_normals(level))
        return measure.mesh_report(data.vertices, data.faces, level.vertices, level.faces, normals=normals,
                                   keep_samples=keep,
                                   n_samples=(deviation_search.report_samples(len(data.faces)),
                                              deviation_search.report_samples(len(level.faces))))

    def fastest(call, repeats):
        best = float("inf")
        for _ in range(repeats):
            t0 = time.perf_counter()
            call()
            best = min(best, time.perf_counter() - t0)
        return best

    print(f"source: {len(data.faces):,} triangles, {len(data.vertices):,} vertices; fastest of "
          f"{args.repeats} (measurements, alternating) and of {5 * args.repeats} (the NumPy parts)", flush=True)
    print("| LOD | triangles | measurement (s) | keeping the points (s) | breakdown (s) | heat map (s) | "
          "extra: breakdown | extra: with heat map |")
    print("|---|---|---|---|---|---|---|---|")
    totals = np.zeros(4)
    for k, level in enumerate(levels, start=1):
        plain = kept = float("inf")
        for _ in range(args.repeats):  # alternating, so a busy machine slows both alike
            plain = min(plain, fastest(lambda: measured(level, False), 1))
            kept = min(kept, fastest(lambda: measured(level, True), 1))
        report = measured(level, True)
        breakdown = fastest(lambda: level_deviation.measure_level(lod_input, level, report), 5 * args.repeats)
        heat = fastest(lambda: level_deviation.with_heat(level, report["sampled"]), 5 * args.repeats)
        row = np.array([plain, max(kept - plain, 0.0), breakdown, heat])
        totals += row
        print(_row(f"LOD{k}", f"{len(level.faces):,}", row), flush=True)
    print(_row("all", "", totals))


def _row(name, triangles, t) -> str:
    plain, keep, breakdown, heat = t
    return (f"| {name} | {triangles} | {plain:.3f} | {keep:.3f} | {breakdown:.3f} | {heat:.3f} | "
            f"{100 * (keep + breakdown) / plain:+.1f} % | {100 * (keep + breakdown + heat) / plain:+.1f} % |")


if __name__ == "__main__":
    main()
