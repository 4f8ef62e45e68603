"""``blender -c line_quadric_lod``: the command the installed extension registers.

The bpy module has no command line of its own, so one Blender child (built extension
installed and enabled) runs tests/scenarios/cli_command.py: it records what the add-on
hands to ``bpy.utils.register_cli_command`` when it is enabled, and then calls that
registered handler with arguments, as Blender does for ``-c``: on a .blend input (FBX
with an Unreal LOD group), on the open file (glTF), on a UV-less STL (OBJ out), and with
bad inputs, a failing exporter and an impossible target next to a good output file that
must survive.
"""
import pytest

from bpy_harness import run_scenario


@pytest.fixture(scope="module")
def result(blender_user_dir, tmp_path_factory):
    work = tmp_path_factory.mktemp("cli_command")
    return run_scenario("cli_command", {"work": str(work)}, user_dir=blender_user_dir)


def errors(run):
    return [line for line in run["stderr"].splitlines() if line.startswith("error:")]


def test_enabling_registers_the_command_and_disabling_unregisters_it(result):
    events = [tuple(e) for e in result["events"]]
    handler = ("register", "line_quadric_lod", events[1][2], "cli_command")
    assert events[1][2].endswith(".addon.cli"), f"expected the handler in <extension>.addon.cli, got {events[1][2]}"
    # disable (start-up handle), enable, disable (the handle register() returned), enable
    assert events == [("unregister", False), handler, ("unregister", True), handler]


def test_blend_to_fbx_with_an_unreal_lod_group(result):
    run = result["fbx_run"]
    assert run["code"] == 0 and run["stderr"] == "", run
    assert result["fbx_has_lodgroup"], "expected an FBX LodGroup node in rock.fbx, found none"
    rock = result["fbx_report"]["files"][0]["objects"]
    assert [o["object"] for o in rock] == ["Rock"]  # --objects: Slab is left alone
    assert [lv["triangles"] for lv in rock[0]["levels"]] == [1280, 600, 200]
    chain = ["Rock_LOD0", "Rock_LOD1", "Rock_LOD2"]
    assert result["fbx_empties"] == {"Rock_LODGroup": chain}
    meshes = result["fbx_meshes"]
    # The whole scene is written; only Rock got LODs.
    assert {n: m["triangles"] for n, m in meshes.items()} == {**dict(zip(chain, [1280, 600, 200])), "Slab": 960}
    assert [meshes[n]["parent"] for n in chain] == ["Rock_LODGroup"] * 3 and meshes["Slab"]["parent"] is None


def test_open_file_to_gltf(result):
    run = result["gltf_run"]
    assert run["code"] == 0, run
    assert {"open.gltf", "open.bin"} <= set(result["gltf_files"]), result["gltf_files"]
    meshes = result["gltf_meshes"]
    assert sorted(meshes) == ["Rock_LOD0", "Rock_LOD1", "Slab_LOD0", "Slab_LOD1"]
    # One asset (asset_budget): LOD1 is half of Rock's and Slab's triangles together, split by error.
    # (Within a triangle a part: each part's share is rounded, a closed part's count is even.)
    assert abs(meshes["Rock_LOD1"]["triangles"] + meshes["Slab_LOD1"]["triangles"] - 1120) <= 2, meshes
    assert "[scene.blend] Slab: LOD1 simplified" in run["stderr"], run["stderr"]  # progress without --quiet
    assert 'note: scene.blend: Rock: no importance (no vertex group "Detail")' in run["stdout"], run["stdout"]


def test_uvless_stl_to_obj(result):
    run = result["stl_run"]
    assert run["code"] == 0, run
    tris = {n: m["triangles"] for n, m in result["obj_meshes"].items()}
    assert tris == {"part_LOD0": 1280, "part_LOD1": 640, "part_LOD2": 320}


def test_failures_are_one_line_and_never_touch_a_good_file(result):
    assert result["good_run"]["code"] == 0, result["good_run"]
    bad = result["bad_objects"]
    assert bad["code"] == 1 and errors(bad) == [
        'error: scene.blend: object "Nope" not found (mesh objects: Rock, Slab); '
        '"Camera" is not a mesh object (its type is CAMERA)']
    impossible = result["impossible"]
    assert impossible["code"] == 1 and errors(impossible) == [
        "error: scene.blend: the asset of 2 objects (2 meshes): --faces 5000 is not fewer than the "
        "asset's 2,240 triangles"]
    export = result["export_fails"]
    assert export["code"] == 1 and len(errors(export)) == 1, export
    message = errors(export)[0]
    assert message.endswith("good.blend: No space left on device") and "could not write" in message, message
    assert result["good_unchanged"], "expected good.blend untouched by the failed runs, but its bytes changed"
    assert result["leftovers"] == [], f"expected no temporary files left, found {result['leftovers']}"
    for run in (bad, impossible, export):
        assert "Traceback" not in run["stderr"] + run["stdout"], run
        assert "FAILED" in run["stdout"], f"expected a FAILED line on stdout, got {run['stdout']!r}"


def test_fresh_scenes_between_inputs_keep_the_extension_enabled(result):
    assert result["still_enabled"], "expected the extension still enabled after the fresh scenes, but it is not"


def test_bad_option_and_help_through_the_handler(result):
    assert result["bogus"]["code"] == 2, result["bogus"]
    assert errors(result["bogus"]) == [
        "error: unrecognized arguments: --bogus (see blender -b [scene.blend] -c line_quadric_lod --help)"]
    assert result["help"]["code"] == 0, result["help"]
    assert result["help"]["stdout"].startswith("usage: blender -b [scene.blend] -c line_quadric_lod"), \
        result["help"]["stdout"][:200]


def test_rerun_on_its_own_output_replaces_the_lods(result):
    assert result["rerun"]["code"] == 0, result["rerun"]
    # One asset (good.blend's objects): one Unreal LOD group, a node per level holding its parts.
    assert result["rerun_objects"] == ["Camera", "Rock_LOD0", "Rock_LOD1", "Slab_LOD0", "Slab_LOD1",
                                       "good_LOD0", "good_LOD1", "good_LODGroup"]
    meshes = result["rerun_meshes"]
    assert [meshes["Rock_LOD0"]["triangles"], meshes["Slab_LOD0"]["triangles"]] == [1280, 960], meshes
    # A quarter of the asset's 2,240 triangles (asset_budget), split by error.
    assert abs(meshes["Rock_LOD1"]["triangles"] + meshes["Slab_LOD1"]["triangles"] - 560) <= 2, meshes
    assert meshes["Rock_LOD1"]["parent"] == "good_LOD1", meshes["Rock_LOD1"]
    assert meshes["Slab_LOD0"]["parent"] == "good_LOD0", meshes["Slab_LOD0"]
