"""The command line on a scene whose mesh several objects use (issue 32 §1): each LOD mesh
is written once to the .glb and every object keeps its own chain. Apart from
tests/test_addon_instances.py because it exports glTF, which crashes Blender 4.2's own
exporter in its bpy module (.ci/run leaves such files out on 4.2)."""
import json
from pathlib import Path
import os
import re
import subprocess
import sys

import pytest

from bpy_harness import REPO_ROOT, isolated_blender_env, run_scenario
from gltf_tools import glb_json
from test_addon_instances import res, work  # noqa: F401  (the scenario and the .blend it saves)


# ----------------------------------------------------------------------------- the command line


@pytest.fixture(scope="module")
def cli(work, res):
    out = work / "out"
    report = work / "report.json"
    env = {**os.environ, **isolated_blender_env(work / "user")}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), "--input", str(work / "instances.blend"),
                           "--ratios", "0.5", "0.25", "--output-dir", str(out), "--format", "glb",
                           "--report", str(report)],
                          capture_output=True, text=True, cwd=work, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return {"stdout": proc.stdout, "stderr": proc.stderr, "glb": glb_json(out / "instances_LODs.glb"),
            "report": json.loads(report.read_text())}


def test_cli_writes_each_lod_mesh_once(cli):
    gltf = cli["glb"]
    # Before: Part and SoloMesh plus two LOD meshes per object (4 objects): 10.
    assert sorted(m["name"] for m in gltf["meshes"]) == ["Part", "Part_LOD1", "Part_LOD2", "SoloMesh",
                                                         "Solo_LOD1", "Solo_LOD2"]
    mesh_of = {n["name"]: n.get("mesh") for n in gltf["nodes"]}
    for k in (1, 2):
        assert len({mesh_of[f"{name}_LOD{k}"] for name in ("A", "B", "C")}) == 1
        assert mesh_of[f"Solo_LOD{k}"] != mesh_of[f"A_LOD{k}"]
    # The file's objects are one asset (addon/asset.py): one MSFT_lod on its LOD0 subtree,
    # each level a node of its own holding every instance's LOD node of that level.
    index = {n["name"]: i for i, n in enumerate(gltf["nodes"])}
    tops = [n for n in gltf["nodes"] if "MSFT_lod" in n.get("extensions", {})]
    assert len(tops) == 1, [n["name"] for n in tops]
    ids = tops[0]["extensions"]["MSFT_lod"]["ids"]
    assert ids == [index["instances_LOD1"], index["instances_LOD2"]]
    for k, node in zip((1, 2), ids):
        children = sorted(gltf["nodes"][c]["name"] for c in gltf["nodes"][node]["children"])
        assert children == sorted(f"{name}_LOD{k}" for name in ("A", "B", "C", "Solo")), children


def test_cli_report_progress_and_table_count_each_mesh_once(cli):
    objects = {o["object"]: o for o in cli["report"]["files"][0]["objects"]}
    assert sorted(objects) == ["A", "B", "C", "Solo"]
    leaders = [n for n in ("A", "B", "C") if objects[n].get("shares") is None]
    assert len(leaders) == 1, leaders
    leader = leaders[0]
    for name in ("A", "B", "C"):
        o = objects[name]
        assert [lv["mesh"] for lv in o["levels"]] == ["Part", "Part_LOD1", "Part_LOD2"]
        assert [lv["name"] for lv in o["levels"]] == [f"{name}_LOD{k}" for k in range(3)]
        if name != leader:
            assert o["shares"] == leader and o["seconds"] == 0.0
            assert all(lv["seconds"] == 0.0 for lv in o["levels"])
    assert objects[leader]["seconds"] > 0 and objects["Solo"]["seconds"] > 0
    started = [line for line in cli["stderr"].splitlines() if re.search(r"triangles -> LOD1", line)]
    assert len(started) == 2, started  # one progress chain per mesh, not per object
    rows = [re.split(r"\s{2,}", line.strip()) for line in cli["stdout"].splitlines()]
    width = len(rows[0])  # the main table's columns (a shape-key column comes and goes with the keys)
    seconds = {cells[1]: cells[-1] for cells in rows if len(cells) == width and re.fullmatch(r"LOD[12]", cells[2])}
    for name in ("A", "B", "C"):
        for k in (1, 2):
            assert (seconds[f"{name}_LOD{k}"] == "shared") == (name != leader), seconds


# ------------------------------------------------------------------ collection instances

