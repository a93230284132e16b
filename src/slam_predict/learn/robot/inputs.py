"""The robot as model input (issue #18): four numbers describing laser and odometry.

``ROBOT_INPUTS`` and their units:

- ``laser_range_max_m`` — the laser range GMapping uses, m: min(laser range_max, maxUrange)
  (:func:`effective_range`; GMapping crops every beam at maxUrange, config/gmapping.yaml's
  30 m, so a longer laser is the same robot to it);
- ``laser_fov_deg`` — the laser's field of view, DEGREES (run.json records it in rad);
- ``odom_xy_error`` — the mean of the x and y odometry error bounds, m/m;
- ``odom_yaw_error`` — the yaw odometry error bound, rad/rad (2 °/rad = 0.0349 rad/rad).

The odometry numbers are the error magnitudes of the sensor's model
(:class:`slam_predict.sensor.OdomConfig`): the bounds of ``uniform_per_run`` (each run draws its
biases uniformly within ± the bound) or the constant biases of ``fixed`` (Stage's code; here
>= 0); ``none`` is either robot with 0. The two describe different robots with the same units,
so a campaign is learned from one of them (:func:`odom_model_of`; a campaign mixing them is
refused) and a model card records which (``odom_model``). ``gaussian_per_step`` (noise
densities) is refused.

Two sources give the same numbers: a run record's ``sensor`` dict (:func:`inputs_from_sensor`)
and a robot description file (:func:`inputs_from_robot`, through its ``to_sensor_config()``),
both with the maxUrange of the GMapping settings the runs were collected with
(:mod:`slam_predict.learn.robot.domain`; a model folder's card records it).
A fifth input, ``laser_resolution_deg`` (:data:`RESOLUTION_INPUT`, degrees between beams,
fov / (samples − 1), rounded to 0.01°), is read from both sources too; a model learns it only
when its configuration asks (``robot_learning.resolution_input``, for campaigns that vary it:
the robot design keeps it at :data:`DESIGN_RESOLUTION_DEG`), and its card lists the robot
inputs it reads (``robot_inputs``; :func:`model_robot_inputs`).

One input depends on the plan AND the robot (:data:`DERIVED_INPUTS`, :func:`derived_inputs`):
``laser_blind_fraction``, the fraction of sight lines from the plan's floor that reach no wall
within the laser's range (:mod:`slam_predict.features.sightline`), read from the plan's curve
at ``laser_range_max_m``.
"""
from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from typing import Any

from slam_predict.errors import InputError

ROBOT_INPUTS = ("laser_range_max_m", "laser_fov_deg", "odom_xy_error", "odom_yaw_error")
RESOLUTION_INPUT = "laser_resolution_deg"   # degrees between beams (optional fifth input)
ALL_ROBOT_INPUTS = (*ROBOT_INPUTS, RESOLUTION_INPUT)   # every name a robot input may have
ROBOT_UNITS = {"laser_range_max_m": "m", "laser_fov_deg": "deg", "odom_xy_error": "m/m",
               "odom_yaw_error": "rad/rad", RESOLUTION_INPUT: "deg"}
DESIGN_RESOLUTION_DEG = 0.5   # the design's laser angular resolution (samples = fov/0.5 + 1)
ODOM_INPUT_MODELS = ("uniform_per_run", "fixed", "none")   # odometry models with error magnitudes
DERIVED_INPUTS = ("laser_blind_fraction",)    # plan × robot inputs
DERIVED_UNITS = {"laser_blind_fraction": "fraction"}


def _value(tree: Mapping[str, Any], path: str, source: os.PathLike | str | None) -> Any:
    """``tree[a][b]`` for ``path`` 'a.b'; InputError naming the missing key otherwise."""
    value: Any = tree
    for key in path.split("."):
        if not isinstance(value, Mapping) or key not in value:
            raise InputError(f"sensor has no '{path}'", source)
        value = value[key]
    return value


def _number(tree: Mapping[str, Any], path: str, source) -> float:
    value = _value(tree, path, source)
    if isinstance(value, bool) or not isinstance(value, (int, float)) \
            or not math.isfinite(value):
        raise InputError(f"sensor '{path}' must be a finite number, got {value!r}", source)
    return float(value)


def odom_model_of(sensor: Mapping[str, Any], source=None) -> str:
    """The sensor's odometry model, one of :data:`ODOM_INPUT_MODELS`; InputError otherwise."""
    model = _value(sensor, "odom.model", source)
    if model not in ODOM_INPUT_MODELS:
        raise InputError(f"odometry model '{model}' is not a robot input (only "
                         f"{', '.join(ODOM_INPUT_MODELS)} give error magnitudes)", source)
    return str(model)


