"""base_local_planner's TrajectoryPlannerROS: plan handling, goal tolerances, rotate-to-goal.

Each cycle (computeVelocityCommands): the global plan (map frame) is transformed into the local
costmap's frame and cut to the points within half the local costmap's size of the robot
(transformGlobalPlan); points are pruned from the front until one is within 1 m of the robot
(prunePlan, also on the stored plan). Within ``xy_goal_tolerance`` of the goal the robot stops
(with the acceleration limits) and then rotates in place to the goal yaw; otherwise the
:class:`~slam_predict.nav.trajectory_planner.TrajectoryPlanner` picks the command. The goal is
reached when position and yaw are within tolerance and the robot has stopped.
"""
from __future__ import annotations

import math

import numpy as np

from slam_predict.geometry import compose, wrap_angle
from slam_predict.nav.config import TrajectoryPlannerConfig
from slam_predict.nav.costmap import Costmap
from slam_predict.nav.trajectory_planner import TrajectoryPlanner

Velocity = tuple[float, float]


class LocalPlanner:
    """TrajectoryPlannerROS over a local costmap; poses in the local costmap's frame."""

    def __init__(self, cfg: TrajectoryPlannerConfig, footprint: np.ndarray, sim_period: float,
                 resolution: float):
        self.cfg = cfg
        self.sim_period = float(sim_period)
        self.tc = TrajectoryPlanner(cfg, footprint, sim_period, resolution)
        self.global_plan = np.empty((0, 3))
        self.rotating_to_goal = False
        self.xy_latch = False
        self.local_plan = np.empty((0, 3))
        self.transformed_plan = np.empty((0, 3))

    def set_plan(self, plan: np.ndarray) -> None:
        """A new global plan (poses (n, 3) in the map frame); clears the tolerance latch."""
        self.global_plan = np.asarray(plan, dtype=float).reshape(-1, 3).copy()
        self.xy_latch = False

    # ---------------------------------------------------------------------------- helpers
    def _transformed(self, costmap: Costmap, pose, map_to_local) -> np.ndarray:
        """transformGlobalPlan + prunePlan; returns the plan segment in the local frame."""
        plan = (compose(map_to_local, self.global_plan) if len(self.global_plan)
                else np.empty((0, 3)))
        threshold = max(costmap.size_x * costmap.resolution,
                        costmap.size_y * costmap.resolution) / 2
        d2 = (plan[:, 0] - pose[0]) ** 2 + (plan[:, 1] - pose[1]) ** 2
        inside = d2 <= threshold ** 2
        if not inside.any():
            segment = plan[:0]
        else:
            first = int(np.argmax(inside))
            rest = inside[first:]
            stop = first + (int(np.argmin(rest)) if not rest.all() else len(rest))
            segment = plan[first:stop]
        if self.cfg.prune_plan and len(segment):
            near = (segment[:, 0] - pose[0]) ** 2 + (segment[:, 1] - pose[1]) ** 2 < 1.0
            cut = int(np.argmax(near)) if near.any() else len(segment)
            segment = segment[cut:]
            self.global_plan = self.global_plan[cut:]
        return segment

    def _stopped(self, vel: Velocity) -> bool:
        return (abs(vel[1]) <= self.cfg.rot_stopped_velocity
                and abs(vel[0]) <= self.cfg.trans_stopped_velocity)

    # ---------------------------------------------------------------------------- control
    def compute_velocity_commands(self, costmap: Costmap, pose, vel: Velocity,
                                  map_to_local) -> Velocity | None:
        """The command (v m/s, ω rad/s), or None when no valid control exists."""
        self.local_plan = np.empty((0, 3))
        plan = self._transformed(costmap, pose, map_to_local)
        self.transformed_plan = plan
        if len(plan) == 0:
            return None
        goal = plan[-1]
        c = self.cfg
        if math.hypot(goal[0] - pose[0], goal[1] - pose[1]) <= c.xy_goal_tolerance or self.xy_latch:
            if c.latch_xy_goal_tolerance:
                self.xy_latch = True
            if abs(wrap_angle(goal[2] - pose[2])) <= c.yaw_goal_tolerance:
                self.rotating_to_goal = False
                self.xy_latch = False
                return (0.0, 0.0)
            self.tc.update_plan(plan)
            self.tc.find_best_path(costmap, pose, vel)
            if not self.rotating_to_goal and not self._stopped(vel):
                return self._stop_with_acc_limits(costmap, pose, vel)
            self.rotating_to_goal = True
            return self._rotate_to_goal(costmap, pose, vel, float(goal[2]))
        self.tc.update_plan(plan)
        best = self.tc.find_best_path(costmap, pose, vel)
        if best.cost < 0:
            return None
        self.local_plan = best.points
        return (best.xv, best.thetav)

    def _stop_with_acc_limits(self, costmap, pose, vel) -> Velocity | None:
        c = self.cfg
        vx = math.copysign(max(0.0, abs(vel[0]) - c.acc_lim_x * self.sim_period), vel[0])
        vth = math.copysign(max(0.0, abs(vel[1]) - c.acc_lim_theta * self.sim_period), vel[1])
        if self.tc.check_trajectory(costmap, pose, vel, vx, vth):
            return (vx, vth)
        return None

    def _rotate_to_goal(self, costmap, pose, vel, goal_th: float) -> Velocity | None:
        c = self.cfg
        diff = wrap_angle(goal_th - pose[2])
        if diff > 0:
            v = min(c.max_vel_theta, max(c.min_in_place_vel_theta, diff))
        else:
            v = max(c.min_vel_theta, min(-c.min_in_place_vel_theta, diff))
        max_acc = abs(vel[1]) + c.acc_lim_theta * self.sim_period
        min_acc = abs(vel[1]) - c.acc_lim_theta * self.sim_period
        v = math.copysign(min(max(abs(v), min_acc), max_acc), v)
        stop_speed = math.sqrt(2.0 * c.acc_lim_theta * abs(diff))
        v = math.copysign(min(stop_speed, abs(v)), v)
        # noetic: min_in_place_vel_theta matters more than the acceleration limits
        if v > 0:
            v = min(c.max_vel_theta, max(c.min_in_place_vel_theta, v))
        else:
            v = max(c.min_vel_theta, min(-c.min_in_place_vel_theta, v))
        if self.tc.check_trajectory(costmap, pose, vel, 0.0, v):
            return (0.0, v)
        return None

    def is_goal_reached(self, pose_map, vel: Velocity) -> bool:
        """Position and yaw within tolerance of the plan's last pose (map frame) and stopped."""
        if len(self.global_plan) == 0:
            return False
        goal = self.global_plan[-1]
        c = self.cfg
        return (math.hypot(goal[0] - pose_map[0], goal[1] - pose_map[1]) <= c.xy_goal_tolerance
                and abs(wrap_angle(goal[2] - pose_map[2])) <= c.yaw_goal_tolerance
                and self._stopped(vel))
