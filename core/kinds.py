"""Vertex kinds and the collapse table: which vertex may merge into which, along which
edges, and where the merged vertex goes.

As in meshoptimizer's simplifier (Kapoulkine, ``kCanCollapse`` and ``kHasOpposite`` in
src/simplifier.cpp), every vertex gets one kind per pass (core.engine._classify) and the
candidate edges (core.selection) are whatever this table allows between the kinds of
their two ends. The more constrained end survives (``RANK``; on a tie, the edge's first
end), so only the upper triangle of the table is ever read.

Kinds, least constrained first:
  FREE     an interior vertex of a manifold surface
  BORDER   on an open boundary: free, but an inner edge joining two border vertices
           never collapses (``EDGE_RULES``), or the boundary would pinch
  SEAM     on a UV or colour seam (its own value changes across two of its edges,
           core.wedges.value_changes): slides only along its seam (rule seams, core.guards)
  COMPLEX  pinched between fans, or on an edge of three or more faces: it holds parts of
           the surface together that an edge collapse cannot keep apart, so it never
           moves; free vertices may merge into it
  LOCKED   locked by the artist, a feature corner, or a seam's end or junction (its
           value changes across one, or three or more, of its edges): never moves
"""
from __future__ import annotations

import numpy as np

FREE, BORDER, SEAM, COMPLEX, LOCKED = 0, 1, 2, 3, 4
NAMES = ("free", "border", "seam", "complex", "locked")

# Which end survives: the higher rank. Border vertices rank with free ones (the boundary
# is kept by its planes, core.vertex_quadrics, and EDGE_RULES, not by the direction of
# the collapse); complex and locked vertices never move, so they always survive.
RANK = np.array([0, 0, 1, 2, 2], dtype=np.int8)

# CAN_COLLAPSE[remove kind, keep kind]: may ``remove`` merge into ``keep``, and along
# which edges.
ANY, ALONG_SEAM, NEVER = 0, 1, 2
CAN_COLLAPSE = np.array([
    # into: FREE   BORDER  SEAM        COMPLEX     LOCKED
    [ANY,   ANY,   ANY,        ANY,        ANY],         # FREE
    [ANY,   ANY,   ANY,        ANY,        ANY],         # BORDER
    [NEVER, NEVER, ALONG_SEAM, ALONG_SEAM, ALONG_SEAM],  # SEAM: only along its seam
    [NEVER, NEVER, NEVER,      NEVER,      NEVER],       # COMPLEX: never moves
    [NEVER, NEVER, NEVER,      NEVER,      NEVER],       # LOCKED: never moves
], dtype=np.int8)

# PLACE[remove kind, keep kind]: where the merged vertex goes. OPTIMAL is the quadric's
# optimum; under a distance bound, an end of the edge instead where that end keeps every
# plane of the pair's faces and the optimum does not (core.selection.exact_end).
OPTIMAL, AT_KEEP, ON_SEAM = 0, 1, 2
PLACE = np.array([
    # into: FREE     BORDER   SEAM     COMPLEX  LOCKED
    [OPTIMAL, OPTIMAL, AT_KEEP, AT_KEEP, AT_KEEP],  # FREE: a seam vertex does not leave its seam
    [OPTIMAL, OPTIMAL, AT_KEEP, AT_KEEP, AT_KEEP],  # BORDER
    [AT_KEEP, AT_KEEP, ON_SEAM, AT_KEEP, AT_KEEP],  # SEAM: the best point of the seam edge
    [AT_KEEP, AT_KEEP, AT_KEEP, AT_KEEP, AT_KEEP],  # (never collapses)
    [AT_KEEP, AT_KEEP, AT_KEEP, AT_KEEP, AT_KEEP],  # (never collapses)
], dtype=np.int8)

# Rules by edge, whatever the kinds of its ends (each is a row of core.guards.RULES).
EDGE_RULES = (
    ("manifold_edges", "an edge of three or more faces never collapses"),
    ("boundaries_stay", "an inner edge (two faces) joining two border vertices never collapses"),
)

# What exporters write and where it is handled: the faults of issue 33, one row each
# (docs/method.md, "What exporters write", has the measurements).
FAULTS = (
    ("coincident vertices", "core.prepare", "welded (exactly coincident by default, weld_distance for more)"),
    ("repeated-corner face", "core.prepare", "dropped: it has no area"),
    ("zero-area face", "core.prepare", "dropped: corners on one line to float32 precision (quality < 1e-6)"),
    ("duplicate face", "core.prepare", "one copy kept; of copies wound both ways, the one wound like its "
                                       "neighbours"),
    ("T-junction crack", "core.stitching", "the border vertex on the other side's border edge splits it "
                                           "(moved onto the edge where the split would turn a thin face "
                                           "over): the slit becomes an inner seam"),
    ("inconsistent winding", "core.orientation", "each part wound like most of its area for the run, and the "
                                                 "LOD's faces turned back as their input faces were"),
    ("edge of three or more faces", "core.kinds", "its vertices are COMPLEX: they stay, the surfaces around "
                                                  "them simplify"),
    ("pinched vertex", "core.kinds", "COMPLEX, as above"),
    ("sliver-rich tessellation", "core.slivers", "the LOD may have the input's share of slivers (5 % or more "
                                                 "of its faces; in an asset, of each part's own)"),
    ("UV changing at one end of a seam edge", "core.wedges", "the other end (a fan pole's ring, a cut's tip) "
                                                             "has one UV: no seam vertex, it moves freely"),
    ("a subdivided UV pole's seams", "core.uv_poles", "the web of seams around a vertex where six or more "
                                                      "start, fading out within the island: no seams but at "
                                                      "the pole"),
    ("normals split at every hard edge", "core.engine", "custom normals are Options.seamless_attributes: "
                                                        "carried, each side its own, but no seams"),
    ("small holes (cracks, pin holes)", "core.validation", "a hole shrinks to three border edges and stays "
                                                            "open while the target allows; then one of them "
                                                            "collapses and closes it (rule small_holes_stay)"),
    ("tiny separate parts", "core.components", "each shrinks to its smallest; below that the smallest parts go "
                                               "whole (remove_small_components, on by default)"),
)


def allowed(k_remove: np.ndarray, k_keep: np.ndarray, seam_edge: np.ndarray) -> np.ndarray:
    """(k,) bool: may each ``remove`` merge into its ``keep`` along its edge, by the table."""
    rule = CAN_COLLAPSE[k_remove, k_keep]
    return (rule == ANY) | ((rule == ALONG_SEAM) & seam_edge)
