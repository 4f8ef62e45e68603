"""Invalid input raises ValueError naming the problem; progress and cancellation."""
from __future__ import annotations

import numpy as np
import pytest

import core
import mesh_builders as build
import mesh_checks as check

V, F = build.grid(6, jitter=0.2)
N, M = len(V), len(F)


def _raises(match, **kwargs):
    """simplify(V, F, ratio=0.5, **kwargs) must raise ValueError matching ``match``."""
    vertices = kwargs.pop("vertices", V)
    faces = kwargs.pop("faces", F)
    if not kwargs.pop("no_target", False) and "target_faces" not in kwargs:
        kwargs.setdefault("ratio", 0.5)
    with pytest.raises(ValueError, match=match):
        core.simplify(vertices, faces, **kwargs)


def _with(i, value):
    v = V.copy()
    v[i, 1] = value
    return v


def test_nan_coordinates():
    _raises(r"(?i)vertices.*(nan|finite)", vertices=_with(5, np.nan))


def test_inf_coordinates():
    _raises(r"(?i)vertices.*(inf|finite)", vertices=_with(7, -np.inf))


def test_negative_face_index():
    f = F.copy()
    f[3, 1] = -1
    _raises(r"(?i)faces.*-1", faces=f)


def test_face_index_too_large():
    f = F.copy()
    f[2, 2] = N
    _raises(rf"(?i)faces.*{N}", faces=f)


def test_vertices_wrong_shape():
    _raises(r"(?i)vertices.*\(n, 3\).*\(49, 2\)", vertices=V[:, :2])


def test_faces_wrong_shape():
    _raises(r"(?i)faces.*\(m, 3\).*4\)", faces=np.c_[F, F[:, :1]])


def test_faces_float_dtype():
    _raises(r"(?i)faces.*integer.*float", faces=F.astype(np.float64))


def test_vertices_non_numeric():
    _raises(r"(?i)vertices", vertices=V.astype(str))


def test_negative_line_weight():
    _raises(r"line_weight", line_weight=-1e-3)


def test_nan_line_weight():
    _raises(r"line_weight", line_weight=float("nan"))


def test_negative_line_weights():
    w = np.full(N, 1e-3)
    w[4] = -0.5
    _raises(r"line_weights.*>= 0", line_weights=w)


def test_quadric_scale_below_one():
    scale = np.ones(N)
    scale[0] = 0.5
    _raises(r"quadric_scale.*>= 1", quadric_scale=scale)


def test_negative_boundary_weight():
    _raises(r"boundary_weight", boundary_weight=-1.0)


@pytest.mark.parametrize("sigma", [-0.1, float("nan"), float("inf")])
def test_bad_probabilistic_sigma(sigma):
    _raises(r"probabilistic_sigma", probabilistic_sigma=sigma)


def test_negative_feature_weight():
    _raises(r"feature_weight", feature_edges=[[0, 1]], feature_weight=-2.0)


@pytest.mark.parametrize("name,value", [
    ("line_weights", np.full(N - 1, 1e-3)),
    ("quadric_scale", np.ones(N + 3)),
    ("locked", np.zeros(N - 2, dtype=bool)),
])
def test_wrong_length_per_vertex_arrays(name, value):
    _raises(rf"{name}.*\({N},\)", **{name: value})


def test_wrong_length_vertex_attribute():
    _raises(r"vertex attribute 'skin'", vertex_attributes={"skin": np.ones((N + 1, 2))})


def test_wrong_shape_corner_attribute():
    _raises(r"corner attribute 'uv'", corner_attributes={"uv": np.zeros((M - 1, 3, 2))})


def test_locked_must_be_boolean():
    _raises(r"locked.*boolean", locked=np.zeros(N))


def test_both_target_faces_and_ratio():
    _raises(r"(?i)target_faces.*ratio|ratio.*target_faces", target_faces=10, ratio=0.5)


@pytest.mark.parametrize("ratio", [0.0, 1.5, -0.2, float("nan")])
def test_ratio_out_of_range(ratio):
    _raises(r"ratio", ratio=ratio)


def test_target_larger_than_the_mesh():
    _raises(rf"(?i)target.*{M + 1}.*{M}", target_faces=M + 1)


def test_negative_target():
    _raises(r"(?i)target.*>= 0", target_faces=-3)


def test_fractional_target():
    _raises(r"(?i)target_faces.*whole", target_faces=10.5)


def test_no_target_at_all():
    _raises(r"(?i)target", no_target=True)


def test_non_callable_progress():
    _raises(r"progress.*callable", progress=0.5)


