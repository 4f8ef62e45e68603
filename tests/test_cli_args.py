"""The command line's parsing and checking, which need no Blender: in-process for the
pure functions, and through ``python <checkout>`` for the messages and exit codes (these
runs stop before bpy is imported, so each costs a fraction of a second)."""
import os
import subprocess
import sys

import pytest

from addon.headless import arguments, inputs, report
from addon.headless.errors import UsageError
from addon.pure.settings import LodError, LodSettings, flagged
from bpy_harness import REPO_ROOT, isolated_blender_env

REQUIRED_OPTIONS = ["--input", "--objects", "--ratios", "--faces", "--output", "--output-dir", "--report",
                    "--jobs", "--line-weight", "--importance-group", "--from-armature", "--from-shape-keys",
                    "--strength", "--lod-group", "--quiet", "--sample", "--mode", "--no-preserve-boundaries",
                    "--no-preserve-seams", "--no-preserve-sharp", "--no-preserve-materials", "--min-quality",
                    "--feature-angle", "--keep-small-parts"]


def parse(*argv):
    return arguments.build_parser("test").parse_args(list(argv))


def run_cli(tmp_path, *argv):
    env = {**os.environ, **isolated_blender_env(tmp_path / "user")}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), *argv], capture_output=True, text=True,
                          cwd=tmp_path, env=env, timeout=120)
    return proc.returncode, proc.stdout, proc.stderr


def error_lines(stderr):
    return [line for line in stderr.splitlines() if line.strip()]


def test_every_documented_option_exists_and_help_has_examples(tmp_path):
    code, out, err = run_cli(tmp_path, "--help")
    assert code == 0, err
    for option in REQUIRED_OPTIONS:
        assert option in out, option
    assert "examples:" in out and "-c line_quadric_lod" in out and "--sample --output-dir" in out
    assert "LodGroup" in out and "_LOD0" in out


@pytest.mark.parametrize("argv, message", [
    (["--bogus"], "unrecognized arguments: --bogus"),
    (["--ratios", "0.5", "x", "--report", "r.json"], "argument --ratios: expected a number, got 'x'"),
    (["--faces", "0", "--report", "r.json"], "must be at least 1, got 0"),
    (["--jobs", "two", "--report", "r.json"], "expected a whole number, got 'two'"),
    (["--mode", "hard", "--report", "r.json"], "invalid choice: 'hard'"),
    (["--ratios", "0.5", "--faces", "100", "--report", "r.json"], "not allowed with argument"),
])
def test_argparse_errors_are_one_line_with_exit_2(tmp_path, argv, message):
    code, out, err = run_cli(tmp_path, *argv)
    assert code == 2
    lines = error_lines(err)
    assert len(lines) == 1, err
    assert lines[0].startswith("error: ") and message in lines[0], lines[0]
    assert "Traceback" not in err and out == ""


def test_each_problem_gets_its_own_line(tmp_path):
    (tmp_path / "notes.txt").write_text("not a mesh")
    (tmp_path / "empty").mkdir()
    code, out, err = run_cli(
        tmp_path, "--input", "missing.obj", "notes.txt", "empty", "nothing*.glb",
        "--ratios", "0.5", "1.5", "--strength", "2", "--output", "out.xyz")
    assert code == 2 and out == ""
    lines = error_lines(err)
    expected = [
        "--ratios: 1.5 not between 0 and 1",
        "--strength must be in [0, 1], got 2",
        "unsupported output format '.xyz' for out.xyz",
        "no such file: missing.obj",
        "unsupported input format '.txt': notes.txt",
        "the folder empty has no files of a supported type",
        "no files match 'nothing*.glb'",
    ]
    assert len(lines) == len(expected), err
    for line, text in zip(lines, expected):
        assert line.startswith("error: ") and text in line, (line, text)
    assert "Traceback" not in err


@pytest.mark.blender  # finding that no .blend is open imports bpy
def test_nothing_to_write_and_no_input(tmp_path):
    code, _, err = run_cli(tmp_path, "--sample")
    assert code == 2
    assert error_lines(err) == ["error: nothing to write: give --output FILE, --output-dir DIR or --report FILE.json"]
    # No --input and no .blend open (the bpy module starts with an unsaved scene).
    code, _, err = run_cli(tmp_path, "--output", "x.blend")
    assert code == 2
    lines = error_lines(err)
    assert len(lines) == 1 and lines[0].startswith("error: no input: give --input FILE"), err


