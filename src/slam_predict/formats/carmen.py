"""CARMEN log files (plain or gzip): read PARAM / ODOM / FLASER / ROBOTLASER1, write them back.

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

``#`` comments, ``NEFF`` and every other message type are skipped (unknown types are logged at
debug level). A last line with fewer fields than its type needs is a truncated write: it is
dropped with a warning (the thesis' adjustment). Any other malformed line raises
:class:`~slam_predict.errors.InputError` naming the file and line. The trailing
``host logger_timestamp`` pair of ODOM/FLASER lines may be missing (some pose-only writers omit
it); the logger timestamp then equals the IPC timestamp.
"""
from __future__ import annotations

import gzip
import io
import logging
import math
import os
import zlib
from typing import Dict, Iterable, Iterator, List, Optional, Sequence, Tuple

import numpy as np

from slam_predict.atomic import atomic_path
from slam_predict.errors import InputError, require_file
from slam_predict.formats.carmen_records import (  # noqa: F401  (re-exported)
    CarmenLog, LaserScan, Odometry, flaser_angular_resolution)

log = logging.getLogger(__name__)

ODOM_FIELDS = 10          # keyword + 9 values
ROBOTLASER1_TAIL = 14     # fields after the remissions
IGNORED_TYPES = frozenset({"NEFF", "SYNC"})

# PARAM names that carry the front laser's maximum range (m), in order of preference.
MAX_RANGE_PARAMS = ("robot_front_laser_max", "laser_front_laser_max_range", "laser_front_laser_maxrange")


class _Truncated(Exception):
    """A line has fewer fields than its message type needs."""


def _floats(tokens: Sequence[str]) -> List[float]:
    return [float(t) for t in tokens]


def _parse_param(tokens: List[str], params: Dict[str, str]) -> None:
    if len(tokens) < 3:
        raise _Truncated()
    # PARAM name value [[timestamp] host logger_timestamp]: CARMEN values hold no spaces.
    params[tokens[1]] = tokens[2]


def _tail_times(tokens: List[str], start: int) -> Tuple[float, Optional[float], str]:
    """ipc timestamp, logger timestamp and host from ``tokens[start:]`` (host/logger optional)."""
    rest = tokens[start:]
    if len(rest) == 1:
        return float(rest[0]), None, "slam_predict"
    if len(rest) == 3:
        return float(rest[0]), float(rest[2]), rest[1]
    raise ValueError(f"expected 'timestamp host logger_timestamp', got {len(rest)} fields")


def _parse_odom(tokens: List[str]) -> Tuple[float, List[float], List[float]]:
    if len(tokens) < ODOM_FIELDS and len(tokens) != ODOM_FIELDS - 2:
        raise _Truncated()
    if len(tokens) > ODOM_FIELDS:
        raise ValueError(f"ODOM needs {ODOM_FIELDS - 1} values, got {len(tokens) - 1}")
    values = _floats(tokens[1:7])
    t, _, _ = _tail_times(tokens, 7)
    return t, values[:3], values[3:]


def _parse_flaser(tokens: List[str], max_range: float) -> LaserScan:
    if len(tokens) < 2:
        raise _Truncated()
    n = int(tokens[1])
    if n < 0:
        raise ValueError(f"negative reading count {n}")
    full = 2 + n + 9
    if len(tokens) < full and len(tokens) != full - 2:
        raise _Truncated()
    if len(tokens) > full:
        raise ValueError(f"FLASER with {n} readings needs {n + 10} fields, got {len(tokens) - 1}")
    ranges = np.array(tokens[2:2 + n], dtype=np.float32)
    poses = _floats(tokens[2 + n:2 + n + 6])
    t, logger_t, host = _tail_times(tokens, 2 + n + 6)
    return LaserScan(timestamp=t, ranges=ranges, start_angle=-math.pi / 2,
                     angular_resolution=flaser_angular_resolution(n), max_range=max_range,
                     pose=poses[:3], odom_pose=poses[3:], kind="FLASER",
                     logger_timestamp=logger_t, host=host, fov=math.pi)


def _parse_robotlaser1(tokens: List[str]) -> LaserScan:
    if len(tokens) < 9:
        raise _Truncated()
    head = _floats(tokens[1:8])
    n = int(tokens[8])
    if n < 0:
        raise ValueError(f"negative reading count {n}")
    if len(tokens) < 10 + n:
        raise _Truncated()
    m = int(tokens[9 + n])
    if m < 0:
        raise ValueError(f"negative remission count {m}")
    tail_start = 10 + n + m
    full = tail_start + ROBOTLASER1_TAIL
    if len(tokens) < full and len(tokens) != full - 2:
        raise _Truncated()
    if len(tokens) > full:
        raise ValueError(f"ROBOTLASER1 has {len(tokens) - tail_start - ROBOTLASER1_TAIL} extra fields")
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


