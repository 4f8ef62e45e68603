# SPDX-License-Identifier: GPL-3.0-or-later
"""The settings of a LOD run, defined once, and its two error types; free of bpy.

``SETTINGS`` is the one table of the settings: each row gives a setting's name (the
``LodSettings`` field, the Blender property and the panel's), default, valid range,
label, tooltip, command-line flag and the core option it becomes. Everything else is
derived from it: ``LodSettings`` (the dataclass), its ``validate()``, the Blender
properties (props.py), the panel's Preserve rows (``PRESERVE_PAIRS``) and the command
line's options (``add_arguments``, ``settings_from_arguments``, ``argument_problems``).

One name per idea across the layers (the add-on's names are Blender property names that
saved files and scripts use, so where the core follows the paper they differ, once, here):

    panel label    setting / property      flag                      core option (core.Options)
    Uniformity     line_weight             --line-weight             line_weight: the paper's w
                                                                     (per vertex: line_weights, w_i)
    Importance     importance_source/_group --importance-group,      (the painted g in [0, 1] per vertex)
                                           --from-armature,
                                           --from-shape-keys
    Strength       importance_strength     --strength                quadric_scale = F(strength) ** g
                                                                     (Sec. 4.4.1; addon/pure/importance.py)
    Boundaries     preserve_boundaries,    --no-preserve-boundaries, boundary_weight (0 when off)
                   boundary_strength       --boundary-strength
    UV Seams       preserve_seams,         --no-preserve-seams,      preserve_seams, and seam edges in
                   seam_strength           --seam-strength           feature_edges with edge_weights
    Sharp Edges /  preserve_sharp/_materials, sharp/material_strength   feature_edges with edge_weights
    Material Borders                                                 (the paper's w_ij, Eq. 19)

"Importance" always means g in [0, 1], painted or derived from the skin weights or the
shape keys; the core
never sees it, only the quadric scale it is turned into.

The ``core=`` column is data where a setting sets one field of ``core.Options``: a
:class:`CoreOption` (the field, how the value converts), which options.core_options_of
reads; tests/test_addon_settings.py checks each one moves its field. Where a setting acts
on the core indirectly, ``core=`` is a text saying how, and the code it names makes it:
  * the Preserve switches of seams, sharp edges and material borders with their
    strengths: feature_edges and edge_weights (options.mesh_options; preserve_seams is
    also a field itself, and preserve_boundaries turns boundary_strength's field to 0);
  * the importance settings: quadric_scale and the line weights, or the rig's
    pose_offsets and pose_weight (options.mesh_options through importance.py);
  * the painted limit: vertex_max_error (limits.py, set by prepare and compute);
  * One Asset: each part's targets (core.budget, core.assembly; addon/asset.py, addon/job.py).
Every other setting is the add-on's own (targets, switch distances, baking, the report).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Callable, Optional, Union

import numpy as np

from ._core import core
from . import deviation_targets, switch_distances
from .importance import DEFAULT_STRENGTH as DEFAULT_IMPORTANCE_STRENGTH


class LodError(Exception):
    """Bad input for LOD generation; the message is written for the user."""


class LodCancelled(Exception):
    """The progress callback asked to stop; nothing was changed."""


IMPORTANCE_GROUP = "LOD_Importance"  # the vertex group Paint Importance and the sample use
LIMIT_GROUP = "LOD_Limit"  # the vertex group Paint Limit makes (addon/pure/limits.py)
PREVIEW_GROUP = "LOD_Importance_Preview"  # where Preview Importance writes what it shows

IMPORTANCE_SOURCES = (
    ('NONE', "None", "Every vertex counts the same"),
    ('VERTEX_GROUP', "Vertex Group",
     "A vertex group (e.g. painted in Weight Paint mode): weight 1 marks the most important vertices"),
    ('ARMATURE', "Armature",
     "From the rig: the LOD is kept close in sample poses of the armature too, and its "
     "skin weights are fitted to them, so it bends like the source (Strength: how much "
     "the poses count)"),
    ('ARMATURE_PAPER', "Armature (Paper)",
     "From the skin weights as in the paper (Sec. 5.3): vertices shared by several deform "
     "bones, near joints, are kept denser"),
    ('SHAPE_KEYS', "Shape Keys",
     "From the shape keys: vertices the keys move are kept denser, the more the farther "
     "they move (importance 1 from the largest movements on, fading to 0 where no key "
     "moves), so expressions and correctives stay close on every LOD. The triangles come "
     "from where the keys leave the surface still: the less of it, the weaker"),
)
TARGET_KINDS = (
    ('COUNT', "Triangles", "A share of the source's triangles (Ratio) or a triangle count"),
    ('DEVIATION', "Deviation", "The largest measured distance to the source, in percent of "
                               "its bounding-box diagonal"),
    ('SCREEN', "Screen Size", "The largest error in pixels when the object covers a given "
                              "height on screen"),
)
LIMIT_UNITS = (
    ('PERCENT', "% of Size", "Percent of the object's bounding-box diagonal (the asset's, when "
                             "several objects are one asset)"),
    ('DISTANCE', "Scene Units", "A distance in scene units (a single object's own units)"),
    ('PIXELS', "Pixels", "Pixels at each LOD's switch distance, where the whole LOD's largest error "
                         "shows Pixel Error pixels: a Limit below Pixel Error keeps the region that much "
                         "finer than the rest (of each LOD's requested deviation with Deviation or Screen Size "
                         "targets)"),
)
# Kept only so files and scripts that set it still load: both act alike since issue 19.
IMPORTANCE_MODES = (
    ('SOFT', "Soft", "No longer used: importance has one calibrated mode (see Strength)"),
    ('STRONG', "Strong", "No longer used: importance has one calibrated mode (see Strength)"),
)


@dataclass(frozen=True)
class Setting:
    """One row of the table.

    low/high: the valid range (None: unbounded), open at low_open/high_open; validation
      and the command line check it, Blender properties get it as their min/max unless
      ``blender`` says otherwise (a property cannot have an open bound).
    blender: further Blender property arguments (soft_max, subtype, precision, ...).
    flag: the command-line option, or None; a bool that is on by default has a flag
      that turns it off (--no-preserve-seams, --keep-small-parts). cli: further argparse
      arguments (metavar, help with {default}).
    what: how messages name it.
    core: the core option it becomes: a CoreOption, which sets that field of core.Options
      (options.core_options_of), or a text saying how it acts on the core indirectly.
    strength: for a preserve_* switch, the name of the setting weighting it.
    """

    name: str
    default: Any
    label: str
    tooltip: str
    low: Optional[float] = None
    high: Optional[float] = None
    low_open: bool = False
    high_open: bool = False
    unit: str = ""  # said after the range in messages
    items: tuple = ()  # enum: (identifier, label, description)
    blender: dict = field(default_factory=dict)
    flag: Optional[str] = None
    cli: dict = field(default_factory=dict)
    what: str = ""
    core: Union["CoreOption", str] = ""
    strength: Optional[str] = None

    @property
    def kind(self) -> type:
        return type(self.default)

    @property
    def words(self) -> str:
        return self.what or self.name.replace("_", " ")

    def problem(self, value, label: Optional[str] = None) -> Optional[str]:
        """Why ``value`` is not valid for this setting (a message naming it as ``label``,
        by default its words), or None when it is."""
        label = label or self.words
        if self.items:
            ids = [i for i, _, _ in self.items]
            if value not in ids:
                return f"{label} must be {', '.join(ids[:-1])} or {ids[-1]}, not {value!r}"
            return None
        if self.kind not in (int, float):
            return None
        low_ok = self.low is None or (value > self.low if self.low_open else value >= self.low)
        high_ok = self.high is None or (value < self.high if self.high_open else value <= self.high)
        if np.isfinite(value) and low_ok and high_ok:
            return None
        if self.high is None:
            bound = f"{'>' if self.low_open else '>='} {self.low:g}"
        else:
            bound = (f"in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}"
                     f"{')' if self.high_open else ']'}")
        return f"{label} must be {bound}{self.unit}, got {value:g}"


@dataclass(frozen=True)
class CoreOption:
    """A setting that sets one field of core.Options: ``field`` gets ``convert(value)``;
    for the strength of a Preserve switch, ``off`` while that switch is off."""

    field: str
    convert: Callable[[Any], Any]
    off: Any = None


def zero_is_off(value) -> Optional[float]:
    """An angle where 0 turns the core's option off (None)."""
    return float(value) or None


