"""core/ and addon/pure/ stay free of Blender: no Blender modules, only relative, stdlib or
numpy imports.

The same core runs inside Blender (as part of the extension package) and outside it
(tests, benchmarks, the command line's worker side), so a stray ``import bpy`` would
break everything outside Blender, and an absolute ``import core`` would break the
installed extension (there the package is ``bl_ext.<repo>.line_quadric_lod.core``).

addon/pure/ is the add-on's Blender-independent part (issue 32 §4): the same rules, and
its relative imports stay inside it or reach ``core`` (``from ... import core``; only its
gateway ``_core`` may also import ``core`` absolutely, for the top-level layout of tests
and benches). Nothing of the Blender side (addon/*.py) may be imported from it.
"""
from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path
from typing import Optional

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
CORE = REPO_ROOT / "core"
PURE = REPO_ROOT / "addon" / "pure"
PURE_PACKAGE = ("addon", "pure")
GATEWAY = "_core.py"  # addon/pure/_core.py: the one module that imports core absolutely too

BLENDER_MODULES = {"bpy", "mathutils", "bmesh", "bpy_extras", "bl_math", "gpu", "gpu_extras",
                   "bgl", "blf", "aud", "freestyle", "idprop", "imbuf", "addon_utils", "_bpy"}
ALLOWED_THIRD_PARTY = {"numpy"}
ALLOWED_TOP = (set(sys.stdlib_module_names) | ALLOWED_THIRD_PARTY | {"__future__"}) - BLENDER_MODULES
DYNAMIC_IMPORTERS = {"import_module", "__import__"}


def imports(source: str, filename: str = "<string>") -> list:
    """Every import of one module's source as (line, level, module, names): level 0 for
    an absolute import (``import a.b`` gives module "a.b"), the dots of a relative one.
    Imports inside functions count too, as do importlib.import_module("...") and
    __import__("...") with a literal name."""
    found = []
    for node in ast.walk(ast.parse(source, filename)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, 0, a.name, ()) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            found.append((node.lineno, node.level, node.module or "", tuple(a.name for a in node.names)))
        elif isinstance(node, ast.Call):
            func = node.func
            fname = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)
            if fname in DYNAMIC_IMPORTERS and node.args and isinstance(node.args[0], ast.Constant) \
                    and isinstance(node.args[0].value, str):
                found.append((node.lineno, 0, node.args[0].value, ()))
    return found


def absolute_problem(name: str, where: str, what: str) -> Optional[str]:
    """Why the absolute import of ``name`` is not allowed (``what`` names the package), or None."""
    top = name.split(".")[0]
    if top in BLENDER_MODULES:
        return f"{where}: imports Blender module {name!r}"
    if top not in ALLOWED_TOP:
        return f"{where}: absolute import of {name!r} ({what} may import only relative, stdlib or numpy modules)"
    return None


def import_violations(source: str, filename: str = "<string>", package_depth: int = 1) -> list[str]:
    """Problems with the imports of one module of core.

    package_depth: how many packages deep the module sits (core/x.py -> 1,
    core/sub/x.py -> 2); a relative import going up further leaves core/.
    """
    problems = []
    for line, level, module, _ in imports(source, filename):
        if level > package_depth:
            problems.append(f"{filename}:{line}: relative import leaves core/ ({'.' * level}{module})")
        elif level == 0:
            problems.append(absolute_problem(module, f"{filename}:{line}", "core"))
    return [p for p in problems if p]


def pure_import_violations(source: str, filename: str = "<string>", package: tuple = PURE_PACKAGE,
                           gateway: bool = False) -> list[str]:
    """Problems with the imports of one module of addon/pure/, sitting in ``package``
    (("addon", "pure") for addon/pure/x.py): a relative import must reach a module of the
    pure package or ``core`` (the repository's top level: ``from ... import core``);
    absolute ones follow core's rules, except that the gateway (``gateway``: _core.py)
    may import ``core`` itself."""
    problems = []
    for line, level, module, names in imports(source, filename):
        where = f"{filename}:{line}"
        if level == 0:
            if not (gateway and module.split(".")[0] == "core"):
                problems.append(absolute_problem(module, where, "addon/pure"))
            continue
        if level > len(package) + 1:
            problems.append(f"{where}: relative import leaves the repository ({'.' * level}{module})")
            continue
        base = list(package[:len(package) - level + 1]) + (module.split(".") if module else [])
        # ``from <pkg> import a, b``: a and b may be modules of <pkg>, so each is checked.
        targets = [base] if _allowed_target(base) else [base + [n] for n in names]
        for target in targets:
            if not _allowed_target(target):
                problems.append(f"{where}: relative import of {'.'.join(target) or '(the top level)'} "
                                f"(addon/pure may reach only its own modules and core)")
    return [p for p in problems if p]


def _allowed_target(parts: list) -> bool:
    return parts[:len(PURE_PACKAGE)] == list(PURE_PACKAGE) or parts[:1] == ["core"]


def core_files() -> list[Path]:
    return sorted(p for p in CORE.rglob("*.py") if "__pycache__" not in p.parts)


