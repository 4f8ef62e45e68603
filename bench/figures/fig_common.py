"""Shared pieces of the figure scripts (bench/figures/fig_*.py): table cells, plotting, output.

Import this first in a figure script: it imports ``_bootstrap`` (repository root on
sys.path, Blender user dirs isolated) before anything can import bpy, and selects
matplotlib's non-interactive Agg backend so figures render without a display.
Figures are written to docs/images/ as PNG.
"""
from __future__ import annotations

import sys
from pathlib import Path

# bench/, for _bootstrap and the scripts the figures share with the benchmarks (tables,
# synthetic_meshes, ...; a figure script runs with only its own folder on sys.path).
_BENCH_DIR = str(Path(__file__).resolve().parent.parent)
if _BENCH_DIR not in sys.path:
    sys.path.insert(0, _BENCH_DIR)

import _bootstrap  # noqa: E402  (path + isolated user dirs, before bpy)

try:
    import matplotlib
except ImportError:  # a dev extra (requirements-dev.txt), never an add-on dependency
    sys.exit("matplotlib is needed for the figures: .venv/bin/python -m pip install matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

REPO_ROOT = _bootstrap.REPO_ROOT
IMAGES = REPO_ROOT / "docs" / "images"
MESH_DIR = _bootstrap.DEFAULT_MESH_DIR
QUALITY_CMAP = "viridis"


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def report_cells(report) -> tuple:
    """A mesh report's table cells: mean q, min q, slivers %, Hausdorff %, mean %
    (the columns of fig_pareto's and fig_weight_sweep's tables)."""
    return (f"{report['mean_quality']:.3f}", f"{report['min_quality']:.3f}", f"{report['sliver_percent']:.2f}",
            f"{report['hausdorff_percent']:.4f}", f"{report['mean_percent']:.5f}")


def plot_mesh_2d(ax, V, F, title: str, quality=None, linewidth: float = 0.3):
    """Top view (x, y) of a flat mesh: every triangle outlined, filled by its quality q."""
    tris = V[F][:, :, :2]
    coll = PolyCollection(tris, edgecolors="black", linewidths=linewidth)
    if quality is not None:
        coll.set_array(quality)
        coll.set_cmap(QUALITY_CMAP)
        coll.set_clim(0.0, 1.0)
    else:
        coll.set_facecolor("#dde6f0")
    ax.add_collection(coll)
    lo, hi = V[:, :2].min(0), V[:, :2].max(0)
    pad = 0.01 * float((hi - lo).max())
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=9)
    return coll


def save(fig, name: str) -> Path:
    IMAGES.mkdir(parents=True, exist_ok=True)
    path = IMAGES / name
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    log(f"wrote {path.relative_to(REPO_ROOT)}")
    return path


def find_mesh(stem: str):
    """Path of ../shared/meshes/<stem>.{obj,gltf,glb} if present, else None."""
    for suffix in (".obj", ".gltf", ".glb"):
        p = MESH_DIR / f"{stem}{suffix}"
        if p.exists():
            return p
    return None
