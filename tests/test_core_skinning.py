"""core.skinning: sample poses of a rig, pose offsets in the error, weights fitted to poses.

A two-bone tube built here (no Blender): the lower bone turns about the elbow at z = 1,
weights blend linearly over the elbow's neighbourhood.
"""
import numpy as np
import pytest

import core
from core import skinning
from surface_distance import mean_distance, nearest_faces


def tube(around=32, rings=60, length=2.0, radius=0.2):
    t = np.linspace(0, 2 * np.pi, around, endpoint=False)
    z = np.linspace(0, length, rings)
    V = np.array([[radius * np.cos(a), radius * np.sin(a), zz] for zz in z for a in t])
    F = []
    for r in range(rings - 1):
        for k in range(around):
            a, b = r * around + k, r * around + (k + 1) % around
            c, d = a + around, b + around
            F += [[a, b, d], [a, d, c]]
    lower = np.clip((V[:, 2] - 0.8) / 0.4, 0, 1)  # blend over z in [0.8, 1.2]
    W = np.stack([1 - lower, lower], axis=1)
    return V, np.array(F), W


def rig():
    rest = np.stack([np.eye(4), np.eye(4)])
    rest[1, 2, 3] = 1.0  # the lower bone's head at the elbow
    return rest, np.array([-1, 0])


def bend(angle_deg):
    """Deform matrices: the upper bone still, the lower one turned about x at the elbow."""
    a = np.radians(angle_deg)
    R = np.eye(4)
    R[1:3, 1:3] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    T, Ti = np.eye(4), np.eye(4)
    T[2, 3], Ti[2, 3] = 1.0, -1.0
    return np.stack([np.eye(4), T @ R @ Ti])


def test_skin_is_linear_blend_and_identity_at_rest():
    V, _, W = tube(8, 6)
    assert np.allclose(skinning.skin(V, W, np.stack([np.eye(4)] * 2)), V)
    M = bend(30)
    expected = W[:, :1] * V + W[:, 1:] * (V @ M[1, :3, :3].T + M[1, :3, 3])
    assert np.allclose(skinning.skin(V, W, M), expected)
    # Rows are normalised like Blender's Armature modifier; no weight, no move.
    assert np.allclose(skinning.skin(V, 3 * W, M), expected)
    assert np.allclose(skinning.skin(V, 0 * W, M), V)


def test_random_poses_keep_children_attached_and_turn_within_the_angle():
    rest, parents = rig()
    poses = skinning.random_poses(rest, parents, count=20, max_angle=40.0, seed=3)
    assert poses.shape == (20, 2, 4, 4)
    elbow = np.array([0, 0, 1.0, 1])
    for M in poses:
        # The elbow moves with the upper bone and stays the lower bone's pivot.
        assert np.allclose(M[0] @ elbow, M[1] @ elbow)
        for b in range(2):
            R = M[b, :3, :3]
            assert np.allclose(R @ R.T, np.eye(3), atol=1e-9)
        relative = np.linalg.inv(M[0, :3, :3]) @ M[1, :3, :3]
        angle = np.degrees(np.arccos(np.clip((np.trace(relative) - 1) / 2, -1, 1)))
        assert angle <= 40.0 + 1e-6
    assert not np.allclose(poses[0], poses[1])  # different poses
    # A child listed before its parent is still posed after it: still attached.
    child_first = skinning.random_poses(rest[::-1], np.array([1, -1]), count=5, seed=3)
    for M in child_first:
        assert np.allclose(M[1] @ elbow, M[0] @ elbow)


def test_pose_offsets_are_error_only_and_checked():
    V, F, W = tube(16, 20)
    poses = np.stack([bend(40), bend(-40)])
    offsets = skinning.pose_offsets(V, W, poses)
    res = core.simplify(V, F, ratio=0.2, vertex_attributes={"skin": W}, pose_offsets=offsets, pose_weight=4.0)
    assert set(res.vertex_attributes) == {"skin"}
    with pytest.raises(ValueError, match="pose_offsets"):
        core.simplify(V, F, ratio=0.2, pose_offsets=offsets[:, :5])
    with pytest.raises(ValueError, match="pose_weight"):
        core.simplify(V, F, ratio=0.2, pose_offsets=offsets, pose_weight=-1)


