"""Painted limits (issue 34 §1): ``vertex_max_error`` bounds how far the LOD may move
around each vertex, the count target is met elsewhere, and a limit that makes it
unreachable stops the run with its own reason. Checked by brute force."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import core
from core.tracked_distance import LIMIT_GRID

import mesh_builders as build
import mesh_checks as check
from surface_distance import distance_to_mesh


def _bumpy_sphere(level: int = 3):
    V, F = build.icosphere(level)
    V = V * (1 + 0.06 * np.sin(9 * V[:, 0]) * np.sin(7 * V[:, 1]))[:, None]
    return V, F


def _diagonal(V) -> float:
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def _tracked_points(V, F, limited):
    """The source points a limit is promised at: the limited vertices, and the points
    core.tracked_distance follows inside faces whose corners are all limited."""
    steps = LIMIT_GRID
    grid = np.array([(steps - i - j, i, j) for i in range(steps + 1) for j in range(steps + 1 - i)]) / steps
    inside = F[limited[F].all(axis=1)]
    return np.concatenate([V[limited], np.einsum("gk,fkj->fgj", grid, V[inside]).reshape(-1, 3)])


@pytest.mark.parametrize("ratio, share", [(0.25, 0.0015), (0.1, 0.003)])
def test_a_painted_region_stays_within_its_limit_both_ways(ratio, share):
    V, F = _bumpy_sphere(4)
    limit = share * _diagonal(V)
    region = V[:, 2] > 0.0
    limits = np.where(region, limit, np.inf)
    target = int(round(ratio * len(F)))

    free = core.simplify(V, F, ratio=ratio)
    held = core.simplify(V, F, ratio=ratio, vertex_max_error=limits)
    check.assert_valid_result(held, V, F)
    # The count is met elsewhere: the free half gives what the painted half keeps.
    assert held.stats.stop_reason == core.STOP_TARGET and len(held.faces) == target
    points = _tracked_points(V, F, region)
    # Without the limit the region moves further (the test can fail)...
    assert distance_to_mesh(points, free.vertices, free.faces).max() > 1.2 * limit
    # ...with it, the source's tracked points are within it (sure bounds), and so are the
    # LOD's vertices well inside the region.
    assert distance_to_mesh(points, held.vertices, held.faces).max() <= limit * (1 + 1e-9)
    inner = held.vertices[held.vertices[:, 2] > 0.2]
    assert len(inner) and distance_to_mesh(inner, V, F).max() <= limit * (1 + 1e-9)
    # The painted half keeps more of its triangles than without the limit.
    up = lambda r: int(np.count_nonzero(r.vertices[r.faces].mean(axis=1)[:, 2] > 0))  # noqa: E731
    assert up(held) > up(free)


def test_a_limit_that_makes_the_count_unreachable_stops_the_run_with_its_own_reason():
    V, F = _bumpy_sphere()
    limits = np.full(len(V), 0.001 * _diagonal(V))
    r = core.simplify(V, F, ratio=0.02, vertex_max_error=limits)
    check.assert_valid_result(r, V, F)
    assert r.stats.stop_reason == core.STOP_LIMIT
    assert len(r.faces) > 0.02 * len(F) + 10
    assert core.STOP_LIMIT in core.STOP_REASON_TEXT
    assert distance_to_mesh(V, r.vertices, r.faces).max() <= limits[0] * (1 + 1e-9)
    assert core.simplify(V, F, ratio=0.02).stats.stop_reason == core.STOP_TARGET


def test_under_a_chain_of_max_error_bounds_the_stop_names_the_limit_when_it_holds_most():
    V, F = _bumpy_sphere()
    d = _diagonal(V)
    limits = np.where(V[:, 2] > 0, 0.001 * d, np.inf)
    results = core.simplify_chain(V, F, [600, 200, 20], vertex_max_error=limits,
                                  max_error=[0.01 * d, 0.02 * d, 0.05 * d])
    assert [r.stats.stop_reason for r in results][1:] == [core.STOP_LIMIT] * 2
    assert len(results[-1].faces) > 200


def test_weights_between_scale_the_limit_at_every_vertex():
    V, F = _bumpy_sphere()
    d = _diagonal(V)
    # A painted gradient: weight w gives a limit L / w, free at 0.
    w = np.clip(V[:, 0] + 0.3, 0.0, 1.0)
    with np.errstate(divide="ignore"):
        limits = 0.003 * d / w
    r = core.simplify(V, F, ratio=0.1, vertex_max_error=limits)
    check.assert_valid_result(r, V, F)
    gap = distance_to_mesh(V, r.vertices, r.faces)
    assert (gap <= limits * (1 + 1e-9)).all()
    # The limit binds where it is tight: vertices there are nearer than where it is loose.
    assert gap[w > 0.9].max() < gap[w == 0].max()


def test_only_parts_without_a_limit_may_be_removed():
    sphere = _bumpy_sphere(3)
    bolts = [build.cube(1)[:2] for _ in range(4)]
    bolts = [(v * 0.05 + np.array([1.5 + 0.3 * i, 0.0, 0.0]), f) for i, (v, f) in enumerate(bolts)]
    V, F = build.components([sphere] + bolts)
    painted_bolt = np.zeros(len(V), dtype=bool)
    painted_bolt[len(sphere[0]) + len(bolts[0][0]):len(sphere[0]) + 2 * len(bolts[0][0])] = True
    limits = np.where(painted_bolt, 0.5 * _diagonal(V), np.inf)
    r = core.simplify(V, F, target_faces=10, vertex_max_error=limits)
    check.assert_valid_result(r, V, F)
    assert r.stats.removed_components >= 1
    kept = np.zeros(len(V), dtype=bool)
    kept[r.vertex_origin] = True
    assert kept[painted_bolt].any(), "the painted part was removed"


def test_no_finite_limit_is_no_limit():
    V, F = _bumpy_sphere()
    a = core.simplify(V, F, ratio=0.2)
    b = core.simplify(V, F, ratio=0.2, vertex_max_error=np.full(len(V), np.inf))
    assert np.array_equal(a.faces, b.faces) and np.array_equal(a.vertices, b.vertices)


@pytest.mark.parametrize("bad, words", [
    (lambda n: np.full(n, np.nan), "NaN"),
    (lambda n: np.zeros(n), "> 0"),
    (lambda n: -np.ones(n), "> 0"),
    (lambda n: np.ones(n + 1), "one value per vertex"),
])
def test_bad_limits_are_named(bad, words):
    V, F = _bumpy_sphere(1)
    with pytest.raises(ValueError, match="vertex_max_error") as info:
        core.simplify(V, F, ratio=0.5, vertex_max_error=bad(len(V)))
    assert words in str(info.value)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**16), share=st.floats(0.1, 0.9), ratio=st.floats(0.05, 0.6),
       scale=st.floats(0.001, 0.05))
def test_every_source_vertex_stays_within_its_own_limit(seed, share, ratio, scale):
    V, F = build.grid(14, height=build.bumps(0.15, 2.0), jitter=0.2, seed=seed)
    rng = np.random.default_rng(seed)
    limits = np.where(rng.random(len(V)) < share, scale * _diagonal(V) * (0.5 + rng.random(len(V))), np.inf)
    r = core.simplify(V, F, ratio=ratio, vertex_max_error=limits)
    check.assert_valid_result(r, V, F)
    assert r.stats.stop_reason in (core.STOP_TARGET, core.STOP_LIMIT)
    if r.stats.stop_reason == core.STOP_TARGET:
        assert len(r.faces) <= max(1, int(round(ratio * len(F))))
    assert (distance_to_mesh(V, r.vertices, r.faces) <= limits * (1 + 1e-9)).all()


def test_a_chain_takes_one_row_of_limits_per_level_each_holding_at_its_level():
    V, F = _bumpy_sphere(4)
    d = _diagonal(V)
    painted = np.where(V[:, 2] > 0, 1.0, np.inf)
    limits = np.stack([painted * 0.001 * d, painted * 0.002 * d, painted * 0.004 * d])
    results = core.simplify_chain(V, F, [2560, 1024, 256], vertex_max_error=limits)
    for r, row in zip(results, limits):
        check.assert_valid_result(r, V, F)
        assert (distance_to_mesh(V, r.vertices, r.faces) <= row * (1 + 1e-9)).all()
    # Each level goes on from the last under its own, larger limits: fewer triangles.
    assert len(results[2].faces) < len(results[1].faces) < len(results[0].faces)
    with pytest.raises(ValueError, match="must not decrease along the chain"):
        core.simplify_chain(V, F, [2560, 1024], vertex_max_error=limits[::-1][:2])
