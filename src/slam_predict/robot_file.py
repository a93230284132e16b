"""Robot description files (``slam-predict collect --robot robot.yaml``): one robot's laser,
odometry error, footprint and speed limits, in the units a Stage .world file writes them.

Schema (every key optional unless marked *required*; unknown keys are refused with a
did-you-mean hint; every error is an :class:`~slam_predict.errors.InputError` naming the file;
values no real robot has, usually a unit mistake, are refused unless ``force``:
:mod:`slam_predict.robot_checks`; the radian spellings and other tools' names:
:mod:`slam_predict.robot_spellings`)::

    name: lds_360_3p5            # required, a non-empty string
    description: "free text"     # optional
    laser:                       # required; Stage's ranger / stage_ros' LaserScan names
      range_max: 3.5             # required, m, > range_min
      fov: 360.0                 # required, DEGREES (Stage's ranger), in (0, 360]; or
                                 # fov_rad: 6.2832, radians in (0, 2 pi] (a LaserScan's)
      samples: 360               # required, beams, >= 1 (bearing i: -fov/2 + i*fov/(samples-1))
      range_min: 0.12            # m, >= 0 (default 0)
      rate_hz: 5.0               # scans per s, > 0 (default 10)
      pose: [0.0, 0.0, 0.0]      # mounting on the robot: x m, y m, yaw DEGREES (default centred)
      noise_std: 0.0             # m, Gaussian range noise on hits, >= 0 (default 0, as Stage)
    odom_error: [0.01, 0.01, 2.0]  # required: x m/m, y m/m, yaw in DEGREES PER RADIAN; Stage's
                                 # 4-value form [x, y, z, yaw] is accepted too (z is unused);
                                 # or odom_error_rad: [x m/m, y m/m, yaw rad/rad]
    odom_model: fixed            # one of sensor.ODOM_MODELS (default fixed: Stage's code, a
                                 # real robot's systematic bias; uniform_per_run draws per run)
    footprint_side: 0.3          # m, square footprint, > 0 (default 0.3)
    max_vel_x: 0.85              # m/s, > 0: base_local_planner's (default 0.85)
    max_vel_theta: 0.7           # rad/s, > 0: base_local_planner's (default 0.7)

The odometry errors are the bounds (or, with ``odom_model: fixed``, the biases, here >= 0) of
:class:`~slam_predict.sensor.OdomConfig`: 2.0 °/rad is 2·π/180 = 0.0349 rad/rad. The
``gaussian_per_step`` model takes its noise densities from the settings' ``sim.odom.gaussian``.

What a description changes, as pure conversions (SI units, rad):

- :meth:`RobotDescription.to_sensor_config`: the :class:`~slam_predict.sensor.SensorConfig`;
- :meth:`RobotDescription.sim_overrides`: the partial ``sim`` tree (laser, odom, and the robot's
  footprint and velocity bounds: Stage's ``velocity_bounds`` are set to the planner's limits, so
  the planner can use them fully);
- :meth:`RobotDescription.nav_overrides`: base_local_planner's ``max_vel_x``, ``max_vel_theta``
  and ``min_vel_theta = −max_vel_theta``, and both costmaps' footprint, a square
  ``COSTMAP_MARGIN`` wider than the body (the seed study's 0.4 m square for its 0.3 m robot);
- :meth:`RobotDescription.explore_overrides`: the thesis explorer's inscribed radius (half that
  square's side);
- :meth:`RobotDescription.gmapping_caps`: GMapping's maxRange / maxUrange capped by the laser,
  so that a short laser's no-hit beams (reported at range_max) are never integrated as hits.
"""
from __future__ import annotations

import dataclasses
import logging
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, TypeVar

