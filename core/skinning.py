"""Skinned meshes: LODs that stay close when the rig poses them (issue 19, paper Sec. 5.3).

A LOD of a character is posed by linear blend skinning (LBS) with its own interpolated
skin weights. Two things make it follow the posed source better than a LOD made for the
rest shape alone, both from sample poses of the rig (random turns of every bone, made
here from the bones' rest matrices, so the scene is never touched):

* the poses in the error (``pose_offsets``, core.Options): every vertex's offset in each
  sample pose is carried like a shape key, so a collapse is charged how far its merged
  vertex, moved by its interpolated offset, lies from the posed planes it absorbs
  (core.shape_keys). Collapses that would flatten a joint's bend cost what they cost
  posed, not the nothing they cost at rest;
* the LOD's skin weights fitted (``fit_weights``): interpolated weights put each LOD
  vertex where the source's weights would, but a LOD triangle spans a stretch of surface
  whose weights change inside it, so in a pose it is a chord of a bend. Least squares
  over the sample poses choose the weights with which the posed LOD triangles lie
  closest to the posed source points they stand for. At rest every matrix is the
  identity and weights that sum to one change nothing: the rest shape is untouched.

Shapes: n vertices, B bones, P poses; matrices are 4 x 4 deform matrices (the pose
matrix times the inverse rest matrix) in the mesh's own coordinates, so that a vertex v
with weights w poses to sum_b w_b M_b v. Lengths are in mesh units.
"""
from __future__ import annotations

import numpy as np

SAMPLE_POSES = 16  # sample poses of the rig (8 gave results that moved with the seed: docs/armature.md)
SAMPLE_ANGLE = 40.0  # degrees: every bone turned by up to this, a generous range of motion
MAX_INFLUENCES = 8  # bones a fitted LOD vertex may take weight from (engines use 4 to 8)
# How much the fit holds to the interpolated weights (x the bounding-box diagonal): only
# enough to make the least squares definite. Measured with the solve converged, a firmer
# hold only gave back what the fit gains: 1e-2 and 3e-2 posed a humanoid at 0.84x and
# 0.91x of no importance against 0.82x here, the Fox subdivided (row B) at 0.74x and
# 0.80x against 0.72x; 1e-3 changed nothing (docs/armature.md).
FIT_SMOOTHING = 3e-3


def skin(points: np.ndarray, weights: np.ndarray, matrices: np.ndarray) -> np.ndarray:
    """(n, 3) points posed by LBS: points (n, 3), weights (n, B), matrices (B, 4, 4).

    Rows are divided by their sum, as Blender's Armature modifier does; a point with no
    weight stays where it is."""
    points = np.asarray(points, dtype=np.float64)
    weights = np.asarray(weights, dtype=np.float64)
    total = weights.sum(axis=1)
    has = total > 0
    w = weights / np.where(has, total, 1.0)[:, None]
    # Blend the matrices first (one (n, B) x (B, 12) product), then apply each point's own.
    blended = (w @ matrices[:, :3, :].reshape(len(matrices), 12)).reshape(-1, 3, 4)
    moved = np.einsum("nij,nj->ni", blended[:, :, :3], points) + blended[:, :, 3]
    return np.where(has[:, None], moved, points)


def random_poses(rest_matrices: np.ndarray, parents: np.ndarray, count: int = SAMPLE_POSES,
                 max_angle: float = SAMPLE_ANGLE, seed: int = 0) -> np.ndarray:
    """(count, B, 4, 4) deform matrices of random poses, in the rest matrices' space.

    Every bone turns about its head, about a random axis of its own frame, by an angle
    uniform in [0, max_angle] degrees (pose_matrices)."""
    B = len(rest_matrices)
    rng = np.random.default_rng(seed)
    out = np.empty((count, B, 4, 4))
    for k in range(count):  # a loop over sample poses, a handful
        axes = rng.normal(size=(B, 3))
        axes /= np.linalg.norm(axes, axis=1, keepdims=True)
        angles = np.radians(rng.uniform(0.0, max_angle, size=B))
        out[k] = pose_matrices(rest_matrices, parents, rotations(axes, angles))
    return out


