"""addon/vertex_groups.py in real Blender (issue 32 §2): weights are written with
VertexGroup.add, one call per distinct (group, weight) pair and no operator, so the cost
does not grow with the scene; they equal the former attribute_convert route and the
float32 values given, zeros stay out of the groups, names and order are kept, objects
need not be in a scene, nothing temporary is left; the read routes agree. One Blender
child runs tests/scenarios/addon_vertex_groups.py without the extension installed."""
import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def res(tmp_path_factory):
    return run_scenario("addon_vertex_groups", user_dir=tmp_path_factory.mktemp("blender"), install=False,
                        timeout=300)


def test_written_without_operators_on_objects_in_no_scene(res):
    assert res["in_scenes"] == [0, 0]
    assert res["auto_without_operators"] is True


def test_an_object_is_read_without_throw_away_data(res):
    # (making and removing an object or a mesh tagged the depsgraph, and the next update
    # re-evaluated the scene: 14-24 ms a part with 300 objects)
    reads = res["read_object_without_new_data"]
    assert reads["base"] is True and reads["modifiers"] is True, reads
    assert reads["modifiers_weights"] == 0.0
    assert reads["modifiers_vertices"][0] == reads["modifiers_vertices"][1] > 120  # subdivided


def test_same_weights_as_the_former_route_and_exact_float32(res):
    assert res["new_vs_old_max"] == 0.0
    assert res["new_vs_expected_max"] == 0.0
    m = res["members"]
    assert m["new_equal"] and m["old_equal"], m  # exactly the nonzero weights, in both routes
    assert m["expected"] > 2000


def test_zeros_clipping_and_tiny_weights(res):
    e = res["edge_cases"]
    assert e["rounds_to_zero_member"] is False  # 1e-50 is 0 in float32: not a member
    assert e["tiny"] == pytest.approx(1e-30, rel=1e-6)  # a float32 weight, however small, is kept
    assert e["clipped"] == 1.0
    assert e["negative_member"] is False
    assert e["empty_group_members"] == 0


def test_group_names_and_order_kept(res):
    names = [f"bone{i:02d}" for i in range(22)] + ["position", "UVMap"]
    # "keep" stays first; "bone03" is replaced, so it moves into the order given.
    assert res["group_order"][0] == ["keep"] + names
    assert res["group_order"][1] == ["keep"] + names
    assert res["keep_untouched"]
    assert res["rewrite_order"] == ["keep"] + names
    assert res["rewrite_max"] == 0.0


def test_linked_object_and_empty_mesh(res):
    assert res["linked_max"] == 0.0
    assert res["linked_modifiers"] == ['ARMATURE']
    assert res["empty_groups"] == ["a", "b"]


def test_nothing_temporary_left(res):
    assert res["datablocks_same"]
    assert res["leftovers"] == {"attributes": [], "groups": [], "modifiers": 0}
    for read in res["reads"].values():
        assert read["datablocks_same"]
        assert read["leftovers"] == {"attributes": [], "groups": [], "modifiers": 0}


def test_bad_arguments_say_so(res):
    e = res["errors"]
    assert "duplicate" in e["duplicate"]
    assert "unknown method" in e["unknown_write"] and "unknown method" in e["unknown_read"]


def test_read_routes_agree_both_sides_of_the_threshold(res):
    small, large = res["reads"]["small"], res["reads"]["large"]
    assert small["vertices"] < res["nodes_min_vertices"] <= large["vertices"]
    for read in (small, large):
        assert read["nonzero"] > 1000
        assert read["auto_vs_python"] == 0.0
        assert read["nodes_vs_python"] == 0.0  # also for groups named "position" and "UVMap"
        assert read["missing"] == [0.0, 0.0]
