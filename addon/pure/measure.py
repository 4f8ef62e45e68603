# SPDX-License-Identifier: GPL-3.0-or-later
"""Surface deviation between two triangle meshes, and the LOD report built on it.

Shared by the benchmarks (bench/), the add-on's report panel and the command line.

Method (what the numbers mean):
  * Each surface is sampled with area-uniform random points (NumPy, vectorised), and its
    vertices (those used by a face of nonzero area) are added to the points of that surface.
  * For every point the exact closest point on the *other* surface is found with
    ``mathutils.bvhtree.BVHTree.find_nearest`` (exact point-to-triangle distance; Blender
    stores the tree in single precision, so distances carry ~1e-7 relative error).
  * From the farthest of A's samples and vertices, a climb tries points around each
    (random, closer each round: ``_climb``) for a larger distance: a maximum inside a
    triangle, which uniform samples only come near by chance.
  * One direction A->B: Hausdorff = the largest distance over A's samples, vertices and
    climbed points; mean = the mean distance over A's area-uniform samples only (an unbiased estimate of
    the area-weighted mean distance; vertices are left out of the mean because they are
    denser where triangles are small and would bias it).
  * Two-sided: ``hausdorff`` = max of both directions, ``mean`` = average of both
    directional means. Both are given in mesh units and in percent of the bounding-box
    diagonal of the *input* (``src``) mesh.

Shading normals (``normal_deviation``, or ``surface_deviation(normals=...)``, which reuses
the src->dst closest points): at each of src's area-uniform samples, src's shading normal
(its corner normals interpolated with the sample's barycentric coordinates) against dst's
at the closest point of dst (core.shading: the point's barycentric coordinates on the
triangle the BVH found, the corner normals interpolated there); the angle in degrees,
summarised as mean, 95th percentile and max. One direction only: how the source's
surface looks on the LOD. Only the interpolated normal counts, not the geometric one, so
a flat-shaded LOD of a smooth source measures its facets.

The random points of a surface depend only on ``seed`` and that surface's own arrays, not
on whether it is passed as src or dst, so swapping the two meshes gives exactly the same
absolute distances (only the *_percent values change, their diagonal is src's).

Speed: the BVH queries are one Python call per point. Two things keep that cheap: the
loop is a bare list comprehension over a prebuilt tree, and each query is bounded by a
search radius taken from an unbounded pilot on a subset (a bounded query prunes most of
the tree); points with nothing inside the radius are queried again without a bound, so
the result is still exact. Measured on this machine (2 cores, bpy 4.5), ogre.obj
(124k faces) against its 10% LOD with the default 500,000 samples per surface: about
1.2-1.6 s per direction when the machine is quiet, about twice that when it is busy; the command
and the numbers are in bench/README.md. The shading normals with the distances
(``normals=``) cost one more number per query and the interpolation in NumPy: the LOD
report (50,000 samples, default chain of 3 LODs) measured 9 % longer on the bunny and
11 % on the ogre with them; ``normal_deviation`` on its own queries again, 26-47 % of a
two-sided distance measurement.

The closest-point tree is the one thing here that needs Blender (``mathutils``): it is
handed in (``set_tree_builder``; addon/bvh.py builds it), so this module imports without
Blender and its sampling and statistics run anywhere; measuring needs bpy's mathutils.
"""
from __future__ import annotations

import contextlib
import gc
import itertools
import operator
import time
import weakref
import zlib
from dataclasses import dataclass
from typing import NamedTuple, Optional

import numpy as np

DEFAULT_SAMPLES = 500_000  # area-uniform samples per surface (vertices come on top)

# Of what find_nearest returns, (location, normal, triangle index, distance):
_DISTANCE = operator.itemgetter(3)
_INDEX_AND_DISTANCE = operator.itemgetter(2, 3)

# The pilot that sets the search radius: this many unbounded queries at most (and one
# query in _PILOT_SHARE, at least _PILOT_MIN), and the radius is this multiple of the
# pilot's high quantile. All only affect speed. (A pilot of 2,000 whatever the count was
# 38 % of the queries measuring an engine's 29 small parts: most calls are a few thousand.
# An unbounded query costs about three bounded ones; one in 100, at most 250, took the
# engine's 41,000 unbounded queries to 11,000, no more of the points missing the radius.)
_PILOT_POINTS = 250
_PILOT_SHARE = 100
_PILOT_MIN = 25
_PILOT_QUANTILE = 0.99
_RADIUS_FACTOR = 2.0
# The vertices' search radius comes from the area samples' distances, as a pilot's would,
# where the direction has at least this many samples (_vertex_distances): a pilot per
# query set paid a fifth of an engine's queries, mostly unbounded ones.
VERTEX_RADIUS_SAMPLES = 100

# The climb towards the largest distance (_climb): from the farthest area samples and
# vertices of a direction (one seed per CLIMB_POINTS_PER_SEED points measured, at most
# CLIMB_SEEDS of each), CLIMB_ROUNDS rounds of CLIMB_TRIES points around each seed's best
# so far, the spread (barycentric units) halving each round. Uniform samples see the
# maximum only where one happens to fall: 50,000 a side came out 5 % under a million
# samples' maximum on average over twelve meshes at three LOD levels, and up to 30 % under
# (homer at 50 %); the report's half as many with the climb 1.5 % over it on average and at
# most 9 % under, in about half the time (bench/measure_accuracy.py).
CLIMB_SEEDS = 16
CLIMB_POINTS_PER_SEED = 1_500
CLIMB_TRIES = 8
CLIMB_ROUNDS = 3
CLIMB_SPREAD = 0.25


class _Deferred:
    """A value Sampled computes the first time it is read: the closest points'
    barycentric coordinates, which only the heat map and painted limits read (and the
    shading normals, which compute theirs at once). Every measurement computed four sets
    where the report reads one: on a 600-part asset 7,204 computations, of which the
    1,801 read take 0.35 s, against 2.4 s for all its queries."""

    __slots__ = ("compute", "args")

    def __init__(self, compute, *args):
        self.compute, self.args = compute, args

    def __call__(self):
        return self.compute(*self.args)


