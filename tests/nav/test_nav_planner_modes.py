"""The TrajectoryPlanner's modes and transitions, through find_best_path and
compute_velocity_commands on small hand-built costmaps (0.05 m cells, the 0.42 m square
footprint of test_nav_local_planner). Each test names the rule of nav/planner_modes.py it checks.
"""
from __future__ import annotations

import math

import numpy as np
from test_nav_local_planner import RES, SQUARE, narrow_corridor_facing_away, straight_plan

from slam_predict.nav import planner_modes as modes
from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import LETHAL, Costmap
from slam_predict.nav.local_planner import LocalPlanner
from slam_predict.nav.planner_modes import Mode, PlannerState
from slam_predict.nav.rollout import footprint_cost
from slam_predict.nav.trajectory_planner import TrajectoryPlanner

STILL = (0.0, 0.0)
IDENTITY = (0.0, 0.0, 0.0)
LIMITS = {"max_vel_x": 0.85, "min_vel_x": 0.1, "max_vel_theta": 0.7, "min_vel_theta": -0.7,
          "acc_lim_x": 1.5, "acc_lim_theta": 2.5, "sim_time": 1.5, "vx_samples": 10,
          "escape_vel": -0.15}


def config(**kw) -> TrajectoryPlannerConfig:
    return TrajectoryPlannerConfig(**{**LIMITS, **kw})


def planner(plan: np.ndarray, **kw) -> TrajectoryPlanner:
    tc = TrajectoryPlanner(config(**kw), SQUARE, 0.1, RES)
    tc.update_plan(plan)
    return tc


def open_map() -> Costmap:
    return Costmap(np.zeros((60, 60), np.uint8), (0.0, 0.0), RES)


def map_with(cells) -> Costmap:
    """An open 3 m × 3 m map with LETHAL at the (row, column) index expressions ``cells``."""
    costs = np.zeros((60, 60), np.uint8)
    for index in cells:
        costs[index] = LETHAL
    return Costmap(costs, (0.0, 0.0), RES)


# ------------------------------------------------------------------------ ESCAPING (upstream)
def touching_behind() -> Costmap:
    """One LETHAL cell under the rear edge of the footprint of a robot at (1.5, 1.5, 0): no
    sample is legal, base_local_planner backs up blind."""
    return map_with([(30, 25)])


def test_nothing_legal_backs_up_and_enters_escape_mode_at_that_pose():
    tc = planner(straight_plan(x0=1.5))
    best = tc.find_best_path(touching_behind(), (1.5, 1.5, 0.0), STILL)
    assert (best.xv, best.thetav, best.cost) == (-0.15, 0.0, 1.0)   # collision reported as 1
    assert tc.state == PlannerState(Mode.ESCAPING, (1.5, 1.5, 0.0))


def test_escape_mode_has_no_forward_samples_until_escape_reset_dist():
    tc = planner(straight_plan(x0=1.5))
    tc.find_best_path(touching_behind(), (1.5, 1.5, 0.0), STILL)
    near = (1.55, 1.5, 0.0)                       # 0.05 m from the escape pose: still escaping
    assert planner(straight_plan(x0=1.5)).find_best_path(open_map(), near, STILL).xv > 0
    best = tc.find_best_path(open_map(), near, STILL)
    assert best.xv == 0.0 and best.cost >= 0 and tc.state.mode is Mode.ESCAPING
    far = (1.62, 1.5, 0.0)                        # 0.12 m: this cycle ends escape mode ...
    assert tc.find_best_path(open_map(), far, STILL).xv <= 0
    assert tc.state == PlannerState()
    assert tc.find_best_path(open_map(), far, STILL).xv > 0     # ... and the next drives on


