# SPDX-License-Identifier: GPL-3.0-or-later
"""The LodSettings of a command-line run: the panel's settings from the options, and the
LOD chain as the options give it.

The panel describes a chain by its first LOD and a factor between levels; the command
line lists every level (--ratios 0.5 0.25 0.1, or --faces 20000 5000 1000), which is
not a geometric series in general. :class:`ChainSettings` is LodSettings with that list:
lod.prepare() asks the settings for the chain (``targets``), so the list takes the place
of the panel's model there, with messages that name the options.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

from ..settings import LodError, LodSettings

DEFAULT_RATIOS = (0.5, 0.25, 0.125)


@dataclass
class ChainSettings(LodSettings):
    """LodSettings whose LOD chain is a list of ratios or of triangle counts."""

    ratios: Optional[tuple] = None  # fractions of the source's triangles (default DEFAULT_RATIOS)
    faces: Optional[tuple] = None  # triangle counts; used instead of the ratios when given

    def targets(self, triangles: int) -> list:
        """The LOD chain's triangle counts for a source of ``triangles``; LodError if impossible."""
        if self.faces:
            counts = list(self.faces)
            if counts[0] >= triangles:
                raise LodError(f"--faces {counts[0]} is not fewer than the mesh's {triangles:,} triangles")
            return counts
        ratios = self.ratios or DEFAULT_RATIOS
        counts = [int(round(r * triangles)) for r in ratios]
        if counts[-1] < 1 or any(b >= a for a, b in zip(counts, counts[1:])) or counts[0] >= triangles:
            raise LodError(f"--ratios {' '.join(f'{r:g}' for r in ratios)} of {triangles:,} triangles give "
                           f"{counts}: each LOD needs fewer triangles than the one before, and at least 1")
        return counts


def settings_from_args(args) -> ChainSettings:
    """The settings every object starts from (importance is chosen per object)."""
    return ChainSettings(
        ratios=tuple(args.ratios) if args.ratios else None,
        faces=tuple(args.faces) if args.faces else None,
        line_weight=args.line_weight,
        min_quality=args.min_quality,
        feature_angle=args.feature_angle,
        remove_small_components=args.remove_small_components,
        importance_strength=args.strength,
        importance_mode=args.mode.upper(),
        preserve_boundaries=not args.no_preserve_boundaries,
        boundary_strength=args.boundary_strength,
        preserve_seams=not args.no_preserve_seams,
        seam_strength=args.seam_strength,
        preserve_sharp=not args.no_preserve_sharp,
        sharp_strength=args.sharp_strength,
        preserve_materials=not args.no_preserve_materials,
        material_strength=args.material_strength,
        use_modifiers=not args.no_modifiers,
        measure_deviation=not args.no_measure,
    )
