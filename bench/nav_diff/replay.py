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
- ``footprint_cells``: the footprint's own cells (exempt from the BFS) as FootprintHelper
  rasterises them: the outline's Bresenham lines, then getFillCells' column fill (ours: cells
  whose centre is inside the polygon grown by half a cell, yaw rounded to 5°).
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
from slam_predict.nav.costmap import Costmap
from slam_predict.nav.planner_modes import Oscillation
from slam_predict.nav.trajectory_planner import TrajectoryPlanner

VARIANTS = ("oscillation", "local_goal", "goal_within", "float_pose", "footprint_cells",
            "no_extensions")


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
    cells = map_grid.footprint_cells(costmap, pose, footprint)
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


def _line_cells(x0, y0, x1, y1) -> list[tuple[int, int]]:
    """FootprintHelper::getLineCells: the Bresenham cells from (x0, y0) to (x1, y1)."""
    dx, dy = abs(x1 - x0), abs(y1 - y0)
    sx, sy = (1 if x1 >= x0 else -1), (1 if y1 >= y0 else -1)
    major_x = dx >= dy
    den, numadd = (dx, dy) if major_x else (dy, dx)
    num, out, x, y = den // 2, [], x0, y0
    for _ in range(den + 1):
        out.append((x, y))
        num += numadd
        if num >= den:
            num -= den
            x, y = (x, y + sy) if major_x else (x + sx, y)
        x, y = (x + sx, y) if major_x else (x, y + sy)
    return out


def _fill(cells: list[tuple[int, int]]) -> None:
    """FootprintHelper::getFillCells, step for step (the list grows while it is read)."""
    i = 0
    while i < len(cells) - 1:
        if cells[i][0] > cells[i + 1][0]:
            cells[i], cells[i + 1] = cells[i + 1], cells[i]
            i = max(i - 1, 0)
        else:
            i += 1
    i = 0
    for x in range(cells[0][0], cells[-1][0] + 1):
        if i >= len(cells) - 1:
            break
        lo, hi = ((cells[i], cells[i + 1]) if cells[i][1] < cells[i + 1][1]
                  else (cells[i + 1], cells[i]))
        i += 2
        while i < len(cells) and cells[i][0] == x:
            if cells[i][1] < lo[1]:
                lo = cells[i]
            elif cells[i][1] > hi[1]:
                hi = cells[i]
            i += 1
        cells.extend((x, y) for y in range(lo[1], hi[1]))


def _upstream_footprint_cells(costmap, pose, footprint) -> np.ndarray:
    """FootprintHelper::getFootprintCells(pos, footprint, costmap, fill=true) as (n, 2)."""
    x, y, th = (float(v) for v in pose[:3])
    c, s = np.cos(th), np.sin(th)
    corners = []
    for fx, fy in footprint:
        corners.append(costmap.world_to_map(x + (fx * c - fy * s), y + (fx * s + fy * c)))
    cells: list[tuple[int, int]] = []
    n = len(corners)
    for k in range(n):   # edges 0-1, 1-2, ..., (n-1)-0, as upstream
        a, b = corners[k], corners[(k + 1) % n]
        if a is None or b is None:
            return np.array(cells, dtype=np.int64).reshape(-1, 2)
        cells += _line_cells(a[0], a[1], b[0], b[1])
    _fill(cells)
    return np.array(cells, dtype=np.int64).reshape(-1, 2)


def _patches(variants) -> list:
    out = []
    if "oscillation" in variants:
        out.append((Oscillation, "after", _upstream_after))
    if "local_goal" in variants:
        out.append((map_grid, "path_and_goal_cells",
                    _last_point_goal(map_grid.path_and_goal_cells)))
    if "goal_within" in variants:
        out.append((map_grid.DistanceGrids, "update", _update_without_goal_exemption))
    if "footprint_cells" in variants:
        out.append((map_grid, "footprint_cells", _upstream_footprint_cells))
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
