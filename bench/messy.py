"""What real exporters write (issue 33): core against Blender's Decimate on messy input.

    .venv/bin/python bench/messy.py [--parts 6] [--ratios 0.25 0.1] [--samples 100000]

Rows, each at every ratio, core and Decimate in this one process on the same triangles:
- generated faults (tests/mesh_builders.py): a UV sphere with flipped caps, a soup of
  duplicate, reversed, zero-area and repeated-corner faces, three sheets on one edge,
  500 bolts of 12 triangles, a sheet with a T-junction slit;
- the ``--parts`` largest meshes of ../shared/assets/2CylinderEngine (a CAD assembly
  exported from a STEP tool) and BoomBox, read by Blender's glTF importer, each mesh once;
- homer.obj and spot.obj from ../shared/meshes (12,000 and 5,856 faces): the organic
  meshes the per-face time is compared with.

Decimate gets the triangles welded (Merge by Distance, as bench/run.py does): unwelded,
it cannot reduce the engine's parts at all. Distances are two-sided, in % of the input's
bounding-box diagonal (addon/pure/measure.py); slivers are faces of quality below 0.3. The
per-face columns are core's time per input face over homer's at the same ratio, and over
that of the organic mesh nearest its size (issue 33 asks for "an organic mesh of similar
size": a pass costs about a millisecond whatever its size, so a small mesh's time per
face is higher however clean; spot's is about 1.4x homer's). Prints a markdown table with
the processor it ran on; docs/method.md quotes it.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import bpy
import numpy as np

import core
from addon.pure.measure import mesh_report
from blender_reference import _clear_scene, decimate, load_mesh, mesh_arrays, stdout_to_stderr
from run import environment, welded

sys.path.insert(0, str(_bootstrap.REPO_ROOT / "tests"))
import mesh_builders as build  # noqa: E402  (the tests' generators: one definition of each fault)

ASSETS = _bootstrap.REPO_ROOT.parent / "shared" / "assets"
GENERATED = {
    "sphere, flipped caps": lambda: build.flipped_caps()[:2],
    "bad-face soup": lambda: build.with_bad_faces(*build.icosphere(3))[:2],
    "three sheets on an edge": build.three_sheets,
    "500 bolts": build.bolts,
    "T-junction slit": build.t_junction_slit,
}


def gltf_meshes(path: Path) -> list:
    """(name, V, F) of every mesh datablock of a glTF file as Blender imports it, each
    once however many objects use it (in its own coordinates)."""
    _clear_scene()
    with stdout_to_stderr():
        bpy.ops.import_scene.gltf(filepath=str(path))
    meshes = {ob.data.name: ob.data for ob in bpy.data.objects if ob.type == "MESH"}
    out = []
    for name, me in meshes.items():
        v, f, _, _ = mesh_arrays(me)
        if len(f):
            out.append((name, v, f))
    _clear_scene()
    return out


def inputs(args) -> list:
    cases = [(name, *make()) for name, make in GENERATED.items()]
    engine = ASSETS / "2CylinderEngine" / "2CylinderEngine.gltf"
    if engine.exists():
        parts = sorted(gltf_meshes(engine), key=lambda m: -len(m[2]))[:args.parts]
        cases += [(f"2CylinderEngine {name}", v, f) for name, v, f in parts]
    boombox = ASSETS / "BoomBox" / "BoomBox.gltf"
    if boombox.exists():
        cases += [("BoomBox", *gltf_meshes(boombox)[0][1:])]
    return cases


def measure(name, V, F, ratio, samples) -> dict:
    t0 = time.perf_counter()
    r = core.simplify(V, F, ratio=ratio)
    seconds = time.perf_counter() - t0
    wv, wf, _ = welded(V, F)
    dec = decimate(wv, wf, ratio * len(F) / len(wf))  # the same target count
    ours = mesh_report(V, F, r.vertices, r.faces, n_samples=samples)
    theirs = mesh_report(V, F, dec.vertices, dec.faces, n_samples=samples)
    return {"input": name, "faces": len(F), "ratio": ratio, "target": r.stats.target_faces,
            "core": len(r.faces), "stop": r.stats.stop_reason, "seconds": seconds,
            "decimate": len(dec.faces), "decimate_seconds": dec.seconds,
            "hausdorff": (ours["hausdorff_percent"], theirs["hausdorff_percent"]),
            "mean": (ours["mean_percent"], theirs["mean_percent"]),
            "slivers": (ours["sliver_percent"], theirs["sliver_percent"])}


ORGANIC = ("homer.obj", "spot.obj")  # the first is the per-face column's divisor everywhere


def nearest_in_size(faces: int, baselines: dict) -> str:
    """The organic mesh (a key of ``baselines``: {name: (faces, {ratio: seconds a face})})
    whose face count is nearest ``faces``, by ratio."""
    return min(baselines, key=lambda name: abs(np.log(baselines[name][0] / faces)))


def table(rows, baselines) -> str:
    head = ("| input | faces | ratio | target | core | stop | core s | per face / homer's | per face / organic "
            "of its size | Decimate | Decimate s | Hausdorff % core / Dec. | mean % core / Dec. | "
            "slivers % core / Dec. |")
    lines = [head, "|" + "---|" * 14]
    first = baselines.get(ORGANIC[0], (0, {}))[1]
    for r in rows:
        per_face = r["seconds"] / r["faces"] / first[r["ratio"]] if r["ratio"] in first else float("nan")
        sized = "-"
        if baselines:
            name = nearest_in_size(r["faces"], baselines)
            per = baselines[name][1].get(r["ratio"])
            sized = f"{r['seconds'] / r['faces'] / per:.2f}x ({Path(name).stem})" if per else "-"

        def pair(key, spec):
            ours, theirs = r[key]
            ratio = f" ({ours / theirs:.2f}x)" if theirs > 0 else ""
            return f"{ours:{spec}} / {theirs:{spec}}{ratio}"
        lines.append(f"| {r['input']} | {r['faces']:,} | {r['ratio']:g} | {r['target']:,} | {r['core']:,} | "
                     f"{r['stop']} | {r['seconds']:.3f} | {per_face:.2f}x | {sized} | {r['decimate']:,} | "
                     f"{r['decimate_seconds']:.3f} | {pair('hausdorff', '.3f')} | {pair('mean', '.4f')} | "
                     f"{pair('slivers', '.1f')} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--parts", type=int, default=6, help="the engine's largest meshes to run (default 6)")
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.25, 0.1])
    ap.add_argument("--samples", type=int, default=100_000, help="area-uniform samples per surface")
    args = ap.parse_args(argv)
    env = environment()
    baselines = {}  # {name: (faces, {ratio: seconds a face})}
    rows = []
    for name in ORGANIC:
        path = _bootstrap.DEFAULT_MESH_DIR / name
        if not path.exists():
            continue
        mesh = load_mesh(path)
        baselines[name] = (len(mesh.faces), {})
        for ratio in args.ratios:
            core.simplify(mesh.vertices, mesh.faces, ratio=ratio)  # warm
            row = measure(f"{name} (organic baseline)", mesh.vertices, mesh.faces, ratio, args.samples)
            baselines[name][1][ratio] = row["seconds"] / row["faces"]
            rows.append(row)
    for name, V, F in inputs(args):
        print(name, file=sys.stderr, flush=True)
        for ratio in args.ratios:
            rows.append(measure(name, V, F, ratio, args.samples))
    print(f"{env['cpu']}, {env['cpu_count']} cores; Blender {env['blender']}, NumPy {env['numpy']}; "
          f"commit {env['commit']}\n")
    print(table(rows, baselines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
