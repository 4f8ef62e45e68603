# SPDX-License-Identifier: GPL-3.0-or-later
"""Headless LOD generation: one argument parser and one implementation for every entry point.

    blender -b scene.blend -c line_quadric_lod [options]      the command the add-on registers
    blender -b scene.blend -P <ext>/addon/cli.py -- [options]  this file run as a script
    python <checkout> [options]                                 __main__.py, with the pip bpy module

All three call :func:`main` (the registered command through :func:`cli_command`); the
parts are in addon/headless/. Parsing and checking the arguments and the input paths
need no Blender, so a mistyped option fails at once; bpy and the LOD modules are
imported only to do the work.

Run as a script there is no package around this file, so nothing is imported from it
at module level: :func:`run_as_script` (also what __main__.py runs) first loads the
checkout as the package ``line_quadric_lod`` and then calls that copy's :func:`main`.

Exit status: 0 everything done, 1 some input failed (the others are still done),
2 nothing was done (bad options, missing or unsupported files, nothing to write),
130 interrupted.
"""
import sys
from pathlib import Path
from typing import Optional

COMMAND_ID = "line_quadric_lod"
PACKAGE_NAME = "line_quadric_lod"  # the checkout is loaded under this name when run as a script
EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


def main(argv=None, prog: Optional[str] = None) -> int:
    """The command line; returns the exit status (never raises, never calls sys.exit)."""
    import time
    import traceback

    from .headless import arguments, executors, freshness, inputs, report
    from .headless.console import Console
    from .headless.errors import UsageError

    argv = list(sys.argv[1:] if argv is None else argv)
    parser = arguments.build_parser(prog)
    console = Console(quiet="--quiet" in argv)
    try:
        args = parser.parse_args(argv)
    except arguments.HelpShown:
        return EXIT_OK
    except UsageError as ex:
        console.error(f"{ex} (see {parser.prog} --help)")
        return EXIT_USAGE
    arguments.apply_sample_defaults(args)
    problems = arguments.check_args(args)
    try:
        jobs = inputs.plan_jobs(args)
    except UsageError as ex:
        problems += ex.messages
    if problems:
        for message in problems:
            console.error(message)
        return EXIT_USAGE
    console.quiet = args.quiet
    # Several inputs at once (threads here, no Dask needed) or a cluster (Dask; checked
    # now, before anything is done).
    batch = args.scheduler is not None or (args.jobs > 1 and len(jobs) > 1)
    if args.scheduler is not None and not executors.dask_available():
        console.error(executors.SCHEDULER_NEEDS_DASK)
        return EXIT_USAGE
    t0 = time.perf_counter()
    try:
        stream = report.StreamedReport(Path(args.report)) if report.is_streamed(args.report) else None
    except OSError as ex:
        console.error(f"cannot write the report {args.report}: {ex.strerror or ex}")
        return EXIT_USAGE
    on_result = stream.add if stream is not None else (lambda entry: None)
    try:
        if batch:
            from .headless.batch import run_batch
            from .headless.one_input import skipped_entry, up_to_date_key

            # Up-to-date inputs are skipped here, before a Blender process is started for them.
            files = [None] * len(jobs)
            todo = []
            for i, job in enumerate(jobs):
                key = up_to_date_key(job, args)
                if key is not None and freshness.up_to_date(job.outputs, key):
                    files[i] = skipped_entry(job)
                    on_result(files[i])
                else:
                    todo.append(i)
            if todo:
                done = run_batch([jobs[i] for i in todo], args, parser, console, on_result)
                for i, entry in zip(todo, done):
                    files[i] = entry
        else:
            from .headless.one_input import run_serial

            files = run_serial(jobs, args, console, on_result)
        result = report.make_report(COMMAND_ID, args, files, time.perf_counter() - t0)
        if stream is not None:
            stream.finish(result)
        elif args.report:
            report.write_json_atomically(Path(args.report), result)
        report.print_results(result)
    except KeyboardInterrupt:
        console.error("interrupted: files being written were left as they were")
        return EXIT_INTERRUPTED
    except executors.SchedulerError as ex:
        console.error(str(ex))
        return EXIT_USAGE
    except Exception as ex:  # our own bug: still one line unless asked for details
        if args.debug:
            traceback.print_exc()
        console.error(f"unexpected {type(ex).__name__}: {ex}" + ("" if args.debug else " (--debug shows details)"))
        return EXIT_FAILED
    finally:
        if stream is not None:
            stream.close()
    return EXIT_OK if result["ok"] else EXIT_FAILED


def cli_command(argv) -> int:
    """The handler of ``blender -c line_quadric_lod [options]`` (bpy.utils.register_cli_command)."""
    return main(list(argv), prog="blender -b [scene.blend] -c line_quadric_lod")


# ----------------------------------------------------------------------------- run as a script


def load_root_package(root: Path):
    """Import the folder ``root`` (the extension's root) as the package ``line_quadric_lod``,
    whatever the folder is called, so ``addon`` and ``core`` are subpackages as when installed."""
    import importlib.util

    loaded = sys.modules.get(PACKAGE_NAME)
    if loaded is not None:
        if Path(loaded.__file__).resolve().parent == root:
            return loaded
        raise ImportError(f"a different {PACKAGE_NAME} is already imported from {loaded.__file__}")
    spec = importlib.util.spec_from_file_location(
        PACKAGE_NAME, root / "__init__.py", submodule_search_locations=[str(root)])
    module = importlib.util.module_from_spec(spec)
    sys.modules[PACKAGE_NAME] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[PACKAGE_NAME]
        raise
    return module


def run_as_script() -> int:
    """``python <checkout>``, ``python addon/cli.py`` or ``blender -b -P addon/cli.py --``,
    each with the options after it; returns the exit status."""
    import importlib

    here = Path(__file__).resolve().parent
    root = here.parent
    # Python put the folder of the script (the checkout, or addon/) first on sys.path,
    # where its folders and modules would shadow top-level names; everything is
    # imported through the package instead.
    sys.path[:] = [p for p in sys.path if not p or Path(p).resolve() not in (here, root)]
    package = load_root_package(root)
    cli = importlib.import_module(package.__name__ + ".addon.cli")
    if "bpy" in sys.modules:  # inside Blender: our options follow "--"
        argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
        prog = f"blender -b [scene.blend] -P {Path(__file__).name} --"
    else:
        argv, prog = sys.argv[1:], f"python {sys.argv[0]}"
    return cli.main(argv, prog=prog)


if __name__ == "__main__" and not __package__:
    sys.exit(run_as_script())
