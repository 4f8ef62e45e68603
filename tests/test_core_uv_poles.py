"""UV poles (core.uv_poles): the seams a UV sphere's pole makes, each triangle with its
own UV there, fade out within the island and hold nothing but the pole. Subdivided, they
held the seam vertices halfway along them at the poles while the rest of the sphere
went: Blender's UV sphere with a Subdivision Surface modifier, at 5 % of its triangles,
measured 11.6 % of its size from the sphere (1.1 % now)."""
import numpy as np
import pytest

import core
from core import topology, uv_poles
from core.wedges import Wedges
import mesh_builders as build
import mesh_checks as check


def _changes(V, F, UV):
    conn = topology.build(F, len(V))
    wedges = Wedges.build(F, {"uv": UV}, ("uv",))
    return conn, wedges.value_changes(F, conn)


def _seam_vertices(conn, change, n):
    return np.bincount(conn.edges[change], minlength=n) > 0


def test_a_subdivided_poles_rays_are_not_seams_but_at_the_pole():
    V, F, UV = build.subdivided_uv_sphere(1)
    conn, change = _changes(V, F, UV)
    cleared = uv_poles.pole_web_changes(conn.edges, change, len(V))
    before, after = _seam_vertices(conn, change, len(V)), _seam_vertices(conn, cleared, len(V))
    poles = np.flatnonzero(np.abs(V[:, 2]) > 1 - 1e-9)
    # The rays' midpoints leave the seams (31 a pole: the 32nd ray is the meridian's own
    # first edge); the poles and the meridian stay.
    assert after[poles].all()
    assert before.sum() - after.sum() == 2 * 31
    meridian = after & (np.abs(V[:, 1]) < 1e-9) & (V[:, 0] > 0)
    assert meridian.sum() == after.sum() - 2
    # Only changes at ray ends were cleared.
    assert not (cleared & ~change).any()


def test_seams_that_do_not_fade_or_start_at_a_junction_stay():
    """The unsubdivided sphere's rays are one edge each (their ring end is continuous
    already): nothing to clear. A seam joining two poles is the meridian: kept."""
    V, F, UV = build.uv_sphere(32, 16, pole_uv="fan")
    conn, change = _changes(V, F, UV)
    assert np.array_equal(uv_poles.pole_web_changes(conn.edges, change, len(V)), change)
    V, F, UV = build.uv_sphere(32, 16, pole_uv="shared")  # no pole: the meridian alone
    conn, change = _changes(V, F, UV)
    assert np.array_equal(uv_poles.pole_web_changes(conn.edges, change, len(V)), change)


def test_an_island_outline_around_a_pole_stays_a_seam():
    """A cap island around the pole (its UVs elsewhere) has an outline of seam vertices
    near the pole, but the outline joins no pole: it stays; the fan's rays are one edge
    each, as before."""
    V, F, UV = build.uv_sphere(32, 16, pole_uv="fan")
    UV = UV.copy()
    cap = (V[F][:, :, 2] > np.cos(2 * np.pi / 16) - 1e-9).all(axis=1)  # the pole's two rings
    UV[cap] += [5.0, 0.0]
    conn, change = _changes(V, F, UV)
    outline = _seam_vertices(conn, change, len(V)) & (np.abs(V[:, 2] - np.cos(2 * np.pi / 16)) < 1e-9)
    assert outline.sum() == 32
    assert np.array_equal(uv_poles.pole_web_changes(conn.edges, change, len(V), conn.border_vertex), change)


@pytest.mark.parametrize("levels, ratio", [(1, 0.05), (2, 0.02)])
def test_a_subdivided_uv_sphere_keeps_its_shape_at_low_counts(levels, ratio):
    """Every face of the LOD stays near the unit sphere (a face across it, as when the
    poles held the budget, has its centroid near the centre)."""
    V, F, UV = build.subdivided_uv_sphere(levels)
    r = core.simplify(V, F, ratio=ratio, corner_attributes={"uv": UV}, uv_attributes=("uv",))
    check.assert_valid_result(r, V, F)
    assert abs(len(r.faces) - round(ratio * len(F))) <= 2
    centroids = r.vertices[r.faces].mean(axis=1)
    assert np.linalg.norm(centroids, axis=1).min() > 0.8