def _preserve(what, label, flag_name, tooltip, strength, strength_tooltip, switch_core, strength_core):
    """A Preserve row's switch and strength (the four share their shape and range)."""
    return (
        Setting(f"preserve_{what}", True, label, tooltip, flag=f"--no-preserve-{what}",
                cli={"help": f"do not preserve {flag_name}"}, core=switch_core, strength=strength),
        Setting(strength, 1.0, "Strength", strength_tooltip, low=0.0,
                blender={"soft_max": 10.0, "max": 1000.0},
                flag=f"--{strength.replace('_', '-')}",
                cli={"metavar": "S", "help": f"how strongly {flag_name} are kept (default 1)"},
                core=strength_core),
    )


SETTINGS = (
    # Target: the LOD chain (the command line gives its chain as ratios or triangle counts).
    Setting("ratio", 0.5, "Ratio",
            "Triangles of the first LOD as a fraction of the source's (used when Triangles is 0)",
            low=0.0, high=1.0, low_open=True, blender={"min": 0.0001, "subtype": 'FACTOR'}),
    Setting("levels", 3, "Levels", "Number of LODs to make (the source itself is LOD0)",
            low=1, blender={"max": 16}),
    Setting("level_factor", 0.5, "Factor",
            "Each LOD has this fraction of the previous LOD's triangles "
            "(3 levels at 0.5 from ratio 0.5: 50 %, 25 %, 12.5 %)",
            low=0.0, high=1.0, low_open=True, high_open=True,
            blender={"min": 0.01, "max": 0.99, "subtype": 'FACTOR'}),
    Setting("target_triangles", 0, "Triangles", "Triangle count of the first LOD; 0 uses the Ratio instead",
            low=0, unit=" (0 uses the ratio)"),
    Setting("target_by", 'COUNT', "By", "What the first LOD is asked for by (each next one then has Factor "
            "as many triangles, or allows 1/Factor as much deviation)", items=TARGET_KINDS),
    Setting("max_deviation", 0.5, "Deviation %",
            "The first LOD's largest distance to the source, measured (two-sided Hausdorff), in "
            "percent of the object's bounding-box diagonal: it gets the fewest triangles within it",
            low=0.0, low_open=True, unit=" %", blender={"min": 0.001, "soft_max": 10.0, "precision": 3},
            what="deviation"),
    Setting("asset_budget", True, "One Asset",
            "The selected objects (an input file's on the command line) are one asset: each LOD's "
            "triangle budget is spread over them by error (a bolt is not kept at half while the "
            "hull loses detail), deviations and switch distances are relative to the whole asset's "
            "size, and every part switches at the same distance. Off: every object is its own chain",
            flag="--per-part",
            cli={"help": "every object its own LOD chain (the same ratio each, deviations relative "
                         "to its own size, its own switch distances); by default an input's objects "
                         "are one asset"},
            core="(core.budget.split_by_error: the parts' counts per level)"),
    Setting("pixel_error", switch_distances.DEFAULT_PIXEL_ERROR, "Pixel Error",
            "The largest error, in pixels, the first LOD may show when the object covers Screen "
            "Height pixels (deviation = object size x pixel error / screen height); each next LOD "
            "is for 1/Factor the distance. Also the budget the engines' switch distances are "
            "computed for (docs/engines.md)", low=0.0, low_open=True, unit=" px",
            blender={"min": 0.01, "soft_max": 16.0}, flag="--pixel-error",
            cli={"metavar": "PX", "help": "the on-screen error budget, in pixels, the engines' switch "
                                          "distances are computed for (default {default:g})"}),
    Setting("screen_height", switch_distances.DEFAULT_SCREEN_HEIGHT, "Screen Height",
            "How many pixels tall the object is on screen where the first LOD takes over (By "
            "Screen Size), and the screen height of the engines' switch distances",
            low=1, unit=" px", blender={"soft_max": 4320}, flag="--screen-height",
            cli={"metavar": "H", "help": "screen height in pixels: with --screen-size how tall the object "
                                         "is on screen, and the screen of the engines' switch distances "
                                         "(default {default})"}),
    Setting("vertical_fov", switch_distances.DEFAULT_VERTICAL_FOV_DEGREES, "Field of View",
            "The camera's vertical field of view, degrees, that the engines' switch distances "
            "are computed for (screen shares do not depend on it)",
            low=0.0, high=180.0, low_open=True, high_open=True, unit=" degrees",
            blender={"min": 1.0, "max": 179.0, "precision": 1}, flag="--fov",
            cli={"metavar": "DEG", "help": "vertical field of view, degrees, of the engines' switch "
                                           "distances (default {default:g})"},
            what="field of view"),
    # Shape.
    Setting("line_weight", core.DEFAULT_LINE_WEIGHT, "Uniformity",
            "Line-quadric weight w for every vertex: higher gives more uniform, "
            "better shaped triangles, lower follows the shape more faithfully "
            "(paper default 0.001; above 0.1 the shape starts to suffer)",
            low=0.0, blender={"soft_max": 0.1, "max": 10.0, "precision": 4, "step": 0.01},
            flag="--line-weight",
            cli={"metavar": "W", "help": "line-quadric weight: higher gives more uniform triangles, lower a more "
                                         "faithful shape (default {default:g}; useful up to 0.1)"},
            core=CoreOption("line_weight", float)),
    Setting("min_quality", core.SLIVER_QUALITY, "Min Quality",
            "No collapse makes a triangle thinner than this quality (1 = equilateral): "
            "lower it (even to 0) for hard-surface parts that need their shape more than "
            "clean triangles. Thin patches between open borders may stay as thin as "
            "the input made them. Relaxed automatically only when the target needs it",
            low=0.0, high=1.0, blender={"subtype": 'FACTOR'}, what="min triangle quality",
            flag="--min-quality",
            cli={"metavar": "Q", "help": "no collapse makes a triangle thinner than this quality, 0 to 1 (1 = "
                                         "equilateral; default {default:g}); 0 with --line-weight 0 gives "
                                         "the closest shape on hard-surface parts, at the cost of slivers"},
            core=CoreOption("min_quality", float)),
    Setting("feature_angle", core.features.DEFAULT_FEATURE_ANGLE, "Feature Angle",
            "Degrees: edges whose faces' normals differ by more than this are kept "
            "like sharp edges, and corners where three of them meet (or where an open "
            "border turns sharply: half as much beyond its neighbours) stay in place, but small ones "
            "crowding a low LOD (a CAD part's bolt holes). 80 keeps the right angles of "
            "hard-surface parts; below about 60 organic meshes suffer. 0 turns it off",
            low=0.0, high=180.0, high_open=True, unit=" degrees (0 = off)",
            blender={"max": 179.0, "precision": 1}, flag="--feature-angle",
            cli={"metavar": "DEG", "help": "edges whose faces' normals differ by more than DEG degrees are kept "
                                           "like sharp edges, and their corners (and sharp turns of open "
                                           "borders) stay in place (default {default:g}; 0 = off)"},
            core=CoreOption("feature_angle", zero_is_off)),
    Setting("remove_small_components", True, "Remove Small Parts",
            "When a target cannot be reached otherwise, delete the smallest separate parts "
            "(bolts, rivets, leaf cards) rather than stop above it; off keeps every part",
            flag="--keep-small-parts",
            cli={"help": "keep every separate part, even where a target cannot be reached otherwise "
                         "(by default the smallest parts, bolts and leaf cards, are deleted then)"},
            core=CoreOption("remove_small_components", bool)),
    # Importance: g in [0, 1] per vertex, from a vertex group, the skin weights or the shape keys.
    Setting("importance_source", 'NONE', "Importance", "Where the per-vertex importance comes from",
            items=IMPORTANCE_SOURCES, core="(chooses g)"),
    Setting("importance_group", "", "Group",
            "Vertex group holding the importance (0 = normal, 1 = most important)", core="(holds g)"),
    Setting("importance_strength", DEFAULT_IMPORTANCE_STRENGTH, "Strength",
            "How much denser important regions stay, on flat and curved surfaces alike "
            "(measured at 10 %): 0.1 about 1.5x, 0.25 about 2.4x, 0.5 about 4.5x, "
            "0.75 about 12x, 1 nearly locked. 0 = importance off",
            low=0.0, high=1.0, blender={"subtype": 'FACTOR'}, flag="--strength",
            cli={"metavar": "S", "help": "importance strength, 0 to 1: about 1.5x as dense at 0.1, 4.5x at 0.5, "
                                         "nearly locked at 1 (default {default:g})"},
            core="quadric_scale = F(strength) ** g (addon/pure/importance.py)"),
    # Painted limits (issue 34, addon/pure/limits.py): how far the LOD may move, not how dense it stays.
    Setting("limit_group", "", "Limit Group",
            "Vertex group painting how far the LOD may move: where its weight is 1 every LOD stays "
            "within Limit of the source, at 0 the region is free, in between the limit grows as "
            "1 / weight. The triangle target is met elsewhere; when the limit makes it unreachable "
            "the LOD stops above it and says so",
            core="vertex_max_error = limit / weight (addon/pure/limits.py)"),
    Setting("limit_distance", 0.1, "Limit",
            "The largest distance to the source where the Limit Group's weight is 1, in percent "
            "of the object's bounding-box diagonal (the whole asset's when several objects are one "
            "asset), in scene units, or in pixels at each LOD's switch distance (Limit Unit)",
            low=0.0, low_open=True, blender={"min": 1e-6, "soft_max": 5.0, "precision": 3},
            what="limit", core="vertex_max_error"),
    Setting("limit_unit", 'PERCENT', "Limit Unit", "What Limit is measured in",
            items=LIMIT_UNITS, core="(percent of the diagonal, scene units, or pixels at the switch distance)"),
    # Unused since issue 19 (one calibrated mode, addon/pure/importance.py): accepted so older
    # scripts, files and the command line's --mode keep working.
    Setting("importance_mode", 'SOFT', "Mode", "No longer used (one calibrated mode); kept so older files load",
            items=IMPORTANCE_MODES, flag="--mode",
            cli={"help": "no longer used (importance has one calibrated mode); accepted so older "
                         "scripts still run"}),
    # Preserve: each switch with the strength of the planes that hold it.
    *_preserve("boundaries", "Boundaries", "open boundaries", "Keep open boundaries (holes, borders) in place",
               "boundary_strength", "Weight of the planes that hold open boundaries (1 = as strong as the surface)",
               "(boundary_weight: its strength's, 0 when off)", CoreOption("boundary_weight", float, off=0.0)),
    *_preserve("seams", "UV Seams", "UV seams",
               "Keep UV seams: seam vertices only slide along the seam, UVs never flip",
               "seam_strength", "Extra weight holding seam edges in place (paper Sec. 4.4.2)",
               CoreOption("preserve_seams", bool), "seam edges in feature_edges, edge_weights (w_ij)"),
    *_preserve("sharp", "Sharp Edges", "sharp edges",
               "Keep edges marked sharp (paper Sec. 4.4.2, dihedral-plane quadrics)",
               "sharp_strength", "Weight holding sharp edges in place",
               "sharp edges in feature_edges", "their edge_weights (w_ij)"),
    *_preserve("materials", "Material Borders", "material borders",
               "Keep the borders between faces of different materials",
               "material_strength", "Weight holding material borders in place",
               "material borders in feature_edges", "their edge_weights (w_ij)"),
    # Run.
    Setting("use_modifiers", True, "Apply Modifiers",
            "Simplify the mesh as the modifiers make it (Armature modifiers excepted: "
            "each LOD gets its own); off: the base mesh",
            flag="--no-modifiers", cli={"help": "simplify the base meshes, ignoring their modifiers"}),
    Setting("hard_edge_angle", 0.0, "Hard Edges",
            "Degrees: LOD edges whose faces' normals differ by more than this are marked sharp, "
            "so a LOD of a mesh shaded by angle keeps hard edges where simplifying made new "
            "ones. 0 = off (custom normals, when the source has them, decide instead)",
            low=0.0, high=180.0, high_open=True, unit=" degrees (0 = off)",
            blender={"max": 179.0, "precision": 1}, flag="--hard-edge-angle",
            cli={"metavar": "DEG", "help": "mark LOD edges sharper than DEG degrees as sharp (hard shading); "
                                           "default {default:g} = off"}),
    Setting("bake_normals", False, "Bake Normals",
            "Bake the detail each LOD lost into a tangent-space normal map (Cycles, from the "
            "source), used by copies of its materials; needs a UV map"),
    Setting("bake_resolution", 1024, "Resolution", "Width and height of each baked normal map, pixels",
            low=8, unit=" px", blender={"max": 16384, "soft_max": 4096}),
    Setting("measure_deviation", True, "Measure Deviation",
            "Measure each LOD's distance to the source, and how far its shading normals "
            "turn from the source's, for the report (takes about a second per LOD on large meshes)",
            flag="--no-measure", cli={"help": "skip the deviation measurement (faster; quality is still reported)"}),
    # Off by default, for the panel too: the attributes would travel into engine exports
    # (FBX writes every colour attribute), and Show Deviation paints a LOD when asked.
    Setting("deviation_colors", False, "Deviation Colors",
            "Give each LOD its measured distance to the source per vertex: the colour attribute "
            "\"LOD_Deviation\" (blue = on the source, red = the LOD's largest distance) and the float "
            "attribute \"LOD_Deviation_Distance\"; measures the LODs like Measure Deviation. Off: Show "
            "Deviation paints a LOD when asked",
            flag="--deviation-colors",
            cli={"help": "give each LOD the colour attribute LOD_Deviation (its distance to the source per "
                         "vertex, blue 0 to red at the LOD's largest) and the float attribute "
                         "LOD_Deviation_Distance (off by default: files for engines do not need them)"}),
)
BY_NAME = {s.name: s for s in SETTINGS}
# The panel's Preserve rows and the command line's --no-preserve-X/--X-strength pairs.
PRESERVE_PAIRS = tuple((s.name, s.strength) for s in SETTINGS if s.strength)


