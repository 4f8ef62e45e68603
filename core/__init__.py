"""Line-quadric mesh simplification in pure NumPy.

Implements "Controlling Quadric Error Simplification with Line Quadrics" (Liu,
Rahimzadeh, Zordan, SGP 2025) as a vectorised edge-collapse engine. NumPy is the only
dependency; nothing here imports Blender, so the same code serves the add-on, the
command line, the tests and the benchmarks.

Public API:
    simplify(vertices, faces, **options) -> SimplifyResult
    simplify_chain(vertices, faces, targets, **options) -> list[SimplifyResult]
    triangle_quality(vertices, faces) -> (m,) quality in [0, 1]
"""
from .result import (
    STOP_MAX_ERROR,
    STOP_REASON_TEXT,
    STOP_TARGET,
    STOP_TOPOLOGY,
    SimplifyCancelled,
    SimplifyResult,
    SimplifyStats,
)
from .simplify import simplify, simplify_chain
from .metrics import triangle_quality, quality_summary
from .weights import importance_from_skin_weights
from . import topology  # connectivity helpers the add-on and bench reuse (connected_labels)

__all__ = [
    "simplify",
    "simplify_chain",
    "SimplifyResult",
    "SimplifyStats",
    "SimplifyCancelled",
    "STOP_TARGET",
    "STOP_MAX_ERROR",
    "STOP_TOPOLOGY",
    "STOP_REASON_TEXT",
    "triangle_quality",
    "quality_summary",
    "importance_from_skin_weights",
    "topology",
]
