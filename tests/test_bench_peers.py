"""bench/peers.py, the optional peer simplifiers of bench/run.py: a peer that does not import is
skipped with a one-line note (CI has none of them installed), outputs are compacted, and
the installed peers reach the face target they are given. No bpy: peers.py never imports it."""
from __future__ import annotations

import sys

import numpy as np
import pytest

from bench import peers
from mesh_builders import torus


def test_missing_peers_are_skipped_with_one_note_each(monkeypatch):
    for peer in peers.PEERS:
        monkeypatch.setitem(sys.modules, peer.module, None)  # `import` raises ModuleNotFoundError
    found, notes = peers.available()
    assert found == []
    assert len(notes) == len(peers.PEERS) == 4
    for peer, note in zip(peers.PEERS, notes):
        assert "\n" not in note
        assert note.startswith(f"{peer.method} skipped: {peer.module} is not installed; ")
        assert peers.INSTALL_HINT in note
    assert "compiler" in notes[[p.key for p in peers.PEERS].index("meshoptimizer")]


def test_a_peer_that_is_installed_but_broken_says_why(monkeypatch):
    # A native library failing to load is not "not installed": the note carries the error.
    real_import = peers.importlib.import_module

    def broken(name, *a, **k):
        if name == "fast_simplification":
            raise OSError("libfoo.so: cannot open shared object file")
        return real_import(name, *a, **k)

    monkeypatch.setattr(peers.importlib, "import_module", broken)
    found, notes = peers.available(["fast-simplification"])
    assert found == []
    assert notes == ["fast-simplification skipped: fast_simplification does not import (OSError: libfoo.so: "
                     "cannot open shared object file); install the optional peers with "
                     f"`{peers.INSTALL_HINT}`"]


def test_selection_and_partial_availability(monkeypatch):
    monkeypatch.setitem(sys.modules, "pymeshlab", None)
    fake = type(sys)("fast_simplification")
    monkeypatch.setitem(sys.modules, "fast_simplification", fake)
    found, notes = peers.available(["meshlab-planar", "fast-simplification"])
    assert [(p.method, m) for p, m in found] == [("fast-simplification", fake)]
    assert len(notes) == 1 and notes[0].startswith("MeshLab planar skipped")


def test_compact_drops_unused_vertices_and_keeps_the_triangles():
    rng = np.random.default_rng(1)
    V = rng.normal(size=(10, 3))
    F = np.array([[7, 2, 9], [9, 2, 4], [4, 2, 7]])
    v, f = peers.compact(V, F)
    assert len(v) == 4 and f.dtype == np.int64
    assert np.array_equal(v[f], V[F])
    assert np.array_equal(np.unique(f), np.arange(4))
    v2, f2 = peers.compact(v, f)  # already compact: unchanged
    assert np.array_equal(v2, v) and np.array_equal(f2, f)


@pytest.mark.parametrize("key", ["meshoptimizer", "fast-simplification"])
def test_installed_peer_reaches_the_target(key):
    peer = next(p for p in peers.PEERS if p.key == key)
    module = pytest.importorskip(peer.module)
    V, F = torus(nu=48, nv=24)
    target = len(F) // 10
    res = peers.run(peer, module, V, F, target)
    assert abs(len(res.faces) - target) <= 0.02 * target
    assert res.faces.dtype == np.int64 and res.vertices.dtype == np.float64
    assert np.array_equal(np.unique(res.faces), np.arange(len(res.vertices)))  # compacted
    assert res.seconds > 0
    # Still a torus of the same size, not a collapsed blob.
    assert np.allclose(np.ptp(res.vertices, axis=0), np.ptp(V, axis=0), rtol=0.1)
