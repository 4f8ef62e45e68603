"""Result and error types of :func:`core.simplify`."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

# Why a run stopped (``SimplifyStats.stop_reason``).
STOP_TARGET = "target_reached"
STOP_MAX_ERROR = "max_error_reached"
# No collapse is possible even with every quality rule relaxed and the small holes free
# to close (core.guards): closed parts, non-manifold edges, locked vertices and faces
# that would turn away from their input faces allow no fewer triangles.
STOP_TOPOLOGY = "topology_limit"
# The painted limits (Options.vertex_max_error) hold back every collapse the target still
# needs, with every quality rule relaxed and every part that may go removed.
STOP_LIMIT = "limit_reached"

# The stop reasons in words, for reports to artists.
STOP_REASON_TEXT = {
    STOP_TARGET: "target reached",
    STOP_MAX_ERROR: "the maximum error allows no further collapse",
    STOP_LIMIT: "the painted limits allow no further collapse where the region must stay close",
    STOP_TOPOLOGY: ("the mesh's topology allows no fewer triangles (each closed part needs at "
                    "least four, each open one at least one; non-manifold edges, locked vertices "
                    "and separate parts keep theirs, and no face may turn away from the surface "
                    "it stands for)"),
}


class SimplifyCancelled(Exception):
    """Raised when the ``progress`` callback returns False. Nothing partial is returned."""


@dataclass
class SimplifyStats:
    """Counts and timings of one run (one LOD level)."""

    input_vertices: int
    input_faces: int
    output_vertices: int
    output_faces: int
    target_faces: int
    passes: int
    seconds: float
    stop_reason: str
    max_error: float = 0.0  # with max_error given: the tracked distance bound reached; else the largest RMS quadric distance of an accepted collapse (mesh units)
    welded_vertices: int = 0  # coincident input vertices merged before simplifying
    relaxation_step: int = 0  # core.guards ladder step the run ended at (0: no rule relaxed)
    removed_components: int = 0  # whole parts removed (remove_small_components)
    collapses: int = 0  # edge collapses applied, from the input to this level

    def as_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass
class SimplifyResult:
    """A simplified mesh and everything carried over from the input.

    vertices: (n_out, 3) float64, faces: (m_out, 3) int64 indices into ``vertices``.
    face_origin: (m_out,) int64, the input face every output face descends from.
    vertex_origin: (n_out,) int64, the input vertex that survived as each output vertex.
    vertex_attributes: {name: (n_out, k) float64}, interpolated along collapsed edges.
    corner_attributes: {name: (m_out, 3, k) float64}, indexed like ``faces``.
    """

    vertices: np.ndarray
    faces: np.ndarray
    face_origin: np.ndarray
    vertex_origin: np.ndarray
    stats: SimplifyStats
    vertex_attributes: dict = field(default_factory=dict)
    corner_attributes: dict = field(default_factory=dict)
