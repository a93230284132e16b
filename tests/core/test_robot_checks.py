"""Plausibility rules of robot descriptions (slam_predict.robot_checks) against hand-made cases."""
from __future__ import annotations

import dataclasses
import math

import pytest

from slam_predict.robot_checks import implausible, implausible_laser
from slam_predict.robot_file import load_robot


def shipped(**laser_changes):
    robot = load_robot("urg_240_5p6")
    return dataclasses.replace(robot, laser=dataclasses.replace(robot.laser, **laser_changes))


@pytest.mark.parametrize("yaw_deg, flagged", [
    (math.pi / 4, True), (math.pi / 2, True), (-math.pi / 2, True), (3.1416, True),
    (3.14, True), (3 * math.pi / 2, True), (2 * math.pi, True),
    (0.0, False), (3.0, False), (1.5, False), (45.0, False), (90.0, False), (180.0, False),
    (-90.0, False), (3.2, False)])
def test_a_mounting_yaw_of_a_multiple_of_45_deg_in_radians_is_flagged(yaw_deg, flagged):
    problems = implausible(shipped(pose=(0.1, 0.0, yaw_deg)))
    assert any("laser.pose yaw" in p for p in problems) is flagged, problems


def test_radian_spellings_are_named_as_written():
    robot = dataclasses.replace(load_robot("urg_240_5p6"), odom_error=(0.01, 0.01, 120.0))
    assert implausible(robot)[0].startswith("odom_error yaw 120 deg/rad")
    assert implausible(robot, ["odom_error_rad"])[0].startswith("odom_error_rad yaw 2.094 "
                                                                 "rad/rad")


def test_the_laser_checks_leave_the_odometry_alone():
    robot = dataclasses.replace(shipped(fov=4.0, samples=10), odom_error=(0.01, 0.01, 0.05))
    assert [key for key, _ in implausible_laser(robot)] == ["laser.fov", "laser.samples"]
    assert len(implausible(robot)) == 3


def test_a_datasheet_robot_breaks_no_rule():
    assert implausible(load_robot("utm_270_30_poor_odom")) == []
