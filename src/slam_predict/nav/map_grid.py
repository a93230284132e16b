"""base_local_planner's MapGrid: the path and goal distance grids the rollouts are scored on.

Each control cycle the plan (in the local costmap's frame) is resolution-adjusted and its first
run of points inside the map on known cells seeds the path distance; the local goal (the last
point of that run, MapGrid::setLocalGoal) seeds the goal distance. Distances are in cells, by
4-connected BFS (nav/kernels.py ``target_distance``); obstacle cells (≥ INSCRIBED, unknown) are
not entered, except those under the robot's footprint. With ``upstream`` (TrajectoryPlannerConfig
``upstream_rules``) three rules are noetic-devel's instead of the project's earlier ones: the
local goal is the run's last point, the goal grid's BFS exempts no footprint cell (findBestPath
marks them on the path grid only), and the footprint cells are FootprintHelper's.
"""
from __future__ import annotations

import numpy as np

from slam_predict.nav import kernels
from slam_predict.nav.costmap import INSCRIBED, NO_INFORMATION, Costmap, footprint_cells
from slam_predict.nav.footprint_helper import footprint_cells_upstream


class DistanceGrids:
    """The path and goal distance grids (cells) of one local costmap, refilled every cycle."""

    def __init__(self, upstream: bool = False) -> None:
        # the three upstream rules, one switch each (bench/nav_diff/replay.py weighs them apart)
        self.helper_cells = self.last_point_goal = self.goal_exempts_nothing = upstream
        self.path = np.zeros((1, 1))
        self.goal = np.zeros((1, 1))
        self._queue = np.empty((0, 2), np.int32)

    def update(self, costmap: Costmap, pose, plan: np.ndarray, footprint: np.ndarray,
               radius: int) -> None:
        """MapGrid::setPathCells for the robot at ``pose`` (x m, y m, θ rad) with the plan
        (n, 3); distances are exact within ``radius`` cells of the robot (farther cells are
        never read by the rollouts)."""
        costs = costmap.costs
        if self.path.shape != costs.shape or len(self._queue) != costs.size:
            self.path = np.empty(costs.shape)
            self.goal = np.empty(costs.shape)
            self._queue = np.empty((costs.size, 2), np.int32)
        within = np.zeros(costs.shape, np.bool_)
        cells = (footprint_cells_upstream if self.helper_cells else footprint_cells)(
            costmap, pose, footprint)
        if len(cells):
            within[cells[:, 1], cells[:, 0]] = True
        path, goal = path_and_goal_cells(costmap, plan)
        if self.last_point_goal:
            goal = path[-1:]
        cell = costmap.world_to_map(float(pose[0]), float(pose[1]))
        cx, cy = cell if cell is not None else (0, 0)
        radius = radius if cell is not None else -1
        kernels.target_distance(costs, within, path[:, 0], path[:, 1], self.path,
                                self._queue, cx, cy, radius)
        if self.goal_exempts_nothing:
            within[:] = False
        kernels.target_distance(costs, within, goal[:, 0], goal[:, 1], self.goal,
                                self._queue, cx, cy, radius)


def adjust_plan_resolution(plan_xy: np.ndarray, resolution: float) -> np.ndarray:
    """MapGrid::adjustPlanResolution: insert points so consecutive ones are ≤ resolution apart
    (a segment of length L > resolution gets ceil(L/resolution) − 1 evenly spaced points)."""
    plan_xy = np.asarray(plan_xy, dtype=float).reshape(-1, 2)
    if len(plan_xy) < 2:
        return plan_xy
    seg = np.diff(plan_xy, axis=0)
    length = np.hypot(seg[:, 0], seg[:, 1])
    steps = np.where(length > resolution, np.ceil(length / resolution), 1).astype(int)
    seg_index = np.repeat(np.arange(len(seg)), steps)
    offsets = np.arange(len(seg_index)) - np.repeat(np.cumsum(steps) - steps, steps)
    frac = offsets / steps[seg_index]
    points = plan_xy[seg_index] + frac[:, None] * seg[seg_index]
    return np.vstack([points, plan_xy[-1:]])


def path_and_goal_cells(costmap: Costmap, plan: np.ndarray):
    """(path cells (n, 2), local goal cell (≤ 1, 2)) of a plan on a local costmap.

    Path cells: the plan's first contiguous run of points (resolution-adjusted) inside the map
    on known cells (MapGrid::setTargetCells). Local goal (MapGrid::setLocalGoal): the last point
    of that run, except that once the plan is more than 1 m from its start, a point in an
    obstacle (≥ INSCRIBED) right after a free one ends the run there.
    """
    empty = np.empty((0, 2), np.int64)
    if len(plan) == 0:
        return empty, empty
    pts = adjust_plan_resolution(np.asarray(plan, dtype=float)[:, :2], costmap.resolution)
    ox, oy = costmap.origin
    inside = (pts[:, 0] >= ox) & (pts[:, 1] >= oy)
    mx = np.zeros(len(pts), np.int64)
    my = np.zeros(len(pts), np.int64)
    mx[inside] = ((pts[inside, 0] - ox) / costmap.resolution).astype(np.int64)
    my[inside] = ((pts[inside, 1] - oy) / costmap.resolution).astype(np.int64)
    inside &= (mx < costmap.size_x) & (my < costmap.size_y)
    ok = np.zeros(len(pts), bool)
    ok[inside] = costmap.costs[my[inside], mx[inside]] != NO_INFORMATION
    if not ok.any():
        return empty, empty
    first = int(np.argmax(ok))
    rest = ok[first:]
    stop = first + (len(rest) if rest.all() else int(np.argmin(rest)))
    run = np.arange(first, stop)
    path = np.stack([mx[run], my[run]], axis=1)
    away = np.maximum.accumulate(np.hypot(*(pts - pts[0]).T) ** 2 > 1.0)[run]
    blocked = costmap.costs[my[run], mx[run]] >= INSCRIBED
    ends = np.nonzero(away[1:] & blocked[1:] & ~blocked[:-1])[0]
    k = ends[0] if len(ends) else len(run) - 1   # the point before the first such break
    return path, path[k:k + 1]
