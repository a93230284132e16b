"""move_base's state machine over the costmaps, the global planner and the local planner.

States PLANNING / CONTROLLING / CLEARING as MoveBase::executeCycle (ros_interfaces.md §3.2):

* PLANNING: plan (once per control cycle; with ``planner_frequency`` 0 and a finite
  ``max_planning_retries`` the immediate retries of move_base's planner thread are folded
  into one attempt, as the costmap cannot change between them). A plan → CONTROLLING; failure
  beyond ``planner_patience`` or ``max_planning_retries`` → CLEARING (trigger PLANNING).
* CONTROLLING: goal reached → SUCCEEDED "Goal reached."; a valid command is published; no
  valid command within ``controller_patience`` → CLEARING (trigger CONTROLLING), otherwise
  zero velocity and re-plan. With ``planner_frequency`` > 0 the plan is refreshed periodically.
* CLEARING: run the next recovery behaviour then PLANNING; none left → ABORTED with move_base's
  text for the trigger.

A new goal preempts the current one (PREEMPTED, actionlib's text), :meth:`cancel_goal` too.
Time is the caller's (sim time): nothing here sleeps. Frames: the global costmap and plans in
``map``, the local costmap and controller in ``odom``; ``map_T_odom`` links them.
"""
from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from enum import Enum, IntEnum

import numpy as np

from slam_predict.geometry import compose, inverse
from slam_predict.nav import recovery
from slam_predict.nav.config import MoveBaseConfig
from slam_predict.nav.layered import LayeredCostmap
from slam_predict.nav.local_planner import LocalPlanner
from slam_predict.nav.planner import GlobalPlanner, Plan

LOG = logging.getLogger(__name__)


class GoalStatus(IntEnum):
    """actionlib_msgs/GoalStatus values."""

    PENDING = 0
    ACTIVE = 1
    PREEMPTED = 2
    SUCCEEDED = 3
    ABORTED = 4
    REJECTED = 5
    PREEMPTING = 6
    RECALLING = 7
    RECALLED = 8
    LOST = 9


TEXT_REACHED = "Goal reached."
TEXT_NO_PLAN = "Failed to find a valid plan. Even after executing recovery behaviors."
TEXT_NO_CONTROL = "Failed to find a valid control. Even after executing recovery behaviors."
TEXT_OSCILLATING = "Robot is oscillating. Even after executing recovery behaviors."
TEXT_NEW_GOAL = ("This goal was canceled because another goal was received by the simple "
                 "action server")
TEXT_INVALID_QUATERNION = "Aborting on goal because it was sent with an invalid quaternion"


class State(Enum):
    """MoveBaseState."""

    PLANNING = "PLANNING"
    CONTROLLING = "CONTROLLING"
    CLEARING = "CLEARING"


class Trigger(Enum):
    """RecoveryTrigger."""

    PLANNING = TEXT_NO_PLAN
    CONTROLLING = TEXT_NO_CONTROL
    OSCILLATION = TEXT_OSCILLATING


@dataclass
class GoalRecord:
    """One goal's life: target (x, y, yaw) in map, times (s), outcome, planning figures."""

    id: int
    target: tuple[float, float, float]
    t_sent: float
    status: GoalStatus = GoalStatus.ACTIVE
    text: str = ""
    t_end: float | None = None
    plan_length: float | None = None
    plans: int = 0
    recoveries: list[str] = field(default_factory=list)

    @property
    def done(self) -> bool:
        """True once the goal reached a terminal status."""
        return self.status not in (GoalStatus.PENDING, GoalStatus.ACTIVE)


