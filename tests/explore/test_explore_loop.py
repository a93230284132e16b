"""The closed loop end to end with the perfect map source: coverage, frontier-free stop,
command limits, stalls, determinism; CI runs tiny and office_500, the sweep is slow."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from slam_predict.explore import run as runner
from slam_predict.explore.loop import ClosedLoop
from slam_predict.world.load import load_plan


@pytest.fixture(scope="module")
def settings(root):
    """The project's settings with the ``nearest`` strategy (these acceptance checks are
    its; the ``thesis`` strategy has tests/explore/test_explore_thesis_strategy.py)."""
    settings = runner.load_explore_settings(root / "config")
    settings.explore = dataclasses.replace(settings.explore, strategy="nearest")
    return settings


def check_run(summary, loop, settings, min_coverage=0.95):
    """The acceptance checks every closed-loop run must pass."""
    assert summary["stop_reason"] == "no_frontiers", summary["explorer_goals"]
    assert summary["coverage"] >= min_coverage
    assert summary["stalls"] <= max(0.0, summary["distance_m"] / 500.0)
    tp = settings.nav.TrajectoryPlannerROS
    cmds = np.array(loop.log.commands)
    dt = np.diff(cmds[:, 0])
    assert np.all(dt > 0)
    assert np.all(cmds[:, 1] <= tp.max_vel_x + 1e-9)
    assert np.all(cmds[:, 1] >= min(tp.escape_vel, 0.0) - 1e-9)
    assert np.all(np.abs(cmds[:, 2]) <= tp.max_vel_theta + 1e-9)
    assert np.all(np.abs(np.diff(cmds[:, 1])) <= tp.acc_lim_x * dt + 1e-9)
    assert np.all(np.abs(np.diff(cmds[:, 2])) <= tp.acc_lim_theta * dt + 1e-9)
    for limit in summary["goal_time_limits_s"]:
        assert limit is None or limit >= settings.explore.goal_timeout_offset


def test_tiny_world_is_explored(root, settings, tmp_path):
    world = load_plan(root / "worlds" / "tiny.world")
    summary, loop = runner.explore_world(world, 1, settings, max_sim_time=900)
    check_run(summary, loop, settings)
    out = runner.write_outputs(tmp_path / "run", summary, loop)
    assert (out / "explore.json").is_file() and (out / "explore.png").stat().st_size > 1000
    assert set(summary) >= {"coverage", "sim_duration_s", "wall_time_s", "distance_m",
                            "rotation_rad", "stalls", "stop_reason"}


def test_office_500_is_explored(root, settings):
    world = load_plan(root / "worlds" / "office_500.world")
    summary, loop = runner.explore_world(world, 1, settings, max_sim_time=2400)
    check_run(summary, loop, settings)


def test_loop_is_deterministic_for_a_seed(root, settings):
    world = load_plan(root / "worlds" / "tiny.world")
    runs = []
    for _ in range(2):
        loop = ClosedLoop(world, 7, settings.nav, settings.explore, settings.sim)
        loop.run(25.0)
        runs.append((np.array(loop.log.true_poses), np.array(loop.log.commands),
                     [g.target for g in loop.navigator.history]))
    np.testing.assert_array_equal(runs[0][0], runs[1][0])
    np.testing.assert_array_equal(runs[0][1], runs[1][1])
    assert runs[0][2] == runs[1][2]
    other = ClosedLoop(world, 8, settings.nav, settings.explore, settings.sim)
    other.run(25.0)
    assert not np.array_equal(np.array(other.log.true_poses), runs[0][0])


def sweep_plans(root, shared):
    plans = [(p, None) for p in sorted((root / "worlds").glob("*.world"))]
    ipa = shared / "floorplans" / "ipa" if shared is not None else None
    if ipa is not None and ipa.is_dir():
        plans += [(p, 0.05) for p in sorted(ipa.glob("*.png")) if "_gt_" not in p.name]
    return plans


@pytest.mark.slow
@pytest.mark.timeout(4 * 3600)   # the sweep takes about an hour on 2 loaded cores
def test_every_shipped_world_and_ipa_plan_is_explored(root, settings, shared_data):
    failures = []
    for plan, resolution in sweep_plans(root, shared_data):
        world = load_plan(plan, resolution=resolution)
        summary, loop = runner.explore_world(world, 1, settings, max_sim_time=4 * 3600)
        try:
            check_run(summary, loop, settings)
        except AssertionError as exc:
            failures.append(f"{plan.name}: {exc}")
    assert not failures, "\n".join(failures)
