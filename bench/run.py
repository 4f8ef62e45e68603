"""THE benchmark: core.simplify against Blender's Decimate and optional peers, speed and quality.

    .venv/bin/python bench/run.py [--meshes DIR] [--ratios 0.25 0.1] [--repeat N]
                                  [--big | --scan] [--json FILE] [--write-docs] [--skip-core]
                                  [--peers KEY ... | --no-peers]

For every mesh in DIR (default ../shared/meshes next to the checkout) and every ratio,
in this one process: core.simplify (default settings, line_weight 1e-3), Blender's
Decimate modifier (Collapse) and every installed optional peer (bench/peers.py: MeshLab
with and without its planar quadric, meshoptimizer, fast-simplification; a peer that is
not installed is skipped with a note) on the same triangle arrays, then the same
measurements of every output against the input (addon/pure/measure.py). Prints a markdown
table on stdout (progress goes to stderr) and the issue-3 acceptance lines (core vs
Blender) at ratio 0.1. --big adds the ~2M-face mesh made by subdividing ogre twice, with
the peak memory of a core run in a child process; --scan runs only the ~7.9M-face ogre
(subdivided three times) and a 5.2M-face scan-like mesh (synthetic_meshes.scan_like: noise,
random numbering) at 10 % and 1 %, the same way (--only ogre / scan-like picks one). --write-docs also draws the plots into
docs/images/. See bench/README.md for every column.
"""
from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from functools import partial
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import tables
import bpy
import numpy as np

import peers
from addon.pure.measure import DEFAULT_SAMPLES, mesh_report
from blender_reference import decimate, load_mesh
import synthetic_meshes
from synthetic_meshes import subdivide_midpoint
from core import DEFAULT_LINE_WEIGHT, SLIVER_QUALITY
from core.weld import weld_map

MESH_SUFFIXES = (".obj", ".gltf", ".glb")
BIG_SOURCE = "ogre.obj"
BIG_RATIO = 0.1
CRITERIA_RATIO = 0.1
FIDELITY_METHOD = "core, fidelity end (line weight 0, min quality 0)"
# Issue 18's acceptance thresholds (speed and memory from issue 3).
TIME_LIMITS = {"ogre": 2.0}  # core time / Blender time, per mesh
BIG_TIME_LIMIT = 1.0
BIG_MEMORY_LIMIT_MB = 2.5 * 1024
DISTANCE_FACTOR = 1.1
QUALITY_MARGIN = 0.03
SLIVER_LIMIT = 1.0
CAD_MESHES = {"fandisk"}  # judged by the hard-surface lines, not the organic ones
CAD_DISTANCE_FACTOR = 2.0
CAD_SLIVER_LIMIT = 2.0
FIDELITY_ALSO = {"Fox"}  # the fidelity end is also judged on these at CRITERIA_RATIO
JUDGED_AT = {"Fox": 0.25}  # where the defaults are judged, when not at CRITERIA_RATIO
PLOT_TIME = "bench_time_ratio.png"
PLOT_QUALITY = "bench_hausdorff_quality.png"
PLOT_CAPTIONS = {
    PLOT_TIME: "Each method's time over Blender's Decimate, per mesh and ratio (log scale; below 1 = faster).",
    PLOT_QUALITY: "Hausdorff distance against mean triangle quality, one point per mesh and method "
                  "(lower and further right is better).",
}


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def run_blender(vertices, faces, ratio, repeat):
    """Blender's Decimate best of ``repeat`` evaluations; returns the Decimated output."""
    best = None
    for _ in range(max(1, repeat)):
        dec = decimate(vertices, faces, ratio)
        if best is None or dec.seconds < best.seconds:
            best = dec
    return best


