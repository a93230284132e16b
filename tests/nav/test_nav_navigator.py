"""The move_base state machine: outcomes, texts, retries, patience, preemption, limits."""
from __future__ import annotations

import dataclasses
import math
from types import SimpleNamespace

import numpy as np
import pytest

from slam_predict.nav.config import load_nav_config
from slam_predict.nav.navigator import (
    TEXT_NEW_GOAL,
    TEXT_NO_CONTROL,
    TEXT_NO_PLAN,
    TEXT_OSCILLATING,
    TEXT_REACHED,
    GoalStatus,
    Navigator,
    State,
)

RES = 0.05
IDENTITY = np.zeros(3)


def room_grid(walls=()):
    """An 8 m x 6 m room (map frame origin at its lower-left corner), walls 0.1 m thick."""
    data = np.zeros((120, 160), np.int8)
    data[:2, :] = data[-2:, :] = 100
    data[:, :2] = data[:, -2:] = 100
    for r0, r1, c0, c1 in walls:
        data[r0:r1, c0:c1] = 100
    return SimpleNamespace(data=data, origin=(0.0, 0.0), resolution=RES)


@pytest.fixture(scope="module")
def cfg(root):
    return load_nav_config(root / "config")


def drive(nav, pose, t0, seconds, dt=0.1, move=True):
    """Step the navigator with an ideal unicycle (velocity = command); returns pose, t, cmds."""
    t = t0
    vel = (0.0, 0.0)
    cmds = []
    for _ in range(int(round(seconds / dt))):
        t += dt
        cmd = nav.step(t, pose, IDENTITY, vel)
        cmds.append((t, *cmd))
        if move:
            v, w = cmd
            pose = np.array([pose[0] + v * math.cos(pose[2]) * dt,
                             pose[1] + v * math.sin(pose[2]) * dt, pose[2] + w * dt])
            vel = cmd
        if nav.goal is None:
            break
    return pose, t, np.array(cmds)


def test_goal_reached_with_move_base_text_and_limited_commands(cfg):
    nav = Navigator(cfg)
    nav.set_map(room_grid())
    start = np.array([1.0, 1.0, 0.0])
    record = nav.send_goal((6.0, 4.0, math.pi / 2), 0.0)
    pose, t, cmds = drive(nav, start, 0.0, 60.0)
    assert record.status == GoalStatus.SUCCEEDED and record.text == TEXT_REACHED
    assert math.hypot(pose[0] - 6.0, pose[1] - 4.0) <= 0.3
    assert record.plan_length == pytest.approx(math.hypot(5, 3), rel=0.15)
    tp = cfg.TrajectoryPlannerROS
    dt = np.diff(cmds[:, 0])
    assert np.all(np.abs(cmds[:, 1]) <= tp.max_vel_x + 1e-9)
    assert np.all(np.abs(cmds[:, 2]) <= tp.max_vel_theta + 1e-9)
    assert np.all(np.abs(np.diff(cmds[:, 1])) <= tp.acc_lim_x * dt + 1e-9)
    assert np.all(np.abs(np.diff(cmds[:, 2])) <= tp.acc_lim_theta * dt + 1e-9)


def test_unreachable_goal_aborts_after_retries_and_recovery(cfg, monkeypatch):
    box = [(60, 62, 100, 140), (90, 92, 100, 140), (60, 92, 100, 102), (60, 92, 138, 140)]
    nav = Navigator(cfg)
    nav.set_map(room_grid(box))
    calls = []
    original = nav.planner.make_plan
    monkeypatch.setattr(nav.planner, "make_plan",
                        lambda *a, **k: calls.append(1) or original(*a, **k))
    record = nav.send_goal((6.0, 3.8, 0.0), 0.0)
    drive(nav, np.array([1.0, 1.0, 0.0]), 0.0, 10.0)
    assert record.status == GoalStatus.ABORTED and record.text == TEXT_NO_PLAN
    assert record.recoveries == ["conservative_reset"]
    # max_planning_retries 3: four attempts, the recovery, four more attempts
    assert len(calls) == 2 * (cfg.max_planning_retries + 1)
    assert nav.goal is None and nav.state == State.PLANNING


