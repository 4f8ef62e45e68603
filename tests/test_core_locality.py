"""core.locality: large meshes are renumbered for the run and come back in the input's order.

The renumbering only starts at core.locality.MIN_VERTICES vertices; these tests lower
that bound so meshes the tests build take the same path as a scan.
"""
from __future__ import annotations

import numpy as np
import pytest

import core
import core.locality as locality
import mesh_builders as build
import mesh_checks as check


@pytest.fixture
def always_renumber(monkeypatch):
    monkeypatch.setattr(locality, "MIN_VERTICES", 1)


def test_morton_order_visits_each_octant_before_the_next():
    cells = np.stack(np.meshgrid(*[np.arange(4)] * 3, indexing="ij"), axis=-1).reshape(-1, 3).astype(float)
    order = np.argsort(locality.morton_codes(cells))
    # Z-order: the 8 cells of every aligned 2x2x2 block are consecutive, and so are the
    # 64 of the whole 4x4x4 grid's 8 octants of 8.
    blocks = (cells[order] // 2).astype(int)
    for start in range(0, 64, 8):
        assert len({tuple(b) for b in blocks[start:start + 8]}) == 1, f"block broken at {start}"
    codes = locality.morton_codes(cells)
    assert len(np.unique(codes)) == len(cells), "two cells share a code"


def test_no_collapse_gives_the_input_back_in_its_own_order(always_renumber):
    V, F = build.shuffled(*build.torus(24, 12))
    weights = np.random.default_rng(1).random((len(V), 2))
    uv = np.random.default_rng(2).random((len(F), 3, 2))
    r = core.simplify(V, F, target_faces=len(F), vertex_attributes={"w": weights},
                      corner_attributes={"uv": uv}, uv_attributes=("uv",))
    assert np.array_equal(r.vertices, V), "vertices reordered or moved"
    assert np.array_equal(r.faces, F), "faces reordered"
    assert np.array_equal(r.face_origin, np.arange(len(F)))
    assert np.array_equal(r.vertex_origin, np.arange(len(V)))
    assert np.array_equal(r.vertex_attributes["w"], weights)
    assert np.array_equal(r.corner_attributes["uv"], uv)


def test_every_per_vertex_and_per_face_input_follows_the_renumbering(monkeypatch):
    # Welded copies, a duplicate face, locks, weights, scales, feature edges, shape keys,
    # skin weights and UVs: with no collapse to make, a renumbered run must give exactly
    # what the input's own numbering gives.
    V, F = build.shuffled(*build.torus(24, 12), seed=8)
    n0 = len(V)
    split = F[0].copy()
    V = np.concatenate([V, V[split]])  # one face on split copies of its corners, welded back
    F = np.concatenate([[n0 + np.arange(3)], F[1:], F[3:4]])  # and a duplicate face, dropped
    rng = np.random.default_rng(9)
    m, n = len(F), len(V)
    options = dict(
        locked=rng.random(n) < 0.05, line_weights=rng.random(n) * 1e-2, quadric_scale=1 + rng.random(n),
        feature_edges=F[:20, :2], vertex_attributes={"key": rng.normal(size=(n, 3)), "w": rng.random((n, 2))},
        shape_attributes=("key",), corner_attributes={"uv": rng.random((m, 3, 2))}, uv_attributes=("uv",),
    )
    plain = core.simplify(V, F, target_faces=m, **options)
    monkeypatch.setattr(locality, "MIN_VERTICES", 1)
    renumbered = core.simplify(V, F, target_faces=m, **options)
    assert renumbered.stats.welded_vertices == plain.stats.welded_vertices > 0
    assert len(plain.faces) < m, "the duplicate face was kept"
    for field in ("vertices", "faces", "face_origin", "vertex_origin"):
        assert np.array_equal(getattr(renumbered, field), getattr(plain, field)), field
    for name in plain.vertex_attributes:
        assert np.array_equal(renumbered.vertex_attributes[name], plain.vertex_attributes[name]), name
    assert np.array_equal(renumbered.corner_attributes["uv"], plain.corner_attributes["uv"])
    # And a run that does collapse, with all of them and a distance bound.
    r = core.simplify(V, F, target_faces=m // 4, max_error=0.05, **options)
    check.assert_valid_result(r, V, F)
    assert np.all(np.diff(r.vertex_origin) > 0) and np.all(np.diff(r.face_origin) > 0)
    locked = np.flatnonzero(options["locked"])
    locked = np.where(locked >= n0, split[np.clip(locked - n0, 0, 2)], locked)  # a copy's lock is its twin's
    assert np.isin(locked, r.vertex_origin).all(), "a locked vertex was removed"


def test_reorder_moves_every_field_of_the_problem_together(monkeypatch):
    from core import prepare
    V, F = build.shuffled(*build.torus(16, 8), seed=10)
    rng = np.random.default_rng(11)
    n, m = len(V), len(F)
    options = core.Options(
        locked=rng.random(n) < 0.2, line_weights=rng.random(n), quadric_scale=1 + rng.random(n),
        feature_edges=F[:10, :2], vertex_attributes={"w": rng.random((n, 2))},
        corner_attributes={"uv": rng.random((m, 3, 2))}, uv_attributes=("uv",))
    p = prepare.validate_and_prepare(V, F, [m // 2], options)
    assert locality.reorder(p) is p and not p.renumbered, "a small mesh was renumbered"
    monkeypatch.setattr(locality, "MIN_VERTICES", 1)
    q = locality.reorder(p)
    assert q.renumbered
    old = q.vertex_origin  # q's vertex i is p's vertex old[i]
    for field in ("vertices", "input_positions", "line_weights", "quadric_scale", "locked"):
        assert np.array_equal(getattr(q, field), getattr(p, field)[old]), field
    assert np.array_equal(q.vertex_attributes["w"], p.vertex_attributes["w"][old])
    face_old = np.argsort(p.face_origin)[np.searchsorted(np.sort(p.face_origin), q.face_origin)]
    assert np.array_equal(old[q.faces], p.faces[face_old]), "faces not renumbered with their vertices"
    assert np.array_equal(q.corner_attributes["uv"], p.corner_attributes["uv"][face_old])
    assert np.array_equal(np.sort(old[q.feature_edges], axis=1), np.sort(p.feature_edges, axis=1))


def test_a_renumbered_run_keeps_everything_in_the_input_numbering(always_renumber):
    V, F = build.shuffled(*build.torus(40, 20), seed=3)
    locked = np.zeros(len(V), dtype=bool)
    locked[np.random.default_rng(4).choice(len(V), 25, replace=False)] = True
    weights = np.random.default_rng(5).random((len(V), 3))
    weights /= weights.sum(axis=1, keepdims=True)
    target = len(F) // 5
    r = core.simplify(V, F, target_faces=target, locked=locked, vertex_attributes={"w": weights},
                      normalize_attributes=("w",))
    check.assert_valid_result(r, V, F)
    check.assert_target_respected(r, target)
    assert np.all(np.diff(r.vertex_origin) > 0), "output vertices not in the input's order"
    assert np.all(np.diff(r.face_origin) > 0), "output faces not in the input's order"
    # Locked vertices are kept, exactly where they were, with their own attributes.
    at = np.searchsorted(r.vertex_origin, np.flatnonzero(locked))
    assert np.array_equal(r.vertex_origin[at], np.flatnonzero(locked)), "a locked vertex was removed"
    assert np.array_equal(r.vertices[at], V[locked])
    assert np.allclose(r.vertex_attributes["w"][at], weights[locked])
    assert np.allclose(r.vertex_attributes["w"].sum(axis=1), 1.0)
    # Every output face keeps the orientation of the input face it descends from.
    n_out = check.face_normals(r.vertices, r.faces)
    n_in = check.face_normals(V, F[r.face_origin])
    assert np.all(np.einsum("ij,ij->i", n_out, n_in) > 0), "a face turned against its origin"


def test_renumbering_changes_order_not_outcome(monkeypatch):
    V, F = build.shuffled(*build.torus(48, 24), seed=6)
    target = len(F) // 10
    plain = core.simplify(V, F, target_faces=target)
    monkeypatch.setattr(locality, "MIN_VERTICES", 1)
    renumbered = core.simplify(V, F, target_faces=target)
    again = core.simplify(V, F, target_faces=target)
    assert np.array_equal(renumbered.vertices, again.vertices) and np.array_equal(renumbered.faces, again.faces), \
        "the renumbered run is not deterministic"
    assert len(renumbered.faces) == len(plain.faces) == target
    # Only the order in which equal costs are taken differs: both LODs are as close to
    # the torus (distance of face centres to the exact surface) and as well shaped.
    def off_torus(r):
        c = r.vertices[r.faces].mean(axis=1)
        return np.abs(np.hypot(np.hypot(c[:, 0], c[:, 1]) - 1.0, c[:, 2]) - 0.35).mean()

    def quality(r):
        from core.metrics import triangle_quality
        return triangle_quality(r.vertices, r.faces).mean()

    assert off_torus(renumbered) == pytest.approx(off_torus(plain), rel=0.2)
    assert quality(renumbered) == pytest.approx(quality(plain), abs=0.03)
