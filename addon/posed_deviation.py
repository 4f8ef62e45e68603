# SPDX-License-Identifier: GPL-3.0-or-later
"""How far skinned LODs are from their source as the rig's own animation poses them
(issue 34 §3): the level report's ``posed`` entry.

For each armature that deforms a measured chain: its actions (the active one, then the
actions of its NLA strips, each once) are played one at a time, at up to
FRAMES_PER_ACTION frames spread over each action's frame range (MAX_FRAMES in all,
spread over the actions; fewer for a heavy rig, frame_budget); at each frame the sources
and their LODs are evaluated by Blender's depsgraph (the Armature modifier as it deforms
them, constraints, IK and Preserve Volume included: exact by construction) and measured
against each other in their own (local) coordinates at posed_samples: level k of all
the chains one armature deforms in one go (measure.part_deviations), each chain's
numbers from its own points. A LOD that moved with its source as one rigid body since
the rest shapes its report measured (level_deviation.moved_rigidly: a part skinned to one
bone, or a frame at the rest pose) is as far from it as at rest and takes the report's
numbers instead: a rigid character's 59 parts took 0.6 s to measure at 4 frames, now
none. Per LOD the report gets the mean and the largest, over the frames, of the
two-sided Hausdorff and mean distance, in percent of the source's bounding-box diagonal
at rest.

The scene is left as it was: the frame, the armature's action (and slot), its NLA
switch, its pose and its transform are put back, whatever happens. An armature with no
actions gets a note instead of numbers. Main thread only (lod.commit calls it, once the
LOD objects are linked).
"""
from __future__ import annotations

import contextlib
from typing import NamedTuple, Optional

import numpy as np

from .pure import level_deviation
from .pure import measure
from .pure.deviation_search import report_samples
from .rig import armature_of

FRAMES_PER_ACTION = 8
MAX_FRAMES = 16  # per armature, spread over its actions (a character may have dozens)
# Each frame poses and measures every source and LOD the armature deforms (trees,
# samples, the depsgraph): about 2.7 us a triangle here. An armature's frames are capped so
# that frames x triangles stays under this (16 frames up to ~31,000 triangles a frame; a
# 75,000-triangle character and its three LODs get 4), never fewer than MIN_FRAMES.
POSED_TRIANGLE_FRAMES = 500_000
MIN_FRAMES = 4
POSED_SAMPLES_MIN = 500  # area samples a surface and frame (posed_samples), and vertices
POSED_SHARE = 2  # a frame: the report's area samples / (POSED_SHARE * frames), as many vertices
_POSE_PROPS = (("location", 3), ("rotation_quaternion", 4), ("rotation_euler", 3), ("rotation_axis_angle", 4),
               ("scale", 3))
_OBJECT_PROPS = ("location", "rotation_quaternion", "rotation_euler", "rotation_axis_angle", "scale")


class Chain(NamedTuple):
    """A measured skinned chain: its ``source`` object, its LOD objects ``lods`` and their
    report entries ``entries`` (each gets ``posed``), the source's bounding-box
    ``diagonal`` at rest (what the percentages are of), its LodInput.part_samples, and
    ``rest``: the surfaces the report measured, [(vertices, faces)] of the source then
    of each LOD, or None (each level is then measured at every frame)."""
    source: object
    lods: list
    entries: list
    diagonal: float
    part_samples: Optional[int] = None
    rest: Optional[list] = None