def pose_matrices(rest_matrices: np.ndarray, parents: np.ndarray, turns: np.ndarray) -> np.ndarray:
    """(B, 4, 4) deform matrices (pose matrix times inverse rest matrix) of one pose.

    rest_matrices (B, 4, 4): each bone's rest frame (Blender's bone.matrix_local, armature
    space); parents (B,): each bone's parent's index or -1, in any order; turns (B, 4, 4):
    each bone's pose in its own rest frame (Blender's pose bone matrix_basis). A bone
    carries its children along (forward kinematics with Blender's default inheritance)."""
    rest = np.asarray(rest_matrices, dtype=np.float64)
    parents = np.asarray(parents, dtype=np.int64)
    B = len(rest)
    inv_rest = np.linalg.inv(rest)
    has_parent = parents >= 0
    local = rest.copy()  # a bone's rest frame in its parent's
    local[has_parent] = inv_rest[parents[has_parent]] @ rest[has_parent]
    depth = np.zeros(B, dtype=np.int64)
    for _ in range(B):  # at most B rounds; a chain, not a per-element pass
        deeper = np.where(has_parent, depth[np.maximum(parents, 0)] + 1, 0)
        if np.array_equal(deeper, depth):
            break
        depth = deeper
    posed = np.empty((B, 4, 4))
    for b in np.argsort(depth, kind="stable").tolist():  # parents first: B bones, a chain
        frame = local[b] @ turns[b]
        posed[b] = frame if parents[b] < 0 else posed[parents[b]] @ frame
    return posed @ inv_rest


