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

import math

import numba as nb
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


@nb.njit(cache=True)
def adjusted_plan(plan, resolution):
    """MapGrid::adjustPlanResolution of ``plan[:, :2]`` (m): (m, 2) points where a segment of
    length L > resolution gets ceil(L/resolution) − 1 evenly spaced points inserted (point j
    of a segment s split in n steps: start + (j/n)·s), the plan's last point at the end."""
    n = plan.shape[0]
    if n < 2:
        out = np.empty((n, 2))
        out[:, :] = plan[:, :2]
        return out
    steps = np.empty(n - 1, np.int64)
    for i in range(n - 1):
        length = math.hypot(plan[i + 1, 0] - plan[i, 0], plan[i + 1, 1] - plan[i, 1])
        steps[i] = int(math.ceil(length / resolution)) if length > resolution else 1
    out = np.empty((steps.sum() + 1, 2))
    m = 0
    for i in range(n - 1):
        sx = plan[i + 1, 0] - plan[i, 0]
        sy = plan[i + 1, 1] - plan[i, 1]
        for j in range(steps[i]):
            frac = j / steps[i]
            out[m, 0] = plan[i, 0] + frac * sx
            out[m, 1] = plan[i, 1] + frac * sy
            m += 1
    out[m, 0] = plan[n - 1, 0]
    out[m, 1] = plan[n - 1, 1]
    return out


@nb.njit(cache=True)
def _known_cells(pts, costs, ox, oy, resolution):
    """Cells (m, 2) of the points (m, 2) m and whether each is on the map on a known cell."""
    ny, nx = costs.shape
    cells = np.zeros((pts.shape[0], 2), np.int64)
    ok = np.zeros(pts.shape[0], np.bool_)
    for i in range(pts.shape[0]):
        if pts[i, 0] >= ox and pts[i, 1] >= oy:
            mx = int((pts[i, 0] - ox) / resolution)
            my = int((pts[i, 1] - oy) / resolution)
            cells[i, 0] = mx
            cells[i, 1] = my
            ok[i] = mx < nx and my < ny and costs[my, mx] != NO_INFORMATION
    return cells, ok


@nb.njit(cache=True)
def plan_cells(plan, costs, ox, oy, resolution):
    """(path cells (n, 2) int64, index of the local goal in them; -1 when n = 0) of a plan
    (k, ≥ 2) m on a costmap (uint8 [ny, nx], origin (ox, oy) m): see
    :func:`path_and_goal_cells`."""
    pts = adjusted_plan(plan, resolution)
    cells, ok = _known_cells(pts, costs, ox, oy, resolution)
    first = 0
    while first < pts.shape[0] and not ok[first]:
        first += 1
    stop = first
    while stop < pts.shape[0] and ok[stop]:
        stop += 1
    path = cells[first:stop].copy()
    if stop == first:
        return path, -1
    away = False
    for i in range(first + 1):        # the plan is more than 1 m from its start by this point
        h = math.hypot(pts[i, 0] - pts[0, 0], pts[i, 1] - pts[0, 1])
        away = away or h * h > 1.0
    was_blocked = costs[path[0, 1], path[0, 0]] >= INSCRIBED
    for k in range(1, stop - first):
        h = math.hypot(pts[first + k, 0] - pts[0, 0], pts[first + k, 1] - pts[0, 1])
        away = away or h * h > 1.0
        blocked = costs[path[k, 1], path[k, 0]] >= INSCRIBED
        if away and blocked and not was_blocked:
            return path, k - 1            # the point before the first such break
        was_blocked = blocked
    return path, stop - first - 1


def adjust_plan_resolution(plan_xy: np.ndarray, resolution: float) -> np.ndarray:
    """MapGrid::adjustPlanResolution of points (n, 2) m (:func:`adjusted_plan`)."""
    plan_xy = np.ascontiguousarray(plan_xy, dtype=float).reshape(-1, 2)
    return adjusted_plan(plan_xy, float(resolution))


def path_and_goal_cells(costmap: Costmap, plan: np.ndarray):
    """(path cells (n, 2), local goal cell (≤ 1, 2)) of a plan on a local costmap.

    Path cells: the plan's first contiguous run of points (resolution-adjusted) inside the map
    on known cells (MapGrid::setTargetCells). Local goal (MapGrid::setLocalGoal): the last point
    of that run, except that once the plan is more than 1 m from its start, a point in an
    obstacle (≥ INSCRIBED) right after a free one ends the run there.
    """
    if len(plan) == 0:
        empty = np.empty((0, 2), np.int64)
        return empty, empty
    plan = np.ascontiguousarray(plan, dtype=float).reshape(len(plan), -1)
    path, k = plan_cells(plan, costmap.costs, float(costmap.origin[0]),
                         float(costmap.origin[1]), float(costmap.resolution))
    return path, path[k:k + 1] if k >= 0 else path


def warmup() -> None:
    """Compile the plan kernels on a two-point plan over a tiny costmap."""
    plan_cells(np.array([[0.05, 0.05, 0.0], [0.25, 0.15, 0.0]]), np.zeros((4, 4), np.uint8),
               0.0, 0.0, 0.1)