from slam_predict.config import (
    AT_LEAST_ONE,
    NON_NEGATIVE,
    POSITIVE,
    Range,
    check_keys,
    from_dict,
    load_yaml,
    to_dict,
)
from slam_predict.errors import InputError, did_you_mean, require_file
from slam_predict.paths import PROJECT_ROOT, portable_path
from slam_predict.robot_checks import implausible
from slam_predict.robot_spellings import check_foreign_keys, to_file_units
from slam_predict.sensor import ODOM_MODELS, LaserConfig, OdomConfig, SensorConfig

DEG = math.pi / 180.0          # rad per degree, as world.model's DEG (Stage's unit), bit for bit
FOV_DEG = Range(0.0, 360.0, open_low=True)
GMAPPING_MARGIN = 0.01         # m: slam_gmapping's default maxRange is range_max − 0.01
COSTMAP_MARGIN = 0.1           # m: costmap footprint side − body side (0.4 m − 0.3 m, seed study)
P = TypeVar("P")
LOG = logging.getLogger(__name__)
ROBOTS_DIR = PROJECT_ROOT / "config" / "robots"


@dataclass(frozen=True)
class RobotLaser:
    """The ``laser:`` section: ranges m, ``fov`` DEGREES, ``samples`` beams, ``rate_hz`` Hz,
    mounting ``pose`` (x m, y m, yaw DEGREES), ``noise_std`` m."""

    range_max: float
    fov: float
    samples: int
    range_min: float = 0.0
    rate_hz: float = 10.0
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    noise_std: float = 0.0
    RANGES: ClassVar[dict[str, Range]] = {
        "range_max": POSITIVE, "fov": FOV_DEG, "samples": AT_LEAST_ONE,
        "range_min": NON_NEGATIVE, "rate_hz": POSITIVE, "noise_std": NON_NEGATIVE}
    REQUIRED: ClassVar[tuple[str, ...]] = ("range_max", "fov", "samples")

    def __post_init__(self) -> None:
        _require_finite("laser", {"range_max": self.range_max, "fov": self.fov,
                                  "range_min": self.range_min, "rate_hz": self.rate_hz,
                                  "noise_std": self.noise_std, "pose": self.pose})
        if not 0.0 < self.fov <= 360.0:
            raise ValueError(f"laser.fov must be in (0, 360] degrees, got {self.fov}")
        if self.samples < 1 or self.rate_hz <= 0 or self.range_min < 0 or self.noise_std < 0:
            raise ValueError("laser samples must be >= 1, rate_hz > 0, range_min and noise_std "
                             ">= 0")
        if not self.range_max > self.range_min:
            raise ValueError(f"laser.range_max ({self.range_max} m) must exceed laser.range_min "
                             f"({self.range_min} m)")
        if not self.range_max > GMAPPING_MARGIN:
            raise ValueError(f"laser.range_max must exceed {GMAPPING_MARGIN} m (GMapping's "
                             f"maxRange is range_max − {GMAPPING_MARGIN} m), got {self.range_max}")

    def to_laser_config(self) -> LaserConfig:
        """The :class:`~slam_predict.sensor.LaserConfig` (fov and mounting yaw in rad)."""
        x, y, yaw = self.pose
        return LaserConfig(fov=self.fov * DEG, samples=self.samples, range_min=self.range_min,
                           range_max=self.range_max, rate_hz=self.rate_hz,
                           pose=(x, y, yaw * DEG), noise_std=self.noise_std)


