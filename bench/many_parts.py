"""A rigged character of many parts against the same geometry as one mesh (issue 32 §2):
an asset should cost what its triangles cost, not what its number of parts costs.

    .venv/bin/python bench/many_parts.py [--parts 59] [--triangles 61000] [--no-measure] [--repeat 3]

Generates a robot-like character (every input is made here): ``--parts`` closed,
bumpy parts (subdivided icospheres stretched into limbs and plates) along a chain of as
many bones, each part skinned to its own bone (an Armature modifier and a vertex group,
as a glTF exporter writes a part per bone), about ``--triangles`` triangles in all, and
an action of 30 frames turning every bone. Then, timed inside one loaded Blender from
the scene to a written .glb (ratios 0.5 0.25 0.125; the same exporter call for all):
  * as an asset: LodJob on the parts, one LOD set (the default), measuring on unless
    --no-measure;
  * as one mesh: the same parts joined into one object (one vertex group per bone);
  * Decimate on every part, static copies and rigged copies (bench/assets.py's scripts).
Prints the times, their ratios and the drawn triangles per level, with the processor.
Run it alone (2 cores).
"""
from __future__ import annotations

import argparse
import time

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import bpy
import numpy as np

import tempfile
from pathlib import Path

from addon import job as job_mod
from addon import lod
from assets import decimate_rigged_script, decimate_script, export, processor

RATIOS = (0.5, 0.25, 0.125)


def icosphere(level: int) -> tuple:
    t = (1.0 + 5 ** 0.5) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    V = np.array(v, dtype=np.float64)
    V /= np.linalg.norm(V, axis=1)[:, None]
    F = np.array(f, dtype=np.int64)
    for _ in range(level):
        edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
        unique, inverse = np.unique(edges, axis=0, return_inverse=True)
        mid = V[unique].mean(axis=1)
        mid /= np.linalg.norm(mid, axis=1)[:, None]
        m = len(F)
        a, b, c = (len(V) + inverse.reshape(-1)[k * m:(k + 1) * m] for k in range(3))
        V = np.concatenate([V, mid])
        F = np.concatenate([np.stack([F[:, 0], a, c], 1), np.stack([a, F[:, 1], b], 1),
                            np.stack([c, b, F[:, 2]], 1), np.stack([a, b, c], 1)])
    return V, F


def part_mesh(index: int, triangles: int, rng) -> tuple:
    """A closed bumpy limb or plate of about ``triangles`` triangles, in its own place."""
    level = max(1, int(round(np.log(max(triangles, 80) / 20.0) / np.log(4.0))))
    V, F = icosphere(level)
    V = V * (1.0 + 0.04 * np.sin(7.0 * V[:, [1]] + index) * np.cos(5.0 * V[:, [2]]))
    V = V * rng.uniform([0.15, 0.15, 0.3], [0.5, 0.5, 1.2])
    V = V + np.array([0.8 * np.cos(index * 0.7), 0.8 * np.sin(index * 0.7), 0.25 * index])
    return V, F


