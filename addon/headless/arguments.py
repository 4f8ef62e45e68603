# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line's options: the parser, the checks argparse cannot make, the
LodSettings they give, and the way back from parsed options to an argument list (for
the --jobs children).

The panel's settings are not written here: their options, defaults, help and range
checks come from the settings table (addon/pure/settings.py: add_arguments,
argument_problems, settings_from_arguments), and the LOD chain is LodSettings' own
(its explicit ratios or triangle_counts). Here are the options that are not panel
settings: the chain as a list, the importance choice per object, inputs, outputs and
how to run.

No bpy: a mistyped option fails at once, before Blender loads anything.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Optional

from ..pure.settings import (IMPORTANCE_GROUP, parse_deviation, parse_limit, PRESERVE_PAIRS, LodSettings, add_arguments,
                        argument_problems, number, settings_from_arguments, whole_number)
from .asset_task import SCHEDULER_ENV
from .errors import UsageError
from .inputs import OUTPUT_FORMATS

DEFAULT_RETRIES = 2
# Options that say how to run, not what to make: they are not part of an input's
# up-to-date key, and the batch gives its children its own values of them.
RUN_OPTIONS = ("input", "sample", "output", "output_dir", "format", "report", "jobs", "scheduler",
               "retries", "force", "quiet", "debug")
CHAIN_LABELS = ("--ratios", "--faces")  # how messages about the chain name it (LodSettings.targets)

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
--from-armature on skinned objects without it, --from-shape-keys on objects with shape
keys without either; other objects are simplified without importance, with a note after
the table and in the report.
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