class _LodSettingsMethods:
    def measuring(self) -> bool:
        """Whether each LOD is measured against the source (Measure Deviation, or the
        Deviation Colors that need the measurement)."""
        return bool(self.measure_deviation or self.deviation_colors)

    @classmethod
    def names(cls) -> list:
        """The settings of the table (Blender property names), without the explicit chain."""
        return [s.name for s in SETTINGS]

    @classmethod
    def from_properties(cls, props) -> "LodSettings":
        """From anything carrying the same attribute names (operator, scene settings)."""
        return cls(**{name: getattr(props, name) for name in cls.names()})

    def validate(self) -> None:
        for s in SETTINGS:
            message = s.problem(getattr(self, s.name))
            if message:
                raise LodError(message)
        message = self.chain_problem()
        if message:
            raise LodError(message)

    def chain_problem(self, ratios_label: str = "ratios", counts_label: str = "triangle counts") -> Optional[str]:
        """What is wrong with the explicit chain (ratios or triangle_counts), or None;
        the labels are how the message names them (the command line: --ratios, --faces)."""
        if self.ratios is not None and self.triangle_counts is not None:
            return f"give {ratios_label} or {counts_label}, not both"
        if self.max_deviations is not None:
            if self.ratios is not None or self.triangle_counts is not None:
                return f"give a chain by deviation or by {ratios_label} / {counts_label}, not both"
            bad = [value for value, _ in self.max_deviations if not (np.isfinite(value) and value > 0)]
            if bad or not self.max_deviations:
                return "deviations must be positive numbers, got " + " ".join(f"{v:g}" for v in bad)
            if len({percent for _, percent in self.max_deviations}) == 1:  # comparable before any mesh
                values = [value for value, _ in self.max_deviations]
                if any(b <= a for a, b in zip(values, values[1:])):
                    return ("deviations must increase (each LOD coarser than the one before), got "
                            + " ".join(deviation_text(v, p) for v, p in self.max_deviations))
            return None
        if self.ratios is not None:
            bad = [r for r in self.ratios if not (np.isfinite(r) and 0.0 < r < 1.0)]
            if bad or not self.ratios:
                return (f"{ratios_label}: " + ", ".join(f"{r:g}" for r in bad)
                        + " not between 0 and 1 (a LOD has fewer triangles than its source)")
            return _not_decreasing(list(self.ratios), ratios_label, lambda r: f"{r:g}")
        if self.triangle_counts is not None:
            counts = list(self.triangle_counts)
            if not counts or any(int(n) != n or n < 1 for n in counts):
                return f"{counts_label} must be whole numbers of at least 1, got {' '.join(map(str, counts))}"
            return _not_decreasing(counts, counts_label, str)
        return None

    def deviation_chain(self) -> Optional[list]:
        """The chain by deviation as (value, percent?) per LOD, or None for a chain by
        triangles: the explicit max_deviations (the command line's), else the panel's By
        Deviation / Screen Size, each next LOD allowing 1/level_factor as much."""
        if self.max_deviations is not None:
            return list(self.max_deviations)
        if self.ratios is not None or self.triangle_counts is not None or self.target_by == 'COUNT':
            return None
        first = self.max_deviation if self.target_by == 'DEVIATION' else 100.0 * self.pixel_error / self.screen_height
        return [(first / self.level_factor ** k, True) for k in range(self.levels)]

    def chain(self) -> tuple:
        """The LOD chain as the settings give it: ("ratios", fractions of the source's
        triangles) or ("triangles", counts), one entry per LOD. Explicit ``ratios`` or
        ``triangle_counts`` (the command line's) win; else the panel's geometric chain:
        ``levels`` LODs from ``target_triangles`` (or ``ratio``), each ``level_factor``
        of the one before."""
        deviations = self.deviation_chain()
        if deviations is not None:
            return "deviations", [deviation_text(value, percent) for value, percent in deviations]
        if self.triangle_counts is not None:
            return "triangles", [int(n) for n in self.triangle_counts]
        if self.ratios is not None:
            return "ratios", [float(r) for r in self.ratios]
        if self.target_triangles > 0:
            return "triangles", self._geometric(self.target_triangles)
        return "ratios", [self.ratio * self.level_factor ** k for k in range(self.levels)]

    def targets(self, triangles: int, ratios_label: str = "ratios", counts_label: str = "triangle counts",
                source: str = "the mesh") -> list:
        """Triangle count of each LOD for a source of ``triangles`` triangles; LodError
        when the chain cannot be made from it (the labels as in chain_problem; ``source``:
        how messages name what is simplified). A chain by deviation gives the ladder of
        rungs its search measures (deviation_targets)."""
        if self.deviation_chain() is not None:
            rungs = deviation_targets.ladder(triangles)
            if not rungs:
                raise LodError(f"{source} ({triangles} triangles) is too small for a LOD by deviation")
            return rungs
        if self.triangle_counts is not None:
            counts = [int(n) for n in self.triangle_counts]
            if counts[0] >= triangles:
                raise LodError(f"{counts_label} {counts[0]} is not fewer than {source}'s {triangles:,} triangles")
            return counts
        if self.ratios is not None:
            counts = [int(round(r * triangles)) for r in self.ratios]
            if counts[-1] < 1 or any(b >= a for a, b in zip(counts, counts[1:])) or counts[0] >= triangles:
                raise LodError(f"{ratios_label} {' '.join(f'{r:g}' for r in self.ratios)} of {triangles:,} "
                               f"triangles give {counts}: each LOD needs fewer triangles than the one "
                               f"before, and at least 1")
            return counts
        first = self.target_triangles if self.target_triangles > 0 else int(round(self.ratio * triangles))
        if first >= triangles:
            raise LodError(
                f"the first LOD's target ({first} triangles) is not smaller than {source} "
                f"({triangles} triangles): lower the ratio or the triangle count")
        counts = self._geometric(first)
        if counts[-1] < 1 or any(b >= a for a, b in zip(counts, counts[1:])):
            raise LodError(
                f"{self.levels} levels at factor {self.level_factor:g} from {first} triangles give "
                f"{counts}: every LOD needs fewer triangles than the one before and at least 1; "
                f"use fewer levels or a larger first LOD")
        return counts

    def deviations(self, diagonal: float) -> list:
        """deviation_chain() in scene units, for a source whose bounding-box diagonal
        is ``diagonal``; LodError unless they increase (each LOD coarser)."""
        chain = self.deviation_chain()
        values = [value * diagonal / 100.0 if percent else value for value, percent in chain]
        if any(b <= a for a, b in zip(values, values[1:])):
            raise LodError("deviations must increase (each LOD coarser than the one before), got "
                           + " ".join(deviation_text(v, p) for v, p in chain)
                           + (f" (the bounding-box diagonal is {diagonal:g})" if any(p for _, p in chain) else ""))
        return values

    def _geometric(self, first: int) -> list:
        return [int(round(first * self.level_factor ** k)) for k in range(self.levels)]


