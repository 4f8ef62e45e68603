# SPDX-License-Identifier: GPL-3.0-or-later
"""The run's result: the JSON report (--report), the table on stdout and the notes and
failures after it. Each object's entry is lod.commit()'s report with the source as LOD0.
"""
from __future__ import annotations

import contextlib
import json
import os
import sys
import tempfile
from pathlib import Path

from ..pure._core import core
from ..pure.settings import LodSettings
from ..pure.wording import listed_names
from .arguments import lod_settings


def chain_entry(commit_report: dict, lod_output, importance: str) -> dict:
    """One object's report entry: lod.commit()'s report with its source as the level 0
    row, each LOD's own seconds, and the importance it was made with ("NONE",
    "ARMATURE", "ARMATURE_PAPER", "SHAPE_KEYS" or "VERTEX_GROUP:<name>"). An object whose LODs share another's meshes
    (``shares``: that object, which has the time) has 0 seconds on every row."""
    rep = commit_report
    data = lod_output.input.data
    source = {"level": 0, "name": rep["object"], "target": None, "triangles": int(len(data.faces)),
              "vertices": int(len(data.vertices)), "seconds": 0.0}
    if rep.get("source_mesh") is not None:
        source["mesh"] = rep["source_mesh"]
    if lod_output.input.settings.measuring():
        source.update(hausdorff_percent=0.0, mean_percent=0.0, normal_mean_degrees=0.0, normal_p95_degrees=0.0,
                      normal_max_degrees=0.0)
    source.update(core.quality_summary(data.vertices, data.faces))
    if rep.get("switch"):  # LOD0's switch numbers (switch_distances.py) go on its row
        source.update(rep["switch"].pop("lod0"))
    previous = 0.0
    for level in rep["levels"]:
        # The engine's time is cumulative along the chain; the report gives each LOD its share.
        cumulative = level["seconds"]
        level["seconds"], previous = max(cumulative - previous, 0.0), cumulative
    rep["levels"] = [source] + rep["levels"]
    rep["importance"] = importance
    return rep


def settings_summary(args) -> dict:
    s = lod_settings(args)
    # The panel's settings but its chain and importance source, which follow as the
    # options gave them: the chain as LodSettings computes it, the importance choice as
    # given (it is made per object).
    panel_only = ("ratio", "levels", "level_factor", "target_triangles", "target_by", "max_deviation",
                  "importance_source", "importance_group", "limit_group")
    out = {name: getattr(s, name) for name in LodSettings.names() if name not in panel_only}
    kind, chain = s.chain()
    out.update(ratios=chain if kind == "ratios" else None, faces=chain if kind == "triangles" else None,
               **({"max_error": chain} if kind == "deviations" else {}),
               importance_group=args.importance_group, from_armature=args.from_armature or False,
               from_shape_keys=bool(getattr(args, "from_shape_keys", False)),
               limit_group=getattr(args, "limit_group", None),
               lod_group=bool(args.lod_group))
    return out


def make_report(tool: str, args, files: list, seconds: float) -> dict:
    failures = [{"input": f["input"], "error": f["error"]} for f in files if not f["ok"]]
    return {
        "tool": tool,
        "settings": settings_summary(args),
        "files": files,
        "failures": failures,
        "skipped": sum(1 for f in files if f.get("skipped")),
        "ok": not failures,
        "seconds": seconds,
    }


def is_streamed(path) -> bool:
    """--report FILE.jsonl: a line per input as it ends, then the summary."""
    return path is not None and Path(path).suffix.lower() == ".jsonl"


class StreamedReport:
    """The .jsonl report: {"record": "input", ...entry} as each input ends (flushed, so a
    crash of the whole run loses nothing written so far), then {"record": "summary", ...}:
    the JSON report without its "files"."""

    def __init__(self, path: Path):
        path.parent.mkdir(parents=True, exist_ok=True)
        self.file = open(path, "w", encoding="utf-8")

    def add(self, entry: dict) -> None:
        self.file.write(json.dumps({"record": "input", **entry}) + "\n")
        self.file.flush()

    def finish(self, result: dict) -> None:
        summary = {key: value for key, value in result.items() if key != "files"}
        self.file.write(json.dumps({"record": "summary", **summary}) + "\n")
        self.close()

    def close(self) -> None:
        if not self.file.closed:
            self.file.close()


