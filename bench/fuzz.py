"""Random crops of the real meshes under random controls: does core.simplify keep its
promises? A script, not a test (it needs ../shared/meshes and runs for minutes).

Each case takes one mesh, optionally crops it to the faces inside a random ball (open
borders, several pieces), optionally damages it (fins: a third face on an edge; pinches:
two far-apart vertices merged), adds noise, and draws a ratio, seed, line weight,
locked vertices, quadric scales, per-vertex line weights, boundary weight, max_error (half
the time with plane_placement) and UVs with a seam. The result must then:
- be a valid mesh: indices in range, no repeated vertex in a face, no duplicate faces,
  every output vertex used; origins in range and one-to-one (but the faces core.stitching
  split at a T-junction, which share their input face);
- stay manifold and consistently oriented if the input was, and never add a
  non-manifold edge if it was not;
- hit the target (within 1) unless the stats say why not (a small part removed may take
  it under: parameters.md, remove_small_components);
- keep every locked vertex that had a face, exactly where it was;
- have no zero-area face other than an untouched zero-area face of the input;
- turn no UV triangle over (when UVs are carried), unless the target needed that rule
  relaxed (stats.relaxation_step);
- remove no part when remove_small_components is False.
A failing case is printed and saved as FAILDIR/case_<k>.npz (input arrays and controls).

    .venv/bin/python bench/fuzz.py --minutes 10 --seed 1 [--damage] [--uv]

Found so far (each fixed, with a test): a mesh part collapsing to nothing with its locked
vertices, a fan hanging off a pinch losing its last face, a vertex pinched between two
closed fans left unlocked, a tetrahedron off a pinch folded flat, and a locked pinch
losing the last face of each of its fans to two collapses of the same pass.
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import _bootstrap  # noqa: F401  (repository on sys.path, Blender user dirs isolated, before bpy)
import numpy as np

import core
from core import stitching
from core.guards import relaxation_ladder
from blender_reference import load_mesh

MESH_SUFFIXES = (".obj", ".gltf", ".glb")


def edge_counts(F):
    """Undirected edges (k, 2) sorted, faces on each (k,)."""
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    return np.unique(e, axis=0, return_counts=True)


def consistently_manifold(F) -> bool:
    _, count = edge_counts(F)
    directed = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return bool(count.max(initial=0) <= 2 and len(np.unique(directed, axis=0)) == len(directed))


def double_areas(V, F):
    return np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)


def uv_signed_areas(uv):
    """(m,) twice the signed area of each (m, 3, 2) UV triangle."""
    d1, d2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    return d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]


def draw_case(rng, meshes, damage, with_uv):
    """(name, V, F, options) of one random case, or None to draw again."""
    name = list(meshes)[rng.integers(len(meshes))]
    V, F = meshes[name]
    diagonal = np.linalg.norm(np.ptp(V, axis=0))
    if rng.random() < 0.6:  # a crop: the faces whose centroid is inside a random ball
        centroid = V[F].mean(axis=1)
        inside = np.linalg.norm(centroid - centroid[rng.integers(len(F))], axis=1) < diagonal * rng.uniform(0.03, 0.5)
        used, F = np.unique(F[inside], return_inverse=True)
        V, F = V[used], F.reshape(-1, 3)
    if len(F) < 4 or (len(F) > 40000 and rng.random() < 0.7):
        return None
    if damage:
        fins = rng.integers(len(F), size=int(rng.integers(1, 6)))
        tips = V[F[fins]].mean(axis=1) + rng.normal(size=(len(fins), 3)) * diagonal * 0.01
        F = np.concatenate([F, np.stack([F[fins, 0], F[fins, 1], len(V) + np.arange(len(fins))], axis=1)])
        V = np.concatenate([V, tips])
        for _ in range(int(rng.integers(0, 3))):
            a, b = rng.integers(len(V), size=2)
            if a != b and not ((F == a).any(axis=1) & (F == b).any(axis=1)).any():
                F = np.where(F == b, a, F)
    V = V + rng.normal(scale=diagonal * rng.choice([0.0, 1e-7, 1e-4]), size=V.shape)
    n = len(V)
    options = dict(ratio=float(rng.uniform(0.02, 0.9)), seed=int(rng.integers(1 << 31)),
                   line_weight=float(rng.choice([0.0, 1e-4, 1e-3, 1e-2, 1e-1])))
    if rng.random() < 0.3:
        options["locked"] = rng.random(n) < rng.uniform(0.01, 0.3)
    if rng.random() < 0.3:
        options["quadric_scale"] = 1.0 + np.where(rng.random(n) < 0.3, rng.uniform(0, 1000, n), 0.0)
    if rng.random() < 0.3:
        options["line_weights"] = rng.uniform(0, 0.1, n)
    if rng.random() < 0.2:
        options["boundary_weight"] = float(rng.choice([0.0, 1.0, 100.0]))
    if rng.random() < 0.2:
        options["max_error"] = float(diagonal * rng.choice([1e-4, 1e-3, 1e-2]))
        options["plane_placement"] = bool(rng.random() < 0.5)
    if rng.random() < 0.3:
        options["feature_angle"] = float(rng.choice([0.0, 20.0, 45.0, 80.0, 120.0]))
    if rng.random() < 0.3:
        options["min_quality"] = float(rng.choice([0.0, 0.1, 0.5]))
    if rng.random() < 0.3:
        options["remove_small_components"] = False
    if with_uv:  # a planar projection with a random ball of faces moved to its own island
        axes = np.linalg.qr(rng.normal(size=(3, 3)))[0][:, :2]
        uv = V[F] @ axes
        centroid = V[F].mean(axis=1)
        island = np.linalg.norm(centroid - centroid[rng.integers(len(F))], axis=1) < diagonal * rng.uniform(0.05, 0.4)
        uv[island] += 1e3
        options["corner_attributes"] = {"uv": uv}
        options["uv_attributes"] = ["uv"]
    return name, V, F, options


def on_t_junctions(V, F, faces) -> bool:
    """Whether each of the input ``faces`` (ids) has a border edge with an input vertex on
    it, strictly between its ends and within core.stitching's tolerance: a T-junction
    crack, which core.stitching closes by splitting the face, so that several output faces
    descend from it. Border edges are judged as core.prepare leaves the faces: without
    degenerate, zero-area or repeated ones."""
    kept = (F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2]) & (double_areas(V, F) > 0)
    _, first = np.unique(np.sort(F[kept], axis=1), axis=0, return_index=True)
    edges, count = edge_counts(F[kept][first])
    border = {tuple(e) for e in edges[count == 1].tolist()}
    diagonal = float(np.linalg.norm(np.ptp(V, axis=0)))
    for f in faces:
        cracked = False
        for a, b in ((F[f, 0], F[f, 1]), (F[f, 1], F[f, 2]), (F[f, 2], F[f, 0])):
            if (min(a, b), max(a, b)) not in border:
                continue
            d = V[b] - V[a]
            length = float(np.linalg.norm(d))
            if length == 0:
                continue
            t = (V - V[a]) @ d / length ** 2
            distance = np.linalg.norm(V[a] + t[:, None] * d - V, axis=1)
            tolerance = min(stitching.RELATIVE_TOLERANCE * length, stitching.ABSOLUTE_TOLERANCE * diagonal)
            inside = (t > stitching.END_MARGIN) & (t < 1 - stitching.END_MARGIN)
            cracked |= bool(np.any(inside & (distance <= tolerance)))
        if not cracked:
            return False
    return True


def broken_promises(V, F, options, r) -> list:
    """What the result ``r`` of simplify(V, F, **options) gets wrong; empty if nothing."""
    out, faces = r.vertices, r.faces
    problems = []
    fo, vo = np.asarray(r.face_origin), np.asarray(r.vertex_origin)
    if len(faces) == 0:
        return problems
    if faces.min() < 0 or faces.max() >= len(out) or not np.array_equal(np.unique(faces), np.arange(len(out))):
        problems.append("face indices out of range or unused output vertices")
    if np.any((faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 0] == faces[:, 2])):
        problems.append("a face repeats a vertex")
    if len(np.unique(np.sort(faces, axis=1), axis=0)) != len(faces):
        problems.append("duplicate faces")
    if len(np.unique(vo)) != len(vo) or fo.max() >= len(F) or vo.max() >= len(V):
        problems.append("vertex origins not one-to-one, or origins out of range")
    origins, count = np.unique(fo, return_counts=True)
    if np.any(count > 1) and not on_t_junctions(V, F, origins[count > 1]):
        problems.append("two output faces descend from one input face that no T-junction split")
    if consistently_manifold(F):
        if not consistently_manifold(faces):
            problems.append("manifold input, non-manifold or inconsistently oriented output")
    else:
        edges, count = edge_counts(faces)
        before, count_before = edge_counts(F)
        known = {tuple(e) for e in before[count_before > 2].tolist()}
        if any(tuple(e) not in known for e in np.sort(vo[edges[count > 2]], axis=1).tolist()):
            problems.append("new non-manifold edge")
    if "max_error" not in options:
        target = int(round(options["ratio"] * len(F)))
        reached = target - 1 <= len(faces) <= target
        # A small part removed when even the cheapest collapse costs more than it is
        # small (core.engine._choose) may take the LOD under its target by its triangles.
        if r.stats.removed_components:
            reached = len(faces) <= target
        if r.stats.stop_reason == "target_reached" and not reached:
            problems.append(f"target {target} said reached, got {len(faces)}")
        if r.stats.stop_reason != "target_reached" and len(faces) <= target:
            problems.append(f"stopped as {r.stats.stop_reason} at {len(faces)} faces, target {target}")
    if r.stats.removed_components and not options.get("remove_small_components", True):
        problems.append("parts removed with remove_small_components=False")
    if "locked" in options:
        locked = np.intersect1d(np.flatnonzero(options["locked"]), F)
        if not np.isin(locked, vo).all():
            problems.append("a locked vertex was removed")
        kept = np.isin(vo, locked)
        if not np.array_equal(out[kept], V[vo[kept]]):
            problems.append("a locked vertex moved")
    zero = double_areas(out, faces) == 0
    if zero.any():
        untouched = np.array_equal(np.sort(vo[faces[zero]], axis=1), np.sort(F[fo[zero]], axis=1))
        if not untouched or np.any(double_areas(V, F[fo[zero]]) > 0):
            problems.append("a new zero-area face")
    # UVs may flip only once the run had to relax that rule to reach its target.
    flips_allowed = not relaxation_ladder()[r.stats.relaxation_step].uv_flip
    if "corner_attributes" in options and not flips_allowed:
        before = uv_signed_areas(options["corner_attributes"]["uv"])
        after = uv_signed_areas(r.corner_attributes["uv"])
        significant = np.abs(before[fo]) > 1e-9 * np.abs(before).max()
        if np.any(significant & (np.sign(before[fo]) != np.sign(after))):
            problems.append("a UV triangle turned over")
    return problems


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--meshes", type=Path, default=_bootstrap.DEFAULT_MESH_DIR)
    ap.add_argument("--minutes", type=float, default=5.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--damage", action="store_true", help="add fins and pinches (non-manifold input)")
    ap.add_argument("--uv", action="store_true", help="carry UVs with a seam and check for UV flips")
    ap.add_argument("--fail-dir", type=Path, default=Path("out/fuzz"))
    args = ap.parse_args(argv)
    paths = sorted(p for p in args.meshes.iterdir() if p.suffix.lower() in MESH_SUFFIXES)
    if not paths:
        ap.error(f"no meshes in {args.meshes}")
    meshes = {}
    for path in paths:
        m = load_mesh(path)
        # Exact welding, as core does, so crops see the connectivity core will.
        unique, index = np.unique(m.vertices, axis=0, return_inverse=True)
        meshes[path.name] = (unique, index.reshape(-1)[m.faces])
    rng = np.random.default_rng(args.seed)
    deadline = time.time() + 60 * args.minutes
    cases = failures = 0
    while time.time() < deadline:
        case = draw_case(rng, meshes, args.damage, args.uv)
        if case is None:
            continue
        name, V, F, options = case
        cases += 1
        try:
            problems = broken_promises(V, F, options, core.simplify(V, F, **options))
        except Exception as error:  # a crash is a finding too
            problems = [f"raised {error!r}"]
        if problems:
            failures += 1
            args.fail_dir.mkdir(parents=True, exist_ok=True)
            saved = {k: v for k, v in options.items() if k not in ("corner_attributes", "uv_attributes")}
            if "corner_attributes" in options:
                saved["uv"] = options["corner_attributes"]["uv"]
            np.savez(args.fail_dir / f"case_{failures}.npz", V=V, F=F, **saved)
            print(f"FAIL {name} ({len(F)} faces) {problems}: saved {args.fail_dir / f'case_{failures}.npz'}",
                  flush=True)
    print(f"{cases} cases, {failures} failing", flush=True)
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
