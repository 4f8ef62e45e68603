"""A LOD keeps its source's generic attributes (what an artist's shader reads with an
Attribute node, or Geometry Nodes wrote): every domain and type, interpolated where the
values are a field and taken from the element each LOD element came from where they are
ids, flags or colours of faces. Before, the LODs had none of them. One Blender child runs
tests/scenarios/addon_attributes.py (a subdivided cube with six such attributes)."""
import numpy as np
import pytest

from bpy_harness import run_scenario

NAMES = {"wear": ('POINT', 'FLOAT'), "top": ('POINT', 'BOOLEAN'), "side": ('FACE', 'INT'),
         "corner_side": ('CORNER', 'INT'), "crease_edge": ('EDGE', 'FLOAT'), "tint": ('FACE', 'FLOAT_COLOR'),
         "bevel_weight_edge": ('EDGE', 'FLOAT'), "turn": ('POINT', 'QUATERNION')}


@pytest.fixture(scope="module")
def res(tmp_path_factory):
    work = tmp_path_factory.mktemp("attributes")
    return run_scenario("addon_attributes", {}, user_dir=work / "user", install=False, timeout=600)


def side_of(normals: np.ndarray) -> np.ndarray:
    axis = np.abs(normals).argmax(axis=1)
    return 2 * axis + (normals[np.arange(len(normals)), axis] > 0)


def test_every_attribute_is_on_every_lod_with_its_domain_and_type(res):
    assert res["unchanged"]
    assert {n: (a["domain"], a["type"]) for n, a in res["source"]["attributes"].items()} == NAMES
    for lod in res["lods"]:
        assert {n: (a["domain"], a["type"]) for n, a in lod["attributes"].items()} == NAMES
        sizes = {'POINT': len(lod["vertices"]), 'FACE': len(lod["face_normals"]),
                 'CORNER': len(lod["loop_vertex"]), 'EDGE': len(lod["edges"])}
        for name, (domain, _) in NAMES.items():
            assert len(lod["attributes"][name]["values"]) == sizes[domain], name


def test_a_field_is_interpolated_and_ids_flags_and_face_colours_are_kept(res):
    for lod in res["lods"]:
        co = np.array(lod["vertices"])
        a = {n: np.array(v["values"]) for n, v in lod["attributes"].items()}
        field = co @ np.array([1.0, 2.0, 3.0])
        assert np.abs(a["wear"] - field).max() <= 0.05 * np.ptp(field), np.abs(a["wear"] - field).max()
        # A vertex keeps its source vertex's flag: off the equator, where z does.
        away = np.abs(co[:, 2]) > 0.3
        assert np.array_equal(a["top"][away], co[away, 2] > 0)
        # No face crosses a cube edge (features kept), so each face's side is its own.
        side = side_of(np.array(lod["face_normals"]))
        assert np.array_equal(a["side"], side)
        assert np.array_equal(a["corner_side"], side[np.array(lod["loop_face"])])
        assert np.allclose(a["tint"][:, 0], side / 5.0) and np.allclose(a["tint"][:, 3], 1.0)
        # A rotation is taken from a source vertex, whole: still a unit quaternion about z.
        assert np.allclose(np.linalg.norm(a["turn"], axis=1), 1.0, atol=1e-5)
        assert np.allclose(a["turn"][:, 1:3], 0.0)
        # An edge attribute of zeros (it failed the run: no marked edge to follow) stays zeros.
        assert not np.any(a["bevel_weight_edge"])


def test_an_edge_attribute_stays_on_the_edges_it_marked(res):
    for lod in res["lods"]:
        co = np.array(lod["vertices"])
        edges = np.array(lod["edges"])
        a, b = co[edges[:, 0]], co[edges[:, 1]]
        rim = ((np.abs(a) > 0.999) & (np.abs(b) > 0.999) & (np.sign(a) == np.sign(b))).sum(axis=1) >= 2
        crease = np.array(lod["attributes"]["crease_edge"]["values"])
        assert rim.any() and np.all(crease[rim] == 1.0) and np.all(crease[~rim] == 0.0)
