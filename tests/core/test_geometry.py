"""SE(2) operations against explicit homogeneous-matrix arithmetic (the slow reference)."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from slam_predict import geometry as g

coord = st.floats(-50, 50, allow_nan=False)
angle = st.floats(-10, 10, allow_nan=False)
pose = st.tuples(coord, coord, angle).map(np.array)


def matrix(p):
    c, s = np.cos(p[2]), np.sin(p[2])
    return np.array([[c, -s, p[0]], [s, c, p[1]], [0, 0, 1.0]])


def from_matrix(m):
    return np.array([m[0, 2], m[1, 2], np.arctan2(m[1, 0], m[0, 0])])


def same_pose(a, b):
    assert np.allclose(a[:2], b[:2], atol=1e-9)
    assert abs(g.wrap_angle(a[2] - b[2])) < 1e-9


@given(pose, pose)
@settings(max_examples=200)
def test_compose_matches_matrices(a, b):
    same_pose(g.compose(a, b), from_matrix(matrix(a) @ matrix(b)))


@given(pose)
@settings(max_examples=200)
def test_inverse_matches_matrix_inverse(a):
    same_pose(g.inverse(a), from_matrix(np.linalg.inv(matrix(a))))


@given(pose, pose)
@settings(max_examples=200)
def test_ominus_is_b_in_frame_of_a(a, b):
    same_pose(g.ominus(b, a), from_matrix(np.linalg.inv(matrix(a)) @ matrix(b)))
    same_pose(g.compose(a, g.ominus(b, a)), b)


def test_batches_match_single_poses():
    rng = np.random.default_rng(0)
    a = rng.uniform(-5, 5, (20, 3))
    b = rng.uniform(-5, 5, (20, 3))
    batch = g.ominus(b, a)
    for i in range(20):
        same_pose(batch[i], g.ominus(b[i], a[i]))


def test_single_poses_are_the_batch_rows_bit_for_bit():
    """One pose takes a cheaper stacking path; its numbers are the batch's exactly."""
    rng = np.random.default_rng(1)
    a = rng.uniform(-5, 5, (200, 3))
    b = rng.uniform(-5, 5, (200, 3))
    composed, inverted = g.compose(a, b), g.inverse(a)
    for i in range(200):
        single = g.compose(a[i], b[i])
        assert single.shape == (3,) and single.dtype == np.float64
        assert np.array_equal(single, composed[i])
        assert np.array_equal(g.inverse(a[i]), inverted[i])


def test_wrap_angle_range():
    angles = np.linspace(-20, 20, 1001)
    wrapped = g.wrap_angle(angles)
    assert wrapped.min() >= -np.pi and wrapped.max() < np.pi
    assert np.allclose(np.sin(wrapped), np.sin(angles))
    assert np.allclose(np.cos(wrapped), np.cos(angles))


def test_quaternion_round_trip():
    yaw = np.linspace(-3.1, 3.1, 50)
    q = g.yaw_to_quaternion(yaw)
    assert np.allclose(np.linalg.norm(q, axis=-1), 1.0)
    assert np.allclose(g.quaternion_to_yaw(*q.T), yaw)


def test_transform_points():
    pts = np.array([[1.0, 0.0], [0.0, 2.0]])
    out = g.transform_points([1.0, 1.0, np.pi / 2], pts)
    assert np.allclose(out, [[1.0, 2.0], [-1.0, 1.0]])


def test_world_T_map_recovers_the_map_frame():
    rng = np.random.default_rng(0)
    world_T_map = np.array([rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-3, 3)])
    slam = np.column_stack([rng.uniform(-10, 10, (50, 2)), rng.uniform(-np.pi, np.pi, 50)])
    gt = g.compose(world_T_map, slam)
    found = g.world_T_map(gt[7], slam[7])
    np.testing.assert_allclose(found, world_T_map, atol=1e-9)
    back = g.compose(g.inverse(found), gt)
    np.testing.assert_allclose(back[:, :2], slam[:, :2], atol=1e-9)