def test_planner_patience_without_retry_limit(cfg):
    import dataclasses
    unlimited = dataclasses.replace(cfg, max_planning_retries=-1)
    nav = Navigator(unlimited)
    nav.set_map(room_grid([(0, 120, 80, 82)]))       # a wall splitting the room
    record = nav.send_goal((6.0, 3.0, 0.0), 0.0)
    _, t, _ = drive(nav, np.array([1.0, 1.0, 0.0]), 0.0, 30.0)
    assert record.status == GoalStatus.ABORTED and record.text == TEXT_NO_PLAN
    assert t > 2 * unlimited.planner_patience      # patience, recovery, patience again


def test_new_goal_preempts_and_cancel(cfg):
    nav = Navigator(cfg)
    nav.set_map(room_grid())
    first = nav.send_goal((6.0, 4.0, 0.0), 0.0)
    drive(nav, np.array([1.0, 1.0, 0.0]), 0.0, 1.0)
    second = nav.send_goal((2.0, 4.0, 0.0), 1.0)
    assert first.status == GoalStatus.PREEMPTED and first.text == TEXT_NEW_GOAL
    assert second.status == GoalStatus.ACTIVE
    nav.cancel_goal(1.5)
    assert second.status == GoalStatus.PREEMPTED and second.text == ""
    assert [g.id for g in nav.history] == [first.id, second.id]


def test_no_valid_control_aborts_after_controller_patience(cfg):
    nav = Navigator(cfg)
    nav.set_map(room_grid())
    pose = np.array([2.0, 3.0, 0.0])
    # a wall seen by the laser (not in the SLAM map) closes the robot's side of the room
    wall = np.column_stack([np.full(121, 3.0), np.linspace(0.0, 6.0, 121)])
    ranges = np.hypot(wall[:, 0] - pose[0], wall[:, 1] - pose[1])
    angles = np.arctan2(wall[:, 1] - pose[1], wall[:, 0] - pose[0])
    order = np.argsort(angles)
    nav.add_scan(ranges[order], angles[order], 0.0, 30.0, pose, IDENTITY, IDENTITY)
    record = nav.send_goal((6.0, 3.0, 0.0), 0.0)
    _, t, _ = drive(nav, pose, 0.0, 60.0, move=False)
    assert record.status == GoalStatus.ABORTED and record.text == TEXT_NO_CONTROL
    assert record.recoveries == ["conservative_reset"]
    # move_base keeps last_valid_control across the recovery: the second failure aborts at once
    assert cfg.controller_patience < t < cfg.controller_patience + 2.0


def test_oscillation_timeout(cfg):
    import dataclasses
    osc = dataclasses.replace(cfg, oscillation_timeout=3.0)
    nav = Navigator(osc)
    nav.set_map(room_grid())
    record = nav.send_goal((6.0, 4.0, 0.0), 0.0)
    _, t, _ = drive(nav, np.array([1.0, 1.0, 0.0]), 0.0, 20.0, move=False)
    assert record.status == GoalStatus.ABORTED and record.text == TEXT_OSCILLATING
    assert 6.0 <= t <= 8.0


def back_up_config(cfg, timeout=3.0):
    """``cfg`` with the oscillation trigger on and a back-up as its only recovery."""
    from slam_predict.nav.config import RecoveryBehaviorConfig

    back_up = RecoveryBehaviorConfig("back_up", "slam_predict/BackUpRecovery", backup_dist=0.3,
                                     backup_speed=0.15, time_allowance=5.0)
    return dataclasses.replace(cfg, oscillation_timeout=timeout,
                               oscillation_recovery_behaviors=(back_up,))


