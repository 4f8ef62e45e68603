# SPDX-License-Identifier: GPL-3.0-or-later
"""``python <checkout> [options]``: the command line through the pip ``bpy`` module.

Runs addon/cli.py as a script does: its bootstrap loads this folder as the package
``line_quadric_lod`` (whatever the folder is called), so ``addon`` and ``core`` are its
subpackages exactly as in the installed extension, and runs the same entry point as
``blender -c line_quadric_lod``.
"""
import importlib.util
import sys
from pathlib import Path

if __name__ == "__main__":
    # Loaded from its file: there is no package yet for addon/cli.py to be imported from.
    spec = importlib.util.spec_from_file_location(
        "line_quadric_lod_entry", Path(__file__).resolve().parent / "addon" / "cli.py")
    entry = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(entry)
    sys.exit(entry.run_as_script())
