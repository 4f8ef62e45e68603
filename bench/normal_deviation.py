"""Do LODs shade like their source? Shading-normal deviation on real meshes (issue 22 §3),
ours against Blender's Decimate.

    .venv/bin/python bench/normal_deviation.py [MESH ...] [--ratios 0.5 0.25 0.1]
        [--samples 200000] [--case MESH:SHADING ...]

Each case is a mesh of ../shared/meshes (default: every one, shaded smooth; plus
fandisk.obj by angle and with Weighted Normal, spot.obj with Weighted Normal and the
bunny with its normals up) made into a Blender object shaded one way:

* ``smooth``: every face smooth, no sharp edges (the files have no normals of their own);
* ``angle``: Smooth by Angle at 30 degrees (sharp edges marked where faces meet sharper);
* ``weighted``: ``angle``, then a Weighted Normal modifier (Face Area, Keep Sharp)
  applied: custom split normals, as hard-surface game assets are shaded;
* ``up``: smooth, with every custom normal pointing up (+z), as foliage and tree crowns
  are lit.

For each case our add-on makes the LOD chain at the ratios (addon/lod.py, default
settings, custom normals carried), and Blender's Decimate modifier (Collapse,
triangulated) runs on the same object at each ratio, in the same run. Every mesh is read
back through Blender (``corner_normals``: the normals as Blender shades it) and measured
with addon/pure/measure.py's ``normal_deviation``: degrees between the source's shading normal
at area-uniform samples and the LOD's at the closest point; mean / 95th percentile. With
custom normals, the LOD is also measured with them dropped (cleared, so Blender computes
its own from the smooth flags and sharp edges): what carrying them is worth. The report's
own number (normals computed before the mesh exists, mesh_data.shading_normals) is checked
against the measured one; a difference over 0.1 degrees is printed to stderr.
Prints a markdown table.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)

import bpy

from addon import lod as lod_module
from addon.pure import measure
from addon import mesh_io
from blender_reference import load_mesh, mesh_from_arrays, stdout_to_stderr
from tables import header, row

SHADINGS = {
    "smooth": "smooth",
    "angle": "by angle 30°",
    "weighted": "Weighted Normal (custom)",
    "up": "all up (custom)",
}
DEFAULT_EXTRA = (("fandisk.obj", "angle"), ("fandisk.obj", "weighted"), ("spot.obj", "weighted"),
                 ("stanford-bunny.obj", "up"))
HARD_ANGLE = 30.0


def _clear_scene() -> None:
    bpy.ops.wm.read_factory_settings(use_empty=True)


def source_object(path: Path, shading: str):
    mesh = load_mesh(path)
    ob = bpy.data.objects.new(path.stem, mesh_from_arrays(path.stem, mesh.vertices, mesh.faces))
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)
    with stdout_to_stderr():
        if shading in ("smooth", "up"):
            bpy.ops.object.shade_smooth()
        else:
            bpy.ops.object.shade_smooth_by_angle(angle=math.radians(HARD_ANGLE))
        if shading == "up":  # foliage and tree crowns: lit as if facing the sky
            ob.data.normals_split_custom_set([(0.0, 0.0, 1.0)] * len(ob.data.loops))
        if shading == "weighted":
            weighted = ob.modifiers.new("Weighted Normal", 'WEIGHTED_NORMAL')
            weighted.mode = 'FACE_AREA'
            weighted.keep_sharp = True
            bpy.ops.object.modifier_apply(modifier=weighted.name)
    return ob


def shading_of(mesh) -> mesh_io.MeshData:
    return mesh_io.read_mesh(mesh)


def deviation(source: mesh_io.MeshData, lod: mesh_io.MeshData, samples: int) -> dict:
    return measure.normal_deviation(source.vertices, source.faces, source.corner_normals,
                                    lod.vertices, lod.faces, lod.corner_normals, n_samples=samples)


def decimated(ob, ratio: float) -> mesh_io.MeshData:
    """Blender's Decimate (Collapse, triangulated) of ``ob`` as shaded, read back."""
    mod = ob.modifiers.new("Decimate", 'DECIMATE')
    mod.decimate_type = 'COLLAPSE'
    mod.ratio = ratio
    mod.use_collapse_triangulate = True
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
        mesh = bpy.data.meshes.new_from_object(ob.evaluated_get(depsgraph), preserve_all_data_layers=True,
                                               depsgraph=depsgraph)
        try:
            return shading_of(mesh)
        finally:
            bpy.data.meshes.remove(mesh)
    finally:
        ob.modifiers.remove(mod)