def test_core_exists_and_has_modules():
    files = core_files()
    assert (CORE / "__init__.py") in files
    assert len(files) >= 2, files


def test_core_imports_are_pure():
    problems = []
    for path in core_files():
        rel = path.relative_to(REPO_ROOT)
        problems += import_violations(path.read_text(encoding="utf-8"), str(rel), len(rel.parts) - 1)
    assert not problems, "core/ must stay pure NumPy:\n" + "\n".join(problems)


# Sources each checker must flag, and sources it must accept.
OFFENDING = {"core": [
    "import bpy",
    "import bpy.types",
    "from mathutils import Vector",
    "import bmesh",
    "from bmesh import ops",
    "import numpy, bpy",
    "def f():\n    import mathutils\n    return mathutils",
    "try:\n    import bpy\nexcept ImportError:\n    bpy = None",
    "import importlib\nbpy = importlib.import_module('bpy')",
    "bm = __import__('bmesh')",
    "import core.simplify",
    "from addon import ops",
    "import scipy.sparse",
    "from .. import addon",
], "pure": [
    "import bpy",
    "from mathutils.bvhtree import BVHTree",
    "def f():\n    import bmesh",
    "import importlib\nbpy = importlib.import_module('bpy')",
    "from .. import lod",
    "from .. import bvh, mesh_io",
    "from ..mesh_io import read_object",
    "from ..headless import report",
    "from ... import addon",
    "from .... import core",
    "import core",
    "import addon.pure.measure",
    "import scipy",
]}
CLEAN = {"core": [
    "import numpy as np",
    "from numpy.linalg import eigh",
    "from . import result",
    "from .simplify import simplify",
    "import math, heapq, time\nfrom dataclasses import dataclass",
    "from __future__ import annotations",
    "from typing import TYPE_CHECKING",
], "pure": [
    "import numpy as np",
    "from . import measure",
    "from . import deviation_targets, switch_distances",
    "from .settings import LodError",
    "from ._core import core",
    "from ... import core",
    "from ...core import options",
    "from .. import pure",
    "def f():\n    from .mesh_data import ColorLayer",
    "from __future__ import annotations\nimport math, zlib",
]}
CHECKERS = {"core": import_violations, "pure": pure_import_violations}


@pytest.mark.parametrize("checker,source", [(c, s) for c, sources in OFFENDING.items() for s in sources])
def test_checker_flags_offending_source(checker, source):
    assert CHECKERS[checker](source), f"{checker} checker missed: {source!r}"


@pytest.mark.parametrize("checker,source", [(c, s) for c, sources in CLEAN.items() for s in sources])
def test_checker_accepts_clean_source(checker, source):
    assert CHECKERS[checker](source) == []


def test_relative_import_depth_follows_package_depth():
    assert import_violations("from .. import x", package_depth=2) == []
    assert import_violations("from ... import x", package_depth=2)


def pure_files() -> list[Path]:
    return sorted(p for p in PURE.rglob("*.py") if "__pycache__" not in p.parts)


def test_pure_package_exists():
    files = pure_files()
    assert (PURE / "__init__.py") in files and (PURE / GATEWAY) in files
    assert len(files) >= 10, files


def test_pure_imports_are_free_of_blender():
    problems = []
    for path in pure_files():
        rel = path.relative_to(REPO_ROOT)
        problems += pure_import_violations(path.read_text(encoding="utf-8"), str(rel), tuple(rel.parts[:-1]),
                                           gateway=path.name == GATEWAY)
    assert not problems, "addon/pure/ must stay free of Blender:\n" + "\n".join(problems)




def test_only_the_gateway_imports_core_absolutely():
    assert pure_import_violations("import core", gateway=True) == []
    assert pure_import_violations("import core")
    assert pure_import_violations("import bpy", gateway=True)


def blender_modules_loaded_by(modules: list) -> tuple:
    """(exit code, the Blender modules loaded, stderr's end) of a clean interpreter that
    imports ``modules``: what static analysis cannot catch (an import hidden behind a
    helper module) shows here."""
    code = ("import sys, importlib; sys.path.insert(0, sys.argv[1]); "
            f"[importlib.import_module(m) for m in {modules!r}]; "
            f"bad = sorted(m for m in sys.modules if m.split('.')[0] in {sorted(BLENDER_MODULES)!r}); "
            "print(','.join(bad)); sys.exit(1 if bad else 0)")
    proc = subprocess.run([sys.executable, "-c", code, str(REPO_ROOT)],
                          capture_output=True, text=True, timeout=120)
    return proc.returncode, proc.stdout.strip(), proc.stderr[-2000:]


def test_importing_the_pure_package_loads_no_blender_module():
    # Every module of addon/pure (the add-on's package, which importing them runs, included).
    code, loaded, err = blender_modules_loaded_by([f"addon.pure.{p.stem}" for p in pure_files()
                                                   if p.name != "__init__.py"])
    assert code == 0, f"importing addon/pure loaded: {loaded} {err}"


def test_importing_core_loads_no_blender_module():
    code, loaded, err = blender_modules_loaded_by(["core"])
    assert code == 0, f"importing core loaded: {loaded} {err}"
