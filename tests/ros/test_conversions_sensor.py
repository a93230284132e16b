"""Round trips of laser scans through sensor_msgs/LaserScan (object and wire format)."""
from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("sensor_msgs.msg", reason="ROS 1 python messages not installed")

from ros_wire import wire  # noqa: E402
from sensor_msgs.msg import LaserScan  # noqa: E402

from slam_predict.ros.conversions.sensor import ScanData, scan_data, scan_from_ros, scan_to_ros  # noqa: E402
from slam_predict.world.model import LaserSpec  # noqa: E402


def stage_scan(stamp=12.3) -> ScanData:
    laser = LaserSpec()  # 270°, 541 samples, [0, 80] m
    ranges = np.random.default_rng(0).uniform(0.1, 80.0, 541).astype(np.float32)
    ranges[::7] = laser.range_max
    return scan_data(ranges, laser, stamp)


def test_scan_round_trip_is_exact():
    scan = stage_scan()
    assert scan_from_ros(scan_to_ros(scan)) == scan


def test_scan_round_trip_through_the_wire():
    scan = stage_scan(stamp=1234.5678)
    back = scan_from_ros(wire(scan_to_ros(scan)))
    np.testing.assert_array_equal(back.ranges, scan.ranges)
    np.testing.assert_array_equal(back.intensities, scan.intensities)
    assert back.stamp == pytest.approx(1234.5678, abs=1e-9)
    assert back.angle_min == pytest.approx(scan.angle_min, rel=1e-7)
    assert back.angle_increment == pytest.approx(scan.angle_increment, rel=1e-7)
    assert back.frame_id == "base_laser_link"


def test_stage_layout_of_the_message():
    msg = scan_to_ros(stage_scan())
    assert isinstance(msg, LaserScan)
    assert msg.angle_min == pytest.approx(-0.75 * math.pi)
    assert msg.angle_max == pytest.approx(0.75 * math.pi)
    assert msg.angle_increment == pytest.approx(math.radians(0.5))
    assert len(msg.ranges) == 541 and msg.range_max == 80.0 and msg.range_min == 0.0
    assert msg.scan_time == 0.0 and msg.time_increment == 0.0
    assert msg.intensities[0] == 0.0 and msg.intensities[1] == 1.0  # no hit vs hit


def test_angles_match_the_laser_spec():
    laser = LaserSpec(fov=math.radians(180), samples=181)
    scan = scan_data(np.ones(181), laser, 0.0)
    np.testing.assert_allclose(scan.angles(), laser.angles(), atol=1e-12)
    assert scan.angle_max == pytest.approx(math.pi / 2)


def test_stamp_overrides_header():
    msg = scan_to_ros(stage_scan(stamp=3.0))
    assert scan_from_ros(msg, stamp=7.5).stamp == 7.5
