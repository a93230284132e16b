"""Round trips of poses, twists, odometry, transforms and clock through ROS messages."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("nav_msgs.msg", reason="ROS 1 python messages not installed")

from ros_wire import wire  # noqa: E402

from slam_predict.geometry import wrap_angle  # noqa: E402
from slam_predict.ros.conversions.geometry import (  # noqa: E402
    clock_from_ros,
    clock_to_ros,
    odometry_from_ros,
    odometry_to_ros,
    pose_from_ros,
    pose_to_ros,
    time_from_ros,
    time_to_ros,
    transform_from_ros,
    transform_to_ros,
    twist_from_ros,
    twist_to_ros,
)

RNG = np.random.default_rng(1)
POSES = np.column_stack([RNG.uniform(-50, 50, (40, 2)), RNG.uniform(-np.pi, np.pi, 40)])


def assert_pose_close(a, b, atol=1e-12):
    np.testing.assert_allclose(a[:2], b[:2], atol=atol)
    assert abs(float(wrap_angle(a[2] - b[2]))) < atol + 1e-12


@pytest.mark.parametrize("t", [0.0, 0.1, 0.3, 12.7, 1e6 + 0.05, 1732.123456789])
def test_time_round_trip(t):
    stamp = time_to_ros(t)
    assert 0 <= stamp.nsecs < 1_000_000_000
    assert time_from_ros(stamp) == pytest.approx(t, abs=1e-9)
    assert time_from_ros(wire(clock_to_ros(t)).clock) == pytest.approx(t, abs=1e-9)


def test_pose_round_trip():
    for pose in POSES:
        assert_pose_close(pose_from_ros(pose_to_ros(pose)), pose)
        assert_pose_close(pose_from_ros(wire(odometry_to_ros(pose, (0, 0), 0.0)).pose.pose),
                          pose)


def test_twist_round_trip():
    assert twist_from_ros(twist_to_ros((0.5, -0.3))) == (0.5, 0.0, -0.3)
    assert twist_from_ros(wire(twist_to_ros((0.5, 0.1, -0.3)))) == (0.5, 0.1, -0.3)


def test_odometry_round_trip():
    msg = odometry_to_ros(POSES[3], (0.4, -0.2), 17.2, "odom", "base_footprint")
    data = odometry_from_ros(wire(msg))
    assert data.stamp == pytest.approx(17.2, abs=1e-9)
    assert (data.frame_id, data.child_frame_id) == ("odom", "base_footprint")
    assert_pose_close(data.pose, POSES[3])
    assert data.twist == (0.4, 0.0, -0.2)
    assert list(msg.pose.covariance) == [0.0] * 36


def test_transform_round_trip():
    for pose in POSES[:10]:
        data = transform_from_ros(wire(transform_to_ros(pose, 3.4, "odom", "base_footprint",
                                                        z=0.25)))
        assert (data.parent, data.child, data.z) == ("odom", "base_footprint", 0.25)
        assert data.stamp == pytest.approx(3.4, abs=1e-9)
        assert_pose_close(data.pose, pose)


def test_clock_round_trip():
    assert clock_from_ros(clock_to_ros(42.1)) == pytest.approx(42.1, abs=1e-9)
