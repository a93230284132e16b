"""The orchestrator's params and config file: overrides, world, bad input as one-line errors."""
from __future__ import annotations

from pathlib import Path

import pytest

from slam_predict.errors import InputError
from slam_predict.ros.orchestrator_config import (
    DEFAULT_CONFIG,
    load_orchestrator_config,
    read_setup,
)

ROOT = Path(__file__).resolve().parents[2]
TINY = str(ROOT / "worlds" / "tiny.world")


class Params:
    """rospy.get_param over a dict of private params (``~name``)."""

    def __init__(self, **params):
        self.params = {f"~{k}": v for k, v in params.items()}

    def get_param(self, name, default=KeyError):
        if name in self.params:
            return self.params[name]
        if default is KeyError:
            raise KeyError(name)
        return default


def test_defaults_and_overrides_from_launch_args(tmp_path):
    setup = read_setup(Params(out=str(tmp_path / "run_000"), world_file=TINY, seed="4000000000",
                              run_index=3, max_sim_time=30.0, snapshot_interval=15.0,
                              ground_truth_source="pose", ground_truth_topic="/mocap/pose",
                              wait_for_nodes="/slam_gmapping /move_base,/explore",
                              sim="slam_predict", nav="move_base"))
    assert setup.info.world == "tiny" and setup.info.seed == 4_000_000_000
    assert setup.info.run_index == 3 and setup.info.world_file == TINY
    assert setup.stop.max_sim_time_s == 30.0
    assert setup.stop.interval_s == setup.stop.small_interval_s == 15.0
    assert setup.stop.mse_threshold == setup.settings.stop.mse_threshold
    gt = setup.config.ground_truth
    assert (gt.source, gt.topic) == ("pose", "/mocap/pose")
    assert setup.wait_for_nodes == ("/slam_gmapping", "/move_base", "/explore")
    assert setup.free_area_m2 == pytest.approx(setup.world.free_area_m2)
    assert setup.info.ros["graph"]["nav"] == "move_base"


def test_real_robot_without_world(tmp_path):
    setup = read_setup(Params(out=str(tmp_path / "r"), free_area_m2=0.0, world_name="lab"))
    assert setup.world is None and setup.free_area_m2 is None and setup.info.world == "lab"
    setup = read_setup(Params(out=str(tmp_path / "r"), free_area_m2=180.0))
    assert setup.free_area_m2 == 180.0 and setup.info.world == "robot"


def test_bad_input_is_one_line_naming_the_file(tmp_path):
    with pytest.raises(InputError, match="~out"):
        read_setup(Params())
    with pytest.raises(InputError) as err:
        read_setup(Params(out=str(tmp_path / "r"), ground_truth_source="mocap"))
    assert "orchestrator.yaml" in err.value.one_line() and "'mocap'" in str(err.value)
    bad = tmp_path / "orchestrator.yaml"
    bad.write_text("ground_truth:\n  sorce: pose\n")
    with pytest.raises(InputError, match="unknown config key 'sorce'.*did you mean 'source'"):
        read_setup(Params(out=str(tmp_path / "r"), config=str(bad)))
    with pytest.raises(InputError):
        read_setup(Params(out=str(tmp_path / "r"), world_file=str(tmp_path / "none.world")))
    with pytest.raises(InputError, match="needs ground_truth.frame"):
        load_orchestrator_config(DEFAULT_CONFIG, {"source": "tf"})
    assert "\n" not in err.value.one_line()


def test_ros_runs_drop_the_in_process_compute_delay():
    """Under ROS GMapping's compute time is real: slam_compute is switched off, with a warning."""
    import dataclasses

    from slam_predict.collect.settings import load_settings
    from slam_predict.ros.orchestrator_config import without_compute_delay
    from slam_predict.slam.compute_delay import ComputeDelayConfig

    warnings = []

    class FakeRospy:
        @staticmethod
        def logwarn(*args):
            warnings.append(args)

    lockstep = load_settings()
    assert without_compute_delay(lockstep, FakeRospy) is lockstep and not warnings
    delayed = dataclasses.replace(lockstep, compute=ComputeDelayConfig(model="cost", scan_s=0.4))
    out = without_compute_delay(delayed, FakeRospy)
    assert not out.compute.enabled and "slam_compute" not in out.hashes()
    assert len(warnings) == 1