@dataclass(frozen=True)
class RobotDescription:
    """One robot, as a robot description file gives it (see the module docstring for units)."""

    name: str
    laser: RobotLaser
    odom_error: tuple[float, float, float]
    description: str = ""
    odom_model: str = "fixed"
    footprint_side: float = 0.3
    max_vel_x: float = 0.85
    max_vel_theta: float = 0.7
    RANGES: ClassVar[dict[str, Range]] = {
        "odom_error": NON_NEGATIVE, "footprint_side": POSITIVE, "max_vel_x": POSITIVE,
        "max_vel_theta": POSITIVE}
    REQUIRED: ClassVar[tuple[str, ...]] = ("name", "laser", "odom_error")

    def __post_init__(self) -> None:
        if not self.name.strip():
            raise ValueError("name must not be empty")
        if self.odom_model not in ODOM_MODELS:
            raise ValueError(f"odom_model must be one of {', '.join(ODOM_MODELS)}, "
                             f"got '{self.odom_model}'")
        _require_finite("", {"odom_error": self.odom_error, "footprint_side": self.footprint_side,
                             "max_vel_x": self.max_vel_x, "max_vel_theta": self.max_vel_theta})
        if any(e < 0 for e in self.odom_error):
            raise ValueError(f"odom_error values are bounds and must be >= 0, got "
                             f"{list(self.odom_error)}")
        if not (self.footprint_side > 0 and self.max_vel_x > 0 and self.max_vel_theta > 0):
            raise ValueError("footprint_side, max_vel_x and max_vel_theta must be > 0")

    # -- conversions (pure) -----------------------------------------------------------------
    def odom_error_si(self) -> tuple[float, float, float]:
        """(x m/m, y m/m, yaw rad/rad): the yaw part converted from °/rad."""
        x, y, yaw = self.odom_error
        return (x, y, yaw * DEG)

    def to_sensor_config(self) -> SensorConfig:
        """The robot's :class:`~slam_predict.sensor.SensorConfig` (SI units, rad)."""
        return SensorConfig(laser=self.laser.to_laser_config(),
                            odom=OdomConfig(model=self.odom_model, error=self.odom_error_si()))

    def sim_overrides(self) -> dict[str, Any]:
        """The partial ``sim`` tree of config/robot.yaml this robot sets (laser, odom, and the
        robot's footprint and Stage velocity bounds, equal to the planner's limits)."""
        laser = to_dict(self.laser.to_laser_config())
        return {"laser": laser,
                "odom": {"model": self.odom_model, "error": list(self.odom_error_si())},
                "robot": {"footprint_side": self.footprint_side, "max_vel_x": self.max_vel_x,
                          "max_vel_theta": self.max_vel_theta}}

    def nav_overrides(self) -> dict[str, Any]:
        """The partial move_base tree (:func:`slam_predict.nav.config.load_nav_config`'s layout)
        this robot sets: base_local_planner's speed limits and the costmaps' footprint."""
        half = self.costmap_half_side()
        square = [[-half, -half], [-half, half], [half, half], [half, -half]]
        return {"TrajectoryPlannerROS": {"max_vel_x": self.max_vel_x,
                                         "max_vel_theta": self.max_vel_theta,
                                         "min_vel_theta": -self.max_vel_theta},
                "global_costmap": {"footprint": square},
                "local_costmap": {"footprint": square}}

    def costmap_half_side(self) -> float:
        """Half the side of the costmaps' square footprint, m: (footprint_side + 0.1) / 2."""
        return (self.footprint_side + COSTMAP_MARGIN) / 2.0

    def explore_overrides(self) -> dict[str, Any]:
        """The partial explore tree this robot sets: the thesis explorer's own costmap's
        inscribed radius (half the costmaps' footprint side, as its 0.2 m for 0.4 m)."""
        return {"thesis": {"inscribed_radius": self.costmap_half_side()}}

    def gmapping_caps(self, params: P) -> P:
        """GMapping parameters ``params`` capped by this robot's laser
        (:func:`gmapping_caps`)."""
        return gmapping_caps(params, self.laser.range_max)


def gmapping_caps(params: P, range_max: float) -> P:
    """A copy of GMapping parameters ``params`` for a laser of ``range_max`` m, set up as the
    gmapping wiki asks for open space to be mapped free: maxUrange < the sensor's range <=
    maxRange. maxUrange = min(theirs, range_max − 0.01, maxRange), so a no-hit beam (reported
    at range_max, as Stage does) is cropped: free space up to maxUrange, no endpoint. maxRange
    stays theirs: >= range_max keeps those beams; below it (the seed study's 60 m with its 80 m
    laser) skips them, as it did there. Unset values stay unset (slam_gmapping then derives
    maxRange = range_max − 0.01 and maxUrange = maxRange from the laser), and a set maxUrange
    with an unset maxRange is capped at that derived maxRange."""
    limit = range_max - GMAPPING_MARGIN
    max_range = params.maxRange  # type: ignore[attr-defined]
    max_urange = params.maxUrange  # type: ignore[attr-defined]
    if max_urange is not None:
        max_urange = min(max_urange, limit if max_range is None else min(limit, max_range))
    return dataclasses.replace(params, maxUrange=max_urange)  # type: ignore[type-var]


