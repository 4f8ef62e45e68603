"""addon/pure/deviation_targets.py: the rung ladder and the bisection that picks, for each
requested deviation, the coarsest measured level within it."""
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from addon.pure import deviation_targets as dt


def test_ladder_steps_down_geometrically_to_the_floor():
    counts = dt.ladder(10_000)
    assert counts[:5] == [9900, 9700, 9400, 9000, 8500] and counts[-1] >= dt.LADDER_FLOOR
    assert all(b < a for a, b in zip(counts, counts[1:])), counts
    ratios = np.array(counts[5:]) / np.array(counts[4:-1])
    assert np.all(ratios[:20] == pytest.approx(dt.LADDER_STEP, abs=0.01)), ratios[:20]
    assert dt.ladder(4) == [] and dt.ladder(5) == [4], "nothing coarser than a tetrahedron"


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=1, max_size=60),
       st.lists(st.floats(1e-4, 1.0), min_size=1, max_size=4, unique=True))
def test_choices_are_the_coarsest_rungs_within_each_bound(steps, deviations):
    """With distance increasing along the ladder, the bisection finds what a scan would,
    and measures only a few rungs."""
    hausdorff = np.cumsum(steps)  # non-decreasing distances, rung by rung
    deviations = sorted(deviations)
    calls = []
    choices = dt.choose_levels(deviations, len(hausdorff), lambda i: calls.append(i) or hausdorff[i])
    below = -1
    for d, choice in zip(deviations, choices):
        within = [i for i in range(below + 1, len(hausdorff)) if hausdorff[i] <= d]
        expected = within[-1] if within else None
        assert choice.level == expected, (d, choice, hausdorff)
        if expected is not None:
            assert choice.hausdorff == hausdorff[expected] <= d
            below = expected
    assert len(set(calls)) <= len(deviations) * (int(np.log2(len(hausdorff))) + 2), calls


def test_every_choice_is_measured_within_its_bound_even_when_distance_wiggles():
    rng = np.random.default_rng(3)
    hausdorff = np.cumsum(rng.uniform(0, 1, 40)) * rng.uniform(0.8, 1.2, 40)  # not monotone
    chosen = 0
    for d in (2.0, 5.0, 11.0, 30.0):
        (choice,) = dt.choose_levels([d], len(hausdorff), lambda i: hausdorff[i])
        assert choice.level is None or hausdorff[choice.level] <= d, (d, choice)
        chosen += choice.level is not None
    assert chosen >= 3, "the larger bounds must find a level"


def test_bad_requests_are_named():
    with pytest.raises(ValueError, match="positive"):
        dt.choose_levels([0.0], 3, lambda i: 1.0)
    with pytest.raises(ValueError, match="increase"):
        dt.choose_levels([0.2, 0.1], 3, lambda i: 1.0)


def test_the_kept_rung_is_confirmed_by_the_exact_measurement():
    """The quick estimate misses a peak on rung 6; the report's measurement catches it,
    and the next finer rung that the exact measurement puts within the bound is kept."""
    quick = np.arange(10, dtype=float)  # rung i at distance i
    exact = quick.copy()
    exact[6] = 9.0
    (choice,) = dt.choose_levels([6.5], 10, lambda i: quick[i], lambda i: exact[i])
    assert (choice.level, choice.hausdorff) == (5, 5.0), choice


def test_counts_between_two_rungs():
    assert dt.between(576, 558) == [574, 572, 570, 568, 566, 564, 562, 560]
    assert dt.between(10, 9) == [], "nothing lies between adjacent counts"
    counts = dt.between(1000, 900, steps=3)
    assert counts == sorted(counts, reverse=True) and all(900 < c < 1000 for c in counts), counts


class _FakeLevel:
    def __init__(self, triangles, collapses=1):
        self.faces = range(triangles)  # only its length is used
        self.stats = SimpleNamespace(collapses=collapses)


def _fake_core(overshoot):
    """A core whose level for bound b has 1000/b triangles and measures ``overshoot``
    times b (the sampled distance above the tracked bound); records the bounds run."""
    runs = []

    def run(bounds, requested):
        runs.append(list(bounds))
        levels = [_FakeLevel(int(1000 / b)) for b in bounds]
        for level, b in zip(levels, bounds):
            level.measured = overshoot * b
        return levels

    return run, runs, lambda level: level.measured


