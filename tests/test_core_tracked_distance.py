"""max_error is a distance (issue 22): core.tracked_distance bounds how far the LOD is from
its source, and the bound holds when measured independently, by brute force."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import core
from core.geometry import closest_on_triangles
from core.tracked_distance import FACE_GRID, _barycentric_grid

import mesh_builders as build
import mesh_checks as check
from surface_distance import distance_to_mesh


def _on_triangles(vertices, faces, steps=6):
    """Points on every triangle: a barycentric grid with ``steps`` a side."""
    grid = np.array([(steps - i - j, i, j) for i in range(steps + 1) for j in range(steps + 1 - i)]) / steps
    return np.einsum("gk,fkj->fgj", grid, vertices[faces]).reshape(-1, 3)


coordinates = st.floats(-2, 2, allow_nan=False, allow_infinity=False)
point3 = st.tuples(coordinates, coordinates, coordinates)


@settings(max_examples=150, deadline=None)
@given(point3, point3, point3, point3)
def test_point_triangle_distance_is_the_distance_to_the_closest_point(p, a, b, c):
    p, a, b, c = (np.array([x], dtype=float) for x in (p, a, b, c))
    d = np.sqrt(closest_on_triangles(p, a, b, c)[1])[0]
    # Never more than the distance to any point of the triangle...
    samples = _on_triangles(np.concatenate([a, b, c]), np.array([[0, 1, 2]]), steps=40)
    nearest_sample = np.linalg.norm(samples - p, axis=1).min()
    assert d <= nearest_sample + 1e-9
    # ...and no less than that minus how far a grid point can be from the closest point.
    spacing = max(np.linalg.norm(a - b), np.linalg.norm(b - c), np.linalg.norm(c - a)) / 40
    assert d >= nearest_sample - spacing - 1e-9


def test_barycentric_grid_leaves_out_the_corners():
    grid = _barycentric_grid(3)
    assert len(grid) == 7 and np.allclose(grid.sum(axis=1), 1) and (grid.max(axis=1) < 1).all()


@pytest.mark.parametrize("bound", [0.01, 0.03])
def test_lod_stays_within_max_error_both_ways(bound):
    V, F = build.grid(24, height=build.bumps(0.12, 1.5))
    r = core.simplify(V, F, max_error=bound)
    check.assert_valid_result(r, V, F)
    assert r.stats.stop_reason == "max_error_reached"
    assert len(r.faces) < 0.5 * len(F)
    # The promise, checked at the tracked points (source vertices, points in its faces)
    # and at the LOD's vertices, by brute force against the whole other mesh.
    src_to_lod = distance_to_mesh(_on_triangles(V, F, steps=FACE_GRID), r.vertices, r.faces).max()
    lod_to_src = distance_to_mesh(r.vertices, V, F).max()
    assert src_to_lod <= bound * (1 + 1e-9), f"source to LOD {src_to_lod:.5f} > {bound}"
    assert lod_to_src <= bound * (1 + 1e-9), f"LOD to source {lod_to_src:.5f} > {bound}"
    assert r.stats.max_error <= bound * (1 + 1e-9)
    # Not needlessly careful: the LOD uses most of what it was allowed.
    assert max(src_to_lod, lod_to_src) > 0.5 * bound
    # Anywhere on the surfaces (denser points) it may stray a little beyond.
    dense = distance_to_mesh(_on_triangles(V, F, steps=8), r.vertices, r.faces).max()
    assert dense <= 1.5 * bound


def test_the_bound_is_in_mesh_units_whatever_the_scale():
    V, F = build.grid(16, height=build.bumps(0.12, 1.5))
    small = core.simplify(V, F, max_error=0.02)
    large = core.simplify(V * 100.0 + 5.0, F, max_error=2.0)
    assert len(small.faces) == len(large.faces)
    assert large.stats.max_error == pytest.approx(100.0 * small.stats.max_error, rel=1e-6)


def test_a_chain_of_bounds_gives_ever_coarser_levels_each_within_its_own():
    V, F = build.grid(24, height=build.bumps(0.12, 1.5))
    bounds = [0.005, 0.01, 0.03]
    levels = core.simplify_chain(V, F, [0, 0, 0], max_error=bounds)
    counts = [len(level.faces) for level in levels]
    assert counts[0] > counts[1] > counts[2]
    for level, bound in zip(levels, bounds):
        check.assert_valid_result(level, V, F)
        assert level.stats.max_error <= bound * (1 + 1e-9)
        assert distance_to_mesh(level.vertices, V, F).max() <= bound * (1 + 1e-9)
    # Each level is about what a single run with its bound gives (the collapse order differs).
    alone = core.simplify(V, F, max_error=bounds[-1])
    assert 2 / 3 <= counts[-1] / len(alone.faces) <= 3 / 2, (counts, len(alone.faces))


def test_face_targets_and_bounds_together_stop_at_whichever_comes_first():
    V, F = build.grid(24, height=build.bumps(0.12, 1.5))
    levels = core.simplify_chain(V, F, [900, 20], max_error=[0.005, 0.005])
    assert len(levels[0].faces) == 900 and levels[0].stats.stop_reason == "target_reached"
    assert len(levels[1].faces) > 20 and levels[1].stats.stop_reason == "max_error_reached"


@pytest.mark.parametrize("bad, message", [
    ([0.01, 0.005], "must not decrease"),
    ([0.01], "one per target"),
    ([0.01, -1.0], ">= 0"),
])
def test_bad_bound_chains_are_named(bad, message):
    V, F = build.grid(6)
    with pytest.raises(ValueError, match=message):
        core.simplify_chain(V, F, [40, 20], max_error=bad)


def test_a_triangle_with_collinear_corners_is_measured_as_its_edges():
    # Found by hypothesis: rounding left the cross term of these corners a hair above 0.
    p = np.array([[0.0, 1.0, 0.0]])
    a, b, c = np.array([[1.0, -0.5323396571642227, 0.0]]), np.array([[1.0, 1.5, 0.0]]), np.array([[1.0, 0.015625, 0.0]])
    bary, d2 = closest_on_triangles(p, a, b, c)
    assert d2[0] == pytest.approx(1.0) and np.allclose(bary @ np.concatenate([a, b, c]), [[1.0, 1.0, 0.0]])


def test_a_level_that_stops_at_its_face_target_hands_the_next_its_own_bound():
    V, F = build.grid(24, height=build.bumps(0.12, 1.5))
    loose_next = core.simplify_chain(V, F, [900, 0], max_error=[0.005, 0.03])
    same_next = core.simplify_chain(V, F, [900, 0], max_error=[0.005, 0.005])
    assert len(loose_next[0].faces) == len(same_next[0].faces) == 900
    assert len(loose_next[1].faces) < 0.5 * len(same_next[1].faces)
    assert 0.005 < loose_next[1].stats.max_error <= 0.03 * (1 + 1e-9)


def test_under_a_bound_no_part_is_removed_and_collapses_are_counted():
    V1, F1 = build.grid(16, height=build.bumps(0.12, 1.5))
    V2, F2 = build.grid(3)
    V = np.concatenate([V1, V2 + [3.0, 0.0, 0.0]])
    F = np.concatenate([F1, F2 + len(V1)])
    r = core.simplify(V, F, max_error=0.02, remove_small_components=True)
    assert r.stats.removed_components == 0 and r.stats.max_error <= 0.02 * (1 + 1e-9)
    assert distance_to_mesh(V, r.vertices, r.faces).max() <= 0.02 * (1 + 1e-9)
    assert r.stats.collapses > 0
    assert core.simplify(V1, F1, max_error=0.0).stats.collapses == 0  # (a flat part could, at no distance)


def test_a_level_under_max_error_ends_when_its_passes_crawl_with_every_rule_relaxed():
    """engine._crawling_under_bound: BOUND_CRAWL_PASSES passes in a row each under
    BOUND_CRAWL_SHARE of the faces left end the level; a pass above resets the count; not
    before the loosest rule step, nor without a global bound (painted limits only)."""
    from types import SimpleNamespace

    from core import engine
    from core.guards import relaxation_ladder

    ladder = relaxation_ladder()

    def state(step, global_bound=True):
        return SimpleNamespace(bound=SimpleNamespace(global_bound=global_bound), guards=ladder[step],
                               ladder=ladder, bound_crawl=0)

    faces, few, many = 100_000, 1, int(engine.BOUND_CRAWL_SHARE * 100_000) + 1
    s = state(len(ladder) - 1)
    calls = [engine._crawling_under_bound(s, few, faces) for _ in range(engine.BOUND_CRAWL_PASSES - 1)]
    assert not any(calls)
    assert not engine._crawling_under_bound(s, many, faces)  # a real pass: the count starts again
    calls = [engine._crawling_under_bound(s, few, faces) for _ in range(engine.BOUND_CRAWL_PASSES)]
    assert calls[-1] and not any(calls[:-1])
    for s in (state(len(ladder) - 2), state(len(ladder) - 1, global_bound=False)):
        assert not any(engine._crawling_under_bound(s, 0, faces) for _ in range(3 * engine.BOUND_CRAWL_PASSES))
    assert not engine._crawling_under_bound(SimpleNamespace(bound=None), 0, faces)


def test_collapses_the_source_side_rejects_skip_the_lod_side_and_the_result_is_the_same(monkeypatch):
    """The LOD side of a collapse is measured only where the source's points left it within
    the bound (TrackedDistance._lod_to_source_of): the same LODs as measuring both sides
    of every collapse, with fewer collapses measured on the LOD side."""
    from core.tracked_distance import TrackedDistance

    V, F = build.grid(24, height=build.bumps(0.12, 1.5))
    measured = {"staged": 0, "full": 0}
    whole = TrackedDistance._lod_to_source

    def counting(key):
        def lod_to_source(self, new_tri, *args):
            measured[key] += len(np.unique(args[1]))  # (the collapses of the rows measured)
            return whole(self, new_tri, *args)
        return lod_to_source

    monkeypatch.setattr(TrackedDistance, "_lod_to_source", counting("staged"))
    staged = core.simplify_chain(V, F, [0, 0], max_error=[0.01, 0.03])
    monkeypatch.setattr(TrackedDistance, "_lod_to_source_of",
                        lambda self, wanted, *args: TrackedDistance._lod_to_source(self, *args))
    monkeypatch.setattr(TrackedDistance, "_lod_to_source", counting("full"))
    full = core.simplify_chain(V, F, [0, 0], max_error=[0.01, 0.03])
    for a, b in zip(staged, full):
        assert np.array_equal(a.vertices, b.vertices) and np.array_equal(a.faces, b.faces)
    assert measured["staged"] < measured["full"], measured
