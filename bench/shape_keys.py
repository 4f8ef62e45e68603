"""Shape keys (issue 34): each key's deviation at 25 % with Source Shape Keys against
without importance, and what it costs at rest. Distances, not time.

    .venv/bin/python bench/shape_keys.py [--ratio 0.25] [--strength 0.5 ...] [--samples 100000]

Two inputs, each simplified through the add-on (lod.prepare + lod.compute, the panel's
defaults but the source and the chain):
  * the face parts of ../shared/assets/RobotExpressive.glb that carry its morph targets
    (Angry, Surprised, Sad), imported with Blender's glTF importer, each part its own chain;
  * a generated face built here: an icosphere "head" (20,480 triangles) with a nose, eye
    sockets, a brow and a mouth groove, and two keys, Blink (the lids close: the sockets
    fill and a narrow lid ridge forms across each eye) and Smile (the mouth corners pulled
    up and back, the cheeks raised, the nasolabial folds deepened).
For each run, each key: the LOD with the key at 1 against the source with the key at 1
(key_deviation.key_offsets, as the report does), two-sided mean and Hausdorff in % of the
rest source's bounding-box diagonal, ``--samples`` area samples per surface (vertices on
top); and the rest pose likewise. Ratios are Shape Keys over none (below 1 = closer).
Prints markdown tables and the processor; docs/benchmarks.md quotes them.
"""
from __future__ import annotations

import argparse

import _bootstrap  # noqa: F401  (path + isolated user dirs)
import numpy as np

import bpy

from addon import job as job_mod
from addon import key_deviation, lod, measure
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


def robot_parts() -> list:
    scene_files.reset_scene()
    with scene_files.blender_output(False):
        bpy.ops.import_scene.gltf(filepath=str(ROBOT))
    return [ob for ob in bpy.context.scene.objects
            if ob.type == 'MESH' and ob.data.shape_keys is not None and len(ob.data.shape_keys.key_blocks) > 1]


def simplify(ob, ratio: float, source: str, strength: float):
    settings = lod.LodSettings(ratios=(ratio,), importance_source=source, importance_strength=strength,
                               measure_deviation=False)
    out = lod.compute(lod.prepare(bpy.context, ob, settings))
    return out.input.data, out.levels[0]


REGION = 0.05  # a key's region: the triangles with a vertex it moves by 5 % of its largest offset or more


def _region_mean(v_a, f_a, moved_a, v_b, f_b, samples: int) -> float:
    """Mean distance from area samples of surface a's triangles in ``moved_a`` (a mask) to surface b."""
    points, _, _ = measure._sample_surface(v_a, f_a[moved_a], samples, np.random.default_rng(SEED))
    return float(measure._distances(measure._build_tree(v_b, f_b), points).mean())


def distances(data, level, samples: int, g_source=None) -> dict:
    """{"rest" or key name: (mean %, Hausdorff %, keyed-region mean %)} of ``level`` against
    ``data``. The keyed-region mean: both directions' mean distance from the samples on the
    triangles the key moves (for rest: those any key moves) only."""
    diagonal = measure.bbox_diagonal(data.vertices, data.faces)
    src, dst = key_deviation.offsets_of(data), key_deviation.offsets_of(level)
    shapes = [("rest", np.zeros_like(data.vertices), np.zeros_like(level.vertices), src, dst)]
    shapes += [(sk.name, src[k], dst[k], src[k:k + 1], dst[k:k + 1]) for k, sk in enumerate(data.shape_keys)]
    out = {}
    for name, a, b, ka, kb in shapes:
        va, vb = data.vertices + a, level.vertices + b
        d = measure.surface_deviation(va, data.faces, vb, level.faces, n_samples=samples, seed=SEED)
        ma, mb = np.linalg.norm(ka, axis=2).max(0), np.linalg.norm(kb, axis=2).max(0)
        top = max(ma.max(), 1e-30)
        in_a, in_b = (ma >= REGION * top)[data.faces].any(1), (mb >= REGION * top)[level.faces].any(1)
        region = float("nan")
        if in_a.any() and in_b.any():
            region = 0.5 * (_region_mean(va, data.faces, in_a, vb, level.faces, samples)
                            + _region_mean(vb, level.faces, in_b, va, data.faces, samples))
        out[name] = (100.0 * d["mean"] / diagonal, 100.0 * d["hausdorff"] / diagonal, 100.0 * region / diagonal)
    return out


def simplify_asset(objects, ratio: float, source: str, strength: float) -> tuple:
    """``objects`` as one asset (LodJob: the budget split over them by error), each with
    ``source``: (source, LOD) as one mesh in world space, each carrying the keys by name."""
    settings = lod.LodSettings(ratios=(ratio,), importance_source=source, importance_strength=strength,
                               measure_deviation=False)
    job = job_mod.LodJob(bpy.context, objects, settings)
    job.run()
    return (_world([out.input.data for out in job.object_outputs], objects),
            _world([out.levels[0] for out in job.object_outputs], objects))


