"""A deterministic, seeded 2-D simulator of one differential-drive robot with a planar laser.

One :meth:`Simulator.step` advances ``interval_sim`` s of sim time, in Stage's order
(ros_interfaces.md §1.2): the command becomes the executed velocity (clamped, ramped); odometry
integrates it (even when the robot is stalled); the robot moves, unless its footprint would
overlap an occupied cell, in which case the move is refused and ``stalled`` is set (the velocity
is not zeroed); a scan is taken when the laser is due (``rate_hz``), after the move by default or
before it as Stage does (``scan_timing``).

Frames: ``true_pose`` is in the world frame; ``odom_pose`` in the odometry frame, whose origin
is the start pose (Stage's ``localization "odom"`` with the default ``localization_origin``), so
with the ``none`` model and the exact integrator ``true_pose = start ⊕ odom_pose``.
"""
from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from slam_predict.geometry import compose
from slam_predict.sensor import LaserConfig, SensorConfig
from slam_predict.sim import kinematics, raycast, stage_ranger
from slam_predict.sim.config import SimConfig
from slam_predict.sim.odometry import make_odometry, world_error
from slam_predict.world.model import RobotSpec, World

LOG = logging.getLogger(__name__)


@dataclass
class SimState:
    """What the simulator reports after a step.

    Attributes:
        t: sim time, s.
        true_pose: (x, y, yaw) in the world frame (m, m, rad).
        odom_pose: (x, y, yaw) in the odometry frame.
        velocity: (v m/s, ω rad/s) executed this step (commanded, clamped, ramped).
        stalled: the move of this step was refused (footprint would hit an obstacle).
        scan: float32 ranges (m) if a scan was taken this step, else None.
        scan_true_pose: robot pose (world frame) the scan was taken from, else None.
        scan_odom_pose: the step's odometry pose, logged with the scan (Stage stamps both
            alike), else None.
    """

    t: float
    true_pose: np.ndarray
    odom_pose: np.ndarray
    velocity: tuple[float, float]
    stalled: bool
    scan: np.ndarray | None = None
    scan_true_pose: np.ndarray | None = None
    scan_odom_pose: np.ndarray | None = None


def _override(spec: Any, overrides: Any) -> Any:
    """``spec`` with every non-None field of ``overrides`` replacing its own."""
    changes = {f.name: getattr(overrides, f.name) for f in dataclasses.fields(overrides)
               if getattr(overrides, f.name) is not None}
    return dataclasses.replace(spec, **changes)


def resolve_sensor(world: World, config: SimConfig) -> SensorConfig:
    """The robot's sensors: the World's laser and odometry error (the Stage file's) with every
    non-None value of ``config``'s ``laser`` and ``odom`` replacing them."""
    error = config.odom.error
    if error is None:
        error = world_error(world.robot.odom_error)
    odom = dataclasses.replace(config.odom, error=tuple(float(e) for e in error))
    return SensorConfig(laser=_override(world.laser, config.laser), odom=odom)