@pytest.mark.parametrize("overshoot", [0.7, 1.0, 1.2, 1.4, 1.8])
def test_tracked_bounds_end_within_and_close(overshoot):
    """Every level ends within its deviation, however far the sampled distance overshoots
    the tracked bound, and not needlessly below it."""
    run, runs, exact = _fake_core(overshoot)
    found = dt.by_tracked_bounds([1.0, 2.0, 4.0], run, exact)
    assert all(f.level is not None and f.hausdorff <= f.deviation for f in found), found
    assert all(f.hausdorff >= 0.5 * f.deviation for f in found), found
    counts = [len(f.level.faces) for f in found]
    assert counts[0] > counts[1] > counts[2]
    assert len(runs) <= dt.TRACKED_RUNS
    assert len(runs[0]) == 6, "the first run stops twice a level: at its share and stretched"
    if overshoot * dt.STRETCH_SHARE <= dt.STRETCH_WITHIN:
        assert len(runs) == 1, "the stretched levels are within: no second run"
        assert [f.hausdorff for f in found] == pytest.approx([overshoot * dt.STRETCH_SHARE * f.deviation for f in found])
    elif dt.TRACKED_CLOSE <= overshoot * dt.TRACKED_SHARE <= 1.0:
        assert len(runs) == 1, "within and close on the first run: no second"
        assert [f.hausdorff for f in found] == pytest.approx([overshoot * dt.TRACKED_SHARE * f.deviation for f in found])
    elif overshoot * dt.TRACKED_SHARE > 1.0:
        assert runs[1][0] < runs[0][0], "the bound shrinks where the level came out beyond"
    else:
        assert runs[1][0] > runs[0][0], "the bound grows where the level came out needlessly close"
    assert all(f.hausdorff >= dt.TRACKED_CLOSE * f.deviation for f in found) or len(runs) == dt.TRACKED_RUNS


def test_a_run_again_stops_at_the_last_level_that_needs_it():
    """Only the first level comes out beyond: the run again makes that level alone, and
    the others keep what the first run made (a CAD engine's run paid its whole tail for
    a first level run again)."""
    runs = []

    def run(bounds, requested):
        runs.append(list(bounds))
        levels = [_FakeLevel(int(1000 / b)) for b in bounds]
        for level, b in zip(levels, bounds):
            level.measured = (1.8 if b < 1.0 else 1.0) * b  # the first level's bounds overshoot
        return levels

    found = dt.by_tracked_bounds([1.0, 2.0, 4.0], run, lambda level: level.measured)
    assert len(runs) >= 2 and all(len(r) == 1 for r in runs[1:]), runs
    assert all(f.level is not None and f.hausdorff <= f.deviation for f in found), found
    assert [f.hausdorff for f in found[1:]] == [dt.STRETCH_SHARE * 2.0, dt.STRETCH_SHARE * 4.0]


def test_a_bound_that_allows_no_collapse_is_no_lod_and_is_loosened():
    runs = []

    def run(bounds, requested):
        runs.append(list(bounds))
        return [_FakeLevel(100, collapses=0) if b < 1.0 else _FakeLevel(80) for b in bounds]

    found = dt.by_tracked_bounds([1.0], run, lambda level: 0.95)
    assert runs[0] == [dt.TRACKED_SHARE, dt.STRETCH_SHARE] and runs[1] == [1.0]
    assert len(found[0].level.faces) == 80


def test_tracked_bounds_leave_out_what_never_comes_within():
    run, runs, _ = _fake_core(1.0)
    found = dt.by_tracked_bounds([1.0, 2.0], run, lambda level: 1e9)
    assert [f.level for f in found] == [None, None] and len(runs) == dt.TRACKED_RUNS


def test_tracked_bounds_keep_each_level_coarser_than_the_one_before():
    """Two bounds that give the same level (a topology limit): the second is left out."""
    found = dt.by_tracked_bounds([1.0, 2.0], lambda bounds, requested: [_FakeLevel(50) for _ in bounds], lambda level: 0.0)
    assert found[0].level is not None and found[1].level is None


