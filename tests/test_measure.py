"""addon/pure/measure.py: surface deviation against cases with known answers.

The sampling runs here in the test process (it is pure NumPy); everything that needs
``mathutils`` runs in one Blender child per session (tests/scenarios/measure_deviation.py),
which gets the test meshes through an .npz file and returns the measured dicts.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from addon.pure import measure
from bpy_harness import run_scenario
from mesh_builders import grid, icosphere
from mesh_checks import max_sagitta


# ---------------------------------------------------------------- NumPy side

def test_module_imports_without_blender_and_samples_by_area():
    # Two triangles of areas 0.5 and 1.5 (same plane): a quarter of the samples on the first.
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [4, 0, 0], [4, 1, 0]], float)
    f = np.array([[0, 1, 2], [1, 3, 4]])
    pts = measure.sample_surface(v, f, 200_000, np.random.default_rng(1))
    first = (pts[:, 0] + pts[:, 1]) <= 1.0
    assert abs(first.mean() - 0.25) < 0.005
    # Uniform inside the triangle: the mean of the samples on the first one is its centroid.
    assert np.allclose(pts[first].mean(0), [1 / 3, 1 / 3, 0], atol=0.005)
    assert np.all(pts[:, 2] == 0)


def test_zero_area_faces_are_never_sampled():
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], float)
    f = np.array([[0, 1, 2], [0, 1, 3], [1, 2, 1]])  # faces 0 and 2 are degenerate
    pts = measure.sample_surface(v, f, 10_000, np.random.default_rng(0))
    # Only face 1 (x + y <= 1, x, y >= 0) may be hit.
    assert np.all(pts[:, 0] + pts[:, 1] <= 1.0 + 1e-12)
    assert np.all(pts[:, 1] >= 0)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(0, 6), min_size=1, max_size=60), st.integers(1, 70))
def test_the_largest_few_are_what_a_full_stable_sort_gives(values, count):
    # The climb's seeds: the same indices in the same order as the sort it replaces,
    # ties (many here) included.
    d = np.asarray(values, dtype=np.float64) / 7.0
    np.testing.assert_array_equal(measure._largest(d, count), np.argsort(d, kind="stable")[-count:])


class _PlaneTree:
    """Stands in for a BVHTree of the plane z = 0, with find_nearest's contract: the
    nearest hit within ``distance``, or a tuple of Nones when there is none."""

    def __init__(self):
        self.bounded_misses = 0

    def find_nearest(self, co, distance=float("inf")):
        d = abs(co[2])
        if d > distance:
            self.bounded_misses += 1
            return (None, None, None, None)
        return ((co[0], co[1], 0.0), (0.0, 0.0, 1.0), 0, d)


def test_bounded_queries_fall_back_to_exact_distances():
    # 99.5 % of the points are close, 0.5 % far away: the pilot's radius excludes the far
    # ones, which must come back exact from the unbounded re-query, not as NaN or radius.
    rng = np.random.default_rng(3)
    z = rng.uniform(0.0, 0.01, 10_000)
    far = rng.random(10_000) < 0.005
    z[far] = rng.uniform(5.0, 10.0, far.sum())
    pts = np.c_[rng.random(10_000), rng.random(10_000), z]
    tree = _PlaneTree()
    d = measure._distances(tree, pts)
    assert tree.bounded_misses >= far.sum()  # the radius really was below the far points
    np.testing.assert_array_equal(d, z)
    # Asked for the faces too, the re-queried points come back with theirs.
    d, faces = measure._distances(_PlaneTree(), pts, with_faces=True)
    np.testing.assert_array_equal(d, z)
    assert faces.dtype == np.int64 and np.all(faces == 0)


def test_queries_run_with_the_collector_paused_and_leave_it_as_they_found_it():
    import gc

    seen = []

    class Tree(_PlaneTree):
        def find_nearest(self, co, distance=float("inf")):
            seen.append(gc.isenabled())
            return super().find_nearest(co, distance)

    pts = np.c_[np.zeros(50), np.zeros(50), np.linspace(0.0, 1.0, 50)]
    was = gc.isenabled()
    try:
        gc.enable()
        np.testing.assert_array_equal(measure._distances(Tree(), pts), pts[:, 2])
        assert seen and not any(seen)  # paused while querying ...
        assert gc.isenabled()  # ... and on again after
        with pytest.raises(RuntimeError):  # on again after a failure inside too
            with measure.gc_paused():
                assert not gc.isenabled()
                raise RuntimeError
        assert gc.isenabled()
        gc.disable()  # a caller that turned it off keeps it off, nested or not
        with measure.gc_paused():
            with measure.gc_paused():
                pass
        assert not gc.isenabled()
    finally:
        (gc.enable if was else gc.disable)()


class _BruteTree:
    """Stands in for a BVHTree of any triangles: every triangle tried (NumPy, exact)."""

    def __init__(self, v, f):
        self.a, self.b, self.c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]

    def find_nearest(self, co, distance=float("inf")):
        from core.geometry import closest_on_triangles

        p = np.broadcast_to(np.asarray(co, dtype=np.float64), self.a.shape)
        bary, d2 = closest_on_triangles(p, self.a, self.b, self.c)
        i = int(np.argmin(d2))
        d = float(np.sqrt(d2[i]))
        if d > distance:
            return (None, None, None, None)
        return (tuple(bary[i] @ np.stack([self.a[i], self.b[i], self.c[i]])), (0.0, 0.0, 1.0), i, d)


@pytest.fixture
def brute_trees(monkeypatch):
    monkeypatch.setattr(measure, "_tree_builder", _BruteTree)
    monkeypatch.setattr(measure, "_tree_cache", [])


def test_triangles_on_other_copies_of_their_vertices_are_known_without_a_query(monkeypatch):
    # A mesh split along seams has several vertices at one position; its LOD may draw an
    # untouched triangle on other copies than the ones a lookup by position finds first.
    # Here the LOD is the source drawn entirely on second copies of its vertices: every
    # point is on a triangle both have, at distance 0, and nothing is searched.
    queries = []

    class Counting(_BruteTree):
        def find_nearest(self, co, distance=float("inf")):
            queries.append(co)
            return super().find_nearest(co, distance)

    monkeypatch.setattr(measure, "_tree_builder", Counting)
    monkeypatch.setattr(measure, "_tree_cache", [])
    v, f = grid(4, jitter=0.2)
    copies = np.concatenate([v, v])
    report = measure.surface_deviation(v, f, copies, f + len(v), n_samples=(300, 200), keep_samples=True)
    assert report["hausdorff"] == 0.0 and report["mean"] == 0.0
    assert queries == []
    sampled = report["sampled"]
    np.testing.assert_array_equal(sampled.src_nearest, sampled.src_triangle)  # the same triangle, not a neighbour


def test_a_source_measured_again_reuses_its_samples_and_gives_the_same_numbers(brute_trees, monkeypatch):
    # A source is measured against each of its levels with the same samples: the second
    # measurement takes them (and the generator the climb goes on with) from the first,
    # and gives exactly what measuring it afresh gives.
    v, f = grid(5, jitter=0.2)
    levels = [v + np.c_[np.zeros((len(v), 2)), h * np.sin(5 * v[:, 0])] for h in (0.03, 0.08)]
    monkeypatch.setattr(measure, "_samples_cache", [])
    made = []
    fresh = measure._surface_rng
    monkeypatch.setattr(measure, "_surface_rng", lambda *a: made.append(a[1]) or fresh(*a))
    measure.surface_deviation(v, f, levels[0], f, n_samples=(300, 200), keep_samples=True)
    again = measure.surface_deviation(v, f, levels[1], f, n_samples=(300, 200), keep_samples=True)
    assert sum(x is v for x in made) == 1  # the source was sampled once
    measure._samples_cache.clear()
    measure._tree_cache.clear()
    afresh = measure.surface_deviation(v, f, levels[1], f, n_samples=(300, 200), keep_samples=True)
    for key in ("hausdorff", "mean", "hausdorff_src_to_dst", "mean_dst_to_src"):
        assert again[key] == afresh[key]
    for name in ("src_distance", "src_climbed_distance", "src_climbed_bary", "dst_vertex_distance"):
        np.testing.assert_array_equal(getattr(again["sampled"], name), getattr(afresh["sampled"], name))
    with pytest.raises(ValueError):
        again["sampled"].src_bary[0, 0] = 1.0  # shared with the cache: read-only


def test_a_freed_surface_leaves_the_caches_at_the_next_measurement(brute_trees, monkeypatch):
    # The trees and samples are kept by array identity for the next level; once a surface's
    # arrays are gone its entries must go too, not wait for eight newer ones (a scan's
    # tree is hundreds of megabytes).
    import gc

    monkeypatch.setattr(measure, "_samples_cache", [])
    v, f = grid(4, jitter=0.2)
    measure.surface_deviation(v.copy(), f.copy(), v + 0.01, f.copy(), n_samples=(100, 100))
    gc.collect()
    kept, kept_too = v + 0.02, v + 0.03
    measure.surface_deviation(kept, f, kept_too, f, n_samples=(100, 100))
    for cache in (measure._tree_cache, measure._samples_cache):
        assert cache and all(entry[0]() is not None and entry[1]() is not None for entry in cache)


def test_part_deviations_of_one_part_are_surface_deviations_numbers(brute_trees):
    v, f = grid(4, jitter=0.2)
    lod_v = v + np.c_[np.zeros((len(v), 2)), 0.05 * np.sin(7 * v[:, 0])]
    for limit in (None, 6):
        whole = measure.surface_deviation(v, f, lod_v, f[::-1], n_samples=(300, 200), vertex_limit=limit)
        h, m = measure.part_deviations(v, f, np.zeros(len(f), int), lod_v, f[::-1], np.zeros(len(f), int), 1,
                                       n_samples=(300, 200), vertex_limit=limit)
        assert h[0] == whole["hausdorff"] and m[0] == pytest.approx(whole["mean"], rel=1e-12)
    capped = measure.surface_deviation(v, f, lod_v, f, n_samples=(300, 200), vertex_limit=6)
    assert capped["points_src"] == 300 + 6 and capped["points_dst"] == 200 + 6


def test_part_deviations_give_each_part_its_own_distance(brute_trees):
    # Three flat parts side by side; in the LOD each part's middle vertex is raised by its
    # own height, so each part's Hausdorff distance is exactly that height (the raised
    # vertex right above its own part's plane), whichever part is nearest elsewhere.
    v, f = grid(4, alternate=False)
    middle = int(np.argmin(np.linalg.norm(v - [0.5, 0.5, 0.0], axis=1)))
    heights = [0.02, 0.3, 0.0]
    src_v, src_f, lod_v = [], [], []
    for j, height in enumerate(heights):
        moved = v + [1.5 * j, 0.0, 0.0]
        src_v.append(moved)
        src_f.append(f + len(v) * j)
        raised = moved.copy()
        raised[middle, 2] += height
        lod_v.append(raised)
    src_v, src_f, lod_v = np.concatenate(src_v), np.concatenate(src_f), np.concatenate(lod_v)
    part = np.repeat(np.arange(3), len(f))
    h, m = measure.part_deviations(src_v, src_f, part, lod_v, src_f, part, 4, n_samples=600)
    np.testing.assert_allclose(h[:3], heights, rtol=1e-12, atol=1e-12)
    assert m[2] == 0.0 and 0.0 < m[0] < m[1] < heights[1]
    assert np.isnan(h[3]) and np.isnan(m[3])  # a part neither surface has


def test_the_normals_angles_come_from_the_closest_points_a_measurement_kept(brute_trees):
    # (compute.level_report: a level the deviation search measured gets its normals from
    # the points it kept, with no query of its own)
    from core.shading import corner_normals

    v, f = grid(6, jitter=0.2)
    lod_v = v + np.c_[np.zeros((len(v), 2)), 0.05 * np.sin(7 * v[:, 0])]
    normals = (corner_normals(v, f, np.ones(len(f), bool)), corner_normals(lod_v, f[::2], np.ones(len(f) // 2, bool)))
    with_normals = measure.surface_deviation(v, f, lod_v, f[::2], n_samples=(300, 200), normals=normals)
    kept = measure.surface_deviation(v, f, lod_v, f[::2], n_samples=(300, 200), keep_samples=True)
    later = measure.normal_keys_of(kept["sampled"], *normals)
    assert later["normal_max_degrees"] > 1.0
    for key in ("normal_mean_degrees", "normal_p95_degrees", "normal_max_degrees", "normal_points"):
        assert later[key] == with_normals[key], key


def test_a_level_the_search_measured_gets_its_normals_with_no_query(brute_trees, monkeypatch):
    from addon.pure import compute, deviation_search
    from addon.pure.mesh_data import MeshData, shading_normals

    def mesh(v, f):
        m = len(f)
        return MeshData(vertices=v, faces=f, material_index=np.zeros(m, np.int64), smooth=np.ones(m, bool),
                        smooth_group=np.zeros(m, np.int64))

    v, f = grid(6, jitter=0.2)
    data, level = mesh(v, f), mesh(v + np.c_[np.zeros((len(v), 2)), 0.05 * np.sin(7 * v[:, 0])], f[::2])
    data.corner_normals = shading_normals(data)
    expected = deviation_search.deviation_report(data, level, (data.corner_normals, shading_normals(level)))
    searched = deviation_search.deviation_report(data, level)  # (as the search measures: no normals)

    def no_query(*args, **kwargs):
        raise AssertionError("measured again")

    monkeypatch.setattr(measure, "normal_deviation", no_query)
    monkeypatch.setattr(measure, "_distances", no_query)
    report = compute.level_report(data, level, searched)
    assert report["normal_max_degrees"] > 1.0
    for key in compute.NORMAL_KEYS + ("hausdorff", "mean"):
        assert report[key] == expected[key], key


def _split_at(v, f, x):
    """(vertices, faces) of the mesh cut along the line of vertices at ``x``: the faces
    beyond it get copies of those vertices, as an importer splits a mesh at a UV seam."""
    beyond = v[f].mean(axis=1)[:, 0] > x
    on = np.flatnonzero(np.isclose(v[:, 0], x))
    copy = np.arange(len(v))
    copy[on] = len(v) + np.arange(len(on))
    f = f.copy()
    f[beyond] = copy[f[beyond]]
    return np.concatenate([v, v[on]]), f


def test_vertices_at_one_position_are_queried_once(brute_trees, monkeypatch):
    # Each vertex query is a Python call; an imported mesh has several vertices at each
    # position of its seams, and their distance is one and the same.
    searched = []

    class CountingTree(_BruteTree):
        def find_nearest(self, co, distance=float("inf")):
            if distance != float("inf"):  # the query loop's (the pilot's are unbounded)
                searched.append(tuple(co))
            return super().find_nearest(co, distance)

    monkeypatch.setattr(measure, "_tree_builder", CountingTree)
    monkeypatch.setattr(measure, "CLIMB_SEEDS", 0)  # (its points are queried on top: _climb)
    v, f = grid(6, alternate=False)
    split_v, split_f = _split_at(v, f, 0.5)
    lod = lambda p: p + np.c_[np.zeros((len(p), 2)), 0.01 * (1.0 + p[:, 0])]  # nothing shared
    welded = measure.surface_deviation(v, f, lod(v), f, n_samples=0, keep_samples=True)
    searched.clear()
    split = measure.surface_deviation(split_v, split_f, lod(split_v), split_f, n_samples=0, keep_samples=True)
    assert len(split_v) == len(v) + 7
    assert len(searched) == 2 * len(v)  # each direction: every position once, not its 7 copies again
    assert split["hausdorff"] == welded["hausdorff"] and split["mean"] == pytest.approx(welded["mean"])
    assert split["points_src"] == len(split_v)  # every vertex still has its distance
    sampled = split["sampled"]
    d = dict(zip(sampled.src_vertices.tolist(), sampled.src_vertex_distance))
    assert all(d[len(v) + i] == d[j] for i, j in enumerate(np.flatnonzero(np.isclose(v[:, 0], 0.5))))


def test_the_climb_finds_a_largest_distance_no_vertex_has(brute_trees, monkeypatch):
    # A flat square over a square pit: the square's points are farthest from the pit's
    # slopes at its centre, where it has no vertex; its corners are the pit's rim. Fifty
    # area samples land around the centre, 17 % short of it; the climb from the farthest
    # of them gets within 3 % of the exact largest distance.
    depth = 0.5
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float), np.array([[0, 1, 2], [0, 2, 3]])
    pit = (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, -depth]], float),
           np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]))
    exact = 0.5 * depth / np.hypot(0.5, depth)
    climbed = measure.surface_deviation(*square, *pit, n_samples=50)["hausdorff_src_to_dst"]
    monkeypatch.setattr(measure, "CLIMB_SEEDS", 0)
    uniform = measure.surface_deviation(*square, *pit, n_samples=50)["hausdorff_src_to_dst"]
    assert uniform < climbed <= exact + 1e-9
    assert climbed > 0.97 * exact and uniform < 0.9 * exact, (uniform, climbed, exact)


def test_climb_seeds_set_how_many_points_the_climb_starts_from(brute_trees):
    """The deviation search's measurement climbs from more seeds than the report's
    (deviation_search.SEARCH_CLIMB_SEEDS): ``climb_seeds`` of the area samples a
    direction, each CLIMB_ROUNDS rounds of CLIMB_TRIES points; the report's one seed
    per CLIMB_POINTS_PER_SEED points gives the pit below one."""
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float), np.array([[0, 1, 2], [0, 2, 3]])
    pit = (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, -0.5]], float),
           np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]))
    exact = 0.5 * 0.5 / np.hypot(0.5, 0.5)
    per_seed = measure.CLIMB_TRIES * measure.CLIMB_ROUNDS
    for seeds, expected in ((None, 1), (10, 10)):
        m = measure.surface_deviation(*square, *pit, n_samples=50, keep_samples=True, climb_seeds=seeds)
        assert len(m["sampled"].src_climbed_distance) == expected * per_seed  # (the square's corners are at 0)
        assert m["hausdorff_src_to_dst"] <= exact + 1e-9


def test_samples_carry_their_triangle_and_barycentric_coordinates():
    v, f = grid(4, jitter=0.2)
    points, tri, bary = measure._sample_surface(v, f, 1000, np.random.default_rng(5))
    assert np.allclose(np.einsum("kc,kcj->kj", bary, v[f[tri]]), points)
    np.testing.assert_array_equal(points, measure.sample_surface(v, f, 1000, np.random.default_rng(5)))


def test_region_deviation_pools_each_direction_over_its_region():
    # Two source triangles, region = the first. src: 3 samples on 0, 1 on 1; dst: 2 samples
    # closest to source triangle 0, 2 to 1; the vertices likewise.
    f = np.array([[0, 1, 2], [1, 3, 2]])
    z2 = np.zeros((2, 3))
    sampled = measure.Sampled(
        src_triangle=np.array([0, 0, 0, 1]), src_bary=np.zeros((4, 3)), src_distance=np.array([1.0, 2.0, 3.0, 50.0]),
        src_nearest=np.zeros(4, np.int64), src_nearest_bary=np.zeros((4, 3)),
        src_vertices=np.array([0, 1, 2, 3]), src_vertex_distance=np.array([4.0, 0.5, 0.5, 60.0]),
        dst_triangle=np.zeros(4, np.int64), dst_bary=np.zeros((4, 3)), dst_distance=np.array([10.0, 20.0, 7.0, 70.0]),
        dst_vertices=np.array([0, 1]), dst_vertex_distance=np.array([5.0, 80.0]),
        dst_nearest=np.array([0, 0, 1, 1]), dst_nearest_bary=np.zeros((4, 3)),
        dst_vertex_nearest=np.array([0, 1]), dst_vertex_nearest_bary=z2)
    r = measure.region_deviation(sampled, f, np.array([True, False]))
    assert r["region_mean_src_to_dst"] == pytest.approx(2.0)  # samples 1, 2, 3
    assert r["region_mean_dst_to_src"] == pytest.approx(15.0)  # samples 10, 20
    assert r["region_mean"] == pytest.approx(8.5)  # the two directions' means, as the two-sided mean
    # The largest: src's region vertices 0-2 (4.0; vertex 3 is only on triangle 1) and dst's
    # points closest to triangle 0 (20.0; vertex 1 at 80 is closest to triangle 1).
    assert r["region_hausdorff"] == pytest.approx(20.0)
    assert (r["region_samples_src"], r["region_samples_dst"]) == (3, 2)
    none = measure.region_deviation(sampled, f, np.zeros(2, bool))
    assert np.isnan(none["region_mean"]) and np.isnan(none["region_hausdorff"]) and none["region_samples_src"] == 0
    with pytest.raises(ValueError, match=r"region must be a \(2,\) bool array"):
        measure.region_deviation(sampled, f, np.ones(3, bool))


# ---------------------------------------------------------------- Blender side


FLAP_HEIGHT = 0.5


def flapped(v, f) -> dict:
    """The plane with an extra triangle floating FLAP_HEIGHT above its left half (a LOD
    piece that the source's samples never find: only the LOD's own samples see it)."""
    flap = np.array([[0.1, 0.2, FLAP_HEIGHT], [0.4, 0.2, FLAP_HEIGHT], [0.25, 0.6, FLAP_HEIGHT]])
    return {"flap_v": np.concatenate([v, flap]), "flap_f": np.concatenate([f, [[len(v), len(v) + 1, len(v) + 2]]])}


def strayed(v, f) -> dict:
    """The plane with a zero-area face far above it (its corners on one line: a .blend
    keeps such faces, the core drops them), and with a thin but real triangle there."""
    stray = np.array([[0.5, 0.5, 5.0], [1.5, 0.5, 5.0], [1.0, 0.5, 5.0]])
    thin = stray + [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 1e-2, 0.0]]
    faces = np.concatenate([f, [[len(v), len(v) + 1, len(v) + 2]]])
    return {"stray_v": np.concatenate([v, stray]), "stray_f": faces,
            "thin_v": np.concatenate([v, thin]), "thin_f": faces}


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("measure")
    plane_v, plane_f = grid(10, alternate=False)
    fine_v, fine_f = icosphere(4)
    coarse_v, coarse_f = icosphere(2)
    path = tmp / "meshes.npz"
    coarse_plane_v, coarse_plane_f = grid(3, jitter=0.2)
    np.savez(path, plane_v=plane_v, plane_f=plane_f, coarse_plane_v=coarse_plane_v, coarse_plane_f=coarse_plane_f,
             shifted_v=plane_v + [0.0, 0.0, 0.1], shifted_f=plane_f,
             fine_v=fine_v, fine_f=fine_f, coarse_v=coarse_v, coarse_f=coarse_f,
             empty_v=plane_v, empty_f=np.empty((0, 3), np.int64),
             step_v=plane_v + np.outer(plane_v[:, 0] >= 0.7, [0.0, 0.0, 0.1]), step_f=plane_f,
             **flapped(plane_v, plane_f), **strayed(plane_v, plane_f))
    result = run_scenario("measure_deviation", {"meshes_npz": str(path)}, user_dir=tmp / "blender",
                          install=False, timeout=300)
    result["sagitta_fine"] = max_sagitta(fine_v, fine_f)
    result["sagitta_coarse"] = max_sagitta(coarse_v, coarse_f)
    return result


def test_identical_meshes_are_zero_apart(measured):
    r = measured["identical"]
    # Single-precision BVH: zero up to float32 rounding of unit-sized coordinates.
    assert r["hausdorff"] < 1e-6
    assert r["mean"] < 1e-7
    assert r["diagonal"] == pytest.approx(2 ** 0.5)


def test_a_zero_area_face_is_no_surface_to_measure(measured):
    # A LOD that dropped a zero-area face far from the rest (as the core does) is the
    # surface the source has: before, its corners measured 5 units (64 % of a real
    # object's size); a thin triangle with an area is measured as any other.
    stray, thin = measured["stray"], measured["thin"]
    assert stray["hausdorff"] < 1e-6, stray
    assert thin["hausdorff"] == pytest.approx(math.hypot(0.5, 5.0), rel=1e-4), thin  # its corner (1.5, 0.5, 5)


def test_plane_shifted_along_its_normal(measured):
    r = measured["shifted"]
    for key in ("hausdorff", "mean", "hausdorff_src_to_dst", "hausdorff_dst_to_src",
                "mean_src_to_dst", "mean_dst_to_src"):
        assert r[key] == pytest.approx(0.1, abs=1e-6), key
    assert r["hausdorff_percent"] == pytest.approx(100 * 0.1 / 2 ** 0.5, rel=1e-5)
    assert r["mean_percent"] == pytest.approx(100 * 0.1 / 2 ** 0.5, rel=1e-5)
    # 20,000 samples + the 121 used vertices per direction.
    assert r["points_src"] == r["points_dst"] == 20_000 + 121


def test_samples_per_unit_area_scales_with_area(measured):
    # Unit square: 1000 samples per unit area -> 1000 samples (+121 vertices).
    assert measured["density"]["points_src"] == 1000 + 121
    assert measured["density"]["hausdorff"] == pytest.approx(0.1, abs=1e-6)


def test_sphere_against_coarser_sphere_within_sagitta(measured):
    r = measured["sphere"]
    s_c, s_f = measured["sagitta_coarse"], measured["sagitta_fine"]
    # Both are inscribed in the unit sphere: every point lies between R - s and R, so
    # radial projection bounds the distance by max(s_c, s_f) = s_c; the deepest point
    # of the coarse mesh is s_c - s_f or more away from the fine one.
    assert r["hausdorff"] <= s_c + 1e-6
    assert r["hausdorff"] >= 0.95 * (s_c - s_f)
    assert 0 < r["mean"] < r["hausdorff"]
    for direction in ("src_to_dst", "dst_to_src"):
        assert r["hausdorff_" + direction] <= s_c + 1e-6
        assert 0 < r["mean_" + direction] < r["hausdorff_" + direction]


def test_two_sided_measure_is_symmetric(measured):
    a, b = measured["sphere"], measured["sphere_swapped"]
    assert a["hausdorff"] == b["hausdorff"]
    assert a["mean"] == b["mean"]
    assert a["hausdorff_src_to_dst"] == b["hausdorff_dst_to_src"]
    assert a["mean_dst_to_src"] == b["mean_src_to_dst"]


def test_mesh_report_adds_output_quality(measured):
    r = measured["report"]
    for key, value in measured["core_quality"].items():
        assert r[key] == pytest.approx(value)
    assert r["src_faces"] == 20 * 4 ** 4 and r["dst_faces"] == 20 * 4 ** 2
    assert r["hausdorff"] <= measured["sagitta_coarse"] + 1e-6


def test_a_flat_plane_shades_like_a_coarser_flat_plane(measured):
    r = measured["normals_plane"]
    assert r["normal_max_degrees"] < 1e-6 and r["normal_points"] == 20_000


def test_normals_tilted_by_a_known_angle_measure_that_angle(measured):
    r = measured["normals_tilted"]
    for key in ("normal_mean_degrees", "normal_p95_degrees", "normal_max_degrees"):
        assert r[key] == pytest.approx(30.0, abs=1e-6), key


def test_a_smooth_coarse_sphere_shades_closer_than_a_flat_one(measured):
    smooth, flat = measured["normals_sphere"], measured["normals_sphere_flat"]
    # icosphere(2) has edges of ~0.3 rad: flat faces are up to ~10 degrees off the fine
    # sphere's normals, interpolated ones a few tenths of that.
    assert 0 < smooth["normal_mean_degrees"] < 1.5 and smooth["normal_max_degrees"] < 5.0, smooth
    assert 4.0 < flat["normal_mean_degrees"] < 10.0, flat
    assert flat["normal_mean_degrees"] > 3 * smooth["normal_mean_degrees"]


def test_surface_deviation_gives_the_normals_from_its_own_closest_points(measured):
    with_normals, without = measured["sphere_with_normals"], measured["sphere_without_normals"]
    alone = measured["normals_sphere"]
    for key in ("normal_mean_degrees", "normal_p95_degrees", "normal_max_degrees", "normal_points"):
        assert with_normals[key] == alone[key], key  # the same samples, the same closest points
    for key in ("hausdorff", "mean", "hausdorff_src_to_dst", "mean_dst_to_src"):
        assert with_normals[key] == without[key], key  # the distances do not change


def test_region_of_a_shifted_plane_is_as_far_as_the_plane(measured):
    r = measured["region_shifted"]
    for key in ("region_hausdorff", "region_mean", "region_mean_src_to_dst", "region_mean_dst_to_src"):
        assert r[key] == pytest.approx(0.1, abs=1e-6), key
    assert r["region_mean"] == pytest.approx(r["mean"], rel=1e-5)
    # The left half: half of each surface's area samples, both ways.
    for side in ("src", "dst"):
        assert abs(r["region_samples_" + side] / 20_000 - 0.5) < 0.02, r["region_samples_" + side]


def test_region_sees_only_its_own_part_of_a_step(measured):
    # The plane against itself raised by 0.1 right of x = 0.7 (a ramp from 0.6 to 0.7).
    left, right, whole = (measured["region_step_" + k] for k in ("left", "right", "without"))
    assert whole["mean"] > 0.02
    assert left["region_hausdorff"] < 1e-6 and left["region_mean"] < 1e-7  # untouched there
    assert 0.08 < right["region_mean"] <= 0.1 + 1e-6 and right["region_mean"] > 2 * whole["mean"]
    assert right["region_hausdorff"] == pytest.approx(0.1, abs=1e-6)
    for r in (left, right):
        for key in ("hausdorff", "mean", "hausdorff_src_to_dst", "mean_dst_to_src", "points_src", "points_dst"):
            assert r[key] == whole[key], key  # the whole surface's numbers do not change


def test_region_counts_lod_points_whose_closest_source_point_is_in_it(measured):
    # An extra triangle FLAP_HEIGHT above the left half: no source sample finds it, only
    # its own samples do, and their closest source points are in the left half.
    left, right = measured["region_flap_left"], measured["region_flap_right"]
    assert left["region_mean_src_to_dst"] < 1e-7
    assert left["region_hausdorff"] == pytest.approx(FLAP_HEIGHT, abs=1e-6)
    assert left["region_mean_dst_to_src"] > 0.0 and left["region_mean"] > 0.0
    assert right["region_hausdorff"] < 1e-6 and right["region_mean"] < 1e-7


def test_an_empty_region_has_no_distances(measured):
    for name in ("region_step_none", "region_flap_none"):
        r = measured[name]
        assert r["region_samples_src"] == r["region_samples_dst"] == 0
        assert all(math.isnan(r[key]) for key in ("region_hausdorff", "region_mean", "region_mean_src_to_dst",
                                                  "region_mean_dst_to_src")), r
        assert r["mean"] > 0.0  # the whole surface is still measured


def test_invalid_input_raises_value_error_naming_the_problem(measured):
    e = measured["errors"]
    assert "(m, 3, 3)" in e["normals_shape"]
    assert "NaN" in e["normals_nan"]
    assert "no faces" in e["empty"]
    assert "outside" in e["index"]
    assert "not both" in e["both_counts"]
    assert "NaN" in e["nan"]
    assert "region must be a (200,) bool array" in e["region_shape"]


def test_measure_uses_the_extensions_own_core_when_installed(blender_user_dir):
    # Installed, addon/ is a subpackage of the extension: mesh_report must reach the
    # sibling core relatively, not a top-level ``core`` (which the harness also makes
    # importable from the checkout, so a wrong branch would go unnoticed otherwise).
    r = run_scenario("measure_installed_core", user_dir=blender_user_dir)
    assert r["hausdorff"] == pytest.approx(0.25, abs=1e-6)
    assert r["mean_quality"] == pytest.approx(2 * 3 ** 0.5 * 1.0 / 4.0)  # right isosceles: q = 0.866
    assert r["normal_max_degrees"] == 0.0  # through the installed core's shading module
    assert r["ext_core"], "the installed measure did not import the extension's own core"
    assert not r["top_core"], "the installed measure imported the checkout's top-level core"


def _brute_force(points, v, f):
    """(k,) distance of each point to the triangles (v, f), and (k, 3) each point's
    closest point, over every triangle."""
    import core

    best, where = np.full(len(points), np.inf), np.zeros((len(points), 3))
    for a, b, c in v[f]:
        k = len(points)
        bary, _ = core.geometry.closest_on_triangles(points, np.tile(a, (k, 1)), np.tile(b, (k, 1)), np.tile(c, (k, 1)))
        q = bary @ np.stack([a, b, c])
        d = np.linalg.norm(points - q, axis=1)
        closer = d < best
        best[closer], where[closer] = d[closer], q[closer]
    return best, where


def test_shared_triangles_are_zero_apart_on_themselves_and_the_rest_is_searched(measured):
    # Plane against the plane with x >= 0.7 stepped up 0.1: the triangles left of it are
    # the same in both, so their points are at 0 on their own triangle, no search; every
    # point's distance and closest point must be what a search of every triangle gives.
    plane_v, plane_f = grid(10, alternate=False)
    step_v = plane_v + np.outer(plane_v[:, 0] >= 0.7, [0.0, 0.0, 0.1])
    pts = {k: np.asarray(v) for k, v in measured["step_points"].items()}
    for side, (v_a, f_a, v_b, f_b) in (("src", (plane_v, plane_f, step_v, plane_f)),
                                         ("dst", (step_v, plane_f, plane_v, plane_f))):
        tri, bary = pts[f"{side}_triangle"].astype(int), pts[f"{side}_bary"]
        on_a = np.einsum("kc,kcj->kj", bary, v_a[f_a[tri]])
        exact, _ = _brute_force(on_a, v_b, f_b)
        np.testing.assert_allclose(pts[f"{side}_distance"], exact, atol=1e-6)
        nearest, at = pts[f"{side}_nearest"].astype(int), pts[f"{side}_nearest_bary"]
        found = np.einsum("kc,kcj->kj", at, v_b[f_b[nearest]])
        np.testing.assert_allclose(np.linalg.norm(found - on_a, axis=1), exact, atol=1e-6)
        unmoved = np.all(v_a[f_a[tri]] == v_b[f_b[tri]], axis=(1, 2))
        assert unmoved.mean() > 0.5  # the left part: shared, exactly 0 on the same triangle
        assert np.all(pts[f"{side}_distance"][unmoved] == 0.0)
        np.testing.assert_allclose(found[unmoved], on_a[unmoved], atol=1e-12)
        verts = pts[f"{side}_vertices"].astype(int)
        exact_v, _ = _brute_force(v_a[verts], v_b, f_b)
        np.testing.assert_allclose(pts[f"{side}_vertex_distance"], exact_v, atol=1e-6)
        vn, vat = pts[f"{side}_vertex_nearest"].astype(int), pts[f"{side}_vertex_nearest_bary"]
        found_v = np.einsum("kc,kcj->kj", vat, v_b[f_b[vn]])
        np.testing.assert_allclose(np.linalg.norm(found_v - v_a[verts], axis=1), exact_v, atol=1e-6)
