"""base_local_planner equivalents against slow references and on small scenes."""
from __future__ import annotations

import math

import numpy as np
import pytest

from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import INSCRIBED, LETHAL, NO_INFORMATION, Costmap, InflationLayer
from slam_predict.nav.local_planner import LocalPlanner
from slam_predict.nav.map_grid import adjust_plan_resolution, path_and_goal_cells
from slam_predict.nav.planner_modes import Mode, PlannerState
from slam_predict.nav.rollout import footprint_cost, rollout
from slam_predict.nav.trajectory_planner import TrajectoryPlanner, shrink_footprint

RES = 0.05
SQUARE = np.array([[-0.21, -0.21], [-0.21, 0.21], [0.21, 0.21], [0.21, -0.21]])


def line_cells(x0, y0, x1, y1):
    """base_local_planner's LineIterator, written out."""
    dx, dy = abs(x1 - x0), abs(y1 - y0)
    xi1 = xi2 = 1 if x1 >= x0 else -1
    yi1 = yi2 = 1 if y1 >= y0 else -1
    if dx >= dy:
        xi1, yi2, den, num, add, n = 0, 0, dx, dx // 2, dy, dx
    else:
        xi2, yi1, den, num, add, n = 0, 0, dy, dy // 2, dx, dy
    x, y, out = x0, y0, []
    for _ in range(n + 1):
        out.append((x, y))
        num += add
        if num >= den:
            num -= den
            x += xi1
            y += yi1
        x += xi2
        y += yi2
    return out


def ref_footprint_cost(cm: Costmap, x, y, th, fp):
    if cm.world_to_map(x, y) is None:
        return -1.0
    pts = [(x + px * math.cos(th) - py * math.sin(th), y + px * math.sin(th) + py * math.cos(th))
           for px, py in fp]
    cells = [cm.world_to_map(*p) for p in pts]
    if any(c is None for c in cells):
        return -1.0
    best = 0.0
    for i in range(len(cells)):
        a, b = cells[i], cells[(i + 1) % len(cells)]
        for cx, cy in line_cells(a[0], a[1], b[0], b[1]):
            v = cm.costs[cy, cx]
            if v in (LETHAL, NO_INFORMATION):
                return -1.0
            best = max(best, float(v))
    return best


def ref_rollout(cm, pose, vel, samp, cfg, pdist, gdist, occdist, path_dist, goal_dist):
    """TrajectoryPlanner::generateTrajectory in plain Python."""
    x, y, th = pose
    vx, vth = vel
    num = int(max(abs(samp[0]) * cfg.sim_time / cfg.sim_granularity,
                  abs(samp[1]) / cfg.angular_sim_granularity) + 0.5) or 1
    dt = cfg.sim_time / num
    impossible = cm.costs.size
    occ = pd = gd = 0.0

    def ramp(goal, cur, acc):
        return min(goal, cur + acc * dt) if goal - cur >= 0 else max(goal, cur - acc * dt)

    for _ in range(num):
        cell = cm.world_to_map(x, y)
        if cell is None:
            return -1.0
        fc = ref_footprint_cost(cm, x, y, th, SQUARE)
        if fc < 0:
            return -1.0
        occ = max(occ, fc, float(cm.costs[cell[1], cell[0]]))
        pd, gd = path_dist[cell[1], cell[0]], goal_dist[cell[1], cell[0]]
        if impossible <= gd or impossible <= pd:
            return -2.0
        vx = ramp(samp[0], vx, cfg.acc_lim_x)
        vth = ramp(samp[1], vth, cfg.acc_lim_theta)
        x, y, th = x + vx * math.cos(th) * dt, y + vx * math.sin(th) * dt, th + vth * dt
    return pdist * pd + gdist * gd + occdist * occ


def cluttered(rng, shape=(60, 60), p=0.01, unknown=0.0):
    costs = np.zeros(shape, np.uint8)
    costs[rng.random(shape) < p] = LETHAL
    InflationLayer(0.6, 7.5, 0.21, RES).apply(costs)
    costs[rng.random(shape) < unknown] = NO_INFORMATION
    return Costmap(costs, (0.0, 0.0), RES)


