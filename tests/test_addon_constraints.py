"""LODs of a part that constraints place (tests/scenarios/addon_constraints.py): each LOD
object carries its source's constraints and stands where the source stands at every
frame. Before, the LODs had the source's transform without its constraints and stood at
the origin, in Blender and in the written files."""
import numpy as np
import pytest

from bpy_harness import run_scenario

pytestmark = [pytest.mark.blender]


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_scenario("addon_constraints", {}, user_dir=blender_user_dir)


def test_each_lod_has_its_sources_constraints(res):
    assert res["constraints"]["Placed"] == [["CHILD_OF", "Anchor"], ["COPY_SCALE", "Sizer"]]
    assert len(res["lods"]["Placed"]) == 2
    for name in res["lods"]["Placed"]:
        assert res["constraints"][name] == res["constraints"]["Placed"], name
    for name in res["lods"]["Ground"]:
        assert res["constraints"][name] == [], name


def test_each_lod_stands_where_its_source_stands_at_every_frame(res):
    first, last = (np.array(res["matrices"][str(f)]["Placed"]) for f in (1, 12))
    assert np.allclose(first[:3, 3], [4.0, 0.0, 0.0], atol=1e-5)  # the constraints place the source,
    assert not np.allclose(first, last, atol=1e-3)  # and the anchor moves it
    assert np.allclose(np.linalg.norm(first[:3, :3], axis=0), 2.0, atol=1e-5)  # sized like Sizer
    for frame, at in res["matrices"].items():
        for source, names in res["lods"].items():
            for name in names:
                np.testing.assert_allclose(at[name], at[source], atol=1e-6, err_msg=f"{name} at frame {frame}")
