"""Shared pieces of the figure scripts (bench/figures/fig_*.py): meshes they build, plotting, output.

Import this first in a figure script: it imports ``_bootstrap`` (repository root on
sys.path, Blender user dirs isolated) before anything can import bpy, and selects
matplotlib's non-interactive Agg backend so figures render without a display.
Figures are written to docs/images/ as PNG.
"""
from __future__ import annotations

import sys
from pathlib import Path

# bench/, for _bootstrap and the scripts the figures share with the benchmarks (a figure
# script runs with only its own folder on sys.path).
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
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

REPO_ROOT = _bootstrap.REPO_ROOT
IMAGES = REPO_ROOT / "docs" / "images"
MESH_DIR = _bootstrap.DEFAULT_MESH_DIR
QUALITY_CMAP = "viridis"


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def grid(n: int, jitter: float = 0.0, seed: int = 0, size: float = 1.0):
    """A flat n x n vertex grid on [0, size]^2 (z = 0), each quad split into two triangles.

    Interior vertices move in the plane by up to ``jitter`` grid spacings (uniform), so the
    triangulation is irregular but the surface stays exactly flat.
    Returns V (n*n, 3) f64, F (2 (n-1)^2, 3) i64, counter-clockwise seen from +z.
    """
    xs = np.linspace(0.0, size, n)
    X, Y = np.meshgrid(xs, xs, indexing="xy")
    V = np.stack([X.ravel(), Y.ravel(), np.zeros(n * n)], axis=1)
    if jitter > 0:
        h = size / (n - 1)
        x, y = V[:, 0], V[:, 1]
        inner = (x > 0) & (x < size) & (y > 0) & (y < size)
        rng = np.random.default_rng(seed)
        V[inner, :2] += rng.uniform(-jitter * h, jitter * h, (int(inner.sum()), 2))
    r, c = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (r * n + c).ravel()
    b, d = a + 1, a + n
    e = d + 1
    F = np.concatenate([np.stack([a, b, e], 1), np.stack([a, e, d], 1)]).astype(np.int64)
    return V, F


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


def bumpy_sphere(subdivisions: int = 5, amplitude: float = 0.08):
    """A procedural stand-in for a scanned mesh: an icosphere with smooth bumps (pure NumPy)."""
    t = (1.0 + 5 ** 0.5) / 2
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
                  [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4],
                  [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8],
                  [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]], np.int64)
    from synthetic_meshes import subdivide_midpoint

    for _ in range(subdivisions):
        V, F = subdivide_midpoint(V, F)
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    x, y, z = V.T
    r = 1.0 + amplitude * (np.sin(5 * x) * np.sin(4 * y) * np.sin(6 * z) + 0.5 * np.sin(11 * x + 3 * z))
    return V * r[:, None], F