def run_core(vertices, faces, ratio, line_weight, repeat, **options):
    """core.simplify best of ``repeat`` wall-clock runs: (vertices, faces, seconds, extra columns)."""
    import core

    best, result = float("inf"), None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        result = core.simplify(vertices, faces, ratio=ratio, line_weight=line_weight, **options)
        best = min(best, time.perf_counter() - t0)
    return (result.vertices, result.faces, best,
            {"stop_reason": result.stats.stop_reason, "passes": result.stats.passes})


def run_peer(peer, module, vertices, faces, ratio, repeat):
    """A peer best of ``repeat`` runs to core's face count for ``ratio`` (output compacted):
    (vertices, faces, seconds of its simplify call, extra columns)."""
    target = max(int(round(ratio * len(faces))), 1)
    best = None
    for _ in range(max(1, repeat)):
        res = peers.run(peer, module, vertices, faces, target)
        if best is None or res.seconds < best.seconds:
            best = res
    return best.vertices, best.faces, best.seconds, {"peer": True}


def measured_row(mesh_name, input_faces, ratio, method, src_v, src_f, out_v, out_f, seconds,
                 samples, extra=None) -> dict:
    rep = mesh_report(src_v, src_f, out_v, out_f, n_samples=samples)
    row = {
        "mesh": mesh_name, "input_faces": int(input_faces), "ratio": ratio, "method": method,
        "faces": int(len(out_f)), "seconds": seconds,
        "hausdorff_percent": rep["hausdorff_percent"], "mean_percent": rep["mean_percent"],
        "mean_quality": rep["mean_quality"], "min_quality": rep["min_quality"],
        "sliver_percent": rep["sliver_percent"], "measure_seconds": rep["seconds"],
    }
    row.update(extra or {})
    return row


def welded(vertices, faces):
    """(vertices, faces, how many vertices merged): exactly coincident vertices welded.

    Exported game assets often give every triangle its own three vertices (the Fox).
    core welds them itself; Blender's Decimate and the peers do not, and on such input
    they can only delete whole triangles. They get what an artist would hand Decimate
    after Merge by Distance: the same surface, welded. Distances are still measured
    against the input as imported."""
    rep = weld_map(vertices, None)
    used, inverse = np.unique(rep, return_inverse=True)
    if len(used) == len(vertices):
        return vertices, faces, 0
    return vertices[used], inverse.reshape(-1)[faces], len(vertices) - len(used)


def bench_mesh(name, vertices, faces, ratios, args) -> list:
    """Rows per ratio: Blender Decimate, core (unless --skip-core), then every available peer.

    Where the input has split (coincident) vertices, Blender and the peers get it welded
    (see ``welded``) and one more row shows Blender's Decimate on the input as imported."""
    rows = []
    w_vertices, w_faces, merged = welded(vertices, faces)
    if merged:
        log(f"  {name}: {merged:,} coincident vertices welded for Blender and the peers")
    for ratio in ratios:
        log(f"  {name} @ {ratio:g}: Blender Decimate (best of {args.repeat}) ...")
        dec = run_blender(w_vertices, w_faces, ratio, args.repeat)
        blender = measured_row(name, len(faces), ratio, "Blender Decimate", vertices, faces,
                               dec.vertices, dec.faces, dec.seconds, args.samples,
                               {"welded_vertices": merged})
        rows.append(blender)
        if merged:
            raw = run_blender(vertices, faces, ratio, 1)
            rows.append(measured_row(name, len(faces), ratio, "Blender Decimate, unwelded", vertices,
                                     faces, raw.vertices, raw.faces, raw.seconds, args.samples,
                                     {"table_only": True}))
        if not args.skip_core:
            log(f"  {name} @ {ratio:g}: core.simplify (best of {args.repeat}) ...")
            rows.append(_timed_row(name, vertices, faces, ratio, "core", dec.seconds, args,
                                   partial(run_core, vertices, faces, ratio, args.line_weight, args.repeat)))
            # The other end of the shape-versus-fidelity control (issue 18): plain
            # Garland-Heckbert order, no sliver floor.
            log(f"  {name} @ {ratio:g}: {FIDELITY_METHOD} ...")
            fidelity = _timed_row(name, vertices, faces, ratio, FIDELITY_METHOD, dec.seconds, args,
                                  partial(run_core, vertices, faces, ratio, 0.0, 1, min_quality=0.0))
            fidelity["table_only"] = True
            rows.append(fidelity)
        for peer, module in args.peer_modules:
            log(f"  {name} @ {ratio:g}: {peer.method} (best of {args.repeat}) ...")
            rows.append(_timed_row(name, vertices, faces, ratio, peer.method, dec.seconds, args,
                                   partial(run_peer, peer, module, w_vertices, w_faces, ratio, args.repeat)))
    return rows


