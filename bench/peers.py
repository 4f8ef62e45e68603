"""Optional peer simplifiers for the benchmarks: MeshLab (pymeshlab), meshoptimizer, fast-simplification.

Dev extras only (requirements-peers.txt), never add-on dependencies: each peer is imported
when it is first asked for, and a peer that does not import is reported as a one-line note
instead of a row. Nothing here imports bpy, but a bench that uses bpy must import it BEFORE
asking for MeshLab: pymeshlab's bundled embree breaks a later ``import bpy`` in the process.

    available(keys=None) -> ([(Peer, module)], [note])   the peers that import, notes for the rest
    run(peer, module, V, F, target_faces) -> PeerResult  one simplification, output compacted
    compact(V, F) -> (V, F)                              drop vertices no face uses

Every peer gets float64 vertices (n, 3) and int64 triangles (m, 3) and a target face count;
the conversion to its own input types happens before its clock starts, so ``seconds`` is
only the peer's simplify call.
"""
from __future__ import annotations

import importlib
import sys
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np

INSTALL_HINT = ".venv/bin/python -m pip install -r requirements-peers.txt"
# MeshLab's own default planar weight; MeshLab sees the mesh scaled to a unit bounding-box
# diagonal (see meshlab_simplify), so the weight means the same on every mesh.
MESHLAB_PLANAR_WEIGHT = 1e-3
# meshoptimizer stops at target_error (relative to the mesh extent) or at the index count,
# whichever comes first. 1.0 = the whole extent: the count decides, as for every other method.
MESHOPT_TARGET_ERROR = 1.0


def log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


@dataclass
class PeerResult:
    vertices: np.ndarray  # (n, 3) f64, every vertex used by a face
    faces: np.ndarray  # (m, 3) i64
    seconds: float  # the peer's simplify call only


@dataclass(frozen=True)
class Peer:
    key: str  # command-line name
    method: str  # row label
    module: str  # what is imported
    package: str  # what pip installs
    options: str  # the call and the options used, for the report
    simplify: Callable  # (module, V, F, target_faces) -> (V, F, seconds)
    build_note: str = ""


# ---------------------------------------------------------------- MeshLab

def meshlab_or_none():
    """pymeshlab, or None (with a log line) when it does not import."""
    try:
        import pymeshlab
    except Exception as ex:  # optional peer: ImportError, or its native libraries failing to load
        log(f"pymeshlab not importable ({type(ex).__name__}: {ex})")
        return None
    return pymeshlab


def meshlab_simplify(pymeshlab, V, F, target, planar_weight):
    """MeshLab's quadric edge collapse to ``target`` faces; planar_weight None = no planar quadric.

    The mesh is handed over scaled to a unit bounding-box diagonal (and the result scaled
    back): MeshLab's planar weight is not scale-invariant (measured on the bunny at weight
    1e-3: mean q 0.868 at its own size, 0.799 scaled 40x), while core's w is. Every
    parameter is passed explicitly: pymeshlab was seen to reuse a previous call's
    planarquadric when it was left out. Returns (V, F, seconds of the filter call).
    """
    lo = V.min(axis=0)
    scale = float(np.linalg.norm(V.max(axis=0) - lo))
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=(V - lo) / scale, face_matrix=F.astype(np.int32)))
    t0 = time.perf_counter()
    ms.meshing_decimation_quadric_edge_collapse(
        targetfacenum=int(target), qualitythr=0.3, preserveboundary=False, boundaryweight=1.0,
        preservenormal=False, preservetopology=False, optimalplacement=True,
        planarquadric=planar_weight is not None,
        planarweight=float(planar_weight) if planar_weight is not None else 0.001,
        qualityweight=False, autoclean=True, selected=False)
    seconds = time.perf_counter() - t0
    m = ms.current_mesh()
    return (np.asarray(m.vertex_matrix(), dtype=np.float64) * scale + lo,
            np.asarray(m.face_matrix(), dtype=np.int64), seconds)


# ---------------------------------------------------------------- meshoptimizer

def _meshoptimizer(meshopt, V, F, target):
    positions = np.ascontiguousarray(V, dtype=np.float32)
    indices = np.ascontiguousarray(F, dtype=np.uint32).reshape(-1)  # the wrapper counts len(indices)
    destination = np.empty_like(indices)
    t0 = time.perf_counter()
    count = meshopt.simplify(destination, indices, positions, target_index_count=3 * int(target),
                             target_error=MESHOPT_TARGET_ERROR, options=0)
    seconds = time.perf_counter() - t0
    # Indices into the input's vertex buffer (never moved, only a subset kept).
    return V, destination[:count].reshape(-1, 3).astype(np.int64), seconds


