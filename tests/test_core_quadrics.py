"""core.quadrics and core.vertex_quadrics against their definitions (paper Sec. 3, 4.1-4.3)."""
from __future__ import annotations

import numpy as np
import pytest

from core import quadrics, topology, vertex_quadrics
import mesh_builders as build
import mesh_checks as check


def _unit(rng, k):
    n = rng.normal(size=(k, 3))
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def test_plane_quadric_is_weighted_squared_point_plane_distance():
    rng = np.random.default_rng(1)
    k = 200
    n, p, w = _unit(rng, k), rng.normal(size=(k, 3)) * 3, rng.uniform(0.1, 5.0, k)
    x = rng.normal(size=(k, 3)) * 3
    q = quadrics.plane_quadrics(n, p, w)
    expected = w * np.einsum("ij,ij->i", n, x - p) ** 2
    np.testing.assert_allclose(quadrics.evaluate(q, x), expected, rtol=1e-9, atol=1e-9)
    # Zero on the plane itself.
    on_plane = x - n * np.einsum("ij,ij->i", n, x - p)[:, None]
    assert np.abs(quadrics.evaluate_raw(q, on_plane)).max() < 1e-9


def test_line_quadric_is_weighted_squared_point_line_distance():
    rng = np.random.default_rng(2)
    k = 200
    d, p, w = _unit(rng, k), rng.normal(size=(k, 3)) * 3, rng.uniform(0.1, 5.0, k)
    x = rng.normal(size=(k, 3)) * 3
    q = quadrics.line_quadrics(d, p, w)
    r = x - p
    perp = r - d * np.einsum("ij,ij->i", d, r)[:, None]
    expected = w * np.einsum("ij,ij->i", perp, perp)
    np.testing.assert_allclose(quadrics.evaluate(q, x), expected, rtol=1e-9, atol=1e-9)
    # Sliding along the line costs nothing (Eq. 13: the line, not a point).
    along = p + d * rng.normal(size=(k, 1)) * 5
    assert np.abs(quadrics.evaluate_raw(q, along)).max() < 1e-9


def test_point_quadric_is_weighted_squared_distance():
    rng = np.random.default_rng(3)
    p, x, w = rng.normal(size=(50, 3)), rng.normal(size=(50, 3)), rng.uniform(0.1, 2.0, 50)
    expected = w * ((x - p) ** 2).sum(1)
    np.testing.assert_allclose(quadrics.evaluate(quadrics.point_quadrics(p, w), x), expected, rtol=1e-9)


def test_summing_rows_sums_errors_and_accumulate_bins():
    rng = np.random.default_rng(4)
    k = 60
    q = np.concatenate([
        quadrics.plane_quadrics(_unit(rng, k), rng.normal(size=(k, 3)), rng.uniform(0.1, 2, k)),
        quadrics.line_quadrics(_unit(rng, k), rng.normal(size=(k, 3)), rng.uniform(0.1, 2, k)),
    ])
    x = rng.normal(size=(1, 3))
    total = quadrics.evaluate(q.sum(0, keepdims=True), x)[0]
    assert total == pytest.approx(quadrics.evaluate(q, np.repeat(x, len(q), 0)).sum(), rel=1e-10)
    # accumulate sums rows into bins like a per-vertex scatter-add.
    bins = rng.integers(0, 7, len(q))
    acc = quadrics.accumulate(bins, q, 9)
    expected = np.zeros((9, quadrics.QUADRIC_SIZE))
    np.add.at(expected, bins, q)
    np.testing.assert_allclose(acc, expected, rtol=1e-12, atol=1e-12)
    assert np.all(acc[7:] == 0)


def _pack(A, b, c):
    return np.array([A[0, 0], A[0, 1], A[0, 2], A[1, 1], A[1, 2], A[2, 2], b[0], b[1], b[2], c])


