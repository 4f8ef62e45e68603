"""Shaded-with-wireframe renders, before and after, made headless through the bpy module.

    .venv/bin/python bench/figures/render.py [--mesh stanford-bunny ogre] [--ratio 0.1] [--size 520]
                                     [--samples 16] [--engine CYCLES|BLENDER_WORKBENCH]

For each mesh (default: stanford-bunny and ogre), renders the input (../shared/meshes/<mesh>.obj), core.simplify's LOD (default
settings, line_weight 1e-3) and Blender's Decimate (Collapse) at the same ratio, each from
the same camera, and puts them side by side with their triangle counts and mean triangle
quality into docs/images/render_<mesh>.png (plus a close-up of the same three,
docs/images/render_<mesh>_closeup.png).

Engines, as tested here without a display (2 cores, bpy 4.5): Cycles on the CPU works and
is the default: a Wireframe shader node (constant pixel width) mixes dark lines into a grey
diffuse material, about 1-3 s per 520 px image at 16 samples. Workbench also renders
(through software EGL, with harmless "EGL_BAD_MATCH" messages) but has no wireframe in
final renders, so --engine BLENDER_WORKBENCH gives plain shaded images. EEVEE took 51 s
for a 200 x 150 test image, so it is not offered.
"""
from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import fig_common as fc
import bpy
import matplotlib.pyplot as plt
import numpy as np
from mathutils import Matrix, Vector

import core
from blender_reference import decimate, load_mesh, mesh_from_arrays, stdout_to_stderr

# Camera per mesh: direction from the mesh centre to the camera, the up vector (OBJ files
# are read without axis conversion, so each keeps its own up axis), and the close-up
# window (centre and size as fractions of the full frame).
VIEWS = {
    "stanford-bunny": dict(direction=(-0.35, 0.2, 1.0), up=(0, 1, 0), closeup=((0.33, 0.42), 0.36)),
    "ogre": dict(direction=(0.35, 0.1, 1.0), up=(0, 1, 0), closeup=((0.5, 0.22), 0.30)),
}
DEFAULT_VIEW = dict(direction=(0.5, -1.0, 0.4), up=(0, 0, 1), closeup=((0.5, 0.5), 0.35))


# The colour attribute render(colors=...) writes and wire_material(vertex_colors=True) reads.
COLOR_ATTRIBUTE = "render_color"


def wire_material(engine: str, vertex_colors: bool = False):
    mat = bpy.data.materials.new("shaded_wire")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (0.45, 0.50, 0.58, 1.0)
    if vertex_colors:
        attr = nodes.new("ShaderNodeAttribute")
        attr.attribute_name = COLOR_ATTRIBUTE
        links.new(attr.outputs["Color"], diffuse.inputs["Color"])
    if engine != "CYCLES":
        links.new(diffuse.outputs["BSDF"], out.inputs["Surface"])
        mat.diffuse_color = (0.45, 0.50, 0.58, 1.0)
        return mat
    line = nodes.new("ShaderNodeBsdfDiffuse")
    line.inputs["Color"].default_value = (0.03, 0.04, 0.06, 1.0)
    wire = nodes.new("ShaderNodeWireframe")
    wire.use_pixel_size = True
    wire.inputs["Size"].default_value = 0.7
    mix = nodes.new("ShaderNodeMixShader")
    links.new(wire.outputs["Fac"], mix.inputs["Fac"])
    links.new(diffuse.outputs["BSDF"], mix.inputs[1])
    links.new(line.outputs["BSDF"], mix.inputs[2])
    links.new(mix.outputs["Shader"], out.inputs["Surface"])
    return mat


def setup_scene(engine: str, size: int, samples: int):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = engine
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.view_settings.view_transform = "Standard"
    scene.render.film_transparent = True  # composed onto the page's white by matplotlib
    if engine == "CYCLES":
        scene.cycles.device = "CPU"
        scene.cycles.samples = samples
        scene.cycles.use_denoising = False  # the denoiser smears one-pixel wire lines
        scene.cycles.max_bounces = 2
    else:
        scene.display.shading.light = "STUDIO"
        scene.display.shading.color_type = "MATERIAL"
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.35
    scene.world = world
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3.0
    scene.collection.objects.link(sun)
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    return scene, sun, cam


def aim(cam, sun, V, view):
    """Camera on ``view['direction']`` from the bounding-sphere centre, framing the mesh."""
    lo, hi = V.min(axis=0), V.max(axis=0)
    centre = Vector(((lo + hi) / 2).tolist())
    radius = float(np.linalg.norm(hi - lo)) / 2
    direction = Vector(view["direction"]).normalized()
    cam.data.lens_unit = "FOV"
    cam.data.angle = np.radians(30.0)
    distance = radius / np.sin(cam.data.angle / 2) * 0.92
    cam.location = centre + direction * distance
    cam.rotation_euler = _look_rotation(direction, Vector(view["up"])).to_euler()
    cam.data.clip_start = distance / 100
    cam.data.clip_end = distance * 10
    # Key light from above-left of the camera, so facets read.
    up = Vector(view["up"])
    side = direction.cross(up).normalized()
    sun.rotation_euler = (-(direction + 0.8 * up - 0.6 * side)).to_track_quat("-Z", "Y").to_euler()


