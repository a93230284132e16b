"""Plausibility of a robot description: values that are legal but that no real robot has,
almost always a unit mistake (radians for degrees, millimetres for metres, rad/rad for °/rad).

Each rule gives one sentence that names the key, the value, the likely mistake and the fix. The
bounds are wide on purpose: they flag what no planar laser or wheeled indoor robot sold has, not
what is merely unusual, so a real datasheet never trips them. ``--force`` accepts such a file.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Collection
from dataclasses import dataclass

TWO_PI = 2.0 * math.pi
# deg/rad: a yaw error up to this (0.17 %) is below any wheeled robot's odometry, while the
# rad/rad values ROS users write (0.01-0.1) all fall in it
MIN_YAW_DEG_PER_RAD = 0.1


@dataclass(frozen=True)
class Rule:
    """One plausibility rule on the value ``key``: ``broken(robot)`` is True when the robot
    breaks it; ``message(robot)`` says so; ``file_hint`` is the spelling with explicit units a
    robot file may use instead (appended to the message for files only); ``radian_message``
    says so when the file gave the value in that spelling (``key`` + ``_rad``)."""

    key: str
    broken: Callable
    message: Callable
    file_hint: str = ""
    radian_message: Callable | None = None


def _yaw(robot) -> float:
    return robot.odom_error[2]


def _mount_yaw(robot) -> float:
    return robot.laser.pose[2]


def _looks_like_radians(angle_deg: float) -> bool:
    """True for ±π/4, ±π/2, ±π, ±3π/2 or ±2π to 0.01: a mounting yaw in radians."""
    turns = abs(angle_deg) / (math.pi / 4.0)
    return angle_deg != 0.0 and round(turns) in (1, 2, 4, 6, 8) and \
        abs(abs(angle_deg) - round(turns) * math.pi / 4.0) < 0.01


def _step_deg(robot) -> float:
    """Angle between neighbouring beams, degrees (the whole fov for one beam)."""
    laser = robot.laser
    return laser.fov / max(laser.samples - 1, 1)


RULES = (
    Rule("laser.fov", lambda r: r.laser.fov <= TWO_PI,
         lambda r: f"laser.fov {r.laser.fov:g} looks like radians: fov is in degrees "
                   f"({math.degrees(r.laser.fov):.0f})", ", or write it as laser.fov_rad",
         lambda r: f"laser.fov_rad {math.radians(r.laser.fov):g} rad is {r.laser.fov:.3g} deg, "
                   f"narrower than any planar laser: fov_rad is in radians"),
    Rule("laser.range_max", lambda r: r.laser.range_max > 100.0,
         lambda r: f"laser.range_max {r.laser.range_max:g} m is beyond any planar laser "
                   f"(<= 100 m): range_max is in metres"
                   + (f" ({r.laser.range_max / 1000:g} m if it was mm)"
                      if r.laser.range_max >= 1000 else "")),
    Rule("laser.range_max", lambda r: r.laser.range_max < 1.0,
         lambda r: f"laser.range_max {r.laser.range_max:g} m is shorter than any planar laser "
                   f"(>= 1 m): range_max is in metres"),
    Rule("laser.range_min", lambda r: r.laser.range_min > 1.0,
         lambda r: f"laser.range_min {r.laser.range_min:g} m is longer than any planar laser's "
                   f"minimum range (<= 1 m): range_min is in metres"),
    Rule("laser.samples", lambda r: r.laser.samples < 30 or _step_deg(r) > 5.0,
         lambda r: f"laser.samples {r.laser.samples} over {r.laser.fov:g} deg is "
                   f"{_step_deg(r):.3g} deg between beams, coarser than any planar laser "
                   f"(<= 5 deg): samples is the number of beams per scan, e.g. "
                   f"{int(round(r.laser.fov)) + 1} for 1 deg"),
    Rule("laser.rate_hz", lambda r: not 1.0 <= r.laser.rate_hz <= 100.0,
         lambda r: f"laser.rate_hz {r.laser.rate_hz:g} is outside what planar lasers scan at "
                   f"(1-100 Hz): rate_hz is scans per second"),
    Rule("laser.noise_std", lambda r: r.laser.noise_std > 0.5,
         lambda r: f"laser.noise_std {r.laser.noise_std:g} m is more than any laser's range "
                   f"noise (<= 0.5 m): noise_std is in metres"),
    Rule("laser.pose", lambda r: _looks_like_radians(_mount_yaw(r)),
         lambda r: f"laser.pose yaw {_mount_yaw(r):g} looks like radians: the mounting yaw is in "
                   f"degrees ({math.degrees(_mount_yaw(r)):.0f})"),
    Rule("odom_error", lambda r: 0.0 < _yaw(r) <= MIN_YAW_DEG_PER_RAD,
         lambda r: f"odom_error yaw {_yaw(r):g} deg/rad is far below any real robot's: the yaw "
                   f"error is in degrees per radian ({math.degrees(_yaw(r)):.3g} if "
                   f"{_yaw(r):g} was rad/rad)", ", or write odom_error_rad",
         lambda r: f"odom_error_rad yaw {math.radians(_yaw(r)):.3g} rad/rad is far below any "
                   f"real robot's (> {math.radians(MIN_YAW_DEG_PER_RAD):.2g})"),
    Rule("odom_error", lambda r: _yaw(r) > 60.0,
         lambda r: f"odom_error yaw {_yaw(r):g} deg/rad is beyond any real robot's (<= 60 "
                   f"deg/rad): the yaw error is in degrees per radian",
         radian_message=lambda r: f"odom_error_rad yaw {math.radians(_yaw(r)):.4g} rad/rad is "
                                  f"beyond any real robot's (<= {math.radians(60.0):.3g}): "
                                  f"odom_error_rad is in radians per radian, or write "
                                  f"odom_error (yaw in deg/rad)"),
    Rule("odom_error", lambda r: max(r.odom_error[:2]) > 0.5,
         lambda r: f"odom_error x/y {max(r.odom_error[:2]):g} m/m is beyond any real robot's "
                   f"(<= 0.5): they are metres per metre (0.01 = 1 %, not a percentage)"),
    Rule("footprint_side", lambda r: not 0.05 <= r.footprint_side <= 3.0,
         lambda r: f"footprint_side {r.footprint_side:g} m is outside indoor robots' sizes "
                   f"(0.05-3 m): it is in metres"),
    Rule("max_vel_x", lambda r: r.max_vel_x > 5.0,
         lambda r: f"max_vel_x {r.max_vel_x:g} m/s is faster than indoor robots (<= 5 m/s): "
                   f"it is in metres per second"),
    Rule("max_vel_theta", lambda r: r.max_vel_theta > 2.0 * TWO_PI,
         lambda r: f"max_vel_theta {r.max_vel_theta:g} rad/s is faster than indoor robots turn "
                   f"(<= 4 pi rad/s): it is in radians per second"),
)


def implausible(robot, in_radians: Collection[str] = ()) -> list[str]:
    """What makes ``robot`` (a :class:`~slam_predict.robot_file.RobotDescription`, read from a
    robot file) implausible, one sentence per broken rule, in the order of :data:`RULES`;
    empty when it is plausible. ``in_radians``: the keys the file gave in their radian
    spelling (``laser.fov_rad``, ``odom_error_rad``), named as written."""
    return [_file_message(rule, robot, in_radians) for rule in RULES if rule.broken(robot)]


def _file_message(rule: Rule, robot, in_radians: Collection[str]) -> str:
    if rule.radian_message is not None and rule.key + "_rad" in in_radians:
        return rule.radian_message(robot)
    return rule.message(robot) + rule.file_hint


def implausible_laser(robot) -> list[tuple[str, str]]:
    """(key, sentence) for each broken rule on ``robot``'s laser, without the robot-file
    spellings: the checks of a laser made from other inputs (a design's factors)."""
    return [(rule.key, rule.message(robot)) for rule in RULES
            if rule.key.startswith("laser.") and rule.broken(robot)]
