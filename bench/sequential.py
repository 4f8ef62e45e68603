"""The paper's sequential algorithm, one collapse at a time: the quality reference for core.

    .venv/bin/python bench/sequential.py [--meshes DIR] [--only NAME ...] [--ratio 0.1]
                                         [--line-weight 1e-3] [--cost paper|per_area]
                                         [--no-guards] [--samples N] [--no-blender]

Liu et al. (SGP 2025), Sec. 3 and 4.1-4.2, as a greedy edge collapse: area-weighted
triangle plane quadrics (Eq. 7-8) plus the line quadric w_i a_i Q_i^l along the
area-weighted vertex normal (Eq. 12-16), memory accumulation Q_new = Q_i + Q_j, the
optimal position from A x = -b, and a binary heap popped cheapest first with lazy
invalidation. The initial quadrics, the mesh preparation (weld, normalise) and the solve
are core's own (core.prepare, core.vertex_quadrics, core.quadrics), so the only thing
that differs from core.simplify is the order of collapses: greedy here, vectorised
passes of independent local minima there. That difference is what this script measures
(issue 3: "Passes must not cost us the sequential algorithm's quality").

A Python loop per collapse is fine here: this is a bench script, not product code.

The command runs, per mesh and in one process, this reference, core.simplify with the
same settings and Blender's Decimate, and prints one markdown table (progress on stderr).
"""
from __future__ import annotations

import heapq
import sys
import time
from pathlib import Path

import numpy as np

# Importable from the tests without bench/_bootstrap (which must precede bpy, and the
# library part below never touches bpy): only the repository root is needed for core.
_REPO_ROOT = Path(__file__).resolve().parent.parent
if str(_REPO_ROOT) not in sys.path:
    sys.path.insert(0, str(_REPO_ROOT))

from core import DEFAULT_LINE_WEIGHT, Options, prepare, quadrics, topology, vertex_quadrics  # noqa: E402
from core.engine import _non_manifold_vertices  # noqa: E402  (same input locking as the engine)
from core.geometry import face_frames  # noqa: E402
from core.result import STOP_TOPOLOGY, STOP_TARGET  # noqa: E402
from core.validation import corner_breaks  # noqa: E402  (the engine's own turn, area and sliver rules)

COSTS = ("paper", "per_area")


def simplify_sequential(vertices, faces, *, target_faces, line_weight=DEFAULT_LINE_WEIGHT, cost="paper",
                        guards=True, boundary_weight=1.0):
    """Greedy cheapest-first edge collapse down to ``target_faces``.

    vertices (n, 3) float, faces (m, 3) int. cost: "paper" ranks by the quadric error
    E(x*) itself (the paper and the authors' reference), "per_area" by E(x*) divided by
    the accumulated vertex areas of the two ends (what core's engine ranks by). guards:
    core.validation's rules checked per collapse (link condition, boundaries, flips,
    zero areas, slivers); off, only non-manifold edges are skipped, as in the paper. In
    both modes the input's non-manifold and pinched vertices stay put, as in the engine
    (a property of the input, not a per-collapse guard; no-op on manifold meshes).

    Returns (V (k, 3) float64 in input units, F (t, 3) int64, info dict with
    passes (collapses applied), seconds, stop_reason, input_faces, output_faces, rejected
    (guard rejections, re-tries included)). Stops at <= target_faces (a closed mesh loses
    two faces per collapse) or when no valid collapse is left.
    """
    if cost not in COSTS:
        raise ValueError(f"cost must be one of {COSTS}, got {cost!r}")
    t0 = time.perf_counter()
    # The engine's own preparation: validation, welding, dropping degenerate and
    # duplicate faces, and the normalisation to a unit bounding-box diagonal, so the
    # quadrics, tolerances and guards see exactly the numbers core's engine sees.
    p = prepare.validate_and_prepare(vertices, faces, [target_faces],
                                     Options(line_weight=line_weight, boundary_weight=boundary_weight))
    run = _Sequential(p, per_area=(cost == "per_area"), guards=guards)
    stop = run.collapse_until(p.targets[0])
    V, F = run.output(p)
    info = {
        "passes": run.collapses,
        "seconds": time.perf_counter() - t0,
        "stop_reason": stop,
        "input_faces": p.input_faces,
        "output_faces": len(F),
        "rejected": run.rejections,
    }
    return V, F, info


