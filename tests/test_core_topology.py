"""core.topology: the connectivity the engine carries from pass to pass must be the one a
fresh build of the surviving faces gives."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings, strategies as st

import core
import mesh_builders as build
import mesh_checks as check
from core import engine, topology

SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow], derandomize=True,
                phases=[Phase.explicit, Phase.generate])


def _canonical(conn, n):
    """Edges by key: (keys, face counts, sorted half-edge pairs), independent of slots."""
    edges = np.asarray(conn.edges)
    keys = edges[:, 0] * np.int64(n) + edges[:, 1]
    order = np.argsort(keys)
    pairs = np.sort(np.stack([conn.edge_he0, conn.edge_he1], axis=1), axis=1)
    return keys[order], conn.edge_faces[order], pairs[order]


def assert_same_connectivity(carried, faces, n):
    fresh = topology.build(faces, n)
    k1, c1, p1 = _canonical(carried, n)
    k2, c2, p2 = _canonical(fresh, n)
    np.testing.assert_array_equal(k1, k2)
    np.testing.assert_array_equal(c1, c2)
    manifold = c1 <= 2  # a non-manifold edge lists only two of its half-edges, any two
    np.testing.assert_array_equal(p1[manifold], p2[manifold])
    np.testing.assert_array_equal(carried.border_vertex, fresh.border_vertex)
    # Every half-edge names the edge between its two corners.
    start = faces.ravel()
    end = faces[:, [1, 2, 0]].ravel()
    ends = np.asarray(carried.edges)[carried.he_edge]
    np.testing.assert_array_equal(ends[:, 0], np.minimum(start, end))
    np.testing.assert_array_equal(ends[:, 1], np.maximum(start, end))
    np.testing.assert_array_equal(np.bincount(carried.he_edge, minlength=len(carried.edges)), carried.edge_faces)


def _checking_every_pass(monkeypatch):
    """Compare the carried connectivity with a fresh build after every pass; returns the
    list of checked passes."""
    checked = []
    apply = engine._apply

    def spy(s, conn, cand, chosen, pass_no):
        apply(s, conn, cand, chosen, pass_no)
        assert_same_connectivity(s.conn, s.F, len(s.V))
        checked.append(pass_no)

    monkeypatch.setattr(engine, "_apply", spy)
    return checked


@st.composite
def meshes(draw):
    """(V, F, locked): open, closed, several components, a non-manifold fin."""
    kind = draw(st.sampled_from(["grid", "sphere", "torus", "components", "fin"]))
    if kind == "grid":
        V, F = build.grid(draw(st.integers(3, 12)), draw(st.integers(3, 12)), jitter=0.2, seed=draw(st.integers(0, 9)),
                       height=build.bumps(0.1, 2.0))
    elif kind == "sphere":
        V, F, _ = build.uv_sphere(draw(st.integers(6, 14)), draw(st.integers(4, 9)))
    elif kind == "torus":
        V, F = build.torus(draw(st.integers(8, 16)), draw(st.integers(5, 8)))
    elif kind == "components":
        V, F = build.components([build.torus(10, 6), build.grid(5)[:2], build.cube(3)[:2]])
    else:
        V, F = build.with_fin(8, 3)
    lock_share = draw(st.sampled_from([0.0, 0.0, 0.1, 0.3]))
    locked = np.random.default_rng(draw(st.integers(0, 99))).random(len(V)) < lock_share
    return V, F, locked


@settings(max_examples=25, **SETTINGS)
@given(mesh=meshes(), ratio=st.floats(0.02, 0.6), seed=st.integers(0, 2**31 - 1))
def test_carried_connectivity_equals_a_fresh_build_after_every_pass(mesh, ratio, seed):
    V, F, locked = mesh
    with pytest.MonkeyPatch.context() as monkeypatch:
        checked = _checking_every_pass(monkeypatch)
        r = core.simplify(V, F, ratio=ratio, seed=seed, locked=locked)
    check.assert_valid_result(r, V, F, manifold=False)
    assert checked, "no pass applied a collapse"


def test_carried_connectivity_on_a_mesh_with_uv_seams(monkeypatch):
    V, F, UV = build.uv_sphere(16, 10)
    checked = _checking_every_pass(monkeypatch)
    r = core.simplify(V, F, ratio=0.1, corner_attributes={"uv": UV}, uv_attributes=("uv",))
    check.assert_valid_result(r, V, F)
    assert len(checked) > 3


def test_dependent_collapses_are_refused_not_merged_wrongly():
    """Two collapses sharing a face cannot be carried (the engine then rebuilds)."""
    V, F = build.grid(4, 4)
    conn = topology.build(F, len(V))
    # Two edges of the same triangle, both collapsed at once.
    f = F[5]
    remap = np.arange(len(V))
    remap[f[1]] = f[0]
    remap[f[2]] = f[0]
    relabelled = remap[F]
    alive = (relabelled[:, 0] != relabelled[:, 1]) & (relabelled[:, 1] != relabelled[:, 2]) & (relabelled[:, 0] != relabelled[:, 2])
    assert topology.after_collapses(conn, alive, remap, np.array([f[1], f[2]])) is None


def test_the_engine_rebuilds_when_collapses_cannot_be_carried(monkeypatch):
    V, F = build.grid(12, 12, jitter=0.2, seed=1, height=build.bumps(0.1, 2.0))
    carried = core.simplify(V, F, ratio=0.2)
    monkeypatch.setattr(topology, "after_collapses", lambda *args: None)
    rebuilt = core.simplify(V, F, ratio=0.2)
    check.assert_valid_result(rebuilt, V, F)
    check.assert_target_respected(rebuilt, carried.stats.target_faces)


def _fans_by_walking(F, n):
    """Reference fan count: per vertex, union the faces that share an edge at it."""
    fans = np.zeros(n, dtype=np.int64)
    E, count = check.edge_table(F)
    interior = {tuple(e) for e in E[count == 2].tolist()}
    for v in range(n):
        around = [f for f in F.tolist() if v in f]
        parent = list(range(len(around)))

        def root(i):
            while parent[i] != i:
                i = parent[i]
            return i

        for i, f in enumerate(around):
            for j in range(i):
                g = around[j]
                for u in set(f) & set(g) - {v}:
                    if tuple(sorted((u, v))) in interior:
                        parent[root(i)] = root(j)
        fans[v] = len({root(i) for i in range(len(around))})
    return fans


@settings(max_examples=40, **SETTINGS)
@given(mesh=meshes(), merges=st.integers(0, 3), seed=st.integers(0, 999))
def test_fans_per_vertex_matches_a_walk_round_each_vertex(mesh, merges, seed):
    # Merging far-apart vertices makes pinches: two closed fans, closed and open, two open.
    V, F, _ = mesh
    rng = np.random.default_rng(seed)
    F = F.copy()
    for _ in range(merges):
        a, b = rng.integers(len(V), size=2)
        if a != b and not ((F == a).any(1) & (F == b).any(1)).any():
            F[F == b] = a
    conn = topology.build(F, len(V))
    np.testing.assert_array_equal(topology.fans_per_vertex(conn, F, len(V)), _fans_by_walking(F, len(V)))


def test_two_closed_fans_at_a_vertex_are_locked_and_stay_apart():
    # Two spheres sharing one vertex: that vertex has as many edges as faces, like a
    # manifold one, but two fans. Left free, collapses around it made a pair of faces on
    # the same three vertices (found by a fuzz run on cropped real meshes with pinches).
    V1, F1, _ = build.uv_sphere(12, 8)
    V2, F2, _ = build.uv_sphere(12, 8)
    pole1 = int(np.argmax(V1[:, 2]))
    pole2 = int(np.argmin(V2[:, 2]))
    V2 = V2 - V2[pole2] + V1[pole1]
    V, F = build.components([(V1, F1), (V2, F2)])
    F[F == len(V1) + pole2] = pole1
    conn = topology.build(F, len(V))
    fans = topology.fans_per_vertex(conn, F, len(V))
    assert fans[pole1] == 2 and np.all(np.delete(fans, [pole1, len(V1) + pole2]) == 1)
    r = core.simplify(V, F, ratio=0.05)
    check.assert_valid_result(r, V, F, manifold=False)
    assert pole1 in r.vertex_origin
    assert np.array_equal(r.vertices[r.vertex_origin == pole1][0], V[pole1])


@settings(max_examples=200, **SETTINGS)
@given(n=st.integers(1, 40), data=st.data())
def test_corners_of_each_listing_match_a_scan_in_order(n, data):
    """gather_corners_of_each: every listing of a vertex (repeats included) gets all its
    corners, ascending, and the listings come in the order given (the validation fans and
    the seam pairs' swept distance read them grouped that way)."""
    faces = np.array(data.draw(st.lists(st.lists(st.integers(0, n - 1), min_size=3, max_size=3), max_size=40)),
                     dtype=np.int64).reshape(-1, 3)
    vertices = np.array(data.draw(st.lists(st.integers(0, n - 1), max_size=20)), dtype=np.int64)
    owner, corners = topology.gather_corners_of_each(faces, vertices, n)
    flat = faces.ravel()
    want = [(i, c) for i, v in enumerate(vertices) for c in np.flatnonzero(flat == v)]
    assert list(zip(owner.tolist(), corners.tolist())) == want