@pytest.fixture(scope="module")
def collection_cli(tmp_path_factory):
    """The command line on tests/scenarios/collection_instances.py's .blend."""
    work = tmp_path_factory.mktemp("collection_instances")
    made = run_scenario("collection_instances", {"blend_out": str(work / "bolts.blend"),
                                                 "shared_out": str(work / "shared.blend")},
                        user_dir=work / "user", install=False, timeout=600)
    out, report = work / "out", work / "report.json"
    env = {**os.environ, **isolated_blender_env(work / "user")}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), "--input", str(work / "bolts.blend"),
                           str(work / "shared.blend"), "--ratios", "0.5", "0.25", "--output-dir", str(out),
                           "--format", "glb", "--report", str(report)],
                          capture_output=True, text=True, cwd=work, env=env, timeout=600)
    files = {Path(f["input"]).name: f for f in json.loads(report.read_text())["files"]}
    assert files["bolts.blend"]["ok"], proc.stderr[-3000:]
    assert proc.returncode == (0 if files["shared.blend"]["ok"] else 1), proc.stderr[-3000:]
    shared_glb = out / "shared_LODs.glb"
    return {"glb": glb_json(out / "bolts_LODs.glb"), "report": {"files": [files["bolts.blend"]]},
            "shared": files["shared.blend"], "shared_glb": glb_json(shared_glb) if shared_glb.exists() else None,
            "work": work, **made}


def test_collection_instances_become_objects_that_share_the_bolts_lods(collection_cli):
    """Each instance of the bolt's collection is made an object of its own sharing the
    bolt's mesh: the bolt is simplified once, and the asset's budget counts it three
    times. The bolt itself, in an excluded collection, draws nothing and gets no LODs."""
    entry = collection_cli["report"]["files"][0]
    objects = {o["object"]: o for o in entry["objects"]}
    copies = sorted(name for name in objects if name != "Base")
    assert len(copies) == 3 and "Bolt" not in objects, sorted(objects)
    assert len({tuple(lv["mesh"] for lv in objects[name]["levels"]) for name in copies}) == 1
    assert sum(1 for name in copies if objects[name].get("shares") is None) == 1
    # One note for the collection, naming its three empties (a kitbash scene has dozens).
    made_real = [w for w in entry["warnings"] if "made real" in w]
    assert made_real == ['collection "Bolts": its 3 instances by "BoltInstance0", "BoltInstance1", '
                         '"BoltInstance2" made real (1 object each, sharing their meshes)'], entry["warnings"]
    assert any(w.startswith('"Bolt" skipped: not in the view layer') for w in entry["warnings"])
    drawn = objects["Base"]["source_triangles"] + 3 * collection_cli["bolt_triangles"]
    for level, ratio in zip(entry["asset"]["levels"], (0.5, 0.25)):
        assert abs(level["triangles"] - ratio * drawn) <= max(2, 0.01 * ratio * drawn), (level, drawn)


def test_each_instance_switches_with_the_asset_and_shows_one_level(collection_cli):
    """In the .glb every instance of the bolt is in each level's subtree once, with that
    level's mesh, and nowhere else: instanced, every instance showed all its levels at
    once, outside the asset's MSFT_lod."""
    gltf = collection_cli["glb"]
    nodes = gltf["nodes"]
    tops = [n for n in nodes if "MSFT_lod" in n.get("extensions", {})]
    assert len(tops) == 1, [n["name"] for n in tops]
    roots = [nodes.index(tops[0])] + tops[0]["extensions"]["MSFT_lod"]["ids"]

    def meshes_under(i):
        node = nodes[i]
        found = [gltf["meshes"][node["mesh"]]["name"]] if "mesh" in node else []
        for c in node.get("children", []):
            found += meshes_under(c)
        return found

    objects = collection_cli["report"]["files"][0]["objects"]
    bolt_meshes = next(o for o in objects if o["object"] != "Base")["levels"]
    bolt_meshes = [lv["mesh"] for lv in bolt_meshes]  # the shared LOD0, LOD1, LOD2 meshes
    assert len(set(bolt_meshes)) == 3
    for k, root in enumerate(roots):
        level = meshes_under(root)
        assert level.count(bolt_meshes[k]) == 3 and len(level) == 4, (k, level, bolt_meshes)
    # No bolt LOD beyond LOD0 is drawn outside its level's subtree.
    for lod_mesh in bolt_meshes[1:]:
        users = [n["name"] for n in nodes if "mesh" in n and gltf["meshes"][n["mesh"]]["name"] == lod_mesh]
        assert len(users) == 3, users


