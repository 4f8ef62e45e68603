"""Switch data for the engines (issue 22 §2) through the installed extension: custom
properties at commit, the Unreal LOD group's screen sizes, MSFT_lod in a .glb from
Blender's own glTF exporter (validated by the Khronos glTF-Validator) and the FBX custom
properties' round trip through Blender's FBX importer (tests/scenarios/engine_switch.py)."""
import numpy as np
import pytest

from bpy_harness import run_scenario
from gltf_tools import glb_json, issue_summary, validate

pytestmark = [pytest.mark.blender]

KEYS = ("deviation", "switch_distance", "msft_screen_coverage", "unreal_screen_size",
        "unity_transition_height", "godot_visibility_range_begin", "godot_visibility_range_end")


@pytest.fixture(scope="module")
def scene(blender_user_dir, tmp_path_factory):
    out = tmp_path_factory.mktemp("engines")
    paths = {"glb": str(out / "monkey.glb"), "fbx": str(out / "monkey.fbx"), "unmeasured_glb": str(out / "plain.glb"),
             "paused_glb": str(out / "skin_paused.glb"), "plain_glb": str(out / "skin_plain.glb")}
    result = run_scenario("engine_switch", paths, user_dir=blender_user_dir)
    return {**result, "paths": paths}


def chain_numbers(scene) -> dict:
    """{key: [LOD0's, LOD1's, ...]} from the objects' custom properties."""
    props = [scene["props"][name.replace("_LOD0", "")] if name.endswith("_LOD0") else scene["props"][name]
             for name in scene["names"]]
    return {key: [p[key] for p in props] for key in KEYS}


def test_commit_sets_the_numbers_on_every_level_and_in_the_report(scene):
    report = scene["report"]
    numbers = chain_numbers(scene)
    assert len(numbers["switch_distance"]) == 4
    for key in KEYS:
        assert [lv[key] for lv in report["levels"]] == numbers[key][1:], key
        assert report["switch"]["lod0"][key] == numbers[key][0], key
    assert numbers["switch_distance"][0] == 0.0 and numbers["deviation"][0] == 0.0
    for key in ("msft_screen_coverage", "unreal_screen_size", "unity_transition_height"):
        assert np.all(np.diff(numbers[key]) <= 0) and numbers[key][-1] > 0, (key, numbers[key])
    assert np.all(np.diff(numbers["switch_distance"]) >= 0)
    # ε from the measured Hausdorff percent: the level's deviation over the switch distance
    # is the same for every level (D = ε H / (2 τ tan 30°)), in world units (scale 2).
    sw = report["switch"]
    assert sw["pixel_error"] == 1.0 and sw["screen_height"] == 1080 and sw["vertical_fov_degrees"] == 60.0
    d = np.array(numbers["switch_distance"][1:])
    eps = np.array(numbers["deviation"][1:])
    np.testing.assert_allclose(d, np.maximum.accumulate(eps * 1080 / (2 * np.tan(np.radians(30)))))
    assert sw["bounding_sphere_radius"] > 1.5  # the monkey (size 2) scaled by 2


def test_lod_group_has_unreal_screen_sizes(scene):
    group = scene["group_props"]
    sizes = [group[f"lqlod_unreal_screen_size_LOD{k}"] for k in range(4)]
    assert sizes == chain_numbers(scene)["unreal_screen_size"]
    assert group["fbx_type"] == "LodGroup"


def test_glb_has_msft_lod_and_screen_coverage_and_validates(scene):
    gltf = glb_json(scene["paths"]["glb"])
    assert "MSFT_lod" in gltf["extensionsUsed"] and "MSFT_lod" not in gltf.get("extensionsRequired", [])
    nodes = gltf["nodes"]
    by_name = {n["name"]: i for i, n in enumerate(nodes)}
    top = nodes[by_name["Monkey_LOD0"]]
    assert top["extensions"]["MSFT_lod"]["ids"] == [by_name[f"Monkey_LOD{k}"] for k in (1, 2, 3)]
    numbers = chain_numbers(scene)
    assert top["extras"]["MSFT_screencoverage"] == pytest.approx(numbers["msft_screen_coverage"])
    for k in range(4):
        extras = nodes[by_name[f"Monkey_LOD{k}"]]["extras"]
        assert extras["visibility_range_begin"] == pytest.approx(numbers["godot_visibility_range_begin"][k])
        assert extras["visibility_range_end"] == pytest.approx(numbers["godot_visibility_range_end"][k])
    report = validate(scene["paths"]["glb"])
    print(issue_summary(report))
    assert report["issues"]["numErrors"] == 0, issue_summary(report)


