"""The settings table (addon/pure/settings.py) and what is derived from it, without Blender."""
from __future__ import annotations

import argparse
import dataclasses

import numpy as np
import pytest

import core
from addon.pure import settings as st
from addon.pure.options import SWITCH_OF, core_options_of
from addon.pure.settings import SETTINGS, CoreOption, LodError, LodSettings


def test_lod_settings_are_the_table_plus_the_explicit_chain():
    fields = [f.name for f in dataclasses.fields(LodSettings)]
    assert fields == [s.name for s in SETTINGS] + ["ratios", "triangle_counts", "max_deviations"]
    assert LodSettings.names() == [s.name for s in SETTINGS]
    assert len(set(LodSettings.names())) == len(SETTINGS)
    defaults = LodSettings()
    assert all(getattr(defaults, s.name) == s.default for s in SETTINGS)


def test_defaults_shared_with_the_core_are_the_cores():
    d = LodSettings()
    assert d.line_weight == core.DEFAULT_LINE_WEIGHT == core.Options().line_weight
    assert d.min_quality == core.SLIVER_QUALITY == core.Options().min_quality
    assert d.feature_angle == core.Options().feature_angle


def test_preserve_pairs_name_a_switch_and_its_strength():
    assert [p for p, _ in st.PRESERVE_PAIRS] == ["preserve_boundaries", "preserve_seams", "preserve_sharp",
                                                 "preserve_materials"]
    for switch, strength in st.PRESERVE_PAIRS:
        assert st.BY_NAME[switch].kind is bool and st.BY_NAME[strength].kind is float


MAPPED = [s for s in SETTINGS if isinstance(s.core, CoreOption)]


def another_value(setting):
    """A valid value of ``setting`` other than its default."""
    if setting.kind is bool:
        return not setting.default
    for value in (setting.default * 0.5, setting.default + 1.0, setting.default * 2.0):
        if value != setting.default and setting.problem(value) is None:
            return setting.kind(value)
    raise AssertionError(f"no other valid value for {setting.name}")


def test_the_core_column_maps_the_shape_settings_onto_core_options():
    # The rows that set a field of core.Options themselves (the rest act through code of
    # their own, which addon/pure/settings.py's docstring lists).
    assert sorted((s.name, s.core.field) for s in MAPPED) == sorted([
        ("line_weight", "line_weight"), ("min_quality", "min_quality"), ("feature_angle", "feature_angle"),
        ("remove_small_components", "remove_small_components"), ("boundary_strength", "boundary_weight"),
        ("preserve_seams", "preserve_seams")])
    assert len({s.core.field for s in MAPPED}) == len(MAPPED), "two settings set one field"
    assert all(isinstance(s.core, str) for s in SETTINGS if s not in MAPPED)


@pytest.mark.parametrize("setting", MAPPED, ids=lambda s: s.name)
def test_each_mapped_setting_moves_its_options_field(setting):
    """Changing the setting changes its field of the core.Options built from the settings,
    and no other field."""
    assert setting.core.field in core.Options.names()
    before = core_options_of(LodSettings())
    value = another_value(setting)
    after = core_options_of(LodSettings(**{setting.name: value}))
    assert getattr(after, setting.core.field) == setting.core.convert(value) != getattr(before, setting.core.field)
    assert core.Options.of(after, **{setting.core.field: getattr(before, setting.core.field)}) == before


def test_the_defaults_map_onto_the_cores_defaults():
    assert core_options_of(LodSettings()) == core.Options()


def test_a_preserve_switch_turns_its_strengths_field_off():
    for s in MAPPED:
        switch = SWITCH_OF.get(s.name)
        if switch is None:
            continue
        off = core_options_of(LodSettings(**{switch: False, s.name: another_value(s)}))
        assert getattr(off, s.core.field) == s.core.off
    assert core_options_of(LodSettings(preserve_boundaries=False)).boundary_weight == 0.0


def test_feature_angle_zero_turns_the_cores_off():
    assert core_options_of(LodSettings(feature_angle=0.0)).feature_angle is None


