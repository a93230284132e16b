"""Robot-file spellings users bring from elsewhere (:mod:`slam_predict.robot_file`).

- Radians where ROS users expect them: ``laser.fov_rad`` (a LaserScan's angle_max − angle_min)
  and ``odom_error_rad`` = [x m/m, y m/m, yaw rad/rad], turned into the file's own units
  (degrees, °/rad); giving a value both ways is refused.
- Names from a LaserScan message, a Stage ranger or slam_gmapping's parameters, refused with
  what to write instead (a plain did-you-mean would point at the wrong key).
"""
from __future__ import annotations

import math
from collections.abc import Collection, Mapping
from typing import Any

from slam_predict.errors import InputError

FOV_RAD_MAX = 2.0 * math.pi
RADIAN_KEYS = ("laser.fov_rad", "odom_error_rad")
FOREIGN_LASER_KEYS = {
    "angle_min": "a LaserScan's angles: write laser.fov_rad = angle_max - angle_min",
    "angle_max": "a LaserScan's angles: write laser.fov_rad = angle_max - angle_min",
    "angle_increment": "a LaserScan's angle step: write laser.samples = fov_rad / "
                       "angle_increment + 1",
    "max_range": "did you mean 'range_max'?",
    "min_range": "did you mean 'range_min'?",
    "maxRange": "slam_gmapping's parameter: write the laser's range as laser.range_max",
    "maxUrange": "slam_gmapping's parameter: write the laser's range as laser.range_max",
    "range": "Stage's 'range [min max]': write laser.range_min and laser.range_max",
    "scan_time": "a LaserScan's scan time: write laser.rate_hz = 1 / scan_time",
    "frequency": "write the scans per second as laser.rate_hz",
}


def check_foreign_keys(data: Mapping[str, Any], path: str,
                       laser_keys: Collection[str] = ()) -> None:
    """InputError with what to write when the laser section uses another tool's name, or a
    key of ``laser_keys`` (with fov_rad) stands at the top level instead of in ``laser:``."""
    for key in data:
        if key in (*laser_keys, "fov_rad"):
            raise InputError(f"unknown config key '{key}' at the top level (it belongs in the "
                             f"laser: section, indented under it)", path)
    laser = data.get("laser")
    if not isinstance(laser, Mapping):
        return
    for key in laser:
        if key in FOREIGN_LASER_KEYS:
            raise InputError(f"unknown config key '{key}' in 'laser' "
                             f"({FOREIGN_LASER_KEYS[key]})", path)


def to_file_units(data: dict[str, Any], path: str) -> tuple[dict[str, Any], list[str]]:
    """``data`` with the radian spellings turned into the file's own units (degrees), and the
    radian keys it used; InputError when a value is given both ways or a radian value is not
    one (a fov_rad beyond a full turn)."""
    used = []
    laser = data.get("laser")
    if isinstance(laser, Mapping) and "fov_rad" in laser:
        if "fov" in laser:
            raise InputError("give laser.fov (degrees) or laser.fov_rad, not both", path)
        fov = _number(laser["fov_rad"], "laser.fov_rad", path)
        if not 0.0 < fov <= FOV_RAD_MAX:
            hint = ": degrees? write laser.fov" if fov > FOV_RAD_MAX else ""
            raise InputError(f"'laser.fov_rad' must be in (0, 2 pi = {FOV_RAD_MAX:.4f}] rad, got "
                             f"{fov:g}{hint}", path)
        rest = {k: v for k, v in laser.items() if k != "fov_rad"}
        data = {**data, "laser": {**rest, "fov": math.degrees(fov)}}
        used.append("laser.fov_rad")
    if "odom_error_rad" in data:
        if "odom_error" in data:
            raise InputError("give odom_error (yaw in deg/rad) or odom_error_rad (yaw in "
                             "rad/rad), not both", path)
        values = data["odom_error_rad"]
        if not isinstance(values, list) or len(values) != 3:
            raise InputError(f"'odom_error_rad' must be [x m/m, y m/m, yaw rad/rad], got "
                             f"{values!r}", path)
        yaw = _number(values[2], "odom_error_rad[2]", path)
        rest = {k: v for k, v in data.items() if k != "odom_error_rad"}
        data = {**rest, "odom_error": [*values[:2], math.degrees(yaw)]}
        used.append("odom_error_rad")
    return data, used


def _number(value: Any, key: str, path: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"'{key}' must be a number, got {value!r}", path)
    return float(value)
