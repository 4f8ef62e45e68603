"""addon/vertex_groups.py (the checkout's copy) on generated meshes: the VertexGroup.add
route against the former attribute_convert route and the exact float32 values, groups
kept and replaced, objects in no scene, no operator called, no temporaries left, and the
read routes agreeing (tests/test_addon_vertex_groups.py checks what this returns). Runs
without the extension installed."""

import bpy
import numpy as np

from addon import vertex_groups as vg
from scene_tools import value_errors

N_GROUPS = 24


def grid_mesh(name: str, nx: int, ny: int):
    xs, ys = np.meshgrid(np.arange(nx, dtype=np.float32), np.arange(ny, dtype=np.float32))
    co = np.stack([xs.ravel(), ys.ravel(), np.zeros(nx * ny, np.float32)], axis=1)
    i = np.arange(nx * ny).reshape(ny, nx)
    quads = np.stack([i[:-1, :-1].ravel(), i[:-1, 1:].ravel(), i[1:, 1:].ravel(), i[1:, :-1].ravel()], axis=1)
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(co))
    me.vertices.foreach_set("co", co.ravel())
    me.loops.add(quads.size)
    me.loops.foreach_set("vertex_index", quads.ravel().astype(np.int32))
    me.polygons.add(len(quads))
    me.polygons.foreach_set("loop_start", np.arange(0, quads.size, 4, dtype=np.int32))
    me.update(calc_edges=True)
    return me


def skin_weights(n: int, g: int, seed: int) -> np.ndarray:
    """(n, g) float64 like interpolated skin weights: each vertex in 1 to 4 groups, rows
    summing to 1 (a quarter of the vertices in one group at exactly 1.0), most of them 0;
    then the edge cases: values that round to 0 in float32, tiny ones that do not, values
    outside [0, 1] (clipped), and a group with no vertex."""
    rng = np.random.default_rng(seed)
    w = np.zeros((n, g))
    k = rng.integers(1, 5, n)
    for j in range(4):
        rows = np.flatnonzero(k > j)
        w[rows, rng.integers(0, g - 1, len(rows))] += rng.random(len(rows))
    w /= np.maximum(w.sum(axis=1, keepdims=True), 1e-300)
    w[0, 0], w[1, 0], w[2, 0], w[3, 0] = 1e-50, 1e-30, 1.5, -0.25
    w[:, g - 1] = 0.0
    return w


def python_read(ob, names) -> np.ndarray:
    return vg.read_weights(ob.data, names, method="python")


def members(ob) -> set:
    """{(vertex, group name)} of the object's vertex groups, read per vertex."""
    names = ob.vertex_groups.keys()
    return {(v.index, names[g.group]) for v in ob.data.vertices for g in v.groups}


class _NoNewObjects:
    """Stands in for ``bpy`` inside the modules under test: any use of ``bpy.data.objects``
    or ``bpy.data.meshes`` fails (making and removing an object or a mesh would tag the
    depsgraph relations, which the next evaluation rebuilds for every object of the scene)."""

    class _Data:
        def __getattr__(self, name):
            if name in ("objects", "meshes"):
                raise AssertionError(f"bpy.data.{name} was used")
            return getattr(bpy.data, name)

    def __init__(self):
        self.data, self.context, self.types, self.ops = self._Data(), bpy.context, bpy.types, bpy.ops


class _NoOperators:
    """Stands in for ``bpy`` inside the module under test: any bpy.ops access fails."""

    def __init__(self):
        self.data, self.context, self.types = bpy.data, bpy.context, bpy.types

    @property
    def ops(self):
        raise AssertionError("an operator was called")


def datablocks() -> dict:
    return {"objects": len(bpy.data.objects), "meshes": len(bpy.data.meshes),
            "node_groups": len(bpy.data.node_groups), "scenes": len(bpy.data.scenes)}


