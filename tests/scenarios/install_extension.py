"""Install the extension zip into the child's (isolated) user dir, enable it and save the
preferences, so later children enable it by reading them (bpy_harness.install_extension)."""
import os
import sys

import bpy
from bpy_harness import EXT_MODULE


def run(zip_path: str, repo: str) -> dict:
    outcome = bpy.ops.extensions.package_install_files(filepath=zip_path, repo=repo, enable_on_install=True)
    if outcome != {"FINISHED"}:
        raise RuntimeError(f"package_install_files returned {outcome!r}")
    enabled = EXT_MODULE in {a.module for a in bpy.context.preferences.addons}
    if not enabled:
        raise RuntimeError(EXT_MODULE + " was installed but is not enabled")
    bpy.ops.wm.save_userpref()
    return {"enabled": enabled, "installed_dir": os.path.dirname(sys.modules[EXT_MODULE].__file__)}