def test_escape_mode_ends_past_escape_reset_theta():
    tc = planner(straight_plan(x0=1.5))
    tc.find_best_path(touching_behind(), (1.5, 1.5, 0.0), STILL)
    tc.find_best_path(open_map(), (1.5, 1.5, 1.4), STILL)
    assert tc.state.mode is Mode.ESCAPING         # 1.4 rad < π/2
    tc.find_best_path(open_map(), (1.5, 1.5, 1.7), STILL)
    assert tc.state == PlannerState()


def test_no_path_does_not_enter_escape_mode():
    """Upstream enters escape mode only "when the planner has given a valid goal point": with
    the plan behind a wall (every sample costs −2) the robot gets no command and stays NORMAL,
    so once the wall is gone it drives on at once."""
    lp = LocalPlanner(config(), SQUARE, 0.1, RES)
    lp.set_plan(straight_plan(x0=2.3, x1=2.9))
    pose = (1.5, 1.5, 0.0)
    assert lp.compute_velocity_commands(map_with([(slice(None), 40)]), pose, STILL,
                                        IDENTITY) is None
    assert lp.tc.state == PlannerState()
    cmd = lp.compute_velocity_commands(open_map(), pose, STILL, IDENTITY)
    assert cmd is not None and cmd[0] > 0


# ------------------------------------------------------------------- REVERSING (extension)
def test_reverse_when_blocked_enters_reversing_where_it_began():
    cm, pose, plan = narrow_corridor_facing_away()
    tc = planner(plan, reverse_when_blocked=True)
    best = tc.find_best_path(cm, pose, STILL)
    assert best.xv == -0.15 and tc.state == PlannerState(Mode.REVERSING, pose)
    tc.find_best_path(cm, (1.45, 1.5, 0.0), (-0.15, 0.0))
    assert tc.state == PlannerState(Mode.REVERSING, pose)          # anchor kept


def test_reversing_is_committed_for_escape_reset_dist_then_ends():
    """Once reversing, it goes on to escape_reset_dist (0.1 m) from where it began even where
    backing up no longer pays (here: a new plan ahead), then the forward sample wins."""
    cm, pose, plan = narrow_corridor_facing_away()
    lp = LocalPlanner(config(reverse_when_blocked=True), SQUARE, 0.1, RES)
    lp.set_plan(plan)
    assert lp.compute_velocity_commands(cm, pose, STILL, IDENTITY)[0] == -0.15
    lp.set_plan(straight_plan(x0=1.45, x1=2.9))                  # the goal is now ahead
    fresh = LocalPlanner(config(reverse_when_blocked=True), SQUARE, 0.1, RES)
    fresh.set_plan(straight_plan(x0=1.45, x1=2.9))
    back = (1.45, 1.5, 0.0)
    assert fresh.compute_velocity_commands(cm, back, (-0.15, 0.0), IDENTITY)[0] > 0
    assert lp.compute_velocity_commands(cm, back, (-0.15, 0.0), IDENTITY)[0] == -0.15
    assert lp.compute_velocity_commands(cm, (1.42, 1.5, 0.0), (-0.15, 0.0),
                                        IDENTITY)[0] == -0.15
    cmd = lp.compute_velocity_commands(cm, (1.38, 1.5, 0.0), STILL, IDENTITY)   # 0.12 m
    assert cmd[0] > 0 and lp.tc.state == PlannerState()