def _parsed_by(parse, expected: str):
    """An argparse type: ``text`` as given, once ``parse`` accepts it; else the error
    saying what was ``expected``."""
    def argument(text):
        try:
            parse(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
        return text.strip()
    return argument


_limit = _parsed_by(parse_limit, "a positive number, a percentage such as 0.2% or pixels such as 0.5px")
_deviation = _parsed_by(parse_deviation, "a positive number, or a percentage such as 0.5%")


_positive_int = whole_number(1)
_non_negative_int = whole_number(0)


def build_parser(prog: Optional[str] = None) -> argparse.ArgumentParser:
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
    t.add_argument("--ratios", nargs="+", type=number, metavar="R",
                   help="fractions of the source's triangles (of an input's objects together: "
                        "--per-part), e.g. 0.5 0.25 0.1 "
                        f"(default {' '.join(f'{r:g}' for r in LodSettings().chain()[1])})")
    t.add_argument("--faces", nargs="+", type=_positive_int, metavar="N",
                   help="triangle counts, e.g. 20000 5000 1000")
    t.add_argument("--max-error", nargs="+", type=_deviation, metavar="D",
                   help="the largest distance to the source each LOD may have, measured (two-sided "
                        "Hausdorff): a number in scene units (the object's own with --per-part), or with "
                        "%% in percent of the bounding-box diagonal of the input's objects together "
                        "(of each object's with --per-part), e.g. 0.1%% 0.5%% 2%%; each LOD is the "
                        "fewest triangles measured within it")
    t.add_argument("--screen-size", nargs="+", type=number, metavar="PX",
                   help="the largest error in pixels each LOD may show while the object covers "
                        "--screen-height pixels (deviation = object size x PX / screen height, the "
                        "size being its bounding-box diagonal), e.g. 1 2 4")
    add_arguments(g, ["screen_height", "asset_budget"])
    g.add_argument("--lods", type=_positive_int, metavar="N",
                   help="with one --max-error or --screen-size value: N LODs, each for twice the "
                        "distance of the one before (twice the deviation), e.g. --screen-size 1 --lods 4")

    g = p.add_argument_group("simplification (the panel's settings)")
    add_arguments(g, ["line_weight", "min_quality", "feature_angle", "remove_small_components"])
    g.add_argument("--importance-group", metavar="NAME",
                   help="vertex group painting where detail matters (weight 1 = keep most)")
    g.add_argument("--from-armature", nargs="?", const="poses", choices=("poses", "paper"), metavar="poses|paper",
                   help="on skinned objects, Source Armature: the rig's sample poses count in the "
                        "error and the LOD's skin weights are fitted to them, so the LOD bends "
                        "like the source (docs/armature.md); '--from-armature paper' uses the "
                        "paper's importance from the skin weights instead")
    g.add_argument("--from-shape-keys", action="store_true",
                   help="on objects with shape keys, Source Shape Keys: the vertices the keys move "
                        "are kept denser, the more the farther they move (docs/weight-painting.md); "
                        "each LOD's report then has every key's deviation, measured with the key at 1")
    g.add_argument("--limit-group", metavar="NAME",
                   help="vertex group painting how far the LODs may move: where its weight is 1 each "
                        "LOD stays within --limit of the source, at 0 the region is free, in between "
                        "the limit grows as 1/weight; the triangle target is met elsewhere "
                        "(docs/weight-painting.md)")
    g.add_argument("--limit", type=_limit, metavar="D",
                   help="with --limit-group: the largest distance where its weight is 1, in scene units "
                        "(the object's own with --per-part), with %% in percent of the bounding-box "
                        "diagonal of the input's objects together (each object's with --per-part), e.g. "
                        "0.1%%, or with px in pixels at each LOD's switch distance (where the whole LOD "
                        "shows --pixel-error pixels; with --ratios or --faces), e.g. 0.5px")
    add_arguments(g, ["importance_strength", "importance_mode", *(switch for switch, _ in PRESERVE_PAIRS),
                      *(strength for _, strength in PRESERVE_PAIRS), "use_modifiers"])

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
    add_arguments(g, ["pixel_error", "vertical_fov", "hard_edge_angle"])
    g.add_argument("--bake-normals", type=whole_number(8), metavar="RES",
                   help="bake each LOD's lost detail into a RES x RES tangent-space normal map "
                        "(Cycles, from the source; needs UVs), used by copies of its materials")
    g.add_argument("--report", metavar="FILE.json",
                   help="per object and LOD: triangles, seconds, Hausdorff and mean deviation, "
                        "triangle quality; a name ending in .jsonl gets one line per input as "
                        "each finishes, then a summary line (nothing is lost if the run stops)")
    add_arguments(g, ["measure_deviation", "deviation_colors"])

    g = p.add_argument_group("running")
    g.add_argument("--jobs", type=_positive_int, default=1, metavar="N",
                   help="process N input files at a time, each in its own Blender process "
                        "(nothing to install; default 1: one after the other in this process)")
    g.add_argument("--scheduler", metavar="ADDRESS", default=os.environ.get(SCHEDULER_ENV) or None,
                   help="run the inputs on the Dask cluster of this scheduler, e.g. "
                        f"tcp://host:8786 (default: ${SCHEDULER_ENV} if set; needs "
                        "dask[distributed]); workers need the inputs, outputs and this tool at "
                        "the same paths")
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
    if args.screen_height >= 1:  # else --screen-size's chain cannot be computed (said below)
        chain = lod_settings(args).chain_problem(*CHAIN_LABELS)
        if chain:
            problems.append(chain)
    problems += argument_problems(args)
    if args.screen_size is not None and any(px <= 0 for px in args.screen_size):
        problems.append("--screen-size: pixel errors must be positive, got "
                        + " ".join(f"{px:g}" for px in args.screen_size))
    if args.lods is not None:
        given = args.max_error if args.max_error is not None else args.screen_size
        if given is None or len(given) != 1:
            problems.append("--lods goes with one --max-error or --screen-size value (N LODs at doubling distances)")
    if args.importance_group is not None and not args.importance_group.strip():
        problems.append("--importance-group needs a vertex group name")
    if args.limit_group is not None and not args.limit_group.strip():
        problems.append("--limit-group needs a vertex group name")
    if (args.limit_group is None) != (args.limit is None):
        problems.append("--limit-group and --limit go together: the group paints where, the limit says how far")
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
        args.importance_group, args.from_armature = IMPORTANCE_GROUP, "poses"


def lod_settings(args, **overrides) -> LodSettings:
    """The LodSettings of a run: the panel's settings from their options, the LOD chain as
    --ratios or --faces list it, then ``overrides`` (each object's importance_source and
    importance_group). Neither option: the panel's default chain, spelled out as the list
    it is (LodSettings().chain()), so each LOD is that share of the source's triangles."""
    deviations = _deviation_chain(args)
    if deviations is not None:
        chain = {"max_deviations": deviations}
    elif args.faces is not None:
        chain = {"triangle_counts": tuple(args.faces)}
    elif args.ratios is not None:
        chain = {"ratios": tuple(args.ratios)}
    else:
        kind, values = LodSettings().chain()
        chain = {"ratios" if kind == "ratios" else "triangle_counts": tuple(values)}
    if getattr(args, "bake_normals", None):
        chain.update(bake_normals=True, bake_resolution=args.bake_normals)
    if getattr(args, "limit", None) is not None:
        value, unit = parse_limit(args.limit)
        chain.update(limit_distance=value, limit_unit=unit)
    return settings_from_arguments(args, **chain, **overrides)


def _deviation_chain(args):
    """--max-error or --screen-size as (value, percent?) per LOD, or None. A pixel error
    becomes a percentage of the diagonal (100 * PX / H); one value with --lods N gives N
    LODs at doubling distances, so doubling deviations."""
    if args.max_error is not None:
        values = [parse_deviation(text) for text in args.max_error]
    elif args.screen_size is not None:
        values = [(100.0 * px / args.screen_height, True) for px in args.screen_size]
    else:
        return None
    if args.lods is not None and len(values) == 1:
        value, percent = values[0]
        values = [(value * 2 ** k, percent) for k in range(args.lods)]
    return tuple(values)


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

