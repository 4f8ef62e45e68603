# SPDX-License-Identifier: GPL-3.0-or-later
"""What the Importance settings mean, as numbers the core understands.

An artist gives importance as a value g_i in [0, 1] per vertex: a painted vertex group,
or the skin-derived weight of the paper (Sec. 5.3) divided by its cap 0.1, which is also
what "Importance from Armature" bakes into the LOD_Importance group so it can be seen
and repainted. The Strength slider (0..1) says how much g counts, in one unit an artist
can see: how many times denser than the rest a fully painted region comes out.

How (paper Sec. 4.4.1, extreme weights). Vertex i's augmented quadric is multiplied by
the core's ``quadric_scale``
    factor_i = F(strength) ** g_i,
F(0) = 1 (importance off) up to F(1) ~ 4,000 (near locking): its planes by the factor,
its line quadric by the factor ** 0.75 (LINE_SCALE_EXPONENT, below). Scaling the error,
not adding line weight, is what gives the slider one meaning on every surface: it
raises the collapse cost whether that cost comes from curvature (plane error) or, on a
flat region, from the small line quadric alone. An added line
weight (the former "Soft" mode, w_i = 0.001 + 0.1 strength g_i) competes with the plane
error instead: on a flat region, where the plane error is zero, it raised the cost 100x
at strength 1 and locked a painted disc (92 % of its vertices kept at 10 %), while on a
curved sheet the same strength gave a third of that density. Issue 19 has the numbers;
docs/weight-painting.md has the measured curve.

Calibration (measured, not derived): STRENGTH_TO_GAIN is the design, the density gain
each slider position should give (subtle ~1.5x at 0.1, ~4x at the default 0.5, near
locking at 1). GAIN_TO_FACTOR is measured by bench/importance_calibration.py --sweep:
the quadric factor that gives each gain, as the geometric mean over a flat grid and a
curved sheet with a painted disc taken to 10 % (with the line quadric scaled by the
factor ** 0.75 the two stay within 0.75-1.9x of each other at every factor; scaling the
whole quadric, flat regions saturated into a lock sooner, 2.5x the curved gain at
strength 0.9). A strength is turned into a gain, then into a factor, by interpolating both
tables on logarithms (density follows the factor's logarithm, smoothly). Re-run the
sweep and paste its table when the core's collapse order changes.

Density gain = (share of the painted vertices kept) / (share of the rest kept). It
depends on the target (at 50 % a region can be at most 2x denser) and on how much is
painted; the calibration is at 10 % with ~10 % of the vertices painted.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from ._core import core

DEFAULT_STRENGTH = 0.5
# The line quadric is scaled by the factor ** 0.75, the planes by the factor
# (core.Options.line_scale_exponent). Measured on the calibration surfaces: scaling the
# whole quadric (1) made a flat region up to 2.5x as dense as a curved one at the same
# strength (a flat region's cost, its line quadric alone, grows more slowly with a
# collapse's size, so the same factor buys more density there); 0.5 turned that over
# (flat 0.4x curved); 0.75 kept them within 0.75-1.9x of each other at every factor.
LINE_SCALE_EXPONENT = 0.75
SKIN_CAP = core.weights.SKIN_WEIGHT_MAX  # 0.1: skin weights are baked as w / cap in [0, 1]
# The paper's "small amount of line quadrics" before scaling (Sec. 4.4.1): a flat region
# needs some error to scale. With Uniformity below this, importance lifts every vertex to
# it (not only the painted ones, or a painted flat region would be compared with zero).
LINE_WEIGHT_FLOOR = core.vertex_quadrics.SCALED_LINE_WEIGHT_FLOOR

# (strength, density gain of a fully painted region): the slider's design.
STRENGTH_TO_GAIN = ((0.0, 1.0), (0.1, 1.5), (0.25, 2.4), (0.5, 4.5), (0.75, 12.0), (1.0, 90.0))
# (density gain, quadric factor): measured, bench/importance_calibration.py --sweep.
GAIN_TO_FACTOR = ((1, 1), (1.33, 1.5), (1.63, 2), (2.09, 3), (2.47, 4), (3.17, 6), (3.84, 8), (4.78, 12),
                  (5.58, 16), (7.81, 24), (9.74, 32), (13.22, 64), (22.25, 128), (35.41, 256), (48.24, 512),
                  (60.66, 1000), (78.62, 2000), (89.82, 4000), (99.67, 8000))


# Source Armature: what the sample poses' mean error counts against the rest error
# (core.Options.pose_weight) at Strength 1; the default 0.5 gives 4, measured on the Fox
# rows (bench/skinned_ablation.py, docs/armature.md): 2, 3 and 6 did no better on B and D,
# posed or at rest.
POSE_WEIGHT_AT_FULL_STRENGTH = 8.0


def pose_weight(strength: float) -> float:
    """core.Options.pose_weight for Source Armature at ``strength`` (0 = poses left out)."""
    return POSE_WEIGHT_AT_FULL_STRENGTH * float(strength)


# Source Shape Keys: importance where the keys move the surface (shape_key_importance).
# A vertex counts as moved when its largest offset is above KEY_MOVING times the largest
# of all (below that it is noise, or a key's far tail); the robust maximum is the
# KEY_REFERENCE_QUANTILE quantile of the moved vertices' offsets, so a few outliers (one
# vertex a key pulls far) do not make the rest of the keyed region count for little.
KEY_MOVING = 1e-3
KEY_REFERENCE_QUANTILE = 0.9


# Source Shape Keys also weighs the keys' own error where the importance is: at g = 1 a
# key's error counts key_weight(strength) times as much as at rest (1 + 14 x Strength: 8 at
# the default), W ** g in between (core.Options.key_scale_exponent, on top of the factor
# every plane gets), as Source Armature counts its sample poses more (pose_weight).
# Measured at 25 % (bench/shape_keys.py, docs/benchmarks.md), each key's region mean over
# the same without importance, against the keys counting as the rest: the generated face
# 0.43x -> 0.32x (rest 1.06x -> 1.08x), RobotExpressive as one asset 0.95x -> 0.76x (rest
# 0.98x -> 0.95x); the robot's face plate alone, which every key moves all of, 1.03x ->
# 1.06x. 16 at the default took the robot to 0.60x but the plate alone to 1.16x.
KEY_WEIGHT_PER_STRENGTH = 14.0


def key_weight(strength: float) -> float:
    """What a shape key's error counts against the rest error at g = 1 under Source Shape
    Keys at ``strength`` (1 = alike, at strength 0)."""
    return 1.0 + KEY_WEIGHT_PER_STRENGTH * float(strength)


def key_scale_exponent(strength: float) -> float:
    """core.Options.key_scale_exponent for Source Shape Keys at ``strength``: the keys'
    planes get factor ** exponent = factor * key_weight at g = 1."""
    top = factor(strength)
    return 1.0 if top <= 1.0 else 1.0 + float(np.log(key_weight(strength)) / np.log(top))


def key_motion(offsets: np.ndarray) -> np.ndarray:
    """(n,) how far the keys move each vertex: the largest offset over the keys (K, n, 3)
    (what each key moves each vertex by at value 1); 0 where not finite."""
    offsets = np.asarray(offsets, dtype=np.float64)
    if offsets.ndim != 3 or offsets.shape[2] != 3:
        raise ValueError(f"shape-key offsets must be a (keys, n, 3) array, got shape {offsets.shape}")
    if offsets.shape[0] == 0 or offsets.shape[1] == 0:
        return np.zeros(offsets.shape[1])
    moved = np.sqrt(np.einsum("knj,knj->kn", offsets, offsets)).max(axis=0)
    moved[~np.isfinite(moved)] = 0.0
    return moved


def motion_reference(moved: np.ndarray) -> float:
    """The robust maximum of key motions ``moved`` (any shape, one unit): the
    KEY_REFERENCE_QUANTILE quantile of those above KEY_MOVING times the largest; 0 when
    nothing moves. Over an asset's parts, give their motions in scene units."""
    moved = np.asarray(moved, dtype=np.float64).ravel()
    top = float(moved.max(initial=0.0))
    if top <= 0.0:
        return 0.0
    return float(np.quantile(moved[moved > KEY_MOVING * top], KEY_REFERENCE_QUANTILE))


