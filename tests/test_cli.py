"""The command line end to end through the bpy-module entry point (``python <checkout>``),
on input files the tests write themselves, with every output re-imported and checked.

Blender processes, kept few (each costs 1-2 s to start): one child writes the inputs
(tests/scenarios/cli_inputs.py), one batch run with --jobs 1 and one with --jobs 2 (which
starts one child per input), one --sample run (the README's demo), and one child
re-imports every output (tests/scenarios/cli_reimport.py).
"""
import json
import os
import re
import subprocess
import sys

import pytest

from bpy_harness import REPO_ROOT, isolated_blender_env, run_scenario

pytestmark = [pytest.mark.blender, pytest.mark.slow]

RATIOS = ["0.5", "0.2"]
GOOD = {"a.obj": ["Ball"], "rig.glb": ["Arm"], "scene.blend": ["Rock", "Slab"]}
FORMATS = ["blend", "glb"]

def run_cli(argv, cwd, user_dir, timeout=600):
    env = {**os.environ, **isolated_blender_env(user_dir)}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), *argv], capture_output=True, text=True,
                          cwd=cwd, env=env, timeout=timeout)
    return proc.returncode, proc.stdout, proc.stderr


STAMP_SUFFIX = ".lqlod.json"  # the up-to-date stamp beside a run's outputs (addon/headless/freshness.py)
SIDECAR_SUFFIX = ".lods.json"  # the switch-data sidecar beside them (addon/headless/sidecar.py)


def lod_files(folder):
    """The files a run wrote into ``folder``, without its up-to-date stamps and sidecars."""
    return [p for p in folder.iterdir() if not p.name.endswith((STAMP_SUFFIX, SIDECAR_SUFFIX))]


def table_rows(stdout):
    """{object name: [cells]} from the table on stdout."""
    rows = {}
    for line in stdout.splitlines():
        cells = re.split(r"\s{2,}", line.strip())
        if len(cells) == 11 and re.fullmatch(r"LOD\d+", cells[2]) and cells[1] != "(asset)":
            rows[cells[1]] = cells
    return rows


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    root = tmp_path_factory.mktemp("cli")
    inputs = root / "in"
    inputs.mkdir()
    written = run_scenario("cli_inputs", {"out": str(inputs)}, user_dir=root / "user", install=False)["written"]
    assert written == ["a.obj", "rig.glb", "scene.blend"], f"expected the three inputs written, got {written}"
    (inputs / "broken.glb").write_bytes(b"glTF\x02\x00\x00\x00 truncated")  # a glb cut short
    return root


@pytest.fixture(scope="module")
def batches(work):
    files = [str(work / "in" / name) for name in ("a.obj", "rig.glb", "scene.blend", "broken.glb")]
    runs = {}
    for jobs in (1, 2):
        out = work / f"out{jobs}"
        report = work / f"report{jobs}.json"
        code, stdout, stderr = run_cli(
            ["--input", *files, "--ratios", *RATIOS, "--from-armature", "--importance-group", "Detail",
             "--output-dir", str(out), "--format", *FORMATS, "--report", str(report), "--jobs", str(jobs)],
            cwd=work, user_dir=work / "user")
        runs[jobs] = {"code": code, "stdout": stdout, "stderr": stderr, "out": out,
                      "report": json.loads(report.read_text()) if report.exists() else None}
    return runs


@pytest.fixture(scope="module")
def sample(work):
    out = work / "sample"
    code, stdout, stderr = run_cli(["--sample", "--output-dir", str(out), "--report", str(work / "sample.json")],
                                   cwd=work, user_dir=work / "user")
    return {"code": code, "stdout": stdout, "stderr": stderr, "out": out,
            "report": json.loads((work / "sample.json").read_text()) if code == 0 else None}


@pytest.fixture(scope="module")
def reimported(work, batches, sample):
    paths = sorted(str(p) for run in batches.values() for p in lod_files(run["out"]))
    paths += sorted(str(p) for p in lod_files(sample["out"]))
    return run_scenario("cli_reimport", {"paths": paths}, user_dir=work / "user", install=False)


