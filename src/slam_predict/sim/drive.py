"""Scripted runs: drive the simulated robot through waypoints and record what it logs.

The follower is turn-then-go on the TRUE pose (a scripted test drive, not navigation): when the
heading error to the next waypoint exceeds ``turn_threshold`` it turns in place, otherwise it
drives forward with a proportional heading correction, slowing down so that it can stop at the
waypoint under the acceleration limit (v ≤ √(2·a·d)). A waypoint is reached within
``tolerance`` m. A robot stalled for ``stall_timeout`` s, or a run longer than ``max_time`` s,
ends the drive with an error (the path is not drivable).

Waypoint files (YAML): ``waypoints: [[x, y], ...]`` (or a bare list), world frame, metres.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from slam_predict.errors import InputError, require_file
from slam_predict.geometry import wrap_angle
from slam_predict.sim.simulator import SimState, Simulator
from slam_predict.world.model import World


@dataclass
class FollowerConfig:
    """Waypoint follower gains and limits (m, rad, s); speeds are capped by the robot's."""

    tolerance: float = 0.1
    turn_threshold: float = 0.35
    heading_gain: float = 2.0
    max_speed: float = 0.8
    max_turn_rate: float = 1.2
    min_turn_rate: float = 0.15
    stall_timeout: float = 3.0
    max_time: float | None = None  # s; None = 60 s + 4 s per metre of path


@dataclass
class DriveLog:
    """Everything a scripted run records (arrays over steps, lists over scans)."""

    t: list[float] = field(default_factory=list)
    true_poses: list[np.ndarray] = field(default_factory=list)
    odom_poses: list[np.ndarray] = field(default_factory=list)
    velocities: list[tuple] = field(default_factory=list)
    scans: list[SimState] = field(default_factory=list)
    stalled_steps: int = 0

    def record(self, state: SimState) -> None:
        self.t.append(state.t)
        self.true_poses.append(state.true_pose)
        self.odom_poses.append(state.odom_pose)
        self.velocities.append(state.velocity)
        self.stalled_steps += int(state.stalled)
        if state.scan is not None:
            self.scans.append(state)

    def path_length(self) -> float:
        """Distance travelled (true poses), m."""
        xy = np.asarray(self.true_poses)[:, :2]
        return float(np.hypot(*np.diff(xy, axis=0).T).sum()) if len(xy) > 1 else 0.0

    def rotation(self) -> float:
        """Sum of absolute heading changes (true poses), rad."""
        yaw = np.asarray(self.true_poses)[:, 2]
        return float(np.abs(wrap_angle(np.diff(yaw))).sum()) if len(yaw) > 1 else 0.0


def _load_yaml_any(path: str):
    """Parsed YAML (any top-level type); InputError for a missing or malformed file."""
    import yaml

    require_file(path, "waypoint file")
    try:
        with open(path, encoding="utf-8") as handle:
            return yaml.safe_load(handle)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        raise InputError(f"YAML syntax error: {getattr(exc, 'problem', exc)}", path,
                         mark.line + 1 if mark is not None else None) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read waypoint file: {exc.__class__.__name__}", path) from None


def read_waypoints(path: str, world: World) -> np.ndarray:
    """(N, 2) waypoints from a YAML file; InputError for a bad file or an unreachable point."""
    data = _load_yaml_any(path)
    points = data.get("waypoints") if isinstance(data, dict) else data
    if not isinstance(points, list) or not points:
        raise InputError("expected a non-empty list 'waypoints: [[x, y], ...]'", path)
    out = []
    for i, point in enumerate(points, 1):
        if (not isinstance(point, (list, tuple)) or len(point) != 2
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                           for v in point)):
            raise InputError(f"waypoint {i} must be [x, y] in metres, got {point!r}", path)
        out.append([float(point[0]), float(point[1])])
    waypoints = np.array(out)
    inside = world.in_bounds(world.world_to_cell(waypoints))
    free = world.is_free_at(waypoints)
    for i in range(len(waypoints)):
        if not inside[i] or not free[i]:
            where = "outside the map" if not inside[i] else "inside a wall"
            raise InputError(f"waypoint {i + 1} ({waypoints[i, 0]:.2f}, {waypoints[i, 1]:.2f}) "
                             f"is {where}", path)
    return waypoints


class WaypointFollower:
    """Turn-then-go controller (see the module docstring)."""

    def __init__(self, waypoints: np.ndarray, config: FollowerConfig, sim: Simulator):
        self.waypoints = np.asarray(waypoints, dtype=float)
        self.config = config
        self.index = 0
        self.v_max = min(config.max_speed, sim.robot.max_vel_x)
        self.w_max = min(config.max_turn_rate, sim.robot.max_vel_theta)
        self.decel = sim.robot.max_acc_x if sim.robot.max_acc_x > 0 else math.inf

    @property
    def done(self) -> bool:
        return self.index >= len(self.waypoints)

    def command(self, pose: np.ndarray) -> tuple:
        """(v m/s, ω rad/s) towards the current waypoint; advances past reached ones."""
        cfg = self.config
        while not self.done:
            dx, dy = self.waypoints[self.index] - pose[:2]
            dist = math.hypot(dx, dy)
            if dist > cfg.tolerance:
                break
            self.index += 1
        if self.done:
            return 0.0, 0.0
        error = float(wrap_angle(math.atan2(dy, dx) - pose[2]))
        w = max(-self.w_max, min(self.w_max, cfg.heading_gain * error))
        if abs(error) > cfg.turn_threshold:
            return 0.0, math.copysign(max(abs(w), cfg.min_turn_rate), error)
        v = min(self.v_max, math.sqrt(2.0 * self.decel * dist) if math.isfinite(self.decel)
                else self.v_max)
        return v * math.cos(error), w


