"""Simulator configuration: integrator, odometry error model, robot/laser overrides.

Robot and laser parameters normally come from the World (i.e. from the Stage .world file, as in
Stage). Every field below that is ``None`` means "use the World's value"; a number overrides it.
Units are SI throughout: m, s, rad (so 90 °/s is 1.5708 rad/s, 2 °/rad is 0.0349 rad/rad).

Load from YAML with ``load_config(SimConfig, "config/robot.yaml", "sim")``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar, Dict, Optional, Tuple

from slam_predict.config import AT_LEAST_ONE, NON_NEGATIVE, POSITIVE, Range

INTEGRATORS = ("exact", "stage")
SCAN_TIMINGS = ("after_move", "before_move")
ODOM_MODELS = ("uniform_per_run", "fixed", "none", "gaussian_per_step")


@dataclass
class OdomConfig:
    """How odometry departs from the executed motion (see :mod:`slam_predict.sim.odometry`).

    Attributes:
        model: ``uniform_per_run`` (default; per-run proportional errors drawn uniformly in
            [-e, +e]), ``fixed`` (Stage's code: the values used as constant biases), ``none``
            (odometry = executed motion) or ``gaussian_per_step`` (random-walk noise).
        error: e per axis (x m/m, y m/m, theta rad/rad): the bound of the uniform draw, or the
            bias of ``fixed`` (signed). ``None`` = the World's ``robot.odom_error`` (x, y, yaw).
        gaussian: ``gaussian_per_step`` noise densities (k_x m/√m, k_y m/√m, k_θθ rad/√rad,
            k_θs rad/√m): after a straight run of L m the x error has std k_x·√L.
    """

    model: str = "uniform_per_run"
    error: Optional[Tuple[float, float, float]] = None
    gaussian: Tuple[float, float, float, float] = (0.005, 0.005, 0.01, 0.002)
    RANGES: ClassVar[Dict[str, Range]] = {"gaussian": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if self.model not in ODOM_MODELS:
            raise ValueError(f"odom model must be one of {', '.join(ODOM_MODELS)}, "
                             f"got '{self.model}'")
        if any(k < 0 for k in self.gaussian):
            raise ValueError("gaussian odom noise densities must be >= 0")


@dataclass
class RobotOverrides:
    """Robot parameters overriding the World's (None = keep). m, m/s, rad/s, m/s², rad/s².

    An acceleration of 0 means unlimited (Stage's velocity mode).
    """

    footprint_side: Optional[float] = None
    max_vel_x: Optional[float] = None
    max_vel_theta: Optional[float] = None
    max_acc_x: Optional[float] = None
    max_acc_theta: Optional[float] = None
    RANGES: ClassVar[Dict[str, Range]] = {
        "footprint_side": NON_NEGATIVE, "max_vel_x": NON_NEGATIVE, "max_vel_theta": NON_NEGATIVE,
        "max_acc_x": NON_NEGATIVE, "max_acc_theta": NON_NEGATIVE}

    def __post_init__(self) -> None:
        for name in ("footprint_side", "max_vel_x", "max_vel_theta", "max_acc_x",
                     "max_acc_theta"):
            value = getattr(self, name)
            if value is not None and value < 0:
                raise ValueError(f"robot {name} must be >= 0, got {value}")


@dataclass
class LaserOverrides:
    """Laser parameters overriding the World's (None = keep). rad, m, Hz, (x m, y m, yaw rad)."""

    fov: Optional[float] = None
    samples: Optional[int] = None
    range_min: Optional[float] = None
    range_max: Optional[float] = None
    rate_hz: Optional[float] = None
    pose: Optional[Tuple[float, float, float]] = None
    noise_std: Optional[float] = None
    RANGES: ClassVar[Dict[str, Range]] = {
        "fov": Range(0.0, 2 * math.pi, open_low=True), "samples": AT_LEAST_ONE,
        "range_min": NON_NEGATIVE, "range_max": POSITIVE, "rate_hz": POSITIVE,
        "noise_std": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if self.samples is not None and self.samples < 1:
            raise ValueError(f"laser samples must be >= 1, got {self.samples}")
        for name in ("fov", "range_max", "rate_hz"):
            value = getattr(self, name)
            if value is not None and not value > 0:
                raise ValueError(f"laser {name} must be > 0, got {value}")
        for name in ("range_min", "noise_std"):
            value = getattr(self, name)
            if value is not None and value < 0:
                raise ValueError(f"laser {name} must be >= 0, got {value}")


@dataclass
class SimConfig:
    """Everything the :class:`~slam_predict.sim.simulator.Simulator` needs beyond the World.

    Attributes:
        integrator: ``exact`` (arc integration of the piecewise-constant velocity) or ``stage``
            (Stage's update: translate along the old heading, then rotate; odometry rotates
            first, then translates along the new heading).
        scan_timing: ``after_move`` (scan taken from the pose reached at the end of the step,
            consistent with that step's poses) or ``before_move`` (Stage: the ranger updates
            before the world moves the robot, so a scan lags ground truth by one step).
        interval_sim: s of sim time per step; None = the World's.
        collisions: refuse moves whose footprint overlaps an occupied cell (Stage's stall).
    """

    integrator: str = "exact"
    scan_timing: str = "after_move"
    interval_sim: Optional[float] = None
    collisions: bool = True
    odom: OdomConfig = field(default_factory=OdomConfig)
    robot: RobotOverrides = field(default_factory=RobotOverrides)
    laser: LaserOverrides = field(default_factory=LaserOverrides)
    RANGES: ClassVar[Dict[str, Range]] = {"interval_sim": POSITIVE}

    def __post_init__(self) -> None:
        if self.integrator not in INTEGRATORS:
            raise ValueError(f"integrator must be one of {', '.join(INTEGRATORS)}, "
                             f"got '{self.integrator}'")
        if self.scan_timing not in SCAN_TIMINGS:
            raise ValueError(f"scan_timing must be one of {', '.join(SCAN_TIMINGS)}, "
                             f"got '{self.scan_timing}'")
        if self.interval_sim is not None and not self.interval_sim > 0:
            raise ValueError("interval_sim must be > 0")