class _Sequential:
    """Mutable mesh for one-at-a-time collapses.

    Topology is in Python lists (faces as [a, b, c] lists, per-vertex sets of face ids)
    because every collapse touches a handful of them and NumPy's per-call overhead would
    dominate; geometry and quadrics stay in NumPy rows, updated per collapse. Vertex and
    face ids are never compacted; dead faces are flagged, dead vertices get version -1.
    """

    def __init__(self, p, per_area: bool, guards: bool):
        n = len(p.vertices)
        conn = topology.build(p.faces, n)
        Q, area = vertex_quadrics.build(
            p.vertices, p.faces, conn, p.line_weights, p.quadric_scale, p.options.boundary_weight,
            p.feature_edges, p.feature_edge_weights, p.options.probabilistic_sigma,
        )
        self.V = p.vertices.copy()  # (n, 3) normalised units
        self.Q = np.ascontiguousarray(Q)  # (n, 10) row-major: one row read/written per end
        self.area = area.copy()  # (n,) accumulated vertex areas (the per_area denominator)
        self.area_scale = float(area.mean()) if n else 1.0  # minimize's regulariser scale, as the engine
        self.per_area = per_area
        self.guards = guards
        # Non-manifold and pinched input vertices never move, as in the engine.
        self.locked = _non_manifold_vertices(conn, p.faces, n) | p.locked
        self.moved = np.zeros(n, dtype=bool)
        self.F = p.faces.tolist()
        self.alive_faces = len(self.F)
        self.faces_of = [set() for _ in range(n)]
        for f, tri in enumerate(self.F):
            for v in tri:
                self.faces_of[v].add(f)
        # Unit normal of every prepared face: no face may end up facing away from the
        # face it descends from (core.validation's cumulative-turn guard).
        self.source_normals = face_frames(p.vertices, p.faces)[0]
        self.version = [0] * n  # bumped when a vertex's quadric or position changes
        self.heap = []
        self.seq = 0  # heap tie-break: first pushed first
        self.rejected = {}  # vertex -> {edge key: heap entry} of guard-rejected edges at it
        self.collapses = 0
        self.rejections = 0
        manifold = (conn.edge_faces == 1) | (conn.edge_faces == 2)
        self._push(conn.edges[manifold, 0], conn.edges[manifold, 1], initial=True)
        heapq.heapify(self.heap)

    # ------------------------------------------------------------ costs and the heap

    def _push(self, a: np.ndarray, b: np.ndarray, initial: bool = False) -> None:
        """Cost and optimal position of collapsing each edge a[i]-b[i] ((k,) ints), onto
        the heap. The locked end, if any, survives and stays put; both locked: skipped."""
        lk = self.locked
        both = lk[a] & lk[b]
        a, b = a[~both], b[~both]
        if len(a) == 0:
            return
        swap = lk[b]
        keep = np.where(swap, b, a)
        remove = np.where(swap, a, b)
        q = self.Q[keep] + self.Q[remove]
        v_keep = self.V[keep]
        pos = quadrics.minimize(q, 0.5 * (v_keep + self.V[remove]), self.area_scale)
        fixed = lk[keep]
        pos[fixed] = v_keep[fixed]
        err = quadrics.evaluate(q, pos)
        if self.per_area:
            err = err / np.maximum(self.area[keep] + self.area[remove], 1e-300)
        ver = self.version
        entries = []
        for c, k, r, x in zip(err.tolist(), keep.tolist(), remove.tolist(), pos.tolist()):
            self.seq += 1
            entries.append((c, self.seq, k, r, ver[k], ver[r], x))
        if initial:
            self.heap = entries  # heapified once by the caller: O(k), not k pushes
        else:
            for e in entries:
                heapq.heappush(self.heap, e)

    def _push_around(self, k: int) -> None:
        """Fresh entries for every edge of k, whose quadric and position just changed."""
        ring = self._neighbours(k)
        if ring:
            self._push(np.full(len(ring), k, dtype=np.int64), np.fromiter(ring, np.int64, len(ring)))

    def _is_current(self, entry) -> bool:
        _, _, k, r, vk, vr, _ = entry
        return self.version[k] == vk and self.version[r] == vr

    # ------------------------------------------------------------ main loop

    def collapse_until(self, target: int) -> str:
        heap = self.heap
        while self.alive_faces > target:
            if not heap:
                return STOP_TOPOLOGY
            entry = heapq.heappop(heap)
            if not self._is_current(entry):
                continue  # lazy invalidation: an end moved or died since this was pushed
            _, _, k, r, _, _, x = entry
            shared = self.faces_of[k] & self.faces_of[r]
            if not 1 <= len(shared) <= 2:
                continue  # non-manifold (or vanished) edge: never collapsed
            if self.guards and not self._valid(k, r, shared, x):
                self._remember_rejection(entry)
                continue
            self._collapse(k, r, shared, x)
        return STOP_TARGET

    def _collapse(self, k: int, r: int, shared: set, x) -> None:
        """Merge r into k at x: faces on the edge die, r's other faces relabel to k."""
        F, faces_of = self.F, self.faces_of
        for f in shared:
            for v in F[f]:
                faces_of[v].discard(f)
            F[f] = None
        for f in faces_of[r]:
            tri = F[f]
            tri[tri.index(r)] = k
            faces_of[k].add(f)
        faces_of[r] = set()
        self.alive_faces -= len(shared)
        self.V[k] = x
        self.Q[k] += self.Q[r]  # memory accumulation: Q_new = Q_i + Q_j
        self.area[k] += self.area[r]
        self.moved[k] = True
        self.version[r] = -1
        self.version[k] += 1
        self.collapses += 1
        self._push_around(k)
        self._retry_rejected(k)

    # ------------------------------------------------------------ rejected edges

    def _remember_rejection(self, entry) -> None:
        """Park a guard-rejected edge until a face around one of its ends changes."""
        self.rejections += 1
        _, _, k, r, _, _, _ = entry
        key = (min(k, r), max(k, r))
        self.rejected.setdefault(k, {})[key] = entry
        self.rejected.setdefault(r, {})[key] = entry

    def _retry_rejected(self, k: int) -> None:
        """After a collapse into k the faces around k and its ring changed: every parked
        edge with an end there goes back on the heap (if its ends are unchanged; edges
        of k itself were just pushed with fresh costs)."""
        for u in [k, *self._neighbours(k)]:
            parked = self.rejected.pop(u, None)
            if not parked:
                continue
            for key, entry in parked.items():
                other = key[1] if key[0] == u else key[0]
                mine = self.rejected.get(other)
                if mine is not None:
                    mine.pop(key, None)
                if self._is_current(entry):
                    heapq.heappush(self.heap, entry)

    # ------------------------------------------------------------ guards

    def _neighbours(self, v: int) -> set:
        F = self.F
        out = set()
        for f in self.faces_of[v]:
            out.update(F[f])
        out.discard(v)
        return out

    def _ring_counts(self, v: int) -> dict:
        """Neighbour -> number of faces of v it is on: 1 marks a border edge."""
        counts = {}
        F = self.F
        for f in self.faces_of[v]:
            for u in F[f]:
                if u != v:
                    counts[u] = counts.get(u, 0) + 1
        return counts

    def _valid(self, k: int, r: int, shared: set, x) -> bool:
        return self._valid_topology(k, r, len(shared)) and self._valid_geometry(k, r, x)

    def _valid_topology(self, k: int, r: int, edge_faces: int) -> bool:
        """core.validation's link condition, fold and bare-vertex tests, and selection's
        border rule, for one edge."""
        ck, cr = self._ring_counts(k), self._ring_counts(r)
        # Boundaries stay boundaries: an inner edge joining two border vertices pinches.
        if edge_faces == 2 and 1 in ck.values() and 1 in cr.values():
            return False
        nk = ck.keys() - {r}
        nr = cr.keys() - {k}
        # Link condition: the ends share exactly the vertices opposite the edge.
        if len(nk & nr) != edge_faces:
            return False
        opposite = nk & nr
        F = self.F
        # No vertex loses its last face: the kept end, or a corner opposite the edge.
        if len(self.faces_of[k]) + len(self.faces_of[r]) - 2 * edge_faces <= 0:
            return False
        if any(len(self.faces_of[o]) <= 1 for o in opposite):
            return False
        # Both ends keep a face on the two opposite corners: it would fold into a pair of
        # faces on the same vertices (a closed tetrahedron, also off a pinch).
        if edge_faces == 2 and len(opposite) == 2:
            on_pair = [any(opposite <= set(F[f]) for f in self.faces_of[end] if other not in F[f])
                       for end, other in ((k, r), (r, k))]
            if all(on_pair):
                return False
        return True

    def _valid_geometry(self, k: int, r: int, x) -> bool:
        """Flip, zero-area, flat-ring fold-over, source-facing and sliver guards over every
        corner of both ends: core.validation.corner_breaks itself, for one collapse."""
        F = self.F
        moving, nb_next, nb_prev, face, dying = [], [], [], [], []
        for end, other in ((k, r), (r, k)):
            for f in self.faces_of[end]:
                tri = F[f]
                s = tri.index(end)
                b, c = tri[(s + 1) % 3], tri[(s + 2) % 3]
                moving.append(end)
                nb_next.append(b)
                nb_prev.append(c)
                face.append(f)
                dying.append(b == other or c == other)
        V = self.V
        k_corners = len(moving)
        bad = corner_breaks(V[moving], V[nb_next], V[nb_prev], np.broadcast_to(np.asarray(x), (k_corners, 3)),
                            np.asarray(dying), np.zeros(k_corners, dtype=np.int64), 1,
                            self.source_normals[face])
        return not bad.any()

    # ------------------------------------------------------------ output

    def output(self, p) -> tuple:
        """(V (k, 3), F (t, 3)) compacted, in input units; unmoved vertices exactly as given."""
        live = [tri for tri in self.F if tri is not None]
        F = np.array(live, dtype=np.int64).reshape(-1, 3)
        used = np.zeros(len(self.V), dtype=bool)
        used[F.ravel()] = True
        new_index = np.cumsum(used) - 1
        V = np.where(self.moved[used, None], self.V[used] * p.scale + p.center, p.input_positions[used])
        return V, new_index[F]



