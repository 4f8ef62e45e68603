"""LODs of parts an object action moves move with them (tests/scenarios/addon_node_animation.py):
a node-animated character's LOD objects share their source's actions, slots and NLA
tracks and so stand where it stands at every frame. (Its .glb: tests/test_engine_switch.py.)"""
import numpy as np
import pytest

from bpy_harness import run_scenario

pytestmark = [pytest.mark.blender]


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_scenario("addon_node_animation", {}, user_dir=blender_user_dir)


def test_every_lod_has_its_sources_animation_and_parent(res):
    assert set(res["lods"]) == {"Body", "Arm"} and all(len(names) == 2 for names in res["lods"].values())
    arm = res["animation"]["Arm"]
    assert arm["action"] == "Swing" and arm["tracks"][0][0] == "Wave"  # the scene as built,
    assert [strip[1:] for strip in arm["tracks"][0][2]] == [[1.0, 12.5], [12.5, 23.5]]  # touching, between frames
    for source, names in res["lods"].items():
        for name in names:
            assert res["animation"][name] == res["animation"][source], name
            assert res["parents"][name] == res["parents"][source], name
    body_keys = res["key_animation"]["Body"]
    assert body_keys["action"] == "Breathe" and body_keys["tracks"][0][0] == "Sigh"
    for name in res["lods"]["Body"]:
        assert res["key_animation"][name] == body_keys, name  # the face's expressions play on every level


def test_every_lod_stands_where_its_source_stands_at_every_frame(res):
    frames = sorted(res["matrices"], key=int)
    arm_path = [np.array(res["matrices"][f]["Arm"]) for f in frames]
    assert not np.allclose(arm_path[0], arm_path[1], atol=1e-3)  # the source really moves
    for frame in frames:
        at = res["matrices"][frame]
        for source, names in res["lods"].items():
            for name in names:
                np.testing.assert_allclose(at[name], at[source], atol=1e-6, err_msg=f"{name} at frame {frame}")
        bulge = res["bulge"][frame]
        assert len(set(bulge.values())) == 1, (frame, bulge)  # every level's key at its source's value
    assert res["bulge"]["6"]["Body"] > 0.9 and res["bulge"]["1"]["Body"] < 0.1


def test_unreal_lod_groups_are_per_chain_and_keep_everything_moving(res):
    """With --lod-group, an asset an animation moves gets a group per chain where its LOD0
    was (one_input.name_chains), and every level still stands where its source stood."""
    assert res["asset_group"] is None
    assert sorted(res["groups"].values()) == ["Arm_LODGroup", "Body_LODGroup"]
    sources = list(res["groups"])  # in the order of "grouped"'s chains
    for frame, chains in res["grouped"].items():
        for source, chain in zip(sources, chains):
            for matrix in chain:
                np.testing.assert_allclose(matrix, res["matrices"][frame][source], atol=1e-6,
                                           err_msg=f"{source}'s chain at frame {frame}")
