"""The extension packaged the official way: Blender's own tool validates the checkout and
builds line_quadric_lod-<version>.zip, the zip carries only the add-on, and bpy 4.5
installs and enables it in an isolated user dir with its operators registered."""
from __future__ import annotations

import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

import bpy_harness
from bpy_harness import run_scenario

OPERATORS = ("line_quadric_lod", "line_quadric_lod_paint", "line_quadric_lod_from_armature",
             "line_quadric_lod_from_shape_keys")
DEV_ONLY_TOP = ("tests/", "docs/", "bench/", ".ci/", "tools/", ".venv/", ".venvs/", ".blender-user/", "out/", "dist/")
DEV_ONLY_FILES = ("lod.sh", "requirements-dev.txt", "requirements-peers.txt", "pyproject.toml", ".gitignore")


@pytest.fixture(scope="module")
def manifest(repo_root):
    with open(repo_root / "blender_manifest.toml", "rb") as fh:
        return tomllib.load(fh)


@pytest.fixture(scope="module")
def zip_names(extension_zip):
    with zipfile.ZipFile(extension_zip) as zf:
        return zf.namelist()


def test_manifest_declares_the_extension(manifest):
    assert manifest["schema_version"] == "1.0.0"
    assert manifest["id"] == "line_quadric_lod"
    assert manifest["name"] == "Line Quadric LOD"
    assert manifest["type"] == "add-on"
    assert manifest["blender_version_min"] == "4.2.0"
    assert manifest["license"] == ["SPDX:GPL-3.0-or-later"]
    # Only the permission the command line needs (it writes LOD files).
    assert set(manifest["permissions"]) == {"files"}


def test_checkout_validates_with_official_tool(repo_root):
    out = bpy_harness.validate(repo_root)
    assert "Success" in out, out


def test_zip_validates_and_is_named_after_manifest(extension_zip, manifest):
    assert extension_zip.name == f"{manifest['id']}-{manifest['version']}.zip"
    out = bpy_harness.validate(extension_zip)
    assert "Success" in out, out


def test_zip_holds_the_addon_and_no_development_files(zip_names, repo_root):
    names = set(zip_names)
    for required in ("blender_manifest.toml", "__init__.py", "LICENSE",
                     "core/__init__.py", "addon/__init__.py"):
        assert required in names, f"{required} missing from the zip"
    leaked = sorted(n for n in names
                    if n.startswith(DEV_ONLY_TOP) or n in DEV_ONLY_FILES
                    or "__pycache__/" in n or n.endswith((".pyc", ".blend1"))
                    or any(part.startswith(".") for part in n.split("/")))
    assert not leaked, f"development files in the zip: {leaked}"
    # Nothing the add-on needs was excluded by an over-broad pattern.
    shipped = {p.relative_to(repo_root).as_posix()
               for pkg in ("core", "addon") for p in (repo_root / pkg).rglob("*.py")
               if "__pycache__" not in p.parts}
    assert shipped <= names, f"package files missing from the zip: {sorted(shipped - names)}"


def test_root_package_imports_without_bpy(repo_root):
    # Installed, the checkout root is the package bl_ext.user_default.line_quadric_lod; importing
    # it (and its core) must not need Blender, only register() may.
    code = (
        "import importlib.util, sys\n"
        "root = sys.argv[1]\n"
        "spec = importlib.util.spec_from_file_location('line_quadric_lod', root + '/__init__.py',"
        " submodule_search_locations=[root])\n"
        "mod = importlib.util.module_from_spec(spec); sys.modules['line_quadric_lod'] = mod\n"
        "spec.loader.exec_module(mod)\n"
        "import line_quadric_lod.core\n"
        "assert callable(mod.register) and callable(mod.unregister)\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('bpy', 'mathutils', 'bmesh'))\n"
        "assert not bad, bad\n"
    )
    proc = subprocess.run([sys.executable, "-c", code, str(repo_root)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]


@pytest.fixture(scope="module")
def installed(blender_user_dir):
    return (run_scenario("packaging_install", {"operators": list(OPERATORS)}, user_dir=blender_user_dir),
            Path(blender_user_dir))


def test_extension_installs_into_isolated_user_dir_and_is_enabled(installed):
    r, user_dir = installed
    assert r["enabled"], "the extension is not enabled after reading the saved preferences"
    assert all(p and Path(p).is_absolute() for p in r["user_paths"]), r["user_paths"]
    outside = [p for p in r["user_paths"] if not Path(p).resolve().is_relative_to(user_dir.resolve())]
    assert not outside, f"Blender user paths outside the isolated dir: {outside}"
    expected = user_dir.resolve() / "extensions" / "user_default" / "line_quadric_lod" / "__init__.py"
    assert r["ext_file"] and Path(r["ext_file"]).resolve() == expected
    assert r["ext_modules_outside"] == [], "extension modules loaded from outside the install"


@pytest.mark.parametrize("name", OPERATORS)
def test_operator_registered(installed, name):
    op = installed[0]["ops"][name]
    assert op["hasattr"] and op["listed"], f"bpy.ops.object.{name} is not registered"
    assert op["identifier"] == "OBJECT_OT_" + name
    assert op["in_types"], f"bpy.types has no {op['identifier']}"


def test_disable_unregisters_and_enable_restores(installed):
    r = installed[0]
    assert r["ops_after_disable"] == {n: False for n in OPERATORS}
    assert r["ops_after_enable"] == {n: True for n in OPERATORS}
