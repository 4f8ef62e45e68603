# SPDX-License-Identifier: GPL-3.0-or-later
"""Where each LOD may switch in, from its measured deviation, in every engine's terms.

No bpy here: floats and NumPy arrays in and out (commit.py passes Blender's numbers in).

The idea: LOD i differs from the source by at most ε_i (its measured two-sided Hausdorff
distance, scene units). Seen from distance D with a perspective camera of vertical field
of view θ on a screen H pixels high, a length ε across the view covers

    p(ε, D) = ε · H / (2 · D · tan(θ/2))    pixels,

so LOD i may be drawn once p(ε_i, D) ≤ τ (the pixel budget), i.e. from the distance

    D_i = ε_i · H / (2 · τ · tan(θ/2))                                  (switch_distances)

on. The source (LOD0, ε = 0) is drawn from D = 0. Drawing nothing is treated as one more
level whose error is the object's whole diameter 2R (R: bounding-sphere radius), so the
object is culled from D_cull = R · H / (τ · tan(θ/2)) on, where it is τ pixels across.
The distances are made non-decreasing along the chain (a running maximum): a coarser
level never switches in before a finer one, even where the sampled Hausdorff distances
came out the other way round; a level whose range is then empty is simply never drawn.

The engines want these switch points as a share of the screen height, not a distance.
At distance D a length L covers L / (2 · D · tan(θ/2)) of the screen's height
(:func:`screen_fraction`), and at D_i that is L · τ / (ε_i · H): the screen fractions do
not depend on θ, nor on the scene's unit; only the distances do.

* glTF MSFT_lod (KhronosGroup/glTF, extensions/2.0/Vendor/MSFT_lod/README.md): the node
  with ``MSFT_lod`` is the highest level, ``ids`` the lower ones in order, and
  ``extras.MSFT_screencoverage`` holds one value per level, "LOD0 rendered from 1.0 to
  c_0, LOD1 from c_0 to c_1, ..., nothing below the last": c_i is where level i hands
  over, i.e. the coverage at D_{i+1} (the last one at D_cull). The README does not
  define coverage beyond that example; we use the projected bounding-sphere diameter
  over the screen height, 2R / (2 · D · tan(θ/2)), the same measure as Unreal's.
* Unreal (Engine/Source/Runtime/Engine/Private/SceneManagement.cpp,
  ComputeBoundsScreenSize): screen size = 2 · max(½·P[0][0], ½·P[1][1]) · R / D, P the
  projection matrix; for a landscape view that is R / (D · tan(θ/2)): the projected
  bounds (sphere) diameter over the screen height. LOD i is used while the screen size
  is at most ScreenSize[i] (and above ScreenSize[i+1]); ScreenSize[0] is no switch
  point, by convention 1.0 (kept at least LOD1's, so the list never increases).
* Unity (LODGroup; UnityCsReference LODUtility.DistanceToRelativeHeight):
  relative height = size · ½ / (D · tan(fov/2)) with size = LODGroup.size (the largest
  side of the group's bounding box; world size × the largest axis scale) and D divided
  by QualitySettings.lodBias. ``LOD[i].screenRelativeTransitionHeight`` is the height
  below which level i hands over to i+1 (the last level: to nothing), so it is the
  height at D_{i+1} (the last at D_cull), like MSFT's list.
* Godot 4 (GeometryInstance3D.visibility_range_begin / _end, distances from the camera
  to the instance's bounds centre, 0 = no limit): level i gets [D_i, D_{i+1}], the last
  [D_n, D_cull]; these do depend on θ and H (DEFAULT_* below: state yours).

Screen fractions above 1 are kept as they come (up to MAX_SCREEN_FRACTION): a level
whose error is visible only when the object is bigger than the screen may switch in
before it even fills it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

# The view's defaults: the settings pixel_error, screen_height and vertical_fov
# (addon/pure/settings.py; --pixel-error, --screen-height, --fov) start from them.
DEFAULT_PIXEL_ERROR = 1.0  # τ: the largest error allowed on screen, pixels
DEFAULT_SCREEN_HEIGHT = 1080  # H: the screen's height, pixels (1080p)
DEFAULT_VERTICAL_FOV_DEGREES = 60.0  # θ: the camera's vertical field of view, degrees
UNREAL_LOD0_SCREEN_SIZE = 1.0  # Unreal's convention for LOD0 (not a switch point)
# Screen fractions are capped here: a level that may switch in at distance 0 (its
# measured error is 0, say on a flat part) would otherwise get an infinite one.
MAX_SCREEN_FRACTION = 1000.0


@dataclass(frozen=True)
class Bounds:
    """A mesh's bounds in its own units: bounding box centre, the radius of the sphere
    about that centre holding every vertex, the box's largest side and its diagonal."""
    center: np.ndarray
    radius: float
    size: float
    diagonal: float