def test_batch_with_a_broken_file_finishes_the_others_and_fails(batches):
    for jobs, run in batches.items():
        assert run["code"] == 1, (jobs, run["stderr"][-3000:])
        errors = [line for line in run["stderr"].splitlines() if line.startswith("error:")]
        assert len(errors) == 1 and errors[0].startswith("error: broken.glb: cannot be read as glTF: "), (jobs, errors)
        assert "Traceback" not in run["stderr"], (jobs, run["stderr"][-3000:])
        failed = [line for line in run["stdout"].splitlines() if line.startswith("FAILED")]
        assert len(failed) == 1 and "broken.glb: cannot be read as glTF: " in failed[0] and "Bad GLB" in failed[0], \
            f"expected one FAILED line for broken.glb (Bad GLB), got {failed}"
        assert "3 of 4 inputs done" in run["stdout"], run["stdout"][-3000:]
        written = sorted(p.name for p in lod_files(run["out"]))
        assert written == sorted(f"{stem}_LODs.{fmt}" for stem in ("a", "rig", "scene") for fmt in FORMATS), written
        report = run["report"]
        assert report["ok"] is False
        assert [f["ok"] for f in report["files"]] == [True, True, True, False]
        assert report["failures"] == [{"input": report["files"][3]["input"], "error": report["files"][3]["error"]}]


def test_progress_lines_per_object_and_lod(batches):
    lines = batches[1]["stderr"].splitlines()
    assert "[a.obj] Ball: 2,208 triangles -> LOD1 1,104, LOD2 442" in lines
    for level in (1, 2):
        assert any(re.fullmatch(rf"\[rig\.glb\] Arm: LOD{level} simplified, target [\d,]+ triangles "
                                rf"\(about (<1|\d+) s left\)", line) for line in lines), level
    assert any(re.fullmatch(r"\[scene\.blend\] Slab: done in [\d.]+ s \(about .* left\)", line) for line in lines)


def test_lod_chains_in_every_output(batches, reimported):
    report = batches[1]["report"]
    for entry in report["files"][:3]:
        stem = os.path.splitext(os.path.basename(entry["input"]))[0]
        expected = {}
        asset = entry.get("asset")  # several objects: one asset, its budget split by error
        assert (asset is None) == (len(entry["objects"]) == 1), entry.get("asset")
        if asset is not None:
            source = sum(obj["levels"][0]["triangles"] for obj in entry["objects"])
            for k, ratio in enumerate(RATIOS, start=1):
                targets = sum(obj["levels"][k]["target"] for obj in entry["objects"])
                # (each part's share rounded: within a triangle a part)
                assert abs(targets - round(float(ratio) * source)) <= len(entry["objects"]), (k, targets)
                assert asset["levels"][k - 1]["triangles"] == sum(obj["levels"][k]["triangles"]
                                                                   for obj in entry["objects"])
        for obj in entry["objects"]:
            levels = obj["levels"]
            assert [lv["name"] for lv in levels] == [f"{obj['object']}_LOD{k}" for k in range(len(RATIOS) + 1)]
            source = levels[0]["triangles"]
            for lv, ratio in zip(levels[1:], RATIOS):
                if asset is None:
                    assert lv["target"] == round(float(ratio) * source)
                if lv["stop_reason"] == "target_reached":
                    assert abs(lv["triangles"] - lv["target"]) <= 1, lv
                else:  # the engine could not go further: said in a note and the report
                    assert any(f"LOD{lv['level']} stopped at {lv['triangles']} triangles" in w
                               for w in obj["warnings"]), (f"expected a note that LOD{lv['level']} stopped at "
                                                           f"{lv['triangles']} triangles, got {obj['warnings']}")
            # (A part of an asset may be kept whole at a level: its budget went elsewhere.)
            assert all(b["triangles"] < a["triangles"] or (asset and b["triangles"] == a["triangles"])
                       for a, b in zip(levels, levels[1:]))
            assert levels[-1]["triangles"] < levels[0]["triangles"]
            expected.update({lv["name"]: lv["triangles"] for lv in levels})
        assert sorted(o["object"] for o in entry["objects"]) == sorted(GOOD[os.path.basename(entry["input"])])
        for fmt in FORMATS:
            path = str(batches[1]["out"] / f"{stem}_LODs.{fmt}")
            meshes = {name: ob for name, ob in reimported[path].items() if ob["type"] == 'MESH'}
            assert sorted(meshes) == sorted(expected), (path, sorted(meshes))
            # (Rock's Subdivision Surface: its LOD0 in the .blend keeps it, in the .glb it is applied)
            assert {name: ob.get("evaluated_triangles", ob["triangles"]) for name, ob in meshes.items()} == expected, path
            if fmt == "glb":
                assert all("evaluated_triangles" not in ob for ob in meshes.values()), path
            assert all(ob["uv_maps"] == 1 for ob in meshes.values()), path


