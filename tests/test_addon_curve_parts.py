"""Curves, text, surfaces and metaballs are parts of an asset (issue 32 §1): Blender and
its exporters draw them as meshes, so the asset's levels hold their LODs, and its budget
counts their triangles. Before, only mesh objects were parts: a bevelled cable or an
extruded logo was written at full resolution beside every level, outside the glTF's
MSFT_lod. One Blender child runs tests/scenarios/addon_curve_parts.py."""
import numpy as np
import pytest

from bpy_harness import run_scenario

RATIOS = (0.5, 0.25)


@pytest.fixture(scope="module")
def res(tmp_path_factory):
    work = tmp_path_factory.mktemp("curve_parts")
    return run_scenario("addon_curve_parts", {}, user_dir=work / "user", install=False, timeout=600)


def test_curves_and_text_are_selected_parts_and_a_curve_without_faces_is_left_out(res):
    assert res["selected"] == ["Cable", "Guide", "Logo", "Monkey"]
    assert res["skipped"] == ['"Guide" skipped: its curve makes no faces (no bevel, extrusion or fill)']
    assert sorted(res["chains"]) == ["Cable", "Logo", "Monkey"]


def test_their_lods_are_meshes_with_their_materials_in_their_place(res):
    for name, material in (("Cable", "Rubber"), ("Logo", "Paint")):
        chain = res["chains"][name]
        assert len(chain) == len(RATIOS)
        for level in chain:
            assert level["type"] == 'MESH' and level["materials"] == [material], (name, level)
            assert np.allclose(level["matrix_world"], res["source_matrix"][name])
        assert chain[-1]["triangles"] < res["drawn"][name]
    assert res["sources"] == {"Monkey": "MESH", "Cable": "CURVE", "Logo": "FONT", "Guide": "CURVE"}
    assert res["unchanged"]


def test_the_asset_budget_counts_what_they_draw(res):
    drawn = sum(n for name, n in res["drawn"].items() if name != "Guide")
    assert res["asset"]["source_triangles"] == drawn
    for ratio, level in zip(RATIOS, res["asset"]["levels"]):
        assert abs(level["triangles"] - ratio * drawn) <= max(4, 0.01 * ratio * drawn), (ratio, level)


def test_a_text_object_alone_gets_its_lods(res):
    chain = res["alone"]["Logo"]
    assert [level["type"] for level in chain] == ['MESH', 'MESH']
    assert chain[0]["triangles"] > chain[1]["triangles"]
    assert abs(chain[0]["triangles"] - RATIOS[0] * res["drawn"]["Logo"]) <= 2


def test_a_curve_without_faces_alone_says_why(res):
    assert res["guide_alone"] == ('"Guide" has nothing to simplify: its curve makes no faces '
                                  '(no bevel, extrusion or fill)')