def test_minimize_solves_Ax_equals_minus_b_on_spd_systems():
    rng = np.random.default_rng(5)
    rows, xs = [], []
    for _ in range(50):
        R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        A = R @ np.diag(rng.uniform(1.0, 10.0, 3)) @ R.T  # SPD, condition number <= 10
        b = rng.normal(size=3)
        rows.append(_pack(A, b, 1.0))
        xs.append(np.linalg.solve(A, -b))
    q, expected = np.array(rows), np.array(xs)
    # The regularising point quadric (1e-6 of the scale) may pull by ~1e-6 per unit of
    # distance to the fallback, no more.
    fallback = expected + rng.normal(size=expected.shape)
    x = quadrics.minimize(q, fallback, 1.0)
    np.testing.assert_allclose(x, expected, rtol=0, atol=1e-5)
    # The optimum is a minimum: nudging it never lowers the error.
    e0 = quadrics.evaluate_raw(q, x)
    for step in np.eye(3) * 1e-3:
        assert np.all(quadrics.evaluate_raw(q, x + step) >= e0 - 1e-12)
        assert np.all(quadrics.evaluate_raw(q, x - step) >= e0 - 1e-12)


def test_minimize_never_fails_on_singular_systems():
    # A single plane quadric (rank 1) and an all-zero quadric: finite answers, near the fallback.
    q = np.stack([quadrics.plane_quadrics(np.array([[0.0, 0, 1]]), np.zeros((1, 3)), np.ones(1))[0],
                  np.zeros(quadrics.QUADRIC_SIZE)])
    fallback = np.array([[0.3, -0.2, 0.7], [1.0, 2.0, 3.0]])
    x = quadrics.minimize(q, fallback, 1.0)
    assert np.isfinite(x).all()
    np.testing.assert_allclose(x[0], [0.3, -0.2, 0.0], atol=1e-5)  # onto the plane, nearest fallback
    np.testing.assert_allclose(x[1], fallback[1], atol=1e-9)


def _flat_grid_quadrics(w, boundary_weight=1.0, n=8, sigma=0.0):
    V, F = build.grid(n, jitter=0.2, seed=7)
    V = V - 0.5  # near the engine's normalised frame (centred, unit-ish size)
    conn = topology.build(F, len(V))
    Q, area = vertex_quadrics.build(V, F, conn, np.full(len(V), w), None, boundary_weight, None, None, sigma)
    return V, F, Q, area


def _A(Q):
    A = np.empty((len(Q), 3, 3))
    idx = [(0, 0, 0), (0, 1, 1), (0, 2, 2), (1, 1, 3), (1, 2, 4), (2, 2, 5)]
    for i, j, c in idx:
        A[:, i, j] = A[:, j, i] = Q[:, c]
    return A


@pytest.mark.parametrize("w", [1e-4, 1e-3, 1e-1])
def test_vertex_quadric_is_well_conditioned_on_flat_input_with_line_weight(w):
    V, F, Q, area = _flat_grid_quadrics(w, boundary_weight=0.0)
    cond = np.linalg.cond(_A(Q))
    assert np.all(cond < 1e8), cond.max()
    # Interior flat vertex: A = a n n^T + w a (I - n n^T), condition exactly 1 / w.
    assert np.allclose(cond, 1.0 / w, rtol=1e-6)
    # Edge sums (what the engine minimises) are just as well conditioned.
    e, _ = check.edge_table(F)
    assert np.all(np.linalg.cond(_A(Q[e[:, 0]] + Q[e[:, 1]])) < 1e8)


def test_vertex_quadric_without_line_weight_is_singular_on_flat_input():
    # The counterpart: plain Garland-Heckbert on a plane cannot fix a position (Sec. 4.2).
    V, F, Q, area = _flat_grid_quadrics(0.0, boundary_weight=0.0)
    assert np.all(np.linalg.cond(_A(Q)) > 1e12)


def test_vertex_areas_are_a_third_of_incident_faces():
    V, F, Q, area = _flat_grid_quadrics(1e-3)
    fa = 0.5 * np.linalg.norm(check.face_normals(V, F), axis=1)
    expected = np.bincount(F.ravel(), weights=np.repeat(fa / 3, 3), minlength=len(V))
    np.testing.assert_allclose(area, expected, rtol=1e-12)
    assert area.sum() == pytest.approx(1.0, rel=1e-12)  # the unit square


def test_vertex_quadric_line_term_is_w_times_area_times_line_distance():
    # Build with w and with 0: the difference is w a_i d_line(x)^2 along the vertex normal (+z).
    V, F, Q1, area = _flat_grid_quadrics(0.01)
    _, _, Q0, _ = _flat_grid_quadrics(0.0)
    rng = np.random.default_rng(8)
    x = V + rng.normal(size=V.shape) * 0.1
    diff = quadrics.evaluate_raw(Q1, x) - quadrics.evaluate_raw(Q0, x)
    expected = 0.01 * area * ((x[:, :2] - V[:, :2]) ** 2).sum(1)
    np.testing.assert_allclose(diff, expected, rtol=1e-8, atol=1e-14)


