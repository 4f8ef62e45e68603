# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line's options: the parser, the checks argparse cannot make, and the
way back from parsed options to an argument list (for the --jobs children).

No bpy: a mistyped option fails at once, before Blender loads anything.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path
from typing import Optional

from ..settings import LodSettings
from .errors import UsageError
from .inputs import OUTPUT_FORMATS
from .lod_settings import DEFAULT_RATIOS

SCHEDULER_ENV = "LQLOD_SCHEDULER"  # the Dask scheduler to use when --scheduler is not given
DEFAULT_RETRIES = 2
# Options that say how to run, not what to make: they are not part of an input's
# up-to-date key, and the batch gives its children its own values of them.
RUN_OPTIONS = ("input", "sample", "output", "output_dir", "format", "report", "jobs", "scheduler",
               "retries", "force", "quiet", "debug")
SAMPLE_IMPORTANCE_GROUP = "LOD_Importance"  # sample.IMPORTANCE_GROUP (that module needs bpy)

EXAMPLES = """\
examples:
  # the built-in sample (a monkey with painted importance, a rigged character):
  # writes out/sample/sample_LODs.blend and .glb and prints the table
  %(prog)s --sample --output-dir out/sample

  # LODs at 50 %%, 25 %%, 10 %% of every mesh object of the open scene, as FBX with an
  # Unreal LOD group, and a JSON report
  blender -b scene.blend -c line_quadric_lod --ratios 0.5 0.25 0.1 \\
      --output scene_LODs.fbx --lod-group --report report.json

  # fixed triangle counts for two objects, importance painted in the group "Face"
  blender -b hero.blend -c line_quadric_lod --objects Head Body \\
      --faces 20000 5000 1000 --importance-group Face --output hero_LODs.blend

  # a folder of assets, 2 Blender processes at a time, glTF out, skinned meshes keep
  # detail at the joints (importance from the armature)
  %(prog)s --input assets/ --jobs 2 --from-armature --output-dir lods --format glb

  # an asset library on a Dask cluster (workers started with `dask worker ADDRESS`),
  # a line of JSON per asset; run it again after an interruption to finish the rest
  %(prog)s --input 'library/**/*.fbx' --scheduler tcp://farm:8786 \\
      --output-dir /shared/lods --report /shared/lods/report.jsonl

  # the same as a script, for installations without the registered command
  blender -b scene.blend -P <extension>/addon/cli.py -- --ratios 0.5 --output out.blend

naming: LOD objects are <name>_LOD1 .. <name>_LODn and the source is renamed <name>_LOD0
(Unity builds its LOD Group from these suffixes). --lod-group also parents each chain to
an Empty "<name>_LODGroup" with the custom property fbx_type = "LodGroup", which the FBX
exporter writes as an FBX LOD group (Unreal: "Import Mesh LODs").

importance: --importance-group NAME is used on every object that has that vertex group,
--from-armature on skinned objects without it; other objects are simplified without
importance, with a note after the table and in the report.
--sample implies --importance-group LOD_Importance --from-armature.

exit status: 0 done, 1 some inputs failed (the others were still done), 2 nothing done
(bad options or inputs), 130 interrupted. Outputs are written to a temporary file and
renamed, so a failed or interrupted run never leaves a half-written file.

reruns: an input whose outputs were all written by an earlier run with the same input
content, options and tool version is skipped (a stamp .<output>.lqlod.json sits beside
its first output); --force remakes it.
"""


class HelpShown(Exception):
    """--help was printed: nothing else to do."""


class _Parser(argparse.ArgumentParser):
    # argparse would print usage and call sys.exit(); inside Blender's -c command that
    # would end Blender, and we want one line per problem, so both become exceptions.
    def error(self, message):
        raise UsageError(message)

    def exit(self, status=0, message=None):
        if message:
            print(message, file=sys.stderr, end="")
        raise HelpShown()


