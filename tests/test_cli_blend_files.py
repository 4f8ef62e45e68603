"""A .blend through the command line as studios keep them (issue 32 §1): textures at
relative paths, and objects linked from a library .blend, one of them also instanced
through its collection. The output is a .blend (the default for a .blend input), so this
runs on every Blender line."""
import json
import os
import subprocess
import sys

import pytest

from bpy_harness import REPO_ROOT, isolated_blender_env, run_scenario


@pytest.fixture(scope="module")
def shot(tmp_path_factory):
    root = tmp_path_factory.mktemp("studio")
    user = root / "user"
    source = run_scenario("linked_library", {"mode": "make", "root": str(root)}, user_dir=user, install=False)
    blend = root / "shots" / "shot.blend"
    before = {p: p.read_bytes() for p in (blend, root / "assets" / "rocks.blend")}
    out, report = root / "lods", root / "report.json"
    env = {**os.environ, **isolated_blender_env(user)}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), "--input", str(blend), "--ratios", "0.5", "0.25",
                           "--no-measure", "--output-dir", str(out), "--report", str(report)],
                          capture_output=True, text=True, cwd=root, env=env, timeout=600)
    written = run_scenario("linked_library", {"mode": "inspect", "blend": str(out / "shot_LODs.blend")},
                           user_dir=user, install=False) if (out / "shot_LODs.blend").is_file() else None
    return {"proc": proc, "report": json.loads(report.read_text()) if report.is_file() else None,
            "source": source, "written": written, "before": before}


def test_the_source_scene_links_its_rock_and_keeps_relative_paths(shot):
    source = shot["source"]
    assert source["objects"]["Rock"]["linked"] and "Crate" in source["objects"]
    assert all(path.startswith("//") and exists for path, exists in source["images"].values()), source["images"]


def test_linked_objects_get_their_lods_under_names_of_their_own(shot):
    """The linked "Rock" and the local copy its collection instance becomes share a name;
    renaming the first source "Rock_LOD0" failed the file, and a linked object cannot be
    renamed at all. Each is now a local object with its own chain."""
    proc = shot["proc"]
    assert proc.returncode == 0, proc.stderr[-3000:]
    entry = shot["report"]["files"][0]
    names = sorted(o["object"] for o in entry["objects"])
    assert len(names) == 3 and "Crate" in names and sum(n.startswith("Rock") for n in names) == 2, names
    assert any("linked from rocks.blend, made a local object" in w for w in entry["warnings"]), entry["warnings"]
    for o in entry["objects"]:
        assert [lv["name"] for lv in o["levels"]] == [f"{o['object']}_LOD{k}" for k in range(3)]
    objects = shot["written"]["objects"]  # every level in the written file, the asset at its ratios
    drawn = sum(objects[f"{o['object']}_LOD0"]["triangles"] for o in entry["objects"])
    for k, ratio in ((1, 0.5), (2, 0.25)):
        level = sum(objects[f"{o['object']}_LOD{k}"]["triangles"] for o in entry["objects"])
        assert abs(level - ratio * drawn) <= 0.02 * drawn, (k, level, drawn)


def test_the_written_blend_finds_its_textures_and_library(shot):
    """Written one folder deep and then moved into place, the .blend's relative paths
    pointed one folder too deep: every texture and library was missing in the output."""
    written = shot["written"]
    assert written is not None, shot["proc"].stderr[-3000:]
    assert set(written["images"]) == {"rock.png", "crate.png"}
    for name, (path, exists) in {**written["images"], **written["libraries"]}.items():
        assert path.startswith("//") and exists, (name, path)


def test_the_input_and_its_library_are_untouched(shot):
    for path, content in shot["before"].items():
        assert path.read_bytes() == content, path
