"""The ROS path's run record: the same folder and run.json as the in-process episode.

Files (:mod:`slam_predict.collect.record`): ``run.json``, ``ground_truth.tum``, ``slam.tum``,
``odom.tum``, the CARMEN logs, ``map.pgm``/``map.yaml``/``map.png``, ``snapshots/`` and, when the
settings ask for it, ``run.bag``. run.json is built by the in-process episode's builder
(:func:`slam_predict.collect.record.build_record`: the same keys, computed the same way), plus
one key ``ros`` describing the graph (node choices, ground-truth source, dropped samples).

Differences that follow from the ROS graph (documented in docs/ros.md): ``timing`` holds wall
times of the run's phases (the nodes' internal timings are not observable); ``coverage`` uses
the map frame's pose in the world estimated from the first sample (ground truth ⊕ SLAM⁻¹) and is
``null`` without a world file (real robot), ``coverage_swept`` is left out then;
``odometry_error`` is what the simulator node reports (``null`` for stageros or a real robot);
``sensor`` is the laser and odometry model of the world file with the robot file's overrides
(``null`` without a world file).
"""
from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from slam_predict.collect import record as rec
from slam_predict.collect.record import RunInfo
from slam_predict.collect.settings import CollectSettings
from slam_predict.config import config_hash, to_dict
from slam_predict.geometry import world_T_map
from slam_predict.ros.orchestrator import RunMonitor
from slam_predict.sim.simulator import resolve_sensor


def run_coverage(world, grid, reach, traj: rec.Trajectories) -> float | None:
    """Share of the reachable free area ``reach`` known in the final map (None without world
    or map)."""
    if world is None or grid is None or len(traj.t) == 0:
        return None
    from slam_predict.explore.coverage import coverage

    return coverage(world, grid, reach, world_T_map(traj.ground_truth[0], traj.slam[0]))


def run_swept(world, reach, settings: CollectSettings, traj: rec.Trajectories,
              sensor) -> float | None:
    """Share of the reachable free area ``reach`` the laser swept from the true trajectory
    (None without a world or trajectory)."""
    if world is None or sensor is None or len(traj.t) == 0:
        return None
    from slam_predict.collect.episode import swept

    return swept(world, reach, traj.ground_truth, sensor.laser, settings)


def reachable(world, settings: CollectSettings):
    """The world's reachable free area (None without a world)."""
    if world is None:
        return None
    from slam_predict.explore.coverage import reachable_free
    from slam_predict.nav.costmap import inscribed_radius

    return reachable_free(world, inscribed_radius(settings.nav.global_costmap))


def build_record(info: RunInfo, settings: CollectSettings, monitor: RunMonitor, world,
                 free_area_m2: float | None, wall_time_s: float,
                 timing: dict[str, float]) -> dict[str, Any]:
    """run.json content of a finished run (see the module docstring)."""
    traj = monitor.trajectories()
    hashes = settings.hashes()
    hashes["stop"] = config_hash(monitor.stop)  # the stop rule actually applied
    ros = {**info.ros, "samples": int(len(traj.t)), "samples_dropped": int(monitor.dropped),
           "first_sample_t": float(traj.t[0]) if len(traj.t) else None}
    resolved = None if world is None else resolve_sensor(world, settings.sim)
    reach = reachable(world, settings)
    end = rec.RunEnd(monitor.reason, monitor.explorer_end, monitor.sim_duration_s, wall_time_s,
                     monitor.stalls, run_coverage(world, monitor.grid, reach, traj),
                     monitor.stuck.record(monitor.stop),
                     run_swept(world, reach, settings, traj, resolved))
    sensor = None if resolved is None else to_dict(resolved)
    record = rec.build_record(dataclasses.replace(info, sensor=sensor), settings, hashes, end,
                              traj, monitor.rule, free_area_m2, timing)
    record["ros"] = ros
    return record


def write_record(folder: Path, record: dict[str, Any], monitor: RunMonitor,
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


def record_layout(folder: Path) -> dict[str, Any]:
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
