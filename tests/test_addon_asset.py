"""Several objects are one asset (issue 32 §1, addon/asset.py): one triangle budget per
level split over the parts by error, deviations and switch numbers relative to the whole
asset, and no part failing the asset for being small. One Blender child runs
tests/scenarios/addon_asset.py (a hull, two instances of a dense bolt, a 2-triangle decal);
the core's split itself is tested in tests/test_core_budget.py."""
import numpy as np
import pytest

from bpy_harness import run_scenario

RATIOS = (0.5, 0.25, 0.125)


def assert_same_counts(levels, others) -> None:
    """Two runs of the scenario's scene draw the same triangles per level, but for ties:
    Blender 5.2's UV sphere comes with its polygons in another order each time it is made
    (the same vertices and polygons), and the greedy order follows the input's at equal
    costs (1,190 triangles against 1,192 at LOD2 with PYTHONHASHSEED=1)."""
    assert len(levels) == len(others)
    for a, b in zip(levels, others):
        assert abs(a["triangles"] - b["triangles"]) <= max(2, 0.005 * b["triangles"]), (a, b)


@pytest.fixture(scope="module")
def res(tmp_path_factory):
    work = tmp_path_factory.mktemp("asset")
    return run_scenario("addon_asset", {}, user_dir=work / "user", install=False, timeout=600)


def test_an_asset_is_simplified_in_one_run_and_as_close_as_split_by_curves(res):
    """The default asset run is one core run (core.assembly); the split by error curves,
    which painted limits and Source Armature still take, gives the same kind of LOD set:
    both meet the budget, and the one run is as close to the source over the levels.

    A level's distance is one chord: where the greedy order of one run and of the part's
    own run first take a cheap collapse whose faces cut across a curve (here a seam
    vertex beside the hull's pole sliding to the next). With the hull at 32x16, 40x20,
    48x24 and 64x32 segments the one run's levels measured 0.58-1.43x the split's (1.59x
    before seam rings were freed), 0.88x in geometric mean: each level within 1.5x, and
    no farther over the three."""
    one, split = res["asset"], res["asset_split"]
    assert one["together"] and not split["together"]
    ratios = []
    for k, (a, b) in enumerate(zip(one["asset"]["levels"], split["asset"]["levels"])):
        assert abs(a["triangles"] - b["triangles"]) <= max(4, 0.01 * b["triangles"]), k
        ratios.append(a["hausdorff"] / b["hausdorff"])
    assert max(ratios) <= 1.5 and np.prod(ratios) <= 1.0, ratios
    # Both ways, the dense bolt gives up more than the hull, and small parts leave far levels
    # (split by curves, the bolt keeps 4 triangles to the 1.5 % level and leaves at 0.6 %,
    # as in the one run: tests/scenarios/addon_asset.py's FAR).
    for run in (one, split):
        share = {n: run["lods"][n][0]["triangles"] / run["source_triangles"][n] for n in ("Hull", "Bolt")}
        assert share["Bolt"] < 0.5 * share["Hull"], share
    assert len(res["far_split"]["lods"]["Bolt"]) < 4


def test_a_small_part_does_not_fail_its_asset(res):
    run = res["asset"]
    assert "error" not in run, run.get("error")
    assert [lev["triangles"] for lev in run["lods"]["Decal"]] == [2, 2, 2]
    assert any("kept whole" in w for w in run["reports"]["Decal"]["warnings"])
    # Per part, as before, the decal cannot be halved: the setting turns the asset off.
    assert "Decal" in res["per_part"]["error"] and "[1, 0, 0]" in res["per_part"]["error"]


def test_each_level_meets_the_asset_budget(res):
    """The budget is what the asset draws: the bolt's mesh counts once per object."""
    run = res["asset"]
    drawn_source = sum(run["source_triangles"].values())
    for k, ratio in enumerate(RATIOS):
        drawn = sum(chain[k]["triangles"] for chain in run["lods"].values())
        assert abs(drawn - round(ratio * drawn_source)) <= max(2, 0.01 * ratio * drawn_source), (k, drawn)
        assert run["asset"]["levels"][k]["triangles"] == drawn
    assert run["asset"]["source_triangles"] == sum(run["source_triangles"].values())
    assert run["unchanged"] and run["fraction_monotonic"]


def test_the_budget_goes_where_the_error_is(res):
    """The dense little bolt gives up far more of its triangles than the hull, which needs
    them for its silhouette (same ratio each would keep half of both)."""
    run = res["asset"]
    share = {n: run["lods"][n][0]["triangles"] / run["source_triangles"][n] for n in ("Hull", "Bolt")}
    assert share["Bolt"] < 0.5 * share["Hull"], share


