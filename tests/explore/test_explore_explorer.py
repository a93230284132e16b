"""Explorer rules with a scripted goal client: nearest choice, seeded ties, time limits,
aborts, blacklisting, in-place goals, stale maps, explore_lite's cost, stop reasons."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from slam_predict.explore.explorer import ExploreConfig, Explorer
from slam_predict.explore.goals import ABORTED, HEADING_UNDEFINED_M, SUCCEEDED, facing

RES = 0.1


class FakeClient:
    """Records goals; the test sets the status and plan length."""

    def __init__(self):
        self.sent = []
        self.cancelled = []
        self._status = None
        self.length = None

    def send_goal(self, target, t):
        self.sent.append((t, target))
        self._status = 1
        self.length = None

    def cancel(self, t):
        self.cancelled.append(t)
        self._status = 2

    def status(self):
        return self._status

    def plan_length(self):
        return self.length


def grid_with_frontiers(*boxes):
    """Known free 20 m x 20 m with unknown holes (x0, y0, x1, y1) in m; origin (0, 0)."""
    data = np.zeros((200, 200), np.int8)
    for x0, y0, x1, y1 in boxes:
        data[int(y0 / RES):int(y1 / RES), int(x0 / RES):int(x1 / RES)] = -1
    return SimpleNamespace(data=data, resolution=RES, origin=(0.0, 0.0))


def explorer(**kw):
    cfg = ExploreConfig(**{"goal_clearance": 0.0, "near_frontier_distance": 0.5, **kw})
    client = FakeClient()
    return Explorer(cfg, client, np.random.default_rng(0)), client


def test_nearest_frontier_is_chosen_and_kept_while_it_lasts():
    ex, client = explorer()
    grid = grid_with_frontiers((15, 15, 17, 17), (4, 4, 6, 6))
    robot = np.array([1.0, 1.0, 0.0])
    ex.step(0.0, grid, robot)
    (t, target), = client.sent
    assert 3.5 < target[0] < 6.5 and 3.5 < target[1] < 6.5     # the near hole
    assert target[2] == pytest.approx(np.arctan2(target[1] - 1, target[0] - 1))
    ex.step(2.0, grid, robot)                                   # same map: keep the goal
    assert len(client.sent) == 1
    seen = grid_with_frontiers((15, 15, 17, 17))               # the near hole got mapped
    ex.step(3.0, seen, robot)
    assert len(client.sent) == 2 and client.sent[-1][1][0] > 14
    assert ex.log.goals[-1]["outcome"] == "replaced"


def test_ties_are_broken_by_the_seeded_generator():
    picks = set()
    for seed in range(12):
        cfg = ExploreConfig(goal_clearance=0.0)
        client = FakeClient()
        ex = Explorer(cfg, client, np.random.default_rng(seed))
        ex.step(0.0, grid_with_frontiers((4, 9, 6, 11), (14, 9, 16, 11)), np.array([10, 10, 0]))
        picks.add(client.sent[0][1][0] > 10)
        again = FakeClient()
        Explorer(cfg, again, np.random.default_rng(seed)).step(
            0.0, grid_with_frontiers((4, 9, 6, 11), (14, 9, 16, 11)), np.array([10, 10, 0]))
        assert again.sent == client.sent                        # deterministic for a seed
    assert picks == {True, False}


def test_time_limit_drops_the_goal_and_a_random_frontier_follows():
    ex, client = explorer()
    grid = grid_with_frontiers((4, 4, 6, 6), (15, 15, 17, 17), (2, 15, 4, 17))
    robot = np.array([1.0, 1.0, 0.0])
    ex.step(0.0, grid, robot)
    client.length = 4.25                              # first plan: 4.25 m
    ex.step(0.1, grid, robot)
    limit = 2.0 * 4.25 / 0.85 + 30.0
    assert ex.goal.time_limit == pytest.approx(limit)
    ex.step(limit - 0.1, grid, robot)
    assert not client.cancelled
    calls = []
    ex.rng = SimpleNamespace(integers=lambda n: calls.append(n) or n - 1)
    ex.step(limit + 0.2, grid, robot)
    assert client.cancelled and ex.log.goals[0]["outcome"] == "timeout"
    assert ex.log.goals[0]["time_limit"] == pytest.approx(limit)
    assert calls and calls[0] == 2                    # random among the two fresh frontiers


def test_aborted_goals_are_blacklisted_until_nothing_is_left():
    ex, client = explorer()
    grid = grid_with_frontiers((4, 4, 6, 6))
    robot = np.array([1.0, 1.0, 0.0])
    ex.step(0.0, grid, robot)
    client._status = ABORTED
    ex.step(0.5, grid, robot)
    assert ex.done and ex.log.stop_reason == "all_frontiers_blacklisted"
    assert ex.log.goals[0]["outcome"] == "aborted"


def test_no_frontier_stops_exploration():
    ex, client = explorer()
    ex.step(0.0, grid_with_frontiers(), np.array([1.0, 1.0, 0.0]))
    assert ex.done and ex.log.stop_reason == "no_frontiers" and not client.sent


def test_near_frontier_gives_an_in_place_goal_and_waits_for_a_new_map():
    ex, client = explorer(near_frontier_distance=1.0)
    grid = grid_with_frontiers((5.3, 4.6, 5.6, 5.4))
    robot = np.array([5.0, 5.0, np.pi])
    ex.step(0.0, grid, robot)
    target = client.sent[0][1]
    assert target[:2] == pytest.approx((5.0, 5.0)) and abs(target[2]) < 0.5   # turn to face it
    client._status = SUCCEEDED
    ex.step(0.5, grid, robot)                          # same (stale) map: nothing new sent
    assert len(client.sent) == 1 and not ex.done
    fresh = grid_with_frontiers((5.3, 4.6, 5.6, 5.4))  # a new map object, frontier still there
    ex.step(1.0, fresh, robot)
    assert len(client.sent) == 2
    # reached once and still there (a laser shadow): now driven onto, not turned to again
    target = client.sent[1][1]
    frontier = ex.frontiers[0]
    assert target[:2] == pytest.approx(tuple(frontier.goal))
    assert np.hypot(target[0] - 5.0, target[1] - 5.0) > 0.1


def test_explore_lite_cost_prefers_large_frontiers():
    ex, client = explorer(strategy="explore_lite", potential_scale=1e-3, gain_scale=1.0)
    grid = grid_with_frontiers((2, 2, 2.5, 2.5), (10, 10, 16, 16))
    ex.step(0.0, grid, np.array([1.0, 1.0, 0.0]))
    assert client.sent[0][1][0] > 9                    # the big one, although farther
    ex2, client2 = explorer(strategy="explore_lite", potential_scale=100.0, gain_scale=1.0)
    ex2.step(0.0, grid, np.array([1.0, 1.0, 0.0]))
    assert client2.sent[0][1][0] < 3


def test_config_rejects_unknown_strategy():
    with pytest.raises(ValueError):
        ExploreConfig(strategy="closest")


def test_blacklist_retry_looks_around_then_forgets_aborted_points_on_a_new_map():
    ex, client = explorer(blacklist_retries=2)
    grid = grid_with_frontiers((4, 4, 6, 6))
    robot = np.array([1.0, 1.0, 0.5])
    ex.step(0.0, grid, robot)
    client._status = ABORTED
    ex.step(0.5, grid, robot)                          # all blacklisted: look around, not stop
    assert not ex.done and ex.retries == 1
    look = client.sent[-1][1]                          # in place, facing the frontier
    gx, gy = ex.frontiers[0].goal
    assert look[:2] == pytest.approx((1.0, 1.0))
    assert look[2] == pytest.approx(np.arctan2(gy - 1.0, gx - 1.0))
    ex.step(1.5, grid, robot)                          # still turning: nothing new
    assert len(client.sent) == 2
    client._status = SUCCEEDED
    ex.step(2.0, grid, robot)                          # turned; the map is still the old one
    ex.step(3.5, grid, robot)
    assert len(client.sent) == 2 and len(ex.blacklist) == 1
    assert ex.log.goals[-1]["outcome"] == "look_around"
    ex.step(4.0, grid_with_frontiers((4, 4, 6, 6)), robot)   # a newer map: try the frontier again
    assert len(client.sent) == 3 and not ex.blacklist
    assert 3.5 < client.sent[-1][1][0] < 6.5
    client._status = SUCCEEDED                         # reached: the retry count restarts
    ex.step(5.0, grid_with_frontiers((4, 4, 6, 6)), robot)
    assert ex.retries == 0


def test_blacklist_retries_are_bounded():
    ex, client = explorer(blacklist_retries=2)
    robot = np.array([1.0, 1.0, 0.0])
    t = 0.0
    for _ in range(20):
        grid = grid_with_frontiers((4, 4, 6, 6))       # a new map every tick, goals all fail
        if client.sent and client._status == 1:
            client._status = ABORTED if abs(client.sent[-1][1][0] - 1.0) > 0.1 else SUCCEEDED
        ex.step(t, grid, robot)
        t += 1.0
        if ex.done:
            break
    assert ex.done and ex.log.stop_reason == "all_frontiers_blacklisted"
    outcomes = [g["outcome"] for g in ex.log.goals]
    assert outcomes.count("look_around") == 2 and outcomes.count("aborted") == 3


def test_blacklist_retry_keeps_points_reached_too_often():
    ex, client = explorer(blacklist_retries=3, max_goal_attempts=1)
    grid = grid_with_frontiers((4, 4, 6, 6))
    robot = np.array([1.0, 1.0, 0.0])
    ex.step(0.0, grid, robot)
    client._status = SUCCEEDED                         # reached, frontier still there
    ex.step(0.5, grid, robot)
    ex.step(1.5, grid_with_frontiers((4, 4, 6, 6)), robot)
    assert ex.done and ex.log.stop_reason == "all_frontiers_blacklisted"   # nothing to forget


def test_config_rejects_negative_blacklist_retries():
    with pytest.raises(ValueError):
        ExploreConfig(blacklist_retries=-1)


def test_a_frontier_around_the_robot_turns_it_around():
    """Karto's first map: a free fan around the robot, unknown beyond and in the laser's blind
    sector behind it, one frontier whose goal point is the robot itself. The in-place goal
    faces backwards (no direction to the point), so the blind sector gets scanned."""
    ex, client = explorer(near_frontier_distance=1.0)
    data = np.full((200, 200), -1, np.int8)
    y, x = (np.mgrid[0:200, 0:200] + 0.5) * RES
    bearing = np.arctan2(y - 10.0, x - 10.0)
    fan = (np.hypot(x - 10.0, y - 10.0) < 2.0) & (np.abs(bearing) < 0.75 * np.pi)
    data[fan] = 0
    grid = SimpleNamespace(data=data, resolution=RES, origin=(0.0, 0.0))
    for yaw in (0.0, 2.0):
        ex, client = explorer(near_frontier_distance=1.0)
        robot = np.array([10.0, 10.0, yaw])
        ex.step(0.0, grid, robot)
        target = client.sent[0][1]
        assert target[:2] == pytest.approx((10.0, 10.0))
        assert np.cos(target[2] - (yaw + np.pi)) == pytest.approx(1.0)


def test_facing_points_at_the_point_unless_it_is_at_the_robot():
    robot = (1.0, 2.0, 0.5)
    assert facing((1.0, 4.0), robot) == pytest.approx(np.pi / 2)
    assert facing((1.0 + HEADING_UNDEFINED_M, 2.0), robot) == pytest.approx(0.0)
    assert facing((1.03, 2.04), robot, at_start=True) == pytest.approx(0.5 - np.pi)
    assert facing((1.03, 2.04), robot) == pytest.approx(np.arctan2(0.04, 0.03))


def test_an_in_place_goal_move_base_aborts_at_the_start_becomes_a_drive_goal():
    """The robot cannot turn where it stands (beside a wall) at the start: the frontier is not
    blacklisted, its next goal is its nearest cell at least near_frontier_distance away."""
    ex, client = explorer(near_frontier_distance=1.0)
    grid = grid_with_frontiers((5.3, 3.0, 5.6, 7.0))   # a 4 m frontier beside the robot
    robot = np.array([5.0, 5.0, np.pi])
    ex.step(0.0, grid, robot)
    assert client.sent[0][1][:2] == pytest.approx((5.0, 5.0))      # in place
    client._status = ABORTED
    ex.step(0.5, grid_with_frontiers((5.3, 3.0, 5.6, 7.0)), robot)
    assert ex.log.goals[0]["outcome"] == "turn_aborted" and not ex.blacklist
    ex.step(1.0, grid_with_frontiers((5.3, 3.0, 5.6, 7.0)), robot)   # the next map
    target = client.sent[1][1]
    assert np.hypot(target[0] - 5.0, target[1] - 5.0) >= 1.0 and not ex.done
    near = ex.frontiers[0].cells
    near = near[np.hypot(*(near - robot[:2]).T) >= 1.0]
    assert np.hypot(target[0] - 5.0, target[1] - 5.0) == pytest.approx(
        np.hypot(*(near - robot[:2]).T).min())
    client._status = ABORTED                           # the drive fails too: blacklisted
    ex.step(1.5, grid_with_frontiers((5.3, 3.0, 5.6, 7.0)), robot)
    assert ex.log.goals[1]["outcome"] == "aborted" and ex.blacklist


def test_after_the_first_drive_goal_an_aborted_turn_is_blacklisted():
    """The start-up rules end with the first goal that is not in place."""
    ex, client = explorer(near_frontier_distance=1.0)
    ex.step(0.0, grid_with_frontiers((15, 15, 17, 17)), np.array([1.0, 1.0, 0.0]))
    assert client.sent[0][1][:2] != pytest.approx((1.0, 1.0)) and ex.started   # a drive goal
    client._status = SUCCEEDED
    robot = np.array([5.0, 5.0, np.pi])
    ex.step(0.5, grid_with_frontiers((5.3, 3.0, 5.6, 7.0)), robot)
    assert client.sent[1][1][:2] == pytest.approx((5.0, 5.0))      # in place
    client._status = ABORTED
    ex.step(1.0, grid_with_frontiers((5.3, 3.0, 5.6, 7.0)), robot)
    assert ex.log.goals[-1]["outcome"] == "aborted" and ex.blacklist and not ex.turn_failed


def test_reachable_frontiers_skip_a_hole_walled_off_from_the_robot():
    """With ``reachable_frontiers`` the nearest frontier is the nearest one in the free space
    joined to the robot: a hole ringed by a wall (its free rim cut off) is skipped."""
    grid = grid_with_frontiers((15, 15, 17, 17), (4, 4, 6, 6))
    data = grid.data
    r0, r1, c0, c1 = int(3.5 / RES), int(6.5 / RES), int(3.5 / RES), int(6.5 / RES)
    data[r0:r1, c0] = data[r0:r1, c1 - 1] = 100        # a wall ring 0.5 m around the near hole,
    data[r0, c0:c1] = data[r1 - 1, c0:c1] = 100        # its free rim inside the ring
    robot = np.array([1.0, 1.0, 0.0])
    plain, plain_client = explorer()
    plain.step(0.0, grid, robot)
    reach, reach_client = explorer(reachable_frontiers=True)
    reach.step(0.0, grid, robot)
    assert np.hypot(*(np.array(plain_client.sent[0][1][:2]) - (5.0, 5.0))) < 1.5
    assert np.hypot(*(np.array(reach_client.sent[0][1][:2]) - (16.0, 16.0))) < 1.5


def test_reachable_first_takes_a_walled_off_hole_only_when_nothing_else_is_left():
    grid = grid_with_frontiers((15, 15, 17, 17), (4, 4, 6, 6))
    data = grid.data
    r0, r1, c0, c1 = int(3.5 / RES), int(6.5 / RES), int(3.5 / RES), int(6.5 / RES)
    data[r0:r1, c0] = data[r0:r1, c1 - 1] = 100
    data[r0, c0:c1] = data[r1 - 1, c0:c1] = 100
    robot = np.array([1.0, 1.0, 0.0])
    ex, client = explorer(reachable_first=True)
    ex.step(0.0, grid, robot)
    assert np.hypot(*(np.array(client.sent[0][1][:2]) - (16.0, 16.0))) < 1.5
    ex.blacklist.append(ex.goal.frontier_point)        # the reachable one is blacklisted
    ex.goal = None
    ex.step(10.0, grid, robot)
    assert np.hypot(*(np.array(client.sent[-1][1][:2]) - (5.0, 5.0))) < 1.5
