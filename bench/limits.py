"""Painted limits (issue 34 §1): every LOD of a painted region stays within its limit,
measured with the report's own sampler, and what the limit costs the rest.

    .venv/bin/python bench/limits.py [--limit 0.2] [--ratios 0.5 0.25 0.1]

Two inputs, each simplified through the add-on (lod.prepare + lod.compute, the panel's
defaults but the chain and the limit), with and without the limit:
  * the generated face of bench/shape_keys.py (20,480 triangles) with its eyes and mouth
    painted in the group "Features": 1 at the eyes' and the mouth's centre, fading to 0
    over about twice their size;
  * ../shared/meshes/ogre.obj with its highest part painted: 1 within 8 % of the
    diagonal of its highest vertex, fading to 0 at 16 %.
The limit is ``--limit`` percent of the object's bounding-box diagonal where the weight
is 1 (L / w where it fades). Per LOD: triangles and stop reason, the report's
``limit_used`` (the largest distance over the local limit at the report's samples and
vertices of both surfaces: <= 1 when the limit holds), the painted region's Hausdorff
distance (weight >= 1/2) and the whole LOD's, both in % of the diagonal, and the
simplification's seconds. Prints markdown tables and the processor; docs/benchmarks.md
quotes them.
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs)
import numpy as np

import bpy

from addon import lod, vertex_groups
from addon.headless import scene_files
from assets import processor
from shape_keys import CORNERS, EYES, SCALE, face_object
from tables import header, row

OGRE = _bootstrap.REPO_ROOT.parent / "shared" / "meshes" / "ogre.obj"
GROUP = "Features"


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def painted_face():
    """The generated face, without its keys, its eyes and mouth painted in GROUP."""
    scene_files.reset_scene()
    ob = face_object(subdivisions=6)
    ob.shape_key_clear()
    p = _unit(_positions(ob) / SCALE)
    weight = np.zeros(len(p))
    for centre, size in [(e, 0.12) for e in EYES] + [((0.0, -0.93, -0.36), 0.14)] + [(c, 0.08) for c in CORNERS]:
        d = np.linalg.norm(p - _unit(np.asarray(centre, dtype=np.float64)), axis=1)
        weight = np.maximum(weight, np.clip((2.0 * size - d) / size, 0.0, 1.0))
    _paint(ob, weight)
    return ob, weight


def painted_ogre():
    scene_files.reset_scene()
    with scene_files.blender_output(False):
        bpy.ops.wm.obj_import(filepath=str(OGRE))
    ob = next(o for o in bpy.context.scene.objects if o.type == 'MESH')
    co = _positions(ob)
    up = int(np.argmax(co[:, 2]))
    diagonal = float(np.linalg.norm(co.max(axis=0) - co.min(axis=0)))
    d = np.linalg.norm(co - co[up], axis=1) / diagonal
    weight = np.clip((0.16 - d) / 0.08, 0.0, 1.0)
    _paint(ob, weight)
    return ob, weight


def _positions(ob) -> np.ndarray:
    n = len(ob.data.vertices)
    flat = np.empty(3 * n, np.float32)
    ob.data.vertices.foreach_get("co", flat)
    return flat.reshape(n, 3).astype(np.float64)


def _paint(ob, weight):
    vertex_groups.write_weights(ob, [GROUP], weight[:, None])


def run(ob, ratios, limit_percent):
    out = {}
    for tag, extra in (("free", {}), ("limit", {"limit_group": GROUP, "limit_distance": limit_percent})):
        settings = lod.LodSettings(ratios=tuple(ratios), **extra)
        t0 = time.perf_counter()
        lod_input = lod.prepare(bpy.context, ob, settings)
        output = lod.compute(lod_input)
        seconds = sum(r["seconds"] for r in output.reports)
        out[tag] = (output.reports, seconds, time.perf_counter() - t0)
    return out


def table(name, faces, painted, result, limit_percent):
    print(f"\n{name}: {faces:,} triangles, {painted:,} vertices painted, limit {limit_percent:g} % "
          f"of the diagonal where the weight is 1")
    print(header("LOD", "run", "triangles (target)", "stop", "limit used", "region Hausdorff %",
                 "LOD Hausdorff %", "simplify s"))
    for tag in ("free", "limit"):
        reports, _, _ = result[tag]
        for r in reports:
            kept = r.get("limit") or {}
            region = kept.get("region_hausdorff_percent", r.get("regions", {}).get(GROUP, {}).get("max_percent"))
            used = kept.get("limit_used")
            print(row(f"LOD{r['level']}", tag, f"{r['triangles']:,} ({r['target']:,})", r["stop_reason"],
                      "-" if used is None else f"{used:.3f}", f"{region:.3f}" if region is not None else "-",
                      f"{r['hausdorff_percent']:.3f}", f"{r['seconds']:.2f}"))
    free_s, limit_s = result["free"][1], result["limit"][1]
    print(f"simplification: {free_s:.2f} s free, {limit_s:.2f} s with the limit ({limit_s / free_s:.2f}x); "
          f"whole run with measuring: {result['free'][2]:.1f} s / {result['limit'][2]:.1f} s")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--limit", type=float, default=0.2, help="percent of the diagonal (default 0.2)")
    parser.add_argument("--ratios", type=float, nargs="+", default=[0.5, 0.25, 0.1])
    args = parser.parse_args()
    print(f"processor: {processor()}; bpy {bpy.app.version_string}")
    ob, weight = painted_face()
    table("generated face, eyes and mouth painted", len(ob.data.polygons), int(np.count_nonzero(weight > 0)),
          run(ob, args.ratios, args.limit), args.limit)
    if Path(OGRE).exists():
        ob, weight = painted_ogre()
        table("ogre.obj, its highest part painted", len(ob.data.polygons), int(np.count_nonzero(weight > 0)),
              run(ob, args.ratios, args.limit), args.limit)
    else:
        print(f"\n{OGRE} not found: the ogre is skipped")


if __name__ == "__main__":
    main()