def test_instances_of_a_part_share_its_lods(res):
    run = res["asset"]
    for a, b in zip(run["lods"]["Bolt"], run["lods"]["Bolt2"]):
        assert a["mesh"] == b["mesh"] and a["triangles"] == b["triangles"]


def test_every_part_switches_with_the_asset(res):
    run = res["asset"]
    levels = run["asset"]["levels"]
    for k, level in enumerate(levels):
        for name, chain in run["lods"].items():
            assert chain[k]["switch"] == pytest.approx(level["switch_distance"]), (name, k)
    assert len({v for v in run["source_switch"].values()}) == 1
    # The asset's deviation is the largest of its parts', in scene units and in % of its size.
    for k, level in enumerate(levels):
        assert level["hausdorff_percent"] == pytest.approx(100 * level["hausdorff"] / run["asset_diagonal"], rel=1e-3)
        assert level["deviation"] == pytest.approx(level["hausdorff"])
    distances = [level["switch_distance"] for level in levels]
    assert distances == sorted(distances) and distances[0] > 0
    # Unmeasured: no switch numbers anywhere, the counts as measured.
    quiet = res["asset_unmeasured"]
    assert all(lev["switch"] is None for chain in quiet["lods"].values() for lev in chain)
    assert_same_counts(quiet["asset"]["levels"], levels)


def test_a_note_on_the_whole_asset_is_the_assets(res):
    # Notes about the asset as a whole are in its entry, not on whichever part came first.
    run = res["deviation_tight"]
    assert "error" not in run, run.get("error")
    assert any(w.startswith("the asset's LOD1 repeats it whole") for w in run["asset"]["warnings"]), run["asset"]
    for name, rep in run["reports"].items():
        assert not any(w.startswith("the asset's") for w in rep["warnings"]), (name, rep["warnings"])
    assert res["deviation"]["asset"]["warnings"] == []


def test_deviations_are_relative_to_the_asset(res):
    run = res["deviation"]
    assert "error" not in run, run.get("error")
    diagonal = run["asset_diagonal"]
    for name in ("Hull", "Bolt"):
        for level, percent in zip(run["reports"][name]["levels"], (1.0, 4.0)):
            scene_units = level["requested_deviation"] * run["world_scale"][name]
            assert scene_units == pytest.approx(percent / 100 * diagonal, rel=1e-3), name
            assert level["requested_deviation_percent"] == pytest.approx(percent, rel=1e-3)
            # ... and in % of the part's own diagonal, as its hausdorff_percent is (the
            # command line's Target column: a bolt's "<=1%" beside its 1.5 % of itself
            # read as a miss).
            own = level["requested_deviation_object_percent"]
            assert own >= percent * (1 - 1e-9), (name, level)  # a part is no larger than its asset
            assert level["hausdorff_percent"] <= own * (1 + 1e-9), (name, level)
    bolt = run["reports"]["Bolt"]["levels"][0]
    assert bolt["requested_deviation_object_percent"] > 2 * bolt["requested_deviation_percent"], bolt
    for level, percent in zip(run["asset"]["levels"], (1.0, 4.0)):
        assert level["requested_deviation_percent"] == pytest.approx(percent, rel=1e-3)
        assert level["hausdorff_percent"] <= percent * (1 + 1e-9)
    # Every part is in every level of the asset. The decal, too small for a search of its
    # own, is searched with the rest (one run for the asset: LodJob._search_together): it
    # stays whole where the asset's bound allows nothing coarser (one mesh for both levels
    # then); per part it is an error.
    assert all(len(chain) == 2 for chain in run["lods"].values()), run["lods"]
    decal = [lev["triangles"] for lev in run["lods"]["Decal"]]
    assert decal[0] == 2 and 1 <= decal[1] <= 2, decal
    assert any("LOD1 repeats the whole part" in w for w in run["reports"]["Decal"]["warnings"])
    # A part that cannot get coarser within a level's bound repeats the level before.
    for name, chain in run["lods"].items():
        for k in (1,):
            if chain[k]["triangles"] == chain[k - 1]["triangles"]:
                assert chain[k]["mesh"] == chain[k - 1]["mesh"], (name, chain)
                assert any(f"LOD{k + 1} repeats LOD{k}" in w for w in run["reports"][name]["warnings"])
    assert "Decal" in res["deviation_per_part"]["error"]
    # One search for the asset: every core run covers all of its parts (the controls' and
    # the lean's tracked-bound runs, at most three each, and a whole asset where a level
    # meets nothing), none a part alone.
    total = sum(run["source_triangles"].values()) - run["source_triangles"]["Bolt2"]  # (Bolt's mesh)
    assert run["core_runs"] and all(m == total for m in run["core_runs"]), (run["core_runs"], total)
    assert len(run["core_runs"]) <= 7
    # Every level of the asset is within its bound (measured in % of the asset's size,
    # with the area-sampled measure's allowance over the tracked bound: core.Options).
    for level, percent in zip(run["asset"]["levels"], (1.0, 4.0)):
        assert level["hausdorff_percent"] <= 1.5 * percent