def _require_finite(section: str, values: Mapping[str, Any]) -> None:
    """ValueError naming the first value (or tuple element) that is NaN or infinite."""
    for key, value in values.items():
        for item in value if isinstance(value, tuple) else (value,):
            if not math.isfinite(item):
                where = f"{section}.{key}" if section else key
                raise ValueError(f"{where} must be finite, got {value!r}")


def load_robot(path: os.PathLike | str, force: bool = False) -> RobotDescription:
    """Read and validate a robot description file; InputError (one line, naming the file)
    on any problem. A file that is valid but implausible (:mod:`slam_predict.robot_checks`,
    usually a unit mistake) is refused too, unless ``force``: then each problem is logged."""
    path = require_file(robot_path(path), "robot file")
    data = load_yaml(path)
    if not data:
        raise InputError("the robot file is empty (it needs at least name, laser and "
                         "odom_error; examples in config/robots/)", path)
    check_foreign_keys(data, path, _field_names(RobotLaser))
    data, in_radians = to_file_units(data, path)
    check_keys(data, _field_names(RobotDescription), path)
    laser = data.get("laser")
    if isinstance(laser, Mapping):
        check_keys(laser, _field_names(RobotLaser), path, "laser")
        _check_required(laser, RobotLaser.REQUIRED, path, "laser.")
    _check_required(data, RobotDescription.REQUIRED, path, "")
    if isinstance(data.get("odom_error"), list) and len(data["odom_error"]) == 4:
        data = _stage_odom_error(data, path)
    robot = from_dict(RobotDescription, data, path)
    problems = implausible(robot, in_radians)
    if problems and not force:
        raise InputError(f"{problems[0]} (--force uses it as written)", path)
    for problem in problems:
        LOG.warning("%s: %s (used as written: --force)", path, problem)
    return robot


def robot_path(spec: os.PathLike | str) -> str:
    """The file of a robot given as a path, or by name as the shipped ones
    (``urg_240_5p6`` = config/robots/urg_240_5p6.yaml); InputError with a did-you-mean when a
    bare name is not one of them."""
    spec = os.fspath(spec)
    if os.path.exists(spec) or os.sep in spec or spec.endswith((".yaml", ".yml")):
        return spec
    shipped = {p.stem: p for p in sorted(ROBOTS_DIR.glob("*.yaml"))}
    if spec in shipped:
        return str(shipped[spec])
    raise InputError(f"robot file not found, nor a shipped robot of {portable_path(ROBOTS_DIR)}"
                     + (did_you_mean(spec, shipped) or f" ({', '.join(shipped)})"), spec)


def _field_names(cls: type) -> list[str]:
    return [f.name for f in dataclasses.fields(cls)]


def _check_required(data: Mapping[str, Any], required: tuple[str, ...], path: str,
                    prefix: str) -> None:
    for key in required:
        if data.get(key) is None:
            raise InputError(f"missing required key '{prefix}{key}'", path)


def _stage_odom_error(data: dict[str, Any], path: str) -> dict[str, Any]:
    """``data`` with Stage's 4-value odom_error [x, y, z, yaw] read as [x, y, yaw]."""
    x, y, z, yaw = data["odom_error"]
    if isinstance(z, bool) or not isinstance(z, (int, float)):
        raise InputError(f"'odom_error[2]' must be a number, got {z!r}", path)
    return {**data, "odom_error": [x, y, yaw]}
