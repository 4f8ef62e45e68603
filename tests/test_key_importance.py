"""Shape keys as importance and in the report (issue 34), without Blender: the importance
from the keys' offsets (addon/pure/importance.py), what each key moves the vertices by
(addon/pure/key_deviation.py), and the core scaling a vertex's keyed error with its importance."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays

import core
import mesh_builders as build
from addon.pure import importance as imp
from addon.pure import key_deviation
from addon.pure.deviation_search import report_samples


def offsets_strategy(max_keys=4, max_vertices=40):
    shape = st.tuples(st.integers(1, max_keys), st.integers(1, max_vertices), st.just(3))
    # Offsets as Blender's float32 coordinates can hold them: none below 1e-30 (squaring
    # 1e-163 underflows a float64, and no mesh moves by that).
    element = st.floats(-10, 10, allow_nan=False).map(lambda x: 0.0 if abs(x) < 1e-30 else x)
    return shape.flatmap(lambda s: arrays(np.float64, s, elements=element))


@settings(max_examples=200, deadline=None)
@given(offsets_strategy())
def test_importance_is_in_unit_range_and_grows_with_the_largest_offset(offsets):
    g = imp.shape_key_importance(offsets)
    assert g.shape == (offsets.shape[1],)
    assert np.all((g >= 0.0) & (g <= 1.0))
    moved = np.linalg.norm(offsets, axis=2).max(axis=0)
    order = np.argsort(moved, kind="stable")
    assert np.all(np.diff(g[order]) >= -1e-12), "a vertex moved further got less importance"
    assert np.all(g[moved == 0.0] == 0.0), "a vertex no key moves got importance"
    if moved.max() > 0:
        assert g[np.argmax(moved)] == pytest.approx(1.0)


@settings(max_examples=100, deadline=None)
@given(offsets_strategy(), st.floats(1e-3, 1e3), st.integers(0, 2 ** 32 - 1))
def test_importance_ignores_units_direction_and_key_order(offsets, scale, seed):
    g = imp.shape_key_importance(offsets)
    rng = np.random.default_rng(seed)
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    turned = (offsets * scale) @ rotation.T
    assert np.allclose(imp.shape_key_importance(turned), g, atol=1e-9)
    assert np.allclose(imp.shape_key_importance(turned[rng.permutation(len(offsets))]), g, atol=1e-9)


def test_importance_of_the_largest_offset_over_the_keys():
    offsets = np.zeros((2, 4, 3))
    offsets[0, 0] = [1.0, 0, 0]
    offsets[1, 1] = [0, 0, 1.0]  # another key moving another vertex as far
    offsets[1, 2] = [0, 0.5, 0]
    g = imp.shape_key_importance(offsets)
    assert g[0] == g[1] == pytest.approx(1.0)
    assert 0.0 < g[2] < 1.0 and g[3] == 0.0
    # In proportion to the robust maximum.
    assert imp.shape_key_importance(np.array([[[1.0, 0, 0]] * 9 + [[0.5, 0, 0]]]))[-1] == pytest.approx(0.5)


def test_one_far_vertex_does_not_flatten_the_rest():
    # A key moving 200 vertices by 1 and one vertex by 100: the region still counts fully.
    offsets = np.zeros((1, 300, 3))
    offsets[0, :200, 2] = 1.0
    offsets[0, 200, 2] = 100.0
    g = imp.shape_key_importance(offsets)
    assert np.all(g[:201] == pytest.approx(1.0)) and np.all(g[201:] == 0.0)


def test_importance_without_movement_or_keys_is_zero():
    assert np.array_equal(imp.shape_key_importance(np.zeros((3, 5, 3))), np.zeros(5))
    assert np.array_equal(imp.shape_key_importance(np.zeros((0, 5, 3))), np.zeros(5))
    offsets = np.zeros((1, 3, 3))
    offsets[0, 0] = [np.nan, 0, 0]
    offsets[0, 1] = [1.0, 0, 0]
    assert np.array_equal(imp.shape_key_importance(offsets), [0.0, 1.0, 0.0])
    with pytest.raises(ValueError, match="shape-key offsets must be a"):
        imp.shape_key_importance(np.zeros((5, 3)))


@dataclass
class Key:
    name: str
    offsets: np.ndarray
    relative_key: str = "Basis"
    vertex_group: str = ""


def test_key_offsets_follow_blenders_mixing():
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=(6, 3)), rng.normal(size=(6, 3))
    weights = rng.random((6, 2))
    keys = [Key("A", a), Key("B", b, relative_key="A"), Key("C", b, vertex_group="Mask"),
            Key("D", b, relative_key="D"), Key("E", b, vertex_group="Missing"), Key("F", a, relative_key="")]
    out = key_deviation.key_offsets(keys, True, ["Other", "Mask"], weights)
    assert np.allclose(out[0], a)
    assert np.allclose(out[1], b - a)  # a chain: the key over the key it is relative to
    assert np.allclose(out[2], b * weights[:, 1:2])  # limited to its vertex group
    assert np.allclose(out[3], 0.0)  # relative to itself: it moves nothing
    assert np.allclose(out[4], b) and np.allclose(out[5], a)  # a group the mesh lacks, no relative key
    # Absolute keys (Relative off): each key's own stored shape.
    assert np.allclose(key_deviation.key_offsets(keys, False, ["Other", "Mask"], weights), np.stack([a, b, b, b, b, a]))
    assert key_deviation.key_offsets([], True).shape == (0, 0, 3)


def test_key_samples_share_the_budget_over_many_keys():
    for triangles in (100, 5_000, 1_000_000):
        full = report_samples(triangles)
        assert key_deviation.key_samples(triangles, 1) == key_deviation.key_samples(triangles, 4) == full
        counts = [key_deviation.key_samples(triangles, k) for k in (5, 16, 100)]
        assert all(a >= b for a, b in zip(counts, counts[1:]))
        assert counts[-1] >= key_deviation.KEY_SAMPLES_MIN


def test_a_parts_key_samples_follow_its_share_of_the_asset_as_its_report_does():
    """A part of an asset samples each key from what its report gets (its share of the
    asset's area), never from its own size alone; a lone mesh is unchanged."""
    triangles = 1_700  # a head of a character: 27,200 samples as a mesh of its own
    own = report_samples(triangles)
    for share in (1_000, 5_000, own, 10 * own):
        assert key_deviation.key_samples(triangles, 4, share) == max(key_deviation.KEY_SAMPLES_MIN,
                                                                     report_samples(triangles, share))
        assert key_deviation.key_samples(triangles, 4, share) <= key_deviation.key_samples(triangles, 4)
    assert key_deviation.key_samples(triangles, 4, 5_000) < key_deviation.key_samples(triangles, 4) == own
    assert key_deviation.key_samples(triangles, 4, None) == own


def test_worst_key_is_the_furthest():
    keys = [{"name": "A", "hausdorff": 0.1}, {"name": "B", "hausdorff": 0.3}, {"name": "C", "hausdorff": 0.2}]
    assert key_deviation.worst(keys)["name"] == "B" and key_deviation.worst([]) is None


def _rippled_bump():
    """(V, F, the bump's vertices, the core's key options): a flat sheet whose one key
    raises a rippled bump in its middle."""
    V, F = build.grid(60)
    r = np.linalg.norm(V[:, :2] - 0.5, axis=1)
    key = np.zeros_like(V)
    key[:, 2] = 0.1 * np.clip(1 - r / 0.2, 0, 1) ** 2 * (1 + 0.5 * np.sin(30 * V[:, 0]))
    return V, F, r < 0.2, dict(vertex_attributes={"key": key}, shape_attributes=("key",))


def test_core_scales_the_keyed_error_with_importance():
    # A flat sheet whose key raises a rippled bump: there the keys' error sets the cost, so
    # importance on the bump must scale it too (it scaled the rest quadric only, and the
    # bump kept 173 vertices rather than 129; scaled, 237).
    V, F, bump, keys = _rippled_bump()
    plain = core.simplify(V, F, ratio=0.1, **keys)
    important = core.simplify(V, F, ratio=0.1, **imp.controls(np.where(bump, 1.0, 0.0), 1e-3, 0.5), **keys)
    assert abs(len(important.faces) - len(plain.faces)) <= 2
    kept_plain, kept = bump[plain.vertex_origin].sum(), bump[important.vertex_origin].sum()
    assert kept >= 1.6 * kept_plain, (kept, kept_plain)


def test_importance_against_a_given_reference():
    # An asset's reference (asset.key_importance): a part moved half as far as the
    # reference gets half the importance, one moved further saturates.
    offsets = np.zeros((1, 4, 3))
    offsets[0, :, 0] = [0.0, 0.5, 1.0, 2.0]
    assert np.allclose(imp.shape_key_importance(offsets, reference=1.0), [0.0, 0.5, 1.0, 1.0])
    assert np.array_equal(imp.shape_key_importance(offsets, reference=0.0), np.zeros(4))
    # Without one, its own robust maximum: the same as motion_reference of key_motion.
    moved = imp.key_motion(offsets)
    assert np.allclose(moved, [0.0, 0.5, 1.0, 2.0])
    assert np.allclose(imp.shape_key_importance(offsets),
                       imp.shape_key_importance(offsets, reference=imp.motion_reference(moved)))
    assert imp.motion_reference(np.zeros(5)) == 0.0


def test_key_region_is_what_the_key_moves():
    V, F = build.grid(10, alternate=False)
    key = np.zeros_like(V)
    key[:, 2] = np.where(V[:, 0] > 0.75, 1.0, 0.0)  # the right quarter...
    key[0, 2] = 0.01  # ...and a corner vertex by 1 %, below REGION_SHARE: not the region
    region = key_deviation.key_region(key, F)
    touched = (V[F][:, :, 0] > 0.75).any(axis=1)  # a vertex moved: the triangle is in
    assert np.array_equal(region, touched)
    assert not key_deviation.key_region(np.zeros_like(V), F).any()
    assert key_deviation.key_region(key, F, share=0.005)[(F == 0).any(axis=1)].all()
    # The share of the area the region covers (a uniform grid: its share of the triangles).
    assert key_deviation._area_share(V, F, region) == pytest.approx(100.0 * touched.mean())


def test_the_keys_weight_follows_the_strength():
    # Source Shape Keys: at g = 1 a key's planes get the factor times key_weight.
    assert imp.key_weight(0.0) == 1.0 and imp.key_scale_exponent(0.0) == 1.0
    assert imp.key_weight(imp.DEFAULT_STRENGTH) == pytest.approx(8.0)
    for s in (0.1, 0.25, 0.5, 0.75, 1.0):
        top = imp.factor(s)
        assert top ** imp.key_scale_exponent(s) == pytest.approx(top * imp.key_weight(s), rel=1e-9)
    g = np.array([0.0, 0.5, 1.0])
    assert "key_scale_exponent" not in imp.controls(g, 1e-3, 0.5)  # other sources: the keys as the rest
    assert imp.controls(g, 1e-3, 0.5, keys=True)["key_scale_exponent"] == imp.key_scale_exponent(0.5)


def test_core_weighs_the_keys_more_with_their_exponent():
    # The rippled bump of test_core_scales_the_keyed_error_with_importance: with the keys'
    # planes weighted more where the importance is, the bump keeps more of its vertices.
    V, F, bump, keys = _rippled_bump()
    controls = imp.controls(np.where(bump, 1.0, 0.0), 1e-3, 0.25)
    alike = core.simplify(V, F, ratio=0.1, **controls, **keys)
    weighted = core.simplify(V, F, ratio=0.1, **controls, key_scale_exponent=2.0, **keys)
    assert abs(len(weighted.faces) - len(alike.faces)) <= 2
    assert bump[weighted.vertex_origin].sum() > 1.1 * bump[alike.vertex_origin].sum()
    # The default leaves the run as it was; a negative exponent is refused.
    assert np.array_equal(core.simplify(V, F, ratio=0.1, **controls, key_scale_exponent=1.0, **keys).faces,
                          alike.faces)
    with pytest.raises(ValueError, match="key_scale_exponent"):
        core.simplify(V, F, ratio=0.1, key_scale_exponent=-1.0)


def test_still_share_counts_faces_the_keys_leave_still_at_every_corner():
    # Two unit right triangles side by side (area 0.5 each) and one twice as large.
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [3, 0, 0], [3, 2, 0.0]])
    faces = np.array([[0, 1, 2], [1, 3, 2], [1, 4, 5]])
    g = np.zeros(6)
    assert imp.still_share(g, vertices, faces) == pytest.approx((3.0, 3.0))
    g[5] = imp.KEY_STILL  # one corner at the threshold: that face moves
    assert imp.still_share(g, vertices, faces) == pytest.approx((1.0, 3.0))
    g[2] = 0.5 * imp.KEY_STILL  # below it: still
    assert imp.still_share(g, vertices, faces) == pytest.approx((1.0, 3.0))
    assert imp.still_share(g, vertices, faces, scale=2.0) == pytest.approx((4.0, 12.0))  # areas in scene units
    assert imp.still_share(g, vertices, np.zeros((0, 3), dtype=int)) == (0.0, 0.0)


def test_key_strength_is_full_from_half_the_surface_still_and_none_without():
    assert imp.key_strength(0.5, 6.0, 10.0) == 0.5
    assert imp.key_strength(0.5, imp.KEY_STILL_FULL * 10.0, 10.0) == pytest.approx(0.5)
    assert imp.key_strength(0.5, 0.5 * imp.KEY_STILL_FULL * 10.0, 10.0) == pytest.approx(0.25)
    assert imp.key_strength(0.8, 0.0, 10.0) == 0.0
    assert imp.key_strength(0.8, 0.0, 0.0) == pytest.approx(0.8)  # no surface: nothing to say
    assert imp.key_strength_note(0.5, 0.5) is None
    assert "move all of the surface" in imp.key_strength_note(0.5, 0.0)
    assert "move most of the surface" in imp.key_strength_note(0.5, 0.2)
