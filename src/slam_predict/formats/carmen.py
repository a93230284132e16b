"""CARMEN log files (plain or gzip): read PARAM / ODOM / FLASER / ROBOTLASER1, write them back.

The line layouts, their parsers and their formatters are in
:mod:`slam_predict.formats.carmen_lines`; this module reads and writes whole files.
``#`` comments, ``NEFF`` and every other message type are skipped (unknown types are logged at
debug level). A last line with fewer fields than its type needs is a truncated write: it is
dropped with a warning (the thesis' adjustment). Any other malformed line raises
:class:`~slam_predict.errors.InputError` naming the file and line.
"""
from __future__ import annotations

import gzip
import io
import logging
import math
import os
import zlib
from collections.abc import Iterable, Iterator, Sequence

import numpy as np

from slam_predict.atomic import atomic_path
from slam_predict.errors import InputError, require_file
from slam_predict.formats.carmen_lines import (
    TruncatedLine,
    odom_line,
    param_line,
    parse_flaser,
    parse_odom,
    parse_param,
    parse_robotlaser1,
    scan_line,
    trajectory_line,
)
from slam_predict.formats.carmen_records import (  # noqa: F401  (re-exported)
    CarmenLog,
    LaserScan,
    Odometry,
    flaser_angular_resolution,
)

log = logging.getLogger(__name__)

IGNORED_TYPES = frozenset({"NEFF", "SYNC"})

# PARAM names that carry the front laser's maximum range (m), in order of preference.
MAX_RANGE_PARAMS = ("robot_front_laser_max", "laser_front_laser_max_range",
                    "laser_front_laser_maxrange")

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
    parts: list[bytes] = []
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


def _read_lines(path: str) -> list[str]:
    """The log's lines (universal newlines, ends kept); InputError for non-UTF-8 content."""
    data = read_log_bytes(path)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise InputError(f"not a CARMEN text log: byte 0x{data[exc.start]:02x} is not UTF-8 "
                         "text", path, line) from None
    return io.StringIO(text, newline=None).readlines()


def read_log(path: os.PathLike | str, max_range: float | None = None) -> CarmenLog:
    """Read a CARMEN log (plain or gzip, detected from the content).

    ``max_range`` (m) is given to FLASER scans, which carry none; default: the PARAM
    ``robot_front_laser_max`` (or ``laser_front_laser_max_range``) when logged, else NaN.
    """
    path = require_file(path, "CARMEN log")
    lines = _read_lines(path)
    last = _last_content_line(lines)
    params: dict[str, str] = {}
    odom_t: list[float] = []
    odom_pose: list[list[float]] = []
    odom_vel: list[list[float]] = []
    scans: list[LaserScan] = []
    unknown: dict[str, int] = {}
    for number, line in enumerate(lines, start=1):
        tokens = line.split()
        if not tokens or tokens[0].startswith("#"):
            continue
        kind = tokens[0]
        try:
            if kind == "PARAM":
                parse_param(tokens, params)
            elif kind == "ODOM":
                t, pose, vel = parse_odom(tokens)
                odom_t.append(t)
                odom_pose.append(pose)
                odom_vel.append(vel)
            elif kind == "FLASER":
                scans.append(parse_flaser(tokens, math.nan))
            elif kind == "ROBOTLASER1":
                scans.append(parse_robotlaser1(tokens))
            elif kind not in IGNORED_TYPES:
                unknown[kind] = unknown.get(kind, 0) + 1
        except TruncatedLine:
            if number != last:
                raise InputError(f"{kind} line has too few fields", path, number) from None
            log.warning("%s:%d: dropping truncated last line (%s)", path, number, kind)
        except ValueError as exc:
            if number == last and not line.endswith("\n"):
                log.warning("%s:%d: dropping unterminated last line (%s)", path, number, exc)
                continue
            raise InputError(f"malformed {kind} line: {exc}", path, number) from None
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


def _last_content_line(lines: list[str]) -> int:
    """1-based number of the last non-blank line (0 when there is none)."""
    for index in range(len(lines) - 1, -1, -1):
        if lines[index].strip():
            return index + 1
    return 0


def _param_max_range(params: dict[str, str]) -> float:
    for name in MAX_RANGE_PARAMS:
        if name in params:
            try:
                return float(params[name])
            except ValueError:
                pass
    return float("nan")


# ----------------------------------------------------------------------------------- writing

def _log_lines(carmen: CarmenLog, range_decimals: int | None) -> Iterator[str]:
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


def write_log(path: os.PathLike | str, carmen: CarmenLog, *, range_decimals: int | None = 3,
              header: Iterable[str] = ()) -> None:
    """Write ``carmen`` as a CARMEN log, atomically; gzip-compressed when ``path`` ends in .gz.

    ``header`` lines are written first as ``#`` comments. Poses and timestamps are written with
    full double precision.
    """
    lines = [f"# {h}" for h in header]
    lines.extend(_log_lines(carmen, range_decimals))
    _write_lines(path, lines)


def write_trajectory(path: os.PathLike | str, t: Sequence[float], poses: np.ndarray, *,
                     odom_poses: np.ndarray | None = None, host: str = "slam_predict",
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
    for ti, pose, opose in zip(t, poses, odom, strict=True):
        lines.append(trajectory_line(ti, pose, opose, host))
    _write_lines(path, lines)


def _write_lines(path: os.PathLike | str, lines: list[str]) -> None:
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
            self._fh = open(tmp, "w", encoding="utf-8")
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
