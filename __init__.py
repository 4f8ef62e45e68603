# SPDX-License-Identifier: GPL-3.0-or-later
"""Line Quadric LOD: the Blender extension entry point.

Installed, this folder is the package ``bl_ext.<repo>.line_quadric_lod``; Blender calls
``register()``/``unregister()`` here and everything touching bpy lives in ``addon/``.
The import of ``addon`` is deferred to those calls so that importing this package (or
``core`` next to it, as the tests and the command line do) never needs bpy.
"""


def register():
    from . import addon

    addon.register()


def unregister():
    from . import addon

    addon.unregister()