# ---------------------------------------------------------------- command line

def _method_name(cost: str, guards: bool) -> str:
    return f"sequential {cost}{'' if guards else ', no guards'}"


def _bench_mesh(mesh, args, run_bench, decimate) -> list:
    """Rows for one mesh: Blender Decimate, core.simplify, then the sequential reference
    for every requested cost and guard setting, all measured the same way."""
    import core

    V, F = mesh.vertices, mesh.faces
    target = max(int(round(args.ratio * len(F))), 0)  # core.simplify's own rounding of ratio
    rows = []

    def measured(method, out_v, out_f, seconds, extra):
        _log(f"  {mesh.name}: measuring {method} ...")
        row = run_bench.measured_row(mesh.name, len(F), args.ratio, method, V, F, out_v, out_f,
                                     seconds, args.samples, extra)
        rows.append(row)
        return row

    blender_seconds = float("nan")
    if not args.no_blender:
        _log(f"  {mesh.name}: Blender Decimate ...")
        # Split vertices welded, as bench/run.py does (core and this reference weld them
        # themselves; Decimate would only delete whole triangles).
        w_v, w_f, _ = run_bench.welded(V, F)
        dec = decimate(w_v, w_f, args.ratio)
        blender_seconds = dec.seconds
        measured("Blender Decimate", dec.vertices, dec.faces, dec.seconds, {})

    _log(f"  {mesh.name}: core.simplify ...")
    t0 = time.perf_counter()
    res = core.simplify(V, F, target_faces=target, line_weight=args.line_weight)
    seconds = time.perf_counter() - t0
    measured("core", res.vertices, res.faces, seconds,
             {"passes": res.stats.passes, "stop_reason": res.stats.stop_reason,
              "time_ratio": seconds / blender_seconds})

    for cost in args.cost:
        for guards in args.guards:
            method = _method_name(cost, guards)
            _log(f"  {mesh.name}: {method} ...")
            out_v, out_f, info = simplify_sequential(V, F, target_faces=target, line_weight=args.line_weight,
                                                     cost=cost, guards=guards)
            measured(method, out_v, out_f, info["seconds"],
                     {"passes": info["passes"], "stop_reason": info["stop_reason"],
                      "rejected": info["rejected"], "time_ratio": info["seconds"] / blender_seconds})
    return rows


