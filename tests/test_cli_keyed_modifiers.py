"""A face modelled with a Mirror modifier and a shape key, through the command line to
FBX and .blend (tests/scenarios/keyed_modifiers.py). The FBX and glTF exporters apply a
mesh's modifiers and then drop its keys: LOD1-3, read through the stack, kept the smile
and LOD0 lost it. Runs on every Blender line (FBX, not glTF: .ci/run)."""
import json
import os
import subprocess
import sys

import pytest

from bpy_harness import REPO_ROOT, isolated_blender_env, run_scenario


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    work = tmp_path_factory.mktemp("keyed")
    user = work / "user"
    blend = work / "face.blend"
    run_scenario("keyed_modifiers", {"mode": "make", "blend": str(blend)}, user_dir=user, install=False)
    out, report = work / "out", work / "report.json"
    env = {**os.environ, **isolated_blender_env(user)}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), "--input", str(blend), "--ratios", "0.5", "0.25",
                           "--no-measure", "--output-dir", str(out), "--format", "fbx", "blend",
                           "--report", str(report)],
                          capture_output=True, text=True, cwd=work, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    inspect = lambda **where: run_scenario("keyed_modifiers", {"mode": "inspect", **where}, user_dir=user,
                                           install=False)
    return {"report": json.loads(report.read_text())["files"][0], "source": inspect(blend=str(blend)),
            "fbx": inspect(fbx=str(out / "face_LODs.fbx")), "blend": inspect(blend=str(out / "face_LODs.blend"))}


def test_every_level_in_the_fbx_smiles_with_both_halves(written):
    fbx = written["fbx"]
    assert sorted(fbx) == sorted(f"{name}_LOD{k}" for name in ("Face", "Ball") for k in range(3)), sorted(fbx)
    for k in range(3):
        level = fbx[f"Face_LOD{k}"]
        assert level["keys"] == ["Basis", "Smile"], (k, level)
        low, high = level["moved_x"]
        assert low < -0.3 and high > 0.3 and abs(low + high) < 0.02, (k, level)  # both halves, mirrored
    assert fbx["Face_LOD0"]["triangles"] > fbx["Face_LOD1"]["triangles"] > fbx["Face_LOD2"]["triangles"]
    assert fbx["Ball_LOD0"]["keys"] == []
    assert any('"Face_LOD0": LOD0 written as its modifiers make it' in w for w in written["report"]["warnings"])


def test_the_blend_keeps_the_source_with_its_modifier_and_keys(written):
    """The .blend is written first: its LOD0 is the source as modelled, half a face and a
    live Mirror."""
    source, lod0 = written["source"]["Face"], written["blend"]["Face_LOD0"]
    assert lod0 == source and lod0["modifiers"] == ["MIRROR"] and lod0["moved_x"][0] > -1e-3