@pytest.mark.parametrize("seed", range(4))
def test_footprint_cost_matches_reference(seed):
    rng = np.random.default_rng(seed)
    cm = cluttered(rng, unknown=0.002)
    for _ in range(200):
        x, y, th = rng.uniform(-0.2, 3.2), rng.uniform(-0.2, 3.2), rng.uniform(-4, 4)
        fast = footprint_cost(cm.costs, 0.0, 0.0, RES, x, y, th, SQUARE)
        assert fast == ref_footprint_cost(cm, x, y, th, SQUARE)


@pytest.mark.parametrize("seed", range(3))
def test_rollout_matches_reference(seed):
    rng = np.random.default_rng(10 + seed)
    cm = cluttered(rng, p=0.004)
    cfg = TrajectoryPlannerConfig(sim_time=1.0, acc_lim_x=1.5, acc_lim_theta=2.5)
    path_dist = rng.integers(0, 40, cm.costs.shape).astype(float)
    goal_dist = rng.integers(0, 40, cm.costs.shape).astype(float)
    goal_dist[rng.random(cm.costs.shape) < 0.01] = cm.costs.size
    for _ in range(60):
        pose = (rng.uniform(0.5, 2.5), rng.uniform(0.5, 2.5), rng.uniform(-3, 3))
        vel = (rng.uniform(0, 0.5), rng.uniform(-0.5, 0.5))
        samp = (rng.uniform(-0.2, 0.85), rng.uniform(-1, 1))
        fast, *_ = rollout(pose[0], pose[1], pose[2], vel[0], vel[1], samp[0], samp[1],
                           cfg.acc_lim_x, cfg.acc_lim_theta, cfg.sim_time, cfg.sim_granularity,
                           cfg.angular_sim_granularity, cm.costs, 0.0, 0.0, RES, SQUARE,
                           path_dist, goal_dist, float(cm.costs.size), 0.6, 0.8, 0.01,
                           np.empty((0, 3)))
        ref = ref_rollout(cm, pose, vel, samp, cfg, 0.6, 0.8, 0.01, path_dist, goal_dist)
        assert fast == pytest.approx(ref, rel=1e-9, abs=1e-9)


def test_adjust_plan_resolution_spacing():
    plan = np.array([[0.0, 0.0], [0.01, 0.0], [1.0, 0.5], [1.0, 0.5], [3.0, 0.5]])
    out = adjust_plan_resolution(plan, 0.05)
    gaps = np.hypot(*np.diff(out, axis=0).T)
    assert gaps.max() <= 0.05 + 1e-12
    for p in plan:                       # every original point is kept
        assert np.min(np.hypot(*(out - p).T)) < 1e-12


def test_local_goal_stops_before_an_obstacle_at_the_plan_end():
    costs = np.zeros((80, 80), np.uint8)
    costs[:, 60:] = INSCRIBED
    cm = Costmap(costs, (0.0, 0.0), RES)
    xs = np.linspace(0.5, 3.5, 61)
    plan = np.column_stack([xs, np.full_like(xs, 2.0), np.zeros_like(xs)])
    path, goal = path_and_goal_cells(cm, plan)
    assert len(path) > 0 and goal[0, 0] == 59          # last free cell before x = 3.0 m
    costs[:, 20:] = INSCRIBED                           # obstacle within 1 m of the start:
    near = plan[plan[:, 0] <= 1.31]                     # no cut, the goal is the last point
    assert path_and_goal_cells(cm, near)[1][0, 0] == 26


def open_planner(**kw):
    cfg = TrajectoryPlannerConfig(**{"max_vel_x": 0.85, "min_vel_x": 0.1, "max_vel_theta": 0.7,
                                     "min_vel_theta": -0.7, "acc_lim_x": 1.5,
                                     "acc_lim_theta": 2.5, "sim_time": 1.5, "vx_samples": 10,
                                     **kw})
    return cfg, TrajectoryPlanner(cfg, SQUARE, 0.1, RES)


def straight_plan(y=1.5, x0=1.0, x1=2.9):
    xs = np.linspace(x0, x1, 40)
    return np.column_stack([xs, np.full_like(xs, y), np.zeros_like(xs)])