def test_importance_on_one_part_keeps_the_asset_in_one_run(res):
    """The hull alone painted (Importance: Vertex Group; the bolts and the decal have no
    such group): its importance exponents are nothing to the unpainted parts, so the
    asset is still one core run by ratios, and one search by deviation; the painted hull
    keeps more of the budget than unpainted."""
    painted, plain = res["importance_one_part"], res["asset"]
    assert "error" not in painted, painted.get("error")
    assert painted["together"] and len(painted["core_runs"]) == 1, painted["core_runs"]
    hull = [lev["triangles"] for lev in painted["lods"]["Hull"]]
    assert all(a > b for a, b in zip(hull, (lev["triangles"] for lev in plain["lods"]["Hull"]))), hull
    assert 'no importance (no vertex group "Face")' in painted["reports"]["Bolt"]["warnings"]
    assert not any(w.startswith("no importance") for w in painted["reports"]["Hull"]["warnings"])
    error = res["importance_no_part_painted"]["error"]
    assert error.startswith('Importance group "Face": none of the 4 objects'), error
    searched = res["importance_one_part_deviation"]
    assert "error" not in searched, searched.get("error")
    total = sum(searched["source_triangles"].values()) - searched["source_triangles"]["Bolt2"]  # (Bolt's mesh)
    assert searched["core_runs"] and all(m == total for m in searched["core_runs"]), searched["core_runs"]


def test_an_asset_too_small_for_its_chain_is_an_error(res):
    error = res["too_small"]["error"]
    assert error.startswith("the asset of 4 objects") and "10000" in error


def test_small_parts_leave_far_levels_unless_kept(res):
    """At 0.6 % the hull's collapses cost more than twice a bolt's whole size: the bolts
    leave the asset (their removal costs less), with a note, and the budget goes to the
    hull. With Remove Small Parts off every part stays."""
    far, kept = res["far"], res["far_kept"]
    assert "error" not in far and "error" not in kept
    bolt = far["lods"]["Bolt"]
    assert len(bolt) < 4 and len(far["lods"]["Bolt2"]) == len(bolt)
    assert any(f"leaves the asset from LOD{len(bolt) + 1}" in w for w in far["reports"]["Bolt"]["warnings"])
    last = far["asset"]["levels"][-1]
    assert last["parts"] < 4
    drawn_source = sum(far["source_triangles"].values())
    # Where every collapse left costs more than a bolt, the bolts go even if the level then
    # ends under its budget, by at most what they drew at the level before (core.engine).
    budget = round(0.006 * drawn_source)
    gone = sum(far["lods"][name][-1]["triangles"] for name in ("Bolt", "Bolt2"))
    assert budget - gone - 2 <= last["triangles"] <= budget + 2, (last["triangles"], budget, gone)
    assert far["lods"]["Hull"][-1]["triangles"] > kept["lods"]["Hull"][-1]["triangles"]
    assert all(len(chain) == 4 for chain in kept["lods"].values())


