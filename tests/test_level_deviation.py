"""addon/pure/level_deviation.py without Blender: the statistics per material and painted
region, the heat map's distance per vertex and its colours, the frames a rig is posed at."""
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from addon.pure import level_deviation as ld
from addon.headless import report
from addon.pure.measure import Sampled
from addon.pure.mesh_data import MeshData

distances = hnp.arrays(np.float64, st.integers(0, 60), elements=st.floats(0.0, 10.0, allow_subnormal=False))


@settings(max_examples=200, deadline=None)
@given(hnp.arrays(np.float64, st.integers(1, 80), elements=st.floats(0.0, 100.0, allow_subnormal=False)),
       st.floats(0.0, 1.0))
def test_equal_weights_give_numpys_inverted_cdf_quantile(values, q):
    got = ld.weighted_quantile(values, np.ones(len(values)), q)
    assert got == np.percentile(values, 100.0 * q, method="inverted_cdf")


def test_weighted_quantile_follows_the_weights():
    # 0 weighs 0.9 of the total: every quantile up to 0.9 is 0, beyond it 5.
    assert ld.weighted_quantile([5.0, 0.0], [0.1, 0.9], 0.9) == 0.0
    assert ld.weighted_quantile([5.0, 0.0], [0.1, 0.9], 0.91) == 5.0
    assert np.isnan(ld.weighted_quantile([], [], 0.5))


@settings(max_examples=200, deadline=None)
@given(distances, distances)
def test_two_sided_pools_the_directions_like_the_report(src, dst):
    """The mean is the mean of the directional means (the report's two-sided mean), each
    direction weighing half whatever its sample count; the max is the largest sample;
    the 95th percentile lies between the smallest and the largest."""
    s = ld.two_sided(src, dst, scale=100.0)
    if len(src) + len(dst) == 0:
        assert s == {"mean": None, "p95": None, "max": None, "samples": 0}
        return
    means = [d.mean() for d in (src, dst) if len(d)]
    every = np.concatenate([src, dst])
    assert s["samples"] == len(every)
    assert s["mean"] == pytest.approx(100.0 * np.mean(means), rel=1e-12, abs=1e-12)
    assert s["max"] == pytest.approx(100.0 * every.max())
    assert 100.0 * every.min() - 1e-9 <= s["p95"] <= s["max"] + 1e-9


def test_two_sided_weighs_each_direction_half():
    # 1 sample at 10 on the source against 99 at 0 on the LOD: the source's half puts the
    # 95th percentile at 10 (unweighted it would be 0).
    s = ld.two_sided([10.0], np.zeros(99))
    assert (s["mean"], s["p95"], s["max"], s["samples"]) == (5.0, 10.0, 10.0, 100)


@settings(max_examples=100, deadline=None)
@given(distances, distances, st.data())
def test_groups_of_a_partition_cover_the_whole(src, dst, data):
    """Materials partition the samples: the largest group max is the overall max, the
    sample counts add up, and one group holding everything is the two-sided whole."""
    groups = 3
    src_label = np.array(data.draw(st.lists(st.integers(0, groups - 1), min_size=len(src), max_size=len(src))), int)
    dst_label = np.array(data.draw(st.lists(st.integers(0, groups - 1), min_size=len(dst), max_size=len(dst))), int)
    names = ["a", "b", "c"]
    got = ld.grouped(src, src_label[:, None] == np.arange(groups), dst, dst_label[:, None] == np.arange(groups), names)
    assert sum(g["samples"] for g in got.values()) == len(src) + len(dst)
    maxima = [g["max"] for g in got.values() if g["max"] is not None]
    if maxima:
        assert max(maxima) == np.concatenate([src, dst]).max()
    whole = ld.grouped(src, np.ones((len(src), 1), bool), dst, np.ones((len(dst), 1), bool), ["all"])["all"]
    assert whole == ld.two_sided(src, dst)


def test_material_groups_merge_slots_and_name_the_empty_ones():
    names, group = ld.material_groups(np.array([0, 1, 2, 3, 7, -1]), ["Red", None, "Red", "Blue"])
    assert names == ["Red", ld.NO_MATERIAL, "Blue"]
    assert group.tolist() == [0, 1, 0, 2, 1, 1]
    assert ld.membership(group[:3], 3).tolist() == [[True, False, False], [False, True, False], [True, False, False]]


