"""The heat map of Deviation Colors on a character at three levels (issue 34 §3), as the
viewport shows it after Show Deviation: Workbench, Solid shading, colour by attribute.

    .venv/bin/python bench/figures/fig_heat_map.py [--asset PATH] [--ratios R R R] [--size 360]

The character is bench/figures/humanoid.py's, built here (subdivision 3: 24,064
triangles, skinned to 19 bones), or with ``--asset`` every mesh object of a .glb/.gltf
as one asset (e.g. ../shared/assets/RobotExpressive.glb, read where it is, never
copied). It is made into three levels by the add-on's own LodJob with Deviation Colors
on, so each LOD carries LOD_Deviation (an asset's parts one scale per level). Each level
is rendered alone (Workbench, studio light, the colour attribute shown: blue on the
source, red at the level's largest distance), and the three are put side by side into
docs/images/heat_map_levels.png with their triangle counts and scales. Prints one line
saying what the picture shows.
"""
from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import fig_common as fc
import bpy
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import LinearSegmentedColormap
from mathutils import Vector

from addon.pure import level_deviation
from addon.job import LodJob
from addon.pure.settings import LodSettings
from blender_reference import stdout_to_stderr
from render import _look_rotation

OUT = "heat_map_levels.png"
RATIOS = (0.1, 0.03, 0.01)


def load(path) -> list:
    """The character's mesh objects: the humanoid built here, or an asset file's."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path is None:
        import humanoid

        with stdout_to_stderr():
            body, _ = humanoid.build(subdivision=3)
        return [body]
    with stdout_to_stderr():
        bpy.ops.import_scene.gltf(filepath=str(path))
    return [ob for ob in bpy.context.scene.objects if ob.type == 'MESH']


def stage(scene, size: int, objects):
    """Workbench as the viewport's Solid mode by attribute; a camera framing ``objects``
    from the front, a little from above."""
    scene.render.engine = 'BLENDER_WORKBENCH'
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.view_settings.view_transform = 'Standard'
    shading = scene.display.shading
    shading.light = 'STUDIO'
    shading.color_type = 'VERTEX'
    corners = np.array([list(ob.matrix_world @ Vector(c)) for ob in objects for c in ob.bound_box])
    lo, hi = corners.min(0), corners.max(0)
    centre = Vector(((lo + hi) / 2).tolist())
    radius = float(np.linalg.norm(hi - lo)) / 2
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.data.lens_unit = 'FOV'
    cam.data.angle = np.radians(30.0)
    direction = Vector((0.35, -1.0, 0.25)).normalized()  # the character faces -Y
    distance = radius / np.sin(cam.data.angle / 2) * 0.9
    cam.location = centre + direction * distance
    cam.rotation_euler = _look_rotation(direction, Vector((0, 0, 1))).to_euler()
    cam.data.clip_start, cam.data.clip_end = distance / 100, distance * 10


def render_level(scene, shown: set, path: Path) -> np.ndarray:
    for ob in scene.objects:
        if ob.type == 'MESH':
            ob.hide_render = ob.name not in shown
    scene.render.filepath = str(path)
    with stdout_to_stderr():
        bpy.ops.render.render(write_still=True)
    return plt.imread(str(path))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--asset", type=Path, help="a .glb/.gltf character instead of the humanoid")
    ap.add_argument("--ratios", type=float, nargs=3, default=RATIOS, help="the three levels' shares of the triangles")
    ap.add_argument("--size", type=int, default=360, help="pixels per image (square)")
    args = ap.parse_args()
    if args.asset is not None and not args.asset.exists():
        print(f"Skipped: {args.asset} not found.")
        return
    t0 = time.perf_counter()
    sources = load(args.asset)
    name = args.asset.name if args.asset else "the humanoid (bench/figures/humanoid.py)"
    job = LodJob(bpy.context, sources, LodSettings(deviation_colors=True, ratios=tuple(args.ratios)))
    job.run()
    reports = job.commit(bpy.context)
    levels = len(reports[0]["levels"])
    names = [{lv["name"] for rep in reports for lv in rep["levels"] if lv["level"] == k} for k in range(1, levels + 1)]
    for group in names:  # the heat map is the active colour, as Show Deviation makes it
        for lod_name in group:
            bpy.data.objects[lod_name].data.color_attributes.active_color_name = level_deviation.HEAT_ATTRIBUTE
    scene = bpy.context.scene
    stage(scene, args.size, [bpy.data.objects[n] for n in names[0]])
    triangles = [sum(lv["triangles"] for rep in reports for lv in rep["levels"] if lv["level"] == k)
                 for k in range(1, levels + 1)]
    source_triangles = sum(rep["source_triangles"] for rep in reports)
    diagonal = (job.asset_report or {}).get("bounding_box_diagonal")
    if diagonal is None:
        corners = np.array([list(ob.matrix_world @ Vector(c)) for ob in sources for c in ob.bound_box])
        diagonal = float(np.linalg.norm(corners.max(0) - corners.min(0)))
    scales = []
    for k in range(1, levels + 1):  # one scale a level (shared by the parts), in scene units
        entry = next(lv for rep in reports for lv in rep["levels"] if lv["level"] == k)
        ob = bpy.data.objects[entry["name"]]
        scales.append(entry["deviation_colors"]["scale"] * max(ob.matrix_world.to_scale()))
    with tempfile.TemporaryDirectory() as tmp:
        images = [render_level(scene, group, Path(tmp) / f"lod{k}.png") for k, group in enumerate(names, start=1)]
    fig, axes = plt.subplots(1, levels, figsize=(3.3 * levels, 3.9), layout="constrained")
    for k, (ax, img) in enumerate(zip(axes, images), start=1):
        ax.imshow(img)
        ax.set_axis_off()
        red = f"{100 * scales[k - 1] / diagonal:.2f} %" if diagonal else f"{scales[k - 1]:.3g}"
        ax.set_title(f"LOD{k}: {triangles[k - 1]:,} triangles\nred = {red} of the size", fontsize=10)
    # The ramp (level_deviation's, in display colours): 0 to the level's own scale.
    ramp = LinearSegmentedColormap.from_list("heat", level_deviation._RAMP_SRGB)
    bar = fig.colorbar(ScalarMappable(cmap=ramp), ax=axes, orientation="horizontal", fraction=0.05, aspect=50,
                       pad=0.02, ticks=[0, 0.5, 1])
    bar.ax.set_xticklabels(["0 (on the source)", "half", "red = the level's largest"], fontsize=8)
    bar.set_label(f"each LOD's distance to the source ({source_triangles:,} triangles), per vertex", fontsize=9)
    fc.save(fig, OUT)
    parts = f"{len(sources)} mesh objects as one asset, " if len(sources) > 1 else ""
    print(f"`{OUT}`: {name} ({parts}{source_triangles:,} triangles) made into LODs at "
          + ", ".join(f"{100 * r:g} %" for r in args.ratios) + " with Deviation Colors and rendered as Solid "
          f"shading by attribute (Workbench, {args.size} px): " + "; ".join(
              f"LOD{k} {t:,} triangles, red at {100 * s / diagonal:.2f} % of the bounding-box diagonal"
              for k, (t, s) in enumerate(zip(triangles, scales), start=1))
          + f" ({time.perf_counter() - t0:.0f} s).")


if __name__ == "__main__":
    main()
