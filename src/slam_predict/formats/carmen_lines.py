"""One line of a CARMEN log: parse a message's tokens into a record, format a record as a line.

Line layouts (ranges in m, angles in rad, timestamps in s):

- ``PARAM name value host timestamp``
- ``ODOM x y theta tv rv accel ipc_timestamp host logger_timestamp``
- ``FLASER n r_1..r_n x y theta odom_x odom_y odom_theta ipc_timestamp host logger_timestamp``
  (old front-laser format: the n readings span 180° starting at −90°; see
  :func:`flaser_angular_resolution`). ``x y theta`` is the laser pose; in our SLAM inputs it is
  the reference (corrected) pose, and ``odom_*`` is the raw odometry.
- ``ROBOTLASER1 laser_type start_angle fov angular_res max_range accuracy remission_mode n
  r_1..r_n m rem_1..rem_m laser_x laser_y laser_theta robot_x robot_y robot_theta laser_tv
  laser_rv forward_safety_dist side_safety_dist turn_axis ipc_timestamp host logger_timestamp``

The trailing ``host logger_timestamp`` pair of ODOM/FLASER lines may be missing (some pose-only
writers omit it); the logger timestamp then equals the IPC timestamp. A parser raises
:class:`TruncatedLine` for fewer fields than the type needs and ``ValueError`` for a malformed
line; what a file does with either is :mod:`slam_predict.formats.carmen`'s policy.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from slam_predict.formats.carmen_records import LaserScan, flaser_angular_resolution

ODOM_FIELDS = 10          # keyword + 9 values
ROBOTLASER1_TAIL = 14     # fields after the remissions


class TruncatedLine(Exception):
    """A line has fewer fields than its message type needs."""


def _floats(tokens: Sequence[str]) -> list[float]:
    return [float(t) for t in tokens]


def parse_param(tokens: list[str], params: dict[str, str]) -> None:
    """Store a PARAM line's name and value in ``params``."""
    if len(tokens) < 3:
        raise TruncatedLine()
    # PARAM name value [[timestamp] host logger_timestamp]: CARMEN values hold no spaces.
    params[tokens[1]] = tokens[2]


def _tail_times(tokens: list[str], start: int) -> tuple[float, float | None, str]:
    """ipc timestamp, logger timestamp and host from ``tokens[start:]`` (host/logger optional)."""
    rest = tokens[start:]
    if len(rest) == 1:
        return float(rest[0]), None, "slam_predict"
    if len(rest) == 3:
        return float(rest[0]), float(rest[2]), rest[1]
    raise ValueError(f"expected 'timestamp host logger_timestamp', got {len(rest)} fields")


def parse_odom(tokens: list[str]) -> tuple[float, list[float], list[float]]:
    """(timestamp s, pose [x, y, theta], [tv, rv, accel]) of an ODOM line."""
    if len(tokens) < ODOM_FIELDS and len(tokens) != ODOM_FIELDS - 2:
        raise TruncatedLine()
    if len(tokens) > ODOM_FIELDS:
        raise ValueError(f"ODOM needs {ODOM_FIELDS - 1} values, got {len(tokens) - 1}")
    values = _floats(tokens[1:7])
    t, _, _ = _tail_times(tokens, 7)
    return t, values[:3], values[3:]


def parse_flaser(tokens: list[str], max_range: float) -> LaserScan:
    """The scan of a FLASER line; ``max_range`` (m) is not in the line."""
    if len(tokens) < 2:
        raise TruncatedLine()
    n = int(tokens[1])
    if n < 0:
        raise ValueError(f"negative reading count {n}")
    full = 2 + n + 9
    if len(tokens) < full and len(tokens) != full - 2:
        raise TruncatedLine()
    if len(tokens) > full:
        raise ValueError(f"FLASER with {n} readings needs {n + 10} fields, got {len(tokens) - 1}")
    ranges = np.array(tokens[2:2 + n], dtype=np.float32)
    poses = _floats(tokens[2 + n:2 + n + 6])
    t, logger_t, host = _tail_times(tokens, 2 + n + 6)
    return LaserScan(timestamp=t, ranges=ranges, start_angle=-math.pi / 2,
                     angular_resolution=flaser_angular_resolution(n), max_range=max_range,
                     pose=poses[:3], odom_pose=poses[3:], kind="FLASER",
                     logger_timestamp=logger_t, host=host, fov=math.pi)


