"""Robot inputs: from run.json's sensor dict and from robot description files, the same."""
from __future__ import annotations

import json
import math

import pytest

from slam_predict.errors import InputError
from slam_predict.learn.robot.inputs import (
    ALL_ROBOT_INPUTS,
    ROBOT_INPUTS,
    ROBOT_UNITS,
    angular_resolution_deg,
    effective_range,
    inputs_from_robot,
    inputs_from_sensor,
    model_robot_inputs,
    sensor_dict,
)
from slam_predict.robot_file import load_robot

# run.json's sensor of a realistic-setting run (data/campaigns/fidelity_sizes)
REALISTIC = {"laser": {"fov": 4.712389, "noise_std": 0.0, "pose": [0.0, 0.0, 0.0],
                       "range_max": 80.0, "range_min": 0.0, "rate_hz": 10.0, "samples": 541},
             "odom": {"error": [0.01, 0.01, 0.0349066], "gaussian": [0.005, 0.005, 0.01, 0.002],
                      "model": "uniform_per_run"}}


def test_inputs_of_a_recorded_sensor():
    inputs = inputs_from_sensor(REALISTIC)
    assert tuple(inputs) == ALL_ROBOT_INPUTS and set(ROBOT_UNITS) == set(ALL_ROBOT_INPUTS)
    assert inputs["laser_range_max_m"] == 80.0
    assert inputs["laser_fov_deg"] == pytest.approx(270.0, abs=1e-5)
    assert inputs["odom_xy_error"] == 0.01 and inputs["odom_yaw_error"] == 0.0349066
    assert angular_resolution_deg(REALISTIC) == pytest.approx(0.5, abs=1e-6)
    assert inputs["laser_resolution_deg"] == 0.5


def test_the_resolution_input_is_degrees_between_beams_rounded_to_a_hundredth():
    """fov / (samples − 1) in degrees (Stage's beam rule), rounded to 0.01° so that a design's
    fov/0.5 + 1 beams (0.4997–0.5003° after rounding the count) are one value; a model reads
    it only when its configuration asks."""
    sensor = json.loads(json.dumps(REALISTIC))
    for samples, expected in ((1081, 0.25), (271, 1.0), (726, 0.37), (541, 0.5)):
        sensor["laser"]["samples"] = samples
        assert inputs_from_sensor(sensor)["laser_resolution_deg"] == expected
    sensor["laser"]["fov"] = math.radians(239.9)   # 480 beams over 239.9°: 0.50084°
    sensor["laser"]["samples"] = 480
    assert inputs_from_sensor(sensor)["laser_resolution_deg"] == 0.5
    assert model_robot_inputs(False) == ROBOT_INPUTS
    assert model_robot_inputs(True) == (*ROBOT_INPUTS, "laser_resolution_deg")


def test_xy_input_is_the_mean_of_the_x_and_y_bounds_and_none_means_zero():
    sensor = json.loads(json.dumps(REALISTIC))
    sensor["odom"]["error"] = [0.01, 0.03, 0.02]
    assert inputs_from_sensor(sensor)["odom_xy_error"] == pytest.approx(0.02)
    sensor["odom"]["model"] = "none"
    inputs = inputs_from_sensor(sensor)
    assert inputs["odom_xy_error"] == 0.0 and inputs["odom_yaw_error"] == 0.0


def test_robot_files_and_their_recorded_sensor_agree(root):
    """Every shipped robot: the description's inputs equal those of the sensor dict its runs
    record (through JSON), and the file's own numbers (fov deg, yaw deg/rad → rad/rad)."""
    files = sorted((root / "config" / "robots").glob("*.yaml"))
    assert files
    for path in files:
        robot = load_robot(path)
        recorded = json.loads(json.dumps(sensor_dict(robot)))
        direct = inputs_from_robot(robot)
        assert direct == inputs_from_sensor(recorded), path.name
        x, y, yaw = robot.odom_error
        assert direct["laser_range_max_m"] == robot.laser.range_max
        assert direct["laser_fov_deg"] == pytest.approx(robot.laser.fov, rel=1e-12)
        assert direct["odom_xy_error"] == pytest.approx((x + y) / 2)
        assert direct["odom_yaw_error"] == pytest.approx(yaw * math.pi / 180.0)
        assert angular_resolution_deg(recorded) == pytest.approx(
            robot.laser.fov / (robot.laser.samples - 1))


@pytest.mark.parametrize("change, message", [
    (lambda s: s["laser"].pop("fov"), "sensor has no 'laser.fov'"),
    (lambda s: s["odom"].update(model="gaussian_per_step"),
     "odometry model 'gaussian_per_step' is not a robot input"),
    (lambda s: s["odom"].update(error=[0.01, 0.01]), "must be [x, y, yaw]"),
    (lambda s: s["odom"].update(error=[0.01, -0.01, 0.0]), "'odom.error[1]' must be a number"),
    (lambda s: s["laser"].update(range_max="far"), "'laser.range_max' must be a finite number"),
])
def test_bad_sensors_are_one_line_errors_naming_the_file(change, message):
    sensor = json.loads(json.dumps(REALISTIC))
    change(sensor)
    with pytest.raises(InputError, match=message.replace("[", r"\[").replace("]", r"\]")) as err:
        inputs_from_sensor(sensor, "DATA/w/run_000/run.json")
    assert err.value.one_line().startswith("DATA/w/run_000/run.json: ")


def test_range_input_is_the_range_gmapping_uses(root):
    """GMapping crops beams at maxUrange (30 m): the seed study's 80 m laser is a 30 m input,
    inside the design's 3.5-30 m; a shorter laser keeps its range; None = no cap."""
    assert effective_range(80.0, 30.0) == 30.0 and effective_range(3.5, 30.0) == 3.5
    assert effective_range(80.0, None) == 80.0
    seed = load_robot(root / "config" / "robots" / "seed_realistic.yaml")
    assert inputs_from_robot(seed, 30.0)["laser_range_max_m"] == 30.0
    assert inputs_from_robot(seed)["laser_range_max_m"] == 80.0
    assert inputs_from_sensor(REALISTIC, max_urange_m=30.0)["laser_range_max_m"] == 30.0
    lds = load_robot(root / "config" / "robots" / "lds_360_3p5.yaml")
    assert inputs_from_robot(lds, 30.0)["laser_range_max_m"] == 3.5
