"""Blender's side of the benchmarks: its importers and its Decimate modifier, as arrays.

Everything here runs bpy in-process (a bench is its own process; import ``_bootstrap``
before this module so the Blender user dirs are isolated). Meshes cross the bpy boundary
only through bulk ``foreach_get``/``foreach_set``.

    load_mesh(path, uv=False) -> Mesh             Blender's OBJ / glTF importer, triangulated
    mesh_from_arrays(name, V, F, uv=None)          a bpy Mesh datablock from arrays
    decimate(V, F, ratio, uv=None) -> Decimated    Decimate (Collapse) through the depsgraph

Run it directly for a quick check: ``python bench/blender_reference.py [mesh] [ratio]``.
"""
from __future__ import annotations

import contextlib
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import bpy
import numpy as np


@dataclass
class Mesh:
    """A triangle mesh read through Blender: vertices (n, 3) f64, faces (m, 3) i64,
    uv (m, 3, 2) f64 per face corner or None, source_polygon (m,) i64 (the polygon of
    the imported mesh each triangle came from)."""

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    uv: Optional[np.ndarray]
    source_polygon: np.ndarray


@dataclass
class Decimated:
    """Blender Decimate output (triangles), and the seconds the depsgraph took to evaluate it."""

    vertices: np.ndarray
    faces: np.ndarray
    uv: Optional[np.ndarray]
    seconds: float


@contextlib.contextmanager
def stdout_to_stderr():
    """Send everything written to file descriptor 1 (Blender's C code and importers print
    progress there) to stderr meanwhile, so a bench's stdout carries only its table."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        os.dup2(2, 1)
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def _clear_scene() -> None:
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.armatures, bpy.data.images,
                 bpy.data.actions, bpy.data.textures):
        for block in list(coll):
            if block.users == 0:
                coll.remove(block)


def mesh_arrays(me, uv: bool = False):
    """(V (n,3) f64, F (m,3) i64, UV (m,3,2) f64 or None, polygon (m,) i64) of a bpy Mesh,
    triangulated by Blender's own loop triangles."""
    me.calc_loop_triangles()
    n, m = len(me.vertices), len(me.loop_triangles)
    co = np.empty(n * 3, dtype=np.float32)
    me.vertices.foreach_get("co", co)
    tri = np.empty(m * 3, dtype=np.int32)
    me.loop_triangles.foreach_get("vertices", tri)
    poly = np.empty(m, dtype=np.int32)
    me.loop_triangles.foreach_get("polygon_index", poly)
    corner_uv = None
    if uv and me.uv_layers.active is not None:
        loops = np.empty(m * 3, dtype=np.int32)
        me.loop_triangles.foreach_get("loops", loops)
        data = np.empty(len(me.loops) * 2, dtype=np.float32)
        me.uv_layers.active.data.foreach_get("uv", data)
        corner_uv = data.reshape(-1, 2)[loops].reshape(m, 3, 2).astype(np.float64)
    return (co.reshape(n, 3).astype(np.float64), tri.reshape(m, 3).astype(np.int64),
            corner_uv, poly.astype(np.int64))


def load_mesh(path, uv: bool = False) -> Mesh:
    """Import ``path`` (.obj, .gltf, .glb) with Blender's importer into triangle arrays.

    Several imported mesh objects are merged (world transforms applied). OBJ is read
    without axis conversion, so coordinates are the file's. Raises ValueError when the
    file has no mesh, RuntimeError when the importer fails.
    """
    path = Path(path)
    _clear_scene()
    suffix = path.suffix.lower()
    if suffix not in (".obj", ".gltf", ".glb"):
        raise ValueError(f"{path.name}: unsupported mesh format {suffix!r} (use .obj, .gltf or .glb)")
    with stdout_to_stderr():
        if suffix == ".obj":
            result = bpy.ops.wm.obj_import(filepath=str(path), forward_axis="Y", up_axis="Z")
        else:
            result = bpy.ops.import_scene.gltf(filepath=str(path))
    if result != {"FINISHED"}:
        raise RuntimeError(f"{path.name}: Blender's importer returned {result}")
    # Importers may add helper meshes that are not part of the asset (glTF's bone-shape
    # icosphere): skip every mesh used as a bone's custom shape.
    shapes = {pb.custom_shape.name for ob in bpy.data.objects if ob.pose
              for pb in ob.pose.bones if pb.custom_shape is not None}
    objects = [ob for ob in bpy.data.objects if ob.type == "MESH" and ob.name not in shapes]
    if not objects:
        raise ValueError(f"{path.name}: the file contains no mesh")
    parts, offset = [], 0
    for ob in objects:
        v, f, c, p = mesh_arrays(ob.data, uv=uv)
        mw = np.array(ob.matrix_world, dtype=np.float64)
        v = v @ mw[:3, :3].T + mw[:3, 3]
        parts.append((v, f + offset, c, p))
        offset += len(v)
    _clear_scene()
    if sum(len(f) for _, f, _, _ in parts) == 0:
        raise ValueError(f"{path.name}: the file's meshes have no faces")
    uvs = [c for _, _, c, _ in parts]
    return Mesh(
        name=path.stem,
        vertices=np.concatenate([v for v, _, _, _ in parts]),
        faces=np.concatenate([f for _, f, _, _ in parts]),
        uv=np.concatenate(uvs) if uv and all(c is not None for c in uvs) else None,
        source_polygon=np.concatenate([p for _, _, _, p in parts]),
    )


