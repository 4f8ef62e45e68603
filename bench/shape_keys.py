"""Shape keys (issue 34): each key's deviation at 25 % with Source Shape Keys against
without importance, and what it costs at rest. Distances, not time.

    .venv/bin/python bench/shape_keys.py [--ratio 0.25] [--strength 0.5 ...] [--samples 100000]
                                         [--only face eyes head4 robot] [--keys-as-rest]

Inputs, each simplified through the add-on (lod.prepare + lod.compute, or LodJob for an
asset, the panel's defaults but the source and the chain):
  * a generated face built here: an icosphere "head" (20,480 triangles) with a nose, eye
    sockets, a brow and a mouth groove, and two keys, Blink (the lids close: the sockets
    fill and a narrow lid ridge forms across each eye) and Smile (the mouth corners pulled
    up and back, the cheeks raised, the nasolabial folds deepened);
  * the same face with two eyeballs (5,120 triangles each) that Blink shifts by 1 % of its
    largest motion, as one asset: once with each mesh's own reference for the keys'
    motion (job.ASSET_KEY_REFERENCE off), once with the asset's;
  * RobotExpressive's face plate Head_4 (../shared/assets/RobotExpressive.glb, imported
    with Blender's glTF importer), the one part its morph targets (Angry, Surprised, Sad)
    move: every key moves all of it;
  * the whole robot as the command line takes an input: every mesh object as one asset,
    --from-shape-keys (Source Shape Keys on the objects with keys, none on the others).
For each run, each key: the LOD with the key at 1 against the source with the key at 1
(key_deviation.key_offsets, as the report does), two-sided mean and Hausdorff in % of the
rest source's bounding-box diagonal, ``--samples`` area samples per surface (vertices on
top), over the whole surface and over the key's region both ways, as the report measures
it (key_deviation.key_region, measure.region_deviation); the rest pose
likewise, its region every key's together. An asset is measured as one mesh in world
space. Ratios are Shape Keys over none (below 1 = closer). ``--keys-as-rest``: the keys'
own error counts as the rest's (importance.KEY_WEIGHT_PER_STRENGTH 0), as before the
keys' weight. Prints markdown tables and the processor; docs/benchmarks.md quotes them.
"""
from __future__ import annotations

import argparse

import _bootstrap  # noqa: F401  (path + isolated user dirs)
import numpy as np

import bpy

from addon import job as job_mod
from addon.pure import key_deviation, measure
from addon import lod
from addon.headless import scene_files
from assets import processor
from tables import header, row

ROBOT = _bootstrap.REPO_ROOT.parent / "shared" / "assets" / "RobotExpressive.glb"
SEED = 3


# ----------------------------------------------------------------------------- the generated face


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _bump(p, centre, sigma):
    """A Gaussian of the distance on the unit sphere around ``centre``."""
    d2 = np.sum((p - _unit(np.asarray(centre, dtype=np.float64))) ** 2, axis=1)
    return np.exp(-d2 / (2.0 * sigma ** 2))


def _band(p, centre, sigma_x, sigma_z):
    """An elongated Gaussian: widths along x and z around ``centre`` (front of the head)."""
    c = _unit(np.asarray(centre, dtype=np.float64))
    dx, dz = p[:, 0] - c[0], p[:, 2] - c[2]
    return np.exp(-dx ** 2 / (2 * sigma_x ** 2) - dz ** 2 / (2 * sigma_z ** 2)) * (p[:, 1] < 0)


def _segment_ridge(p, a, b, sigma):
    """A ridge along the segment a-b (points of the unit sphere's front), Gaussian across."""
    a, b = _unit(np.asarray(a, dtype=np.float64)), _unit(np.asarray(b, dtype=np.float64))
    ab = b - a
    t = np.clip((p - a) @ ab / (ab @ ab), 0.0, 1.0)
    d2 = np.sum((p - (a + t[:, None] * ab)) ** 2, axis=1)
    return np.exp(-d2 / (2 * sigma ** 2))


EYES = ((0.33, -0.85, 0.22), (-0.33, -0.85, 0.22))
CORNERS = ((0.24, -0.9, -0.36), (-0.24, -0.9, -0.36))
SCALE = np.array([0.85, 0.95, 1.15])  # the sphere made head-shaped