def _positive_int(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def _non_negative_int(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be 0 or more, got {value}")
    return value


def _number(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value



def build_parser(prog: Optional[str] = None) -> argparse.ArgumentParser:
    d = LodSettings()
    p = _Parser(
        prog=prog or "line_quadric_lod",
        description="Make LOD chains of mesh objects with line-quadric simplification "
                    "(Liu et al., SGP 2025), without opening Blender's UI.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
        allow_abbrev=False,
    )
    g = p.add_argument_group("input (default: the open .blend)")
    src = g.add_mutually_exclusive_group()
    src.add_argument("--input", nargs="+", metavar="PATH",
                     help="files (.blend .obj .ply .stl .glb .gltf .fbx), directories (their "
                          "files of those types) or quoted glob patterns; each is one job")
    src.add_argument("--sample", action="store_true",
                     help="use the built-in sample scene instead of an input file")
    g.add_argument("--objects", nargs="+", metavar="NAME",
                   help="mesh objects to simplify (default: every mesh object that is not a LOD)")

    g = p.add_argument_group("LOD chain (one LOD per value, each smaller than the one before)")
    t = g.add_mutually_exclusive_group()
    t.add_argument("--ratios", nargs="+", type=_number, metavar="R",
                   help="fractions of the source's triangles, e.g. 0.5 0.25 0.1 "
                        f"(default {' '.join(f'{r:g}' for r in DEFAULT_RATIOS)})")
    t.add_argument("--faces", nargs="+", type=_positive_int, metavar="N",
                   help="triangle counts, e.g. 20000 5000 1000")

    g = p.add_argument_group("simplification (the panel's settings)")
    g.add_argument("--line-weight", type=_number, default=d.line_weight, metavar="W",
                   help="line-quadric weight: higher gives more uniform triangles, lower a more "
                        f"faithful shape (default {d.line_weight:g}; useful up to 0.1)")
    g.add_argument("--min-quality", type=_number, default=d.min_quality, metavar="Q",
                   help="no collapse makes a triangle thinner than this quality, 0 to 1 (1 = "
                        f"equilateral; default {d.min_quality:g}); 0 with --line-weight 0 gives "
                        "the closest shape on hard-surface parts, at the cost of slivers")
    g.add_argument("--feature-angle", type=_number, default=d.feature_angle, metavar="DEG",
                   help="edges whose faces' normals differ by more than DEG degrees are kept like "
                        "sharp edges, and their corners (and turns of open borders by half as much) stay in "
                        f"place (default {d.feature_angle:g}; 0 = off)")
    g.add_argument("--remove-small-components", action="store_true",
                   help="when a target cannot be reached otherwise, delete the smallest separate "
                        "parts (bolts, leaf cards) rather than stop above it")
    g.add_argument("--importance-group", metavar="NAME",
                   help="vertex group painting where detail matters (weight 1 = keep most)")
    g.add_argument("--from-armature", action="store_true",
                   help="importance from the skin weights of skinned objects (paper Sec. 5.3): "
                        "detail is kept where bones bend")
    g.add_argument("--strength", type=_number, default=d.importance_strength, metavar="S",
                   help="importance strength, 0 to 1: about 1.5x as dense at 0.1, 4.5x at 0.5, "
                        f"nearly locked at 1 (default {d.importance_strength:g})")
    g.add_argument("--mode", choices=("soft", "strong"), default=d.importance_mode.lower(),
                   help="no longer used (importance has one calibrated mode); accepted so older "
                        "scripts still run")
    for name, what in (("boundaries", "open boundaries"), ("seams", "UV seams"),
                       ("sharp", "sharp edges"), ("materials", "material borders")):
        g.add_argument(f"--no-preserve-{name}", action="store_true", help=f"do not preserve {what}")
    for name, what in (("boundary", "open boundaries"), ("seam", "UV seams"),
                       ("sharp", "sharp edges"), ("material", "material borders")):
        g.add_argument(f"--{name}-strength", type=_number, default=getattr(d, f"{name}_strength"),
                       metavar="S", help=f"how strongly {what} are kept (default 1)")
    g.add_argument("--no-modifiers", action="store_true",
                   help="simplify the base meshes, ignoring their modifiers")

    g = p.add_argument_group("output")
    o = g.add_mutually_exclusive_group()
    o.add_argument("--output", metavar="FILE",
                   help="one file, format by extension: .blend .glb .gltf .fbx .obj")
    o.add_argument("--output-dir", metavar="DIR",
                   help="a folder: each input X is written as X_LODs.<format>")
    g.add_argument("--format", nargs="+", choices=OUTPUT_FORMATS, metavar="EXT",
                   help="formats written into --output-dir (default: the input's own if it is "
                        "one of blend glb gltf fbx obj, else blend; blend glb for --sample)")
    g.add_argument("--lod-group", action="store_true",
                   help='parent each chain to an Empty with fbx_type = "LodGroup" (Unreal)')
    g.add_argument("--report", metavar="FILE.json",
                   help="per object and LOD: triangles, seconds, Hausdorff and mean deviation, "
                        "triangle quality; a name ending in .jsonl gets one line per input as "
                        "each finishes, then a summary line (nothing is lost if the run stops)")
    g.add_argument("--no-measure", action="store_true",
                   help="skip the deviation measurement (faster; quality is still reported)")

    g = p.add_argument_group("running")
    g.add_argument("--jobs", type=_positive_int, default=1, metavar="N",
                   help="process N input files at a time, each in its own Blender process, on an "
                        "in-process Dask cluster (needs dask[distributed]; default 1: one after "
                        "the other in this process)")
    g.add_argument("--scheduler", metavar="ADDRESS", default=os.environ.get(SCHEDULER_ENV) or None,
                   help="run the inputs on the Dask cluster of this scheduler, e.g. "
                        f"tcp://host:8786 (default: ${SCHEDULER_ENV} if set); workers need the "
                        "inputs, outputs and this tool at the same paths")
    g.add_argument("--retries", type=_non_negative_int, default=DEFAULT_RETRIES, metavar="N",
                   help="run an input again up to N times if its Blender process crashes or is "
                        f"killed (default {DEFAULT_RETRIES}; inputs that fail cleanly are not retried)")
    g.add_argument("--force", action="store_true",
                   help="remake every input's LODs, also those whose outputs are up to date "
                        "(same input content, options and tool version)")
    g.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    g.add_argument("--debug", action="store_true",
                   help="show tracebacks and the importers' and exporters' own output")
    return p



def check_args(args) -> list:
    """Problems with option values that argparse cannot see (one message each)."""
    problems = []
    if args.ratios is not None:
        bad = [r for r in args.ratios if not 0.0 < r < 1.0]
        if bad:
            problems.append("--ratios: " + ", ".join(f"{r:g}" for r in bad)
                            + " not between 0 and 1 (a LOD has fewer triangles than its source)")
        elif any(b >= a for a, b in zip(args.ratios, args.ratios[1:])):
            problems.append("--ratios must decrease (each LOD smaller than the one before), got "
                            + " ".join(f"{r:g}" for r in args.ratios))
    if args.faces is not None and any(b >= a for a, b in zip(args.faces, args.faces[1:])):
        problems.append("--faces must decrease (each LOD smaller than the one before), got "
                        + " ".join(str(n) for n in args.faces))
    if args.line_weight < 0:
        problems.append(f"--line-weight must be >= 0, got {args.line_weight:g}")
    if not 0.0 <= args.min_quality <= 1.0:
        problems.append(f"--min-quality must be between 0 and 1, got {args.min_quality:g}")
    if not 0.0 <= args.feature_angle < 180.0:
        problems.append(f"--feature-angle must be in degrees from 0 (off) to below 180, got {args.feature_angle:g}")
    if not 0.0 <= args.strength <= 1.0:
        problems.append(f"--strength must be between 0 and 1, got {args.strength:g}")
    for name in ("boundary", "seam", "sharp", "material"):
        value = getattr(args, f"{name}_strength")
        if value < 0:
            problems.append(f"--{name}-strength must be >= 0, got {value:g}")
    if args.importance_group is not None and not args.importance_group.strip():
        problems.append("--importance-group needs a vertex group name")
    if args.output is not None:
        ext = Path(args.output).suffix.lower().lstrip(".")
        if ext not in OUTPUT_FORMATS:
            problems.append(f"unsupported output format {Path(args.output).suffix or '(no extension)'!r} "
                            f"for {args.output}: use " + ", ".join("." + f for f in OUTPUT_FORMATS))
        if args.format:
            problems.append("--format goes with --output-dir; the --output file's extension picks its format")
    if args.output is None and args.output_dir is None and args.report is None:
        problems.append("nothing to write: give --output FILE, --output-dir DIR or --report FILE.json")
    if args.report is not None and Path(args.report).is_dir():
        problems.append(f"--report {args.report} is a directory; give a file name")
    return problems



def apply_sample_defaults(args) -> None:
    """--sample implies --importance-group LOD_Importance --from-armature (unless either is given)."""
    if args.sample and args.importance_group is None and not args.from_armature:
        args.importance_group, args.from_armature = SAMPLE_IMPORTANCE_GROUP, True


def option_argv(parser, args, skip) -> list:
    """``args`` back into command-line options (those not at their default), minus ``skip``."""
    argv = []
    for action in parser._actions:
        if not action.option_strings or action.dest in skip or action.dest == "help":
            continue
        value = getattr(args, action.dest, None)
        if value == action.default or value is None:
            continue
        option = action.option_strings[0]
        if isinstance(action, (argparse._StoreTrueAction, argparse._StoreFalseAction)):
            argv.append(option)
        elif isinstance(value, (list, tuple)):
            argv += [option, *map(str, value)]
        else:
            argv += [option, str(value)]
    return argv

