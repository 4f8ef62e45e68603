"""Calibration of the Importance Strength slider (issue 19): density against strength.

    .venv/bin/python bench/importance_calibration.py [--sweep] [--no-ogre]
        ->  docs/images/importance_calibration.png and the tables of docs/weight-painting.md

Painted importance scales the whole augmented quadric of a vertex by a factor (paper Sec.
4.4.1). What an artist sees is vertex density, so the slider is calibrated on it:

  --sweep  measures the density gain each factor gives (core.simplify, ratio 0.1) on
           the two calibration surfaces below and prints GAIN_TO_FACTOR, the table
           addon/pure/importance.py interpolates (paste it there after a change to the core);
  always   runs the add-on's own mapping (addon.pure.importance.controls) at the slider's
           strengths on both surfaces and prints the curve that docs/weight-painting.md
           shows, then (unless --no-ogre, or the mesh is absent) the default strength on
           a real mesh: ogre.obj with the 15 % of its vertices nearest its top painted.

Calibration surfaces: the issue's setup, a 120 x 120 grid on [-1, 1]^2 (14,641 vertices,
28,800 triangles) with a disc of radius 0.35 at (0.3, 0.2) painted 1 (1,370 vertices),
flat and as a curved sheet z = 0.08 sin(3 pi x) cos(3 pi y) (three bumps a side, so the
plane error dominates the line quadric everywhere). Both taken to 10 % (2,880 triangles).

Density in/out = (fraction of the painted vertices kept) / (fraction of the others kept),
the painted region's vertex density against the rest's relative to the input's (on the
uniform grid: the density inside the disc over that outside). Density gain = density
in/out over that of the same surface simplified without importance (0.93 on the flat
grid, whose preserved border keeps the outside a little denser).
"""
from __future__ import annotations

import argparse

from figures import fig_common as fc  # first: it imports _bootstrap, which must precede bpy
import tables
import bpy  # noqa: F401  (imported early: nothing else may load first, see _bootstrap)
import matplotlib.pyplot as plt
import numpy as np

import core
from addon.pure import importance as imp
from addon.pure import measure
from synthetic_meshes import grid

RATIO = 0.1
CENTER, RADIUS = np.array([0.3, 0.2]), 0.35
SWEEP_FACTORS = (1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 64.0, 128.0, 256.0, 512.0, 1000.0,
                 2000.0, 4000.0, 8000.0)
STRENGTHS = (0.0, 0.1, 0.25, 0.4, 0.5, 0.6, 0.75, 0.9, 1.0)
OGRE_SHARE = 0.15  # of the vertices, nearest the top, painted 1


def former_soft(g, strength):
    """The former Soft mode (before issue 19), for comparison: an added line weight,
    w_i = 0.001 + 0.1 strength g_i (paper Eq. 16), no scaling."""
    w = core.DEFAULT_LINE_WEIGHT
    return {"line_weight": w, "line_weights": w + 0.1 * strength * np.asarray(g)}


def region_quality(res, g) -> float:
    """Mean triangle quality of the LOD triangles whose three vertices came from the region."""
    q = core.triangle_quality(res.vertices, res.faces)
    inside = (g[res.vertex_origin] >= 0.5)[res.faces].all(axis=1)
    return float(q[inside].mean()) if inside.any() else float("nan")


def sheet(curved: bool):
    """The calibration grid (flat or curved) and its painted disc g (0/1 per vertex)."""
    V, F = grid(121, size=2.0, start=-1.0)
    if curved:
        V[:, 2] = 0.08 * np.sin(3 * np.pi * V[:, 0]) * np.cos(3 * np.pi * V[:, 1])
    g = (np.linalg.norm(V[:, :2] - CENTER, axis=1) < RADIUS).astype(np.float64)
    return V, F, g


def kept(res, g) -> tuple:
    """(fraction of painted vertices kept, of the others kept, density gain)."""
    painted = g[res.vertex_origin] >= 0.5
    n_in = np.count_nonzero(g >= 0.5)
    n_out = len(g) - n_in
    k_in, k_out = np.count_nonzero(painted) / n_in, np.count_nonzero(~painted) / n_out
    return k_in, k_out, k_in / k_out


def sweep() -> None:
    """Density gain of each quadric factor on both surfaces -> GAIN_TO_FACTOR."""
    rows, base = [], {}
    for f in SWEEP_FACTORS:  # starts at 1: the unpainted run each gain is relative to
        gains = []
        for curved in (False, True):
            V, F, g = sheet(curved)
            res = core.simplify(V, F, ratio=RATIO, line_weight=core.DEFAULT_LINE_WEIGHT,
                                quadric_scale=1.0 + (f - 1.0) * g, line_scale_exponent=imp.LINE_SCALE_EXPONENT)
            in_out = kept(res, g)[2]
            base.setdefault(curved, in_out)
            gains.append(in_out / base[curved])
        rows.append((f, *gains, float(np.sqrt(gains[0] * gains[1]))))
        fc.log(f"factor {f:g}: gain flat {gains[0]:.2f}, curved {gains[1]:.2f}")
    print(tables.header("quadric factor", "gain, flat", "gain, curved", "geometric mean"))
    for f, a, b, m in rows:
        print(tables.row(f"{f:g}", f"{a:.2f}", f"{b:.2f}", f"{m:.2f}"))
    # The table addon/pure/importance.py interpolates: strictly rising in the gain, so a
    # non-monotone measurement (noise of the last collapses) is dropped, not pasted.
    table, best = [], 0.0
    for f, _, _, m in rows:
        if m > best:
            table.append((round(m, 2), f))
            best = m
    print("GAIN_TO_FACTOR = (" + ", ".join(f"({m:g}, {f:g})" for m, f in table) + ")")


