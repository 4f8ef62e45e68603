"""A seam pair's cost (core.selection.swept_distance): a seam vertex slides only along its
seam, so a pair merges on the chord between its ends; its cost is at least the squared
distance that chord moves the surface away from the ends. Every input is generated here."""
from __future__ import annotations

import numpy as np
import pytest

import core
import mesh_builders as build
import mesh_checks as check
from core import kinds, selection
from surface_distance import distance_to_mesh


def _fan(ends_z=0.0):
    """Two vertices, 0 (keep, x = -0.5) and 1 (remove, x = +0.5), at height ``ends_z``,
    in a ring of eight (vertices 2-9) at height 0: a closed fan of 10 triangles, two of
    them (with vertices 4 and 8) on the edge 0-1."""
    angle = np.arange(8) * np.pi / 4
    ring = np.c_[1.5 * np.cos(angle), np.sin(angle), np.zeros(8)]
    V = np.concatenate([[[-0.5, 0.0, ends_z], [0.5, 0.0, ends_z]], ring])
    r = 2 + np.arange(8)
    F = [[1, r[7], r[0]], [1, r[0], r[1]], [1, r[1], r[2]], [1, r[2], 0],
         [0, r[2], r[3]], [0, r[3], r[4]], [0, r[4], r[5]], [0, r[5], r[6]], [0, r[6], 1], [1, r[6], r[7]]]
    return V, np.array(F, dtype=np.int64)


def test_a_merge_on_a_flat_fan_sweeps_nothing():
    V, F = _fan()
    swept = selection.swept_distance(V, F, np.array([0]), np.array([1]), np.array([[0.0, 0.0, 0.0]]))
    assert swept[0] == pytest.approx(0.0, abs=1e-24)


@pytest.mark.parametrize("height", [0.01, 0.1, 0.3])
def test_a_merge_below_a_ridge_sweeps_the_ridge_height(height):
    """Both ends on a ridge ``height`` above a flat ring, merged at the ring's height: the
    fan left is flat, so each end is exactly ``height`` from it."""
    V, F = _fan(ends_z=height)
    swept = selection.swept_distance(V, F, np.array([0]), np.array([1]), np.array([[0.0, 0.0, 0.0]]))
    assert swept[0] == pytest.approx(height ** 2, rel=1e-12)


def test_the_farther_end_counts():
    """Merged at the keep end's place (raised), the keep end is on the fan left; the
    remove end, below it, is measured."""
    V, F = _fan()
    V[0, 2] = 0.2
    merged = V[[0]].copy()
    swept = selection.swept_distance(V, F, np.array([0]), np.array([1]), merged)
    want = distance_to_mesh(V[[1]], *_merged_fan(V, F, 0, 1, merged[0])) ** 2
    assert swept[0] == pytest.approx(want[0], rel=1e-9) and swept[0] > 0


def _merged_fan(V, F, keep, remove, position):
    """The faces of F left around a collapse of ``remove`` into ``keep`` at ``position``,
    as their own (vertices, faces): the faces on the edge go, both ends become the merged
    vertex (index len(V))."""
    around = np.any((F == keep) | (F == remove), axis=1) & ~(np.any(F == keep, axis=1) & np.any(F == remove, axis=1))
    faces = np.where((F[around] == keep) | (F[around] == remove), len(V), F[around])
    return np.concatenate([V, position[None]]), faces


@pytest.mark.parametrize("mesh", ["puck", "sphere"])
def test_every_seam_pair_costs_at_least_what_it_sweeps(monkeypatch, mesh):
    """At every pass, for seam pairs (kinds.ON_SEAM) the cost the selection ranks by is at
    least the squared distance from either end to the faces its merge leaves, measured
    here by brute force on the mesh as it is at that pass (so a cost kept from an earlier
    pass while a neighbour moved would fail too)."""
    V, F, UV = build.filleted_puck() if mesh == "puck" else build.uv_sphere(32, 16, pole_uv="fan")
    candidates = selection.candidates
    seen = []

    def checked(s, conn, kind, pass_no):
        cand = candidates(s, conn, kind, pass_no)
        rows = np.flatnonzero(kinds.PLACE[kind[cand.remove], kind[cand.keep]] == kinds.ON_SEAM)
        for i in rows[:: max(1, len(rows) // 25)]:  # a spread of each pass's seam pairs
            k, r = cand.keep[i], cand.remove[i]
            d = distance_to_mesh(s.V[[k, r]], *_merged_fan(s.V, s.F, k, r, cand.position[i]))
            seen.append((pass_no, cand.cost[i], float(np.max(d) ** 2)))
        return cand

    monkeypatch.setattr(selection, "candidates", checked)
    r = core.simplify(V, F, ratio=0.15, corner_attributes={"uv": UV}, uv_attributes=("uv",))
    check.assert_valid_result(r, V, F)
    cost, swept = np.array([c for _, c, _ in seen]), np.array([d for _, _, d in seen])
    assert len({p for p, _, _ in seen}) > 5 and np.any(swept > 0)
    assert np.all(cost >= swept * (1 - 1e-9) - 1e-18)
