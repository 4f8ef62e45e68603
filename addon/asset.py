# SPDX-License-Identifier: GPL-3.0-or-later
"""The objects of one run as one asset (issue 32): one LOD set, not one chain per part.

Artists ship assets (a character's body, clothes and eyes; an engine's hundred parts), and
an engine switches an asset's levels together. So when ``asset_budget`` is on (the
default) and a run has several objects:
  * a chain by triangles is the asset's: each level's budget (its ratio of what all the
    parts draw, or its count) is spread over the parts at equal error (core.budget: each
    part's error curve from its own run, in scene units); each part is then simplified
    to its share. A part the split keeps whole stays whole; with remove_small_components
    a part leaves the asset once a level's error is larger than the part itself;
  * a chain by deviation or screen size is relative to the asset's bounding box, and in
    scene units, so every part is held to the same distance;
  * every part of level k gets the same switch numbers, from the largest measured
    deviation of that level over the parts, in scene units, and the asset's bounds.
Objects sharing a mesh (LodJob's groups) are one part, counted once per object.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional, Sequence

import numpy as np

from .pure._core import core
from .pure import importance, key_deviation, limits, switch_distances
from .pure.settings import LodSettings


# On every object of an asset's chains, sources too: the asset's name (addon/gltf_lod.py
# makes each of its levels one glTF subtree with it).
ASSET_PROP = "lqlod_asset"


@dataclass(frozen=True)
class Asset:
    """The asset's bounds in scene units (the objects' world-space bounding boxes), how
    many objects it has, and its name."""
    bounds: switch_distances.Bounds
    objects: int
    name: str = "Asset"

    @property
    def diagonal(self) -> float:
        return self.bounds.diagonal


def is_asset(objects: list, settings: list) -> bool:
    """Whether a run of ``objects`` (one LodSettings each) is one asset: several objects,
    ``asset_budget`` on for all and one chain for all (objects given chains of their own
    are chains of their own)."""
    if len(objects) < 2 or not all(s.asset_budget for s in settings):
        return False
    chains = [(s.chain(), s.deviation_chain()) for s in settings]
    return all(c == chains[0] for c in chains)


def world_matrix(ob) -> np.ndarray:
    """``ob``'s world matrix as a (4, 4) array."""
    return np.array([list(row) for row in ob.matrix_world], dtype=np.float64)


def matrix_scale(matrix: np.ndarray) -> float:
    """The largest axis scale of a (4, 4) matrix (what local units are multiplied by:
    conservative when the scale is not uniform)."""
    return float(np.linalg.norm(matrix[:3, :3], axis=0).max())


def matrix_scale_max(matrices: list) -> float:
    """The largest matrix_scale of the world matrices a part is drawn with: its size in
    the asset (conservative for a mesh instanced at several sizes)."""
    return max(matrix_scale(m) for m in matrices)


def world_scale(ob) -> float:
    """The largest axis scale of ``ob``'s world matrix, as Blender computes it (the
    switch numbers of a single object have always used this)."""
    return max(abs(c) for c in ob.matrix_world.to_scale())