def _target_cell(level: dict) -> str:
    """The triangle count asked for, or for a LOD by deviation the bound it is within, in
    the unit of its row's Hausdorff %: a part of an asset's in % of its own diagonal."""
    for key in ("requested_deviation_object_percent", "requested_deviation_percent"):
        if level.get(key) is not None:
            return f"<={level[key]:.3g}%"
    return _fmt(level.get("target"), ",")


def _fmt(value, spec, empty="-"):
    return empty if value is None else format(value, spec)


def _normals_cell(level: dict) -> str:
    """The shading normals' mean and 95th-percentile angle to the source's, degrees."""
    if level.get("normal_mean_degrees") is None:
        return "-"
    return f"{level['normal_mean_degrees']:.2f} / {level['normal_p95_degrees']:.1f}"


def _keys_cell(level: dict) -> str:
    """The shape key the LOD is furthest from (largest Hausdorff with the key at 1,
    key_deviation.py): its name, Hausdorff % and mean %."""
    keys = level.get("shape_keys")
    if not keys:
        return "-"
    worst = max(keys, key=lambda entry: entry["hausdorff_percent"])
    return f"{worst['name']} {worst['hausdorff_percent']:.3f} / {worst['mean_percent']:.4f}"


def _breakdown_rows(files: list) -> list:
    """One row per LOD and material (when the object has several) or painted region."""
    rows = []
    for f in files:
        for obj in f["objects"]:
            for level in obj["levels"]:
                materials = level.get("materials") or {}
                groups = ([("material", materials)] if len(materials) > 1 else []) + \
                    [("region", level.get("regions") or {})]
                for kind, entries in groups:
                    for name, s in entries.items():
                        rows.append([f["label"], level["name"], f"LOD{level['level']}", kind, name,
                                     _fmt(s["mean_percent"], ".4f"), _fmt(s["p95_percent"], ".4f"),
                                     _fmt(s["max_percent"], ".3f"), f"{s['samples']:,}"])
    return rows


def format_breakdown(files: list) -> str:
    """The distance per material and painted region (addon/pure/level_deviation.py), a table of
    its own under the main one; "" when no level has any."""
    return _aligned(["File", "Object", "LOD", "Per", "Name", "Mean %", "P95 %", "Max %", "Samples"],
                    _breakdown_rows(files), left={0, 1, 2, 3, 4})


def limit_lines(files: list) -> list:
    """One line per LOD with a painted limit (addon/pure/limits.py): how much of it the LOD uses."""
    lines = []
    for f in files:
        for obj in f["objects"]:
            for level in obj["levels"]:
                kept = level.get("limit")
                if kept:
                    lines.append(f"limit: {f['label']}: {level['name']}: \"{kept['group']}\" within "
                                 f"{kept['limit_percent']:.3g} %: {100 * kept['limit_used']:.0f} % of it used, "
                                 f"region max {kept['region_hausdorff_percent']:.3f} %"
                                 + ("" if kept["within"] else " (BEYOND the limit)"))
    return lines


def posed_lines(files: list) -> list:
    """One line per skinned LOD: its distance over the rig's own actions (addon/posed_deviation.py)."""
    lines = []
    for f in files:
        for obj in f["objects"]:
            notes = set()
            for level in obj["levels"]:
                posed = level.get("posed")
                if not posed:
                    continue
                if posed.get("frames"):
                    names = [a["name"] for a in posed["actions"]]
                    actions = ", ".join(names) if len(names) <= 3 else f"{len(names)} actions"
                    h, m = posed["hausdorff_percent"], posed["mean_percent"]
                    lines.append(f"posed: {f['label']}: {level['name']}: {posed['frames']} frames of {actions}: "
                                 f"Hausdorff mean {h['mean']:.3f} % max {h['max']:.3f} %, "
                                 f"mean distance mean {m['mean']:.4f} % max {m['max']:.4f} %")
                if posed.get("note") and posed["note"] not in notes:
                    notes.add(posed["note"])
                    lines.append(f"posed: {f['label']}: {obj['object']}: {posed['note']}")
    return lines


