# SPDX-License-Identifier: GPL-3.0-or-later
"""The settings of a LOD run and its two error types, free of bpy (the command line
parses into them, and tests check them without Blender)."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np


class LodError(Exception):
    """Bad input for LOD generation; the message is written for the user."""


class LodCancelled(Exception):
    """The progress callback asked to stop; nothing was changed."""


@dataclass
class LodSettings:
    """Every setting of a LOD run; the field names are the operator's property names."""

    ratio: float = 0.5
    levels: int = 3
    level_factor: float = 0.5
    target_triangles: int = 0
    line_weight: float = 1e-3
    min_quality: float = 0.3
    feature_angle: float = 80.0
    remove_small_components: bool = False
    importance_source: str = 'NONE'
    importance_group: str = ""
    importance_strength: float = 0.5  # the calibrated default (addon/importance.py)
    # Unused since issue 19 (one calibrated mode, addon/importance.py): accepted so older
    # scripts, files and the command line's --mode keep working.
    importance_mode: str = 'SOFT'
    preserve_boundaries: bool = True
    boundary_strength: float = 1.0
    preserve_seams: bool = True
    seam_strength: float = 1.0
    preserve_sharp: bool = True
    sharp_strength: float = 1.0
    preserve_materials: bool = True
    material_strength: float = 1.0
    use_modifiers: bool = True
    measure_deviation: bool = True

    @classmethod
    def names(cls) -> list:
        return [f.name for f in dataclasses.fields(cls)]

    @classmethod
    def from_properties(cls, props) -> "LodSettings":
        """From anything carrying the same attribute names (operator, scene settings)."""
        return cls(**{name: getattr(props, name) for name in cls.names()})

    def validate(self) -> None:
        if self.importance_source not in ('NONE', 'VERTEX_GROUP', 'ARMATURE'):
            raise LodError(f"importance source must be NONE, VERTEX_GROUP or ARMATURE, not {self.importance_source!r}")
        if self.importance_mode not in ('SOFT', 'STRONG'):
            raise LodError(f"importance mode must be SOFT or STRONG, not {self.importance_mode!r}")
        if not (0.0 < self.ratio <= 1.0):
            raise LodError(f"ratio must be in (0, 1], got {self.ratio}")
        if self.levels < 1:
            raise LodError(f"levels must be at least 1, got {self.levels}")
        if not (0.0 < self.level_factor < 1.0):
            raise LodError(f"level factor must be between 0 and 1, got {self.level_factor}")
        if not (0.0 <= self.min_quality <= 1.0):
            raise LodError(f"min triangle quality must be in [0, 1], got {self.min_quality}")
        if not (0.0 <= self.feature_angle < 180.0):
            raise LodError(f"feature angle must be in [0, 180) degrees (0 = off), got {self.feature_angle}")
        if self.target_triangles < 0:
            raise LodError(f"target triangles must be 0 (use the ratio) or positive, got {self.target_triangles}")
        for name in ("line_weight", "importance_strength", "boundary_strength", "seam_strength",
                     "sharp_strength", "material_strength"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0:
                raise LodError(f"{name.replace('_', ' ')} must be >= 0, got {value}")

    def targets(self, triangles: int) -> list:
        """Triangle count of each LOD for a source of ``triangles`` triangles."""
        first = self.target_triangles if self.target_triangles > 0 else int(round(self.ratio * triangles))
        if first >= triangles:
            raise LodError(
                f"the first LOD's target ({first} triangles) is not smaller than the mesh "
                f"({triangles} triangles): lower the ratio or the triangle count")
        counts = [int(round(first * self.level_factor ** k)) for k in range(self.levels)]
        if counts[-1] < 1 or any(b >= a for a, b in zip(counts, counts[1:])):
            raise LodError(
                f"{self.levels} levels at factor {self.level_factor:g} from {first} triangles give "
                f"{counts}: every LOD needs fewer triangles than the one before and at least 1; "
                f"use fewer levels or a larger first LOD")
        return counts
