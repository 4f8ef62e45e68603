# SPDX-License-Identifier: GPL-3.0-or-later
"""Everything that touches bpy. Placeholder until the add-on lands: registers nothing."""


def register():
    pass


def unregister():
    pass
