# SPDX-License-Identifier: GPL-3.0-or-later
"""One input in this Blender process: load it, make the LODs of its objects through the
same LodJob the panel uses, name the chains, write the outputs.

A failing input becomes its report entry with ``ok`` False and the reason; the other
inputs of the run are still done.
"""
from __future__ import annotations

import time
import traceback

from ..pure.settings import LodError
from . import freshness, report, scene_files, sidecar, sources
from .arguments import CHAIN_LABELS, RUN_OPTIONS, lod_settings
from .console import Console
from .errors import InputError
from .inputs import InputJob


def make_lods(objects, args, console: Console, label: str, files_left_seconds: float) -> tuple:
    """Simplify ``objects`` and link their LODs; returns (one report entry per object, the
    asset's entry or None: addon/asset.py, the input's objects as one asset, and
    sources.keys_the_export_drops of the objects)."""
    import bpy

    from ..job import LodJob
    from .progress import ProgressLines

    choices = sources.importance_choice(objects, args)
    limited = sources.limit_choice(objects, args)
    settings = [lod_settings(args, importance_source=source, importance_group=group, limit_group=limit_group)
                for (source, group, _), (limit_group, _) in zip(choices, limited)]
    # An input's objects are one asset (addon/asset.py), named after the file.
    job = LodJob(bpy.context, objects, settings, CHAIN_LABELS, asset_name=asset_name(label),
                 named=bool(args.objects))
    # Objects sharing one input (LodJob: one mesh, equal settings) have the same note.
    for lod_input, (_, _, note), (_, limit_note) in zip(job.object_inputs, choices, limited):
        for text in (note, limit_note):
            if text and text not in lod_input.warnings:
                lod_input.warnings.append(text)
    # Progress per group: a mesh several objects use is simplified once.
    job.run(observer=ProgressLines(console, label, job.inputs, files_left_seconds))
    reports = job.commit(bpy.context)
    return [report.chain_entry(rep, out, sources.importance_label(source, group))
            for rep, out, (source, group, _) in zip(reports, job.object_outputs, choices)], job.asset_report, \
        sources.keys_the_export_drops(objects, job.object_inputs)


def asset_name(label: str) -> str:
    """An input's asset name: its file name without the extension ("engine.glb": "engine")."""
    from pathlib import PurePath

    return PurePath(label).stem or label


def name_chains(entries: list, lod_group: bool, asset: dict = None) -> None:
    """Rename each source "<name>_LOD0" and, with ``lod_group``, group for Unreal
    (addon/lod_group.py): an asset as one LOD group, else (and for an asset with a
    skinned part or a part an animation moves, animation.moved_by_animation: gathered under a
    level's Empty a part would lose its rig or its parent's motion) each chain; the
    entries get the new names (and ``asset`` its group's)."""
    import bpy

    from .. import lod_group as naming
    from ..animation import moved_by_animation
    from ..rig import armature_of

    chains = {}
    for entry in entries:
        base = entry["object"]
        source = bpy.data.objects[base]
        entry["levels"][0]["name"] = naming.rename_as_lod0(source)
        chains[base] = [source] + [bpy.data.objects[level["name"]] for level in entry["levels"][1:]]
    if not lod_group:
        return
    if asset is not None and not any(armature_of(chain[0]) or moved_by_animation(chain[0]) for chain in chains.values()):
        levels = [[chain[k] for chain in chains.values() if len(chain) > k] for k in range(len(asset["levels"]) + 1)]
        group = naming.group_asset(bpy.context, asset["name"], levels).name
        asset["lod_group"] = group
        for entry in entries:
            entry["lod_group"] = group
        return
    for entry in entries:
        entry["lod_group"] = naming.group_chain(bpy.context, entry["object"], chains[entry["object"]]).name


