# SPDX-License-Identifier: GPL-3.0-or-later
"""Headless LOD generation: one argument parser and one implementation for every entry point.

    blender -b scene.blend -c line_quadric_lod [options]      the command the add-on registers
    blender -b scene.blend -P <ext>/addon/cli.py -- [options]  this file run as a script
    python <checkout> [options]                                 __main__.py, with the pip bpy module

All three call :func:`main` (the registered command through :func:`cli_command`).
Parsing and checking the arguments and the input paths need no Blender, so a mistyped
option fails at once; bpy and the LOD modules are imported only to do the work.

Exit status: 0 everything done, 1 some input failed (the others are still done),
2 nothing was done (bad options, missing or unsupported files, nothing to write),
130 interrupted.
"""
from __future__ import annotations

import argparse
import contextlib
import glob
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

COMMAND_ID = "line_quadric_lod"
PACKAGE_NAME = "line_quadric_lod"  # the checkout is loaded under this name when run as a script


def _load_root_package(root: Path):
    """Import the folder ``root`` (the extension's root) as the package ``line_quadric_lod``,
    whatever the folder is called, so ``addon`` and ``core`` are subpackages as when installed."""
    import importlib.util

    loaded = sys.modules.get(PACKAGE_NAME)
    if loaded is not None:
        if Path(loaded.__file__).resolve().parent == root:
            return loaded
        raise ImportError(f"a different {PACKAGE_NAME} is already imported from {loaded.__file__}")
    spec = importlib.util.spec_from_file_location(
        PACKAGE_NAME, root / "__init__.py", submodule_search_locations=[str(root)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[PACKAGE_NAME] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[PACKAGE_NAME]
        raise
    return module


def _run_as_script() -> int:
    """``blender -b -P addon/cli.py -- [options]`` or ``python addon/cli.py [options]``."""
    import importlib

    here = Path(__file__).resolve().parent
    root = here.parent
    # ``python addon/cli.py`` puts addon/ first on sys.path, where its modules would
    # shadow top-level names; everything is imported through the package instead.
    sys.path[:] = [p for p in sys.path if not p or Path(p).resolve() != here]
    package = _load_root_package(root)
    cli = importlib.import_module(package.__name__ + ".addon.cli")
    if "bpy" in sys.modules:  # inside Blender: our options follow "--"
        argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
        prog = f"blender -b [scene.blend] -P {Path(__file__).name} --"
    else:
        argv, prog = sys.argv[1:], f"python {sys.argv[0]}"
    return cli.main(argv, prog=prog)


if __name__ == "__main__" and not __package__:
    # Run as a script there is no package for the relative imports below: load this
    # checkout as one and run that copy of the module instead.
    sys.exit(_run_as_script())


from .settings import LodError, LodSettings  # noqa: E402  (after the script-mode bootstrap)

INPUT_FORMATS = (".blend", ".obj", ".ply", ".stl", ".glb", ".gltf", ".fbx")
OUTPUT_FORMATS = ("blend", "glb", "gltf", "fbx", "obj")
DEFAULT_RATIOS = (0.5, 0.25, 0.125)
SAMPLE_FORMATS = ("blend", "glb")
SAMPLE_IMPORTANCE_GROUP = "LOD_Importance"
BASE_NAME_PROP = "lod_base_name"  # on a source renamed "<name>_LOD0": its name before
LOD_GROUP_SUFFIX = "_LODGroup"
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130

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
"""


class UsageError(Exception):
    """A bad command line (one message per problem)."""

    def __init__(self, *messages):
        super().__init__("; ".join(messages))
        self.messages = list(messages)


class CliError(Exception):
    """An input that cannot be processed; the message is for the user."""


class _HelpShown(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    # argparse would print usage and call sys.exit(); inside Blender's -c command that
    # would end Blender, and we want one line per problem, so both become exceptions.
    def error(self, message):
        raise UsageError(message)

    def exit(self, status=0, message=None):
        if message:
            print(message, file=sys.stderr, end="")
        raise _HelpShown()


def _positive_int(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
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
                        "triangle quality")
    g.add_argument("--no-measure", action="store_true",
                   help="skip the deviation measurement (faster; quality is still reported)")

    g = p.add_argument_group("running")
    g.add_argument("--jobs", type=_positive_int, default=1, metavar="N",
                   help="process N input files at a time, each in its own Blender process (default 1)")
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


def _has_glob(text: str) -> bool:
    return any(ch in text for ch in "*?[")


def _readable(path: Path) -> Optional[str]:
    try:
        with open(path, "rb") as fh:
            fh.read(1)
    except OSError as ex:
        return f"cannot read {path}: {ex.strerror or ex}"
    return None


def expand_inputs(patterns) -> tuple:
    """(files, problems): --input paths, directories and globs as a list of files."""
    files, problems = [], []
    supported = " ".join(INPUT_FORMATS)
    for pattern in patterns:
        if _has_glob(pattern) and not Path(pattern).exists():
            matches = [Path(m) for m in sorted(glob.glob(pattern, recursive=True)) if Path(m).is_file()]
            found = [m for m in matches if m.suffix.lower() in INPUT_FORMATS]
            if not matches:
                problems.append(f"no files match {pattern!r}")
            elif not found:
                problems.append(f"no files of a supported type ({supported}) match {pattern!r}")
            files += found
        elif Path(pattern).is_dir():
            found = sorted(p for p in Path(pattern).iterdir()
                           if p.is_file() and p.suffix.lower() in INPUT_FORMATS and not p.name.startswith("."))
            if not found:
                problems.append(f"the folder {pattern} has no files of a supported type ({supported})")
            files += found
        elif not Path(pattern).exists():
            problems.append(f"no such file: {pattern}")
        elif Path(pattern).suffix.lower() not in INPUT_FORMATS:
            problems.append(f"unsupported input format {Path(pattern).suffix or '(no extension)'!r}: "
                            f"{pattern} (supported: {supported})")
        else:
            files.append(Path(pattern))
    unique, seen = [], set()
    for f in files:
        key = f.resolve()
        if key not in seen:
            seen.add(key)
            unique.append(f)
    for f in unique:
        problem = _readable(f)
        if problem:
            problems.append(problem)
    return unique, problems


@dataclass
class Job:
    """One input and what to write for it."""

    label: str  # short name in messages and the table
    kind: str  # "open" (the open .blend), "sample" or "file"
    path: Optional[Path] = None
    outputs: list = field(default_factory=list)


def make_jobs(args) -> list:
    """The jobs of this run and their output paths; raises UsageError."""
    problems = []
    if args.sample:
        jobs = [Job("sample", "sample")]
        stems = ["sample"]
    elif args.input:
        files, problems = expand_inputs(args.input)
        jobs = [Job(f.name, "file", f) for f in files]
        stems = [f.stem for f in files]
    else:
        import bpy

        if not bpy.data.filepath:
            raise UsageError("no input: give --input FILE ..., --sample, or open a .blend "
                             "(blender -b scene.blend -c line_quadric_lod ...)")
        path = Path(bpy.data.filepath)
        jobs = [Job(path.name, "open", path)]
        stems = [path.stem]
    if problems:
        raise UsageError(*problems)

    if args.output is not None:
        if len(jobs) > 1:
            raise UsageError(f"--output writes one file but there are {len(jobs)} inputs: use --output-dir")
        jobs[0].outputs = [Path(args.output)]
    elif args.output_dir is not None:
        out_dir = Path(args.output_dir)
        if out_dir.exists() and not out_dir.is_dir():
            raise UsageError(f"--output-dir {out_dir} exists and is not a folder")
        for job, stem in zip(jobs, stems):
            formats = args.format or _default_formats(job)
            job.outputs = [out_dir / f"{stem}_LODs.{fmt}" for fmt in dict.fromkeys(formats)]
        owners = {}
        for job in jobs:
            for out in job.outputs:
                owners.setdefault(out.resolve(), []).append(job)
        clashes = [f"{', '.join(str(j.path) for j in js)} would all be written to {out}"
                   for out, js in owners.items() if len(js) > 1]
        if clashes:
            raise UsageError(*clashes)
    return jobs


def _default_formats(job: Job) -> tuple:
    if job.kind == "sample":
        return SAMPLE_FORMATS
    ext = job.path.suffix.lower().lstrip(".")
    return (ext,) if ext in OUTPUT_FORMATS else ("blend",)


def _settings(args) -> LodSettings:
    """The settings every object starts from (importance is chosen per object)."""
    return LodSettings(
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


def targets_for(args, triangles: int) -> list:
    """The LOD chain's triangle counts for a source of ``triangles``; LodError if impossible."""
    if args.faces is not None:
        counts = list(args.faces)
        if counts[0] >= triangles:
            raise LodError(f"--faces {counts[0]} is not fewer than the mesh's {triangles:,} triangles")
        return counts
    ratios = args.ratios or DEFAULT_RATIOS
    counts = [int(round(r * triangles)) for r in ratios]
    if counts[-1] < 1 or any(b >= a for a, b in zip(counts, counts[1:])) or counts[0] >= triangles:
        raise LodError(f"--ratios {' '.join(f'{r:g}' for r in ratios)} of {triangles:,} triangles give "
                       f"{counts}: each LOD needs fewer triangles than the one before, and at least 1")
    return counts


# ----------------------------------------------------------------------------- console


class Console:
    """Progress lines on stderr (unless quiet) and error lines (always)."""

    def __init__(self, quiet: bool):
        self.quiet = quiet
        self.lock = threading.Lock()

    def progress(self, message: str) -> None:
        if not self.quiet:
            self._write(message)

    def error(self, message: str) -> None:
        self._write(f"error: {message}")

    def _write(self, message: str) -> None:
        with self.lock:
            sys.stderr.write(message + "\n")
            sys.stderr.flush()


def duration(seconds: float) -> str:
    if seconds < 1.0:
        return "<1 s"
    if seconds < 90:
        return f"{seconds:.0f} s"
    return f"{int(seconds // 60)} min {int(seconds % 60):02d} s"


def _clean_blender_error(ex: BaseException) -> str:
    # Operators fail with RuntimeError("Error: <report>\n"); one line, without the prefix.
    text = " ".join(line.strip() for line in str(ex).strip().splitlines() if line.strip())
    for prefix in ("Error: ", "Error:"):
        if text.startswith(prefix):
            text = text[len(prefix):]
    return text or type(ex).__name__


@contextlib.contextmanager
def blender_output(show: bool):
    """Keep importers' and exporters' own prints (C and Python) off our stdout/stderr.

    stdout carries the table, stderr our progress and errors; Blender's "Info: Saved",
    "OBJ import ... took" and the glTF add-on's messages would interleave with both.
    Errors still reach the user through the operator's exception.
    """
    if show:
        yield
        return
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    try:
        with open(os.devnull, "wb") as sink:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            try:
                yield
            finally:
                sys.stdout.flush()
                sys.stderr.flush()
                _flush_c_stdio()
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in saved:
            os.close(fd)


def _flush_c_stdio() -> None:
    # Blender's C code prints through stdio buffers; flush them into the sink before the
    # real descriptors come back, or the text would appear later on the console.
    try:
        import ctypes

        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError, TypeError):
        pass


# ----------------------------------------------------------------------------- one input (needs bpy)


def _reset_scene() -> None:
    import bpy

    # Keeps the preferences and enabled add-ons (read_factory_settings would not).
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)


