"""LODs by deviation through the command line (issue 22): --max-error in scene units or
percent of the bounding-box diagonal; the measured distance is within what was asked."""
import json
import os
import subprocess
import sys

import pytest

from bench.synthetic_meshes import uv_sphere
from bpy_harness import REPO_ROOT, isolated_blender_env


def run_cli(argv, cwd):
    env = {**os.environ, **isolated_blender_env(cwd / "user")}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), *argv], capture_output=True, text=True,
                          cwd=cwd, env=env, timeout=600)
    return proc.returncode, proc.stdout, proc.stderr


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    root = tmp_path_factory.mktemp("deviation")
    vertices, faces = uv_sphere(40)  # 6,240 triangles, radius 1: diagonal 2 * sqrt(3)
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    (root / "ball.obj").write_text("\n".join(lines) + "\n")
    return root


def test_each_lod_is_measured_within_its_deviation_and_close_to_it(sphere):
    report = sphere / "report.json"
    code, stdout, stderr = run_cli(["--input", str(sphere / "ball.obj"), "--max-error", "0.2%", "0.02", "1%",
                                    "--output-dir", str(sphere / "out"), "--format", "obj", "--report", str(report)],
                                   sphere)
    assert code == 0, stderr[-3000:]
    levels = json.loads(report.read_text())["files"][0]["objects"][0]["levels"][1:]
    assert len(levels) == 3, levels
    diagonal = 2.0 * 3 ** 0.5
    asked = [0.2, 0.02 / diagonal * 100.0, 1.0]
    for level, percent in zip(levels, asked):
        assert level["requested_deviation_percent"] == pytest.approx(percent), level
        assert level["hausdorff_percent"] <= percent, f"measured {level['hausdorff_percent']} for {percent} asked"
        assert level["hausdorff_percent"] >= 0.5 * percent, f"needlessly dense: {level['hausdorff_percent']} for {percent}"
        assert level["target"] is None
    triangles = [level["triangles"] for level in levels]
    assert triangles == sorted(triangles, reverse=True) and len(set(triangles)) == 3, triangles
    assert "<=0.2%" in stdout, stdout


def test_deviations_that_do_not_grow_or_are_not_numbers_are_named(sphere):
    code, _, stderr = run_cli(["--input", str(sphere / "ball.obj"), "--max-error", "1%", "0.5%",
                               "--output-dir", str(sphere / "bad")], sphere)
    assert code == 2 and "deviations must increase" in stderr, stderr[-2000:]  # before any input loads
    # Units and percentages compare only on a mesh (its diagonal, 3.46 here): 0.02 > 0.5 %.
    code, _, stderr = run_cli(["--input", str(sphere / "ball.obj"), "--max-error", "0.02", "0.5%",
                               "--output-dir", str(sphere / "bad")], sphere)
    assert code == 1 and "deviations must increase" in stderr and "diagonal" in stderr, stderr[-2000:]
    code, _, stderr = run_cli(["--input", str(sphere / "ball.obj"), "--screen-size", "1", "--screen-height", "0",
                               "--output-dir", str(sphere / "bad")], sphere)
    assert code == 2 and "--screen-height must be" in stderr and "Traceback" not in stderr, stderr[-2000:]
    code, _, stderr = run_cli(["--input", str(sphere / "ball.obj"), "--max-error", "abc",
                               "--output-dir", str(sphere / "bad")], sphere)
    assert code == 2 and "a percentage such as 0.5%" in stderr, stderr[-2000:]
    code, _, stderr = run_cli(["--input", str(sphere / "ball.obj"), "--max-error", "1%", "--ratios", "0.5",
                               "--output-dir", str(sphere / "bad")], sphere)
    assert code == 2 and "not allowed with" in stderr, stderr[-2000:]


def test_screen_size_with_lods_doubles_the_deviation_per_lod(sphere):
    report = sphere / "screen.json"
    code, stdout, stderr = run_cli(["--input", str(sphere / "ball.obj"), "--screen-size", "2", "--lods", "3",
                                    "--screen-height", "1000", "--output-dir", str(sphere / "screen"),
                                    "--format", "obj", "--report", str(report)], sphere)
    assert code == 0, stderr[-3000:]
    levels = json.loads(report.read_text())["files"][0]["objects"][0]["levels"][1:]
    asked = [level["requested_deviation_percent"] for level in levels]
    assert asked == pytest.approx([0.2, 0.4, 0.8]), "2 px of 1000, then at twice and four times the distance"
    assert all(level["hausdorff_percent"] <= pct for level, pct in zip(levels, asked)), levels


def test_the_view_of_the_switch_distances_is_set_on_the_command_line(sphere):
    out = sphere / "view"
    code, _, stderr = run_cli(["--input", str(sphere / "ball.obj"), "--ratios", "0.5", "--pixel-error", "2",
                               "--fov", "90", "--screen-height", "720", "--output-dir", str(out), "--format", "obj"],
                              sphere)
    assert code == 0, stderr[-3000:]
    sidecar = json.loads((out / "ball_LODs.lods.json").read_text())
    assert sidecar["view"] == {"pixel_error": 2.0, "screen_height": 720.0, "vertical_fov_degrees": 90.0}
    switch = sidecar["objects"][0]["switch"]
    # Culled where the whole object (2R) would be the pixel budget: R H / (PX tan(fov / 2)).
    assert switch["cull_distance"] == pytest.approx(switch["bounding_sphere_radius"] * 720 / 2.0), switch


def test_a_low_poly_mesh_gets_close_to_tight_bounds(tmp_path):
    """Where each collapse of the error-ordered sequence jumps past a tight bound (a
    low-poly mesh: the Fox kept 0.35x of 0.2 % that way), the core's tracked distance
    bound still finds a level close to it."""
    vertices, faces = uv_sphere(12)
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    (tmp_path / "pebble.obj").write_text("\n".join(lines) + "\n")
    report = tmp_path / "report.json"
    code, _, stderr = run_cli(["--input", str(tmp_path / "pebble.obj"), "--max-error", "0.5%", "2%",
                               "--output-dir", str(tmp_path / "out"), "--format", "obj", "--report", str(report)],
                              tmp_path)
    assert code == 0, stderr[-3000:]
    levels = json.loads(report.read_text())["files"][0]["objects"][0]["levels"][1:]
    assert [level["requested_deviation_percent"] for level in levels] == pytest.approx([0.5, 2.0])
    for level in levels:
        ratio = level["hausdorff_percent"] / level["requested_deviation_percent"]
        assert 0.5 <= ratio <= 1.0, (level["triangles"], ratio)
    assert levels[0]["triangles"] > levels[1]["triangles"]
