"""The add-on in real Blender (bpy module, built extension installed and enabled):
a subdivided monkey's LOD chain, replacement on re-run, cancel, undo, bad inputs and the
panel. One Blender child runs tests/scenarios/addon_monkey.py (module fixture); the tests
then check what it returns."""
import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_scenario("addon_monkey", user_dir=blender_user_dir, timeout=600)


def test_three_lods_with_the_right_counts(res):
    assert res["op_result"] == ["FINISHED"]
    rep = res["report"][0]
    assert rep["object"] == "Monkey" and rep["source_triangles"] == 15744
    assert [lv["target"] for lv in rep["levels"]] == [7872, 3936, 1968]
    for lv, info in zip(rep["levels"], res["lods"]):
        assert info is not None
        assert abs(info["triangles"] - lv["target"]) <= 1
        assert info["triangles"] == lv["triangles"]
        assert info["corner_counts"] == [3]  # triangles only
        assert 0 < lv["hausdorff_percent"] < 5 and 0 < lv["mean_percent"] < lv["hausdorff_percent"]
        assert 0.3 < lv["mean_quality"] <= 1


def test_objects_and_collection(res):
    assert res["collection_objects"] == ["Monkey_LOD1", "Monkey_LOD2", "Monkey_LOD3"]
    assert res["collection_in_scene"], "Monkey_LODs is not linked into the scene"
    for k, info in enumerate(res["lods"], start=1):
        assert info["in_collection"] == ["Monkey_LODs"]
        assert info["lod_level"] == k
        assert info["matrix_same"], f"LOD{k} is not placed where the source is"
        assert info["game_id"] == 42  # custom properties copied
        assert info["modifiers"] == []  # the subdivision is applied, not copied


def test_materials_uvs_colours_groups_shape_keys_carried(res):
    for info in res["lods"]:
        assert info["materials"] == ["Skin", "Eyes"]
        assert info["material_indices"] == [0, 1]
        assert info["uv_maps"] == ["UVMap"]
        assert 0.0 <= info["uv_range"][0] < info["uv_range"][1] <= 1.0
        assert ["Tint", "CORNER", "BYTE_COLOR"] in info["colors"]
        assert ["Heat", "POINT", "FLOAT_COLOR"] in info["colors"]
        lo, hi, other = info["heat_range"]
        assert 0.0 <= lo < 0.1 and 0.9 < hi <= 1.0 and other == 0.0  # interpolated, in range
        assert info["color_mean"] == pytest.approx([1.0, 0.5, 0.25, 1.0], abs=0.02)
        assert info["groups"] == ["Top"]
        assert max(info["top_weights"]) == pytest.approx(0.75, abs=1e-3)
        assert info["shape_keys"] == ["Basis", "Smile"]
        assert info["smile_value"] == pytest.approx([1.7, 1.5, 3.0])
        assert info["smile_offset"] == pytest.approx(0.1, abs=1e-3)
        assert info["flat_faces"] == 0  # smooth shading carried
        assert info["sharp_edges"] > 0  # the ear's sharp rim still splits normals
        assert info["seam_edges"] > 0  # seams are marked where the source had them
        assert info["seam_x"] < 0.05  # on the mid line (held softly: within 2 % of the width)


def test_input_had_features(res):
    assert res["sharp_input"] > 0 and res["seams_input"] > 0


def test_source_unchanged(res):
    assert res["source_diff"] == {}  # {what: [before, after]}


def test_rerun_replaces_previous_lods(res):
    assert res["rerun_objects"] == ["Monkey_LOD1", "Monkey_LOD2"]
    assert res["rerun_meshes"] == ["Monkey_LOD1", "Monkey_LOD2"]
    assert res["rerun_report_targets"] == [4723, 2362]
    assert all(abs(t - g) <= 1 for t, g in zip(res["rerun_triangles"], res["rerun_report_targets"]))


def test_source_selected_with_its_lods(res):
    assert res["with_lods_selected"] == [["FINISHED"], ["Monkey"], ["Monkey_LOD1", "Monkey_LOD2"]]


def test_cancel_leaves_the_scene_as_it_was(res):
    assert res["cancel_raised"], "cancelling through the progress callback raised no LodCancelled"
    assert res["cancel_calls"] == 2
    assert res["cancel_changes"] == {}  # {what: [before, after]}
    assert res["job_cancel_raised"], "committing a cancelled job raised no LodCancelled"
    assert res["job_cancel_changes"] == {}
    assert abs(res["job_threaded_triangles"][0] - 3149) <= 1
    assert res["job_threaded_objects"] == ["Monkey_LOD1"]