def line_status(tokens: List[str]) -> str:
    """'ok', 'truncated' (fewer fields than the type needs), 'malformed' or 'ignored'."""
    if not tokens or tokens[0].startswith("#"):
        return "ignored"
    parsers = {"PARAM": lambda tk: _parse_param(tk, {}), "ODOM": _parse_odom,
               "FLASER": lambda tk: _parse_flaser(tk, math.nan), "ROBOTLASER1": _parse_robotlaser1}
    if tokens[0] not in parsers:
        return "ignored"
    try:
        parsers[tokens[0]](tokens)
    except _Truncated:
        return "truncated"
    except ValueError:
        return "malformed"
    return "ok"


GZIP_MAGIC = b"\x1f\x8b"


def read_log_bytes(path: str) -> bytes:
    """The content of a CARMEN log, gunzipped when it starts with the gzip magic.

    InputError (one line, naming the file) for a ``.gz`` name without gzip data, corrupt gzip
    data and a truncated gzip file (naming the line where the data stops).
    """
    try:
        with open(path, "rb") as fh:
            raw = fh.read()
    except OSError as exc:
        raise InputError(f"cannot read CARMEN log ({exc.strerror or exc})", path) from None
    if raw[:2] == GZIP_MAGIC:
        return _gunzip(raw, path)
    if path.lower().endswith(".gz"):
        raise InputError("not a gzip file (the name ends in .gz but the content is not gzip "
                         "data)", path)
    return raw


def _gunzip(raw: bytes, path: str) -> bytes:
    """All gzip members of ``raw``, decompressed; InputError when corrupt or truncated."""
    parts: List[bytes] = []
    while raw:
        member = zlib.decompressobj(wbits=16 + zlib.MAX_WBITS)
        try:
            parts.append(member.decompress(raw))
        except zlib.error as exc:
            raise InputError(f"not a gzip file or corrupt gzip data ({exc})", path) from None
        if not member.eof:
            data = b"".join(parts)
            line = data.count(b"\n") + 1
            raise InputError(f"truncated gzip file: the data stops inside line {line}",
                             path, line)
        raw = member.unused_data
    return b"".join(parts)


def _read_lines(path: str) -> List[str]:
    """The log's lines (universal newlines, ends kept); InputError for non-UTF-8 content."""
    data = read_log_bytes(path)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise InputError(f"not a CARMEN text log: byte 0x{data[exc.start]:02x} is not UTF-8 "
                         "text", path, line) from None
    return io.StringIO(text, newline=None).readlines()


def read_log(path: os.PathLike | str, max_range: Optional[float] = None) -> CarmenLog:
    """Read a CARMEN log (plain or gzip, detected from the content).

    ``max_range`` (m) is given to FLASER scans, which carry none; default: the PARAM
    ``robot_front_laser_max`` (or ``laser_front_laser_max_range``) when logged, else NaN.
    """
    path = require_file(path, "CARMEN log")
    lines = _read_lines(path)
    last = _last_content_line(lines)
    params: Dict[str, str] = {}
    odom_t: List[float] = []
    odom_pose: List[List[float]] = []
    odom_vel: List[List[float]] = []
    scans: List[LaserScan] = []
    unknown: Dict[str, int] = {}
    for number, line in enumerate(lines, start=1):
        tokens = line.split()
        if not tokens or tokens[0].startswith("#"):
            continue
        kind = tokens[0]
        try:
            if kind == "PARAM":
                _parse_param(tokens, params)
            elif kind == "ODOM":
                t, pose, vel = _parse_odom(tokens)
                odom_t.append(t)
                odom_pose.append(pose)
                odom_vel.append(vel)
            elif kind == "FLASER":
                scans.append(_parse_flaser(tokens, math.nan))
            elif kind == "ROBOTLASER1":
                scans.append(_parse_robotlaser1(tokens))
            elif kind not in IGNORED_TYPES:
                unknown[kind] = unknown.get(kind, 0) + 1
        except _Truncated:
            if number != last:
                raise InputError(f"{kind} line has too few fields", path, number)
            log.warning("%s:%d: dropping truncated last line (%s)", path, number, kind)
        except ValueError as exc:
            if number == last and not line.endswith("\n"):
                log.warning("%s:%d: dropping unterminated last line (%s)", path, number, exc)
                continue
            raise InputError(f"malformed {kind} line: {exc}", path, number)
    flaser_range = _param_max_range(params) if max_range is None else float(max_range)
    for scan in scans:
        if scan.kind == "FLASER":
            scan.max_range = flaser_range
    for kind, count in unknown.items():
        log.debug("%s: skipped %d '%s' lines (type not read)", path, count, kind)
    vel = np.array(odom_vel, dtype=float).reshape(-1, 3)
    odometry = Odometry(np.array(odom_t), np.array(odom_pose).reshape(-1, 3),
                        vel[:, 0], vel[:, 1], vel[:, 2])
    return CarmenLog(params=params, odometry=odometry, scans=scans, path=path)


def _last_content_line(lines: List[str]) -> int:
    """1-based number of the last non-blank line (0 when there is none)."""
    for index in range(len(lines) - 1, -1, -1):
        if lines[index].strip():
            return index + 1
    return 0


