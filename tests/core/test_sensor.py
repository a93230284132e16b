"""SensorConfig: validation in SI units, and every consumer reading the one config (simulator,
perfect map source, GMapping's range defaults, traversal features)."""
import logging
import math
import sys
from pathlib import Path

import numpy as np
import pytest

from slam_predict.config import from_dict, load_config, to_dict
from slam_predict.errors import InputError
from slam_predict.sensor import LaserConfig, OdomConfig, SensorConfig, sensor_hash
from slam_predict.sim import SimConfig
from slam_predict.sim.config import LaserOverrides
from slam_predict.sim.simulator import Simulator, resolve_sensor
from slam_predict.world.model import LaserSpec, RobotSpec

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "sim"))
from sim_worlds import box_world  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def test_defaults_are_the_seed_study_laser_in_rad():
    sensor = SensorConfig()
    assert sensor.laser.fov == math.radians(270.0) and sensor.laser.samples == 541
    assert sensor.laser.range_max == 80.0 and sensor.odom.error[2] == pytest.approx(0.0349066)
    assert LaserSpec is LaserConfig and LaserSpec() == sensor.laser
    angles = sensor.laser.angles()
    assert angles[0] == pytest.approx(-3 * math.pi / 4)
    assert angles[-1] == pytest.approx(3 * math.pi / 4)


@pytest.mark.parametrize("laser, message", [
    ({"range_max": -1.0}, r"'sensor\.laser\.range_max' must be > 0"),
    ({"fov": 7.0}, r"'sensor\.laser\.fov' must be in \(0, 6\.28"),
    ({"fov": 270.0}, r"'sensor\.laser\.fov' must be in \(0, 6\.28"),   # degrees by mistake
    ({"samples": 0}, r"'sensor\.laser\.samples' must be"),
    ({"range_min": 5.0, "range_max": 4.0}, r"range_max \(4\.0 m\) must exceed range_min"),
    ({"beams": 100}, r"unknown config key 'beams'"),
])
def test_bad_laser_values_are_refused_with_the_key(laser, message):
    with pytest.raises(InputError, match=message):
        from_dict(SensorConfig, {"laser": laser}, "robot.yaml", "sensor")


def test_odometry_needs_a_known_model_and_its_error():
    with pytest.raises(InputError, match="odom model must be one of"):
        from_dict(SensorConfig, {"odom": {"model": "bad", "error": [0, 0, 0]}})
    with pytest.raises(InputError, match="odom.error must be given"):
        from_dict(SensorConfig, {"odom": {"model": "fixed"}})
    with pytest.raises(InputError, match="gaussian. must be ≥ 0"):
        from_dict(SensorConfig, {"odom": {"error": [0, 0, 0], "gaussian": [-1, 0, 0, 0]}})


def test_hash_of_config_and_of_its_recorded_form_agree():
    sensor = from_dict(SensorConfig, {"laser": {"range_max": 3.5, "fov": 2 * math.pi}})
    import json
    assert sensor_hash(sensor) == sensor_hash(json.loads(json.dumps(to_dict(sensor))))
    assert sensor_hash(sensor) != sensor_hash(SensorConfig())


def test_robot_yaml_sim_laser_keys_stay_valid():
    sim = load_config(SimConfig, ROOT / "config" / "robot.yaml", "sim")
    sensor = resolve_sensor(box_world(), sim)
    assert sensor.laser.fov == 4.712389 and sensor.laser.range_max == 80.0
    assert sensor.odom.error == (0.01, 0.01, 0.0349066)


def test_simulator_senses_with_the_resolved_sensor():
    world = box_world(8.0, 8.0, laser=LaserSpec(range_max=30.0),
                      robot=RobotSpec(odom_error=(0.02, 0.03, 0.0, 0.05)))
    config = SimConfig(laser=LaserOverrides(fov=math.pi, samples=181, range_max=2.5),
                       odom=OdomConfig(model="fixed"))
    sim = Simulator(world, config, np.random.default_rng(0))
    assert sim.sensor.laser == LaserConfig(fov=math.pi, samples=181, range_max=2.5)
    assert sim.sensor.odom.error == (0.02, 0.03, 0.05)        # the World's (x, y, yaw)
    assert sim.odom_error["bias"] == [0.02, 0.03, 0.05]
    state = sim.step(0.0, 0.0)
    assert state.scan.shape == (181,)
    assert np.all(state.scan <= 2.5) and np.any(state.scan == np.float32(2.5))  # walls at 4 m
    assert sim.laser_angles[0] == pytest.approx(-math.pi / 2)


def _loop(map_source, slam_params=None, range_max=12.0):
    from slam_predict.explore.explorer import ExploreConfig
    from slam_predict.explore.loop import ClosedLoop
    from slam_predict.nav.config import load_nav_config

    sim = SimConfig(laser=LaserOverrides(range_max=range_max, samples=181))
    return ClosedLoop(box_world(10.0, 10.0), 1, load_nav_config(ROOT / "config"), ExploreConfig(),
                      sim, map_source=map_source, slam_params=slam_params)


def test_perfect_map_source_takes_the_sensor_laser():
    loop = _loop("perfect", range_max=12.0)
    assert loop.source.max_range == 12.0
    assert np.array_equal(loop.source.laser.angles, loop.sim.sensor.laser.angles())


def test_gmapping_range_defaults_come_from_the_sensor_and_its_file_wins():
    from slam_predict.slam.gmapping.params import GMappingParams

    defaults = _loop("gmapping", GMappingParams(particles=2), range_max=12.0).source.params
    assert (defaults.maxRange, defaults.maxUrange) == (pytest.approx(11.99), pytest.approx(11.99))
    thesis = GMappingParams(particles=2, maxRange=60.0, maxUrange=30.0)
    given = _loop("gmapping", thesis, range_max=80.0).source.params
    assert (given.maxRange, given.maxUrange) == (60.0, 30.0)


def test_traversal_reads_the_laser_and_the_old_degree_key_warns(caplog):
    from slam_predict.features.traversal import TraversalConfig

    laser = LaserConfig(fov=math.radians(240.0), range_max=5.6)
    assert TraversalConfig().for_laser(laser).laser_range_m == 5.6
    assert TraversalConfig().for_laser(laser).laser_fov == laser.fov
    assert TraversalConfig().for_laser(SensorConfig().laser, 30.0).laser_range_m == 30.0
    with caplog.at_level(logging.WARNING):
        old = from_dict(TraversalConfig, {"laser_fov_deg": 240.0})
    assert "laser_fov_deg is deprecated" in caplog.text
    assert old.laser_fov == math.radians(240.0) and old.laser_fov_deg is None
    with pytest.raises(InputError, match="not both"):
        from_dict(TraversalConfig, {"laser_fov_deg": 240.0, "laser_fov": 4.0})


def test_feature_version_of_the_shipped_models_is_kept():
    """Models trained before laser_fov (rad) replaced laser_fov_deg keep their version."""
    import json

    from slam_predict.features.plan import full_feature_config, version_of
    from slam_predict.features.vector import feature_version
    from slam_predict.learn.config import yaml_section

    card = json.loads((ROOT / "models" / "thesis-realistic" / "card.json").read_text())
    assert card["feature_config"]["traversal"]["laser_fov_deg"] == 270.0
    assert version_of(card["feature_config"]) == card["feature_version"]
    shipped = full_feature_config(yaml_section(ROOT / "config" / "features.yaml", "features"))
    assert version_of(shipped) == card["feature_version"] == feature_version()
    narrow = dict(shipped, traversal=dict(shipped["traversal"], laser_fov=math.pi))
    assert version_of(narrow) != card["feature_version"]
