"""Whole assets (issue 32): one asset's LOD set against Blender's Decimate on every part,
end to end inside one loaded Blender, and how far each level is from the source asset.

    .venv/bin/python bench/assets.py [--ratios 0.5 0.25 0.125] [--repeat 3] [ASSET ...]

Default assets: ../shared/assets (the CAD engine, the robot, the Kenney character,
BoomBox). For each one, after its import (not timed), three or four ways to its LOD set, each
timed from the imported scene to a written .glb (the same exporter call, measuring on):
  * decimate   a script: a Decimate modifier (ratio) on a copy of every mesh object per
               level, applied, then the export;
  * decimate, rigged   (assets an armature deforms or an animation moves) the same
               Decimate, but each copy keeps its rig as an artist's LODs of a character
               must: its parent, its own animation (actions, NLA tracks) and Armature
               modifier, the vertex groups Decimate carries (shape keys cannot be kept:
               Blender applies no modifier to a mesh with keys). Our LODs keep rig,
               animation and keys, and the exporter's animation sampling pays for animated
               copies (docs/benchmarks.md): this is the like-for-like script;
  * asset      LodJob on all the mesh objects, one asset (the default: the budget split
               over the parts by error, one switch set);
  * per part   LodJob with asset_budget off: every object its own chain, the same ratio.
Then every level of each is compared with the source asset as a whole: all its objects'
evaluated triangles in world space against all the level's, two-sided Hausdorff (in % of
the asset's bounding-box diagonal, one sampler for all) and the triangles drawn.
Prints a markdown table per asset, with the processor model. Run it alone (2 cores).
"""
from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs)
import numpy as np

import bpy

from addon import asset as asset_set
from addon.animation import moved_by_animation
from addon import job as job_mod
from addon import lod
from addon.pure import measure
from addon.headless import scene_files
from tables import header, row

ASSETS = _bootstrap.REPO_ROOT.parent / "shared" / "assets"
DEFAULT = ["2CylinderEngine/2CylinderEngine.gltf", "RobotExpressive.glb", "kenney-character/character.glb",
           "BoomBox/BoomBox.gltf"]
SAMPLES = 200_000  # area samples per side for the asset's Hausdorff distance
SEED = 7


def processor() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def load(path: Path) -> list:
    with scene_files.blender_output(False):
        scene_files.import_file(path)
    return [ob for ob in bpy.context.scene.objects if ob.type == 'MESH']


