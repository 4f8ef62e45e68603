"""Batches through the real command line (issues 21 and 32): --jobs N in a Python without
Dask (the standard library's threads), where a crash fails only its input, nothing is
left half-written and a rerun skips what is up to date; an unreadable input is one line;
--scheduler on a separately started Dask scheduler and worker, and its errors. Inputs
and outputs are OBJ (Blender 4.2's bpy module crashes in its glTF exporter; its OBJ one
is sound); the unreadable inputs are .glb files written here."""
import json
import os
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from bench.synthetic_meshes import uv_sphere
from bpy_harness import REPO_ROOT, isolated_blender_env
from dask_cluster import scheduler_and_worker

BALLS = {"ball_a.obj": 10, "ball_b.obj": 14, "ball_c.obj": 18}
# A binary PLY header promising four billion vertices: Blender's importer aborts the
# process trying to allocate them (SIGABRT), as a corrupt file from a scanner might.
CRASHING_PLY = (b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                b"property float y\nproperty float z\nelement face 4000000000\n"
                b"property list uchar int vertex_indices\nend_header\n\0\0\0\0")


def write_uv_sphere(path: Path, rings: int) -> None:
    vertices, faces = uv_sphere(rings)
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in vertices] + [f"f {i + 1} {j + 1} {k + 1}" for i, j, k in faces]
    path.write_text("\n".join(lines) + "\n")


def glb_bytes(vertices, faces, index_view: int = 1) -> bytes:
    """One mesh as a glTF binary (header, JSON chunk, BIN chunk). ``index_view`` other
    than 1 makes the indices name a buffer view the file does not have: the file passes
    the importer's header checks and its Python then fails with an IndexError."""
    positions = np.asarray(vertices, dtype="<f4")
    indices = np.asarray(faces, dtype="<u4").ravel()
    binary = positions.tobytes() + indices.tobytes()
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0, "name": "Ball"}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
           "buffers": [{"byteLength": len(binary)}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": positions.nbytes},
                           {"buffer": 0, "byteOffset": positions.nbytes, "byteLength": indices.nbytes}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(positions), "type": "VEC3",
                          "min": positions.min(axis=0).tolist(), "max": positions.max(axis=0).tolist()},
                         {"bufferView": index_view, "componentType": 5125, "count": len(indices), "type": "SCALAR"}]}
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def run_cli(argv, cwd, env_extra=None, timeout=600):
    env = {**os.environ, **isolated_blender_env(cwd / "user"), **(env_extra or {})}
    proc = subprocess.run([sys.executable, str(REPO_ROOT), *argv], capture_output=True, text=True,
                          cwd=cwd, env=env, timeout=timeout)
    return proc.returncode, proc.stdout, proc.stderr


def read_jsonl(path: Path) -> tuple:
    records = [json.loads(line) for line in path.read_text().splitlines()]
    inputs = {Path(r["input"]).name: r for r in records if r["record"] == "input"}
    summaries = [r for r in records if r["record"] == "summary"]
    assert len(summaries) == 1 and records[-1]["record"] == "summary", f"one summary line last, got {records}"
    return inputs, summaries[0]


@pytest.fixture(scope="module")
def without_dask(tmp_path_factory) -> dict:
    """Environment for a command line whose Python cannot import Dask, as a stock
    Blender's: packages ``dask`` and ``distributed`` first on the path, raising ImportError."""
    blocker = tmp_path_factory.mktemp("no_dask")
    for name in ("dask", "distributed"):
        (blocker / name).mkdir()
        (blocker / name / "__init__.py").write_text("raise ImportError('no dask here')\n")
    env = {"PYTHONPATH": os.pathsep.join(filter(None, [str(blocker), os.environ.get("PYTHONPATH")]))}
    probe = subprocess.run([sys.executable, "-c", "import distributed"], env={**os.environ, **env},
                           capture_output=True, text=True)
    assert probe.returncode != 0 and "no dask here" in probe.stderr, "the blocker does not hide Dask"
    return env


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    root = tmp_path_factory.mktemp("batch")
    folder = root / "library"
    folder.mkdir()
    for name, rings in BALLS.items():
        write_uv_sphere(folder / name, rings)
    (folder / "broken.obj").write_text("this is no mesh\n")
    (folder / "crash.ply").write_bytes(CRASHING_PLY)
    return root


def batch_argv(root, *extra):
    return ["--input", str(root / "library"), "--ratios", "0.5", "0.25", "--no-measure",
            "--output-dir", str(root / "out"), "--format", "obj", "--report", str(root / "report.jsonl"),
            *extra]


def outputs(root) -> dict:
    return {p.name: p.stat().st_mtime_ns for p in (root / "out").iterdir()}


