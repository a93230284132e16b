"""Replay captured cycles through our TrajectoryPlanner open loop, optionally with the rules where
the real base_local_planner (noetic-devel) differs switched to its behaviour, to measure what
each difference accounts for.

Variants (names for :func:`replay`):

- ``oscillation``: the rotation memory of createTrajectories' first ``cost >= 0`` block (the
  one a non-holonomic robot reaches): a negative in-place vθ sets ``rotating_right`` (and
  ``stuck_right`` when already set), a positive one ``rotating_left`` / ``stuck_left``; ours
  follows the second block, reached only with holonomic_robot.
- ``local_goal``: MapGrid::setLocalGoal of noetic-devel: the last point of the plan's first run
  inside the map on known cells (ours stops early at an obstacle once 1 m from the start).
- ``goal_within``: the goal distance BFS without the footprint exemption (findBestPath marks
  ``within_robot`` on path_map_ only).
- ``float_pose``: pose and velocity rounded to float32 (findBestPath's Eigen::Vector3f).
- ``no_extensions``: reverse_when_blocked, escape_footprint_margin, escape_alternate off.
"""
from __future__ import annotations

import dataclasses
from contextlib import ExitStack, contextmanager
from dataclasses import replace
from pathlib import Path

import numpy as np

from slam_predict.formats.nav_cycles import read_cycles
from slam_predict.nav import kernels, map_grid
from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import Costmap, footprint_cells
from slam_predict.nav.planner_modes import Oscillation
from slam_predict.nav.trajectory_planner import TrajectoryPlanner

VARIANTS = ("oscillation", "local_goal", "goal_within", "float_pose", "no_extensions")


@contextmanager
def _patched(owner, name, value):
    saved = getattr(owner, name)
    setattr(owner, name, value)
    try:
        yield
    finally:
        setattr(owner, name, saved)


def _upstream_after(self, xv, thetav, xy):
    """Oscillation.after as createTrajectories' first block sets the flags."""
    if xv > 0:
        return self
    osc = self
    if thetav < 0:
        osc = replace(osc, stuck_right=osc.stuck_right or osc.rotating_right,
                      rotating_right=True)
    elif thetav > 0:
        osc = replace(osc, stuck_left=osc.stuck_left or osc.rotating_left, rotating_left=True)
    return replace(osc, prev_xy=(float(xy[0]), float(xy[1])))


def _last_point_goal(original):
    def path_and_goal_cells(costmap, plan):
        path, _ = original(costmap, plan)
        return path, path[-1:]
    return path_and_goal_cells


def _update_without_goal_exemption(self, costmap, pose, plan, footprint, radius):
    """DistanceGrids.update with no footprint exemption in the goal BFS."""
    costs = costmap.costs
    if self.path.shape != costs.shape or len(self._queue) != costs.size:
        self.path = np.empty(costs.shape)
        self.goal = np.empty(costs.shape)
        self._queue = np.empty((costs.size, 2), np.int32)
    within = np.zeros(costs.shape, np.bool_)
    cells = footprint_cells(costmap, pose, footprint)
    if len(cells):
        within[cells[:, 1], cells[:, 0]] = True
    path, goal = map_grid.path_and_goal_cells(costmap, plan)
    cell = costmap.world_to_map(float(pose[0]), float(pose[1]))
    cx, cy = cell if cell is not None else (0, 0)
    radius = radius if cell is not None else -1
    kernels.target_distance(costs, within, path[:, 0], path[:, 1], self.path, self._queue,
                            cx, cy, radius)
    kernels.target_distance(costs, np.zeros_like(within), goal[:, 0], goal[:, 1], self.goal,
                            self._queue, cx, cy, radius)


def _patches(variants) -> list:
    out = []
    if "oscillation" in variants:
        out.append((Oscillation, "after", _upstream_after))
    if "local_goal" in variants:
        out.append((map_grid, "path_and_goal_cells",
                    _last_point_goal(map_grid.path_and_goal_cells)))
    if "goal_within" in variants:
        out.append((map_grid.DistanceGrids, "update", _update_without_goal_exemption))
    return out


def _f32(values):
    return tuple(float(np.float32(v)) for v in values)


def replay(folder: Path, cfg: TrajectoryPlannerConfig, footprint: np.ndarray,
           sim_period: float, variants=()) -> dict[str, np.ndarray]:
    """Our commands (xv m/s, thetav rad/s, cost) per captured cycle, open loop, one planner."""
    unknown = set(variants) - set(VARIANTS)
    if unknown:
        raise ValueError(f"unknown variants {sorted(unknown)}; known: {', '.join(VARIANTS)}")
    if "no_extensions" in variants:
        cfg = dataclasses.replace(cfg, reverse_when_blocked=False, escape_footprint_margin=0.0,
                                  escape_alternate=False)
    rows, tp = [], None
    with ExitStack() as stack:
        for owner, name, value in _patches(variants):
            stack.enter_context(_patched(owner, name, value))
        for cycle in read_cycles(folder / "cycles.bin"):
            local = cycle.costmap
            if tp is None:
                tp = TrajectoryPlanner(cfg, footprint, sim_period, local.resolution)
            pose, vel = cycle.pose, cycle.vel
            if "float_pose" in variants:
                pose, vel = _f32(pose), _f32(vel)
            tp.update_plan(cycle.plan)
            best = tp.find_best_path(Costmap(local.costs, local.origin, local.resolution), pose,
                                     vel)
            rows.append((best.xv, best.thetav, best.cost))
    table = np.array(rows, dtype=float).reshape(-1, 3)
    return {"xv": table[:, 0], "thetav": table[:, 1], "cost": table[:, 2]}
