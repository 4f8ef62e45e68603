# SPDX-License-Identifier: GPL-3.0-or-later
"""Files in and out of the Blender scene: an input file imported into a fresh scene,
the scene exported to an output atomically (a temporary folder, then a rename), and the
importers' and exporters' own console output kept off ours; their failures become one
short line each ("cannot be read as glTF: ..."), never their Python tracebacks.

bpy is imported inside the functions: the options are checked before Blender loads.
"""
from __future__ import annotations

import contextlib
import os
import shutil
import sys
import tempfile
from pathlib import Path

from .errors import InputError


# What each input's importer reads, for "cannot be read as glTF: ..." (inputs.INPUT_FORMATS).
FORMAT_NAMES = {".blend": "a .blend file", ".obj": "OBJ", ".ply": "PLY", ".stl": "STL",
                ".glb": "glTF", ".gltf": "glTF", ".fbx": "FBX"}
MESSAGE_LIMIT = 200  # characters of an importer's or exporter's message kept in ours


def clean_blender_error(ex: BaseException) -> str:
    """One short line for an operator's failure. Operators fail with RuntimeError("Error:
    <report>\n"); when the importer or exporter itself raised, the report is its whole
    Python traceback, which the user cannot act on: then only its last line is kept
    (e.g. "IndexError: list index out of range"). --debug shows the importers' own
    output, traceback included."""
    lines = [line.strip() for line in str(ex).strip().splitlines() if line.strip()]
    lines = [line for line in lines if not line.startswith("Location: ")]  # where bpy.ops raised
    if any("Traceback (most recent call last)" in line for line in lines):
        lines = lines[-1:]
    text = " ".join(lines)
    for prefix in ("Error: ", "Error:"):
        if text.startswith(prefix):
            text = text[len(prefix):]
    if len(text) > MESSAGE_LIMIT:
        text = text[:MESSAGE_LIMIT - 3].rstrip() + "..."
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



def reset_scene() -> None:
    import bpy

    # Keeps the preferences and enabled add-ons (read_factory_settings would not).
    bpy.ops.wm.read_homefile(use_empty=True, use_factory_startup=True)


def import_file(path: Path) -> None:
    import bpy

    ext = path.suffix.lower()
    fp = str(path)
    if ext == ".blend":
        bpy.ops.wm.open_mainfile(filepath=fp, load_ui=False)
        return
    reset_scene()
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
        raise InputError(f"unsupported input format {ext!r}")


def load(job, show_output: bool) -> None:
    """Bring ``job``'s input into the scene: a file opened or imported into a fresh
    scene, the built-in sample built in one, or the open .blend as it is."""
    import bpy

    from .. import sample

    if job.kind == "file":
        try:
            with blender_output(show_output):
                import_file(job.path)
        except RuntimeError as ex:
            # The messages name the input already: "broken.glb: cannot be read as glTF: ..."
            what = FORMAT_NAMES.get(job.path.suffix.lower(), job.path.suffix)
            raise InputError(f"cannot be read as {what}: {clean_blender_error(ex)}") from ex
    elif job.kind == "sample":
        reset_scene()
        with blender_output(show_output):
            sample.build(bpy.context)
    ctx = bpy.context
    if ctx.view_layer is not None and ctx.mode != 'OBJECT' and ctx.view_layer.objects.active is not None:
        bpy.ops.object.mode_set(mode='OBJECT')


# This extension's top-level package: "bl_ext.<repo>.line_quadric_lod" installed,
# "line_quadric_lod" when the command line loads the checkout (addon/cli.py).
PACKAGE = __package__.rsplit(".addon.headless", 1)[0]


@contextlib.contextmanager
def gltf_hooks_visible():
    """List this package among the enabled add-ons while the glTF exporter runs, if it is
    not already: the exporter takes user extensions (addon/gltf_lod.py) only from enabled
    add-ons' modules, and the command line through the ``bpy`` module enables none.
    Nothing is registered (the entry only names the module) and the entry goes after."""
    import bpy

    addons = bpy.context.preferences.addons
    if PACKAGE in addons.keys() or PACKAGE not in sys.modules:
        yield
        return
    entry = addons.new()
    entry.module = PACKAGE
    try:
        yield
    finally:
        addon = addons.get(PACKAGE)
        if addon is not None:
            addons.remove(addon)