def test_reverse_cut_short_by_a_wall_behind_drives_on_until_the_robot_can_turn():
    """REVERSE_BLOCKED: in a corridor too narrow to turn, with the goal behind and a wall
    0.45 m behind the robot's centre, the reverse stops 5 cm after it began; the robot then drives
    forward past escape_reset_dist (0.1 m) instead of reversing again, which a planner without
    that memory does there (the 2 cm shuttle of NLB run_000, stuck for 511 s)."""
    cm, pose, _ = narrow_corridor_facing_away()
    boxed = Costmap(cm.costs.copy(), (0.0, 0.0), RES)
    boxed.costs[:, 20] = LETHAL                                # x = 1.00–1.05 m
    plan = straight_plan(x0=1.5, x1=1.15)
    tc = planner(plan, reverse_when_blocked=True)
    assert tc.find_best_path(boxed, pose, STILL).xv == -0.15
    cut = (1.45, 1.5, 0.0)
    assert tc.find_best_path(boxed, cut, (-0.15, 0.0)).xv > 0
    assert tc.state == PlannerState(Mode.REVERSE_BLOCKED, cut)
    ahead = (1.6, 1.5, 0.0)                                    # 0.15 m from where it stopped
    assert tc.find_best_path(boxed, ahead, (0.1, 0.0)).xv > 0
    assert tc.state == PlannerState(Mode.REVERSE_BLOCKED, cut)
    fresh = planner(plan, reverse_when_blocked=True)
    assert fresh.find_best_path(boxed, ahead, (0.1, 0.0)).xv == -0.15


def test_reversing_robot_with_nothing_legal_enters_escape_mode():
    cm, pose, plan = narrow_corridor_facing_away()
    tc = planner(plan, reverse_when_blocked=True)
    tc.find_best_path(cm, pose, STILL)
    assert tc.state.mode is Mode.REVERSING
    best = tc.find_best_path(touching_behind(), pose, STILL)
    assert best.xv == -0.15 and tc.state == PlannerState(Mode.ESCAPING, pose)


# ---------------------------------------------------------------- KEEPING_MOVE (extension)
def tilted_in_a_corner() -> Costmap:
    """A wall at y = 1.25–1.30 m the footprint of a robot at (1.5, 1.5, 0.15) touches, and one
    at x = 1.75–1.80 m just ahead of it: with escape_footprint_margin 0.04 m the shrunk
    footprint (the body) clears both, but has no legal forward sample or rotation, and backing
    straight up it would hit the first wall."""
    return map_with([(25, slice(None)), (slice(None), 35)])


CORNER_POSE = (1.5, 1.5, 0.15)


def escaped_from_corner():
    """A margin planner after its first cycle at CORNER_POSE, and that cycle's command."""
    tc = planner(straight_plan(x0=1.5, x1=1.7), escape_footprint_margin=0.04)
    return tc, tc.find_best_path(tilted_in_a_corner(), CORNER_POSE, STILL)


def along(tc: TrajectoryPlanner, best, k: int):
    """Pose k of the command's rollout with the body, and the velocity there."""
    pts = tc.trajectory_points(tilted_in_a_corner(), CORNER_POSE, STILL, best.xv, best.thetav,
                               tc.body)
    return tuple(pts[k]), (best.xv, best.thetav)


def test_body_safe_escape_is_kept_with_the_escape_pose():
    tc, best = escaped_from_corner()
    assert best.xv == -0.15 and best.thetav < 0 and best.cost >= 0
    assert tc.state == PlannerState(Mode.KEEPING_MOVE, CORNER_POSE, (best.xv, best.thetav))


def test_kept_move_is_commanded_again_where_a_fresh_choice_differs():
    tc, first = escaped_from_corner()
    pose, vel = along(tc, first, 3)
    fresh = planner(straight_plan(x0=1.5, x1=1.7), escape_footprint_margin=0.04)
    other = fresh.find_best_path(tilted_in_a_corner(), pose, vel)
    assert (other.xv, other.thetav) != (first.xv, first.thetav)
    again = tc.find_best_path(tilted_in_a_corner(), pose, vel)
    assert (again.xv, again.thetav) == (first.xv, first.thetav) and again.cost >= 0
    assert tc.state.mode is Mode.KEEPING_MOVE and tc.state.anchor == CORNER_POSE


def test_kept_move_is_dropped_when_the_body_no_longer_clears_it():
    tc, first = escaped_from_corner()
    pose, vel = along(tc, first, 3)
    blocked = map_with([(25, slice(None)), (slice(None), 35), (slice(25, 35), 24)])
    best = tc.find_best_path(blocked, pose, vel)                 # a new obstacle behind
    assert (best.xv, best.thetav) != (first.xv, first.thetav)
    assert tc.state.escaping and tc.state.move != (first.xv, first.thetav)