def shape_key_importance(offsets: np.ndarray, reference: Optional[float] = None) -> np.ndarray:
    """Importance g in [0, 1] per vertex from shape-key offsets (K, n, 3) (what each key
    moves each vertex by at value 1): the largest offset over the keys, m_i (key_motion),
    in proportion to a robust maximum r (motion_reference: the KEY_REFERENCE_QUANTILE
    quantile of m over the vertices that move), g = min(m / r, 1). ``reference``: r given
    (in the offsets' unit), e.g. an asset's, taken over all of its parts.

    The falloff is the keys' own: g follows how far the vertex moves, so where a key fades
    into the still surface its importance fades with it, continuously (a step in g would
    be a step in density), and saturates at 1 for the furthest-moving tenth (one vertex
    pulled far does not make the rest of the keyed region count for little). Measured
    against a smoothstep of the same ratio (which lets the small movements at a key's
    tail count less): the linear ramp kept the keyed regions as close or closer at the
    same cost at rest (docs/benchmarks.md, shape keys). Vertices that no key moves get 0;
    no key moving anything gives 0 everywhere."""
    moved = key_motion(offsets)
    r = motion_reference(moved) if reference is None else float(reference)
    if not r > 0.0:
        return np.zeros(len(moved))
    return np.minimum(moved / r, 1.0)