def rotations(axes: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """(B, 4, 4) rotations by ``angles`` (radians) about unit ``axes`` (Rodrigues)."""
    x, y, z = axes.T
    c, s = np.cos(angles), np.sin(angles)
    C = 1.0 - c
    R = np.zeros((len(axes), 4, 4))
    R[:, 0] = np.stack([c + x * x * C, x * y * C - z * s, x * z * C + y * s, 0 * x], axis=1)
    R[:, 1] = np.stack([y * x * C + z * s, c + y * y * C, y * z * C - x * s, 0 * x], axis=1)
    R[:, 2] = np.stack([z * x * C - y * s, z * y * C + x * s, c + z * z * C, 0 * x], axis=1)
    R[:, 3, 3] = 1.0
    return R


def change_of_space(matrices: np.ndarray, to_space: np.ndarray) -> np.ndarray:
    """Deform matrices (..., 4, 4) given in one space, for points given in another:
    ``to_space`` (4, 4) maps the points' space into the matrices' (for a mesh and its
    armature in Blender: armature.matrix_world^-1 @ mesh.matrix_world)."""
    return np.linalg.inv(to_space) @ matrices @ to_space


def pose_offsets(vertices: np.ndarray, weights: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """(P, n, 3): how far each vertex moves in each pose (poses (P, B, 4, 4)); the
    core.Options ``pose_offsets``."""
    return np.stack([skin(vertices, weights, m) - vertices for m in poses])


def surface_samples(vertices: np.ndarray, faces: np.ndarray, weights: np.ndarray, count: int,
                    seed: int = 0) -> tuple:
    """Area-uniform points of a skinned surface and their interpolated weights:
    ((count, 3), (count, B))."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    area = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)
    rng = np.random.default_rng(seed)
    if len(f) == 0 or area.sum() <= 0:
        return np.empty((0, 3)), np.empty((0, weights.shape[1]))
    face = rng.choice(len(f), size=count, p=area / area.sum())
    r1, r2 = np.sqrt(rng.random(count)), rng.random(count)
    bary = np.stack([1.0 - r1, r1 * (1.0 - r2), r1 * r2], axis=1)
    points = np.einsum("sk,skj->sj", bary, v[f[face]])
    return points, np.einsum("sk,skb->sb", bary, np.asarray(weights, dtype=np.float64)[f[face]])


def posed_gap(lod_vertices: np.ndarray, lod_faces: np.ndarray, lod_weights: np.ndarray,
              sample_points: np.ndarray, sample_weights: np.ndarray, sample_faces: np.ndarray,
              sample_bary: np.ndarray, poses: np.ndarray) -> float:
    """Mean distance, over the poses (P, B, 4, 4) and the source samples, between each
    posed source point and the posed LOD point it stands for (the same barycentric
    coordinates on its LOD triangle, as in fit_weights), in mesh units: how well a LOD
    with weights (n, B) follows the source in those poses."""
    corners = np.asarray(lod_faces, dtype=np.int64)[sample_faces]
    total = 0.0
    for matrices in poses:  # a loop over a handful of poses
        posed = skin(lod_vertices, lod_weights, matrices)
        on_lod = np.einsum("sk,skj->sj", sample_bary, posed[corners])
        total += float(np.linalg.norm(skin(sample_points, sample_weights, matrices) - on_lod, axis=1).mean())
    return total / max(len(poses), 1)


def fit_weights(lod_vertices: np.ndarray, lod_faces: np.ndarray, lod_weights: np.ndarray,
                sample_points: np.ndarray, sample_weights: np.ndarray, sample_faces: np.ndarray,
                sample_bary: np.ndarray, poses: np.ndarray, *, smoothing: float = FIT_SMOOTHING,
                iterations: int = 200, tolerance: float = 1e-4) -> np.ndarray:
    """(n, B) LOD skin weights with which the posed LOD lies closest to the posed source.

    lod_*: the LOD (n vertices, its interpolated weights (n, B)); sample_points (S, 3) and
    sample_weights (S, B): points of the source surface (surface_samples); sample_faces
    (S,) and sample_bary (S, 3): the LOD triangle closest to each point and the point's
    barycentric coordinates on it; poses (P, B, 4, 4).

    Minimises, over the poses and samples, the squared distance between the posed source
    point and the posed LOD point with the same barycentric coordinates, plus
    ``smoothing`` (times the bounding-box diagonal) times the change from the interpolated
    weights. Each vertex may only take weight from the MAX_INFLUENCES bones that weigh most
    in its own and its samples' weights; the result is clipped to >= 0 and each row scaled
    to sum to one, so the rest shape does not move.

    How: the least squares' normal equations are assembled per LOD triangle once (what a
    triangle's samples contribute depends on them only through the second moments of
    their barycentric coordinates), then solved by conjugate gradients over the vertices'
    weights, preconditioned by each vertex's own block: each step costs a few products per
    triangle, not one per sample and pose. It stops when the preconditioned residual has
    fallen by ``tolerance`` or after ``iterations`` steps.
    """
    V = np.asarray(lod_vertices, dtype=np.float64)
    F = np.asarray(lod_faces, dtype=np.int64)
    w0 = np.asarray(lod_weights, dtype=np.float64)
    n, B = w0.shape
    P, S = len(poses), len(sample_points)
    if n == 0 or S == 0 or P == 0 or B == 0:
        return w0.copy()
    tri = np.asarray(sample_faces, dtype=np.int64)
    beta = np.asarray(sample_bary, dtype=np.float64)
    corners = F[tri]  # (S, 3)

    # Which bones each vertex may use: the strongest among its own weights and those of
    # the samples that land on its triangles.
    seen = w0.copy()
    for k in range(3):
        np.maximum.at(seen, corners[:, k], sample_weights * (beta[:, k:k + 1] > 0))
    m = min(MAX_INFLUENCES, B)
    bones = np.argsort(-seen, axis=1, kind="stable")[:, :m]  # (n, m)
    usable = np.take_along_axis(seen, bones, axis=1) > 1e-4
    start = np.take_along_axis(w0, bones, axis=1) * usable

    # U[p, c, :, j]: vertex c posed by bone bones[c, j] alone in pose p.
    vh = np.concatenate([V, np.ones((n, 1))], axis=1)
    U = np.einsum("pcjik,ck->pcij", poses[:, bones, :3, :], vh)  # (P, n, 3, m)

    diag = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0))) or 1.0
    data = 1.0 / (S * P)
    lam2 = (smoothing * diag) ** 2 / n
    gam2 = diag ** 2 / n  # the weights' sum held at one

    # The data term, per LOD triangle with samples: the second moments of the samples'
    # barycentric coordinates times the poses' sums of U products of its corners.
    used, tri_of = np.unique(tri, return_inverse=True)
    Fu = F[used]  # (T, 3)
    moments = np.empty((len(used), 3, 3))
    for k in range(3):
        for l in range(3):
            moments[:, k, l] = np.bincount(tri_of, weights=beta[:, k] * beta[:, l], minlength=len(used))
    Uf = U[:, Fu]  # (P, T, 3 corners, 3, m)
    blocks = np.einsum("tkl,ptkia,ptlib->tklab", moments * data, Uf, Uf, optimize=True)  # (T, 3, 3, m, m)
    del Uf
    # and the right-hand side: the posed source points pulled back through U.
    targets = np.stack([skin(sample_points, sample_weights, M) for M in poses])  # (P, S, 3)
    pulled = np.zeros((P, n, 3))
    for k in range(3):
        for i in range(3):
            pulled[:, :, i] += np.stack([np.bincount(corners[:, k], weights=beta[:, k] * targets[p, :, i],
                                                     minlength=n) for p in range(P)])
    rhs = (np.einsum("pcij,pci->cj", U, pulled) * data + lam2 * start + gam2) * usable

    corner_vertex = Fu.ravel()
    by_vertex = np.argsort(corner_vertex, kind="stable")
    starts = np.flatnonzero(np.r_[True, np.diff(corner_vertex[by_vertex]) != 0])
    reached = corner_vertex[by_vertex][starts]

    def apply(w):
        """The normal equations' matrix times w (n, m), on the usable bones."""
        per_corner = np.einsum("tklab,tlb->tka", blocks, w[Fu]).reshape(-1, m)
        out = lam2 * w + gam2 * w.sum(axis=1, keepdims=True)
        out[reached] += np.add.reduceat(per_corner[by_vertex], starts, axis=0)
        return out * usable

    # Block-Jacobi preconditioner: each vertex's own m x m block (its corners' blocks, the
    # smoothing and the sum's penalty), so the solve converges in tens of steps rather than
    # hundreds. Plain conjugate gradients stopped at 60 steps were far from the solution,
    # and the half-solved weights posed worse: 0.98x against 0.93x of the interpolated
    # weights' distance on a humanoid (docs/armature.md).
    own = np.zeros((n, m, m))
    np.add.at(own, Fu.ravel(), blocks[:, np.arange(3), np.arange(3)].reshape(-1, m, m))
    own += lam2 * np.eye(m) + gam2
    mask = usable[:, :, None] & usable[:, None, :]
    own = np.where(mask, own, np.eye(m))
    inverse = np.linalg.inv(own)

    def precondition(r):
        return np.einsum("cab,cb->ca", inverse, r) * usable

    w = start.copy()
    r = rhs - apply(w)
    z = precondition(r)
    d = z.copy()
    rz = float((r * z).sum())
    first = rz
    for _ in range(iterations):
        if rz <= tolerance ** 2 * first or rz <= 0.0:
            break
        q = apply(d)
        alpha = rz / float((d * q).sum())
        w += alpha * d
        r -= alpha * q
        z = precondition(r)
        rz_new = float((r * z).sum())
        d = z + (rz_new / rz) * d
        rz = rz_new

    w = np.clip(w, 0.0, None) * usable
    total = w.sum(axis=1, keepdims=True)
    fitted = np.zeros((n, B))
    np.put_along_axis(fitted, bones, w / np.where(total > 0, total, 1.0), axis=1)
    # A vertex left with no weight (nothing could be fitted) keeps what it had.
    return np.where(total > 0, fitted, w0)
