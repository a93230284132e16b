"""The campaign-mismatch message speaks in the robot file's units (degrees, deg/rad)."""
from __future__ import annotations

import math

from slam_predict.collect.campaign import differences, mismatch


def campaign(fov: float, yaw_error: float, seed: int = 0) -> dict:
    return {"base_seed": seed, "settings": {"sim": {
        "laser": {"fov": fov, "samples": 541, "pose": [0.0, 0.0, 0.0]},
        "odom": {"model": "fixed", "error": [0.01, 0.01, yaw_error]}}}}


def test_fov_and_yaw_error_are_shown_in_degrees():
    old = campaign(math.radians(270.0), math.radians(2.0))
    new = campaign(math.radians(240.0), math.radians(3.0))
    text = mismatch(old, new)
    assert "sim.laser.fov: 270 deg -> 240 deg" in text
    assert "sim.odom.error: [0.01, 0.01, 2 deg/rad] -> [0.01, 0.01, 3 deg/rad]" in text


def test_other_values_keep_their_own_form():
    assert differences({"a": {"samples": 541}}, {"a": {"samples": 360}}) == [
        "a.samples: 541 -> 360"]
    assert differences({"laser": {"fov": None}}, {"laser": {"fov": 1.0}})[0].startswith(
        "laser.fov: None -> 57.2958 deg")


def test_the_robot_s_values_come_first_with_their_units():
    old = {"base_seed": 0, "settings": {
        "gmapping": {"maxUrange": 3.49},
        "sim": {"laser": {"range_max": 3.5, "rate_hz": 5.0}, "robot": {"max_vel_x": 0.5}}}}
    new = {"base_seed": 0, "settings": {
        "gmapping": {"maxUrange": 5.59},
        "sim": {"laser": {"range_max": 5.6, "rate_hz": 10.0}, "robot": {"max_vel_x": 0.85}}}}
    assert mismatch(old, new) == (
        "the settings differ from the campaign's: sim.laser.range_max: 3.5 m -> 5.6 m; "
        "sim.laser.rate_hz: 5.0 Hz -> 10.0 Hz; sim.robot.max_vel_x: 0.5 m/s -> 0.85 m/s "
        "(and 1 more)")
