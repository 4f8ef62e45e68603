"""core.allocation: a large run keeps its arrays in the process's heap, and leaves the
process as it found it.

The switch only engages at core.allocation.MIN_FACES faces; these tests lower that bound
so meshes the tests build take the same path as a scan.
"""
from __future__ import annotations

import numpy as np
import pytest

import core
import core.allocation as allocation
import mesh_builders as build


class RecordingLibc:
    """Stands in for glibc: records the allocator settings a run makes."""

    def __init__(self):
        self.calls = []

    def mallopt(self, parameter, value):
        self.calls.append(("mallopt", parameter, value))
        return 1

    def malloc_trim(self, pad):
        self.calls.append(("malloc_trim", pad))
        return 1


@pytest.fixture
def recording_libc(monkeypatch):
    libc = RecordingLibc()
    monkeypatch.setattr(allocation, "MIN_FACES", 1)
    monkeypatch.setattr(allocation, "_glibc_allocator", lambda: libc)
    return libc


def _hugepage_setting():
    switch = allocation._hugepage_switch()
    before = switch(True)
    switch(before)
    return before


def test_settings_are_restored_and_memory_released_after_a_run(recording_libc):
    hugepage_before = _hugepage_setting()
    V, F = build.torus(24, 12)
    core.simplify(V, F, ratio=0.3)
    calls = recording_libc.calls
    set_mmap = calls.index(("mallopt", allocation._M_MMAP_MAX, 0))
    restore_mmap = calls.index(("mallopt", allocation._M_MMAP_MAX, allocation._DEFAULT_MMAP_MAX))
    restore_trim = calls.index(("mallopt", allocation._M_TRIM_THRESHOLD, allocation._DEFAULT_TRIM_THRESHOLD))
    assert set_mmap < restore_mmap and set_mmap < restore_trim
    assert calls[-1] == ("malloc_trim", 0), "free memory not handed back after the run"
    assert _hugepage_setting() == hugepage_before


def test_settings_are_restored_when_the_run_fails(recording_libc):
    hugepage_before = _hugepage_setting()
    V, F = build.torus(24, 12)
    with pytest.raises(ValueError):
        core.simplify(V, F, ratio=0.3, line_weight=-1.0)
    assert ("mallopt", allocation._M_MMAP_MAX, allocation._DEFAULT_MMAP_MAX) in recording_libc.calls
    assert recording_libc.calls[-1] == ("malloc_trim", 0)
    assert _hugepage_setting() == hugepage_before


def test_small_runs_leave_the_allocator_alone(monkeypatch):
    libc = RecordingLibc()
    monkeypatch.setattr(allocation, "_glibc_allocator", lambda: libc)
    V, F = build.torus(24, 12)
    assert len(F) < allocation.MIN_FACES
    core.simplify(V, F, ratio=0.3)
    assert libc.calls == []


def test_the_real_allocator_switch_gives_the_same_lod(monkeypatch):
    """On this machine's own allocator (glibc on Linux; elsewhere nothing is switched), the
    output is bit-identical: only where the memory comes from changes."""
    V, F = build.torus(40, 20)
    plain = core.simplify(V, F, ratio=0.2)
    monkeypatch.setattr(allocation, "MIN_FACES", 1)
    switched = core.simplify(V, F, ratio=0.2)
    assert np.array_equal(plain.vertices, switched.vertices)
    assert np.array_equal(plain.faces, switched.faces)