def test_output_needs_one_input_and_same_stems_clash(tmp_path):
    for name in ("a/x.obj", "b/x.obj"):
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text("v 0 0 0\n")
    code, _, err = run_cli(tmp_path, "--input", "a/x.obj", "b/x.obj", "--output", "x.blend")
    assert code == 2 and "--output writes one file but there are 2 inputs: use --output-dir" in err
    code, _, err = run_cli(tmp_path, "--input", "a/x.obj", "b/x.obj", "--output-dir", "out")
    assert code == 2 and "would all be written to" in err and "x_LODs.obj" in err


def test_check_args_rules():
    assert arguments.check_args(parse("--ratios", "0.5", "0.25", "--report", "r.json")) == []
    assert arguments.check_args(parse("--ratios", "0.25", "0.5", "--report", "r.json")) == [
        "--ratios must decrease (each LOD smaller than the one before), got 0.25 0.5"]
    assert arguments.check_args(parse("--faces", "100", "100", "--report", "r.json")) == [
        "--faces must decrease (each LOD smaller than the one before), got 100 100"]
    assert arguments.check_args(parse("--line-weight", "-1", "--report", "r.json")) == ["--line-weight must be >= 0, got -1"]
    assert arguments.check_args(parse("--min-quality", "1.5", "--report", "r.json")) == [
        "--min-quality must be in [0, 1], got 1.5"]
    assert arguments.check_args(parse("--feature-angle", "180", "--report", "r.json")) == [
        "--feature-angle must be in [0, 180) degrees (0 = off), got 180"]
    settings = arguments.lod_settings(parse("--min-quality", "0", "--feature-angle", "0", "--keep-small-parts",
                                   "--report", "r.json"))
    assert (settings.min_quality, settings.feature_angle, settings.remove_small_components) == (0.0, 0.0, False)
    defaults = arguments.lod_settings(parse("--report", "r.json"))
    assert (defaults.min_quality, defaults.feature_angle, defaults.remove_small_components) == (0.3, 80.0, True)
    assert arguments.check_args(parse("--output", "a.fbx", "--format", "glb")) == [
        "--format goes with --output-dir; the --output file's extension picks its format"]
    assert arguments.check_args(parse("--importance-group", " ", "--report", "r.json")) == [
        "--importance-group needs a vertex group name"]


def test_the_panels_settings_options_are_the_tables():
    """Each panel setting's option is the table's: its flag, stored under the setting's
    name with the setting's default; the chain is LodSettings' own."""
    actions = {a.option_strings[0]: a for a in arguments.build_parser("test")._actions if a.option_strings}
    for s in flagged():
        assert (actions[s.flag].dest, actions[s.flag].default) == (s.name, s.default), s.flag
    assert arguments.lod_settings(parse("--report", "r.json")) == LodSettings(ratios=(0.5, 0.25, 0.125))
    given = arguments.lod_settings(parse("--faces", "90", "9", "--no-preserve-seams", "--importance-group", "G",
                                         "--report", "r.json"))
    assert given == LodSettings(triangle_counts=(90, 9), preserve_seams=False)  # importance: per object


def targets(*argv, triangles):
    """The chain lod.prepare() gets from the settings the options give."""
    return arguments.lod_settings(parse(*argv, "--report", "r.json")).targets(triangles, *arguments.CHAIN_LABELS)


def test_the_options_chain_replaces_the_panels():
    assert targets("--ratios", "0.5", "0.25", "0.1", triangles=1000) == [500, 250, 100]
    assert targets(triangles=1000) == [500, 250, 125]  # the default chain
    with pytest.raises(LodError, match=r"of 12 triangles give \[6, 3, 0\]: each LOD needs fewer"):
        targets("--ratios", "0.5", "0.25", "0.01", triangles=12)
    with pytest.raises(LodError, match="--faces 2000 is not fewer than the mesh's 1,000 triangles"):
        targets("--faces", "2000", "10", triangles=1000)
    assert targets("--faces", "900", "10", triangles=1000) == [900, 10]
    # The chain's own check replaces the panel's first-LOD-and-factor one, also on a
    # one-triangle mesh where the panel's default chain would be the message.
    with pytest.raises(LodError, match="--ratios 0.5 of 1 triangles give"):
        targets("--ratios", "0.5", triangles=1)


