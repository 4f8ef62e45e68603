"""The batch's task, executors and rules (addon/headless/asset_task.py, executors.py,
task_runner.py) and the up-to-date stamps (addon/headless/freshness.py), with a
stand-in child process; tests/test_cli_batch.py runs the real command line.

--jobs N runs on the standard library's threads; the Dask cluster test skips without
dask[distributed]."""
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from addon.headless import asset_task, executors, freshness, task_runner
from dask_cluster import scheduler_and_worker

REPO_ROOT = Path(__file__).resolve().parent.parent
FAKE_CHILD = Path(__file__).with_name("fake_asset_child.py")


def run(assets, *, jobs=1, scheduler=None, retries=2, on_result=None):
    """The batch as the command line runs it (addon/headless/batch.py): the executor of
    --jobs or --scheduler, the runner's rules."""
    with executors.open_executor(jobs, scheduler) as (executor, _):
        return task_runner.run(executor, assets, retries=retries, on_result=on_result)


def asset(behaviour: str) -> asset_task.Asset:
    return asset_task.Asset(behaviour, behaviour, [sys.executable, str(FAKE_CHILD), behaviour])


def test_a_crash_fails_only_its_asset_and_is_retried(tmp_path):
    flaky = tmp_path / "crashed-once"
    assets = [asset("a"), asset("bad"), asset("crash"), asset(f"flaky:{flaky}"), asset("b")]
    streamed = []
    entries = run(assets, jobs=2, retries=2, on_result=streamed.append)

    assert [e["label"] for e in entries] == [a.label for a in assets], "entries come back in input order"
    by_label = {e["label"]: e for e in entries}
    assert by_label["a"]["ok"] and by_label["b"]["ok"]
    assert not by_label["bad"]["ok"] and by_label["bad"]["error"] == "no mesh objects in bad"
    crash = by_label["crash"]
    assert not crash["ok"] and "SIGABRT" in crash["error"] and "3 attempts" in crash["error"], crash["error"]
    assert flaky.exists() and by_label[f"flaky:{flaky}"]["ok"], "a crash that does not repeat is retried"
    assert sorted(e["label"] for e in streamed) == sorted(a.label for a in assets), "every asset streamed once"


def test_clean_failures_are_not_retried(tmp_path):
    counter = tmp_path / "runs"
    # "bad" writes its report with ok False: running it again would say the same.
    child = tmp_path / "counting_child.py"
    child.write_text(f"import runpy, sys\nopen({str(counter)!r}, 'a').write('x')\n"
                     f"sys.argv = [{str(FAKE_CHILD)!r}] + sys.argv[1:]\nrunpy.run_path({str(FAKE_CHILD)!r}, run_name='__main__')\n")
    entries = run([asset_task.Asset("bad", "bad", [sys.executable, str(child), "bad"])], jobs=1, retries=2)
    assert not entries[0]["ok"]
    assert counter.read_text() == "x", f"ran {len(counter.read_text())} times, expected once"