# Source Shape Keys moves triangles from where the keys leave the surface still to where
# they move it. Where they move nearly all of it there is nothing to take triangles from,
# and the importance only moves detail around inside the region the keys are judged on:
# RobotExpressive's face plate alone, which every key moves all of (by 15-100 % of the
# reference), came out 1.24x further from the source at each key and 1.36x at rest than
# without importance (bench/shape_keys.py, 25 %), where the generated face (90 % of its
# surface still) came out 0.31x and the robot as one asset (the plate a small part of
# it) 0.24x. So the strength is scaled by the share of the surface the keys leave still
# (importance below KEY_STILL at every corner of a face), in full from KEY_STILL_FULL of it
# and linearly down to none (key_strength). An asset's share is the asset's (asset.py).
KEY_STILL = 0.05
KEY_STILL_FULL = 0.5


def still_share(g: np.ndarray, vertices: np.ndarray, faces: np.ndarray, scale: float = 1.0) -> tuple:
    """(still area, total area) of the triangles ``faces`` (m, 3) over ``vertices`` (n, 3),
    in the vertices' units times ``scale`` squared: still, those whose every corner has
    importance ``g`` (n,) below KEY_STILL. Sums, so that an asset's parts add up."""
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if not len(f):
        return 0.0, 0.0
    areas = core.geometry.face_frames(np.asarray(vertices, dtype=np.float64), f)[1] * float(scale) ** 2
    still = (np.asarray(g, dtype=np.float64)[f] < KEY_STILL).all(axis=1)
    return float(areas[still].sum()), float(areas.sum())


def key_strength(strength: float, still: float, total: float) -> float:
    """The strength Source Shape Keys runs at when the keys leave ``still`` of a surface's
    ``total`` area still: ``strength`` from KEY_STILL_FULL of it, scaled down linearly to
    0 when nothing is still."""
    share = still / total if total > 0 else 1.0
    return float(strength) * min(1.0, share / KEY_STILL_FULL)


def key_strength_note(strength: float, scaled: float) -> Optional[str]:
    """The note of a mesh whose Source Shape Keys ``strength`` key_strength scaled to
    ``scaled``, or None when it was not."""
    if scaled >= strength - 1e-9:
        return None
    return (f"the shape keys move {'all' if scaled <= 0 else 'most'} of the surface: Source Shape Keys "
            f"strength {strength:g} -> {scaled:.2g} (it takes triangles from where the keys leave the "
            f"surface still)")