def test_vertex_group_routes_agree(res):
    fast, slow, expected = res["vg_read_shapes"]
    assert fast == slow == expected
    assert res["vg_read_max_difference"] == 0.0  # the C-side and per-vertex reads agree exactly
    assert res["vg_write_names"] == ["position", "g2"]  # a group may share an attribute's name
    assert res["vg_write_err"] < 1e-6
    assert res["vg_write_members"] == [res["vg_nonzero"]] * 2


EXPECTED_ERRORS = {
    "no_mesh_selected": "Select one or more mesh objects",
    "only_lods_selected": "Only LOD objects are selected: select their source mesh",
    "empty_mesh": '"Empty Mesh" has an empty mesh',
    "no_faces": '"Wire" has no faces',
    "missing_group": '"Monkey" has no vertex group "Nope"',
    "not_skinned": '"Monkey" is not skinned',
    "no_deform_bones": 'armature "Rig" has no deform bones',
    "from_armature_no_deform": 'armature "Rig" has no deform bones',
    "target_not_smaller": "is not smaller than the mesh",
    "too_many_levels": "use fewer levels",
    "edit_mode": "Switch to Object Mode",
    "edit_mode_api": "is in Edit Mode",
}


@pytest.mark.parametrize("case", sorted(EXPECTED_ERRORS))
def test_bad_input_gives_a_clear_report(res, case):
    message = res["errors"][case]
    assert message is not None, f"{case}: no error reported"
    assert EXPECTED_ERRORS[case] in message
    assert "Traceback" not in message and "Python:" not in message


def test_bad_inputs_change_nothing(res):
    assert res["errors_diff"] == {}


OPTIONAL_OPERATORS = {"object.line_quadric_lod_from_shape_keys", "object.line_quadric_lod_show_deviation",
                      "object.line_quadric_lod_deviation_back"}


def test_panel_draws_in_every_state(res):
    assert res["panel_registered"], "bpy.types has no VIEW3D_PT_line_quadric_lod"
    assert res["panel_category"] == "LOD"
    draws = res["draws"]
    assert ["label", "Select a mesh object"] in draws["no_object"]
    ops = [x[1] for x in draws["NONE"] if x[0] == "operator"]
    # In the panel's order; the shape-key bake and the deviation view come and go with their subjects.
    assert [op for op in ops if op not in OPTIONAL_OPERATORS] == [
        "object.line_quadric_lod_paint", "object.line_quadric_lod_from_armature",
        "object.line_quadric_lod_paint_limit", "object.line_quadric_lod"]
    assert ["prop_search", "limit_group"] in draws["NONE"]
    props = {x[1] for x in draws["NONE"] if x[0] == "prop"}
    assert {"ratio", "levels", "level_factor", "target_triangles", "line_weight", "importance_source",
            "preserve_boundaries", "preserve_seams", "preserve_sharp", "preserve_materials",
            "boundary_strength", "seam_strength", "sharp_strength", "material_strength"} <= props
    assert ["prop_search", "importance_group"] in draws["VERTEX_GROUP"]
    armature_props = {x[1] for x in draws["ARMATURE"] if x[0] == "prop"}
    assert "importance_strength" in armature_props and "importance_mode" not in armature_props  # one mode
    # Source Armature acts through sample poses, not a per-vertex importance: no preview.
    assert "object.line_quadric_lod_preview_importance" not in [x[1] for x in draws["ARMATURE"] if x[0] == "operator"]
    assert any("has no group" in x[1] for x in draws["missing_group"] if x[0] == "label")
    # The last run's report is shown: one row per LOD.
    assert ["label", "LOD2"] in draws["NONE"]


# What the docs' picture of the panel (bench/figures/fig_panel.py) shows with the default settings:
# each field's label (RNA name or the panel's text override) and value as Blender formats it.
PANEL_DEFAULTS = {
    "target_by": ["By", "Triangles"], "target_triangles": ["Triangles", "0"], "ratio": ["Ratio", "0.50"],
    "levels": ["Levels", "3"],
    "level_factor": ["Factor", "0.50"], "remove_small_components": ["Remove Small Parts", ""],
    "line_weight": ["Uniformity", "0.0010"], "min_quality": ["Min Quality", "0.30"],
    "feature_angle": ["Feature Angle", "80.0"],
    "importance_source": ["Source", "None"],
    "preserve_boundaries": ["Boundaries", ""], "boundary_strength": ["", "1.00"],
    "preserve_seams": ["UV Seams", ""], "seam_strength": ["", "1.00"],
    "preserve_sharp": ["Sharp Edges", ""], "sharp_strength": ["", "1.00"],
    "preserve_materials": ["Material Borders", ""], "material_strength": ["", "1.00"],
    "use_modifiers": ["Apply Modifiers", ""], "measure_deviation": ["Measure Deviation", ""],
    "deviation_colors": ["Deviation Colors", ""],
    "hard_edge_angle": ["Hard Edges", "0.0"], "bake_normals": ["Bake Normals", ""], "bake_resolution": ["", "1024"],
}


