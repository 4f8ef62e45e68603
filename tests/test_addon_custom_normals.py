"""LODs shade like their source (issue 22 §3): custom split normals are carried to every
LOD corner, whatever they are (normals pointing up for foliage, flat shading from custom
normals alone)."""
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
    assert flat["mean_angle"] < 0.01 and flat["largest_angle"] < 0.1, flat


def test_hard_edges_mark_the_creases_of_a_mesh_shaded_by_angle(res):
    assert res["hard_0"]["sharp"] == 0, res["hard_0"]  # off: nothing marked
    hard = res["hard_30"]
    assert hard["sharp"] >= 12, f"expected the cube's 12 edges (in segments) marked sharp, got {hard}"
    # Mostly the cube's edges; a few LOD triangles fold across them near the corners, and
    # those folds are creases of the LOD too.
    assert hard["on_cube_edges"] >= 0.8 * hard["sharp"], f"expected mostly the cube's edges sharp: {hard}"