def test_regions_are_the_painted_groups_not_the_skin_or_the_preview():
    names = ["Spine", "Face", "LOD_Importance_Preview", "Arm", "Hat"]
    assert ld.region_columns(names, skin_columns=[0, 3]) == [("Face", 1), ("Hat", 4)]
    # The importance group counts even when it is a deform group.
    assert ld.region_columns(names, [0, 3], importance_group="Spine") == [("Face", 1), ("Hat", 4), ("Spine", 0)]
    assert ld.region_columns(names, [0, 3], importance_group="Face") == [("Face", 1), ("Hat", 4)]


def _quad_pair():
    """Two triangles making the unit square (0-1-2, 0-2-3), material 0 and 1; the LOD is
    the same square with the other diagonal."""
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    return v, np.array([[0, 1, 2], [0, 2, 3]]), np.array([[0, 1, 3], [1, 2, 3]])


def test_level_breakdown_sorts_samples_by_material_and_interpolated_weight():
    v, f_src, f_lod = _quad_pair()
    # The group "Paint": vertex 2 at 1, the rest 0; vertex 1 (a skin group column) ignored.
    weights = np.array([[0.0, 1.0], [0.0, 1.0], [1.0, 0.0], [0.0, 0.0]])
    source = SimpleNamespace(vertices=v, faces=f_src, material_index=np.array([0, 1]), group_weights=weights)
    level = SimpleNamespace(vertices=v, faces=f_lod, material_index=np.array([1, 1]), group_weights=weights)
    sampled = Sampled(
        # Source samples: on triangle 0 at vertex 2 (weight 1), at its centre (1/3), on triangle 1 at
        # the midpoint of 0-2 (0.5: counts), just short of it (0.49: does not).
        src_triangle=np.array([0, 0, 1, 1]),
        src_bary=np.array([[0, 0, 1], [1 / 3, 1 / 3, 1 / 3], [0.5, 0.5, 0], [0.51, 0.49, 0]]),
        src_distance=np.array([4.0, 1.0, 2.0, 8.0]),
        src_nearest=np.zeros(4, int), src_nearest_bary=np.full((4, 3), 1 / 3),
        src_vertices=np.arange(4), src_vertex_distance=np.zeros(4),
        # LOD samples: both on material 1.
        dst_triangle=np.array([0, 1]), dst_bary=np.array([[1.0, 0, 0], [0, 1.0, 0]]),
        dst_distance=np.array([3.0, 6.0]), dst_vertices=np.arange(4), dst_vertex_distance=np.zeros(4))
    out = ld.level_breakdown(source, level, sampled, ["Red", "Blue"], [("Paint", 0)], diagonal=200.0)
    assert set(out) == {"materials", "regions"}
    red, blue = out["materials"]["Red"], out["materials"]["Blue"]
    # Red: source samples 4, 1 only (the LOD has no Red); in % of 200: half.
    assert (red["mean_percent"], red["max_percent"], red["samples"]) == (1.25, 2.0, 2)
    # Blue: source 2, 8 (mean 5) and LOD 3, 6 (mean 4.5): two-sided mean 4.75.
    assert (blue["mean_percent"], blue["max_percent"], blue["samples"]) == (4.75 / 2, 4.0, 4)
    # Paint: the source samples at vertex 2 (4.0) and the midpoint (2.0), and the LOD's at
    # vertex 2 (its triangle 1, corner 1: 6.0); the LOD sample at vertex 0 is not painted.
    paint = out["regions"]["Paint"]
    assert (paint["mean_percent"], paint["max_percent"], paint["samples"]) == ((3.0 + 6.0) / 2 / 2, 3.0, 3)
    assert ld.level_breakdown(source, level, sampled, [], [], 200.0) == {}, "nothing to break down"