@contextlib.contextmanager
def armature_deform_paused():
    """Every Armature modifier off in the viewport while the glTF exporter runs, as it was
    after.

    The exporter samples each action frame by frame (``scene.frame_set``), and every frame
    re-evaluates each skinned mesh's deformation, which it never reads: with skins and
    ``export_apply`` on it switches each object's Armature modifiers off itself to read the
    rest mesh (io_scene_gltf2 ``blender/exp/nodes.py``), finds the skin by the modifier's
    type and object, and reads only bones and shape-key weights per frame. A LOD chain
    multiplies the skinned meshes by its levels: on RobotExpressive (19 parts, 3 levels)
    the export then took 5.5 s instead of 4 s, the written file byte-identical either way.
    """
    import bpy

    paused = []
    try:
        for mod in [mod for ob in bpy.data.objects if ob.type == 'MESH'
                    for mod in ob.modifiers if mod.type == 'ARMATURE' and mod.show_viewport]:
            mod.show_viewport = False
            paused.append(mod)  # so that a failure part way still puts back what it paused
        yield
    finally:
        for mod in paused:
            mod.show_viewport = True


def modifiers_to_apply() -> bool:
    """Whether an object of the scene's file has a modifier the viewport shows other than
    an Armature modifier: what the glTF exporter's ``export_apply`` is needed for.

    The exporter skins a mesh by its Armature modifier either way, but with
    ``export_apply`` on it evaluates every object that has any modifier on its own: it
    switches the Armature modifiers off and back (which tags the depsgraph) and asks for
    the evaluated depsgraph, which then re-evaluates every object in the scene, once per
    object (io_scene_gltf2 ``blender/exp/nodes.py``). A 150-part rigged character's LODs
    (600 skinned objects) took 9.1 s to write with it and 2.7 s without, the file the
    same size, its meshes, skin and channels the same; the robot's sampled bone channels
    differ in the seventh digit."""
    import bpy

    return any(mod.type != 'ARMATURE' and mod.show_viewport for ob in bpy.data.objects for mod in ob.modifiers)


def export_scene(path: Path) -> None:
    import bpy

    from .. import animation

    ext = path.suffix.lower()
    fp = str(path)
    if ext == ".blend":
        bpy.ops.wm.save_as_mainfile(filepath=fp, copy=True, check_existing=False)
    elif ext in (".glb", ".gltf"):
        # export_apply: the LODs were made from the evaluated meshes, so LOD0 must be
        # written evaluated too (the exporter leaves skinning to the glTF skin); only
        # where a modifier other than Armature changes a mesh (modifiers_to_apply).
        # The hooks add MSFT_lod and the switch data (addon/gltf_lod.py).
        # The LODs' copies of their sources' shape-key animation are paused: gltf_lod
        # gives their nodes the sources' channels (addon/animation.py says why).
        # use_active_scene: the scene the LODs were made in, as the FBX and OBJ exporters
        # write it; the glTF exporter wrote a file's other scenes too, without LODs.
        with gltf_hooks_visible(), armature_deform_paused(), animation.key_copies_paused(bpy.context.scene):
            bpy.ops.export_scene.gltf(filepath=fp, export_format='GLB' if ext == ".glb" else 'GLTF_SEPARATE',
                                      use_selection=False, use_active_scene=True, export_apply=modifiers_to_apply())
    elif ext == ".fbx":
        # use_custom_props: the switch data on the LOD objects and the LOD group (docs/engines.md).
        bpy.ops.export_scene.fbx(filepath=fp, use_selection=False, use_mesh_modifiers=True,
                                 use_custom_props=True, add_leaf_bones=False)
    elif ext == ".obj":
        bpy.ops.wm.obj_export(filepath=fp, export_selected_objects=False, apply_modifiers=True)
    else:
        raise InputError(f"unsupported output format {ext!r}")


def write_atomically(path: Path, show_output: bool) -> None:
    """Export the scene to ``path`` through a temporary folder next to it, then rename.

    The exporter writes into ``.<name>.<random>.part/<name>`` (companion files such as a
    .gltf's .bin or an .obj's .mtl keep the names it gives them); only after it
    succeeded are the files moved into place, the main file last. A failure leaves any
    earlier file at ``path`` untouched. A .blend is written beside ``path`` as
    ``.<name>.<random>.part.blend``: Blender makes the paths it holds (textures, linked
    libraries) relative to where it writes the file, and from the folder below every
    "//" path pointed one folder too deep once the file was moved into place.
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp_dir = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent))
    target = path.parent / f"{tmp_dir.name}.blend" if path.suffix.lower() == ".blend" else tmp_dir / path.name
    try:
        try:
            with blender_output(show_output):
                export_scene(target)
        except RuntimeError as ex:
            raise InputError(f"could not write {path}: {clean_blender_error(ex)}") from ex
        if not target.is_file():
            raise InputError(f"could not write {path}: the exporter wrote nothing")
        for extra in sorted(tmp_dir.iterdir()):
            if extra != target:
                dest = path.parent / extra.name
                if extra.is_dir() and dest.is_dir():
                    shutil.rmtree(dest)
                os.replace(extra, dest)
        os.replace(target, path)
    finally:
        shutil.rmtree(tmp_dir, ignore_errors=True)
        if target.parent != tmp_dir:
            target.unlink(missing_ok=True)

