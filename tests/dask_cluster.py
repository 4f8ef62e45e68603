"""A real Dask cluster for the tests: `dask scheduler` and `dask worker` started as their
own processes on this machine, as an operator would start them on a farm."""
import contextlib
import json
import subprocess
import sys
import time


def _dask(command: str, *args) -> list:
    return [sys.executable, "-m", f"distributed.cli.{command}", *args]


@contextlib.contextmanager
def scheduler_and_worker(folder, env, threads: int = 1):
    """Yields the scheduler's address while a scheduler and one worker (``threads`` tasks
    at a time) run; both are stopped after."""
    scheduler_file = folder / "scheduler.json"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL, "cwd": folder, "env": env}
    procs = [subprocess.Popen(_dask("dask_scheduler", "--scheduler-file", str(scheduler_file), "--host",
                                    "127.0.0.1", "--port", "0", "--no-dashboard"), **quiet)]
    try:
        deadline = time.monotonic() + 60
        while not scheduler_file.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        address = json.loads(scheduler_file.read_text())["address"]
        procs.append(subprocess.Popen(_dask("dask_worker", address, "--nthreads", str(threads), "--no-dashboard"),
                                      **quiet))
        yield address
    finally:
        for proc in procs:
            proc.terminate()
        for proc in procs:
            proc.wait(timeout=30)