def process(job: InputJob, args, console: Console, files_left_seconds: float = 0.0) -> dict:
    """Load one input, make its LODs, write its outputs. Never raises (but KeyboardInterrupt):
    returns the file's report entry with ``ok`` and ``error``."""
    t0 = time.perf_counter()
    entry = {"input": str(job.path) if job.path else job.label, "label": job.label, "ok": False,
             "error": None, "outputs": [], "objects": [], "warnings": [], "seconds": 0.0}
    key = up_to_date_key(job, args)
    if key is not None and freshness.up_to_date(job.outputs, key):
        console.progress(f"[{job.label}] up to date, skipped")
        return skipped_entry(job)
    try:
        import bpy

        from .. import lod_group

        console.progress(f"[{job.label}] loading")
        scene_files.load(job, args.debug)
        scene = bpy.context.scene
        lod_group.restore_base_names(scene)
        entry["warnings"] += sources.make_instances_real(scene, bpy.context.view_layer)
        made_real, instancers_only = sources.make_node_instances_real(bpy.context.view_layer)
        entry["warnings"] += made_real + sources.make_linked_local(bpy.context.view_layer)
        objects, skipped = sources.select_objects(scene, args.objects, bpy.context.view_layer,
                                                  bpy.context.evaluated_depsgraph_get(),
                                                  getattr(args, "use_modifiers", True), instancers_only)
        entry["warnings"] += skipped + sources.drop_replaced_lods(scene, objects)
        entries, asset, keyed = make_lods(objects, args, console, job.label, files_left_seconds)
        name_chains(entries, args.lod_group, asset)
        entry["objects"] = entries
        if asset is not None:
            entry["asset"] = asset
        if job.outputs:
            freshness.forget(job.outputs)  # an interrupted rewrite is never taken for done
        # A .blend keeps modifiers and keys together; the other formats then get the
        # keyed sources' LOD0 as their stacks make it (sources.bake_keyed_sources).
        for out in sorted(job.outputs, key=lambda o: o.suffix.lower() != ".blend"):
            if keyed and out.suffix.lower() != ".blend":
                entry["warnings"] += sources.bake_keyed_sources(keyed)
                keyed = []
            console.progress(f"[{job.label}] writing {out}")
            scene_files.write_atomically(out, args.debug)
            entry["outputs"].append(str(out))
        if job.outputs:  # every engine's switch numbers beside the outputs
            entry["sidecars"] = sidecar.write(job.outputs, entry)
        if key is not None:
            freshness.mark_done(job.outputs, key)
        entry["ok"] = True
    except (InputError, LodError) as ex:
        entry["error"] = str(ex)
    except KeyboardInterrupt:
        raise
    except Exception as ex:  # a bug or an importer's surprise: one line, details on request
        if args.debug:
            traceback.print_exc()
        entry["error"] = f"unexpected {type(ex).__name__}: {ex}" + ("" if args.debug else " (--debug shows details)")
    entry["seconds"] = time.perf_counter() - t0
    return entry


def up_to_date_key(job: InputJob, args):
    """The key of ``job``'s outputs (freshness.py), or None when there is nothing to keep
    up to date (no outputs, or --force)."""
    if not job.outputs or args.force:
        return None
    options = {name: value for name, value in sorted(vars(args).items()) if name not in RUN_OPTIONS}
    options["input_kind"] = job.kind
    import bpy  # Blender's importers and exporters shape the outputs too

    options["blender"] = bpy.app.version_string
    try:
        return freshness.asset_key(job.path if job.kind != "sample" else None, options)
    except OSError:
        return None  # loading the input says what is wrong with it


def skipped_entry(job: InputJob) -> dict:
    return {"input": str(job.path) if job.path else job.label, "label": job.label, "ok": True,
            "skipped": True, "error": None, "outputs": [str(o) for o in job.outputs], "objects": [],
            "warnings": [], "seconds": 0.0}


def run_serial(jobs: list, args, console: Console, on_result=None) -> list:
    """Every input in this process, one after the other; their report entries
    (``on_result(entry)`` as each ends)."""
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
        if on_result is not None:
            on_result(entry)
    return files