@pytest.mark.parametrize("setting", [s for s in SETTINGS if s.kind in (int, float)], ids=lambda s: s.name)
def test_validate_follows_each_range(setting):
    LodSettings().validate()
    outside = [setting.low - 1 if setting.low is not None else None,
               setting.high + 1 if setting.high is not None else None,
               setting.low if setting.low_open else None, setting.high if setting.high_open else None]
    for value in [v for v in outside if v is not None]:
        with pytest.raises(LodError, match=setting.words):
            LodSettings(**{setting.name: value}).validate()
    if setting.kind is float:
        with pytest.raises(LodError, match=setting.words):
            LodSettings(**{setting.name: float("nan")}).validate()


def test_chain_geometric_and_explicit():
    assert LodSettings().chain() == ("ratios", [0.5, 0.25, 0.125])
    assert LodSettings(target_triangles=300, levels=2).chain() == ("triangles", [300, 150])
    assert LodSettings(ratios=(0.5, 0.2), levels=7).chain() == ("ratios", [0.5, 0.2])
    assert LodSettings(ratios=(0.5, 0.25, 0.1)).targets(1000) == [500, 250, 100]
    assert LodSettings(triangle_counts=(300, 100), ratio=0.9).targets(1000) == [300, 100]


@pytest.mark.parametrize("chain,message", [
    ({"ratios": (0.5, 1.5)}, "ratios: 1.5 not between 0 and 1"),
    ({"ratios": (0.25, 0.5)}, r"ratios must decrease \(each LOD smaller than the one before\), got 0.25 0.5"),
    ({"triangle_counts": (100, 200)}, "triangle counts must decrease"),
    ({"triangle_counts": (100, 0)}, "at least 1"),
    ({"ratios": (0.5,), "triangle_counts": (100,)}, "not both"),
])
def test_explicit_chain_is_validated(chain, message):
    with pytest.raises(LodError, match=message):
        LodSettings(**chain).validate()


def test_explicit_chain_messages_can_name_the_options():
    s = LodSettings(ratios=(0.25, 0.5))
    assert s.chain_problem("--ratios", "--faces").startswith("--ratios must decrease")
    with pytest.raises(LodError, match="--ratios 0.5 of 1 triangles give"):
        LodSettings(ratios=(0.5,)).targets(1, "--ratios", "--faces")
    with pytest.raises(LodError, match="--faces 5000 is not fewer than the mesh's 1,000 triangles"):
        LodSettings(triangle_counts=(5000,)).targets(1000, "--ratios", "--faces")


def test_command_line_options_come_from_the_table():
    parser = argparse.ArgumentParser()
    st.add_arguments(parser)
    defaults = parser.parse_args([])
    assert st.settings_from_arguments(defaults) == LodSettings()
    assert st.argument_problems(defaults) == []
    args = parser.parse_args(["--line-weight", "0.01", "--no-preserve-seams", "--mode", "strong",
                              "--no-measure", "--seam-strength", "3"])
    got = st.settings_from_arguments(args, ratios=(0.5,))
    assert (got.line_weight, got.preserve_seams, got.importance_mode, got.measure_deviation) == \
        (0.01, False, 'STRONG', False)
    assert (got.seam_strength, got.ratios) == (3.0, (0.5,))
    bad = parser.parse_args(["--min-quality", "2", "--strength", "-1", "--feature-angle", "180"])
    assert st.argument_problems(bad) == ["--min-quality must be in [0, 1], got 2",
                                         "--feature-angle must be in [0, 180) degrees (0 = off), got 180",
                                         "--strength must be in [0, 1], got -1"]


def test_the_panel_chain_by_deviation_and_by_screen_size():
    by_deviation = LodSettings(target_by='DEVIATION', max_deviation=0.5, levels=3, level_factor=0.5)
    assert by_deviation.deviation_chain() == [(0.5, True), (1.0, True), (2.0, True)]
    assert by_deviation.chain() == ("deviations", ["0.5%", "1%", "2%"])
    assert by_deviation.deviations(diagonal=4.0) == [0.02, 0.04, 0.08]
    by_screen = LodSettings(target_by='SCREEN', pixel_error=2.0, screen_height=1000, levels=2, level_factor=0.5)
    assert by_screen.deviation_chain() == [(0.2, True), (0.4, True)], "2 px of 1000 is 0.2 % of the size"
    assert LodSettings().deviation_chain() is None, "the default chain is by triangles"
    explicit = LodSettings(target_by='DEVIATION', ratios=(0.5,))
    assert explicit.deviation_chain() is None, "an explicit chain by ratios wins over the panel's By"


