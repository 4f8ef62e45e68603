"""Every option of a simplification run, in one dataclass: its name, default and meaning.

``simplify`` and ``simplify_chain`` take an ``Options`` (``options=``) and/or the same
fields as keywords; core.prepare checks the values. Names follow the paper where it has
one: ``line_weight`` is its w, ``line_weights`` its per-vertex w_i (Eq. 16),
``quadric_scale`` the factor on the whole augmented quadric of Sec. 4.4.1 ("extreme
weights"), ``edge_weights`` its w_ij (Eq. 19).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any, Mapping, Optional, Sequence, Union

from .features import DEFAULT_FEATURE_ANGLE
from .metrics import SLIVER_QUALITY

# The paper's default line-quadric weight w (Sec. 4.2: "our default is w_i = 10^-3"):
# enough to regularise flat regions, too little to pull the shape.
DEFAULT_LINE_WEIGHT = 1e-3


@dataclass(frozen=True)
class Options:
    """How to simplify (everything but the mesh, the targets and the progress callback).

    Target:
      max_error: a distance in mesh units, or None: no collapse may take the LOD
        farther than this from the source, measured both ways at points of the surfaces
        (source vertices and points inside its faces to the LOD, points of the new faces
        to the source: core.tracked_distance); the run stops at the target or there,
        whichever comes first. For simplify_chain, one non-decreasing bound per target
        (each level goes on from the last under its own bound). Under a bound the
        quality rules relax only while the bound is not what holds the run back, and no
        part is removed (remove_small_components is ignored: a part removed is as far as
        can be). The area-sampled
        Hausdorff distance (addon/pure/measure.py) can come out somewhat above it, up to
        about 1.4x on the meshes measured: points between the tracked ones.
      vertex_max_error: (n,) distances in mesh units (inf where free), or None: painted
        limits, a local max_error; for simplify_chain also (targets, n), one row per
        level, not decreasing along the chain. The LOD stays within vertex_max_error[i] of the source
        around vertex i (tracked both ways as for max_error; a point inside a face takes
        the limit its corners' limits give through the barycentric mean of 1 / limit, so
        a painted weight w over a limit L, L / w, interpolates as w does). The count
        target is honoured elsewhere; where the limits make it unreachable the run stops
        above it with STOP_LIMIT. Rules relax as for a count target, and only parts with
        no finite limit may be removed. With max_error too, the smaller bound holds.

    Controls (paper Eq. 16 and Sec. 4.4):
      line_weight: w for every vertex (1e-3 by default; 0 gives plain Garland-Heckbert).
      line_weights: (n,) per-vertex w_i >= 0, replaces line_weight where given.
      quadric_scale: (n,) >= 1 or None, the extreme-weight variant (Sec. 4.4.1): vertex
        i's whole augmented quadric (planes + line quadric) is multiplied by
        quadric_scale_i, so flat regions are controllable too. Where it is above 1 the
        line weight is raised to at least SCALED_LINE_WEIGHT_FLOOR (core.vertex_quadrics),
        since scaling a zero error changes nothing.
      line_scale_exponent: > 0, the line quadric is multiplied by quadric_scale raised to
        this (1, the default, scales the whole augmented quadric as the paper does). A
        flat region's cost is its line quadric alone and grows more slowly with the size
        of a collapse than a curved region's plane error, so the same factor makes it
        denser; the add-on uses 0.75, which gives both the same density gain (measured:
        addon/pure/importance.py).
      boundary_weight: weight of the planes through open boundary edges (0 turns them off).
      locked: (n,) bool, vertices that never move and are never removed.
      feature_edges: (k, 2) vertex pairs kept softly by dihedral-plane quadrics (Eq. 18-19)
        weighted by ``feature_weight`` or by per-edge ``edge_weights`` (k,), the w_ij.
      feature_angle: degrees in [0, 180) (80 by default), or None/0 (off): interior edges
        whose faces' normals differ by more than this are creases, kept softly like
        ``feature_edges`` (weighted by ``feature_weight``); vertices where three or more
        creases or feature edges meet, and open-boundary vertices where the boundary
        turns by the angle, or by half of it beyond its neighbours' turns the same way
        (core.features.boundary_corners), are corners and stay put (unless the target
        cannot be reached otherwise, or they crowd a LOD and are smaller than its error:
        core.engine._release_small_corners).
      plane_placement: under a distance bound (max_error, or painted limits around their
        vertices), a merged vertex goes to the optimum of its pair's planes, with
        core.selection.PLANE_PLACEMENT_LINE_SHARE of its line quadrics to keep the solve
        conditioned, instead of the whole quadric's; the cost stays the whole quadric's
        there. Count targets ignore it (False by default; the deviation search runs it
        beside the controls, addon/pure/deviation_targets.alternatives). Where the planes
        leave a direction free (a flat cap, a straight wall) the line quadrics choose where
        a merge lands; on a bevelled cylinder at 0.05 % of its diagonal those merges held
        the LOD at 1,162 triangles, placed by the planes 1,044 (Decimate's count).
      min_quality: in [0, 1], the triangle quality (core.metrics.triangle_quality; 1 for
        equilateral) below which no collapse may turn a face (SLIVER_QUALITY = 0.3 by
        default, 0 turns the rule off): lower it for closer hard-surface shapes at the
        cost of slivers.
      remove_small_components: when no collapse is possible short of the target, delete
        whole parts, smallest area first (never the largest, never one with a locked
        vertex), instead of stopping above the target (True by default, as game LOD
        tools do: a bolt kept as a tetrahedron costs four triangles and looks like
        nothing; 500 bolts of 12 triangles hold a LOD at 2,000). False keeps every part
        (each closed one at four triangles or more).
      probabilistic_sigma: >= 0, the alternative regulariser the paper compares with
        (Trettner & Kobbelt 2020): the standard deviation of isotropic noise on the unit
        face normals (dimensionless; sigma^2 plays the part of w). 0 (default) leaves it
        off; combine with line_weight=0 to compare the two.
      seed: the same input and seed give bit-identical output.

    Carried data:
      vertex_attributes: {name: (n, k)} interpolated along each collapsed edge.
      normalize_attributes: names among vertex_attributes whose rows summed to one and must
        keep doing so (skin weights).
      corner_attributes: {name: (m, 3, k)} per face corner (UVs, corner colours); an edge
        across which one of them is discontinuous is a seam, kept when preserve_seams.
      uv_attributes: names among corner_attributes (k = 2) whose triangles must not flip.
      seamless_attributes: names among corner_attributes whose splits are no seams:
        carried through collapses like the rest (each side of a split keeps its values)
        but never holding a collapse back. For custom normals, whose splits are hard
        edges (give those as feature_edges to keep their shape): as seams, the hard edges
        of a faceted low-poly mesh lock nearly every vertex (a character: 512 of its 808
        inner edges), and its LODs keep their triangles where they would do least.
      shape_attributes: names among vertex_attributes (k = 3) that are shape-key offsets
        (mesh units): the LOD is kept close at each key's full value too, not only at rest
        (the strongest 16 count; core.shape_keys).
      pose_offsets: (P, n, 3) or None, offsets (mesh units) of every vertex in P sample
        poses of its rig (core.skinning.pose_offsets): like shape keys, the LOD is kept
        close in each pose too, only in the error (nothing is carried to the result).
      pose_weight: >= 0, what the poses' mean error counts against the rest error (1 =
        alike; 0 leaves the poses out).
      key_scale_exponent: >= 0, the shape keys' planes of vertex i (not the poses') are
        multiplied by quadric_scale_i raised to this: 1 (the default) scales them as the
        rest planes; above 1 a key's error counts more than the rest where the importance
        is (Source Shape Keys: the keys are what matters there).
      weld_distance: weld vertices closer than this before simplifying (split vertices of
        exported assets); None welds only exactly coincident ones, a negative value none.
      stitch_cracks: close T-junction cracks before simplifying (core.stitching): a
        border vertex on another border's edge (within 1 % of the edge's length and 0.1 %
        of the mesh's size) is inserted into that edge, so the two sides of a seam that an
        exporter tessellated apart share their edges. The faces this splits come back
        with the face_origin of the face they split.

    Several parts in one run (an asset's meshes, core.assembly):
      vertex_part: (n,) int >= 0, or None (one part): the part each vertex belongs to.
        Vertices of different parts are never welded, so every output face lies in one
        part and the result splits back into the parts.
      part_copies: (parts,) int >= 1, or None (1 each): how many times each part is drawn
        (a mesh instanced by several objects). Targets then count drawn triangles: a face
        of part j counts part_copies[j] times, so one budget holds for the whole asset.
    """

    max_error: Union[float, Sequence[float], None] = None
    vertex_max_error: Any = None
    line_weight: float = DEFAULT_LINE_WEIGHT
    line_weights: Any = None
    quadric_scale: Any = None
    line_scale_exponent: float = 1.0
    boundary_weight: float = 1.0
    locked: Any = None
    seed: int = 0
    vertex_attributes: Optional[Mapping[str, Any]] = None
    normalize_attributes: Sequence[str] = ()
    corner_attributes: Optional[Mapping[str, Any]] = None
    uv_attributes: Sequence[str] = ()
    seamless_attributes: Sequence[str] = ()
    preserve_seams: bool = True
    feature_edges: Any = None
    feature_weight: float = 1.0
    edge_weights: Any = None
    weld_distance: Optional[float] = None
    stitch_cracks: bool = True
    probabilistic_sigma: float = 0.0
    feature_angle: Optional[float] = DEFAULT_FEATURE_ANGLE
    min_quality: float = SLIVER_QUALITY
    plane_placement: bool = False
    remove_small_components: bool = True
    shape_attributes: Sequence[str] = ()
    pose_offsets: Any = None
    pose_weight: float = 1.0
    key_scale_exponent: float = 1.0
    vertex_part: Any = None
    part_copies: Any = None

    @classmethod
    def names(cls) -> tuple:
        return tuple(f.name for f in dataclasses.fields(cls))

    @classmethod
    def of(cls, options: Optional["Options"] = None, **values) -> "Options":
        """``options`` (default: all defaults) with ``values`` replacing fields; ValueError
        naming any keyword that is not an option (a typo would otherwise be ignored)."""
        if options is not None and not isinstance(options, cls):
            raise ValueError(f"options must be a core.Options, got {type(options).__name__}")
        unknown = set(values) - set(cls.names())
        if unknown:
            raise ValueError(f"unknown option(s): {', '.join(sorted(unknown))}")
        return dataclasses.replace(options if options is not None else cls(), **values)