def _import(path: Path) -> None:
    import bpy

    ext = path.suffix.lower()
    fp = str(path)
    if ext == ".blend":
        bpy.ops.wm.open_mainfile(filepath=fp, load_ui=False)
        return
    _reset_scene()
    if ext == ".obj":
        bpy.ops.wm.obj_import(filepath=fp)
    elif ext == ".ply":
        bpy.ops.wm.ply_import(filepath=fp)
    elif ext == ".stl":
        bpy.ops.wm.stl_import(filepath=fp)
    elif ext in (".glb", ".gltf"):
        # No bone-shape icosphere: it would be one more mesh object to make LODs of.
        bpy.ops.import_scene.gltf(filepath=fp, disable_bone_shape=True)
    elif ext == ".fbx":
        bpy.ops.import_scene.fbx(filepath=fp)
    else:  # expand_inputs lets only the formats above through
        raise CliError(f"unsupported input format {ext!r}")


def _export(path: Path) -> None:
    import bpy

    ext = path.suffix.lower()
    fp = str(path)
    if ext == ".blend":
        bpy.ops.wm.save_as_mainfile(filepath=fp, copy=True, check_existing=False)
    elif ext in (".glb", ".gltf"):
        # export_apply: the LODs were made from the evaluated meshes, so LOD0 must be
        # written evaluated too (the exporter leaves skinning to the glTF skin).
        bpy.ops.export_scene.gltf(filepath=fp, export_format='GLB' if ext == ".glb" else 'GLTF_SEPARATE',
                                  use_selection=False, export_apply=True)
    elif ext == ".fbx":
        bpy.ops.export_scene.fbx(filepath=fp, use_selection=False, use_mesh_modifiers=True,
                                 use_custom_props=True, add_leaf_bones=False)
    elif ext == ".obj":
        bpy.ops.wm.obj_export(filepath=fp, export_selected_objects=False, apply_modifiers=True)
    else:
        raise CliError(f"unsupported output format {ext!r}")


