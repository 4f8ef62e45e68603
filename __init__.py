# SPDX-License-Identifier: GPL-3.0-or-later
"""Line Quadric LOD: the Blender extension entry point.

Installed, this folder is the package ``bl_ext.<repo>.line_quadric_lod``; Blender calls
``register()``/``unregister()`` here and everything touching bpy lives in ``addon/``.
The import of ``addon`` is deferred to those calls so that importing this package (or
``core`` next to it, as the tests and the command line do) never needs bpy.
"""


def __getattr__(name):
    # The glTF exporter looks for this attribute on every enabled add-on's module
    # (addon/gltf_lod.py); handed out on demand, so importing the package needs no bpy.
    if name == "glTF2ExportUserExtension":
        from .addon.gltf_lod import glTF2ExportUserExtension

        return glTF2ExportUserExtension
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def register():
    from . import addon

    addon.register()


def unregister():
    from . import addon

    addon.unregister()
