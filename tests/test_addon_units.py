"""The add-on's bpy-free parts: edge bookkeeping, importance mapping, settings checks."""
import numpy as np
import pytest

from addon.pure import edges, importance
from addon.pure.settings import LodError, LodSettings
from mesh_builders import grid


def test_adjacent_pairs_counts_interior_edges():
    v, f = grid(3, alternate=False)
    e, fa, fb = edges.adjacent_triangle_pairs(f)
    # Every interior edge has two half-edges, each of the 12 boundary edges one.
    total = (3 * len(f) + 12) // 2
    assert len(e) == total - 12
    shared = [set(f[i]) & set(f[j]) for i, j in zip(fa, fb)]
    assert all(len(s) == 2 and s == set(ed) for s, ed in zip(shared, e))


def test_differing_edges_is_the_material_border():
    v, f = grid(4, alternate=False)
    centroid_x = v[f].mean(axis=1)[:, 0]
    mat = (centroid_x > 0.5).astype(int)
    border = edges.differing_edges(f, mat)
    # The border is the vertical line x = 0.5: 4 edges, both ends on it.
    assert len(border) == 4
    assert np.allclose(v[border][:, :, 0], 0.5)


def test_corner_discontinuous_edges_finds_the_seam_only():
    v, f = grid(4, alternate=False)
    uv = v[f][:, :, :2].copy()
    right = v[f].mean(axis=1)[:, 0] > 0.5
    uv[right] += [2.0, 0.0]  # the right half is a separate UV island
    seam = edges.corner_discontinuous_edges(f, uv)
    assert len(seam) == 4 and np.allclose(v[seam][:, :, 0], 0.5)
    assert len(edges.corner_discontinuous_edges(f, v[f][:, :, :2])) == 0


def test_merge_keeps_largest_weight_and_each_edge_once():
    e, w = edges.merge_weighted_edges([(np.array([[0, 1], [2, 3]]), 1.0), (np.array([[1, 0], [4, 5]]), 5.0)])
    got = {tuple(p): x for p, x in zip(e.tolist(), w.tolist())}
    assert got == {(0, 1): 5.0, (2, 3): 1.0, (4, 5): 5.0}


def test_mark_edges():
    mesh_edges = np.array([[0, 1], [1, 2], [2, 0]])
    assert edges.mark_edges(mesh_edges, np.array([[2, 1]]), 3).tolist() == [False, True, False]
    assert edges.mark_edges(mesh_edges, np.empty((0, 2)), 3).tolist() == [False] * 3


def test_chains_through_removed_vertices_join_the_kept_ends():
    # A path 0-1-2-3-4 with a branch 2-5, and a loop 6-7-8.
    e = np.array([[0, 1], [1, 2], [2, 3], [3, 4], [2, 5], [6, 7], [7, 8], [8, 6]])
    kept = np.zeros(9, dtype=bool)
    kept[[0, 2, 3, 4, 5, 6, 8]] = True
    assert edges.chains_through(e, kept).tolist() == [[0, 2], [2, 3], [2, 5], [3, 4], [6, 8]]
    # A removed junction ends the chains through it; a loop back to its start is no edge.
    kept[[2, 8]] = False
    assert edges.chains_through(e, kept).tolist() == [[3, 4]]
    assert edges.chains_through(np.empty((0, 2)), kept).shape == (0, 2)


def test_chains_through_names_each_chains_first_edge_and_edge_index_finds_rows():
    e = np.array([[0, 1], [1, 2], [2, 3], [3, 4], [2, 5], [6, 7], [7, 8], [8, 6]])
    kept = np.zeros(9, dtype=bool)
    kept[[0, 2, 3, 4, 5, 6, 8]] = True
    pairs, first = edges.chains_through(e, kept, with_edges=True)
    assert pairs.tolist() == edges.chains_through(e, kept).tolist()
    for (a, b), i in zip(pairs, first):  # the first edge leaves one end of its chain
        assert a in e[i] or b in e[i], (a, b, e[i])
    assert first[pairs.tolist().index([0, 2])] in (0, 1)
    rows = edges.edge_index(np.array([[2, 1], [4, 3], [0, 4], [6, 8]]), e, 9)
    assert rows.tolist() == [1, 3, -1, 7]
    assert edges.edge_index(np.empty((0, 2)), e, 9).shape == (0,)


def test_importance_scales_the_quadric_by_a_rising_factor():
    g = np.array([0.0, 0.5, 1.0])
    factors = [importance.controls(g, 1e-3, s)["quadric_scale"] for s in (0.0, 0.1, 0.25, 0.5, 0.75, 1.0)]
    assert np.allclose(factors[0], 1.0)  # strength 0: importance off
    assert all(f[0] == 1.0 for f in factors)  # unpainted vertices are never scaled
    top = [f[2] for f in factors]
    assert all(b > a for a, b in zip(top, top[1:])), top
    # The slider's top: the planes x ~4,000, the line quadric x ~500 (factor ** 0.75), the
    # paper's extreme weights (Sec. 4.4.1).
    assert 2000 < top[-1] <= 8000
    assert importance.controls(g, 1e-3, 0.5)["line_scale_exponent"] == importance.LINE_SCALE_EXPONENT == 0.75
    # A half-painted vertex gets the geometric mean: half the effect in the log-factor.
    assert all(np.isclose(f[1], np.sqrt(f[2])) for f in factors)
    # With the default line weight the line quadric is left as it is: only the scale acts.
    assert "line_weights" not in importance.controls(g, 1e-3, 0.5)