def _timed_row(name, vertices, faces, ratio, method, blender_seconds, args, run) -> dict:
    """The measured row of one method; ``run()`` -> (vertices, faces, seconds, extra columns)."""
    try:
        out_v, out_f, seconds, extra = run()
        if len(out_f) == 0:
            raise ValueError("returned no faces")
    except Exception as ex:  # one failing method or mesh must not cost the rest of the table
        log(f"  {method} failed on {name} @ {ratio:g}: {type(ex).__name__}: {ex}")
        return {"mesh": name, "input_faces": int(len(faces)), "ratio": ratio,
                "method": method, "error": f"{type(ex).__name__}: {ex}"}
    extra["time_ratio"] = seconds / blender_seconds if blender_seconds > 0 else float("nan")
    return measured_row(name, len(faces), ratio, method, vertices, faces, out_v, out_f, seconds,
                        args.samples, extra)


def core_peak_memory(vertices, faces, ratio, line_weight) -> dict:
    """Run core_memory.py in a child process on these arrays; its JSON report."""
    with tempfile.TemporaryDirectory(prefix="lqlod_bench_") as tmp:
        path = Path(tmp) / "mesh.npz"
        np.savez(path, vertices=vertices, faces=faces)
        proc = subprocess.run(
            [sys.executable, str(_bootstrap.BENCH_DIR / "core_memory.py"), str(path), str(ratio),
             str(line_weight)], capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"core_memory.py failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def bench_big(mesh_dir: Path, args, subdivisions: int = 2, ratios=(BIG_RATIO,)) -> tuple:
    """ogre subdivided ``subdivisions`` times (each 1 -> 4 faces) at ``ratios``: rows and the
    memory report (of the first ratio; every core row gets its own peak_rss_mb)."""
    src = mesh_dir / BIG_SOURCE
    base = load_mesh(src)
    v, f = base.vertices, base.faces
    for _ in range(subdivisions):
        v, f = subdivide_midpoint(v, f)
    name = f"{src.stem} x{4 ** subdivisions} (subdivided {subdivisions} times)"
    log(f"big mesh: {name}, {len(f):,} faces")
    rows = bench_mesh(name, v, f, list(ratios), args)
    for row in rows:
        row["big"] = True
    memory = None
    if not args.skip_core:
        for ratio in ratios:
            log(f"  core.simplify peak memory at {ratio:g} in a child process ...")
            report = core_peak_memory(v, f, ratio, args.line_weight)
            memory = memory or report
            for row in rows:
                if row["method"] == "core" and row["ratio"] == ratio:
                    row["peak_rss_mb"] = report["peak_rss_mb"]
                    log(f"  {ratio:g}: peak {report['peak_rss_mb']:.0f} MB, {report['seconds']:.1f} s in the child")
    return rows, memory


def bench_scan_like(args) -> list:
    """synthetic_meshes.scan_like at SCAN_RATIOS, each core row with its peak memory."""
    v, f = synthetic_meshes.scan_like()
    name = f"{SCAN_LIKE} (noisy bumpy sphere, random order)"
    log(f"scan-like mesh: {name}, {len(f):,} faces")
    rows = bench_mesh(name, v, f, list(SCAN_RATIOS), args)
    if not args.skip_core:
        for ratio in SCAN_RATIOS:
            log(f"  core.simplify peak memory at {ratio:g} in a child process ...")
            report = core_peak_memory(v, f, ratio, args.line_weight)
            log(f"  {ratio:g}: peak {report['peak_rss_mb']:.0f} MB, {report['seconds']:.1f} s in the child")
            for row in rows:
                if row["method"] == "core" and row["ratio"] == ratio:
                    row["peak_rss_mb"] = report["peak_rss_mb"]
    return rows


# ---------------------------------------------------------------- report

def _fmt(value, spec):
    return "–" if value is None or (isinstance(value, float) and np.isnan(value)) else format(value, spec)


def markdown_table(rows) -> str:
    lines = [tables.header("mesh", "input faces", "ratio", "method", "faces", "time (s)", "× Blender", "Hausdorff %",
                           "mean %", "mean q", "min q", f"q<{SLIVER_QUALITY:g} %")]
    for r in rows:
        if "error" in r:
            # the failure spans the remaining columns: empty cells without spaces
            lines.append(tables.row(r['mesh'], f"{r['input_faces']:,}", f"{r['ratio']:g}", r['method'],
                                    f"failed: {r['error']}") + "|" * 6)
            continue
        lines.append(tables.row(
            r['mesh'], f"{r['input_faces']:,}", f"{r['ratio']:g}", r['method'], f"{r['faces']:,}",
            _fmt(r['seconds'], '.3f'), _fmt(r.get('time_ratio'), '.2f'),
            _fmt(r['hausdorff_percent'], '.4f'), _fmt(r['mean_percent'], '.5f'),
            _fmt(r['mean_quality'], '.3f'), _fmt(r['min_quality'], '.3f'),
            _fmt(r['sliver_percent'], '.2f')))
    return "\n".join(lines)


def plot_results(rows, directory: Path) -> list:
    """PNGs in ``directory``: time / Blender's per mesh and method (bars, one panel per ratio),
    and Hausdorff against mean q (colour = method, marker = mesh, one panel per ratio).

    Returns the paths written ([] and a log line when matplotlib is missing)."""
    try:
        import matplotlib
    except ImportError:
        log("plots skipped: matplotlib is not installed (it is in requirements-dev.txt)")
        return []
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FormatStrFormatter

    ok = [r for r in rows if "error" not in r and not r.get("table_only")]
    methods = list(dict.fromkeys(r["method"] for r in ok))
    meshes = list(dict.fromkeys(r["mesh"] for r in ok))
    ratios = sorted({r["ratio"] for r in ok}, reverse=True)
    color = {m: f"C{i}" for i, m in enumerate(methods)}
    marker = {m: "osD^v<>pP*hX"[i % 12] for i, m in enumerate(meshes)}
    timed = [m for m in methods if m != "Blender Decimate"]
    directory.mkdir(parents=True, exist_ok=True)
    paths = []

    def finish(fig, name, handles):
        fig.legend(handles=handles, loc="outside lower center", ncols=min(len(handles), 4), fontsize=8)
        paths.append(directory / name)
        fig.savefig(paths[-1], dpi=110)
        plt.close(fig)
        log(f"wrote {paths[-1]}")

    def log_axis(ax):
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.grid(alpha=0.3, which="both")

    if timed:
        fig, axes = plt.subplots(len(ratios), 1, squeeze=False, layout="constrained",
                                 figsize=(max(6.0, 0.45 * len(meshes) * len(timed)), 1.2 + 2.8 * len(ratios)))
        width = 0.8 / len(timed)
        for ax, ratio in zip(axes[:, 0], ratios):
            for j, m in enumerate(timed):
                val = {r["mesh"]: r.get("time_ratio", np.nan) for r in ok if r["method"] == m and r["ratio"] == ratio}
                ax.bar(np.arange(len(meshes)) + (j - (len(timed) - 1) / 2) * width,
                       [val.get(mesh, np.nan) for mesh in meshes], width, color=color[m])
            ax.axhline(1.0, color="black", lw=0.8)
            log_axis(ax)
            ax.set_xticks(np.arange(len(meshes)), meshes, fontsize=8)
            ax.set_ylabel("time / Blender Decimate's")
            ax.set_title(f"ratio {ratio:g}: below 1 = faster than Blender's Decimate", fontsize=9)
        finish(fig, PLOT_TIME, [plt.Rectangle((0, 0), 1, 1, color=color[m], label=m) for m in timed])

    fig, axes = plt.subplots(1, len(ratios), figsize=(1 + 5 * len(ratios), 4.8), squeeze=False, layout="constrained")
    for ax, ratio in zip(axes[0], ratios):
        for r in ok:
            if r["ratio"] == ratio:
                ax.scatter(r["mean_quality"], r["hausdorff_percent"], color=color[r["method"]],
                           marker=marker[r["mesh"]], s=30, alpha=0.85)
        log_axis(ax)
        ax.set_xlabel("mean triangle quality q (higher is better)")
        ax.set_ylabel("Hausdorff, % of bounding-box diagonal (lower is better)")
        ax.set_title(f"ratio {ratio:g}", fontsize=9)
    finish(fig, PLOT_QUALITY,
           [Line2D([], [], ls="", marker="o", color=color[m], label=m) for m in methods]
           + [Line2D([], [], ls="", marker=marker[m], color="gray", label=m) for m in meshes])
    return paths


# Issue 21: the scan-sized meshes (--scan) at 10 % and 1 %.
SCAN_RATIOS = (0.1, 0.01)
SCAN_LIKE = "scan-like"
SCAN_TIME_LIMIT = 0.7  # x Decimate's time, in the same process
SCAN_MEMORY_LIMIT_MB = 6 * 1024  # peak RSS of a process that loads the mesh and runs the core


def scan_criteria(rows) -> list:
    """Issue 21's lines for the --scan mesh: (passed, text) per ratio, time and memory."""
    out = []
    for c in rows:
        if c["method"] != "core" or "error" in c:
            continue
        tag = f"{c['mesh']} @ {c['ratio']:.0%}"
        out.append((c["time_ratio"] <= SCAN_TIME_LIMIT,
                    f"{tag}: core time {c['seconds']:.1f} s = {c['time_ratio']:.2f}x Blender's (limit {SCAN_TIME_LIMIT}x)"))
        if "peak_rss_mb" in c:
            out.append((c["peak_rss_mb"] <= SCAN_MEMORY_LIMIT_MB,
                        f"{tag}: core peak RSS {c['peak_rss_mb']:.0f} MB (limit {SCAN_MEMORY_LIMIT_MB} MB; "
                        f"child process)"))
    return out


def criteria(rows, memory=None, big_name=None) -> list:
    """Issue 18's acceptance checks: (passed, text) per check.

    Speed and memory at CRITERIA_RATIO (ogre, the big mesh). Organic meshes (all but the
    CAD ones) with the defaults at their judging ratio (10 %, the Fox 25 %): Hausdorff and
    mean distance within 1.1x Decimate's, mean quality 0.03 above, slivers at most 1 %.
    CAD meshes with the defaults at 10 %: Hausdorff within 2x, slivers at most 2 %. The
    fidelity end (line weight 0, min quality 0) of CAD meshes and the Fox at 10 %:
    Hausdorff and mean within 1.1x."""
    out = []
    by_key = {}
    for r in rows:
        by_key.setdefault((r["mesh"], round(r["ratio"], 6)), {})[r["method"]] = r
    for (mesh, ratio), group in sorted(by_key.items(), key=lambda kv: (kv[0][0], -kv[0][1])):
        b, c = group.get("Blender Decimate"), group.get("core")
        if b is None or c is None:
            continue
        tag = f"{mesh} @ {ratio:.0%}"
        if "error" in c:
            out.append((False, f"{tag}: core failed: {c['error']}"))
            continue
        at_criteria = abs(ratio - CRITERIA_RATIO) < 1e-9
        limit = BIG_TIME_LIMIT if mesh == big_name else TIME_LIMITS.get(mesh)
        if limit is not None and at_criteria:
            out.append((c["time_ratio"] <= limit,
                        f"{tag}: core time {c['seconds']:.3f} s = {c['time_ratio']:.2f}x Blender's "
                        f"{b['seconds']:.3f} s (limit {limit:.1f}x)"))
        if mesh == big_name:
            # Only speed and memory for the generated mesh: Decimate can rebuild the
            # original, flat-faced ogre from it almost exactly, a degenerate comparison.
            if memory is not None:
                out.append((memory["peak_rss_mb"] <= BIG_MEMORY_LIMIT_MB,
                            f"{tag}: core peak RSS {memory['peak_rss_mb']:.0f} MB "
                            f"(limit {BIG_MEMORY_LIMIT_MB:.0f} MB; child process, {memory['source']})"))
            continue
        fid = group.get(FIDELITY_METHOD)
        if at_criteria and (mesh in CAD_MESHES or mesh in FIDELITY_ALSO) and fid is not None:
            for key, label in (("hausdorff_percent", "Hausdorff"), ("mean_percent", "mean distance")):
                ok = "error" not in fid and fid[key] <= DISTANCE_FACTOR * b[key]
                out.append((ok, f"{tag}: fidelity end {label} {fid.get(key, float('nan')):.4f} % vs "
                                f"Blender {b[key]:.4f} % (limit {DISTANCE_FACTOR}x)"))
        if mesh in CAD_MESHES:
            if at_criteria:
                out.append((c["hausdorff_percent"] <= CAD_DISTANCE_FACTOR * b["hausdorff_percent"],
                            f"{tag}: Hausdorff {c['hausdorff_percent']:.4f} % vs Blender "
                            f"{b['hausdorff_percent']:.4f} % (limit {CAD_DISTANCE_FACTOR}x)"))
                out.append((c["sliver_percent"] <= CAD_SLIVER_LIMIT,
                            f"{tag}: slivers (q<{SLIVER_QUALITY:g}) {c['sliver_percent']:.2f} % "
                            f"(limit {CAD_SLIVER_LIMIT:g} %)"))
            continue
        if abs(ratio - JUDGED_AT.get(mesh, CRITERIA_RATIO)) > 1e-9:
            continue
        for key, label in (("hausdorff_percent", "Hausdorff"), ("mean_percent", "mean distance")):
            out.append((c[key] <= DISTANCE_FACTOR * b[key],
                        f"{tag}: {label} {c[key]:.4f} % vs Blender {b[key]:.4f} % "
                        f"(limit {DISTANCE_FACTOR}x = {DISTANCE_FACTOR * b[key]:.4f} %)"))
        out.append((c["mean_quality"] >= b["mean_quality"] + QUALITY_MARGIN,
                    f"{tag}: mean q {c['mean_quality']:.3f} vs Blender {b['mean_quality']:.3f} "
                    f"(need >= {b['mean_quality'] + QUALITY_MARGIN:.3f})"))
        out.append((c["sliver_percent"] <= SLIVER_LIMIT,
                    f"{tag}: slivers (q<{SLIVER_QUALITY:g}) {c['sliver_percent']:.2f} % (limit {SLIVER_LIMIT:g} %)"))
    return out


def environment() -> dict:
    try:
        commit = subprocess.run(["git", "-C", str(_bootstrap.REPO_ROOT), "describe", "--always",
                                 "--dirty"], capture_output=True, text=True).stdout.strip()
    except OSError:
        commit = ""
    cpu = platform.processor()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {
        "date": datetime.datetime.now().isoformat(timespec="seconds"),
        "commit": commit, "blender": bpy.app.version_string, "numpy": np.__version__,
        "python": platform.python_version(), "cpu": cpu, "cpu_count": os.cpu_count(),
        "load_average": [round(x, 2) for x in os.getloadavg()],
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--meshes", type=Path, default=_bootstrap.DEFAULT_MESH_DIR,
                    help="directory of .obj/.gltf/.glb meshes (default: %(default)s)")
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.25, 0.1])
    ap.add_argument("--repeat", type=int, default=1,
                    help="runs per case of each method; the best time counts (default %(default)s)")
    ap.add_argument("--line-weight", type=float, default=DEFAULT_LINE_WEIGHT)
    ap.add_argument("--samples", type=int, default=DEFAULT_SAMPLES,
                    help="area-uniform samples per surface for the distances (default %(default)s)")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="only meshes whose file stem is listed")
    ap.add_argument("--big", action="store_true", help="also the ~2M-face subdivided ogre at 10%%")
    ap.add_argument("--big-only", action="store_true", help="only the ~2M-face mesh")
    ap.add_argument("--scan", action="store_true",
                    help="only the scan-sized meshes: the ~7.9M-face ogre (subdivided three times) and a "
                         "5.2M-face scan-like one, at 10%% and 1%%, with the core's peak memory in a child "
                         "process (issue 21; about 35 minutes; --only ogre or scan-like for one)")
    ap.add_argument("--skip-core", action="store_true", help="no core rows (a dry run of the rest)")
    ap.add_argument("--peers", nargs="+", choices=peers.PEER_KEYS, metavar="KEY",
                    help=f"only these optional peers ({', '.join(peers.PEER_KEYS)}; default: every installed one)")
    ap.add_argument("--no-peers", action="store_true", help="core and Blender only")
    ap.add_argument("--json", type=Path, help="also write every row and the environment as JSON")
    ap.add_argument("--write-docs", action="store_true",
                    help="write the table to docs/benchmarks.md and the plots to docs/images/")
    args = ap.parse_args(argv)
    # Taken before the run: the working tree (the engine) may change while a long run goes.
    env = environment()
    load_start = env["load_average"]

    if not args.skip_core:
        try:
            import core  # noqa: F401
        except Exception as ex:
            log(f"error: core does not import ({type(ex).__name__}: {ex}); use --skip-core for a dry run")
            return 2
    if not args.meshes.is_dir():
        log(f"error: no mesh directory {args.meshes} (give one with --meshes)")
        return 2
    # Imported only now, after bpy (see peers.py: pymeshlab's embree breaks a later bpy import).
    args.peer_modules, peer_notes = ([], []) if args.no_peers else peers.available(args.peers)
    for note in peer_notes:
        log(note)
    env["peers"] = {p.method: peers.version_of(p) for p, _ in args.peer_modules}

    rows, skipped, memory, big_name = [], [], None, None
    if args.scan:
        unknown = sorted(set(args.only or ()) - {"ogre", SCAN_LIKE})
        if unknown:
            ap.error(f"--scan --only takes ogre and/or {SCAN_LIKE}, not {', '.join(unknown)}")
        scan_rows = []
        if not args.only or "ogre" in args.only:
            scan_rows += bench_big(args.meshes, args, subdivisions=3, ratios=SCAN_RATIOS)[0]
        if not args.only or SCAN_LIKE in args.only:
            scan_rows += bench_scan_like(args)
        rows += scan_rows
        for row in scan_rows:
            if "peak_rss_mb" in row:
                log(f"{row['mesh']} @ {row['ratio']:g}: core {row['seconds']:.1f} s "
                    f"({row.get('time_ratio', float('nan')):.2f}x Decimate), peak {row['peak_rss_mb']:.0f} MB")
    elif not args.big_only:
        files = sorted(p for p in args.meshes.iterdir() if p.suffix.lower() in MESH_SUFFIXES)
        if args.only:
            files = [p for p in files if p.stem in args.only]
        for path in files:
            log(f"{path.name}")
            try:
                mesh = load_mesh(path)
            except Exception as ex:
                log(f"  skipped {path.name}: {type(ex).__name__}: {ex}")
                skipped.append((path.name, f"{type(ex).__name__}: {ex}"))
                continue
            rows += bench_mesh(mesh.name, mesh.vertices, mesh.faces, args.ratios, args)
    if args.big or args.big_only:
        big_rows, memory = bench_big(args.meshes, args)
        big_name = big_rows[0]["mesh"]
        rows += big_rows

    env["load_average_start"] = load_start
    env["load_average"] = [round(x, 2) for x in os.getloadavg()]
    table = markdown_table(rows)
    checks = scan_criteria(rows) if args.scan else criteria(rows, memory, big_name)
    check_lines = [f"{'PASS' if ok else 'FAIL'} {text}" for ok, text in checks]
    notes = [f"skipped {name}: {why}" for name, why in skipped]
    notes += peer_notes
    notes += [f"{p.method} {env['peers'][p.method]}: {p.options}" for p, _ in args.peer_modules]
    # Times are wall clock on a shared machine: say how busy it was.
    notes.append(f"load average (1/5/15 min) at start {load_start}, at end {env['load_average']} "
                 f"on {env['cpu_count']} cores")
    if memory is not None:
        notes.append(f"core peak memory on the big mesh: {memory['peak_rss_mb']:.0f} MB peak RSS "
                     f"({memory['source']}) of a child "
                     f"process running only core.simplify ({memory['before_rss_mb']:.0f} MB before the call: "
                     f"interpreter, NumPy, input arrays); simplify took {memory['seconds']:.2f} s there")
    print(table)
    print()
    for line in check_lines + notes:
        print(line)
    if args.json:
        args.json.write_text(json.dumps({"environment": env, "rows": rows, "criteria": checks,
                                         "skipped": skipped, "memory": memory, "peer_notes": peer_notes},
                                        indent=2))
    if args.write_docs:
        cmd = "bench/run.py " + " ".join(argv if argv is not None else sys.argv[1:])
        plots = plot_results(rows, _bootstrap.REPO_ROOT / "docs" / "images")
        doc = [
            "# Benchmarks", "",
            f"Generated by `.venv/bin/python {cmd.strip()}` on {env['date']} "
            f"(commit {env['commit']}; Blender {env['blender']} as the bpy module, NumPy {env['numpy']}, "
            f"Python {env['python']}; {env['cpu']}, {env['cpu_count']} cores; "
            f"load average {env['load_average_start'][0]} at start).", "",
            "core.simplify (line_weight 1e-3), Blender's Decimate modifier (Collapse) and the optional "
            "peers that are installed (MeshLab's quadric edge collapse with and without its planar quadric, "
            "meshoptimizer, fast-simplification; options in the notes below) run in the same "
            "process on the same triangles; × Blender is each method's time over Decimate's. "
            "Distances are two-sided, in % of the input's bounding-box "
            "diagonal; q is triangle quality (1 = equilateral). Columns are explained in "
            "[bench/README.md](../bench/README.md). The acceptance lines compare core with Blender only.", "",
            table, "",
            *(f"- {line}" for line in check_lines + notes),
            "",
            *(f"{PLOT_CAPTIONS[p.name]}\n\n![{p.stem}](images/{p.name})\n" for p in plots),
        ]
        out = _bootstrap.REPO_ROOT / "docs" / "benchmarks.md"
        out.parent.mkdir(exist_ok=True)
        out.write_text("\n".join(doc), encoding="utf-8")
        log(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