def test_the_vertices_count_in_each_groups_max_as_in_the_hausdorff_distance():
    v, f_src, f_lod = _quad_pair()
    weights = np.array([[0.0], [0.0], [1.0], [0.0]])
    source = SimpleNamespace(vertices=v, faces=f_src, material_index=np.array([0, 1]), group_weights=weights)
    level = SimpleNamespace(vertices=v, faces=f_lod, material_index=np.array([0, 0]), group_weights=weights)
    sampled = Sampled(np.array([0, 1]), np.full((2, 3), 1 / 3), np.array([1.0, 2.0]), np.zeros(2, int),
                      np.full((2, 3), 1 / 3), np.arange(4), np.array([0.0, 0.0, 0.0, 7.0]),
                      np.array([0]), np.array([[0.0, 0.0, 1.0]]), np.array([3.0]), np.arange(4),
                      np.array([0.0, 0.0, 9.0, 0.0]))
    out = ld.level_breakdown(source, level, sampled, ["Red", "Blue"], [("Paint", 0)], diagonal=100.0)
    # Source vertex 3 (7.0) is on the Blue triangle 0-2-3 only; LOD vertex 2 (9.0) on LOD
    # triangle 1-2-3, which is Red (the LOD is all Red): Red's max is 9, Blue's 7.
    assert out["materials"]["Red"]["max_percent"] == 9.0
    assert out["materials"]["Blue"]["max_percent"] == 7.0
    # The means are the area samples' alone: Red 1 (source) and 3 (LOD), Blue 2.
    assert (out["materials"]["Red"]["mean_percent"], out["materials"]["Blue"]["mean_percent"]) == (2.0, 2.0)
    # Painted: vertex 2 of either surface (9.0 on the LOD); samples: none of the source's
    # centroids (1/3), the LOD sample on its vertex 3 (3.0, weight 0) neither.
    assert out["regions"]["Paint"]["samples"] == 0 and out["regions"]["Paint"]["max_percent"] is None
    assert max(m["max_percent"] for m in out["materials"].values()) == 9.0, "the Hausdorff distance"


def test_a_region_nothing_samples_is_listed_empty():
    v, f_src, f_lod = _quad_pair()
    source = SimpleNamespace(vertices=v, faces=f_src, material_index=np.zeros(2, int), group_weights=np.zeros((4, 1)))
    sampled = Sampled(np.array([0]), np.array([[1.0, 0, 0]]), np.array([1.0]), np.zeros(1, int), np.ones((1, 3)) / 3,
                      np.arange(4), np.zeros(4), np.array([0]), np.array([[1.0, 0, 0]]), np.array([1.0]),
                      np.arange(4), np.zeros(4))
    out = ld.level_breakdown(source, source, sampled, None, [("Empty", 0)], 1.0)
    assert out == {"regions": {"Empty": {"mean_percent": None, "p95_percent": None, "max_percent": None,
                                         "samples": 0}}}


def test_vertex_distances_raise_each_vertex_to_the_source_samples_it_stands_for():
    faces = np.array([[0, 1, 2], [1, 3, 2]])
    sampled = SimpleNamespace(
        dst_vertices=np.array([0, 1, 2, 3]), dst_vertex_distance=np.array([0.1, 0.2, 0.3, 0.4]),
        # Source samples landing on LOD triangle 0 nearest corner 1 (5.0), on triangle 1
        # nearest its corner 2 = vertex 2 (0.05: below vertex 2's own 0.3), and nearest
        # vertex 3 (2.0, 3.0: the larger wins).
        src_nearest=np.array([0, 1, 1, 1]),
        src_nearest_bary=np.array([[0.1, 0.8, 0.1], [0.2, 0.2, 0.6], [0.1, 0.7, 0.2], [0.0, 0.9, 0.1]]),
        src_distance=np.array([5.0, 0.05, 2.0, 3.0]))
    got = ld.vertex_distances(5, faces, sampled)
    assert got.tolist() == [0.1, 5.0, 0.3, 3.0, 0.0]  # vertex 4: in no face


@settings(max_examples=100, deadline=None)
@given(hnp.arrays(np.float64, st.integers(1, 50), elements=st.floats(0.0, 10.0, allow_subnormal=False)),
       st.floats(0.01, 10.0))
