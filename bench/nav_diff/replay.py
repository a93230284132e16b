"""Replay captured cycles through our TrajectoryPlanner open loop, optionally with the rules where
the real base_local_planner (noetic-devel) differs switched to its behaviour, to measure what
each difference accounts for. The switches are the library's own (TrajectoryPlannerConfig
``upstream_rules`` sets all five; here they are set one at a time: DistanceGrids' three, the
rotation memory's ``upstream`` argument, and the float32 inputs of findBestPath).

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
from pathlib import Path

import numpy as np

from slam_predict.formats.nav_cycles import read_cycles
from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import Costmap
from slam_predict.nav.trajectory_planner import TrajectoryPlanner

VARIANTS = ("oscillation", "local_goal", "goal_within", "float_pose", "footprint_cells",
            "no_extensions")


# variant -> (the planner's DistanceGrids or itself, its switch for that rule)
SWITCHES = {"local_goal": ("grids", "last_point_goal"),
            "goal_within": ("grids", "goal_exempts_nothing"),
            "footprint_cells": ("grids", "helper_cells"),
            "oscillation": (None, "upstream_turn_memory"), "float_pose": (None, "float_pose")}


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
    for cycle in read_cycles(folder / "cycles.bin"):
        local = cycle.costmap
        if tp is None:
            tp = TrajectoryPlanner(cfg, footprint, sim_period, local.resolution)
            for variant, (part, switch) in SWITCHES.items():
                setattr(getattr(tp, part) if part else tp, switch, variant in variants)
        tp.update_plan(cycle.plan)
        best = tp.find_best_path(Costmap(local.costs, local.origin, local.resolution),
                                 cycle.pose, cycle.vel)
        rows.append((best.xv, best.thetav, best.cost))
    table = np.array(rows, dtype=float).reshape(-1, 3)
    return {"xv": table[:, 0], "thetav": table[:, 1], "cost": table[:, 2]}