def _found(deviation, faces, share=0.5):
    """A Found of ``faces`` triangles (None: no level) measured at ``share`` of its deviation."""
    level = None if faces is None else SimpleNamespace(faces=np.zeros((faces, 3), dtype=np.int64))
    return dt.Found(deviation, level, float("nan") if faces is None else share * deviation)


def test_each_deviation_keeps_the_lean_run_where_it_saves_a_tenth():
    mine = [_found(1.0, 900), _found(2.0, None), _found(4.0, 300), _found(8.0, 100)]
    lean = [_found(1.0, 800), _found(2.0, 500), _found(4.0, 350), _found(8.0, 95)]
    kept = dt.fewest_each(mine, lean)
    assert [len(f.level.faces) for f in kept] == [800, 500, 300, 100]  # 95 saves only 5 %
    # Still each coarser than the one before: a lean level no coarser is left out.
    kept = dt.fewest_each([_found(1.0, 900), _found(2.0, 950)], [_found(1.0, 400), _found(2.0, None)])  # noqa
    assert len(kept[0].level.faces) == 400 and kept[1].level is None


def test_a_smaller_saving_is_kept_where_it_costs_no_slivers_and_no_margin():
    """fewest_each with ``slivers``: a level under a tenth fewer triangles replaces the
    controls' where its share of slivers is no larger and it measures within
    STRETCH_WITHIN of its deviation; otherwise the tenth still decides."""
    def found(deviation, faces, share, slivers):
        level = SimpleNamespace(faces=np.zeros((faces, 3), dtype=np.int64), slivers=slivers)
        return dt.Found(deviation, level, share * deviation)

    def slivers(level):
        return level.slivers

    mine = [found(1.0, 100, 0.9, 30.0), found(2.0, 80, 0.9, 30.0), found(4.0, 60, 0.9, 30.0),
            found(8.0, 40, 0.9, 30.0), found(16.0, 20, 0.9, 30.0)]
    other = [found(1.0, 95, 0.9, 28.8),  # fewer, fewer slivers, with margin: kept
             found(2.0, 76, 0.9, 30.5),  # more slivers
             found(4.0, 58, 0.99, 20.0),  # just under its bound
             found(8.0, 40, 0.5, 0.0),  # no fewer triangles
             found(16.0, 10, 0.99, 90.0)]  # half the triangles: the tenth decides
    kept = dt.fewest_each(mine, other, slivers=slivers)
    assert [len(f.level.faces) for f in kept] == [95, 80, 60, 40, 10]
    assert kept[0].hausdorff == 0.9 and kept[0].level.slivers == 28.8
    # Without ``slivers`` only the tenth counts.
    mine = [found(1.0, 100, 0.9, 30.0)]
    assert len(dt.fewest_each(mine, [found(1.0, 95, 0.9, 28.8)])[0].level.faces) == 100


