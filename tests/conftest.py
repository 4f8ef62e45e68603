"""Shared pytest setup: the repo root on sys.path (tests import ``core`` as a top-level
package) and session-scoped Blender fixtures, so one test session builds and installs
the extension exactly once however many bpy test files use it. See bpy_harness.py."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
for p in (str(REPO_ROOT), str(Path(__file__).resolve().parent)):
    if p not in sys.path:
        sys.path.insert(0, p)

import bpy_harness  # noqa: E402  (needs the path set above)


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO_ROOT


@pytest.fixture(scope="session")
def extension_zip(tmp_path_factory) -> Path:
    """line_quadric_lod-<version>.zip built from this checkout by Blender's own tool."""
    return bpy_harness.build_extension_zip(tmp_path_factory.mktemp("dist"))


@pytest.fixture(scope="session")
def blender_user_dir(tmp_path_factory, extension_zip) -> Path:
    """An isolated Blender user dir with the extension installed and enabled in its saved
    preferences. Pass it as ``user_dir=`` to ``bpy_harness.run_scenario``."""
    user_dir = tmp_path_factory.mktemp("blender_user")
    bpy_harness.install_extension(extension_zip, user_dir)
    return user_dir


def pytest_collection_modifyitems(config, items):
    # `./lod.sh test -m "not blender"` skips the bpy subprocess tests that use the shared
    # install; tests that start Blender some other way mark themselves.
    for item in items:
        if {"blender_user_dir", "extension_zip"} & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.blender)
