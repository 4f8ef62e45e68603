"""addon/pure/switch_distances.py: the switch points of a LOD chain from its measured error
(no Blender: plain NumPy)."""
import math

import numpy as np
import pytest

from addon.pure import switch_distances as sd

TAN30 = math.tan(math.radians(30.0))


def chain(percent=(0.0, 0.1, 0.5, 2.0)):
    # A 2 x 2 x 2 cube: diagonal 2·sqrt(3), bounding sphere radius sqrt(3), size 2.
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    f = np.array([[0, 1, 2], [4, 5, 6], [3, 7, 1]])
    return sd.chain_switch_data(list(percent), v, f)


def test_distance_matches_the_formula():
    d = sd.switch_distances([0.0, 0.01, 0.1], pixel_error=2.0, screen_height=1000, vertical_fov_degrees=60)
    np.testing.assert_allclose(d, [0.0, 0.01 * 1000 / (2 * 2.0 * TAN30), 0.1 * 1000 / (2 * 2.0 * TAN30)])
    assert sd.cull_distance(0.5, 1.0, 1080, 60) == pytest.approx(0.5 * 1080 / TAN30)


def test_chain_numbers_match_the_formulas_and_decrease_with_level():
    data = chain()
    r, size, diag = math.sqrt(3), 2.0, 2 * math.sqrt(3)
    assert data["bounding_sphere_radius"] == pytest.approx(r)
    assert data["bounding_box_size"] == pytest.approx(size)
    eps = np.array([0.0, 0.1, 0.5, 2.0]) / 100 * diag
    np.testing.assert_allclose(data["deviation"], eps)
    d = eps * 1080 / (2 * TAN30)
    np.testing.assert_allclose(data["switch_distance"], d)
    cull = r * 1080 / TAN30
    assert data["cull_distance"] == pytest.approx(cull)
    hand = np.append(d[1:], cull)
    # MSFT: sphere diameter over screen height where each level hands over; FOV-free form.
    np.testing.assert_allclose(data["msft_screen_coverage"], 2 * r / (2 * hand * TAN30))
    np.testing.assert_allclose(data["msft_screen_coverage"][:-1], 2 * r * 1.0 / (eps[1:] * 1080))
    assert data["msft_screen_coverage"][-1] == pytest.approx(1 / 1080)
    # Unreal: the same measure where each level switches in; LOD0 by convention.
    np.testing.assert_allclose(data["unreal_screen_size"][1:], 2 * r / (eps[1:] * 1080))
    assert data["unreal_screen_size"][0] == max(1.0, data["unreal_screen_size"][1])
    # Unity: LODGroup.size * 0.5 / (D tan(fov/2)) where each level hands over.
    np.testing.assert_allclose(data["unity_transition_height"], size * 0.5 / (hand * TAN30))
    np.testing.assert_allclose(data["godot_visibility_range_begin"], d)
    np.testing.assert_allclose(data["godot_visibility_range_end"], hand)
    for key in ("msft_screen_coverage", "unreal_screen_size", "unity_transition_height"):
        assert np.all(np.diff(data[key]) <= 0), (key, data[key])
    for key in ("switch_distance", "godot_visibility_range_begin", "godot_visibility_range_end"):
        assert np.all(np.diff(data[key]) >= 0), (key, data[key])


def test_lod0_has_no_switch_point_and_ranges_tile():
    data = chain()
    levels = sd.per_level(data)
    assert levels[0]["switch_distance"] == 0.0 and levels[0]["godot_visibility_range_begin"] == 0.0
    for a, b in zip(levels, levels[1:]):
        assert a["godot_visibility_range_end"] == b["godot_visibility_range_begin"]


def test_screen_fractions_do_not_depend_on_fov_or_units():
    v = np.random.default_rng(1).normal(size=(50, 3))
    f = np.array([[i, i + 1, i + 2] for i in range(48)])
    a = sd.chain_switch_data([0, 0.3, 1.0], v, f, vertical_fov_degrees=40)
    b = sd.chain_switch_data([0, 0.3, 1.0], v * 100, f, vertical_fov_degrees=90)
    for key in ("msft_screen_coverage", "unreal_screen_size", "unity_transition_height"):
        np.testing.assert_allclose(a[key], b[key])
    c = sd.chain_switch_data([0, 0.3, 1.0], v, f, world_scale=3.0)
    d = sd.chain_switch_data([0, 0.3, 1.0], v, f)
    np.testing.assert_allclose(c["switch_distance"], 3 * np.array(d["switch_distance"]))


def test_a_finer_error_after_a_coarser_one_never_switches_in_earlier():
    d = sd.switch_distances([0.0, 0.2, 0.1, 0.3])
    assert d[2] == d[1] and np.all(np.diff(d) >= 0)


def test_zero_error_level_gets_a_finite_capped_fraction():
    data = chain((0.0, 0.0, 1.0))
    assert data["switch_distance"][1] == 0.0
    assert data["msft_screen_coverage"][0] == sd.MAX_SCREEN_FRACTION
    assert all(math.isfinite(x) for key in sd.PER_LEVEL_KEYS for x in data[key])


def test_unmeasured_levels_are_a_clear_error():
    with pytest.raises(ValueError, match=r"no measured deviation for level\(s\) \[2\].*Measure Deviation"):
        chain((0.0, 0.1, None))
    with pytest.raises(ValueError, match="no measured deviation"):
        sd.deviation_from_percent([0.0, float("nan")], 1.0)


@pytest.mark.parametrize("kwargs, message", [
    ({"pixel_error": 0}, "pixel error"), ({"screen_height": -1}, "screen height"),
    ({"vertical_fov_degrees": 180}, "field of view")])
def test_bad_view_settings_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        sd.switch_distances([0.0, 1.0], **kwargs)