def dropped(lod_object) -> mesh_io.MeshData:
    """The LOD with its custom normals cleared: Blender's own from its smooth flags and
    sharp edges."""
    with bpy.context.temp_override(object=lod_object, active_object=lod_object):
        bpy.ops.mesh.customdata_custom_splitnormals_clear()
    return shading_of(lod_object.data)


def _cell(d: dict) -> str:
    return f"{d['normal_mean_degrees']:.2f} / {d['normal_p95_degrees']:.1f}"


def run_case(path: Path, shading: str, ratios: list, samples: int) -> None:
    _clear_scene()
    ob = source_object(path, shading)
    source = shading_of(ob.data)
    custom = ob.data.has_custom_normals
    with stdout_to_stderr():
        report = lod_module.generate_lods(bpy.context, ob, lod_module.LodSettings(ratios=tuple(ratios)))
    for ratio, level in zip(ratios, report["levels"]):
        lod_object = bpy.data.objects[level["name"]]
        ours = deviation(source, shading_of(lod_object.data), samples)
        if abs(ours["normal_mean_degrees"] - level["normal_mean_degrees"]) > 0.1:
            print(f"note: {path.name} {shading} {ratio:g}: the report's normal deviation "
                  f"{level['normal_mean_degrees']:.3f} differs from Blender's normals' {ours['normal_mean_degrees']:.3f}",
                  file=sys.stderr)
        without = _cell(deviation(source, dropped(lod_object), samples)) if custom else "-"
        blender = decimated(ob, ratio)
        theirs = deviation(source, blender, samples)
        print(row(path.name, SHADINGS[shading], f"{ratio:g}", f"{len(source.faces):,}",
                  f"{level['triangles']:,} / {len(blender.faces):,}", _cell(ours), without, _cell(theirs)),
              flush=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("meshes", nargs="*", type=Path, help="meshes shaded smooth (default: all of ../shared/meshes)")
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.5, 0.25, 0.1])
    ap.add_argument("--samples", type=int, default=200_000, help="area samples on the source per measurement")
    ap.add_argument("--case", action="append", default=None, metavar="MESH:SHADING",
                    help=f"a mesh and a shading ({', '.join(SHADINGS)}); replaces the default extra cases")
    args = ap.parse_args(argv)
    meshes = args.meshes or sorted(p for p in _bootstrap.DEFAULT_MESH_DIR.iterdir()
                                   if p.suffix in (".obj", ".gltf", ".glb"))
    cases = [(p, "smooth") for p in meshes]
    if args.case is not None:
        extra = [tuple(c.rsplit(":", 1)) for c in args.case]
    else:
        extra = DEFAULT_EXTRA if not args.meshes else ()
    for name, shading in extra:
        if shading not in SHADINGS:
            ap.error(f"unknown shading {shading!r} (one of {', '.join(SHADINGS)})")
        path = Path(name) if Path(name).exists() else _bootstrap.DEFAULT_MESH_DIR / name
        cases.append((path, shading))
    print(header("mesh", "shading", "ratio", "source triangles", "triangles ours / Decimate",
                 "ours: mean / p95 °", "ours, normals dropped", "Decimate: mean / p95 °"))
    for path, shading in cases:
        run_case(path, shading, args.ratios, args.samples)
    return 0


if __name__ == "__main__":
    sys.exit(main())
