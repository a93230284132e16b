"""Karto's pose and averaging arithmetic as the port restates it: the same values as plain
geometry (compose/relative, means, the weighted mean), checked on seeded random inputs."""
import math

import numpy as np

from slam_predict.slam.karto.graph import weighted_mean
from slam_predict.slam.karto.matcher import angle_near, average_best_pose
from slam_predict.slam.karto.scan import compose, normalize_angle, relative, transform_pose


def test_transform_pose_is_compose_after_relative():
    rng = np.random.default_rng(0)
    for _ in range(200):
        a, b, p = (np.append(rng.normal(0, 5, 2), rng.uniform(-math.pi, math.pi))
                   for _ in range(3))
        expected = compose(b, relative(a, p))
        got = transform_pose(a, b, p)
        assert np.allclose(got[:2], expected[:2], atol=1e-12)
        assert abs(normalize_angle(got[2] - expected[2])) < 1e-12


def test_normalize_angle_keeps_angles_in_range_and_turns_others_by_whole_turns():
    rng = np.random.default_rng(1)
    for angle in rng.uniform(-30, 30, 200):
        got = normalize_angle(float(angle))
        assert -math.pi <= got <= math.pi
        assert math.isclose(math.remainder(got - angle, 2 * math.pi), 0.0, abs_tol=1e-9)
    assert normalize_angle(0.3) == 0.3


def test_angle_near_is_within_half_a_turn_of_the_reference():
    for angle, ref in [(3.0, -3.0), (-3.0, 3.0), (0.2, 0.1), (10.0, 0.0)]:
        got = angle_near(angle, ref)
        assert abs(got - ref) <= math.pi
        assert math.isclose(math.remainder(got - angle, 2 * math.pi), 0.0, abs_tol=1e-12)


def test_average_best_pose_is_the_mean_of_the_tied_poses():
    rng = np.random.default_rng(2)
    xs, ys, angles = np.linspace(-0.1, 0.1, 5), np.linspace(-0.2, 0.2, 4), np.linspace(-1, 1, 3)
    responses = rng.uniform(0, 0.5, (4, 5, 3))
    ties = [(1, 2, 0), (3, 4, 2), (0, 0, 1)]
    for t in ties:
        responses[t] = 0.9
    center = np.array([2.0, -1.0, 0.3])
    got = average_best_pose(responses, 0.9, center, xs, ys, angles)
    assert math.isclose(got[0], center[0] + np.mean([xs[t[1]] for t in ties]))
    assert math.isclose(got[1], center[1] + np.mean([ys[t[0]] for t in ties]))
    heads = [angles[t[2]] for t in ties]
    assert math.isclose(got[2], math.atan2(np.mean(np.sin(heads)), np.mean(np.cos(heads))))


def test_weighted_mean_is_the_information_weighted_mean():
    rng = np.random.default_rng(3)
    means, covs = [], []
    for _ in range(4):
        m = rng.normal(size=(3, 3))
        covs.append(m @ m.T + 0.5 * np.eye(3))
        means.append(np.append(rng.normal(0, 1, 2), rng.uniform(-1, 1)))
    info = [np.linalg.inv(c) for c in covs]
    expected = np.linalg.solve(sum(info), sum(i @ m for i, m in zip(info, means, strict=True)))
    got = weighted_mean(means, covs)
    assert np.allclose(got[:2], expected[:2], atol=1e-12)
    heads = [m[2] for m in means]
    assert math.isclose(got[2], math.atan2(np.mean(np.sin(heads)), np.mean(np.cos(heads))))