def test_oscillation_backs_up_then_aborts(cfg):
    """A robot that cannot move: after oscillation_timeout the back-up commands escape
    (negative v, no turn) for its time allowance, then after another timeout the goal is
    ABORTED as move_base's oscillation; the PLANNING/CONTROLLING recoveries stay the list's."""
    nav = Navigator(back_up_config(cfg))
    nav.set_map(room_grid())
    record = nav.send_goal((6.0, 4.0, 0.0), 0.0)
    _, t, cmds = drive(nav, np.array([1.0, 1.0, 0.0]), 0.0, 30.0, move=False)
    assert record.status == GoalStatus.ABORTED and record.text == TEXT_OSCILLATING
    assert record.recoveries == ["back_up"]
    backing = cmds[cmds[:, 1] < 0]
    assert len(backing) > 0 and np.all(backing[:, 2] == 0.0)
    assert backing[:, 0].min() > 3.0 and np.isclose(backing[:, 1].min(), -0.15)
    assert 3.0 + 5.0 + 3.0 <= t <= 3.0 + 5.0 + 3.0 + 2.5     # timeout, allowance, timeout


@pytest.mark.parametrize("across", [False, True])
def test_oscillation_across_goals_backs_up_a_robot_whose_goals_all_fail(cfg, across):
    """Goals that fail at planning end within seconds and each new goal restarts move_base's
    oscillation timer, so a robot no plan leaves never backs up; with oscillation_across_goals
    the timer runs on over the goals and the back-up comes in PLANNING."""
    nav = Navigator(dataclasses.replace(back_up_config(cfg), oscillation_across_goals=across))
    nav.set_map(room_grid())
    t, records, pose = 0.0, [], np.array([1.0, 1.0, 0.0])
    while t < 12.0:
        records.append(nav.send_goal((50.0, 5.0, 0.0), t))
        _, t, _ = drive(nav, pose, t, 5.0, move=False)
    backed = [r for r in records if "back_up" in r.recoveries]
    assert records[0].status == GoalStatus.ABORTED and records[0].t_end < 1.5
    assert bool(backed) == across
    if across:
        assert backed[0].t_sent > 3.0 - 1.5


def test_back_up_recovery_ends_after_its_distance_or_its_time():
    """BackUpRecovery: straight back at backup_speed until the odometry is backup_dist from
    the start (a moving robot), or until time_allowance (a stalled one)."""
    from slam_predict.nav.config import RecoveryBehaviorConfig
    from slam_predict.nav.recovery import BackUpRecovery

    behavior = RecoveryBehaviorConfig("back_up", "slam_predict/BackUpRecovery",
                                      backup_dist=0.3, backup_speed=0.15, time_allowance=5.0)
    backer = BackUpRecovery()
    pose, t = np.array([2.0, 1.0, math.pi / 2]), 10.0
    backer.start(behavior, pose, t)
    while True:
        done, v = backer.step(pose, t)
        if done:
            break
        assert v == -0.15
        pose = pose + np.array([0.0, v * 0.1, 0.0])
        t += 0.1
    assert 0.3 <= 1.0 - pose[1] < 0.3 + 0.015 and t < 10.0 + 0.3 / 0.15 + 0.15
    backer.start(behavior, pose, t)
    stalled = [backer.step(pose, t + k * 0.1) for k in range(60)]
    assert [done for done, _ in stalled].index(True) == 50


def test_make_plan_and_clear_costmaps_services(cfg):
    nav = Navigator(cfg)
    nav.set_map(room_grid())
    nav.step(0.0, np.array([1.0, 1.0, 0.0]), IDENTITY, (0.0, 0.0))
    plan = nav.make_plan((1.0, 1.0), (7.0, 5.0, 0.0))
    assert plan is not None and plan.reaches_goal
    assert nav.make_plan((1.0, 1.0), (50.0, 5.0, 0.0)) is None
    nav.add_scan(np.array([1.0]), np.array([0.0]), 0.0, 30.0, np.array([1.0, 1.0, 0.0]),
                 IDENTITY, IDENTITY)
    nav.local_costmap.update((1.0, 1.0, 0.0))
    assert nav.local_costmap.costmap.costs.max() == 254
    nav.clear_costmaps()
    nav.local_costmap.update((1.0, 1.0, 0.0))
    assert nav.local_costmap.costmap.costs.max() == 0


