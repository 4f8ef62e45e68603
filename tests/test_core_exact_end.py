"""Under a distance bound a merged vertex goes to an end of its edge where that end keeps
every plane of the pair's faces and the quadric's optimum does not
(core.selection.exact_end). Every input is generated here."""
from __future__ import annotations

import numpy as np
import pytest

import core
import mesh_builders as build
from core import quadrics, selection
from core.geometry import face_frames
from surface_distance import distance_to_mesh


def _crease_quadric(flat_area=1.0, crease_area=0.01):
    """(1, 10) the quadric of the plane z = 0 (weight ``flat_area``) and the plane x = 0
    (weight ``crease_area``): they meet on the y axis."""
    normals = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    planes = quadrics.plane_quadrics(normals, np.zeros((2, 3)), np.array([flat_area, crease_area]))
    return planes.sum(axis=0, keepdims=True)


def test_an_optimum_off_the_crease_goes_to_the_end_on_it():
    """Keep on the crease (the y axis), remove on the flat side: the keep end is exact."""
    q = _crease_quadric()
    keep, remove = np.array([[0.0, 1.0, 0.0]]), np.array([[0.5, 0.0, 0.0]])
    optimum = np.array([[0.2, 0.5, 0.0]])  # on the flat plane, off the crease
    out = selection.exact_end(q, np.array([1.01]), keep, remove, optimum)
    np.testing.assert_array_equal(out, keep)
    # ... and the remove end when that is the one on the crease.
    out = selection.exact_end(q, np.array([1.01]), remove, keep, optimum)
    np.testing.assert_array_equal(out, keep)


def test_an_optimum_on_every_plane_stays():
    q = _crease_quadric()
    keep, remove = np.array([[0.0, 1.0, 0.0]]), np.array([[0.0, -1.0, 0.0]])
    optimum = np.array([[0.0, 0.3, 0.0]])  # on the crease between the ends
    np.testing.assert_array_equal(selection.exact_end(q, np.array([1.01]), keep, remove, optimum), optimum)


def test_no_exact_end_no_change():
    """Neither end on the crease: the optimum stays, however far off it is."""
    q = _crease_quadric()
    keep, remove = np.array([[0.3, 1.0, 0.0]]), np.array([[0.5, 0.0, 0.0]])
    optimum = np.array([[0.4, 0.5, 0.0]])
    np.testing.assert_array_equal(selection.exact_end(q, np.array([1.01]), keep, remove, optimum), optimum)


def _flat_faces(V, F) -> int:
    normals, _ = face_frames(V, F)
    return int((np.abs(normals).max(axis=1) > 1.0 - 1e-9).sum())


def test_a_bevelled_box_loses_its_flat_sides_spare_vertices_under_a_bound():
    """The flat sides of a bevelled box (docs/method.md, "Props as Blender makes them")
    merge into their bevels' feet at no distance, so under a tight bound each side ends
    as two triangles, as Decimate and w = 0 leave it; with the line quadric's optimum
    the merges left the feet and the bound refused them (all 48 flat triangles kept)."""
    V, F = build.bevelled_box()
    assert _flat_faces(V, F) == 48
    diagonal = np.linalg.norm(V.max(0) - V.min(0))
    bound = 0.0005 * diagonal
    r = core.simplify(V, F, target_faces=0, max_error=bound)
    assert _flat_faces(r.vertices, r.faces) == 12
    assert len(r.faces) < 0.6 * len(F)
    # Within the bound both ways, at the vertices of either surface.
    assert distance_to_mesh(V, r.vertices, r.faces).max() <= bound * (1 + 1e-6)
    assert distance_to_mesh(r.vertices, V, F).max() <= bound * (1 + 1e-6)


@pytest.mark.parametrize("share", [0.25, 0.1])
def test_count_targets_do_not_read_it(share, monkeypatch):
    """Only a distance bound places at exact ends: a count target is the same without it.
    (On the filleted puck exact ends at count targets do change the LOD: its flat cap's
    vertices merge into the fillet's foot.)"""
    V, F, _ = build.filleted_puck()
    target = int(share * len(F))
    r = core.simplify(V, F, target_faces=target)
    monkeypatch.setattr(selection, "exact_end", lambda geometric, area, keep, remove, position: position)
    plain = core.simplify(V, F, target_faces=target)
    np.testing.assert_array_equal(r.faces, plain.faces)
    np.testing.assert_array_equal(r.vertices, plain.vertices)


def test_the_rows_that_may_go_to_an_end():
    """Rows placed at the optimum where a bound holds: all of them under max_error, only
    those with an end under a painted limit under limits alone, none without a bound."""
    from types import SimpleNamespace

    from core import kinds

    place = np.array([kinds.OPTIMAL, kinds.OPTIMAL, kinds.AT_KEEP, kinds.OPTIMAL, kinds.ON_SEAM])
    keep, remove = np.array([0, 1, 2, 3, 4]), np.array([5, 6, 7, 8, 9])
    limited = np.zeros(10, dtype=bool)
    limited[[1, 8]] = True  # rows 1 (its keep) and 3 (its remove)
    everywhere = SimpleNamespace(line_part=object(), bound=SimpleNamespace(global_bound=True, limited=limited))
    np.testing.assert_array_equal(selection.exact_end_rows(everywhere, place, keep, remove), [0, 1, 3])
    painted = SimpleNamespace(line_part=object(), bound=SimpleNamespace(global_bound=False, limited=limited))
    np.testing.assert_array_equal(selection.exact_end_rows(painted, place, keep, remove), [1, 3])
    unbounded = SimpleNamespace(line_part=None, bound=None)
    assert len(selection.exact_end_rows(unbounded, place, keep, remove)) == 0