def mesh_bounds(vertices: np.ndarray, faces: Optional[np.ndarray] = None) -> Bounds:
    """Bounds of the vertices used by ``faces`` (all vertices when None), scene units.

    The diagonal is the one measure.py's percentages are relative to; the sphere is
    centred on the box like Unreal's static-mesh bounds."""
    v = np.asarray(vertices, dtype=np.float64)
    if faces is not None and len(faces):
        v = v[np.unique(np.asarray(faces))]
    if len(v) == 0:
        raise ValueError("mesh_bounds: the mesh has no vertices")
    lo, hi = v.min(axis=0), v.max(axis=0)
    center = (lo + hi) / 2.0
    return Bounds(center=center, radius=float(np.linalg.norm(v - center, axis=1).max()),
                  size=float((hi - lo).max()), diagonal=float(np.linalg.norm(hi - lo)))


def deviation_from_percent(hausdorff_percent: Sequence, diagonal: float) -> np.ndarray:
    """ε per level (scene units) from measured Hausdorff distances in percent of the
    source's bounding-box diagonal (the report's ``hausdorff_percent``).

    A level without a measurement (None or NaN) is a ValueError: a switch distance
    needs the measured error (turn Measure Deviation on); nothing is guessed."""
    values = [math.nan if p is None else float(p) for p in hausdorff_percent]
    eps = np.asarray(values, dtype=np.float64) * (float(diagonal) / 100.0)
    missing = np.flatnonzero(~np.isfinite(eps))
    if len(missing):
        raise ValueError(f"no measured deviation for level(s) {missing.tolist()}: switch distances "
                         f"need the measured Hausdorff distance (Measure Deviation on)")
    if (eps < 0).any():
        raise ValueError(f"negative deviation {eps.min()}")
    return eps


def _half_tan(vertical_fov_degrees: float) -> float:
    fov = float(vertical_fov_degrees)
    if not 0.0 < fov < 180.0:
        raise ValueError(f"vertical field of view must be in (0, 180) degrees, got {fov}")
    return math.tan(math.radians(fov) / 2.0)


def _check_screen(pixel_error: float, screen_height: float) -> None:
    if not pixel_error > 0:
        raise ValueError(f"pixel error must be > 0 pixels, got {pixel_error}")
    if not screen_height > 0:
        raise ValueError(f"screen height must be > 0 pixels, got {screen_height}")


def switch_distances(eps: Sequence, pixel_error: float = DEFAULT_PIXEL_ERROR,
                     screen_height: float = DEFAULT_SCREEN_HEIGHT,
                     vertical_fov_degrees: float = DEFAULT_VERTICAL_FOV_DEGREES) -> np.ndarray:
    """D_i = ε_i · H / (2 τ tan(θ/2)), made non-decreasing (running maximum): from how far
    away (scene units, from the bounds centre) each level's error ε_i (scene units) is at
    most τ pixels on an H-pixel-high screen with vertical field of view θ (degrees).
    ε = 0 (the source) gives 0."""
    _check_screen(pixel_error, screen_height)
    e = np.asarray(eps, dtype=np.float64)
    raw = e * float(screen_height) / (2.0 * float(pixel_error) * _half_tan(vertical_fov_degrees))
    return np.maximum.accumulate(raw) if len(raw) else raw


def cull_distance(radius: float, pixel_error: float = DEFAULT_PIXEL_ERROR,
                  screen_height: float = DEFAULT_SCREEN_HEIGHT,
                  vertical_fov_degrees: float = DEFAULT_VERTICAL_FOV_DEGREES) -> float:
    """The distance (scene units) from which the whole object, diameter 2R, is at most τ
    pixels across: R · H / (τ tan(θ/2)), the switch distance of 'nothing' (ε = 2R)."""
    return float(switch_distances([2.0 * float(radius)], pixel_error, screen_height, vertical_fov_degrees)[0])


def screen_fraction(length: float, distances: Sequence,
                    vertical_fov_degrees: float = DEFAULT_VERTICAL_FOV_DEGREES) -> np.ndarray:
    """The share of the screen's height a length (scene units) covers at each distance:
    L / (2 D tan(θ/2)), at most MAX_SCREEN_FRACTION (so D = 0 gives that)."""
    d = np.asarray(distances, dtype=np.float64)
    with np.errstate(divide="ignore"):
        return np.minimum(float(length) / (2.0 * d * _half_tan(vertical_fov_degrees)), MAX_SCREEN_FRACTION)


def handover_points(distances: Sequence, cull: float) -> np.ndarray:
    """Where each level hands over (scene units): D_1 .. D_n, then the cull distance."""
    d = np.asarray(distances, dtype=np.float64)
    return np.append(d[1:], max(float(cull), float(d[-1]) if len(d) else 0.0))


def msft_screen_coverage(distances: Sequence, cull: float, radius: float,
                         vertical_fov_degrees: float = DEFAULT_VERTICAL_FOV_DEGREES) -> np.ndarray:
    """``extras.MSFT_screencoverage``: one value per level, the projected bounding-sphere
    diameter over the screen height where level i hands over (level n: to nothing)."""
    return screen_fraction(2.0 * float(radius), handover_points(distances, cull), vertical_fov_degrees)


