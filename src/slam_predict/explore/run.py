"""One exploration run end to end: settings from config/, the closed loop, its summary and files.

``explore_world(world, seed, settings, map_source, max_sim_time)`` returns the summary that
``slam-predict explore`` writes as ``explore.json``; :func:`write_outputs` writes it and the
map picture (``explore.png``) atomically.
"""
from __future__ import annotations

import json
import math
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from slam_predict.atomic import write_text
from slam_predict.config import (
    POSITIVE,
    Range,
    check_keys,
    config_hash,
    from_dict,
    load_config,
    load_yaml,
)
from slam_predict.explore import PERFECT
from slam_predict.explore.coverage import coverage, reachable_free, render_png
from slam_predict.explore.explorer import ExploreConfig
from slam_predict.explore.loop import ClosedLoop
from slam_predict.explore.mapsource import PerfectMapConfig
from slam_predict.nav.config import MoveBaseConfig, load_nav_config
from slam_predict.nav.costmap import inscribed_radius
from slam_predict.paths import PROJECT_ROOT
from slam_predict.sim import SimConfig
from slam_predict.world.model import World

DEFAULT_CONFIG_DIR = PROJECT_ROOT / "config"


@dataclass
class LoopSettings:
    """The closed loop's own settings (``loop:`` in closed_loop.yaml)."""

    max_sim_time: float = 10800.0
    RANGES: ClassVar[dict[str, Range]] = {"max_sim_time": POSITIVE}


@dataclass
class ExploreSettings:
    """Every configuration a closed-loop exploration needs."""

    nav: MoveBaseConfig
    explore: ExploreConfig
    sim: SimConfig
    perfect: PerfectMapConfig
    loop: LoopSettings
    slam_params: Any = None    # the map source's parameters when it is a SLAM back-end


def load_explore_settings(config_dir: os.PathLike | str = DEFAULT_CONFIG_DIR,
                          map_source: str = "perfect") -> ExploreSettings:
    """``explore``'s settings from the YAML files in ``config_dir``; a missing file means its
    defaults (unlike :func:`collect.settings.load_settings`, where every file must exist); a
    SLAM back-end ``map_source`` takes its parameters from ``<map_source>.yaml`` there."""
    config_dir = Path(config_dir)

    def path(name: str) -> Path | None:
        p = config_dir / name
        return p if p.is_file() else None

    explore = load_config(ExploreConfig, path("explore.yaml")) if path("explore.yaml") \
        else ExploreConfig()
    sim = load_config(SimConfig, path("robot.yaml"), "sim") if path("robot.yaml") else SimConfig()
    closed = load_yaml(path("closed_loop.yaml")) if path("closed_loop.yaml") else {}
    source = str(path("closed_loop.yaml"))
    check_keys(closed, ("perfect_map", "loop"), source)
    perfect = from_dict(PerfectMapConfig, closed.get("perfect_map"), source, "perfect_map")
    loop = from_dict(LoopSettings, closed.get("loop"), source, "loop")
    slam_params = None
    if map_source != PERFECT:
        from slam_predict import slam
        params_file = path(f"{map_source}.yaml")
        slam_params = (slam.load_params(map_source, params_file) if params_file
                       else slam.params_from_dict(map_source, None))
    return ExploreSettings(load_nav_config(config_dir), explore, sim, perfect, loop, slam_params)


def explore_world(world: World, seed: int, settings: ExploreSettings, map_source: str = "perfect",
                  max_sim_time: float | None = None):
    """Run the closed loop until the explorer stops (or ``max_sim_time`` s); returns
    (summary dict, the finished :class:`ClosedLoop`)."""
    limit = settings.loop.max_sim_time if max_sim_time is None else float(max_sim_time)
    loop = ClosedLoop(world, seed, settings.nav, settings.explore, settings.sim, map_source,
                      settings.perfect, settings.slam_params)
    start = time.perf_counter()
    reason = loop.run(limit)
    wall = time.perf_counter() - start
    return summarize(loop, reason, wall, settings), loop


