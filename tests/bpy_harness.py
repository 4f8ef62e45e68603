"""The shared way for tests to run Blender (the ``bpy`` module) and the extension tool.

Why a subprocess: ``bpy`` can be imported only once per process and keeps global state
(scene, preferences, registered classes), so every Blender check runs in a fresh child
of the test interpreter (``sys.executable``, i.e. ``.venv/bin/python``). A child costs
about 0.5-2 s to start: put several checks into one scenario rather than one per test.

Isolation: the child gets ``isolated_blender_env(user_dir)``: every ``BLENDER_USER_*``
variable and ``HOME`` point inside ``user_dir``, so the real ``~/.config/blender`` is
never read or written.

Installing the extension (what works with bpy 4.5, measured): the bpy module starts
with factory preferences and does *not* read ``userpref.blend`` on import. So
``install_extension()`` runs one child that calls
``bpy.ops.extensions.package_install_files(filepath=zip, repo="user_default",
enable_on_install=True)`` and then ``bpy.ops.wm.save_userpref()``; every later child
calls ``bpy.ops.wm.read_userpref()`` before the scenario, which re-enables the installed
extension exactly as Blender does at start-up. A marker file in ``user_dir`` records the
installed zip's hash, so the install happens once per user dir (the session fixture
``blender_user_dir`` in conftest.py does it once per test session).

Writing a scenario for ``run_scenario``: a file tests/scenarios/<name>.py, imported in the
child after bpy (tests/scenarios/ and tests/ are on sys.path, so it can import
``scene_tools`` and ``bpy_harness``; the checkout is appended, so ``import core`` gives the
development copy of the pure-NumPy core). Its ``run(**params)`` returns JSON-serialisable
values; ``run_scenario`` returns them. An uncaught exception in the scenario makes
``run_scenario`` raise ``BlenderError`` carrying the child's traceback and output tail.

Unregister what you register: measured with bpy 4.5, a class registered by hand (outside
an add-on's register()) and left registered makes the interpreter hang at exit. The
harness kills a child that has not exited EXIT_GRACE_SECONDS after its scenario finished
and raises BlenderError saying so. Add-ons enabled through preferences are unregistered
by Blender at exit and do not hang.

Example (tests/scenarios/monkey_faces.py, then the test)::

    import bpy

    def run(size: float) -> dict:
        bpy.ops.mesh.primitive_monkey_add(size=size)
        return {"faces": len(bpy.context.active_object.data.polygons)}

    from bpy_harness import run_scenario
    def test_ops(blender_user_dir):
        r = run_scenario("monkey_faces", {"size": 2.0}, user_dir=blender_user_dir)
        assert r["faces"] == 500, f"expected the monkey's 500 faces, got {r['faces']}"
"""
from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parent.parent
if str(REPO_ROOT) not in sys.path:
    sys.path.insert(0, str(REPO_ROOT))
from tools.blender_env import isolated_blender_env  # noqa: E402  (re-exported for the tests)

EXTENSION_ID = "line_quadric_lod"
REPO_MODULE = "user_default"
EXT_MODULE = f"bl_ext.{REPO_MODULE}.{EXTENSION_ID}"

_INSTALL_MARKER = "line_quadric_lod.installed"
# How long a child may take to exit after its scenario wrote the result (normal: < 1 s).
EXIT_GRACE_SECONDS = 30


class BlenderError(RuntimeError):
    """A Blender child process (or the extension tool) failed."""


def bpy_scripts_dir() -> Path:
    """The ``scripts`` folder inside the installed bpy wheel, found without importing bpy."""
    import importlib.util

    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        raise BlenderError("the bpy module is not installed in this interpreter: run ./lod.sh test")
    pkg = Path(next(iter(spec.submodule_search_locations)))
    found = sorted(pkg.glob("[0-9]*.[0-9]*/scripts"))
    if not found:
        raise BlenderError(f"no <version>/scripts folder in the bpy package at {pkg}")
    return found[-1]


def blender_ext_tool() -> Path:
    """Blender's own extension tool (same code as ``blender -c extension ...``)."""
    return bpy_scripts_dir() / "addons_core" / "bl_pkg" / "cli" / "blender_ext.py"


def blender_valid_tags() -> Path:
    """The tag list ``blender -c extension build/validate`` enforces (blender_ext.py alone does not)."""
    return bpy_scripts_dir() / "modules" / "_bpy_internal" / "extensions" / "tags.py"


def _run_tool(args: list[str], timeout: float = 120) -> subprocess.CompletedProcess:
    cmd = [sys.executable, str(blender_ext_tool()), *args]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        raise BlenderError(
            f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}"
        )
    return proc


def validate(source=REPO_ROOT) -> str:
    """Validate a source folder or a built zip with the official tool and Blender's tag list.

    Returns the tool's output; raises BlenderError on any validation error.
    """
    return _run_tool(["validate", str(source), "--valid-tags", str(blender_valid_tags())]).stdout