def curve(mapping=None, strengths=STRENGTHS) -> list:
    """A strength mapping (the add-on's by default) at the slider's strengths on both surfaces."""
    mapping = mapping or (lambda g, s: imp.controls(g, core.DEFAULT_LINE_WEIGHT, s))
    runs = []
    for curved in (False, True):
        V, F, g = sheet(curved)
        base = kept(core.simplify(V, F, ratio=RATIO, line_weight=core.DEFAULT_LINE_WEIGHT), g)[2]
        for s in strengths:
            res = core.simplify(V, F, ratio=RATIO, **mapping(g, s))
            k_in, k_out, in_out = kept(res, g)
            runs.append(dict(surface="curved" if curved else "flat", strength=s, triangles=len(res.faces),
                             target=int(round(RATIO * len(F))), kept_in=k_in, kept_out=k_out, in_out=in_out,
                             gain=in_out / base, expected=imp.expected_gain(s), quality=region_quality(res, g)))
    return runs


def ogre_check() -> None:
    """The default strength on a real curved mesh: the painted region's share of vertices
    kept and its mean distance to the LOD, against the unpainted run at the same count."""
    path = fc.find_mesh("ogre")
    if path is None:
        fc.log("ogre.obj not found in ../shared/meshes: real-mesh check skipped")
        return
    from blender_reference import load_mesh

    m = load_mesh(path)
    V, F = m.vertices, m.faces
    up = int(np.argmax(np.ptp(V, axis=0)))  # the tall axis (y in the file)
    top = V[np.argmax(V[:, up])]
    g = np.zeros(len(V))
    g[np.argsort(np.linalg.norm(V - top, axis=1))[:int(round(OGRE_SHARE * len(V)))]] = 1.0
    # Mean distance from the painted region of the input (area samples) to the LOD.
    region = F[(g[F] > 0).all(axis=1)]
    points = measure.sample_surface(V, region, 100_000, np.random.default_rng(0))
    rows = []
    w = core.DEFAULT_LINE_WEIGHT
    for label, opts in (("no importance", {"line_weight": w}),
                        ("strength 0.25", imp.controls(g, w, 0.25)),
                        (f"default strength {imp.DEFAULT_STRENGTH:g}", imp.controls(g, w, imp.DEFAULT_STRENGTH)),
                        ("strength 0.75", imp.controls(g, w, 0.75)),
                        ("former Soft, strength 1 (its default)", former_soft(g, 1.0))):
        res = core.simplify(V, F, ratio=RATIO, **opts)
        k_in, k_out, in_out = kept(res, g)
        tree = measure._build_tree(res.vertices, res.faces)
        rows.append((label, len(res.faces), int(round(k_in * g.sum())), k_in, in_out,
                     float(measure._distances(tree, points).mean()), region_quality(res, g)))
    base = rows[0]
    print(f"ogre.obj ({len(F):,} triangles) at {RATIO:.0%}, the {int(g.sum()):,} vertices nearest its top painted "
          f"(region mean distance: from area samples of the painted input surface to the LOD):")
    print(tables.header(
        "run", "triangles", "region vertices kept", "density gain", "region mean distance", "region mean q"))
    for label, tris, n_kept, k_in, gain, dist, q in rows:
        print(tables.row(label, f"{tris:,}", f"{n_kept:,} ({k_in:.0%})", f"{gain / base[4]:.2f}x",
                         f"{dist / base[5]:.2f}x", f"{q:.3f}"))