def _param_max_range(params: Dict[str, str]) -> float:
    for name in MAX_RANGE_PARAMS:
        if name in params:
            try:
                return float(params[name])
            except ValueError:
                pass
    return float("nan")


# ----------------------------------------------------------------------------------- writing

def _num(value: float) -> str:
    """Shortest text that reads back as the same double."""
    return repr(float(value))


def _ranges_text(values: np.ndarray, decimals: Optional[int]) -> List[str]:
    if decimals is None:  # 9 significant digits: reads back as the same float32
        return ["%.9g" % v for v in np.asarray(values, dtype=np.float32).tolist()]
    fmt = f"{{:.{int(decimals)}f}}".format
    return [fmt(v) for v in np.asarray(values, dtype=float).tolist()]


def _times(timestamp: float, logger_timestamp: Optional[float], host: str) -> List[str]:
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


def scan_line(scan: LaserScan, range_decimals: Optional[int] = 3) -> str:
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


def _log_lines(carmen: CarmenLog, range_decimals: Optional[int]) -> Iterator[str]:
    """PARAM lines, then ODOM and scan lines merged by timestamp (ODOM first on ties)."""
    for name, value in carmen.params.items():
        yield param_line(name, value)
    odo = carmen.odometry
    records = [(float(t), 0, i) for i, t in enumerate(odo.t)]
    records += [(float(s.timestamp), 1, i) for i, s in enumerate(carmen.scans)]
    records.sort()
    for _, kind, i in records:
        if kind == 0:
            yield odom_line(odo.t[i], odo.poses[i], odo.tv[i], odo.rv[i], odo.accel[i])
        else:
            yield scan_line(carmen.scans[i], range_decimals)


def write_log(path: os.PathLike | str, carmen: CarmenLog, *, range_decimals: Optional[int] = 3,
              header: Iterable[str] = ()) -> None:
    """Write ``carmen`` as a CARMEN log, atomically; gzip-compressed when ``path`` ends in .gz.

    ``header`` lines are written first as ``#`` comments. Poses and timestamps are written with
    full double precision.
    """
    lines = [f"# {h}" for h in header]
    lines.extend(_log_lines(carmen, range_decimals))
    _write_lines(path, lines)


def write_trajectory(path: os.PathLike | str, t: Sequence[float], poses: np.ndarray, *,
                     odom_poses: Optional[np.ndarray] = None, host: str = "slam_predict",
                     header: Iterable[str] = ()) -> None:
    """Write a pose trajectory as ``FLASER 0 x y theta ox oy otheta t host t`` lines, atomically.

    This is how SLAM (or ground-truth) trajectories are handed to Freiburg's metricEvaluator.
    ``odom_poses`` fills the odom fields (default: the poses themselves).
    """
    t = np.asarray(t, dtype=float).reshape(-1)
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    odom = poses if odom_poses is None else np.asarray(odom_poses, dtype=float).reshape(-1, 3)
    if not len(t) == len(poses) == len(odom):
        raise ValueError(f"length mismatch: {len(t)} times, {len(poses)} poses, {len(odom)} odom")
    lines = [f"# {h}" for h in header]
    for ti, pose, opose in zip(t, poses, odom):
        lines.append(" ".join(["FLASER", "0", *map(_num, pose), *map(_num, opose),
                               *_times(ti, None, host)]))
    _write_lines(path, lines)


def _write_lines(path: os.PathLike | str, lines: List[str]) -> None:
    text = "\n".join(lines) + ("\n" if lines else "")
    gz = os.fspath(path).endswith(".gz")
    with atomic_path(path) as tmp:
        if gz:
            with gzip.open(tmp, "wt", encoding="utf-8", compresslevel=6) as fh:
                fh.write(text)
        else:
            tmp.write_text(text, encoding="utf-8")


class CarmenLogWriter:
    """Writes a CARMEN log line by line (streamed) under a temporary name beside ``path``;
    gzip-compressed when ``path`` ends in .gz. :meth:`close` renames it onto ``path``,
    :meth:`abort` deletes it. ``header`` lines are written first as ``#`` comments."""

    def __init__(self, path: os.PathLike | str, header: Iterable[str] = (), compresslevel: int = 3):
        import contextlib

        self._stack = contextlib.ExitStack()
        tmp = self._stack.enter_context(atomic_path(path))
        if os.fspath(path).endswith(".gz"):
            self._fh = gzip.open(tmp, "wt", encoding="utf-8", compresslevel=compresslevel)
        else:
            self._fh = open(tmp, "wt", encoding="utf-8")
        self.lines = 0
        for line in header:
            self.write(f"# {line}")

    def write(self, line: str) -> None:
        """One line (without its newline)."""
        self._fh.write(line + "\n")
        self.lines += 1

    def close(self) -> None:
        """Finish the file and rename it onto its final name."""
        self._fh.close()
        self._stack.close()

    def abort(self) -> None:
        """Drop the partial file."""
        self._fh.close()
        self._stack.__exit__(InterruptedError, InterruptedError("aborted"), None)