def face_object(subdivisions: int = 6):
    """The generated face: a mesh object with the keys Blink and Smile."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=subdivisions, radius=1.0)
    ob = bpy.context.active_object
    ob.name = ob.data.name = "Face"
    n = len(ob.data.vertices)
    co = np.empty(3 * n, np.float32)
    ob.data.vertices.foreach_get("co", co)
    p = _unit(co.reshape(n, 3).astype(np.float64))
    rest = (0.12 * _bump(p, (0, -1, 0.0), 0.11)
            - 0.06 * sum(_bump(p, e, 0.09) for e in EYES)
            + 0.03 * sum(_band(p, (e[0], e[1], e[2] + 0.14), 0.12, 0.035) for e in EYES)
            - 0.025 * _band(p, (0, -0.93, -0.36), 0.2, 0.03))
    blink = sum(0.06 * _bump(p, e, 0.09) + 0.025 * _band(p, (e[0], e[1], e[2] - 0.01), 0.09, 0.03) for e in EYES)
    smile_radial = sum(-0.03 * _bump(p, c, 0.05) + 0.03 * _bump(p, (c[0] * 1.6, c[1], c[2] + 0.2), 0.09)
                       + 0.02 * _segment_ridge(p, (np.sign(c[0]) * 0.14, -0.95, -0.05), c, 0.035)
                       for c in CORNERS)
    smile_up = sum(0.04 * _bump(p, c, 0.07) for c in CORNERS)

    def place(radial, up=0.0):
        return (p * (1.0 + radial)[:, None] + np.outer(up, [0.0, 0.0, 1.0])) * SCALE

    basis = place(rest)
    ob.data.vertices.foreach_set("co", basis.astype(np.float32).ravel())
    ob.data.update()
    ob.shape_key_add(name="Basis", from_mix=False)
    for name, shape in (("Blink", place(rest + blink)), ("Smile", place(rest + smile_radial, smile_up))):
        key = ob.shape_key_add(name=name, from_mix=False)
        key.data.foreach_set("co", shape.astype(np.float32).ravel())
    return ob


# ----------------------------------------------------------------------------- the runs


def eyes(face, share: float = 0.01) -> list:
    """Two eyeballs inside the generated face's sockets (5,120 triangles each) that its key
    Blink shifts by ``share`` of the blink's largest motion: a part the keys barely move,
    as a glTF primitive gets every morph target of its mesh with near-zero deltas."""
    offsets = key_deviation.offsets_of(lod.prepare(bpy.context, face, lod.LodSettings()).data)
    names = [kb.name for kb in face.data.shape_keys.key_blocks[1:]]
    blink = np.linalg.norm(offsets[names.index("Blink")], axis=1).max()
    out = []
    for i, e in enumerate(EYES):
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=4, radius=0.12,
                                              location=tuple(np.asarray(e) * 0.7 * SCALE))
        ob = bpy.context.active_object
        ob.name = ob.data.name = f"Eye{i}"
        n = len(ob.data.vertices)
        co = np.empty(3 * n, np.float32)
        ob.data.vertices.foreach_get("co", co)
        ob.shape_key_add(name="Basis", from_mix=False)
        moved = co.reshape(n, 3) + np.array([0.0, 0.0, -share * blink], np.float32)
        ob.shape_key_add(name="Blink", from_mix=False).data.foreach_set("co", moved.ravel())
        ob.shape_key_add(name="Smile", from_mix=False)
        out.append(ob)
    return out


def robot_objects() -> list:
    """RobotExpressive's objects as the command line takes an input's: every mesh object
    that is not a rig widget (headless/sources.select_objects)."""
    from addon.headless import sources

    scene_files.reset_scene()
    with scene_files.blender_output(False):
        bpy.ops.import_scene.gltf(filepath=str(ROBOT))
    objects, _ = sources.select_objects(bpy.context.scene, None)
    return objects


def keyed(objects: list) -> list:
    return [ob for ob in objects if ob.data.shape_keys is not None and len(ob.data.shape_keys.key_blocks) > 1]


def settings_for(ob, ratio: float, source: str, strength: float) -> lod.LodSettings:
    """The panel's defaults but the chain and the source; as the command line's
    --from-shape-keys, Source Shape Keys only on an object with keys (sources.importance_choice)."""
    has_keys = ob.data.shape_keys is not None and len(ob.data.shape_keys.key_blocks) > 1
    return lod.LodSettings(ratios=(ratio,), importance_source=source if has_keys else 'NONE',
                           importance_strength=strength, measure_deviation=False)


def simplify(ob, ratio: float, source: str, strength: float):
    out = lod.compute(lod.prepare(bpy.context, ob, settings_for(ob, ratio, source, strength)))
    return out.input.data, out.levels[0]


def distances(data, level, samples: int) -> dict:
    """{"rest" or key name: (mean %, Hausdorff %, region mean %, region Hausdorff %)} of
    ``level`` against ``data``, each with the key at 1, as the report measures them
    (key_deviation.py: the key's region both ways, measure.region_deviation); for rest,
    the region is every key's together."""
    diagonal = measure.bbox_diagonal(data.vertices, data.faces)
    src, dst = key_deviation.offsets_of(data), key_deviation.offsets_of(level)
    regions = [key_deviation.key_region(src[k], data.faces) for k in range(len(src))]
    union = np.any(regions, axis=0) if regions else np.zeros(len(data.faces), dtype=bool)
    shapes = [("rest", np.zeros_like(data.vertices), np.zeros_like(level.vertices), union)]
    shapes += [(sk.name, src[k], dst[k], regions[k]) for k, sk in enumerate(data.shape_keys)]
    out = {}
    for name, a, b, region in shapes:
        d = measure.surface_deviation(data.vertices + a, data.faces, level.vertices + b, level.faces,
                                      n_samples=samples, seed=SEED, keep_samples=True)
        d.update(measure.region_deviation(d.pop("sampled"), data.faces, region))
        out[name] = tuple(100.0 * d[key] / diagonal for key in ("mean", "hausdorff", "region_mean",
                                                                 "region_hausdorff"))
    return out


def simplify_asset(objects, ratio: float, source: str, strength: float) -> tuple:
    """``objects`` as one asset (LodJob, as the command line runs an input: the budget split
    over them by error, Source Shape Keys on those with keys): (source, LOD) as one mesh
    in world space, each carrying the keys by name."""
    job = job_mod.LodJob(bpy.context, objects, [settings_for(ob, ratio, source, strength) for ob in objects])
    job.run()
    return (_world([out.input.data for out in job.object_outputs], objects),
            _world([out.levels[0] if out.levels else None for out in job.object_outputs], objects))


def _world(parts: list, objects: list):
    """The MeshData ``parts`` of ``objects`` (None: a part the asset's split removed) as
    one MeshData in world space (keys by name)."""
    from addon import mesh_io

    pairs = [(data, ob) for data, ob in zip(parts, objects) if data is not None]
    names = list(dict.fromkeys(sk.name for data, _ in pairs for sk in data.shape_keys))
    verts, faces, keys, start = [], [], [[] for _ in names], 0
    for data, ob in pairs:
        mat = np.array(ob.matrix_world)
        verts.append(data.vertices @ mat[:3, :3].T + mat[:3, 3])
        faces.append(data.faces + start)
        start += len(data.vertices)
        offsets = dict(zip([sk.name for sk in data.shape_keys], key_deviation.offsets_of(data)))
        for k, name in enumerate(names):
            keys[k].append(offsets[name] @ mat[:3, :3].T if name in offsets else np.zeros_like(data.vertices))
    v = np.concatenate(verts)
    return mesh_io.MeshData(vertices=v, faces=np.concatenate(faces), material_index=np.zeros(0),
                            smooth=np.zeros(0), smooth_group=np.zeros(0),
                            shape_keys=[mesh_io.ShapeKeyData(name, np.concatenate(k)) for name, k in zip(names, keys)])


def keyed_share(data) -> float:
    """Share of the source's vertices that Source Shape Keys gives importance >= 0.5 (one
    reference over the whole mesh: for an asset, the asset's)."""
    from addon.pure import importance

    return float(np.mean(importance.shape_key_importance(key_deviation.offsets_of(data)) >= 0.5))


SUMMARY = []  # (mesh, strength, keys' ratios (mean, Hausdorff, region mean, region Hausdorff), rest's)
COLUMNS = ("mean", "Hausdorff", "region mean", "region Hausdorff")


def bench(label: str, ob, ratio: float, strengths: list, samples: int, baseline: dict = None) -> list:
    """``ob`` (a mesh object, or a list of them: one asset) without importance and with
    Source Shape Keys at each strength: the table's rows (and a SUMMARY entry per strength).
    ``baseline``: {"data", "plain", "base"} of an earlier run without importance, reused."""
    run = (lambda source, s: simplify_asset(ob, ratio, source, s)) if isinstance(ob, list) else \
        (lambda source, s: simplify(ob, ratio, source, s))
    if baseline is None or not baseline:
        data, plain = run('NONE', 0.5)
        fresh = {"data": data, "plain": plain, "base": distances(data, plain, samples)}
        if baseline is not None:
            baseline.update(fresh)
        baseline = fresh
    data, plain, base = baseline["data"], baseline["plain"], baseline["base"]
    rows = []
    for strength in strengths:
        _, ours_lod = run('SHAPE_KEYS', strength)
        ours = distances(data, ours_lod, samples)
        keys = [name for name in base if name != "rest"]
        for name in base:
            cells = []
            for i in range(4):
                cells += [f"{base[name][i]:.4f}", f"{ours[name][i]:.4f}", _ratio(ours[name][i], base[name][i])]
            rows.append(row(label, f"{len(data.faces):,} → {len(plain.faces):,} / {len(ours_lod.faces):,}",
                            f"{keyed_share(data):.0%}", f"{strength:g}", name, *cells))
        if keys:
            means = [_geomean([ours[n][i] / base[n][i] for n in keys if base[n][i] > 0]) for i in range(4)]
            rest = [ours["rest"][i] / base["rest"][i] if base["rest"][i] > 0 else float("nan") for i in range(4)]
            cells = []
            for i in range(4):
                cells += ["", "", f"**{means[i]:.2f}x**"]
            rows.append(row(label, "", "", f"{strength:g}", "**keys, geometric mean**", *cells))
            SUMMARY.append((label, strength, means, rest))
    return rows


def _ratio(ours, base) -> str:
    return f"{ours / base:.2f}x" if base > 0 and np.isfinite(ours / base) else "-"


def _geomean(values) -> float:
    values = [v for v in values if np.isfinite(v) and v > 0]
    return float(np.exp(np.mean(np.log(values)))) if values else float("nan")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ratio", type=float, default=0.25)
    parser.add_argument("--strength", nargs="+", type=float, default=[0.5],
                        help="Strengths of Source Shape Keys to compare with no importance (default 0.5)")
    parser.add_argument("--samples", type=int, default=100_000, help="area samples per surface and shape")
    parser.add_argument("--no-robot", action="store_true", help="the generated face only")
    parser.add_argument("--only", nargs="+", choices=("face", "eyes", "head4", "robot"),
                        default=("face", "eyes", "head4", "robot"), help="which inputs (default all)")
    parser.add_argument("--keys-as-rest", action="store_true",
                        help="the keys' own error counts as the rest's (no key weight)")
    args = parser.parse_args()
    if args.keys_as_rest:
        from addon.pure import importance

        importance.KEY_WEIGHT_PER_STRENGTH = 0.0
    print(f"Processor: {processor()}; bpy {bpy.app.version_string}; ratio {args.ratio:g}; two-sided mean and "
          f"Hausdorff in % of the rest source's diagonal, {args.samples:,} area samples per surface"
          f"{'; keys counted as the rest' if args.keys_as_rest else ''}\n")
    print(header("mesh", "triangles: source → none / Shape Keys", "keyed (g >= 0.5)", "strength", "shape",
                 *[f"{c}{suffix}" for c in COLUMNS for suffix in (": none", ": Shape Keys", ": ratio")]))
    if {"face", "eyes"} & set(args.only):
        scene_files.reset_scene()
        face = face_object()
        if "face" in args.only:
            for line in bench("generated face", face, args.ratio, args.strength, args.samples):
                print(line, flush=True)
        if "eyes" in args.only:
            # A part the keys barely move: each mesh its own reference against the asset's.
            parts = [face] + eyes(face)
            base = {}
            for shared in (False, True):
                job_mod.ASSET_KEY_REFERENCE = shared
                label = (f"generated face + eyes the blink moves 1 %, one asset, "
                         f"{'asset' if shared else 'mesh'}'s reference")
                for line in bench(label, parts, args.ratio, args.strength, args.samples, base):
                    print(line, flush=True)
            job_mod.ASSET_KEY_REFERENCE = True
    if not args.no_robot and {"head4", "robot"} & set(args.only):
        if not ROBOT.is_file():
            print(f"(skipped {ROBOT}: not found)")
        else:
            objects = robot_objects()
            if "head4" in args.only:
                for ob in keyed(objects):
                    if not np.any(key_deviation.offsets_of(lod.prepare(bpy.context, ob, lod.LodSettings()).data)):
                        continue  # its keys move nothing: the same LOD either way
                    for line in bench(f"RobotExpressive {ob.name}", ob, args.ratio, args.strength, args.samples):
                        print(line, flush=True)
            if "robot" in args.only:
                label = f"RobotExpressive, {len(objects)} objects as one asset"
                for line in bench(label, objects, args.ratio, args.strength, args.samples):
                    print(line, flush=True)
    print("\nSummary: Shape Keys over no importance (keys: geometric mean over the keys; below 1 = closer)\n")
    print(header("mesh", "strength", *[f"keys: {c}" for c in COLUMNS], *[f"rest: {c}" for c in COLUMNS]))
    for label, strength, keys, rest in SUMMARY:
        print(row(label, f"{strength:g}", *[f"{x:.2f}x" for x in keys], *[f"{x:.2f}x" for x in rest]))


if __name__ == "__main__":
    main()
