# SPDX-License-Identifier: GPL-3.0-or-later
"""``python <checkout> [options]``: the command line through the pip ``bpy`` module.

Loads this folder as the package ``line_quadric_lod`` (whatever the folder is called),
so ``addon`` and ``core`` are its subpackages exactly as in the installed extension,
and runs the same entry point as ``blender -c line_quadric_lod`` (addon/cli.py).
"""
import importlib
import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent
PACKAGE_NAME = "line_quadric_lod"


def _package():
    loaded = sys.modules.get(PACKAGE_NAME)
    if loaded is not None:
        return loaded
    spec = importlib.util.spec_from_file_location(
        PACKAGE_NAME, ROOT / "__init__.py", submodule_search_locations=[str(ROOT)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[PACKAGE_NAME] = module
    spec.loader.exec_module(module)
    return module


if __name__ == "__main__":
    # Python put the checkout itself first on sys.path; its folders (core, addon, tests,
    # ...) are reached through the package, not as top-level modules.
    sys.path[:] = [p for p in sys.path if not p or Path(p).resolve() != ROOT]
    cli = importlib.import_module(_package().__name__ + ".addon.cli")
    sys.exit(cli.main(sys.argv[1:], prog=f"python {sys.argv[0]}"))