def write_atomically(path: Path, show_output: bool) -> None:
    """Export the scene to ``path`` through a temporary folder next to it, then rename.

    The exporter writes into ``.<name>.<random>.part/<name>`` (companion files such as a
    .gltf's .bin or an .obj's .mtl keep the names it gives them); only after it
    succeeded are the files moved into place, the main file last. A failure leaves any
    earlier file at ``path`` untouched.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp_dir = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent))
    try:
        target = tmp_dir / path.name
        try:
            with blender_output(show_output):
                _export(target)
        except RuntimeError as ex:
            raise CliError(f"could not write {path}: {_clean_blender_error(ex)}") from ex
        if not target.is_file():
            raise CliError(f"could not write {path}: the exporter wrote nothing")
        for extra in sorted(tmp_dir.iterdir()):
            if extra != target:
                dest = path.parent / extra.name
                if extra.is_dir() and dest.is_dir():
                    shutil.rmtree(dest)
                os.replace(extra, dest)
        os.replace(target, path)
    finally:
        shutil.rmtree(tmp_dir, ignore_errors=True)


def write_json_atomically(path: Path, data) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            json.dump(data, fh, indent=2)
            fh.write("\n")
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _object_mode() -> None:
    import bpy

    ctx = bpy.context
    if ctx.view_layer is not None and ctx.mode != 'OBJECT' and ctx.view_layer.objects.active is not None:
        bpy.ops.object.mode_set(mode='OBJECT')


def _restore_base_names(scene) -> None:
    # A re-run on our own output: sources renamed "<name>_LOD0" get their name back, so
    # their earlier LODs (which record "<name>" as their source) are replaced instead
    # of gaining LODs of their own.
    for ob in scene.objects:
        base = ob.get(BASE_NAME_PROP)
        if isinstance(base, str) and ob.name == f"{base}_LOD0":
            ob.name = base
            del ob[BASE_NAME_PROP]


def select_objects(scene, names) -> tuple:
    """(objects, skipped) to simplify: ``names`` or every mesh object that is not a LOD."""
    from . import lod

    # Meshes drawn as bone shapes (rig widgets) are display helpers, not assets.
    widgets = {pb.custom_shape for ob in scene.objects if ob.type == 'ARMATURE' and ob.pose
               for pb in ob.pose.bones if pb.custom_shape is not None}
    meshes = [ob for ob in scene.objects if ob.type == 'MESH' and lod.LEVEL_PROP not in ob and ob not in widgets]
    if names:
        problems, picked = [], []
        for name in dict.fromkeys(names):
            ob = scene.objects.get(name)
            if ob is None:
                available = ", ".join(sorted(o.name for o in meshes)[:12]) or "none"
                problems.append(f'object "{name}" not found (mesh objects: {available})')
            elif ob.type != 'MESH':
                problems.append(f'"{name}" is not a mesh object (its type is {ob.type})')
            elif lod.LEVEL_PROP in ob:
                problems.append(f'"{name}" is a LOD made by an earlier run, not a source')
            else:
                picked.append(ob)
        if problems:
            raise CliError("; ".join(problems))
        return picked, []
    with_faces = [ob for ob in meshes if len(ob.data.polygons)]
    if not with_faces:
        raise CliError("no mesh objects with faces" if meshes else "no mesh objects")
    skipped = [f'"{ob.name}" skipped: no faces' for ob in meshes if not len(ob.data.polygons)]
    return with_faces, skipped


def importance_choice(objects, args) -> list:
    """Per object: (importance_source, group, note or None).

    In a batch of mixed assets only some have the painted group or a rig, so an object
    without either is simplified without importance and gets a note (in the report and
    after the table) rather than failing the input."""
    from . import lod

    group = args.importance_group
    choices = []
    for ob in objects:
        if group and group in ob.vertex_groups:
            choices.append(('VERTEX_GROUP', group, None))
        elif args.from_armature and lod.armature_of(ob) is not None:
            choices.append(('ARMATURE', "", None))
        else:
            wanted = [w for w, on in ((f'no vertex group "{group}"', bool(group)),
                                      ("not skinned", args.from_armature)) if on]
            note = f"no importance ({' and '.join(wanted)})" if wanted else None
            choices.append(('NONE', "", note))
    return choices


def _prefixed(name: str, ex: Exception) -> str:
    text = str(ex)
    return text if f'"{name}"' in text else f'"{name}": {text}'


class TimeLeft:
    """Time-left estimate for the objects of one input.

    Simplifying and measuring cost very differently (measuring a LOD is a fixed number
    of point queries, about the same for a small and a large LOD), so each has its own
    rate: seconds per triangle removed and seconds per LOD measured, taken from what
    this run has done so far (the current object's live progress before anything has
    finished), with rough priors before that. ``later`` adds the inputs still waiting.
    """

    PRIOR_SIMPLIFY = 5e-5  # s per triangle removed (2-core machine, bpy 4.5)
    PRIOR_MEASURE = 0.5  # s per LOD measured at lod.DEVIATION_SAMPLES samples

    def __init__(self, inputs, later: float):
        self.simplify_left = sum(len(i.data.faces) - i.targets[-1] for i in inputs)
        self.measure_left = sum(len(i.targets) for i in inputs if i.settings.measure_deviation)
        self.simplify_done = self.simplify_seconds = 0.0
        self.measure_done = self.measure_seconds = 0.0
        self.later = later

    def rate(self, done, seconds, live_done, live_seconds, prior) -> float:
        if done > 0:
            return (seconds + live_seconds) / (done + live_done)
        if live_done > 0:
            return live_seconds / live_done
        return prior

    def left(self, live_simplify=0.0, live_simplify_s=0.0, live_measure=0.0, live_measure_s=0.0) -> float:
        rs = self.rate(self.simplify_done, self.simplify_seconds, live_simplify, live_simplify_s, self.PRIOR_SIMPLIFY)
        rm = self.rate(self.measure_done, self.measure_seconds, live_measure, live_measure_s, self.PRIOR_MEASURE)
        return (rs * max(self.simplify_left - live_simplify, 0.0) + rm * max(self.measure_left - live_measure, 0.0)
                + self.later)

    def record(self, removed, simplify_s, measured, measure_s) -> None:
        self.simplify_done += removed
        self.simplify_seconds += simplify_s
        self.simplify_left -= removed
        self.measure_done += measured
        self.measure_seconds += measure_s
        self.measure_left -= measured


class _ObjectProgress:
    """The per-LOD progress lines of one object, from lod.compute's fraction callback."""

    def __init__(self, console, label, lod_input, estimate: TimeLeft):
        self.console = console
        self.label = label
        self.input = lod_input
        m = len(lod_input.data.faces)
        targets = lod_input.targets
        self.removed = max(m - targets[-1], 1)
        # The engine reports (faces removed) / (faces to remove down to the last target).
        self.marks = [(m - t) / self.removed for t in targets]
        self.measuring = lod_input.settings.measure_deviation
        self.share = 0.8 if self.measuring else 1.0  # how lod.compute splits its fraction
        self.next = 0
        self.estimate = estimate
        self.t0 = time.perf_counter()
        self.t_simplified = None

    def _left(self, chain: float, measured: float) -> str:
        now = time.perf_counter()
        if self.t_simplified is None:
            left = self.estimate.left(chain * self.removed, now - self.t0)
        else:
            left = self.estimate.left(self.removed, self.t_simplified - self.t0, measured, now - self.t_simplified)
        return f"about {duration(left)} left"

    def __call__(self, fraction: float):
        chain = min(fraction / self.share, 1.0)
        if chain >= 1.0 and self.t_simplified is None:
            self.t_simplified = time.perf_counter()
        while self.next < len(self.marks) and chain >= self.marks[self.next] - 1e-9:
            self.announce(self.next, chain)
            self.next += 1
        return True

    def announce(self, index: int, chain: float) -> None:
        name = self.input.source_name
        self.console.progress(f"[{self.label}] {name}: LOD{index + 1} simplified, target "
                              f"{self.input.targets[index]:,} triangles ({self._left(chain, 0.0)})")

    def finish(self) -> None:
        while self.next < len(self.marks):  # levels that stopped early
            self.announce(self.next, 1.0)
            self.next += 1
        now = time.perf_counter()
        simplified = self.t_simplified or now
        measured = len(self.marks) if self.measuring else 0
        self.estimate.record(self.removed, simplified - self.t0, measured, now - simplified)
        self.console.progress(f"[{self.label}] {self.input.source_name}: done in {now - self.t0:.1f} s "
                              f"(about {duration(self.estimate.left())} left)")


