"""addon/pure/skin_fit.skinned_levels without Blender: a coarse level it remakes without
the poses in the error runs under the painted limits its chain was held to (issue 34 §1
with Source Armature). Before, the remake ran free, and where it followed the check poses
closer it replaced the held level with one that broke the limit (the Blender test, with a
real rig, stops its coarse levels at the limit, so it cannot tell the two apart)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from addon.pure import skin_fit


def level(faces: int, tag: str):
    return SimpleNamespace(faces=np.zeros((faces, 3), dtype=np.int64), tag=tag)


def test_a_remade_coarse_level_runs_under_its_chains_limits(monkeypatch):
    # Two bones: levels under 80 triangles are coarse (COARSE_TRIANGLES_PER_BONE = 40).
    rows = np.array([[0.1, np.inf, 0.2], [0.2, np.inf, 0.4], [0.3, np.inf, 0.6]])
    lod_input = SimpleNamespace(names={"skin": [0, 1]}, targets=[500, 60, 20], limit_rows=rows)
    held = [level(500, "held"), level(60, "held"), level(20, "held")]
    calls = []

    def simplify(targets, **options):
        calls.append((list(targets), options))
        return [level(t, "remade") for t in targets]

    # The remade levels follow the check poses closer, so they are kept.
    monkeypatch.setattr(skin_fit, "fit_skin", lambda _input, result, scored=False: (
        result, None if not scored else (0.5 if result.tag == "remade" else 1.0)))
    out = skin_fit.skinned_levels(lod_input, held, simplify, True, lambda: None)
    assert [r.tag for r in out] == ["held", "remade", "remade"]
    (targets, options), = calls
    assert targets == [60, 20] and options["pose_offsets"] is None and options["pose_weight"] == 0.0
    np.testing.assert_array_equal(options["vertex_max_error"], rows[1:])


def test_without_a_limit_the_remake_is_a_plain_run(monkeypatch):
    lod_input = SimpleNamespace(names={"skin": [0, 1]}, targets=[60], limit_rows=None)
    calls = []
    monkeypatch.setattr(skin_fit, "fit_skin", lambda _input, result, scored=False: (result, 1.0))
    skin_fit.skinned_levels(lod_input, [level(60, "held")], lambda t, **o: calls.append(o) or [level(60, "r")],
                            True, lambda: None)
    assert calls and "vertex_max_error" not in calls[0]