def test_probabilistic_term_is_sigma_squared_times_area_times_point_distance():
    # TK20's isotropic normal noise: in expectation a plane through p costs
    # sigma^2 |x - p|^2 more, with p the vertex; here area-weighted like the planes.
    V, F, Q1, area = _flat_grid_quadrics(0.0, sigma=0.05)
    _, _, Q0, _ = _flat_grid_quadrics(0.0)
    rng = np.random.default_rng(9)
    x = V + rng.normal(size=V.shape) * 0.1
    diff = quadrics.evaluate_raw(Q1, x) - quadrics.evaluate_raw(Q0, x)
    np.testing.assert_allclose(diff, 0.05**2 * area * ((x - V) ** 2).sum(1), rtol=1e-8, atol=1e-14)
    # ... and like the line quadric it makes the flat-region solve well-posed.
    assert np.all(np.linalg.cond(_A(Q1)) < 1e8)


def test_optimum_on_a_plane_is_the_area_weighted_centroid():
    """Sec. 4.3: on a plane the summed line quadrics (weights = vertex areas) are minimised
    by the area-weighted mean of the vertices, the Fréchet mean."""
    rng = np.random.default_rng(9)
    for trial in range(20):
        k = rng.integers(2, 12)
        p = np.c_[rng.uniform(-1, 1, (k, 2)), np.zeros(k)]
        a = rng.uniform(0.01, 1.0, k)
        up = np.tile([0.0, 0.0, 1.0], (k, 1))
        w = 10.0 ** rng.uniform(-4, -1)
        lines = quadrics.line_quadrics(up, p, w * a)
        planes = quadrics.plane_quadrics(up, p, a)  # zero everywhere on the plane
        mean = (a[:, None] * p).sum(0) / a.sum()
        fallback = np.array([[0.9, -0.9, 0.0]])  # a point on the plane, far from the mean
        x = quadrics.minimize((lines + planes).sum(0, keepdims=True), fallback, a.mean())[0]
        # The regularising point quadric (weight eps = 1e-6 max(mean diagonal of A,
        # area_scale), the mean diagonal being (1 + 2w) S / 3 with S the area sum) competes
        # with the tangential stiffness w S: it may pull x towards the fallback by
        # eps / (w S) of the distance, no more.
        S = a.sum()
        pull = 1e-6 * max((1 + 2 * w) * S / 3, a.mean()) / (w * S)
        assert x[2] == pytest.approx(0.0, abs=1e-12)
        assert np.linalg.norm(x - mean) <= 1.01 * pull * np.linalg.norm(fallback[0] - mean) + 1e-12
        if w >= 1e-3:
            np.testing.assert_allclose(x, mean, atol=1e-3 * 1e-3 / w)
        # The line quadrics alone fix x and y (z is free along the lines).
        x_lines = quadrics.minimize(lines.sum(0, keepdims=True), fallback, a.mean())[0]
        pull_lines = 1e-6 * max(2 * w * S / 3, a.mean()) / (w * S)
        assert np.linalg.norm(x_lines[:2] - mean[:2]) <= 1.01 * pull_lines * np.linalg.norm(fallback[0] - mean) + 1e-12
        # Not the unweighted mean (unless the areas happen to agree).
        if np.ptp(a) > 0.3 and np.linalg.norm(p.mean(0) - mean) > 1e-2:
            assert np.linalg.norm(x - p.mean(0)) > 1e-3


def test_minimize_on_segment_finds_constrained_minimum():
    rng = np.random.default_rng(10)
    for _ in range(20):
        target = rng.normal(size=(1, 3))
        q = quadrics.point_quadrics(target, np.ones(1))
        p0, p1 = rng.normal(size=(1, 3)), rng.normal(size=(1, 3))
        x, t = quadrics.minimize_on_segment(q, p0, p1)
        ts = np.linspace(0, 1, 2001)
        pts = p0 + ts[:, None] * (p1 - p0)
        best = ts[np.argmin(((pts - target) ** 2).sum(1))]
        assert abs(t[0] - best) < 1e-3
        np.testing.assert_allclose(x[0], p0[0] + t[0] * (p1 - p0)[0], atol=1e-12)