def test_blend_output_keeps_the_scene_and_marks_the_lods(batches, reimported):
    scene = reimported[str(batches[1]["out"] / "scene_LODs.blend")]
    assert scene["Camera"]["type"] == 'CAMERA'  # everything else in the file is kept
    assert [scene[f"Rock_LOD{k}"]["lod_level"] for k in range(3)] == [None, 1, 2]
    assert "Detail" in scene["Slab_LOD1"]["groups"], scene["Slab_LOD1"]  # vertex groups travel with the LODs


def test_skinned_input_gives_skinned_lods(batches, reimported):
    for fmt in FORMATS:
        objects = reimported[str(batches[1]["out"] / f"rig_LODs.{fmt}")]
        armatures = [name for name, ob in objects.items() if ob["type"] == 'ARMATURE']
        assert len(armatures) == 1, objects
        for k in range(3):
            lod = objects[f"Arm_LOD{k}"]
            assert lod["armature"] == armatures[0], (fmt, k, lod)
            assert {"Lower", "Upper"} <= set(lod["groups"]), (fmt, k, lod)
    arm = next(o for o in batches[1]["report"]["files"][1]["objects"])
    assert arm["importance"] == "ARMATURE"


def test_report_matches_the_table_and_the_settings(batches):
    run = batches[1]
    report = run["report"]
    rows = table_rows(run["stdout"])
    names = [lv["name"] for f in report["files"] for o in f["objects"] for lv in o["levels"]]
    assert sorted(rows) == sorted(names)
    for f in report["files"][:3]:
        for obj in f["objects"]:
            for lv in obj["levels"]:
                cells = rows[lv["name"]]
                assert [cells[0], cells[2]] == [os.path.basename(f["input"]), f"LOD{lv['level']}"], cells
                assert int(cells[3].replace(",", "")) == lv["triangles"]
                assert float(cells[5]) == pytest.approx(lv["hausdorff_percent"], abs=6e-4)
                assert float(cells[6]) == pytest.approx(lv["mean_percent"], abs=6e-5)
                assert cells[7] == f"{lv['normal_mean_degrees']:.2f} / {lv['normal_p95_degrees']:.1f}"
                assert cells[8] == f"{lv['mean_quality']:.3f} / {lv['min_quality']:.3f}"
                if lv["level"]:
                    simplified = lv["triangles"] < obj["levels"][0]["triangles"]  # (not kept whole)
                    assert lv["hausdorff_percent"] > 0 or not simplified, lv
                    assert lv["mean_percent"] <= lv["hausdorff_percent"], lv
                    # (the mean may exceed the 95th percentile: a few large angles, the rest ~0)
                    assert 0 <= lv["normal_mean_degrees"] <= lv["normal_max_degrees"] <= 180, lv
                    assert 0 <= lv["normal_p95_degrees"] <= lv["normal_max_degrees"], lv
                    assert 0 < lv["min_quality"] <= lv["mean_quality"] <= 1 and lv["seconds"] >= 0, lv
                else:
                    assert lv["hausdorff_percent"] == 0.0 and lv["target"] is None, lv
    importance = {o["object"]: o["importance"] for f in report["files"] for o in f["objects"]}
    assert importance == {"Ball": "NONE", "Arm": "ARMATURE", "Rock": "NONE", "Slab": "VERTEX_GROUP:Detail"}
    rock = next(o for o in report["files"][2]["objects"] if o["object"] == "Rock")
    assert 'no importance (no vertex group "Detail" and not skinned)' in rock["warnings"], rock["warnings"]
    assert report["settings"]["ratios"] == [0.5, 0.2] and report["settings"]["importance_group"] == "Detail"


