"""collect settings with a robot description file (``load_settings(..., robot=FILE)``): the
robot's laser, odometry, speeds and footprint replace the settings', last; settings without a
robot keep the config hashes committed campaigns were collected with."""
import json
from pathlib import Path

import pytest

from slam_predict.collect.settings import load_settings
from slam_predict.config import to_dict
from slam_predict.errors import InputError
from slam_predict.nav.config import load_nav_config
from slam_predict.robot_file import load_robot

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "config"
ROBOTS = CONFIG / "robots"


def differing_paths(old, new, prefix=""):
    """Key paths where two plain trees differ."""
    if isinstance(old, dict) and isinstance(new, dict):
        return [p for key in sorted(set(old) | set(new))
                for p in differing_paths(old.get(key), new.get(key), f"{prefix}{key}.")]
    return [] if old == new else [prefix.rstrip(".")]


def test_settings_without_a_robot_keep_the_committed_campaign_hashes():
    """data/campaigns/fidelity_sizes was collected with config/fidelity/sizes.yaml: its
    run.json hashes must still be what those settings give (resumable campaigns)."""
    record = sorted((ROOT / "data" / "campaigns" / "fidelity_sizes").glob("*/run_000/run.json"))
    recorded = json.loads(record[0].read_text())["config_hashes"]
    assert load_settings(CONFIG / "fidelity" / "sizes.yaml").hashes() == recorded
    assert load_settings(CONFIG / "fidelity" / "sizes.yaml", robot=None).hashes() == recorded


def test_the_fidelity_campaign_resolves_to_its_settings_file():
    """data/campaigns/fidelity_seed_study's runs name the probe file they ran with (removed
    after ef78bcf); the settings file of record resolves to their hashes and resumes it."""
    records = sorted((ROOT / "data" / "campaigns" / "fidelity_seed_study").glob(
        "*/run_*/run.json"))
    assert len(records) >= 51
    recorded = {json.dumps(json.loads(r.read_text())["config_hashes"], sort_keys=True)
                for r in records}
    assert len(recorded) == 1
    ours = load_settings(CONFIG / "fidelity" / "seed_study.yaml").hashes()
    assert json.dumps(ours, sort_keys=True) == recorded.pop()


def test_seed_realistic_changes_only_the_simulators_rounding_and_speed_bounds():
    base = load_settings()
    seed = load_settings(robot=ROBOTS / "seed_realistic.yaml")
    for name in ("gmapping", "nav", "explore", "stop", "metric"):
        assert seed.hashes()[name] == base.hashes()[name], name
    assert differing_paths(to_dict(base.sim), to_dict(seed.sim)) == [
        "laser.fov", "odom.error", "robot.max_vel_theta", "robot.max_vel_x"]
    assert seed.sim.robot.max_vel_x == seed.nav.TrajectoryPlannerROS.max_vel_x == 0.85
    assert seed.sim.robot.max_vel_theta == seed.nav.TrajectoryPlannerROS.max_vel_theta == 0.7


def test_lds_robot_sets_laser_gmapping_caps_and_keeps_the_rest():
    base = load_settings()
    lds = load_settings(robot=ROBOTS / "lds_360_3p5.yaml")
    laser = lds.sim.laser
    assert (laser.fov, laser.samples, laser.range_max, laser.range_min, laser.rate_hz) == \
        (2 * 3.141592653589793, 360, 3.5, 0.12, 5.0)
    assert lds.slam.params.maxRange == base.slam.params.maxRange == 60.0
    assert lds.slam.params.maxUrange == pytest.approx(3.49)
    for name in ("sim", "gmapping"):
        assert lds.hashes()[name] != base.hashes()[name]
    assert lds.hashes()["nav"] == base.hashes()["nav"]
    assert lds.sim.integrator == base.sim.integrator and lds.sim.odom.gaussian == \
        base.sim.odom.gaussian


def test_nav_is_load_nav_config_with_the_robots_overrides(tmp_path):
    text = (ROBOTS / "utm_270_30_poor_odom.yaml").read_text()
    text = text.replace("footprint_side: 0.3", "footprint_side: 0.5").replace(
        "max_vel_theta: 0.7 ", "max_vel_theta: 1.2 ")
    path = tmp_path / "wide.yaml"
    path.write_text(text)
    robot = load_robot(path)
    settings = load_settings(robot=path)
    assert settings.nav == load_nav_config(CONFIG, robot.nav_overrides())
    assert settings.nav.TrajectoryPlannerROS.min_vel_theta == -1.2
    assert settings.nav.global_costmap.footprint[2] == pytest.approx((0.3, 0.3))
    assert settings.explore.thesis.inscribed_radius == pytest.approx(0.3)
    assert settings.sim.robot.footprint_side == 0.5


def test_robot_is_merged_after_the_settings_sim_overrides(tmp_path):
    settings_file = tmp_path / "s.yaml"
    settings_file.write_text(f"extends: {CONFIG / 'collect.yaml'}\nsim_overrides:\n"
                             "  ranger_model: stage\n  odom: {model: gaussian_per_step}\n"
                             "  laser: {range_max: 60.0}\n")
    settings = load_settings(settings_file, robot=ROBOTS / "urg_240_5p6.yaml")
    assert settings.sim.ranger_model == "stage"            # the settings' own choice, kept
    assert settings.sim.odom.model == "fixed"              # the robot's, over the settings'
    assert settings.sim.laser.range_max == 5.6


@pytest.mark.parametrize("edit, words", [
    (("max_vel_x: 0.85", "max_vel_x: 0.05"), ["max_vel_x 0.05 m/s", "min_vel_x 0.1"]),
    (("max_vel_theta: 0.7", "max_vel_theta: 0.3"), ["max_vel_theta 0.3", "min_in_place"]),
])
def test_speeds_the_planner_cannot_use_are_refused(tmp_path, edit, words):
    path = tmp_path / "slow.yaml"
    path.write_text((ROBOTS / "seed_realistic.yaml").read_text().replace(*edit))
    with pytest.raises(InputError) as info:
        load_settings(robot=path)
    assert info.value.path == str(path)
    assert all(word in info.value.problem for word in words), info.value.problem
