"""core.shading: Blender's corner normals, the closest point on a triangle, the normal
interpolated there and the angle statistics the normal deviation reports (issue 22 §3).
Pure NumPy: the closest-point search over a whole mesh is addon/pure/measure.py's, tested in
tests/test_measure.py."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings, strategies as st

from core import shading
from core.geometry import closest_on_triangles
import mesh_builders as build

SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True,
                phases=[Phase.explicit, Phase.generate], max_examples=60)


def _unit(x):
    return x / np.linalg.norm(x, axis=-1, keepdims=True)


def _random_triangles(seed, k):
    rng = np.random.default_rng(seed)
    return rng.normal(size=(k, 3)), rng.normal(size=(k, 3)), rng.normal(size=(k, 3)), rng


# ------------------------------------------------------------------ interpolation, angles

@settings(**SETTINGS)
@given(seed=st.integers(0, 2**32 - 1))
def test_interpolation_at_a_corner_is_that_corners_normal(seed):
    rng = np.random.default_rng(seed)
    normals = _unit(rng.normal(size=(7, 3, 3)))
    tri = rng.integers(0, 7, 30)
    corner = rng.integers(0, 3, 30)
    at = shading.interpolate(normals, tri, np.eye(3)[corner])
    assert np.allclose(at, normals[tri, corner], atol=1e-12)


def test_interpolation_between_two_normals_is_their_bisector_made_unit():
    normals = np.array([[[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]])
    at = shading.interpolate(normals, [0], [[0.5, 0.5, 0.0]])
    assert np.allclose(at, [[2 ** -0.5, 0.0, 2 ** -0.5]])
    opposite = np.array([[[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]]])
    assert np.all(shading.interpolate(opposite, [0], [[0.5, 0.5, 0.0]]) == 0.0), "they cancel: zero, not NaN"


@pytest.mark.parametrize("tilt", [0.0, 0.5, 10.0, 30.0, 90.0, 135.0, 180.0])
def test_angle_of_a_known_tilt(tilt):
    up = np.tile([0.0, 0.0, 1.0], (5, 1))
    t = np.radians(tilt)
    tilted = np.tile([np.sin(t), 0.0, np.cos(t)], (5, 1)) * 3.0  # length does not matter
    assert np.allclose(shading.angles_degrees(up, tilted), tilt, atol=1e-9)


def test_a_zero_normal_is_ninety_degrees_from_anything():
    assert shading.angles_degrees([[0.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]]).tolist() == [90.0]


def test_angle_summary():
    s = shading.angle_summary(np.arange(101.0))
    assert s == {"mean": 50.0, "p95": 95.0, "max": 100.0}
    assert shading.angle_summary(np.empty(0)) == {"mean": 0.0, "p95": 0.0, "max": 0.0}


# ------------------------------------------------------------------ closest point

@settings(**SETTINGS)
@given(seed=st.integers(0, 2**32 - 1))
def test_closest_point_is_no_farther_than_any_point_of_the_triangle(seed):
    a, b, c, rng = _random_triangles(seed, 200)
    p = rng.normal(size=(200, 3)) * 2.0
    bary, _ = closest_on_triangles(p, a, b, c)
    assert np.all(bary >= -1e-12) and np.allclose(bary.sum(axis=1), 1.0)
    q = bary[:, :1] * a + bary[:, 1:2] * b + bary[:, 2:] * c
    d = np.linalg.norm(q - p, axis=1)
    # Against a fine barycentric grid (and the corners) of every triangle.
    n = 24
    for i in range(n + 1):
        for j in range(n + 1 - i):
            other = (i * a + j * b + (n - i - j) * c) / n
            assert np.all(d <= np.linalg.norm(other - p, axis=1) + 1e-9)


@settings(**SETTINGS)
@given(seed=st.integers(0, 2**32 - 1))
def test_a_point_on_the_triangle_is_its_own_closest_point(seed):
    a, b, c, rng = _random_triangles(seed, 100)
    w = rng.dirichlet([1.0, 1.0, 1.0], 100)
    p = w[:, :1] * a + w[:, 1:2] * b + w[:, 2:] * c
    assert np.allclose(closest_on_triangles(p, a, b, c)[0], w, atol=1e-7)


def test_degenerate_triangles_are_their_edges():
    a = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    b = np.array([[2.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    c = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])  # a segment, and a point
    p = np.array([[1.5, 1.0, 0.0], [1.0, 1.0, 1.0]])
    bary, _ = closest_on_triangles(p, a, b, c)
    assert np.all(np.isfinite(bary))
    q = bary[:, :1] * a + bary[:, 1:2] * b + bary[:, 2:] * c
    assert np.allclose(q, [[1.5, 0.0, 0.0], [0.0, 0.0, 0.0]])


# ------------------------------------------------------------------ Blender's corner normals

def _face_normals(v, f):
    return _unit(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]))


def test_flat_faces_get_their_own_normal():
    v, f = build.icosphere(2)
    n = shading.corner_normals(v, f, np.zeros(len(f), bool))
    assert np.allclose(n, _face_normals(v, f)[:, None, :])


def test_a_smooth_plane_is_up_everywhere():
    v, f = build.grid(6, jitter=0.2)
    n = shading.corner_normals(v, f, np.ones(len(f), bool))
    assert np.allclose(n, [0.0, 0.0, 1.0])


def test_a_smooth_cube_points_along_its_diagonals_and_sharp_edges_make_it_flat():
    v, f, _ = build.cube(3)
    n = shading.corner_normals(v, f, np.ones(len(f), bool))
    # Angle-weighted: each side meets a cube corner at 90 degrees, however it is split.
    corner = np.all(np.abs(v[f]) == 1.0, axis=2)
    assert np.allclose(n[corner], np.sign(v[f][corner]) / 3 ** 0.5)
    # The cube's twelve edges marked sharp: every corner shades like its side.
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    on_cube_edge = (np.abs(v[edges]) == 1.0).sum(axis=2).min(axis=1) >= 2
    hard = shading.corner_normals(v, f, np.ones(len(f), bool), np.unique(edges[on_cube_edge], axis=0))
    assert np.allclose(hard, _face_normals(v, f)[:, None, :])


def test_fans_split_at_boundaries_of_flat_faces_and_wrong_winding():
    # Two triangles folded 90 degrees along the edge 0-1.
    v = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    f = np.array([[0, 1, 2], [1, 0, 3]])
    fn = _face_normals(v, f)
    smooth = shading.corner_normals(v, f, [True, True])
    assert np.allclose(smooth[0, :2], _unit(fn[0] + fn[1]))  # along the fold: the mean
    assert np.allclose(smooth[0, 2], fn[0]) and np.allclose(smooth[1, 2], fn[1])  # alone
    one_flat = shading.corner_normals(v, f, [True, False])
    assert np.allclose(one_flat, fn[:, None, :])
    flipped = f.copy()
    flipped[1] = [0, 1, 3]  # both faces wind 0 -> 1: Blender splits there
    assert np.allclose(shading.corner_normals(v, flipped, [True, True]), _face_normals(v, flipped)[:, None, :])


# ------------------------------------------------- same triangles (core.geometry), for measuring

@pytest.mark.parametrize("seed", range(5))
def test_same_triangles_finds_each_shared_triangle_whatever_its_rotation_and_winding(seed):
    """b: some of a's triangles (rotated, some wound the other way, under other vertex
    ids), others moved by a hair; each shared one is found with its corner map, no other."""
    from core.geometry import same_points, same_triangles

    rng = np.random.default_rng(seed)
    va = rng.random((40, 3))
    fa = np.array([rng.choice(40, 3, replace=False) for _ in range(60)])
    relabel = rng.permutation(40)
    vb = np.empty_like(va)
    vb[relabel] = va
    fb = relabel[fa].copy()
    shift = rng.integers(0, 3, len(fb))
    fb = np.take_along_axis(fb, (np.arange(3)[None, :] + shift[:, None]) % 3, axis=1)
    flip = rng.random(len(fb)) < 0.5
    fb[flip] = fb[flip][:, ::-1]
    moved = rng.random(len(fb)) < 0.3
    vb_moved = np.concatenate([vb, vb[fb[moved]].reshape(-1, 3) + 1e-12])
    fb[moved] = len(vb) + np.arange(3 * int(moved.sum())).reshape(-1, 3)
    order = rng.permutation(len(fb))
    fb = fb[order]
    match, corner = same_triangles(va, fa, vb_moved, fb)
    expected = np.full(len(fa), -1)
    expected[order[~moved[order]]] = np.flatnonzero(~moved[order])
    np.testing.assert_array_equal(match, expected)
    hit = match >= 0
    np.testing.assert_array_equal(va[fa[hit]], np.take_along_axis(vb_moved[fb[match[hit]]], corner[hit][:, :, None], axis=1))
    points = same_points(va, vb_moved)
    np.testing.assert_array_equal(points, relabel)  # every a vertex is one of b's, moved copies aside


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 4))
def test_same_triangles_match_whichever_copies_of_a_position_the_triangles_use(seed, copies):
    """Meshes split along UV seams and hard edges have several vertices at one position.
    A triangle of a is found in b when b has a triangle at the same three positions, on
    any copies (a brute-force comparison of position sets), and the corner map is right."""
    from core.geometry import position_ids, same_triangles

    rng = np.random.default_rng(seed)
    points = rng.integers(0, 4, (12, 3)).astype(np.float64)  # few distinct positions: many repeats
    va = points[rng.integers(0, 12, 12 * copies)]
    vb = points[rng.integers(0, 12, 12 * copies)]
    fa = np.array([rng.choice(len(va), 3, replace=False) for _ in range(30)])
    fb = np.array([rng.choice(len(vb), 3, replace=False) for _ in range(30)])
    match, corner = same_triangles(va, fa, vb, fb)
    key = lambda v, f: tuple(sorted(map(tuple, v[f])))
    keys_b = [key(vb, t) for t in fb]
    for i, t in enumerate(fa):
        expected = keys_b.index(key(va, t)) if key(va, t) in keys_b else -1
        assert match[i] == expected
        if expected >= 0:
            np.testing.assert_array_equal(va[t], vb[fb[expected]][corner[i]])
    ids_a, ids_b = position_ids(va, vb)
    same = (va[:, None, :] == vb[None, :, :]).all(axis=2)
    np.testing.assert_array_equal(ids_a[:, None] == ids_b[None, :], same)
