"""core.assembly: an asset's parts in one run, split back per part (issue 32 §2), and
parts smaller than the LOD's error leaving it (issue 33 §1). Every input is generated here."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import core
import core.components
from core import assembly
import mesh_builders as build
import mesh_checks as check


def _sphere(level=3, radius=1.0, offset=(0.0, 0.0, 0.0)):
    V, F = build.icosphere(level)[:2]
    return np.asarray(V, dtype=np.float64) * radius + np.asarray(offset), np.asarray(F, dtype=np.int64)


def _run(parts, targets):
    """(per level, each part's result; the combined results)."""
    v, f, options, layout = assembly.combine(parts)
    results = core.simplify_chain(v, f, targets, options)
    return [assembly.split(r, layout) for r in results], results


def _drawn(level, parts):
    return sum(0 if r is None else len(r.faces) * p.copies for r, p in zip(level, parts))


def test_parts_that_touch_come_back_apart_and_valid():
    """Two copies of one sphere at the same place: every vertex coincides with one of the
    other part's, and a weld would join them; each part comes back a valid closed mesh of
    its own, in its own indices."""
    V, F = _sphere(3)
    parts = [assembly.Part(V, F, core.Options()), assembly.Part(V.copy(), F, core.Options())]
    levels, _ = _run(parts, [2 * len(F)])
    for r, p in zip(levels[0], parts):
        check.assert_valid_result(r, p.vertices, p.faces)
        assert len(r.faces) == len(F)  # (nothing to remove: both whole)
    levels, _ = _run(parts, [len(F)])
    assert _drawn(levels[0], parts) == len(F)
    for r, p in zip(levels[0], parts):
        check.assert_valid_result(r, p.vertices, p.faces)
        assert np.allclose(np.linalg.norm(r.vertices, axis=1), 1.0, atol=0.05)


def test_a_part_drawn_several_times_counts_each_time():
    """Targets count what the asset draws: a part instanced four times counts four times
    for every triangle it keeps. Both parts are alike, so at equal error they keep alike
    counts, and what is drawn meets the budget."""
    V, F = _sphere(3)
    parts = [assembly.Part(V, F, core.Options(), copies=1), assembly.Part(V + 3.0, F, core.Options(), copies=4)]
    drawn = 5 * len(F)
    levels, _ = _run(parts, [drawn // 2, drawn // 5])
    for target, level in zip([drawn // 2, drawn // 5], levels):
        assert target - 2 * 4 <= _drawn(level, parts) <= target
        assert abs(len(level[1].faces) - len(level[0].faces)) <= 0.1 * len(level[0].faces)


def test_the_larger_part_keeps_more_at_equal_error():
    """One mesh at two sizes: the run is in the asset's units, so the large copy's
    collapses cost more and it keeps more triangles; each comes back in its own units."""
    V, F = _sphere(3)
    parts = [assembly.Part(V, F, core.Options(), scale=1.0), assembly.Part(V, F, core.Options(), scale=5.0)]
    (small, large), = _run(parts, [len(F)])[0]
    assert len(large.faces) > 1.5 * len(small.faces)
    for r in (small, large):
        assert np.allclose(np.linalg.norm(r.vertices, axis=1), 1.0, atol=0.1)  # own units


@pytest.mark.parametrize("tiny", [1e-4, 1e-6])
def test_a_part_ten_million_times_smaller_does_not_stop_the_run(tiny):
    """A sphere at 1,000 units and one at 1e-4 (or 1e-6) in one run under a distance
    bound, as an asset's search by deviation runs it: rule no_degenerate_face measures
    each face against its own part's size. Against the run's, every face of the small
    part was below the floor, none of its collapses was allowed, and the run stopped
    before the large part lost a triangle."""
    V, F = _sphere(3)
    parts = [assembly.Part(V, F, core.Options(), scale=1000.0), assembly.Part(V, F, core.Options(), scale=tiny)]
    v, f, options, layout = assembly.combine(parts)
    result = core.simplify_chain(v, f, [0], core.Options.of(options, max_error=[50.0]))[0]
    large, small = assembly.split(result, layout)
    assert len(large.faces) < 0.5 * len(F), len(large.faces)
    assert small is None or len(small.faces) < len(F)
    for r, p in zip((large, small), parts):
        if r is not None:
            check.assert_valid_result(r, p.vertices, p.faces)


def test_uv_seams_do_not_decide_which_part_pays():
    """A large sphere and six small ones, each a UV sphere whose pole triangles have a UV
    of their own (as Blender makes them): with their UVs, the parts share every level
    about as they do without, by error. The rings around the small spheres' poles are
    not seam vertices (the UV changes at the pole only); counted as seam ends they were
    locked, and the large sphere paid for them with 34 of the 536 triangles of the 10 %
    level, against 376 without UVs."""
    big = build.uv_sphere(48, 24, radius=4.0)
    small = [build.uv_sphere(24, 12, radius=0.4, pole_uv="fan") for _ in range(6)]
    meshes = [big] + [(V + [6.0 + i, 0.0, 0.0], F, UV) for i, (V, F, UV) in enumerate(small)]
    total = sum(len(F) for _, F, _ in meshes)
    targets = [total // 4, total // 10]
    shares = []
    for with_uv in (False, True):
        parts = [assembly.Part(V, F, core.Options(corner_attributes={"uv": UV}, uv_attributes=("uv",))
                               if with_uv else core.Options()) for V, F, UV in meshes]
        levels, results = _run(parts, targets)
        for target, level, r in zip(targets, levels, results):
            assert r.stats.stop_reason == core.STOP_TARGET and target - 1 <= _drawn(level, parts) <= target
        shares.append([len(level[0].faces) / _drawn(level, parts) for level in levels])
    plain, with_uv = np.array(shares)
    assert np.all(with_uv >= 0.8 * plain), (plain, with_uv)


def test_attributes_a_part_lacks_are_padded_and_left_out_of_its_result():
    """Part A has a UV map, a shape key and two skin columns; B has one skin column and
    nothing else. Each comes back with exactly its own attributes and widths, the key's
    offsets in A's own units (A drawn at twice its size)."""
    V, F = _sphere(3)
    n, m = len(V), len(F)
    uv = np.stack([V[F][..., 0], V[F][..., 1]], axis=-1)
    key = np.zeros((n, 3))
    key[V[:, 2] > 0.5, 2] = 0.2
    skin2 = np.stack([np.clip(V[:, 0] + 0.5, 0, 1), 1 - np.clip(V[:, 0] + 0.5, 0, 1)], axis=1)
    a = core.Options(vertex_attributes={"skin": skin2, "shape0": key}, normalize_attributes=("skin",),
                     corner_attributes={"uv0": uv}, uv_attributes=("uv0",), shape_attributes=("shape0",))
    b = core.Options(vertex_attributes={"skin": np.ones((n, 1))}, normalize_attributes=("skin",))
    parts = [assembly.Part(V, F, a, scale=2.0), assembly.Part(V + 4.0, F, b)]
    (ra, rb), = _run(parts, [2 * m])[0]
    assert set(ra.vertex_attributes) == {"skin", "shape0"} and set(ra.corner_attributes) == {"uv0"}
    assert set(rb.vertex_attributes) == {"skin"} and rb.corner_attributes == {}
    assert ra.vertex_attributes["skin"].shape[1] == 2 and rb.vertex_attributes["skin"].shape[1] == 1
    np.testing.assert_allclose(ra.vertex_attributes["skin"].sum(axis=1), 1.0)
    np.testing.assert_allclose(rb.vertex_attributes["skin"], 1.0)
    # A whole part is its input: offsets and UVs exactly as given (through the scale and back).
    np.testing.assert_allclose(ra.vertex_attributes["shape0"], key[ra.vertex_origin], atol=1e-12)
    np.testing.assert_allclose(ra.corner_attributes["uv0"], uv[ra.face_origin], atol=0)
    half, _ = _run(parts, [m])
    ra = half[0][0]
    assert ra.vertex_attributes["shape0"].max() <= 0.2 + 1e-9  # not scaled by 2


@pytest.mark.parametrize("change", [dict(min_quality=0.1), dict(seed=3), dict(remove_small_components=False)])
def test_parts_must_share_the_options_a_run_has_one_of(change):
    V, F = _sphere(2)
    with pytest.raises(ValueError, match=next(iter(change))):
        assembly.combine([assembly.Part(V, F, core.Options()), assembly.Part(V, F, core.Options(**change))])


def _keyed_sphere(importance: bool, **exponents):
    """A sphere whose top a shape key lifts, with importance (quadric_scale 4 on the top,
    as Source Shape Keys gives) or without, and ``exponents`` (line_/key_scale_exponent)."""
    V, F = _sphere(3)
    key = np.zeros((len(V), 3))
    key[V[:, 2] > 0.5, 2] = 0.2
    scale = np.where(V[:, 2] > 0.5, 4.0, 1.0) if importance else None
    return V, F, core.Options(vertex_attributes={"shape0": key}, shape_attributes=("shape0",),
                              quadric_scale=scale, **exponents)


@pytest.mark.parametrize("scale", [None, "ones"])
def test_importance_exponents_do_not_touch_a_part_without_importance(scale):
    """line_scale_exponent and key_scale_exponent raise quadric_scale: a mesh without
    one (or with 1 everywhere) simplifies the same under any value of them."""
    V, F, base = _keyed_sphere(False)
    if scale == "ones":
        base = core.Options.of(base, quadric_scale=np.ones(len(V)))
    plain = core.simplify(V, F, target_faces=len(F) // 4, options=base)
    raised = core.simplify(V, F, target_faces=len(F) // 4,
                           options=core.Options.of(base, line_scale_exponent=0.75, key_scale_exponent=1.9))
    np.testing.assert_array_equal(plain.faces, raised.faces)
    np.testing.assert_array_equal(plain.vertices, raised.vertices)


def test_a_part_with_importance_shares_a_run_with_parts_without():
    """Importance on one part (its exponents the add-on's) and none on the other (the
    defaults): one run, with the painted part's exponents, and no part's result is
    changed by what the other part's options say about them. Two parts with importance
    must agree."""
    Va, Fa, painted = _keyed_sphere(True, line_scale_exponent=0.75, key_scale_exponent=1.9)
    Vb, Fb, plain = _keyed_sphere(False)
    parts = [assembly.Part(Va, Fa, painted), assembly.Part(Vb + 4.0, Fb, plain)]
    options = assembly.combine(parts)[2]
    assert (options.line_scale_exponent, options.key_scale_exponent) == (0.75, 1.9)
    levels, _ = _run(parts, [len(Fa) // 2])
    alike = [parts[0], assembly.Part(Vb + 4.0, Fb, core.Options.of(plain, line_scale_exponent=0.75,
                                                                   key_scale_exponent=1.9))]
    same, _ = _run(alike, [len(Fa) // 2])
    for got, want in zip(levels[0], same[0]):
        np.testing.assert_array_equal(got.faces, want.faces)
    other = core.Options.of(painted, line_scale_exponent=1.0)
    with pytest.raises(ValueError, match="line_scale_exponent"):
        assembly.combine([parts[0], assembly.Part(Vb + 4.0, Fb, other)])


@pytest.mark.parametrize("change", [dict(max_error=0.1), dict(vertex_max_error=np.full(162, 0.1))])
def test_distance_bounds_are_not_combined(change):
    """The tracked distance finds the closest source point, which could be on another part."""
    V, F = _sphere(2)
    with pytest.raises(ValueError, match=next(iter(change))):
        assembly.combine([assembly.Part(V, F, core.Options(**change)), assembly.Part(V, F, core.Options())])


@pytest.mark.parametrize("bad, message", [
    (dict(part_copies=[1, 1]), "needs vertex_part"),
    (dict(vertex_part=np.full(162, -1)), "integers >= 0"),
    (dict(vertex_part=np.zeros(5, dtype=int)), "one value per vertex"),
    (dict(vertex_part=np.zeros(162, dtype=int), part_copies=[0]), "whole numbers >= 1"),
    (dict(vertex_part=np.r_[np.zeros(100, int), np.ones(62, int)], part_copies=[2]), "one value per part"),
])
def test_bad_part_options_are_named(bad, message):
    V, F = _sphere(2)
    with pytest.raises(ValueError, match=message):
        core.simplify(V, F, target_faces=100, **bad)


def test_a_drawn_target_cannot_exceed_what_the_parts_draw():
    V, F = _sphere(2)
    labels = np.zeros(len(V), dtype=int)
    core.simplify(V, F, target_faces=3 * len(F), vertex_part=labels, part_copies=[3])  # all drawn: fine
    with pytest.raises(ValueError, match="faces the input's parts draw"):
        core.simplify(V, F, target_faces=3 * len(F) + 1, vertex_part=labels, part_copies=[3])


def test_parts_smaller_than_the_error_leave_the_lod():
    """A sphere and 40 specks a thousandth of its size, one mesh: at 10 % the sphere's
    error is far larger than a speck, so the specks go (their removal costs less) and
    their triangles go to the sphere; with remove_small_components off they all stay."""
    big = _sphere(3)
    specks = [_sphere(1, 0.001, (1.2 + 0.01 * i, 0.0, 0.0)) for i in range(40)]
    V, F = build.components([big] + specks)
    target = len(big[1]) // 10
    r = core.simplify(V, F, target_faces=target)
    check.assert_target_respected(r, target)
    assert r.stats.removed_components == 40
    kept = np.zeros(len(V), dtype=bool)
    kept[r.vertex_origin] = True
    assert not kept[len(big[0]):].any() and len(r.faces) >= target - 1
    whole = core.simplify(V, F, target_faces=target, remove_small_components=False)
    assert whole.stats.removed_components == 0 and len(whole.faces) > len(r.faces) - 1


def test_parts_larger_than_the_error_stay():
    """At 50 % a sphere's error is far below the size of a second, smaller sphere: both stay."""
    V, F = build.components([_sphere(3), _sphere(3, 0.2, (2.0, 0.0, 0.0))])
    r = core.simplify(V, F, target_faces=len(F) // 2)
    assert r.stats.removed_components == 0
    assert len(np.unique(core.components.face_labels(r.faces, len(r.vertices)))) == 2


@settings(max_examples=20, deadline=None)
@given(st.lists(st.tuples(st.integers(1, 3), st.floats(0.2, 5.0), st.integers(1, 4)), min_size=2, max_size=5),
       st.floats(0.1, 0.8))
def test_every_part_comes_back_valid_and_the_asset_meets_its_budget(spec, ratio):
    """Any mix of parts (size, scale, copies): each level's parts are valid meshes in their
    own indices, and what the asset draws meets the target (within one collapse of the
    most drawn part), or falls short only by parts that left."""
    parts = [assembly.Part(*_sphere(level, 1.0, (3.0 * i, 0.0, 0.0)), core.Options(), scale=scale, copies=copies)
             for i, (level, scale, copies) in enumerate(spec)]
    drawn = sum(len(p.faces) * p.copies for p in parts)
    target = max(int(ratio * drawn), 1)
    levels, combined = _run(parts, [target])
    got = _drawn(levels[0], parts)
    stop = combined[0].stats.stop_reason  # (each part's share is its own target, reached)
    assert all(r is None or r.stats.stop_reason == core.STOP_TARGET for r in levels[0])
    if stop == core.STOP_TARGET:
        assert target - 2 * max(p.copies for p in parts) <= got <= target
    else:  # (closed parts keep four triangles each)
        assert got > target
    for r, p in zip(levels[0], parts):
        if r is not None:
            check.assert_valid_result(r, p.vertices, p.faces)


def test_a_part_seamless_corner_data_stays_seamless_in_the_run():
    """Part A (the second) carries faceted normals without seams (Options.seamless_attributes),
    B nothing: the combined run must not turn A's normal splits into seams, so A is
    simplified as far as it would be without them, at the strictest rules."""
    V, F = _sphere(3)
    face_normals, _ = core.geometry.face_frames(V, F)
    normals = np.repeat(face_normals[:, None, :], 3, axis=1)
    a = core.Options(corner_attributes={"normal": normals}, seamless_attributes=("normal",))
    parts = [assembly.Part(V + 4.0, F, core.Options()), assembly.Part(V, F, a)]
    v, f, options, _ = assembly.combine(parts)
    assert options.seamless_attributes == ("normal",)
    levels, results = _run(parts, [len(F) // 2])
    rb, ra = levels[0]
    assert results[0].stats.relaxation_step == 0
    # The same sphere twice, normals or not: about the same share each (324 and 316 here).
    assert abs(len(ra.faces) - len(rb.faces)) <= 0.05 * len(F)
    assert set(ra.corner_attributes) == {"normal"}


def test_unmoved_vertices_of_a_scaled_part_come_back_as_given():
    """A part drawn at an odd scale, taken down only a little: the vertices no collapse
    moved are its own, bit for bit (x * s / s need not be x), as for one mesh, so a
    measurement finds the triangles no collapse reached unchanged."""
    V, F = _sphere(4, radius=0.37, offset=(0.011, 0.0, 0.0))
    parts = [assembly.Part(V, F, core.Options(), scale=3.3), assembly.Part(V + 5.0, F, core.Options())]
    levels, _ = _run(parts, [int(1.8 * len(F))])
    moved = 0
    for part, r in zip(parts, levels[0]):
        given = np.asarray(part.vertices)[r.vertex_origin]
        same = np.all(r.vertices == given, axis=1)
        assert same.mean() > 0.2
        moved += int((~same).sum())
        # The rest moved: none is a rounding of its own input position.
        near = np.all(np.isclose(r.vertices, given, rtol=0, atol=1e-12), axis=1)
        np.testing.assert_array_equal(same, near)
        match, _ = core.geometry.same_triangles(part.vertices, part.faces, r.vertices, r.faces)
        assert (match >= 0).mean() > 0.3
    assert moved > 0


def _rounded_box(k=6, flat=0.85):
    """A cube rounded at its edges and corners by 1 - ``flat`` in two segments, as a bevel
    makes it: long thin strips along every edge, 44 % of its 432 triangles slivers."""
    V, F = build.cube(k)[:2]
    V, F = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
    a = np.abs(V)
    V = np.sign(V) * np.where(a <= 1 / 3, 3 * a * flat, flat + 1.5 * (a - 1 / 3) * (1 - flat))
    centre = np.clip(V, -flat, flat)
    off = V - centre
    length = np.linalg.norm(off, axis=1, keepdims=True)
    return np.where(length > 0, centre + (1 - flat) * off / np.maximum(length, 1e-12), V), F


def test_a_part_whose_thin_strips_are_its_shape_keeps_them_beside_a_smooth_part():
    """Whether slivers are a part's shape or faults is judged per part: the bevelled box
    is 44 % slivers, its strips its rounding; beside a 20,480-triangle sphere the asset is
    under 1 % slivers, and taken as faults (core.slivers.ranked_first) the strips went
    first, whatever their removal cost: the box kept 328 and 288 of its 432 triangles
    while the sphere's collapses cost far less."""
    V, F = _rounded_box()
    assert (core.metrics.triangle_quality(V, F) < core.SLIVER_QUALITY).mean() > 0.4
    S, SF = _sphere(5, offset=(4.0, 0.0, 0.0))
    parts = [assembly.Part(V, F, core.Options()), assembly.Part(S, SF, core.Options())]
    total = len(F) + len(SF)
    levels, _ = _run(parts, [total // 2, total // 4])
    for level in levels:
        assert len(level[0].faces) >= 0.95 * len(F), [len(r.faces) for r in level]
    # The sphere alone still takes its slivers first: a sliver in it is a fault.
    assert core.slivers.sliver_allowance(core.metrics.triangle_quality(S, SF)) == 0.0