def default_max_time(start: Sequence[float], waypoints: np.ndarray) -> float:
    """60 s plus 4 s per metre of the straight-line path through the waypoints."""
    points = np.vstack([np.asarray(start, float)[:2], waypoints])
    return 60.0 + 4.0 * float(np.hypot(*np.diff(points, axis=0).T).sum())


def drive(sim: Simulator, waypoints: np.ndarray, config: FollowerConfig,
          source: str | None = None) -> DriveLog:
    """Run the follower until the last waypoint is reached; returns the recorded log.

    Raises InputError (naming ``source``, the waypoint file) when the robot stays stalled for
    ``stall_timeout`` s or the run exceeds ``max_time``.
    """
    follower = WaypointFollower(waypoints, config, sim)
    max_time = config.max_time or default_max_time(sim.true_pose, follower.waypoints)
    log = DriveLog()
    stalled_since: float | None = None
    while True:
        v, w = follower.command(sim.true_pose)
        if follower.done and sim.velocity == (0.0, 0.0):
            return log
        state = sim.step(v, w)
        log.record(state)
        if state.stalled:
            stalled_since = state.t if stalled_since is None else stalled_since
            if state.t - stalled_since >= config.stall_timeout:
                x, y = state.true_pose[:2]
                raise InputError(f"path blocked: the robot is stuck at ({x:.2f}, {y:.2f}) on the "
                                 f"way to waypoint {follower.index + 1}", source)
        else:
            stalled_since = None
        if state.t > max_time:
            raise InputError(f"waypoint {follower.index + 1} not reached within {max_time:.0f} s "
                             "of sim time", source)


def carmen_log(log: DriveLog, sim: Simulator, message: str = "ROBOTLASER1"):
    """The run as a :class:`~slam_predict.formats.carmen.CarmenLog`.

    ODOM lines: the odometry pose every step. Scan lines: ``pose`` (ROBOTLASER1 laser_x/y/θ,
    FLASER x/y/θ) is the TRUE laser pose in the world frame (the reference), ``odom_pose``
    (robot_x/y/θ, FLASER odom_*) the robot's odometry pose when the scan was taken.
    """
    from slam_predict.formats.carmen import CarmenLog, LaserScan, Odometry
    from slam_predict.geometry import compose

    laser = sim.laser
    velocities = np.asarray(log.velocities, dtype=float).reshape(-1, 2)
    odometry = Odometry(np.asarray(log.t), np.asarray(log.odom_poses), velocities[:, 0],
                        velocities[:, 1])
    start = -laser.fov / 2.0
    step = laser.fov / (laser.samples - 1) if laser.samples > 1 else 0.0
    if message == "FLASER":
        start, step = -math.pi / 2, math.pi / (laser.samples - 1)
    scans = [LaserScan(timestamp=s.t, ranges=s.scan, start_angle=start, angular_resolution=step,
                       max_range=laser.range_max, pose=compose(s.scan_true_pose, sim.laser_pose),
                       odom_pose=s.scan_odom_pose, kind=message, fov=laser.fov,
                       tv=s.velocity[0], rv=s.velocity[1])
             for s in log.scans]
    params = {"robot_front_laser_max": f"{laser.range_max:g}",
              "robot_frontlaser_offset": f"{sim.laser_pose[0]:g}",
              "laser_front_laser_fov": f"{math.degrees(laser.fov):g}",
              "laser_front_laser_resolution": f"{math.degrees(step):g}"}
    return CarmenLog(params=params, odometry=odometry, scans=scans)


def write_run(out_dir: str, log: DriveLog, sim: Simulator, metadata: dict,
              message: str = "ROBOTLASER1") -> None:
    """Write ``run.log`` (CARMEN), ``ground_truth.tum``, ``odometry.tum`` and ``run.json``
    into ``out_dir`` atomically (the folder appears complete or not at all)."""
    import json

    from slam_predict.atomic import atomic_dir
    from slam_predict.formats.carmen import write_log
    from slam_predict.formats.tum import write_tum

    t = np.asarray(log.t)
    header = [f"slam_predict sim drive: world {metadata.get('world', '?')}, "
              f"seed {metadata.get('seed')}, odometry {sim.odom_error['model']}",
              "scan poses: laser_x/y/theta = true laser pose (world frame), "
              "robot_x/y/theta = odometry pose"]
    with atomic_dir(out_dir) as tmp:
        write_log(tmp / "run.log", carmen_log(log, sim, message), header=header)
        write_tum(tmp / "ground_truth.tum", t, np.asarray(log.true_poses),
                  header=["true robot pose, world frame"])
        write_tum(tmp / "odometry.tum", t, np.asarray(log.odom_poses),
                  header=["odometry pose, odometry frame (origin = start pose)"])
        (tmp / "run.json").write_text(json.dumps(metadata, indent=2, sort_keys=True) + "\n",
                                      encoding="utf-8")
