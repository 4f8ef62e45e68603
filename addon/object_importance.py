# SPDX-License-Identifier: GPL-3.0-or-later
"""The importance g in [0, 1] of an object's vertices under the settings' source: a
painted vertex group, the rig's skin weights (the paper's Sec. 5.3) or the shape keys'
motion (pure/importance.py says what each means), with the messages naming what is
missing; and the preview that writes it back as a vertex group.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from . import mesh_io
from . import vertex_groups
from .pure import importance as imp
from .pure import key_deviation
from .pure.settings import LodError, LodSettings
from .pure.wording import quoted_names
from .rig import deform_columns, skinned_columns


def skin_importance_of(obj, group_names, group_weights) -> np.ndarray:
    """The paper's (Sec. 5.3) importance g in [0, 1] from ``obj``'s deform-bone weights."""
    _, cols = skinned_columns(obj, group_names)
    return imp.skin_importance(np.asarray(group_weights)[:, cols])


def no_shape_keys(obj) -> str:
    """The message for Source Shape Keys on an object without any."""
    return (f'"{obj.name}" has no shape keys: add some (Object Data Properties > Shape Keys) '
            f'or choose another importance source')


def none_has_source(settings: LodSettings, names: list) -> str:
    """The message for an importance source that none of several objects has."""
    of = f"none of the {len(names)} objects ({quoted_names(names)})"
    source = settings.importance_source
    if source == 'SHAPE_KEYS':
        return (f"Source Shape Keys: {of} has shape keys: add some "
                f"(Object Data Properties > Shape Keys) or choose another importance source")
    if source == 'VERTEX_GROUP':
        return (f'Importance group "{settings.importance_group}": {of} has it: paint it '
                f"(Weight Paint mode) or choose another group")
    return (f"Source Armature: {of} is skinned (an Armature modifier or armature parent, and vertex "
            f"groups named after its deform bones): choose another importance source")


def missing_source(obj, settings: LodSettings, data) -> Optional[str]:
    """Why ``obj`` (its mesh read as ``data``, pure/mesh_data.MeshData) cannot give the
    settings' importance source, in the command line's words (headless/sources.py):
    'no vertex group "X"', 'not skinned' or 'no shape keys'; None when it can or the
    source is None. prepare() raises LodError for an object alone, and gives a part of
    several objects no importance and the note no_importance_note(reason)."""
    source = settings.importance_source
    if source == 'VERTEX_GROUP' and settings.importance_group \
            and settings.importance_group not in data.group_names:
        return f'no vertex group "{settings.importance_group}"'
    if source in ('ARMATURE', 'ARMATURE_PAPER') and not deform_columns(obj, data.group_names)[1]:
        return "not skinned"
    if source == 'SHAPE_KEYS' and not data.shape_keys:
        return "no shape keys"
    return None


def no_importance_note(reason: str) -> str:
    """The note of a part made without importance: missing_source's ``reason``."""
    return f"no importance ({reason})"


def shape_key_importance_of(obj) -> np.ndarray:
    """Importance g in [0, 1] per vertex of ``obj``'s own mesh (not the modifier result)
    from its shape keys (importance.shape_key_importance); LodError when it has none."""
    names = obj.vertex_groups.keys()
    weights = vertex_groups.read_weights(obj.data, names, all_names=names) if names else None
    basis_name, use_relative, keys = mesh_io.read_shape_keys(obj.data)
    if not keys:
        raise LodError(no_shape_keys(obj))
    return imp.shape_key_importance(key_deviation.key_offsets(keys, use_relative, names, weights, basis_name))


def importance_of(obj, settings, group_names, group_weights, key_offsets=None) -> Optional[np.ndarray]:
    """Importance g in [0, 1] per vertex from the settings' source, or None (no source);
    group_names and group_weights (n, g) are the mesh's vertex groups, ``key_offsets()``
    what its shape keys move each vertex by (key_deviation.key_offsets; only called for
    Source Shape Keys). LodError names what is missing."""
    if settings.importance_source == 'VERTEX_GROUP':
        name = settings.importance_group
        if not name:
            raise LodError("importance source is Vertex Group but no group is chosen")
        if name not in group_names:
            raise LodError(f'"{obj.name}" has no vertex group "{name}"')
        return np.asarray(group_weights)[:, list(group_names).index(name)]
    if settings.importance_source == 'ARMATURE_PAPER':
        return skin_importance_of(obj, group_names, group_weights)
    if settings.importance_source == 'SHAPE_KEYS':
        offsets = key_offsets() if key_offsets is not None else np.zeros((0, 0, 3))
        if len(offsets) == 0:
            raise LodError(no_shape_keys(obj))
        return imp.shape_key_importance(offsets)
    return None  # 'ARMATURE' acts through the sample poses (prepare), not through g


def importance_preview(obj, settings: LodSettings) -> tuple:
    """The effective importance of ``obj``'s vertices in [0, 1] (addon/pure/importance.py,
    ``effective``) under ``settings``, read from the object's own mesh (not the modifier
    result, so it can be written back as a vertex group), how many vertices count as
    painted (g >= 0.5), and the strength it is at (Source Shape Keys: scaled by the surface
    the keys leave still, importance.key_strength). Raises LodError when the settings name
    no importance."""
    if obj is None or getattr(obj, "type", None) != 'MESH':
        raise LodError("Make a mesh object active")
    if settings.importance_source == 'NONE':
        raise LodError("Importance source is None: choose a vertex group, the armature or the shape keys first")
    if settings.importance_source == 'ARMATURE':
        raise LodError("Source Armature works through sample poses of the rig, not a per-vertex importance: "
                       "there is nothing to preview (Armature (Paper) has one)")
    strength = settings.importance_strength
    if settings.importance_source == 'SHAPE_KEYS':
        g = shape_key_importance_of(obj)
        # As a run of the object alone scales it (lod.prepare): by the surface left still.
        strength = imp.key_strength(strength, *imp.still_share(g, mesh_io.positions(obj.data),
                                                               mesh_io.triangles(obj.data)[0]))
    else:
        names = obj.vertex_groups.keys()
        g = importance_of(obj, settings, names, vertex_groups.read_weights(obj.data, names, all_names=names))
    return imp.effective(g, strength), int(np.count_nonzero(g >= imp.PAINTED)), strength