def test_heat_colors_run_from_blue_to_red(d, scale):
    c = ld.heat_colors(d, scale)
    assert c.shape == (len(d), 4) and np.all(c[:, 3] == 1.0) and np.all((c >= 0) & (c <= 1))
    order = np.argsort(d, kind="stable")
    # Along the ramp red never decreases before green does, and blue never increases:
    # the hue runs one way (blue, cyan, green, yellow, red).
    hue = c[order, 0] - c[order, 2]
    assert np.all(np.diff(hue) >= -1e-12)


def test_heat_colors_ends_and_middle():
    c = ld.heat_colors(np.array([0.0, 1.0, 2.0, 4.0]), 2.0)
    assert c[:, :3].tolist() == [[0, 0, 1], [0, 1, 0], [1, 0, 0], [1, 0, 0]]
    assert ld.heat_colors(np.array([0.0, 3.0]), 0.0)[:, :3].tolist() == [[0, 0, 1], [0, 0, 1]]
    # A quarter: cyan, in display colours (0, 1, 1); between stops linear values of sRGB ones.
    mid = ld.heat_colors(np.array([0.125]), 1.0)[0, :3]  # halfway blue to cyan: sRGB (0, 0.5, 1)
    assert mid.tolist() == pytest.approx([0.0, float(ld.srgb_to_linear(0.5)), 1.0])


def test_frames_are_spread_over_the_action_and_bounded():
    assert ld.sample_frames(1, 20, 8) == [1, 4, 6, 9, 12, 15, 17, 20]
    assert ld.sample_frames(1, 4, 8) == [1, 2, 3, 4]
    assert ld.sample_frames(10, 10, 8) == [10]
    assert ld.sample_frames(1, 21, 1) == [11]
    assert ld.frames_per_action(1, 8, 16) == 8
    assert ld.frames_per_action(3, 8, 16) == 5
    assert ld.frames_per_action(40, 8, 16) == 1


