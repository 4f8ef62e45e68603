"""Meshes as importers bring them, read by addon/mesh_io.py. One Blender child runs
tests/scenarios/addon_reading.py."""
import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def res(tmp_path_factory):
    work = tmp_path_factory.mktemp("reading")
    return run_scenario("addon_reading", {}, user_dir=work / "user", install=False, timeout=600)


def test_sharp_marks_on_most_edges_are_for_shading_and_a_few_are_creases(res):
    """Blender's FBX importer marks a flat-shaded mesh's every edge sharp but those between
    coplanar faces: not every edge, and such marks were taken for creases (the monkey's
    LODs measured 3.5-4x the same .blend's distance). More than half the edges marked
    says "shaded flat"; a cube's four marked edges are creases."""
    monkey = res["fbx_monkey"]
    assert 0.5 * monkey["edges"] < monkey["sharp"] < monkey["edges"], monkey
    assert monkey["for_shading"]
    assert res["cube"]["sharp"] == 4 and not res["cube"]["for_shading"]


def test_triangles_and_positions_are_what_blender_gives(res):
    """mesh_io.triangles reads a mesh of triangles only as one block of corners (a LOD, a
    glTF import, the posed distance's evaluated meshes), and triangulates any other as
    Blender does; positions read the "position" attribute. Each the same arrays as
    Blender's loop triangles and vertex coordinates."""
    tri = res["triangles"]
    assert tri["triangulated"]["all_triangles"] and not tri["quads"]["all_triangles"] and \
        not tri["ngons"]["all_triangles"]
    for name in ("triangulated", "quads", "ngons"):
        assert tri[name]["triangles"] > 0 and tri[name]["same"] and tri[name]["positions"], (name, tri[name])