def test_expand_inputs_files_folders_globs(tmp_path):
    for name in ("b.obj", "a.glb", "c.GLTF", "c.bin", ".hidden.obj", "sub/d.fbx"):
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text("x")
    files, problems = inputs.expand_inputs([str(tmp_path)])
    assert problems == [] and [f.name for f in files] == ["a.glb", "b.obj", "c.GLTF"]
    files, problems = inputs.expand_inputs([str(tmp_path / "*.obj"), str(tmp_path / "b.obj"), str(tmp_path / "**/*.fbx")])
    assert problems == [] and [f.name for f in files] == ["b.obj", "d.fbx"]  # duplicates once, recursive glob
    files, problems = inputs.expand_inputs([str(tmp_path / "*.bin")])
    assert files == [] and problems == [f"no files of a supported type (.blend .obj .ply .stl .glb .gltf .fbx) "
                                        f"match {str(tmp_path / '*.bin')!r}"]


def test_option_round_trip_for_child_processes():
    """--jobs children get the parent's options back from the parsed namespace."""
    parser = arguments.build_parser("test")
    argv = ["--input", "a.obj", "--objects", "A", "B C", "--faces", "900", "90", "--line-weight", "0.0125",
            "--importance-group", "Paint Me", "--from-armature", "--from-shape-keys", "--strength", "0.3",
            "--mode", "strong",
            "--no-preserve-seams", "--no-preserve-materials", "--sharp-strength", "2.5", "--no-modifiers",
            "--lod-group", "--no-measure", "--quiet", "--debug", "--output-dir", "out", "--format", "fbx",
            "--jobs", "3", "--report", "r.json"]
    args = parser.parse_args(argv)
    skip = {"input", "sample", "output", "output_dir", "format", "report", "jobs"}
    again = parser.parse_args(arguments.option_argv(parser, args, skip) + ["--report", "other.json"])
    for name, value in vars(args).items():
        if name not in skip:
            assert getattr(again, name) == value, name
    assert again.input is None and again.jobs == 1 and again.output_dir is None


def test_table_format():
    level = {"level": 1, "name": "Rock_LOD1", "target": 1000, "triangles": 999, "hausdorff_percent": 0.5,
             "mean_percent": 0.01, "mean_quality": 0.8, "min_quality": 0.3, "sliver_percent": 1.25, "seconds": 0.5}
    files = [{"label": "rock.obj", "objects": [{"levels": [
        dict(level, level=0, name="Rock_LOD0", target=None, triangles=2000, seconds=0.0), level]}]}]
    lines = report.format_table(files).splitlines()
    assert lines[0].split("  ")[0] == "File" and len(lines) == 4
    cells = lines[3].split()
    assert cells[:6] == ["rock.obj", "Rock_LOD1", "LOD1", "999", "1,000", "0.500"]
    assert lines[2].split()[4] == "-"  # LOD0 has no target


def test_table_gives_each_bound_in_its_rows_unit():
    # A part of an asset asked for 1 % of the asset: its Hausdorff % is of its own size,
    # and so is its Target; the asset's row has the asset's bound.
    level = {"level": 1, "name": "Bolt_LOD1", "target": None, "triangles": 40, "hausdorff_percent": 1.5,
             "mean_percent": 0.1, "mean_quality": 0.8, "min_quality": 0.3, "sliver_percent": 0.0, "seconds": 0.1,
             "requested_deviation": 0.02, "requested_deviation_percent": 1.0,
             "requested_deviation_object_percent": 1.54}
    source = dict(level, level=0, name="Bolt_LOD0", triangles=80, requested_deviation_percent=None,
                  requested_deviation_object_percent=None)
    files = [{"label": "a.glb", "objects": [{"levels": [source, level]}],
              "asset": {"levels": [{"level": 1, "triangles": 40, "hausdorff_percent": 0.97,
                                    "requested_deviation_percent": 1.0}]}}]
    rows = [line.split() for line in report.format_table(files).splitlines()[2:]]
    assert rows[1][1] == "Bolt_LOD1" and rows[1][4] == "<=1.54%" and rows[1][5] == "1.500", rows
    assert rows[2][1] == "(asset)" and rows[2][4] == "<=1%" and rows[2][5] == "0.970", rows
    # A single object's bound is of its own size already.
    alone = dict(level, requested_deviation_object_percent=None)
    files = [{"label": "a.glb", "objects": [{"levels": [source, alone]}]}]
    assert report.format_table(files).splitlines()[3].split()[4] == "<=1%"


