"""A LOD set switching by distance (docs/engines.md): what the camera sees at each switch.

    .venv/bin/python bench/figures/switch_distances.py [--mesh spot] [--screen-size 1] [--lods 4]
                                                [--crop 96] [--out docs/images/lod_switching.png]

Makes a measured LOD chain of the mesh (default spot from ../shared/meshes; without that
folder a subdivided Suzanne) through the add-on's own path: the command line's options
``--screen-size PX --lods N`` (addon/headless/arguments.py) give the LodSettings, and
LodJob computes and commits the chain as the panel and the command line do. Each level's
switch distance D_i is read back from the custom property ``lqlod_switch_distance`` of its
object (the number the FBX, glTF and sidecar carry; addon/pure/switch_distances.py).

Then, per switch, the camera is put D_i from the source's bounds centre (the distance the
engines measure), with the engines' view: θ = 60° vertical on a 1920 x 1080 frame (the
settings' defaults, H = 1080; --fov changes θ for the chain and the camera alike), and
Workbench renders both the source and LOD i, the level an engine switches to there. One
row per switch: the whole frame (LOD i), then source and LOD i at the frame's own pixels,
2x enlarged, in a window around their largest difference, and the difference itself.
Measured per row and printed (a markdown table): how far apart the two silhouettes are,
in pixels (for each pixel covered by one render only, the distance to the nearest pixel
covered by the other: what the switch distance bounds), the largest grey-level
difference (0-255), and inside the object (pixels both cover) the largest and mean ones and
the share of pixels differing by more than VISIBLE: shading, which the bound does not
cover. Workbench is deterministic, so every difference is the LOD's, not noise.
"""
from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path

import fig_common as fc
import bpy
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Rectangle
from mathutils import Matrix, Vector

from addon import lod_objects
from addon.pure import switch_distances
from addon.headless import arguments
from addon.job import LodJob
from blender_reference import load_mesh, stdout_to_stderr
from tables import header, row

FRAME = (1920, 1080)  # the rendered frame, pixels: 1080p; its height is the settings' H
ASPECT = FRAME[0] / FRAME[1]
# Direction from the bounds centre to the camera, and the image's up, per mesh (OBJ files
# are read without axis conversion: spot is y-up, its head towards -z; Suzanne z-up facing -y).
VIEWS = {"spot": dict(direction=(1.0, 0.4, -0.7), up=(0, 1, 0)),
         "suzanne": dict(direction=(0.6, -1.0, 0.35), up=(0, 0, 1))}
DEFAULT_VIEW = dict(direction=(0.6, -1.0, 0.35), up=(0, 0, 1))
GREY = (0.72, 0.72, 0.72)  # the single Workbench colour, both renders
BACKGROUND = 1.0  # the page's white, what transparent pixels are composed onto
VISIBLE = 8  # grey levels (of 255) from which a difference is counted as visible
# Alpha from which a pixel counts as fully covered: Workbench's 8 anti-aliasing samples
# leave 254/255 inside an object, never 1.
INSIDE_ALPHA = 0.98


# ----------------------------------------------------------------------------- the chain


def source_object(stem: str):
    """The source as a smooth-shaded Blender object, and its name for the captions:
    ../shared/meshes/<stem>.* when there, else Suzanne subdivided twice (z-up)."""
    path = fc.find_mesh(stem)
    if path is not None:
        mesh = load_mesh(path)
        data = bpy.data.meshes.new(path.stem)
        data.from_pydata(mesh.vertices.tolist(), [], mesh.faces.tolist())
        ob = bpy.data.objects.new(path.stem, data)
        bpy.context.collection.objects.link(ob)
        name = path.stem
    else:
        fc.log(f"{stem} not found in {fc.MESH_DIR}: using a subdivided Suzanne")
        bpy.ops.mesh.primitive_monkey_add()
        ob = bpy.context.active_object
        ob.modifiers.new("subdivide", 'SUBSURF').levels = 2
        bpy.ops.object.modifier_apply(modifier="subdivide")
        bpy.ops.object.modifier_add(type='TRIANGULATE')
        bpy.ops.object.modifier_apply(modifier="Triangulate")
        ob.name = name = "suzanne"
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    bpy.ops.object.shade_smooth()
    return ob, name


def chain_argv(args) -> list:
    """The command line's options for this chain (``lod.sh run`` takes the same)."""
    return ["--screen-size", f"{args.screen_size:g}", "--lods", str(args.lods),
            "--screen-height", str(FRAME[1]), "--fov", f"{args.fov:g}"]