def test_heavy_rigs_are_posed_at_fewer_frames_and_sampled_from_their_reports():
    from addon import posed_deviation as pd

    # A light rig gets every frame; frames x triangles stays under the budget; never below the floor.
    assert pd.frame_budget(3_000) == pd.MAX_FRAMES
    for triangles in (40_000, 141_000, 10_000_000):
        frames = pd.frame_budget(triangles)
        assert pd.MIN_FRAMES <= frames < pd.MAX_FRAMES
        assert frames * triangles <= pd.POSED_TRIANGLE_FRAMES or frames == pd.MIN_FRAMES
    assert pd.frame_budget(141_000) == pd.MIN_FRAMES  # a 75,000-triangle character and its LODs
    # Over its frames a level queries about its report's area samples: half on the area a frame.
    from addon.pure.deviation_search import report_samples
    assert pd.posed_samples(20_000, frames=16) == report_samples(20_000) // 32
    assert pd.posed_samples(20_000, frames=4) == report_samples(20_000) // 8
    assert pd.posed_samples(100, frames=16) == pd.POSED_SAMPLES_MIN
    # Several surfaces measured as one: their reports' samples together, the floor once.
    parts = [(1_000, 1_200), (1_000, 1_200), (50, None)]
    assert pd.posed_samples_of(parts, 4) == max(pd.POSED_SAMPLES_MIN,
                                                sum(report_samples(t, s) for t, s in parts) // 8)


def _bumpy_part(seed: int):
    """(vertices, faces) of a closed, bumpy part: an octahedron's faces over jittered points."""
    rng = np.random.default_rng(seed)
    v = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
    v = v * rng.uniform(0.5, 1.5, size=(6, 1)) + [3.0, -2.0, 7.0]
    f = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return v, f


def _rotation(rng, reflect: bool) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if (np.linalg.det(q) < 0) != reflect:
        q[:, 0] = -q[:, 0]
    return q


@settings(max_examples=100, deadline=None)
@given(st.integers(0, 2**31 - 1), st.booleans(), st.floats(-10.0, 10.0))
def test_a_rigid_motion_of_source_and_lod_keeps_their_rest_distances(seed, reflect, shift):
    rng = np.random.default_rng(seed)
    source, lod = _bumpy_part(seed), _bumpy_part(seed + 1)
    lod = (lod[0], lod[1][:6])  # (a LOD of other vertices and fewer faces)
    rot, move = _rotation(rng, reflect), rng.normal(size=3) * shift
    posed = [(v @ rot.T + move, f) for v, f in (source, lod)]
    diagonal = float(np.linalg.norm(np.ptp(source[0], axis=0)))
    # Moved far enough from its origin that float32's steps there exceed RIGID_MOST of its
    # size, a part is measured rather than taken for rigid (the test below): no claim then.
    farthest = max(float(np.abs(v).max()) for v, _ in [source, lod] + posed)
    if ld.RIGID_ROUNDING * float(np.spacing(np.float32(farthest))) <= ld.RIGID_MOST * diagonal:
        assert ld.moved_rigidly([source, lod], posed, diagonal)
    # A scale, a bend (one vertex of the LOD off its place) or other faces is not rigid.
    centre = posed[0][0].mean(axis=0)
    assert not ld.moved_rigidly([source, lod], [((v - centre) * 1.01 + centre, f) for v, f in posed], diagonal)
    bent = posed[1][0].copy()
    bent[int(rng.integers(len(bent)))] += 1e-2 * diagonal
    assert not ld.moved_rigidly([source, lod], [posed[0], (bent, lod[1])], diagonal)
    assert not ld.moved_rigidly([source, lod], [posed[0], (posed[1][0], lod[1][::-1])], diagonal)
    assert not ld.moved_rigidly([source, lod], [posed[0], (posed[1][0][:-1], lod[1])], diagonal)


def test_a_small_part_far_from_its_origin_is_measured():
    # A 1.4 cm part 100 units out: float32 steps there (8e-6) are 6e-4 of its size, so
    # a bend of 1 % of it must not pass as rounding, nor can a rigid move be told apart.
    v, f = _bumpy_part(0)
    v = (v - v.mean(axis=0)) * 0.006 + [100.0, 0.0, 0.0]
    diagonal = float(np.linalg.norm(np.ptp(v, axis=0)))
    bent = v.copy()
    bent[0] += [0.0, 0.0, 0.01 * diagonal]
    assert not ld.moved_rigidly([(v, f)], [(bent, f)], diagonal)
    assert not ld.moved_rigidly([(v, f)], [(v + [0.0, 1.0, 0.0], f)], diagonal)
    near = v - [100.0, 0.0, 0.0]  # the same part at its origin: a rigid move is one
    assert ld.moved_rigidly([(near, f)], [(near + [0.0, 1e-3, 0.0], f)], diagonal)


def test_a_flat_part_is_rigid_only_when_it_moved_so():
    # A square and its LOD in one plane: the fit is free about the plane's normal, and the
    # check at every vertex still tells a turn from a fold.
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0]], dtype=np.float64)
    f = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    lod = (v[:4].copy(), np.array([[0, 1, 2], [0, 2, 3]]))
    c, s = np.cos(0.7), np.sin(0.7)
    turn = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    assert ld.moved_rigidly([(v, f), lod], [(v @ turn.T, f), (lod[0] @ turn.T, lod[1])], 1.4)
    folded = v.copy()
    folded[4, 2] = 0.1
    assert not ld.moved_rigidly([(v, f), lod], [(folded, f), lod], 1.4)


def test_posed_summary_is_the_mean_and_largest_over_frames():
    s = ld.posed_summary([1.0, 3.0], [0.1, 0.2])
    assert s == {"hausdorff_percent": {"mean": 2.0, "max": 3.0}, "mean_percent": {"mean": pytest.approx(0.15),
                                                                                  "max": 0.2}}
    assert ld.posed_summary([], []) == {}


def test_the_module_needs_no_blender():
    import subprocess
    import sys

    from bpy_harness import REPO_ROOT

    code = "import sys; import addon.pure.level_deviation, addon.pure.mesh_data; assert 'bpy' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], cwd=REPO_ROOT, check=True, timeout=60)


