"""move_base recovery behaviours: ClearCostmapRecovery (instant), RotateRecovery (a 360°
in-place turn lasting several control cycles) and, an extension, BackUpRecovery (a straight
reverse, after Nav2's BackUp behaviour)."""
from __future__ import annotations

import math

import numpy as np

from slam_predict.geometry import wrap_angle
from slam_predict.nav.config import RecoveryBehaviorConfig, TrajectoryPlannerConfig
from slam_predict.nav.costmap import Costmap
from slam_predict.nav.rollout import footprint_cost

CLEAR = "clear_costmap_recovery/ClearCostmapRecovery"
ROTATE = "rotate_recovery/RotateRecovery"
BACK_UP = "slam_predict/BackUpRecovery"


def clear_costmaps(behavior: RecoveryBehaviorConfig, global_costmap, local_costmap,
                   pose_map, pose_local) -> None:
    """ClearCostmapRecovery::runBehavior on the layers named ``layer_names`` ("obstacles" is
    the obstacle layer; our static layers are never cleared)."""
    if "obstacles" not in behavior.layer_names:
        return
    if behavior.affected_maps in ("global", "both"):
        global_costmap.clear_outside(pose_map, behavior.reset_distance,
                                     behavior.invert_area_to_clear)
    if behavior.affected_maps in ("local", "both"):
        local_costmap.clear_outside(pose_local, behavior.reset_distance,
                                    behavior.invert_area_to_clear)


class RotateRecovery:
    """A full counter-clockwise turn in place (rotate_recovery): first past 180°, then back
    to the start yaw within ``yaw_goal_tolerance``; stops early if the footprint would hit an
    obstacle in the local costmap. Speed sqrt(2·acc_lim_theta·angle_left), clamped to
    [min_in_place_vel_theta, max_vel_theta]."""

    sim_granularity = 0.017

    def __init__(self, cfg: TrajectoryPlannerConfig, footprint):
        self.cfg = cfg
        self.footprint = footprint
        self.start_yaw: float | None = None
        self.got_180 = False

    def start(self, yaw: float) -> None:
        """Begin a turn from ``yaw`` (rad)."""
        self.start_yaw = float(yaw)
        self.got_180 = False

    def step(self, costmap: Costmap, pose) -> tuple[bool, float]:
        """(finished, ω command rad/s) for the robot at ``pose`` in the costmap's frame."""
        if self.start_yaw is None:
            return True, 0.0
        yaw = float(pose[2])
        tol = self.cfg.yaw_goal_tolerance
        if self.got_180 and abs(wrap_angle(yaw - self.start_yaw)) <= tol:
            self.start_yaw = None
            return True, 0.0
        if not self.got_180:
            to_180 = abs(float(wrap_angle(self.start_yaw + math.pi - yaw)))
            left = math.pi + to_180
            if to_180 < tol:
                self.got_180 = True
        else:
            left = abs(float(wrap_angle(self.start_yaw - yaw)))
        sim = 0.0
        while sim < left:
            if footprint_cost(costmap.costs, costmap.origin[0], costmap.origin[1],
                              costmap.resolution, float(pose[0]), float(pose[1]), yaw + sim,
                              self.footprint) < 0:
                self.start_yaw = None
                return True, 0.0
            sim += self.sim_granularity
        vel = math.sqrt(2.0 * self.cfg.acc_lim_theta * left)
        vel = min(max(vel, self.cfg.min_in_place_vel_theta), self.cfg.max_vel_theta)
        return False, vel