def make_chain(source, args) -> list:
    """The LOD chain of ``source`` as the command line makes it; per level (LOD0 first)
    {name, triangles, switch_distance, deviation}, the switch numbers as the objects'
    custom properties hold them (checked against the run's report)."""
    settings = arguments.lod_settings(arguments.build_parser().parse_args(chain_argv(args)))
    job = LodJob(bpy.context, [source], settings)
    job.run()
    report = job.commit(bpy.context)[0]
    for warning in report["warnings"]:
        fc.log(f"warning: {warning}")
    levels = [dict(name=source.name, triangles=report["source_triangles"])]
    levels += [dict(name=level["name"], triangles=level["triangles"]) for level in report["levels"]]
    for i, level in enumerate(levels):
        ob = bpy.data.objects[level["name"]]
        for key in ("switch_distance", "deviation"):
            level[key] = float(ob[lod_objects.switch_prop(key)])
        if i and not math.isclose(level["switch_distance"], report["levels"][i - 1]["switch_distance"]):
            raise RuntimeError(f"{level['name']}: the custom property and the report disagree")
    levels[0]["cull_distance"] = float(report["switch"]["cull_distance"])
    return levels


# ----------------------------------------------------------------------------- rendering


def stage(fov: float):
    """Workbench, studio light, one grey, transparent film; a camera with ``fov`` degrees
    vertical on the 1080p frame (sensor fit vertical, as the formula's θ)."""
    scene = bpy.context.scene
    scene.render.engine = 'BLENDER_WORKBENCH'
    scene.render.resolution_x, scene.render.resolution_y = FRAME
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.render.image_settings.file_format = 'PNG'
    scene.render.image_settings.color_mode = 'RGBA'
    scene.view_settings.view_transform = 'Standard'
    shading = scene.display.shading
    shading.light = 'STUDIO'
    shading.color_type = 'SINGLE'
    shading.single_color = GREY
    scene.display.render_aa = '8'
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.data.sensor_fit = 'VERTICAL'
    cam.data.angle_y = math.radians(fov)
    return scene, cam


def bounds_centre(ob) -> Vector:
    """The bounds centre the switch distances are measured from (switch_distances.mesh_bounds)."""
    co = np.empty(len(ob.data.vertices) * 3)
    ob.data.vertices.foreach_get("co", co)
    centre = switch_distances.mesh_bounds(co.reshape(-1, 3)).center
    return ob.matrix_world @ Vector(centre.tolist())


def place(cam, centre: Vector, distance: float, view: dict) -> None:
    """Camera ``distance`` from ``centre`` along the view's direction, looking at it, with
    the view's up vector pointing up in the image."""
    z = Vector(view["direction"]).normalized()  # the camera looks down its -Z
    x = Vector(view["up"]).cross(z).normalized()
    cam.location = centre + z * distance
    cam.rotation_euler = Matrix((x, z.cross(x), z)).transposed().to_euler()
    cam.data.clip_start = distance / 1000.0
    cam.data.clip_end = distance * 10.0


def render(scene, show, path: Path) -> np.ndarray:
    """Render with only ``show`` visible; RGBA floats (h, w, 4), top row first."""
    for ob in scene.objects:
        if ob.type == 'MESH':
            ob.hide_render = ob is not show
    scene.render.filepath = str(path)
    with stdout_to_stderr():
        bpy.ops.render.render(write_still=True)
    return plt.imread(path)


def on_white(rgba: np.ndarray) -> np.ndarray:
    """Grey levels (h, w) in 0-255 of a render composed onto the page's white."""
    grey = rgba[..., :3].mean(axis=-1)
    alpha = rgba[..., 3]
    return 255.0 * (alpha * grey + (1.0 - alpha) * BACKGROUND)


# ----------------------------------------------------------------------------- measures