def test_jobs_2_gives_the_same_outputs_as_jobs_1(batches, reimported):
    one, two = batches[1], batches[2]
    names = sorted(p.name for p in lod_files(one["out"]))
    assert names == sorted(p.name for p in lod_files(two["out"]))
    for name in names:
        if name.endswith(".glb"):  # the exporter is deterministic: byte for byte
            assert (one["out"] / name).read_bytes() == (two["out"] / name).read_bytes(), name
        a, b = reimported[str(one["out"] / name)], reimported[str(two["out"] / name)]
        assert a == b, name

    def numbers(report):
        return [(f["ok"], f["error"], [(o["object"], o["importance"], o["warnings"],
                                        [{k: v for k, v in lv.items() if k != "seconds"} for lv in o["levels"]])
                                       for o in f["objects"]]) for f in report["files"]]

    assert numbers(one["report"]) == numbers(two["report"])


def test_sample_demo_writes_blend_and_glb_and_prints_the_table(sample, reimported):
    assert sample["code"] == 0, sample["stderr"][-3000:]
    out = sample["out"]
    assert sorted(p.name for p in lod_files(out)) == ["sample_LODs.blend", "sample_LODs.glb"]
    rows = table_rows(sample["stdout"])
    chains = {base: [f"{base}_LOD{k}" for k in range(4)] for base in ("Monkey", "Character")}
    assert sorted(rows) == sorted(n for chain in chains.values() for n in chain)
    objects = {o["object"]: o for o in sample["report"]["files"][0]["objects"]}
    assert objects["Monkey"]["importance"] == "VERTEX_GROUP:LOD_Importance"
    assert objects["Character"]["importance"] == "ARMATURE"
    for fmt in ("blend", "glb"):
        scene = reimported[str(out / f"sample_LODs.{fmt}")]
        for base, chain in chains.items():
            tris = [scene[name]["triangles"] for name in chain]
            assert tris == [lv["triangles"] for lv in objects[base]["levels"]], (fmt, base)
        for name in chains["Character"]:
            assert scene[name]["armature"] is not None, (fmt, name)
    blend = reimported[str(out / "sample_LODs.blend")]
    assert "LOD_Importance" in blend["Monkey_LOD0"]["groups"], blend["Monkey_LOD0"]
    assert blend["Character_LOD0"]["armature"] == "Rig"


def test_no_temporary_files_left(batches, sample):
    for folder in [run["out"] for run in batches.values()] + [sample["out"]]:
        hidden = sorted(p.name for p in folder.iterdir() if p.name.startswith("."))
        stamps = [name for name in hidden if name.endswith(STAMP_SUFFIX)]
        assert hidden == stamps, f"expected only up-to-date stamps among hidden files in {folder}, got {hidden}"


def test_script_mode_takes_the_options_after_double_dash(work):
    """``blender -b -P addon/cli.py -- [options]``: Blender has bpy loaded when it runs the
    script and leaves its own arguments in sys.argv; mimicked here with the bpy module."""
    script = str(REPO_ROOT / "addon" / "cli.py")
    report = work / "script.json"
    argv = ["blender", "-b", "-P", script, "--", "--input", str(work / "in" / "a.obj"), str(work / "in" / "broken.glb"),
            "--ratios", "0.5", "--no-measure", "--report", str(report), "--quiet"]
    code = f"import bpy, runpy, sys\nsys.argv = {argv!r}\nrunpy.run_path({script!r}, run_name='__main__')\n"
    env = {**os.environ, **isolated_blender_env(work / "user")}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=work, env=env, timeout=300)
    assert proc.returncode == 1, proc.stderr[-3000:]  # sys.exit() carries the status out of the script
    data = json.loads(report.read_text())
    assert [f["ok"] for f in data["files"]] == [True, False]
    assert [lv["triangles"] for lv in data["files"][0]["objects"][0]["levels"]] == [2208, 1104]
    assert "Ball_LOD1" in table_rows(proc.stdout), proc.stdout


