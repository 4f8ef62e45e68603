# SPDX-License-Identifier: GPL-3.0-or-later
"""Reading the rig: the armature deforming an object, which of its vertex groups are the
deform bones' (the skin), the bones' rest matrices, and core.skinning's random sample
poses of the armature in the mesh's own coordinates (Source Armature).

The scene's pose is never read or touched: the poses are made from the rest matrices.
"""
from __future__ import annotations

import numpy as np

from .pure._core import core
from .pure.settings import LodError


def armature_of(obj):
    """The armature object deforming ``obj`` (Armature modifier, else armature parent)."""
    for md in obj.modifiers:
        if md.type == 'ARMATURE' and md.object is not None and md.object.type == 'ARMATURE':
            return md.object
    if obj.parent is not None and obj.parent.type == 'ARMATURE' and obj.parent_type == 'ARMATURE':
        return obj.parent
    return None


def deform_columns(obj, group_names) -> tuple:
    """(armature, column indices of the groups named after its deform bones) or (None, [])."""
    arm = armature_of(obj)
    if arm is None:
        return None, []
    deform = {b.name for b in arm.data.bones if b.use_deform}
    return arm, [i for i, name in enumerate(group_names) if name in deform]


def skinned_columns(obj, group_names) -> tuple:
    """(armature, columns of the groups named after its deform bones); LodError naming
    what is missing when ``obj`` is not skinned."""
    arm = armature_of(obj)
    if arm is None:
        raise LodError(f'"{obj.name}" is not skinned: it has no Armature modifier or armature parent')
    if not any(b.use_deform for b in arm.data.bones):
        raise LodError(f'armature "{arm.name}" has no deform bones')
    _, cols = deform_columns(obj, group_names)
    if not cols:
        raise LodError(
            f'"{obj.name}" has no vertex groups named after the deform bones of "{arm.name}": '
            f'weight it first (e.g. Parent > With Automatic Weights)')
    return arm, cols


def rig_arrays(obj, arm) -> tuple:
    """(bone names, rest matrices (B, 4, 4) in armature space, parent indices (B,),
    the matrix taking ``obj``'s coordinates into ``arm``'s) for core.skinning."""
    bones = list(arm.data.bones)
    names = [b.name for b in bones]
    rest = np.array([np.array(b.matrix_local, dtype=np.float64) for b in bones])
    parents = np.array([names.index(b.parent.name) if b.parent is not None else -1 for b in bones])
    to_armature = np.linalg.inv(np.array(arm.matrix_world, dtype=np.float64)) @ np.array(obj.matrix_world,
                                                                                     dtype=np.float64)
    return names, rest, parents, to_armature


def sample_poses(obj, group_names, count: int = core.skinning.SAMPLE_POSES, seed: int = 0) -> np.ndarray:
    """(count, B, 4, 4) deform matrices of core.skinning's random sample poses of
    ``obj``'s armature, in the mesh's own coordinates, one per deform-bone group in the
    order of ``deform_columns``. Made from the bones' rest matrices: the scene's pose is
    not read or touched. The first SAMPLE_POSES are the same whatever ``count``."""
    arm, cols = skinned_columns(obj, group_names)
    names, rest, parents, to_armature = rig_arrays(obj, arm)
    poses = core.skinning.change_of_space(core.skinning.random_poses(rest, parents, count=count, seed=seed),
                                          to_armature)
    return poses[:, [names.index(group_names[c]) for c in cols]]
