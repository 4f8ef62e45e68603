"""bench/fuzz.py's checker (broken_promises): what it calls a broken promise must be one.
Faces core.stitching splits at a T-junction share their input face by design
(docs/method.md); two output faces from one input face anywhere else are a fault."""
from __future__ import annotations

import dataclasses
import importlib
from pathlib import Path

import numpy as np
import pytest

import core
import mesh_builders as build

BENCH = Path(__file__).resolve().parents[1] / "bench"


@pytest.fixture
def fuzz(monkeypatch):
    monkeypatch.syspath_prepend(str(BENCH))
    return importlib.import_module("fuzz")


def test_faces_split_at_a_t_junction_may_share_their_input_face(fuzz):
    V, F = build.t_junction_slit()
    r = core.simplify(V, F, ratio=0.95)
    _, count = np.unique(r.face_origin, return_counts=True)
    assert np.any(count > 1)  # (the slit's faces were split and kept)
    assert fuzz.broken_promises(V, F, {"ratio": 0.95}, r) == []


def test_two_faces_from_one_input_face_elsewhere_are_a_broken_promise(fuzz):
    V, F = build.grid(10)
    r = core.simplify(V, F, ratio=0.5)
    assert fuzz.broken_promises(V, F, {"ratio": 0.5}, r) == []
    origin = r.face_origin.copy()
    origin[1] = origin[0]
    problems = fuzz.broken_promises(V, F, {"ratio": 0.5}, dataclasses.replace(r, face_origin=origin))
    assert any("descend from one input face" in p for p in problems)


def test_a_crack_is_seen_past_a_face_the_input_has_twice(fuzz):
    """Damaged input repeats faces; core.prepare drops the copies before the stitching
    sees the crack's border, and so does the checker."""
    V, F = build.t_junction_slit()
    origin, count = np.unique(core.simplify(V, F, ratio=0.95).face_origin, return_counts=True)
    face = origin[count > 1][0]  # a face split at the slit, whose slit edge is a border edge
    doubled = np.concatenate([F, F[[face]]])  # (that slit edge is on two raw faces)
    r = core.simplify(V, doubled, ratio=0.95)
    origin, count = np.unique(r.face_origin, return_counts=True)
    assert face in origin[count > 1]  # (that face was split)
    assert fuzz.broken_promises(V, doubled, {"ratio": 0.95}, r) == []
