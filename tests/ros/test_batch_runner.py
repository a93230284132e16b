"""batch_explore's pure parts: worlds, node choices, per-node seeds, single_run.launch arguments."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from slam_predict.collect.batch import Batch, BatchConfig, RunSpec
from slam_predict.collect.store import run_seed
from slam_predict.errors import InputError
from slam_predict.ros import batch_runner as br

ROOT = Path(__file__).resolve().parents[2]


def test_node_seeds_follow_the_in_process_split_and_fit_xmlrpc():
    seeds = br.node_seeds(123)
    children = np.random.SeedSequence(123).spawn(3)   # ClosedLoop: sim, explore, slam
    assert seeds == {"sim_seed": int(children[0].generate_state(1)[0] >> 1),
                     "explore_seed": int(children[1].generate_state(1)[0] >> 1),
                     "slam_seed": int(children[2].generate_state(1)[0] >> 1)}
    assert len(set(seeds.values())) == 3 and br.node_seeds(123) == seeds
    for seed in range(50):
        assert all(0 <= v < 2 ** 31 for v in br.node_seeds(seed).values())


def test_find_worlds(tmp_path):
    assert br.find_worlds(str(ROOT / "worlds" / "tiny.world")) == {
        "tiny": str((ROOT / "worlds" / "tiny.world").resolve())}
    worlds = br.find_worlds(str(ROOT / "worlds"))
    assert "tiny" in worlds and list(worlds) == sorted(worlds)
    with pytest.raises(InputError, match="no \\*.world files"):
        br.find_worlds(str(tmp_path))
    with pytest.raises(InputError, match="no such world file or folder"):
        br.find_worlds(str(tmp_path / "missing"))


def test_choices_are_checked_with_a_hint():
    br.check_choices({"sim": "stage", "slam": "gmapping", "nav": "none",
                      "explore": "explore_lite"})
    with pytest.raises(InputError, match="nav:=move_bas is not one of .*did you mean 'move_base'"):
        br.check_choices({"nav": "move_bas"})


def test_launch_arguments_of_a_batch_run(tmp_path):
    batch = Batch({"tiny": str(ROOT / "worlds" / "tiny.world")}, tmp_path,
                  BatchConfig(runs=2, base_seed=7, options={"nav": "move_base",
                                                            "max_sim_time": 30.0,
                                                            "ground_truth_source": ""}))
    spec = batch.pending()[1]
    args = dict(a.split(":=", 1) for a in br.launch_arguments(spec))
    assert args["world"] == str(ROOT / "worlds" / "tiny.world") and args["world_name"] == "tiny"
    assert args["run_index"] == "1" and args["seed"] == str(run_seed(7, "tiny", 1))
    assert args["out"] == str(tmp_path / "tiny" / "run_001")
    assert args["sim_seed"] == str(br.node_seeds(spec.seed)["sim_seed"])
    assert args["nav"] == "move_base" and args["sim"] == "slam_predict"
    assert args["max_sim_time"] == "30.0" and "ground_truth_source" not in args
    config = ROOT / "config"
    assert args["settings"] == str(config / "collect.yaml")
    assert args["robot_config"] == str(config / "robot.yaml")
    assert args["gmapping_config"] == str(config / "gmapping.yaml")
    assert args["nav_config_dir"] == str(config)
    assert args["explore_config"] == str(config / "explore.yaml")


def test_component_configs_follow_the_settings_file(tmp_path):
    (tmp_path / "nav").mkdir()
    settings = tmp_path / "collect.yaml"
    settings.write_text("robot: my_robot.yaml\nnavigation: nav\n")
    got = br.component_configs(str(settings))
    assert got["robot_config"] == str(tmp_path / "my_robot.yaml")
    assert got["nav_config_dir"] == str(tmp_path / "nav")
    assert got["gmapping_config"] == str(tmp_path / "gmapping.yaml")
    settings.write_text("robots: x.yaml\n")
    with pytest.raises(InputError, match="unknown config key 'robots'.*did you mean 'robot'"):
        br.component_configs(str(settings))


def test_the_slam_back_end_and_inline_parameters_reach_the_launch(tmp_path):
    import yaml

    settings = tmp_path / "collect.yaml"
    settings.write_text("slam: {type: dummy, params: {delta: 0.1}}\n")
    got = br.component_configs(str(settings))
    assert got["slam_type"] == "dummy"
    assert yaml.safe_load(Path(got["gmapping_config"]).read_text()) == {"type": "dummy",
                                                                          "delta": 0.1}
    assert br.component_configs(str(ROOT / "config" / "collect.yaml"))["slam_type"] == "gmapping"


def test_run_spec_options_reach_the_launch(tmp_path):
    spec = RunSpec("/w/a.world", "a", 0, 5, str(tmp_path / "a" / "run_000"),
                   {"sim": "stage", "speedup": 0.0, "odom_model": "fixed"})
    args = br.launch_arguments(spec)
    assert "sim:=stage" in args and "odom_model:=fixed" in args and "speedup:=0.0" in args


class _FakePM:
    """Process monitor stand-in: all processes have exited from the ``checks``-th look on;
    ``on_check(n)`` runs at each look."""

    def __init__(self, checks=None, on_check=None):
        self.checks, self.on_check, self.count = checks, on_check, 0

    @property
    def is_shutdown(self):
        self.count += 1
        if self.on_check:
            self.on_check(self.count)
        return self.checks is not None and self.count >= self.checks


class _FakeLaunch:
    """ROSLaunchParent stand-in."""

    def __init__(self, **pm):
        self.runner = type("Runner", (), {})()
        self.runner.pm = _FakePM(**pm)

    def spin_once(self):
        raise AssertionError("spin_once re-takes the signal handlers: not to be called")


def _spec(tmp_path):
    return RunSpec("w.world", "w", 0, 1, str(tmp_path / "w" / "run_000"))


def test_a_run_ends_when_every_process_of_its_launch_has_exited(tmp_path):
    import time
    launch = _FakeLaunch(checks=3)
    assert br._wait_for_run_end(launch, tmp_path / "run.json", time.monotonic(), 60.0,
                                _spec(tmp_path)) == "ended"


def test_a_stop_request_ends_the_run_wait(tmp_path):
    import time

    from slam_predict.collect import interrupt
    launch = _FakeLaunch(on_check=lambda n: n == 2 and interrupt.request_stop())
    try:
        assert br._wait_for_run_end(launch, tmp_path / "run.json", time.monotonic(), 60.0,
                                    _spec(tmp_path)) == "stop"
    finally:
        interrupt.reset()


def test_nodes_left_running_after_the_record_are_not_waited_for_forever(tmp_path, monkeypatch):
    import time
    monkeypatch.setattr(br, "END_GRACE_S", 0.3)
    (tmp_path / "run.json").write_text("{}")
    started = time.monotonic()
    assert br._wait_for_run_end(_FakeLaunch(), tmp_path / "run.json", started, 60.0,
                                _spec(tmp_path)) == "timeout"
    assert time.monotonic() - started < 5.0


# -- campaign.json on the ROS path -------------------------------------------------------------

def no_episode(spec):
    raise AssertionError("a refused resume must not start any run")


def test_a_resume_with_another_seed_or_nodes_is_refused_and_force_goes_on(tmp_path, monkeypatch):
    from slam_predict.collect.campaign import CampaignMismatch, read_campaign

    out = tmp_path / "data"
    first = br.open_ros_campaign(out, {"max_sim_time": 45.0}, base_seed=0)
    assert first["base_seed"] == 0 and first["ros"]["slam"] == "slam_predict"
    assert first["ros"]["max_sim_time"] == "45.0"
    assert br.open_ros_campaign(out, {"max_sim_time": 45.0}, base_seed=0)["base_seed"] == 0
    written = (out / "campaign.json").read_text()
    monkeypatch.setattr(br, "launch_episode", no_episode)
    tiny = str(ROOT / "worlds" / "tiny.world")
    for options, seed, words in [({"max_sim_time": 45.0}, 5, "--seed 0, not --seed 5"),
                                 ({"max_sim_time": 45.0, "slam": "gmapping"}, 0,
                                  "slam: 'slam_predict' -> 'gmapping'"),
                                 ({"max_sim_time": 60}, 0, "max_sim_time: '45.0' -> '60.0'")]:
        with pytest.raises(CampaignMismatch, match=words) as refused:
            br.run_batch(tiny, 1, str(out), options, base_seed=seed)
        assert "force:=true" in str(refused.value)
        assert (out / "campaign.json").read_text() == written
        assert not (out / "tiny").exists()
    forced = br.open_ros_campaign(out, {"max_sim_time": 45.0, "force": "true"}, base_seed=5)
    assert forced["base_seed"] == 5 and read_campaign(out / "campaign.json")["history"]


def test_a_collect_campaign_is_not_resumed_through_the_ros_graph(tmp_path):
    from slam_predict.collect.campaign import CampaignMismatch, identity, open_campaign
    from slam_predict.collect.record import code_version
    from slam_predict.collect.settings import load_settings

    out = tmp_path / "data"
    out.mkdir()
    open_campaign(out, identity(load_settings(), 0, code_version()))
    with pytest.raises(CampaignMismatch, match="collected in-process"):
        br.open_ros_campaign(out, {}, base_seed=0)


def test_slam_type_karto_picks_the_karto_settings_and_node(tmp_path):
    options = {"slam_type": "slam_toolbox"}
    br.resolve_slam_type(options)
    assert options == {"settings": str(ROOT / "config" / "collect_karto.yaml")}
    configs = br.component_configs(options["settings"])
    assert configs["slam_type"] == "karto" and configs["karto_mode"] == "sync"
    assert configs["gmapping_config"] == str(ROOT / "config" / "karto.yaml")
    assert br.run_nodes(options)[-1] == "/slam_toolbox"
    assert br.run_nodes({"slam": "gmapping", **options})[-1] == "/slam_gmapping"
    settings = tmp_path / "s.yaml"
    settings.write_text(f"extends: {ROOT / 'config' / 'collect_karto.yaml'}\n"
                        "slam: {type: karto, params: {scan_gate: async}}\n")
    assert br.component_configs(str(settings))["karto_mode"] == "async"
    with pytest.raises(InputError, match="slam.type is gmapping, not karto"):
        br.resolve_slam_type({"slam_type": "karto",
                              "settings": str(ROOT / "config" / "collect.yaml")})
    same = {"slam_type": "gmapping"}
    br.resolve_slam_type(same)
    assert same["settings"] == str(ROOT / "config" / "collect.yaml")