def test_drives_forward_along_a_clear_plan_and_respects_the_window():
    cm = Costmap(np.zeros((60, 60), np.uint8), (0.0, 0.0), RES)
    cfg, tc = open_planner()
    tc.update_plan(straight_plan())
    best = tc.find_best_path(cm, (1.0, 1.5, 0.0), (0.0, 0.0))
    assert best.cost >= 0 and best.xv > 0.5 and best.thetav == 0.0
    _, dwa = open_planner(dwa=True)
    dwa.update_plan(straight_plan())
    slow = dwa.find_best_path(cm, (1.0, 1.5, 0.0), (0.0, 0.0))
    assert slow.xv <= 1.5 * 0.1 + 1e-9            # v + acc_lim_x · sim_period


def test_turns_in_place_towards_a_plan_behind():
    cm = Costmap(np.zeros((60, 60), np.uint8), (0.0, 0.0), RES)
    cfg, tc = open_planner()
    plan = straight_plan(x0=1.5, x1=0.2)
    tc.update_plan(plan)
    best = tc.find_best_path(cm, (1.5, 1.5, 0.3), (0.0, 0.0))
    assert best.xv == 0.0 and abs(best.thetav) >= cfg.min_in_place_vel_theta


def test_never_selects_a_colliding_trajectory_and_escapes_when_boxed_in():
    costs = np.zeros((60, 60), np.uint8)
    costs[:, 36] = LETHAL                       # a wall 0.3 m ahead of the robot at x = 1.5
    InflationLayer(0.3, 10.0, 0.21, RES).apply(costs)
    cm = Costmap(costs, (0.0, 0.0), RES)
    cfg, tc = open_planner()
    tc.update_plan(straight_plan(x0=1.5, x1=2.9))
    best = tc.find_best_path(cm, (1.5, 1.5, 0.0), (0.0, 0.0))
    pts = tc.trajectory_points(cm, (1.5, 1.5, 0.0), (0.0, 0.0), best.xv, best.thetav)
    for x, y, th in pts:
        assert footprint_cost(costs, 0.0, 0.0, RES, x, y, th, SQUARE) >= 0
    boxed = np.zeros((60, 60), np.uint8)
    boxed[25:36, 25:36] = LETHAL
    boxed[29:32, 29:32] = 0                     # robot inside a pocket: nothing is legal
    cm2 = Costmap(boxed, (0.0, 0.0), RES)
    cfg, tc2 = open_planner(escape_vel=-0.15)
    tc2.update_plan(straight_plan(y=1.52, x0=1.52, x1=2.9))
    best = tc2.find_best_path(cm2, (1.52, 1.52, 0.0), (0.0, 0.0))
    assert best.xv == -0.15 and tc2.state.mode is Mode.ESCAPING


def test_goal_tolerance_stop_then_rotate_then_reached():
    cm = Costmap(np.zeros((60, 60), np.uint8), (0.0, 0.0), RES)
    cfg = TrajectoryPlannerConfig(xy_goal_tolerance=0.3, yaw_goal_tolerance=0.2, max_vel_theta=0.7,
                                  min_vel_theta=-0.7, acc_lim_theta=2.5)
    lp = LocalPlanner(cfg, SQUARE, 0.1, RES)
    plan = straight_plan(x0=1.0, x1=1.5)
    plan[-1, 2] = math.pi / 2
    lp.set_plan(plan)
    pose = (1.4, 1.5, 0.0)
    identity = (0.0, 0.0, 0.0)
    cmd = lp.compute_velocity_commands(cm, pose, (0.5, 0.0), identity)
    assert cmd[0] == pytest.approx(0.5 - cfg.acc_lim_x * 0.1)     # stopping first
    cmd = lp.compute_velocity_commands(cm, pose, (0.0, 0.0), identity)
    assert cmd[0] == 0.0 and cmd[1] >= cfg.min_in_place_vel_theta  # then turning left
    assert not lp.is_goal_reached(pose, (0.0, 0.0))
    done = (1.4, 1.5, math.pi / 2 - 0.1)
    assert lp.compute_velocity_commands(cm, done, (0.0, 0.0), identity) == (0.0, 0.0)
    assert lp.is_goal_reached(done, (0.0, 0.0))
    assert not lp.is_goal_reached(done, (0.2, 0.0))                # must have stopped