def world_triangles(objects) -> tuple:
    """(vertices, faces) of ``objects``' evaluated meshes in world space, as one mesh."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    verts, faces, offset = [], [], 0
    for ob in objects:
        ev = ob.evaluated_get(depsgraph)
        me = ev.to_mesh()
        me.calc_loop_triangles()
        n, m = len(me.vertices), len(me.loop_triangles)
        co = np.empty(n * 3, np.float32)
        me.vertices.foreach_get("co", co)
        tri = np.empty(m * 3, np.int32)
        me.loop_triangles.foreach_get("vertices", tri)
        mat = np.array(ob.matrix_world)
        verts.append(co.reshape(-1, 3).astype(np.float64) @ mat[:3, :3].T + mat[:3, 3])
        faces.append(tri.reshape(-1, 3).astype(np.int64) + offset)
        offset += n
        ev.to_mesh_clear()
    return np.concatenate(verts), np.concatenate(faces)


def export(path: Path) -> None:
    with scene_files.blender_output(False):
        scene_files.export_scene(path)


def decimate_script(objects, ratios, out: Path, keep_rig: bool = False) -> list:
    """Decimate on every part, per level; returns the level objects per level. (Made at
    rest: a copy of an evaluated skinned mesh has its deformation applied, and the
    comparison is at rest.) ``keep_rig``: each copy keeps its parent, its own animation
    and Armature modifiers (Object.copy), the Decimate applied to the rest mesh (the
    Armature modifiers off while the copy is made)."""
    at_rest()
    levels = []
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for k, ratio in enumerate(ratios, start=1):
        made = []
        for ob in objects:
            rigs = [m for m in ob.modifiers if m.type == 'ARMATURE' and m.show_viewport] if keep_rig else []
            for m in rigs:
                m.show_viewport = False
            mod = ob.modifiers.new("LODDecimate", 'DECIMATE')
            mod.ratio = ratio
            depsgraph.update()
            mesh = bpy.data.meshes.new_from_object(ob.evaluated_get(depsgraph))
            ob.modifiers.remove(mod)
            for m in rigs:
                m.show_viewport = True
            if keep_rig:
                copy = ob.copy()
                copy.name, copy.data = f"{ob.name}_DLOD{k}", mesh
                for m in [m for m in copy.modifiers if m.type != 'ARMATURE']:
                    copy.modifiers.remove(m)
            else:
                copy = bpy.data.objects.new(f"{ob.name}_DLOD{k}", mesh)
                copy.matrix_world = ob.matrix_world
            for coll in ob.users_collection:
                coll.objects.link(copy)
            made.append(copy)
        levels.append(made)
    export(out)
    return levels


def decimate_rigged_script(objects, ratios, out: Path) -> list:
    """decimate_script with every copy keeping its rig."""
    return decimate_script(objects, ratios, out, keep_rig=True)


def is_rigged(objects) -> bool:
    """Whether an armature deforms a part or an animation moves one (a node-animated
    character): its LODs must keep what moves it."""
    return any(m.type == 'ARMATURE' for ob in objects for m in ob.modifiers) or \
        any(moved_by_animation(ob) for ob in objects)


def ours(objects, ratios, out: Path, per_part: bool) -> list:
    settings = lod.LodSettings(ratios=tuple(ratios), asset_budget=not per_part)
    job = job_mod.LodJob(bpy.context, objects, settings, asset_name="bench")
    job.run()
    reports = job.commit(bpy.context)
    export(out)
    return [[bpy.data.objects[r["levels"][k]["name"]] for r in reports if len(r["levels"]) > k]
            for k in range(len(ratios))]


def at_rest(frame=None) -> None:
    """Every armature in its rest position, and with ``frame`` the scene at that frame (the
    one the asset was loaded at, where the static Decimate copies were made): the
    exporter's animation sampling leaves the scene posed at some frame, and a
    node-animated asset's parts (and our LODs, which keep their animation) moved with it;
    source and LODs are compared as modelled."""
    for arm in bpy.data.armatures:
        arm.pose_position = 'REST'
    if frame is not None:
        bpy.context.scene.frame_set(frame)
    bpy.context.view_layer.update()


def measure_levels(source, levels, diagonal) -> list:
    out = []
    for objects in levels:
        v, f = world_triangles(objects)
        d = measure.surface_deviation(source[0], source[1], v, f, n_samples=SAMPLES, seed=SEED)
        out.append((len(f), 100.0 * d["hausdorff"] / diagonal, 100.0 * d["mean"] / diagonal))
    return out


def run_asset(path: Path, ratios: list, repeat: int = 1) -> list:
    rows = []
    results = {}
    for way in ("decimate", "decimate, rigged", "asset", "per part"):
        times = []
        for _ in range(repeat):
            objects = load(path)
            loaded_at = bpy.context.scene.frame_current
            if way == "decimate, rigged" and not is_rigged(objects):
                break
            with tempfile.TemporaryDirectory() as tmp:
                t0 = time.perf_counter()
                if way == "decimate":
                    levels = decimate_script(objects, ratios, Path(tmp) / "out.glb")
                elif way == "decimate, rigged":
                    levels = decimate_rigged_script(objects, ratios, Path(tmp) / "out.glb")
                else:
                    levels = ours(objects, ratios, Path(tmp) / "out.glb", per_part=way == "per part")
                times.append(time.perf_counter() - t0)
        if not times:
            continue
        seconds = min(times)
        at_rest(loaded_at)
        source = world_triangles(objects)
        diagonal = float(np.linalg.norm(source[0].max(0) - source[0].min(0)))
        results[way] = (seconds, measure_levels(source, levels, diagonal), len(objects), len(source[1]))
    base = results["decimate"]
    rigged = results.get("decimate, rigged")
    for way, (seconds, levels, n_objects, triangles) in results.items():
        for k, (tri, hausdorff, mean) in enumerate(levels, start=1):
            dec = base[1][k - 1]
            rows.append(row(path.name, n_objects, f"{triangles:,}", way, f"LOD{k}", f"{tri:,}",
                            f"{hausdorff:.3f}", f"{hausdorff / dec[1]:.2f}x" if dec[1] > 0 else "-",
                            f"{mean:.4f}", f"{seconds:.2f}" if k == 1 else "",
                            f"{seconds / base[0]:.2f}x" if k == 1 else "",
                            (f"{seconds / rigged[0]:.2f}x" if rigged else "-") if k == 1 else ""))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("assets", nargs="*", default=[str(ASSETS / a) for a in DEFAULT])
    parser.add_argument("--ratios", nargs="+", type=float, default=[0.5, 0.25, 0.125])
    parser.add_argument("--repeat", type=int, default=1,
                        help="time each way this many times, each from a fresh import, and keep the fastest "
                             "(a few seconds move by half from run to run here)")
    args = parser.parse_args()
    print(f"Processor: {processor()}; bpy {bpy.app.version_string}; ratios {args.ratios}; "
          f"Hausdorff and mean in % of the asset's diagonal, both sides {SAMPLES:,} samples; "
          f"seconds: the fastest of {args.repeat}\n")
    print(header("asset", "objects", "triangles", "way", "LOD", "drawn", "Hausdorff %", "vs Decimate",
                 "mean %", "seconds", "vs Decimate", "vs Decimate, rigged"))
    for a in args.assets:
        path = Path(a)
        if not path.is_file():
            print(f"(skipped {a}: not found)")
            continue
        for line in run_asset(path, args.ratios, args.repeat):
            print(line, flush=True)


if __name__ == "__main__":
    main()