def test_robot_pinned_against_a_wall_is_not_aborted(cfg):
    """school_6000 (issue #5): stalled with its centre 0.12 m from a wall (inside the 0.21 m
    inscribed band: its cell and every neighbour INSCRIBED) the robot got no plan to anywhere,
    each goal ended ABORTED after the conservative reset. It now plans its way out."""
    nav = Navigator(cfg)
    nav.set_map(room_grid())
    pose = np.array([4.0, 0.22, math.pi])
    nav.step(0.0, pose, IDENTITY, (0.0, 0.0))
    costs = nav.global_costmap.costmap.costs
    assert np.all(costs[3:6, 79:82] >= 253)       # cell (80, 4) and its 8 neighbours
    record = nav.send_goal((4.0, 3.0, math.pi / 2), 0.0)
    pose, t, _ = drive(nav, pose, 0.0, 3.0, move=False)
    assert record.status == GoalStatus.ACTIVE and nav.state == State.CONTROLLING
    assert record.plan_length is not None and record.plan_length < 3.5
    pose, t, _ = drive(nav, pose, t, 60.0)
    assert record.status == GoalStatus.SUCCEEDED


def test_back_up_recovery_with_simulate_ahead_stops_before_a_wall_behind():
    """simulate_ahead_time > 0 (Nav2's BackUp check): the robot backs towards a LETHAL wall
    behind it and stops while its footprint is still clear of it; with a clear path it backs
    the whole distance, and blind (0) it drives on into the wall until its time is up."""
    from slam_predict.nav.config import RecoveryBehaviorConfig
    from slam_predict.nav.recovery import BackUpRecovery

    res, half = 0.02, 0.2
    footprint = np.array([[half, half], [half, -half], [-half, -half], [-half, half]])
    costs = np.zeros((150, 150), np.uint8)
    costmap = SimpleNamespace(costs=costs, origin=(0.0, 0.0), resolution=res)

    def back_up(wall_x: float | None, horizon: float, side_wall: bool = False) -> float:
        costs[:] = 0
        if wall_x is not None:
            costs[:, : int(wall_x / res)] = 254
        if side_wall:                  # a wall along the robot's left side, touching it
            costs[int(round((1.5 + half) / res)) - 1:, :] = 254
        behavior = RecoveryBehaviorConfig("back_up", "slam_predict/BackUpRecovery",
                                          backup_dist=0.5, backup_speed=0.15,
                                          time_allowance=10.0, simulate_ahead_time=horizon)
        backer = BackUpRecovery(footprint)
        pose, t = np.array([1.5, 1.5, 0.0]), 0.0
        backer.start(behavior, pose, t)
        while True:
            done, v = backer.step(pose, t, costmap)
            if done:
                return 1.5 - pose[0]
            if wall_x is None or pose[0] - half + v * 0.1 > wall_x:   # the simulator's refusal
                pose = pose + np.array([v * 0.1, 0.0, 0.0])
            t += 0.1

    assert back_up(None, 2.0) == pytest.approx(0.5, abs=0.016)
    assert back_up(None, 2.0, side_wall=True) == pytest.approx(0.5, abs=0.016)
    wall = 1.5 - half - 0.45                    # the footprint's back 0.45 m from the wall
    # it stops once the wall is within its look-ahead (2 s × 0.15 m/s = 0.3 m), give or take
    # a step and a costmap cell
    assert back_up(wall, 2.0) == pytest.approx(0.45 - 0.3, abs=0.015 + res)
    assert back_up(wall, 0.0) == pytest.approx(0.45, abs=0.016)   # blind: against the wall


def test_rear_edges_are_the_edges_facing_backwards():
    from slam_predict.nav.recovery import rear_edges

    square = np.array([[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]])   # clockwise
    for polygon in (square, square[::-1]):
        edges = rear_edges(polygon)
        assert len(edges) == 1 and np.allclose(edges[0][:, 0], -0.2)
    arrow = np.array([[0.3, 0.0], [-0.2, 0.2], [-0.1, 0.0], [-0.2, -0.2]])      # notched tail
    assert len(rear_edges(arrow)) == 2


def test_shortened_edge():
    from slam_predict.nav.recovery import shortened

    got = shortened(np.array([[-0.2, -0.2], [-0.2, 0.2]]), 0.05)
    assert np.allclose(got, [[-0.2, -0.15], [-0.2, 0.15]])
    assert np.allclose(shortened(np.array([[0.0, 0.0], [0.0, 0.06]]), 0.05), [[0, 0.03]] * 2)
