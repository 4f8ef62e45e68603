"""Deviation targets fall back to the ladder where the core's tracked bound finds no level
(addon/pure/deviation_search.py by_deviation; the scenario replaces the tracked search by one that finds
nothing)."""
import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def res(blender_user_dir):
    return run_scenario("deviation_fallback", user_dir=blender_user_dir, timeout=600)


def test_the_ladder_gives_levels_within_their_bounds_when_the_bound_finds_none(res):
    # The three tracked searches (the artist's controls, lean and the planes' placement:
    # deviation_targets.alternatives) were asked and found nothing.
    assert res["fallback_calls"] == [2, 2, 2], res
    for name in ("tracked", "ladder"):
        levels = res[name]
        assert [level["requested_deviation_percent"] for level in levels] == pytest.approx([0.5, 2.0]), (name, levels)
        for level in levels:
            assert level["hausdorff_percent"] <= level["requested_deviation_percent"], (name, level)
            assert level["triangles"] < res["source_triangles"], (name, level)
        assert levels[0]["triangles"] > levels[1]["triangles"], (name, levels)


def test_a_level_the_bound_kept_far_under_its_deviation_gives_way_to_a_coarser_count(res):
    """deviation_search.probe_below (issue 33 §3): the tracked distance over-estimates
    across a bevel, so the bound stops the box well under 1 %; a run by count measures
    coarser levels within it, and the coarsest kept is measured within STRETCH_WITHIN."""
    probe = res["probe"]
    off, on = probe["off"], probe["on"]
    assert off["hausdorff_percent"] < probe["probe_below"] * off["requested_deviation_percent"], probe
    assert on["triangles"] < off["triangles"] < probe["source_triangles"], probe
    assert on["hausdorff_percent"] <= probe["stretch_within"] * on["requested_deviation_percent"], probe


def test_an_alternative_saving_under_a_tenth_is_kept_where_it_costs_nothing(res):
    """deviation_targets.fewest_each with slivers (issue 33 §3): the bevelled cylinder's
    planes' placement at 1 % saves under a tenth of the controls' triangles, with no
    larger share of slivers and a margin to its bound: kept."""
    free = res["free_saving"]
    off, on = free["off"], free["on"]
    assert on["triangles"] < off["triangles"] < on["triangles"] / (1.0 - free["min_saving"]), free
    assert on["sliver_percent"] <= off["sliver_percent"], free
    assert on["hausdorff_percent"] <= free["stretch_within"] * on["requested_deviation_percent"], free
