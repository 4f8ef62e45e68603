"""Input checking: every bad argument gets a ValueError that names it."""
from __future__ import annotations

from typing import Optional

import numpy as np


def as_vertices(vertices) -> np.ndarray:
    v = np.asarray(vertices)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices must be an (n, 3) array, got shape {v.shape}")
    if not np.issubdtype(v.dtype, np.number) or np.issubdtype(v.dtype, np.complexfloating):
        raise ValueError(f"vertices must be real numbers, got dtype {v.dtype}")
    v = v.astype(np.float64)
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        raise ValueError(f"vertices contain NaN or infinite coordinates (first at vertex {int(np.argmax(bad))})")
    return v


def as_faces(faces, n_vertices: int) -> np.ndarray:
    f = np.asarray(faces)
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces must be an (m, 3) array of triangles, got shape {f.shape}")
    if f.size and not np.issubdtype(f.dtype, np.integer):
        raise ValueError(f"faces must hold integer vertex indices, got dtype {f.dtype}")
    f = f.astype(np.int64)
    if f.size and (f.min() < 0 or f.max() >= n_vertices):
        bad = int(f.max()) if f.max() >= n_vertices else int(f.min())
        raise ValueError(f"faces index vertex {bad}, outside 0..{n_vertices - 1}")
    return f


def limits(values, n: int, levels: int, name: str) -> np.ndarray:
    """(levels, n) distances > 0, infinite where there is no limit, from (n,) (every
    level alike) or (levels, n) not decreasing along the chain; ValueError otherwise."""
    a = np.asarray(values)
    if a.shape == (n,):
        a = np.broadcast_to(a, (levels, n))
    if a.shape != (levels, n):
        raise ValueError(f"{name} must have one value per vertex, shape ({n},), or one row per target, "
                         f"({levels}, {n}), got {a.shape}")
    a = a.astype(np.float64)
    if np.isnan(a).any():
        raise ValueError(f"{name} contains NaN (give inf where a vertex has no limit)")
    if (a <= 0).any():
        raise ValueError(f"{name} must be > 0, inf where there is no limit (found {a.min()}): "
                         f"lock the vertices that must not move")
    if (a[1:] < a[:-1]).any():
        raise ValueError(f"{name} must not decrease along the chain: each level goes on from the last")
    return a


def per_vertex(values, n: int, name: str, dtype=np.float64) -> np.ndarray:
    a = np.asarray(values)
    if a.shape != (n,):
        raise ValueError(f"{name} must have one value per vertex, shape ({n},), got {a.shape}")
    if dtype is bool:
        if a.dtype != bool:
            raise ValueError(f"{name} must be a boolean array, got dtype {a.dtype}")
        return a
    a = a.astype(np.float64)
    if not np.isfinite(a).all():
        raise ValueError(f"{name} contains NaN or infinite values")
    if (a < 0).any():
        raise ValueError(f"{name} must be >= 0 (found {a.min()})")
    return a


def non_negative(value, name: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not np.isfinite(x) or x < 0:
        raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
    return x


def targets(targets, m: int, drawn: Optional[int] = None) -> list:
    """``targets`` as ints, non-increasing, each at most the input's count: ``m`` faces,
    or ``drawn`` when parts are drawn several times (Options.part_copies)."""
    top = m if drawn is None else drawn
    out = []
    for t in targets:
        if isinstance(t, (bool, np.bool_)) or int(t) != t:
            raise ValueError(f"target face counts must be whole numbers, got {t!r}")
        t = int(t)
        if t < 0:
            raise ValueError(f"target face count must be >= 0, got {t}")
        if t > top:
            raise ValueError(f"target of {t} faces is more than the input's {m} faces" if drawn is None else
                             f"target of {t} faces is more than the {top} faces the input's parts draw")
        out.append(t)
    if not out:
        raise ValueError("give at least one target")
    if any(b > a for a, b in zip(out, out[1:])):
        raise ValueError(f"LOD targets must not increase, got {out}")
    return out


def max_errors(max_error, levels: int) -> list:
    """``max_error`` as one bound per level: a number for every level, or a sequence of
    ``levels`` non-decreasing ones (a chain of distance targets)."""
    if np.ndim(max_error) == 0:
        return [non_negative(max_error, "max_error")] * levels
    bounds = [non_negative(e, "max_error") for e in max_error]
    if len(bounds) != levels:
        raise ValueError(f"max_error has {len(bounds)} bounds for {levels} targets: give one per target")
    if any(b < a for a, b in zip(bounds, bounds[1:])):
        raise ValueError(f"max_error bounds must not decrease along the chain, got {bounds}")
    return bounds


def vertex_attributes(attrs, n: int) -> dict:
    out = {}
    for name, values in (attrs or {}).items():
        a = np.asarray(values, dtype=np.float64)
        if a.ndim == 1:
            a = a[:, None]
        if a.ndim != 2 or a.shape[0] != n:
            raise ValueError(f"vertex attribute {name!r} must be (n, k) with n = {n}, got shape {np.shape(values)}")
        if not np.isfinite(a).all():
            raise ValueError(f"vertex attribute {name!r} contains NaN or infinite values")
        out[name] = a
    return out


def corner_attributes(attrs, m: int) -> dict:
    out = {}
    for name, values in (attrs or {}).items():
        a = np.asarray(values, dtype=np.float64)
        if a.ndim == 2:
            a = a[:, :, None]
        if a.ndim != 3 or a.shape[:2] != (m, 3):
            raise ValueError(f"corner attribute {name!r} must be (m, 3, k) with m = {m}, got shape {np.shape(values)}")
        if not np.isfinite(a).all():
            raise ValueError(f"corner attribute {name!r} contains NaN or infinite values")
        out[name] = a
    return out


def edge_list(edges, n: int, name: str) -> np.ndarray:
    e = np.asarray(edges)
    if e.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if e.ndim != 2 or e.shape[1] != 2 or not np.issubdtype(e.dtype, np.integer):
        raise ValueError(f"{name} must be a (k, 2) integer array of vertex pairs, got shape {e.shape}, dtype {e.dtype}")
    if e.min() < 0 or e.max() >= n:
        raise ValueError(f"{name} index vertices outside 0..{n - 1}")
    return e.astype(np.int64)


def parts(vertex_part, part_copies, n: int) -> tuple:
    """(labels (n,) int64 or None, copies (n,) float64 per vertex or None): Options.vertex_part
    and Options.part_copies checked; copies need the labels."""
    if vertex_part is None:
        if part_copies is not None:
            raise ValueError("part_copies needs vertex_part: which part each vertex belongs to")
        return None, None
    labels = np.asarray(vertex_part)
    if labels.shape != (n,):
        raise ValueError(f"vertex_part must have one value per vertex, shape ({n},), got {labels.shape}")
    if n and (not np.issubdtype(labels.dtype, np.integer) or labels.min() < 0):
        raise ValueError("vertex_part must hold part numbers: integers >= 0")
    labels = labels.astype(np.int64)
    if part_copies is None:
        return labels, None
    copies = np.asarray(part_copies, dtype=np.float64)
    count = int(labels.max()) + 1 if n else 0
    if copies.ndim != 1 or len(copies) < count:
        raise ValueError(f"part_copies must have one value per part ({count}), got shape {copies.shape}")
    if not np.isfinite(copies).all() or (copies < 1).any() or (copies != np.round(copies)).any():
        raise ValueError("part_copies must be whole numbers >= 1: how many times each part is drawn")
    return labels, copies[labels]