@dataclass
class Sampled:
    """What surface_deviation(keep_samples=True) measured point by point, for reports that
    break the distance down (addon/pure/level_deviation.py) without querying again.

    Per direction (src_: src's points measured against dst; dst_: dst's against src),
    for each area-uniform sample: ``triangle`` (k,) of its own surface it lies on and its
    ``bary`` (k, 3) coordinates there, its ``distance`` (k,) to the other surface; and for
    the surface's ``vertices`` (j,) (the ids of those a face uses) their
    ``vertex_distance`` (j,). For src's samples also the triangle of dst their closest
    point is on (``src_nearest`` (k,)) and that point's coordinates there
    (``src_nearest_bary`` (k, 3)); the same for dst's samples (``dst_nearest``, on src)
    and for both surfaces' vertices (``*_vertex_nearest``, ``*_vertex_nearest_bary``).
    The points the climb towards the largest distance tried (_climb): their triangle
    ``*_climbed_triangle`` (c,), barycentric coordinates ``*_climbed_bary`` (c, 3) and
    distance ``*_climbed_distance`` (c,); they count in the largest distance, not in the mean.
    Read the fields as attributes: the barycentric coordinates of closest points are
    computed on first reading (_Deferred), so ``vars()`` may show them unevaluated.
    """

    src_triangle: np.ndarray
    src_bary: np.ndarray
    src_distance: np.ndarray
    src_nearest: np.ndarray
    src_nearest_bary: np.ndarray
    src_vertices: np.ndarray
    src_vertex_distance: np.ndarray
    dst_triangle: np.ndarray
    dst_bary: np.ndarray
    dst_distance: np.ndarray
    dst_vertices: np.ndarray
    dst_vertex_distance: np.ndarray
    dst_nearest: Optional[np.ndarray] = None
    dst_nearest_bary: Optional[np.ndarray] = None
    src_vertex_nearest: Optional[np.ndarray] = None
    src_vertex_nearest_bary: Optional[np.ndarray] = None
    dst_vertex_nearest: Optional[np.ndarray] = None
    dst_vertex_nearest_bary: Optional[np.ndarray] = None
    src_climbed_triangle: Optional[np.ndarray] = None
    src_climbed_bary: Optional[np.ndarray] = None
    src_climbed_distance: Optional[np.ndarray] = None
    dst_climbed_triangle: Optional[np.ndarray] = None
    dst_climbed_bary: Optional[np.ndarray] = None
    dst_climbed_distance: Optional[np.ndarray] = None

    def __getattribute__(self, name):
        value = object.__getattribute__(self, name)
        if type(value) is _Deferred:  # (computed once, on first reading)
            value = value()
            object.__setattr__(self, name, value)
        return value


def _as_mesh(vertices, faces, what: str):
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"{what} vertices must be an (n, 3) array, got shape {v.shape}")
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"{what} faces must be an (m, 3) array of triangles, got shape {f.shape}")
    if len(f) == 0:
        raise ValueError(f"{what} mesh has no faces: there is no surface to measure")
    if not np.issubdtype(f.dtype, np.integer):
        raise ValueError(f"{what} faces must be integer indices, got dtype {f.dtype}")
    f = f.astype(np.int64, copy=False)
    if f.min() < 0 or f.max() >= len(v):
        raise ValueError(f"{what} faces index vertices outside 0..{len(v) - 1}")
    if not np.isfinite(v).all():
        raise ValueError(f"{what} vertices contain NaN or infinite coordinates")
    return v, f


def _surface_rng(seed: int, v: np.ndarray, f: np.ndarray) -> np.random.Generator:
    # Seeded by the surface's own content, so its samples are the same whichever side
    # of the comparison it is on (makes the two-sided measure exactly symmetric).
    key = zlib.crc32(np.ascontiguousarray(f).view(np.uint8))
    key = zlib.crc32(np.ascontiguousarray(v).view(np.uint8), key)
    return np.random.default_rng([int(seed) & 0xFFFFFFFF, key])


def _triangle_areas(v: np.ndarray, f: np.ndarray) -> np.ndarray:
    from ._core import core

    p0 = v[f[:, 0]]
    return 0.5 * np.linalg.norm(core.geometry.cross(v[f[:, 1]] - p0, v[f[:, 2]] - p0), axis=1)


def mesh_area(vertices, faces) -> float:
    """The surface area of a triangle mesh (vertices (n, 3), faces (m, 3)), in its units squared."""
    return float(_triangle_areas(np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64)).sum())


