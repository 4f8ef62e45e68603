"""Importance from the armature, measured where it matters: the posed LOD against the posed
source (issue 19 § 2), on a procedural rig the test builds: a tube of 48 x 80 vertices
along z with three bones (elbow at z = 1, wrist at z = 2), parented with Automatic Weights.

Each LOD (5 %, same triangle count) is posed by the rig in four random poses (seeded
quaternions, every bone turned by 20 to 50 degrees about a random axis) and measured against the posed source: two-sided
mean distance, % of the bounding-box diagonal (addon/pure/measure.py). One Blender child runs
everything; the tests check its RESULT.
"""
import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_scenario("addon_skinned_poses", user_dir=blender_user_dir, timeout=600)


def _mean(xs):
    return sum(xs) / len(xs)


def test_same_count_and_still_skinned(res):
    counts = {k: v for k, v in res["triangles"].items() if not k.endswith("_COARSE")}
    assert max(counts.values()) - min(counts.values()) <= 1
    assert abs(res["triangles"]["NONE_COARSE"] - res["triangles"]["ARMATURE_COARSE"]) <= 1
    assert res["parent"] == ["FINISHED"]
    assert res["modifiers"] == ["ARMATURE"]
    assert res["moved"] > 0.3  # every pose really bends the tube


def test_armature_makes_posed_lods_closer(res):
    """Source Armature (the rig's sample poses in the error, weights fitted to them)
    against no importance at the same count: at least 10 % closer posed, on average over
    the poses (issue 19; measured 0.84x), and the rest-pose cost within the issue's 1.2x
    (measured 1.03x). The test's poses (20-50 degrees, seeds 11-14) are not the sample
    poses (core.skinning.random_poses, seed 0, up to 40 degrees)."""
    none, ours = _mean(res["posed"]["NONE"]), _mean(res["posed"]["ARMATURE"])
    assert ours < 0.9 * none, res["posed"]
    assert res["rest"]["ARMATURE"] <= 1.2 * res["rest"]["NONE"], res["rest"]


def test_a_coarse_level_is_no_further_posed_than_without_importance(res):
    """At 15 triangles a bone a LOD cannot spend triangles on every joint, and the poses
    in the error were a coin toss there (docs/armature.md); the level is checked against
    one made without them, and the closer of the two in further random poses kept. So
    it is no further posed than no importance, on the test's own poses, at no more than
    the issue's rest cost."""
    none, ours = _mean(res["posed"]["NONE_COARSE"]), _mean(res["posed"]["ARMATURE_COARSE"])
    assert ours <= none, res["posed"]
    assert res["rest"]["ARMATURE_COARSE"] <= 1.2 * res["rest"]["NONE_COARSE"], res["rest"]


def test_papers_mapping_makes_posed_lods_a_little_closer(res):
    """Source Armature (Paper), the paper's mapping through the calibrated slider: closer
    posed, but by less than the issue's 10 % (measured 0.97x; docs/armature.md)."""
    none, ours = _mean(res["posed"]["NONE"]), _mean(res["posed"]["ARMATURE_PAPER"])
    assert ours < 0.99 * none, res["posed"]
    assert res["rest"]["ARMATURE_PAPER"] <= 1.2 * res["rest"]["NONE"], res["rest"]


def test_sample_poses_deform_as_blender_does(res):
    """core.skinning's forward kinematics and skinning, with the armature moved, turned and
    scaled and the mesh's own transform, give Blender's Armature deformation (single
    precision: about 1e-7 of the size)."""
    assert max(res["forward_kinematics"]) < 1e-5, res["forward_kinematics"]
