"""The sliver rule where an open border forces thin faces (core.slivers.border_floors).

A patch soup (every triangle its own part, as a game export gives after Subdivision
Surface) can only end in faces as thin as its patches: holding them at the floor spent
the face budget on them and left the rest coarser. A border without input slivers keeps
the full floor.
"""
import numpy as np

import core
import mesh_builders as build
from core import slivers
from core.guards import SLIVER_QUALITY
from surface_distance import mean_distance


def soup_and_ball():
    """40 thin curved patches beside a closed ball that competes for the same faces;
    and how many vertices the patches have (the ball's come after)."""
    ball, soup = build.icosphere(3), build.thin_patches(40, seed=1)
    return (*build.components([soup, (1.5 * ball[0], ball[1])]), len(soup[0]))


def test_thin_patches_cost_no_more_distance_than_without_the_rule():
    V, F, on_patches = soup_and_ball()
    assert np.mean(core.triangle_quality(V, F) < SLIVER_QUALITY) > 0.2
    default = core.simplify(V, F, ratio=0.15)
    no_rule = core.simplify(V, F, ratio=0.15, min_quality=0.0)
    assert default.stats.stop_reason == "target_reached"
    # Before the border floors, the rule held the patches and cost 1.31x here.
    assert mean_distance(V, default.vertices, default.faces) <= 1.1 * mean_distance(V, no_rule.vertices, no_rule.faces)
    # The ball has no border: none of its faces is a sliver.
    on_ball = default.vertex_origin[default.faces].min(axis=1) >= on_patches
    assert on_ball.any()
    assert core.triangle_quality(default.vertices, default.faces[on_ball]).min() >= SLIVER_QUALITY


def test_a_ribbon_without_input_slivers_gets_none():
    # Two rows of quads bent into an arc: every face has all its corners on the border.
    V, F = build.grid(nx=80, ny=2, size=(4.0, 0.1))
    t = V[:, 0]
    V = np.c_[np.cos(t) * (1 + V[:, 1]), np.sin(t) * (1 + V[:, 1]), 0.3 * np.sin(2 * t)]
    assert core.triangle_quality(V, F).min() >= SLIVER_QUALITY
    for ratio in (0.5, 0.25, 0.1):
        r = core.simplify(V, F, ratio=ratio)
        assert r.stats.stop_reason == "target_reached"
        assert core.triangle_quality(r.vertices, r.faces).min() >= SLIVER_QUALITY, ratio


def test_border_floors_relax_only_bordered_faces_with_an_input_sliver():
    # Vertices 0-3 on the border, 4 inside; 0 and 1 carry an input sliver (quality 0.1).
    worst = np.array([0.1, 0.8, 0.8, 0.8, 0.1])
    border = np.array([True, True, True, True, False])
    keep, remove = np.array([0, 2]), np.array([1, 3])
    # Corners of collapse 0 (ends 0, 1: worst 0.1): faces on (2, 3) and on (2, 4);
    # of collapse 1 (ends 2, 3: worst 0.8): a face on (1, 2) whose corners carry 0.8.
    nb_next, nb_prev, collapse = np.array([2, 2, 1]), np.array([3, 4, 2]), np.array([0, 0, 1])
    floors = slivers.border_floors(0.3, worst, border, keep, remove, nb_next, nb_prev, collapse)
    assert np.allclose(floors, [0.05, 0.3, 0.3])


def test_the_face_qualities_a_run_keeps_are_those_of_its_faces(monkeypatch):
    """The engine keeps each face's quality up to date pass by pass (engine._face_quality,
    for the sliver allowance) instead of measuring every face again: at every pass the
    kept values are those of the faces as they are, in a run of one mesh and of several
    parts, parts dropped whole included."""
    from core import engine
    from core.metrics import triangle_quality

    checked = []
    original = engine._face_quality

    def compared(s):
        kept = original(s)
        assert np.array_equal(kept, triangle_quality(s.V, s.F))
        checked.append(len(s.F))
        return kept

    monkeypatch.setattr(engine, "_face_quality", compared)
    V, F = build.thin_patches(40, seed=3)
    core.simplify(V, F, ratio=0.1)
    single = len(checked)
    assert single > 3
    parts = [build.thin_patches(12, seed=seed) for seed in range(3)] + [build.bolts(30)]
    V, F = build.components(parts)
    part = np.concatenate([np.full(len(v), i) for i, (v, _) in enumerate(parts)])
    r = core.simplify(V, F, ratio=0.05, vertex_part=part)
    assert r.stats.removed_components > 0
    assert len(checked) > single + 3
