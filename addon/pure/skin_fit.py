# SPDX-License-Identifier: GPL-3.0-or-later
"""LOD skin weights fitted to the rig's sample poses (Source Armature), so a LOD follows
its source when posed and not only at rest; coarse levels are checked against a run
without the poses in the error.

The core carries each LOD vertex's skin weights from the source vertices it came from;
``fit_skin`` then refits them (core.skinning.fit_weights) so that, in the sample poses the
LOD was made with, each LOD point matched at rest to a point of the source stays as close
to it as it can. At a few triangles a bone the poses in the error stop paying (a coin toss), so
``skinned_levels`` also makes such a level without them and keeps whichever of the two
follows the source closer in further check poses (CHECK_POSES, never fitted to).

compute.py calls in here with the run's phases.LodInput (its ``poses`` and
``check_poses`` made by lod.prepare); this module does not import compute.py (which imports it).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from ._core import core
from . import measure

# Source points the weights are fitted at: 20,000, or 4 per LOD triangle on larger LODs so
# every triangle gets some (a triangle without any leaves its corners' weights as they were).
SKIN_FIT_SAMPLES = 20_000
SKIN_FIT_SAMPLES_PER_TRIANGLE = 4


# Levels with fewer triangles than this per deform bone are checked against the same level
# made without the poses in the error (skinned_levels). Down there a LOD cannot spend
# triangles on every joint, and the poses gave a coin toss: the Fox at 144 triangles (6 a
# bone) 0.80-1.10x of no importance's posed distance over six sample seeds, a humanoid at
# 150 (8 a bone) 0.99-1.15x, where the fitted weights alone gave 0.92-0.97x. At 32 a
# bone and above (the Fox's and the humanoid's other rows) the poses won on every seed.
COARSE_TRIANGLES_PER_BONE = 40
# Random poses of the rig besides the sample poses, never fitted to: the check of the
# coarse levels measures in them (lod.prepare makes them with the sample poses).
CHECK_POSES = 16


def skinned_levels(lod_input, results: list, simplify, may_remake: bool, tick) -> list:
    """The levels with their skin weights fitted to the sample poses (fit_skin). A coarse
    level (COARSE_TRIANGLES_PER_BONE) is also made without the poses in the error and
    fitted, and of the two the one that follows the source closer in the check poses is
    kept (``may_remake``: not for a chain by deviation, whose levels were measured).
    ``simplify(targets, **options)``: the core run on ``lod_input`` (compute.py's).
    ``tick()`` before each level's fit lets Esc in between."""
    bones = max(len(lod_input.names["skin"]), 1)
    coarse = [may_remake and len(r.faces) < COARSE_TRIANGLES_PER_BONE * bones for r in results]
    # Under a painted limit, each remade level under the limits its chain was run with.
    limited = {} if lod_input.limit_rows is None else {"vertex_max_error": lod_input.limit_rows[np.asarray(coarse)]}
    plain = iter(simplify([t for t, c in zip(lod_input.targets, coarse) if c], pose_offsets=None, pose_weight=0.0,
                          **limited)
                 if any(coarse) else [])
    out = []
    for result, check in zip(results, coarse):
        tick()
        fitted, gap = fit_skin(lod_input, result, scored=check)
        if check:
            other, other_gap = fit_skin(lod_input, next(plain), scored=True)
            if other_gap < gap and len(other.faces) == len(fitted.faces):
                fitted = other
        out.append(fitted)
    return out


def fit_skin(lod_input, result, scored: bool = False):
    """(the LOD with its skin weights fitted to the rig's sample poses
    (core.skinning.fit_weights), and, if ``scored``, how far it lies from the source in
    the check poses: the mean distance between source points and the LOD points they were
    matched to at rest, both posed, over the check poses; else None)."""
    data = lod_input.data
    skin = data.group_weights[:, lod_input.names["skin"]]
    count = max(SKIN_FIT_SAMPLES, SKIN_FIT_SAMPLES_PER_TRIANGLE * len(result.faces))
    points, weights = core.skinning.surface_samples(data.vertices, data.faces, skin, count)
    tri, bary = measure.closest_points(result.vertices, result.faces, points)
    fitted = core.skinning.fit_weights(result.vertices, result.faces, result.vertex_attributes["skin"],
                                       points, weights, tri, bary, lod_input.poses)
    gap = core.skinning.posed_gap(result.vertices, result.faces, fitted, points, weights, tri, bary,
                                  lod_input.check_poses) if scored else None
    return dataclasses.replace(result, vertex_attributes={**result.vertex_attributes, "skin": fitted}), gap