def test_sample_writes_switch_data_in_the_sidecar_the_report_and_the_glb(sample):
    """Issue 22 §2 through the command line (the bpy module, no installed extension: the
    glTF exporter's hook comes from addon/headless/scene_files.gltf_hooks_visible)."""
    from gltf_tools import glb_json, issue_summary, validate

    assert sample["code"] == 0, sample["stderr"][-3000:]
    sidecar = json.loads((sample["out"] / f"sample_LODs{SIDECAR_SUFFIX}").read_text())
    assert sidecar["outputs"] == ["sample_LODs.blend", "sample_LODs.glb"]
    assert sidecar["view"] == {"pixel_error": 1.0, "screen_height": 1080, "vertical_fov_degrees": 60.0}
    objects = {o["object"]: o for o in sample["report"]["files"][0]["objects"]}
    gltf = glb_json(sample["out"] / "sample_LODs.glb")
    by_name = {n["name"]: i for i, n in enumerate(gltf["nodes"])}
    assert "MSFT_lod" in gltf["extensionsUsed"]
    for chain in sidecar["objects"]:
        levels = objects[chain["object"]]["levels"]
        assert [lv["name"] for lv in chain["levels"]] == [lv["name"] for lv in levels]
        coverage = chain["gltf"]["MSFT_screencoverage"]
        assert coverage == [lv["msft_screen_coverage"] for lv in levels]  # the report has the same numbers
        assert chain["unreal"]["screen_sizes"] == [lv["unreal_screen_size"] for lv in levels]
        assert all(a >= b for a, b in zip(coverage, coverage[1:])), coverage
        top = gltf["nodes"][by_name[levels[0]["name"]]]
        assert top["extensions"]["MSFT_lod"]["ids"] == [by_name[lv["name"]] for lv in levels[1:]]
        assert top["extras"]["MSFT_screencoverage"] == pytest.approx(coverage)
    report = validate(sample["out"] / "sample_LODs.glb")
    print(issue_summary(report))
    assert report["issues"]["numErrors"] == 0, issue_summary(report)


def test_an_inputs_objects_switch_as_one_asset_in_the_glb(batches):
    """Issue 32 §1: scene.blend's Rock and Slab are one asset. Its .glb has one MSFT_lod,
    on the LOD0 subtree, whose ids are one node per level holding that level's parts (each
    where its object was in the world), with the asset's screen coverage; the Khronos
    validator finds no error."""
    from gltf_tools import glb_json, issue_summary, validate

    entry = next(f for f in batches[1]["report"]["files"] if f["input"].endswith("scene.blend"))
    asset = entry["asset"]
    assert asset["name"] == "scene" and asset["objects"] == 2
    path = batches[1]["out"] / "scene_LODs.glb"
    gltf = glb_json(path)
    # Only the scene the LODs were made in: the file's other scene, "Storyboard", was
    # written too before, its cube without LODs (the FBX and OBJ exporters write one).
    assert len(gltf["scenes"]) == 1 and "Spare" not in {n["name"] for n in gltf["nodes"]}
    nodes = gltf["nodes"]
    by_name = {n["name"]: i for i, n in enumerate(nodes)}
    tops = [i for i, n in enumerate(nodes) if "MSFT_lod" in n.get("extensions", {})]
    assert len(tops) == 1, [nodes[i]["name"] for i in tops]
    top = nodes[tops[0]]

    def subtree(i):
        return [nodes[i]["name"]] + [name for c in nodes[i].get("children", []) for name in subtree(c)]

    assert {"Rock_LOD0", "Slab_LOD0"} <= set(subtree(tops[0]))
    assert not any("_LOD1" in name or "_LOD2" in name for name in subtree(tops[0]))
    ids = top["extensions"]["MSFT_lod"]["ids"]
    assert ids == [by_name["scene_LOD1"], by_name["scene_LOD2"]]
    for k, i in enumerate(ids, start=1):
        assert sorted(subtree(i)[1:]) == [f"Rock_LOD{k}", f"Slab_LOD{k}"]
    coverage = [lv["msft_screen_coverage"] for lv in asset["levels"]]
    assert top["extras"]["MSFT_screencoverage"][1:] == pytest.approx(coverage)
    # Each level node sits at the scene's root, each part where its object is: Slab's LODs
    # where Slab is (its LOD0 node's translation), Rock's at the origin.
    roots = gltf["scenes"][gltf.get("scene", 0)]["nodes"]
    assert set(ids) <= set(roots)
    slab = nodes[by_name["Slab_LOD0"]].get("translation")
    for k in (1, 2):
        assert nodes[by_name[f"Slab_LOD{k}"]].get("translation") == pytest.approx(slab)
    report = validate(path)
    assert report["issues"]["numErrors"] == 0, issue_summary(report)
