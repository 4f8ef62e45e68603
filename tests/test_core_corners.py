"""Feature corners that crowd a LOD give way when they are smaller than its error
(core.engine._release_small_corners, issue 33 §3 on CAD exports), and the corner spacing
they are judged by (core.features.nearest_other). The shapes whose corners must stay (a
box, a polygon plate, logos) are in tests/test_core_targets.py."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from hypothesis import given, settings, strategies as st

from core import engine, features


def brute_nearest(p):
    d = np.linalg.norm(p[:, None] - p[None], axis=2)
    np.fill_diagonal(d, np.inf)
    return d.min(axis=1)


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 300), st.integers(0, 2**16), st.sampled_from(["normal", "clusters"]))
def test_nearest_other_is_exact_by_pairs_and_by_grid(k, seed, spread):
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(k, 3)) * [1.0, 0.3, 3.0]
    if spread == "clusters":  # dense clusters far apart (bolt holes on a hull), and duplicates
        p = rng.normal(size=(5, 3))[rng.integers(0, 5, k)] * 100.0 + p * 1e-3
        p[: k // 10] = p[0]
    exact = brute_nearest(p)
    np.testing.assert_allclose(features.nearest_other(p), exact, rtol=1e-12, atol=0)
    np.testing.assert_allclose(features.nearest_other(p, brute_force_below=0), exact, rtol=1e-9, atol=1e-12)


def test_a_lone_corner_has_no_neighbour():
    assert np.isinf(features.nearest_other(np.zeros((1, 3)))).all()
    assert len(features.nearest_other(np.zeros((0, 3)))) == 0


def state(corners, size, error, faces_around=1):
    n = len(corners)
    return SimpleNamespace(corners=np.asarray(corners, dtype=bool), corner_size=np.asarray(size, dtype=float),
                           max_error_seen=error, face_count=np.full(n, faces_around))


def test_crowding_small_corners_give_way_and_large_ones_stay():
    # 6 corners, four of them a bolt hole's (0.01 apart), two a box's (1 apart).
    size = [0.01, 0.01, 0.01, 0.01, 1.0, 1.0, np.inf, np.inf]
    corners = [True] * 6 + [False] * 2
    s = state(corners, size, error=0.01)
    engine._release_small_corners(s, target=12)  # room for 0.5 * 6 = 3 corners: crowded
    assert s.corners.tolist() == [False] * 4 + [True, True, False, False]


def test_corners_stay_while_there_is_room_or_while_they_are_larger_than_the_error():
    size = [0.01] * 4 + [np.inf] * 4
    corners = [True] * 4 + [False] * 4
    roomy = state(corners, size, error=1.0)
    engine._release_small_corners(roomy, target=100)  # room for 25
    assert roomy.corners.tolist() == corners
    fine = state(corners, size, error=0.004)  # 2 x 0.004 < 0.01
    engine._release_small_corners(fine, target=4)
    assert fine.corners.tolist() == corners
    # Gone vertices (no faces) do not count towards the crowd.
    gone = state(corners, size, error=1.0, faces_around=0)
    engine._release_small_corners(gone, target=4)
    assert gone.corners.tolist() == corners
