"""move_base recovery behaviours: ClearCostmapRecovery (instant), RotateRecovery (a 360°
in-place turn lasting several control cycles) and, an extension, BackUpRecovery (a straight
reverse, after Nav2's BackUp behaviour)."""
from __future__ import annotations

import math

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
    ``backup_dist`` (m) from where it started or ``time_allowance`` (s) has passed. Like
    base_local_planner's escape it is blind (the seed study's robot has no laser behind it;
    Nav2's BackUp checks its costmap instead): a wall behind stalls the robot until the time
    is up."""

    def __init__(self):
        self.start_xy: tuple[float, float] | None = None
        self.start_t = 0.0
        self.behavior = None

    def start(self, behavior, pose, t: float) -> None:
        """Begin backing up from odometry ``pose`` at sim time ``t`` (s)."""
        self.behavior = behavior
        self.start_xy = (float(pose[0]), float(pose[1]))
        self.start_t = float(t)

    def step(self, pose, t: float) -> tuple[bool, float]:
        """(finished, v command m/s) at odometry ``pose`` and sim time ``t``."""
        if self.start_xy is None:
            return True, 0.0
        moved = math.hypot(float(pose[0]) - self.start_xy[0], float(pose[1]) - self.start_xy[1])
        if moved >= self.behavior.backup_dist or t - self.start_t >= self.behavior.time_allowance:
            self.start_xy = None
            return True, 0.0
        return False, -self.behavior.backup_speed