# ---------------------------------------------------------------- fast-simplification

def _fast_simplification(fs, V, F, target):
    points = np.ascontiguousarray(V, dtype=np.float64)
    triangles = np.ascontiguousarray(F, dtype=np.int32)
    reduction = 1.0 - int(target) / len(F)
    t0 = time.perf_counter()
    v, f = fs.simplify(points, triangles, target_reduction=reduction)
    seconds = time.perf_counter() - t0
    return np.asarray(v, dtype=np.float64), np.asarray(f, dtype=np.int64), seconds


PEERS = (
    Peer("meshlab", "MeshLab", "pymeshlab", "pymeshlab",
         "pymeshlab MeshSet.meshing_decimation_quadric_edge_collapse(targetfacenum=target, "
         "qualitythr=0.3, optimalplacement=True, planarquadric=False, preserveboundary/normal/topology=False, "
         "autoclean=True), mesh scaled to a unit bounding-box diagonal",
         lambda mod, V, F, t: meshlab_simplify(mod, V, F, t, None)),
    Peer("meshlab-planar", "MeshLab planar", "pymeshlab", "pymeshlab",
         f"as MeshLab, with planarquadric=True, planarweight={MESHLAB_PLANAR_WEIGHT:g} (MeshLab's default) "
         "on the unit-diagonal mesh",
         lambda mod, V, F, t: meshlab_simplify(mod, V, F, t, MESHLAB_PLANAR_WEIGHT)),
    Peer("meshoptimizer", "meshoptimizer", "meshoptimizer", "meshoptimizer",
         f"meshoptimizer.simplify(dest, indices, float32 positions, target_index_count=3*target, "
         f"target_error={MESHOPT_TARGET_ERROR:g}, options=0) (meshopt_simplify, its default simplifier "
         "with no flags; target_error 1 = the whole extent, so the count decides)",
         _meshoptimizer,
         build_note="the PyPI package builds from source and needs a C/C++ compiler"),
    Peer("fast-simplification", "fast-simplification", "fast_simplification", "fast-simplification",
         "fast_simplification.simplify(points, triangles, target_reduction=1-target/faces) "
         "(its defaults: agg=7, preserve_border=False)",
         _fast_simplification),
)
PEER_KEYS = tuple(p.key for p in PEERS)


def version_of(peer: Peer) -> str:
    try:
        from importlib.metadata import version

        return version(peer.package)
    except Exception:
        return "?"


def available(keys=None):
    """Import the selected peers (all by default): ([(Peer, module)], [one-line note per missing peer])."""
    selected = [p for p in PEERS if keys is None or p.key in keys]
    found, notes, failed = [], [], {}
    for peer in selected:
        if peer.module not in failed:
            try:
                module = importlib.import_module(peer.module)
            except ModuleNotFoundError as ex:
                failed[peer.module] = ("is not installed" if ex.name == peer.module
                                       else f"does not import ({type(ex).__name__}: {ex})")
            except Exception as ex:  # installed, but e.g. a native library that does not load
                failed[peer.module] = f"does not import ({type(ex).__name__}: {ex})"
            else:
                found.append((peer, module))
                continue
        hint = f" ({peer.build_note})" if peer.build_note else ""
        notes.append(f"{peer.method} skipped: {peer.module} {failed[peer.module]}; "
                     f"install the optional peers with `{INSTALL_HINT}`{hint}")
    return found, notes


def compact(vertices, faces):
    """(V, F) without the vertices no face references, faces renumbered."""
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    used = np.zeros(len(vertices), dtype=bool)
    used[faces.ravel()] = True
    if used.all():
        return np.asarray(vertices, dtype=np.float64), faces
    remap = np.cumsum(used) - 1
    return np.asarray(vertices, dtype=np.float64)[used], remap[faces]


def run(peer: Peer, module, vertices, faces, target_faces: int) -> PeerResult:
    """One peer simplification of (V, F) to ``target_faces``; unused vertices removed (untimed)."""
    v, f, seconds = peer.simplify(module, np.asarray(vertices, dtype=np.float64),
                                  np.asarray(faces, dtype=np.int64), int(target_faces))
    v, f = compact(v, f)
    return PeerResult(vertices=v, faces=f, seconds=seconds)
