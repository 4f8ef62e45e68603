"""Make a bench script standalone: repository root on sys.path, Blender user dirs isolated.

Import this first in every bench script (before bpy): ``bpy`` reads the BLENDER_USER_*
variables when it is imported, so they must be set before. They point at
``$LQLOD_BLENDER_HOME`` or ``<repo>/.blender-user`` (git-ignored), the same place
tools/env.sh uses, with HOME redirected too (tools/blender_env.py, shared with the tests),
so a bench never reads or writes the real ~/.config/blender.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
BENCH_DIR = Path(__file__).resolve().parent
DEFAULT_MESH_DIR = (REPO_ROOT / ".." / "shared" / "meshes").resolve()


def _isolate_blender_user_dirs() -> None:
    if "bpy" in sys.modules:
        raise RuntimeError("bench/_bootstrap must be imported before bpy")
    from tools.blender_env import isolated_blender_env

    os.environ.update(isolated_blender_env(os.environ.get("LQLOD_BLENDER_HOME", REPO_ROOT / ".blender-user")))


for _p in (str(REPO_ROOT), str(BENCH_DIR)):
    if _p not in sys.path:
        sys.path.insert(0, _p)
_isolate_blender_user_dirs()