@pytest.fixture(scope="module")
def first_run(library, without_dask):
    # No Dask: crash isolation, retries, streaming and stamps are the standard library's.
    code, stdout, stderr = run_cli(batch_argv(library, "--jobs", "2", "--retries", "1"), library,
                                   env_extra=without_dask)
    return {"code": code, "stdout": stdout, "stderr": stderr, "outputs": outputs(library),
            "report": read_jsonl(library / "report.jsonl")}


def test_a_crash_fails_only_its_input_and_is_retried(first_run):
    assert first_run["code"] == 1, first_run["stderr"][-3000:]
    inputs, summary = first_run["report"]
    assert sorted(inputs) == sorted([*BALLS, "broken.obj", "crash.ply"])
    assert all(inputs[name]["ok"] for name in BALLS), {n: inputs[n]["error"] for n in BALLS}
    crash = inputs["crash.ply"]["error"]
    assert "SIGABRT" in crash and "(2 attempts)" in crash, f"a crash named and retried once, got {crash!r}"
    broken = inputs["broken.obj"]["error"]
    assert broken == "no mesh objects", f"a clean failure, reported as the child said it, got {broken!r}"
    assert summary["ok"] is False and summary["skipped"] == 0
    assert sorted(f["input"] for f in summary["failures"]) == sorted(
        str(Path(inputs[n]["input"])) for n in ("broken.obj", "crash.ply"))
    assert "Traceback" not in first_run["stderr"]
    assert "3 of 5 inputs done" in first_run["stdout"], first_run["stdout"][-1500:]


def test_nothing_half_written(first_run):
    names = sorted(first_run["outputs"])
    lods = sorted(f"{Path(n).stem}_LODs.obj" for n in BALLS)
    stamps = sorted(f".{Path(n).stem}_LODs.obj.lqlod.json" for n in BALLS)
    mtl = sorted(f"{Path(n).stem}_LODs.mtl" for n in BALLS)
    leftovers = sorted(set(names) - set(lods) - set(stamps) - set(mtl))
    assert not leftovers, f"only finished outputs and their stamps, also found {leftovers}"
    assert set(lods) <= set(names) and set(stamps) <= set(names), names


def test_a_rerun_skips_what_is_up_to_date_and_redoes_what_changed(library, first_run):
    code, stdout, stderr = run_cli(batch_argv(library, "--jobs", "2", "--retries", "0"), library)
    assert code == 1, stderr[-3000:]  # the two bad inputs are still bad
    inputs, summary = read_jsonl(library / "report.jsonl")
    assert summary["skipped"] == 3 and all(inputs[n].get("skipped") for n in BALLS), summary
    assert outputs(library) == first_run["outputs"], "skipped inputs' files are not touched"
    assert "3 of them up to date (skipped)" in stdout

    write_uv_sphere(library / "library" / "ball_b.obj", 16)  # new content
    run_cli(batch_argv(library, "--jobs", "2", "--retries", "0"), library)
    inputs, summary = read_jsonl(library / "report.jsonl")
    redone = sorted(n for n in BALLS if not inputs[n].get("skipped"))
    assert redone == ["ball_b.obj"], f"only the changed input is redone, got {redone}"

    run_cli(batch_argv(library, "--ratios", "0.4", "--jobs", "2", "--retries", "0"), library)  # other options
    inputs, summary = read_jsonl(library / "report.jsonl")
    assert summary["skipped"] == 0, summary

    before = outputs(library)
    run_cli(batch_argv(library, "--ratios", "0.4", "--force", "--jobs", "2", "--retries", "0"), library)
    inputs, summary = read_jsonl(library / "report.jsonl")
    assert summary["skipped"] == 0
    changed = [n for n, t in outputs(library).items() if n.endswith(".obj") and t != before[n]]
    assert len(changed) == 3, f"--force rewrites every output, rewrote {changed}"


def test_jobs_without_dask_write_the_good_inputs_and_name_the_unreadable_one(tmp_path, without_dask):
    folder = tmp_path / "assets"
    folder.mkdir()
    write_uv_sphere(folder / "ball_a.obj", 10)
    write_uv_sphere(folder / "ball_b.obj", 12)
    (folder / "broken.glb").write_bytes(glb_bytes(*uv_sphere(10))[:100])  # a .glb cut short
    report = tmp_path / "report.json"
    code, stdout, stderr = run_cli(["--input", str(folder), "--jobs", "2", "--ratios", "0.5", "--no-measure",
                                    "--output-dir", str(tmp_path / "out"), "--format", "obj",
                                    "--report", str(report)], tmp_path, env_extra=without_dask)
    assert code == 1, stderr[-3000:]
    assert "Dask" not in stderr, stderr
    assert sorted(p.name for p in (tmp_path / "out").glob("*.obj")) == ["ball_a_LODs.obj", "ball_b_LODs.obj"]
    named = [line for line in stderr.splitlines() if "broken.glb" in line]
    assert len(named) == 1 and named[0].startswith("error: broken.glb: cannot be read as glTF: "), stderr
    assert "Traceback" not in stderr, stderr
    files = {Path(f["input"]).name: f for f in json.loads(report.read_text())["files"]}
    assert [files[n]["ok"] for n in ("ball_a.obj", "ball_b.obj", "broken.glb")] == [True, True, False], files
    assert files["broken.glb"]["error"] == named[0][len("error: broken.glb: "):], files["broken.glb"]


