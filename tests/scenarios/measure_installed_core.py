"""The installed extension's addon/pure/measure.py reaches its own core (tests/test_measure.py)."""
import sys

import numpy as np
from bpy_harness import EXT_MODULE
from scene_tools import extension_module


def run() -> dict:
    measure = extension_module("addon.pure.measure")
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    f = np.array([[0, 1, 2], [1, 3, 2]])
    up = np.tile([0.0, 0.0, 1.0], (2, 3, 1))
    report = measure.mesh_report(v, f, v + [0.0, 0.0, 0.25], f, n_samples=1000, normals=(up, up))
    return {"hausdorff": report["hausdorff"], "mean_quality": report["mean_quality"],
            "normal_max_degrees": report["normal_max_degrees"],
            "ext_core": (EXT_MODULE + ".core") in sys.modules, "top_core": "core" in sys.modules}