def _aligned(header: list, rows: list, left: set) -> str:
    if not rows:
        return ""
    widths = [max(len(str(r[i])) for r in rows + [header]) for i in range(len(header))]

    def line(cells):
        return "  ".join(str(c).ljust(w) if i in left else str(c).rjust(w)
                         for i, (c, w) in enumerate(zip(cells, widths))).rstrip()

    return "\n".join([line(header), line(["-" * w for w in widths])] + [line(r) for r in rows])


def format_table(files: list) -> str:
    # The worst shape key's column only when some LOD measured its keys.
    keys = any(level.get("shape_keys") for f in files for obj in f["objects"] for level in obj["levels"])
    header = ["File", "Object", "LOD", "Triangles", "Target", "Hausdorff %", "Mean %"]
    header += ["Worst key Hausdorff % / mean %"] if keys else []
    header += ["Normals deg mean/p95", "Quality mean/min", "Slivers %", "Seconds"]
    rows = []
    for f in files:
        for obj in f["objects"]:
            shared = obj.get("shares") is not None  # its LODs were made for another object
            for level in obj["levels"]:
                rows.append([
                    f["label"], level["name"], f"LOD{level['level']}", f"{level['triangles']:,}",
                    _target_cell(level),
                    _fmt(level.get("hausdorff_percent"), ".3f"), _fmt(level.get("mean_percent"), ".4f"),
                    *([_keys_cell(level)] if keys else []),
                    _normals_cell(level),
                    f"{level['mean_quality']:.3f} / {level['min_quality']:.3f}",
                    f"{level['sliver_percent']:.2f}",
                    "-" if level["level"] == 0 else "shared" if shared else f"{level['seconds']:.2f}",
                ])
        for level in (f.get("asset") or {}).get("levels", []):
            # The whole asset (addon/asset.py): what it draws, its deviation in % of its size.
            rows.append([f["label"], "(asset)", f"LOD{level['level']}", f"{level['triangles']:,}",
                         _target_cell(level),
                         _fmt(level.get("hausdorff_percent"), ".3f"), "-", *(["-"] if keys else []),
                         "-", "-", "-", "-"])
    return _aligned(header, rows, left={0, 1, 2})


# A note several objects share is printed once, naming this many of them.
NOTE_NAMES = 4


def object_notes(objects: list) -> dict:
    """{note: the names of the objects that have it}, in the order first met, of an
    input's object entries: the copies of an instanced part share their mesh's notes
    (the report keeps them per object)."""
    notes = {}
    for obj in objects:
        for warning in obj.get("warnings", []):
            names = notes.setdefault(warning, [])
            if obj["object"] not in names:
                names.append(obj["object"])
    return notes


def noted_names(names: list) -> str:
    """The objects a note is about, as print_results names them: the first NOTE_NAMES,
    then how many more."""
    return listed_names(names, NOTE_NAMES)


def print_results(report: dict) -> None:
    table = format_table(report["files"])
    if table:
        print(table)
    breakdown = format_breakdown(report["files"])
    if breakdown:
        print("\nDistance to the source per material and painted region (% of the diagonal; "
              "mean, 95th percentile, max over both surfaces' samples):")
        print(breakdown)
    for line in limit_lines(report["files"]) + posed_lines(report["files"]):
        print(line)
    for f in report["files"]:
        for warning in f["warnings"] + (f.get("asset") or {}).get("warnings", []):
            print(f"note: {f['label']}: {warning}")
        for warning, names in object_notes(f["objects"]).items():
            print(f"note: {f['label']}: {noted_names(names)}: {warning}")
    n = len(report["files"])
    failed = report["failures"]
    skipped = report.get("skipped", 0)
    written = [o for f in report["files"] if not f.get("skipped") for o in f["outputs"]]
    print(f"{n - len(failed)} of {n} input{'s' if n != 1 else ''} done in {report['seconds']:.1f} s"
          + (f", {skipped} of them up to date (skipped)" if skipped else "")
          + (f", {len(written)} file{'s' if len(written) != 1 else ''} written" if written else ""))
    for f in failed:
        print(f"FAILED {f['input']}: {f['error']}")
    sys.stdout.flush()


def write_json_atomically(path: Path, data) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    try:
        # mkstemp makes the file private (0600); a report is read by the rest of the
        # pipeline, so it gets the permissions a plain open() would give it.
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            json.dump(data, fh, indent=2)
            fh.write("\n")
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