def test_a_part_under_a_limit_in_pixels_gets_its_share_under_that_limit(res):
    """The hull's top held to 0.1 px where each level switches in (the bolts and the decal
    have no such group): the split by error curves runs the hull's curve under that limit
    (asset.pixel_limited_curve), so where the asset's budget allows, the hull gets more
    than its unlimited share and the other parts give it, rather than the hull meeting
    its free share by tearing its unpainted bottom away."""
    held, free = res["limit_pixels"], res["asset_split"]
    assert not held["together"] and "error" not in held, held.get("error")
    hull = held["reports"]["Hull"]["levels"]
    drawn_source = sum(held["source_triangles"].values())
    for k in (0, 1):  # levels the budget can meet with the region held
        drawn = sum(chain[k]["triangles"] for chain in held["lods"].values() if len(chain) > k)  # (bolts leave)
        # Within its budget, but that a part leaves whole (core.budget.split_by_error: at
        # the level where it may go, the nearer of its last count and none). So the level
        # may end under its budget by what the parts leaving there drew at the level
        # before (the bolts at LOD2 with Blender 4.5: 1,117 for 1,192), or over it by what
        # the parts at their last level keep (with 5.2's primitives the bolts keep 78 each
        # at LOD2 and leave at LOD3: 1,267).
        budget = RATIOS[k] * drawn_source
        gone = sum(chain[k - 1]["triangles"] for chain in held["lods"].values() if k and len(chain) == k)
        last = sum(chain[k]["triangles"] for chain in held["lods"].values() if len(chain) == k + 1 < 3)
        slack = max(2, 0.01 * budget)
        assert budget - gone - slack <= drawn <= budget + last + slack, (k, drawn, gone, last)
        assert hull[k]["triangles"] > free["lods"]["Hull"][k]["triangles"]
        # Its held top (0.1 px: nearly still) is two fifths of its triangles, so the rest
        # goes coarser than unpainted (5-11x the distance at LOD2), but it is not torn as at
        # LOD3, whose budget no split can meet with the top held (the hull stops at the
        # limit after tearing its bottom: 13.9 % of its size). Given its free share, the
        # hull met LOD2 so too (13.6 %).
        assert hull[k]["hausdorff_percent"] <= 0.25 * hull[2]["hausdorff_percent"], k
    assert hull[2]["stop_reason"] == "limit_reached"
    for level in hull:
        kept = level["limit"]
        assert kept["within"] and kept["region_pixels"] <= 0.1 * (1 + 1e-9), kept
    # The parts without the group say they are free.
    assert any('no vertex group "Face"' in w for w in held["reports"]["Bolt"]["warnings"])


def test_a_part_whose_modifiers_leave_no_faces_is_left_out_with_a_note(res):
    """A cube whose Mask modifier leaves nothing drew nothing: the asset goes on without
    it, with a note, and its budget is the other parts'. It failed the asset before:
    '"Masked" has an empty mesh'."""
    run, plain = res["masked"], res["asset"]
    assert "error" not in run, run.get("error")
    assert run["skipped"] == ['"Masked" skipped: its modifiers leave no faces']
    assert "Masked" not in run["lods"] and sorted(run["lods"]) == sorted(plain["lods"])
    assert_same_counts(run["asset"]["levels"], plain["asset"]["levels"])


def test_boolean_cutters_render_disabled_objects_collision_meshes_and_own_lods_are_not_parts(res):
    """Selected with the parts, a Boolean cutter (a wire cylinder the hull's modifier cuts
    with), a box disabled in renders, a "UCX_" collision box and the file's own "Hull_LOD1"
    are left out with a note each: no LODs of their own, no share of the budget, which is
    what the asset draws (the hull as its Boolean modifier leaves it). Before, they were
    parts: the cutter took a share of every level and its LODs were drawn solid, and an
    asset-store file's LOD1 and LOD2 got LODs of their own beside its LOD0's."""
    run = res["helpers"]
    assert "error" not in run, run.get("error")
    assert run["skipped"] == [
        '"Cutter" skipped: a Boolean modifier\'s operand (its shape is already in the object whose modifier uses it)',
        '"Proxy" skipped: disabled in renders',
        '"UCX_Hull" skipped: a collision mesh (Unreal\'s UCX_ naming), which engines take as it is',
        '"Hull_LOD1" skipped: an existing LOD1 of "Hull" (by its name): "Hull" is the source']
    assert sorted(run["lods"]) == ["Bolt", "Bolt2", "Decal", "Hull"], sorted(run["lods"])
    assert run["unchanged"]
    drawn = run["drawn_triangles"]
    asset = drawn["Hull"] + 2 * drawn["Bolt"] + drawn["Decal"]
    assert drawn["Hull"] != run["source_triangles"]["Hull"]  # the hole is cut
    assert run["asset"]["source_triangles"] == asset, run["asset"]
    for k, level in enumerate(run["asset"]["levels"]):
        assert abs(level["triangles"] - RATIOS[k] * asset) <= max(4, 0.01 * asset * RATIOS[k]), (k, level)


def test_a_files_own_lods_are_found_by_the_names_engines_give_them(res):
    """Level 1 and up of a name with a level 0 (or a base name) beside it; a lone
    "Rock_LOD1" or "Cup_LOD10" is a part like any other."""
    named = res["named_lods"]
    assert sorted(named) == ["Chair LOD2", "Chair_LOD1", "TreeLOD1", "Tree_LOD2", "chair.lod3"], named
    assert named["chair.lod3"] == 'an existing LOD3 of "Chair" (by its name): "Chair" is the source'
    assert named["TreeLOD1"] == 'an existing LOD1 of "Tree_LOD0" (by its name): "Tree_LOD0" is the source'
