"""The installed extension: enabled from the saved preferences, loaded from the isolated
user dir, its operators registered, unregistered on disable and back on enable
(tests/test_packaging.py checks what this returns)."""
import os
import sys

import addon_utils
import bpy
from bpy_harness import EXT_MODULE


def operator_state(operators) -> dict:
    state = {}
    for name in operators:
        # hasattr(bpy.ops.object, name) is True for ANY name in bpy 4.5 (the lookup is lazy),
        # so registration is checked through dir() and the operator's RNA type.
        listed = name in dir(bpy.ops.object)
        ident = None
        if listed:
            ident = getattr(bpy.ops.object, name).get_rna_type().identifier
        state[name] = {"hasattr": hasattr(bpy.ops.object, name), "listed": listed,
                       "identifier": ident, "in_types": bool(ident) and hasattr(bpy.types, ident)}
    return state


def run(operators: list) -> dict:
    ext_package = sys.modules.get(EXT_MODULE)
    user_ext_dir = bpy.utils.user_resource("EXTENSIONS")
    result = {
        "enabled": EXT_MODULE in {a.module for a in bpy.context.preferences.addons},
        "ext_file": getattr(ext_package, "__file__", None),
        "user_ext_dir": user_ext_dir,
        "user_paths": [bpy.utils.user_resource(k) for k in ("CONFIG", "SCRIPTS", "DATAFILES", "EXTENSIONS")]
        + [os.path.expanduser("~")],
        "ext_modules_outside": sorted(
            name for name, m in list(sys.modules.items())
            if name.startswith(EXT_MODULE) and getattr(m, "__file__", None)
            and not os.path.realpath(m.__file__).startswith(os.path.realpath(user_ext_dir))),
        "ops": operator_state(operators),
    }
    addon_utils.disable(EXT_MODULE, default_set=True)
    result["ops_after_disable"] = {n: n in dir(bpy.ops.object) for n in operators}
    addon_utils.enable(EXT_MODULE, default_set=True, handle_error=None)
    result["ops_after_enable"] = {n: n in dir(bpy.ops.object) for n in operators}
    return result