class Navigator:
    """move_base in-process: feed it maps, scans and poses, step it at the controller rate."""

    def __init__(self, cfg: MoveBaseConfig):
        self.cfg = cfg
        self.global_costmap = LayeredCostmap(cfg.global_costmap, "global_costmap")
        self.local_costmap = LayeredCostmap(cfg.local_costmap, "local_costmap")
        self.planner = GlobalPlanner(cfg)
        tp = cfg.TrajectoryPlannerROS
        footprint = self.local_costmap.footprint
        self.controller = LocalPlanner(tp, footprint, cfg.sim_period, cfg.local_costmap.resolution)
        self.rotator = recovery.RotateRecovery(tp, footprint)
        self.backer = recovery.BackUpRecovery(footprint)
        self.goal: GoalRecord | None = None
        self.history: list[GoalRecord] = []
        self.plan: Plan | None = None
        self.last_cmd: tuple[float, float] = (0.0, 0.0)
        self._last_cmd_t: float | None = None
        self._next_id = 1
        self.oscillation_pose = None
        self._reset_state()

    # ------------------------------------------------------------------------------ inputs
    def set_map(self, grid) -> None:
        """A new SLAM map (OccupancyGrid-like: data, origin, resolution) for the static layers."""
        self.global_costmap.set_map(grid)
        self.local_costmap.set_map(grid)

    def add_scan(self, ranges: np.ndarray, angles: np.ndarray, range_min: float, range_max: float,
                 odom_pose, laser_pose, map_T_odom) -> None:
        """A laser scan taken at ``odom_pose`` (odom frame); ``laser_pose`` on the robot."""
        ranges = np.asarray(ranges, dtype=float)
        valid = np.isfinite(ranges) & (ranges < range_max) & (ranges >= range_min)
        sensor = compose(odom_pose, laser_pose)
        a = sensor[2] + np.asarray(angles, dtype=float)[valid]
        r = ranges[valid]
        points = np.stack([sensor[0] + r * np.cos(a), sensor[1] + r * np.sin(a)], axis=1)
        self.local_costmap.add_scan(sensor, points)
        if self.global_costmap.has_obstacles:
            sensor_map = compose(map_T_odom, sensor)
            c, s = math.cos(map_T_odom[2]), math.sin(map_T_odom[2])
            pts = np.stack([map_T_odom[0] + c * points[:, 0] - s * points[:, 1],
                            map_T_odom[1] + s * points[:, 0] + c * points[:, 1]], axis=1)
            self.global_costmap.add_scan(sensor_map, pts)

    # ------------------------------------------------------------------------------- goals
    def send_goal(self, target: Sequence[float], t: float) -> GoalRecord:
        """Start a goal (x, y, yaw in map); an active goal is PREEMPTED."""
        if self.goal is not None:
            self._finish(GoalStatus.PREEMPTED, TEXT_NEW_GOAL, t)
        record = GoalRecord(self._next_id,
                            (float(target[0]), float(target[1]), float(target[2])), t)
        self._next_id += 1
        self.goal = record
        self.history.append(record)
        across = self.cfg.oscillation_across_goals and self.oscillation_pose is not None
        self._reset_state()
        self.run_planner = True
        self.last_valid_plan = self.last_valid_control = t
        if not across:
            self.last_oscillation_reset = t
        self.planning_retries = 0
        return record

    def cancel_goal(self, t: float) -> None:
        """Cancel the active goal (PREEMPTED, empty text)."""
        if self.goal is not None:
            self._finish(GoalStatus.PREEMPTED, "", t)

    def _finish(self, status: GoalStatus, text: str, t: float) -> None:
        goal = self.goal
        if goal is None:
            return
        goal.status, goal.text, goal.t_end = status, text, t
        LOG.debug("goal %d %s at %.1f s: %s", goal.id, status.name, t, text)
        self.goal = None
        self._reset_state()

    def _reset_state(self) -> None:
        """MoveBase::resetState."""
        self.state = State.PLANNING
        self.recovery_index = 0
        self.recovery_trigger = Trigger.PLANNING
        self.run_planner = False
        self.new_plan: Plan | None = None
        self.rotating = False
        self.backing_up = False
        self.planning_retries = 0
        self._next_plan_t = -math.inf
        if not self.cfg.oscillation_across_goals:
            self.oscillation_pose = None

    # ------------------------------------------------------------------------------- cycle
    def step(self, t: float, odom_pose, map_T_odom, velocity) -> tuple[float, float]:
        """One controller cycle at sim time ``t``; returns the published (v, ω)."""
        odom_pose = np.asarray(odom_pose, dtype=float)
        map_T_odom = np.asarray(map_T_odom, dtype=float)
        pose_map = compose(map_T_odom, odom_pose)
        vel = (float(velocity[0]), float(velocity[1]))
        self.global_costmap.maybe_update(t, pose_map)
        self.local_costmap.maybe_update(t, odom_pose)
        if self.goal is None:
            return self._publish(t, (0.0, 0.0))
        if self.rotating:
            return self._publish(t, self._rotate_cycle(t, odom_pose))
        if self.backing_up:
            return self._publish(t, self._back_up_cycle(t, odom_pose))
        self._run_planner(t, pose_map)
        cmd = self._execute_cycle(t, odom_pose, pose_map, map_T_odom, vel)
        return self._publish(t, cmd)

    def _run_planner(self, t: float, pose_map) -> None:
        """The planner thread's work for this cycle."""
        freq = self.cfg.planner_frequency
        due = self.state == State.PLANNING or (freq > 0 and t + 1e-9 >= self._next_plan_t)
        if not (self.run_planner and due):
            return
        goal = self.goal
        plan = self.planner.make_plan(self.global_costmap.costmap, pose_map, goal.target)
        if freq > 0:
            self._next_plan_t = t + 1.0 / freq
        if plan is not None and len(plan):
            self.last_valid_plan = t
            self.planning_retries = 0
            self.new_plan = plan
            goal.plans += 1
            if goal.plan_length is None:
                goal.plan_length = plan.length
            self.state = State.CONTROLLING
            if freq <= 0:
                self.run_planner = False
            return
        if self.state != State.PLANNING:
            return
        retries = self.cfg.max_planning_retries
        self.planning_retries += 1
        if freq <= 0 and retries >= 0:
            self.planning_retries = max(self.planning_retries, retries + 1)
        if t > self.last_valid_plan + self.cfg.planner_patience or (
                retries >= 0 and self.planning_retries > retries):
            self.state = State.CLEARING
            self.run_planner = False
            self.recovery_trigger = Trigger.PLANNING

    def _execute_cycle(self, t, odom_pose, pose_map, map_T_odom, vel) -> tuple[float, float]:
        cfg = self.cfg
        if self.oscillation_pose is None or math.hypot(
                pose_map[0] - self.oscillation_pose[0],
                pose_map[1] - self.oscillation_pose[1]) >= cfg.oscillation_distance:
            self.last_oscillation_reset = t
            self.oscillation_pose = pose_map.copy()
            if self.recovery_trigger == Trigger.OSCILLATION:
                self.recovery_index = 0
        if (cfg.oscillation_across_goals and self.state == State.PLANNING
                and self._oscillating(t)):
            self.run_planner = False
            self._start_oscillation_recovery()
        if self.new_plan is not None:
            self.plan, self.new_plan = self.new_plan, None
            self.controller.set_plan(self.plan.poses)
            if self.recovery_trigger == Trigger.PLANNING:
                self.recovery_index = 0
        if self.state == State.PLANNING:
            self.run_planner = True
            return (0.0, 0.0)
        if self.state == State.CONTROLLING:
            return self._control(t, odom_pose, pose_map, map_T_odom, vel)
        return self._clear(t, odom_pose, pose_map)

    def _control(self, t, odom_pose, pose_map, map_T_odom, vel) -> tuple[float, float]:
        cfg = self.cfg
        if self.controller.is_goal_reached(pose_map, vel):
            self._finish(GoalStatus.SUCCEEDED, TEXT_REACHED, t)
            return (0.0, 0.0)
        if self._oscillating(t):
            self._start_oscillation_recovery()
            if cfg.oscillation_across_goals:   # no CONTROLLING trigger to take its place
                return (0.0, 0.0)
        cmd = self.controller.compute_velocity_commands(
            self.local_costmap.costmap, odom_pose, vel, inverse(map_T_odom))
        if cmd is not None:
            self.last_valid_control = t
            if self.recovery_trigger == Trigger.CONTROLLING:
                self.recovery_index = 0
            return cmd
        if t > self.last_valid_control + cfg.controller_patience:
            self.state = State.CLEARING
            self.recovery_trigger = Trigger.CONTROLLING
        else:
            self.last_valid_plan = t
            self.planning_retries = 0
            self.state = State.PLANNING
            self.run_planner = True
        return (0.0, 0.0)

    def _oscillating(self, t: float) -> bool:
        """move_base's oscillation condition: no move of oscillation_distance for
        oscillation_timeout s (0: off)."""
        timeout = self.cfg.oscillation_timeout
        return timeout > 0 and self.last_oscillation_reset + timeout < t

    def _start_oscillation_recovery(self) -> None:
        """CLEARING for the oscillation trigger; with oscillation_across_goals its own list
        starts at its first behaviour (the recoveries of another trigger ran before)."""
        if self.cfg.oscillation_across_goals and self.recovery_trigger != Trigger.OSCILLATION:
            self.recovery_index = 0
        self.state = State.CLEARING
        self.recovery_trigger = Trigger.OSCILLATION

    def _clear(self, t, odom_pose, pose_map) -> tuple[float, float]:
        behaviors = self._recoveries()
        if self.cfg.recovery_behavior_enabled and self.recovery_index < len(behaviors):
            behavior = behaviors[self.recovery_index]
            self.goal.recoveries.append(behavior.name)
            LOG.debug("recovery %s (%s)", behavior.name, self.recovery_trigger.name)
            if behavior.type == recovery.ROTATE:
                self.rotator.start(float(odom_pose[2]))
                self.rotating = True
                return self._rotate_cycle(t, odom_pose)
            if behavior.type == recovery.BACK_UP:
                self.backer.start(behavior, odom_pose, t)
                self.backing_up = True
                return self._back_up_cycle(t, odom_pose)
            recovery.clear_costmaps(behavior, self.global_costmap, self.local_costmap,
                                    pose_map, odom_pose)
            self._after_recovery(t)
            return (0.0, 0.0)
        self.run_planner = False
        self._finish(GoalStatus.ABORTED, self.recovery_trigger.value, t)
        return (0.0, 0.0)

    def _recoveries(self):
        behaviors = self.cfg.recovery_behaviors
        if (self.recovery_trigger == Trigger.OSCILLATION
                and self.cfg.oscillation_recovery_behaviors is not None):
            behaviors = self.cfg.oscillation_recovery_behaviors
        if not self.cfg.clearing_rotation_allowed:
            behaviors = tuple(b for b in behaviors if b.type != recovery.ROTATE)
        return behaviors

    def _after_recovery(self, t: float) -> None:
        if not self.cfg.oscillation_across_goals or self.recovery_trigger == Trigger.OSCILLATION:
            self.last_oscillation_reset = t
        self.last_valid_plan = t
        self.planning_retries = 0
        self.state = State.PLANNING
        self.recovery_index += 1

    def _rotate_cycle(self, t: float, odom_pose) -> tuple[float, float]:
        done, w = self.rotator.step(self.local_costmap.costmap, odom_pose)
        if done:
            self.rotating = False
            self._after_recovery(t)
            return (0.0, 0.0)
        return (0.0, w)

    def _back_up_cycle(self, t: float, odom_pose) -> tuple[float, float]:
        done, v = self.backer.step(odom_pose, t, self.local_costmap.costmap)
        if done:
            self.backing_up = False
            self._after_recovery(t)
            return (0.0, 0.0)
        return (v, 0.0)

    # ----------------------------------------------------------------------------- output
    def _publish(self, t: float, cmd: tuple[float, float]) -> tuple[float, float]:
        """Clamp to the velocity limits and, with ``smooth_cmd_vel``, to the previous command ±
        acc_lim·Δt (the acceleration the rollouts assume)."""
        tp = self.cfg.TrajectoryPlannerROS
        v = min(max(cmd[0], min(tp.escape_vel, tp.min_vel_x, 0.0)), tp.max_vel_x)
        w = min(max(cmd[1], tp.min_vel_theta), tp.max_vel_theta)
        if self.cfg.smooth_cmd_vel:
            dt = self.cfg.sim_period if self._last_cmd_t is None else max(t - self._last_cmd_t, 0.0)
            pv, pw = self.last_cmd
            v = min(max(v, pv - tp.acc_lim_x * dt), pv + tp.acc_lim_x * dt)
            w = min(max(w, pw - tp.acc_lim_theta * dt), pw + tp.acc_lim_theta * dt)
        self.last_cmd = (float(v), float(w))
        self._last_cmd_t = t
        return self.last_cmd

    # ---------------------------------------------------------------------------- services
    def make_plan(self, start, goal, tolerance: float | None = None) -> Plan | None:
        """The ~make_plan service: a plan on the current global costmap (map frame)."""
        return self.planner.make_plan(self.global_costmap.costmap, start, goal, tolerance)

    def clear_costmaps(self) -> None:
        """The ~clear_costmaps service: forget every obstacle-layer mark."""
        self.global_costmap.reset_layers()
        self.local_costmap.reset_layers()
