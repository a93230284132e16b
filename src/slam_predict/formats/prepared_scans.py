"""Prepared scans: the exact input of a GMapping run as text, for the differential check against
the real openslam_gmapping (``bench/gmapping_diff/driver.cpp`` reads it, ``bench/
bench_gmapping_diff.py`` writes it from the same input object our runner uses).

Format (version 1), one item per line::

    slam_predict_prepared_scans 1
    seed 3
    angle_mode node                  # node: RangeSensor angles as slam_gmapping builds them
    maxRange 49.99                   # resolved as slam_gmapping does (range_max - 0.01, ...)
    <every other GMapping parameter the filter uses, slam_gmapping names>
    laser_pose x y theta             # laser in the base frame (m, rad)
    angles N a_0 ... a_N-1           # beam angles in the laser frame (rad)
    SCAN t x y theta r_0 ... r_N-1   # time (s), robot odometry pose (m, rad), ranges (m)

Numbers are written with ``repr`` (shortest text that reads back to the same double), so both
sides see identical values. The driver's output (:func:`read_driver_output`): ``scan_index time
x y theta`` per processed scan of the best particle (robot poses, map frame), ``# neff v`` lines
and a ``# summary processed K resamples R best B`` line.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np

from slam_predict.atomic import write_text
from slam_predict.errors import InputError, require_file

MAGIC = "slam_predict_prepared_scans 1"
ANGLE_MODES = ("node", "exact")
# The GMapping parameters the filter reads (slam_gmapping names), in the order written.
FILTER_PARAMS = ("particles", "maxRange", "maxUrange", "sigma", "kernelSize", "lstep", "astep",
                 "iterations", "lsigma", "ogain", "lskip", "srr", "srt", "str", "stt",
                 "linearUpdate", "angularUpdate", "resampleThreshold", "temporalUpdate", "xmin",
                 "ymin", "xmax", "ymax", "delta", "llsamplerange", "llsamplestep",
                 "lasamplerange", "lasamplestep", "minimumScore")


def _text(value) -> str:
    return repr(float(value)) if not isinstance(value, (int, np.integer)) else str(int(value))


def checked_scans(times, odometry, ranges, laser):
    """(times (N,), odometry (N, 3), ranges (N, B)) as float arrays; ValueError when their
    lengths or the beam count of ``laser`` disagree."""
    times = np.asarray(times, dtype=float)
    odometry = np.asarray(odometry, dtype=float).reshape(-1, 3)
    ranges = np.asarray(ranges, dtype=float)
    if ranges.ndim != 2 or ranges.shape[1] != laser.beams or len(ranges) != len(times):
        raise ValueError(f"ranges {ranges.shape} do not match {len(times)} scans of "
                         f"{laser.beams} beams")
    if len(odometry) != len(times):
        raise ValueError("odometry and times differ in length")
    return times, odometry, ranges


def prepared_scans_text(times, odometry, ranges, laser, params, seed: int,
                        angle_mode: str = "node") -> str:
    """The prepared-scans text of one run. ``params`` must have maxRange/maxUrange resolved
    (``params.with_ranges``); ``laser`` is a :class:`slam_predict.slam.LaserGeometry`."""
    if angle_mode not in ANGLE_MODES:
        raise ValueError(f"angle_mode must be one of {ANGLE_MODES}, not {angle_mode!r}")
    if params.maxRange is None or params.maxUrange is None:
        raise ValueError("maxRange/maxUrange must be resolved (params.with_ranges)")
    times, odometry, ranges = checked_scans(times, odometry, ranges, laser)
    lines = [MAGIC, f"seed {int(seed)}", f"angle_mode {angle_mode}"]
    lines += [f"{name} {_text(getattr(params, name))}" for name in FILTER_PARAMS]
    lines.append("laser_pose " + " ".join(_text(v) for v in laser.pose_in_base))
    lines.append(f"angles {laser.beams} " + " ".join(repr(float(a)) for a in laser.angles))
    for t, pose, row in zip(times.tolist(), odometry.tolist(), ranges.tolist(), strict=False):
        lines.append("SCAN " + " ".join(repr(v) for v in (t, *pose, *row)))
    return "\n".join(lines) + "\n"


def write_prepared_scans(path: os.PathLike | str, times, odometry, ranges, laser, params,
                         seed: int, angle_mode: str = "node") -> None:
    """Write :func:`prepared_scans_text` to ``path`` (atomically)."""
    write_text(path, prepared_scans_text(times, odometry, ranges, laser, params, seed,
                                         angle_mode))


@dataclass
class DriverOutput:
    """The driver's result: processed-scan indices into the input (K,), times (K,) s, robot poses
    in the map frame (K, 3), Neff after each scan match, resampling count, best particle."""

    indices: np.ndarray
    times: np.ndarray
    poses: np.ndarray
    neff: list[float] = field(default_factory=list)
    resamples: int = 0
    best: int = 0


def read_driver_output(path: os.PathLike | str) -> DriverOutput:
    """Read the trajectory file the driver writes."""
    path = require_file(path, "driver output")
    rows, neff, summary = [], [], None
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            fields = line.split()
            if not fields:
                continue
            try:
                if fields[:2] == ["#", "neff"]:
                    neff.append(float(fields[2]))
                elif fields[:2] == ["#", "summary"]:
                    summary = dict(zip(fields[2::2], (int(v) for v in fields[3::2]), strict=False))
                elif fields[0] != "#":
                    if len(fields) != 5:
                        raise ValueError("expected 5 fields")
                    rows.append([float(v) for v in fields])
            except (ValueError, IndexError) as exc:
                raise InputError(f"line {number}: {exc}", path) from None
    if summary is None:
        raise InputError("no summary line (driver output incomplete)", path)
    table = np.array(rows, dtype=float).reshape(-1, 5)
    if len(table) != summary.get("processed", -1):
        raise InputError(f"{len(table)} poses but the summary says {summary.get('processed')}",
                         path)
    return DriverOutput(table[:, 0].astype(np.int64), table[:, 1], table[:, 2:5], neff,
                        summary.get("resamples", 0), summary.get("best", 0))
