"""LODs shade like their source (issue 22 §3): custom split normals are carried to every
LOD corner, whatever they are (normals pointing up for foliage, flat shading from custom
normals alone), and the report's normal deviation shows it: small with them carried,
large with them dropped, and what Blender's own normals of the built LOD measure."""
import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_scenario("addon_custom_normals", user_dir=blender_user_dir, timeout=600)


def test_normals_pointing_up_stay_up(res):
    up = res["up"]
    assert up["has_custom"], "the LOD lost its custom normals"
    assert up["largest_angle"] < 0.5, f"expected every corner normal within 0.5 degree of up, got {up['largest_angle']:.2f}"


def test_flat_shading_from_custom_normals_stays_flat(res):
    flat = res["flat"]
    assert flat["has_custom"], "the LOD lost its custom normals"
    # Normal splits make no seams (core Options.seamless_attributes): a vertex on the cube's
    # edges may slide along them as the sharp edges' planes allow, tilting its triangles
    # by a few hundredths of a degree (0.27 at most measured) against the normals they carry.
    assert flat["mean_angle"] < 0.05 and flat["largest_angle"] < 0.5, flat


def test_hard_edges_mark_the_creases_of_a_mesh_shaded_by_angle(res):
    assert res["hard_0"]["sharp"] == 0, res["hard_0"]  # off: nothing marked
    hard = res["hard_30"]
    assert hard["sharp"] >= 12, f"expected the cube's 12 edges (in segments) marked sharp, got {hard}"
    # Mostly the cube's edges; a few LOD triangles fold across them near the corners, and
    # those folds are creases of the LOD too.
    assert hard["on_cube_edges"] >= 0.8 * hard["sharp"], f"expected mostly the cube's edges sharp: {hard}"



def test_carried_normals_measure_small_and_dropped_ones_clearly_larger(res):
    # The report's normal deviation (measure.normal_deviation at the report's samples):
    # degrees between the source's shading normal and the LOD's at the closest point.
    up, weighted = res["deviation"]["up"], res["deviation"]["weighted"]
    assert up["has_custom"] and weighted["has_custom"]
    assert up["report"][0] < 0.1 and up["report"][1] < 0.5, up
    assert not up["dropped_has_custom"] and up["dropped"][0] > 45.0, up  # the sphere's own normals
    # Weighted Normal shading on a bevelled box: flat sides stay flat with the normals
    # carried; dropped, Blender's smooth normals bend them towards the bevels.
    assert weighted["report"][0] < 1.5, weighted
    assert not weighted["dropped_has_custom"] and weighted["dropped"][0] > 2.5 * weighted["report"][0], weighted


def test_vertices_split_apart_in_the_source_stay_hard_edges(res):
    # Every triangle with its own vertices (an Edge Split at 0 degrees, applied): the
    # source looks faceted with neither sharp edges nor custom normals. The core welds the
    # vertices; the LOD marks the edges between faces of different source regions sharp,
    # so it looks faceted too (it was shaded smooth).
    split = res["deviation"]["split"]
    assert not split["has_custom"] and split["facet_angle"] < 0.1, split


def test_a_sharp_crease_that_ends_inside_its_smoothing_region_stays_sharp(res):
    # Sharp edges along half a meridian of a smooth sphere (8 in the source): they bound no
    # smoothing region, yet the LOD keeps them sharp where the chain survives.
    dangling = res["dangling"]
    assert dangling["source_sharp"] == 8, dangling
    assert dangling["sharp"] >= 3 and dangling["on_meridian"] == dangling["sharp"], dangling


def test_the_report_measures_the_normals_blender_gives_the_lod(res):
    # The report computes the LOD's normals before the mesh exists (carried custom
    # normals, or core.shading.corner_normals from smooth flags and sharp edges); Blender's
    # corner normals of the built LOD must measure the same.
    for name, entry in res["deviation"].items():
        (mean, p95), (b_mean, b_p95) = entry["report"], entry["blender"]
        assert abs(mean - b_mean) < 0.05 and abs(p95 - b_p95) < 0.2, (name, entry)
    assert not res["deviation"]["by_angle"]["has_custom"]  # sharp edges by angle, no custom normals