def build(parts: int, triangles: int, joined: bool) -> list:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rng = np.random.default_rng(3)
    arm_data = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", arm_data)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode='EDIT')
    for i in range(parts):
        bone = arm_data.edit_bones.new(f"bone{i}")
        bone.head = (0.8 * np.cos(i * 0.7), 0.8 * np.sin(i * 0.7), 0.25 * i - 0.1)
        bone.tail = (bone.head[0], bone.head[1], bone.head[2] + 0.2)
    bpy.ops.object.mode_set(mode='OBJECT')
    animate(rig)
    meshes = [part_mesh(i, triangles // parts, rng) for i in range(parts)]
    groups = [np.full(len(V), i) for i, (V, _) in enumerate(meshes)]
    if joined:
        offsets = np.cumsum([0] + [len(V) for V, _ in meshes])
        meshes = [(np.concatenate([V for V, _ in meshes]),
                   np.concatenate([F + o for (_, F), o in zip(meshes, offsets)]))]
        groups = [np.concatenate(groups)]
    objects = []
    for k, ((V, F), group) in enumerate(zip(meshes, groups)):
        me = bpy.data.meshes.new(f"Part{k}")
        me.from_pydata(V.tolist(), [], F.tolist())
        ob = bpy.data.objects.new(f"Part{k}", me)
        bpy.context.scene.collection.objects.link(ob)
        for b in np.unique(group):
            vg = ob.vertex_groups.new(name=f"bone{b}")
            vg.add(np.flatnonzero(group == b).tolist(), 1.0, 'REPLACE')
        mod = ob.modifiers.new("Armature", 'ARMATURE')
        mod.object = rig
        ob.parent = rig
        objects.append(ob)
    return objects


def animate(rig) -> None:
    """An action of 30 frames: every bone turns a little and back (the exporter samples it)."""
    for frame, angle in ((1, 0.0), (15, 0.3), (30, 0.0)):
        for i, bone in enumerate(rig.pose.bones):
            bone.rotation_mode = 'XYZ'
            bone.rotation_euler = (angle * (1 if i % 2 else -1), 0.0, 0.0)
            bone.keyframe_insert("rotation_euler", frame=frame)
    bpy.context.scene.frame_start, bpy.context.scene.frame_end = 1, 30


def timed(parts: int, triangles: int, joined: bool, measure: bool) -> tuple:
    objects = build(parts, triangles, joined)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        job = job_mod.LodJob(bpy.context, objects, lod.LodSettings(ratios=RATIOS, measure_deviation=measure))
        job.run()
        reports = job.commit(bpy.context)
        export(Path(tmp) / "out.glb")
        seconds = time.perf_counter() - t0
    drawn = [sum(r["levels"][k]["triangles"] for r in reports if len(r["levels"]) > k) for k in range(len(RATIOS))]
    source = sum(r["source_triangles"] for r in reports)
    return seconds, source, drawn


def timed_script(parts: int, triangles: int, script) -> tuple:
    objects = build(parts, triangles, False)
    source = sum(len(ob.data.polygons) for ob in objects)  # the parts are triangles
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        levels = script(objects, list(RATIOS), Path(tmp) / "out.glb")
        seconds = time.perf_counter() - t0
    drawn = [sum(len(ob.data.polygons) for ob in level) for level in levels]
    return seconds, source, drawn


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", type=int, default=59)
    parser.add_argument("--triangles", type=int, default=61_000)
    parser.add_argument("--no-measure", action="store_true")
    parser.add_argument("--repeat", type=int, default=1, help="time each way this many times, keep the fastest")
    args = parser.parse_args()
    print(f"Processor: {processor()}; bpy {bpy.app.version_string}; ratios {RATIOS}; "
          f"measuring {'off' if args.no_measure else 'on'}\n")
    print("| input | objects | triangles | LOD1 / LOD2 / LOD3 drawn | seconds | vs one mesh "
          "| vs Decimate | vs Decimate, rigged |")
    print("|---|---|---|---|---|---|---|---|")
    def fastest(run):
        return min((run() for _ in range(max(args.repeat, 1))), key=lambda r: r[0])

    static = fastest(lambda: timed_script(args.parts, args.triangles, decimate_script))
    rigged = fastest(lambda: timed_script(args.parts, args.triangles, decimate_rigged_script))
    one = fastest(lambda: timed(args.parts, args.triangles, True, not args.no_measure))
    many = fastest(lambda: timed(args.parts, args.triangles, False, not args.no_measure))
    for name, objects, (seconds, source, drawn) in (("Decimate, static copies", args.parts, static),
                                                    ("Decimate, rigged copies", args.parts, rigged),
                                                    ("one mesh", 1, one), ("asset", args.parts, many)):
        print(f"| {name} | {objects} | {source:,} | {' / '.join(f'{d:,}' for d in drawn)} | {seconds:.2f} | "
              f"{seconds / one[0]:.2f}x | {seconds / static[0]:.2f}x | {seconds / rigged[0]:.2f}x |", flush=True)


if __name__ == "__main__":
    main()
