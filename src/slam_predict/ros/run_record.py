"""The ROS path's run record: the same folder and run.json as the in-process episode.

Files (:mod:`slam_predict.collect.record`): ``run.json``, ``ground_truth.tum``, ``slam.tum``,
``odom.tum``, the CARMEN logs, ``map.pgm``/``map.yaml``/``map.png``, ``snapshots/`` and, when the
settings ask for it, ``run.bag``. run.json has every key of the in-process record
(:func:`slam_predict.collect.episode.run_episode`), computed the same way (metric:
:func:`~slam_predict.collect.episode.measure` on the pause-free trajectories), plus one key
``ros`` describing the graph (node choices, ground-truth source, dropped samples).

Differences that follow from the ROS graph (documented in docs/ros.md): ``timing`` holds wall
times of the run's phases (the nodes' internal timings are not observable); ``coverage`` uses
the map frame's pose in the world estimated from the first sample (ground truth ⊕ SLAM⁻¹) and is
``null`` without a world file (real robot); ``odometry_error`` is what the simulator node
reports (``null`` for stageros or a real robot).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Optional

import numpy as np

from slam_predict.collect import record as rec
from slam_predict.collect.episode import code_version, inscribed_radius, measure
from slam_predict.collect.settings import CollectSettings
from slam_predict.config import config_hash
from slam_predict.geometry import compose, inverse
from slam_predict.paths import portable_path
from slam_predict.ros.orchestrator import RunMonitor


@dataclass
class RunInfo:
    """What the batch knows about a run: world name and file (may be empty), index, seed."""

    world: str
    world_file: str = ""
    run_index: int = 0
    seed: int = 0
    odometry_model: str = ""
    odometry_error: Optional[Dict[str, Any]] = None
    ros: Dict[str, Any] = field(default_factory=dict)


def world_T_map(traj: rec.Trajectories) -> np.ndarray:
    """The map frame's pose in the world frame from the first sample: gt₀ ⊕ slam₀⁻¹."""
    if len(traj.t) == 0:
        return np.zeros(3)
    return compose(traj.ground_truth[0], inverse(traj.slam[0]))


def run_coverage(world, grid, settings: CollectSettings, traj: rec.Trajectories) -> Optional[float]:
    """Share of the reachable free area known in the final map (None without world or map)."""
    if world is None or grid is None or len(traj.t) == 0:
        return None
    from slam_predict.explore.coverage import coverage, reachable_free

    reach = reachable_free(world, inscribed_radius(settings.nav.global_costmap))
    return coverage(world, grid, reach, world_T_map(traj))


def build_record(info: RunInfo, settings: CollectSettings, monitor: RunMonitor, world,
                 free_area_m2: Optional[float], wall_time_s: float,
                 timing: Dict[str, float]) -> Dict[str, Any]:
    """run.json content of a finished run (see the module docstring)."""
    traj = monitor.trajectories()
    hashes = settings.hashes()
    hashes["stop"] = config_hash(monitor.stop)  # the stop rule actually applied
    rule = monitor.rule
    ros = {**info.ros, "samples": int(len(traj.t)), "samples_dropped": int(monitor.dropped),
           "first_sample_t": float(traj.t[0]) if len(traj.t) else None}
    return {
        "world": info.world, "world_file": portable_path(info.world_file), "run_index": info.run_index,
        "seed": info.seed, "code_version": code_version(), "config_hashes": hashes,
        "slam": settings.slam.record(),
        "settings_file": portable_path(settings.source),
        "odometry_model": info.odometry_model or settings.sim.odom.model,
        "odometry_error": info.odometry_error,
        "stop_reason": monitor.reason, "explorer_end": monitor.explorer_end,
        "sim_duration_s": monitor.sim_duration_s, "wall_time_s": float(wall_time_s),
        "distance_m": rec.path_length(traj.ground_truth),
        "rotation_rad": rec.path_rotation(traj.ground_truth),
        "coverage": run_coverage(world, monitor.grid, settings, traj),
        "stalls": int(monitor.stalls), "free_area_m2": free_area_m2,
        "snapshots": [{"t": t, "mse": m} for t, m in zip(rule.times, [None] + rule.mses)],
        "metric": measure(traj, settings, info.seed),
        "timing": {k: float(v) for k, v in timing.items()},
        "ros": ros,
    }


def write_record(folder: Path, record: Dict[str, Any], monitor: RunMonitor,
                 settings: CollectSettings) -> None:
    """Trajectories, final map, optional bag, then run.json (last: it marks completion)."""
    folder = Path(folder)
    traj = monitor.trajectories()
    rec.write_trajectories(folder, traj)
    grid = monitor.grid
    if grid is not None:
        rec.write_map(folder, grid.data, grid.resolution, grid.origin)
    if settings.bag:
        rec.write_bag(folder, traj)
    rec.write_run_json(folder, record)


def record_layout(folder: Path) -> Dict[str, Any]:
    """The format of a run record, to compare two (ROS path vs in-process): its files (snapshot
    numbers masked), run.json's keys and the keys of its nested sections."""
    import json
    import re

    folder = Path(folder)
    files = {re.sub(r"snapshot_\d+", "snapshot_NN", str(p.relative_to(folder)))
             for p in folder.rglob("*") if p.is_file()}
    record = json.loads((folder / "run.json").read_text())
    nested = {key: sorted(value) for key, value in record.items() if isinstance(value, dict)}
    return {"files": sorted(files), "keys": sorted(record), "nested": nested}