def test_a_part_of_an_asset_is_measured_by_its_area_share_and_its_size():
    """deviation_search.part_samples (issue 32 §2): a part gets its share of the asset's
    samples, at least one a triangle up to ASSET_PART_SAMPLES_MIN, so that an asset of
    many small parts is not measured with the floor once per part."""
    from addon.pure import deviation_search as ds

    floor = ds.ASSET_PART_SAMPLES_MIN
    asset = ds.report_samples(96_000)
    assert ds.part_samples(0.5, 96_000, 48_000) == int(np.ceil(0.5 * asset))  # its share
    assert ds.part_samples(1e-4, 96_000, floor // 2) == floor // 2  # a small part: one a triangle
    assert ds.part_samples(1e-4, 96_000, 10 * floor) == floor  # a large one with little area
    assert ds.part_samples(0.0, 96_000, 0) == 1
    # 300 equal parts of 320 triangles: the floor or one a triangle, whichever is fewer,
    # where its share is less; together a small multiple of what the asset gets as one.
    parts = [ds.part_samples(1 / 300, 96_000, 320) for _ in range(300)]
    assert parts == [max(min(floor, 320), int(np.ceil(asset / 300)))] * 300
    assert sum(parts) <= 4 * asset


def test_the_search_climbs_from_seeds_in_proportion_to_a_level_samples(monkeypatch):
    """deviation_search.search_report: SEARCH_CLIMB_SEEDS for a level measured with
    DEVIATION_SAMPLES, proportionally fewer for fewer samples (a small level, a part of an
    asset), never fewer than the report's own (measure.CLIMB_SEEDS)."""
    from addon.pure import deviation_search as ds
    from addon.pure import measure

    seeds = []
    monkeypatch.setattr(measure, "mesh_report", lambda *args, climb_seeds=None, **kw: seeds.append(climb_seeds))

    def level(triangles):
        return SimpleNamespace(vertices=np.zeros((3, 3)), faces=np.zeros((triangles, 3), dtype=np.int64))

    source = level(100_000)
    ds.search_report(source, level(50_000))  # capped at DEVIATION_SAMPLES
    ds.search_report(source, level(ds.DEVIATION_SAMPLES // ds.DEVIATION_SAMPLES_PER_TRIANGLE // 2))  # half of them
    ds.search_report(source, level(50_000), part_samples=ds.DEVIATION_SAMPLES // 4)  # a part: its share
    ds.search_report(source, level(10), part_samples=20)  # a bolt
    assert seeds == [ds.SEARCH_CLIMB_SEEDS, ds.SEARCH_CLIMB_SEEDS // 2, ds.SEARCH_CLIMB_SEEDS // 4, measure.CLIMB_SEEDS]


def test_a_level_measured_far_under_its_bound_is_probed_by_count_down_to_the_next():
    """probe_counts: below a level the tracked bound kept at under PROBE_BELOW of its
    deviation, decreasing counts down to PROBE_SHARE of its triangles, all coarser than
    the next level kept; none for a level measured close to its bound."""
    found = [_found(1.0, 1000, 0.5), _found(2.0, 700, 0.6), _found(4.0, 200, 0.9), _found(8.0, 60, 0.3)]
    first = dt.probe_counts(found, 0)
    assert first == sorted(first, reverse=True) and len(set(first)) == len(first)
    assert first[0] < 1000 and first[-1] == 701, "down to the next level kept, never to it"
    second = dt.probe_counts(found, 1)
    assert second[-1] == int(np.ceil(700 * dt.PROBE_SHARE)) and second[0] < 700 and len(second) > 2
    assert dt.probe_counts(found, 2) == [], "measured at 0.9 of its bound: nothing to probe"
    last = dt.probe_counts(found, 3)
    assert last[-1] == 30 and all(c < 60 for c in last)
    assert dt.probe_counts([_found(1.0, 5, 0.1)], 0) == [dt.LADDER_FLOOR], "a tetrahedron at least"
    assert dt.probe_counts([_found(1.0, 10, 0.1), _found(2.0, 9, 0.5)], 0) == [], "no count between"
    assert dt.probe_counts([dt.Found(1.0, None, float("nan"))], 0) == []


def test_the_probe_keeps_the_coarsest_count_measured_within_stretch_of_the_bound():
    """deviation_search.probe_below: the run by count's levels are measured (bisection,
    then the report's measurement) against STRETCH_WITHIN of the deviation; the coarsest
    within replaces the level; where none is, the level stays."""
    from addon.pure import deviation_search as ds

    runs = []

    def run_counts(counts):
        runs.append(list(counts))
        return [SimpleNamespace(faces=np.zeros((c, 3), dtype=np.int64)) for c in counts]

    def distance(level):  # grows as the count falls: the bound 1.0 at 100 triangles
        return 100.0 / len(level.faces)

    found = [_found(1.0, 200, 0.5), _found(4.0, 40, 0.9)]
    counts = dt.probe_counts(found, 0)
    ds.probe_below(found, run_counts, distance, distance)
    assert runs == [counts[:1], counts[1:]], "the finest count first; the second level is close to its bound"
    kept = len(found[0].level.faces)
    assert 100.0 / kept <= dt.STRETCH_WITHIN < 100.0 / min(c for c in counts if c < kept), runs
    assert found[0].hausdorff == 100.0 / kept and len(found[1].level.faces) == 40
    # Nothing below is within: the level stays as the tracked bound kept it.
    runs.clear()
    found = [_found(1.0, 200, 0.5)]
    ds.probe_below(found, run_counts, lambda level: 2.0, lambda level: 2.0)
    assert len(found[0].level.faces) == 200 and found[0].hausdorff == 0.5
    assert runs == [counts[:1]], "the finest count beyond: the coarser ones are not run"