def narrow_corridor_facing_away():
    """A 0.6 m corridor along x (the 0.42 m footprint cannot turn in it), the robot at x = 1.5
    facing +x, its plan leading back to x = 0.3."""
    costs = np.zeros((60, 60), np.uint8)
    costs[24, :] = LETHAL                       # walls at y = 1.2 and y = 1.8
    costs[36, :] = LETHAL
    InflationLayer(0.3, 10.0, 0.21, RES).apply(costs)
    return Costmap(costs, (0.0, 0.0), RES), (1.5, 1.5, 0.0), straight_plan(x0=1.5, x1=0.3)


def test_facing_away_in_a_narrow_corridor_backs_up_with_reverse_when_blocked():
    cm, pose, plan = narrow_corridor_facing_away()
    cfg, plain = open_planner(escape_vel=-0.15)
    plain.update_plan(plan)
    best = plain.find_best_path(cm, pose, (0.0, 0.0))
    assert best.xv > 0                          # base_local_planner drives on, away from the goal
    for k in range(3):                          # no in-place rotation is legal here
        assert footprint_cost(cm.costs, 0.0, 0.0, RES, 1.5, 1.5, 0.3 * (k + 1), SQUARE) < 0
    cfg, tc = open_planner(escape_vel=-0.15, reverse_when_blocked=True)
    tc.update_plan(plan)
    best = tc.find_best_path(cm, pose, (0.0, 0.0))
    assert best.xv == -0.15 and tc.state.mode is Mode.REVERSING
    pts = tc.trajectory_points(cm, pose, (0.0, 0.0), best.xv, best.thetav)
    assert pts[-1, 0] < pose[0] and all(
        footprint_cost(cm.costs, 0.0, 0.0, RES, x, y, th, SQUARE) >= 0 for x, y, th in pts)
    # reversing is kept up while it pays, and for escape_reset_dist (0.1 m, from x = 1.5) in
    # any case; facing the goal again after that, it drives forward
    best = tc.find_best_path(cm, (1.45, 1.5, 0.0), (-0.15, 0.0))
    assert best.xv == -0.15
    tc.update_plan(straight_plan(x0=1.5, x1=2.9))
    best = tc.find_best_path(cm, (1.45, 1.5, 0.0), (-0.15, 0.0))
    assert best.xv == -0.15 and tc.state.mode is Mode.REVERSING
    best = tc.find_best_path(cm, (1.38, 1.5, 0.0), (0.0, 0.0))
    assert best.xv > 0 and tc.state.mode is Mode.NORMAL