def sample_surface(vertices, faces, n: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` points distributed uniformly by area over the triangles, (n, 3) float64."""
    return _sample_surface(vertices, faces, n, rng)[0]


def _sample_surface(vertices, faces, n: int, rng: np.random.Generator) -> tuple:
    """sample_surface's points, (n, 3), with the triangle (n,) and the barycentric
    coordinates (n, 3) of each."""
    v, f = np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64)
    area = _triangle_areas(v, f)
    cdf = np.cumsum(area)
    if n <= 0 or cdf[-1] <= 0.0:
        return np.empty((0, 3)), np.empty(0, dtype=np.int64), np.empty((0, 3))
    # searchsorted on the area CDF picks a face with probability area/total; the
    # "right" side never selects a zero-area face.
    tri = np.searchsorted(cdf, rng.random(n) * cdf[-1], side="right")
    np.minimum(tri, len(f) - 1, out=tri)
    r1 = np.sqrt(rng.random(n))
    r2 = rng.random(n)
    a, b, c = v[f[tri, 0]], v[f[tri, 1]], v[f[tri, 2]]
    # Osada et al. 2002: uniform on the triangle.
    bary = np.stack([1.0 - r1, r1 * (1.0 - r2), r1 * r2], axis=1)
    points = bary[:, 0, None] * a + bary[:, 1, None] * b + bary[:, 2, None] * c
    return points, tri, bary


@contextlib.contextmanager
def gc_paused():
    """Python's cyclic garbage collector off for a block that makes many short-lived
    containers and no reference cycle: a tree's vertex and face lists, the query loop's
    point lists and find_nearest's result tuples. Each few hundred of them started a
    collection, and in a loaded Blender (its whole heap tracked) those made tolist 2.7x
    slower than with the collector off. Nothing is left uncollected: counting resumes
    after the block. Nested blocks leave it to the outermost."""
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


# How a surface becomes a tree that answers closest-point queries: Blender has the tree
# (mathutils.bvhtree.BVHTree, addon/bvh.py), so it is handed in (set_tree_builder, which
# the add-on's package calls on import) and this module imports nothing of Blender's.
_tree_builder = None


def set_tree_builder(build) -> None:
    """Measure through ``build(vertices (n, 3) float64, faces (m, 3) int64)``: a tree of the
    surface's triangles with mathutils BVHTree's ``find_nearest(point, distance=inf)``
    (location, normal, triangle index, distance; all None when nothing is within
    ``distance``)."""
    global _tree_builder
    _tree_builder = build


# The trees of the last few surfaces measured, by the identity of their arrays: a source
# is measured against each of its levels (and its parts' sources once per level of an
# asset), and building its tree again took a third of the engine's tree time. An entry
# holds weak references, so a freed array (whose id Python may give to a new one) never
# matches; the arrays are read, never written, while measured.
_TREE_CACHE_SIZE = 8
_tree_cache: list = []


def _build_tree(v: np.ndarray, f: np.ndarray):
    if _tree_builder is None:
        raise RuntimeError("no closest-point tree to measure with: the add-on's package installs "
                           "Blender's on import (addon/bvh.py)")
    found = _cached(_tree_cache, v, f, _tree_builder)
    if found is not None:
        return found
    with gc_paused():
        tree = _tree_builder(v, f)
    return _cache(_tree_cache, _TREE_CACHE_SIZE, v, f, _tree_builder, tree)


def _cached(cache: list, v: np.ndarray, f: np.ndarray, key):
    """The value ``cache`` holds for the surface (v, f), by array identity, and ``key``
    (moved to the newest end), or None. Entries: (weak v, weak f, key, value)."""
    for i, (v_ref, f_ref, entry_key, value) in enumerate(cache):
        if v_ref() is v and f_ref() is f and entry_key == key:
            cache.append(cache.pop(i))
            return value
    return None


def _cache(cache: list, size: int, v: np.ndarray, f: np.ndarray, key, value):
    """``value`` kept in ``cache`` for (v, f) and ``key``: the entries of freed surfaces
    dropped first, at most ``size`` kept, the oldest going. Returns ``value``."""
    cache[:] = _live(cache)
    cache.append((weakref.ref(v), weakref.ref(f), key, value))
    del cache[:-size]
    return value


def _live(cache: list) -> list:
    """The entries of a cache whose arrays are still alive: a freed surface's tree or
    samples are let go at the next insertion instead of when eight newer ones push them
    out (a scan's tree, or a million samples, is hundreds of megabytes)."""
    return [entry for entry in cache if entry[0]() is not None and entry[1]() is not None]


# Likewise the area samples of the last few surfaces: a source is sampled the same way
# for each of its levels (the same count and seed), and a posed character's joined
# source for each level of a frame. A hit gives the arrays (read-only) and a generator
# where the sampling left it, for the climb that draws from it next.
_SAMPLES_CACHE_SIZE = 8
_samples_cache: list = []
_used_cache: list = []  # and the vertices queried (_queried_vertices), by the same rule


def _sampled(v: np.ndarray, f: np.ndarray, n: int, seed: int) -> tuple:
    """(points (n, 3), triangles (n,), barycentric coordinates (n, 3), the generator
    after them): _sample_surface of (v, f) with _surface_rng(seed, v, f)."""
    found = _cached(_samples_cache, v, f, (n, seed))
    if found is None:
        rng = _surface_rng(seed, v, f)
        arrays = _sample_surface(v, f, n, rng)
        for a in arrays:
            a.setflags(write=False)
        found = _cache(_samples_cache, _SAMPLES_CACHE_SIZE, v, f, (n, seed), (*arrays, rng.bit_generator.state))
    *arrays, state = found
    rng = np.random.Generator(np.random.PCG64())
    rng.bit_generator.state = state
    return (*arrays, rng)


def _distances(tree, points: np.ndarray, with_faces: bool = False, radius: Optional[float] = None):
    """Exact distance from each point to the surface in ``tree``, (k,) float64; with
    ``with_faces`` also the index (k,) int64 of the tree's triangle the closest point is on.
    ``radius``: the search radius, when the caller knows about how far the points are (no
    pilot); None: from a pilot on a subset."""
    if len(points) == 0:
        return (np.empty(0), np.empty(0, dtype=np.int64)) if with_faces else np.empty(0)
    with gc_paused():
        return _queried(tree, points, with_faces, radius)


def _upper_quantile(values: np.ndarray) -> float:
    """The _PILOT_QUANTILE quantile of ``values`` (non-empty), rounded up to one of them:
    a search radius, which only decides how many queries are asked again (a point beyond
    it is searched without one), not what they find. np.quantile's interpolation cost
    more than the partition (20 ms of the engine's level reports)."""
    k = int(np.ceil(_PILOT_QUANTILE * (len(values) - 1)))
    return float(np.partition(values, k)[k])


def _queried(tree, points: np.ndarray, with_faces: bool, radius: Optional[float] = None) -> tuple:
    """_distances of a non-empty ``points``, the collector paused."""
    # Lists as tolist gives them: mathutils reads a list as fast as a tuple, and making
    # the tuples cost a third of the queries' own time.
    pts = points.tolist()
    find = tree.find_nearest
    if radius is None:
        pilot_count = min(_PILOT_POINTS, len(pts), max(_PILOT_MIN, len(pts) // _PILOT_SHARE))
        pilot_idx = np.linspace(0, len(pts) - 1, pilot_count).astype(np.int64)
        pilot = np.fromiter(map(_DISTANCE, map(find, map(pts.__getitem__, pilot_idx.tolist()))),
                            dtype=np.float64, count=pilot_count)
        radius = _upper_quantile(pilot) * _RADIUS_FACTOR
    # A floor keeps the radius positive when the surfaces coincide (all pilot distances 0).
    extent = float((points.max(axis=0) - points.min(axis=0)).max()) if len(points) > 1 else 1.0
    radius = max(radius, extent * 1e-6, 1e-12)
    # None (nothing within the radius) becomes NaN here and is re-queried unbounded.
    # map, itemgetter and fromiter keep the loop over the points in C: no bytecode and no
    # intermediate list per point.
    found = map(find, pts, itertools.repeat(radius))
    if not with_faces:
        d = np.fromiter(map(_DISTANCE, found), dtype=np.float64, count=len(pts))
        miss = np.flatnonzero(np.isnan(d))
        if len(miss):
            d[miss] = [find(pts[i])[3] for i in miss.tolist()]
        return d
    # (index, distance) pairs: one slice of find_nearest's tuple, flattened.
    hits = np.fromiter(itertools.chain.from_iterable(map(_INDEX_AND_DISTANCE, found)),
                       dtype=np.float64, count=2 * len(pts)).reshape(-1, 2)
    miss = np.flatnonzero(np.isnan(hits[:, 1]))
    if len(miss):
        hits[miss] = [find(pts[i])[2:] for i in miss.tolist()]
    return hits[:, 1], hits[:, 0].astype(np.int64)


def closest_points(v: np.ndarray, f: np.ndarray, points: np.ndarray) -> tuple:
    """For each point (k, 3), the triangle of (v, f) its closest point is on (k,) and that
    point's barycentric coordinates on it (k, 3)."""
    from ._core import core

    v = np.asarray(v, dtype=np.float64)
    f = np.asarray(f, dtype=np.int64)
    _, tri = _distances(_build_tree(v, f), np.asarray(points, dtype=np.float64), with_faces=True)
    bary, _ = core.geometry.closest_on_triangles(points, v[f[tri, 0]], v[f[tri, 1]], v[f[tri, 2]])
    return tri, bary


def bbox_diagonal(v: np.ndarray, f: np.ndarray) -> float:
    """The diagonal of the bounding box of the vertices ``f`` uses (what *_percent divide by)."""
    return _bbox_diagonal(np.asarray(v, dtype=np.float64), np.asarray(f))


def _bbox_diagonal(v: np.ndarray, f: np.ndarray) -> float:
    used = v[_queried_vertices(f, None)]
    return float(np.linalg.norm(used.max(0) - used.min(0)))


def _sample_count(v, f, samples_per_unit_area, n_samples) -> int:
    if n_samples is not None and samples_per_unit_area is not None:
        raise ValueError("give either n_samples or samples_per_unit_area, not both")
    if n_samples is not None:
        if int(n_samples) != n_samples or n_samples < 0:
            raise ValueError(f"n_samples must be a whole number >= 0, got {n_samples!r}")
        return int(n_samples)
    if samples_per_unit_area is not None:
        density = float(samples_per_unit_area)
        if not np.isfinite(density) or density < 0:
            raise ValueError(f"samples_per_unit_area must be finite and >= 0, got {samples_per_unit_area!r}")
        return int(np.ceil(_triangle_areas(v, f).sum() * density))
    return DEFAULT_SAMPLES


def _queried_vertices(f: np.ndarray, limit: Optional[int], v: Optional[np.ndarray] = None) -> np.ndarray:
    """The ids of the vertices ``f`` uses, or ``limit`` of them spread evenly over the ids
    (a mesh's vertex order follows its surface, so the subset does too). With the
    vertices ``v``, those only zero-area faces use are left out: such a face has no
    surface (the core drops it, core.prepare.ZERO_AREA_QUALITY), and a stray one far from
    the rest (a .blend's corners on a line) measured a LOD that dropped it at 64 % of its
    object's size."""
    from ._core import core

    if v is not None and len(f):
        surface = core.triangle_quality(v, f) >= core.prepare.ZERO_AREA_QUALITY
        if surface.any() and not surface.all():
            f = f[surface]
    # The ids in order, as np.unique gives them, without its sort of every corner.
    used = np.flatnonzero(np.bincount(f.ravel(), minlength=int(f.max()) + 1 if f.size else 0))
    if limit is not None and len(used) > limit:
        used = np.unique(used[np.linspace(0, len(used) - 1, max(int(limit), 1)).round().astype(np.int64)])
    return used


def _one_direction(v_a, f_a, seed, n_a, tree_b, shading=None, keep=None, b=None, vertex_limit=None,
                   climb_seeds=None) -> tuple:
    """(Hausdorff, mean, query points, normal angles or None) from surface a to the tree of
    surface b; with ``shading`` = (a's corner normals, b's vertices, faces and corner
    normals) also the normal angles at a's area samples. ``keep``: None, or (b's vertices
    and faces, or None when the closest points are not wanted, and a dict): the dict gets
    the per-point results (Sampled's fields without their src_/dst_ prefix). ``b``: a
    _Coincident of a and b: points on a triangle b has too, and vertices at a position b's
    triangles use, are at distance 0 on it without a search (a LOD keeps its source's
    untouched triangles exactly: a third of the engine's large parts' at LOD1).
    ``vertex_limit``: query at most that many of a's vertices (_queried_vertices);
    ``climb_seeds``: _climb's seeds of each kind (None: the report's, one per
    CLIMB_POINTS_PER_SEED points, at most CLIMB_SEEDS)."""
    samples, tri, bary, rng_a = _sampled(v_a, f_a, n_a, seed)
    used = _cached(_used_cache, v_a, f_a, vertex_limit)
    if used is None:  # (a source is measured against each of its levels: its vertices once)
        used = _queried_vertices(f_a, vertex_limit, v_a)
        used.setflags(write=False)
        _cache(_used_cache, _SAMPLES_CACHE_SIZE, v_a, f_a, vertex_limit, used)
    verts = v_a[used]
    wanted = shading is not None or (keep is not None and keep[0] is not None)
    d_samples, nearest, at = _distances_known(
        tree_b, samples, wanted, *(_on_same_triangles(tri, bary, f_a, b) if b is not None else (None, None, None)))
    angles = None
    if wanted:
        v_b, f_b = (shading[1], shading[2]) if shading is not None else keep[0]
        if shading is not None:
            at = _closest_bary(samples, nearest, v_b, f_b, at)
            angles = _normal_angles(tri, bary, nearest, at, shading[0], shading[3])
        else:
            at = _Deferred(_closest_bary, samples, nearest, v_b, f_b, at)
        if keep is not None and keep[0] is not None:
            keep[1].update(nearest=nearest, nearest_bary=at)
    if keep is not None:
        keep[1].update(triangle=tri, bary=bary, distance=d_samples)
    wanted = keep is not None and keep[0] is not None
    d_verts, vertex_nearest, vertex_at = _vertex_distances(tree_b, verts, used, wanted, b, d_samples)
    if wanted:
        keep[1].update(vertex_nearest=vertex_nearest,
                       vertex_nearest_bary=_Deferred(_closest_bary, verts, vertex_nearest, *keep[0], vertex_at))
    if keep is not None:
        keep[1].update(vertices=used, vertex_distance=d_verts)
    d_climbed, climbed, climbed_at = _climb(v_a, f_a, tri, bary, d_samples, used, d_verts, tree_b, rng_a,
                                            climb_seeds)
    if keep is not None:
        keep[1].update(climbed_triangle=climbed, climbed_bary=climbed_at, climbed_distance=d_climbed)
    hausdorff = float(max(d_samples.max(initial=0.0), d_verts.max(initial=0.0), d_climbed.max(initial=0.0)))
    # With no area samples (n_samples=0 or a zero-area surface) fall back to the vertices.
    mean = float(d_samples.mean()) if len(d_samples) else float(d_verts.mean())
    return hausdorff, mean, len(samples) + len(verts), angles


def _climb(v_a, f_a, tri, bary, d_samples, used, d_verts, tree_b, rng, seeds=None) -> tuple:
    """(distances (c,), triangles (c,), barycentric coordinates (c, 3)) of the points tried
    climbing from the farthest of a's area samples (on triangles ``tri`` at ``bary``, distances ``d_samples``) and of
    its vertices ``used`` (distances ``d_verts``; from each, on every triangle around it)
    towards the largest distance to b's tree: CLIMB_ROUNDS rounds of CLIMB_TRIES random
    points around each seed's best point so far (see CLIMB_SEEDS). ``seeds``: how many of
    each kind (None: one per CLIMB_POINTS_PER_SEED points, at most CLIMB_SEEDS). Seeds at
    distance 0 (a's surface on b's) are not climbed from."""
    points = len(d_samples) + len(d_verts)
    count = min(CLIMB_SEEDS, -(-points // CLIMB_POINTS_PER_SEED)) if seeds is None else int(seeds)
    seed_tri, seed_bary = [], []
    if count and len(d_samples):
        top = _largest(d_samples, count)
        top = top[d_samples[top] > 0]
        seed_tri.append(tri[top])
        seed_bary.append(bary[top])
    if count and len(d_verts):
        top = _largest(d_verts, count)
        seeded = np.zeros(len(v_a), dtype=bool)
        seeded[used[top[d_verts[top] > 0]]] = True
        faces, slot = np.nonzero(seeded[f_a])
        at = np.zeros((len(faces), 3))
        at[np.arange(len(faces)), slot] = 1.0
        seed_tri.append(faces)
        seed_bary.append(at)
    seeds = np.concatenate(seed_tri) if seed_tri else np.zeros(0, dtype=np.int64)
    if len(seeds) == 0:
        return np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros((0, 3))
    best = np.concatenate(seed_bary)
    # The points tried are about as far as their seeds: twice the farthest seed's distance
    # bounds nearly every query (no pilot; those beyond it are asked again without a bound).
    radius = _RADIUS_FACTOR * float(max(d_samples.max(initial=0.0), d_verts.max(initial=0.0)))
    trial_tri = np.repeat(seeds, CLIMB_TRIES)
    corners = v_a[f_a[trial_tri]]
    spread, found, tried = CLIMB_SPREAD, [], []
    for _ in range(CLIMB_ROUNDS):
        around = np.repeat(best, CLIMB_TRIES, axis=0)
        trial = np.clip(around + rng.normal(scale=spread, size=around.shape), 0.0, None)
        total = trial.sum(axis=1)
        lost = total <= 1e-12  # (every coordinate clipped: the seed's point again)
        trial[lost], total[lost] = around[lost], 1.0
        trial /= total[:, None]
        d = _distances(tree_b, np.einsum("ki,kij->kj", trial, corners), radius=radius)
        found.append(d)
        tried.append(trial)
        pick = d.reshape(-1, CLIMB_TRIES).argmax(axis=1)
        best = trial.reshape(-1, CLIMB_TRIES, 3)[np.arange(len(seeds)), pick]
        spread *= 0.5
    return np.concatenate(found), np.tile(trial_tri, CLIMB_ROUNDS), np.concatenate(tried)


def _largest(values: np.ndarray, count: int) -> np.ndarray:
    """np.argsort(values, kind="stable")[-count:] (the ``count`` largest, ties to the later
    index) without sorting them all: those at least the count-th largest, sorted."""
    if count >= len(values):
        return np.argsort(values, kind="stable")[-count:]
    kth = len(values) - count
    at = np.flatnonzero(values >= np.partition(values, kth)[kth])
    return at[np.argsort(values[at], kind="stable")][-count:]


def _vertex_distances(tree_b, verts, used, with_faces, b, d_samples) -> tuple:
    """_distances_known for a's vertices ``verts`` (k, 3), a's vertices ``used``: each
    position queried once. A mesh split along its UV seams and hard edges has several
    vertices at one position (an imported CAD engine: 55,843 vertices at 36,206
    positions), and each query is a Python call; the answer for a position is the same
    for all its copies. The search radius comes from the area samples' distances
    ``d_samples`` where there are enough of them (VERTEX_RADIUS_SAMPLES), as a pilot
    would measure it: no pilot. ``b``: a's _Coincident with b, or None."""
    from ._core import core

    if b is None:
        first, inverse = core.geometry.distinct_points(verts)
    else:  # (the same positions in the same order, from the ids already sorted)
        _, first, inverse = np.unique(b.ids_a[used], return_index=True, return_inverse=True)
        inverse = inverse.reshape(-1)
    distinct = verts[first]
    radius = None
    if len(d_samples) >= VERTEX_RADIUS_SAMPLES and d_samples.max() > 0:
        radius = _upper_quantile(d_samples) * _RADIUS_FACTOR
    found = _distances_known(tree_b, distinct, with_faces,
                             *(_on_same_vertices(b.ids_a[used[first]], b) if b is not None else (None, None, None)),
                             radius=radius)
    return tuple(None if x is None else x[inverse] for x in found)


class _Coincident(NamedTuple):
    """Where surface a meets surface b exactly: b's faces (m_b, 3) and both surfaces'
    vertex ids by position (core.geometry.position_ids, one sort for both directions)."""
    faces_b: np.ndarray
    ids_a: np.ndarray
    ids_b: np.ndarray


def _coincident(v_a, v_b, f_b) -> "_Coincident":
    """a's _Coincident with b (vertices ``v_a``; b's vertices ``v_b`` and faces ``f_b``);
    _coincident_back turns it round without sorting again."""
    from ._core import core

    ids_a, ids_b = core.geometry.position_ids(v_a, v_b)
    return _Coincident(f_b, ids_a, ids_b)


def _coincident_back(c: "_Coincident", f_a) -> "_Coincident":
    """The _Coincident of b with a, from a's with b and a's faces."""
    return _Coincident(f_a, c.ids_b, c.ids_a)


def _on_same_triangles(tri, bary, f_a, b: _Coincident) -> tuple:
    """For points at ``bary`` on a's triangles ``tri``: (k,) bool those on a triangle b has
    too, that triangle of b, and the points' barycentric coordinates on it."""
    from ._core import core

    match, corner = core.geometry.triangles_at_same_positions(b.ids_a, f_a, b.ids_b, b.faces_b)
    on = match[tri] >= 0
    at = np.zeros((int(on.sum()), 3))
    np.put_along_axis(at, corner[tri[on]], bary[on], axis=1)
    return on, match[tri[on]], at


def _on_same_vertices(point_ids, b: _Coincident) -> tuple:
    """For points of a with position ids ``point_ids``: (k,) bool those at a vertex b's
    triangles use, one triangle of b with that corner, and the one-hot barycentric
    coordinates there."""
    from ._core import core

    f_b = b.faces_b
    corner_face = np.repeat(np.arange(len(f_b)), 3)
    face_of, slot_of = np.full(len(b.ids_b), -1, dtype=np.int64), np.zeros(len(b.ids_b), dtype=np.int64)
    face_of[f_b.ravel()] = corner_face
    slot_of[f_b.ravel()] = np.tile(np.arange(3), len(f_b))
    used = np.flatnonzero(face_of >= 0)
    match = core.geometry.index_of(point_ids, b.ids_b[used])
    on = match >= 0
    vertex = used[match[on]]
    at = np.zeros((int(on.sum()), 3))
    at[np.arange(len(vertex)), slot_of[vertex]] = 1.0
    return on, face_of[vertex], at


def _distances_known(tree, points, with_faces, known=None, known_face=None, known_at=None,
                     radius: Optional[float] = None) -> tuple:
    """(distances (k,), nearest triangle (k,) or None, barycentric (k, 3) or None): the
    points ``known`` (bool, or None) are at distance 0 on ``known_face`` at ``known_at``;
    the tree is searched for the rest (``_distances``, with ``radius``). Barycentric
    coordinates come back only for the known points (NaN elsewhere: _closest_bary computes those)."""
    if known is None or not known.any():
        if not with_faces:
            return _distances(tree, points, radius=radius), None, None
        d, nearest = _distances(tree, points, with_faces=True, radius=radius)
        return d, nearest, None
    d = np.zeros(len(points))
    rest = np.flatnonzero(~known)
    if not with_faces:
        d[rest] = _distances(tree, points[rest], radius=radius)
        return d, None, None
    nearest = np.zeros(len(points), dtype=np.int64)
    at = np.full((len(points), 3), np.nan)
    nearest[known], at[known] = known_face, known_at
    d[rest], nearest[rest] = _distances(tree, points[rest], with_faces=True, radius=radius)
    return d, nearest, at


def _corner_normals(normals, f: np.ndarray, what: str) -> np.ndarray:
    n = np.asarray(normals, dtype=np.float64)
    if n.shape != (len(f), 3, 3):
        raise ValueError(f"{what} corner normals must be an (m, 3, 3) array for its {len(f)} triangles, "
                         f"got shape {n.shape}")
    if not np.isfinite(n).all():
        raise ValueError(f"{what} corner normals contain NaN or infinite values")
    return n


def _closest_bary(points, nearest, v_b, f_b, known=None) -> np.ndarray:
    """(k, 3) barycentric coordinates of each point's closest point on b's triangle
    ``nearest``; ``known``: (k, 3) those already known, NaN where not (_distances_known)."""
    from ._core import core

    todo = slice(None) if known is None else np.flatnonzero(np.isnan(known[:, 0]))
    on_b = f_b[nearest[todo]]
    at, _ = core.geometry.closest_on_triangles(points[todo], v_b[on_b[:, 0]], v_b[on_b[:, 1]], v_b[on_b[:, 2]])
    if known is None:
        return at
    out = known.copy()
    out[todo] = at
    return out


def _normal_angles(tri, bary, nearest, at, normals_a, normals_b) -> np.ndarray:
    """Degrees between a's shading normal at each sample (triangle ``tri``, barycentric
    ``bary``) and b's at the closest point (barycentric ``at``) on b's triangle ``nearest``."""
    from ._core import core

    shading = core.shading
    return shading.angles_degrees(shading.interpolate(normals_a, tri, bary),
                                  shading.interpolate(normals_b, nearest, at))


def _normal_keys(angles: np.ndarray) -> dict:
    from ._core import core

    summary = core.shading.angle_summary(angles)
    return {"normal_mean_degrees": summary["mean"], "normal_p95_degrees": summary["p95"],
            "normal_max_degrees": summary["max"], "normal_points": int(len(angles))}


def surface_deviation(src_vertices, src_faces, dst_vertices, dst_faces, *,
                      samples_per_unit_area=None, n_samples=None, seed=0, normals=None,
                      keep_samples=False, vertex_limit=None, climb_seeds=None) -> dict:
    """Two-sided Hausdorff and mean surface distance between two triangle meshes.

    src_*: the input (reference) mesh, whose bounding-box diagonal the percentages use;
    dst_*: the mesh compared with it (e.g. a LOD). vertices (n, 3) float, faces (m, 3) int.
    Sampling density per surface: ``n_samples`` points (or a pair: src's, dst's), or
    ``samples_per_unit_area`` points per unit of its area, or by default DEFAULT_SAMPLES;
    vertices are always added (at most ``vertex_limit`` of them a surface, spread over
    it, when given: a measurement repeated over many poses). ``climb_seeds``: seeds of
    the climb towards the largest distance (_climb) of each kind, area samples and
    vertices, a direction; None: the report's (CLIMB_SEEDS, fewer on small surfaces).
    normals: optional (src corner normals, dst corner normals), each (m, 3, 3) per
    triangle corner of its mesh: also the shading-normal deviation (normal_deviation's
    keys), from the closest points the src->dst distances found (no queries of its own).

    Returns a dict of floats (distances in mesh units unless *_percent):
      hausdorff, mean, hausdorff_percent, mean_percent, diagonal,
      hausdorff_src_to_dst, mean_src_to_dst, hausdorff_dst_to_src, mean_dst_to_src,
      points_src, points_dst (area samples and vertices measured per direction; the climb
      towards the largest distance, _climb, queries a few points more),
      seconds_src_to_dst, seconds_dst_to_src, seconds (wall time, tree builds included);
      with ``normals``: normal_mean_degrees, normal_p95_degrees, normal_max_degrees,
      normal_points; with ``keep_samples``: ``sampled``, a :class:`Sampled` (every
      point's own distance, where it lies and where its closest point is; the numbers
      above are the same with or without it).
    """
    t0 = time.perf_counter()
    vs, fs = _as_mesh(src_vertices, src_faces, "src")
    vd, fd = _as_mesh(dst_vertices, dst_faces, "dst")
    n_src_given, n_dst_given = n_samples if isinstance(n_samples, (tuple, list)) else (n_samples, n_samples)
    n_src = _sample_count(vs, fs, samples_per_unit_area, n_src_given)
    n_dst = _sample_count(vd, fd, samples_per_unit_area, n_dst_given)
    shading = None
    if normals is not None:
        shading = (_corner_normals(normals[0], fs, "src"), vd, fd, _corner_normals(normals[1], fd, "dst"))

    kept = ({}, {}) if keep_samples else None
    src_on_dst = _coincident(vs, vd, fd)
    h_sd, m_sd, k_src, angles = _one_direction(vs, fs, seed, n_src, _build_tree(vd, fd),
                                               shading, kept and ((vd, fd), kept[0]), b=src_on_dst,
                                               vertex_limit=vertex_limit, climb_seeds=climb_seeds)
    t1 = time.perf_counter()
    h_ds, m_ds, k_dst, _ = _one_direction(vd, fd, seed, n_dst, _build_tree(vs, fs),
                                          keep=kept and ((vs, fs), kept[1]), b=_coincident_back(src_on_dst, fs),
                                          vertex_limit=vertex_limit, climb_seeds=climb_seeds)
    t2 = time.perf_counter()

    diagonal = _bbox_diagonal(vs, fs)
    hausdorff = max(h_sd, h_ds)
    mean = 0.5 * (m_sd + m_ds)
    scale = 100.0 / diagonal if diagonal > 0 else float("nan")
    report = {
        "hausdorff": hausdorff,
        "mean": mean,
        "hausdorff_percent": hausdorff * scale,
        "mean_percent": mean * scale,
        "diagonal": diagonal,
        "hausdorff_src_to_dst": h_sd,
        "mean_src_to_dst": m_sd,
        "hausdorff_dst_to_src": h_ds,
        "mean_dst_to_src": m_ds,
        "points_src": k_src,
        "points_dst": k_dst,
        "seconds_src_to_dst": t1 - t0,
        "seconds_dst_to_src": t2 - t1,
        "seconds": time.perf_counter() - t0,
    }
    if angles is not None:
        report.update(_normal_keys(angles))
    if kept is not None:
        report["sampled"] = Sampled(**{f"src_{k}": v for k, v in kept[0].items()},
                                    **{f"dst_{k}": v for k, v in kept[1].items()})
    return report


def part_deviations(src_vertices, src_faces, src_part, dst_vertices, dst_faces, dst_part, parts: int, *,
                    n_samples, seed=0, vertex_limit=None, find_shared=True) -> tuple:
    """Two surfaces made of the same ``parts`` parts (an asset and its LOD, say), measured
    in one go: (hausdorff (parts,), mean (parts,)), each part's two-sided Hausdorff and mean
    distance as surface_deviation defines them, from the points on that part of either
    surface (their closest points may be on any part). NaN for a part neither surface has.

    src_part (m_src,) / dst_part (m_dst,): the part (0 .. parts - 1) of each triangle.
    n_samples, seed, vertex_limit: as surface_deviation takes them, for the whole surfaces;
    a single part gives surface_deviation's numbers (the mean to rounding).
    ``find_shared=False``: no search for the triangles and vertices both surfaces have
    (at distance 0 without a query: _one_direction), which sorts both whole surfaces;
    for surfaces that share little (posed ones) and few queries. One tree and one query loop
    per direction, however many parts: the posed distance of a 59-part character took
    2,832 measurements of a few hundred points a frame, each paying its own trees."""
    vs, fs = _as_mesh(src_vertices, src_faces, "src")
    vd, fd = _as_mesh(dst_vertices, dst_faces, "dst")
    n_src, n_dst = n_samples if isinstance(n_samples, (tuple, list)) else (n_samples, n_samples)
    sides = []
    src_on_dst = _coincident(vs, vd, fd) if find_shared else None
    for (v_a, f_a, part_a, n_a), (v_b, f_b), b in (
            ((vs, fs, src_part, n_src), (vd, fd), src_on_dst),
            ((vd, fd, dst_part, n_dst), (vs, fs), None if src_on_dst is None else _coincident_back(src_on_dst, fs))):
        part_a = np.asarray(part_a, dtype=np.int64)
        kept = {}
        _one_direction(v_a, f_a, seed, _sample_count(v_a, f_a, None, n_a),
                       _build_tree(v_b, f_b), keep=(None, kept), b=b, vertex_limit=vertex_limit)
        vertex_part = np.empty(len(v_a), dtype=np.int64)
        vertex_part[f_a.ravel()] = np.repeat(part_a, 3)
        sides.append(_per_part(part_a[kept["triangle"]], kept["distance"],
                               vertex_part[kept["vertices"]], kept["vertex_distance"], parts,
                               part_a[kept["climbed_triangle"]], kept["climbed_distance"]))
    (h_sd, m_sd), (h_ds, m_ds) = sides
    return np.fmax(h_sd, h_ds), 0.5 * (m_sd + m_ds)


def _per_part(sample_part, d_samples, vertex_part, d_vertices, parts: int, climbed_part=None,
              d_climbed=None) -> tuple:
    """(largest, mean) distance per part of one direction: the largest over its samples,
    vertices and climbed points, the mean over its area samples, over its vertices when it
    has none (as _one_direction falls back); NaN where neither."""
    largest = np.full(parts, -np.inf)
    np.maximum.at(largest, sample_part, d_samples)
    np.maximum.at(largest, vertex_part, d_vertices)
    if climbed_part is not None:
        np.maximum.at(largest, climbed_part, d_climbed)
    count = np.bincount(sample_part, minlength=parts)
    mean = np.bincount(sample_part, weights=d_samples, minlength=parts) / np.maximum(count, 1)
    v_count = np.bincount(vertex_part, minlength=parts)
    v_mean = np.bincount(vertex_part, weights=d_vertices, minlength=parts) / np.maximum(v_count, 1)
    mean = np.where(count > 0, mean, np.where(v_count > 0, v_mean, np.nan))
    largest[np.isneginf(largest)] = np.nan
    return largest, mean


def region_deviation(sampled: Sampled, src_faces, region) -> dict:
    """The distances over a region of src's triangles (e.g. what a shape key moves), both
    ways, from the points surface_deviation(keep_samples=True) measured (``sampled``):
    src's samples on those triangles and the vertices they use, to dst; dst's samples and
    vertices whose closest point of src is on them, to src (a LOD triangle across the
    region counts, whichever of it the region's own samples miss).

    ``src_faces``: src's (m, 3) triangles; ``region``: (m,) bool. Returns, in mesh units:
    region_hausdorff (the largest over both directions' points in the region),
    region_mean (the mean of each direction's mean over its area samples there, as the
    two-sided mean; over its vertices when no sample fell there), region_mean_src_to_dst,
    region_mean_dst_to_src, region_samples_src, region_samples_dst (area samples in the
    region per direction); NaN where no point is in the region."""
    f = np.asarray(src_faces, dtype=np.int64)
    mask = np.asarray(region, dtype=bool)
    if mask.shape != (len(f),):
        raise ValueError(f"region must be a ({len(f)},) bool array, one per src triangle, got shape {mask.shape}")
    if sampled.dst_nearest is None or sampled.dst_vertex_nearest is None:
        raise ValueError("a region needs where dst's points are closest to src: measure with keep_samples=True")
    in_vertex = np.zeros(int(f.max(initial=-1)) + 1, dtype=bool)
    in_vertex[f[mask]] = True  # a vertex is in the region when a triangle of the region uses it
    src = _region_stats(sampled.src_distance, mask[sampled.src_triangle], sampled.src_vertex_distance,
                        in_vertex[sampled.src_vertices],
                        None if sampled.src_climbed_triangle is None else sampled.src_climbed_distance[
                            mask[sampled.src_climbed_triangle]])
    dst = _region_stats(sampled.dst_distance, mask[sampled.dst_nearest], sampled.dst_vertex_distance,
                        mask[sampled.dst_vertex_nearest])
    largest, means = np.array([src[0], dst[0]]), np.array([src[1], dst[1]])
    return {"region_hausdorff": float(np.nanmax(largest)) if np.isfinite(largest).any() else float("nan"),
            "region_mean": float(np.nanmean(means)) if np.isfinite(means).any() else float("nan"),
            "region_mean_src_to_dst": src[1], "region_mean_dst_to_src": dst[1],
            "region_samples_src": src[2], "region_samples_dst": dst[2]}


def _region_stats(d_samples, in_samples, d_verts, in_verts, d_climbed=None) -> tuple:
    """(largest distance, mean distance, area samples) over the points in a region: the
    largest over its samples, vertices and climbed points (``d_climbed``: those in it),
    the mean over its area samples (over its vertices when no sample fell in it); NaN
    when no sample or vertex is in it."""
    picked, picked_verts = np.asarray(d_samples)[in_samples], np.asarray(d_verts)[in_verts]
    if not len(picked) and not len(picked_verts):
        return float("nan"), float("nan"), 0
    largest = float(max(picked.max(initial=0.0), picked_verts.max(initial=0.0),
                        0.0 if d_climbed is None else np.max(d_climbed, initial=0.0)))
    mean = float(picked.mean()) if len(picked) else float(picked_verts.mean())
    return largest, mean, int(len(picked))


def normal_deviation(src_vertices, src_faces, src_normals, dst_vertices, dst_faces, dst_normals, *,
                     samples_per_unit_area=None, n_samples=None, seed=0) -> dict:
    """How far dst's shading normals are from src's: the angle, in degrees, between src's
    shading normal at area-uniform samples of its surface and dst's at the closest point
    of dst to each sample.

    *_normals: (m, 3, 3) the unit normal of each triangle corner of that mesh as it is
    shaded (Blender's ``corner_normals``: custom split normals, smooth or flat; for
    arrays without Blender, core.shading.corner_normals); each is interpolated with the
    barycentric coordinates of the point on its triangle. The samples are the ones
    surface_deviation takes on src (same seed and count), and so is the closest point;
    surface_deviation(normals=...) gives the same numbers. Where dst has a hard edge the
    closest point is on one side of it, and a sample near the source's matching hard
    edge may find the other side: those few samples make the max (and, when there are
    many such edges, the 95th percentile), not the mean.

    Returns {normal_mean_degrees, normal_p95_degrees, normal_max_degrees, normal_points
    (samples), seconds}.
    """
    t0 = time.perf_counter()
    vs, fs = _as_mesh(src_vertices, src_faces, "src")
    vd, fd = _as_mesh(dst_vertices, dst_faces, "dst")
    ns, nd = _corner_normals(src_normals, fs, "src"), _corner_normals(dst_normals, fd, "dst")
    samples, tri, bary = _sample_surface(vs, fs, _sample_count(vs, fs, samples_per_unit_area, n_samples),
                                         _surface_rng(seed, vs, fs))
    _, nearest = _distances(_build_tree(vd, fd), samples, with_faces=True)
    report = _normal_keys(_normal_angles(tri, bary, nearest, _closest_bary(samples, nearest, vd, fd), ns, nd))
    report["seconds"] = time.perf_counter() - t0
    return report


def mesh_report(src_v, src_f, dst_v, dst_f, **deviation_options) -> dict:
    """surface_deviation(src, dst) plus the triangle quality of dst and both face counts.

    Keys: everything surface_deviation returns, plus mean_quality, min_quality,
    sliver_percent (core.quality_summary of dst), src_faces, dst_faces.
    """
    from ._core import core  # (imported where it is used, as elsewhere in this module)

    report = surface_deviation(src_v, src_f, dst_v, dst_f, **deviation_options)
    report.update(core.quality_summary(np.asarray(dst_v, dtype=np.float64), np.asarray(dst_f)))
    report["src_faces"] = int(np.shape(src_f)[0])
    report["dst_faces"] = int(np.shape(dst_f)[0])
    return report


def normal_keys_of(sampled: Sampled, src_normals, dst_normals) -> dict:
    """normal_deviation's keys from the closest points a measurement kept (``sampled``,
    surface_deviation(keep_samples=True)), with no query: the same numbers as measuring
    with normals=(src_normals, dst_normals) gives."""
    return _normal_keys(_normal_angles(sampled.src_triangle, sampled.src_bary, sampled.src_nearest,
                                       sampled.src_nearest_bary, src_normals, dst_normals))