def test_kept_move_ends_past_escape_reset_dist():
    tc, first = escaped_from_corner()
    out = (1.36, 1.48, 0.1)                       # 0.14 m from the escape pose, in the open
    best = tc.find_best_path(open_map(), out, STILL)
    assert (best.xv, best.thetav) != (first.xv, first.thetav)
    assert tc.state == PlannerState()


# ------------------------------------------------------------ rotation memory (upstream)
def test_in_place_turn_one_way_then_the_other_refuses_the_first_way():
    """base_local_planner: after a left (vθ > 0) turn in place and then a right one without
    moving oscillation_reset_dist, left turns in place are refused until it moves."""
    tc = planner(straight_plan(x0=1.5, x1=1.5 - 1.2))   # goal behind: turn in place
    pose = (1.5, 1.5, 0.3)
    first = tc.find_best_path(open_map(), pose, STILL)
    assert first.xv == 0.0 and first.thetav > 0
    tc.update_plan(np.array([[1.5, 1.5 - k * 0.05, 0.0] for k in range(20)]))   # to the right
    second = tc.find_best_path(open_map(), pose, STILL)
    assert second.xv == 0.0 and second.thetav < 0
    tc.update_plan(straight_plan(x0=1.5, x1=1.5 - 1.2))
    third = tc.find_best_path(open_map(), pose, STILL)
    assert not (third.xv == 0.0 and third.thetav > 0)     # no left turn in place
    moved = (1.44, 1.5, 0.3)                     # a forward cycle 0.06 m away clears the flags
    tc.update_plan(straight_plan(x0=1.44))
    assert tc.find_best_path(open_map(), moved, STILL).xv > 0
    tc.update_plan(straight_plan(x0=1.44, x1=1.44 - 1.2))
    again = tc.find_best_path(open_map(), moved, STILL)
    assert again.xv == 0.0 and again.thetav > 0


# --------------------------------------------------------------- the transition function
RESETS = modes.Resets(0.1, math.pi / 2)
AT = (1.0, 1.0, 0.0)
NEAR = (1.05, 1.0, 0.0)
FAR = (1.2, 1.0, 0.0)
MOVE = (-0.15, -0.2)


def test_next_state_table():
    C = modes.Chosen
    normal = PlannerState()
    escaping = PlannerState(Mode.ESCAPING, AT)
    keeping = PlannerState(Mode.KEEPING_MOVE, AT, MOVE)
    reversing = PlannerState(Mode.REVERSING, AT)
    blocked = PlannerState(Mode.REVERSE_BLOCKED, AT)
    turned = (1.0, 1.0, 1.7)                        # 1.7 rad from AT's heading: > π/2
    table = [
        (normal, C.SAMPLE, NEAR, None, normal),
        (normal, C.NO_PATH, NEAR, None, normal),
        (normal, C.BACK_UP, NEAR, None, PlannerState(Mode.ESCAPING, NEAR)),
        (normal, C.BODY_SAFE, NEAR, MOVE, PlannerState(Mode.KEEPING_MOVE, NEAR, MOVE)),
        (normal, C.REVERSE, NEAR, None, PlannerState(Mode.REVERSING, NEAR)),
        (reversing, C.REVERSE, FAR, None, reversing),
        (reversing, C.SAMPLE, NEAR, None, PlannerState(Mode.REVERSE_BLOCKED, NEAR)),
        (reversing, C.SAMPLE, FAR, None, normal),
        (blocked, C.SAMPLE, FAR, None, blocked),
        (blocked, C.SAMPLE, turned, None, normal),
        (blocked, C.BACK_UP, NEAR, None, PlannerState(Mode.ESCAPING, NEAR)),
        (reversing, C.BACK_UP, NEAR, None, PlannerState(Mode.ESCAPING, NEAR)),
        (escaping, C.SAMPLE, NEAR, None, escaping),
        (escaping, C.SAMPLE, FAR, None, normal),
        (escaping, C.NO_PATH, NEAR, None, escaping),
        (escaping, C.BACK_UP, FAR, None, normal),
        (escaping, C.BODY_SAFE, NEAR, MOVE, keeping),
        (keeping, C.KEPT_MOVE, NEAR, None, keeping),
        (keeping, C.BACK_UP, NEAR, None, escaping),
        (keeping, C.BODY_SAFE, NEAR, (-0.15, 0.3),
         PlannerState(Mode.KEEPING_MOVE, AT, (-0.15, 0.3))),
        (keeping, C.SAMPLE, FAR, None, normal),
    ]
    for before, chosen, pose, move, after in table:
        seen = modes.Observed(chosen, pose, move)
        assert modes.next_state(before, seen, RESETS) == after, (before, chosen)


