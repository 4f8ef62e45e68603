"""addon/pure/limits.py without Blender: the painted limit per vertex, per level in pixels,
and the reruns' scaling (issue 34 §1)."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from addon.pure import limits


def test_a_weight_over_the_limit_fades_to_free():
    w = np.array([1.0, 0.5, 0.25, 0.0, 1e-9, 1.5, -0.2])
    got = limits.vertex_limits(w, 2.0)
    share = limits.CORE_SHARE
    assert got[:3] == pytest.approx([2.0 * share, 4.0 * share, 8.0 * share])
    assert np.isinf(got[3]) and np.isinf(got[4]) and np.isinf(got[6])  # unpainted (or noise): free
    assert got[5] == pytest.approx(2.0 * share)  # weights are clipped to [0, 1]


def test_limit_units():
    assert limits.limit_in_mesh_units(0.5, True, diagonal=200.0, scale=4.0) == pytest.approx(1.0)
    assert limits.limit_in_mesh_units(2.0, False, diagonal=200.0, scale=4.0) == pytest.approx(0.5)


def test_pixels_are_a_share_of_each_levels_error_never_decreasing():
    got = limits.pixel_limits([0.2, 0.1, 0.8], pixels=0.5, pixel_error=2.0)
    assert got == pytest.approx([0.05, 0.05, 0.2])


def test_a_level_measured_below_its_limits_error_switches_in_where_its_region_shows_the_pixels():
    # Limit 0.25 px of a requested 2.0: the region within 0.5; the level measured at 1.0.
    # Switched in for its own error, the region would show 0.5 px; it comes in at 2.0.
    got = limits.pixel_switch(hausdorff=1.0, region=0.5, pixels=0.25, pixel_error=1.0, diagonal=10.0)
    assert got["switch_deviation"] == pytest.approx(2.0) and got["switch_deviation_percent"] == pytest.approx(20.0)
    assert got["region_pixels"] == pytest.approx(0.25)
    # A region well within: the level's own error decides, the region shows less.
    got = limits.pixel_switch(hausdorff=1.0, region=0.1, pixels=0.25, pixel_error=2.0, diagonal=10.0)
    assert got["switch_deviation"] == pytest.approx(1.0) and got["region_pixels"] == pytest.approx(0.2)
    assert limits.switch_percent({"hausdorff_percent": 3.0}) == 3.0
    assert limits.switch_percent({"hausdorff_percent": 3.0, "limit": {"switch_deviation_percent": 4.0}}) == 4.0


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.0, 3.0), min_size=1, max_size=5), st.integers(0, 2**16))
def test_reruns_tighten_only_the_levels_beyond_and_keep_the_chain_non_decreasing(used, seed):
    rng = np.random.default_rng(seed)
    k = len(used)
    rows = np.sort(rng.uniform(0.1, 1.0, (k, 6)), axis=0)
    rows[:, 0] = np.inf  # a free vertex stays free
    scale = limits.rerun_scales(used)
    if max(used) <= 1.0:
        assert scale is None
        return
    assert ((scale < 1.0) == (np.asarray(used) > 1.0)).all()
    new = limits.scaled_rows(rows, scale)
    assert (new[1:] >= new[:-1]).all()  # the core's rule
    assert (new <= rows * scale[:, None] + 1e-12).all()  # never looser than asked
    assert np.isinf(new[:, 0]).all()
    beyond = np.flatnonzero(np.asarray(used) > 1.0)
    assert (new[beyond, 1:] <= rows[beyond, 1:] * limits.RERUN_AIM / np.asarray(used)[beyond, None] + 1e-12).all()