def test_an_asset_of_one_mesh_drawn_three_times_splits_its_budget_over_the_copies(collection_cli):
    """Every object of the file draws one mesh (one of them mirrored, one stretched): the
    asset's levels are what it draws, so each copy gets a third of each. Before, the one
    mesh got the asset's whole budget: LOD1's 1,452 triangles for its 968, an error. A
    cube whose Mask modifier leaves no faces is skipped with a note (it failed the file:
    '"Masked" has an empty mesh'), and so are a Boolean cutter and a collision box, which
    were parts before."""
    entry = collection_cli["shared"]
    assert entry["ok"], entry["error"]
    assert '"Masked" skipped: its modifiers leave no faces' in entry["warnings"], entry["warnings"]
    assert any(w.startswith('"Cutter" skipped: a Boolean modifier') for w in entry["warnings"]), entry["warnings"]
    assert any(w.startswith('"UCX_Right" skipped: a collision mesh') for w in entry["warnings"]), entry["warnings"]
    # The file's own "Right_LOD1" is no part, and is not written: drawn at every distance
    # it would lie on the new levels (the input file itself is not touched).
    assert '"Right_LOD1" not written: the new levels of "Right" replace it' in entry["warnings"], entry["warnings"]
    drawn = 3 * collection_cli["monkey_triangles"]
    for level, ratio in zip(entry["asset"]["levels"], (0.5, 0.25)):
        assert drawn * ratio - 3 <= level["triangles"] <= drawn * ratio, (level["triangles"], drawn)
    objects = {o["object"]: o for o in entry["objects"]}
    assert sorted(objects) == ["Left", "Right", "Tall"]
    assert len({tuple(lv["mesh"] for lv in o["levels"]) for o in objects.values()}) == 1
    gltf = collection_cli["shared_glb"]
    assert len([n for n in gltf["nodes"] if "MSFT_lod" in n.get("extensions", {})]) == 1
    named = [n for n in gltf["nodes"] if n["name"] == "Right_LOD1"]
    assert len(named) == 1 and gltf["meshes"][named[0]["mesh"]]["name"] == objects["Right"]["levels"][1]["mesh"]


def test_curves_and_text_switch_with_the_asset_in_the_glb(tmp_path):
    """A bevelled cable and an extruded logo beside a monkey (tests/scenarios/
    addon_curve_parts.py's scene): the .glb has one MSFT_lod whose every level holds their
    LOD meshes too; a curve that draws no faces is skipped with a note. Before, only the
    monkey had levels, and the cable and logo were written whole beside every level."""
    blend = tmp_path / "curves.blend"
    run_scenario("addon_curve_parts", {"blend_out": str(blend)}, user_dir=tmp_path / "user", install=False)
    out, report = tmp_path / "curves.glb", tmp_path / "report.json"
    env = {**os.environ, **isolated_blender_env(tmp_path / "user")}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), "--input", str(blend), "--ratios", "0.5", "0.25",
                           "--output", str(out), "--report", str(report)],
                          capture_output=True, text=True, cwd=tmp_path, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    entry = json.loads(report.read_text())["files"][0]
    assert sorted(o["object"] for o in entry["objects"]) == ["Cable", "Logo", "Monkey"]
    assert any(w.startswith('"Guide" skipped: its curve makes no faces') for w in entry["warnings"]), entry["warnings"]
    gltf = glb_json(out)
    tops = [n for n in gltf["nodes"] if "MSFT_lod" in n.get("extensions", {})]
    assert len(tops) == 1, [n["name"] for n in tops]
    for k, node in enumerate(tops[0]["extensions"]["MSFT_lod"]["ids"], start=1):
        children = sorted(gltf["nodes"][c]["name"] for c in gltf["nodes"][node]["children"])
        assert children == [f"Cable_LOD{k}", f"Logo_LOD{k}", f"Monkey_LOD{k}"], children
    # Nothing of the parts is drawn outside the asset's levels.
    in_levels = {c for n in gltf["nodes"] for c in n.get("children", ())}
    roots = [n["name"] for i, n in enumerate(gltf["nodes"]) if i not in in_levels]
    assert len(roots) == 1 + len(tops[0]["extensions"]["MSFT_lod"]["ids"]) + 1, roots  # the levels and Guide


def test_objects_named_one_by_one_are_parts_as_asked(collection_cli):
    """--objects names the parts: a Boolean cutter named there is simplified with the
    monkey, not skipped as a helper (the docs promise it; LodJob skipped it before)."""
    work = collection_cli["work"]
    report = work / "named.json"
    env = {**os.environ, **isolated_blender_env(work / "user")}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), "--input", str(work / "shared.blend"),
                           "--objects", "Right", "Cutter", "--ratios", "0.5", "--no-measure",
                           "--output", str(work / "named.glb"), "--report", str(report)],
                          capture_output=True, text=True, cwd=work, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    entry = json.loads(report.read_text())["files"][0]
    assert sorted(o["object"] for o in entry["objects"]) == ["Cutter", "Right"]
    assert not any("skipped" in w for w in entry["warnings"]), entry["warnings"]
