"""core.budget.split_by_error: one triangle budget for several parts, split by error
(issue 32 §1). Every input is generated here."""
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


def _own(V, F):
    """The vertices ``F`` uses, and ``F`` renumbered into them."""
    used, inverse = np.unique(F, return_inverse=True)
    return V[used], inverse.reshape(F.shape)


def _quad(offset=(5.0, 0.0, 0.0)):
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float64) * 0.2 + offset
    return V, np.array([[0, 1, 2], [0, 2, 3]])


def test_counts_add_up_to_each_target_and_never_grow():
    parts = [_moved(build.icosphere(4)), _moved(build.icosphere(3), 0.3, (3, 0, 0)), _quad()]
    targets = [3000, 1500, 600, 120]
    counts = budget.split_by_error(parts, targets)
    assert counts.shape == (4, 3)
    assert counts.sum(axis=1).tolist() == targets
    assert np.all(np.diff(counts, axis=0) <= 0)
    assert np.all(counts <= np.array([len(f) for _, f in parts]))


def test_a_dense_small_part_gives_up_more_than_a_coarse_large_one():
    """Same ratio each would keep half of both; by error, the finely tessellated little
    sphere (tiny collapse errors) goes first and the large one keeps its silhouette."""
    large = _moved(build.uv_sphere(24, 12), 2.0)
    small = _moved(build.icosphere(4), 0.05, (2.1, 0, 0))
    m = len(large[1]) + len(small[1])
    counts = budget.split_by_error([large, small], [m // 2])
    kept = counts[0] / np.array([len(large[1]), len(small[1])])
    assert kept[1] < 0.5 and kept[0] > 0.9, kept


def test_the_split_follows_scale():
    """Two copies of one mesh, one twice the size: the larger one's collapses cost four
    times as much, so it keeps more."""
    mesh = build.icosphere(3)
    counts = budget.split_by_error([_moved(mesh), _moved(mesh, 2.0, (5, 0, 0))], [640])
    assert counts[0, 1] > counts[0, 0]


def test_importance_controls_are_per_part():
    """A part whose vertices carry a quadric scale (painted importance) keeps more of its
    triangles than its unpainted twin."""
    mesh = build.icosphere(3)
    a, b = _moved(mesh), _moved(mesh, 1.0, (4, 0, 0))
    controls = [{"quadric_scale": np.full(len(a[0]), 20.0), "line_scale_exponent": 0.5}, None]
    counts = budget.split_by_error([a, b], [640], controls=controls)
    assert counts[0, 0] > 1.5 * counts[0, 1]
    plain = budget.split_by_error([a, b], [640])
    assert abs(int(plain[0, 0]) - int(plain[0, 1])) <= 0.1 * plain[0].sum()


def test_tiny_parts_may_leave_when_small_parts_may_go():
    """A hundred 12-triangle bolts beside a sphere, taken far down: a count of 0 is a part
    the run removed (remove_small_components), and without it every part keeps some."""
    bolts = build.bolts(count=100, seed=3, spread=4.0)
    parts = [_moved(build.icosphere(3), 3.0)] + [_own(bolts[0], f) for f in np.split(bolts[1], 100)]
    targets = [400]
    counts = budget.split_by_error(parts, targets)
    assert counts.sum() == 400 and np.any(counts[0, 1:] == 0)
    kept = budget.split_by_error(parts, [600], core.Options(remove_small_components=False))
    assert np.all(kept[0] > 0)


def test_bad_parts_are_named():
    with pytest.raises(ValueError, match="part 1 has no faces"):
        budget.split_by_error([_quad(), (np.zeros((3, 3)), np.zeros((0, 3), int))], [1])
    with pytest.raises(ValueError, match="at least one part"):
        budget.split_by_error([], [1])


@settings(max_examples=15, deadline=None)
@given(sizes=st.lists(st.floats(0.05, 3.0), min_size=2, max_size=5), ratio=st.floats(0.1, 0.9))
def test_any_split_is_a_split(sizes, ratio):
    parts = [_moved(build.icosphere(2), s, (4.0 * i, 0, 0)) for i, s in enumerate(sizes)]
    m = sum(len(f) for _, f in parts)
    target = int(round(ratio * m))
    counts = budget.split_by_error(parts, [target])
    assert abs(int(counts.sum()) - target) <= 1  # a collapse on a closed part takes two
    assert np.all(counts >= 0) and np.all(counts[0] <= len(parts[0][1]))
