# SPDX-License-Identifier: GPL-3.0-or-later
"""The core.Options a LOD run asks for: the settings table's own fields (each row whose
``core=`` is a CoreOption sets its field: core_options_of), and what the mesh brings
(mesh_options): its attributes for the core to carry, the edges to keep (the Preserve
rows), and the importance or the rig's sample poses.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from ._core import core
from . import edges as edge_util
from . import importance as imp
from .mesh_data import MeshData, interpolated
from .settings import PRESERVE_PAIRS, SETTINGS, CoreOption

# The Preserve switch each strength belongs to (a CoreOption's ``off`` applies while it is off).
SWITCH_OF = {strength: switch for switch, strength in PRESERVE_PAIRS}


def core_options_of(settings) -> core.Options:
    """core.Options with the field of every setting whose ``core=`` is a CoreOption set
    from ``settings`` (a LodSettings), the rest at the core's defaults."""
    fields = {}
    for s in SETTINGS:
        if not isinstance(s.core, CoreOption):
            continue
        switch = SWITCH_OF.get(s.name)
        if switch is not None and not getattr(settings, switch):
            fields[s.core.field] = s.core.off
        else:
            fields[s.core.field] = s.core.convert(getattr(settings, s.name))
    return core.Options.of(**fields)


def interpolated_attributes(data: MeshData) -> dict:
    """{"attr<i>": data.attributes[i]} of the generic attributes the core interpolates
    along its collapses (mesh_data.ATTRIBUTE_TYPES): those on points and corners of a
    float type with finite values (a NaN would fail the core's checks; such a layer is
    carried as ids are, rebuild.carried_attribute)."""
    return {f"attr{i}": layer for i, layer in enumerate(data.attributes)
            if layer.domain in ('POINT', 'CORNER') and interpolated(layer) and np.isfinite(layer.data).all()}


def mesh_options(settings, data: MeshData, skin_columns: list, g: Optional[np.ndarray] = None,
                 poses: Optional[np.ndarray] = None) -> tuple:
    """(core.Options, names) of a run on the mesh ``data``: core_options_of(settings), and
    the attributes the core carries (names: the attribute keys given to the core -> what
    they stand for: "skin" and "groups" -> columns of data.group_weights), the Preserve
    rows' feature edges, the importance ``g`` (importance.controls) and the rig's sample
    ``poses`` (the pose offsets of the skin: ``skin_columns``, the columns of the groups
    named after the deform bones)."""
    names = {}
    vattr, cattr, normalize, uvs = {}, {}, [], []
    weights = data.group_weights
    if data.group_names:
        other_cols = [i for i in range(len(data.group_names)) if i not in set(skin_columns)]
        if skin_columns:
            skin = weights[:, skin_columns]
            vattr["skin"] = skin
            names["skin"] = skin_columns
            # Renormalised only when the artist's weights were normalised to begin with.
            if np.allclose(skin.sum(axis=1), 1.0, atol=1e-3):
                normalize.append("skin")
        if other_cols:
            vattr["groups"] = weights[:, other_cols]
            names["groups"] = other_cols
    seamless = []  # corner attributes carried without making seams (core Options.seamless_attributes)
    # Corner values are judged on the triangles as the core welds them: an exported mesh's
    # copies along its seams and hard edges make no triangle pairs until then, so a UV
    # island or a colour per face of a glTF import was never seen as faceted.
    welded = edge_util.welded_faces(data.vertices, data.faces)
    for i, layer in enumerate(data.colors):
        key = f"color{i}"
        (vattr if layer.domain == 'POINT' else cattr)[key] = layer.data
        if layer.domain != 'POINT' and edge_util.faceted(welded, layer.data):
            # A colour per facet: as seams its jumps made every vertex a junction, locked,
            # and in an asset six such gems kept all 320 of their triangles at LOD1 while
            # a rounded cube beside them went from 3,072 to 576 (to 4 at LOD2). Carried
            # like the custom normals below: each side keeps its own colours.
            seamless.append(key)
    for key, layer in interpolated_attributes(data).items():
        if layer.domain == 'POINT':
            vattr[key] = layer.data
        else:  # an artist's data, not a seam to keep: carried as custom normals are
            cattr[key] = layer.data
            seamless.append(key)
    for i, sk in enumerate(data.shape_keys):
        vattr[f"shape{i}"] = sk.offsets
    for i, (uv_name, corners) in enumerate(data.uv_maps.items()):
        cattr[f"uv{i}"] = corners
        uvs.append(f"uv{i}")
        if edge_util.faceted(welded, corners):
            seamless.append(f"uv{i}")  # each face its own island (Lightmap Pack): as a colour per facet
    if data.custom_normals is not None:
        # Carried like any corner attribute: a corner keeps (or interpolates) its source
        # corners' normals, and a hard edge, where the normals differ, stays a split. But
        # no seam (core Options.seamless_attributes): an exporter's hard edges are
        # everywhere on a faceted low-poly mesh and would lock nearly every vertex.
        cattr["normal"] = data.custom_normals
        seamless.append("normal")

    feature_sets = []
    # Sharp marks on most edges say "shaded flat", not where the creases are (the OBJ and
    # FBX importers mark every edge of a flat-shaded mesh but those between coplanar
    # faces): as features they held a dense part's every collapse back. In an asset of a
    # subdivided cube and ten UV spheres so exported the cube kept 2,076 triangles at LOD3
    # where 1,114 met the same error as the spheres, the asset's distance 3.3x the
    # .blend's; a flat-shaded monkey through FBX (97 % of its edges marked) measured
    # 0.341 / 0.570 / 1.240 % against the .blend's 0.098 / 0.124 / 0.308 %. Like a colour
    # per facet (edges.faceted), marks on more than half the edges are no features. The
    # creases are the planes' and the feature corners' to keep; the marks are still
    # written on the LODs.
    if settings.preserve_sharp and not data.sharp_for_shading:
        feature_sets.append((data.sharp_edges, settings.sharp_strength))
    if settings.preserve_seams:
        feature_sets.append((data.seam_edges, settings.seam_strength))
    if settings.preserve_materials:
        feature_sets.append((edge_util.differing_edges(data.faces, data.material_index), settings.material_strength))
    feature_edges, edge_weights = edge_util.merge_weighted_edges(feature_sets)

    options = core.Options.of(
        core_options_of(settings),
        # Shape keys count in the error too: the LOD stays close at each key's full value.
        shape_attributes=tuple(f"shape{i}" for i in range(len(data.shape_keys))),
        vertex_attributes=vattr,
        normalize_attributes=tuple(normalize),
        corner_attributes=cattr,
        uv_attributes=tuple(uvs),
        seamless_attributes=tuple(seamless),
    )
    if len(feature_edges):
        options = core.Options.of(options, feature_edges=feature_edges, edge_weights=edge_weights)
    if g is not None:
        options = core.Options.of(options, **imp.controls(g, settings.line_weight, settings.importance_strength,
                                                          keys=settings.importance_source == 'SHAPE_KEYS'))
    if poses is not None:
        options = core.Options.of(options, pose_weight=imp.pose_weight(settings.importance_strength),
                                  pose_offsets=core.skinning.pose_offsets(data.vertices, vattr["skin"], poses))
    return options, names
