"""addon/pure/measure.py (the checkout's copy) on meshes the test wrote to an .npz file: known
distances and normal angles, the mesh report, and what invalid input raises (tests/test_measure.py checks
what this returns). Runs without the extension installed."""
import dataclasses

import numpy as np

import core
from addon.pure import measure
from scene_tools import value_errors


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
        "stray": deviation("stray", "plane", n_samples=20_000),
        "thin": deviation("thin", "plane", n_samples=20_000),
        "report": measure.mesh_report(d["fine_v"], d["fine_f"], d["coarse_v"], d["coarse_f"], n_samples=5000),
        "core_quality": core.quality_summary(d["coarse_v"], d["coarse_f"]),
    }
    # Shading normals (measure.normal_deviation): a coarser plane's, flat and tilted, and
    # a coarse sphere's smooth ones against a fine sphere's.
    up = core.shading.corner_normals(d["plane_v"], d["plane_f"], np.zeros(len(d["plane_f"]), bool))
    coarse_up = core.shading.corner_normals(d["coarse_plane_v"], d["coarse_plane_f"],
                                            np.zeros(len(d["coarse_plane_f"]), bool))
    tilt = np.radians(30.0)
    tilted = np.broadcast_to([np.sin(tilt), 0.0, np.cos(tilt)], coarse_up.shape)
    fine_n = core.shading.corner_normals(d["fine_v"], d["fine_f"], np.ones(len(d["fine_f"]), bool))
    coarse_n = core.shading.corner_normals(d["coarse_v"], d["coarse_f"], np.ones(len(d["coarse_f"]), bool))
    coarse_flat = core.shading.corner_normals(d["coarse_v"], d["coarse_f"], np.zeros(len(d["coarse_f"]), bool))

    def normals(a, b, na, nb, **kwargs):
        return measure.normal_deviation(d[a + "_v"], d[a + "_f"], na, d[b + "_v"], d[b + "_f"], nb,
                                        n_samples=20_000, **kwargs)

    result["normals_plane"] = normals("plane", "coarse_plane", up, coarse_up)
    result["normals_tilted"] = normals("plane", "coarse_plane", up, tilted)
    result["normals_sphere"] = normals("fine", "coarse", fine_n, coarse_n)
    result["normals_sphere_flat"] = normals("fine", "coarse", fine_n, coarse_flat)
    result["sphere_with_normals"] = deviation("fine", "coarse", n_samples=20_000, normals=(fine_n, coarse_n))
    result["sphere_without_normals"] = deviation("fine", "coarse", n_samples=20_000)
    # A region of src (measure.region_deviation): the left half of the plane, the right half, none.
    plane_v, plane_f = d["plane_v"], d["plane_f"]
    x = plane_v[plane_f][:, :, 0]
    left, right = x.max(axis=1) <= 0.5, x.min(axis=1) >= 0.7

    def regional(a, b, region):
        out = deviation(a, b, n_samples=20_000, keep_samples=True)
        out.update(measure.region_deviation(out.pop("sampled"), d[a + "_f"], region))
        return out

    result["region_shifted"] = regional("plane", "shifted", left)
    for name, region in (("left", left), ("right", right), ("none", np.zeros(len(plane_f), bool))):
        result["region_step_" + name] = regional("plane", "step", region)
        result["region_flap_" + name] = regional("plane", "flap", region)
    result["region_step_without"] = deviation("plane", "step", n_samples=20_000)
    # Half the plane stepped up: the other half's triangles are the source's, measured
    # without a search (core.geometry.same_triangles); every point comes back for the test
    # to check against a brute-force distance.
    kept = deviation("plane", "step", n_samples=3000, keep_samples=True)["sampled"]
    # (read as attributes: the closest points' coordinates are computed on first reading)
    fields = [f.name for f in dataclasses.fields(kept)]
    result["step_points"] = {k: np.asarray(getattr(kept, k)).tolist() for k in fields if getattr(kept, k) is not None}
    unkept = deviation("plane", "step", n_samples=10, keep_samples=True)["sampled"]
    invalid_calls = {
        "normals_shape": lambda: normals("plane", "coarse_plane", up[:-1], coarse_up),
        "normals_nan": lambda: normals("plane", "coarse_plane", up, coarse_up * np.nan),
        "empty": lambda: deviation("plane", "empty"),
        "index": lambda: measure.surface_deviation(d["plane_v"], d["plane_f"] + 1000, d["plane_v"], d["plane_f"]),
        "both_counts": lambda: deviation("plane", "plane", n_samples=10, samples_per_unit_area=10),
        "region_shape": lambda: measure.region_deviation(unkept, plane_f, left[:-1]),
        "nan": lambda: measure.surface_deviation(d["plane_v"] * np.nan, d["plane_f"], d["plane_v"], d["plane_f"]),
    }
    errors = value_errors(invalid_calls)
    result["errors"] = errors
    return result
