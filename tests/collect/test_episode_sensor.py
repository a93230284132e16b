"""run.json records the whole SensorConfig a run sensed with (``sensor``)."""
import dataclasses
from pathlib import Path

from slam_predict.collect.batch import RunSpec
from slam_predict.collect.episode import run_episode
from slam_predict.collect.record import load_record
from slam_predict.collect.settings import load_settings
from slam_predict.config import to_dict
from slam_predict.sensor import sensor_hash
from slam_predict.sim.config import LaserOverrides
from slam_predict.sim.simulator import resolve_sensor
from slam_predict.world.load import load_plan

ROOT = Path(__file__).resolve().parents[2]
TINY = ROOT / "worlds" / "tiny.world"
if not TINY.exists():
    TINY = ROOT / "tests" / "data" / "world_map" / "tiny.world"


def test_run_json_carries_the_sensor(tmp_path):
    settings = load_settings()
    settings.slam.params = dataclasses.replace(settings.slam.params, particles=4)
    settings.stop = dataclasses.replace(settings.stop, max_sim_time_s=15.0, small_interval_s=10.0)
    settings.sim = dataclasses.replace(settings.sim, laser=dataclasses.replace(
        settings.sim.laser, range_max=12.0, samples=271))
    spec = RunSpec(str(TINY), "tiny", 0, 5, str(tmp_path / "tiny" / "run_000"))
    record = run_episode(spec, settings)
    expected = to_dict(resolve_sensor(load_plan(TINY), settings.sim))
    assert record["sensor"] == expected
    assert expected["laser"]["range_max"] == 12.0 and expected["laser"]["samples"] == 271
    assert record["sensor"]["odom"]["error"] == record["odometry_error"]["bound"]
    reloaded, _ = load_record(Path(spec.out_dir))
    assert sensor_hash(reloaded["sensor"]) == sensor_hash(resolve_sensor(load_plan(TINY),
                                                                         settings.sim))
    assert isinstance(settings.sim.laser, LaserOverrides)