def _odom_bounds(sensor: Mapping[str, Any], source) -> tuple[float, float, float]:
    """(x m/m, y m/m, yaw rad/rad) error magnitudes (bounds or biases) of the sensor's odometry
    model."""
    model = odom_model_of(sensor, source)
    error = _value(sensor, "odom.error", source)
    if not isinstance(error, (list, tuple)) or len(error) != 3:
        raise InputError(f"sensor 'odom.error' must be [x, y, yaw], got {error!r}", source)
    bounds = []
    for i, item in enumerate(error):
        if isinstance(item, bool) or not isinstance(item, (int, float)) \
                or not math.isfinite(item) or item < 0:
            raise InputError(f"sensor 'odom.error[{i}]' must be a number >= 0, got {item!r}",
                             source)
        bounds.append(float(item))
    if model == "none":
        return (0.0, 0.0, 0.0)
    return (bounds[0], bounds[1], bounds[2])


def effective_range(range_max: float, max_urange_m: float | None) -> float:
    """The laser range GMapping uses, m: min(range_max, maxUrange); ``range_max`` when
    maxUrange is None (unset: slam_gmapping then takes the laser's own range)."""
    return float(range_max) if max_urange_m is None else min(float(range_max),
                                                             float(max_urange_m))


def inputs_from_sensor(sensor: Mapping[str, Any], source: os.PathLike | str | None = None,
                       max_urange_m: float | None = None) -> dict[str, float]:
    """The robot inputs of a run record's ``sensor`` dict (SI units, fov in rad): the four of
    :data:`ROBOT_INPUTS` and :data:`RESOLUTION_INPUT`.

    Args:
        sensor: ``{"laser": {"range_max" m, "fov" rad, "samples", ...}, "odom": {"model",
            "error": [x m/m, y m/m, yaw rad/rad]}}`` as run.json records it.
        source: file named in the InputError raised for a missing or malformed value.
        max_urange_m: GMapping's maxUrange, m (None: no cap), see :func:`effective_range`.
    """
    if not isinstance(sensor, Mapping):
        raise InputError(f"'sensor' must be a mapping, got {type(sensor).__name__}", source)
    range_max = _number(sensor, "laser.range_max", source)
    fov = _number(sensor, "laser.fov", source)
    if range_max <= 0 or fov <= 0:
        raise InputError("sensor laser range_max and fov must be > 0", source)
    x, y, yaw = _odom_bounds(sensor, source)
    return {"laser_range_max_m": effective_range(range_max, max_urange_m),
            "laser_fov_deg": math.degrees(fov),
            "odom_xy_error": 0.5 * (x + y), "odom_yaw_error": yaw,
            RESOLUTION_INPUT: resolution_input_value(angular_resolution_deg(sensor, source))}


def resolution_input_value(degrees: float) -> float:
    """The :data:`RESOLUTION_INPUT` of an angular resolution, deg: rounded to 0.01° (a
    design's fov/0.5 + 1 beams, the count rounded, give 0.4997–0.5003°: all 0.5)."""
    return round(float(degrees), 2)


def model_robot_inputs(resolution_input: bool) -> tuple[str, ...]:
    """The robot inputs a model learns: :data:`ROBOT_INPUTS`, with :data:`RESOLUTION_INPUT`
    when ``resolution_input`` (robot_learning.resolution_input)."""
    return ALL_ROBOT_INPUTS if resolution_input else ROBOT_INPUTS


def sensor_dict(robot) -> dict[str, Any]:
    """The run.json ``sensor`` form of a :class:`~slam_predict.robot_file.RobotDescription`."""
    from slam_predict.config import to_dict

    return to_dict(robot.to_sensor_config())


def inputs_from_robot(robot, max_urange_m: float | None = None) -> dict[str, float]:
    """The robot inputs of a :class:`~slam_predict.robot_file.RobotDescription` (its
    ``to_sensor_config()``, so the numbers equal those of the runs collected with it), the
    range capped at GMapping's ``max_urange_m`` (m, None: no cap)."""
    return inputs_from_sensor(sensor_dict(robot), f"robot '{robot.name}'", max_urange_m)


def angular_resolution_deg(sensor: Mapping[str, Any],
                           source: os.PathLike | str | None = None) -> float:
    """Degrees between beams, fov / (samples − 1) (Stage's beam rule); the fov for one beam."""
    fov = math.degrees(_number(sensor, "laser.fov", source))
    samples = _number(sensor, "laser.samples", source)
    if samples < 1:
        raise InputError(f"sensor 'laser.samples' must be >= 1, got {samples:g}", source)
    return fov if samples == 1 else fov / (samples - 1)


def reads_sight_lines(derived: Sequence[str], names: Sequence[str]) -> bool:
    """Whether a model with these derived inputs and input ``names`` needs the plan's sight
    lines (features/sightline.py): a derived input, or a feature of
    :data:`~slam_predict.features.sightline.PLAN_COLUMNS`."""
    from slam_predict.features.sightline import PLAN_COLUMNS

    return bool(derived) or any(name in PLAN_COLUMNS for name in names)


def derived_inputs(curve: Mapping[str, float], robot: Mapping[str, float]) -> dict[str, float]:
    """The plan × robot inputs of :data:`DERIVED_INPUTS` from a plan's sight-line curve
    (columns of :func:`slam_predict.features.sightline.curve_columns`) and robot inputs."""
    from slam_predict.features.sightline import blind_fraction

    return {"laser_blind_fraction": blind_fraction(curve, robot["laser_range_max_m"])}