def test_escape_footprint_margin_backs_away_from_a_wall_the_blind_escape_would_hit():
    costs = np.zeros((60, 60), np.uint8)
    costs[25, :] = LETHAL                       # a wall at y = 1.25..1.30 m
    cm = Costmap(costs, (0.0, 0.0), RES)
    pose = (1.5, 1.5, 0.15)                     # tilted toward the wall: backing drives into it
    plan = straight_plan(x0=1.5, x1=2.9)
    body = shrink_footprint(SQUARE, 0.04)
    np.testing.assert_allclose(np.abs(body), 0.17)
    assert footprint_cost(costs, 0.0, 0.0, RES, *pose, SQUARE) < 0     # nothing is legal
    assert footprint_cost(costs, 0.0, 0.0, RES, *pose, body) >= 0
    cfg, blind = open_planner(escape_vel=-0.15)
    blind.update_plan(plan)
    best = blind.find_best_path(cm, pose, (0.0, 0.0))
    assert (best.xv, best.thetav) == (-0.15, 0.0)          # base_local_planner: straight back
    back = [(pose[0] - d * math.cos(pose[2]), pose[1] - d * math.sin(pose[2]), pose[2])
            for d in np.linspace(0.0, 0.2, 9)]             # ... where the body meets the wall
    assert any(footprint_cost(costs, 0.0, 0.0, RES, x, y, th, body) < 0 for x, y, th in back)
    cfg, safe = open_planner(escape_vel=-0.15, escape_footprint_margin=0.04)
    safe.update_plan(plan)
    body_tc = TrajectoryPlanner(cfg, body, 0.1, RES)
    body_tc.update_plan(plan)
    body_tc.compute_maps(cm, pose)
    safe.state = PlannerState(Mode.ESCAPING, pose)     # already escaping: no forward samples
    best = safe.find_best_path(cm, pose, (0.0, 0.0))
    assert (best.xv, best.thetav) != (-0.15, 0.0) and best.cost >= 0 and safe.state.escaping
    pts = body_tc.trajectory_points(cm, pose, (0.0, 0.0), best.xv, best.thetav)
    assert len(pts) >= 5 and pts[-1, 0] < pose[0] and abs(pts[-1, 2] - pose[2]) > 0.1
    assert all(footprint_cost(costs, 0.0, 0.0, RES, x, y, th, body) >= 0 for x, y, th in pts)
    safe.state = PlannerState()            # not escaping: the cycle is planned with the body
    best = safe.find_best_path(cm, pose, (0.0, 0.0))
    assert best.xv > 0 and best.cost >= 0 and safe.footprint_at(cm, pose) is safe.body
    pts = body_tc.trajectory_points(cm, pose, (0.0, 0.0), best.xv, best.thetav)
    assert len(pts) >= 5 and pts[-1, 0] > pose[0] + 0.1
    assert all(footprint_cost(costs, 0.0, 0.0, RES, x, y, th, body) >= 0 for x, y, th in pts)
    boxed = np.full((60, 60), LETHAL, np.uint8)             # nothing safe: the blind escape
    boxed[29:32, 29:32] = 0
    safe.update_plan(straight_plan(y=1.52, x0=1.52, x1=2.9))
    best = safe.find_best_path(Costmap(boxed, (0.0, 0.0), RES), (1.52, 1.52, 0.0), (0.0, 0.0))
    assert (best.xv, best.thetav) == (-0.15, 0.0)


def test_escape_footprint_margin_escapes_forward_off_a_wall_it_has_backed_into():
    costs = np.zeros((60, 60), np.uint8)
    costs[:, 24] = LETHAL                       # a wall behind the robot at x = 1.20..1.25 m
    costs[34, :] = LETHAL                       # the full footprint's left edge touches y = 1.70
    cm = Costmap(costs, (0.0, 0.0), RES)
    pose = (1.5, 1.5, 0.0)
    plan = straight_plan(x0=1.5, x1=2.9)
    body = shrink_footprint(SQUARE, 0.04)
    assert footprint_cost(costs, 0.0, 0.0, RES, *pose, SQUARE) < 0     # nothing is legal
    assert footprint_cost(costs, 0.0, 0.0, RES, *pose, body) >= 0
    cfg, safe = open_planner(escape_vel=-0.15, escape_footprint_margin=0.04)
    safe.update_plan(plan)
    safe.compute_maps(cm, pose)
    back = safe._escape_samples(pose, (0.0, 0.0), -0.15)
    assert (safe._score(cm, pose, (0.0, 0.0), back, body)[0] < 0).all()   # no way back
    safe.state = PlannerState(Mode.ESCAPING, pose)     # escaping: no forward samples
    best = safe.find_best_path(cm, pose, (0.0, 0.0))
    assert best.xv == 0.15 and best.cost >= 0 and safe.state.escaping
    body_tc = TrajectoryPlanner(cfg, body, 0.1, RES)
    body_tc.update_plan(plan)
    body_tc.compute_maps(cm, pose)
    pts = body_tc.trajectory_points(cm, pose, (0.0, 0.0), best.xv, best.thetav)
    assert len(pts) >= 5 and pts[-1, 0] > pose[0] + 0.1
    assert all(footprint_cost(costs, 0.0, 0.0, RES, x, y, th, body) >= 0 for x, y, th in pts)
    cfg, blind = open_planner(escape_vel=-0.15)
    blind.update_plan(plan)
    best = blind.find_best_path(cm, pose, (0.0, 0.0))
    assert (best.xv, best.thetav) == (-0.15, 0.0)          # base_local_planner: into the wall