def _world(parts: list, objects: list):
    """The MeshData ``parts`` of ``objects`` as one MeshData in world space (keys by name)."""
    from addon import mesh_io

    names = list(dict.fromkeys(sk.name for data in parts for sk in data.shape_keys))
    verts, faces, keys, start = [], [], [[] for _ in names], 0
    for data, ob in zip(parts, objects):
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
    """Share of the source's vertices that Source Shape Keys gives importance >= 0.5."""
    from addon import importance

    return float(np.mean(importance.shape_key_importance(key_deviation.offsets_of(data)) >= 0.5))


SUMMARY = []  # (mesh, strength, keys' ratios (mean, Hausdorff, region), rest's): the closing table


def bench(label: str, ob, ratio: float, strengths: list, samples: int) -> list:
    """``ob`` (a mesh object, or a list of them: one asset) without importance and with
    Source Shape Keys at each strength: the table's rows (and a SUMMARY entry per strength)."""
    run = (lambda source, s: simplify_asset(ob, ratio, source, s)) if isinstance(ob, list) else \
        (lambda source, s: simplify(ob, ratio, source, s))
    data, plain = run('NONE', 0.5)
    base = distances(data, plain, samples)
    rows = []
    for strength in strengths:
        _, keyed = run('SHAPE_KEYS', strength)
        ours = distances(data, keyed, samples)
        keys = [name for name in base if name != "rest"]
        for name in base:
            (m0, h0, r0), (m1, h1, r1) = base[name], ours[name]
            rows.append(row(label, f"{len(data.faces):,} → {len(keyed.faces):,}", f"{keyed_share(data):.0%}",
                            f"{strength:g}", name, f"{m0:.4f}", f"{m1:.4f}", _ratio(m1, m0),
                            f"{r0:.4f}", f"{r1:.4f}", _ratio(r1, r0), f"{h0:.3f}", f"{h1:.3f}", _ratio(h1, h0)))
        if keys:
            means = [_geomean([ours[n][i] / base[n][i] for n in keys if base[n][i] > 0]) for i in range(3)]
            rows.append(row(label, "", "", f"{strength:g}", "**keys, geometric mean**", "", "",
                            f"**{means[0]:.2f}x**", "", "", f"**{means[2]:.2f}x**", "", "", f"**{means[1]:.2f}x**"))
            SUMMARY.append((label, strength, means, [ours["rest"][i] / base["rest"][i] for i in range(3)]))
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
    args = parser.parse_args()
    print(f"Processor: {processor()}; bpy {bpy.app.version_string}; ratio {args.ratio:g}; two-sided mean and "
          f"Hausdorff in % of the rest source's diagonal, {args.samples:,} area samples per surface\n")
    print(header("mesh", "triangles", "keyed (g >= 0.5)", "strength", "shape", "mean: none", "Shape Keys",
                 "ratio", "keyed region mean: none", "Shape Keys", "ratio", "Hausdorff: none", "Shape Keys", "ratio"))
    scene_files.reset_scene()
    for line in bench("generated face", face_object(), args.ratio, args.strength, args.samples):
        print(line, flush=True)
    if not args.no_robot:
        if not ROBOT.is_file():
            print(f"(skipped {ROBOT}: not found)")
            return
        parts = robot_parts()
        for ob in parts:
            if not np.any(key_deviation.offsets_of(lod.prepare(bpy.context, ob, lod.LodSettings()).data)):
                print(row(f"RobotExpressive {ob.name}", f"{len(ob.data.loop_triangles):,}", "0%", "", "its keys "
                          "move nothing: the same LOD either way", *[""] * 9), flush=True)
                continue
            for line in bench(f"RobotExpressive {ob.name}", ob, args.ratio, args.strength, args.samples):
                print(line, flush=True)
        names = " + ".join(ob.name for ob in parts)
        for line in bench(f"RobotExpressive head ({names}, one asset)", parts, args.ratio, args.strength,
                          args.samples):
            print(line, flush=True)
    print("\nSummary: Shape Keys over no importance (geometric mean over the keys; below 1 = closer)\n")
    print(header("mesh", "strength", "keys: mean", "keyed region mean", "Hausdorff", "rest: mean",
                 "keyed region mean", "Hausdorff"))
    for label, strength, keys, rest in SUMMARY:
        print(row(label, f"{strength:g}", *[f"{keys[i]:.2f}x" for i in (0, 2, 1)],
                  *[f"{rest[i]:.2f}x" for i in (0, 2, 1)]))


if __name__ == "__main__":
    main()