def test_table_shows_the_worst_shape_key_when_keys_were_measured():
    keys = [{"name": "Blink", "hausdorff_percent": 0.2, "mean_percent": 0.01},
            {"name": "Smile", "hausdorff_percent": 0.7, "mean_percent": 0.02}]
    level = {"level": 1, "name": "Face_LOD1", "target": 1000, "triangles": 999, "hausdorff_percent": 0.5,
             "mean_percent": 0.01, "mean_quality": 0.8, "min_quality": 0.3, "sliver_percent": 1.25, "seconds": 0.5}
    source = dict(level, level=0, name="Face_LOD0", target=None, triangles=2000, seconds=0.0)
    files = [{"label": "face.glb", "objects": [{"levels": [source, dict(level, shape_keys=keys)]},
                                               {"levels": [dict(source, name="Rock_LOD0"),
                                                           dict(level, name="Rock_LOD1")]}]}]
    lines = report.format_table(files).splitlines()
    assert "Worst key Hausdorff % / mean %" in lines[0]
    assert "Smile 0.700 / 0.0200" in lines[3] and "Blink" not in lines[3]
    assert lines[2].split()[7] == "-" and lines[5].split()[7] == "-"  # LOD0, an object without keys
    without = [{"label": "rock.obj", "objects": [{"levels": [dict(source, name="Rock_LOD0"), dict(level)]}]}]
    assert "Worst key" not in report.format_table(without)


def test_a_note_several_objects_share_is_printed_once(capsys):
    # Six copies of an instanced bolt share their mesh's note; the report keeps it per object.
    kept = "kept whole at LOD1 (the asset's budget is spent where it lowers the error more)"
    objects = [{"object": f"Bolt.{i:03d}", "levels": [], "warnings": [kept]} for i in range(6)]
    objects.append({"object": "Base", "levels": [], "warnings": ["no importance (no shape keys)", kept]})
    assert report.object_notes(objects) == {kept: [o["object"] for o in objects],
                                            "no importance (no shape keys)": ["Base"]}
    asset = {"levels": [], "warnings": ["the asset's LOD2 repeats its LOD1: nothing coarser is within its "
                                        "deviation 1 (scene units)"]}
    report.print_results({"files": [{"label": "bolts.blend", "warnings": [], "objects": objects, "outputs": [],
                                     "asset": asset}], "failures": [], "seconds": 1.0})
    notes = [line for line in capsys.readouterr().out.splitlines() if line.startswith("note: ")]
    assert notes == [f"note: bolts.blend: {asset['warnings'][0]}",  # the asset's own, not a part's
                     f"note: bolts.blend: Bolt.000, Bolt.001, Bolt.002, Bolt.003 and 3 more: {kept}",
                     "note: bolts.blend: Base: no importance (no shape keys)"]


def test_from_shape_keys_is_a_switch():
    assert parse("--input", "a.obj").from_shape_keys is False
    assert parse("--input", "a.obj", "--from-shape-keys").from_shape_keys is True
    args = parse("--input", "a.obj", "--from-shape-keys", "--report", "r.json")
    assert report.settings_summary(args)["from_shape_keys"] is True


def test_from_armature_chooses_the_sample_poses_or_the_papers_mapping():
    assert parse("--input", "a.obj").from_armature is None
    assert parse("--input", "a.obj", "--from-armature").from_armature == "poses"
    assert parse("--input", "a.obj", "--from-armature", "paper").from_armature == "paper"
    with pytest.raises(UsageError, match="invalid choice: 'bones'"):
        parse("--input", "a.obj", "--from-armature", "bones")
    parser = arguments.build_parser("test")
    args = parse("--input", "a.obj", "--from-armature", "paper")
    assert parser.parse_args(arguments.option_argv(parser, args, set())).from_armature == "paper"
