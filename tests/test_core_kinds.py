"""The collapse table (core.kinds) is what the selection reads, and it says what the
engine does with each kind of vertex."""
from __future__ import annotations

import numpy as np
import pytest

import core
from core import kinds
import mesh_builders as build
import mesh_checks as check


def test_the_selection_reads_the_table(monkeypatch):
    """Forbid free and border vertices from merging into anything: nothing collapses. The
    table, not code beside it, decides."""
    V, F = build.grid(8, jitter=0.1)
    table = kinds.CAN_COLLAPSE.copy()
    table[kinds.FREE, :] = kinds.NEVER
    table[kinds.BORDER, :] = kinds.NEVER
    monkeypatch.setattr(kinds, "CAN_COLLAPSE", table)
    r = core.simplify(V, F, ratio=0.5, remove_small_components=False)
    assert len(r.faces) == len(F) and r.stats.stop_reason == core.STOP_TOPOLOGY


def test_the_placement_reads_the_table(monkeypatch):
    """With every merged vertex placed at its kept end, no vertex of the LOD is new: each
    is an input vertex where it was."""
    V, F = build.icosphere(2)
    table = np.full_like(kinds.PLACE, kinds.AT_KEEP)
    monkeypatch.setattr(kinds, "PLACE", table)
    r = core.simplify(V, F, ratio=0.3)
    assert np.allclose(r.vertices, V[r.vertex_origin])


def test_table_shapes_and_ranks():
    n = len(kinds.NAMES)
    assert kinds.CAN_COLLAPSE.shape == kinds.PLACE.shape == (n, n) and len(kinds.RANK) == n
    # What never moves ranks highest, so it is always the end that survives.
    for k in (kinds.COMPLEX, kinds.LOCKED):
        assert kinds.RANK[k] == kinds.RANK.max()
        assert (kinds.CAN_COLLAPSE[k] == kinds.NEVER).all()
    # A seam vertex never merges into a vertex off every seam.
    assert (kinds.CAN_COLLAPSE[kinds.SEAM, [kinds.FREE, kinds.BORDER]] == kinds.NEVER).all()


def test_complex_vertices_stay_and_free_ones_merge_into_them():
    """A fin on a sheet: the row it stands on has edges of four faces. Those vertices are
    COMPLEX: each is in the LOD where it was, and the sheet and fin simplify around it."""
    V, F = build.with_fin(12, 4)
    r = core.simplify(V, F, ratio=0.3)
    check.assert_valid_mesh(r.vertices, r.faces, manifold=False)
    edges, count = check.edge_table(F)
    row = np.unique(edges[count > 2])
    assert np.isin(row, r.vertex_origin).all()
    at = np.searchsorted(r.vertex_origin, row)
    assert np.array_equal(r.vertices[at], V[row])
    assert len(r.faces) <= round(0.3 * len(F))


def test_every_fault_names_its_module():
    import importlib
    for fault, module, what in kinds.FAULTS:
        assert importlib.import_module(module) is not None and what, fault
