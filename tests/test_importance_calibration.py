"""The Importance Strength slider's calibration (issue 19), on grids built here.

addon/pure/importance.py turns a strength into a factor on the painted vertices' quadrics
(paper Sec. 4.4.1), calibrated so that a fully painted region comes out a given number
of times denser than the rest at 10 % (bench/importance_calibration.py). Checked on the
issue's setup, a 120 x 120 grid with a painted disc of radius 0.35 taken to 10 %, both
flat and as a curved sheet (where the plane error, not the line quadric, sets the cost):

  * the target is met at every strength;
  * the disc's density against the rest rises with the strength;
  * 0.1 is a subtle preference, the default is clearly denser (>= 2x) yet soft (the disc
    still loses at least half its vertices), the top nearly locks the disc;
  * one meaning on every surface: flat and curved gains within 2x of each other below
    the near-locking top (at the top, where both keep 89-97 % of the disc, the gains of a
    near lock are ill-conditioned: 2.2x here, 1.6x on the bench's sheet);
  * on the curved sheet at the default, the disc's deviation is at most half that of the
    run without importance (the issue's "keep what works on curved meshes").

Pure NumPy (core + addon/pure/importance.py); the run through Blender's operator is in
tests/test_addon_importance.py.
"""
from __future__ import annotations

import functools

import numpy as np
import pytest

import core
import mesh_builders
from addon.pure import importance

RATIO = 0.1
STRENGTHS = (0.0, 0.1, 0.25, 0.5, 0.75, 1.0)
CENTER, RADIUS = np.array([0.3, 0.2]), 0.35


def height(x, y):
    # On [-1, 1]^2 after the shift below: three bumps a side, slopes up to ~0.75.
    return 0.08 * np.sin(3 * np.pi * (x - 1.0)) * np.cos(3 * np.pi * (y - 1.0))


def sheet(curved):
    V, F = mesh_builders.grid(120, size=2.0, height=height if curved else None)
    V[:, :2] -= 1.0
    g = (np.linalg.norm(V[:, :2] - CENTER, axis=1) < RADIUS).astype(np.float64)
    return V, F, g


def vertical_deviation(points, V, F):
    """Mean |z| distance from ``points`` to the height-field mesh (V, F) above/below them
    (the LOD of a height field stays one: every point lies over exactly one triangle)."""
    a, b, c = V[F[:, 0], :2], V[F[:, 1], :2], V[F[:, 2], :2]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
    out = np.full(len(points), np.nan)
    for start in range(0, len(points), 256):
        p = points[start:start + 256, None, :2]
        l1 = ((p[..., 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (p[..., 1] - a[:, 1])) / det
        l2 = ((b[:, 0] - a[:, 0]) * (p[..., 1] - a[:, 1]) - (p[..., 0] - a[:, 0]) * (b[:, 1] - a[:, 1])) / det
        l0 = 1.0 - l1 - l2
        inside = (l0 >= -1e-9) & (l1 >= -1e-9) & (l2 >= -1e-9)
        tri = np.argmax(inside, axis=1)
        rows = np.arange(len(tri))
        z = (l0[rows, tri] * V[F[tri, 0], 2] + l1[rows, tri] * V[F[tri, 1], 2] + l2[rows, tri] * V[F[tri, 2], 2])
        found = inside[rows, tri]
        out[start:start + len(tri)] = np.where(found, np.abs(z - points[start:start + 256, 2]), np.nan)
    assert np.isfinite(out).all(), "a point lies over no LOD triangle: the LOD folded"
    return float(out.mean())


@functools.lru_cache(maxsize=None)
def measured(surface):
    curved = surface == "curved"
    V, F, g = sheet(curved)
    painted = g > 0
    out = {"surface": surface, "faces": len(F), "disc": int(painted.sum()), "strength": {}}
    for s in STRENGTHS:
        res = core.simplify(V, F, ratio=RATIO, **importance.controls(g, 1e-3, s))
        inside = painted[res.vertex_origin]
        k_in = np.count_nonzero(inside) / painted.sum()
        k_out = np.count_nonzero(~inside) / (~painted).sum()
        out["strength"][s] = {
            "triangles": len(res.faces), "kept": k_in, "in_out": k_in / k_out,
            "deviation": vertical_deviation(V[painted], res.vertices, res.faces) if curved else None,
        }
    base = out["strength"][0.0]["in_out"]
    for r in out["strength"].values():
        r["gain"] = r["in_out"] / base
    return out


@pytest.fixture(params=["flat", "curved"])
def runs(request):
    return measured(request.param)


def test_target_met_at_every_strength(runs):
    target = int(round(RATIO * runs["faces"]))
    assert runs["disc"] > 1300
    for s, r in runs["strength"].items():
        assert abs(r["triangles"] - target) <= 1, (s, r)


def test_density_rises_with_strength(runs):
    in_out = [runs["strength"][s]["in_out"] for s in STRENGTHS]
    assert all(b > a for a, b in zip(in_out, in_out[1:])), in_out
    assert 0.8 < in_out[0] < 1.2  # strength 0 is the uniform run


def test_subtle_default_soft_top_near_locking(runs):
    r = runs["strength"]
    # 0.1: a subtle preference (the calibration aims at 1.5x).
    assert 1.2 <= r[0.1]["gain"] <= 2.0, r[0.1]
    # The default: clearly denser, yet soft: the disc loses at least half its vertices.
    default = r[importance.DEFAULT_STRENGTH]
    assert default["in_out"] >= 2.0 and default["gain"] >= 2.0, default
    assert default["kept"] <= 0.5, default
    # The top: nearly locked (measured 98 % flat, 91 % curved).
    assert r[1.0]["kept"] >= 0.85, r[1.0]


def test_default_halves_the_painted_deviation_on_a_curved_sheet():
    r = measured("curved")["strength"]
    assert r[importance.DEFAULT_STRENGTH]["deviation"] <= 0.5 * r[0.0]["deviation"], r


def test_expected_gain_holds_within_a_factor_of_two(runs):
    # The slider's promise (panel: "about Nx as dense") on both surfaces, below the top.
    for s in STRENGTHS[1:-1]:
        expected = importance.expected_gain(s)
        assert expected / 2 <= runs["strength"][s]["gain"] <= expected * 2, (s, runs["strength"][s])


def test_one_meaning_on_flat_and_curved():
    # With the line quadric scaled by the factor ** 0.75 (addon/pure/importance.py) the two
    # are within 0.75-1.3x of each other up to 0.75 (measured); scaling the whole quadric
    # gave a flat region 1.4x the curved gain at 0.75 and 2.5x at 0.9 on the bench.
    flat, curved = measured("flat")["strength"], measured("curved")["strength"]
    for s in STRENGTHS[1:-1]:
        assert 0.7 <= flat[s]["gain"] / curved[s]["gain"] <= 1.5, (s, flat[s], curved[s])