def posed_samples_of(surfaces: list, frames: int = MAX_FRAMES) -> int:
    """Area samples a frame for surfaces measured as one, [(triangles, part_samples or
    None)], and the most vertices queried on top: over its ``frames`` frames a level's
    area samples and vertices together are about as many as the area samples its reports
    measure it with once (report_samples; ``part_samples``: for a part of an asset, what
    its report gets), half of them on the area; at least POSED_SAMPLES_MIN a frame, once
    for them all. (A quarter of the report's a frame, every vertex on top, made the
    posed distance of a 75,000-triangle character 10 s of a 14 s run.)"""
    total = sum(report_samples(triangles, share) for triangles, share in surfaces)
    return max(POSED_SAMPLES_MIN, total // (POSED_SHARE * max(int(frames), 1)))


def posed_samples(triangles: int, part_samples: Optional[int] = None, frames: int = MAX_FRAMES) -> int:
    """posed_samples_of one surface."""
    return posed_samples_of([(triangles, part_samples)], frames)


def actions_of(arm) -> list:
    """[(action, slot or None)] the armature object plays: its active action, then the
    actions of its NLA strips, each action once (slots: Blender 4.4+, else None)."""
    anim = arm.animation_data
    if anim is None:
        return []
    found, seen = [], set()

    def add(action, slot):
        if action is not None and action.name not in seen:
            seen.add(action.name)
            found.append((action, slot))

    add(anim.action, getattr(anim, "action_slot", None))
    for track in anim.nla_tracks:
        for strip in track.strips:
            add(strip.action, getattr(strip, "action_slot", None))
    return found


def _vector_props(collection, props) -> dict:
    saved = {}
    for prop, width in props:
        values = np.empty(len(collection) * width, dtype=np.float32)
        collection.foreach_get(prop, values)
        saved[prop] = values
    return saved


@contextlib.contextmanager
def _animation_kept(scene, arm, depsgraph_of):
    """Put the scene's frame and ``arm``'s action, slot, NLA switch, pose and transform
    back afterwards (and evaluate the scene so)."""
    anim = arm.animation_data
    frame, subframe = scene.frame_current, scene.frame_subframe
    action = anim.action
    slot = getattr(anim, "action_slot", None)
    use_nla = anim.use_nla
    pose = _vector_props(arm.pose.bones, _POSE_PROPS) if arm.pose is not None else {}
    transform = {prop: tuple(getattr(arm, prop)) for prop in _OBJECT_PROPS}
    try:
        yield
    finally:
        anim.action = action
        if slot is not None and getattr(anim, "action_slot", None) != slot:
            anim.action_slot = slot
        anim.use_nla = use_nla
        scene.frame_set(frame, subframe=subframe)
        for prop, values in pose.items():
            arm.pose.bones.foreach_set(prop, values)
        for prop, value in transform.items():
            setattr(arm, prop, value)
        arm.update_tag()
        depsgraph_of().update()


def _play(arm, action, slot) -> None:
    """``action`` alone on ``arm``: the active action (in its slot), the NLA off."""
    anim = arm.animation_data
    anim.use_nla = False
    anim.action = action
    if hasattr(anim, "action_slot"):
        if slot is not None and anim.action_slot != slot:
            anim.action_slot = slot
        elif anim.action_slot is None and len(anim.action_suitable_slots):
            anim.action_slot = anim.action_suitable_slots[0]


def _measure_frame(depsgraph, group, frames: int) -> list:
    """[(level entry, Hausdorff %, mean %, whether it moved rigidly)] of every level of
    the ``group``'s chains as the depsgraph poses them now. A chain whose source and LODs
    moved as one rigid body since the rest shapes the report measured (a part skinned to
    one bone; level_deviation.moved_rigidly) is as far from them as at rest: its levels
    take their reports' numbers, no query. The others, level k of all the chains, are measured
    in one go against all their sources (measure.part_deviations: one tree and one query
    loop a side, whatever the number of parts), each chain's numbers from the points on
    its own triangles, in percent of its own diagonal at rest; the sources' joined mesh
    (and so its tree) is the same for every level that has the same chains."""
    sources = [evaluated_triangles(chain.source, depsgraph) for chain in group]
    levels = [[evaluated_triangles(lod, depsgraph) for lod in chain.lods] for chain in group]
    out = []
    measured = []  # (chain index, level index) of the levels that moved otherwise
    for i, chain in enumerate(group):
        # (one fit for the chain: its LODs carry its skin, so they move with it or not at all)
        rigid = (chain.rest is not None and len(chain.rest) == len(chain.entries) + 1
                 and all("hausdorff_percent" in entry for entry in chain.entries)
                 and level_deviation.moved_rigidly(chain.rest, [sources[i], *levels[i]], chain.diagonal))
        for k, entry in enumerate(chain.entries):
            if rigid:
                out.append((entry, float(entry["hausdorff_percent"]), float(entry["mean_percent"]), True))
            else:
                measured.append((i, k))
    if not measured:
        return out
    moves = _apart([sources[i]] + levels[i] for i in range(len(group)))
    joined_sources = {}
    for k in sorted({k for _, k in measured}):
        chains = tuple(i for i, kk in measured if kk == k and len(sources[i][1]) and len(levels[i][k][1]))
        if not chains:
            continue
        if chains not in joined_sources:
            joined_sources[chains] = _joined([sources[i] for i in chains], moves[list(chains)])
        src_v, src_f, src_part = joined_sources[chains]
        dst_v, dst_f, dst_part = _joined([levels[i][k] for i in chains], moves[list(chains)])
        n_src = posed_samples_of([(len(sources[i][1]), group[i].part_samples) for i in chains], frames)
        n_dst = posed_samples_of([(len(levels[i][k][1]), group[i].part_samples) for i in chains], frames)
        hausdorff, mean = measure.part_deviations(src_v, src_f, src_part, dst_v, dst_f, dst_part, len(chains),
                                                  n_samples=(n_src, n_dst), vertex_limit=max(n_src, n_dst),
                                                  find_shared=False)
        for j, i in enumerate(chains):
            diagonal = group[i].diagonal
            scale = 100.0 / diagonal if diagonal > 0 else float("nan")
            out.append((group[i].entries[k], float(hausdorff[j]) * scale, float(mean[j]) * scale, False))
    return out


def _apart(meshes_per_chain) -> np.ndarray:
    """(chains, 3) translations that put each chain (its source and LODs, a list of
    (vertices, faces)) in its own cell of a grid, three times the largest chain's extent
    apart: each is measured in its own object's coordinates, as if alone (no point is
    nearer another chain's surface than its own), and the cells stay few per axis, as
    the trees are single precision."""
    stacked = [np.concatenate([v for v, _ in meshes]) for meshes in meshes_per_chain]
    if len(stacked) == 1:
        return np.zeros((1, 3))
    lows = np.array([v.min(0) if len(v) else np.zeros(3) for v in stacked])
    span = max((float(np.ptp(v, axis=0).max()) for v in stacked if len(v)), default=0.0)
    side = int(np.ceil(len(stacked) ** (1.0 / 3.0) - 1e-9))
    j = np.arange(len(stacked))
    cells = np.stack([j % side, (j // side) % side, j // (side * side)], axis=1)
    return cells * (3.0 * max(span, 1e-9)) - lows


def _joined(meshes: list, moves: np.ndarray) -> tuple:
    """(vertices, faces, part of each face) of several (vertices, faces), each moved by
    its row of ``moves``, as one mesh."""
    offsets = np.cumsum([0] + [len(v) for v, _ in meshes[:-1]])
    return (np.concatenate([v + move for (v, _), move in zip(meshes, moves)]),
            np.concatenate([f + o for (_, f), o in zip(meshes, offsets)]),
            np.concatenate([np.full(len(f), j, dtype=np.int64) for j, (_, f) in enumerate(meshes)]))


def evaluated_triangles(ob, depsgraph) -> tuple:
    """(vertices (n, 3) float64 in the object's own coordinates, triangles (m, 3)) of
    ``ob`` as the depsgraph evaluates it now (modifiers, pose)."""
    from .mesh_io import positions, triangles

    evaluated = ob.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        vertices, faces = positions(mesh), triangles(mesh)[0]
    finally:
        evaluated.to_mesh_clear()
    return vertices, faces


def measure_chains(scene, depsgraph_of, chains: list) -> None:
    """Give each level entry of the skinned ``chains`` its ``posed`` entry.

    chains: [Chain]; a chain whose source no armature deforms is left out.
    ``depsgraph_of()``: the scene's evaluated depsgraph, current."""
    by_armature = {}
    for chain in chains:
        arm = armature_of(chain.source)
        if arm is not None and chain.lods:
            by_armature.setdefault(arm.name, (arm, []))[1].append(chain)
    for arm, group in by_armature.values():
        actions = actions_of(arm)
        if not actions:
            for entries in (chain.entries for chain in group):
                for entry in entries:
                    entry["posed"] = {"actions": [], "frames": 0,
                                      "note": f'the armature "{arm.name}" has no actions: nothing to pose it with'}
            continue
        if arm.animation_data.use_tweak_mode:
            for entries in (chain.entries for chain in group):
                for entry in entries:
                    entry["posed"] = {"actions": [], "frames": 0,
                                      "note": f'the armature "{arm.name}" is in NLA tweak mode: not posed'}
            continue
        _measure_group(scene, depsgraph_of, arm, actions, group)


def frame_budget(triangles_a_frame: int) -> int:
    """How many frames an armature's chains are posed at: MAX_FRAMES, fewer (at least
    MIN_FRAMES) when posing and measuring them all, ``triangles_a_frame`` (sources and
    LODs), that often would pass POSED_TRIANGLE_FRAMES."""
    return int(min(MAX_FRAMES, max(MIN_FRAMES, POSED_TRIANGLE_FRAMES // max(int(triangles_a_frame), 1))))


def _triangles(ob) -> int:
    """The triangles of ``ob``'s own mesh (its polygons' corners less two each)."""
    polygons = ob.data.polygons
    totals = np.empty(len(polygons), dtype=np.int64)
    polygons.foreach_get("loop_total", totals)
    return int((totals - 2).sum())


def _measure_group(scene, depsgraph_of, arm, actions, group) -> None:
    most = frame_budget(sum(_triangles(source) + sum(_triangles(lod) for lod in lods)
                            for source, lods, *_ in group))
    played = actions[:most]
    count = level_deviation.frames_per_action(len(played), FRAMES_PER_ACTION, most)
    per_level = {id(entry): [] for chain in group for entry in chain.entries}
    frames_of = [{"name": action.name, "frames": level_deviation.sample_frames(*action.frame_range, count)}
                 for action, _ in played]
    frames_in_all = sum(len(f["frames"]) for f in frames_of)
    with _animation_kept(scene, arm, depsgraph_of):
        for (action, slot), frames in zip(played, (f["frames"] for f in frames_of)):
            _play(arm, action, slot)
            for frame in frames:
                scene.frame_set(frame)
                depsgraph = depsgraph_of()
                depsgraph.update()
                for entry, h, m, rigid in _measure_frame(depsgraph, group, frames_in_all):
                    per_level[id(entry)].append((action.name, frame, h, m, rigid))
    skipped = len(actions) - len(played)
    for entries in (chain.entries for chain in group):
        for entry in entries:
            rows = per_level[id(entry)]
            posed = {"armature": arm.name, "actions": frames_of, "frames": len(rows),
                     **level_deviation.posed_summary([r[2] for r in rows], [r[3] for r in rows]),
                     # (frames at which the LOD moved with its source as one rigid body: its rest numbers)
                     "rigid_frames": sum(1 for r in rows if r[4]),
                     "per_frame": [{"action": a, "frame": f, "hausdorff_percent": h, "mean_percent": m}
                                   for a, f, h, m, _ in rows]}
            if skipped:
                posed["note"] = f"{skipped} more actions not played (at most {most} frames for this armature)"
            entry["posed"] = posed