def _log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def main(argv=None) -> int:
    import argparse

    import _bootstrap  # noqa: F401  (isolated Blender user dirs, before bpy)
    import bpy  # noqa: F401  (addon.pure.measure's BVH trees need bpy's mathutils)
    import run as run_bench
    from addon.pure.measure import DEFAULT_SAMPLES
    from blender_reference import decimate, load_mesh

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--meshes", type=Path, default=_bootstrap.DEFAULT_MESH_DIR,
                    help="directory of .obj/.gltf/.glb meshes (default: %(default)s)")
    ap.add_argument("--only", type=lambda s: [x for x in s.split(",") if x],
                    help="comma-separated file stems, run in this order (default: every mesh)")
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--line-weight", type=float, default=DEFAULT_LINE_WEIGHT)
    ap.add_argument("--cost", nargs="+", choices=COSTS, default=["paper"],
                    help="ranking of the sequential reference; several give one row each")
    ap.add_argument("--guards", nargs="+", choices=("on", "off"), default=["on"],
                    help="core.validation's guards in the sequential reference; 'on off' gives both rows")
    ap.add_argument("--samples", type=int, default=DEFAULT_SAMPLES,
                    help="area-uniform samples per surface for the distances (default %(default)s)")
    ap.add_argument("--no-blender", action="store_true", help="skip Blender's Decimate row")
    args = ap.parse_args(argv)
    args.guards = [g == "on" for g in args.guards]
    if not args.meshes.is_dir():
        _log(f"error: no mesh directory {args.meshes} (give one with --meshes)")
        return 2
    files = {p.stem: p for p in sorted(args.meshes.iterdir()) if p.suffix.lower() in run_bench.MESH_SUFFIXES}
    names = args.only or list(files)
    missing = [n for n in names if n not in files]
    if missing:
        _log(f"error: no mesh named {', '.join(missing)} in {args.meshes}")
        return 2

    rows = []
    for name in names:
        _log(files[name].name)
        mesh = load_mesh(files[name])
        rows += _bench_mesh(mesh, args, run_bench, decimate)
    print(run_bench.markdown_table(rows))
    print()
    for r in rows:
        if "passes" in r:
            extra = f", {r['rejected']} guard rejections" if "rejected" in r else ""
            print(f"- {r['mesh']} / {r['method']}: {r['passes']} {'collapses' if 'rejected' in r else 'passes'}, "
                  f"stop: {r['stop_reason']}{extra}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