def test_an_importer_traceback_is_one_line_and_debug_shows_it(tmp_path, without_dask):
    """The glTF importer fails in its own Python on a .glb whose indices name a missing
    buffer view; Blender hands us its traceback as the operator's error."""
    (tmp_path / "bad_view.glb").write_bytes(glb_bytes(*uv_sphere(6), index_view=7))
    argv = ["--input", str(tmp_path / "bad_view.glb"), "--ratios", "0.5", "--no-measure",
            "--output-dir", str(tmp_path / "out"), "--format", "obj"]
    code, stdout, stderr = run_cli(argv, tmp_path)
    assert code == 1, stderr[-3000:]
    errors = [line for line in stderr.splitlines() if line.startswith("error:")]
    assert errors == ["error: bad_view.glb: cannot be read as glTF: IndexError: list index out of range"], stderr
    assert "Traceback" not in stderr + stdout, stderr
    # --debug, also through a batch's child process: the importer's traceback is shown.
    write_uv_sphere(tmp_path / "ball.obj", 6)
    argv[1:2] = [str(tmp_path / "bad_view.glb"), str(tmp_path / "ball.obj")]
    code, stdout, stderr = run_cli([*argv, "--jobs", "2", "--debug"], tmp_path, env_extra=without_dask)
    assert code == 1 and "Traceback (most recent call last)" in stderr and "IndexError" in stderr, stderr[-3000:]


def test_a_scheduler_that_cannot_be_used_is_one_line(tmp_path, library, without_dask):
    argv = ["--input", *(str(library / "library" / n) for n in list(BALLS)[:2]), "--no-measure",
            "--output-dir", str(tmp_path / "out"), "--format", "obj"]
    # Without Dask: --scheduler (or $LQLOD_SCHEDULER) says what it needs, and nothing is done.
    for extra, env in ((["--scheduler", "tcp://127.0.0.1:1"], {}), ([], {"LQLOD_SCHEDULER": "tcp://127.0.0.1:1"})):
        code, stdout, stderr = run_cli([*argv, *extra], tmp_path, env_extra={**without_dask, **env})
        assert code == 2 and stderr.splitlines() == [
            "error: --scheduler (or $LQLOD_SCHEDULER) needs Dask, which this Python does not have: pip install "
            "'dask[distributed]' (./lod.sh provisions it); --jobs N needs nothing"], (extra, stderr)
        assert not (tmp_path / "out").exists()
    # With Dask, nothing listening there.
    pytest.importorskip("distributed", reason="dask[distributed] is a test dependency (requirements-dev.txt)")
    code, stdout, stderr = run_cli([*argv, "--scheduler", "tcp://127.0.0.1:1"], tmp_path)
    lines = stderr.splitlines()
    assert code == 2 and len(lines) == 1, stderr[-3000:]
    assert lines[0].startswith("error: cannot reach the Dask scheduler at tcp://127.0.0.1:1: "), stderr
    assert not (tmp_path / "out").exists()


def test_a_separately_started_scheduler_and_worker_run_the_batch(tmp_path, library):
    pytest.importorskip("distributed", reason="dask[distributed] is a test dependency (requirements-dev.txt)")
    out = tmp_path / "cluster_out"
    with scheduler_and_worker(tmp_path, {**os.environ, **isolated_blender_env(tmp_path / "user")}, threads=2) as address:
        code, stdout, stderr = run_cli(
            ["--input", *(str(library / "library" / n) for n in BALLS), "--ratios", "0.5", "--no-measure",
             "--output-dir", str(out), "--format", "obj", "--scheduler", address], library)
    assert code == 0, stderr[-3000:]
    assert sorted(p.name for p in out.glob("*.obj")) == sorted(f"{Path(n).stem}_LODs.obj" for n in BALLS)
    assert "3 of 3 inputs done" in stdout, stdout[-1500:]


def test_one_job_at_a_time_streams_and_skips_too(tmp_path, library):
    argv = ["--input", *(str(library / "library" / n) for n in BALLS), "--ratios", "0.5", "--no-measure",
            "--output-dir", str(tmp_path / "serial"), "--format", "obj", "--report", str(tmp_path / "r.jsonl")]
    code, stdout, stderr = run_cli(argv, library)
    assert code == 0, stderr[-3000:]
    inputs, summary = read_jsonl(tmp_path / "r.jsonl")
    assert sorted(inputs) == sorted(BALLS) and summary["skipped"] == 0
    code, stdout, stderr = run_cli(argv, library)
    inputs, summary = read_jsonl(tmp_path / "r.jsonl")
    assert code == 0 and summary["skipped"] == 3, (stderr[-2000:], summary)