def make_lods(objects, args, console: Console, label: str, files_left_seconds: float) -> list:
    """Simplify ``objects`` and link their LODs; returns one report dict per object."""
    import dataclasses

    import bpy

    from . import lod
    from ._core import core

    base = _settings(args)
    inputs, notes = [], []
    for ob, (source, group, note) in zip(objects, importance_choice(objects, args)):
        settings = dataclasses.replace(base, importance_source=source, importance_group=group)
        try:
            # prepare() checks a geometric chain from these fields; ours is replaced right
            # after by the exact --ratios/--faces chain, with messages naming the options.
            settings.ratio, settings.levels, settings.target_triangles = 0.5, 1, 0
            lod_input = lod.prepare(bpy.context, ob, settings)
            lod_input.targets = targets_for(args, len(lod_input.data.faces))
        except LodError as ex:
            raise CliError(_prefixed(ob.name, ex)) from ex
        if note:
            lod_input.warnings.append(note)
        inputs.append(lod_input)
        notes.append(source if source != 'VERTEX_GROUP' else f"VERTEX_GROUP:{group}")

    estimate = TimeLeft(inputs, files_left_seconds)
    outputs = []
    for lod_input in inputs:
        m = len(lod_input.data.faces)
        console.progress(f"[{label}] {lod_input.source_name}: {m:,} triangles -> "
                         + ", ".join(f"LOD{k} {t:,}" for k, t in enumerate(lod_input.targets, start=1)))
        tracker = _ObjectProgress(console, label, lod_input, estimate)
        try:
            out = lod.compute(lod_input, tracker)
        except LodError as ex:
            raise CliError(_prefixed(lod_input.source_name, ex)) from ex
        tracker.finish()
        outputs.append(out)

    reports = lod.commit(bpy.context, outputs)
    for rep, out, importance in zip(reports, outputs, notes):
        data = out.input.data
        source = {"level": 0, "name": rep["object"], "target": None, "triangles": int(len(data.faces)),
                  "vertices": int(len(data.vertices)), "seconds": 0.0}
        if out.input.settings.measure_deviation:
            source.update(hausdorff_percent=0.0, mean_percent=0.0)
        source.update(core.quality_summary(data.vertices, data.faces))
        previous = 0.0
        for level in rep["levels"]:
            # The engine's time is cumulative along the chain; the report gives each LOD its share.
            cumulative = level["seconds"]
            level["seconds"], previous = max(cumulative - previous, 0.0), cumulative
        rep["levels"] = [source] + rep["levels"]
        rep["importance"] = importance
    return reports


