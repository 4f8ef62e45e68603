"""Blender user folders redirected into one directory, for tests and benchmarks alike.

``bpy`` (and a Blender child process) reads the BLENDER_USER_* variables when it starts,
so they must be set before; HOME is redirected too, so nothing can fall back to the real
``~/.config/blender``. Development tooling only: never part of the extension.
"""
from __future__ import annotations

from pathlib import Path


def isolated_blender_env(base_dir) -> dict:
    """Environment overrides that keep Blender inside ``base_dir`` (creates the folders).

    Returns only the overrides: merge them into ``os.environ`` (this process, before
    ``import bpy``) or into a child process's environment.
    """
    base = Path(base_dir).resolve()
    dirs = {
        "BLENDER_USER_RESOURCES": base,
        "BLENDER_USER_CONFIG": base / "config",
        "BLENDER_USER_SCRIPTS": base / "scripts",
        "BLENDER_USER_DATAFILES": base / "datafiles",
        "BLENDER_USER_EXTENSIONS": base / "extensions",
        "HOME": base / "home",
    }
    for d in dirs.values():
        d.mkdir(parents=True, exist_ok=True)
    env = {k: str(v) for k, v in dirs.items()}
    env["PYTHONNOUSERSITE"] = "1"
    return env
