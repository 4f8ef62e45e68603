"""core.Options.plane_placement: under a distance bound a merged vertex goes to the optimum
of its pair's planes (core.selection.plane_optimum), the line quadrics kept at a
hundredth; the deviation search runs it beside the controls and lean
(addon/pure/deviation_targets.alternatives). Every input is generated here."""
from __future__ import annotations

import numpy as np
import pytest

import core
import mesh_builders as build
from core import quadrics, selection
from surface_distance import distance_to_mesh


def test_the_planes_decide_where_they_can():
    """A corner (the planes x = 0, y = 0, z = 0 meet at the origin, the keep end) merged
    with a vertex along one of its creases: the whole quadric's optimum leaves the corner
    towards the other end's normal line, the planes' optimum stays on every plane (up to
    the hundredth of the line quadrics it keeps)."""
    normals = np.eye(3)
    ends = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    planes = quadrics.plane_quadrics(normals, np.zeros((3, 3)), np.ones(3)).sum(axis=0, keepdims=True)
    line_normals = np.array([[1.0, 1.0, 1.0], [0.0, 1.0, 1.0]])
    line_normals /= np.linalg.norm(line_normals, axis=1, keepdims=True)
    q = planes + quadrics.line_quadrics(line_normals, ends, np.full(2, 1e-2)).sum(axis=0, keepdims=True)
    whole = quadrics.minimize(q, ends.mean(axis=0, keepdims=True), 1.0)
    by_planes = selection.plane_optimum(q, planes, ends[:1], ends[1:], 1.0)
    assert whole[0, 0] > 1e-3  # pulled along the crease, off the corner
    assert quadrics.evaluate(planes, by_planes)[0] < 1e-3 * quadrics.evaluate(planes, whole)[0]
    np.testing.assert_allclose(by_planes, ends[:1], atol=2e-4)


def test_a_flat_pair_keeps_a_well_conditioned_solve():
    """Two coplanar vertices: the planes alone leave a whole plane of optima; the hundredth
    of the line quadrics picks the point between the ends, on the plane."""
    normals = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    ends = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    planes = quadrics.plane_quadrics(normals, ends, np.ones(2)).sum(axis=0, keepdims=True)
    q = planes + quadrics.line_quadrics(normals, ends, np.full(2, 1e-3)).sum(axis=0, keepdims=True)
    at = selection.plane_optimum(q, planes, ends[:1], ends[1:], 1.0)
    np.testing.assert_allclose(at, [[0.5, 0.0, 0.0]], atol=1e-9)


def test_a_bevelled_disc_needs_fewer_triangles_under_a_bound():
    """Blender's bevelled cylinder, generated: at 0.18 % of its diagonal the whole
    quadric's placement spends the bound on the bevels' rings (392 triangles when
    written), the planes' placement about a fifth fewer, and both LODs stay within the
    bound both ways at the vertices of either surface."""
    V, F = build.bevelled_disc()
    bound = 0.0018 * np.linalg.norm(V.max(0) - V.min(0))
    whole = core.simplify(V, F, target_faces=0, max_error=bound)
    by_planes = core.simplify(V, F, target_faces=0, max_error=bound, plane_placement=True)
    assert len(by_planes.faces) <= 0.9 * len(whole.faces)
    for r in (whole, by_planes):
        assert distance_to_mesh(V, r.vertices, r.faces).max() <= bound * (1 + 1e-6)
        assert distance_to_mesh(r.vertices, V, F).max() <= bound * (1 + 1e-6)


@pytest.mark.parametrize("share", [0.25, 0.1])
def test_count_targets_do_not_read_it(share):
    """Without a bound the whole quadric places every merge: the same LOD either way."""
    V, F = build.bevelled_disc()
    plain = core.simplify(V, F, target_faces=int(share * len(F)))
    flagged = core.simplify(V, F, target_faces=int(share * len(F)), plane_placement=True)
    np.testing.assert_array_equal(flagged.faces, plain.faces)
    np.testing.assert_array_equal(flagged.vertices, plain.vertices)


def test_the_search_runs_it_after_lean():
    """deviation_targets.alternatives: core options, lean first (compared first), then the
    planes' placement with the controls' line weight and sliver floor."""
    from addon.pure import deviation_targets

    lean, planes = deviation_targets.alternatives({"line_weight": 2e-3}, 0.4)
    assert lean == {"line_weight": 2e-3 * deviation_targets.LEAN_LINE_WEIGHT,
                    "min_quality": 0.4 * deviation_targets.LEAN_MIN_QUALITY}
    assert planes == {"plane_placement": True}
    for variant in (lean, planes):
        core.Options.of(**variant)  # every key an option (a typo raises)
    # An asset's parts in one run carry the line weight per vertex.
    per_vertex, _ = deviation_targets.alternatives({"line_weights": np.array([1e-3, 2e-3])}, 0.3)
    np.testing.assert_allclose(per_vertex["line_weights"], np.array([1e-3, 2e-3]) * deviation_targets.LEAN_LINE_WEIGHT)