def test_a_stopped_batch_leaves_no_child_running(tmp_path):
    """Ctrl-C: stop_running_children ends the running children, and retries that come
    after it do not start new ones."""
    import threading

    pids = [tmp_path / f"{i}.pid" for i in range(2)]
    result = {}
    runner = threading.Thread(target=lambda: result.update(
        entries=run([asset(f"sleep:{p}") for p in pids], jobs=2, retries=2)))
    runner.start()
    deadline = time.monotonic() + 60
    while not all(p.exists() and p.read_text() for p in pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    asset_task.stop_running_children()
    runner.join(timeout=60)
    assert not runner.is_alive(), "the batch did not end after its children were stopped"
    for p in pids:
        assert not Path(f"/proc/{p.read_text()}").exists() or "zombie" in Path(f"/proc/{p.read_text()}/status").read_text().lower(), p
    assert all(not e["ok"] for e in result["entries"]), result


INTERRUPTED_BATCH = """\
import signal, sys
# Started from a background job (nohup, or & where the shell has no job control) the
# process inherits SIGINT ignored, and Python leaves it so: Ctrl-C as a terminal sends it.
signal.signal(signal.SIGINT, signal.default_int_handler)
sys.path.insert(0, {root!r})
from addon.headless import asset_task, executors, task_runner
assets = [asset_task.Asset(p, p, [sys.executable, {child!r}, "sleep:" + p]) for p in sys.argv[1:]]
with executors.open_executor(2) as (executor, _):
    task_runner.run(executor, assets, retries=2)
"""


# The same batch, but the Ctrl-C reaches one of its other threads: the kernel may deliver
# a process's SIGINT to any thread, and Python raises it in the main thread only when that
# thread next runs.
INTERRUPTED_IN_A_THREAD = """\
import os, signal, sys, threading, time
pids = sys.argv[1:]
def interrupt():
    while not all(os.path.exists(p) and open(p).read() for p in pids[:2]):
        time.sleep(0.05)
    signal.pthread_kill(threading.get_ident(), signal.SIGINT)
threading.Thread(target=interrupt, daemon=True).start()
""" + INTERRUPTED_BATCH


@pytest.mark.parametrize("where", ["process", "thread"])
def test_ctrl_c_on_a_local_batch_kills_its_children_and_starts_no_more(tmp_path, where):
    """SIGINT to the batch's process alone (as Ctrl-C, but its children do not get it), or
    delivered to one of its threads other than the main one: closing the thread executor
    stops the two running children and never starts the queued third, whose retries are
    not run either."""
    script = tmp_path / "batch.py"
    template = INTERRUPTED_BATCH if where == "process" else INTERRUPTED_IN_A_THREAD
    script.write_text(template.format(root=str(REPO_ROOT), child=str(FAKE_CHILD)))
    pids = [tmp_path / f"{i}.pid" for i in range(3)]
    proc = subprocess.Popen([sys.executable, str(script), *map(str, pids)], stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while not all(p.exists() and p.read_text() for p in pids[:2]) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert all(p.exists() for p in pids[:2]), "the first two children did not start"
        if where == "process":
            proc.send_signal(signal.SIGINT)
        interrupted = time.monotonic()
        _, stderr = proc.communicate(timeout=90)
        waited = time.monotonic() - interrupted
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode != 0 and "KeyboardInterrupt" in stderr, stderr[-2000:]
    # The stand-in children sleep 60 s: a batch that waited for them did not stop them.
    assert waited < 20, f"the interrupted batch took {waited:.0f} s to end"
    for p in pids[:2]:
        status = Path(f"/proc/{p.read_text()}/status")
        assert not status.exists(), f"child {p.read_text()} still runs after the interrupt"
    assert not pids[2].exists(), "the queued input was started after the interrupt"


def test_no_retries_means_one_attempt():
    entries = run([asset("crash")], jobs=1, retries=0)
    assert not entries[0]["ok"] and "attempts" not in entries[0]["error"], entries[0]["error"]


def test_a_separately_started_scheduler_and_worker_run_the_batch(tmp_path):
    """The cluster path: `dask scheduler` and `dask worker` as their own processes, the
    batch submitted to the scheduler's address; the worker has no copy of our package."""
    pytest.importorskip("distributed", reason="dask[distributed] is a test dependency (requirements-dev.txt)")
    with scheduler_and_worker(tmp_path, {**os.environ, "PYTHONPATH": ""}) as address:
        entries = run([asset("a"), asset("bad"), asset("crash")], scheduler=address, retries=1)
    assert [e["ok"] for e in entries] == [True, False, False], entries
    assert "SIGABRT" in entries[2]["error"] and "2 attempts" in entries[2]["error"], entries[2]["error"]


# ----------------------------------------------------------------------------- stamps


def test_stamp_round_trip_and_what_invalidates_it(tmp_path):
    source = tmp_path / "rock.obj"
    source.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    outputs = [tmp_path / "out" / "rock_LODs.glb", tmp_path / "out" / "rock_LODs.obj"]
    outputs[0].parent.mkdir()
    key = freshness.asset_key(source, {"ratios": [0.5]})
    assert not freshness.up_to_date(outputs, key), "nothing written yet"
    for out in outputs:
        out.write_bytes(b"lod")
    assert not freshness.up_to_date(outputs, key), "outputs without a stamp may be from an interrupted run"
    freshness.mark_done(outputs, key)
    assert freshness.up_to_date(outputs, key)

    assert freshness.asset_key(source, {"ratios": [0.25]}) != key, "other settings, other key"
    outputs[1].unlink()
    assert not freshness.up_to_date(outputs, key), "a missing output is redone"
    outputs[1].write_bytes(b"lod")
    source.write_text("v 0 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\n")
    assert freshness.asset_key(source, {"ratios": [0.5]}) != key, "other content, other key"
    freshness.forget(outputs)
    assert not freshness.up_to_date(outputs, key)


def test_companion_files_count_in_the_key(tmp_path):
    gltf = tmp_path / "crate.gltf"
    (tmp_path / "crate.bin").write_bytes(b"\0" * 12)
    gltf.write_text(json.dumps({"asset": {"version": "2.0"}, "buffers": [{"uri": "crate.bin", "byteLength": 12}],
                                "images": [{"uri": "data:image/png;base64,AAAA"}]}))
    assert freshness.companion_files(gltf) == [(tmp_path / "crate.bin").resolve()]
    key = freshness.asset_key(gltf, {})
    (tmp_path / "crate.bin").write_bytes(b"\1" * 12)
    assert freshness.asset_key(gltf, {}) != key, "a changed buffer changes the key"

    obj = tmp_path / "rock.obj"
    (tmp_path / "rock.mtl").write_text("newmtl stone\n")
    (tmp_path / "moss.mtl").write_text("newmtl moss\n")
    obj.write_text("mtllib rock.mtl moss.mtl\nv 0 0 0\n")
    assert freshness.companion_files(obj) == [(tmp_path / "rock.mtl").resolve(), (tmp_path / "moss.mtl").resolve()]

    spaced = tmp_path / "big rock.gltf"
    (tmp_path / "big rock.bin").write_bytes(b"\0" * 4)
    spaced.write_text(json.dumps({"asset": {"version": "2.0"}, "buffers": [{"uri": "big%20rock.bin"}]}))
    assert freshness.companion_files(spaced) == [(tmp_path / "big rock.bin").resolve()], "URIs are percent-encoded"