def skin_importance(skin_weights: np.ndarray) -> np.ndarray:
    """Importance g in [0, 1] from (n, bones) deform weights: the paper's Sec. 5.3 line
    weights w_i over their cap (w / 0.1)."""
    return core.skin_line_weights(skin_weights) / SKIN_CAP


def _log_interp(x: float, table) -> float:
    xs, ys = np.log(np.array(table, dtype=np.float64)).T
    return float(np.exp(np.interp(np.log(x), xs, ys)))


def expected_gain(strength: float) -> float:
    """How many times denser than the rest a fully painted region should come out (at 10 %)."""
    s, gain = np.array(STRENGTH_TO_GAIN, dtype=np.float64).T
    # Linear in log(gain) between the design's points: each step of the slider
    # multiplies the density alike within a segment.
    return float(np.exp(np.interp(float(strength), s, np.log(gain))))


def factor(strength: float) -> float:
    """Quadric factor of a fully painted vertex (g = 1) at ``strength``."""
    return _log_interp(expected_gain(strength), GAIN_TO_FACTOR)


def effective(g: np.ndarray, strength: float) -> np.ndarray:
    """Per-vertex effective importance in [0, 1]: log(factor_i) / log(factor at strength 1).

    What "Preview Importance" shows in Weight Paint: 0 = simplified like the rest, 1 =
    the slider's top (near locking). Half-way means half the top's factor, in logarithm.
    """
    g = np.clip(np.asarray(g, dtype=np.float64), 0.0, 1.0)
    return g * (np.log(factor(strength)) / np.log(factor(1.0)))


def controls(g: np.ndarray, line_weight: float, strength: float, keys: bool = False) -> dict:
    """Core options (quadric_scale, line_scale_exponent, maybe line_weights) for importance
    g in [0, 1]; ``keys`` (Source Shape Keys): also key_scale_exponent."""
    g = np.clip(np.asarray(g, dtype=np.float64), 0.0, 1.0)
    out = {"quadric_scale": np.power(factor(strength), g), "line_scale_exponent": LINE_SCALE_EXPONENT}
    if keys:
        out["key_scale_exponent"] = key_scale_exponent(strength)
    if line_weight < LINE_WEIGHT_FLOOR and np.any(out["quadric_scale"] > 1):
        out["line_weights"] = np.full(len(g), LINE_WEIGHT_FLOOR)
    return out


# The report: how dense the painted region came out.
PAINTED = 0.5  # importance g from which a vertex counts as painted in the density report


def region_word(source: str) -> str:
    """What the report and the panel call the region of g >= 0.5 for an importance source:
    "keyed" for Source Shape Keys (nobody painted it), else "painted"."""
    return "keyed" if source == 'SHAPE_KEYS' else "painted"


def importance_density(g: np.ndarray, vertex_origin: np.ndarray, region: str = "painted") -> Optional[dict]:
    """How dense the painted region (g >= 0.5) came out against the rest: the share of
    each kept and their ratio, the density in/out relative to the input's (on a uniform
    mesh simply the painted region's vertex density over the rest's). ``region``: what
    the panel calls that region (region_word). None when nothing or everything is painted."""
    painted = np.asarray(g) >= PAINTED
    n_in = int(np.count_nonzero(painted))
    n_out = len(painted) - n_in
    if n_in == 0 or n_out == 0:
        return None
    kept_in = int(np.count_nonzero(painted[vertex_origin]))
    kept_out = len(vertex_origin) - kept_in
    share_in, share_out = kept_in / n_in, kept_out / n_out
    return {"painted_vertices": n_in, "painted_kept": kept_in, "painted_kept_percent": 100.0 * share_in,
            "rest_kept_percent": 100.0 * share_out,
            "painted_density": share_in / share_out if share_out > 0 else float("inf"), "region": region}
