"""The collapse rules in one place: which rule, its threshold, and whether it may relax.

A collapse is applied only if every rule below holds for it (core.validation checks
them; core.selection and core.engine apply the ones about which edges may collapse at
all). Two families:

- Topology rules never relax: they are what "manifold in, manifold out" means, and
  breaking one corrupts the mesh rather than making it uglier.
- Quality rules keep the output pleasant (no slivers, no sharp turns, seams and UVs
  intact). They are what stops a run above a low target (a 360-triangle UV sphere
  asked for 36), so when no collapse passes them the engine relaxes them one step of
  ``RELAXATION_LADDER`` at a time, for the remaining collapses only, and resumes. Only
  when the loosest step finds nothing either does the run stop, and then the topology
  itself forbids the target (``STOP_TOPOLOGY``).

The table is data so that a newcomer can read the rules at a glance; the code that
enforces each rule names it in a comment. Which vertex may merge into which, and where
the merged vertex goes, is a table the selection reads: core.kinds (cf. meshoptimizer's
``kCanCollapse``), which also lists how each fault of exported meshes is handled.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

# Triangle quality (4 sqrt(3) area / sum of squared edges) below which a face counts as
# a sliver: the default of ``min_quality`` and the threshold of every report.
from .metrics import SLIVER_QUALITY  # noqa: E402  (defined once, beside the quality metric)

# A face that already is a sliver may lose up to this share of its quality, or the
# input's slivers would freeze their whole neighbourhood; and a face an open border
# forces thin may be as thin as this share of the worst input sliver merged into it.
SLIVER_SLACK = 0.5


@dataclass(frozen=True)
class Rule:
    name: str
    what: str
    relaxes: bool


RULES = (
    # Topology: never relaxed.
    Rule("manifold_edges", "edges with three or more faces never collapse", False),
    Rule("locked_vertices", "locked, pinched and non-manifold vertices never move (core.kinds: "
                            "LOCKED and COMPLEX; the collapse table by vertex kind)", False),
    Rule("boundaries_stay", "an inner edge joining two border vertices never collapses", False),
    Rule("link_condition", "the ends share exactly the neighbours opposite the edge", False),
    Rule("no_fold_onto_opposite_edge", "no two faces end up on the same three vertices", False),
    Rule("no_bare_vertex", "no vertex loses its last face, so no part disappears", False),
    Rule("no_degenerate_face", "no face collapses to zero area", False),
    Rule("no_turn_over", "no face turns more than 90 degrees, faces away from its input "
                         "face, or faces against a nearly flat ring", False),
    # Quality: relaxed step by step, in RELAXATION_LADDER's order.
    Rule("normal_turn", "no face turns by more than arccos(min_normal_cosine)", True),
    Rule("sliver", "no face becomes a sliver (quality below min_quality), but where its "
                   "three corners lie on open borders, and while a sliver-rich input's LOD has "
                   "fewer slivers than the input's share (core.slivers)", True),
    Rule("seams", "seam vertices (whose own corner values change, core.wedges.value_changes) slide "
                  "only along their seam; seam ends and junctions stay put (a UV pole's web of seams "
                  "is none: core.uv_poles)", True),
    Rule("feature_corners", "corners where three creases meet, and sharp turns of an open "
                            "boundary, stay put (feature_angle), but those that crowd a LOD "
                            "and are smaller than its error (core.engine._release_small_corners)", True),
    Rule("uv_area", "no UV triangle shrinks below min_uv_area_kept of its area", True),
    Rule("uv_flip", "no UV triangle flips", True),
    # Topology that changes but stays manifold: relaxed after every quality rule
    # (core.engine._unstick), before the smallest parts go.
    Rule("small_holes_stay", "a hole of three border edges stays open; once nothing else can reach the "
                             "target, collapsing one of its edges closes it (core.validation, as Decimate "
                             "does)", True),
)


@dataclass(frozen=True)
class Thresholds:
    """The quality rules' settings at one step of the ladder.

    min_normal_cosine: a face's new normal . old normal must be at least this (unit
      normals); 0 allows any turn short of turning over (which is a topology rule).
    min_quality: a face may not become a sliver below this quality (one that already is
      one may lose at most half its quality, and one with its three corners on open
      borders may go as low as half the worst input sliver merged into them); 0 turns the
      rule off.
    seams: "kept" (seam ends and junctions locked, seam vertices slide along the seam),
      "slide" (ends and junctions slide along a seam edge too) or "free" (collapses may
      cross seams; the far side keeps its corner values).
    min_uv_area_kept: share of its UV area a UV triangle must keep (0 = off).
    uv_flip: whether UV triangles may not flip.
    corners_kept: whether feature corners (core.features) stay put.
    """

    step: int
    min_normal_cosine: float
    min_quality: float
    seams: str
    min_uv_area_kept: float
    uv_flip: bool
    corners_kept: bool = True


def relaxation_ladder(min_quality: float = SLIVER_QUALITY) -> tuple:
    """The steps the quality rules go through when a run is stuck, strictest first.

    Ordered by what an artist notices least: first let faces turn further and accept
    thinner triangles (what a low LOD needs on a curved cap), then let seam ends slide
    along their seams (the UV layout keeps its islands), then drop the sliver and UV-area
    floors, and last let collapses cross seams, UVs flip and feature corners move (the
    texture distorts and a box loses its corners, but a 36-triangle LOD is seen from far
    away, and eight kept corners would hold a box at twelve triangles). Each step keeps
    the previous ones' relaxations.
    """
    strict = Thresholds(0, min_normal_cosine=0.2, min_quality=min_quality, seams="kept",
                        min_uv_area_kept=0.05, uv_flip=True)
    turns = replace(strict, step=1, min_normal_cosine=0.0, min_quality=0.5 * min_quality)
    ends = replace(turns, step=2, seams="slide")
    floors = replace(ends, step=3, min_quality=0.0, min_uv_area_kept=0.0)
    anything = replace(floors, step=4, seams="free", uv_flip=False, corners_kept=False)
    return (strict, turns, ends, floors, anything)
