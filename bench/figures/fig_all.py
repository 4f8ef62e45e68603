"""Regenerate every figure and render, and copy what each script printed into its doc.

    .venv/bin/python bench/figures/fig_all.py [--only fig_planar fig_pareto ...] [--no-docs]

Runs each script below in its own process (bpy can be imported once per process), in
the repository root, and replaces the block between its markers in the script's doc
(docs/figures.md unless DOCS names another: fig_panel's pictures go to docs/panel.md)

    <!-- BEGIN output of bench/figures/fig_planar.py -->
    ...
    <!-- END output of bench/figures/fig_planar.py -->

with the script's stdout, so the numbers quoted in the docs are exactly the ones the
scripts print. A script that fails leaves its block as it was and makes the exit status 1.
"""
from __future__ import annotations

import argparse
import re
import subprocess
import sys
import time
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[2]
DOC = REPO_ROOT / "docs" / "figures.md"
SCRIPTS = ("fig_planar", "fig_weight_sweep", "fig_importance", "importance_calibration", "fig_pareto", "fig_skinned",
           "render", "fig_panel", "switch_distances", "fig_heat_map")
# Where a script lives, where it is not next to this one: the calibration is a measurement
# (addon/pure/importance.py's table comes from it) that also draws a figure.
SCRIPT_PATHS = {"importance_calibration": "bench/importance_calibration.py"}
# The doc a script's output block lives in, where it is not DOC.
DOCS = {"fig_panel": REPO_ROOT / "docs" / "panel.md", "fig_heat_map": REPO_ROOT / "docs" / "panel.md",
        "importance_calibration": REPO_ROOT / "docs" / "weight-painting.md",
        "switch_distances": REPO_ROOT / "docs" / "engines.md"}


def doc_for(name: str) -> Path:
    return DOCS.get(name, DOC)


def script_path(name: str) -> str:
    """The script's path from the repository root, as the docs name it."""
    return SCRIPT_PATHS.get(name, f"bench/figures/{name}.py")


def markers(name: str) -> tuple:
    return f"<!-- BEGIN output of {script_path(name)} -->", f"<!-- END output of {script_path(name)} -->"


def run(name: str) -> tuple:
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, str(REPO_ROOT / script_path(name))], cwd=REPO_ROOT,
                          capture_output=True, text=True)
    return proc, time.perf_counter() - t0


def git_head() -> str:
    proc = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO_ROOT, capture_output=True, text=True)
    return proc.stdout.strip() or "unknown"


def as_markdown(out: str) -> str:
    """Each printed line its own paragraph, tables kept together (blank lines around them)."""
    lines, prev_table = [], None
    for line in out.splitlines():
        is_table = line.startswith("|")
        if prev_table is not None and not (is_table and prev_table):
            lines.append("")
        lines.append(line)
        prev_table = is_table
    return "\n".join(lines)


def replace_block(text: str, name: str, body: str) -> str:
    begin, end = markers(name)
    pattern = re.compile(re.escape(begin) + r".*?" + re.escape(end), re.S)
    if not pattern.search(text):
        doc = doc_for(name).relative_to(REPO_ROOT)
        raise SystemExit(f"{doc} has no markers for {name}: add\n{begin}\n{end}")
    return pattern.sub(lambda _: f"{begin}\n{body}\n{end}", text)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", nargs="+", choices=SCRIPTS, metavar="NAME", help="a subset of: " + " ".join(SCRIPTS))
    ap.add_argument("--no-docs", action="store_true", help="run the scripts but leave the docs alone")
    args = ap.parse_args()
    status = 0
    head = git_head()
    for name in args.only or SCRIPTS:
        print(f"running {script_path(name)} ...", file=sys.stderr, flush=True)
        proc, seconds = run(name)
        if proc.returncode != 0:
            status = 1
            print(f"{script_path(name)} failed ({proc.returncode}):\n{proc.stderr[-3000:]}", file=sys.stderr)
            continue
        out = proc.stdout.strip()
        print(f"== {script_path(name)} ({seconds:.0f} s)\n{out}\n", flush=True)
        doc = doc_for(name)
        if not args.no_docs and doc.exists():
            body = (f"{as_markdown(out)}\n\n<sub>Printed by `.venv/bin/python {script_path(name)}` at commit {head}, "
                    f"{seconds:.0f} s on this machine.</sub>")
            # Read and written per script, so a later failure keeps what is done.
            doc.write_text(replace_block(doc.read_text(encoding="utf-8"), name, body), encoding="utf-8")
    return status


if __name__ == "__main__":
    sys.exit(main())