def unreal_screen_sizes(distances: Sequence, radius: float,
                        vertical_fov_degrees: float = DEFAULT_VERTICAL_FOV_DEGREES) -> np.ndarray:
    """Unreal's LOD screen sizes: the projected bounds diameter 2R over the screen height
    at the distance each level switches in; LOD0's is UNREAL_LOD0_SCREEN_SIZE (or LOD1's
    when that is larger), since LOD0 has no switch point."""
    sizes = screen_fraction(2.0 * float(radius), distances, vertical_fov_degrees)
    if len(sizes):
        sizes[0] = max(UNREAL_LOD0_SCREEN_SIZE, float(sizes[1]) if len(sizes) > 1 else 0.0)
    return sizes


def unity_transition_heights(distances: Sequence, cull: float, size: float,
                             vertical_fov_degrees: float = DEFAULT_VERTICAL_FOV_DEGREES) -> np.ndarray:
    """Unity's ``LOD.screenRelativeTransitionHeight`` per level: the LODGroup size (the
    bounding box's largest side) over the screen height where level i hands over to
    i+1 (the last: to nothing); at lodBias 1."""
    return screen_fraction(float(size), handover_points(distances, cull), vertical_fov_degrees)


def godot_visibility_ranges(distances: Sequence, cull: float) -> tuple:
    """Godot 4's (visibility_range_begin, visibility_range_end) per level, scene units:
    [D_i, D_{i+1}], the last level [D_n, D_cull]; LOD0 begins at 0 (no lower limit)."""
    d = np.asarray(distances, dtype=np.float64)
    return d.copy(), handover_points(d, cull)


def chain_switch_data(hausdorff_percent: Sequence, vertices: np.ndarray, faces: np.ndarray,
                      world_scale: float = 1.0, pixel_error: float = DEFAULT_PIXEL_ERROR,
                      screen_height: float = DEFAULT_SCREEN_HEIGHT,
                      vertical_fov_degrees: float = DEFAULT_VERTICAL_FOV_DEGREES) -> dict:
    """Everything above for one chain: ``hausdorff_percent`` per level, LOD0 first (0.0),
    the source's vertices and faces in its own units, and ``world_scale``, the factor from
    those to scene units (an object's largest axis scale: conservative when the scale is
    not uniform). Returns plain floats and lists (JSON-ready):
    {pixel_error, screen_height, vertical_fov_degrees, bounding_sphere_radius,
     bounding_box_size, deviation: [ε_i], switch_distance: [D_i], cull_distance,
     msft_screen_coverage, unreal_screen_size, unity_transition_height,
     godot_visibility_range_begin, godot_visibility_range_end} (lists per level)."""
    scale = abs(float(world_scale))
    bounds = mesh_bounds(vertices, faces)
    eps = deviation_from_percent(hausdorff_percent, bounds.diagonal) * scale
    return switch_data(eps, bounds.radius * scale, bounds.size * scale, pixel_error=pixel_error,
                       screen_height=screen_height, vertical_fov_degrees=vertical_fov_degrees)


def switch_data(eps: Sequence, radius: float, size: float, pixel_error: float = DEFAULT_PIXEL_ERROR,
                screen_height: float = DEFAULT_SCREEN_HEIGHT,
                vertical_fov_degrees: float = DEFAULT_VERTICAL_FOV_DEGREES) -> dict:
    """:func:`chain_switch_data` from the deviations themselves: ``eps`` per level, LOD0
    first (0.0), and the bounding sphere's ``radius`` and the box's largest side ``size``,
    all in scene units (an asset's: addon/asset.py)."""
    eps = np.asarray(eps, dtype=np.float64)
    radius, size = float(radius), float(size)
    view = dict(pixel_error=pixel_error, screen_height=screen_height, vertical_fov_degrees=vertical_fov_degrees)
    d = switch_distances(eps, **view)
    cull = max(cull_distance(radius, **view), float(d[-1]))
    begin, end = godot_visibility_ranges(d, cull)
    return {
        "pixel_error": float(pixel_error),
        "screen_height": float(screen_height),
        "vertical_fov_degrees": float(vertical_fov_degrees),
        "bounding_sphere_radius": radius,
        "bounding_box_size": size,
        "deviation": eps.tolist(),
        "switch_distance": d.tolist(),
        "cull_distance": cull,
        "msft_screen_coverage": msft_screen_coverage(d, cull, radius, vertical_fov_degrees).tolist(),
        "unreal_screen_size": unreal_screen_sizes(d, radius, vertical_fov_degrees).tolist(),
        "unity_transition_height": unity_transition_heights(d, cull, size, vertical_fov_degrees).tolist(),
        "godot_visibility_range_begin": begin.tolist(),
        "godot_visibility_range_end": end.tolist(),
    }


PER_LEVEL_KEYS = ("deviation", "switch_distance", "msft_screen_coverage", "unreal_screen_size",
                  "unity_transition_height", "godot_visibility_range_begin", "godot_visibility_range_end")


def per_level(data: dict) -> list:
    """:func:`chain_switch_data`'s lists as one dict per level (LOD0 first)."""
    n = len(data["switch_distance"])
    return [{key: data[key][i] for key in PER_LEVEL_KEYS} for i in range(n)]
