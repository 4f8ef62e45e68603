"""core.budget: one triangle budget for several parts, split at equal error (issue 32 §1).
Every input is generated here."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import core
from core import budget
import mesh_builders as build


def _moved(mesh, scale=1.0, offset=(0.0, 0.0, 0.0)):
    V, F = mesh[0], mesh[1]
    return np.asarray(V, dtype=np.float64) * scale + np.asarray(offset), np.asarray(F)


def _curve(mesh, **kw):
    return budget.error_curve(mesh[0], mesh[1], **kw)


def test_an_error_curve_starts_whole_and_never_gets_cheaper():
    mesh = _moved(build.icosphere(3))
    counts, errors = _curve(mesh)
    assert counts[0] == len(mesh[1]) and errors[0] == 0.0
    assert np.all(np.diff(counts) <= 0) and counts[1] < counts[0] and np.all(np.diff(errors) >= 0)
    assert counts[-1] <= 8  # down to the floor (a closed part keeps four triangles)
    floored = _curve(mesh, floor=100)
    assert floored[0][-1] >= 100 - 1 and len(floored[0]) < len(counts)


def test_an_error_curve_is_in_mesh_units():
    """Twice the size, twice the error at the same count."""
    mesh = build.icosphere(3)
    small, large = _curve(_moved(mesh)), _curve(_moved(mesh, 2.0))
    np.testing.assert_array_equal(small[0], large[0])
    np.testing.assert_allclose(large[1], 2.0 * small[1], rtol=1e-6, atol=1e-12)


def test_counts_meet_each_target_and_never_grow():
    parts = [_moved(build.icosphere(4)), _moved(build.icosphere(3), 0.3, (3, 0, 0)), _moved(build.torus())]
    curves = [_curve(p) for p in parts]
    total = sum(len(p[1]) for p in parts)
    targets = [total // 2, total // 4, total // 10]
    counts = budget.split_by_error(curves, targets)
    assert counts.shape == (3, 3)
    assert np.all(np.abs(counts.sum(axis=1) - targets) <= len(parts))  # (rounding, one a part)
    assert np.all(np.diff(counts, axis=0) <= 0)
    assert np.all(counts <= np.array([len(p[1]) for p in parts]))


def test_a_dense_small_part_gives_up_more_than_a_coarse_large_one():
    """The same ratio each would keep half of both; at equal error the finely tessellated
    little sphere (tiny errors) goes first and the large one keeps its silhouette."""
    large = _moved(build.uv_sphere(24, 12), 2.0)
    small = _moved(build.icosphere(4), 0.05, (2.1, 0, 0))
    m = len(large[1]) + len(small[1])
    counts = budget.split_by_error([_curve(large), _curve(small)], [m // 2])
    kept = counts[0] / np.array([len(large[1]), len(small[1])])
    assert kept[1] < 0.5 and kept[0] > 0.9, kept


def test_every_part_ends_at_about_the_same_error():
    """The point of the split: no part far worse than the rest (the asset's Hausdorff
    distance is its worst part's). Against the same ratio each."""
    parts = [_moved(build.icosphere(4)), _moved(build.icosphere(4), 0.2, (3, 0, 0)),
             _moved(build.torus(32, 16), 0.7, (0, 3, 0))]
    curves = [_curve(p) for p in parts]
    total = sum(len(p[1]) for p in parts)
    counts = budget.split_by_error(curves, [total // 8])[0]

    def error_at(curve, count):  # (the curve's error where it passes ``count``)
        return float(np.interp(-count, -curve[0], curve[1]))

    split = [error_at(c, n) for c, n in zip(curves, counts)]
    same = [error_at(c, len(p[1]) / 8) for c, p in zip(curves, parts)]
    assert max(split) < 0.7 * max(same), (split, same)


def test_weights_count_what_the_asset_draws():
    """A part drawn four times costs four times its triangles: it gives up more."""
    mesh = _moved(build.icosphere(3))
    curve = _curve(mesh)
    plain = budget.split_by_error([curve, curve], [640])[0]
    weighted = budget.split_by_error([curve, curve], [640], weights=[4, 1])[0]
    assert abs(int(plain[0]) - int(plain[1])) <= 2
    assert weighted[0] == weighted[1]  # (one error for both: equal curves, equal counts)
    assert abs(4 * int(weighted[0]) + int(weighted[1]) - 640) <= 5


def test_flat_parts_share_what_is_left():
    """Grids collapse at no error down to a few triangles: the target is still met, the
    parts sharing it in proportion to what they could give."""
    flat = [_moved(build.grid(12)), _moved(build.grid(8), 1.0, (3, 0, 0))]
    curves = [_curve(p) for p in flat]
    total = sum(len(p[1]) for p in flat)
    counts = budget.split_by_error(curves, [total // 2])[0]
    assert abs(int(counts.sum()) - total // 2) <= 2, counts


def test_bad_calls_are_named():
    curve = _curve(_moved(build.icosphere(1)))
    with pytest.raises(ValueError, match="at least one part"):
        budget.split_by_error([], [1])
    with pytest.raises(ValueError, match="2 weights for 1 parts"):
        budget.split_by_error([curve], [10], weights=[1, 2])


@settings(max_examples=15, deadline=None)
@given(sizes=st.lists(st.floats(0.05, 3.0), min_size=2, max_size=5), ratio=st.floats(0.1, 0.9))
def test_any_split_is_a_split(sizes, ratio):
    parts = [_moved(build.icosphere(2), s, (4.0 * i, 0, 0)) for i, s in enumerate(sizes)]
    curves = [_curve(p) for p in parts]
    m = sum(len(f) for _, f in parts)
    target = int(round(ratio * m))
    counts = budget.split_by_error(curves, [target])
    assert abs(int(counts.sum()) - target) <= len(parts)
    assert np.all(counts >= 0) and np.all(counts[0] <= np.array([len(f) for _, f in parts]))


def test_a_part_leaves_once_the_error_is_past_its_removal():
    """with_removal: a tiny part leaves whole (never a sliver of it) once the level's error
    is beyond what removing it costs, and stays before."""
    large = _moved(build.icosphere(4), 2.0)
    tiny = _moved(build.icosphere(2), 0.02, (2.05, 0, 0))
    curves = [_curve(large), budget.with_removal(_curve(tiny), 0.04)]
    m = len(large[1]) + len(tiny[1])
    counts = budget.split_by_error(curves, [m // 2, 40])
    assert counts[0, 1] > 0 and counts[1, 1] == 0, counts
    assert abs(int(counts[1].sum()) - 40) <= 2
    for n in counts[:, 1]:  # whole or gone, never part of its last rung
        assert n == 0 or n >= curves[1][0][-3]
    same = budget.with_removal(curves[0], 0.0)  # no cheaper than its curve: unchanged
    assert same is curves[0]
