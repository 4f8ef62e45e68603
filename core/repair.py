"""Step 0b: the faults of exported tessellations, repaired for the run.

core.prepare has checked the arguments, normalised the positions, welded coincident
vertices and dropped the faces nothing can use (degenerate, zero-area, duplicate). What
is left can still carry two faults that an edge collapse engine cannot work around:

1. T-junction cracks (core.stitching): the seam between two faces of a CAD solid
   tessellated on each side alone is a slit of two border chains; stitched, it is an
   inner seam like any other.
2. Inconsistent winding (core.orientation): parts of a surface written the other way
   round; turned for the run, every part is wound one way.

Both keep the way back: ``Problem.face_source`` maps the run's face ids (what the engine
calls face_origin) to the input face each descends from, ``Problem.flipped_origin`` says
which run faces to turn back, and ``engine._snapshot`` applies both, so every LOD face
has the winding and the origin of its input face. Of a face the input has twice, once
each way, the copy wound like its neighbours is the one the LOD keeps. The repairs build
the mesh's connectivity once and hand it to the engine (``Problem.connectivity``).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from . import orientation, stitching, topology
from .geometry import rows


def repaired(p, twin=None, stitch: bool = True):
    """The Problem ``p`` with its cracks stitched and its winding made consistent.

    twin: (input faces,) for each input face the first copy of its corners wound the
    other way, or -1 (core.prepare._first_copies), or None. p.face_origin must hold
    input face ids (run_faces == input_faces): this runs once, right after prepare."""
    n = len(p.vertices)
    if len(p.faces) == 0:
        return p
    conn = topology.build(p.faces, n)
    if stitch:
        stitched = stitching.stitch(p.vertices, p.faces, conn, fixed=p.locked)
        if stitched is not None:
            *split, conn, vertices = stitched
            p = _with_splits(p, *split)
            p = _moved(p, vertices)
    flip = orientation.faces_to_flip(p.vertices, p.faces, conn)
    if flip.any():
        p = _turned(p, flip, twin)
        conn = None  # built on the faces before turning: its half-edges are off
    return dataclasses.replace(p, connectivity=conn)


def _with_splits(p, faces, parent, split_rows, weights):
    """``p`` on the stitched faces: each a new run face id, numbered in the input's order
    (by the input face it descends from, then by its place in the split), so that the
    engine's input-order output (core.locality) still holds."""
    source = p.face_origin[parent]
    order = np.lexsort((np.arange(len(parent)), source))
    run_id = np.empty(len(parent), dtype=np.int64)
    run_id[order] = np.arange(len(parent))
    face_source = np.empty(len(parent), dtype=np.int64)
    face_source[run_id] = source
    corner_attributes = {}
    for name, values in p.corner_attributes.items():
        values = values[parent]
        values[split_rows] = np.einsum("fij,fjk->fik", weights, values[split_rows])  # the split faces' corners
        corner_attributes[name] = values
    return dataclasses.replace(p, faces=faces, face_origin=run_id, face_source=face_source,
                               unsplit_faces=rows(p.faces, parent), run_faces=len(parent),
                               corner_attributes=corner_attributes)


def _moved(p, vertices):
    """``p`` with its vertices at ``vertices`` (normalised units), those that moved given
    back in input units too (a point stitching put onto the edge it went into)."""
    moved = np.flatnonzero(np.any(vertices != p.vertices, axis=1))
    if len(moved) == 0:
        return p
    input_positions = p.input_positions.copy()
    input_positions[moved] = vertices[moved] * p.scale + p.center
    return dataclasses.replace(p, vertices=vertices, input_positions=input_positions)


def _turned(p, flip, twin):
    """``p`` with the faces ``flip`` (m,) bool turned over, and the way back recorded."""
    faces = p.faces.copy()
    faces[flip] = faces[flip][:, [0, 2, 1]]
    unsplit = None
    if p.unsplit_faces is not None:
        unsplit = p.unsplit_faces.copy()
        unsplit[flip] = unsplit[flip][:, [0, 2, 1]]
    corner_attributes = {k: _swap_corners(a, flip) for k, a in p.corner_attributes.items()}
    flipped_origin = np.zeros(p.run_faces, dtype=bool)
    flipped_origin[p.face_origin[flip]] = True
    face_source = p.face_source
    # A turned face whose input also has it wound the run's way descends from that copy
    # and keeps the run's winding.
    if twin is not None:
        input_id = p.face_origin if face_source is None else face_source[p.face_origin]
        other = twin[input_id[flip]]
        has_twin = other >= 0
        if has_twin.any():
            turned = p.face_origin[np.flatnonzero(flip)[has_twin]]
            flipped_origin[turned] = False
            face_source = np.arange(p.run_faces) if face_source is None else face_source.copy()
            face_source[turned] = other[has_twin]
    return dataclasses.replace(p, faces=faces, unsplit_faces=unsplit, corner_attributes=corner_attributes,
                               flipped_origin=flipped_origin, face_source=face_source)


def _swap_corners(values: np.ndarray, flip: np.ndarray) -> np.ndarray:
    """Corner values (m, 3, k) with corners 1 and 2 swapped on the faces ``flip``: a face
    turned over as (a, c, b) keeps each value on its vertex."""
    values = values.copy()
    values[flip] = values[flip][:, [0, 2, 1]]
    return values
