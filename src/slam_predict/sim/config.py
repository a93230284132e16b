"""Simulator configuration: integrator, odometry error model, robot/laser overrides.

Robot and laser parameters normally come from the World (i.e. from the Stage .world file, as in
Stage). Every field below that is ``None`` means "use the World's value"; a number overrides it.
Units are SI throughout: m, s, rad (so 90 °/s is 1.5708 rad/s, 2 °/rad is 0.0349 rad/rad).

Load from YAML with ``load_config(SimConfig, "config/robot.yaml", "sim")``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

from slam_predict.config import AT_LEAST_ONE, NON_NEGATIVE, POSITIVE, Range
from slam_predict.sensor import FULL_TURN, ODOM_MODELS, OdomConfig, check_laser

__all__ = ["INTEGRATORS", "ODOM_MODELS", "RANGER_MODELS", "SCAN_TIMINGS", "LaserOverrides",
           "OdomConfig", "RobotOverrides", "SimConfig"]

INTEGRATORS = ("exact", "stage")
SCAN_TIMINGS = ("after_move", "before_move")
RANGER_MODELS = ("exact", "stage")


@dataclass
class RobotOverrides:
    """Robot parameters overriding the World's (None = keep). m, m/s, rad/s, m/s², rad/s².

    An acceleration of 0 means unlimited (Stage's velocity mode).
    """

    footprint_side: float | None = None
    max_vel_x: float | None = None
    max_vel_theta: float | None = None
    max_acc_x: float | None = None
    max_acc_theta: float | None = None
    RANGES: ClassVar[dict[str, Range]] = {
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

    fov: float | None = None
    samples: int | None = None
    range_min: float | None = None
    range_max: float | None = None
    rate_hz: float | None = None
    pose: tuple[float, float, float] | None = None
    noise_std: float | None = None
    RANGES: ClassVar[dict[str, Range]] = {
        "fov": FULL_TURN, "samples": AT_LEAST_ONE,
        "range_min": NON_NEGATIVE, "range_max": POSITIVE, "rate_hz": POSITIVE,
        "noise_std": NON_NEGATIVE}

    def __post_init__(self) -> None:
        check_laser(self)


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
        ranger_model: ``exact`` (exact distance to the bitmap's first occupied cell) or
            ``stage`` (Stage 4.1.1's laser: the bitmap rasterised into Stage's cell grid and
            Stage's ray walk, :mod:`slam_predict.sim.stage_ranger`).
        stage_resolution: Stage's raytrace cell (m) for ``ranger_model: stage``; None = the
            .world file's ``resolution`` when the World carries one, else 0.025 m.
    """

    integrator: str = "exact"
    scan_timing: str = "after_move"
    interval_sim: float | None = None
    collisions: bool = True
    ranger_model: str = "exact"
    stage_resolution: float | None = None
    odom: OdomConfig = field(default_factory=OdomConfig)
    robot: RobotOverrides = field(default_factory=RobotOverrides)
    laser: LaserOverrides = field(default_factory=LaserOverrides)
    RANGES: ClassVar[dict[str, Range]] = {"interval_sim": POSITIVE, "stage_resolution": POSITIVE}
    # fields left out of config_hash while at these defaults (added after runs were recorded)
    HASH_OMIT_IF: ClassVar[dict[str, object]] = {"ranger_model": "exact",
                                                  "stage_resolution": None}

    def __post_init__(self) -> None:
        if self.integrator not in INTEGRATORS:
            raise ValueError(f"integrator must be one of {', '.join(INTEGRATORS)}, "
                             f"got '{self.integrator}'")
        if self.scan_timing not in SCAN_TIMINGS:
            raise ValueError(f"scan_timing must be one of {', '.join(SCAN_TIMINGS)}, "
                             f"got '{self.scan_timing}'")
        if self.interval_sim is not None and not self.interval_sim > 0:
            raise ValueError("interval_sim must be > 0")
        if self.ranger_model not in RANGER_MODELS:
            raise ValueError(f"ranger_model must be one of {', '.join(RANGER_MODELS)}, "
                             f"got '{self.ranger_model}'")
        if self.stage_resolution is not None and not self.stage_resolution > 0:
            raise ValueError("stage_resolution must be > 0")
