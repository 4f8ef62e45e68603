"""A mesh used by several objects is simplified once per level and its LODs are shared the
same way (issue 32 §1): LodJob groups the objects whose LODs would be identical (same
mesh datablock, equal settings, no evaluated geometry modifier, no armature), computes
each group once, and commit gives every object its own LOD objects using the group's
LOD meshes. One Blender child runs tests/scenarios/addon_instances.py (the checkout's
addon package, no install); tests/test_cli_instances.py runs the command line on the .blend
it saves."""
import pytest

from bpy_harness import run_scenario

SHARED = ["A", "B", "C", "F"]  # Part, no modifier in the viewport, same settings
APART = ["Solo", "D", "E"]  # own mesh / Subdivision on / other ratios
ORDER = ["A", "Solo", "B", "D", "C", "E", "F"]


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    return tmp_path_factory.mktemp("instances")


@pytest.fixture(scope="module")
def res(work):
    return run_scenario("addon_instances", {"blend_out": str(work / "instances.blend")}, user_dir=work / "user",
                        install=False, timeout=600)


def test_groups_by_mesh_settings_and_modifiers(res):
    assert res["groups"] == [SHARED, ["Solo"], ["D"], ["E"]]
    assert res["inputs"] == ["A", "Solo", "D", "E"]


def test_core_runs_once_per_group(res):
    assert res["compute_calls"] == ["A", "Solo", "D", "E"]
    assert len(res["simplify_calls"]) == 4, res["simplify_calls"]
    assert res["simplify_calls"][2] > res["simplify_calls"][0]  # D's subdivided input is its own
    assert res["observer_started"] == ["A", "Solo", "D", "E"] and res["observer_finished"] == 4
    assert res["fraction_monotonic"] and res["fraction_end"] == 1.0


def test_instances_share_one_mesh_per_level(res):
    lods = res["lods"]
    for k in (1, 2):
        ids = {lods[name][k - 1]["mesh_id"] for name in SHARED}
        assert len(ids) == 1, f"LOD{k} of the instances uses {len(ids)} meshes"
        for name in SHARED:
            info = lods[name][k - 1]
            assert info["mesh"] == f"Part_LOD{k}" and info["users"] == len(SHARED), info
            assert info["triangles"] == lods["A"][k - 1]["triangles"]
        for name in APART:
            info = lods[name][k - 1]
            assert info["mesh"] == f"{name}_LOD{k}" and info["users"] == 1, info
            assert info["mesh_id"] not in ids
    assert lods["A"][0]["mesh_id"] != lods["A"][1]["mesh_id"]
    assert len({lods[name][0]["mesh_id"] for name in APART}) == 3
    assert lods["E"][0]["triangles"] != lods["A"][0]["triangles"]  # its own ratios
    # The LOD meshes are new: no LOD uses a source's mesh.
    assert not set(res["source_mesh_ids"].values()) & {i["mesh_id"] for chain in lods.values() for i in chain}


def test_each_instance_has_its_own_lod_objects_placed_as_today(res):
    lods = res["lods"]
    for name in ORDER:
        chain = lods[name]
        assert [i["name"] for i in chain] == [f"{name}_LOD1", f"{name}_LOD2"]
        for k, info in enumerate(chain, start=1):
            assert info["lod_source"] == name and info["lod_level"] == k
            assert info["matrix_gap"] < 1e-5, (name, k, info["matrix_gap"])
            assert info["collections"] == [f"{name}_LODs"]
            assert info["collection_parents"] == [info["source_collection"]]  # beside the source
            assert (info["source_collection"] == "Parts") == (name == "C")
            assert info["parent"] == ("Holder" if name == "C" else None)
            assert info["asset_id"] == {"A": 7, "B": 8}.get(name)
            assert info["groups"] == ["Top"]
            assert info["shape_keys"] == ["Basis", "Bulge"]
            assert info["mesh_materials"] == ["Grey", "Blue"]
            expected_slots = [["OBJECT", "Red"], ["DATA", "Blue"]] if name == "B" else [["DATA", "Grey"],
                                                                                          ["DATA", "Blue"]]
            assert info["slots"] == expected_slots, (name, k, info["slots"])


def test_switch_distances_follow_each_instances_scale(res):
    lods = res["lods"]
    for k in (0, 1):
        a = lods["A"][k]["switch_distance"]
        assert a and a > 0
        assert lods["B"][k]["switch_distance"] == pytest.approx(2.0 * a, rel=1e-6)
        assert lods["C"][k]["switch_distance"] == pytest.approx(0.5 * a, rel=1e-6)
        assert lods["F"][k]["switch_distance"] == pytest.approx(a, rel=1e-6)


def test_report_one_entry_per_object_time_counted_once(res):
    reports = res["reports"]
    assert [r["object"] for r in reports] == ORDER
    by = {r["object"]: r for r in reports}
    assert by["A"]["seconds"] > 0 and by["A"].get("shares") is None
    assert by["A"]["shared_with"] == ["B", "C", "F"]
    for name in ("B", "C", "F"):
        r = by[name]
        assert r["shares"] == "A" and r["seconds"] == 0.0
        assert r["shared_with"] == [n for n in SHARED if n != name]
        assert all(lv["seconds"] == 0.0 for lv in r["levels"])
    for name in SHARED:
        r = by[name]
        assert r["source_mesh"] == "Part" and r["collection"] == f"{name}_LODs"
        assert [lv["mesh"] for lv in r["levels"]] == ["Part_LOD1", "Part_LOD2"]
        assert [lv["name"] for lv in r["levels"]] == [f"{name}_LOD1", f"{name}_LOD2"]
        assert [lv["hausdorff_percent"] for lv in r["levels"]] == [lv["hausdorff_percent"]
                                                                    for lv in by["A"]["levels"]]
        assert r["warnings"] == by["A"]["warnings"]
    for name in APART:
        r = by[name]
        assert r["shared_with"] == [] and r.get("shares") is None and r["seconds"] > 0
        assert [lv["mesh"] for lv in r["levels"]] == [f"{name}_LOD1", f"{name}_LOD2"]


def test_sources_unchanged_and_only_the_lod_meshes_new(res):
    assert res["sources_changed"] == {}  # mesh, users, transform, slots, properties (but the switch numbers)
    assert res["new_meshes"] == sorted(f"{n}_LOD{k}" for n in ("Part", "Solo", "D", "E") for k in (1, 2))


def test_cancel_uncommitted_and_failed_commit_leave_the_scene_as_it_was(res):
    assert res["cancel_raised"] is True and res["cancel_changes"] == {}
    assert res["uncommitted_changes"] == {}
    assert 'the object "C" no longer exists' in (res["failed_commit_raised"] or "")
    assert res["failed_commit_changes"] == {}
    assert res["orphan_meshes_after_failure"] == []


def test_rerun_replaces_the_shared_lods(res):
    assert res["rerun_meshes"] == res["new_meshes"]  # same names: the old shared meshes are gone
    assert res["rerun_objects"] == sorted(f"{n}_LOD{k}" for n in ORDER for k in (1, 2))
    assert res["orphan_meshes"] == []
    assert res["rerun_part_lod_users"] == [len(SHARED), len(SHARED)]