def parse_deviation(text: str) -> tuple:
    """ "0.5%" -> (0.5, True): percent of the bounding-box diagonal; "0.01" -> (0.01, False):
    scene units. ValueError for anything else."""
    text = str(text).strip()
    percent = text.endswith("%")
    value = float(text[:-1] if percent else text)
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"a deviation must be a positive number, got {text!r}")
    return value, percent


def parse_limit(text: str) -> tuple:
    """ "0.2%" -> (0.2, 'PERCENT'), "0.5px" -> (0.5, 'PIXELS'), "0.01" -> (0.01,
    'DISTANCE'): a painted limit (addon/pure/limits.py). ValueError for anything else."""
    text = str(text).strip()
    unit = 'PIXELS' if text.lower().endswith("px") else 'PERCENT' if text.endswith("%") else 'DISTANCE'
    number = text[:-2] if unit == 'PIXELS' else text[:-1] if unit == 'PERCENT' else text
    value = float(number)
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"a limit must be a positive number, got {text!r}")
    return value, unit


def deviation_text(value: float, percent: bool) -> str:
    return f"{value:g}%" if percent else f"{value:g}"


def _not_decreasing(values, label, fmt) -> Optional[str]:
    if any(b >= a for a, b in zip(values, values[1:])):
        return f"{label} must decrease (each LOD smaller than the one before), got " + " ".join(fmt(v) for v in values)
    return None