def summarize(loop: ClosedLoop, reason: str, wall: float, settings: ExploreSettings) -> dict:
    """The explore.json content of a finished loop."""
    world = loop.world
    grid = loop.source.map()
    reach = reachable_free(world, inscribed_radius(settings.nav.global_costmap))
    cov = coverage(world, grid, reach, loop.world_T_map)
    log = loop.log
    cmds = np.array(log.commands) if log.commands else np.zeros((0, 3))
    goals = [{"id": g.id, "target": [round(v, 3) for v in g.target], "status": g.status.name,
              "text": g.text, "t_sent": round(g.t_sent, 2),
              "t_end": None if g.t_end is None else round(g.t_end, 2),
              "plan_length_m": None if g.plan_length is None else round(g.plan_length, 3),
              "recoveries": g.recoveries} for g in loop.navigator.history]
    total = sum(loop.timing.values()) or 1.0
    return {
        "world": world.name,
        "source": world.provenance.get("source"),
        "seed": loop.seed,
        "map_source": loop.map_source_name,
        "coverage": round(cov, 4),
        "reachable_free_m2": round(float(reach.sum()) * world.resolution ** 2, 2),
        "sim_duration_s": round(loop.t, 2),
        "wall_time_s": round(wall, 2),
        "distance_m": round(log.distance_m, 3),
        "rotation_rad": round(log.rotation_rad, 3),
        "stalls": log.stalls,
        "stalled_steps": log.stalled_steps,
        "stalls_per_500m": round(500.0 * log.stalls / log.distance_m, 3) if log.distance_m else 0.0,
        "stop_reason": reason,
        "frontier_free_stop": reason == "no_frontiers",
        "start_pose": [round(float(v), 4) for v in world.start_pose],
        "explorer_goals": loop.explorer.log.counts(),
        "goal_time_limits_s": [g["time_limit"] for g in loop.explorer.log.goals],
        "navigator_goals": goals,
        "commands": command_stats(cmds, settings.nav),
        "timing": {k: round(v, 3) for k, v in sorted(loop.timing.items())},
        "timing_share": {k: round(v / total, 4) for k, v in sorted(loop.timing.items())},
        "config_hashes": {"nav": config_hash(settings.nav),
                          "explore": config_hash(settings.explore),
                          "sim": config_hash(settings.sim),
                          "perfect_map": config_hash(settings.perfect)},
    }


def command_stats(cmds: np.ndarray, nav: MoveBaseConfig) -> dict[str, float]:
    """Largest |v|, |ω| and command-to-command accelerations of the published commands."""
    if len(cmds) < 2:
        return {"count": int(len(cmds))}
    dt = np.diff(cmds[:, 0])
    dt[dt <= 0] = math.nan
    tp = nav.TrajectoryPlannerROS
    return {
        "count": int(len(cmds)),
        "violations": limit_violations(cmds, tp),
        "max_abs_v": float(np.max(np.abs(cmds[:, 1]))),
        "max_abs_w": float(np.max(np.abs(cmds[:, 2]))),
        "max_acc_v": float(np.nanmax(np.abs(np.diff(cmds[:, 1])) / dt)),
        "max_acc_w": float(np.nanmax(np.abs(np.diff(cmds[:, 2])) / dt)),
        "limit_v": tp.max_vel_x, "limit_w": tp.max_vel_theta,
        "limit_acc_v": tp.acc_lim_x, "limit_acc_w": tp.acc_lim_theta,
    }


def limit_violations(cmds: np.ndarray, tp, tol: float = 1e-9) -> int:
    """Commands (rows t s, v m/s, ω rad/s) outside [min(escape_vel, 0), max_vel_x],
    |ω| ≤ max_vel_theta, or changing faster than acc_lim_x / acc_lim_theta since the previous
    one (a non-increasing time stamp counts as a violation too)."""
    v, w = cmds[:, 1], cmds[:, 2]
    bad = (v > tp.max_vel_x + tol) | (v < min(tp.escape_vel, 0.0) - tol)
    bad |= np.abs(w) > tp.max_vel_theta + tol
    dt = np.diff(cmds[:, 0])
    jump = ((dt <= 0) | (np.abs(np.diff(v)) > tp.acc_lim_x * dt + tol)
            | (np.abs(np.diff(w)) > tp.acc_lim_theta * dt + tol))
    bad[1:] |= jump
    return int(bad.sum())


def write_outputs(out_dir: os.PathLike | str, summary: dict, loop: ClosedLoop) -> Path:
    """Write ``explore.json`` and ``explore.png`` (map + true path) into ``out_dir``."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    poses = np.array(loop.log.true_poses) if loop.log.true_poses else np.zeros((0, 3))
    render_png(out / "explore.png", loop.source.map(), poses[:, :2], loop.world_T_map)
    write_text(out / "explore.json", json.dumps(summary, indent=1) + "\n")
    return out
