"""bench/sequential.py, the one-collapse-at-a-time reference of the paper's algorithm: its
output is a valid mesh at the target, and its first collapse is the globally cheapest
edge under the paper's cost. No bpy: only the command line part imports it."""
from __future__ import annotations

import numpy as np
import pytest

from bench import sequential
from core import prepare, quadrics, topology, vertex_quadrics
from mesh_builders import torus, tube
from mesh_checks import assert_valid_mesh, edge_table, euler_characteristic


def _bumpy_torus(seed=0):
    """A closed torus (Euler characteristic 0) with radial noise, so costs differ."""
    V, F = torus(nu=24, nv=12)
    rng = np.random.default_rng(seed)
    return V * (1.0 + 0.03 * rng.standard_normal(len(V)))[:, None], F


def _assert_clean(V, F):
    assert_valid_mesh(V, F)
    area2 = np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    assert area2.min() > 1e-9, "zero-area face"


@pytest.mark.parametrize("cost", ["paper", "per_area"])
def test_closed_mesh_stays_a_closed_manifold_at_the_target(cost):
    V, F = _bumpy_torus()
    target = 120  # even: a closed mesh loses exactly two faces per collapse
    out_v, out_f, info = sequential.simplify_sequential(V, F, target_faces=target, cost=cost)
    assert len(out_f) == target and info["output_faces"] == target
    assert info["stop_reason"] == "target_reached"
    assert info["passes"] == (len(F) - target) // 2
    _assert_clean(out_v, out_f)
    _, count = edge_table(out_f)
    assert np.all(count == 2), "closed input must give a closed output"
    assert euler_characteristic(out_f) == 0, "the torus's genus changed"


def test_open_mesh_keeps_its_borders():
    V, F = tube(n_around=24, n_height=12)
    out_v, out_f, info = sequential.simplify_sequential(V, F, target_faces=100)
    assert len(out_f) in (99, 100)
    _assert_clean(out_v, out_f)
    _, count = edge_table(out_f)
    assert count.max() == 2
    # An annulus still: two boundary loops, Euler characteristic 0.
    assert euler_characteristic(out_f) == 0
    border = edge_table(out_f)[0][count == 1]
    # The boundary planes are soft (quadrics, not constraints): near the rims, far less
    # than a row of the input (height 2 / 12 rows).
    z = out_v[np.unique(border), 2]
    assert np.all(np.isclose(z, 0.0, atol=0.01) | np.isclose(z, 2.0, atol=0.01)), "a border left its rim"


def test_first_collapse_is_the_cheapest_edge_at_its_optimal_position():
    V, F = _bumpy_torus(seed=1)
    # Brute force with core's own pieces: every edge's quadric error at its optimum.
    p = prepare.validate_and_prepare(V, F, [len(F) - 2])
    conn = topology.build(p.faces, len(p.vertices))
    Q, area = vertex_quadrics.build(p.vertices, p.faces, conn, p.line_weights, None, 1.0, None, None)
    a, b = conn.edges[:, 0], conn.edges[:, 1]
    q = Q[a] + Q[b]
    pos = quadrics.minimize(q, 0.5 * (p.vertices[a] + p.vertices[b]), float(area.mean()))
    err = quadrics.evaluate(q, pos)
    best = int(np.argmin(err))
    assert np.partition(err, 1)[1] > err[best] * (1 + 1e-9), "tie: the test would not decide anything"

    out_v, out_f, info = sequential.simplify_sequential(V, F, target_faces=len(F) - 2, guards=False)
    assert info["passes"] == 1 and len(out_v) == len(V) - 1
    expected = pos[best] * p.scale + p.center
    assert np.min(np.linalg.norm(out_v - expected, axis=1)) < 1e-12
    gone = {int(a[best]), int(b[best])}
    survivors = {tuple(v) for v in np.round(out_v, 12)}
    assert sum(tuple(np.round(V[i], 12)) in survivors for i in gone) == 0, "both ends should have moved"


def test_unknown_cost_is_refused():
    V, F = torus(nu=8, nv=6)
    with pytest.raises(ValueError, match="cost"):
        sequential.simplify_sequential(V, F, target_faces=50, cost="raw")
