"""Robot description files: the shipped examples load, the seed robot is config/robot.yaml's, the
unit conversions match hand-computed values, every bad file is one InputError naming it, and the
GMapping caps agree with slam_gmapping's own range rule."""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from slam_predict.config import from_dict, load_config, to_dict
from slam_predict.errors import InputError
from slam_predict.robot_file import RobotDescription, RobotLaser, load_robot
from slam_predict.sim import SimConfig
from slam_predict.sim.simulator import resolve_sensor
from slam_predict.slam.gmapping.params import GMappingParams, load_params
from slam_predict.world.load import load_plan

ROOT = Path(__file__).resolve().parents[2]
ROBOTS = ROOT / "config" / "robots"
EXAMPLES = ("seed_realistic", "seed_realistic_fixed", "seed_optimistic", "lds_360_3p5",
            "urg_240_5p6", "utm_270_30_poor_odom")

VALID = """\
name: test_robot
laser:
  range_max: 5.6
  range_min: 0.02
  fov: 240.0
  samples: 683
  rate_hz: 10.0
  pose: [0.1, -0.05, 90.0]
odom_error: [0.01, 0.02, 2.0]
max_vel_x: 0.5
max_vel_theta: 1.0
"""


def robot_file(tmp_path: Path, text: str = VALID, name: str = "robot.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


# -- shipped examples ---------------------------------------------------------------------------

def test_the_examples_are_shipped():
    assert sorted(p.stem for p in ROBOTS.glob("*.yaml")) == sorted(EXAMPLES)


@pytest.mark.parametrize("name", EXAMPLES)
def test_each_example_loads_and_names_itself(name):
    robot = load_robot(ROBOTS / f"{name}.yaml")
    assert robot.name == name and robot.description
    sensor = robot.to_sensor_config()
    assert sensor.laser.range_max == robot.laser.range_max
    assert robot.max_vel_x == 0.85 and robot.max_vel_theta == 0.7
    assert robot.footprint_side == 0.3


@pytest.mark.parametrize("name", EXAMPLES)
def test_dict_round_trip(name):
    robot = load_robot(ROBOTS / f"{name}.yaml")
    assert from_dict(RobotDescription, to_dict(robot)) == robot


UNIFORM, FIXED = "uniform_per_run", "fixed"


@pytest.mark.parametrize("name, fov, samples, range_min, range_max, rate, odom, model", [
    ("seed_realistic", 270.0, 541, 0.0, 80.0, 10.0, (0.01, 0.01, 2.0), UNIFORM),
    ("seed_realistic_fixed", 270.0, 541, 0.0, 80.0, 10.0, (0.01, 0.01, 2.0), FIXED),
    ("seed_optimistic", 270.0, 541, 0.0, 80.0, 10.0, (0.01, 0.01, 0.0), UNIFORM),
    ("lds_360_3p5", 360.0, 360, 0.12, 3.5, 5.0, (0.01, 0.01, 2.0), FIXED),
    ("urg_240_5p6", 240.0, 683, 0.02, 5.6, 10.0, (0.01, 0.01, 2.0), FIXED),
    ("utm_270_30_poor_odom", 270.0, 1081, 0.1, 30.0, 40.0, (0.02, 0.02, 4.0), FIXED),
])
def test_examples_hold_their_spec_values(name, fov, samples, range_min, range_max, rate, odom,
                                         model):
    robot = load_robot(ROBOTS / f"{name}.yaml")
    assert robot.laser == RobotLaser(range_max=range_max, fov=fov, samples=samples,
                                     range_min=range_min, rate_hz=rate)
    assert robot.odom_error == odom and robot.odom_model == model


def assert_same_sensor(ours, theirs):
    """Equal field by field; fov and the yaw error only to robot.yaml's printed digits (it
    writes 4.712389 rad and 0.0349066 rad/rad, the robot files 270 deg and 2 deg/rad exactly)."""
    assert math.isclose(ours.laser.fov, theirs.laser.fov, rel_tol=0, abs_tol=5e-7)
    assert math.isclose(ours.odom.error[2], theirs.odom.error[2], rel_tol=0, abs_tol=5e-8)
    same_fov = dataclasses.replace(ours.laser, fov=theirs.laser.fov)
    same_yaw = dataclasses.replace(ours.odom, error=ours.odom.error[:2] + theirs.odom.error[2:])
    assert dataclasses.replace(ours, laser=same_fov, odom=same_yaw) == theirs


def test_seed_realistic_fixed_is_the_fidelity_campaigns_sensor():
    """The fidelity campaign's settings (config/fidelity/seed_study.yaml) and the robot file the
    robots campaign starts from describe the same sensor (to robot.yaml's printed digits)."""
    from slam_predict.collect.settings import load_settings

    sim = load_settings(ROOT / "config" / "fidelity" / "seed_study.yaml").sim
    theirs = resolve_sensor(load_plan(ROOT / "worlds" / "tiny.world"), sim)
    ours = load_robot(ROBOTS / "seed_realistic_fixed.yaml").to_sensor_config()
    assert theirs.odom.model == ours.odom.model == FIXED
    assert_same_sensor(ours, theirs)


def test_seed_realistic_is_config_robot_yaml_sensor():
    """The simulator's sensor with config/robot.yaml (over the tiny world) and the seed
    robot's are the same sensor."""
    sim = load_config(SimConfig, ROOT / "config" / "robot.yaml", "sim")
    theirs = resolve_sensor(load_plan(ROOT / "worlds" / "tiny.world"), sim)
    ours = load_robot(ROBOTS / "seed_realistic.yaml").to_sensor_config()
    assert_same_sensor(ours, theirs)


# -- unit conversions ---------------------------------------------------------------------------

def test_degrees_become_radians(tmp_path):
    robot = load_robot(robot_file(tmp_path))
    sensor = robot.to_sensor_config()
    assert math.isclose(sensor.laser.fov, 4.1887902047863905, rel_tol=1e-15)  # 4π/3
    assert sensor.laser.pose == pytest.approx((0.1, -0.05, 1.5707963267948966), rel=1e-15)
    assert sensor.odom.error == pytest.approx((0.01, 0.02, 0.03490658503988659), rel=1e-15)
    assert sensor.laser.samples == 683 and sensor.laser.range_min == 0.02


@pytest.mark.parametrize("degrees, radians", [(360.0, 2 * math.pi), (270.0, 3 * math.pi / 2),
                                              (180.0, math.pi), (0.5, math.pi / 360)])
def test_fov_conversion_against_multiples_of_pi(degrees, radians):
    laser = RobotLaser(range_max=10.0, fov=degrees, samples=3)
    assert math.isclose(laser.to_laser_config().fov, radians, rel_tol=1e-15)


def test_stage_four_value_odom_error_drops_z(tmp_path):
    text = VALID.replace("odom_error: [0.01, 0.02, 2.0]", "odom_error: [0.01, 0.02, 0.0, 2.0]")
    assert load_robot(robot_file(tmp_path, text)).odom_error == (0.01, 0.02, 2.0)


def test_sim_overrides_are_the_sensor_in_si_units(tmp_path):
    robot = load_robot(robot_file(tmp_path))
    tree = robot.sim_overrides()
    sensor = robot.to_sensor_config()
    assert tree["laser"]["fov"] == sensor.laser.fov and tree["laser"]["pose"][2] == math.pi / 2
    assert tree["odom"] == {"model": "fixed", "error": list(sensor.odom.error)}   # the default
    assert tree["robot"] == {"footprint_side": 0.3, "max_vel_x": 0.5, "max_vel_theta": 1.0}


def test_nav_and_explore_overrides_follow_speed_and_footprint(tmp_path):
    robot = dataclasses.replace(load_robot(robot_file(tmp_path)), footprint_side=0.5)
    nav = robot.nav_overrides()
    assert nav["TrajectoryPlannerROS"] == {"max_vel_x": 0.5, "max_vel_theta": 1.0,
                                           "min_vel_theta": -1.0}
    square = [[-0.3, -0.3], [-0.3, 0.3], [0.3, 0.3], [0.3, -0.3]]   # (0.5 + 0.1) / 2
    corners = [tuple(corner) for corner in nav["global_costmap"]["footprint"]]
    assert corners == [pytest.approx(tuple(corner)) for corner in square]
    assert nav["local_costmap"]["footprint"] == nav["global_costmap"]["footprint"]
    assert robot.explore_overrides() == {"thesis": {"inscribed_radius": pytest.approx(0.3)}}


# -- validation ---------------------------------------------------------------------------------

def edit(old: str, new: str) -> str:
    assert old in VALID
    return VALID.replace(old, new)


BAD_FILES = [
    ("unknown laser key", edit("  fov: 240.0", "  fvo: 240.0"),
     ["unknown config key 'fvo' in 'laser'", "did you mean 'fov'"]),
    ("unknown top key", edit("max_vel_x: 0.5", "max_vel: 0.5"),
     ["unknown config key 'max_vel'", "did you mean 'max_vel_x'"]),
    ("negative range_max", edit("range_max: 5.6", "range_max: -3.5"),
     ["'laser.range_max' must be > 0", "-3.5"]),
    ("negative range_min", edit("range_min: 0.02", "range_min: -0.1"),
     ["'laser.range_min' must be ≥ 0"]),
    ("range_max equal to range_min", edit("range_min: 0.02", "range_min: 5.6"),
     ["range_max (5.6 m) must exceed laser.range_min (5.6 m)"]),
    ("range_max below range_min", edit("range_max: 5.6", "range_max: 0.01"),
     ["must exceed laser.range_min"]),
    ("fov 0", edit("fov: 240.0", "fov: 0"), ["'laser.fov' must be in (0, 360]", "got 0.0"]),
    ("fov over 360", edit("fov: 240.0", "fov: 361"), ["'laser.fov' must be in (0, 360]"]),
    ("samples 0", edit("samples: 683", "samples: 0"), ["'laser.samples' must be ≥ 1"]),
    ("samples not an integer", edit("samples: 683", "samples: 68.5"),
     ["'laser.samples' must be an integer"]),
    ("rate 0", edit("rate_hz: 10.0", "rate_hz: 0"), ["'laser.rate_hz' must be > 0"]),
    ("bad odom_model", VALID + "odom_model: gaussian\n", ["odom_model must be one of",
                                                         "uniform_per_run", "'gaussian'"]),
    ("non-numeric range", edit("range_max: 5.6", "range_max: far"),
     ["'laser.range_max' must be a number, got 'far'"]),
    ("negative odom error", edit("[0.01, 0.02, 2.0]", "[0.01, -0.02, 2.0]"),
     ["'odom_error' must be ≥ 0"]),
    ("infinite odom error", edit("[0.01, 0.02, 2.0]", "[0.01, .inf, 2.0]"),
     ["odom_error must be finite"]),
    ("two odom errors", edit("[0.01, 0.02, 2.0]", "[0.01, 0.02]"),
     ["'odom_error' needs 3 values, got 2"]),
    ("NaN pose", edit("pose: [0.1, -0.05, 90.0]", "pose: [0.1, .nan, 90.0]"),
     ["laser.pose must be finite"]),
    ("zero speed", edit("max_vel_theta: 1.0", "max_vel_theta: 0"),
     ["'max_vel_theta' must be > 0"]),
    ("zero footprint", VALID + "footprint_side: 0.0\n", ["'footprint_side' must be > 0"]),
    ("missing fov", edit("  fov: 240.0\n", ""), ["missing required key 'laser.fov'"]),
    ("missing name", edit("name: test_robot\n", ""), ["missing required key 'name'"]),
    ("empty name", edit("name: test_robot", "name: ' '"), ["name must not be empty"]),
    ("laser not a mapping", "name: r\nlaser: 3\nodom_error: [0, 0, 0]\n",
     ["'laser' must be a mapping"]),
    ("not a mapping", "- just\n- a list\n", ["top level must be a mapping"]),
    ("empty file", "", ["the robot file is empty"]),
    ("YAML syntax", "name: [unclosed\n", ["YAML syntax error"]),
]


@pytest.mark.parametrize("case, text, words", BAD_FILES, ids=[c[0] for c in BAD_FILES])
def test_bad_robot_file_is_one_input_error_naming_it(tmp_path, case, text, words):
    path = robot_file(tmp_path, text, "bad_robot.yaml")
    with pytest.raises(InputError) as info:
        load_robot(path)
    assert info.value.path == str(path)
    line = info.value.one_line()
    assert line.startswith(str(path)) and "\n" not in line
    assert all(word in info.value.problem for word in words), info.value.problem


def test_missing_robot_file(tmp_path):
    with pytest.raises(InputError, match="robot file not found"):
        load_robot(tmp_path / "none.yaml")


def test_direct_construction_is_validated_too():
    laser = RobotLaser(range_max=3.5, fov=360.0, samples=360)
    with pytest.raises(ValueError, match="fov"):
        RobotLaser(range_max=3.5, fov=400.0, samples=360)
    with pytest.raises(ValueError, match="odom_model"):
        RobotDescription("r", laser, (0.0, 0.0, 0.0), odom_model="perfect")
    with pytest.raises(ValueError, match="odom_error"):
        RobotDescription("r", laser, (0.0, -1.0, 0.0))


# -- GMapping caps ------------------------------------------------------------------------------

def gmapping_yaml() -> GMappingParams:
    return load_params(ROOT / "config" / "gmapping.yaml")


def test_gmapping_caps_of_a_3p5_m_laser():
    """config/gmapping.yaml's 60 / 30 m become 60 / 3.49 m: maxUrange below the sensor's range
    <= maxRange, the gmapping wiki's setting for open space to be mapped free."""
    robot = load_robot(ROBOTS / "lds_360_3p5.yaml")
    params = gmapping_yaml()
    assert (params.maxRange, params.maxUrange) == (60.0, 30.0)
    capped = robot.gmapping_caps(params)
    assert capped.maxRange == 60.0 and capped.maxUrange == pytest.approx(3.49, abs=1e-12)
    assert dataclasses.replace(capped, maxUrange=30.0) == params
    # unset stays unset: the node derives 3.49 / 3.49 from the laser, a set maxUrange is capped
    unset = dataclasses.replace(params, maxRange=None, maxUrange=None)
    assert robot.gmapping_caps(unset) == unset
    only_urange = robot.gmapping_caps(dataclasses.replace(params, maxRange=None))
    assert only_urange.maxRange is None and only_urange.maxUrange == pytest.approx(3.49)


@pytest.mark.parametrize("name", ["lds_360_3p5", "urg_240_5p6"])
def test_a_short_lasers_no_hit_beams_map_free_space_and_no_walls(name):
    """In a space wider than its range a short laser reports range_max on every beam (Stage's
    no-hit). With the capped parameters GMapping marks the disc free and no cell occupied;
    with maxRange below range_max (the capping before 2026-12-04) it marked nothing, and the
    explorer found its only frontier under the robot."""
    from slam_predict.slam import LaserGeometry
    from slam_predict.slam.gmapping.filter import GMapping

    robot = load_robot(ROBOTS / f"{name}.yaml")
    sensor = robot.to_sensor_config().laser
    angles = (np.arange(sensor.samples) - 0.5 * (sensor.samples - 1)) * (
        sensor.fov / (sensor.samples - 1))
    laser = LaserGeometry(angles, (0.0, 0.0, 0.0), sensor.range_max)

    def free_and_occupied(params):
        slam = GMapping(dataclasses.replace(params, particles=1), laser,
                        np.random.default_rng(0))
        slam.update(np.zeros(3), np.full(sensor.samples, sensor.range_max), 0.0)
        data = slam.map().data
        return int((data == 0).sum()), int((data == 100).sum())

    params = gmapping_yaml()
    free, occupied = free_and_occupied(robot.gmapping_caps(params))
    disc = sensor.fov / 2 * (sensor.range_max - 0.01) ** 2 / params.delta ** 2   # cells
    assert occupied == 0 and free > 0.8 * disc
    old = dataclasses.replace(params, maxRange=sensor.range_max - 0.01,
                              maxUrange=sensor.range_max - 0.01)
    assert free_and_occupied(old) == (0, 0)


def test_gmapping_caps_keep_the_thesis_values_with_the_80_m_laser():
    params = gmapping_yaml()
    assert load_robot(ROBOTS / "seed_realistic.yaml").gmapping_caps(params) == params
    capped = load_robot(ROBOTS / "utm_270_30_poor_odom.yaml").gmapping_caps(params)
    assert (capped.maxRange, capped.maxUrange) == (60.0, 29.99)


@pytest.mark.parametrize("theirs, expected", [
    ((None, None), (None, None)),          # unset: slam_gmapping derives them from the laser
    ((None, 30.0), (None, 3.49)),
    ((2.0, 30.0), (2.0, 2.0)),             # below the laser: kept; maxUrange ≤ maxRange
    ((60.0, 1.0), (60.0, 1.0)),            # maxRange is never lowered
    ((60.0, 30.0), (60.0, 3.49)),
])
def test_gmapping_caps_table(theirs, expected):
    robot = load_robot(ROBOTS / "lds_360_3p5.yaml")
    params = GMappingParams(maxRange=theirs[0], maxUrange=theirs[1])
    capped = robot.gmapping_caps(params)
    assert (capped.maxRange, capped.maxUrange) == pytest.approx(expected, abs=1e-12)
