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


def test_replacing_the_lods_removes_their_baked_copies_and_images(res):
    # The second run's LODs replaced the first's: their copies and images went with
    # them, except LOD1's copy, which the artist put on a cube (and its image, which
    # that copy uses). The artist's unused "Spare" and the source's "Stone" stay.
    first, second = res["first_lods"], res["lods"]
    assert {"Stone", "Spare"} <= set(res["materials"]), res["materials"]
    assert first[0]["material"] in res["materials"] and first[0]["images"][0] in res["images"], res
    assert res["unused"] == {"materials": ["Spare"], "images": []}, f"orphans left: {res['unused']}"
    # What the bakes made and is still there: the cube's copy and the new LODs' own.
    assert res["marked"] == {"materials": sorted([first[0]["material"]] + [lod["material"] for lod in second]),
                             "images": sorted(first[0]["images"] + [lod["images"][0] for lod in second])}, res
    # The replaced LOD2's copy and map went first, so the new ones take their names
    # again (no ".001"); LOD1's, kept by the cube, push the new LOD1's aside.
    assert [second[1]["material"], second[1]["images"]] == [first[1]["material"], first[1]["images"]], res
    assert second[0]["material"] == first[0]["material"] + ".001", res


def test_a_failed_or_interrupted_bake_leaves_no_copies(res):
    refused = res["failing"]["refused"]
    assert len(refused["warnings"]) == 2 and all("no normal map baked" in w for w in refused["warnings"]), refused
    assert "simulated failure" in refused["warnings"][1], refused["warnings"]
    assert refused["lod_materials"] == ["Clay", "Clay"], "a LOD whose bake failed must keep its material"
    assert refused["marked"] == {"materials": [], "images": []}, refused["marked"]
    assert refused["unused"] == {"materials": [], "images": []}, refused["unused"]
    interrupted = res["failing"]["interrupted"]
    assert res["failing"]["interrupted_raised"], "Ctrl-C during the bake must go on up"
    assert interrupted == {"unused": {"materials": [], "images": []},
                           "marked": {"materials": [], "images": []}}, interrupted


def test_an_object_linked_slot_gets_the_baked_copy(res):
    linked = res["object_linked"]
    assert not linked["warnings"], linked["warnings"]
    assert linked["source_nodes_unchanged"], "the source's object-linked material changed"
    for lod in linked["lods"]:
        assert lod["slot_link"] == 'OBJECT' and lod["material"] != "Moss", lod
        assert lod["normal_linked"] and lod["pixel_std"] > 0.01, lod
