"""The engine's screening (core.engine._screened, core.validation.screened): once the
passes' validation rejects nearly everything they try, as in the tail of a CAD part, the
candidates that fail the rules judging a collapse by itself are dropped before choosing.
Every input is generated here."""
from __future__ import annotations

import numpy as np
import pytest

import core
from core import engine, topology, validation
import mesh_builders as build
import mesh_checks as check


def _disks(count: int = 60, around: int = 32, seed: int = 1):
    """``count`` squat closed cylinders (washers, flanges: a CAD assembly's), each a tube
    of one row of ``around`` quads with both ends closed by a fan, turned and scattered.
    Near the target most of their cheapest collapses fail the link condition."""
    rng = np.random.default_rng(seed)
    meshes = []
    for _ in range(count):
        v, f = build.tube(around, 1, 0.5, 0.1)
        top, bottom = np.arange(around) * 2 + 1, np.arange(around) * 2
        v = np.concatenate([v, [[0.0, 0.0, 0.1], [0.0, 0.0, 0.0]]])
        caps = [np.c_[top, np.roll(top, -1), np.full(around, len(v) - 2)],
                np.c_[np.roll(bottom, -1), bottom, np.full(around, len(v) - 1)]]
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        meshes.append((v @ q.T + rng.uniform(0.0, 10.0, 3), np.concatenate([f] + caps)))
    return build.components(meshes)


def _unscreened(monkeypatch):
    monkeypatch.setattr(engine, "SCREEN_BELOW", -1.0)


def _screenings(monkeypatch) -> list:
    """A list that gets an entry each time a pass screens its candidates."""
    calls = []
    original = engine._screened
    monkeypatch.setattr(engine, "_screened", lambda *a: calls.append(1) or original(*a))
    return calls


def test_a_part_whose_tail_rejects_nearly_everything_takes_fewer_passes(monkeypatch):
    V, F = _disks()
    screened = core.simplify(V, F, ratio=0.25)
    _unscreened(monkeypatch)
    plain = core.simplify(V, F, ratio=0.25)
    assert len(screened.faces) == len(plain.faces) == len(F) // 4
    assert screened.stats.passes <= 0.8 * plain.stats.passes, (screened.stats.passes, plain.stats.passes)
    check.assert_valid_result(screened, V, F)


def test_a_mesh_whose_passes_accept_most_of_what_they_try_is_not_screened(monkeypatch):
    calls = _screenings(monkeypatch)
    V, F = build.grid(24, jitter=0.2)
    V[:, 2] = 0.1 * np.sin(4.0 * V[:, 0]) * np.cos(3.0 * V[:, 1])
    core.simplify(V, F, ratio=0.1)
    assert calls == []


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_every_collapse_the_screening_drops_validation_rejects_on_its_own(monkeypatch, seed):
    """validation.screened judges candidates that need not be independent; each one it
    rejects must be rejected as the only collapse of a pass too."""
    dropped = []
    screened = validation.screened

    def checked(s, conn, cand, idx):
        ok = screened(s, conn, cand, idx)
        for i in idx[~ok]:
            one = np.array([i])
            opposite = validation.opposite_corners(s.F, conn, cand.edge[one])
            taken = np.zeros(len(s.V), dtype=s.face_count.dtype)
            corners = np.concatenate([opposite[0], opposite[1][opposite[1] >= 0]])
            np.add.at(taken, corners, 1)
            assert not validation.valid_collapses(s, conn, cand, one, opposite, taken)[0]
            dropped.append(i)
        return ok

    monkeypatch.setattr(engine.validation, "screened", checked)
    V, F = _disks(count=20, seed=seed)
    core.simplify(V, F, ratio=0.2)
    assert dropped  # (the screening ran and dropped some)


def test_corners_of_each_listing_of_a_vertex():
    F = np.array([[0, 1, 2], [0, 2, 3], [3, 2, 4]])
    owner, corners = topology.gather_corners_of_each(F, np.array([2, 0, 2, 4]), 5)
    flat = F.ravel()
    got = {(int(o), int(c)) for o, c in zip(owner, corners)}
    want = {(o, c) for o, v in enumerate([2, 0, 2, 4]) for c in np.flatnonzero(flat == v)}
    assert got == want and len(owner) == len(want)
    assert np.all(np.diff(owner) >= 0)


def test_a_run_under_a_distance_bound_is_not_screened(monkeypatch):
    """Under max_error the tail's rejections are mostly the bound's, which screening
    cannot catch: the run stays as it was (the same LOD as unscreened)."""
    calls = _screenings(monkeypatch)
    V, F = _disks()
    core.simplify(V, F, ratio=0.25)
    assert calls  # (this mesh does screen at a count target)
    calls.clear()
    diagonal = float(np.linalg.norm(V.max(0) - V.min(0)))
    bounded = core.simplify(V, F, max_error=0.02 * diagonal)
    assert calls == []
    _unscreened(monkeypatch)
    plain = core.simplify(V, F, max_error=0.02 * diagonal)
    assert np.array_equal(bounded.faces, plain.faces) and np.array_equal(bounded.vertices, plain.vertices)
