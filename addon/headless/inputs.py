# SPDX-License-Identifier: GPL-3.0-or-later
"""What a run reads and writes: the file formats, --input expanded into files (folders
and glob patterns), and one :class:`InputJob` per input with its output paths.

No bpy, except to ask for the open .blend when there is no --input.
"""
from __future__ import annotations

import glob
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from .errors import UsageError

INPUT_FORMATS = (".blend", ".obj", ".ply", ".stl", ".glb", ".gltf", ".fbx")
OUTPUT_FORMATS = ("blend", "glb", "gltf", "fbx", "obj")
SAMPLE_FORMATS = ("blend", "glb")


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
class InputJob:
    """One input and what to write for it."""

    label: str  # short name in messages and the table
    kind: str  # "open" (the open .blend), "sample" or "file"
    path: Optional[Path] = None
    outputs: list = field(default_factory=list)


def plan_jobs(args) -> list:
    """The jobs of this run and their output paths; raises UsageError."""
    problems = []
    if args.sample:
        jobs = [InputJob("sample", "sample")]
        stems = ["sample"]
    elif args.input:
        files, problems = expand_inputs(args.input)
        jobs = [InputJob(f.name, "file", f) for f in files]
        stems = [f.stem for f in files]
    else:
        import bpy

        if not bpy.data.filepath:
            raise UsageError("no input: give --input FILE ..., --sample, or open a .blend "
                             "(blender -b scene.blend -c line_quadric_lod ...)")
        path = Path(bpy.data.filepath)
        jobs = [InputJob(path.name, "open", path)]
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



def _default_formats(job: InputJob) -> tuple:
    if job.kind == "sample":
        return SAMPLE_FORMATS
    ext = job.path.suffix.lower().lstrip(".")
    return (ext,) if ext in OUTPUT_FORMATS else ("blend",)

