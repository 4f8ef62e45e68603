# SPDX-License-Identifier: GPL-3.0-or-later
"""Each shape key's deviation: a LOD with the key at 1 against the source with the key at 1.

Every LOD keeps every shape key (their offsets are carried through the collapses, and
core/shape_keys.py keeps the strongest ones close in the error), but a LOD is measured
at rest. This measures each key's shape too: for every key, the source and the LOD are
each moved by what that key does at value 1 (the other keys at 0), and compared as the
level itself is (measure.surface_deviation: two-sided Hausdorff and mean), in scene
units and in percent of the *rest* source's bounding-box diagonal, the level's own
denominator, so a key's numbers read against the level's.

Each key is given twice. Over the whole surface, as the level is measured, so a key reads
against the level's own numbers. And over the key's own region (``region_*``): the source
triangles with a vertex the key moves by more than REGION_SHARE of its largest motion,
measured both ways from the same queries: the source's samples in the region to the LOD
with the key, and the LOD's samples whose closest source point is in the region to the
source with the key (so a LOD triangle cutting across a closed lid counts, not only the
lid's own samples). Why both: a face's keys move a few percent of the head, so with a
blink at 1 the whole-surface mean is the rest pose's mean and cannot say whether the
blink survived; the region's numbers do. The whole surface still catches what a key does
to the rest (and a key that moves everything has the whole mesh as its region).

"What the key does at 1" is what Blender shows with that slider at 1 (key_offsets):
relative keys move each vertex by (key - its relative key) times the key's vertex group
weight; a key relative to another key (a chain) is measured on its own, not on top of
that key. Absolute keys (Relative off, mixed by evaluation time) have no value of 1:
each is measured as its own stored shape.

Cost: two BVH trees and queries per key and level. Up to KEYS_AT_FULL_SAMPLES keys are
sampled as the level is (deviation_search.report_samples, the source's side
SOURCE_SHARE of it); beyond that the samples are
shared out so that all keys together cost about as much as KEYS_AT_FULL_SAMPLES levels,
at least KEY_SAMPLES_MIN per surface. Every vertex of both surfaces is queried on top
(the Hausdorff distance needs them), so a rig of a hundred keys still costs a hundred
times the vertices; keys that move nothing on this mesh (a glTF import gives every part
all of its morph targets) are the rest shape and are measured once.

No bpy here (mathutils only when measuring), so the offsets can be tested without Blender.
"""
from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np

from . import measure
from .deviation_search import SOURCE_SHARE, report_samples

KEYS_AT_FULL_SAMPLES = 4
KEY_SAMPLES_MIN = 2_000
# A key's region: the source triangles with a vertex the key moves by more than this share
# of its largest motion on the mesh (below it, a key's far tail or noise).
REGION_SHARE = 0.05


def key_offsets(shape_keys: Sequence, use_relative: bool = True, group_names: Sequence = (),
                group_weights: Optional[np.ndarray] = None, basis_name: str = "Basis") -> np.ndarray:
    """(K, n, 3): how far each key moves each vertex at value 1, the others at 0.

    ``shape_keys``: mesh_io.ShapeKeyData-like (name, offsets from the basis, relative_key,
    vertex_group); ``group_names`` / ``group_weights`` (n, g): the mesh's vertex groups,
    for keys limited to one. Relative keys: offsets minus their relative key's (a key
    relative to itself moves nothing, as in Blender), times the group's weights when the
    key names a group the mesh has. Absolute keys (``use_relative`` False): the stored offsets.
    """
    if not shape_keys:
        return np.zeros((0, 0, 3))
    stored = np.stack([np.asarray(sk.offsets, dtype=np.float64) for sk in shape_keys])
    if not use_relative:
        return stored
    index = {sk.name: i for i, sk in enumerate(shape_keys)}
    names = list(group_names)
    out = stored.copy()
    for k, sk in enumerate(shape_keys):  # a loop over keys, not vertices
        rel = sk.relative_key
        if rel and rel != basis_name and rel in index:
            out[k] -= stored[index[rel]]
        if sk.vertex_group and sk.vertex_group in names and group_weights is not None:
            out[k] *= np.asarray(group_weights, dtype=np.float64)[:, names.index(sk.vertex_group), None]
    return out


def offsets_of(data) -> np.ndarray:
    """key_offsets of a mesh_io.MeshData (the source or a LOD)."""
    return key_offsets(data.shape_keys, data.shape_use_relative, data.group_names, data.group_weights,
                       data.basis_name)