def finish_names(reports, lod_group: bool) -> None:
    """Rename each source "<name>_LOD0" and, with ``lod_group``, parent each chain to an
    Empty "<name>_LODGroup" whose fbx_type = "LodGroup" the FBX exporter writes out."""
    import bpy

    scene = bpy.context.scene
    for rep in reports:
        base = rep["object"]
        source = bpy.data.objects[base]
        wanted = f"{base}_LOD0"
        if wanted in bpy.data.objects:
            raise CliError(f'cannot rename "{base}" to "{wanted}": an object of that name exists')
        source.name = wanted
        source[BASE_NAME_PROP] = base
        rep["object"] = base
        rep["levels"][0]["name"] = source.name
        if not lod_group:
            continue
        chain = [source] + [bpy.data.objects[level["name"]] for level in rep["levels"][1:]]
        name = base + LOD_GROUP_SUFFIX
        empty = bpy.data.objects.get(name)
        if empty is None or empty.type != 'EMPTY':
            empty = bpy.data.objects.new(name, None)
            collection = next((c for c in source.users_collection
                               if c == scene.collection or c in scene.collection.children_recursive[:]),
                              scene.collection)
            collection.objects.link(empty)
        empty["fbx_type"] = "LodGroup"
        empty.parent = source.parent
        if source.parent is not None and source.parent_type == 'BONE':
            empty.parent_type, empty.parent_bone = 'BONE', source.parent_bone
        empty.matrix_parent_inverse = source.matrix_parent_inverse.copy()
        bpy.context.view_layer.update()
        for ob in chain:
            world = ob.matrix_world.copy()
            ob.parent = empty
            ob.parent_type = 'OBJECT'
            ob.matrix_parent_inverse.identity()
            ob.matrix_world = world
        rep["lod_group"] = empty.name