def test_unknown_corner_attribute_in_uv_attributes():
    uv = np.zeros((M, 3, 2))
    _raises(r"uv_attributes.*'UVMap'", corner_attributes={"uv": uv}, uv_attributes=("UVMap",))


def test_uv_attribute_must_have_two_components():
    _raises(r"uv_attributes.*'col'", corner_attributes={"col": np.zeros((M, 3, 3))}, uv_attributes=("col",))


def test_normalize_attribute_must_be_a_vertex_attribute():
    _raises(r"normalize_attributes.*'skin'", normalize_attributes=("skin",))


def test_feature_edges_out_of_range():
    _raises(r"feature_edges", feature_edges=[[0, N]])


def test_edge_weights_length_must_match_feature_edges():
    _raises(r"edge_weights", feature_edges=[[0, 1], [1, 2]], edge_weights=[1.0])


def test_unknown_option_in_chain():
    with pytest.raises(ValueError, match="bogus"):
        core.simplify_chain(V, F, targets=[10], bogus=1)


def test_chain_targets_must_not_increase():
    with pytest.raises(ValueError, match="(?i)increase"):
        core.simplify_chain(V, F, targets=[10, 20])


def test_valid_call_with_the_same_arguments_works():
    # The fixture mesh itself is fine: the errors above come from the one bad argument.
    r = core.simplify(V, F, ratio=0.5)
    check.assert_valid_result(r, V, F)


# ---------------------------------------------------------------- progress / cancel


def test_progress_returning_false_cancels():
    calls = []

    def stop_after_two(frac):
        calls.append(frac)
        return len(calls) < 2

    Vs, Fs, _ = build.uv_sphere(24, 16)
    with pytest.raises(core.SimplifyCancelled):
        core.simplify(Vs, Fs, ratio=0.1, progress=stop_after_two)
    assert len(calls) == 2  # cancelled right after the callback said so


def test_progress_returning_none_or_true_does_not_cancel():
    Vs, Fs, _ = build.uv_sphere(16, 10)
    r = core.simplify(Vs, Fs, ratio=0.2, progress=lambda f: None)
    assert r.stats.stop_reason == "target_reached"


def test_progress_fractions_increase_within_unit_interval():
    calls = []
    Vs, Fs, _ = build.uv_sphere(24, 16)
    r = core.simplify(Vs, Fs, ratio=0.1, progress=lambda f: calls.append(f) or True)
    assert r.stats.stop_reason == "target_reached"
    f = np.array(calls)
    assert len(f) >= r.stats.passes >= 2, (len(f), r.stats.passes)  # every pass, and between steps of long ones
    assert np.all((f >= 0) & (f <= 1))
    assert np.all(np.diff(f) >= 0)
    assert f[-1] == 1.0
    assert f[0] < 1.0


def test_long_steps_report_progress_and_cancel_inside_a_pass(monkeypatch):
    """A scan's set-up and passes take seconds: the heartbeat calls progress between steps
    and between chunks of the per-edge work, and a False there cancels at once."""
    from core import heartbeat

    monkeypatch.setattr(heartbeat, "BEAT_INTERVAL", 0.0)  # every beat reaches the callback
    monkeypatch.setattr(heartbeat, "CHUNK_ROWS", 64)
    Vs, Fs, _ = build.uv_sphere(24, 16)
    calls = []
    r = core.simplify(Vs, Fs, ratio=0.1, progress=lambda f: calls.append(f) or True)
    assert len(calls) > 3 * r.stats.passes, f"beats inside passes expected, got {len(calls)} calls for {r.stats.passes} passes"
    assert calls[0] == 0.0 and np.all(np.diff(calls) >= 0), calls[:10]

    seen = []
    with pytest.raises(core.SimplifyCancelled):
        core.simplify(Vs, Fs, ratio=0.1, progress=lambda f: seen.append(f) or len(seen) < 3)
    assert seen == [0.0, 0.0, 0.0], f"cancelled during set-up, before the first pass ended: {seen}"


def test_chunked_edge_costs_give_the_same_result(monkeypatch):
    from core import heartbeat

    Vs, Fs, _ = build.uv_sphere(24, 16)
    whole = core.simplify(Vs, Fs, ratio=0.2)
    monkeypatch.setattr(heartbeat, "CHUNK_ROWS", 7)
    chunked = core.simplify(Vs, Fs, ratio=0.2)
    assert np.array_equal(whole.faces, chunked.faces) and np.array_equal(whole.vertices, chunked.vertices)