def build_extension_zip(out_dir, source_dir=REPO_ROOT) -> Path:
    """Build ``line_quadric_lod-<version>.zip`` into ``out_dir`` with the official tool."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    _run_tool([
        "build",
        "--source-dir", str(source_dir),
        "--output-dir", str(out),
        "--valid-tags", str(blender_valid_tags()),
    ])
    zips = sorted(out.glob(f"{EXTENSION_ID}-*.zip"), key=lambda p: p.stat().st_mtime)
    if not zips:
        raise BlenderError(f"the extension tool reported success but wrote no zip into {out}")
    return zips[-1]


def _tail(path: Path, n: int) -> str:
    try:
        return path.read_text(encoding="utf-8", errors="replace")[-n:]
    except FileNotFoundError:
        return ""


CHILD_PROGRAM = Path(__file__).resolve().parent / "blender_child.py"
SCENARIOS_DIR = Path(__file__).resolve().parent / "scenarios"


def _run_child(user_dir: Path, timeout: float, load_prefs: bool, scenario: Path, params: dict = None) -> dict:
    """Run blender_child.py on a scenario file with ``params``; return what it returned,
    or raise BlenderError with the child's traceback and output."""
    user_dir = Path(user_dir)
    work = user_dir / "runs"
    work.mkdir(parents=True, exist_ok=True)
    tag = f"{os.getpid()}_{os.urandom(6).hex()}"
    files = {k: work / f"{k}_{tag}{ext}" for k, ext in (
        ("result", ".json"), ("stdout", ".txt"), ("stderr", ".txt"), ("params", ".json"))}
    files["params"].write_text(json.dumps(params or {}), encoding="utf-8")
    env = {**os.environ, **isolated_blender_env(user_dir)}
    cmd = [sys.executable, str(CHILD_PROGRAM), str(files["result"]), str(REPO_ROOT),
           "1" if load_prefs else "0", str(scenario), str(files["params"])]
    try:
        with open(files["stdout"], "wb") as out, open(files["stderr"], "wb") as err:
            proc = subprocess.Popen(cmd, stdout=out, stderr=err, env=env, cwd=str(work))
            start = time.monotonic()
            finished_at = None
            while proc.poll() is None:
                now = time.monotonic()
                if finished_at is None and files["result"].exists():
                    finished_at = now
                if finished_at is not None and now - finished_at > EXIT_GRACE_SECONDS:
                    # Measured with bpy 4.5: a class registered by hand (not through an
                    # add-on's register()) and left registered makes interpreter exit hang.
                    proc.kill()
                    proc.wait()
                    raise BlenderError(
                        f"the scenario finished but Blender did not exit within {EXIT_GRACE_SECONDS} s; "
                        "usually a bpy class registered outside an add-on was left registered.\n"
                        f"--- stderr (tail) ---\n{_tail(files['stderr'], 4000)}")
                if now - start > timeout:
                    proc.kill()
                    proc.wait()
                    raise BlenderError(
                        f"Blender scenario timed out after {timeout} s.\n"
                        f"--- stderr (tail) ---\n{_tail(files['stderr'], 4000)}\n"
                        f"--- stdout (tail) ---\n{_tail(files['stdout'], 2000)}")
                time.sleep(0.05)
        report = json.loads(files["result"].read_text(encoding="utf-8")) if files["result"].exists() else None
        if report is None or not report["ok"] or proc.returncode != 0:
            raise BlenderError(
                f"Blender scenario failed (exit {proc.returncode}).\n"
                + (f"--- scenario traceback ---\n{report['traceback']}\n" if report and not report["ok"] else "")
                + f"--- stderr (tail) ---\n{_tail(files['stderr'], 6000)}\n"
                f"--- stdout (tail) ---\n{_tail(files['stdout'], 3000)}"
            )
        return report["result"]
    finally:
        for p in (*files.values(), files["result"].with_name(files["result"].name + ".tmp")):
            p.unlink(missing_ok=True)


def _sha256(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def install_extension(zip_path, user_dir, timeout: float = 300) -> dict:
    """Install + enable the zip in ``user_dir`` and save the preferences; once per zip.

    Returns what the install child reported ({"enabled": bool, "installed_dir": str}).
    """
    user_dir = Path(user_dir)
    marker = user_dir / _INSTALL_MARKER
    digest = _sha256(zip_path)
    if marker.exists():
        saved = json.loads(marker.read_text(encoding="utf-8"))
        if saved.get("sha256") == digest:
            return saved["report"]
    report = _run_child(user_dir, timeout, load_prefs=False, scenario=SCENARIOS_DIR / "install_extension.py",
                        params={"zip_path": str(Path(zip_path).resolve()), "repo": REPO_MODULE})
    marker.write_text(json.dumps({"sha256": digest, "report": report}), encoding="utf-8")
    return report


def _ensure_installed(user_dir, install: bool, zip_path) -> None:
    """With install=True: the extension is installed in ``user_dir`` (built from this
    checkout unless ``zip_path`` is given, and only if not installed there already)."""
    user_dir = Path(user_dir)
    if install:
        if zip_path is None and not (user_dir / _INSTALL_MARKER).exists():
            zip_path = build_extension_zip(user_dir / "dist")
        if zip_path is not None:
            install_extension(zip_path, user_dir)


def run_scenario(name: str, params: dict = None, *, user_dir, timeout: float = 600, install: bool = True,
                 zip_path=None) -> dict:
    """Run ``run(**params)`` of tests/scenarios/<name>.py in a fresh bpy child with isolated
    user dirs; return what it returned (JSON-serialisable, through JSON).

    ``params`` go through JSON too (paths as strings). install=True: the extension is
    installed in ``user_dir`` (built from this checkout unless ``zip_path`` is given, and
    only if not installed there already) and enabled through the saved preferences before
    the scenario runs. install=False: factory Blender, the extension is not loaded
    (``import core`` still works). Raises BlenderError with the child's traceback and
    stderr tail if the scenario fails or outlives ``timeout`` seconds.
    """
    scenario = SCENARIOS_DIR / f"{name}.py"
    if not scenario.is_file():
        raise BlenderError(f"no scenario {scenario}")
    _ensure_installed(user_dir, install, zip_path)
    return _run_child(user_dir, timeout, load_prefs=install, scenario=scenario, params=params)