def process(job: Job, args, console: Console, files_left_seconds: float = 0.0) -> dict:
    """Load one input, make its LODs, write its outputs. Never raises (but KeyboardInterrupt):
    returns the file's report entry with ``ok`` and ``error``."""
    t0 = time.perf_counter()
    entry = {"input": str(job.path) if job.path else job.label, "label": job.label, "ok": False,
             "error": None, "outputs": [], "objects": [], "warnings": [], "seconds": 0.0}
    try:
        import bpy

        from . import sample

        console.progress(f"[{job.label}] loading")
        if job.kind == "file":
            try:
                with blender_output(args.debug):
                    _import(job.path)
            except RuntimeError as ex:
                raise CliError(f"could not import {job.path}: {_clean_blender_error(ex)}") from ex
        elif job.kind == "sample":
            _reset_scene()
            with blender_output(args.debug):
                sample.build(bpy.context)
        _object_mode()
        scene = bpy.context.scene
        _restore_base_names(scene)
        objects, skipped = select_objects(scene, args.objects)
        entry["warnings"] += skipped
        reports = make_lods(objects, args, console, job.label, files_left_seconds)
        finish_names(reports, args.lod_group)
        entry["objects"] = reports
        for out in job.outputs:
            console.progress(f"[{job.label}] writing {out}")
            write_atomically(out, args.debug)
            entry["outputs"].append(str(out))
        entry["ok"] = True
    except (CliError, LodError) as ex:
        entry["error"] = str(ex)
    except KeyboardInterrupt:
        raise
    except Exception as ex:  # a bug or an importer's surprise: one line, details on request
        if args.debug:
            traceback.print_exc()
        entry["error"] = f"unexpected {type(ex).__name__}: {ex}" + ("" if args.debug else " (--debug shows details)")
    entry["seconds"] = time.perf_counter() - t0
    return entry


