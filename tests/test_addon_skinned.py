"""A skinned arm in real Blender: Importance from Armature, LODs that deform with the rig,
and the posed LOD against Blender's Decimate at the same triangle count.

The test builds its own character: a 3-bone armature and a capped tube "arm" (48 x 64
vertices, with a narrowing at the elbow), parented with Automatic Weights. One Blender
child runs everything (module fixture); the tests check its RESULT.
"""
import statistics

import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_scenario("addon_skinned", user_dir=blender_user_dir, timeout=600)


def test_character_is_skinned(res):
    assert res["parent"] == ["FINISHED"]
    assert res["groups"] == ["Upper", "Lower", "Hand"]


def test_importance_from_armature_is_the_papers_formula(res):
    assert res["from_armature"] == ["FINISHED"]
    # Baked as w_i / 0.1 so the group reads 0..1 in Weight Paint mode.
    assert res["baked_error"] < 1e-6
    lo, hi = res["baked_range"]
    assert 0.0 <= lo and hi <= 1.0 and hi > 0.5
    elbow, mid = res["baked_elbow_vs_mid"]
    assert elbow > 2 * mid
    assert res["settings_after_bake"] == ["VERTEX_GROUP", "LOD_Importance"]


def test_lods_deform_with_the_rig(res):
    info = res["runs"]["ARMATURE_0.1"]
    assert info["modifiers"] == [["ARMATURE", "Rig"]]
    assert info["parent"] == "Rig"
    assert info["groups"][:3] == ["Upper", "Lower", "Hand"] and "LOD_Importance" in info["groups"]
    lo, hi = info["weight_range"]
    assert lo >= 0.0 and hi <= 1.0
    assert info["bones_used"] == 3
    # Interpolated weights stay within the source's range of weight sums.
    src_lo, src_hi = info["source_sum_range"]
    lo, hi = info["weight_sum_range"]
    assert lo >= src_lo - 1e-3 and hi <= src_hi + 1e-3


@pytest.mark.parametrize("ratio", [0.1, 0.03])
def test_posed_lod_beats_decimate(res, ratio):
    """The paper's mapping (Source Armature (Paper), or its baked group)."""
    for source in ("ARMATURE_PAPER", "VERTEX_GROUP"):
        info = res["runs"][f"{source}_{ratio}"]
        assert info["moved"] > 0.5  # the pose really bends the arm
        for tris in info["triangles"]:
            assert abs(tris - round(ratio * res["source_triangles"])) <= 1
        assert abs(info["decimate_triangles"] - info["triangles"][0]) <= 0.02 * info["triangles"][0]
        hausdorff = [h for h, _ in info["ours"]]
        mean = [m for _, m in info["ours"]]
        dec_h, dec_mean = info["decimate"]
        # The median of the three seeds: on this symmetric tube the tie-breaking seed moves
        # a single LOD's distances a lot. Over eight seeds, the posed mean at 3 % ranged
        # 0.98-1.12x Decimate's and the Hausdorff distance at 10 % 0.68-1.33x.
        assert max(hausdorff) < (2.0 if ratio == 0.1 else 3.0)  # bounded, % of the bbox diagonal
        # At 3 % the joints decide the worst spot, and protecting them wins clearly. At 10 %
        # the worst spot is a single vertex somewhere on the arm: only "as close, within
        # that scatter" holds.
        assert statistics.median(hausdorff) < (dec_h if ratio < 0.1 else 1.2 * dec_h)
        # On average as close at 10 %. At 3 % (184 triangles) the greedy cheapest-first
        # order itself is a little further on average on this tube (bench/arm_order.py).
        assert statistics.median(mean) < (1.05 if ratio >= 0.1 else 1.1) * dec_mean


@pytest.mark.parametrize("ratio", [0.1, 0.03])
def test_sample_poses_make_the_posed_lod_closer_on_average(res, ratio):
    """Source Armature (sample poses in the error, weights fitted to them): closer than no
    importance on average, and as close as Decimate (measured 0.87x / 0.80x none's mean,
    0.80x / 0.97x Decimate's at 10 % / 3 %). At 3 % (184 triangles) its worst spot, at the
    wrist the test pose turns by 50 degrees and twists by 30, is further than the paper
    mapping's and Decimate's (measured 3.76 % against 1.8-2.3 % and 2.71 %; 3.66 % without
    the fitted weights), so only a bound is asserted there (docs/armature.md)."""
    info, none = res["runs"][f"ARMATURE_{ratio}"], res["runs"][f"NONE_{ratio}"]
    (hausdorff, mean), = info["ours"]
    assert abs(info["triangles"][0] - none["triangles"][0]) <= 1
    assert mean < 0.97 * none["ours"][0][1]
    assert mean < (1.0 if ratio >= 0.1 else 1.1) * info["decimate"][1]
    assert hausdorff < (1.2 * info["decimate"][0] if ratio >= 0.1 else 4.0)


def test_posed_source_is_read_at_rest(res):
    run = res["posed_run"]
    assert run["mods_after"] == run["mods_before"]  # Armature modifier switched back on
    assert run["lod_mods"] == ["ARMATURE"]  # Subdivision applied, skinning kept live
    rep = run["report"]
    assert rep["source_triangles"] == 63 * 48 * 8 + 2 * 48 * 2  # the subdivided arm was read
    assert abs(run["triangles"] - rep["levels"][0]["target"]) <= 1
    # Against the unposed, unsubdivided arm: close (a bent arm would be ~20 % off).
    assert run["rest_hausdorff"] < 2.0


def test_coarse_levels_remade_without_the_poses_keep_a_painted_limit(res):
    """Source Armature with a painted limit (4 % on the arm's tip): the coarse levels
    (fewer than 40 triangles a bone) are also made without the poses in the error and the
    one that follows the source closer is kept (skin_fit.skinned_levels); that remake runs
    under the limits its chain was last held to (LodInput.limit_rows), so every level
    keeps the limit either way. (With a limit in pixels the remake had none at all; on
    this arm a pixel limit tight enough to matter stops the coarse levels above their
    targets, so no remake happens there.)"""
    limited = res["limited"]
    levels = limited["levels"]
    assert any(level["triangles"] < 40 * limited["bones"] for level in levels), [(lv["triangles"], lv["target"]) for lv in levels]
    for level in levels:
        assert level["limit"] is not None and level["limit"]["within"], level


def test_an_unskinned_part_beside_a_skinned_one_gets_no_importance_with_a_note(res):
    """Source Armature on a selection with a prop no bone deforms: the arm is kept close in
    the rig's poses, the prop is simplified without importance and says so (the command
    line's words); the prop alone, or only such props, is an error naming them."""
    mixed = res["unskinned_prop"]
    assert "error" not in mixed, mixed.get("error")
    assert mixed["poses"] == {"Arm": True, "Prop": False}
    assert "no importance (not skinned)" in mixed["warnings"]["Prop"], mixed["warnings"]
    assert not any(w.startswith("no importance") for w in mixed["warnings"]["Arm"]), mixed["warnings"]
    assert all(len(chain) == 2 for chain in mixed["triangles"].values()), mixed["triangles"]
    assert '"Prop" is not skinned' in mixed["alone_error"], mixed["alone_error"]
    assert mixed["none_error"].startswith("Source Armature: none of the 2 objects"), mixed["none_error"]