def silhouette_gap(a: np.ndarray, b: np.ndarray) -> float:
    """How far apart two silhouettes (boolean masks) are, pixels: for each pixel in one
    only, the distance to the nearest pixel of the other; the largest (0: identical)."""
    worst = 0.0
    for one, other in ((a, b), (b, a)):
        only = np.argwhere(one & ~other).astype(np.float64)
        if not len(only):
            continue
        # Only the other's boundary can be nearest to a pixel outside it (np.roll wraps
        # at the frame's edges: that adds targets, still pixels of the other, never loses one).
        edge = other & ~(np.roll(other, 1, 0) & np.roll(other, -1, 0) & np.roll(other, 1, 1) & np.roll(other, -1, 1))
        targets = np.argwhere(edge).astype(np.float64)
        if not len(targets):
            return math.inf
        for chunk in np.array_split(only, max(1, len(only) // 2048)):
            d2 = ((chunk[:, None, :] - targets[None, :, :]) ** 2).sum(-1).min(axis=1)
            worst = max(worst, float(np.sqrt(d2.max())))
    return worst


def compare(source_rgba: np.ndarray, lod_rgba: np.ndarray) -> dict:
    """The two renders' differences: the silhouette gap (pixels; covered = alpha over
    one half), the largest grey-level difference (0-255) anywhere (an edge pixel one
    render covers more than the other), and inside (pixels both cover fully,
    INSIDE_ALPHA: shading only) the largest, the mean and the share over VISIBLE;
    the |difference| image (h, w) and the source's height on screen (pixels)."""
    a, b = source_rgba[..., 3] > 0.5, lod_rgba[..., 3] > 0.5
    diff = np.abs(on_white(source_rgba) - on_white(lod_rgba))
    inside = diff[(source_rgba[..., 3] > INSIDE_ALPHA) & (lod_rgba[..., 3] > INSIDE_ALPHA)]
    rows = np.nonzero(a.any(axis=1))[0]
    return dict(silhouette_px=silhouette_gap(a, b), max_grey=float(diff.max()),
                inside_max=float(inside.max()), inside_mean=float(inside.mean()),
                inside_visible=100.0 * float((inside > VISIBLE).mean()), diff=diff,
                object_px=int(rows[-1] - rows[0] + 1) if len(rows) else 0)


def crop_window(diff: np.ndarray, size: int) -> tuple:
    """(top, left) of the size x size window centred on the largest difference (3 x 3
    box-filtered, so one stray pixel does not win over a patch), inside the frame."""
    padded = np.pad(diff, 1)
    box = sum(padded[1 + dy:1 + dy + diff.shape[0], 1 + dx:1 + dx + diff.shape[1]]
              for dy in (-1, 0, 1) for dx in (-1, 0, 1))
    y, x = np.unravel_index(int(np.argmax(box)), box.shape)
    top = int(np.clip(y - size // 2, 0, diff.shape[0] - size))
    left = int(np.clip(x - size // 2, 0, diff.shape[1] - size))
    return top, left


# ----------------------------------------------------------------------------- figure


def thumbnail(rgba: np.ndarray, factor: int) -> np.ndarray:
    """The frame on white, ``factor`` x smaller (box filter), RGB."""
    rgb = rgba[..., :3] * rgba[..., 3:] + (1.0 - rgba[..., 3:]) * BACKGROUND
    h, w = rgb.shape[0] // factor * factor, rgb.shape[1] // factor * factor
    return rgb[:h, :w].reshape(h // factor, factor, w // factor, factor, 3).mean(axis=(1, 3))


def enlarge(image: np.ndarray, factor: int = 2) -> np.ndarray:
    """Nearest-neighbour enlargement: each pixel a factor x factor block, so pixels show."""
    return np.repeat(np.repeat(image, factor, axis=0), factor, axis=1)


def number(x: float) -> str:
    """A distance for a label: three significant digits, no exponent."""
    return f"{x:,.0f}" if x >= 100 else f"{x:.3g}"


def compose(rows: list, levels: list, args, name: str, out: Path) -> None:
    """The figure: per switch (rows: (level i, compare()'s result with the renders and
    the window)) the frame, the two close-ups and their difference, with the numbers."""
    n, factor = len(rows), 5  # the frame shown 5 x smaller: 384 x 216
    fig, axes = plt.subplots(n, 4, figsize=(12.8, 2.3 * n + 0.6),
                             gridspec_kw=dict(width_ratios=[ASPECT, 1, 1, 1]), squeeze=False)
    titles = (f"{FRAME[0]} x {FRAME[1]} frame, camera at D$_i$", f"source, {args.crop} px window, 2x",
              "LOD i, same window", f"|source - LOD i| x {args.amplify:g}")
    for ax, title in zip(axes[0], titles):
        ax.set_title(title, fontsize=10)
    for r, (i, result) in enumerate(rows):
        level, (top, left, size) = levels[i], result["window"]
        end = levels[i + 1]["switch_distance"] if i + 1 < len(levels) else levels[0]["cull_distance"]
        ax = axes[r, 0]
        ax.imshow(thumbnail(result["lod_rgba"], factor))
        ax.add_patch(Rectangle((left / factor, top / factor), size / factor, size / factor, fill=False,
                               edgecolor="#d62728", linewidth=1.0))
        ax.set_ylabel(f"D$_{i}$ = {number(level['switch_distance'])}\nLOD{i}, {level['triangles']:,} tris,\n"
                      f"drawn from {number(level['switch_distance'])}\nto {number(end)}",
                      fontsize=9, rotation=0, ha="right", va="center", labelpad=6)
        window = (slice(top, top + size), slice(left, left + size))
        axes[r, 1].imshow(enlarge(thumbnail(result["source_rgba"][window], 1)), interpolation="nearest")
        axes[r, 2].imshow(enlarge(thumbnail(result["lod_rgba"][window], 1)), interpolation="nearest")
        axes[r, 3].imshow(enlarge(np.clip(result["diff"][window] * args.amplify, 0, 255)), cmap="Reds",
                          vmin=0, vmax=255, interpolation="nearest")
        axes[r, 3].text(1.05, 0.5, f"source {result['object_px']:,} px high\n"
                                   f"silhouettes {result['silhouette_px']:.0f} px apart\n"
                                   f"largest grey difference {result['max_grey']:.0f}\n"
                                   f"inside: largest {result['inside_max']:.0f}, "
                                   f"mean {result['inside_mean']:.1f},\n"
                                   f"{result['inside_visible']:.1f} % of pixels > {VISIBLE}\n"
                                   f"(grey levels of 255)",
                        transform=axes[r, 3].transAxes, fontsize=8.5, va="center")
        for ax in axes[r]:
            ax.set_xticks([])
            ax.set_yticks([])
    fig.suptitle(f"{name} ({levels[0]['triangles']:,} triangles), LODs by --screen-size {args.screen_size:g} "
                 f"--lods {args.lods}: the camera at each switch distance D$_i$ ({args.fov:g}° vertical, "
                 f"{FRAME[1]} px high; scene units), LOD i drawn there", fontsize=10.5)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=100, bbox_inches="tight", pad_inches=0.1)
    plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", default="spot", help="a file stem in ../shared/meshes (default spot)")
    ap.add_argument("--screen-size", type=float, default=switch_distances.DEFAULT_PIXEL_ERROR, metavar="PX",
                    help="the pixel error of LOD1 (the command line's --screen-size)")
    ap.add_argument("--lods", type=int, default=4)
    ap.add_argument("--fov", type=float, default=switch_distances.DEFAULT_VERTICAL_FOV_DEGREES,
                    help="vertical field of view, degrees, of the switch distances and the camera")
    ap.add_argument("--crop", type=int, default=96, help="close-up window, frame pixels")
    ap.add_argument("--amplify", type=float, default=4.0, help="the difference image's gain")
    ap.add_argument("--out", type=Path, default=fc.IMAGES / "lod_switching.png")
    args = ap.parse_args(argv)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    source, name = source_object(args.mesh)
    levels = make_chain(source, args)
    scene, cam = stage(args.fov)
    centre = bounds_centre(source)
    view = VIEWS.get(name, DEFAULT_VIEW)
    rows = []
    with tempfile.TemporaryDirectory(prefix="lqlod_switch_") as tmp:
        for i in range(1, len(levels)):
            place(cam, centre, levels[i]["switch_distance"], view)
            fc.log(f"rendering source and {levels[i]['name']} at D = {levels[i]['switch_distance']:.4g}")
            source_rgba = render(scene, source, Path(tmp) / f"source{i}.png")
            lod_rgba = render(scene, bpy.data.objects[levels[i]["name"]], Path(tmp) / f"lod{i}.png")
            result = compare(source_rgba, lod_rgba)
            result.update(source_rgba=source_rgba, lod_rgba=lod_rgba,
                          window=(*crop_window(result["diff"], args.crop), args.crop))
            rows.append((i, result))
    compose(rows, levels, args, name, args.out)
    fc.log(f"wrote {args.out}")
    print(f"{name}, {levels[0]['triangles']:,} triangles, LODs by `{' '.join(chain_argv(args))}`; "
          f"source and LOD i rendered by Workbench at LOD i's switch distance D_i "
          f"({FRAME[0]} x {FRAME[1]}, {args.fov:g}° vertical):")
    print(header("level", "triangles", "deviation", "D_i", "source on screen", "silhouette gap",
                 "largest grey diff", "inside: largest", "inside: mean", f"inside: > {VISIBLE}"))
    for i, result in rows:
        level = levels[i]
        print(row(level["name"], f"{level['triangles']:,}", f"{level['deviation']:.4g}",
                  f"{level['switch_distance']:.4g}", f"{result['object_px']} px", f"{result['silhouette_px']:.0f} px",
                  f"{result['max_grey']:.0f}", f"{result['inside_max']:.0f}", f"{result['inside_mean']:.2f}",
                  f"{result['inside_visible']:.2f} %"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
