"""Issue 18's target-reach table: low-poly and extreme targets, core against Decimate.

    .venv/bin/python bench/targets.py [--meshes DIR]

Blender's own primitives (UV spheres, with their fan-pole UVs, and Suzanne) and the
low-poly meshes of DIR (spot, the Fox) at targets down to a few dozen triangles, each
simplified by core.simplify (defaults, UVs carried and seams kept where the mesh has
them) and by Blender's Decimate in the same process. Prints a markdown table: the
triangles each reached, core's stop reason and how far its quality rules had to relax
(core.guards; 0 = not at all).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import tables
import bpy

import core
from blender_reference import decimate, load_mesh, mesh_arrays, stdout_to_stderr
from run import welded


def primitive(op, **kw):
    """(V, F, UV) of a fresh Blender primitive, triangulated."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    with stdout_to_stderr():
        op(**kw)
    v, f, uv, _ = mesh_arrays(bpy.context.object.data, uv=True)
    return v, f, uv


def cases(mesh_dir: Path):
    for seg, rings, targets in ((20, 10, (36,)), (40, 20, (152, 76)), (60, 40, (234, 46))):
        v, f, uv = primitive(bpy.ops.mesh.primitive_uv_sphere_add, segments=seg, ring_count=rings)
        for t in targets:
            yield f"UV sphere {seg}x{rings}", v, f, uv, t
    v, f, uv = primitive(bpy.ops.mesh.primitive_monkey_add)
    for t in (20, 9):
        yield "Suzanne", v, f, uv, t
    for name, targets in (("spot.obj", (29,)), ("Fox.gltf", (58, 29))):
        path = mesh_dir / name
        if path.exists():
            m = load_mesh(path, uv=True)
            for t in targets:
                yield path.stem, m.vertices, m.faces, m.uv, t


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--meshes", type=Path, default=_bootstrap.DEFAULT_MESH_DIR)
    args = ap.parse_args(argv)
    print(tables.header(
        "input", "triangles", "target", "core", "stop reason", "relaxed to step", "core s", "Decimate", "Decimate s"))
    for name, v, f, uv, target in cases(args.meshes):
        options = {} if uv is None else {"corner_attributes": {"uv": uv}, "uv_attributes": ("uv",)}
        t0 = time.perf_counter()
        r = core.simplify(v, f, target_faces=target, **options)
        seconds = time.perf_counter() - t0
        wv, wf, _ = welded(v, f)
        dec = decimate(wv, wf, target / len(f))
        print(tables.row(name, f"{len(f):,}", target, len(r.faces), r.stats.stop_reason,
                         r.stats.relaxation_step, f"{seconds:.3f}", len(dec.faces), f"{dec.seconds:.3f}"), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