# ----------------------------------------------------------------------------- report and table


def settings_summary(args) -> dict:
    s = _settings(args)
    out = {k: v for k, v in vars(s).items() if k not in ("ratio", "levels", "level_factor", "target_triangles",
                                                         "importance_source", "importance_group")}
    out.update(ratios=None if args.faces else list(args.ratios or DEFAULT_RATIOS),
               faces=list(args.faces) if args.faces else None,
               importance_group=args.importance_group, from_armature=bool(args.from_armature),
               lod_group=bool(args.lod_group))
    return out


def make_report(args, files: list, seconds: float) -> dict:
    failures = [{"input": f["input"], "error": f["error"]} for f in files if not f["ok"]]
    return {
        "tool": COMMAND_ID,
        "settings": settings_summary(args),
        "files": files,
        "failures": failures,
        "ok": not failures,
        "seconds": seconds,
    }


def _fmt(value, spec, empty="-"):
    return empty if value is None else format(value, spec)


def format_table(files: list) -> str:
    header = ["File", "Object", "LOD", "Triangles", "Target", "Hausdorff %", "Mean %",
              "Quality mean/min", "Slivers %", "Seconds"]
    rows = []
    for f in files:
        for obj in f["objects"]:
            for level in obj["levels"]:
                rows.append([
                    f["label"], level["name"], f"LOD{level['level']}", f"{level['triangles']:,}",
                    _fmt(level.get("target"), ","),
                    _fmt(level.get("hausdorff_percent"), ".3f"), _fmt(level.get("mean_percent"), ".4f"),
                    f"{level['mean_quality']:.3f} / {level['min_quality']:.3f}",
                    f"{level['sliver_percent']:.2f}",
                    "-" if level["level"] == 0 else f"{level['seconds']:.2f}",
                ])
    if not rows:
        return ""
    widths = [max(len(str(r[i])) for r in rows + [header]) for i in range(len(header))]
    left = {0, 1, 2}

    def line(cells):
        return "  ".join(str(c).ljust(w) if i in left else str(c).rjust(w)
                         for i, (c, w) in enumerate(zip(cells, widths))).rstrip()

    out = [line(header), line(["-" * w for w in widths])]
    out += [line(r) for r in rows]
    return "\n".join(out)


def print_results(report: dict) -> None:
    table = format_table(report["files"])
    if table:
        print(table)
    for f in report["files"]:
        for warning in f["warnings"]:
            print(f"note: {f['label']}: {warning}")
        for obj in f["objects"]:
            for warning in obj.get("warnings", []):
                print(f"note: {f['label']}: {obj['object']}: {warning}")
    n = len(report["files"])
    failed = report["failures"]
    written = [o for f in report["files"] for o in f["outputs"]]
    print(f"{n - len(failed)} of {n} input{'s' if n != 1 else ''} done in {report['seconds']:.1f} s"
          + (f", {len(written)} file{'s' if len(written) != 1 else ''} written" if written else ""))
    for f in failed:
        print(f"FAILED {f['input']}: {f['error']}")
    sys.stdout.flush()


# ----------------------------------------------------------------------------- running


def run_serial(jobs: list, args, console: Console) -> list:
    files = []
    t0 = time.perf_counter()
    for i, job in enumerate(jobs):
        if len(jobs) > 1:
            console.progress(f"[{job.label}] file {i + 1} of {len(jobs)}")
        # Files not started yet, estimated at the average so far (0 before the first ends).
        average = (time.perf_counter() - t0) / i if i else 0.0
        entry = process(job, args, console, average * (len(jobs) - 1 - i))
        if not entry["ok"]:
            console.error(f"{job.label}: {entry['error']}")
        files.append(entry)
    return files


def _option_argv(parser, args, skip) -> list:
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


def child_command() -> list:
    """How to start this same command line in a new process."""
    import bpy

    script = str(Path(__file__).resolve())
    binary = bpy.app.binary_path
    if binary:  # inside Blender: a background Blender running this file as a script
        return [binary, "--background", "--python-exit-code", "1", "--python", script, "--"]
    return [sys.executable, script]  # the bpy module: the same interpreter