LodSettings = dataclasses.make_dataclass(
    "LodSettings",
    [(s.name, s.kind, s.default) for s in SETTINGS] + [
        # An explicit chain (the command line's --ratios / --faces), replacing the
        # geometric one of ratio, levels, level_factor and target_triangles.
        ("ratios", Optional[tuple], None),
        ("triangle_counts", Optional[tuple], None),
        # Or a chain by deviation (the command line's --max-error): per LOD the largest
        # measured distance to the source allowed, (value, True) in percent of the
        # source's bounding-box diagonal or (value, False) in scene units
        # (addon/pure/deviation_targets.py makes it).
        ("max_deviations", Optional[tuple], None),
    ],
    bases=(_LodSettingsMethods,),
)
LodSettings.__module__ = __name__
LodSettings.__doc__ = """Every setting of a LOD run: the fields of SETTINGS (the operator's
property names, same defaults), plus an optional explicit chain (ratios or
triangle_counts). See chain() and targets()."""


# ----------------------------------------------------------------------------- command line


def flagged() -> list:
    """The settings the command line has an option for, in table order."""
    return [s for s in SETTINGS if s.flag]


def add_arguments(group, names=None) -> None:
    """Add the argparse option of each setting in ``names`` (default: every one with a
    flag) to ``group`` (a parser or argument group). Each stores into the setting's own
    name (``args.line_weight``; a --no-X switch stores False into ``args.preserve_X``),
    with the table's default, so ``settings_from_arguments`` can read them back."""
    for s in (flagged() if names is None else [BY_NAME[n] for n in names]):
        extra = dict(s.cli)
        if "help" in extra:
            extra["help"] = extra["help"].format(default=s.default)
        if s.kind is bool:
            off = s.default is True  # the flag changes the default
            group.add_argument(s.flag, dest=s.name, action="store_false" if off else "store_true",
                               default=s.default, **extra)
        elif s.items:
            ids = [i.lower() for i, _, _ in s.items]
            group.add_argument(s.flag, dest=s.name, type=_choice(ids), default=s.default,
                               metavar="{" + ",".join(ids) + "}", **extra)
        else:
            group.add_argument(s.flag, dest=s.name, type=number if s.kind is float else whole_number(),
                               default=s.default, **extra)