@pytest.fixture(scope="module")
def bent_lods():
    V, F, W = tube()
    rest, parents = rig()
    train = skinning.random_poses(rest, parents, count=8, seed=0)
    # Measured in poses the run never saw: the elbow bent both ways, and twisted.
    test = [bend(60), bend(-45), bend(35)]
    offsets = skinning.pose_offsets(V, W, train)
    plain = core.simplify(V, F, ratio=0.04, vertex_attributes={"skin": W}, normalize_attributes=("skin",))
    posed = core.simplify(V, F, ratio=0.04, vertex_attributes={"skin": W}, normalize_attributes=("skin",),
                          pose_offsets=offsets, pose_weight=4.0)
    return V, F, W, train, test, plain, posed


def posed_error(V, F, W, lod_v, lod_f, lod_w, poses):
    out = []
    for M in poses:
        out.append(mean_distance(skinning.skin(V, W, M), skinning.skin(lod_v, lod_w, M), lod_f))
    return float(np.mean(out))


def test_poses_in_the_error_make_the_posed_lod_closer(bent_lods):
    V, F, W, _, test, plain, posed = bent_lods
    assert abs(len(plain.faces) - len(posed.faces)) <= 1
    e_plain = posed_error(V, F, W, plain.vertices, plain.faces, plain.vertex_attributes["skin"], test)
    e_posed = posed_error(V, F, W, posed.vertices, posed.faces, posed.vertex_attributes["skin"], test)
    assert e_posed < 0.95 * e_plain, (e_posed, e_plain)


def test_fitted_weights_are_closer_posed_and_leave_the_rest_shape(bent_lods):
    V, F, W, train, test, plain, _ = bent_lods
    points, weights = skinning.surface_samples(V, F, W, 6000, seed=1)
    tri, bary, _ = nearest_faces(points, plain.vertices, plain.faces)
    w0 = plain.vertex_attributes["skin"]
    fitted = skinning.fit_weights(plain.vertices, plain.faces, w0, points, weights, tri, bary, train)
    assert fitted.shape == w0.shape
    assert fitted.min() >= 0 and np.allclose(fitted.sum(axis=1), 1.0)
    rest = np.stack([np.eye(4)] * 2)
    assert np.allclose(skinning.skin(plain.vertices, fitted, rest), plain.vertices)
    before = posed_error(V, F, W, plain.vertices, plain.faces, w0, test)
    after = posed_error(V, F, W, plain.vertices, plain.faces, fitted, test)
    assert after < 0.99 * before, (after, before)  # measured 0.973x on this tube


def test_posed_gap_ranks_weights_as_the_posed_distance_does(bent_lods):
    """posed_gap, what Source Armature checks a coarse level with: at rest, the mean
    distance from the source points to the LOD points they were matched to; in poses the
    fitted weights score lower than the interpolated ones, as they measure closer."""
    V, F, W, train, test, plain, _ = bent_lods
    points, weights = skinning.surface_samples(V, F, W, 6000, seed=1)
    tri, bary, distance = nearest_faces(points, plain.vertices, plain.faces)
    w0 = plain.vertex_attributes["skin"]
    at_rest = skinning.posed_gap(plain.vertices, plain.faces, w0, points, weights, tri, bary, np.stack([bend(0)]))
    assert np.isclose(at_rest, distance.mean())
    fitted = skinning.fit_weights(plain.vertices, plain.faces, w0, points, weights, tri, bary, train)
    gap = [skinning.posed_gap(plain.vertices, plain.faces, w, points, weights, tri, bary, np.stack(test))
           for w in (w0, fitted)]
    measured = [posed_error(V, F, W, plain.vertices, plain.faces, w, test) for w in (w0, fitted)]
    assert (gap[1] < gap[0]) == (measured[1] < measured[0]) and gap[1] < gap[0], (gap, measured)