def test_fbx_custom_properties_round_trip(scene):
    back = scene["fbx_props"]
    numbers = chain_numbers(scene)
    for k in range(4):
        props = back[f"Monkey_LOD{k}"]
        for key in KEYS:
            assert props[f"lqlod_{key}"] == pytest.approx(numbers[key][k]), (k, key)
    group = back["Monkey_LODGroup"]
    assert [group[f"lqlod_unreal_screen_size_LOD{k}"] for k in range(4)] == pytest.approx(numbers["unreal_screen_size"])


def test_unmeasured_chain_has_no_switch_data(scene):
    assert scene["unmeasured"] == {"switch": None, "props": []}
    gltf = glb_json(scene["paths"]["unmeasured_glb"])
    assert "MSFT_lod" not in gltf.get("extensionsUsed", [])
    assert not any("MSFT_lod" in n.get("extensions", {}) for n in gltf["nodes"])


def test_pausing_armature_deform_for_the_export_changes_no_byte_and_restores_the_modifiers(scene):
    """The command line's glTF export switches every Armature modifier off while the
    exporter samples the actions (addon/headless/scene_files.armature_deform_paused): the
    file must be the exporter's own, skins and animation included, and the scene as it was."""
    from pathlib import Path

    skin = scene["animated_skin"]
    assert skin["armature_modifiers"] == 3  # the tube and its two LODs
    assert skin["shown_after"] == [True] * 3
    paused, plain = (Path(scene["paths"][k]).read_bytes() for k in ("paused_glb", "plain_glb"))
    assert paused == plain
    doc = glb_json(scene["paths"]["paused_glb"])
    assert len(doc["skins"]) == 1 and len(doc["animations"]) == 1
    assert sum("skin" in node for node in doc["nodes"]) == 3


@pytest.fixture(scope="module")
def walker(blender_user_dir, tmp_path_factory):
    """tests/scenarios/addon_node_animation.py's node-animated character, written to a .glb."""
    glb = tmp_path_factory.mktemp("node_animation") / "walker.glb"
    out = run_scenario("addon_node_animation", {"glb": str(glb)}, user_dir=blender_user_dir)
    return {**out, "glb": glb}


def test_the_glb_animates_every_level_and_switches_each_part(walker):
    """An asset an animation moves gets one MSFT_lod per part, each level's node where its
    LOD0 is and moved by the same channels (gltf_lod._asset_levels): a level moved to a
    root of its own would lose what moves it."""
    gltf = glb_json(walker["glb"])
    nodes = gltf["nodes"]
    by_name = {n["name"]: i for i, n in enumerate(nodes)}
    moved = {}
    for animation in gltf["animations"]:
        for channel in animation["channels"]:
            target = channel["target"]
            moved.setdefault(nodes[target["node"]]["name"], set()).add((animation["name"], target["path"]))
    parent = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    for source, names in walker["lods"].items():
        lod0 = next(n for n in by_name if n in (source, f"{source}_LOD0"))
        assert lod0 in moved or source == "Body", lod0  # Body moves with Root, not by its own channels
        top = nodes[by_name[lod0]]
        assert top["extensions"]["MSFT_lod"]["ids"] == [by_name[name] for name in names]
        for name in names:
            assert moved.get(name) == moved.get(lod0), name  # the same channels as its LOD0
            assert parent.get(by_name[name]) == parent.get(by_name[lod0]), name  # where LOD0 is
    assert not any(n["name"].endswith(("_LOD1", "_LOD2")) and "children" in n for n in nodes)
    # Morph weights: every level's node plays its LOD0's samplers (gltf_lod._share_morph_channels),
    # in each of the key's two actions; the LODs' own copies are back in Blender after.
    for animation in gltf["animations"]:
        weights = {nodes[c["target"]["node"]]["name"]: c["sampler"] for c in animation["channels"]
                   if c["target"]["path"] == "weights"}
        if weights:
            assert set(weights) == {"Body_LOD0", "Body_LOD1", "Body_LOD2"}  # (the sources are renamed for the export)
            assert len(set(weights.values())) == 1, weights
    assert sum(1 for a in gltf["animations"] if any(c["target"]["path"] == "weights" for c in a["channels"])) == 2
    after = walker["key_animation_after"]["Body"]
    assert all(level == after[0] for level in after[1:]) and after[0]["action"] == "Breathe"
    report = validate(walker["glb"])
    assert report["issues"]["numErrors"] == 0, issue_summary(report)