def in_world(vertices: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """(n, 3) local coordinates through a (4, 4) world matrix."""
    return np.asarray(vertices, dtype=np.float64) @ matrix[:3, :3].T + matrix[:3, 3]


def asset_of(objects: list, name: str) -> Asset:
    """The asset made of ``objects``: their bounding boxes (Blender's, of the evaluated
    mesh) in world space, one box around them all."""
    corners = np.concatenate([in_world(np.array([tuple(c) for c in ob.bound_box], dtype=np.float64),
                                       world_matrix(ob)) for ob in objects])
    return Asset(switch_distances.mesh_bounds(corners), len(objects), name)


def default_name(objects: list) -> str:
    """An asset's name when none is given: the collection holding all of its objects (not
    a scene's own), else "Asset"."""
    import bpy

    # (A scene's own collection is not in bpy.data.collections.)
    shared = set.intersection(*[{c.name for c in ob.users_collection} for ob in objects])
    named = sorted(n for n in shared if n in bpy.data.collections)
    return named[0] if named else "Asset"


def mark(asset: Asset, reports: list) -> None:
    """Name the asset on every object of its chains (ASSET_PROP), sources and LODs."""
    import bpy

    for rep in reports:
        for name in [rep["object"]] + [level["name"] for level in rep["levels"]]:
            ob = bpy.data.objects.get(name)
            if ob is not None:
                ob[ASSET_PROP] = asset.name


def key_importance(inputs: list, matrices: list, shared_reference: bool = True) -> None:
    """Source Shape Keys over an asset: every part's importance from one robust maximum of
    the keys' motion over all parts (importance.motion_reference), in scene units through
    the largest scale each part is drawn at, rather than each mesh's own
    (``shared_reference`` False: each mesh's own), and its strength scaled by the share of
    the asset's surface the keys leave still (importance.key_strength: every part's area
    as drawn, the parts without keys still). ``inputs``: one phases.LodInput per part (a
    mesh), ``matrices``: per part, its objects' world matrices (as split_budget). Sets each
    keyed part's ``importance`` and core options, and a note where the strength was scaled
    down; parts without Source Shape Keys, or without keys, are left alone.

    Why one reference: importance says where the keys move the asset, in proportion to how
    far. Per mesh, a part the keys barely move (teeth a smile shifts a millimetre) would
    get as much importance as the face they shape, and the budget split would spend
    triangles on it; over the asset it gets what its motion is worth. Why the asset's
    still surface: a face plate the keys move all of takes its triangles from the rest of
    the character, which they leave still (lod.prepare scales a mesh on its own by its own)."""
    scales = [matrix_scale_max(placed) for placed in matrices]
    keyed = [k for k, i in enumerate(inputs)
             if i.settings.importance_source == 'SHAPE_KEYS' and i.data.shape_keys]
    if not keyed:
        return
    offsets = {k: key_deviation.offsets_of(inputs[k].data) for k in keyed}
    if shared_reference and len(keyed) > 1:  # one keyed part: its own reference is the asset's
        moved = {k: importance.key_motion(offsets[k]) * scales[k] for k in keyed}
        reference = importance.motion_reference(np.concatenate(list(moved.values())))
        g_of = {k: np.minimum(m / reference, 1.0) if reference > 0 else np.zeros(len(m)) for k, m in moved.items()}
    else:
        g_of = {k: importance.shape_key_importance(offsets[k]) for k in keyed}
    still = total = 0.0
    for k, (i, placed) in enumerate(zip(inputs, matrices)):
        g = g_of.get(k, np.zeros(len(i.data.vertices)))
        part_still, part_total = importance.still_share(g, i.data.vertices, i.data.faces, scales[k])
        still, total = still + part_still * len(placed), total + part_total * len(placed)
    for k in keyed:
        i, settings = inputs[k], inputs[k].settings
        strength = importance.key_strength(settings.importance_strength, still, total)
        note = importance.key_strength_note(settings.importance_strength, strength)
        if note is not None:
            i.warnings.append(note)
        i.core_options = core.Options.of(i.core_options, **importance.controls(
            g_of[k], settings.line_weight, strength, keys=True))
        i.importance = None if settings.importance_strength <= 0 else g_of[k]


# A part's error curve goes down to this share of the asset's smallest level ratio: a
# part the split takes lower (a dense little bolt drawn many times) stays there. Going
# further would cost each part a run into the low-poly end it will rarely need.
FLOOR_SHARE = 0.5


def split_budget(inputs: list, matrices: list, totals: list,
                 progress: Optional[Callable[[float], object]] = None) -> np.ndarray:
    """(levels, parts) triangle counts: the asset's ``totals`` (triangles drawn) spread
    over the parts at equal error (core.budget). ``inputs``: one phases.LodInput per part
    (a mesh); ``matrices``: per part, the world matrix of each object drawing it.

    Each part's error curve comes from its own run (its options, attributes and rig),
    in scene units through the largest scale it is drawn at; a part drawn by eight
    objects weighs eight times in the totals."""
    drawn = [len(i.data.faces) * len(placed) for i, placed in zip(inputs, matrices)]
    floor_ratio = FLOOR_SHARE * totals[-1] / max(sum(drawn), 1)
    done, whole = 0.0, float(sum(len(i.data.faces) for i in inputs))
    curves = []
    for i, placed in zip(inputs, matrices):
        m = len(i.data.faces)

        def step(f, done=done, m=m):
            return progress is None or progress((done + f * m) / whole)

        floor = int(floor_ratio * m)
        counts, errors = core.budget.error_curve(i.data.vertices, i.data.faces, i.core_options,
                                                 floor=floor, progress=step)
        if i.limit is not None and i.limit[1] is None:
            counts, errors = pixel_limited_curve(i, errors, floor)
        scale = matrix_scale_max(placed)
        curve = (counts, errors * scale)
        if i.settings.remove_small_components:
            # Gone, a part is as far from the LOD as its surface is from the rest: within
            # its own size where it sits on the asset (a bolt on its hull).
            curve = core.budget.with_removal(curve, switch_distances.mesh_bounds(i.data.vertices, i.data.faces)
                                             .diagonal * scale)
        curves.append(curve)
        done += m
    return core.budget.split_by_error(curves, totals, [len(placed) for placed in matrices])


def pixel_limited_curve(lod_input, errors: np.ndarray, floor: int) -> tuple:
    """A part's error curve under its painted limit in pixels (limits.py): each rung run
    again with the limit Limit / Pixel Error of the error that rung had reached without
    it (``errors``, the free curve's), as the part's own run will hold each level to that
    share of its error (limits.with_pixel_limit). Without this the split gave a part with
    a tightly held region its free share, and the part's run met that count elsewhere on
    it: a hull whose painted top stayed put lost its bottom (13.6 % of its size at the
    asset's LOD2, against 0.22 % unpainted), while the bolts kept triangles they did not
    need (tests/test_addon_asset.py)."""
    column, _, _ = lod_input.limit
    settings = lod_input.settings
    per_rung = limits.pixel_limits(errors[1:], settings.limit_distance, settings.pixel_error)
    options = core.Options.of(lod_input.core_options, vertex_max_error=limits.level_rows(
        lod_input.data.group_weights[:, column], per_rung))
    return core.budget.error_curve(lod_input.data.vertices, lod_input.data.faces, options, floor=floor)


def part_targets(counts: np.ndarray, faces: int) -> tuple:
    """(targets, note) of a part from its column of split_budget: the levels where it has
    triangles (a part the split removed leaves the asset from that level on), and what
    the report says about it (or None)."""
    kept = [int(c) for c in counts if c > 0]
    if len(kept) == len(counts):
        whole = sum(1 for c in kept if c >= faces)
        note = None if whole == 0 else (
            f"kept whole at LOD1-{whole}" if whole > 1 else "kept whole at LOD1") + \
            " (the asset's budget is spent where it lowers the error more)"
        return kept, note
    return kept, (f"leaves the asset from LOD{len(kept) + 1}: removing it costs less error than "
                  f"simplifying the other parts further")


def level_deviations(chains: list, for_switch: bool = False) -> Optional[list]:
    """The asset's measured deviation per level, LOD0 first (0.0), scene units: per level
    the largest over the parts that have it. ``chains``: (phases.LodOutput, world scale) per
    object. None when a level was not measured. ``for_switch``: each part's switch error
    instead (limits.switch_percent: more than its deviation where a limit in pixels
    needs the LOD to come in later), what the asset's switch distances are computed from."""
    eps = [0.0]
    diagonals = {}  # id(output) -> its source's diagonal (objects sharing a mesh share it)
    for out, scale in chains:
        if id(out) not in diagonals:
            diagonals[id(out)] = switch_distances.mesh_bounds(out.input.data.vertices, out.input.data.faces).diagonal
        diagonal = diagonals[id(out)]
        for k, entry in enumerate(out.reports, start=1):
            if "hausdorff_percent" not in entry:
                return None
            while len(eps) <= k:
                eps.append(0.0)
            percent = limits.switch_percent(entry) if for_switch else entry["hausdorff_percent"]
            eps[k] = max(eps[k], percent / 100.0 * diagonal * scale)
    return list(np.maximum.accumulate(eps)) if len(eps) > 1 else None


def switch_data(asset: Asset, eps: list, settings: LodSettings) -> dict:
    """switch_distances.switch_data of the asset: one set of switch numbers for every part."""
    return switch_distances.switch_data(eps, asset.bounds.radius, asset.bounds.size,
                                        pixel_error=settings.pixel_error, screen_height=settings.screen_height,
                                        vertical_fov_degrees=settings.vertical_fov)


def report(asset: Asset, reports: list, switch: Optional[dict], eps: Optional[list],
           notes: Sequence[str] = ()) -> dict:
    """The run's asset entry: what the asset draws per level (every object counted, shared
    meshes too), its measured deviation in scene units and in percent of its diagonal,
    its switch numbers, and ``notes`` on the asset as a whole ("warnings")."""
    levels = max((len(r["levels"]) for r in reports), default=0)
    out = {"name": asset.name, "objects": asset.objects, "bounding_box_diagonal": asset.diagonal,
           "source_triangles": int(sum(r["source_triangles"] for r in reports)), "levels": [],
           "warnings": list(notes)}
    for k in range(1, levels + 1):
        present = [r for r in reports if len(r["levels"]) >= k]
        entry = {"level": k, "parts": len(present),
                 "triangles": int(sum(r["levels"][k - 1]["triangles"] for r in present))}
        asked = [r["levels"][k - 1]["requested_deviation_percent"] for r in present
                 if r["levels"][k - 1].get("requested_deviation_percent") is not None]
        if asked:  # every part's bound is the asset's, in % of the asset's diagonal
            entry["requested_deviation_percent"] = float(asked[0])
        if eps is not None:
            entry["hausdorff"] = float(eps[k])
            entry["hausdorff_percent"] = float(100.0 * eps[k] / asset.diagonal) if asset.diagonal > 0 else 0.0
        if switch is not None:
            entry.update({key: switch[key][k] for key in switch_distances.PER_LEVEL_KEYS})
        out["levels"].append(entry)
    if switch is not None:
        out["switch"] = {key: value for key, value in switch.items() if key not in switch_distances.PER_LEVEL_KEYS}
    return out