def leftovers(obs) -> dict:
    return {"attributes": sorted({a.name for ob in obs for a in ob.data.attributes if a.name.startswith("__lqlod")}),
            "groups": sorted({g.name for ob in obs for g in ob.vertex_groups if g.name.startswith("__lqlod")}),
            "modifiers": sum(len(ob.modifiers) for ob in obs)}


def run() -> dict:
    result = {}
    n = 40 * 30
    names = [f"bone{i:02d}" for i in range(N_GROUPS - 2)] + ["position", "UVMap"]  # attribute names too
    w = skin_weights(n, N_GROUPS, seed=3)
    expected = np.clip(w, 0.0, 1.0).astype(np.float32).astype(np.float64)

    # Two unlinked objects on copies of one mesh with a UV map (an attribute named like a group).
    base = grid_mesh("base", 40, 30)
    base.uv_layers.new(name="UVMap")
    new_ob = bpy.data.objects.new("new_route", base.copy())
    old_ob = bpy.data.objects.new("old_route", base.copy())
    for ob in (new_ob, old_ob):  # an unrelated group first, and one that gets replaced
        keep = ob.vertex_groups.new(name="keep")
        keep.add([0, 5, 7], 0.375, 'REPLACE')
        ob.vertex_groups.new(name="bone03").add(list(range(n)), 0.5, 'REPLACE')
    result["in_scenes"] = [len(ob.users_scene) for ob in (new_ob, old_ob)]

    before = datablocks()
    real_bpy = vg.bpy
    vg.bpy = _NoOperators()
    try:
        vg.write_weights(new_ob, names, w)  # "auto": must not touch bpy.ops
        result["auto_without_operators"] = True
    except AssertionError as ex:
        result["auto_without_operators"] = str(ex)
    finally:
        vg.bpy = real_bpy
    vg.write_weights(old_ob, names, w, method="convert")
    result["datablocks_same"] = datablocks() == before
    result["leftovers"] = leftovers([new_ob, old_ob])

    new_w = python_read(new_ob, names)
    old_w = python_read(old_ob, names)
    result["group_order"] = [ob.vertex_groups.keys() for ob in (new_ob, old_ob)]
    result["new_vs_old_max"] = float(np.abs(new_w - old_w).max())
    result["new_vs_expected_max"] = float(np.abs(new_w - expected).max())
    want = {(int(v), names[int(c)]) for v, c in zip(*np.nonzero(expected))}
    got_new = {m for m in members(new_ob) if m[1] in names}
    got_old = {m for m in members(old_ob) if m[1] in names}
    result["members"] = {"expected": len(want), "new": len(got_new), "old": len(got_old),
                         "new_equal": got_new == want, "old_equal": got_old == want}
    result["edge_cases"] = {"rounds_to_zero_member": (0, names[0]) in got_new, "tiny": float(new_w[1, 0]),
                            "clipped": float(new_w[2, 0]), "negative_member": (3, names[0]) in got_new,
                            "empty_group_members": sum(1 for m in got_new if m[1] == names[-1])}
    keep_w = python_read(new_ob, ["keep"])[:, 0]
    result["keep_untouched"] = sorted(np.flatnonzero(keep_w).tolist()) == [0, 5, 7] and bool(
        np.all(keep_w[[0, 5, 7]] == 0.375))

    # Written again: replaced, not doubled.
    vg.write_weights(new_ob, names, w[::-1].copy())
    result["rewrite_order"] = new_ob.vertex_groups.keys()
    result["rewrite_max"] = float(np.abs(python_read(new_ob, names) - expected[::-1]).max())

    # A linked object with an Armature modifier (as skinned LODs are), and a mesh without vertices.
    linked = bpy.data.objects.new("linked", grid_mesh("linked", 12, 10))
    bpy.context.scene.collection.objects.link(linked)
    linked.modifiers.new("Armature", 'ARMATURE')
    lw = skin_weights(120, 6, seed=5)
    vg.write_weights(linked, [f"b{i}" for i in range(6)], lw)
    result["linked_max"] = float(np.abs(python_read(linked, [f"b{i}" for i in range(6)])
                                        - np.clip(lw, 0, 1).astype(np.float32)).max())
    result["linked_modifiers"] = [m.type for m in linked.modifiers]
    empty = bpy.data.objects.new("empty", bpy.data.meshes.new("empty"))
    vg.write_weights(empty, ["a", "b"], np.zeros((0, 2)))
    result["empty_groups"] = empty.vertex_groups.keys()

    errors = value_errors({
        "duplicate": lambda: vg.write_weights(empty, ["a", "a"], np.zeros((0, 2))),
        "unknown_write": lambda: vg.write_weights(empty, ["a"], np.zeros((0, 1)), method="x"),
        "unknown_read": lambda: vg.read_weights(base, ["a"], method="x"),
    })
    result["errors"] = errors

    # Reading: "auto" (Python below NODES_MIN_VERTICES, Geometry Nodes from there on) agrees
    # with both routes exactly, on a small mesh and on one just past the threshold.
    reads = {}
    for label, ob in (("small", new_ob), ("large", None)):
        if ob is None:
            side = int(np.ceil(np.sqrt(vg.NODES_MIN_VERTICES))) + 1
            ob = bpy.data.objects.new("large", grid_mesh("large", side, side))
            vg.write_weights(ob, names, skin_weights(side * side, N_GROUPS, seed=7))
        before = datablocks()
        auto = vg.read_weights(ob.data, names)
        nodes = vg.read_weights(ob.data, names, method="nodes")
        python = vg.read_weights(ob.data, names, method="python")
        missing = vg.read_weights(ob.data, ["missing", names[1]], method="nodes")  # a group the mesh lacks reads 0
        reads[label] = {"vertices": len(ob.data.vertices), "auto_vs_python": float(np.abs(auto - python).max()),
                        "missing": [float(np.abs(missing[:, 0]).max()), float(np.abs(missing[:, 1] - python[:, 1]).max())],
                        "nodes_vs_python": float(np.abs(nodes - python).max()), "nonzero": int(np.count_nonzero(python)),
                        "datablocks_same": datablocks() == before, "leftovers": leftovers([ob])}
    result["reads"] = reads

    # An object's mesh is read through the object's own group names, and through modifiers
    # the evaluated object's temporary mesh: no throw-away object or mesh in bpy.data.
    from addon import mesh_io
    shaped = bpy.data.objects.new("shaped", grid_mesh("shaped", 12, 10))
    bpy.context.scene.collection.objects.link(shaped)
    vg.write_weights(shaped, ["a", "b"], skin_weights(120, 2, seed=5))
    shaped.modifiers.new("sub", 'SUBSURF').levels = 1
    depsgraph = bpy.context.evaluated_depsgraph_get()
    # (the reference: what the evaluated mesh holds, through a mesh made in bpy.data)
    made = bpy.data.meshes.new_from_object(shaped.evaluated_get(depsgraph), preserve_all_data_layers=True,
                                           depsgraph=depsgraph)
    made_names = vg.group_names(made)
    made_weights = vg.read_weights(made, made_names)
    bpy.data.meshes.remove(made)
    reads_without = {}
    vg.bpy = mesh_io.bpy = _NoNewObjects()
    try:
        for label, ob, modifiers in (("base", new_ob, False), ("modifiers", shaped, True)):
            try:
                data, _ = mesh_io.read_object(ob, depsgraph, use_modifiers=modifiers)
                reads_without[label] = data.group_names == (made_names if modifiers else ob.vertex_groups.keys())
                if modifiers:
                    reads_without["modifiers_weights"] = float(np.abs(data.group_weights - made_weights).max())
                    reads_without["modifiers_vertices"] = [len(data.vertices), len(made_weights)]
            except AssertionError as ex:
                reads_without[label] = str(ex)
    finally:
        vg.bpy = mesh_io.bpy = real_bpy
    result["read_object_without_new_data"] = reads_without
    result["nodes_min_vertices"] = vg.NODES_MIN_VERTICES
    return result
