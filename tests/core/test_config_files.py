"""The shipped config/ files load strictly; a bad key or value names the file that holds it."""
from __future__ import annotations

import shutil

import pytest

from slam_predict.errors import InputError
from slam_predict.explore.run import load_explore_settings
from slam_predict.nav.config import load_nav_config


@pytest.fixture()
def config_dir(root, tmp_path):
    """A copy of the project's config/ to spoil one file at a time."""
    copy = tmp_path / "config"
    shutil.copytree(root / "config", copy)
    return copy


def test_shipped_files_load(root):
    settings = load_explore_settings(root / "config", "gmapping")
    assert settings.nav.controller_frequency > 0 and settings.slam_params.particles >= 1


@pytest.mark.parametrize("name,extra,message", [
    ("local_costmap.yaml", "  widht: 3\n",
     "unknown config key 'widht' in 'local_costmap' (did you mean 'width'?)"),
    ("local_costmap.yaml", "  resolution: -1\n", "'local_costmap.resolution' must be > 0"),
    ("global_costmap.yaml", "local_costmap: {}\n", "unknown config key 'local_costmap'"),
    ("costmap_common.yaml", "inflation_radius: -3\n", "'inflation_radius' must be ≥ 0"),
    ("base_local_planner.yaml", "  vx_samples: 0\n",
     "'TrajectoryPlannerROS.vx_samples' must be ≥ 1, got 0"),
    ("move_base.yaml", "controller_frequncy: 3\n", "did you mean 'controller_frequency'"),
    ("closed_loop.yaml", "loops: {}\n", "unknown config key 'loops' (did you mean 'loop'?)"),
    ("closed_loop.yaml", "loop:\n  max_sim_tim: 3\n", "unknown config key 'max_sim_tim' in 'loop'"),
    ("closed_loop.yaml", "loop:\n  max_sim_time: 0\n", "'loop.max_sim_time' must be > 0, got 0.0"),
    ("robot.yaml", "  odom:\n    gaussian: [0, 0, -1, 0]\n", "'sim.odom.gaussian' must be ≥ 0"),
    ("robot.yaml", "integrator: exact\n", "unknown config key 'integrator' (expected 'sim')"),
    ("gmapping.yaml", "occ_thresh: 1.5\n", "'occ_thresh' must be in [0, 1], got 1.5"),
])
def test_bad_key_or_value_names_its_file(config_dir, name, extra, message):
    with open(config_dir / name, "a") as handle:
        handle.write(extra)
    with pytest.raises(InputError) as info:
        load_explore_settings(config_dir, "gmapping")
    assert info.value.path == str(config_dir / name)
    assert message in info.value.problem


def test_collect_settings_stop_section(config_dir):
    from slam_predict.collect.settings import load_settings

    with open(config_dir / "collect.yaml", "a") as handle:
        handle.write("stop:\n  max_snapshots: -5\n")
    with pytest.raises(InputError) as info:
        load_settings(config_dir / "collect.yaml")
    assert info.value.problem == "'stop.max_snapshots' must be ≥ 1, got -5"


def test_nav_loader_alone(config_dir):
    (config_dir / "costmap_common.yaml").write_text("robot_radius: -0.2\n")
    with pytest.raises(InputError, match="costmap_common.yaml: 'robot_radius' must be ≥ 0"):
        load_nav_config(config_dir)
