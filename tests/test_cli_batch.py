"""Batches on Dask through the real command line (issue 21): a crash fails only its input,
nothing is left half-written, a rerun skips what is up to date, and a separately started
scheduler and worker run the same batch. Inputs and outputs are OBJ (Blender 4.2's bpy
module crashes in its glTF exporter; its OBJ one is sound)."""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from bench.synthetic_meshes import uv_sphere
from bpy_harness import REPO_ROOT, isolated_blender_env
from dask_cluster import scheduler_and_worker

pytest.importorskip("distributed", reason="dask[distributed] is a test dependency (requirements-dev.txt)")

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
def first_run(library):
    code, stdout, stderr = run_cli(batch_argv(library, "--jobs", "2", "--retries", "1"), library)
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


def test_without_dask_several_jobs_say_how_to_get_it(tmp_path, library):
    blocker = tmp_path / "no_dask"
    (blocker / "distributed").mkdir(parents=True)
    (blocker / "distributed" / "__init__.py").write_text("raise ImportError('no dask here')\n")
    code, stdout, stderr = run_cli(batch_argv(library, "--jobs", "2"), library,
                                   env_extra={"PYTHONPATH": str(blocker)})
    assert code == 2, stderr
    assert "dask[distributed]" in stderr and "--jobs 1" in stderr, stderr


def test_a_separately_started_scheduler_and_worker_run_the_batch(tmp_path, library):
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
