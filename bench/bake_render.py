"""What Bake Normals buys (issue 22 §3): rendered shading error of a LOD against its
source, without and with the baked normal map.

    .venv/bin/python bench/bake_render.py [MESH ...] [--ratio 0.1] [--size 256] [--bake 1024]

For each mesh (default: a bumpy UV sphere the bench makes, and spot.obj from
../shared/meshes, which has UVs) one LOD at the ratio is made by the add-on
(addon/lod.py), once plain and once with Bake Normals. Each is rendered by Cycles from
the same camera and light, with a plain grey material, as is the source; the error is
the mean absolute difference of the rendered grey levels over the pixels the source
covers (0-1). Prints a markdown table. ``--image PNG`` also writes the first mesh's
three renders side by side (source, LOD, LOD with the baked map): docs/panel.md shows it.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)

import bpy
import numpy as np
from mathutils import Vector

from addon import lod as lod_module
from blender_reference import load_mesh
from tables import header, row


def bumpy_sphere():
    bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48)
    ob = bpy.context.active_object
    bumps = ob.modifiers.new("bumps", 'DISPLACE')
    bumps.texture = bpy.data.textures.new("bumps", 'CLOUDS')
    bumps.texture.noise_scale = 0.25
    bumps.strength = 0.12
    bpy.ops.object.modifier_apply(modifier="bumps")
    ob.name = "bumpy_sphere"
    return ob


def from_file(path: Path):
    mesh = load_mesh(path, uv=True)
    data = bpy.data.meshes.new(path.stem)
    data.from_pydata(mesh.vertices.tolist(), [], mesh.faces.tolist())
    if mesh.uv is not None:
        layer = data.uv_layers.new(name="UVMap")
        layer.uv.foreach_set("vector", np.asarray(mesh.uv, dtype=np.float32).ravel())
    ob = bpy.data.objects.new(path.stem, data)
    bpy.context.collection.objects.link(ob)
    return ob


def stage(ob):
    """Camera and sun framing ``ob``; Cycles at a few samples."""
    scene = bpy.context.scene
    corners = [ob.matrix_world @ Vector(c) for c in ob.bound_box]
    centre = sum(corners, Vector()) / 8.0
    radius = max((c - centre).length for c in corners)
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    scene.collection.objects.link(cam)
    cam.location = centre + Vector((0.0, -2.6 * radius, 0.9 * radius))
    cam.rotation_euler = (centre - cam.location).to_track_quat('-Z', 'Y').to_euler()
    scene.camera = cam
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", 'SUN'))
    sun.rotation_euler = (math.radians(50), math.radians(10), math.radians(30))
    scene.collection.objects.link(sun)
    scene.render.engine = 'CYCLES'
    scene.cycles.samples = 16
    scene.world = scene.world or bpy.data.worlds.new("world")
    return scene


def render(scene, show, size: int) -> np.ndarray:
    for ob in scene.objects:
        if ob.type == 'MESH':
            ob.hide_render = ob is not show
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    path = str(Path(bpy.app.tempdir) / "bake_render.png")
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path, check_existing=False)
    pixels = np.array(image.pixels[:]).reshape(size, size, 4)
    bpy.data.images.remove(image)
    return pixels


def grey_material(ob, name="grey"):
    mat = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    mat.use_nodes = True
    ob.data.materials.clear()
    ob.data.materials.append(mat)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="*", type=Path)
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--bake", type=int, default=1024)
    ap.add_argument("--image", type=Path, help="write the first mesh's three renders side by side")
    args = ap.parse_args(argv)
    strip = []
    cases = args.meshes or [None, _bootstrap.DEFAULT_MESH_DIR / "spot.obj"]
    print(header("mesh", "triangles", "LOD triangles", "error plain", "error baked", "baked / plain"))
    for case in cases:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        src = bumpy_sphere() if case is None else from_file(case)
        bpy.context.view_layer.objects.active = src
        bpy.ops.object.shade_smooth()
        grey_material(src)
        scene = stage(src)
        errors, tris = {}, 0
        reference = render(scene, src, args.size)
        mask = reference[..., 3] > 0.5
        if not strip:
            strip.append(reference)
        for bake in (False, True):
            report = lod_module.generate_lods(bpy.context, src, lod_module.LodSettings(
                levels=1, ratio=args.ratio, bake_normals=bake, bake_resolution=args.bake))
            lod = bpy.data.objects[report["levels"][0]["name"]]
            tris = len(lod.data.polygons)
            image = render(scene, lod, args.size)
            errors[bake] = float(np.abs(image[..., :3] - reference[..., :3]).mean(axis=-1)[mask].mean())
            if len(strip) < 3 and case == cases[0]:
                strip.append(image)
        name = "bumpy sphere" if case is None else case.name
        print(row(name, f"{len(src.data.polygons):,}", f"{tris:,}", f"{errors[False]:.4f}", f"{errors[True]:.4f}",
                  f"{errors[True] / errors[False]:.2f}"), flush=True)
    if args.image and len(strip) == 3:
        write_png(args.image, np.concatenate(strip, axis=1))
    return 0


def write_png(path: Path, pixels: np.ndarray) -> None:
    """``pixels`` (h, w, 4) floats, bottom row first as Blender keeps them, to a PNG."""
    h, w = pixels.shape[:2]
    image = bpy.data.images.new("strip", w, h, alpha=True)
    image.pixels.foreach_set(np.ascontiguousarray(pixels, dtype=np.float32).ravel())
    image.filepath_raw = str(path)
    image.file_format = 'PNG'
    image.save()
    bpy.data.images.remove(image)


if __name__ == "__main__":
    sys.exit(main())
