"""Regenerate every figure and render, and copy what each script printed into docs/figures.md.

    .venv/bin/python bench/fig_all.py [--only fig_planar fig_pareto ...] [--no-docs]

Runs each script below in its own process (bpy can be imported once per process), in
the repository root, and replaces the block between its markers in docs/figures.md

    <!-- BEGIN output of bench/fig_planar.py -->
    ...
    <!-- END output of bench/fig_planar.py -->

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

REPO_ROOT = Path(__file__).resolve().parent.parent
DOC = REPO_ROOT / "docs" / "figures.md"
SCRIPTS = ("fig_planar", "fig_weight_sweep", "fig_importance", "fig_pareto", "fig_skinned", "render")


def markers(name: str) -> tuple:
    return f"<!-- BEGIN output of bench/{name}.py -->", f"<!-- END output of bench/{name}.py -->"


def run(name: str) -> tuple:
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, str(REPO_ROOT / "bench" / f"{name}.py")], cwd=REPO_ROOT,
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
        raise SystemExit(f"docs/figures.md has no markers for {name}: add\n{begin}\n{end}")
    return pattern.sub(lambda _: f"{begin}\n{body}\n{end}", text)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", nargs="+", choices=SCRIPTS, metavar="NAME", help="a subset of: " + " ".join(SCRIPTS))
    ap.add_argument("--no-docs", action="store_true", help="run the scripts but leave docs/figures.md alone")
    args = ap.parse_args()
    status = 0
    text = DOC.read_text(encoding="utf-8") if DOC.exists() and not args.no_docs else None
    head = git_head()
    for name in args.only or SCRIPTS:
        print(f"running bench/{name}.py ...", file=sys.stderr, flush=True)
        proc, seconds = run(name)
        if proc.returncode != 0:
            status = 1
            print(f"bench/{name}.py failed ({proc.returncode}):\n{proc.stderr[-3000:]}", file=sys.stderr)
            continue
        out = proc.stdout.strip()
        print(f"== bench/{name}.py ({seconds:.0f} s)\n{out}\n", flush=True)
        if text is not None:
            body = (f"{as_markdown(out)}\n\n<sub>Printed by `.venv/bin/python bench/{name}.py` at commit {head}, "
                    f"{seconds:.0f} s on this machine.</sub>")
            text = replace_block(text, name, body)
            DOC.write_text(text, encoding="utf-8")  # after each script, so a later failure keeps it
    return status


if __name__ == "__main__":
    sys.exit(main())