def _sharp_cube(everywhere: bool):
    """A cube's 12 triangles with its 18 edges: all marked sharp, or the 12 box edges only."""
    from addon.pure.mesh_data import MeshData

    v = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    f = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    box = np.array(sorted({tuple(sorted(e)) for a, b, c, d in quads for e in ((a, b), (b, c), (c, d), (d, a))}))
    diagonals = np.array([(a, c) for a, b, c, d in quads])
    sharp = np.concatenate([box, diagonals]) if everywhere else box
    return MeshData(vertices=v, faces=f, material_index=np.zeros(len(f), np.int64), smooth=np.zeros(len(f), bool),
                    smooth_group=np.zeros(len(f), np.int64), sharp_edges=sharp, sharp_for_shading=everywhere)


def test_sharp_marks_on_every_edge_hold_no_collapse_back():
    """Marks on every edge (how the OBJ and FBX importers bring a flat-shaded mesh) single
    out no crease: no feature edges from them; marks on some edges are features."""
    from addon.pure.options import mesh_options

    flat, options_of = _sharp_cube(True), LodSettings(preserve_seams=False, preserve_materials=False)
    some = _sharp_cube(False)
    assert mesh_options(options_of, flat, [])[0].feature_edges is None
    assert len(mesh_options(options_of, some, [])[0].feature_edges) == len(some.sharp_edges)


def test_a_colour_or_uv_per_facet_is_carried_without_making_seams():
    """A corner colour layer with a colour per triangle jumps across every edge: as seams
    every vertex would be a junction, locked. It is carried like custom normals
    (seamless); a layer with two colour regions keeps its seam. A UV map alike."""
    from addon.pure.mesh_data import ColorLayer
    from addon.pure.options import mesh_options

    cube = _sharp_cube(False)
    per_face = np.repeat(np.random.default_rng(1).random((len(cube.faces), 1, 4)), 3, axis=1)
    halves = np.repeat(np.where(cube.vertices[cube.faces].mean(axis=1)[:, :1] < 0.5, 0.0, 1.0)[:, :, None]
                       * np.ones((1, 1, 4)), 3, axis=1)
    settings = LodSettings(preserve_seams=False, preserve_materials=False, preserve_sharp=False)
    for values, seamless in ((per_face, True), (halves, False)):
        cube.colors = [ColorLayer("Col", 'CORNER', 'FLOAT_COLOR', values)]
        # The same for a UV map: each face its own island, as Lightmap Pack makes them.
        cube.uv_maps = {"UVMap": values[..., :2]}
        options = mesh_options(settings, cube, [])[0]
        for key in ("color0", "uv0"):
            assert (key in options.seamless_attributes) == seamless, key
            assert key in options.corner_attributes
        assert options.uv_attributes == ("uv0",)


def test_a_uv_or_colour_per_facet_of_a_split_mesh_is_seen_as_the_core_welds_it():
    """An exported mesh comes split: each triangle of a glTF import with an island per
    face has vertices of its own, so no two triangles share an edge until the core welds
    the copies. Judged on the split triangles, such a map was no facet layer: the core
    then made every vertex a seam junction, locked, and six such gems beside a cube
    held the cube's share until it went to 4 triangles (LOD3, 13.9 % of the asset's
    diagonal against 0.56 % for the same scene as a .blend)."""
    from addon.pure.mesh_data import ColorLayer
    from addon.pure.options import mesh_options

    cube = _sharp_cube(False)
    cube.vertices = cube.vertices[cube.faces].reshape(-1, 3)  # three copies a triangle
    cube.faces = np.arange(3 * len(cube.faces)).reshape(-1, 3)
    per_face = np.repeat(np.random.default_rng(1).random((len(cube.faces), 1, 4)), 3, axis=1)
    cube.colors = [ColorLayer("Col", 'CORNER', 'FLOAT_COLOR', per_face)]
    cube.uv_maps = {"UVMap": per_face[..., :2]}
    options = mesh_options(LodSettings(preserve_seams=False, preserve_materials=False, preserve_sharp=False),
                           cube, [])[0]
    assert "color0" in options.seamless_attributes and "uv0" in options.seamless_attributes
