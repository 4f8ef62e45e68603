# SPDX-License-Identifier: GPL-3.0-or-later
"""What the three phases of a LOD run hand on (addon/lod.py): prepare() reads Blender
data into a LodInput, compute() turns it into a LodOutput, commit() writes that back.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ._core import core
from .mesh_data import MeshData
from .settings import LodSettings


@dataclass
class LodInput:
    """What prepare() read from Blender for one mesh (or one part of an asset): its arrays,
    the settings, the targets and the core options they make, and what compute() needs
    besides (importance for the report, the rig's poses, deviations, a painted limit)."""

    source_name: str
    settings: LodSettings
    data: MeshData
    targets: list
    core_options: core.Options
    names: dict  # attribute keys given to the core -> what they stand for
    warnings: list = field(default_factory=list)
    importance: Optional[np.ndarray] = None  # g in [0, 1] per vertex, for the density report
    # Source Armature: the rig's sample poses (P, deform bones, 4, 4) in mesh coordinates,
    # in the order of names["skin"] (core.skinning): the LODs' weights are fitted to them.
    poses: Optional[np.ndarray] = None
    # and further random poses, never fitted to, that coarse levels are checked in
    # (skin_fit.skinned_levels)
    check_poses: Optional[np.ndarray] = None
    # A chain by deviation: each LOD's largest allowed measured distance, in the object's
    # own (local) units, like the mesh data;
    # ``targets`` are then the rungs the search measures (addon/pure/deviation_search.py,
    # addon/pure/deviation_targets.py).
    deviations: Optional[list] = None
    # A part of an asset (addon/asset.py): its targets are the asset budget's share
    # (set by LodJob before compute; [] when the split removes it at LOD1), deviations are
    # the asset's, and a level the part cannot meet is left out rather than an error.
    # ``reference_diagonal``: what "percent" means, in the object's own units (the asset's
    # bounding-box diagonal; None: the mesh's own).
    in_asset: bool = False
    reference_diagonal: Optional[float] = None
    # The source's material per slot (None: an empty slot), for the report's breakdown
    # per material (addon/pure/level_deviation.py).
    material_names: list = field(default_factory=list)
    # Painted limits (addon/pure/limits.py): (the limit group's column of data.group_weights,
    # the limit L in the object's units, or per level a tuple of them (pixels: set by
    # compute), their size in scene units), or None.
    limit: Optional[tuple] = None
    # A part of an asset simplified with the others in one core run (LodJob, core.assembly):
    # its levels, as that run left them (compute measures and writes them), or None.
    chain: Optional[list] = None
    # and, for an asset's chain by deviation searched in one run (LodJob), each level's
    # requested deviation (the object's units) and its measurement by id of the level.
    chain_requested: Optional[list] = None
    chain_measured: Optional[dict] = None
    # A part of an asset: the area samples a side its levels are measured with (its share
    # of the asset's, deviation_search.part_samples), or None: its own size's.
    part_samples: Optional[int] = None
    # Under a painted limit by triangles: the per-level vertex limits (levels, n) the
    # chain was last run with (limits.held_to_limit), for runs that remake a level
    # (skin_fit.skinned_levels).
    limit_rows: Optional[np.ndarray] = None


@dataclass
class LodOutput:
    """What compute() made of a LodInput: each LOD's mesh and report entry, and the time."""

    input: LodInput
    levels: list  # MeshData per LOD
    reports: list  # dict per LOD
    seconds: float
