"""Navigation config: thesis values from config/, move_base's file layout, strict keys."""
from __future__ import annotations

import math

import pytest

from slam_predict.config import from_dict, to_dict
from slam_predict.errors import InputError
from slam_predict.nav.config import MoveBaseConfig, load_nav_config, merge_nav_files


def test_project_files_hold_the_thesis_values(root):
    cfg = load_nav_config(root / "config")
    assert (cfg.controller_frequency, cfg.planner_frequency) == (10.0, 0.2)
    assert (cfg.controller_patience, cfg.planner_patience,
            cfg.max_planning_retries) == (15.0, 5.0, 3)
    assert [b.type for b in cfg.recovery_behaviors] == [
        "clear_costmap_recovery/ClearCostmapRecovery"]
    tp = cfg.TrajectoryPlannerROS
    assert (tp.max_vel_x, tp.max_vel_theta, tp.acc_lim_x, tp.acc_lim_theta) == (0.85, 0.7, 1.5, 2.5)
    assert (tp.escape_vel, tp.escape_reset_dist, tp.oscillation_reset_dist) == (-0.15, 0.15, 0.25)
    assert (tp.xy_goal_tolerance, tp.yaw_goal_tolerance, tp.sim_time) == (0.3, 0.2, 1.5)
    assert (tp.vx_samples, tp.vtheta_samples, tp.holonomic_robot) == (10, 20, False)
    for costmap in (cfg.global_costmap, cfg.local_costmap):      # costmap_common in both
        assert costmap.inflation_radius == 2.25 and costmap.cost_scaling_factor == 7.5
        assert costmap.obstacle_range == 30.0 and costmap.max_obstacle_height == 0.6
        assert costmap.update_frequency == 2.0
        assert len(costmap.footprint) == 4
    local = cfg.local_costmap
    assert (local.rolling_window, local.width, local.height, local.resolution) == (True, 6, 6, 0.02)
    assert cfg.global_costmap.static_map and cfg.global_costmap.global_frame == "map"


def test_defaults_are_ros_defaults():
    cfg = MoveBaseConfig()
    assert cfg.controller_frequency == 20.0 and cfg.max_planning_retries == -1
    assert cfg.global_costmap.inflation_radius == 0.55
    assert cfg.global_costmap.cost_scaling_factor == 10.0
    assert cfg.TrajectoryPlannerROS.sim_time == 1.7
    assert cfg.TrajectoryPlannerROS.escape_reset_theta == pytest.approx(math.pi / 2)
    assert len(cfg.recovery_behaviors) == 4
    assert from_dict(MoveBaseConfig, to_dict(cfg)) == cfg


def test_unknown_keys_rejected_with_a_hint(tmp_path):
    (tmp_path / "move_base.yaml").write_text("controller_frequncy: 5\n")
    with pytest.raises(InputError, match="did you mean 'controller_frequency'"):
        load_nav_config(tmp_path)
    (tmp_path / "move_base.yaml").write_text("TrajectoryPlannerROS:\n  max_vel: 1.0\n")
    with pytest.raises(InputError, match="max_vel"):
        load_nav_config(tmp_path)


def test_costmap_common_goes_into_both_costmaps_and_own_files_win(tmp_path):
    (tmp_path / "costmap_common.yaml").write_text("inflation_radius: 1.0\nobstacle_range: 4.0\n")
    (tmp_path / "local_costmap.yaml").write_text("local_costmap:\n  inflation_radius: 0.3\n")
    tree = merge_nav_files(tmp_path)
    assert tree["global_costmap"] == {"inflation_radius": 1.0, "obstacle_range": 4.0}
    assert tree["local_costmap"] == {"inflation_radius": 0.3, "obstacle_range": 4.0}
    cfg = load_nav_config(tmp_path, {"TrajectoryPlannerROS": {"max_vel_x": 0.3}})
    assert cfg.local_costmap.inflation_radius == 0.3
    assert cfg.TrajectoryPlannerROS.max_vel_x == 0.3


def test_invalid_values_are_input_errors(tmp_path):
    (tmp_path / "move_base.yaml").write_text("base_global_planner: carrot_planner/CarrotPlanner\n")
    with pytest.raises(InputError, match="base_global_planner"):
        load_nav_config(tmp_path)
    (tmp_path / "move_base.yaml").write_text("TrajectoryPlannerROS:\n  holonomic_robot: true\n")
    with pytest.raises(InputError, match="holonomic"):
        load_nav_config(tmp_path)
