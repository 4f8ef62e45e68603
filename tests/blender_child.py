"""The program every Blender child of the tests runs (started by bpy_harness, never by hand).

It imports bpy, restores the saved preferences (which enable the installed extension),
runs one scenario and writes the outcome as JSON for the parent:

    blender_child.py RESULT.json REPO_ROOT LOAD_PREFS(0|1) SCENARIO.py PARAMS.json

SCENARIO.py (tests/scenarios/) is imported as a module and its ``run(**params)`` called;
what it returns is the result. The outcome file holds {"ok": true, "result": ...} or
{"ok": false, "traceback": ...}; the parent raises BlenderError on the latter. Kept free
of test logic.
"""
import importlib.util
import json
import os
import sys
import traceback
from pathlib import Path

SCENARIOS_DIR = Path(__file__).resolve().parent / "scenarios"


def _enable_extension(ext_module: str) -> None:
    import bpy

    if bpy.app.version < (4, 3, 0):
        # The bpy module of Blender 4.2 crashes (signal 11) in wm.read_userpref(), also with
        # no add-on installed and no preferences saved: enable the installed extension the
        # way its saved preferences would (docs/install.md, tested versions).
        import addon_utils

        addon_utils.enable(ext_module, default_set=True, persistent=True)
    else:
        bpy.ops.wm.read_userpref()


def _run_scenario(path: str, params_path: str):
    spec = importlib.util.spec_from_file_location(Path(path).stem, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses and pickling look their module up
    spec.loader.exec_module(module)
    params = json.loads(Path(params_path).read_text(encoding="utf-8"))
    return module.run(**params)


def main(argv: list) -> int:
    result_path, repo_root, load_prefs, scenario_path, params_path = argv
    # Appended, not prepended: the installed extension's own modules come first; the
    # checkout's top-level ``core`` and ``addon`` are importable for tests that want them.
    sys.path.append(repo_root)
    sys.path.insert(0, str(SCENARIOS_DIR))
    from bpy_harness import EXT_MODULE

    import bpy  # noqa: F401  (before anything else of Blender's)

    if load_prefs == "1":
        _enable_extension(EXT_MODULE)
    try:
        result = _run_scenario(scenario_path, params_path)
        outcome = {"ok": True, "result": result}
        json.dumps(outcome)
    except BaseException:
        outcome = {"ok": False, "traceback": traceback.format_exc()}
    with open(result_path + ".tmp", "w", encoding="utf-8") as fh:
        json.dump(outcome, fh)
    os.replace(result_path + ".tmp", result_path)
    return 0 if outcome["ok"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
