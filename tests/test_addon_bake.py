"""Bake Normals (issue 22 §3): each LOD gets its own normal map, baked from the source's
detail, in copies of its materials; the source's materials are left alone."""
import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_scenario("addon_bake", {"resolution": 64}, user_dir=blender_user_dir, timeout=600)


def test_each_lod_has_its_own_packed_normal_map_in_a_material_copy(res):
    assert not res["warnings"], res["warnings"]
    assert res["source_material"] == "Stone" and res["source_nodes_unchanged"], "the source's material changed"
    names = [lod["material"] for lod in res["lods"]]
    assert len(set(names)) == 2 and "Stone" not in names, names
    for lod in res["lods"]:
        assert lod["size"] == [64, 64] and lod["packed"], lod
        assert lod["normal_linked"], f"the baked map does not reach the BSDF's Normal: {lod}"


def test_the_map_carries_the_lost_detail(res):
    for lod in res["lods"]:
        # A flat tangent-space map is (0.5, 0.5, 1) everywhere; the bumps tilt it.
        assert lod["pixel_std"] > 0.01, f"expected a map with detail, got a flat one: {lod}"
        assert lod["mean_blue"] > 0.8, f"expected mostly outward normals, got {lod}"