def test_importance_lifts_a_zero_line_weight_everywhere():
    # Sec. 4.4.1: scaling needs some line quadric on flat regions; giving it to every
    # vertex (not only the painted ones) keeps painted and unpainted comparable.
    c = importance.controls(np.array([0.0, 1.0]), 0.0, 0.5)
    assert np.allclose(c["line_weights"], importance.LINE_WEIGHT_FLOOR)
    assert "line_weights" not in importance.controls(np.array([0.0, 1.0]), 0.0, 0.0)


def test_expected_gain_and_preview_follow_the_slider():
    s = np.linspace(0.0, 1.0, 21)
    gain = [importance.expected_gain(x) for x in s]
    assert gain[0] == 1.0 and all(b > a for a, b in zip(gain, gain[1:]))
    assert np.isclose(importance.expected_gain(importance.DEFAULT_STRENGTH), 4.5)
    g = np.array([0.0, 0.5, 1.0])
    assert np.allclose(importance.effective(g, 1.0), [0.0, 0.5, 1.0])
    assert np.allclose(importance.effective(g, 0.0), 0.0)
    mid = importance.effective(g, 0.5)
    assert 0.0 < mid[2] < 1.0 and np.isclose(mid[1], mid[2] / 2)


def test_settings_default_strength_is_the_calibrated_default():
    assert LodSettings().importance_strength == importance.DEFAULT_STRENGTH


def test_skin_importance_is_the_papers_formula_over_its_cap():
    skin = np.array([[1.0, 0.0], [0.5, 0.5], [0.8, 0.2], [0.0, 0.0]])
    got = importance.skin_importance(skin)
    expected = np.minimum(0.15 * (1 - skin.max(axis=1)), 0.1) / 0.1
    assert np.allclose(got, expected)
    assert got.min() >= 0 and got.max() <= 1


def test_targets_chain_and_errors():
    assert LodSettings(ratio=0.5, levels=3, level_factor=0.5).targets(1000) == [500, 250, 125]
    assert LodSettings(target_triangles=300, levels=2, level_factor=0.5).targets(1000) == [300, 150]
    with pytest.raises(LodError, match="not smaller than the mesh"):
        LodSettings(ratio=1.0).targets(1000)
    with pytest.raises(LodError, match="not smaller than the mesh"):
        LodSettings(target_triangles=1000).targets(1000)
    with pytest.raises(LodError, match="fewer levels"):
        LodSettings(ratio=0.01, levels=8, level_factor=0.5).targets(200)


@pytest.mark.parametrize("field,value,message", [
    ("importance_source", "BONES", "importance source"),
    ("importance_mode", "HARD", "importance mode"),
    ("levels", 0, "levels"),
    ("level_factor", 1.0, "level factor"),
    ("line_weight", -1.0, "line weight"),
    ("min_quality", 1.2, "min triangle quality"),
    ("feature_angle", 180.0, "feature angle"),
    ("feature_angle", -1.0, "feature angle"),
])
def test_validate_rejects_bad_values(field, value, message):
    with pytest.raises(LodError, match=message):
        LodSettings(**{field: value}).validate()


def test_face_regions_split_by_closed_cuts_only():
    v, f = grid(6, alternate=False)
    cx = v[f].mean(axis=1)[:, 0]
    vertical = np.array([[i * 7 + 3, (i + 1) * 7 + 3] for i in range(6)])  # the line x = 0.5
    labels = edges.face_regions(f, vertical)
    assert len(np.unique(labels)) == 2
    assert len(np.unique(labels[cx < 0.5])) == 1 and len(np.unique(labels[cx > 0.5])) == 1
    assert len(np.unique(edges.face_regions(f, vertical[:3]))) == 1  # a cut into the region
    assert len(np.unique(edges.face_regions(f, np.empty((0, 2))))) == 1


def test_face_regions_split_a_long_strip_at_its_one_cut():
    # A 2 x 4000 strip: the diameter is 8000 triangles; hook-and-compress needs few rounds.
    x, y = np.meshgrid(np.arange(4001), np.arange(2))
    v = np.c_[x.ravel(), y.ravel(), np.zeros(x.size)]
    idx = np.arange(x.size).reshape(2, 4001)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    f = np.r_[np.c_[a, b, c], np.c_[a, c, d]]
    cut = np.array([[idx[0, 2000], idx[1, 2000]]])
    labels = edges.face_regions(f, cut)
    assert len(np.unique(labels)) == 2