def ogre_operator_check() -> None:
    """The issue's own check, through the add-on (addon.lod.generate_lods, every other
    setting at its default: seams, sharp edges, boundaries kept): ogre.obj imported as a
    user would (Blender's OBJ importer, Y up -> Z up), the 15 % of its vertices nearest
    its top in the group LOD_Importance, 10 %, without importance and at the default."""
    path = fc.find_mesh("ogre")
    if path is None:
        fc.log("ogre.obj not found in ../shared/meshes: operator check skipped")
        return
    from addon import lod
    from addon.pure.settings import LodSettings
    from blender_reference import mesh_arrays, stdout_to_stderr

    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    with stdout_to_stderr():
        bpy.ops.wm.obj_import(filepath=str(path))
    ob = next(o for o in bpy.data.objects if o.type == 'MESH')
    V, F, _, _ = mesh_arrays(ob.data)
    top = V[np.argmax(V[:, 2])]
    g = np.zeros(len(V))
    g[np.argsort(np.linalg.norm(V - top, axis=1))[:int(round(OGRE_SHARE * len(V)))]] = 1.0
    ob.vertex_groups.new(name="LOD_Importance").add(np.flatnonzero(g).tolist(), 1.0, 'REPLACE')
    points = measure.sample_surface(V, F[(g[F] > 0).all(axis=1)], 100_000, np.random.default_rng(0))
    rows = []
    for label, source in (("no importance", 'NONE'), (f"default strength {imp.DEFAULT_STRENGTH:g}", 'VERTEX_GROUP')):
        rep = lod.generate_lods(bpy.context, ob, LodSettings(
            ratio=RATIO, levels=1, importance_source=source, importance_group="LOD_Importance",
            measure_deviation=False))
        L = bpy.data.objects[rep["levels"][0]["name"]]
        Lv, Lf, _, _ = mesh_arrays(L.data)
        # Region vertices kept, by position: LOD vertices within the painted region's
        # reach (nearest input vertex painted).
        from mathutils.kdtree import KDTree

        kd = KDTree(len(V))
        for i, co in enumerate(V.tolist()):
            kd.insert(co, i)
        kd.balance()
        near = np.array([kd.find(co)[1] for co in Lv.tolist()])
        tree = measure._build_tree(Lv, Lf)
        rows.append((label, len(Lf), int(g[near].sum()), float(measure._distances(tree, points).mean()),
                     rep["levels"][0].get("importance")))
    base = rows[0]
    print(f"Through the add-on (generate_lods, default settings), ogre.obj imported by Blender, "
          f"{int(g.sum()):,} vertices nearest its top in LOD_Importance, {RATIO:.0%}:")
    print(tables.header(
        "run", "triangles", "region vertices kept", "region mean distance", "report: painted density"))
    for label, tris, n_kept, dist, rep in rows:
        dens = f"{rep['painted_density']:.1f}x" if rep else "-"
        print(tables.row(label, f"{tris:,}", f"{n_kept:,} ({n_kept / g.sum():.0%})", f"{dist / base[3]:.2f}x", dens))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sweep", action="store_true", help="measure gain per quadric factor (the calibration table)")
    ap.add_argument("--no-ogre", action="store_true", help="skip the real-mesh check")
    args = ap.parse_args()
    if args.sweep:
        sweep()
        return
    runs = curve()
    print(tables.header(
        "strength", "expected gain", "flat: in/out", "gain", "disc kept", "curved: in/out", "gain", "disc kept",
        "triangles"))
    flat = [r for r in runs if r["surface"] == "flat"]
    curved = [r for r in runs if r["surface"] == "curved"]
    for a, b in zip(flat, curved):
        print(tables.row(f"{a['strength']:g}", f"{a['expected']:.1f}x", f"{a['in_out']:.2f}", f"{a['gain']:.2f}x",
                         f"{a['kept_in']:.0%}", f"{b['in_out']:.2f}", f"{b['gain']:.2f}x", f"{b['kept_in']:.0%}",
                         f"{a['triangles']:,} / {b['triangles']:,}"))

    # The former Soft mode (an added line weight): its strength meant different densities
    # on flat and curved regions, which is why it went (issue 19).
    soft = curve(former_soft, (0.1, 0.25, 0.5, 1.0))
    print("The former Soft mode (w = 0.001 + 0.1 strength g) on the same surfaces, for comparison:")
    print(tables.header(
        "former Soft strength", "flat: gain", "disc kept", "curved: gain", "disc kept", "flat / curved"))
    half = len(soft) // 2
    for a, b in zip(soft[:half], soft[half:]):
        print(tables.row(f"{a['strength']:g}", f"{a['gain']:.2f}x", f"{a['kept_in']:.0%}", f"{b['gain']:.2f}x",
                         f"{b['kept_in']:.0%}", f"{a['gain'] / b['gain']:.1f}"))

    fig, ax = plt.subplots(figsize=(6.4, 4.2), layout="constrained")
    s = [r["strength"] for r in flat]
    ax.semilogy(s, [r["gain"] for r in flat], "o-", label="flat grid, painted disc")
    ax.semilogy(s, [r["gain"] for r in curved], "s-", label="curved sheet, painted disc")
    ax.semilogy(s, [r["expected"] for r in flat], "k--", lw=1, label="expected (the slider's calibration)")
    ss = [r["strength"] for r in soft[:half]]
    ax.semilogy(ss, [r["gain"] for r in soft[:half]], "o:", color="C0", alpha=0.5, label="former Soft mode, flat")
    ax.semilogy(ss, [r["gain"] for r in soft[half:]], "s:", color="C1", alpha=0.5, label="former Soft mode, curved")
    ax.axvline(imp.DEFAULT_STRENGTH, color="gray", lw=0.8, ls=":")
    ax.set_xlabel("Importance strength")
    ax.set_ylabel("vertex density, painted / rest (relative to input)")
    ax.set_title(f"Painted importance at {RATIO:.0%}: density against strength", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fc.save(fig, "importance_calibration.png")
    if not args.no_ogre:
        ogre_check()
        ogre_operator_check()


if __name__ == "__main__":
    main()
