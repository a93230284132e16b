"""The ``escape_alternate`` extension of the TrajectoryPlanner: a blind escape right after a blind
escape drives forward instead of backing into the wall again."""
from __future__ import annotations

import numpy as np

from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import LETHAL, Costmap
from slam_predict.nav.planner_modes import BlindEscapes, Mode, PlannerState
from slam_predict.nav.trajectory_planner import TrajectoryPlanner

RES = 0.05
SQUARE = np.array([[-0.21, -0.21], [-0.21, 0.21], [0.21, 0.21], [0.21, -0.21]])
POSE = (1.52, 1.52, 0.0)


def planner(**kw) -> TrajectoryPlanner:
    cfg = TrajectoryPlannerConfig(max_vel_x=0.85, min_vel_x=0.1, max_vel_theta=0.7,
                                  min_vel_theta=-0.7, acc_lim_x=1.5, acc_lim_theta=2.5,
                                  sim_time=1.5, vx_samples=10, escape_vel=-0.15, **kw)
    tc = TrajectoryPlanner(cfg, SQUARE, 0.1, RES)
    xs = np.linspace(1.52, 2.9, 40)
    tc.update_plan(np.column_stack([xs, np.full_like(xs, 1.52), np.zeros_like(xs)]))
    return tc


def boxed() -> Costmap:
    """A pocket whose walls the footprint already touches: nothing is legal and the straight
    escape collides (a blind escape)."""
    costs = np.zeros((60, 60), np.uint8)
    costs[25:36, 25:36] = LETHAL
    costs[29:32, 29:32] = 0
    return Costmap(costs, (0.0, 0.0), RES)


def escapes(tc: TrajectoryPlanner, costmap: Costmap, n: int) -> list[float]:
    """vx of the first cycle of ``n`` escapes, each begun anew (the reset passed: NORMAL)."""
    out = []
    for _ in range(n):
        tc.state = PlannerState()
        best = tc.find_best_path(costmap, POSE, (0.0, 0.0))
        assert tc.state.mode is Mode.ESCAPING and best.cost >= 0
        out.append(best.xv)
    return out


def test_blind_escapes_alternate_only_with_the_extension():
    assert escapes(planner(), boxed(), 4) == [-0.15] * 4            # base_local_planner
    assert escapes(planner(escape_alternate=True), boxed(), 4) == [-0.15, 0.15, -0.15, 0.15]


def test_an_escape_keeps_its_direction_until_its_reset():
    tc = planner(escape_alternate=True)
    assert escapes(tc, boxed(), 2) == [-0.15, 0.15]
    again = tc.find_best_path(boxed(), POSE, (0.0, 0.0))          # still ESCAPING: no new begin
    assert again.xv == 0.15 and tc.blind == BlindEscapes(True, True)


def test_a_legal_command_between_two_blind_escapes_forgets_the_first():
    tc = planner(escape_alternate=True)
    assert escapes(tc, boxed(), 1) == [-0.15]
    tc.state = PlannerState()
    free = tc.find_best_path(Costmap(np.zeros((60, 60), np.uint8), (0.0, 0.0), RES), POSE,
                             (0.0, 0.0))
    assert free.xv > 0 and tc.blind == BlindEscapes()
    assert escapes(tc, boxed(), 1) == [-0.15]


def test_an_escape_with_a_clear_straight_path_is_not_blind():
    """A straight escape the costmap shows clear is upstream's, and resets the alternation."""
    assert BlindEscapes(True, True).begin(False) == BlindEscapes(False, False)
    assert BlindEscapes().begin(True) == BlindEscapes(True, False)
    assert BlindEscapes(True, False).begin(True) == BlindEscapes(True, True)
    assert BlindEscapes(True, True).begin(True) == BlindEscapes(True, False)
