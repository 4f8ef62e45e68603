"""The command line on instances that geometry nodes draw (a scatter of rocks, bolts on a
panel): each becomes an object sharing its instanced geometry's mesh, simplified once and
counted per instance in the asset's budget; the instancer draws them no more. Before,
a scatter failed its file ('"Scatter": its modifiers leave no faces') and an object with
faces of its own lost its instances in every level. tests/scenarios/node_instances.py
makes the .blend."""
import json
import os
import subprocess
import sys

import pytest

from bpy_harness import REPO_ROOT, isolated_blender_env, run_scenario

RATIOS = (0.5, 0.25)


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    work = tmp_path_factory.mktemp("node_instances")
    scene = run_scenario("node_instances", {"blend_out": str(work / "scatter.blend")}, user_dir=work / "user",
                         install=False, timeout=600)
    out, report = work / "out", work / "report.json"
    env = {**os.environ, **isolated_blender_env(work / "user")}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), "--input", str(work / "scatter.blend"), "--ratios",
                           *map(str, RATIOS), "--output-dir", str(out), "--format", "blend", "--report", str(report)],
                          capture_output=True, text=True, cwd=work, env=env, timeout=600)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    written = run_scenario("node_instances", {"check": str(out / "scatter_LODs.blend")}, user_dir=work / "user",
                           install=False, timeout=600)
    return {"scene": scene, "entry": json.loads(report.read_text())["files"][0], "written": written,
            "stdout": proc.stdout}


def test_the_panel_names_instances_as_what_it_cannot_simplify(made):
    """Selected in the panel, the scatter is left out with the reason and the way out; an
    object that draws faces of its own beside instances gets LODs of its faces, with a
    note that its instances are not in them."""
    assert made["scene"]["scatter_reason"] == \
        "its geometry nodes draw only instances (Object > Convert > Mesh makes them faces)"
    count = len(made["scene"]["drawn"]["Field"]["instances"])
    assert f"the {count} instances its geometry nodes draw are not in its LODs (Object > Convert > Mesh " \
           f"makes them faces)" in made["scene"]["field_notes"], made["scene"]["field_notes"]


def test_each_instance_is_an_object_sharing_its_geometrys_lods(made):
    drawn = made["scene"]["drawn"]
    objects = {o["object"]: o for o in made["entry"]["objects"]}
    scatter = sorted(n for n in objects if n.startswith("Scatter."))
    cones = sorted(n for n in objects if n.startswith("Field."))
    assert len(scatter) == len(drawn["Scatter"]["instances"]) > 1, sorted(objects)
    assert len(cones) == len(drawn["Field"]["instances"]) > 1, sorted(objects)
    assert "Scatter" not in objects  # it draws nothing of its own
    for copies, instances in ((scatter, drawn["Scatter"]["instances"]), (cones, drawn["Field"]["instances"])):
        # One chain of meshes for all the copies of one instanced geometry.
        assert len({tuple(lv["mesh"] for lv in objects[n]["levels"]) for n in copies}) == 1
        assert sum(1 for n in copies if objects[n].get("shares") is None) == 1
        assert {objects[n]["source_triangles"] for n in copies} == set(instances)
    # The field's own grid is still a part, with its faces alone.
    assert objects["Field"]["source_triangles"] == drawn["Field"]["own"] > 0
    # The asset's budget counts every instance (a collapse in the shared icosphere takes
    # two triangles from each of its copies: the budget is met to that step).
    total = sum(of["own"] + sum(of["instances"]) for of in drawn.values())
    step = 2 * len(scatter)
    for level, ratio in zip(made["entry"]["asset"]["levels"], RATIOS):
        assert abs(level["triangles"] - ratio * total) <= max(step, 0.01 * ratio * total), (level, total)
    notes = [w for w in made["entry"]["warnings"] if "geometry nodes" in w]
    assert notes == [f'"Scatter": the {len(scatter)} instances its geometry nodes draw made real (1 mesh, shared), '
                     'its modifiers applied',
                     f'"Field": the {len(cones)} instances its geometry nodes draw made real (1 mesh, shared), '
                     'its modifiers applied'], made["entry"]["warnings"]
    assert not any("skipped" in w for w in made["entry"]["warnings"]), made["entry"]["warnings"]


def test_the_written_file_draws_each_instance_once(made):
    """The instancers' geometry-nodes modifiers are applied in the written file: the
    instances are drawn by the new objects (and their levels) alone."""
    written = made["written"]
    assert written["with_nodes"] == []
    assert sum(written["instances"].values()) == 0, written["instances"]
