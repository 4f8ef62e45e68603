# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line's parts; addon/cli.py is its entry point and shows the whole run.

Modules (one idea each). Those marked * need bpy and are imported only once the options
and inputs have been checked, so a mistyped option or a missing file fails at once:
    errors        UsageError (bad command line) and InputError (one input fails)
    arguments     the parser and --help (the panel's settings' options from the settings
                  table, addon/pure/settings.py), checks argparse cannot make, the run's
                  LodSettings (its chain as --ratios/--faces give it), options back to argv
    inputs        file formats, --input expanded into files, one InputJob per input (bpy
                  only for the open .blend when there is no --input)
    console       progress and error lines on stderr
    progress    * an input's per-object, per-LOD progress lines with the time left
    scene_files * an input into the scene, the scene out to a file atomically
    sources     * which objects get LODs, with which importance
    one_input   * one input: load, LodJob (addon/job.py), LOD0 names and group, write
    report        the JSON report (or a .jsonl line per input), the table and the notes
    freshness     is an input's output up to date? (content, options and tool version)
    asset_task    one input's task: this command line on it in a Blender process of its
                  own (standard library only: it also travels by value to Dask workers)
    executors     where the tasks run: N threads here (--jobs) or a Dask cluster (--scheduler,
                  the only part that imports Dask)
    task_runner   the tasks on an executor: retries after crashes, entries streamed as they
                  end and returned in input order
    batch       * --jobs N / --scheduler: the inputs as tasks running this command line
"""