def run_parallel(jobs: list, args, parser, console: Console) -> list:
    """Each job in its own process (the same command on one input), ``args.jobs`` at a time."""
    base = child_command() + _option_argv(
        parser, args, {"input", "sample", "output", "output_dir", "format", "report", "jobs"})
    files = [None] * len(jobs)
    pending = list(enumerate(jobs))
    running = {}
    tmp = Path(tempfile.mkdtemp(prefix="lqlod-jobs-"))
    t0 = time.perf_counter()
    finished = 0
    try:
        while pending or running:
            while pending and len(running) < args.jobs:
                i, job = pending.pop(0)
                report = tmp / f"{i}.json"
                argv = base + ["--input", str(job.path), "--report", str(report)]
                if job.outputs:
                    out_dir = job.outputs[0].parent
                    argv += ["--output-dir", str(out_dir), "--format", *(o.suffix[1:] for o in job.outputs)]
                proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                        stderr=subprocess.PIPE, text=True, errors="replace")
                lines = []
                pump = threading.Thread(target=_pump, args=(proc.stderr, lines, console), daemon=True)
                pump.start()
                running[i] = (job, proc, pump, lines, report)
            time.sleep(0.05)
            for i in [i for i, r in running.items() if r[1].poll() is not None]:
                job, proc, pump, lines, report = running.pop(i)
                pump.join()
                files[i] = _child_entry(job, proc.returncode, lines, report)
                finished += 1
                if not files[i]["ok"]:
                    console.error(f"{job.label}: {files[i]['error']}")
                elapsed = time.perf_counter() - t0
                left = len(jobs) - finished
                estimate = elapsed / finished * left / min(args.jobs, max(left, 1)) if left else 0.0
                console.progress(f"[{job.label}] {'done' if files[i]['ok'] else 'failed'} "
                                 f"({finished} of {len(jobs)} inputs, about {duration(estimate)} left)")
    finally:
        for job, proc, *_ in running.values():
            if proc.poll() is None:
                proc.terminate()
        for job, proc, *_ in running.values():
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
        shutil.rmtree(tmp, ignore_errors=True)
    return files


def _pump(stream, lines: list, console: Console) -> None:
    # A child's progress goes straight through; its error lines are kept for the
    # summary (the parent prints each failure once).
    for raw in stream:
        line = raw.rstrip("\n")
        lines.append(line)
        if line and not line.startswith("error:"):
            console.progress(line)


def _child_entry(job: Job, code: int, lines: list, report: Path) -> dict:
    try:
        data = json.loads(report.read_text(encoding="utf-8"))
        entry = data["files"][0]
        entry["label"] = job.label
        return entry
    except (OSError, ValueError, KeyError, IndexError):
        pass
    errors = [line[len("error: "):] for line in lines if line.startswith("error:")]
    reason = errors[-1] if errors else (
        f"the process exited with status {code}" + (f": {lines[-1]}" if lines else ""))
    return {"input": str(job.path), "label": job.label, "ok": False, "error": reason,
            "outputs": [], "objects": [], "warnings": [], "seconds": 0.0}


def main(argv=None, prog: Optional[str] = None) -> int:
    """The command line; returns the exit status (never raises, never calls sys.exit)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser(prog)
    console = Console(quiet="--quiet" in argv)
    try:
        args = parser.parse_args(argv)
    except _HelpShown:
        return EXIT_OK
    except UsageError as ex:
        console.error(f"{ex} (see {parser.prog} --help)")
        return EXIT_USAGE
    if args.sample and args.importance_group is None and not args.from_armature:
        args.importance_group, args.from_armature = SAMPLE_IMPORTANCE_GROUP, True
    problems = check_args(args)
    try:
        jobs = make_jobs(args)
    except UsageError as ex:
        problems += ex.messages
    if problems:
        for message in problems:
            console.error(message)
        return EXIT_USAGE
    console.quiet = args.quiet
    t0 = time.perf_counter()
    try:
        if args.jobs > 1 and len(jobs) > 1:
            files = run_parallel(jobs, args, parser, console)
        else:
            files = run_serial(jobs, args, console)
        report = make_report(args, files, time.perf_counter() - t0)
        if args.report:
            write_json_atomically(Path(args.report), report)
        print_results(report)
    except KeyboardInterrupt:
        console.error("interrupted: files being written were left as they were")
        return EXIT_INTERRUPTED
    except Exception as ex:  # our own bug: still one line unless asked for details
        if args.debug:
            traceback.print_exc()
        console.error(f"unexpected {type(ex).__name__}: {ex}" + ("" if args.debug else " (--debug shows details)"))
        return EXIT_FAILED
    return EXIT_OK if report["ok"] else EXIT_FAILED


def cli_command(argv) -> int:
    """The handler of ``blender -c line_quadric_lod [options]`` (bpy.utils.register_cli_command)."""
    return main(list(argv), prog="blender -b [scene.blend] -c line_quadric_lod")
