"""tools/env.sh picks the Blender line, its virtualenv and the Python its bpy module needs
(issue 23), and says what to install when that Python is missing. Runs the shell
functions in a copy of the checkout's tools, so nothing is provisioned."""
import shutil
import subprocess

import pytest

from bpy_harness import REPO_ROOT


@pytest.fixture()
def checkout(tmp_path):
    (tmp_path / "tools").mkdir()
    shutil.copy(REPO_ROOT / "tools" / "env.sh", tmp_path / "tools" / "env.sh")
    shutil.copy(REPO_ROOT / "requirements-dev.txt", tmp_path / "requirements-dev.txt")
    return tmp_path


def bash(checkout, script, **env):
    full_env = {"PATH": "/usr/bin:/bin", "HOME": str(checkout), **env}
    return subprocess.run(["bash", "-c", f"source tools/env.sh; {script}"], cwd=checkout, env=full_env,
                          capture_output=True, text=True, timeout=60)


def test_default_line_is_the_pinned_one(checkout):
    pinned = next(line.split("==")[1].rstrip(".*") for line in (REPO_ROOT / "requirements-dev.txt").read_text().splitlines()
                  if line.startswith("bpy=="))
    out = bash(checkout, 'echo "$BLENDER $VENV $REQ"').stdout.split()
    assert out == [pinned, str(checkout / ".venv"), str(checkout / "requirements-dev.txt")]


def test_another_line_gets_its_own_venv_and_requirements(checkout):
    out = bash(checkout, 'echo "$BLENDER $VENV"; cat "$REQ"', LQLOD_BLENDER="5.2").stdout.splitlines()
    assert out[0] == f"5.2 {checkout / '.venvs' / 'blender-5.2'}"
    assert "bpy==5.2.*" in out[1:] and not any(line.startswith("bpy==4") for line in out[1:])
    assert "pytest>=7" in out[1:]  # the rest of the requirements is kept


@pytest.mark.parametrize("blender, python", [("4.2", "3.11"), ("4.5", "3.11"), ("5.0", "3.11"),
                                             ("5.1", "3.13"), ("5.2", "3.13")])
def test_python_for_each_line(checkout, blender, python):
    assert bash(checkout, f"python_for_blender {blender}").stdout.strip() == python


def test_missing_python_is_named_with_what_to_install(checkout):
    if shutil.which("python3.13", path="/usr/bin:/bin"):
        pytest.skip("this machine has a system python3.13, so nothing is missing")
    r = bash(checkout, "ensure_env", LQLOD_BLENDER="5.2", PYENV_ROOT=str(checkout / "no-pyenv"))
    assert r.returncode == 2
    assert "needs Python 3.13, and none was found" in r.stderr
    assert "pyenv install 3.13" in r.stderr and "PYTHON=/path/to/python3.13" in r.stderr
    assert not (checkout / ".venvs" / "blender-5.2" / "bin").exists()