def key_samples(triangles: int, keys: int, part_samples: Optional[int] = None) -> int:
    """Area samples per surface and key for a surface of ``triangles`` triangles with ``keys``
    keys; ``part_samples``: for a part of an asset, what its report gets
    (deviation_search.part_samples), so that its keys follow its share of the asset's area
    as its report does (the robot's three head parts paid their own 10,000-28,000 a key)."""
    share = math.ceil(max(keys, 1) / KEYS_AT_FULL_SAMPLES)
    return max(KEY_SAMPLES_MIN, report_samples(triangles, part_samples) // share)


def key_region(offsets: np.ndarray, faces: np.ndarray, share: float = REGION_SHARE) -> np.ndarray:
    """(m,) bool: the triangles of ``faces`` with a vertex that ``offsets`` (n, 3), one
    key's, move by more than ``share`` of their largest motion; none for a key that moves nothing."""
    moved = np.linalg.norm(np.asarray(offsets, dtype=np.float64), axis=1)
    top = float(moved.max(initial=0.0))
    if not top > 0.0:
        return np.zeros(len(faces), dtype=bool)
    return (moved > share * top)[np.asarray(faces)].any(axis=1)


def _area_share(vertices: np.ndarray, faces: np.ndarray, region: np.ndarray) -> float:
    """The share of the surface's area the triangles ``region`` cover, in percent."""
    p = vertices[faces]
    area = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    total = float(area.sum())
    return 100.0 * float(area[region].sum()) / total if total > 0 else 0.0


def level_key_deviations(data, level, diagonal: Optional[float] = None,
                         part_samples: Optional[int] = None) -> list:
    """[{name, hausdorff, mean, hausdorff_percent, mean_percent, and for a key that moves
    the mesh: region_mean, region_hausdorff, region_mean_percent, region_hausdorff_percent,
    region_area_percent}] per shape key of the source ``data``: ``level`` (a LOD of it,
    carrying the same keys) against ``data``, both with that key at 1, over the whole
    surface and over the key's own region (key_region, measured both ways:
    measure.region_deviation; region_area_percent: the share of the source's
    area with the key at 1 that the region covers). Percent of ``diagonal`` (by default
    the rest source's bounding-box diagonal); ``part_samples`` as key_samples takes it.
    [] when the source has no shape keys."""
    if not data.shape_keys:
        return []
    if diagonal is None:
        diagonal = measure.bbox_diagonal(data.vertices, data.faces)
    source, lod = offsets_of(data), offsets_of(level)
    keys = len(data.shape_keys)
    # (the source's side its share, as the level's report has it: deviation_search.SOURCE_SHARE)
    samples = (int(SOURCE_SHARE * key_samples(len(data.faces), keys, part_samples)),
               key_samples(len(level.faces), keys, part_samples))
    scale = 100.0 / diagonal if diagonal > 0 else float("nan")
    out = []
    still = None  # keys that move nothing are the rest shape: measured once
    for k, sk in enumerate(data.shape_keys):
        if not source[k].any() and not lod[k].any():
            if still is None:
                still = measure.surface_deviation(data.vertices, data.faces, level.vertices, level.faces,
                                                  n_samples=samples)
            d = still
        else:
            region = key_region(source[k], data.faces)
            d = measure.surface_deviation(data.vertices + source[k], data.faces, level.vertices + lod[k],
                                          level.faces, n_samples=samples, keep_samples=True)
            d.update(measure.region_deviation(d.pop("sampled"), data.faces, region))
        entry = {"name": sk.name, "hausdorff": float(d["hausdorff"]), "mean": float(d["mean"]),
                 "hausdorff_percent": float(d["hausdorff"] * scale), "mean_percent": float(d["mean"] * scale)}
        if "region_mean" in d and np.isfinite(d["region_mean"]):
            entry.update({"region_mean": float(d["region_mean"]), "region_hausdorff": float(d["region_hausdorff"]),
                          "region_mean_percent": float(d["region_mean"] * scale),
                          "region_hausdorff_percent": float(d["region_hausdorff"] * scale),
                          "region_area_percent": _area_share(data.vertices + source[k], data.faces, region)})
        out.append(entry)
    return out


def worst(keys: list) -> Optional[dict]:
    """The key entry with the largest Hausdorff distance, or None for no keys."""
    return max(keys, key=lambda entry: entry["hausdorff"]) if keys else None
