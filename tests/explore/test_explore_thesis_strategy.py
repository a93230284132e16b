"""``strategy: thesis`` with a scripted goal client (timing, goal keeping, time limit, random
fallback, back-off, return home), a short closed loop on tiny.world, strict config."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from test_explore_explorer import FakeClient

from slam_predict.config import from_dict
from slam_predict.errors import InputError
from slam_predict.explore import run as runner
from slam_predict.explore.explorer import ExploreConfig, Explorer
from slam_predict.explore.goals import ABORTED, SUCCEEDED
from slam_predict.explore.thesis_strategy import ThesisExplorer
from slam_predict.slam import OccupancyGrid
from slam_predict.world.load import load_plan


def room_grid(open_right=True):
    """A 6 m x 4 m free room (0.05 m cells) walled on three sides, unknown to its right."""
    data = np.full((160, 240), -1, np.int8)
    data[40:120, 40:160] = 0
    data[40:120, 40] = data[40, 40:160] = data[119, 40:160] = 100
    if not open_right:
        data[40:120, 159] = 100
    return OccupancyGrid(data, 0.05, (0.0, 0.0))


POSE = np.array([3.0, 4.0, 0.0])


def make(**thesis):
    cfg = ExploreConfig(strategy="thesis")
    cfg = dataclasses.replace(cfg, thesis=dataclasses.replace(cfg.thesis, **thesis))
    client = FakeClient()
    return Explorer(cfg, client, np.random.default_rng(0)), client


def run_until(explorer, t0, t1, grid, dt=0.1):
    t = t0
    while t <= t1 + 1e-9:
        explorer.step(round(t, 6), grid, POSE)
        t += dt
    return round(t, 6)


def test_explorer_factory_and_first_goal_after_the_start_delay():
    explorer, client = make()
    assert isinstance(explorer, ThesisExplorer)
    grid = room_grid()
    run_until(explorer, 0.0, 16.9, grid)
    assert client.sent == []
    run_until(explorer, 17.0, 17.0, grid)
    (t, target), = client.sent
    assert t == pytest.approx(17.0) and target[2] == 0.0          # yaw 0: the package's w = 1
    assert 7.0 < target[0] < 8.0                                 # near the open side (x = 8 m)
    frontier = explorer.goal.point
    assert math.hypot(target[0] - frontier[0], target[1] - frontier[1]) == pytest.approx(0.1)


def test_goal_is_kept_until_the_time_limit_then_a_random_point_follows():
    explorer, client = make()
    grid = room_grid()
    run_until(explorer, 0.0, 17.0, grid)
    t_sent = client.sent[0][0]
    other = room_grid(open_right=False)                          # the map changes: no effect
    run_until(explorer, 17.1, t_sent + 90.4, other)
    assert len(client.sent) == 1 and client.cancelled == []
    run_until(explorer, t_sent + 90.5, t_sent + 90.5, grid)
    assert client.cancelled == [pytest.approx(t_sent + 90.5)]
    assert explorer.log.goals[-1]["outcome"] == "timeout"
    assert explorer.store.unreachable and explorer.failed_last
    run_until(explorer, t_sent + 90.6, t_sent + 92.4, grid)
    assert len(client.sent) == 1
    run_until(explorer, t_sent + 92.5, t_sent + 92.5, grid)
    assert len(client.sent) == 2 and explorer.goal.kind == "random"


@pytest.mark.parametrize("tau,detected", [(1.2, 1.2), (5.2, 5.5)])
def test_results_are_seen_at_the_first_wait_or_the_next_half_second_poll(tau, detected):
    explorer, client = make()
    grid = room_grid()
    run_until(explorer, 0.0, 17.0, grid)
    t_sent, point = client.sent[0][0], tuple(explorer.goal.point)
    run_until(explorer, 17.1, t_sent + tau - 0.1, grid)
    client._status = SUCCEEDED
    run_until(explorer, t_sent + tau, t_sent + detected - 0.1, grid)
    assert explorer.goal is not None
    run_until(explorer, t_sent + detected, t_sent + detected, grid)
    assert explorer.goal is None and explorer.log.goals[-1]["outcome"] == "succeeded"
    assert explorer.store.visited[-1] == point                   # the frontier point
    assert not explorer.failed_last
    end = t_sent + detected
    run_until(explorer, end + 0.1, end + 1.9, grid)
    assert len(client.sent) == 1                                 # the 2 s pause
    run_until(explorer, end + 2.0, end + 2.0, grid)
    assert len(client.sent) == 2 and explorer.goal.kind == "frontier"


def test_an_aborted_goal_is_unreachable_and_the_next_is_random():
    explorer, client = make()
    grid = room_grid()
    run_until(explorer, 0.0, 17.0, grid)
    point = tuple(explorer.goal.point)
    client._status = ABORTED
    run_until(explorer, 17.1, 19.0, grid)
    assert explorer.log.goals[-1]["outcome"] == "aborted"
    assert explorer.store.unreachable[-1] == point and explorer.failed_last
    run_until(explorer, 19.1, 21.5, grid)
    assert explorer.goal.kind == "random"


def test_only_invalid_points_turn_in_place_then_finish():
    """A closed room: the home point, stored as a frontier and never cleared as seen while it
    is the only point (the package's > 1 rule), is an invalid goal: turns, then home."""
    explorer, client = make(max_idle_turns=2)
    grid = room_grid(open_right=False)
    t = run_until(explorer, 0.0, 17.0, grid)
    for _ in range(2):
        assert explorer.goal.kind == "turn"
        assert client.sent[-1][1] == (3.0, 4.0, pytest.approx(45.0 - 14 * math.pi))
        client._status = SUCCEEDED
        t = run_until(explorer, t, t + 2.5, grid)
    assert explorer.goal.kind == "home"
    client._status = SUCCEEDED
    run_until(explorer, t, t + 1.0, grid)
    assert explorer.done and explorer.log.stop_reason == "only_invalid_frontiers"


def test_nothing_left_drives_home_then_stops():
    explorer, client = make()
    grid = room_grid(open_right=False)
    run_until(explorer, 0.0, 0.0, grid)
    explorer.store.points.clear()                                # no stored point at all
    run_until(explorer, 0.1, 17.0, grid)
    (t, target), = client.sent
    assert explorer.goal.kind == "home" and target == (3.0, 4.0, 0.0)
    t = 17.1
    for attempt in range(5):                                     # 5 attempts, each aborted
        assert not explorer.done and len(client.sent) == attempt + 1
        client._status = ABORTED
        t = run_until(explorer, t, t + 1.0, grid)
    assert explorer.done and explorer.log.stop_reason == "no_frontiers"
    assert len(client.sent) == 5
    explorer, client = make(return_home=False)
    run_until(explorer, 0.0, 0.0, grid)
    explorer.store.points.clear()
    run_until(explorer, 0.1, 17.0, grid)
    assert explorer.done and client.sent == []


def test_config_is_strict():
    with pytest.raises(ValueError):
        ExploreConfig(strategy="thesis_like")
    with pytest.raises(InputError):
        from_dict(ExploreConfig, {"strategy": "thesis", "thesis": {"pause": 1.0}})
    with pytest.raises(InputError):
        from_dict(ExploreConfig, {"thesis": {"max_time_before_goal_abortion": 0.0}})
    cfg = from_dict(ExploreConfig, {"thesis": {"selection_pause": 1.5}})
    assert cfg.thesis.selection_pause == 1.5


@pytest.mark.parametrize("data, where", [
    ({"tie_tolerance": -0.1}, "'tie_tolerance' must be ≥ 0"),
    ({"max_goal_attempts": 0}, "'max_goal_attempts' must be ≥ 1"),
    ({"goal_timeout_factor": 0.0}, "'goal_timeout_factor' must be > 0"),
    ({"thesis": {"inflation_radius": -2.0}}, "'thesis.inflation_radius' must be ≥ 0"),
])
def test_config_value_ranges_name_the_key_path(data, where):
    with pytest.raises(InputError, match=where):
        from_dict(ExploreConfig, data, "explore.yaml")
    assert from_dict(ExploreConfig, {"thesis": {"turn_yaw": -3.0}}).thesis.turn_yaw == -3.0


def test_tiny_world_closed_loop_explores_and_returns_home(root):
    settings = runner.load_explore_settings(root / "config")
    settings.explore = dataclasses.replace(settings.explore, strategy="thesis")
    world = load_plan(root / "worlds" / "tiny.world")
    summary, loop = runner.explore_world(world, 1, settings, max_sim_time=900)
    assert summary["stop_reason"] == "no_frontiers"
    assert summary["coverage"] >= 0.8 and summary["stalls"] == 0
    kinds = [g["kind"] for g in loop.explorer.log.goals]
    assert kinds[-1] == "home" and loop.explorer.log.goals[-1]["outcome"] == "succeeded"
    end = loop.log.true_poses[-1]
    assert math.hypot(*(end[:2] - world.start_pose[:2])) < 0.5
    sent = [g["t_sent"] for g in loop.explorer.log.goals]
    ends = [g["t_end"] for g in loop.explorer.log.goals]
    assert sent[0] >= 17.0 - 1e-6
    assert all(s - e >= 2.0 - 1e-6 for s, e in zip(sent[1:], ends[:-1], strict=True))


def test_turns_count_toward_the_end_only_when_no_point_is_valid():
    explorer, client = make(max_idle_turns=3)
    run_until(explorer, 0.0, 0.0, room_grid())
    explorer.store.points.clear()
    explorer.store.add_cells(np.array([[1.0, 1.0], [5.0, 5.0]]))
    explorer.store.unreachable = [(1.0, 1.0)]           # one invalid, one valid point
    for k in range(8):                                  # e.g. unlucky random draws
        explorer.goal = None
        explorer._turn(float(k), POSE)
    assert not explorer.done and explorer.goal.kind == "turn"
    explorer.store.unreachable.append((5.0, 5.0))       # now none is valid
    for k in range(3):
        explorer.goal = None
        explorer._turn(10.0 + k, POSE)
        assert explorer.goal.kind == "turn"
    explorer.goal = None
    explorer._turn(20.0, POSE)
    assert explorer.goal.kind == "home"                 # finishing: drive home first