def argument_problems(args) -> list:
    """One message per flagged setting whose value in ``args`` is out of range, naming
    the flag (e.g. "--min-quality must be in [0, 1], got 2")."""
    return [message for s in flagged() if hasattr(args, s.name)
            for message in [s.problem(getattr(args, s.name), s.flag)] if message]


def settings_from_arguments(args, **overrides) -> "LodSettings":
    """LodSettings from every flagged setting ``args`` carries (see add_arguments), the
    rest at their defaults, then ``overrides`` (e.g. ratios=..., importance_source=...).
    Only the flagged ones: a parser may hold an option of its own under a setting's name
    (the command line's --importance-group, a choice made per object, given as override)."""
    values = {s.name: getattr(args, s.name) for s in flagged() if hasattr(args, s.name)}
    values.update(overrides)
    return LodSettings(**values)


def number(text):
    """The argparse type of a number option: a finite float, or a one-line error."""
    import argparse

    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not np.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def _choice(ids):
    """An enum's argparse type: the lower-case identifiers in, the table's (upper case) out."""
    import argparse

    def choice(text):
        if text.lower() not in ids:
            raise argparse.ArgumentTypeError(
                f"invalid choice: {text!r} (choose from {', '.join(map(repr, ids))})")
        return text.upper()
    return choice


def whole_number(minimum: Optional[int] = None):
    """An argparse type: a whole number, of at least ``minimum`` when one is given (a
    setting's own range is checked by argument_problems, naming the flag)."""
    import argparse

    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if minimum is not None and value < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}, got {value}")
        return value
    return parse
