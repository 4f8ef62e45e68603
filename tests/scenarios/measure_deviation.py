"""addon/measure.py (the checkout's copy) on meshes the test wrote to an .npz file: known
distances, the mesh report, and what invalid input raises (tests/test_measure.py checks
what this returns). Runs without the extension installed."""
import numpy as np

import core
from addon import measure


def run(meshes_npz: str) -> dict:
    d = np.load(meshes_npz)

    def deviation(a, b, **kwargs):
        return measure.surface_deviation(d[a + "_v"], d[a + "_f"], d[b + "_v"], d[b + "_f"], **kwargs)

    result = {
        "identical": deviation("plane", "plane", n_samples=20_000),
        "shifted": deviation("plane", "shifted", n_samples=20_000),
        "sphere": deviation("fine", "coarse", n_samples=50_000),
        "sphere_swapped": deviation("coarse", "fine", n_samples=50_000),
        "density": deviation("plane", "shifted", samples_per_unit_area=1000),
        "report": measure.mesh_report(d["fine_v"], d["fine_f"], d["coarse_v"], d["coarse_f"], n_samples=5000),
        "core_quality": core.quality_summary(d["coarse_v"], d["coarse_f"]),
    }
    invalid_calls = {
        "empty": lambda: deviation("plane", "empty"),
        "index": lambda: measure.surface_deviation(d["plane_v"], d["plane_f"] + 1000, d["plane_v"], d["plane_f"]),
        "both_counts": lambda: deviation("plane", "plane", n_samples=10, samples_per_unit_area=10),
        "nan": lambda: measure.surface_deviation(d["plane_v"] * np.nan, d["plane_f"], d["plane_v"], d["plane_f"]),
    }
    errors = {}
    for name, call in invalid_calls.items():
        try:
            call()
            errors[name] = None
        except ValueError as ex:
            errors[name] = str(ex)
    result["errors"] = errors
    return result