def _look_rotation(direction, up):
    """Rotation of a camera (looking down its -Z) placed along ``direction`` from its target,
    with ``up`` (any vector not parallel to the direction) pointing up in the image."""
    z = direction.normalized()
    x = up.cross(z).normalized()
    y = z.cross(x)
    return Matrix((x, y, z)).transposed()


def render(scene, V, F, mat, path: Path, colors=None) -> None:
    """Render the mesh (V, F) with ``mat`` into ``path``; ``colors`` (n, 3) linear RGB per
    vertex, if given, are stored for a wire_material(vertex_colors=True) to show."""
    me = mesh_from_arrays("render_mesh", V, F)
    if colors is not None:
        rgba = np.ones((len(V), 4), dtype=np.float32)
        rgba[:, :3] = colors
        me.color_attributes.new(COLOR_ATTRIBUTE, "FLOAT_COLOR", "POINT").data.foreach_set("color", rgba.ravel())
    me.materials.append(mat)
    ob = bpy.data.objects.new("render_mesh", me)
    scene.collection.objects.link(ob)
    scene.render.filepath = str(path)
    with stdout_to_stderr():
        bpy.ops.render.render(write_still=True)
    bpy.data.objects.remove(ob, do_unlink=True)
    bpy.data.meshes.remove(me)


def zoom(cam, closeup, full_angle):
    """Point the camera at a window of the full frame: ((cx, cy) from the top left, size),
    all as fractions of the frame, by narrowing the field of view and shifting the lens,
    so the close-up is a real render at full resolution rather than an enlarged crop."""
    (cx, cy), size = closeup
    cam.data.angle = 2 * np.arctan(size * np.tan(full_angle / 2))
    cam.data.shift_x = (cx - 0.5) / size
    cam.data.shift_y = (0.5 - cy) / size


def compose(images, titles, out_name: str) -> None:
    fig, axes = plt.subplots(1, len(images), figsize=(4.2 * len(images), 4.6), layout="constrained")
    for ax, img, title in zip(axes, images, titles):
        ax.imshow(img)
        ax.set_axis_off()
        ax.set_title(title, fontsize=11)
    fc.save(fig, out_name)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesh", nargs="+", default=["stanford-bunny", "ogre"],
                    help="file stems in ../shared/meshes")
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--size", type=int, default=520, help="pixels per image (square)")
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--engine", default="CYCLES", choices=("CYCLES", "BLENDER_WORKBENCH"))
    args = ap.parse_args()
    for stem in args.mesh:
        path = fc.find_mesh(stem)
        if path is None:
            print(f"Skipped {stem}: not found in {fc.MESH_DIR}.")
            continue
        render_mesh(stem, path, args)


def render_mesh(stem, path, args) -> None:
    mesh = load_mesh(path)
    V, F = mesh.vertices, mesh.faces
    res = core.simplify(V, F, ratio=args.ratio)
    dec = decimate(V, F, args.ratio)
    entries = [("input", V, F), ("ours (core.simplify)", res.vertices, res.faces),
               ("Blender Decimate", dec.vertices, dec.faces)]

    scene, sun, cam = setup_scene(args.engine, args.size, args.samples)
    view = VIEWS.get(stem, DEFAULT_VIEW)
    aim(cam, sun, V, view)
    mat = wire_material(args.engine)
    titles = []
    for label, v, f in entries:
        q = core.quality_summary(v, f)
        titles.append(f"{label}\n{len(f):,} triangles, mean q {q['mean_quality']:.2f}, "
                      f"{q['sliver_percent']:.1f} % slivers")
    full_angle = cam.data.angle
    with tempfile.TemporaryDirectory(prefix="lqlod_render_") as tmp:
        for suffix, closeup in (("", None), ("_closeup", view["closeup"])):
            if closeup is not None:
                zoom(cam, closeup, full_angle)
            images = []
            for i, (label, v, f) in enumerate(entries):
                fc.log(f"rendering {label} ({len(f):,} triangles){' close-up' if closeup else ''}")
                png = Path(tmp) / f"{i}{suffix}.png"
                render(scene, v, f, mat, png)
                images.append(plt.imread(png))
            compose(images, titles, f"render_{stem}{suffix}.png")
    qs = [core.quality_summary(v, f) for _, v, f in entries]
    print(f"{stem} ({len(F):,} triangles) and its {args.ratio:.0%} LODs rendered side by side ({args.engine}, "
          f"{args.size}px, {args.samples} samples): ours {len(res.faces):,} triangles with mean q "
          f"{qs[1]['mean_quality']:.3f} and {qs[1]['sliver_percent']:.2f} % slivers, Blender's Decimate "
          f"{len(dec.faces):,} with {qs[2]['mean_quality']:.3f} and {qs[2]['sliver_percent']:.2f} %.")


if __name__ == "__main__":
    main()