def test_oscillation_memory():
    osc = modes.Oscillation().after(0.0, 0.5, (1.0, 1.0))
    assert osc.rotating_right and not osc.stuck_left
    osc = osc.after(0.0, -0.5, (1.0, 1.0))
    assert osc.stuck_right and not osc.allows(0.5) and osc.allows(-0.5)
    assert osc.after(0.3, 0.0, (5.0, 5.0)) == osc              # driving forward: unchanged
    assert osc.reset_if_moved((1.04, 1.0), 0.05) == osc
    assert osc.reset_if_moved((1.06, 1.0), 0.05) == modes.Oscillation(prev_xy=(1.0, 1.0))


# ------------------------------------------------------------------ one footprint rule
def beside_a_wall() -> Costmap:
    """A wall at y = 1.25–1.30 m: the footprint of a robot at (1.5, 1.5, 0) touches it, the
    footprint shrunk by 0.04 m does not."""
    return map_with([(25, slice(None))])


def test_check_trajectory_agrees_with_the_cycles_scoring():
    """With escape_footprint_margin the cycle scores its samples with the shrunk footprint
    where the footprint touches a wall; check_trajectory must judge them the same way."""
    cm, pose = beside_a_wall(), (1.5, 1.5, 0.0)
    tc = planner(straight_plan(x0=1.5), escape_footprint_margin=0.04)
    best = tc.find_best_path(cm, pose, STILL)
    assert best.cost >= 0 and best.xv > 0
    assert tc.check_trajectory(cm, pose, STILL, best.xv, best.thetav)
    assert len(best.points) >= 5 and best.points[-1, 0] > pose[0]      # local_plan


def test_stopping_at_the_goal_beside_a_wall_is_checked_with_the_cycles_footprint():
    """Within xy_goal_tolerance the robot first stops (acc limits), the stop checked by
    check_trajectory: beside the wall it is legal for the footprint the cycle scores with."""
    plan = straight_plan(x0=1.3, x1=1.6)
    plan[-1, 2] = math.pi / 2                       # the goal yaw: turn after stopping
    lp = LocalPlanner(config(escape_footprint_margin=0.04, xy_goal_tolerance=0.3), SQUARE, 0.1,
                      RES)
    lp.set_plan(plan)
    cmd = lp.compute_velocity_commands(beside_a_wall(), (1.5, 1.5, 0.0), (0.3, 0.0), IDENTITY)
    assert cmd is not None and cmd[1] == 0.0 and abs(cmd[0] - 0.15) < 1e-12


def test_body_safe_escape_carries_its_poses():
    """The move is rolled out with the shrunk footprint it was chosen with (local_plan)."""
    tc, best = escaped_from_corner()
    costs = tilted_in_a_corner().costs
    assert len(best.points) >= 5 and best.points[-1, 0] < CORNER_POSE[0]
    assert all(footprint_cost(costs, 0.0, 0.0, RES, x, y, th, tc.body) >= 0
               for x, y, th in best.points)
