"""The quadric each input vertex starts with: planes of its triangles, its line quadric,
boundary planes and feature-edge planes (paper Sec. 3, 4.1, 4.2, 4.4)."""
from __future__ import annotations

import numpy as np

from . import quadrics
from .geometry import face_frames
from .options import DEFAULT_LINE_WEIGHT
from .topology import Connectivity

# Sec. 4.4.1: the extreme-weight variant needs some line quadric before scaling, or a
# flat region (zero error) stays uncontrollable; this is the floor applied where
# quadric_scale > 1 and the caller's line weight is smaller: the paper's default w.
SCALED_LINE_WEIGHT_FLOOR = DEFAULT_LINE_WEIGHT


def _unit_rows(v: np.ndarray) -> tuple:
    length = np.linalg.norm(v, axis=1)
    ok = length > 1e-300
    out = np.zeros_like(v)
    out[ok] = v[ok] / length[ok, None]
    return out, ok


def build(
    vertices: np.ndarray,
    faces: np.ndarray,
    conn: Connectivity,
    line_weights: np.ndarray,
    quadric_scale,
    boundary_weight: float,
    feature_edges,
    feature_edge_weights,
    probabilistic_sigma: float = 0.0,
    line_scale_exponent: float = 1.0,
    line_part: bool = False,
) -> tuple:
    """Returns (Q (n, 10), vertex areas (n,)) for the input mesh; with ``line_part`` also
    the line quadrics' share of Q (n, 10), scaled as Q is, or None where there is none.

    line_weights: (n,) w_i of Eq. 16; quadric_scale: (n,) >= 1 or None (Sec. 4.4.1), which
    multiplies the planes and multiplies the line quadric by quadric_scale **
    line_scale_exponent (1: the whole augmented quadric, as the paper);
    feature_edges: (k, 2) or None with feature_edge_weights (k,) (Eq. 19);
    probabilistic_sigma: standard deviation of the noise on the unit normals of Trettner
    & Kobbelt's probabilistic planes (dimensionless): the alternative regulariser the
    paper compares with (Fig. 9), off at 0.
    """
    n = len(vertices)
    normals, areas = face_frames(vertices, faces)

    # Eq. 7-8: area-weighted triangle planes, a third of each face per corner.
    plane = quadrics.plane_quadrics(normals, vertices[faces[:, 0]], areas / 3.0)
    q = quadrics.accumulate(faces, plane, n)
    vertex_area = quadrics.scatter_sum(faces, areas / 3.0, n)

    # Eq. 12 and 16: line along the area-weighted vertex normal, weighted by w_i a_i.
    vertex_normal, has_normal = _unit_rows(quadrics.scatter_sum(faces, normals * areas[:, None], n))
    w = np.asarray(line_weights, dtype=np.float64)
    if quadric_scale is not None:
        w = np.where(quadric_scale > 1, np.maximum(w, SCALED_LINE_WEIGHT_FLOOR), w)
    line_w = np.where(has_normal, w * vertex_area, 0.0)
    if quadric_scale is not None and line_scale_exponent != 1.0:
        line_w = line_w * quadric_scale ** (line_scale_exponent - 1.0)  # q *= quadric_scale below
    lines = None
    if np.any(line_w > 0):
        lines = quadrics.line_quadrics(vertex_normal, vertices, line_w)
        q += lines

    if probabilistic_sigma > 0:
        # With isotropic normal noise sigma, a plane through p costs its squared distance
        # plus sigma^2 |x - p|^2 in expectation (TK20, Sec. 3); p the vertex, area-weighted
        # like the planes. Position noise only adds a constant, which the per-area cost
        # ordering ignores.
        q += quadrics.point_quadrics(vertices, probabilistic_sigma ** 2 * vertex_area)
    if boundary_weight > 0:
        q += _boundary_quadrics(vertices, normals, conn, boundary_weight, n)
    if feature_edges is not None and len(feature_edges):
        q += _feature_quadrics(vertices, normals, areas, conn, feature_edges, feature_edge_weights, n)

    if quadric_scale is not None:
        q *= quadric_scale[:, None]
        if lines is not None:
            lines *= quadric_scale[:, None]
    return (q, vertex_area, lines) if line_part else (q, vertex_area)


def _boundary_quadrics(vertices, face_normals, conn, weight, n):
    """Planes through each open boundary edge, perpendicular to its face (GH98), weighted
    by the squared edge length so they scale like the area-weighted face planes."""
    border = conn.edge_faces == 1
    e = conn.edges[border]
    direction = vertices[e[:, 1]] - vertices[e[:, 0]]
    plane_normal, ok = _unit_rows(np.cross(direction, face_normals[conn.edge_face0[border]]))
    w = weight * np.einsum("ij,ij->i", direction, direction) * ok
    plane = quadrics.plane_quadrics(plane_normal, vertices[e[:, 0]], w)
    return quadrics.accumulate(e, plane, n)


def _feature_quadrics(vertices, face_normals, face_areas, conn, feature_edges, edge_weights, n):
    """Dihedral-plane quadrics of Eq. 18-19 on the given edges.

    The plane contains the edge and its area-weighted edge normal; weighted by
    w_ij * a_ij / 2 with a_ij a third of the incident face areas, added to both ends.
    """
    fe = np.sort(np.asarray(feature_edges, dtype=np.int64), axis=1)
    keys = fe[:, 0] * np.int64(n) + fe[:, 1]
    idx = np.searchsorted(conn.edge_keys, keys)
    idx = np.minimum(idx, len(conn.edge_keys) - 1)
    present = conn.edge_keys[idx] == keys  # edges not in the mesh are ignored
    idx, fe, w_in = idx[present], fe[present], np.asarray(edge_weights, dtype=np.float64)[present]
    f0, f1 = conn.edge_face0[idx], conn.edge_face1[idx]
    has1 = f1 >= 0
    f1s = np.where(has1, f1, f0)
    area0 = face_areas[f0]
    area1 = np.where(has1, face_areas[f1s], 0.0)
    edge_normal = face_normals[f0] * area0[:, None] + face_normals[f1s] * area1[:, None]
    edge_normal, _ = _unit_rows(edge_normal)
    direction = vertices[fe[:, 1]] - vertices[fe[:, 0]]
    plane_normal, ok = _unit_rows(np.cross(direction, edge_normal))
    edge_area = (area0 + area1) / 3.0
    plane = quadrics.plane_quadrics(plane_normal, vertices[fe[:, 0]], w_in * edge_area / 2.0 * ok)
    return quadrics.accumulate(fe, plane, n)
