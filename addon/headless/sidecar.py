# SPDX-License-Identifier: GPL-3.0-or-later
"""The switch-data sidecar: ``<output stem>.lods.json`` beside an input's outputs, with
every engine's switch numbers for each LOD chain (addon/pure/switch_distances.py), the same
ones the --report JSON has per level. Written atomically, after the outputs; only when
the deviation was measured (the numbers come from it).
"""
from __future__ import annotations

from pathlib import Path

from ..pure import switch_distances as sd
from .report import write_json_atomically

SUFFIX = ".lods.json"
FORMAT = "line_quadric_lod.switch/1"


def paths_for(outputs) -> list:
    """One sidecar per output folder and stem (scene_LODs.glb and scene_LODs.fbx share one)."""
    seen = []
    for out in outputs:
        path = Path(out).with_name(Path(out).stem + SUFFIX)
        if path not in seen:
            seen.append(path)
    return seen


def _chain(obj: dict) -> dict:
    levels = obj["levels"]
    switch = obj.get("switch")
    keep = ("level", "name", "triangles", "hausdorff_percent") + sd.PER_LEVEL_KEYS
    chain = {"object": obj["object"], "lod_group": obj.get("lod_group"),
             "levels": [{key: level[key] for key in keep if key in level} for level in levels]}
    if not switch:
        chain["switch"] = None
        chain["note"] = "not measured (Measure Deviation off, or no deviation): no switch data"
        return chain
    chain["switch"] = dict(switch)
    chain["gltf"] = {"MSFT_screencoverage": [lv["msft_screen_coverage"] for lv in levels]}
    chain["unreal"] = {"screen_sizes": [lv["unreal_screen_size"] for lv in levels]}
    chain["unity"] = {"screen_relative_transition_heights": [lv["unity_transition_height"] for lv in levels]}
    chain["godot"] = {"visibility_ranges": [[lv["godot_visibility_range_begin"], lv["godot_visibility_range_end"]]
                                            for lv in levels]}
    return chain


def _asset(entry: dict) -> dict:
    """An asset's LOD set (addon/asset.py): per level, LOD0 first, the objects an engine's
    one LOD group holds there (a part the budget's split removed is in none from there
    on) and the asset's switch numbers, which every part's chain above repeats."""
    asset = entry["asset"]
    count = len(asset["levels"])
    renderers = [[obj["levels"][k]["name"] for obj in entry["objects"] if len(obj["levels"]) > k]
                 for k in range(count + 1)]
    out = {"name": asset["name"], "bounding_box_diagonal": asset["bounding_box_diagonal"],
           "levels": [{"level": k, "objects": renderers[k]} for k in range(count + 1)]}
    chains = [obj for obj in entry["objects"] if obj.get("switch")]
    if chains and asset.get("switch"):
        first = chains[0]["levels"]  # (every part of a level has the asset's numbers)
        for k, level in enumerate(out["levels"]):
            source = first[0] if k == 0 else asset["levels"][k - 1]
            level.update({key: source[key] for key in sd.PER_LEVEL_KEYS if key in source})
        out["switch"] = dict(asset["switch"])
    return out


def _view(entry: dict) -> dict:
    """The view the numbers were computed for (the run's --pixel-error, --screen-height,
    --fov), as the chains' switch data carries it."""
    for obj in entry["objects"]:
        if obj.get("switch"):
            return {key: obj["switch"][key] for key in ("pixel_error", "screen_height", "vertical_fov_degrees")}
    return {"pixel_error": sd.DEFAULT_PIXEL_ERROR, "screen_height": sd.DEFAULT_SCREEN_HEIGHT,
            "vertical_fov_degrees": sd.DEFAULT_VERTICAL_FOV_DEGREES}


def content(entry: dict) -> dict:
    """The sidecar of one input's report entry (one_input.process)."""
    return {
        "format": FORMAT,
        "input": entry["input"],
        "outputs": [Path(p).name for p in entry["outputs"]],
        "view": _view(entry),
        "units": "distances in scene units (Blender: metres at unit scale 1); screen values as a share "
                 "of the screen height; see docs/engines.md",
        "objects": [_chain(obj) for obj in entry["objects"]],
        **({"asset": _asset(entry)} if entry.get("asset") else {}),
    }


def write(outputs, entry: dict) -> list:
    """Write the sidecar(s) of ``entry`` beside ``outputs``; returns their paths. Nothing
    measured (--no-measure): no sidecar, and an earlier one there goes (it would describe
    LODs that were just replaced)."""
    paths = paths_for(outputs)
    if not any(obj.get("switch") for obj in entry["objects"]):
        for path in paths:
            path.unlink(missing_ok=True)
        return []
    data = content(entry)
    for path in paths:
        write_json_atomically(path, data)
    return [str(p) for p in paths]