def parse_robotlaser1(tokens: list[str]) -> LaserScan:
    """The scan of a ROBOTLASER1 line."""
    if len(tokens) < 9:
        raise TruncatedLine()
    head = _floats(tokens[1:8])
    n = int(tokens[8])
    if n < 0:
        raise ValueError(f"negative reading count {n}")
    if len(tokens) < 10 + n:
        raise TruncatedLine()
    m = int(tokens[9 + n])
    if m < 0:
        raise ValueError(f"negative remission count {m}")
    tail_start = 10 + n + m
    full = tail_start + ROBOTLASER1_TAIL
    if len(tokens) < full and len(tokens) != full - 2:
        raise TruncatedLine()
    if len(tokens) > full:
        extra = len(tokens) - tail_start - ROBOTLASER1_TAIL
        raise ValueError(f"ROBOTLASER1 has {extra} extra fields")
    tail = _floats(tokens[tail_start:tail_start + 11])
    t, logger_t, host = _tail_times(tokens, tail_start + 11)
    return LaserScan(
        timestamp=t, ranges=np.array(tokens[9:9 + n], dtype=np.float32), start_angle=head[1],
        angular_resolution=head[3], max_range=head[4], pose=tail[0:3], odom_pose=tail[3:6],
        kind="ROBOTLASER1", logger_timestamp=logger_t, host=host, fov=head[2],
        remissions=np.array(tokens[10 + n:tail_start], dtype=np.float32),
        laser_type=int(head[0]), accuracy=head[5], remission_mode=int(head[6]),
        tv=tail[6], rv=tail[7], forward_safety_dist=tail[8], side_safety_dist=tail[9],
        turn_axis=tail[10])


def line_status(tokens: list[str]) -> str:
    """'ok', 'truncated' (fewer fields than the type needs), 'malformed' or 'ignored'."""
    if not tokens or tokens[0].startswith("#"):
        return "ignored"
    parsers = {"PARAM": lambda tk: parse_param(tk, {}), "ODOM": parse_odom,
               "FLASER": lambda tk: parse_flaser(tk, math.nan), "ROBOTLASER1": parse_robotlaser1}
    if tokens[0] not in parsers:
        return "ignored"
    try:
        parsers[tokens[0]](tokens)
    except TruncatedLine:
        return "truncated"
    except ValueError:
        return "malformed"
    return "ok"


def _num(value: float) -> str:
    """Shortest text that reads back as the same double."""
    return repr(float(value))


def _ranges_text(values: np.ndarray, decimals: int | None) -> list[str]:
    if decimals is None:  # 9 significant digits: reads back as the same float32
        return [f"{v:.9g}" for v in np.asarray(values, dtype=np.float32).tolist()]
    fmt = f"{{:.{int(decimals)}f}}".format
    return [fmt(v) for v in np.asarray(values, dtype=float).tolist()]


def _times(timestamp: float, logger_timestamp: float | None, host: str) -> list[str]:
    logger_t = timestamp if logger_timestamp is None else logger_timestamp
    return [_num(timestamp), host or "slam_predict", _num(logger_t)]


def param_line(name: str, value, timestamp: float = 0.0, host: str = "slam_predict") -> str:
    """One ``PARAM name value host timestamp`` line (no newline); values hold no spaces."""
    return f"PARAM {name} {value} {host} {_num(timestamp) if timestamp else 0}"


def odom_line(t: float, pose: Sequence[float], tv: float = 0.0, rv: float = 0.0,
              accel: float = 0.0, host: str = "slam_predict") -> str:
    """One ``ODOM`` line (no newline)."""
    fields = ["ODOM", *map(_num, pose), _num(tv), _num(rv), _num(accel), *_times(t, None, host)]
    return " ".join(fields)


def scan_line(scan: LaserScan, range_decimals: int | None = 3) -> str:
    """One ``FLASER`` or ``ROBOTLASER1`` line for ``scan`` (no newline).

    ``range_decimals``: digits after the point for ranges (3 = mm, CARMEN's habit); None writes
    each float32 reading exactly: 9 significant digits (``%.9g``), which read back as the same
    float32 whether parsed as a float (C's strtof) or as a double rounded to float.
    """
    ranges = _ranges_text(scan.ranges, range_decimals)
    times = _times(scan.timestamp, scan.logger_timestamp, scan.host)
    if scan.kind == "FLASER":
        return " ".join(["FLASER", str(len(ranges)), *ranges, *map(_num, scan.pose),
                         *map(_num, scan.odom_pose), *times])
    if scan.kind == "ROBOTLASER1":
        head = [str(scan.laser_type), _num(scan.start_angle), _num(scan.fov),
                _num(scan.angular_resolution), _num(scan.max_range), _num(scan.accuracy),
                str(scan.remission_mode)]
        rem = _ranges_text(scan.remissions, None)
        tail = [*map(_num, scan.pose), *map(_num, scan.odom_pose), _num(scan.tv), _num(scan.rv),
                _num(scan.forward_safety_dist), _num(scan.side_safety_dist), _num(scan.turn_axis)]
        return " ".join(["ROBOTLASER1", *head, str(len(ranges)), *ranges, str(len(rem)), *rem,
                         *tail, *times])
    raise ValueError(f"cannot write laser message type {scan.kind!r}")


def trajectory_line(t: float, pose: Sequence[float], odom_pose: Sequence[float],
                    host: str = "slam_predict") -> str:
    """One pose-only ``FLASER 0 x y theta ox oy otheta t host t`` line (no newline)."""
    return " ".join(["FLASER", "0", *map(_num, pose), *map(_num, odom_pose),
                     *_times(t, None, host)])
