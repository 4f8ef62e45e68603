"""Line-quadric mesh simplification in pure NumPy.

Implements "Controlling Quadric Error Simplification with Line Quadrics" (Liu,
Rahimzadeh, Zordan, SGP 2025) as a vectorised edge-collapse engine. NumPy is the only
dependency; nothing here imports Blender, so the same code serves the add-on, the
command line, the tests and the benchmarks.

Public API:
    Options                     every option of a run, documented once (core/options.py)
    simplify(vertices, faces, target_faces=/ratio=, options=None, progress=None, **fields)
        -> SimplifyResult       (fields: any Options field, e.g. line_weight=0.01)
    simplify_chain(vertices, faces, targets, options=None, progress=None, **fields)
        -> list[SimplifyResult]
    triangle_quality(vertices, faces) -> (m,) quality in [0, 1]; SLIVER_QUALITY below it
        a triangle is a sliver (the default min_quality and every report's threshold)
    skin_line_weights(skin) -> (n,) the paper's Sec. 5.3 w_i from skinning weights
    skinning                    sample poses of a rig, pose offsets for the error, and
        LOD skin weights fitted to the poses (skinned characters, issue 19)
    budget                      one triangle budget for many parts (an asset), split
        by error: split_by_error(parts, targets) -> counts per level and part
    assembly                    many parts (an asset's meshes) in one run: combine(parts) ->
        one mesh and Options, split(result, layout) -> one result per part
    shading                     Blender's corner normals from smooth flags and sharp edges,
        and the geometry of comparing two meshes' shading normals
"""
from .result import (
    STOP_LIMIT,
    STOP_MAX_ERROR,
    STOP_REASON_TEXT,
    STOP_TARGET,
    STOP_TOPOLOGY,
    SimplifyCancelled,
    SimplifyResult,
    SimplifyStats,
)
from .options import DEFAULT_LINE_WEIGHT, Options
from .simplify import simplify, simplify_chain
from .metrics import SLIVER_QUALITY, triangle_quality, quality_summary
from .weights import skin_line_weights
from . import topology  # connectivity helpers the add-on and bench reuse (connected_labels)
from . import shading  # shading normals and their deviation (addon/pure/measure.py's normal_deviation)
from . import budget  # one triangle budget for many parts, split by error (addon/asset.py)
from . import assembly  # many parts in one run, and its results split back (addon/job.py)
from . import skinning  # posed error and fitted weights for skinned LODs (addon/rig.py, addon/pure/skin_fit.py)
from . import weld  # welding coincident vertices as a run does (addon/pure/edges.py's welded_faces)

__all__ = [
    "Options",
    "DEFAULT_LINE_WEIGHT",
    "SLIVER_QUALITY",
    "simplify",
    "simplify_chain",
    "SimplifyResult",
    "SimplifyStats",
    "SimplifyCancelled",
    "STOP_TARGET",
    "STOP_LIMIT",
    "STOP_MAX_ERROR",
    "STOP_TOPOLOGY",
    "STOP_REASON_TEXT",
    "triangle_quality",
    "quality_summary",
    "skin_line_weights",
    "topology",
    "shading",
    "skinning",
    "budget",
    "assembly",
]
