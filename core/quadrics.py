"""Quadrics as packed arrays, built and solved in bulk.

A quadric Q = [[A, b], [b^T, c]] (A symmetric 3x3) is stored as a row of 10 numbers
[a00, a01, a02, a11, a12, a22, b0, b1, b2, c]; its error at x is x^T A x + 2 b.x + c.
Summing quadrics is summing rows, which is what lets the engine accumulate them with
bincount instead of a loop (paper Eq. 7-10).
"""
from __future__ import annotations

import numpy as np

QUADRIC_SIZE = 10
_AXX, _AXY, _AXZ, _AYY, _AYZ, _AZZ, _BX, _BY, _BZ, _C = range(10)


def plane_quadrics(unit_normals: np.ndarray, points: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Weighted squared distance to the planes through ``points`` with ``unit_normals``.

    unit_normals, points: (k, 3); weights: (k,). Returns (k, 10) (paper Eq. 4).
    """
    n = unit_normals
    d = -np.einsum("ij,ij->i", n, points)
    q = np.empty((len(n), QUADRIC_SIZE))
    q[:, _AXX] = n[:, 0] * n[:, 0]
    q[:, _AXY] = n[:, 0] * n[:, 1]
    q[:, _AXZ] = n[:, 0] * n[:, 2]
    q[:, _AYY] = n[:, 1] * n[:, 1]
    q[:, _AYZ] = n[:, 1] * n[:, 2]
    q[:, _AZZ] = n[:, 2] * n[:, 2]
    q[:, _BX:_C] = d[:, None] * n
    q[:, _C] = d * d
    q *= weights[:, None]
    return q


def line_quadrics(unit_normals: np.ndarray, points: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Weighted squared distance to the lines through ``points`` along ``unit_normals``.

    The sum of two plane quadrics whose normals span the plane orthogonal to the line
    (paper Eq. 13-15); that sum is A = I - n n^T whichever orthonormal pair is chosen, so
    no Gram-Schmidt basis is needed. unit_normals, points: (k, 3); weights: (k,).
    """
    n = unit_normals
    q = np.empty((len(n), QUADRIC_SIZE))
    q[:, _AXX] = 1.0 - n[:, 0] * n[:, 0]
    q[:, _AXY] = -n[:, 0] * n[:, 1]
    q[:, _AXZ] = -n[:, 0] * n[:, 2]
    q[:, _AYY] = 1.0 - n[:, 1] * n[:, 1]
    q[:, _AYZ] = -n[:, 1] * n[:, 2]
    q[:, _AZZ] = 1.0 - n[:, 2] * n[:, 2]
    # b = -A p, c = p^T A p, with A p = p - n (n.p)
    ap = points - n * np.einsum("ij,ij->i", n, points)[:, None]
    q[:, _BX:_C] = -ap
    q[:, _C] = np.einsum("ij,ij->i", points, ap)
    q *= weights[:, None]
    return q


def point_quadrics(points: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Weighted squared distance to ``points`` (the isotropic probabilistic quadric)."""
    q = np.zeros((len(points), QUADRIC_SIZE))
    q[:, _AXX] = q[:, _AYY] = q[:, _AZZ] = 1.0
    q[:, _BX:_C] = -points
    q[:, _C] = np.einsum("ij,ij->i", points, points)
    q *= weights[:, None]
    return q


def accumulate(owners: np.ndarray, quadrics: np.ndarray, count: int) -> np.ndarray:
    """Sum rows of ``quadrics`` (k, 10) into ``count`` bins: row i goes to every bin in
    owners[i] ((k,) or (k, c), e.g. the three corners of a face)."""
    return scatter_sum(owners, quadrics, count)


def scatter_sum(owners: np.ndarray, values: np.ndarray, count: int) -> np.ndarray:
    """(count,) or (count, d): values (k,) or (k, d) summed into the bins listed in
    owners (k,) or (k, c). One value column at a time is repeated per owner, never the
    whole (k, d) block (a third of a GB of quadrics on a 2M-face mesh). The result is
    column-major, the layout the engine keeps its quadrics in (see ``pair_sums``)."""
    owners = owners[:, None] if owners.ndim == 1 else owners
    flat_owners = owners.ravel()
    flat = values.ndim == 1
    vals = values[:, None] if flat else values
    out = np.empty((count, vals.shape[1]), order="F")
    for d in range(vals.shape[1]):
        out[:, d] = np.bincount(flat_owners, weights=np.repeat(vals[:, d], owners.shape[1]), minlength=count)
    return out[:, 0] if flat else out


def pair_sums(Q: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """(k, 10) column-major: Q[i] + Q[j], the quadric of each collapsed pair.

    Q is kept column-major (coefficient by coefficient): gathering one coefficient of
    all pairs at a time reads a column that stays in cache, 2-7x faster than gathering
    whole 80-byte rows, and the solve reads the result column by column too."""
    q = np.empty((len(i), Q.shape[1]), order="F")
    for c in range(Q.shape[1]):
        column = Q[:, c]
        np.add(column[i], column[j], out=q[:, c])
    return q


def merge_rows(Q: np.ndarray, keep: np.ndarray, remove: np.ndarray) -> None:
    """Q[keep] += Q[remove] in place (the paper's memory accumulation), column by column
    for the same reason as ``pair_sums``. ``keep`` must not repeat."""
    for c in range(Q.shape[1]):
        column = Q[:, c]
        column[keep] += column[remove]


def evaluate(q: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Quadric error of each row of q (k, 10) at each point x (k, 3), clamped at 0
    (round-off can take a true zero slightly negative)."""
    return np.maximum(evaluate_raw(q, x), 0.0)


def minimize(q: np.ndarray, fallback: np.ndarray, area_scale: float) -> np.ndarray:
    """Optimal positions x* solving A x = -b (paper Eq. 11) for each row of q (k, 10).

    Where A is singular or nearly so (a flat region with no line quadric, degenerate
    elements) the system is regularised by a tiny point quadric centred on ``fallback``
    (k, 3) - the probabilistic point quadric the paper adds in that case - so the solve
    never fails and picks the point nearest ``fallback`` among the minimisers. Its weight
    is 1e-6 of the quadric's own scale (or of ``area_scale`` when A vanishes), so it does
    not move well-defined optima.
    """
    a00, a01, a02 = q[:, _AXX], q[:, _AXY], q[:, _AXZ]
    a11, a12, a22 = q[:, _AYY], q[:, _AYZ], q[:, _AZZ]
    eps = 1e-6 * np.maximum((a00 + a11 + a22) / 3.0, area_scale)
    a00 = a00 + eps
    a11 = a11 + eps
    a22 = a22 + eps
    # Right-hand side -b plus the regulariser's pull, one coordinate at a time (q is
    # column-major, fallback row-major: mixing them in one 2-D expression is slow).
    r0 = eps * fallback[:, 0] - q[:, _BX]
    r1 = eps * fallback[:, 1] - q[:, _BY]
    r2 = eps * fallback[:, 2] - q[:, _BZ]
    # Symmetric 3x3 inverse by cofactors: vectorised and exact enough at this conditioning.
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    c11 = a00 * a22 - a02 * a02
    c12 = a01 * a02 - a00 * a12
    c22 = a00 * a11 - a01 * a01
    det = a00 * c00 + a01 * c01 + a02 * c02
    good = np.abs(det) > 1e-300
    d = np.where(good, det, 1.0)
    x = np.empty_like(fallback)
    x[:, 0] = (c00 * r0 + c01 * r1 + c02 * r2) / d
    x[:, 1] = (c01 * r0 + c11 * r1 + c12 * r2) / d
    x[:, 2] = (c02 * r0 + c12 * r1 + c22 * r2) / d
    x[~good] = fallback[~good]
    return x


def minimize_on_segment(q: np.ndarray, p0: np.ndarray, p1: np.ndarray) -> tuple:
    """Minimiser of each quadric restricted to the segment p0 + t (p1 - p0), t in [0, 1].

    Returns (points (k, 3), t (k,)). Used where a vertex must stay on a polyline (a seam).
    """
    d = p1 - p0
    e0 = evaluate_raw(q, p0)
    e1 = evaluate_raw(q, p1)
    em = evaluate_raw(q, 0.5 * (p0 + p1))
    # error(t) = alpha t^2 + beta t + e0, fitted through t = 0, 0.5, 1
    alpha = 2.0 * (e1 + e0) - 4.0 * em
    beta = e1 - e0 - alpha
    t = np.where(alpha > 0, -beta / np.where(alpha > 0, 2.0 * alpha, 1.0), np.where(e1 < e0, 1.0, 0.0))
    t = np.clip(t, 0.0, 1.0)
    return p0 + t[:, None] * d, t


def evaluate_raw(q: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Quadric error without clamping (for fitting)."""
    X, Y, Z = x[:, 0], x[:, 1], x[:, 2]
    return (
        q[:, _AXX] * X * X
        + q[:, _AYY] * Y * Y
        + q[:, _AZZ] * Z * Z
        + 2.0 * (q[:, _AXY] * X * Y + q[:, _AXZ] * X * Z + q[:, _AYZ] * Y * Z)
        + 2.0 * (q[:, _BX] * X + q[:, _BY] * Y + q[:, _BZ] * Z)
        + q[:, _C]
    )