def _part(distances_per_level, diagonal_size):
    """A fake LodOutput of one part: per level a triangle carrying the heat map of its
    vertex distances (as with_heat leaves it), and report entries saying so."""
    v = np.array([[0, 0, 0], [diagonal_size, 0, 0], [0, 0, 0.0]])
    f = np.array([[0, 1, 2]])
    levels, reports = [], []
    for d in distances_per_level:
        level = MeshData(vertices=v, faces=f, material_index=np.zeros(1, int), smooth=np.zeros(1, bool),
                         smooth_group=np.zeros(1, int))
        sampled = SimpleNamespace(dst_vertices=np.arange(3), dst_vertex_distance=np.array(d, float),
                                  src_nearest=np.zeros(0, int), src_nearest_bary=np.zeros((0, 3)),
                                  src_distance=np.zeros(0))
        levels.append(ld.with_heat(level, sampled))
        reports.append({"deviation_colors": {"scale": max(d), "scale_percent": 100.0 * max(d) / diagonal_size}})
    return SimpleNamespace(levels=levels, reports=reports, input=SimpleNamespace(data=SimpleNamespace(vertices=v,
                                                                                                       faces=f)))


def test_the_parts_of_an_asset_share_each_levels_scale():
    """The hull (unit 1) is 4 off at LOD1, the bolt (its object scaled 2x) 1 in its units:
    LOD1 is red at 4 scene units on both, so the bolt's 1 (2 scene units) is green."""
    hull, bolt = _part([[0, 2, 4], [0, 8, 8]], 10.0), _part([[0, 0, 1], [0, 0, 5]], 10.0)
    ld.share_scales([(hull, 1.0), (bolt, 2.0)])
    assert hull.levels[0].mesh_properties[ld.SCALE_PROPERTY] == 4.0
    assert bolt.levels[0].mesh_properties[ld.SCALE_PROPERTY] == 2.0, "4 scene units in the bolt's own"
    bolt_colors = next(c for c in bolt.levels[0].colors if c.name == ld.HEAT_ATTRIBUTE).data
    assert bolt_colors[:, :3].tolist() == [[0, 0, 1], [0, 0, 1], [0, 1, 0]]
    # LOD2: the bolt's 5 (10 scene units) is the largest; the hull's 8 is not red.
    assert (hull.levels[1].mesh_properties[ld.SCALE_PROPERTY], bolt.levels[1].mesh_properties[ld.SCALE_PROPERTY]) \
        == (10.0, 5.0)
    assert bolt.reports[1]["deviation_colors"] == {"scale": 5.0, "scale_percent": 50.0, "shared": "asset"}
    assert hull.reports[0]["deviation_colors"]["scale_percent"] == 40.0


def test_the_command_line_prints_the_breakdown_and_the_posed_distance():
    stats = {"mean_percent": 0.01, "p95_percent": 0.05, "max_percent": 0.2, "samples": 1200}
    level = {"level": 1, "name": "Bump_LOD1", "materials": {"Flat": stats, "Bumpy": stats},
             "regions": {"Hill": stats, "Unused": {"mean_percent": None, "p95_percent": None, "max_percent": None,
                                                   "samples": 0}},
             "posed": {"frames": 8, "actions": [{"name": "Bend", "frames": [1, 2]}],
                       "hausdorff_percent": {"mean": 1.0, "max": 2.0}, "mean_percent": {"mean": 0.1, "max": 0.2}}}
    one_material = {"level": 1, "name": "Rock_LOD1", "materials": {"Stone": stats},
                    "posed": {"frames": 0, "actions": [], "note": "no actions"}}
    files = [{"label": "bump.blend", "objects": [{"object": "Bump", "levels": [level]},
                                                 {"object": "Rock", "levels": [one_material]}]}]
    lines = report.format_breakdown(files).splitlines()
    assert lines[0].split() == ["File", "Object", "LOD", "Per", "Name", "Mean", "%", "P95", "%", "Max", "%", "Samples"]
    rows = [line.split() for line in lines[2:]]
    assert [r[3:5] for r in rows] == [["material", "Flat"], ["material", "Bumpy"], ["region", "Hill"],
                                      ["region", "Unused"]], "one material alone is the level's own row"
    assert rows[0][5:] == ["0.0100", "0.0500", "0.200", "1,200"] and rows[3][5:] == ["-", "-", "-", "0"]
    assert report.posed_lines(files) == [
        "posed: bump.blend: Bump_LOD1: 8 frames of Bend: Hausdorff mean 1.000 % max 2.000 %, "
        "mean distance mean 0.1000 % max 0.2000 %",
        "posed: bump.blend: Rock: no actions"]
