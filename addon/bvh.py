# SPDX-License-Identifier: GPL-3.0-or-later
"""Closest-point trees of triangle meshes from Blender's ``mathutils`` (BVHTree): what the
deviation measurement (measure.py) queries, handed to it by the add-on's package on import.

``mathutils`` is imported when a tree is built, so importing this module needs no Blender;
measuring does.
"""
from __future__ import annotations

import numpy as np


def build_tree(vertices: np.ndarray, faces: np.ndarray):
    """A BVHTree of the triangles ``faces`` (m, 3) over ``vertices`` (n, 3)."""
    from mathutils.bvhtree import BVHTree

    return BVHTree.FromPolygons(vertices.tolist(), faces.tolist(), all_triangles=True)
