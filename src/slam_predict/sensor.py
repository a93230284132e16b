"""The robot's sensors in one place, SI units: the planar laser and the odometry error model.

:class:`SensorConfig` is what the simulator senses with (``Simulator.sensor``), what the perfect
map source and GMapping's defaults (maxRange = range_max − 0.01, maxUrange = maxRange, unless the
GMapping file sets them) take the laser from, what the traversal features can be given
(:meth:`slam_predict.features.traversal.TraversalConfig.for_laser`), and what run.json records
whole (``sensor``). Its hash, :func:`sensor_hash`, is the robot configuration key of the
collection summary and the learning dataset.

Units: m, rad, Hz, m/m and rad/rad (so 270 ° = 4.712389 rad, 2 °/rad = 0.0349 rad/rad).
Parameter names are Stage's (``fov``, ``samples``, ``range_min``/``range_max``) and the
odometry ``error`` is Stage's ``odom_error`` (x, y, yaw).
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar, Optional

import numpy as np

from slam_predict.config import AT_LEAST_ONE, NON_NEGATIVE, POSITIVE, Range, config_hash

ODOM_MODELS = ("uniform_per_run", "fixed", "none", "gaussian_per_step")
FULL_TURN = Range(0.0, 2 * math.pi, open_low=True)
DEFAULT_FOV = 270.0 * (math.pi / 180.0)  # = world.model 270.0 * DEG, bit for bit


@dataclass
class LaserConfig:
    """A planar laser (Stage's ranger): ``fov`` rad, ``samples`` beams, ranges m, scans at
    ``rate_hz``, mounted at ``pose`` (x m, y m, yaw rad) on the robot, Gaussian range noise
    ``noise_std`` m on hits. Beam i points at −fov/2 + i·fov/(samples − 1) (Stage's rule)."""

    fov: float = DEFAULT_FOV
    samples: int = 541
    range_min: float = 0.0
    range_max: float = 80.0
    rate_hz: float = 10.0
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    noise_std: float = 0.0
    RANGES: ClassVar[dict[str, Range]] = {
        "fov": FULL_TURN, "samples": AT_LEAST_ONE, "range_min": NON_NEGATIVE,
        "range_max": POSITIVE, "rate_hz": POSITIVE, "noise_std": NON_NEGATIVE}

    def __post_init__(self) -> None:
        check_laser(self)

    def angles(self) -> np.ndarray:
        """Beam bearings in rad in the laser frame, Stage's rule: −fov/2 + i·fov/(samples−1)."""
        if self.samples == 1:
            return np.zeros(1)
        return -self.fov / 2.0 + np.arange(self.samples) * self.fov / (self.samples - 1)


def check_laser(laser: Any) -> None:
    """ValueError unless the laser fields (None = not set, allowed) are physically valid."""
    def given(name: str) -> float | None:
        return getattr(laser, name)

    if given("samples") is not None and given("samples") < 1:
        raise ValueError(f"laser samples must be >= 1, got {given('samples')}")
    fov = given("fov")
    if fov is not None and not 0.0 < fov <= 2 * math.pi:
        raise ValueError(f"laser fov must be in (0, 2*pi] rad, got {fov}")
    for name in ("range_max", "rate_hz"):
        if given(name) is not None and not given(name) > 0:
            raise ValueError(f"laser {name} must be > 0, got {given(name)}")
    for name in ("range_min", "noise_std"):
        if given(name) is not None and not given(name) >= 0:
            raise ValueError(f"laser {name} must be >= 0, got {given(name)}")
    low, high = given("range_min"), given("range_max")
    if low is not None and high is not None and not high > low:
        raise ValueError(f"laser range_max ({high} m) must exceed range_min ({low} m)")


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
    error: Optional[tuple[float, float, float]] = None  # noqa: UP045 (from_dict)
    gaussian: tuple[float, float, float, float] = (0.005, 0.005, 0.01, 0.002)
    RANGES: ClassVar[dict[str, Range]] = {"gaussian": NON_NEGATIVE}

    def __post_init__(self) -> None:
        if self.model not in ODOM_MODELS:
            raise ValueError(f"odom model must be one of {', '.join(ODOM_MODELS)}, "
                             f"got '{self.model}'")
        if any(k < 0 for k in self.gaussian):
            raise ValueError("gaussian odom noise densities must be >= 0")
        if self.error is not None and not all(math.isfinite(e) for e in self.error):
            raise ValueError(f"odom error must be finite, got {list(self.error)}")


@dataclass
class SensorConfig:
    """The robot's laser and odometry, every value given (the World's defaults resolved)."""

    laser: LaserConfig = field(default_factory=LaserConfig)
    odom: OdomConfig = field(default_factory=lambda: OdomConfig(
        error=(0.01, 0.01, 2.0 * (math.pi / 180.0))))

    def __post_init__(self) -> None:
        if self.odom.error is None:
            raise ValueError("odom.error must be given (x m/m, y m/m, theta rad/rad)")


def sensor_hash(sensor: SensorConfig | Mapping[str, Any]) -> str:
    """The robot configuration key (12 hex digits) of a SensorConfig or of its plain-dict form
    (run.json's ``sensor``): both give the same hash."""
    return config_hash(sensor)
