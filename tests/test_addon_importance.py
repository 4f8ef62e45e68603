"""Painted importance on a flat plane (paper Fig. 1 and 5), in real Blender.

A 120 x 120 grid (14,641 vertices, 28,800 triangles) with a painted disc taken to 10 %:
the target is met, the disc keeps clearly more vertices per area than the rest, that
density rises with the strength in both modes, and at moderate strength the disc is
still simplified (soft, not frozen). For contrast, Blender's Decimate with the same vertex group is recorded.
"""
import pytest

from bpy_harness import run_in_blender

SOFT = (0.0, 0.1, 0.25, 0.5, 1.0)
STRONG = (0.1, 0.25, 0.5, 0.75, 1.0)

SNIPPET = r'''
import importlib, math
import numpy as np

lod = importlib.import_module(EXT + ".addon.lod")
R = RESULT
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
bpy.ops.mesh.primitive_grid_add(x_subdivisions=120, y_subdivisions=120, size=2)
ob = bpy.context.active_object
me = ob.data
n = len(me.vertices)
co = np.empty(n * 3, np.float32); me.vertices.foreach_get("co", co); co = co.reshape(-1, 3)
center, radius = np.array([0.3, 0.2]), 0.35
disc_area, rest_area = math.pi * radius ** 2, 4.0 - math.pi * radius ** 2
inside = np.linalg.norm(co[:, :2] - center, axis=1) < radius
ob.vertex_groups.new(name="LOD_Importance").add(np.flatnonzero(inside).tolist(), 1.0, 'REPLACE')
R["input"] = {"vertices": n, "disc_vertices": int(inside.sum())}

def densities(mesh):
    P = np.empty(len(mesh.vertices) * 3, np.float32); mesh.vertices.foreach_get("co", P); P = P.reshape(-1, 3)
    ins = np.linalg.norm(P[:, :2] - center, axis=1) < radius
    return int(ins.sum()), float(ins.sum() / disc_area), float((~ins).sum() / rest_area), len(P)

runs = []
for mode, strengths in (("SOFT", %(soft)r), ("STRONG", %(strong)r)):
    for s in strengths:
        rep = lod.generate_lods(bpy.context, ob, lod.LodSettings(
            ratio=0.1, levels=1, importance_source='VERTEX_GROUP', importance_group="LOD_Importance",
            importance_strength=s, importance_mode=mode, measure_deviation=False))
        L = bpy.data.objects[ob.name + "_LOD1"]
        disc, d_in, d_out, nv = densities(L.data)
        P = np.empty(len(L.data.vertices) * 3, np.float32); L.data.vertices.foreach_get("co", P)
        runs.append({"mode": mode, "strength": s, "triangles": len(L.data.polygons),
                     "target": rep["levels"][0]["target"], "vertices": nv, "disc_vertices": disc,
                     "density_ratio": d_in / d_out, "quality": rep["levels"][0]["mean_quality"],
                     "flat": float(np.abs(P.reshape(-1, 3)[:, 2]).max())})
R["runs"] = runs

# Blender's Decimate with the same group, for contrast (the issue's numbers).
dec = ob.modifiers.new("Decimate", 'DECIMATE')
dec.ratio = 0.1
dec.vertex_group = "LOD_Importance"
contrast = {}
for invert in (False, True):
    dec.invert_vertex_group = invert
    dg = bpy.context.evaluated_depsgraph_get(); dg.update()
    m = ob.evaluated_get(dg).to_mesh()
    disc, d_in, d_out, nv = densities(m)
    contrast["inverted" if invert else "plain"] = {"vertices": nv, "disc_vertices": disc}
    ob.evaluated_get(dg).to_mesh_clear()
ob.modifiers.remove(dec)
R["decimate"] = contrast
''' % {"soft": SOFT, "strong": STRONG}


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_in_blender(SNIPPET, user_dir=blender_user_dir, timeout=600)


def _runs(res, mode):
    return [r for r in res["runs"] if r["mode"] == mode]


def test_target_met_and_plane_stays_flat(res):
    assert res["input"]["vertices"] == 14641
    for run in res["runs"]:
        assert run["target"] == 2880
        assert abs(run["triangles"] - 2880) <= 1
        assert run["flat"] < 1e-6
        assert run["quality"] > 0.7


@pytest.mark.parametrize("mode", ["SOFT", "STRONG"])
def test_painted_region_denser_and_rising_with_strength(res, mode):
    runs = _runs(res, mode)
    ratios = [r["density_ratio"] for r in runs]
    # Rising with strength until it saturates: Strong at 0.75 and 1 already multiplies
    # the painted error by 178x and 1000x, and the density then levels off (within a
    # tenth of its peak, where the order of the last few collapses decides).
    saturated = [r >= 0.9 * max(ratios) for r in ratios]
    assert all(b > a or (sa and sb) for a, b, sa, sb in zip(ratios, ratios[1:], saturated, saturated[1:])), ratios
    assert ratios[1] > ratios[0] and ratios[-1] >= 0.9 * max(ratios), ratios
    assert ratios[-1] > 5  # clearly denser at full strength
    # Soft, not frozen: at moderate strength the painted disc is simplified too. At full
    # strength its error is 100x (Soft) or 1000x (Strong) the rest's, and the near-greedy
    # order spends the budget outside while the target allows: the disc may then keep
    # nearly all its vertices (measured 92 % Soft, 100 % Strong), as the sequential
    # algorithm would.
    moderate = [r for r in runs if r["strength"] <= 0.25]
    assert all(r["disc_vertices"] < 0.9 * res["input"]["disc_vertices"] for r in moderate)


def test_zero_strength_is_uniform(res):
    zero = _runs(res, "SOFT")[0]
    assert zero["strength"] == 0.0
    assert 0.7 < zero["density_ratio"] < 1.4


def test_decimate_contrast(res):
    # Decimate's vertex group acts as a mask on a flat plane: it stops far above the
    # target, or keeps every painted vertex; ours meets the target with a graded disc.
    plain, inverted = res["decimate"]["plain"], res["decimate"]["inverted"]
    ours = max(r["vertices"] for r in res["runs"])
    assert plain["vertices"] > 5 * ours or inverted["disc_vertices"] == res["input"]["disc_vertices"]