def test_panel_recording_names_values_and_greys_out(res):
    items = res["draw_items"]
    shown = {i[1]: i[2:4] for i in items["NONE"] if i[0] == "prop"}
    assert shown == PANEL_DEFAULTS
    assert [i[2] for i in items["NONE"] if i[0] == "operator" and i[1] not in OPTIONAL_OPERATORS] == [
        "Paint Importance", "Importance from Armature", "Paint Limit", "Generate LODs"]
    # Nothing greyed out by default but the bake's resolution (Bake Normals is off).
    assert [i[1] for i in items["NONE"] if not i[4]] == ["bake_resolution"], [i for i in items["NONE"] if not i[4]]
    assert ["label", None, "LOD1..3: 50% · 25% · 12.5%", None, True] in items["NONE"]
    group = {i[1]: i[2:4] for i in items["VERTEX_GROUP"] if i[0] in ("prop", "prop_search")}
    assert group["importance_group"] == ["Group", "Top"]
    assert "importance_mode" not in group and group["importance_strength"] == ["Strength", "0.50"]
    # Triangles > 0 greys out the Ratio, an option that is off greys out its strength.
    assert sorted(i[1] for i in items["greyed"] if not i[4]) == ["bake_resolution", "ratio", "seam_strength"]
    assert ["label", None, "LOD1..3: 20,000 · 10,000 · 5,000 triangles", None, True] in items["greyed"]

    # By Deviation / Screen Size: their own fields instead of Triangles and Ratio, and the
    # chain as the bounds each LOD is measured within.
    for state, fields in (("by_deviation", {"max_deviation"}), ("by_screen", {"pixel_error", "screen_height"})):
        props = {i[1] for i in items[state] if i[0] == "prop"}
        assert fields <= props and not {"ratio", "target_triangles"} & props, (state, sorted(props))
    assert ["label", None, "LOD1..3: ≤0.5% · ≤1% · ≤2% of the size", None, True] in items["by_deviation"], \
        [i for i in items["by_deviation"] if i[0] == "label"]


def test_paint_importance(res):
    p = res["paint"]
    assert p["result"] == ["FINISHED"] and p["mode"] == "WEIGHT_PAINT"
    assert p["active_group"] == "LOD_Importance"
    assert p["source"] == "VERTEX_GROUP" and p["group"] == "LOD_Importance"
    assert res["paint_groups"].count("LOD_Importance") == 1


def test_generate_button_uses_panel_settings(res):
    for state in ("NONE", "VERTEX_GROUP", "ARMATURE"):
        sets = {x[2]: x[3] for x in res["draws"][state] if x[0] == "set" and x[1] == "object.line_quadric_lod"}
        assert sets == res["draw_settings"][state]
    assert res["invoke_result"] == ["EXECUTED"]
    assert res["invoke_settings"] == [1, pytest.approx(0.2), pytest.approx(0.3)]


def test_modal_esc_cancels_and_timer_commits(res):
    assert res["modal_running"] == ["RUNNING_MODAL"]  # editing is blocked while it runs
    assert res["modal_navigation"] == ["PASS_THROUGH"]  # looking around is not
    assert res["modal_esc"] == ["CANCELLED"]
    assert res["modal_esc_messages"] == [[["WARNING"], "LOD generation cancelled: nothing was changed"]]
    assert res["modal_esc_changes"] == {}  # {what: [before, after]}
    assert res["modal_timer"] == ["FINISHED"]
    assert res["modal_timer_objects"] == ["Monkey_LOD1"]


def test_undo_is_one_step(res):
    assert res["undo_flag"], "the operator's bl_options has no 'UNDO'"
    assert res["undo_after_run"] == ["Monkey_LOD1", "Monkey_LOD2", "Monkey_LOD3"]
    assert res["undo_changes"] == {}  # {data-block type: [before, after undo]}
    assert res["undo_after_undo"] == ["Monkey_LOD1"]  # the threaded job's LOD from before
    assert res["redo_objects"] == ["Monkey_LOD1", "Monkey_LOD2", "Monkey_LOD3"]