class Simulator:
    """Steps a robot through a World; see the module docstring for the order of events.

    Args:
        world: the environment; the robot starts at ``world.start_pose``.
        config: integrator, odometry model, overrides of the World's robot/laser parameters.
        rng: the run's random generator (odometry draws and laser noise); nothing else is random.
    """

    def __init__(self, world: World, config: SimConfig, rng: np.random.Generator):
        self.world = world
        self.config = config
        self.rng = rng
        self.robot: RobotSpec = _override(world.robot, config.robot)
        self.sensor: SensorConfig = resolve_sensor(world, config)
        self.laser: LaserConfig = self.sensor.laser
        self.dt = float(config.interval_sim or world.interval_sim)
        self._check_specs()
        self.limits = kinematics.VelocityLimits(self.robot.max_vel_x, self.robot.max_vel_theta,
                                                self.robot.max_acc_x, self.robot.max_acc_theta)
        self.grid = raycast.LaserGrid.of_world(world)
        self.stage_grid = None
        if config.ranger_model == "stage":
            res = stage_ranger.stage_resolution(world, config.stage_resolution)
            self.stage_grid = stage_ranger.cached_stage_grid(world, res)
        self.laser_angles = self.laser.angles().astype(float)
        self._cos = np.cos(self.laser_angles)
        self._sin = np.sin(self.laser_angles)
        self.laser_pose = np.asarray(self.laser.pose, dtype=float)
        self.odometry = make_odometry(self.sensor.odom, self.sensor.odom.error, rng)
        self.reset()
        if self.collides(self.true_pose):
            LOG.warning("%s: the footprint at the start pose (%.2f, %.2f) overlaps an obstacle; "
                        "every move will stall", world.name, *self.true_pose[:2])

    def _check_specs(self) -> None:
        if not self.dt > 0:
            raise ValueError("interval_sim must be > 0")
        if not (self.laser.samples >= 1 and self.laser.range_max > 0 and self.laser.rate_hz > 0):
            raise ValueError("laser needs samples >= 1, range_max > 0 and rate_hz > 0")
        if not (self.robot.footprint_side >= 0 and self.robot.max_vel_x >= 0
                and self.robot.max_vel_theta >= 0):
            raise ValueError("robot footprint and velocity bounds must be >= 0")

    # -- state -----------------------------------------------------------------------------
    def reset(self) -> None:
        """Back to the start pose at t = 0 with zero velocity (the odometry error is kept)."""
        self.step_count = 0
        self.true_pose = np.array(self.world.start_pose, dtype=float)
        self._last_start = self.true_pose.copy()  # true pose at the start of the last step
        self.odom_pose = np.zeros(3)
        self.velocity = (0.0, 0.0)
        self.stalled = False

    @property
    def t(self) -> float:
        """Sim time in s."""
        return self.step_count * self.dt

    @property
    def odom_error(self) -> dict[str, Any]:
        """The odometry model and the per-run errors actually in use (for run metadata)."""
        return self.odometry.metadata()

    # -- sensing and collision -------------------------------------------------------------
    def laser_world_pose(self, robot_pose: np.ndarray) -> np.ndarray:
        """World pose of the laser when the robot is at ``robot_pose``."""
        return compose(robot_pose, self.laser_pose)

    def scan_from(self, robot_pose: np.ndarray,
                  previous_pose: np.ndarray | None = None) -> np.ndarray:
        """float32 ranges (m) of a scan with the robot at ``robot_pose`` (noise included).

        ``previous_pose``: with the Stage ranger, where the robot's body was one step earlier
        (Stage keeps it in its other grid layer; it only changes where the ray walk jumps).
        """
        lx, ly, lyaw = self.laser_world_pose(robot_pose)
        if self.stage_grid is not None:
            out = self.stage_grid.scan(robot_pose, (lx, ly, lyaw), self.laser.fov,
                                       self.laser.samples, self.laser.range_max,
                                       self.robot.footprint_side, previous_pose=previous_pose)
        else:
            out = self.grid.scan(lx, ly, lyaw, self._cos, self._sin, self.laser.range_max)
        if self.laser.noise_std > 0:
            self._add_noise(out)
        return out

    def _add_noise(self, ranges: np.ndarray) -> None:
        """Gaussian range noise on hits (beams below range_max), clipped to [0, range_max]."""
        hits = ranges < self.laser.range_max
        noise = self.rng.normal(0.0, self.laser.noise_std, int(hits.sum()))
        ranges[hits] = np.clip(ranges[hits] + noise, 0.0, self.laser.range_max)

    def collides(self, pose: np.ndarray) -> bool:
        """True when the footprint at ``pose`` overlaps an occupied cell or leaves the map."""
        return self.grid.collides(pose[0], pose[1], pose[2], self.robot.footprint_side)

    def _scan_due(self, step: int) -> bool:
        """A scan is taken at the steps where t crosses a multiple of 1/rate_hz."""
        rate_dt = self.laser.rate_hz * self.dt
        return math.floor(step * rate_dt + 1e-9) > math.floor((step - 1) * rate_dt + 1e-9)

    # -- stepping --------------------------------------------------------------------------
    def step(self, v_cmd: float, w_cmd: float) -> SimState:
        """Advance one ``interval_sim`` with command (v m/s, ω rad/s); returns the new state."""
        self.step_count += 1
        dt = self.dt
        v, w = kinematics.limit_velocity(v_cmd, w_cmd, self.velocity[0], self.velocity[1],
                                         self.limits, dt)
        self.velocity = (v, w)
        integrator = self.config.integrator
        delta = kinematics.body_delta(integrator, v, w, dt)
        odom_delta = self.odometry.perturb(delta, self.rng)
        if integrator == "stage":
            self.odom_pose = kinematics.rotate_then_translate(self.odom_pose, odom_delta)
        else:
            self.odom_pose = kinematics.apply_delta(self.odom_pose, odom_delta)
        scan_due = self._scan_due(self.step_count)
        start = self.true_pose.copy()
        state = SimState(self.t, self.true_pose.copy(), self.odom_pose.copy(), self.velocity,
                         False)
        if scan_due and self.config.scan_timing == "before_move":
            self._attach_scan(state, self._last_start)
        self._move(delta)
        state.true_pose = self.true_pose.copy()
        state.stalled = self.stalled
        if scan_due and self.config.scan_timing == "after_move":
            self._attach_scan(state, start)
        self._last_start = start
        return state

    def _move(self, delta: tuple[float, float, float]) -> None:
        """Apply ``delta`` to the true pose unless the footprint would hit something."""
        if delta == (0.0, 0.0, 0.0):
            self.stalled = False  # not trying to move
            return
        candidate = kinematics.apply_delta(self.true_pose, delta)
        if self.config.collisions and self.collides(candidate):
            self.stalled = True
            return
        self.stalled = False
        self.true_pose = candidate

    def _attach_scan(self, state: SimState, previous_pose: np.ndarray) -> None:
        state.scan_true_pose = self.true_pose.copy()
        state.scan_odom_pose = self.odom_pose.copy()
        state.scan = self.scan_from(self.true_pose, previous_pose)