class BackUpRecovery:
    """Drive straight back at ``backup_speed`` (m/s) until the odometry has moved
    ``backup_dist`` (m) from where it started or ``time_allowance`` (s) has passed.

    With ``simulate_ahead_time`` 0 it is blind, like base_local_planner's escape (the seed
    study's robot has no laser behind it): a wall behind stalls the robot until the time is up,
    while Stage's odometry goes on. With ``simulate_ahead_time`` > 0 it checks its path first,
    as Nav2's BackUp does: every cycle the footprint at the poses of the next
    ``simulate_ahead_time`` s (at :attr:`cycle_frequency`, no farther than the distance left)
    is tested in the local costmap, and the behaviour ends at once when one touches a LETHAL or
    unknown cell. Unlike Nav2 only the footprint's edges that face backwards are tested, less
    :attr:`edge_margin_cells` costmap cells at each end, and not at the current pose: a robot
    whose front or side touches a wall in the costmap may still back away from it or along
    it."""

    cycle_frequency = 10.0   # Hz: Nav2's behaviour server default, the simulated steps
    edge_margin_cells = 2    # cells left out at each end of a rear edge: a wall beside the
    #                          robot that its side touches in the costmap is not behind it

    def __init__(self, footprint=None):
        self.rear_edges = [] if footprint is None else rear_edges(footprint)
        self.start_xy: tuple[float, float] | None = None
        self.start_t = 0.0
        self.behavior = None

    def start(self, behavior, pose, t: float) -> None:
        """Begin backing up from odometry ``pose`` at sim time ``t`` (s)."""
        self.behavior = behavior
        self.start_xy = (float(pose[0]), float(pose[1]))
        self.start_t = float(t)

    def step(self, pose, t: float, costmap: Costmap | None = None) -> tuple[bool, float]:
        """(finished, v command m/s) at odometry ``pose`` and sim time ``t``; ``costmap``: the
        local costmap (odometry frame) for the check of ``simulate_ahead_time``."""
        if self.start_xy is None:
            return True, 0.0
        moved = math.hypot(float(pose[0]) - self.start_xy[0], float(pose[1]) - self.start_xy[1])
        behavior = self.behavior
        if (moved >= behavior.backup_dist or t - self.start_t >= behavior.time_allowance
                or not self._path_free(pose, behavior.backup_dist - moved, costmap)):
            self.start_xy = None
            return True, 0.0
        return False, -behavior.backup_speed

    def _path_free(self, pose, left: float, costmap: Costmap | None) -> bool:
        """Nav2 BackUp's isCollisionFree on the rear edges (class doc): clear of LETHAL and
        unknown cells at each simulated pose behind ``pose`` (m left to drive ``left``)."""
        horizon = self.behavior.simulate_ahead_time
        if horizon <= 0 or costmap is None or not self.rear_edges:
            return True
        x, y, yaw = (float(v) for v in pose[:3])
        margin = self.edge_margin_cells * costmap.resolution
        edges = [shortened(edge, margin) for edge in self.rear_edges]
        for k in range(1, int(self.cycle_frequency * horizon)):
            back = self.behavior.backup_speed * k / self.cycle_frequency
            if left - back <= 0:
                break
            bx, by = x - back * math.cos(yaw), y - back * math.sin(yaw)
            if any(footprint_cost(costmap.costs, costmap.origin[0], costmap.origin[1],
                                  costmap.resolution, bx, by, yaw, edge) < 0
                   for edge in edges):
                return False
        return True


def shortened(edge: np.ndarray, margin: float) -> np.ndarray:
    """The segment ``edge`` (2, 2) less ``margin`` (m) at each end (its midpoint when it is
    shorter than twice that)."""
    a, b = edge
    length = float(np.hypot(*(b - a)))
    if length <= 2 * margin:
        middle = (a + b) / 2
        return np.ascontiguousarray(np.stack([middle, middle]))
    step = (b - a) / length * margin
    return np.ascontiguousarray(np.stack([a + step, b - step]))


def rear_edges(footprint) -> list[np.ndarray]:
    """The edges (2, 2) of the footprint polygon (k, 2; robot frame, x forward) whose outward
    normal points backwards: what a straight reverse drives into."""
    points = np.asarray(footprint, dtype=float)
    area2 = float(np.sum(points[:, 0] * np.roll(points[:, 1], -1)
                         - np.roll(points[:, 0], -1) * points[:, 1]))
    edges = []
    for a, b in zip(points, np.roll(points, -1, axis=0), strict=True):
        normal_x = (b[1] - a[1]) if area2 > 0 else (a[1] - b[1])   # outward normal's x
        if normal_x < -1e-12:
            edges.append(np.ascontiguousarray(np.stack([a, b])))
    return edges