def mesh_from_arrays(name: str, vertices, faces, uv=None):
    """A new bpy Mesh from triangle arrays (and per-corner UVs (m, 3, 2)), via foreach_set."""
    v = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1)
    f = np.ascontiguousarray(faces, dtype=np.int32).reshape(-1)
    m = len(f) // 3
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(v) // 3)
    me.loops.add(len(f))
    me.polygons.add(m)
    me.vertices.foreach_set("co", v)
    me.loops.foreach_set("vertex_index", f)
    me.polygons.foreach_set("loop_start", np.arange(0, len(f), 3, dtype=np.int32))
    if uv is not None:
        layer = me.uv_layers.new(name="UVMap")
        layer.data.foreach_set("uv", np.ascontiguousarray(uv, dtype=np.float32).reshape(-1))
    me.update(calc_edges=True)
    return me


def decimate(vertices, faces, ratio: float, uv=None, *, triangulate: bool = True) -> Decimated:
    """Blender's Decimate modifier (Collapse, ``ratio``) on a mesh built from the arrays.

    The timer covers only the depsgraph evaluation of the modifier: the object is first
    evaluated with the modifier disabled (mesh copy, caches), then the modifier is enabled
    and ``evaluated_depsgraph_get()`` re-evaluates it. ``triangulate`` sets the modifier's
    use_collapse_triangulate so the output is all triangles (the input is triangles, so
    this only stops Blender from re-joining pairs into quads). use_symmetry stays off.
    """
    me = mesh_from_arrays("decimate_input", vertices, faces, uv)
    ob = bpy.data.objects.new("decimate_input", me)
    bpy.context.scene.collection.objects.link(ob)
    try:
        mod = ob.modifiers.new("Decimate", "DECIMATE")
        mod.decimate_type = "COLLAPSE"
        mod.ratio = float(ratio)
        mod.use_collapse_triangulate = triangulate
        mod.show_viewport = False
        bpy.context.evaluated_depsgraph_get()
        mod.show_viewport = True
        t0 = time.perf_counter()
        depsgraph = bpy.context.evaluated_depsgraph_get()
        ob_eval = ob.evaluated_get(depsgraph)
        seconds = time.perf_counter() - t0
        out = ob_eval.to_mesh()
        try:
            v, f, c, _ = mesh_arrays(out, uv=uv is not None)
        finally:
            ob_eval.to_mesh_clear()
    finally:
        bpy.data.objects.remove(ob, do_unlink=True)
        bpy.data.meshes.remove(me)
    return Decimated(vertices=v, faces=f, uv=c, seconds=seconds)


if __name__ == "__main__":
    path = Path(sys.argv[1]) if len(sys.argv) > 1 else _bootstrap.DEFAULT_MESH_DIR / "ogre.obj"
    ratio = float(sys.argv[2]) if len(sys.argv) > 2 else 0.1
    mesh = load_mesh(path, uv=True)
    print(f"{mesh.name}: {len(mesh.vertices)} vertices, {len(mesh.faces)} triangles, "
          f"uv={'yes' if mesh.uv is not None else 'no'}")
    res = decimate(mesh.vertices, mesh.faces, ratio, mesh.uv)
    print(f"Decimate {ratio}: {len(res.faces)} triangles in {res.seconds:.3f} s")
