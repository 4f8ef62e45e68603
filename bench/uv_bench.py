"""UV benchmark (issue 4): seams, UV flips and texture stretch, core vs Blender's Decimate.

    .venv/bin/python bench/uv_bench.py [--meshes DIR] [--names spot beast] [--ratios 0.25 0.1]
                                       [--json FILE]

For each UV-mapped mesh and ratio, in this process: Blender's Decimate (Collapse, default
options, use_symmetry off; it carries the UV layer itself) at the ratio, then
core.simplify to the *same face count* with the UVs passed as a corner attribute
(``corner_attributes={"uv": ...}, uv_attributes=("uv",)``). Both start from the same
triangle arrays and UVs (Blender's OBJ importer, triangulated). Prints a markdown table on
stdout; bench/README.md explains every column.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (path + isolated user dirs, before bpy)
import tables
import numpy as np

from blender_reference import decimate, load_mesh
from core import DEFAULT_LINE_WEIGHT

UV_TOL = 1e-5  # UV values closer than this are the same (Blender stores UVs as float32)
REF_STRETCH_LIMIT = 100.0  # see uv_metrics: input faces this distorted are no local reference


# ---------------------------------------------------------------- metrics (NumPy)

def edge_table(faces, uv):
    """Undirected edges of a triangle mesh and whether each is a UV seam.

    Returns dict: edges (e, 2) vertex pairs (lo, hi); seam (e,) bool for the interior
    (two-face) edges where the UV of either endpoint differs between the two faces;
    pair (e, 2) the two faces of each interior edge (-1 where not interior); boundary
    and nonmanifold counts.
    """
    f = np.asarray(faces, dtype=np.int64)
    m = len(f)
    a, b = f.ravel(), f[:, [1, 2, 0]].ravel()
    ua, ub = uv.reshape(-1, 2), uv[:, [1, 2, 0]].reshape(-1, 2)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    # The UV at the lower/higher-numbered endpoint, as this face sees it.
    uv_lo = np.where((a == lo)[:, None], ua, ub)
    uv_hi = np.where((a == lo)[:, None], ub, ua)
    key = lo * (int(f.max()) + 1 if m else 1) + hi
    order = np.argsort(key, kind="stable")
    ks = key[order]
    start = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    count = np.diff(np.r_[start, len(ks)])
    edges = np.c_[lo[order[start]], hi[order[start]]]
    interior = count == 2
    h1, h2 = order[start[interior]], order[start[interior] + 1]
    differs = (np.abs(uv_lo[h1] - uv_lo[h2]).max(1) > UV_TOL) | (np.abs(uv_hi[h1] - uv_hi[h2]).max(1) > UV_TOL)
    seam = np.zeros(len(edges), dtype=bool)
    seam[interior] = differs
    pair = np.full((len(edges), 2), -1, dtype=np.int64)
    pair[interior] = np.c_[h1 // 3, h2 // 3]
    return {"edges": edges, "seam": seam, "pair": pair, "interior": interior,
            "boundary": int(np.count_nonzero(count == 1)),
            "nonmanifold": int(np.count_nonzero(count > 2))}


def signed_uv_area(uv) -> np.ndarray:
    d1, d2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    return 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def area_3d(vertices, faces) -> np.ndarray:
    p = vertices[faces]
    return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)


class Source:
    """The input mesh as the reference every output is compared with."""

    def __init__(self, vertices, faces, uv):
        from mathutils.bvhtree import BVHTree

        self.vertices = np.asarray(vertices, dtype=np.float64)
        self.faces = np.asarray(faces, dtype=np.int64)
        self.signed_uv_area = signed_uv_area(uv)
        a3 = area_3d(self.vertices, self.faces)
        with np.errstate(divide="ignore", invalid="ignore"):
            self.area_ratio = a3 / np.abs(self.signed_uv_area)  # inf/nan where degenerate
        ok = np.isfinite(self.area_ratio) & (self.area_ratio > 0)
        self.median_ratio = float(np.median(self.area_ratio[ok]))
        self.tree = BVHTree.FromPolygons(self.vertices.tolist(), self.faces.tolist(), all_triangles=True)

    def nearest_face(self, points) -> np.ndarray:
        """Index of the input face closest to each point (exact, BVH)."""
        find = self.tree.find_nearest
        return np.array([find(p)[2] for p in map(tuple, np.asarray(points).tolist())], dtype=np.int64)


def _stretch(r) -> np.ndarray:
    return np.maximum(r, 1.0 / r)


def uv_metrics(vertices, faces, uv, src: Source, face_origin=None) -> dict:
    """Seams, flips and stretch of one UV-mapped triangle mesh against the input ``src``.

    face_origin (when the method reports provenance, as core does): the input face of
    each output face, for flips against the exact source face.
    """
    v, f = np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64)
    et = edge_table(f, uv)
    seam_edges = et["edges"][et["seam"]]
    seam_length = float(np.linalg.norm(v[seam_edges[:, 0]] - v[seam_edges[:, 1]], axis=1).sum())

    s = signed_uv_area(uv)
    a3 = area_3d(v, f)
    # UV islands: faces joined across interior edges whose UVs agree.
    joined = et["interior"] & ~et["seam"]
    from core.topology import connected_labels  # here, after main() checked that core imports

    island = connected_labels(len(f), et["pair"][joined, 0], et["pair"][joined, 1])
    _, island_idx = np.unique(island, return_inverse=True)
    orientation = np.sign(np.bincount(island_idx, weights=s))  # area-weighted majority
    eps_uv = 1e-12 * max(float(np.abs(s).max(initial=0.0)), 1e-30)
    eps_3d = 1e-12 * max(float(a3.max(initial=0.0)), 1e-30)
    degenerate = np.abs(s) <= eps_uv
    flips_island = int(np.count_nonzero(~degenerate & (np.sign(s) != orientation[island_idx])))

    # The input face under each output triangle's centroid: the same approximate
    # provenance for every method (Blender's Decimate reports none).
    near = src.nearest_face(v[f].mean(axis=1))
    near_sign = np.sign(src.signed_uv_area[near])
    flips_nearest = int(np.count_nonzero(~degenerate & (near_sign != 0) & (np.sign(s) != near_sign)))
    flips_source = None
    if face_origin is not None:
        src_sign = np.sign(src.signed_uv_area[np.asarray(face_origin)])
        flips_source = int(np.count_nonzero(~degenerate & (src_sign != 0) & (np.sign(s) != src_sign)))

    ok = ~degenerate & (a3 > eps_3d)
    ratio = a3[ok] / np.abs(s[ok])
    global_stretch = _stretch(ratio / src.median_ratio)
    ref_local = src.area_ratio[near[ok]]
    # Input faces whose own UV area is off by more than REF_STRETCH_LIMIT from the input's
    # median (near-degenerate UV triangles in the asset) make no reference.
    ref_stretch = _stretch(ref_local / src.median_ratio)
    has_ref = np.isfinite(ref_local) & (ref_local > 0) & (ref_stretch <= REF_STRETCH_LIMIT)
    local_stretch = _stretch(ratio[has_ref] / ref_local[has_ref])
    nan = float("nan")
    return {
        "faces": int(len(f)),
        "seam_edges": int(len(seam_edges)),
        "seam_length": seam_length,
        "islands": int(len(orientation)),
        "flips_island": flips_island,
        "flips_nearest": flips_nearest,
        "flips_source": flips_source,
        "uv_degenerate": int(np.count_nonzero(degenerate)),
        "stretch_mean": float(global_stretch.mean()) if len(global_stretch) else nan,
        "stretch_max": float(global_stretch.max()) if len(global_stretch) else nan,
        "local_stretch_mean": float(local_stretch.mean()) if len(local_stretch) else nan,
        "local_stretch_max": float(local_stretch.max()) if len(local_stretch) else nan,
    }


# ---------------------------------------------------------------- bench

def bench(path: Path, ratios, line_weight) -> list:
    import core

    mesh = load_mesh(path, uv=True)
    if mesh.uv is None:
        raise ValueError(f"{path.name} has no UV map")
    v, f, uv = mesh.vertices, mesh.faces, mesh.uv
    source = Source(v, f, uv)
    rows = [{"mesh": mesh.name, "ratio": 1.0, "method": "input", "seconds": None,
             **uv_metrics(v, f, uv, source, face_origin=np.arange(len(f)))}]
    for ratio in ratios:
        print(f"  {mesh.name} @ {ratio:g}: Blender Decimate ...", file=sys.stderr, flush=True)
        dec = decimate(v, f, ratio, uv)
        rows.append({"mesh": mesh.name, "ratio": ratio, "method": "Blender Decimate",
                     "seconds": dec.seconds, **uv_metrics(dec.vertices, dec.faces, dec.uv, source)})
        print(f"  {mesh.name} @ {ratio:g}: core.simplify to {len(dec.faces)} faces ...",
              file=sys.stderr, flush=True)
        t0 = time.perf_counter()
        res = core.simplify(v, f, target_faces=len(dec.faces), line_weight=line_weight,
                            corner_attributes={"uv": uv}, uv_attributes=("uv",))
        seconds = time.perf_counter() - t0
        rows.append({"mesh": mesh.name, "ratio": ratio, "method": "core", "seconds": seconds,
                     "stop_reason": res.stats.stop_reason,
                     **uv_metrics(res.vertices, res.faces, res.corner_attributes["uv"], source,
                                  face_origin=res.face_origin)})
    src = rows[0]
    for row in rows:
        row["seam_length_percent"] = 100.0 * row["seam_length"] / src["seam_length"] if src["seam_length"] else float("nan")
    return rows


def _fmt(value, spec):
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return "–"
    return format(value, spec)


def markdown_table(rows) -> str:
    lines = [tables.header("mesh", "ratio", "method", "faces", "time (s)", "seam edges", "seam length %", "UV islands",
                           "flips: island", "flips: nearest input", "flips: face_origin", "UV-degenerate",
                           "stretch mean / max", "local stretch mean / max")]
    for r in rows:
        lines.append(tables.row(
            r['mesh'], f"{r['ratio']:g}", r['method'], f"{r['faces']:,}", _fmt(r['seconds'], '.3f'),
            f"{r['seam_edges']:,}", _fmt(r['seam_length_percent'], '.1f'), f"{r['islands']:,}",
            r['flips_island'], r['flips_nearest'], _fmt(r['flips_source'], 'd'),
            r['uv_degenerate'], f"{_fmt(r['stretch_mean'], '.2f')} / {_fmt(r['stretch_max'], '.1f')}",
            f"{_fmt(r['local_stretch_mean'], '.3f')} / {_fmt(r['local_stretch_max'], '.1f')}"))
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--meshes", type=Path, default=_bootstrap.DEFAULT_MESH_DIR)
    ap.add_argument("--names", nargs="+", default=["spot.obj", "beast.obj"],
                    help="UV-mapped mesh files in --meshes (default: %(default)s)")
    ap.add_argument("--ratios", type=float, nargs="+", default=[0.25, 0.1])
    ap.add_argument("--line-weight", type=float, default=DEFAULT_LINE_WEIGHT)
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(argv)
    try:
        import core  # noqa: F401
    except Exception as ex:
        print(f"error: core does not import ({type(ex).__name__}: {ex})", file=sys.stderr)
        return 2
    rows = []
    for name in args.names:
        path = args.meshes / name
        print(path.name, file=sys.stderr, flush=True)
        try:
            rows += bench(path, args.ratios, args.line_weight)
        except Exception as ex:
            print(f"  skipped {path.name}: {type(ex).__name__}: {ex}", file=sys.stderr)
    print(markdown_table(rows))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
